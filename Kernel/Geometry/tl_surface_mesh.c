/* Checks and queries of surface meshes (tl_stl.h): topology by sorting
 * half-edges, volume by the divergence theorem, point containment by ray
 * parity with exact predicates; repair through the CGAL shim. */
#include "tl_stl.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_config.h"
#include "tl_memory.h"
#include "tl_predicates.h"
#include "tl_triangle_geometry.h"

typedef struct {
  int lo, hi, tri, from; /* edge (lo < hi), its triangle and the vertex it leaves */
} TlMeshHalfEdge;

static int half_edge_compare(const void *pa, const void *pb)
{
  const TlMeshHalfEdge *a = pa, *b = pb;
  if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
  if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
  return (a->tri > b->tri) - (a->tri < b->tri);
}

static TlStatus sorted_half_edges(const TlSurfaceMesh *m, TlMeshHalfEdge **h)
{
  size_t nh = 3 * m->n_triangles;
  TL_CHECK(tl_calloc(h, nh + 1, sizeof **h));
  for (size_t t = 0; t < m->n_triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      int a = m->tri[t][k], b = m->tri[t][(k + 1) % 3];
      (*h)[3 * t + (size_t)k] = (TlMeshHalfEdge){a < b ? a : b, a < b ? b : a, (int)t, a};
    }
  qsort(*h, nh, sizeof **h, half_edge_compare);
  return TL_OK;
}

/* Length of the boundary cycle through boundary half-edge (a -> b): follows
 * boundary edges from b.  Boundary half-edges are given as a sorted list of
 * (from, to) pairs. */
typedef struct {
  int from, to;
} TlDirEdge;

static int dir_compare(const void *pa, const void *pb)
{
  const TlDirEdge *a = pa, *b = pb;
  if (a->from != b->from) return a->from < b->from ? -1 : 1;
  return (a->to > b->to) - (a->to < b->to);
}

static size_t hole_length(const TlDirEdge *bd, size_t nb, TlDirEdge start)
{
  size_t len = 1;
  int at = start.to;
  while (at != start.from && len <= nb) {
    TlDirEdge key = {at, INT32_MIN};
    size_t lo = 0, hi = nb; /* first entry with from == at */
    while (lo < hi) {
      size_t mid = (lo + hi) / 2;
      if (dir_compare(&bd[mid], &key) < 0) lo = mid + 1;
      else hi = mid;
    }
    if (lo >= nb || bd[lo].from != at) break;
    at = bd[lo].to;
    ++len;
  }
  return len;
}

TlStatus tl_surface_mesh_check(const TlSurfaceMesh *m, int flags)
{
  if (!m) TL_ERROR(TL_ERR_ARG, "tl_surface_mesh_check: NULL mesh");
  if (m->n_triangles == 0) TL_ERROR(TL_ERR_ARG, "surface '%s' has no triangle", m->name);
  for (size_t t = 0; t < m->n_triangles; ++t) {
    const int *v = m->tri[t];
    for (int k = 0; k < 3; ++k)
      if (v[k] < 0 || (size_t)v[k] >= m->n_vertices)
        TL_ERROR(TL_ERR_ARG, "facet %zu: vertex index %d outside [0, %zu)", t, v[k], m->n_vertices);
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
      TL_ERROR(TL_ERR_NUMERIC, "facet %zu has zero area: two of its corners (vertices %d, %d, %d) coincide", t, v[0],
               v[1], v[2]);
    TlVec3 a = m->x[v[0]], b = m->x[v[1]], c = m->x[v[2]];
    if (!tl_v3_isfinite(a) || !tl_v3_isfinite(b) || !tl_v3_isfinite(c))
      TL_ERROR(TL_ERR_NUMERIC, "facet %zu has a non-finite vertex", t);
    if (tl_collinear3d(a, b, c))
      TL_ERROR(TL_ERR_NUMERIC, "facet %zu has zero area: its corners (%g, %g, %g), (%g, %g, %g), (%g, %g, %g) are "
               "exactly collinear", t, a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z);
    double q = tl_triangle_quality(a, b, c);
    if (!(q >= 1e-6))
      TL_ERROR(TL_ERR_NUMERIC, "facet %zu (vertices %d, %d, %d) is a needle or a cap: quality %.3g below 1e-6 "
               "(1 = equilateral)", t, v[0], v[1], v[2], q);
  }
  TlMeshHalfEdge *h = NULL;
  TlDirEdge *bd = NULL;
  TL_CHECK(sorted_half_edges(m, &h));
  TlStatus status = TL_OK;
  size_t nh = 3 * m->n_triangles, nb = 0;
  TL_CHECK_GOTO(status, tl_calloc(&bd, nh + 1, sizeof *bd), done);
  for (size_t i = 0; i < nh;) {
    size_t j = i + 1;
    while (j < nh && h[j].lo == h[i].lo && h[j].hi == h[i].hi) ++j;
    if (j - i > 2) {
      status = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                            "surface '%s': edge (%d, %d) is non-manifold: shared by %zu facets (%d, %d, %d%s)", m->name,
                            h[i].lo, h[i].hi, j - i, h[i].tri, h[i + 1].tri, h[i + 2].tri, j - i > 3 ? ", ..." : "");
      goto done;
    }
    if (j - i == 2 && h[i].from == h[i + 1].from) {
      status = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                            "surface '%s': facets %d and %d traverse their shared edge (%d, %d) in the same direction: "
                            "inconsistent orientation", m->name, h[i].tri, h[i + 1].tri, h[i].lo, h[i].hi);
      goto done;
    }
    if (j - i == 1) bd[nb++] = (TlDirEdge){h[i].from, h[i].from == h[i].lo ? h[i].hi : h[i].lo};
    i = j;
  }
  if ((flags & TL_SURFACE_CLOSED) && nb > 0) {
    qsort(bd, nb, sizeof *bd, dir_compare);
    size_t len = hole_length(bd, nb, bd[0]);
    status = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                          "surface '%s' is open where a closed one is required: boundary edge (%d, %d) of a hole of "
                          "%zu edges (%zu boundary edges in all)", m->name, bd[0].from, bd[0].to, len, nb);
    goto done;
  }
