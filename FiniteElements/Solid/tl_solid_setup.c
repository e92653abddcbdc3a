/* Set-up of a solid: dof numbering, reference geometry, colours, matrix
 * pattern, masses, scratch. */
#include "tl_solid_private.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <string.h>

#include "tl_memory.h"

/* Greedy colouring of a block's elements so that no two elements of one
 * colour share a node: assembly of one colour is race-free.  Up to
 * TL_SOLID_MAX_COLOURS colours: an unstructured tetrahedral mesh has nodes
 * in 20 to 60 elements, so an element meets a hundred others and greedy
 * colouring in mesh order can pass 64. */
#define TL_SOLID_MAX_COLOURS 256
#define COLOUR_WORDS (TL_SOLID_MAX_COLOURS / 64)
static TlStatus colour_block(const TlSolid *s, const TlElementBlock *blk, SolidBlock *B)
{
  uint64_t *used = NULL;
  int *colour = NULL;
  size_t *fill = NULL;
  TlStatus st = TL_OK;
  TL_CHECK_GOTO(st, tl_calloc(&used, COLOUR_WORDS * s->n_nodes, sizeof *used), done);
  TL_CHECK_GOTO(st, tl_calloc(&colour, blk->n_elements ? blk->n_elements : 1, sizeof *colour), done);
  int nn = blk->type->n_nodes, nc = 0;
  for (size_t e = 0; e < blk->n_elements; ++e) {
    uint64_t forbidden[COLOUR_WORDS] = {0};
    for (int a = 0; a < nn; ++a)
      for (int w = 0; w < COLOUR_WORDS; ++w) forbidden[w] |= used[COLOUR_WORDS * blk->conn[e * nn + a] + w];
    int c = 0;
    while (c < TL_SOLID_MAX_COLOURS && (forbidden[c / 64] >> (c % 64) & 1u)) ++c;
    if (c == TL_SOLID_MAX_COLOURS) {
      st = tl_error_set(TL_ERR_UNSUPPORTED, __FILE__, __LINE__,
                        "block %s: element %zu needs more than %d colours (too many elements per node)",
                        blk->name, e, TL_SOLID_MAX_COLOURS);
      goto done;
    }
    colour[e] = c;
    if (c + 1 > nc) nc = c + 1;
    for (int a = 0; a < nn; ++a) used[COLOUR_WORDS * blk->conn[e * nn + a] + c / 64] |= (uint64_t)1 << (c % 64);
  }
  B->n_colours = nc;
  TL_CHECK_GOTO(st, tl_calloc(&B->colour_ptr, nc + 1, sizeof(size_t)), done);
  TL_CHECK_GOTO(st, tl_calloc(&B->colour_elements, blk->n_elements ? blk->n_elements : 1, sizeof(size_t)), done);
  for (size_t e = 0; e < blk->n_elements; ++e) B->colour_ptr[colour[e] + 1]++;
  for (int c = 0; c < nc; ++c) B->colour_ptr[c + 1] += B->colour_ptr[c];
  TL_CHECK_GOTO(st, tl_calloc(&fill, nc, sizeof *fill), done);
  for (size_t e = 0; e < blk->n_elements; ++e)
    B->colour_elements[B->colour_ptr[colour[e]] + fill[colour[e]]++] = e;
done:
  tl_free(&used);
  tl_free(&colour);
  tl_free(&fill);
  return st;
}

/* Reference geometry of one block: gradients dN/dxi and weights at the
 * stiffness points, weights at the mass points, lumped masses. */
