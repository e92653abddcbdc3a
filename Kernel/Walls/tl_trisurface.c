#include "tl_trisurface.h"

#include <float.h>
#include <math.h>

#include <stdint.h>
#include <stdlib.h>
#include "tl_memory.h"
#include "tl_predicates.h"

/* One directed edge of a triangle, for building the edge list by sorting. */
typedef struct {
  int lo, hi;   /* vertex indices, lo < hi */
  int tri, k;   /* triangle and local edge */
} TlHalfEdge;

static int tl_half_edge_compare(const void *pa, const void *pb)
{
  const TlHalfEdge *a = pa, *b = pb;
  if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
  if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
  if (a->tri != b->tri) return a->tri < b->tri ? -1 : 1;
  return (a->k > b->k) - (a->k < b->k);
}

void tl_trisurface_destroy(TlTriSurface **surface)
{
  if (!surface || !*surface) return;
  TlTriSurface *s = *surface;
  tl_free(&s->x);
  tl_free(&s->v);
  tl_free(&s->tri);
  tl_free(&s->edge_vertex);
  tl_free(&s->edge_tri);
  tl_free(&s->tri_edge);
  tl_free(&s->tri_nbr);
  tl_free(&s->normal);
  tl_free(&s->area);
  tl_free(&s->box_lo);
  tl_free(&s->box_hi);
  tl_free(&s->edge_shape);
  tl_free(&s->edge_fold);
  tl_free(&s->edge_sharp);
  tl_free(&s->edge_twin);
  tl_free(&s->edge_shift);
  tl_free(surface);
}

/* Builds edges and neighbours; refuses non-manifold edges and inconsistent
 * orientation, which would make edge shapes meaningless. */
static TlStatus tl_trisurface_build_topology(TlTriSurface *s)
{
  size_t nt = s->n_triangles, nh = 3 * nt;
  TlHalfEdge *h = NULL;
  TL_CHECK(tl_calloc(&h, nh, sizeof *h));
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      int a = s->tri[3 * t + k], b = s->tri[3 * t + (k + 1) % 3];
      h[3 * t + k] = (TlHalfEdge){a < b ? a : b, a < b ? b : a, (int)t, k};
    }
  qsort(h, nh, sizeof *h, tl_half_edge_compare);

  TlStatus status = TL_OK;
  size_t ne = 0;
  for (size_t i = 0; i < nh;) {
    size_t j = i + 1;
    while (j < nh && h[j].lo == h[i].lo && h[j].hi == h[i].hi) ++j;
    if (j - i > 2) {
      status = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                            "edge (%d, %d) is shared by %zu triangles (%d, %d, %d, ...); a "
                            "triangulated surface allows at most 2 per edge",
                            h[i].lo, h[i].hi, j - i, h[i].tri, h[i + 1].tri, h[i + 2].tri);
      goto done;
    }
    if (j - i == 2) {
      /* Consistent orientation: the two triangles traverse the edge in
       * opposite directions. */
      int a0 = s->tri[3 * h[i].tri + h[i].k];
      int a1 = s->tri[3 * h[i + 1].tri + h[i + 1].k];
      if (a0 == a1) {
        status = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                              "triangles %d and %d traverse their shared edge (%d, %d) in the "
                              "same direction: orient all triangles counter-clockwise seen "
                              "from the same side",
                              h[i].tri, h[i + 1].tri, h[i].lo, h[i].hi);
        goto done;
      }
    }
    ++ne;
    i = j;
  }
  s->n_edges = ne;
  TL_CHECK_GOTO(status, tl_calloc(&s->edge_vertex, 2 * ne, sizeof *s->edge_vertex), done);
  TL_CHECK_GOTO(status, tl_calloc(&s->edge_tri, 2 * ne, sizeof *s->edge_tri), done);
  TL_CHECK_GOTO(status, tl_calloc(&s->edge_shape, ne, sizeof *s->edge_shape), done);
  TL_CHECK_GOTO(status, tl_calloc(&s->edge_fold, ne, sizeof *s->edge_fold), done);
  TL_CHECK_GOTO(status, tl_calloc(&s->edge_sharp, ne, sizeof *s->edge_sharp), done);
  TL_CHECK_GOTO(status, tl_calloc(&s->edge_twin, ne, sizeof *s->edge_twin), done);
  TL_CHECK_GOTO(status, tl_calloc(&s->edge_shift, ne, sizeof *s->edge_shift), done);
  for (size_t k = 0; k < ne; ++k) s->edge_twin[k] = -1;
  TL_CHECK_GOTO(status, tl_calloc(&s->tri_edge, 3 * nt, sizeof *s->tri_edge), done);
  TL_CHECK_GOTO(status, tl_calloc(&s->tri_nbr, 3 * nt, sizeof *s->tri_nbr), done);
  size_t e = 0;
  for (size_t i = 0; i < nh; ++e) {
    size_t j = i + 1;
    while (j < nh && h[j].lo == h[i].lo && h[j].hi == h[i].hi) ++j;
    s->edge_vertex[2 * e] = h[i].lo;
    s->edge_vertex[2 * e + 1] = h[i].hi;
    s->edge_tri[2 * e] = h[i].tri;
    s->edge_tri[2 * e + 1] = j - i == 2 ? h[i + 1].tri : -1;
    s->tri_edge[3 * h[i].tri + h[i].k] = (int)e;
    s->tri_nbr[3 * h[i].tri + h[i].k] = j - i == 2 ? h[i + 1].tri : -1;
    if (j - i == 2) {
      s->tri_edge[3 * h[i + 1].tri + h[i + 1].k] = (int)e;
      s->tri_nbr[3 * h[i + 1].tri + h[i + 1].k] = h[i].tri;
    }
    i = j;
  }
