/* Loads and boundary conditions of a solid: their declaration, the dead
 * loads assembled at set-up, the follower pressure and the external force. */
#include "tl_solid_private.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_memory.h"

static void note_set(TlSolid *s, const char *name)
{
  if (strstr(s->constraint_sets, name)) return;
  size_t l = strlen(s->constraint_sets);
  if (l + strlen(name) + 3 < sizeof s->constraint_sets)
    snprintf(s->constraint_sets + l, sizeof s->constraint_sets - l, "%s%s", l ? ", " : "", name);
}

static TlStatus add_body(TlSolid *s, int block, int gravity, TlVec3 b, TlAmplitude amp, void *ctx)
{
  if (!tl_v3_isfinite(b)) TL_ERROR(TL_ERR_ARG, "solid: body force is not finite");
  TL_CHECK(tl_realloc(&s->body, s->n_body + 1, sizeof *s->body));
  s->body[s->n_body++] = (BodyForce){block, gravity, b, amp, ctx};
  return TL_OK;
}

TlStatus tl_solid_add_body_force(TlSolid *s, const char *block, TlVec3 b, TlAmplitude amp, void *ctx)
{
  TL_CHECK(tl_solid_not_after_setup(s, "add_body_force"));
  int k;
  if (!tl_solid_block_of_name(s, block, &k))
    TL_ERROR(TL_ERR_NOT_FOUND, "solid: no element block '%s' for the body force", block);
  return add_body(s, k, 0, b, amp, ctx);
}

TlStatus tl_solid_add_gravity(TlSolid *s, TlVec3 g)
{
  TL_CHECK(tl_solid_not_after_setup(s, "add_gravity"));
  return add_body(s, -1, 1, g, NULL, NULL);
}

static TlStatus add_surface(TlSolid *s, const char *face_set, int pressure, TlVec3 t, double p,
                            TlAmplitude amp, void *ctx)
{
  TL_CHECK(tl_solid_not_after_setup(s, "add_traction/add_pressure"));
  const TlFaceSet *fs = NULL;
  TL_CHECK(tl_mesh_find_face_set(s->mesh, face_set, &fs));
  if (!tl_v3_isfinite(t) || !isfinite(p))
    TL_ERROR(TL_ERR_ARG, "solid: load on face set %s is not finite", face_set);
  TL_CHECK(tl_realloc(&s->surface, s->n_surface + 1, sizeof *s->surface));
  s->surface[s->n_surface++] =
      (SurfaceLoad){(int)(fs - s->mesh->face_sets), pressure, t, p, amp, ctx};
  return TL_OK;
}

TlStatus tl_solid_add_traction(TlSolid *s, const char *face_set, TlVec3 t, TlAmplitude amp, void *ctx)
{
  return add_surface(s, face_set, 0, t, 0.0, amp, ctx);
}

TlStatus tl_solid_add_pressure(TlSolid *s, const char *face_set, double p, TlAmplitude amp, void *ctx)
{
  return add_surface(s, face_set, 1, tl_v3(0, 0, 0), p, amp, ctx);
}

TlStatus tl_solid_add_point_force(TlSolid *s, size_t node, TlVec3 f, TlAmplitude amp, void *ctx)
{
  TL_CHECK(tl_solid_not_after_setup(s, "add_point_force"));
  if (node >= s->n_nodes)
    TL_ERROR(TL_ERR_ARG, "solid: point force on node %zu, the mesh has %zu nodes", node, s->n_nodes);
  if (!tl_v3_isfinite(f)) TL_ERROR(TL_ERR_ARG, "solid: point force on node %zu is not finite", node);
  TL_CHECK(tl_array_reserve(&s->points, &s->cap_points, s->n_points + 1, sizeof *s->points));
  s->points[s->n_points++] = (PointForce){node, f, amp, ctx};
  return TL_OK;
}