static TlStatus setup_block_geometry(TlSolid *s, int b)
{
  const TlElementBlock *blk = &s->mesh->blocks[b];
  SolidBlock *B = &s->blocks[b];
  const TlElementType *t = blk->type;
  int dim = s->dim, nn = t->n_nodes;
  TL_CHECK(tl_element_quadrature(t, t->order_stiffness, &B->q));
  TL_CHECK(tl_element_quadrature(t, t->order_mass, &B->qm));
  B->nn = nn;
  B->nd = nn * dim;
  B->symmetric = tl_material_symmetric_tangent(B->material);
  B->nq = B->q.n;
  size_t ne = blk->n_elements ? blk->n_elements : 1;
  TL_CHECK(tl_calloc(&B->grad, ne * B->nq * nn * dim, sizeof(double)));
  if (dim == 3) TL_CHECK(tl_calloc(&B->grad_t, ne * B->nq * nn * 3, sizeof(double)));
  if (dim == 3) TL_CHECK(tl_calloc(&B->grad_n, ne * B->nq * nn * 3, sizeof(double)));
  TL_CHECK(tl_calloc(&B->wdet, ne * B->nq, sizeof(double)));
  TL_CHECK(tl_calloc(&B->Nm, (size_t)B->qm.n * nn, sizeof(double)));
  TL_CHECK(tl_calloc(&B->wdetm, ne * B->qm.n, sizeof(double)));
  TL_CHECK(tl_calloc(&B->lumped, ne * nn, sizeof(double)));
  double dNq[TL_QUADRATURE_MAX * TL_ELEMENT_MAX_NODES * 3];
  double dNm[TL_QUADRATURE_MAX * TL_ELEMENT_MAX_NODES * 3];
  double Nq[TL_QUADRATURE_MAX * TL_ELEMENT_MAX_NODES];
  t->eval(B->q.n, &B->q.xi[0][0], Nq, dNq);
  t->eval(B->qm.n, &B->qm.xi[0][0], B->Nm, dNm);
  double rho = B->material->density;
  if (B->w_nodes) TL_CHECK(tl_solid_interpolate_weights(s, b, Nq));
  if (B->pw) TL_CHECK(tl_calloc(&B->wdet_plain, ne * B->nq, sizeof(double)));
  for (size_t e = 0; e < blk->n_elements; ++e) {
    double x[TL_ELEMENT_MAX_NODES * 3];
    tl_mesh_element_coords(s->mesh, b, e, x);
    for (int pass = 0; pass < 2; ++pass) {
      const TlQuadrature *q = pass ? &B->qm : &B->q;
      const double *dN = pass ? dNm : dNq;
      for (int p = 0; p < q->n; ++p) {
        double J[3][3];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) J[i][j] = (i == j && i >= dim) ? 1.0 : 0.0;
        for (int a = 0; a < nn; ++a)
          for (int i = 0; i < dim; ++i)
            for (int j = 0; j < dim; ++j) J[i][j] += x[3 * a + i] * dN[(p * nn + a) * dim + j];
        TlMat3 Jm, Ji;
        memcpy(Jm.m, J, sizeof J);
        double det = tl_m3_det(Jm);
        if (!(det > 0.0) || !tl_m3_inverse(Jm, &Ji))
          TL_ERROR(TL_ERR_NUMERIC, "block %s element %zu: Jacobian determinant %g at Gauss point %d",
                   blk->name, e, det, p);
        if (pass) {
          B->wdetm[e * q->n + p] = q->w[p] * det * (B->pw_mass ? B->pw_mass[e * q->n + p] : 1.0);
          continue;
        }
        B->wdet[e * B->nq + p] = q->w[p] * det;
        if (B->pw) {
          B->wdet_plain[e * B->nq + p] = B->wdet[e * B->nq + p];
          B->wdet[e * B->nq + p] *= B->pw[e * B->nq + p];
        }
        double *g = B->grad + ((e * B->nq + p) * nn) * dim;
        for (int a = 0; a < nn; ++a)
          for (int d = 0; d < dim; ++d) {
            double v = 0.0;
            for (int j = 0; j < dim; ++j) v += dN[(p * nn + a) * dim + j] * Ji.m[j][d];
            g[a * dim + d] = v;
          }
      }
    }
    if (dim == 3)
      for (int p = 0; p < B->nq; ++p)
        for (int a = 0; a < nn; ++a)
          for (int j = 0; j < 3; ++j)
            B->grad_t[((e * nn + a) * 3 + j) * B->nq + p] = B->grad_n[((e * 3 + j) * B->nq + p) * nn + a] =
                B->grad[((e * B->nq + p) * nn + a) * 3 + j];
    /* HRZ lumping: diagonal of the consistent mass scaled to the element
     * mass; positive for every element type (row sums are not for
     * quadratic serendipity and simplex elements). */
    double diag[TL_ELEMENT_MAX_NODES] = {0}, total = 0.0, dsum = 0.0;
    for (int p = 0; p < B->qm.n; ++p) {
      double w = rho * B->wdetm[e * B->qm.n + p];
      total += w;
      for (int a = 0; a < nn; ++a) diag[a] += w * B->Nm[p * nn + a] * B->Nm[p * nn + a];
    }
    for (int a = 0; a < nn; ++a) dsum += diag[a];
    /* an element weighted out entirely has no mass */
    for (int a = 0; a < nn; ++a) B->lumped[e * nn + a] = dsum > 0.0 ? diag[a] * total / dsum : 0.0;
  }
  return TL_OK;
}