done:
  tl_free(&h);
  return status;
}

TlStatus tl_trisurface_create(size_t n_vertices, const double *x, size_t n_triangles,
                              const int *tri, TlTriSurface **surface)
{
  if (!surface) TL_ERROR(TL_ERR_ARG, "tl_trisurface_create: surface pointer is NULL");
  *surface = NULL;
  if (n_vertices < 3 || n_triangles < 1 || !x || !tri)
    TL_ERROR(TL_ERR_ARG, "a triangulated surface needs at least 3 vertices and 1 triangle "
             "(got %zu vertices, %zu triangles)", n_vertices, n_triangles);
  if (n_vertices > (size_t)INT32_MAX || n_triangles > (size_t)INT32_MAX / 3)
    TL_ERROR(TL_ERR_ARG, "surface too large: %zu vertices, %zu triangles (limit %d)", n_vertices,
             n_triangles, INT32_MAX / 3);
  for (size_t t = 0; t < n_triangles; ++t) {
    const int *v = tri + 3 * t;
    for (int k = 0; k < 3; ++k)
      if (v[k] < 0 || (size_t)v[k] >= n_vertices)
        TL_ERROR(TL_ERR_ARG, "triangle %zu: vertex index %d outside [0, %zu)", t, v[k], n_vertices);
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
      TL_ERROR(TL_ERR_ARG, "triangle %zu repeats a vertex (%d, %d, %d): degenerate", t, v[0], v[1],
               v[2]);
  }
  TlTriSurface *s = NULL;
  TL_CHECK(TL_NEW(s));
  TlStatus status = TL_OK;
  s->n_vertices = n_vertices;
  s->n_triangles = n_triangles;
  s->flat_tolerance = 1e-9;
  s->quality_tolerance = 1e-6;
  s->feature_angle = TL_TRISURFACE_FEATURE_ANGLE;
  s->feature_cos = cos(s->feature_angle * (TL_PI / 180.0));
  TL_CHECK_GOTO(status, tl_calloc(&s->x, n_vertices, sizeof *s->x), fail);
  TL_CHECK_GOTO(status, tl_calloc(&s->v, n_vertices, sizeof *s->v), fail);
  TL_CHECK_GOTO(status, tl_calloc(&s->tri, 3 * n_triangles, sizeof *s->tri), fail);
  TL_CHECK_GOTO(status, tl_calloc(&s->normal, n_triangles, sizeof *s->normal), fail);
  TL_CHECK_GOTO(status, tl_calloc(&s->area, n_triangles, sizeof *s->area), fail);
  TL_CHECK_GOTO(status, tl_calloc(&s->box_lo, n_triangles, sizeof *s->box_lo), fail);
  TL_CHECK_GOTO(status, tl_calloc(&s->box_hi, n_triangles, sizeof *s->box_hi), fail);
  for (size_t i = 0; i < n_vertices; ++i) s->x[i] = tl_v3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  for (size_t i = 0; i < 3 * n_triangles; ++i) s->tri[i] = tri[i];
  TL_CHECK_GOTO(status, tl_trisurface_build_topology(s), fail);
  TL_CHECK_GOTO(status, tl_trisurface_update(s), fail);
  *surface = s;
  return TL_OK;
fail:
  tl_trisurface_destroy(&s);
  return status;
}