TlStatus tl_solid_fix(TlSolid *s, const char *node_set, int mask)
{
  TL_CHECK(tl_solid_not_after_setup(s, "fix"));
  const TlNodeSet *ns = NULL;
  TL_CHECK(tl_mesh_find_node_set(s->mesh, node_set, &ns));
  if (mask <= 0 || mask >= (1 << s->dim))
    TL_ERROR(TL_ERR_ARG, "solid: component mask %d for node set %s outside [1, %d]", mask, node_set,
             (1 << s->dim) - 1);
  for (size_t i = 0; i < ns->n; ++i)
    for (int c = 0; c < s->dim; ++c)
      if (mask & (1 << c)) {
        unsigned char *k = &s->constraint[ns->nodes[i] * s->dim + c];
        if (*k == 2)
          TL_ERROR(TL_ERR_ARG, "solid: node %zu component %d of set %s is both fixed and prescribed",
                   ns->nodes[i], c, node_set);
        *k = 1;
      }
  note_set(s, node_set);
  return TL_OK;
}

TlStatus tl_solid_prescribe(TlSolid *s, const char *node_set, int component, TlPrescribed fn, void *ctx)
{
  TL_CHECK(tl_solid_not_after_setup(s, "prescribe"));
  const TlNodeSet *ns = NULL;
  TL_CHECK(tl_mesh_find_node_set(s->mesh, node_set, &ns));
  if (component < 0 || component >= s->dim)
    TL_ERROR(TL_ERR_ARG, "solid: component %d for node set %s outside [0, %d]", component, node_set,
             s->dim - 1);
  if (!fn) TL_ERROR(TL_ERR_ARG, "solid: NULL prescribed function for node set %s", node_set);
  for (size_t i = 0; i < ns->n; ++i) {
    unsigned char *k = &s->constraint[ns->nodes[i] * s->dim + component];
    if (*k)
      TL_ERROR(TL_ERR_ARG, "solid: node %zu component %d of set %s is already constrained",
               ns->nodes[i], component, node_set);
    *k = 2;
    TL_CHECK(tl_array_reserve(&s->prescribed, &s->cap_prescribed, s->n_prescribed + 1,
                              sizeof *s->prescribed));
    s->prescribed[s->n_prescribed++] = (Prescribed){ns->nodes[i], component, fn, ctx};
  }
  note_set(s, node_set);
  return TL_OK;
}

TlStatus tl_solid_matrix_add_nodes(const TlSolid *s, TlSparse *K, int n, const size_t *nodes, double scale,
                                   const double *Ke)
{
  TlSparseIndex dofs[3 * TL_ELEMENT_MAX_NODES * 4];
  int nd = n * s->dim;
  if (nd > (int)(sizeof dofs / sizeof dofs[0]))
    TL_ERROR(TL_ERR_ARG, "solid: matrix block of %d nodes exceeds %d", n, (int)(sizeof dofs / sizeof dofs[0]) / s->dim);
  for (int a = 0; a < n; ++a)
    for (int c = 0; c < s->dim; ++c) dofs[a * s->dim + c] = s->dof[nodes[a] * s->dim + c];
  TL_CHECK(tl_sparse_add_element(K, nd, dofs, scale, Ke));
  return TL_OK;
}