done:
  tl_free(&h);
  tl_free(&bd);
  return status;
}

int tl_surface_mesh_is_closed(const TlSurfaceMesh *m)
{
  if (!m || m->n_triangles == 0) return 0;
  TlMeshHalfEdge *h = NULL;
  if (sorted_half_edges(m, &h) != TL_OK) return 0;
  size_t nh = 3 * m->n_triangles;
  int closed = 1;
  for (size_t i = 0; i < nh && closed;) {
    size_t j = i + 1;
    while (j < nh && h[j].lo == h[i].lo && h[j].hi == h[i].hi) ++j;
    closed = j - i == 2;
    i = j;
  }
  tl_free(&h);
  return closed;
}

static void tl_surface_mesh_corners(const void *ctx, size_t t, TlVec3 c[3])
{
  const TlSurfaceMesh *m = ctx;
  for (int k = 0; k < 3; ++k) c[k] = m->x[m->tri[t][k]];
}

int tl_surface_mesh_volume_sign(const TlSurfaceMesh *m)
{
  return tl_volume_sign(m->n_triangles, tl_surface_mesh_corners, m);
}

TlStatus tl_surface_mesh_volume(const TlSurfaceMesh *m, double *volume)
{
  if (!m || !volume) TL_ERROR(TL_ERR_ARG, "tl_surface_mesh_volume: NULL argument");
  *volume = 0.0;
  TL_CHECK(tl_surface_mesh_check(m, TL_SURFACE_CLOSED));
  /* about the centre of the box, to keep the terms small */
  TlVec3 lo, hi;
  tl_surface_mesh_bounds(m, &lo, &hi);
  TlVec3 o = tl_v3_scale(tl_v3_add(lo, hi), 0.5);
  double v = 0.0;
  for (size_t t = 0; t < m->n_triangles; ++t) {
    TlVec3 a = tl_v3_sub(m->x[m->tri[t][0]], o), b = tl_v3_sub(m->x[m->tri[t][1]], o), c = tl_v3_sub(m->x[m->tri[t][2]], o);
    v += tl_v3_dot(a, tl_v3_cross(b, c));
  }
  *volume = v / 6.0;
  return TL_OK;
}

double tl_surface_mesh_area(const TlSurfaceMesh *m)
{
  double s = 0.0;
  for (size_t t = 0; m && t < m->n_triangles; ++t) {
    TlVec3 a = m->x[m->tri[t][0]], b = m->x[m->tri[t][1]], c = m->x[m->tri[t][2]];
    s += 0.5 * tl_v3_norm(tl_v3_cross(tl_v3_sub(b, a), tl_v3_sub(c, a)));
  }
  return s;
}

void tl_surface_mesh_bounds(const TlSurfaceMesh *m, TlVec3 *lo, TlVec3 *hi)
{
  TlVec3 l = tl_v3(INFINITY, INFINITY, INFINITY), h = tl_v3(-INFINITY, -INFINITY, -INFINITY);
  for (size_t i = 0; m && i < m->n_vertices; ++i) {
    TlVec3 p = m->x[i];
    l = tl_v3(fmin(l.x, p.x), fmin(l.y, p.y), fmin(l.z, p.z));
    h = tl_v3(fmax(h.x, p.x), fmax(h.y, p.y), fmax(h.z, p.z));
  }
  if (lo) *lo = l;
  if (hi) *hi = h;
}