TlStatus tl_trisurface_set_vertices(TlTriSurface *s, const double *x, const double *v)
{
  if (!s || !x) TL_ERROR(TL_ERR_ARG, "tl_trisurface_set_vertices: NULL surface or positions");
  for (size_t i = 0; i < s->n_vertices; ++i) s->x[i] = tl_v3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  if (v)
    for (size_t i = 0; i < s->n_vertices; ++i) s->v[i] = tl_v3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  TL_CHECK(tl_trisurface_update(s));
  return TL_OK;
}

static inline TlVec3 vmin(TlVec3 a, TlVec3 b) { return tl_v3(tl_min(a.x, b.x), tl_min(a.y, b.y), tl_min(a.z, b.z)); }
static inline TlVec3 vmax(TlVec3 a, TlVec3 b) { return tl_v3(tl_max(a.x, b.x), tl_max(a.y, b.y), tl_max(a.z, b.z)); }

static TlStatus check_vertices(const TlTriSurface *s)
{
  /* A branch-free pass first (every step of a moving surface), the
   * offender looked up only when one is flagged. */
  double sum = 0.0;
  for (size_t i = 0; i < s->n_vertices; ++i)
    sum += fabs(s->x[i].x) + fabs(s->x[i].y) + fabs(s->x[i].z) + fabs(s->v[i].x) + fabs(s->v[i].y) + fabs(s->v[i].z);
  if (sum <= DBL_MAX) return TL_OK;
  for (size_t i = 0; i < s->n_vertices; ++i)
    if (!tl_v3_isfinite(s->x[i]) || !tl_v3_isfinite(s->v[i]))
      TL_ERROR(TL_ERR_NUMERIC, "vertex %zu has a non-finite position (%g, %g, %g) or velocity "
               "(%g, %g, %g)", i, s->x[i].x, s->x[i].y, s->x[i].z, s->v[i].x, s->v[i].y, s->v[i].z);
  return TL_OK;
}

/* Normal, area and box of triangle t. */
static TlStatus triangle_geometry(TlTriSurface *s, size_t t)
{
  const int *v = s->tri + 3 * t;
  TlVec3 a = s->x[v[0]], b = s->x[v[1]], c = s->x[v[2]];
  double q = tl_triangle_quality(a, b, c);
  /* zero area decided exactly, whatever the tolerance (a poor triangle's
   * quality in doubles could pass a tolerance set very low) */
  if (q < 1e-3 && tl_collinear3d(a, b, c)) q = 0.0;
  if (!(q >= s->quality_tolerance))
    TL_ERROR(TL_ERR_NUMERIC, "triangle %zu (vertices %d, %d, %d) is degenerate: quality %.3g "
             "below the tolerance %.3g (1 = equilateral, 0 = zero area or needle)",
             t, v[0], v[1], v[2], q, s->quality_tolerance);
  TlVec3 n = tl_v3_cross(tl_v3_sub(b, a), tl_v3_sub(c, a));
  double len = tl_v3_norm(n);
  s->normal[t] = tl_v3_scale(n, 1.0 / len);
  s->area[t] = 0.5 * len;
  s->box_lo[t] = vmin(a, vmin(b, c));
  s->box_hi[t] = vmax(a, vmax(b, c));
  return TL_OK;
}

/* Shape, fold and sharpness of edge e.  A fold whose sine is within the
 * flat tolerance is flat (a tolerance on a magnitude: the sense does not
 * matter).  Any other fold takes its sense, concave or convex, from the exact
 * orientation predicate (B's far vertex above or below A's plane), so that a
 * fold is never given the wrong sense by round-off, whatever the
 * tolerances, and exactly coplanar faces are flat.  Flat edges thus cost
 * nothing more, and for folded ones the predicate's floating-point filter
 * decides in a few dozen flops (its exact stage is for nearly coplanar
 * faces, which only a flat tolerance below round-off lets through).  The
 * angle between the two normals then compares with the feature angle. */