TlStatus tl_solid_setup_dead_loads(TlSolid *s)
{
  int dim = s->dim;
  size_t n = s->n_nodes * dim;
  int count = s->n_body;
  for (int i = 0; i < s->n_surface; ++i) count += !s->surface[i].pressure;
  TL_CHECK(tl_calloc(&s->dead, count ? count : 1, sizeof *s->dead));
  for (int i = 0; i < s->n_body; ++i) {
    const BodyForce *bf = &s->body[i];
    DeadLoad *dl = &s->dead[s->n_dead++];
    dl->amp = bf->amp;
    dl->ctx = bf->ctx;
    TL_CHECK(tl_calloc(&dl->f, n, sizeof(double)));
    for (int b = 0; b < s->mesh->n_blocks; ++b) {
      if (bf->block >= 0 && bf->block != b) continue;
      const TlElementBlock *blk = &s->mesh->blocks[b];
      const SolidBlock *B = &s->blocks[b];
      double scale = bf->gravity ? B->material->density : 1.0;
      double bv[3] = {bf->b.x * scale, bf->b.y * scale, bf->b.z * scale};
      for (size_t e = 0; e < blk->n_elements; ++e)
        for (int p = 0; p < B->qm.n; ++p)
          for (int a = 0; a < B->nn; ++a) {
            double w = B->wdetm[e * B->qm.n + p] * B->Nm[p * B->nn + a];
            size_t node = blk->conn[e * B->nn + a];
            for (int c = 0; c < dim; ++c) dl->f[node * dim + c] += w * bv[c];
          }
    }
  }
  for (int i = 0; i < s->n_surface; ++i) {
    const SurfaceLoad *sl = &s->surface[i];
    if (sl->pressure) continue;
    DeadLoad *dl = &s->dead[s->n_dead++];
    dl->amp = sl->amp;
    dl->ctx = sl->ctx;
    TL_CHECK(tl_calloc(&dl->f, n, sizeof(double)));
    const TlFaceSet *fs = &s->mesh->face_sets[sl->face_set];
    double tv[3] = {sl->t.x, sl->t.y, sl->t.z};
    for (size_t k = 0; k < fs->n; ++k) {
      const TlElementType *ft = s->mesh->blocks[fs->faces[k].block].type->face_type;
      size_t fnodes[TL_ELEMENT_MAX_FACE_NODES];
      double fx[TL_ELEMENT_MAX_FACE_NODES * 3];
      tl_mesh_face_nodes(s->mesh, fs->faces[k], fnodes, fx);
      TlQuadrature q;
      TL_CHECK(tl_element_quadrature(ft, ft->order_mass, &q));
      for (int p = 0; p < q.n; ++p) {
        double N[TL_ELEMENT_MAX_FACE_NODES], nA[3];
        ft->eval(1, q.xi[p], N, NULL);
        tl_element_face_normal(ft, dim, fx, q.xi[p], nA);
        double dA = q.w[p] * sqrt(nA[0] * nA[0] + nA[1] * nA[1] + nA[2] * nA[2]);
        for (int a = 0; a < ft->n_nodes; ++a)
          for (int c = 0; c < dim; ++c) dl->f[fnodes[a] * dim + c] += dA * N[a] * tv[c];
      }
    }
  }
  return TL_OK;
}

static double amplitude(TlAmplitude amp, void *ctx, double t) { return amp ? amp(t, ctx) : 1.0; }

/* Follower pressure on the deformed faces: f_a = -p int N_a n dA with
 * n dA = x_s x x_t (3-D) or (y_s, -x_s) (2-D), and its derivative. */