/* Crossing of segment p -> q with triangle (a, b, c), from signs only:
 * 1 crossed, 0 missed, -1 degenerate (the segment meets an edge, a vertex,
 * or lies in the triangle's plane, or p is on the triangle: try another
 * ray), -2 p lies on the triangle. */
static int segment_crosses(TlVec3 p, TlVec3 q, TlVec3 a, TlVec3 b, TlVec3 c)
{
  int sp = tl_orient3d(a, b, c, p), sq = tl_orient3d(a, b, c, q);
  if (sp == 0) {
    /* p in the plane: on the triangle when inside its 2D extent; decided
     * from the signs of orientations about the edges with q off-plane */
    if (sq == 0) return -1;
    int s1 = tl_orient3d(p, q, a, b), s2 = tl_orient3d(p, q, b, c), s3 = tl_orient3d(p, q, c, a);
    if ((s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0)) return -2;
    return 0;
  }
  if (sq == 0) return -1;
  if (sp == sq) return 0;
  int s1 = tl_orient3d(p, q, a, b), s2 = tl_orient3d(p, q, b, c), s3 = tl_orient3d(p, q, c, a);
  if (s1 == 0 || s2 == 0 || s3 == 0) {
    /* through an edge or a vertex, or missing along an edge's line */
    if ((s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0)) return -1;
    return 0;
  }
  return (s1 == s2 && s2 == s3) ? 1 : 0;
}

TlStatus tl_surface_mesh_contains(const TlSurfaceMesh *m, TlVec3 p, int *inside)
{
  if (!m || !inside) TL_ERROR(TL_ERR_ARG, "tl_surface_mesh_contains: NULL argument");
  if (!tl_v3_isfinite(p)) TL_ERROR(TL_ERR_ARG, "tl_surface_mesh_contains: point (%g, %g, %g) is not finite", p.x, p.y, p.z);
  TlVec3 lo, hi;
  tl_surface_mesh_bounds(m, &lo, &hi);
  if (p.x < lo.x || p.y < lo.y || p.z < lo.z || p.x > hi.x || p.y > hi.y || p.z > hi.z) {
    *inside = 0;
    return TL_OK;
  }
  /* a ray to a point beyond the box, in a direction drawn from a fixed
   * sequence (reproducible) until no crossing is degenerate */
  double reach = 4.0 * (tl_v3_norm(tl_v3_sub(hi, lo)) + 1.0);
  uint64_t seed = 0x9e3779b97f4a7c15ull;
  for (int attempt = 0; attempt < 64; ++attempt) {
    TlVec3 d;
    do {
      double r[3];
      for (int k = 0; k < 3; ++k) {
        seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17;
        r[k] = 2.0 * (double)(seed >> 11) / 9007199254740992.0 - 1.0;
      }
      d = tl_v3(r[0], r[1], r[2]);
    } while (!(tl_v3_norm(d) > 0.1));
    TlVec3 q = tl_v3_axpy(p, reach / tl_v3_norm(d), d);
    int crossings = 0, degenerate = 0;
    for (size_t t = 0; t < m->n_triangles && !degenerate; ++t) {
      TlVec3 a = m->x[m->tri[t][0]], b = m->x[m->tri[t][1]], c = m->x[m->tri[t][2]];
      /* boxes first: most triangles are far from the ray */
      double bx0 = fmin(a.x, fmin(b.x, c.x)), bx1 = fmax(a.x, fmax(b.x, c.x));
      double by0 = fmin(a.y, fmin(b.y, c.y)), by1 = fmax(a.y, fmax(b.y, c.y));
      double bz0 = fmin(a.z, fmin(b.z, c.z)), bz1 = fmax(a.z, fmax(b.z, c.z));
      if (fmax(p.x, q.x) < bx0 || fmin(p.x, q.x) > bx1 || fmax(p.y, q.y) < by0 || fmin(p.y, q.y) > by1 ||
          fmax(p.z, q.z) < bz0 || fmin(p.z, q.z) > bz1)
        continue;
      int c1 = segment_crosses(p, q, a, b, c);
      if (c1 == -2) {
        *inside = -1;
        return TL_OK;
      }
      if (c1 < 0) degenerate = 1;
      else crossings += c1;
    }
    if (!degenerate) {
      *inside = crossings & 1;
      return TL_OK;
    }
  }
  TL_ERROR(TL_ERR_NUMERIC, "point (%g, %g, %g): every ray tried meets an edge or a vertex of surface '%s'", p.x, p.y,
           p.z, m->name);
}