static void edge_geometry(TlTriSurface *s, size_t e)
{
  int ta = s->edge_tri[2 * e], tb = s->edge_tri[2 * e + 1];
  if (ta < 0 || tb < 0) {
    /* a boundary edge, or the absorbed half of a periodic pair */
    s->edge_shape[e] = TL_EDGE_BOUNDARY;
    s->edge_fold[e] = 0.0;
    s->edge_sharp[e] = 0;
    return;
  }
  /* Sine of the fold: how far B's far vertex rises above A's plane,
   * relative to its distance from the shared edge (B brought into A's
   * frame across a periodic face). */
  TlVec3 p0 = s->x[s->edge_vertex[2 * e]], p1 = s->x[s->edge_vertex[2 * e + 1]];
  const int *va = s->tri + 3 * (size_t)ta, *vb = s->tri + 3 * (size_t)tb;
  TlVec3 shift = tl_v3(0, 0, 0);
  int e0 = s->edge_vertex[2 * e], e1 = s->edge_vertex[2 * e + 1];
  if (s->edge_twin[e] >= 0) {
    /* B's own edge vertices are the twins of e0 and e1 */
    shift = tl_v3_sub(s->x[s->edge_twin[e]], p0);
    int kb = 0;
    while (kb < 2 && s->tri_edge[3 * (size_t)tb + kb] != (int)e) ++kb;
    e0 = vb[kb], e1 = vb[(kb + 1) % 3];
  }
  s->edge_shift[e] = shift;
  int far = vb[0];
  for (int k = 0; k < 3; ++k)
    if (vb[k] != e0 && vb[k] != e1) far = vb[k];
  TlVec3 q = s->edge_twin[e] >= 0 ? tl_v3_sub(s->x[far], shift) : s->x[far];
  TlVec3 u = tl_v3_normalize(tl_v3_sub(p1, p0));
  TlVec3 d = tl_v3_sub(q, p0);
  TlVec3 h = tl_v3_axpy(d, -tl_v3_dot(d, u), u);
  double fold = tl_v3_dot(s->normal[ta], h) / tl_v3_norm(h);
  if (fabs(fold) > s->flat_tolerance) fold = tl_orient3d(s->x[va[0]], s->x[va[1]], s->x[va[2]], q) * fabs(fold);
  s->edge_fold[e] = fold;
  s->edge_shape[e] = fold > s->flat_tolerance    ? TL_EDGE_CONCAVE
                     : fold < -s->flat_tolerance ? TL_EDGE_CONVEX
                                                 : TL_EDGE_FLAT;
  /* The fold angle is the angle between the normals (0 when flat, up to
   * 180 degrees for a closed blade), 180 degrees less the dihedral angle
   * between the two half-planes at the edge: sharp when the dihedral angle
   * is below 180 - feature, whose cosine is -feature_cos, decided exactly
   * (a fold on the feature angle is not sharp). */
  int fa = va[0];
  for (int k = 0; k < 3; ++k)
    if (va[k] != s->edge_vertex[2 * e] && va[k] != s->edge_vertex[2 * e + 1]) fa = va[k];
  s->edge_sharp[e] = s->edge_shape[e] != TL_EDGE_FLAT && tl_dihedral_compare(p0, p1, s->x[fa], q, -s->feature_cos) < 0;
}

static void surface_box(TlTriSurface *s)
{
  TlVec3 lo = tl_v3(INFINITY, INFINITY, INFINITY), hi = tl_v3(-INFINITY, -INFINITY, -INFINITY);
  for (size_t i = 0; i < s->n_vertices; ++i) lo = vmin(lo, s->x[i]), hi = vmax(hi, s->x[i]);
  s->surface_lo = lo;
  s->surface_hi = hi;
}

TlStatus tl_trisurface_update(TlTriSurface *s)
{
  if (!s) TL_ERROR(TL_ERR_ARG, "tl_trisurface_update: NULL surface");
  TL_CHECK(check_vertices(s));
  for (size_t t = 0; t < s->n_triangles; ++t) TL_CHECK(triangle_geometry(s, t));
  surface_box(s);
  ++s->version;
  for (size_t e = 0; e < s->n_edges; ++e) edge_geometry(s, e);
  s->geometry_stale = 0;
  return TL_OK;
}

TlStatus tl_trisurface_move_vertices(TlTriSurface *s, const double *x, const double *v)
{
  if (!s || !x) TL_ERROR(TL_ERR_ARG, "tl_trisurface_move_vertices: NULL surface or positions");
  for (size_t i = 0; i < s->n_vertices; ++i) s->x[i] = tl_v3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  if (v)
    for (size_t i = 0; i < s->n_vertices; ++i) s->v[i] = tl_v3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  TL_CHECK(check_vertices(s));
  surface_box(s);
  ++s->version;
  s->geometry_stale = 1;
  return TL_OK;
}

