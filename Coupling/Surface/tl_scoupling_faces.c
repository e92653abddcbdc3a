/* SCoupling faces of any element type: wall pieces and CG quadrature. */
#include "tl_scoupling_faces.h"

#include <math.h>
#include <string.h>
#include "tl_memory.h"

/* Index of the wall vertex at reference point (s, t): a face node there, an
 * extra point already made, or a new extra point. */
static TlStatus point_index(TlSCouplingFaceType *ft, double s, double t, int *index)
{
  const double *ref = ft->type->ref_coords;
  for (int a = 0; a < ft->nf; ++a)
    if (fabs(ref[2 * a] - s) < 1e-12 && fabs(ref[2 * a + 1] - t) < 1e-12) return *index = a, TL_OK;
  for (int k = 0; k < ft->n_extra; ++k)
    if (fabs(ft->extra_ref[k][0] - s) < 1e-12 && fabs(ft->extra_ref[k][1] - t) < 1e-12) return *index = ft->nf + k, TL_OK;
  if (ft->n_extra == TL_SCOUPLING_MAX_EXTRA)
    TL_ERROR(TL_ERR_UNSUPPORTED, "face type '%s' needs more than %d interpolated wall vertices", ft->type->header.name,
             TL_SCOUPLING_MAX_EXTRA);
  ft->extra_ref[ft->n_extra][0] = s;
  ft->extra_ref[ft->n_extra][1] = t;
  *index = ft->nf + ft->n_extra++;
  return TL_OK;
}

static TlStatus add_piece(TlSCouplingFaceType *ft, const double p[3][2])
{
  if (ft->n_pieces == TL_SCOUPLING_MAX_PIECES)
    TL_ERROR(TL_ERR_UNSUPPORTED, "face type '%s' needs more than %d wall triangles", ft->type->header.name,
             TL_SCOUPLING_MAX_PIECES);
  for (int k = 0; k < 3; ++k) TL_CHECK(point_index(ft, p[k][0], p[k][1], &ft->piece[ft->n_pieces][k]));
  ft->n_pieces++;
  return TL_OK;
}

/* A quadrilateral cell of the reference face (counter-clockwise corners) as
 * four triangles around its centre. */
static TlStatus add_quad_cell(TlSCouplingFaceType *ft, const double c[4][2])
{
  double m[2] = {0.25 * (c[0][0] + c[1][0] + c[2][0] + c[3][0]), 0.25 * (c[0][1] + c[1][1] + c[2][1] + c[3][1])};
  for (int k = 0; k < 4; ++k) {
    const double p[3][2] = {{c[k][0], c[k][1]}, {c[(k + 1) % 4][0], c[(k + 1) % 4][1]}, {m[0], m[1]}};
    TL_CHECK(add_piece(ft, p));
  }
  return TL_OK;
}

