#include "tl_cg_surface.h"

#include <math.h>
#include <string.h>
#include "tl_memory.h"

enum { TL_CG_SURFACE_BATCH = 64 };

/* Scratch kept with the surface so that the per-step calls never allocate. */
typedef struct {
  double *r2, *w;        /* qp_per_face */
  double *g;             /* n_faces x nodes_per_face: unnormalised sums of one contact's candidate faces */
  double *part;          /* n_faces: sum_q w_q W of each candidate face */
  TlVec3 *face_nodal;    /* n_faces x nodes_per_face: per-face forces of tl_cg_surface_nodal_forces */
  unsigned char *face_mark; /* n_faces */
  size_t *face_list;     /* n_faces: the faces marked */
  double *N;             /* TL_CG_SURFACE_BATCH x nodes_per_face */
  /* faces binned by the centre of their box, cells as wide as the widest
   * face, rebuilt at every update: a contact visits the faces near it */
  size_t *cand;          /* n_faces: candidate faces of one query */
  size_t *bin_start, cap_bin_start, *bin_index, *bin_of;
  TlVec3 bin_lo, bin_cell, half_extent;
  int bin_n[3];
  /* faces refreshed by the last tl_cg_surface_update_near */
  size_t *near, n_near;
  int partial;
} TlCGSurfaceScratch;

/* The scratch lives right after the public struct. */
typedef struct {
  TlCGSurface pub;
  TlCGSurfaceScratch scratch;
} TlCGSurfaceImpl;

static TlCGSurfaceScratch *scratch_of(const TlCGSurface *s) { return &((TlCGSurfaceImpl *)s)->scratch; }

/* ------------------------------------------------------------ triangles */

/* Degree-4 six-point rule on a triangle (barycentric coordinates; weights
 * sum to 1). */
static const double tri6_a = 0.445948490915965, tri6_b = 0.091576213509771;
static const double tri6_wa = 0.223381589678011, tri6_wb = 0.109951743655322;

static void tri6_point(int g, double L[3], double *w)
{
  double a = g < 3 ? tri6_a : tri6_b, o = 1.0 - 2.0 * a;
  int k = g % 3;
  L[0] = L[1] = L[2] = a;
  L[k] = o;
  *w = g < 3 ? tri6_wa : tri6_wb;
}

/* Sub-triangle t of the s x s split of the reference triangle (rows of
 * upward triangles, each but the last followed by a downward one): its
 * three corners in (xi, eta). */