TlStatus tl_trisurface_vertices_moved(TlTriSurface *s)
{
  if (!s) TL_ERROR(TL_ERR_ARG, "tl_trisurface_vertices_moved: NULL surface");
  TL_CHECK(check_vertices(s));
  surface_box(s);
  ++s->version;
  s->geometry_stale = 1;
  return TL_OK;
}

TlStatus tl_trisurface_update_triangles(TlTriSurface *s, size_t n, const int32_t *triangles)
{
  for (size_t k = 0; k < n; ++k) {
    const size_t t = (size_t)triangles[k];
    if (t >= s->n_triangles) TL_ERROR(TL_ERR_ARG, "triangle %zu outside [0, %zu)", t, s->n_triangles);
    /* the triangle and those across its edges (periodic twins included) */
    for (int j = 0; j < 3; ++j) {
      const size_t e = (size_t)s->tri_edge[3 * t + (size_t)j];
      for (int side = 0; side < 2; ++side)
        if (s->edge_tri[2 * e + (size_t)side] >= 0) TL_CHECK(triangle_geometry(s, (size_t)s->edge_tri[2 * e + (size_t)side]));
    }
  }
  for (size_t k = 0; k < n; ++k)
    for (int j = 0; j < 3; ++j) edge_geometry(s, (size_t)s->tri_edge[3 * (size_t)triangles[k] + (size_t)j]);
  return TL_OK;
}

TlStatus tl_trisurface_set_tolerances(TlTriSurface *s, double flat_tolerance, double quality_tolerance)
{
  if (!s) TL_ERROR(TL_ERR_ARG, "tl_trisurface_set_tolerances: NULL surface");
  if (!(flat_tolerance > 0.0 && flat_tolerance < 1.0))
    TL_ERROR(TL_ERR_ARG, "flat tolerance %g outside (0, 1)", flat_tolerance);
  if (!(quality_tolerance > 0.0 && quality_tolerance < 1.0))
    TL_ERROR(TL_ERR_ARG, "quality tolerance %g outside (0, 1)", quality_tolerance);
  s->flat_tolerance = flat_tolerance;
  s->quality_tolerance = quality_tolerance;
  TL_CHECK(tl_trisurface_update(s));
  return TL_OK;
}

TlStatus tl_trisurface_set_feature_angle(TlTriSurface *s, double degrees)
{
  if (!s) TL_ERROR(TL_ERR_ARG, "tl_trisurface_set_feature_angle: NULL surface");
  if (!(degrees >= 0.0 && degrees <= 180.0))
    TL_ERROR(TL_ERR_ARG, "feature angle %g degrees outside [0, 180]", degrees);
  s->feature_angle = degrees;
  s->feature_cos = cos(degrees * (TL_PI / 180.0));
  for (size_t e = 0; e < s->n_edges; ++e) edge_geometry(s, e);
  return TL_OK;
}

TlEdgeShape tl_trisurface_edge_shape_seen_from(const TlTriSurface *s, int e, TlVec3 x, int t)
{
  TlEdgeShape shape = (TlEdgeShape)s->edge_shape[e];
  if (shape == TL_EDGE_FLAT || shape == TL_EDGE_BOUNDARY) return shape;
  /* which side of each face's plane the centre lies on, decided exactly
   * (x in A's frame, x + shift in B's across a periodic face) */
  if (t == s->edge_tri[2 * e + 1]) x = tl_v3_sub(x, s->edge_shift[e]);
  const int *va = s->tri + 3 * (size_t)s->edge_tri[2 * e], *vb = s->tri + 3 * (size_t)s->edge_tri[2 * e + 1];
  TlVec3 xb = tl_v3_add(x, s->edge_shift[e]);
  int above_a = tl_orient3d(s->x[va[0]], s->x[va[1]], s->x[va[2]], x) > 0;
  int above_b = tl_orient3d(s->x[vb[0]], s->x[vb[1]], s->x[vb[2]], xb) > 0;
  int outside = shape == TL_EDGE_CONVEX ? (above_a || above_b) : (above_a && above_b);
  if (outside) return shape;
  return shape == TL_EDGE_CONVEX ? TL_EDGE_CONCAVE : TL_EDGE_CONVEX;
}