TlStatus tl_solid_pressure_loads(TlSolid *s, double t, const double *u_nodes, double *f_nodes, double c,
                               TlSparse *K)
{
  int dim = s->dim;
  for (int i = 0; i < s->n_surface; ++i) {
    const SurfaceLoad *sl = &s->surface[i];
    if (!sl->pressure) continue;
    double p = sl->p * amplitude(sl->amp, sl->ctx, t);
    const TlFaceSet *fs = &s->mesh->face_sets[sl->face_set];
    for (size_t k = 0; k < fs->n; ++k) {
      const TlElementType *ft = s->mesh->blocks[fs->faces[k].block].type->face_type;
      int nf = ft->n_nodes, fd = ft->dim;
      size_t fnodes[TL_ELEMENT_MAX_FACE_NODES];
      double x[TL_ELEMENT_MAX_FACE_NODES * 3];
      tl_mesh_face_nodes(s->mesh, fs->faces[k], fnodes, x);
      for (int a = 0; a < nf; ++a)
        for (int c_ = 0; c_ < dim; ++c_) x[3 * a + c_] += u_nodes[fnodes[a] * dim + c_];
      TlQuadrature q;
      TL_CHECK(tl_element_quadrature(ft, ft->order_mass, &q));
      double Kf[(TL_ELEMENT_MAX_FACE_NODES * 3) * (TL_ELEMENT_MAX_FACE_NODES * 3)];
      int nd = nf * dim;
      memset(Kf, 0, sizeof(double) * nd * nd);
      for (int qp = 0; qp < q.n; ++qp) {
        double N[TL_ELEMENT_MAX_FACE_NODES], dN[TL_ELEMENT_MAX_FACE_NODES * 2], nA[3];
        ft->eval(1, q.xi[qp], N, dN);
        tl_element_face_normal(ft, dim, x, q.xi[qp], nA);
        double w = q.w[qp];
        if (f_nodes)
          for (int a = 0; a < nf; ++a)
            for (int c_ = 0; c_ < dim; ++c_) f_nodes[fnodes[a] * dim + c_] -= w * p * N[a] * nA[c_];
        if (!K) continue;
        double ts[3] = {0, 0, 0}, tt[3] = {0, 0, 0};
        for (int a = 0; a < nf; ++a)
          for (int c_ = 0; c_ < 3; ++c_) {
            ts[c_] += x[3 * a + c_] * dN[a * fd];
            if (fd > 1) tt[c_] += x[3 * a + c_] * dN[a * fd + 1];
          }
        for (int b = 0; b < nf; ++b)
          for (int kc = 0; kc < dim; ++kc) {
            /* dn/dx_{b,kc} */
            double dn[3] = {0, 0, 0};
            if (dim == 3) {
              double e[3] = {0, 0, 0};
              e[kc] = 1.0;
              double gs = dN[b * fd], gt = dN[b * fd + 1];
              /* gs (e x tt) + gt (ts x e) */
              dn[0] = gs * (e[1] * tt[2] - e[2] * tt[1]) + gt * (ts[1] * e[2] - ts[2] * e[1]);
              dn[1] = gs * (e[2] * tt[0] - e[0] * tt[2]) + gt * (ts[2] * e[0] - ts[0] * e[2]);
              dn[2] = gs * (e[0] * tt[1] - e[1] * tt[0]) + gt * (ts[0] * e[1] - ts[1] * e[0]);
            } else {
              double gs = dN[b];
              if (kc == 0) dn[1] = -gs;
              else dn[0] = gs;
            }
            for (int a = 0; a < nf; ++a)
              for (int ic = 0; ic < dim; ++ic) Kf[(a * dim + ic) * nd + b * dim + kc] -= w * p * N[a] * dn[ic];
          }
      }
      if (K) {
        TlSparseIndex dofs[TL_ELEMENT_MAX_FACE_NODES * 3];
        for (int a = 0; a < nf; ++a)
          for (int c_ = 0; c_ < dim; ++c_) dofs[a * dim + c_] = s->dof[fnodes[a] * dim + c_];
        TL_CHECK(tl_sparse_add_element(K, nd, dofs, c, Kf));
      }
    }
  }
  return TL_OK;
}

TlStatus tl_solid_external_nodes(TlSolid *s, double t, const double *u, double *f_nodes)
{
  size_t nc = s->n_nodes * s->dim;
  memset(f_nodes, 0, nc * sizeof(double));
  for (int i = 0; i < s->n_dead; ++i) {
    double a = amplitude(s->dead[i].amp, s->dead[i].ctx, t);
    if (a == 0.0) continue;
    for (size_t k = 0; k < nc; ++k) f_nodes[k] += a * s->dead[i].f[k];
  }
  for (size_t i = 0; i < s->n_points; ++i) {
    const PointForce *pf = &s->points[i];
    double a = amplitude(pf->amp, pf->ctx, t);
    double fv[3] = {pf->f.x, pf->f.y, pf->f.z};
    for (int c = 0; c < s->dim; ++c) f_nodes[pf->node * s->dim + c] += a * fv[c];
  }
  /* Follower (pressure) loads and the wrappers' loads need the deformed
   * state. */
  int follower = 0, wrapped = tl_solid_has_wrapper_loads(s);
  for (int i = 0; i < s->n_surface; ++i) follower |= s->surface[i].pressure;
  if (!follower && !wrapped) return TL_OK;
  tl_solid_dofs_to_nodes(s, u, s->un);
  if (follower) TL_CHECK(tl_solid_pressure_loads(s, t, s->un, f_nodes, 0.0, NULL));
  if (wrapped) TL_CHECK(tl_solid_wrapper_loads(s, t, s->un, f_nodes, 0.0, NULL));
  return TL_OK;
}