static void tri_sub(int s, int t, double P[3][2])
{
  int idx = 0, found = 0;
  double c[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  for (int j = 0; j < s && !found; ++j)
    for (int i = 0; i + j < s && !found; ++i) {
      if (idx++ == t) {
        double up[3][2] = {{i, j}, {i + 1, j}, {i, j + 1}};
        memcpy(c, up, sizeof c);
        found = 1;
      } else if (i + j < s - 1 && idx++ == t) {
        double down[3][2] = {{i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
        memcpy(c, down, sizeof c);
        found = 1;
      }
    }
  for (int a = 0; a < 3; ++a) {
    P[a][0] = c[a][0] / s;
    P[a][1] = c[a][1] / s;
  }
}

static TlStatus tri_quadrature(const TlCGSurface *s, size_t n, const size_t *faces, TlVec3 *xq, double *wq, double *Nq)
{
  int sub = s->subdivisions, nsub = sub * sub;
  for (size_t k = 0; k < n; ++k) {
    const size_t f = faces ? faces[k] : k;
    const int *v = s->face_node + 3 * f;
    TlVec3 X0 = s->x[v[0]], X1 = s->x[v[1]], X2 = s->x[v[2]];
    double area = 0.5 * tl_v3_norm(tl_v3_cross(tl_v3_sub(X1, X0), tl_v3_sub(X2, X0)));
    if (!(area > 0.0))
      TL_ERROR(TL_ERR_NUMERIC, "triangle %zu (nodes %d %d %d) has area %g", f, v[0], v[1], v[2], area);
    size_t slot = f * (size_t)s->qp_per_face;
    for (int t = 0; t < nsub; ++t) {
      double P[3][2];
      tri_sub(sub, t, P);
      for (int g = 0; g < 6; ++g, ++slot) {
        double L[3], w;
        tri6_point(g, L, &w);
        double xi = L[0] * P[0][0] + L[1] * P[1][0] + L[2] * P[2][0];
        double eta = L[0] * P[0][1] + L[1] * P[1][1] + L[2] * P[2][1];
        double *N = Nq + slot * 3;
        N[0] = 1.0 - xi - eta;
        N[1] = xi;
        N[2] = eta;
        xq[slot] = tl_v3_add(tl_v3_add(tl_v3_scale(X0, N[0]), tl_v3_scale(X1, N[1])), tl_v3_scale(X2, N[2]));
        wq[slot] = w * area / nsub;
      }
    }
  }
  return TL_OK;
}

static TlStatus tri_shape_at(const TlCGSurface *s, size_t n, const size_t *face, const TlVec3 *point, double *N)
{
  for (size_t k = 0; k < n; ++k) {
    const int *v = s->face_node + 3 * face[k];
    TlVec3 X0 = s->x[v[0]], e1 = tl_v3_sub(s->x[v[1]], X0), e2 = tl_v3_sub(s->x[v[2]], X0);
    TlVec3 d = tl_v3_sub(point[k], X0);
    /* least squares in the plane: [e1 e2]^T [e1 e2] (xi, eta) = [e1 e2]^T d */
    double a11 = tl_v3_dot(e1, e1), a12 = tl_v3_dot(e1, e2), a22 = tl_v3_dot(e2, e2);
    double b1 = tl_v3_dot(e1, d), b2 = tl_v3_dot(e2, d), det = a11 * a22 - a12 * a12;
    double xi = (a22 * b1 - a12 * b2) / det, eta = (a11 * b2 - a12 * b1) / det;
    double L[3] = {1.0 - xi - eta, xi, eta};
    /* a contact point slightly off the face (round-off) is pulled back */
    double sum = 0.0;
    for (int a = 0; a < 3; ++a) {
      if (L[a] < 0.0) L[a] = 0.0;
      sum += L[a];
    }
    if (!(sum > 0.0) || !isfinite(sum))
      TL_ERROR(TL_ERR_NUMERIC, "contact %zu: no barycentric coordinates on triangle %zu", k, face[k]);
    for (int a = 0; a < 3; ++a) N[k * 3 + a] = L[a] / sum;
  }
  return TL_OK;
}

static const TlCGSurfaceOps tl_cg_surface_triangle_ops = {
    {TL_CG_SURFACE_KIND, "triangle3", "linear triangles, degree-4 rule on s x s sub-triangles"},
    tri_quadrature, tri_shape_at};

/* ------------------------------------------------------- quadrilaterals */

static void quad_shape(double xi, double eta, double N[4], double dxi[4], double deta[4])
{
  N[0] = 0.25 * (1 - xi) * (1 - eta);
  N[1] = 0.25 * (1 + xi) * (1 - eta);
  N[2] = 0.25 * (1 + xi) * (1 + eta);
  N[3] = 0.25 * (1 - xi) * (1 + eta);
  dxi[0] = -0.25 * (1 - eta), dxi[1] = 0.25 * (1 - eta), dxi[2] = 0.25 * (1 + eta), dxi[3] = -0.25 * (1 + eta);
  deta[0] = -0.25 * (1 - xi), deta[1] = -0.25 * (1 + xi), deta[2] = 0.25 * (1 + xi), deta[3] = 0.25 * (1 - xi);
}

/* The bilinear map on sub-squares, written as interpolation between the
 * edges xi = -1 (A) and xi = +1 (B) at each eta: the point, its two tangents
 * and the shape values in a few operations per point, the face's edge
 * differences computed once (the moving faces near contacts are redone at
 * every coupled step). */
static TlStatus quad_quadrature(const TlCGSurface *s, size_t n, const size_t *faces, TlVec3 *xq, double *wq, double *Nq)
{
  static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
  static const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  int sub = s->subdivisions;
  double hs = 1.0 / sub;
  for (size_t i = 0; i < n; ++i) {
    const size_t f = faces ? faces[i] : i;
    const int *v = s->face_node + 4 * f;
    const TlVec3 X0 = s->x[v[0]], X1 = s->x[v[1]], X2 = s->x[v[2]], X3 = s->x[v[3]];
    const TlVec3 d03 = tl_v3_sub(X3, X0), d12 = tl_v3_sub(X2, X1);
    size_t slot = f * (size_t)s->qp_per_face;
    for (int si = 0; si < sub; ++si)
      for (int sj = 0; sj < sub; ++sj)
        for (int gi = 0; gi < 3; ++gi)
          for (int gj = 0; gj < 3; ++gj, ++slot) {
            const double xi = -1.0 + (2.0 * si + 1.0 + gx[gi]) * hs, eta = -1.0 + (2.0 * sj + 1.0 + gx[gj]) * hs;
            const double sx = 0.5 * (1.0 + xi), se = 0.5 * (1.0 + eta);
            const TlVec3 A = tl_v3_axpy(X0, se, d03), B = tl_v3_axpy(X1, se, d12), AB = tl_v3_sub(B, A);
            /* tangents d/dxi = (B - A)/2, d/deta = ((1 - xi) d03 + (1 + xi) d12)/4 */
            const TlVec3 a = tl_v3_scale(AB, 0.5), b = tl_v3_scale(tl_v3_axpy(tl_v3_scale(d03, 1.0 - sx), sx, d12), 0.5);
            const double jac = tl_v3_norm(tl_v3_cross(a, b));
            if (!(jac > 0.0))
              TL_ERROR(TL_ERR_NUMERIC, "quadrilateral %zu (nodes %d %d %d %d) has area element %g at (%g, %g)", f,
                       v[0], v[1], v[2], v[3], jac, xi, eta);
            xq[slot] = tl_v3_axpy(A, sx, AB);
            wq[slot] = gw[gi] * gw[gj] * hs * hs * jac;
            double *N = Nq + slot * 4;
            N[0] = (1.0 - sx) * (1.0 - se), N[1] = sx * (1.0 - se), N[2] = sx * se, N[3] = (1.0 - sx) * se;
          }
  }
  return TL_OK;
}

static TlStatus quad_shape_at(const TlCGSurface *s, size_t n, const size_t *face, const TlVec3 *point, double *Nout)
{
  for (size_t k = 0; k < n; ++k) {
    const int *v = s->face_node + 4 * face[k];
    TlVec3 X[4] = {s->x[v[0]], s->x[v[1]], s->x[v[2]], s->x[v[3]]};
    double xi = 0.0, eta = 0.0, N[4], dxi[4], deta[4];
    /* Gauss-Newton on |X(xi, eta) - p|^2, clamped to the reference square */
    for (int it = 0; it < 50; ++it) {
      quad_shape(xi, eta, N, dxi, deta);
      TlVec3 r = tl_v3_neg(point[k]), a = tl_v3(0, 0, 0), b = tl_v3(0, 0, 0);
      for (int q = 0; q < 4; ++q) {
        r = tl_v3_axpy(r, N[q], X[q]);
        a = tl_v3_axpy(a, dxi[q], X[q]);
        b = tl_v3_axpy(b, deta[q], X[q]);
      }
      double a11 = tl_v3_dot(a, a), a12 = tl_v3_dot(a, b), a22 = tl_v3_dot(b, b);
      double r1 = -tl_v3_dot(a, r), r2 = -tl_v3_dot(b, r), det = a11 * a22 - a12 * a12;
      if (!(det > 0.0)) TL_ERROR(TL_ERR_NUMERIC, "quadrilateral %zu is degenerate at (%g, %g)", face[k], xi, eta);
      double dx = (a22 * r1 - a12 * r2) / det, de = (a11 * r2 - a12 * r1) / det;
      xi = fmin(1.0, fmax(-1.0, xi + dx));
      eta = fmin(1.0, fmax(-1.0, eta + de));
      if (fabs(dx) + fabs(de) < 1e-15) break;
    }
    quad_shape(xi, eta, N, dxi, deta);
    for (int q = 0; q < 4; ++q) Nout[k * 4 + q] = N[q];
  }
  return TL_OK;
}

static const TlCGSurfaceOps tl_cg_surface_quad_ops = {
    {TL_CG_SURFACE_KIND, "quad4", "bilinear quadrilaterals, 3 x 3 Gauss on s x s sub-squares"},
    quad_quadrature, quad_shape_at};

/* ------------------------------------------------------------ life cycle */

void tl_cg_surface_destroy(TlCGSurface **surface)
{
  if (!surface || !*surface) return;
  TlCGSurface *s = *surface;
  TlCGSurfaceScratch *w = scratch_of(s);
  tl_free(&s->face_node);
  tl_free(&s->xq);
  tl_free(&s->wq);
  tl_free(&s->Nq);
  tl_free(&s->face_lo);
  tl_free(&s->face_hi);
  tl_free(&w->r2);
  tl_free(&w->w);
  tl_free(&w->g);
  tl_free(&w->part);
  tl_free(&w->face_nodal);
  tl_free(&w->face_mark);
  tl_free(&w->face_list);
  tl_free(&w->N);
  tl_free(&w->cand);
  tl_free(&w->bin_start);
  tl_free(&w->bin_index);
  tl_free(&w->bin_of);
  tl_free(&w->near);
  tl_free(surface);
}

TlStatus tl_cg_surface_create(const TlCGSurfaceOps *ops, size_t n_nodes, const TlVec3 *x, size_t n_faces,
                              int nodes_per_face, const int *face_node, int qp_per_face, void *context,
                              TlCGSurface **surface)
{
  *surface = NULL;
  if (!ops || !ops->quadrature || !ops->shape_at) TL_ERROR(TL_ERR_ARG, "surface ops table is incomplete");
  if (n_nodes == 0 || n_faces == 0 || !x || !face_node)
    TL_ERROR(TL_ERR_ARG, "surface needs nodes and faces (got %zu nodes, %zu faces)", n_nodes, n_faces);
  if (nodes_per_face < 2 || nodes_per_face > 27)
    TL_ERROR(TL_ERR_ARG, "nodes per face %d outside [2, 27]", nodes_per_face);
  if (qp_per_face < 1) TL_ERROR(TL_ERR_ARG, "quadrature points per face %d must be positive", qp_per_face);
  for (size_t k = 0; k < n_faces * (size_t)nodes_per_face; ++k)
    if (face_node[k] < 0 || (size_t)face_node[k] >= n_nodes)
      TL_ERROR(TL_ERR_ARG, "face %zu names node %d, outside [0, %zu)", k / (size_t)nodes_per_face, face_node[k],
               n_nodes);
  TlCGSurfaceImpl *impl;
  TL_CHECK(TL_NEW(impl));
  TlCGSurface *s = &impl->pub;
  TlCGSurfaceScratch *w = &impl->scratch;
  s->ops = ops;
  s->n_nodes = n_nodes;
  s->n_faces = n_faces;
  s->nodes_per_face = nodes_per_face;
  s->qp_per_face = qp_per_face;
  s->subdivisions = 1;
  s->context = context;
  size_t nq = n_faces * (size_t)qp_per_face;
  TlStatus st = TL_OK;
  TL_CHECK_GOTO(st, tl_calloc(&s->face_node, n_faces * (size_t)nodes_per_face, sizeof(int)), fail);
  memcpy(s->face_node, face_node, n_faces * (size_t)nodes_per_face * sizeof(int));
  TL_CHECK_GOTO(st, tl_calloc(&s->xq, nq, sizeof(TlVec3)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&s->wq, nq, sizeof(double)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&s->Nq, nq * (size_t)nodes_per_face, sizeof(double)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&s->face_lo, n_faces, sizeof(TlVec3)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&s->face_hi, n_faces, sizeof(TlVec3)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->r2, (size_t)qp_per_face, sizeof(double)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->w, (size_t)qp_per_face, sizeof(double)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->g, n_faces * (size_t)nodes_per_face, sizeof(double)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->part, n_faces, sizeof(double)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->face_nodal, n_faces * (size_t)nodes_per_face, sizeof(TlVec3)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->face_mark, n_faces, 1), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->face_list, n_faces, sizeof(size_t)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->N, TL_CG_SURFACE_BATCH * (size_t)nodes_per_face, sizeof(double)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->cand, n_faces, sizeof(size_t)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->bin_index, n_faces, sizeof(size_t)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->bin_of, n_faces, sizeof(size_t)), fail);
  TL_CHECK_GOTO(st, tl_calloc(&w->near, n_faces, sizeof(size_t)), fail);
  s->x = x;
  *surface = s;
  return TL_OK;
fail:
  tl_cg_surface_destroy(&s);
  return st;
}

static TlStatus create_builtin(const TlCGSurfaceOps *ops, int npf, int qp_base, size_t n_nodes, const TlVec3 *x,
                               size_t n_faces, const int *nodes, int subdivisions, TlCGSurface **surface)
{
  *surface = NULL;
  if (subdivisions < 1 || subdivisions > 64)
    TL_ERROR(TL_ERR_ARG, "surface quadrature subdivisions %d outside [1, 64]", subdivisions);
  TlCGSurface *s;
  TL_CHECK(tl_cg_surface_create(ops, n_nodes, x, n_faces, npf, nodes, qp_base * subdivisions * subdivisions, NULL, &s));
  s->subdivisions = subdivisions;
  TlStatus st = tl_cg_surface_update(s, NULL);
  if (st != TL_OK) {
    tl_cg_surface_destroy(&s);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  *surface = s;
  return TL_OK;
}

TlStatus tl_cg_surface_create_triangles(size_t n_nodes, const TlVec3 *x, size_t n_faces, const int *tri,
                                        int subdivisions, TlCGSurface **surface)
{
  TL_CHECK(create_builtin(&tl_cg_surface_triangle_ops, 3, 6, n_nodes, x, n_faces, tri, subdivisions, surface));
  return TL_OK;
}

TlStatus tl_cg_surface_create_quads(size_t n_nodes, const TlVec3 *x, size_t n_faces, const int *quad,
                                    int subdivisions, TlCGSurface **surface)
{
  TL_CHECK(create_builtin(&tl_cg_surface_quad_ops, 4, 9, n_nodes, x, n_faces, quad, subdivisions, surface));
  return TL_OK;
}

/* Squared distance from p to the box [lo, hi] (0 inside). */
static inline double box_distance2(TlVec3 lo, TlVec3 hi, TlVec3 p)
{
  const double dx = tl_max(tl_max(lo.x - p.x, p.x - hi.x), 0.0), dy = tl_max(tl_max(lo.y - p.y, p.y - hi.y), 0.0),
               dz = tl_max(tl_max(lo.z - p.z, p.z - hi.z), 0.0);
  return dx * dx + dy * dy + dz * dz;
}

static TlStatus bin_faces(TlCGSurface *s);
static TlStatus face_box(TlCGSurface *s, size_t f);

TlStatus tl_cg_surface_update(TlCGSurface *s, const TlVec3 *x)
{
  if (x) s->x = x;
  for (size_t i = 0; i < s->n_nodes; ++i)
    if (!tl_v3_isfinite(s->x[i]))
      TL_ERROR(TL_ERR_NUMERIC, "surface node %zu is not finite (%g, %g, %g)", i, s->x[i].x, s->x[i].y, s->x[i].z);
  TL_CHECK(s->ops->quadrature(s, s->n_faces, NULL, s->xq, s->wq, s->Nq));
  for (size_t f = 0; f < s->n_faces; ++f) TL_CHECK(face_box(s, f));
  scratch_of(s)->partial = 0;
  TL_CHECK(bin_faces(s));
  return TL_OK;
}

/* Box of face f from its nodes and quadrature points (which are checked). */
static TlStatus face_box(TlCGSurface *s, size_t f)
{
  TlVec3 lo = s->x[s->face_node[f * (size_t)s->nodes_per_face]], hi = lo;
  for (int a = 0; a < s->nodes_per_face; ++a) {
    TlVec3 p = s->x[s->face_node[f * (size_t)s->nodes_per_face + (size_t)a]];
    lo = tl_v3(tl_min(lo.x, p.x), tl_min(lo.y, p.y), tl_min(lo.z, p.z));
    hi = tl_v3(tl_max(hi.x, p.x), tl_max(hi.y, p.y), tl_max(hi.z, p.z));
  }
  for (int q = 0; q < s->qp_per_face; ++q) {
    size_t slot = f * (size_t)s->qp_per_face + (size_t)q;
    TlVec3 p = s->xq[slot];
    if (!(s->wq[slot] > 0.0) || !isfinite(s->wq[slot]) || !tl_v3_isfinite(p))
      TL_ERROR(TL_ERR_NUMERIC, "face %zu quadrature point %d has weight %g", f, q, s->wq[slot]);
    lo = tl_v3(tl_min(lo.x, p.x), tl_min(lo.y, p.y), tl_min(lo.z, p.z));
    hi = tl_v3(tl_max(hi.x, p.x), tl_max(hi.y, p.y), tl_max(hi.z, p.z));
  }
  s->face_lo[f] = lo;
  s->face_hi[f] = hi;
  return TL_OK;
}

TlStatus tl_cg_surface_update_near(TlCGSurface *s, size_t n, const TlVec3 *points, double reach)
{
  TlCGSurfaceScratch *w = scratch_of(s);
  for (size_t i = 0; i < s->n_nodes; ++i)
    if (!tl_v3_isfinite(s->x[i]))
      TL_ERROR(TL_ERR_NUMERIC, "surface node %zu is not finite (%g, %g, %g)", i, s->x[i].x, s->x[i].y, s->x[i].z);
  const int npf = s->nodes_per_face;
  w->n_near = 0;
  for (size_t f = 0; f < s->n_faces; ++f) {
    TlVec3 lo = s->x[s->face_node[f * (size_t)npf]], hi = lo;
    for (int a = 1; a < npf; ++a) {
      TlVec3 p = s->x[s->face_node[f * (size_t)npf + (size_t)a]];
      lo = tl_v3(tl_min(lo.x, p.x), tl_min(lo.y, p.y), tl_min(lo.z, p.z));
      hi = tl_v3(tl_max(hi.x, p.x), tl_max(hi.y, p.y), tl_max(hi.z, p.z));
    }
    int near = 0;
    for (size_t k = 0; k < n && !near; ++k) near = box_distance2(lo, hi, points[k]) < reach * reach;
    if (near) w->near[w->n_near++] = f;
  }
  TL_CHECK(s->ops->quadrature(s, w->n_near, w->near, s->xq, s->wq, s->Nq));
  for (size_t k = 0; k < w->n_near; ++k) TL_CHECK(face_box(s, w->near[k]));
  w->partial = 1;
  return TL_OK;
}

/* ----------------------------------------------------------- evaluation */

/* The kernel's support is the ball of radius c: a face is near p when its
 * box is closer than c. */
static inline int face_near(const TlCGSurface *s, size_t f, TlVec3 p, double c)
{
  return box_distance2(s->face_lo[f], s->face_hi[f], p) < c * c;
}

/* Sorts the faces into a uniform grid by the centre of their boxes. */
static TlStatus bin_faces(TlCGSurface *s)
{
  TlCGSurfaceScratch *w = scratch_of(s);
  TlVec3 lo = tl_v3(INFINITY, INFINITY, INFINITY), hi = tl_v3(-INFINITY, -INFINITY, -INFINITY);
  TlVec3 ext = tl_v3(0, 0, 0);
  for (size_t f = 0; f < s->n_faces; ++f) {
    TlVec3 c = tl_v3_scale(tl_v3_add(s->face_lo[f], s->face_hi[f]), 0.5), e = tl_v3_sub(s->face_hi[f], s->face_lo[f]);
    lo = tl_v3(tl_min(lo.x, c.x), tl_min(lo.y, c.y), tl_min(lo.z, c.z));
    hi = tl_v3(tl_max(hi.x, c.x), tl_max(hi.y, c.y), tl_max(hi.z, c.z));
    ext = tl_v3(tl_max(ext.x, e.x), tl_max(ext.y, e.y), tl_max(ext.z, e.z));
  }
  double size = fmax(ext.x, fmax(ext.y, ext.z));
  if (!(size > 0.0)) size = 1.0;
  size_t limit = 4 * s->n_faces + 64, total;
  for (;;) {
    total = 1;
    for (int d = 0; d < 3; ++d) {
      double m = floor(((&hi.x)[d] - (&lo.x)[d]) / size) + 1.0;
      w->bin_n[d] = (int)fmin(m, 1e6);
      total *= (size_t)w->bin_n[d];
    }
    if (total <= limit) break;
    size *= 1.25;
  }
  w->bin_lo = lo;
  w->bin_cell = tl_v3(size, size, size);
  w->half_extent = tl_v3_scale(ext, 0.5);
  TL_CHECK(tl_array_reserve(&w->bin_start, &w->cap_bin_start, total + 1, sizeof(size_t)));
  memset(w->bin_start, 0, (total + 1) * sizeof(size_t));
  for (size_t f = 0; f < s->n_faces; ++f) {
    TlVec3 c = tl_v3_scale(tl_v3_add(s->face_lo[f], s->face_hi[f]), 0.5);
    size_t cell = 0, stride = 1;
    for (int d = 0; d < 3; ++d) {
      int i = (int)floor(((&c.x)[d] - (&lo.x)[d]) / size);
      if (i < 0) i = 0;
      if (i >= w->bin_n[d]) i = w->bin_n[d] - 1;
      cell += (size_t)i * stride;
      stride *= (size_t)w->bin_n[d];
    }
    w->bin_of[f] = cell;
    w->bin_start[cell + 1]++;
  }
  for (size_t k = 0; k < total; ++k) w->bin_start[k + 1] += w->bin_start[k];
  for (size_t f = 0; f < s->n_faces; ++f) w->bin_index[w->bin_start[w->bin_of[f]]++] = f;
  for (size_t k = total; k > 0; --k) w->bin_start[k] = w->bin_start[k - 1];
  w->bin_start[0] = 0;
  return TL_OK;
}

/* Faces whose box, enlarged by c, contains p: into scratch->cand. */
static size_t candidates(const TlCGSurface *s, TlVec3 p, double c)
{
  TlCGSurfaceScratch *w = scratch_of(s);
  if (w->partial) {
    /* after tl_cg_surface_update_near: the refreshed faces only */
    size_t n = 0;
    for (size_t k = 0; k < w->n_near; ++k)
      if (face_near(s, w->near[k], p, c)) w->cand[n++] = w->near[k];
    return n;
  }
  int i0[3], i1[3];
  for (int d = 0; d < 3; ++d) {
    double reach = c + (&w->half_extent.x)[d], cell = (&w->bin_cell.x)[d];
    double a = floor(((&p.x)[d] - reach - (&w->bin_lo.x)[d]) / cell);
    double b = floor(((&p.x)[d] + reach - (&w->bin_lo.x)[d]) / cell);
    a = fmax(a, 0.0);
    b = fmin(b, w->bin_n[d] - 1.0);
    if (a > b) return 0;
    i0[d] = (int)a;
    i1[d] = (int)b;
  }
  size_t n = 0;
  for (int k = i0[2]; k <= i1[2]; ++k)
    for (int j = i0[1]; j <= i1[1]; ++j)
      for (int i = i0[0]; i <= i1[0]; ++i) {
        size_t cell = (size_t)i + (size_t)w->bin_n[0] * ((size_t)j + (size_t)w->bin_n[1] * (size_t)k);
        for (size_t e = w->bin_start[cell]; e < w->bin_start[cell + 1]; ++e) {
          size_t f = w->bin_index[e];
          if (face_near(s, f, p, c)) w->cand[n++] = f;
        }
      }
  return n;
}

/* Kernel values at the points of face f into scratch->w; returns sum w_q W. */
static TlStatus face_kernel(const TlCGSurface *s, const TlCGKernel *k, size_t f, TlVec3 p, double *sum)
{
  TlCGSurfaceScratch *w = scratch_of(s);
  size_t base = f * (size_t)s->qp_per_face;
  for (int q = 0; q < s->qp_per_face; ++q) w->r2[q] = tl_v3_norm2(tl_v3_sub(s->xq[base + (size_t)q], p));
  TL_CHECK(tl_cg_kernel_eval(k, (size_t)s->qp_per_face, w->r2, w->w, NULL));
  double acc = 0.0;
  for (int q = 0; q < s->qp_per_face; ++q) {
    w->w[q] *= s->wq[base + (size_t)q];
    acc += w->w[q];
  }
  *sum = acc;
  return TL_OK;
}

static TlStatus no_support_error(const TlCGKernel *k, TlVec3 p)
{
  TL_ERROR(TL_ERR_ARG,
           "no surface quadrature point lies within c = %g of contact point (%g, %g, %g): the kernel is narrower "
           "than the quadrature spacing or the point is off the surface; raise the subdivisions or use the dirac kernel",
           k->c, p.x, p.y, p.z);
}

static TlStatus surface_sum(const TlCGSurface *s, const TlCGKernel *k, TlVec3 p, double *total)
{
  double S = 0.0;
  size_t nc = candidates(s, p, k->c);
  for (size_t q = 0; q < nc; ++q) {
    size_t f = scratch_of(s)->cand[q];
    double part = 0.0;
    TL_CHECK(face_kernel(s, k, f, p, &part));
    S += part;
  }
  if (!(S > 0.0)) TL_CHECK(no_support_error(k, p));
  *total = S;
  return TL_OK;
}

TlStatus tl_cg_surface_weights(const TlCGSurface *s, const TlCGKernel *k, TlVec3 point, size_t max, size_t *count,
                               size_t *slot, double *weight)
{
  if (tl_cg_kernel_is_dirac(k))
    TL_ERROR(TL_ERR_UNSUPPORTED, "the dirac kernel has no surface weights: Eq. 16 uses the shape functions at the point");
  if (!tl_v3_isfinite(point)) TL_ERROR(TL_ERR_NUMERIC, "contact point is not finite");
  TlCGSurfaceScratch *w = scratch_of(s);
  double S;
  TL_CHECK(surface_sum(s, k, point, &S));
  size_t m = 0, needed = 0;
  size_t nc = candidates(s, point, k->c);
  for (size_t qc = 0; qc < nc; ++qc) {
    size_t f = w->cand[qc];
    double part = 0.0;
    TL_CHECK(face_kernel(s, k, f, point, &part));
    for (int q = 0; q < s->qp_per_face; ++q)
      if (w->w[q] > 0.0) {
        if (m < max) {
          slot[m] = f * (size_t)s->qp_per_face + (size_t)q;
          weight[m] = w->w[q] / S;
          ++m;
        }
        ++needed;
      }
  }
  *count = m;
  if (needed > max) TL_ERROR(TL_ERR_ARG, "contact point has %zu weighted quadrature points, room for %zu", needed, max);
  return TL_OK;
}

/* Marks face f touched (flag and list), if the caller asked for them. */
static inline void mark_face(size_t f, unsigned char *flag, size_t *list, size_t *n_list)
{
  if (!flag || flag[f]) return;
  flag[f] = 1;
  if (list) list[(*n_list)++] = f;
}

TlStatus tl_cg_surface_face_forces(const TlCGSurface *s, const TlCGKernel *k, size_t n, const size_t *face,
                                   const TlVec3 *point, const TlVec3 *f_wall, TlVec3 *face_nodal,
                                   unsigned char *face_touched, size_t *touched, size_t *n_touched)
{
  TlCGSurfaceScratch *w = scratch_of(s);
  const size_t npf = (size_t)s->nodes_per_face;
  if (touched && (!face_touched || !n_touched))
    TL_ERROR(TL_ERR_ARG, "the list of touched faces needs the face flags and a count");
  if (tl_cg_kernel_is_dirac(k)) {
    /* Eq. 16: the shape functions of the contact's face at the contact point */
    if (n && !face) TL_ERROR(TL_ERR_ARG, "the dirac kernel needs the face of every contact");
    for (size_t k0 = 0; k0 < n; k0 += TL_CG_SURFACE_BATCH) {
      size_t m = n - k0 < TL_CG_SURFACE_BATCH ? n - k0 : TL_CG_SURFACE_BATCH;
      for (size_t j = 0; j < m; ++j)
        if (face[k0 + j] >= s->n_faces)
          TL_ERROR(TL_ERR_ARG, "contact %zu names face %zu, the surface has %zu", k0 + j, face[k0 + j], s->n_faces);
      TL_CHECK(s->ops->shape_at(s, m, face + k0, point + k0, w->N));
      for (size_t j = 0; j < m; ++j) {
        const size_t f = face[k0 + j];
        TlVec3 *out = face_nodal + f * npf;
        for (size_t a = 0; a < npf; ++a) out[a] = tl_v3_axpy(out[a], -w->N[j * npf + a], f_wall[k0 + j]);
        mark_face(f, face_touched, touched, n_touched);
      }
    }
    return TL_OK;
  }
  for (size_t c = 0; c < n; ++c) {
    TlVec3 p = point[c];
    if (!tl_v3_isfinite(p) || !tl_v3_isfinite(f_wall[c]))
      TL_ERROR(TL_ERR_NUMERIC, "contact %zu has a non-finite point or force", c);
    /* unnormalised face-node sums g_fa = sum_q w_q W N_qa, then divided by
     * the surface total S once it is known */
    double S = 0.0;
    size_t nc = candidates(s, p, k->c);
    for (size_t qc = 0; qc < nc; ++qc) {
      size_t f = w->cand[qc];
      double part = 0.0;
      TL_CHECK(face_kernel(s, k, f, p, &part));
      w->part[qc] = part;
      if (part == 0.0) continue;
      S += part;
      const double *N = s->Nq + f * (size_t)s->qp_per_face * npf;
      for (size_t a = 0; a < npf; ++a) {
        double g = 0.0;
        for (int q = 0; q < s->qp_per_face; ++q) g += w->w[q] * N[(size_t)q * npf + a];
        w->g[qc * npf + a] = g;
      }
    }
    if (!(S > 0.0)) TL_CHECK(no_support_error(k, p));
    for (size_t qc = 0; qc < nc; ++qc) {
      if (w->part[qc] == 0.0) continue;
      const size_t f = w->cand[qc];
      TlVec3 *out = face_nodal + f * npf;
      for (size_t a = 0; a < npf; ++a) out[a] = tl_v3_axpy(out[a], -w->g[qc * npf + a] / S, f_wall[c]);
      mark_face(f, face_touched, touched, n_touched);
    }
  }
  return TL_OK;
}

void tl_cg_surface_assemble_faces(const TlCGSurface *s, size_t n, const size_t *faces, const TlVec3 *face_nodal,
                                  TlVec3 *nodal)
{
  const size_t npf = (size_t)s->nodes_per_face;
  for (size_t k = 0; k < n; ++k) {
    const size_t f = faces ? faces[k] : k;
    const int *v = s->face_node + f * npf;
    const TlVec3 *in = face_nodal + f * npf;
    for (size_t a = 0; a < npf; ++a) nodal[v[a]] = tl_v3_add(nodal[v[a]], in[a]);
  }
}

TlStatus tl_cg_surface_nodal_forces(const TlCGSurface *s, const TlCGKernel *k, size_t n, const size_t *face,
                                    const TlVec3 *point, const TlVec3 *f_wall, TlVec3 *nodal)
{
  /* The per-face forces of the touched faces, assembled, then cleared for
   * the next call. */
  TlCGSurfaceScratch *w = scratch_of(s);
  const size_t npf = (size_t)s->nodes_per_face;
  size_t nt = 0;
  TlStatus st = tl_cg_surface_face_forces(s, k, n, face, point, f_wall, w->face_nodal, w->face_mark, w->face_list, &nt);
  if (st == TL_OK) tl_cg_surface_assemble_faces(s, nt, w->face_list, w->face_nodal, nodal);
  for (size_t t = 0; t < nt; ++t) {
    const size_t f = w->face_list[t];
    memset(w->face_nodal + f * npf, 0, npf * sizeof(TlVec3));
    w->face_mark[f] = 0;
  }
  if (st != TL_OK) return tl_error_trace(st, __FILE__, __LINE__);
  return TL_OK;
}

TlStatus tl_cg_surface_traction(const TlCGSurface *s, const TlCGKernel *k, size_t n, const TlVec3 *point,
                                const TlVec3 *f_wall, TlVec3 *traction)
{
  if (tl_cg_kernel_is_dirac(k))
    TL_ERROR(TL_ERR_UNSUPPORTED, "the dirac kernel has no traction field: use the nodal forces of Eq. 16");
  TlCGSurfaceScratch *w = scratch_of(s);
  for (size_t c = 0; c < n; ++c) {
    double S;
    TL_CHECK(surface_sum(s, k, point[c], &S));
    size_t nc = candidates(s, point[c], k->c);
    for (size_t qc = 0; qc < nc; ++qc) {
      size_t f = w->cand[qc];
      double part = 0.0;
      TL_CHECK(face_kernel(s, k, f, point[c], &part));
      size_t base = f * (size_t)s->qp_per_face;
      for (int q = 0; q < s->qp_per_face; ++q)
        if (w->w[q] > 0.0)
          traction[base + (size_t)q] =
              tl_v3_axpy(traction[base + (size_t)q], -w->w[q] / (S * s->wq[base + (size_t)q]), f_wall[c]);
    }
  }
  return TL_OK;
}

TlStatus tl_cg_project_to_element(const TlCGKernel *k, size_t n_qp, const TlVec3 *xq, const double *wq, int n_shape,
                                  const double *Nq, TlVec3 point, double scale, double *out)
{
  if (tl_cg_kernel_is_dirac(k))
    TL_ERROR(TL_ERR_UNSUPPORTED, "the dirac kernel has no volume weights: Eq. 19 uses N_a at the particle");
  enum { B = 128 };
  double r2[B], w[B];
  for (size_t q0 = 0; q0 < n_qp; q0 += B) {
    size_t m = n_qp - q0 < B ? n_qp - q0 : B;
    for (size_t j = 0; j < m; ++j) r2[j] = tl_v3_norm2(tl_v3_sub(xq[q0 + j], point));
    TL_CHECK(tl_cg_kernel_eval(k, m, r2, w, NULL));
    for (size_t j = 0; j < m; ++j) {
      if (w[j] == 0.0) continue;
      double sw = scale * wq[q0 + j] * w[j];
      const double *N = Nq + (q0 + j) * (size_t)n_shape;
      for (int a = 0; a < n_shape; ++a) out[a] += sw * N[a];
    }
  }
  return TL_OK;
}