static TlStatus build_pieces(TlSCouplingFaceType *ft)
{
  const TlElementType *t = ft->type;
  if (t->shape == TL_SHAPE_TRI && t->n_nodes == 3) {
    const double p[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    TL_CHECK(add_piece(ft, p));
  } else if (t->shape == TL_SHAPE_TRI && t->n_nodes == 6) {
    const double sub[4][3][2] = {{{0, 0}, {0.5, 0}, {0, 0.5}},
                                 {{0.5, 0}, {1, 0}, {0.5, 0.5}},
                                 {{0, 0.5}, {0.5, 0.5}, {0, 1}},
                                 {{0.5, 0}, {0.5, 0.5}, {0, 0.5}}};
    for (int k = 0; k < 4; ++k) TL_CHECK(add_piece(ft, sub[k]));
  } else if (t->shape == TL_SHAPE_QUAD && t->n_nodes == 4) {
    const double c[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    TL_CHECK(add_quad_cell(ft, c));
  } else if (t->shape == TL_SHAPE_QUAD && (t->n_nodes == 8 || t->n_nodes == 9)) {
    const double cells[4][4][2] = {{{-1, -1}, {0, -1}, {0, 0}, {-1, 0}},
                                   {{0, -1}, {1, -1}, {1, 0}, {0, 0}},
                                   {{0, 0}, {1, 0}, {1, 1}, {0, 1}},
                                   {{-1, 0}, {0, 0}, {0, 1}, {-1, 1}}};
    for (int k = 0; k < 4; ++k) TL_CHECK(add_quad_cell(ft, cells[k]));
  } else {
    TL_ERROR(TL_ERR_UNSUPPORTED, "surface coupling has no wall pieces for face type '%s' (%d nodes)", t->header.name,
             t->n_nodes);
  }
  double xi[TL_SCOUPLING_MAX_EXTRA * 3] = {0};
  for (int k = 0; k < ft->n_extra; ++k) xi[3 * k] = ft->extra_ref[k][0], xi[3 * k + 1] = ft->extra_ref[k][1];
  double N[TL_SCOUPLING_MAX_EXTRA * TL_ELEMENT_MAX_FACE_NODES];
  if (ft->n_extra) t->eval(ft->n_extra, xi, N, NULL);
  for (int k = 0; k < ft->n_extra; ++k)
    for (int a = 0; a < ft->nf; ++a) ft->extra_N[k][a] = N[k * ft->nf + a];
  return TL_OK;
}

/* Points and weights of the sub-cell rule on the reference face. */
static TlStatus build_quadrature(TlSCouplingFaceType *ft)
{
  const TlElementType *t = ft->type;
  TlQuadrature rule;
  TL_CHECK(tl_element_quadrature(t, 3, &rule));
  const int s = ft->subdivisions, nf = ft->nf;
  const int cells = s * s; /* squares, or up and down triangles */
  ft->nq = cells * rule.n;
  double *xi = NULL;
  TL_CHECK(tl_calloc(&ft->w_ref, (size_t)ft->nq, sizeof(double)));
  TL_CHECK(tl_calloc(&ft->N, (size_t)ft->nq * (size_t)nf, sizeof(double)));
  TL_CHECK(tl_calloc(&ft->dN, (size_t)ft->nq * (size_t)nf * 2, sizeof(double)));
  TL_CHECK(tl_calloc(&xi, (size_t)ft->nq * 3, sizeof(double)));
  int q = 0;
  const double scale = 1.0 / (double)(s * s);
  if (t->shape == TL_SHAPE_QUAD) {
    for (int i = 0; i < s; ++i)
      for (int j = 0; j < s; ++j)
        for (int g = 0; g < rule.n; ++g, ++q) {
          xi[3 * q] = -1.0 + (2.0 * i + 1.0 + rule.xi[g][0]) / s;
          xi[3 * q + 1] = -1.0 + (2.0 * j + 1.0 + rule.xi[g][1]) / s;
          ft->w_ref[q] = rule.w[g] * scale;
        }
  } else {
    for (int i = 0; i < s; ++i)
      for (int j = 0; i + j < s; ++j)
        for (int up = 1; up >= 0; --up) {
          if (!up && i + j >= s - 1) continue;
          /* up: (i, j) (i+1, j) (i, j+1); down: (i+1, j+1) (i, j+1) (i+1, j) */
          double A[2] = {up ? i : i + 1.0, up ? j : j + 1.0};
          double B[2] = {up ? i + 1.0 : i, up ? j : j + 1.0};
          double C[2] = {up ? i : i + 1.0, up ? j + 1.0 : j};
          for (int g = 0; g < rule.n; ++g, ++q) {
            const double a = rule.xi[g][0], b = rule.xi[g][1];
            xi[3 * q] = (A[0] + (B[0] - A[0]) * a + (C[0] - A[0]) * b) / s;
            xi[3 * q + 1] = (A[1] + (B[1] - A[1]) * a + (C[1] - A[1]) * b) / s;
            ft->w_ref[q] = rule.w[g] * scale;
          }
        }
  }
  if (q != ft->nq) {
    tl_free(&xi);
    TL_ERROR(TL_ERR_STATE, "face quadrature: %d points made, %d expected", q, ft->nq);
  }
  t->eval(ft->nq, xi, ft->N, ft->dN);
  tl_free(&xi);
  return TL_OK;
}

TlStatus tl_scoupling_face_type_create(const TlElementType *face_type, int subdivisions, TlSCouplingFaceType **out)
{
  *out = NULL;
  if (!face_type || face_type->dim != 2 || !face_type->eval)
    TL_ERROR(TL_ERR_ARG, "surface coupling needs a 2-D face type (got '%s')", face_type ? face_type->header.name : "none");
  if (subdivisions < 1 || subdivisions > 64) TL_ERROR(TL_ERR_ARG, "CG subdivisions %d outside [1, 64]", subdivisions);
  TlSCouplingFaceType *ft;
  TL_CHECK(TL_NEW(ft));
  ft->type = face_type;
  ft->nf = face_type->n_nodes;
  ft->subdivisions = subdivisions;
  TlStatus s = build_pieces(ft);
  if (s == TL_OK) s = build_quadrature(ft);
  if (s != TL_OK) {
    tl_scoupling_face_type_destroy(&ft);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  *out = ft;
  return TL_OK;
}

void tl_scoupling_face_type_destroy(TlSCouplingFaceType **pft)
{
  TlSCouplingFaceType *ft = *pft;
  if (!ft) return;
  tl_free(&ft->w_ref);
  tl_free(&ft->N);
  tl_free(&ft->dN);
  tl_free(pft);
}

/* ---- the CG surface plug-in ------------------------------------------- */

static TlStatus faces_quadrature(const TlCGSurface *s, size_t n, const size_t *faces, TlVec3 *xq, double *wq,
                                 double *Nq)
{
  const TlSCouplingFaceType *ft = s->context;
  const int nf = ft->nf, nq = ft->nq;
  for (size_t k = 0; k < n; ++k) {
    const size_t f = faces ? faces[k] : k;
    const int *fn = s->face_node + f * (size_t)nf;
    for (int q = 0; q < nq; ++q) {
      const double *N = ft->N + (size_t)q * nf, *dN = ft->dN + (size_t)q * nf * 2;
      TlVec3 x = tl_v3(0, 0, 0), t1 = tl_v3(0, 0, 0), t2 = tl_v3(0, 0, 0);
      for (int a = 0; a < nf; ++a) {
        const TlVec3 xa = s->x[fn[a]];
        x = tl_v3_axpy(x, N[a], xa);
        t1 = tl_v3_axpy(t1, dN[2 * a], xa);
        t2 = tl_v3_axpy(t2, dN[2 * a + 1], xa);
      }
      const size_t slot = f * (size_t)nq + (size_t)q;
      xq[slot] = x;
      wq[slot] = ft->w_ref[q] * tl_v3_norm(tl_v3_cross(t1, t2));
      memcpy(Nq + slot * (size_t)nf, N, (size_t)nf * sizeof *N);
    }
  }
  return TL_OK;
}

/* The point of the curved face nearest to p, by Gauss-Newton from the
 * face's centre, kept inside the reference face. */
static void project(const TlSCouplingFaceType *ft, const TlVec3 *x, TlVec3 p, double xi[3], double *N)
{
  const TlElementType *t = ft->type;
  const int nf = ft->nf;
  double dN[2 * TL_ELEMENT_MAX_FACE_NODES];
  xi[0] = xi[1] = t->shape == TL_SHAPE_TRI ? 1.0 / 3.0 : 0.0;
  xi[2] = 0.0;
  for (int it = 0; it < 30; ++it) {
    t->eval(1, xi, N, dN);
    TlVec3 y = tl_v3(0, 0, 0), t1 = tl_v3(0, 0, 0), t2 = tl_v3(0, 0, 0);
    for (int a = 0; a < nf; ++a) {
      y = tl_v3_axpy(y, N[a], x[a]);
      t1 = tl_v3_axpy(t1, dN[2 * a], x[a]);
      t2 = tl_v3_axpy(t2, dN[2 * a + 1], x[a]);
    }
    const TlVec3 r = tl_v3_sub(p, y);
    const double a11 = tl_v3_dot(t1, t1), a12 = tl_v3_dot(t1, t2), a22 = tl_v3_dot(t2, t2);
    const double b1 = tl_v3_dot(t1, r), b2 = tl_v3_dot(t2, r), det = a11 * a22 - a12 * a12;
    if (!(det > 0.0)) break;
    const double d1 = (a22 * b1 - a12 * b2) / det, d2 = (a11 * b2 - a12 * b1) / det;
    xi[0] += d1, xi[1] += d2;
    if (t->shape == TL_SHAPE_QUAD) {
      xi[0] = tl_min(1.0, tl_max(-1.0, xi[0]));
      xi[1] = tl_min(1.0, tl_max(-1.0, xi[1]));
    } else {
      xi[0] = tl_max(0.0, xi[0]), xi[1] = tl_max(0.0, xi[1]);
      if (xi[0] + xi[1] > 1.0) {
        const double sum = xi[0] + xi[1];
        xi[0] /= sum, xi[1] /= sum;
      }
    }
    if (fabs(d1) + fabs(d2) < 1e-14) break;
  }
  t->eval(1, xi, N, NULL);
}

static TlStatus faces_shape_at(const TlCGSurface *s, size_t n, const size_t *face, const TlVec3 *point, double *Nout)
{
  const TlSCouplingFaceType *ft = s->context;
  const int nf = ft->nf;
  TlVec3 x[TL_ELEMENT_MAX_FACE_NODES];
  for (size_t k = 0; k < n; ++k) {
    const int *fn = s->face_node + face[k] * (size_t)nf;
    for (int a = 0; a < nf; ++a) x[a] = s->x[fn[a]];
    double xi[3];
    project(ft, x, point[k], xi, Nout + k * (size_t)nf);
  }
  return TL_OK;
}

static const TlCGSurfaceOps tl_cg_surface_element_face_ops = {
    .header = {TL_CG_SURFACE_KIND, "element_faces", "faces of any finite-element face type, through its shape functions"},
    .quadrature = faces_quadrature,
    .shape_at = faces_shape_at,
};

/* A plug-in surface with its quadrature computed. */
static TlStatus create_updated(const TlCGSurfaceOps *ops, size_t n_nodes, const TlVec3 *x, size_t n, int per_item,
                               const int *item_node, int nq, const void *context, int subdivisions, TlCGSurface **surface)
{
  TL_CHECK(tl_cg_surface_create(ops, n_nodes, x, n, per_item, item_node, nq, (void *)context, surface));
  (*surface)->subdivisions = subdivisions;
  TlStatus s = tl_cg_surface_update(*surface, NULL);
  if (s != TL_OK) {
    tl_cg_surface_destroy(surface);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}

TlStatus tl_cg_surface_create_element_faces(const TlSCouplingFaceType *ft, size_t n_nodes, const TlVec3 *x,
                                            size_t n_faces, const int *face_node, TlCGSurface **surface)
{
  return create_updated(&tl_cg_surface_element_face_ops, n_nodes, x, n_faces, ft->nf, face_node, ft->nq, ft,
                        ft->subdivisions, surface);
}

/* ---- the SCoupling elements as the CG support -------------------------- */

TlStatus tl_scoupling_volume_type_create(const TlElementType *type, TlSCouplingVolumeType **out)
{
  *out = NULL;
  if (!type || type->dim != 3)
    TL_ERROR(TL_ERR_UNSUPPORTED, "element CG support needs a 3-D solid element type (got %s)", type ? type->header.name : "none");
  TlQuadrature rule;
  TL_CHECK(tl_element_quadrature(type, type->order_stiffness, &rule));
  TlSCouplingVolumeType *vt = NULL;
  TL_CHECK(TL_NEW(vt));
  vt->type = type;
  vt->ne = type->n_nodes;
  vt->nq = rule.n;
  memcpy(vt->w_ref, rule.w, (size_t)rule.n * sizeof *rule.w);
  TlStatus s = TL_OK;
  if ((s = tl_calloc(&vt->N, (size_t)vt->nq * (size_t)vt->ne, sizeof *vt->N)) != TL_OK ||
      (s = tl_calloc(&vt->dN, (size_t)vt->nq * (size_t)vt->ne * 3, sizeof *vt->dN)) != TL_OK) {
    tl_scoupling_volume_type_destroy(&vt);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  type->eval(rule.n, &rule.xi[0][0], vt->N, vt->dN);
  *out = vt;
  return TL_OK;
}

void tl_scoupling_volume_type_destroy(TlSCouplingVolumeType **pvt)
{
  if (!pvt || !*pvt) return;
  tl_free(&(*pvt)->N);
  tl_free(&(*pvt)->dN);
  tl_free(pvt);
}

static TlStatus volumes_quadrature(const TlCGSurface *s, size_t n, const size_t *elems, TlVec3 *xq, double *wq,
                                   double *Nq)
{
  const TlSCouplingVolumeType *vt = s->context;
  const int ne = vt->ne, nq = vt->nq;
  for (size_t k = 0; k < n; ++k) {
    const size_t e = elems ? elems[k] : k;
    const int *en = s->face_node + e * (size_t)ne;
    for (int q = 0; q < nq; ++q) {
      const double *N = vt->N + (size_t)q * ne, *dN = vt->dN + (size_t)q * ne * 3;
      TlVec3 x = tl_v3(0, 0, 0);
      double J[3][3] = {{0}};
      for (int a = 0; a < ne; ++a) {
        const TlVec3 xa = s->x[en[a]];
        x = tl_v3_axpy(x, N[a], xa);
        const double c[3] = {xa.x, xa.y, xa.z};
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) J[i][j] += c[i] * dN[3 * a + j];
      }
      const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
      if (!(det > 0.0))
        TL_ERROR(TL_ERR_NUMERIC, "CG support element %zu: det J = %g at integration point %d (inverted element)", e, det, q);
      const size_t slot = e * (size_t)nq + (size_t)q;
      xq[slot] = x;
      wq[slot] = vt->w_ref[q] * det;
      memcpy(Nq + slot * (size_t)ne, N, (size_t)ne * sizeof *N);
    }
  }
  return TL_OK;
}

/* Shape values at a point (the Dirac limit, which the coupling takes on
 * faces instead; here for completeness): the point mapped into the element,
 * clamped to it. */
static TlStatus volumes_shape_at(const TlCGSurface *s, size_t n, const size_t *elem, const TlVec3 *point, double *Nout)
{
  const TlSCouplingVolumeType *vt = s->context;
  const int ne = vt->ne;
  double x[3 * TL_ELEMENT_MAX_NODES];
  for (size_t k = 0; k < n; ++k) {
    const int *en = s->face_node + elem[k] * (size_t)ne;
    for (int a = 0; a < ne; ++a) x[3 * a] = s->x[en[a]].x, x[3 * a + 1] = s->x[en[a]].y, x[3 * a + 2] = s->x[en[a]].z;
    double xi[3] = {0, 0, 0}, p[3] = {point[k].x, point[k].y, point[k].z};
    int inside = 0;
    TL_CHECK(tl_element_inverse_map(vt->type, 3, x, p, xi, &inside));
    vt->type->eval(1, xi, Nout + k * (size_t)ne, NULL);
  }
  return TL_OK;
}

static const TlCGSurfaceOps tl_cg_surface_element_volume_ops = {
    .header = {TL_CG_SURFACE_KIND, "element_volumes", "solid elements, through their integration points"},
    .quadrature = volumes_quadrature,
    .shape_at = volumes_shape_at,
};

TlStatus tl_cg_surface_create_element_volumes(const TlSCouplingVolumeType *vt, size_t n_nodes, const TlVec3 *x,
                                              size_t n_elements, const int *elem_node, TlCGSurface **surface)
{
  return create_updated(&tl_cg_surface_element_volume_ops, n_nodes, x, n_elements, vt->ne, elem_node, vt->nq, vt, 1,
                        surface);
}