TlStatus tl_trisurface_create_rectangle(double x0, double y0, double lx, double ly, double z0,
                                        int nx, int ny, int pattern, TlTriSurface **surface)
{
  if (nx < 1 || ny < 1) TL_ERROR(TL_ERR_ARG, "rectangle needs nx, ny >= 1 (got %d, %d)", nx, ny);
  if (pattern < 0 || pattern > 2) TL_ERROR(TL_ERR_ARG, "rectangle pattern %d outside [0, 2]", pattern);
  if (!(lx > 0.0 && ly > 0.0)) TL_ERROR(TL_ERR_ARG, "rectangle sides %g, %g must be positive", lx, ly);
  size_t ncorner = (size_t)(nx + 1) * (size_t)(ny + 1);
  size_t nsq = (size_t)nx * (size_t)ny;
  size_t nv = ncorner + (pattern == 2 ? nsq : 0);
  size_t nt = nsq * (pattern == 2 ? 4 : 2);
  double *x = NULL;
  int *tri = NULL;
  TlStatus status = TL_OK;
  TL_CHECK_GOTO(status, tl_calloc(&x, 3 * nv, sizeof *x), done);
  TL_CHECK_GOTO(status, tl_calloc(&tri, 3 * nt, sizeof *tri), done);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      size_t id = (size_t)j * (size_t)(nx + 1) + (size_t)i;
      x[3 * id] = x0 + lx * i / nx;
      x[3 * id + 1] = y0 + ly * j / ny;
      x[3 * id + 2] = z0;
    }
  size_t t = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      int p00 = j * (nx + 1) + i, p10 = p00 + 1, p01 = p00 + nx + 1, p11 = p01 + 1;
      int q[12], n = 0;
      if (pattern == 0 || (pattern == 1 && (i + j) % 2 == 0)) {
        int tmp[6] = {p00, p10, p11, p00, p11, p01};
        for (n = 0; n < 6; ++n) q[n] = tmp[n];
      } else if (pattern == 1) {
        int tmp[6] = {p00, p10, p01, p10, p11, p01};
        for (n = 0; n < 6; ++n) q[n] = tmp[n];
      } else {
        int c = (int)ncorner + j * nx + i;
        x[3 * c] = x0 + lx * (i + 0.5) / nx;
        x[3 * c + 1] = y0 + ly * (j + 0.5) / ny;
        x[3 * c + 2] = z0;
        int tmp[12] = {p00, p10, c, p10, p11, c, p11, p01, c, p01, p00, c};
        for (n = 0; n < 12; ++n) q[n] = tmp[n];
      }
      for (int m = 0; m < n; ++m) tri[3 * t + m] = q[m];
      t += (size_t)n / 3;
    }
  TL_CHECK_GOTO(status, tl_trisurface_create(nv, x, nt, tri, surface), done);
done:
  tl_free(&x);
  tl_free(&tri);
  return status;
}

TlStatus tl_trisurface_create_box(TlVec3 lo, TlVec3 hi, TlTriSurface **surface)
{
  if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z))
    TL_ERROR(TL_ERR_ARG, "box corners lo (%g, %g, %g), hi (%g, %g, %g) do not span a volume", lo.x,
             lo.y, lo.z, hi.x, hi.y, hi.z);
  double x[24];
  for (int id = 0; id < 8; ++id) {
    x[3 * id] = id & 1 ? hi.x : lo.x;
    x[3 * id + 1] = id & 2 ? hi.y : lo.y;
    x[3 * id + 2] = id & 4 ? hi.z : lo.z;
  }
  /* Corner c(i,j,k) = i + 2j + 4k; each face a quad counter-clockwise seen
   * from inside the box. */
  static const int quad[6][4] = {
      {0, 1, 3, 2}, /* z = lo, normal +z */
      {4, 6, 7, 5}, /* z = hi, normal -z */
      {0, 4, 5, 1}, /* y = lo, normal +y */
      {2, 3, 7, 6}, /* y = hi, normal -y */
      {0, 2, 6, 4}, /* x = lo, normal +x */
      {1, 5, 7, 3}, /* x = hi, normal -x */
  };
  int tri[36];
  for (int f = 0; f < 6; ++f) {
    const int *q = quad[f];
    int t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
    for (int m = 0; m < 6; ++m) tri[6 * f + m] = t[m];
  }
  TL_CHECK(tl_trisurface_create(8, x, 12, tri, surface));
  return TL_OK;
}