TlStatus tl_solid_setup(TlSolid *s)
{
  if (s->ready) return TL_OK;
  const TlMesh *mesh = s->mesh;
  int dim = s->dim;
  int symmetric = 1;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    if (!s->blocks[b].material)
      TL_ERROR(TL_ERR_STATE, "solid: element block '%s' has no material", mesh->blocks[b].name);
    TlMaterial *m = s->blocks[b].material;
    if (!m->ready) TL_CHECK(tl_material_setup(m));
    symmetric &= tl_material_symmetric_tangent(m);
  }
  for (int i = 0; i < s->n_surface; ++i) symmetric &= !s->surface[i].pressure;
  /* Without path-dependent state the system has no commit or rollback
   * (the contract's "elastic"): a stepper then need not evaluate the
   * accepted iterate to commit its trial state. */
  int stateful = 0;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlMaterial *m = s->blocks[b].material;
    stateful |= m->state_size > 0 || m->ops->commit || m->ops->rollback;
  }
  s->base.ops = stateful ? &tl_solid_ops_stateful : &tl_solid_ops_elastic;
  /* Dof numbering. */
  size_t nc = s->n_nodes * dim;
  TL_CHECK(tl_calloc(&s->dof, nc, sizeof *s->dof));
  TlSparseIndex ndof = 0, ndir = 0;
  size_t *root = NULL;
  if (s->tie_master) {
    /* Tied nodes (tl_solid_tie) take the dofs of their root node, whose
     * boundary conditions they must share. */
    TL_CHECK(tl_calloc(&root, s->n_nodes, sizeof *root));
    TlStatus st = tl_solid_tie_roots(s, root);
    for (size_t i = 0; st == TL_OK && i < nc; ++i) {
      size_t r = root[i / dim] * dim + i % dim;
      if (s->constraint[i] != s->constraint[r])
        st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                          "solid: component %zu of node %zu is %s but its periodic master, node %zu, is %s: tied "
                          "nodes must share their boundary conditions",
                          i % dim, i / dim, s->constraint[i] == 1 ? "clamped" : s->constraint[i] == 2 ? "prescribed" : "free",
                          r / dim, s->constraint[r] == 1 ? "clamped" : s->constraint[r] == 2 ? "prescribed" : "free");
    }
    if (st) {
      tl_free(&root);
      return st;
    }
  }
  for (size_t i = 0; i < nc; ++i) {
    if (root && root[i / dim] != i / dim) continue;
    s->dof[i] = s->constraint[i] == 1 ? -1 : ndof++;
    ndir += s->constraint[i] == 2;
  }
  if (root)
    for (size_t i = 0; i < nc; ++i)
      if (root[i / dim] != i / dim) s->dof[i] = s->dof[root[i / dim] * dim + i % dim];
  if (ndof == 0) {
    tl_free(&root);
    TL_ERROR(TL_ERR_ARG, "solid: every dof is clamped, nothing to solve");
  }
  TlStatus sd = tl_calloc(&s->base.dirichlet_dofs, ndir ? ndir : 1, sizeof(TlSparseIndex));
  if (sd) {
    tl_free(&root);
    return sd;
  }
  for (size_t i = 0, k = 0; i < nc; ++i)
    if (s->constraint[i] == 2 && !(root && root[i / dim] != i / dim)) s->base.dirichlet_dofs[k++] = s->dof[i];
  tl_free(&root);
  s->base.ndof = ndof;
  s->base.n_dirichlet = ndir;
  s->base.symmetric = symmetric;
  s->base.damped = 0;
  /* Geometry, state, colours, element dof lists. */
  s->n_elements = 0;
  s->max_nd = 0;
  s->max_nq = 0;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    TL_CHECK(setup_block_geometry(s, b));
    TL_CHECK(colour_block(s, &mesh->blocks[b], B));
    B->offset = s->n_elements;
    s->n_elements += mesh->blocks[b].n_elements;
    if (B->nd > s->max_nd) s->max_nd = B->nd;
    if (B->nq > s->max_nq) s->max_nq = B->nq;
    size_t ss = B->material->state_size, nst = mesh->blocks[b].n_elements * B->nq;
    if (ss) {
      TL_CHECK(tl_calloc(&B->state_old, nst * ss, sizeof(double)));
      TL_CHECK(tl_calloc(&B->state_new, nst * ss, sizeof(double)));
      if (B->material->ops->init_state) TL_CHECK(B->material->ops->init_state(B->material, nst, B->state_old));
      memcpy(B->state_new, B->state_old, nst * ss * sizeof(double));
    }
  }
  size_t total = 0;
  s->n_pattern = s->n_elements;
  TL_CHECK(tl_calloc(&s->elem_ptr, s->n_pattern + 1, sizeof(TlSparseIndex)));
  for (int b = 0; b < mesh->n_blocks; ++b) total += mesh->blocks[b].n_elements * s->blocks[b].nd;
  TL_CHECK(tl_calloc(&s->elem_dofs, total ? total : 1, sizeof(TlSparseIndex)));
  size_t k = 0, g = 0;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    for (size_t e = 0; e < blk->n_elements; ++e, ++g) {
      s->elem_ptr[g] = (TlSparseIndex)k;
      for (int a = 0; a < blk->type->n_nodes; ++a)
        for (int c = 0; c < dim; ++c) s->elem_dofs[k++] = s->dof[blk->conn[e * blk->type->n_nodes + a] * dim + c];
    }
  }
  s->elem_ptr[g] = (TlSparseIndex)k;
  /* Lumped masses. */
  TL_CHECK(tl_calloc(&s->lumped_nodes, nc, sizeof(double)));
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    const SolidBlock *B = &s->blocks[b];
    for (size_t e = 0; e < blk->n_elements; ++e)
      for (int a = 0; a < B->nn; ++a)
        for (int c = 0; c < dim; ++c) s->lumped_nodes[blk->conn[e * B->nn + a] * dim + c] += B->lumped[e * B->nn + a];
  }
  if (s->lumped_weights)
    for (size_t i = 0; i < nc; ++i) s->lumped_nodes[i] *= s->lumped_weights[i / dim];
  for (size_t i = 0; i < nc; ++i)
    if (!(s->lumped_nodes[i] > 0.0))
      TL_ERROR(TL_ERR_ARG, "solid: node %zu has zero mass: it belongs to no element, or the weights of every "
               "element around it vanish", i / dim);
  TL_CHECK(tl_solid_setup_dead_loads(s));
  TL_CHECK(tl_calloc(&s->un, nc, sizeof(double)));
  TL_CHECK(tl_calloc(&s->fn, nc, sizeof(double)));
  TL_CHECK(tl_calloc(&s->gn, nc, sizeof(double)));
  /* Per-thread scratch. */
  s->n_threads = omp_get_max_threads();
  TL_CHECK(tl_calloc(&s->scratch, s->n_threads, sizeof *s->scratch));
  size_t maxss = 0;
  for (int b = 0; b < mesh->n_blocks; ++b)
    if (s->blocks[b].material->state_size > maxss) maxss = s->blocks[b].material->state_size;
  size_t npts = (size_t)CHUNK * s->max_nq, nd = s->max_nd;
  /* DB also holds the nn x nn consistent element mass (tl_solid_system.c),
   * larger than 6 nd for elements of more than 6 dim nodes (Hex27: 729 > 486). */
  size_t ndb = 6 * nd;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    size_t nn = (size_t)s->blocks[b].nn;
    if (nn * nn > ndb) ndb = nn * nn;
  }
  for (int t = 0; t < s->n_threads; ++t) {
    Scratch *w = &s->scratch[t];
    TL_CHECK(tl_calloc(&w->F, npts, sizeof(TlMat3)));
    TL_CHECK(tl_calloc(&w->S, npts, sizeof(TlMat3)));
    TL_CHECK(tl_calloc(&w->Hsoa, 9 * npts, sizeof(double)));
    TL_CHECK(tl_calloc(&w->Ssoa, 6 * npts, sizeof(double)));
    TL_CHECK(tl_calloc(&w->D, 36 * npts, sizeof(double)));
    TL_CHECK(tl_calloc(&w->W, npts, sizeof(double)));
    TL_CHECK(tl_calloc(&w->state_old, npts * (maxss ? maxss : 1), sizeof(double)));
    TL_CHECK(tl_calloc(&w->state_new, npts * (maxss ? maxss : 1), sizeof(double)));
    TL_CHECK(tl_calloc(&w->fe, nd, sizeof(double)));
    TL_CHECK(tl_calloc(&w->Ke, nd * nd, sizeof(double)));
    TL_CHECK(tl_calloc(&w->B, 6 * nd, sizeof(double)));
    TL_CHECK(tl_calloc(&w->DB, ndb, sizeof(double)));
    TL_CHECK(tl_calloc(&w->ue, nd, sizeof(double)));
    TL_CHECK(tl_calloc(&w->dofs, nd, sizeof(TlSparseIndex)));
  }
  s->ready = 1;
  return TL_OK;
}