TlStatus tl_surface_mesh_lattice_inside(const TlSurfaceMesh *m, double pitch, size_t max, double **points, size_t *n)
{
  if (!m || !points || !n) TL_ERROR(TL_ERR_ARG, "tl_surface_mesh_lattice_inside: NULL argument");
  *points = NULL;
  *n = 0;
  TL_CHECK(tl_surface_mesh_check(m, TL_SURFACE_CLOSED));
  TlVec3 lo, hi;
  tl_surface_mesh_bounds(m, &lo, &hi);
  if (!(pitch > 0.0) || !isfinite(pitch)) TL_ERROR(TL_ERR_ARG, "lattice pitch %g must be positive", pitch);
  double cells = ((hi.x - lo.x) / pitch + 1) * ((hi.y - lo.y) / pitch + 1) * ((hi.z - lo.z) / pitch + 1);
  if (!(cells <= 1e9)) TL_ERROR(TL_ERR_ARG, "lattice of pitch %g over the box of the surface has %.3g sites (limit 1e9)", pitch, cells);
  size_t cap = 0;
  double *x = NULL;
  for (double z = lo.z + 0.5 * pitch; z < hi.z && *n < max; z += pitch)
    for (double y = lo.y + 0.5 * pitch; y < hi.y && *n < max; y += pitch)
      for (double xx = lo.x + 0.5 * pitch; xx < hi.x && *n < max; xx += pitch) {
        int in = 0;
        TlStatus st = tl_surface_mesh_contains(m, tl_v3(xx, y, z), &in);
        if (st == TL_OK && in == 1) {
          if (*n == cap) {
            cap = cap ? 2 * cap : 1024;
            st = tl_realloc(&x, 3 * cap, sizeof *x);
          }
          if (st == TL_OK) x[3 * *n] = xx, x[3 * *n + 1] = y, x[3 * *n + 2] = z, ++*n;
        }
        if (st != TL_OK) {
          tl_free(&x);
          *n = 0;
          return tl_error_trace(st, __FILE__, __LINE__);
        }
      }
  *points = x;
  return TL_OK;
}

void tl_surface_repair_options_default(TlSurfaceRepairOptions *o)
{
  o->needle_ratio = 1e4;
  o->cap_cosine = -0.9999;
  o->outward = 1;
}

#if TALUS_WITH_CGAL
/* Kernel/Geometry/tl_surface_repair_cgal.cpp: the soup in, the repaired
 * mesh out (malloc'd arrays the caller frees), counts in stats[]. */
int tl_cgal_surface_repair(size_t nv, const double *x, size_t nt, const int *tri, double needle_ratio,
                           double cap_cosine, int outward, size_t *nv_out, double **x_out, size_t *nt_out,
                           int **tri_out, size_t stats[4], char *message, size_t message_size);
#endif

/* Non-manifold edges of the input, by name, before repair splits them. */
static TlStatus count_nonmanifold(const TlSurfaceMesh *m, TlSurfaceReport *r)
{
  TlMeshHalfEdge *h = NULL;
  TL_CHECK(sorted_half_edges(m, &h));
  size_t nh = 3 * m->n_triangles;
  for (size_t i = 0; i < nh;) {
    size_t j = i + 1;
    while (j < nh && h[j].lo == h[i].lo && h[j].hi == h[i].hi) ++j;
    if (j - i > 2 && h[i].lo != h[i].hi) {
      if (!r->nonmanifold_edges)
        snprintf(r->first_nonmanifold, sizeof r->first_nonmanifold, "edge (%d, %d): facets %d, %d, %d%s", h[i].lo,
                 h[i].hi, h[i].tri, h[i + 1].tri, h[i + 2].tri, j - i > 3 ? ", ..." : "");
      ++r->nonmanifold_edges;
    }
    i = j;
  }
  tl_free(&h);
  return TL_OK;
}