/* Whether v is a lattice vector of the domain (integer reduced coordinates
 * along periodic directions, zero along the others) other than zero. */
static int tl_is_lattice_vector(const TlDomain *d, TlVec3 v, double tol)
{
  TlVec3 r = tl_m3_mulv(d->h_inv, v);
  int nonzero = 0;
  for (int k = 0; k < 3; ++k) {
    double c = tl_v3_get(r, k), n = nearbyint(c);
    if (fabs(c - n) > tol) return 0;
    if (!d->periodic[k] && n != 0.0) return 0;
    nonzero |= n != 0.0;
  }
  return nonzero;
}

TlStatus tl_trisurface_link_periodic(TlTriSurface *s, const TlDomain *domain, double tolerance, size_t *n_linked)
{
  if (!s || !domain) TL_ERROR(TL_ERR_ARG, "tl_trisurface_link_periodic: NULL surface or domain");
  if (!(tolerance > 0.0 && tolerance < 0.1))
    TL_ERROR(TL_ERR_ARG, "periodic link tolerance %g outside (0, 0.1)", tolerance);
  if (n_linked) *n_linked = 0;
  if (!domain->any_periodic) return TL_OK;
  size_t nb = 0;
  int *be = NULL;
  TL_CHECK(tl_calloc(&be, s->n_edges + 1, sizeof *be));
  for (size_t e = 0; e < s->n_edges; ++e)
    if (s->edge_tri[2 * e] >= 0 && s->edge_tri[2 * e + 1] < 0) be[nb++] = (int)e;
  double scale = pow(fabs(tl_m3_det(domain->h)), 1.0 / 3.0);
  size_t linked = 0;
  TlStatus status = TL_OK;
  for (size_t i = 0; i < nb; ++i) {
    int e = be[i];
    if (e < 0) continue;
    int ta = s->edge_tri[2 * e], ka = 0;
    while (ka < 2 && s->tri_edge[3 * (size_t)ta + ka] != e) ++ka;
    int a_from = s->tri[3 * (size_t)ta + ka], a_to = s->tri[3 * (size_t)ta + (ka + 1) % 3];
    for (size_t j = i + 1; j < nb; ++j) {
      int f = be[j];
      if (f < 0) continue;
      int tb = s->edge_tri[2 * f], kb = 0;
      while (kb < 2 && s->tri_edge[3 * (size_t)tb + kb] != f) ++kb;
      int b_from = s->tri[3 * (size_t)tb + kb], b_to = s->tri[3 * (size_t)tb + (kb + 1) % 3];
      /* images traversed the same way: inconsistent orientation */
      TlVec3 u1 = tl_v3_sub(s->x[b_from], s->x[a_from]), u2 = tl_v3_sub(s->x[b_to], s->x[a_to]);
      if (tl_v3_norm(tl_v3_sub(u1, u2)) <= tolerance * scale && tl_is_lattice_vector(domain, u1, tolerance)) {
        status = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                              "edges %d (triangle %d) and %d (triangle %d) are periodic images traversed in the "
                              "same direction: orient the triangles consistently across the periodic faces",
                              e, ta, f, tb);
        goto done;
      }
      /* opposite traversal: b_from is the image of a_to, b_to that of a_from */
      TlVec3 t1 = tl_v3_sub(s->x[b_from], s->x[a_to]), t2 = tl_v3_sub(s->x[b_to], s->x[a_from]);
      if (tl_v3_norm(tl_v3_sub(t1, t2)) > tolerance * scale || !tl_is_lattice_vector(domain, t1, tolerance)) continue;
      /* join: f is absorbed into e */
      s->edge_tri[2 * e + 1] = tb;
      s->tri_nbr[3 * (size_t)ta + ka] = tb;
      s->tri_nbr[3 * (size_t)tb + kb] = ta;
      s->tri_edge[3 * (size_t)tb + kb] = e;
      s->edge_twin[e] = s->edge_vertex[2 * e] == a_to ? b_from : b_to;
      s->edge_tri[2 * f] = -1;
      s->edge_tri[2 * f + 1] = -1;
      be[j] = -1;
      ++linked;
      break;
    }
  }
  TL_CHECK_GOTO(status, tl_trisurface_update(s), done);
  if (n_linked) *n_linked = linked;
done:
  tl_free(&be);
  return status;
}