#if TALUS_WITH_CGAL
/* Holes after repair: cycles of boundary half-edges. */
static TlStatus count_holes(const TlSurfaceMesh *m, TlSurfaceReport *r)
{
  TlMeshHalfEdge *h = NULL;
  TlDirEdge *bd = NULL;
  unsigned char *seen = NULL;
  TL_CHECK(sorted_half_edges(m, &h));
  TlStatus status = TL_OK;
  size_t nh = 3 * m->n_triangles, nb = 0;
  TL_CHECK_GOTO(status, tl_calloc(&bd, nh + 1, sizeof *bd), done);
  for (size_t i = 0; i < nh;) {
    size_t j = i + 1;
    while (j < nh && h[j].lo == h[i].lo && h[j].hi == h[i].hi) ++j;
    if (j - i == 1) bd[nb++] = (TlDirEdge){h[i].from, h[i].from == h[i].lo ? h[i].hi : h[i].lo};
    i = j;
  }
  qsort(bd, nb, sizeof *bd, dir_compare);
  TL_CHECK_GOTO(status, tl_calloc(&seen, nb + 1, 1), done);
  r->boundary_edges = nb;
  for (size_t i = 0; i < nb; ++i) {
    if (seen[i]) continue;
    /* walk the cycle, marking */
    size_t len = 0, k = i;
    int first = bd[i].from;
    char names[64] = "";
    size_t used = 0;
    while (k < nb && !seen[k]) {
      seen[k] = 1;
      if (used < sizeof names - 12) used += (size_t)snprintf(names + used, sizeof names - used, "%s%d", len ? ", " : "", bd[k].from);
      ++len;
      int at = bd[k].to;
      if (at == first) break;
      TlDirEdge key = {at, INT32_MIN};
      size_t lo = 0, hi = nb;
      while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (dir_compare(&bd[mid], &key) < 0) lo = mid + 1;
        else hi = mid;
      }
      k = lo < nb && bd[lo].from == at ? lo : nb;
    }
    if (!r->holes)
      snprintf(r->first_hole, sizeof r->first_hole, "hole of %zu edges through vertices %s%s", len, names,
               used >= sizeof names - 12 ? ", ..." : "");
    ++r->holes;
  }
done:
  tl_free(&h);
  tl_free(&bd);
  tl_free(&seen);
  return status;
}
#endif

TlStatus tl_surface_mesh_repair(TlSurfaceMesh *m, const TlSurfaceRepairOptions *options, TlSurfaceReport *report)
{
  if (!m) TL_ERROR(TL_ERR_ARG, "tl_surface_mesh_repair: NULL mesh");
  TlSurfaceRepairOptions o;
  tl_surface_repair_options_default(&o);
  if (options) o = *options;
  if (!(o.needle_ratio > 1.0)) TL_ERROR(TL_ERR_ARG, "needle ratio %g must exceed 1", o.needle_ratio);
  if (!(o.cap_cosine > -1.0 && o.cap_cosine < 0.0)) TL_ERROR(TL_ERR_ARG, "cap cosine %g outside (-1, 0)", o.cap_cosine);
  TlSurfaceReport r;
  memset(&r, 0, sizeof r);
  TL_CHECK(count_nonmanifold(m, &r));
#if TALUS_WITH_CGAL
  size_t nv = 0, nt = 0, stats[4] = {0, 0, 0, 0};
  double *x = NULL;
  int *tri = NULL;
  char msg[256] = "";
  if (tl_cgal_surface_repair(m->n_vertices, &m->x[0].x, m->n_triangles, &m->tri[0][0], o.needle_ratio, o.cap_cosine,
                             o.outward, &nv, &x, &nt, &tri, stats, msg, sizeof msg) != 0) {
    free(x);
    free(tri);
    TL_ERROR(TL_ERR_NUMERIC, "surface '%s' could not be repaired: %s", m->name, msg);
  }
  if (nt == 0) {
    free(x);
    free(tri);
    TL_ERROR(TL_ERR_NUMERIC, "surface '%s': no triangle is left after removing %zu degenerate ones", m->name, stats[1]);
  }
  TlSurfaceMesh *fixed = NULL;
  TlStatus status = tl_surface_mesh_create(nv, x, nt, tri, &fixed);
  free(x);
  free(tri);
  TL_CHECK(status);
  memcpy(fixed->name, m->name, sizeof m->name);
  tl_free(&m->x);
  tl_free(&m->tri);
  *m = *fixed;
  tl_free(&fixed);
  r.vertices_merged = stats[0];
  r.triangles_removed = stats[1];
  r.triangles_flipped = stats[2];
  r.vertices_split = stats[3];
  TL_CHECK(count_holes(m, &r));
  r.closed = r.boundary_edges == 0;
  if (r.closed) TL_CHECK(tl_surface_mesh_volume(m, &r.volume));
  else TL_CHECK(tl_surface_mesh_check(m, 0));
  if (report) *report = r;
  return TL_OK;
#else
  (void)report;
  TL_ERROR(TL_ERR_UNSUPPORTED, "surface '%s': repair needs CGAL (build with -DTALUS_WITH_CGAL=ON, Debian libcgal-dev)",
           m->name);
#endif
}
