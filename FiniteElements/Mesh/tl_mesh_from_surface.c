/* Closed surface -> tetrahedral solid: the checks of the surface, the
 * TlMesh built from CGAL's tetrahedra (tl_mesh_from_surface_cgal.cpp). */
#include "tl_mesh_from_surface.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_config.h"
#include "tl_memory.h"
#include "tl_mesh_from_surface_cgal.h"
#include "tl_predicates.h"

/* A triangle whose area is below this fraction of its longest edge squared
 * is a needle or a collapsed triangle: no mesher can respect it. */
#define TL_SURFACE_MIN_SHAPE 1e-12

void tl_mesh_from_surface_options_default(TlMeshFromSurfaceOptions *o)
{
  memset(o, 0, sizeof *o);
  o->type = &tl_element_tet4;
  o->facet_angle = 25.0;
  o->radius_edge = 3.0;
  o->feature_angle = 60.0;
  o->exude = 1;
}

static TlStatus surface_alloc(size_t nv, size_t nt, double **x, size_t **t)
{
  TL_CHECK(tl_calloc(x, 3 * nv, sizeof(double)));
  TlStatus st = tl_calloc(t, 3 * nt, sizeof(size_t));
  if (st) tl_free(x);
  return st;
}

static const double *vtx(const TlSurfaceArrays *s, size_t i) { return s->x + 3 * i; }

static void surface_corners(const void *ctx, size_t t, TlVec3 c[3])
{
  const TlSurfaceArrays *s = ctx;
  for (int k = 0; k < 3; ++k) {
    const double *p = vtx(s, s->tri[3 * t + k]);
    c[k] = tl_v3(p[0], p[1], p[2]);
  }
}

static void sub3(const double *a, const double *b, double *out)
{
  for (int k = 0; k < 3; ++k) out[k] = a[k] - b[k];
}

static void cross3(const double *a, const double *b, double *out)
{
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

typedef struct {
  size_t lo, hi; /* vertex indices, lo < hi */
  size_t tri;
  int forward;   /* the triangle runs lo -> hi */
} Edge;

static int cmp_edge(const void *pa, const void *pb)
{
  const Edge *a = pa, *b = pb;
  if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
  if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
  return a->tri < b->tri ? -1 : (a->tri > b->tri);
}

/* Every edge in exactly two triangles, traversed once each way. */
static TlStatus check_edges(const TlSurfaceArrays *s)
{
  size_t ne = 3 * s->n_triangles;
  Edge *e = NULL;
  TL_CHECK(tl_calloc(&e, ne, sizeof *e));
  for (size_t t = 0; t < s->n_triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      size_t a = s->tri[3 * t + k], b = s->tri[3 * t + (k + 1) % 3];
      Edge *x = &e[3 * t + k];
      x->lo = a < b ? a : b;
      x->hi = a < b ? b : a;
      x->tri = t;
      x->forward = a < b;
    }
  qsort(e, ne, sizeof *e, cmp_edge);
  TlStatus st = TL_OK;
  for (size_t i = 0; i < ne;) {
    size_t j = i;
    while (j < ne && e[j].lo == e[i].lo && e[j].hi == e[i].hi) ++j;
    const double *p = vtx(s, e[i].lo), *q = vtx(s, e[i].hi);
    if (j - i == 1) {
      st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                        "the surface is open: edge (%zu, %zu) from (%g, %g, %g) to (%g, %g, %g) "
                        "belongs to triangle %zu only (a closed surface has every edge in two "
                        "triangles)", e[i].lo, e[i].hi, p[0], p[1], p[2], q[0], q[1], q[2], e[i].tri);
      break;
    }
    if (j - i > 2) {
      st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                        "the surface is not manifold: edge (%zu, %zu) from (%g, %g, %g) to (%g, %g, "
                        "%g) belongs to %zu triangles (%zu, %zu, %zu...), at most 2",
                        e[i].lo, e[i].hi, p[0], p[1], p[2], q[0], q[1], q[2], j - i, e[i].tri,
                        e[i + 1].tri, e[i + 2].tri);
      break;
    }
    if (e[i].forward == e[i + 1].forward) {
      st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                        "the surface is not consistently oriented: triangles %zu and %zu both run "
                        "edge (%zu, %zu) from (%g, %g, %g) to (%g, %g, %g) the same way",
                        e[i].tri, e[i + 1].tri, e[i].lo, e[i].hi, p[0], p[1], p[2], q[0], q[1], q[2]);
      break;
    }
    i = j;
  }
  tl_free(&e);
  return st;
}

TlStatus tl_surface_check(const TlSurfaceArrays *s, double *volume, double *area)
{
  if (!s || !s->x || !s->tri) TL_ERROR(TL_ERR_ARG, "surface: NULL arrays");
  if (s->n_vertices < 4 || s->n_triangles < 4)
    TL_ERROR(TL_ERR_ARG, "surface of %zu vertices and %zu triangles: a closed surface has at least 4 "
             "of each", s->n_vertices, s->n_triangles);
  for (size_t i = 0; i < 3 * s->n_vertices; ++i)
    if (!isfinite(s->x[i]))
      TL_ERROR(TL_ERR_ARG, "surface vertex %zu has a non-finite coordinate %g", i / 3, s->x[i]);
  double vol = 0.0, ar = 0.0;
  for (size_t t = 0; t < s->n_triangles; ++t) {
    const size_t *c = s->tri + 3 * t;
    for (int k = 0; k < 3; ++k)
      if (c[k] >= s->n_vertices)
        TL_ERROR(TL_ERR_ARG, "surface triangle %zu refers to vertex %zu, the surface has %zu", t, c[k],
                 s->n_vertices);
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
      TL_ERROR(TL_ERR_ARG, "surface triangle %zu (%zu, %zu, %zu) repeats a vertex", t, c[0], c[1], c[2]);
    double a[3], b[3], d[3], n[3];
    sub3(vtx(s, c[1]), vtx(s, c[0]), a);
    sub3(vtx(s, c[2]), vtx(s, c[0]), b);
    sub3(vtx(s, c[2]), vtx(s, c[1]), d);
    cross3(a, b, n);
    double l2 = fmax(dot3(a, a), fmax(dot3(b, b), dot3(d, d)));
    double twice_area = sqrt(dot3(n, n));
    if (!(twice_area > TL_SURFACE_MIN_SHAPE * l2))
      TL_ERROR(TL_ERR_ARG, "surface triangle %zu (vertices %zu, %zu, %zu at (%g, %g, %g)) has area %g "
               "m^2, %g of its longest edge squared, below the limit %g (a needle or zero-area "
               "triangle)", t, c[0], c[1], c[2], vtx(s, c[0])[0], vtx(s, c[0])[1], vtx(s, c[0])[2],
               0.5 * twice_area, 0.5 * twice_area / l2, 0.5 * TL_SURFACE_MIN_SHAPE);
    ar += 0.5 * twice_area;
    vol += dot3(vtx(s, c[0]), n) / 6.0; /* divergence theorem */
  }
  TL_CHECK(check_edges(s));
  if (tl_volume_sign(s->n_triangles, surface_corners, s) != 1) /* the exact sign, not vol's */
    TL_ERROR(TL_ERR_ARG, "the surface encloses a volume %g m^3: it must be positive (triangles "
             "counter-clockwise seen from outside); this surface is inside out", vol);
#if TALUS_WITH_CGAL
  {
    TlCgalSurface cs = {s->n_vertices, s->x, s->n_triangles, s->tri};
    size_t pair[2] = {0, 0}, n_pairs = 0;
    char msg[256] = "";
    if (tl_cgal_self_intersection(&cs, pair, &n_pairs, msg, sizeof msg))
      TL_ERROR(TL_ERR_ARG, "surface self-intersection test failed: %s", msg);
    if (n_pairs)
      TL_ERROR(TL_ERR_ARG, "the surface intersects itself: triangles %zu and %zu (and %zu pair(s) in "
               "all) meet other than in a shared edge or vertex", pair[0], pair[1], n_pairs);
  }
#endif
  if (volume) *volume = vol;
  if (area) *area = ar;
  return TL_OK;
}

/* The mesher's post-processing (with CGAL only). */
#if TALUS_WITH_CGAL
static double tet_signed_volume(const double *x, const size_t *c)
{
  double a[3], b[3], d[3], n[3];
  sub3(x + 3 * c[1], x + 3 * c[0], a);
  sub3(x + 3 * c[2], x + 3 * c[0], b);
  sub3(x + 3 * c[3], x + 3 * c[0], d);
  cross3(a, b, n);
  return dot3(n, d) / 6.0;
}

/* Dihedral angles (degrees) of a tetrahedron: along each edge, between the
 * two faces meeting there. */
static void tet_dihedrals(const double *x, const size_t *c, double *lo, double *hi)
{
  static const int edges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                  {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
  for (int k = 0; k < 6; ++k) {
    const double *p = x + 3 * c[edges[k][0]], *q = x + 3 * c[edges[k][1]];
    const double *r = x + 3 * c[edges[k][2]], *s = x + 3 * c[edges[k][3]];
    double e[3], u[3], v[3], n1[3], n2[3];
    sub3(q, p, e);
    sub3(r, p, u);
    sub3(s, p, v);
    cross3(e, u, n1);
    cross3(e, v, n2);
    double cs = dot3(n1, n2) / sqrt(dot3(n1, n1) * dot3(n2, n2));
    double ang = acos(fmax(-1.0, fmin(1.0, cs))) * 180.0 / M_PI;
    if (ang < *lo) *lo = ang;
    if (ang > *hi) *hi = ang;
  }
}

typedef struct {
  size_t lo, hi, tet;
  int slot; /* 4 + local edge */
} TetEdge;

static int cmp_tet_edge(const void *pa, const void *pb)
{
  const TetEdge *a = pa, *b = pb;
  if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
  if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
  return 0;
}

/* Tet10 from Tet4: one midside node per distinct edge, at its midpoint, in
 * the type's edge order (its nodes 4..9 between the corners named below). */
static TlStatus add_midside_nodes(const TlElementType *type, size_t *n_nodes, double **x,
                                  size_t n_tets, const size_t *c4, size_t *c10)
{
  /* The edge of each midside node, read from the type's reference
   * coordinates so that no node order is assumed here. */
  int ends[6][2];
  for (int m = 0; m < 6; ++m) {
    const double *xm = type->ref_coords + 3 * (4 + m);
    int found = 0;
    for (int a = 0; a < 4 && !found; ++a)
      for (int b = a + 1; b < 4 && !found; ++b) {
        const double *xa = type->ref_coords + 3 * a, *xb = type->ref_coords + 3 * b;
        int ok = 1;
        for (int d = 0; d < 3; ++d) ok &= fabs(0.5 * (xa[d] + xb[d]) - xm[d]) < 1e-12;
        if (ok) {
          ends[m][0] = a;
          ends[m][1] = b;
          found = 1;
        }
      }
    if (!found)
      TL_ERROR(TL_ERR_UNSUPPORTED, "element type %s: node %d is not the midpoint of an edge",
               type->header.name, 4 + m);
  }
  size_t ne = 6 * n_tets;
  TetEdge *e = NULL;
  TL_CHECK(tl_calloc(&e, ne ? ne : 1, sizeof *e));
  for (size_t t = 0; t < n_tets; ++t)
    for (int m = 0; m < 6; ++m) {
      size_t a = c4[4 * t + ends[m][0]], b = c4[4 * t + ends[m][1]];
      e[6 * t + m] = (TetEdge){a < b ? a : b, a < b ? b : a, t, 4 + m};
    }
  qsort(e, ne, sizeof *e, cmp_tet_edge);
  size_t distinct = 0;
  for (size_t i = 0; i < ne; ++i)
    if (i == 0 || cmp_tet_edge(&e[i], &e[i - 1])) ++distinct;
  TlStatus st = tl_realloc(x, 3 * (*n_nodes + distinct), sizeof(double));
  if (st) {
    tl_free(&e);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  size_t next = *n_nodes;
  for (size_t t = 0; t < n_tets; ++t) memcpy(c10 + 10 * t, c4 + 4 * t, 4 * sizeof(size_t));
  for (size_t i = 0; i < ne; ++i) {
    if (i == 0 || cmp_tet_edge(&e[i], &e[i - 1])) {
      for (int d = 0; d < 3; ++d) (*x)[3 * next + d] = 0.5 * ((*x)[3 * e[i].lo + d] + (*x)[3 * e[i].hi + d]);
      ++next;
    }
    c10[10 * e[i].tet + e[i].slot] = next - 1;
  }
  *n_nodes = next;
  tl_free(&e);
  return TL_OK;
}

#endif

static TlStatus check_options(const TlMeshFromSurfaceOptions *o, const TlSurfaceArrays *s,
                              double area, TlCgalMeshCriteria *c)
{
  const TlElementType *t = o->type ? o->type : &tl_element_tet4;
  if (t->shape != TL_SHAPE_TET || t->dim != 3 || t->n_corners != 4 || (t->n_nodes != 4 && t->n_nodes != 10))
    TL_ERROR(TL_ERR_ARG, "meshing a surface: element type %s is not a 4- or 10-node tetrahedron",
             t->header.name);
  if (!(o->cell_size > 0.0) || !isfinite(o->cell_size))
    TL_ERROR(TL_ERR_ARG, "meshing a surface: cell size %g m must be > 0", o->cell_size);
  c->cell_size = o->cell_size;
  c->facet_size = o->facet_size > 0.0 ? o->facet_size : o->cell_size;
  c->facet_distance = o->facet_distance > 0.0 ? o->facet_distance : c->facet_size / 10.0;
  c->edge_size = o->edge_size > 0.0 ? o->edge_size : c->facet_size;
  if (!(o->facet_angle > 0.0 && o->facet_angle <= 30.0))
    TL_ERROR(TL_ERR_ARG, "meshing a surface: facet angle %g degrees outside (0, 30] (beyond 30 the "
             "surface refinement need not end)", o->facet_angle);
  if (!(o->radius_edge >= 2.0 && isfinite(o->radius_edge)))
    TL_ERROR(TL_ERR_ARG, "meshing a surface: radius-edge ratio %g below 2 (Delaunay refinement need "
             "not end below 2)", o->radius_edge);
  if (!(o->feature_angle > 0.0 && o->feature_angle < 180.0))
    TL_ERROR(TL_ERR_ARG, "meshing a surface: feature angle %g degrees outside (0, 180)", o->feature_angle);
  /* A cell size tiny against the body asks for more tetrahedra than memory
   * holds: estimate the count from the surface's bounding box before
   * meshing (a regular tetrahedron of circumradius R has volume 8 R^3 /
   * (9 sqrt 3)); and the surface triangles from its area. */
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < s->n_vertices; ++i)
    for (int d = 0; d < 3; ++d) {
      lo[d] = fmin(lo[d], s->x[3 * i + d]);
      hi[d] = fmax(hi[d], s->x[3 * i + d]);
    }
  double box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
  double r = fmin(c->cell_size, c->facet_size);
  double est = box / (8.0 * r * r * r / (9.0 * sqrt(3.0))) + area / (r * r);
  if (!(est <= 2e7))
    TL_ERROR(TL_ERR_ARG, "meshing a surface: size %g m in a bounding box of %g m^3 asks for about %.3g "
             "tetrahedra, beyond the limit 2e7: raise the cell and facet sizes", r, box, est);
  c->facet_angle = o->facet_angle;
  c->radius_edge = o->radius_edge;
  c->feature_angle = o->feature_angle;
  c->exude = o->exude;
  c->seed = o->seed;
  return TL_OK;
}

TlStatus tl_mesh_from_surface(const TlSurfaceArrays *s, const TlMeshFromSurfaceOptions *o_in,
                              TlMesh **mesh, TlMeshFromSurfaceInfo *info)
{
  if (!mesh) TL_ERROR(TL_ERR_ARG, "tl_mesh_from_surface: NULL output");
  *mesh = NULL;
  TlMeshFromSurfaceOptions o;
  if (o_in) o = *o_in;
  else tl_mesh_from_surface_options_default(&o);
  if (!o.type) o.type = &tl_element_tet4;
  double vol = 0.0, area = 0.0;
  TL_CHECK(tl_surface_check(s, &vol, &area));
  TlCgalMeshCriteria crit;
  TL_CHECK(check_options(&o, s, area, &crit));
#if !TALUS_WITH_CGAL
  (void)vol;
  (void)info;
  TL_ERROR(TL_ERR_UNSUPPORTED, "meshing a surface into tetrahedra needs CGAL (build with "
           "-DTALUS_WITH_CGAL=ON and Debian libcgal-dev)");
#else
  TlCgalSurface cs = {s->n_vertices, s->x, s->n_triangles, s->tri};
  TlCgalTetMesh tm;
  char msg[256] = "";
  if (tl_cgal_mesh_3(&cs, &crit, &tm, msg, sizeof msg))
    TL_ERROR(TL_ERR_NUMERIC, "meshing the surface (%zu triangles) failed: %s", s->n_triangles, msg);
  TlStatus st = TL_OK;
  double *x = NULL;
  size_t *c10 = NULL, n_nodes = tm.n_nodes;
  TlMesh *m = NULL;
  TlFaceRef *faces = NULL;
  if (tm.n_tets == 0) {
    st = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__,
                      "meshing the surface gave no tetrahedron: the cell size %g m may exceed the body",
                      crit.cell_size);
    goto done;
  }
  TL_CHECK_GOTO(st, tl_calloc(&x, 3 * n_nodes, sizeof(double)), done);
  memcpy(x, tm.x, 3 * n_nodes * sizeof(double));
  double min_vol = INFINITY, mesh_vol = 0.0, dmin = 180.0, dmax = 0.0;
  for (size_t t = 0; t < tm.n_tets; ++t) {
    size_t *c = tm.tets + 4 * t;
    double v = tet_signed_volume(x, c);
    /* the corner order from the exact orientation, the volume only summed */
    if (tl_orient3d(tl_v3(x[3 * c[0]], x[3 * c[0] + 1], x[3 * c[0] + 2]), tl_v3(x[3 * c[1]], x[3 * c[1] + 1], x[3 * c[1] + 2]),
                    tl_v3(x[3 * c[2]], x[3 * c[2] + 1], x[3 * c[2] + 2]), tl_v3(x[3 * c[3]], x[3 * c[3] + 1], x[3 * c[3] + 2])) < 0) {
      /* the type's corner order is positive: swap two corners */
      size_t tmp = c[1];
      c[1] = c[2];
      c[2] = tmp;
    }
    v = fabs(v);
    min_vol = fmin(min_vol, v);
    mesh_vol += v;
    tet_dihedrals(x, c, &dmin, &dmax);
  }
  size_t npe = (size_t)o.type->n_nodes;
  if (npe == 10) {
    TL_CHECK_GOTO(st, tl_calloc(&c10, 10 * tm.n_tets, sizeof(size_t)), done);
    TL_CHECK_GOTO(st, add_midside_nodes(o.type, &n_nodes, &x, tm.n_tets, tm.tets, c10), done);
  }
  TL_CHECK_GOTO(st, tl_mesh_create(3, &m), done);
  TL_CHECK_GOTO(st, tl_mesh_set_nodes(m, n_nodes, x), done);
  TL_CHECK_GOTO(st, tl_mesh_add_block(m, "body", o.type, tm.n_tets, npe == 10 ? c10 : tm.tets, NULL, NULL), done);
  TL_CHECK_GOTO(st, tl_mesh_finalize(m), done);
  TL_CHECK_GOTO(st, tl_calloc(&faces, m->n_boundary ? m->n_boundary : 1, sizeof *faces), done);
  memcpy(faces, m->boundary, m->n_boundary * sizeof *faces);
  TL_CHECK_GOTO(st, tl_mesh_add_face_set(m, "surface", m->n_boundary, faces), done);
  TL_CHECK_GOTO(st, tl_mesh_add_node_set_from_faces(m, "surface", "surface"), done);
  if (info) {
    info->surface_volume = vol;
    info->surface_area = area;
    info->mesh_volume = mesh_vol;
    info->n_tetrahedra = tm.n_tets;
    info->n_nodes = n_nodes;
    info->n_boundary_faces = m->n_boundary;
    info->min_dihedral = dmin;
    info->max_dihedral = dmax;
    info->min_volume = min_vol;
  }
  *mesh = m;
  m = NULL;
done:
  free(tm.x);
  free(tm.tets);
  tl_free(&x);
  tl_free(&c10);
  tl_free(&faces);
  tl_mesh_destroy(&m);
  return st;
#endif
}

TlStatus tl_mesh_from_surface_mesh(const TlSurfaceMesh *sm, const TlMeshFromSurfaceOptions *o, TlMesh **mesh,
                                   TlMeshFromSurfaceInfo *info)
{
  if (!sm) TL_ERROR(TL_ERR_ARG, "tl_mesh_from_surface_mesh: NULL surface");
  double *x = NULL;
  size_t *tri = NULL;
  TL_CHECK(surface_alloc(sm->n_vertices ? sm->n_vertices : 1, sm->n_triangles ? sm->n_triangles : 1, &x, &tri));
  for (size_t i = 0; i < sm->n_vertices; ++i) {
    x[3 * i] = sm->x[i].x;
    x[3 * i + 1] = sm->x[i].y;
    x[3 * i + 2] = sm->x[i].z;
  }
  TlStatus st = TL_OK;
  for (size_t t = 0; t < sm->n_triangles && !st; ++t)
    for (int k = 0; k < 3; ++k) {
      if (sm->tri[t][k] < 0) {
        st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "surface triangle %zu refers to vertex %d", t, sm->tri[t][k]);
        break;
      }
      tri[3 * t + k] = (size_t)sm->tri[t][k];
    }
  TlSurfaceArrays s = {sm->n_vertices, x, sm->n_triangles, tri};
  if (!st) st = tl_mesh_from_surface(&s, o, mesh, info);
  tl_free(&x);
  tl_free(&tri);
  return st;
}

TlStatus tl_mesh_add_face_set_on_plane(TlMesh *mesh, const char *name, const double point[3],
                                       const double normal_in[3], double tol)
{
  if (!mesh || !mesh->finalized) TL_ERROR(TL_ERR_STATE, "face set on a plane: the mesh is not finalized");
  double nl = sqrt(dot3(normal_in, normal_in));
  if (!(nl > 0.0) || !isfinite(nl)) TL_ERROR(TL_ERR_ARG, "face set %s: plane normal of length %g", name, nl);
  if (!(tol >= 0.0)) TL_ERROR(TL_ERR_ARG, "face set %s: tolerance %g m must be >= 0", name, tol);
  double n[3] = {normal_in[0] / nl, normal_in[1] / nl, normal_in[2] / nl};
  TlFaceRef *sel = NULL;
  size_t k = 0;
  TL_CHECK(tl_calloc(&sel, mesh->n_boundary ? mesh->n_boundary : 1, sizeof *sel));
  for (size_t i = 0; i < mesh->n_boundary; ++i) {
    TlFaceRef f = mesh->boundary[i];
    const TlElementType *ft = mesh->blocks[f.block].type->face_type;
    size_t nodes[TL_ELEMENT_MAX_FACE_NODES];
    double fx[3 * TL_ELEMENT_MAX_FACE_NODES];
    tl_mesh_face_nodes(mesh, f, nodes, fx);
    int on = 1;
    for (int a = 0; a < ft->n_nodes && on; ++a) {
      double dpt[3];
      sub3(fx + 3 * a, point, dpt);
      on = fabs(dot3(dpt, n)) <= tol;
    }
    if (!on) continue;
    double s[3] = {1.0 / 3.0, 1.0 / 3.0, 0.0}, nda[3];
    tl_element_face_normal(ft, 3, fx, s, nda);
    double l = sqrt(dot3(nda, nda));
    if (l > 0.0 && dot3(nda, n) / l >= cos(1e-6)) sel[k++] = f;
  }
  TlStatus st = TL_OK;
  if (k == 0)
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                      "face set %s: no boundary face lies within %g m of the plane through (%g, %g, %g) "
                      "with outward normal (%g, %g, %g)", name, tol, point[0], point[1], point[2],
                      n[0], n[1], n[2]);
  if (!st) st = tl_mesh_add_face_set(mesh, name, k, sel);
  if (!st) st = tl_mesh_add_node_set_from_faces(mesh, name, name);
  tl_free(&sel);
  return st;
}

/* ------------------------------------------------------------ test surfaces */

void tl_surface_arrays_free(TlSurfaceArrays *s)
{
  if (!s) return;
  double *x = (double *)s->x;
  size_t *t = (size_t *)s->tri;
  tl_free(&x);
  tl_free(&t);
  memset(s, 0, sizeof *s);
}

TlStatus tl_surface_sphere(const double c[3], double r, int level, TlSurfaceArrays *s)
{
  if (!(r > 0.0) || !isfinite(r)) TL_ERROR(TL_ERR_ARG, "sphere surface: radius %g m must be > 0", r);
  if (level < 0 || level > 7)
    TL_ERROR(TL_ERR_ARG, "sphere surface: %d subdivisions outside [0, 7] (20 * 4^7 = 327680 triangles)", level);
  size_t nt = 20, nv = 12;
  for (int l = 0; l < level; ++l) {
    nv += 3 * nt / 2; /* one new vertex per edge */
    nt *= 4;
  }
  double *x = NULL;
  size_t *t = NULL;
  TL_CHECK(surface_alloc(nv, nt, &x, &t));
  const double p = (1.0 + sqrt(5.0)) / 2.0;
  const double ico[12][3] = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                             {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  static const size_t f[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                  {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                  {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                  {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int i = 0; i < 12; ++i)
    for (int d = 0; d < 3; ++d) x[3 * i + d] = ico[i][d];
  for (int i = 0; i < 20; ++i)
    for (int k = 0; k < 3; ++k) t[3 * i + k] = f[i][k];
  size_t cur_v = 12, cur_t = 20;
  TlStatus st = TL_OK;
  size_t *tmp = NULL, *mid = NULL;
  for (int l = 0; l < level && !st; ++l) {
    /* Edge midpoints through a sorted edge list: midpoint index per (tri, edge). */
    size_t ne = 3 * cur_t;
    Edge *e = NULL;
    if ((st = tl_calloc(&e, ne, sizeof *e))) break;
    if ((st = tl_calloc(&mid, ne, sizeof *mid))) {
      tl_free(&e);
      break;
    }
    for (size_t i = 0; i < cur_t; ++i)
      for (int k = 0; k < 3; ++k) {
        size_t a = t[3 * i + k], b = t[3 * i + (k + 1) % 3];
        e[3 * i + k] = (Edge){a < b ? a : b, a < b ? b : a, 3 * i + k, 0};
      }
    qsort(e, ne, sizeof *e, cmp_edge);
    for (size_t i = 0; i < ne; ++i) {
      if (i == 0 || e[i].lo != e[i - 1].lo || e[i].hi != e[i - 1].hi) {
        for (int d = 0; d < 3; ++d) x[3 * cur_v + d] = 0.5 * (x[3 * e[i].lo + d] + x[3 * e[i].hi + d]);
        ++cur_v;
      }
      mid[e[i].tri] = cur_v - 1; /* .tri holds the (triangle, edge) slot */
    }
    tl_free(&e);
    if ((st = tl_calloc(&tmp, 3 * cur_t, sizeof *tmp))) break;
    memcpy(tmp, t, 3 * cur_t * sizeof *tmp);
    for (size_t i = 0; i < cur_t; ++i) {
      size_t a = tmp[3 * i], b = tmp[3 * i + 1], cc = tmp[3 * i + 2];
      size_t ab = mid[3 * i], bc = mid[3 * i + 1], ca = mid[3 * i + 2];
      size_t q[4][3] = {{a, ab, ca}, {ab, b, bc}, {ca, bc, cc}, {ab, bc, ca}};
      for (int j = 0; j < 4; ++j)
        for (int k = 0; k < 3; ++k) t[3 * (4 * i + j) + k] = q[j][k];
    }
    cur_t *= 4;
    tl_free(&tmp);
    tl_free(&mid);
  }
  tl_free(&tmp);
  tl_free(&mid);
  if (st) {
    tl_free(&x);
    tl_free(&t);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  for (size_t i = 0; i < nv; ++i) {
    double l = sqrt(dot3(x + 3 * i, x + 3 * i));
    for (int d = 0; d < 3; ++d) x[3 * i + d] = c[d] + r * x[3 * i + d] / l;
  }
  *s = (TlSurfaceArrays){nv, x, nt, t};
  return TL_OK;
}

TlStatus tl_surface_cone(const double apex[3], double r, double h, double r_tip, int n, TlSurfaceArrays *s)
{
  if (!(r > 0.0) || !isfinite(r) || !(h > 0.0) || !isfinite(h))
    TL_ERROR(TL_ERR_ARG, "cone surface: radius %g m and height %g m must be > 0", r, h);
  if (!(r_tip >= 0.0 && r_tip < r))
    TL_ERROR(TL_ERR_ARG, "cone surface: tip radius %g m outside [0, %g) (the base radius)", r_tip, r);
  if (n < 3 || n > 100000) TL_ERROR(TL_ERR_ARG, "cone surface: %d rim segments outside [3, 100000]", n);
  /* Vertices: the tip (the apex, or the centre of the flat tip and its
   * ring), the base centre and the base ring; the flank between the rings
   * (a fan about the apex when sharp), the base a fan about its centre. */
  const int flat = r_tip > 0.0;
  size_t nv = (size_t)n + 2 + (flat ? (size_t)n : 0), nt = 2 * (size_t)n + (flat ? 2 * (size_t)n : 0);
  double *x = NULL;
  size_t *t = NULL;
  TL_CHECK(surface_alloc(nv, nt, &x, &t));
  for (int d = 0; d < 3; ++d) {
    x[d] = apex[d];     /* 0: apex or tip centre */
    x[3 + d] = apex[d]; /* 1: base centre */
  }
  x[5] += h;
  const size_t base0 = 2, tip0 = 2 + (size_t)n;
  for (int i = 0; i < n; ++i) {
    double a = 2.0 * M_PI * i / n;
    x[3 * (base0 + i) + 0] = apex[0] + r * cos(a);
    x[3 * (base0 + i) + 1] = apex[1] + r * sin(a);
    x[3 * (base0 + i) + 2] = apex[2] + h;
    if (flat) {
      x[3 * (tip0 + i) + 0] = apex[0] + r_tip * cos(a);
      x[3 * (tip0 + i) + 1] = apex[1] + r_tip * sin(a);
      x[3 * (tip0 + i) + 2] = apex[2];
    }
  }
  size_t k = 0;
  for (int i = 0; i < n; ++i) {
    size_t a = base0 + (size_t)i, b = base0 + (size_t)((i + 1) % n);
    /* Base (normal +z): centre, this, next. */
    size_t base_tri[3] = {1, a, b};
    memcpy(t + 3 * k++, base_tri, sizeof base_tri);
    if (!flat) {
      /* Flank seen from outside (below and beside): apex, next, this. */
      size_t fl[3] = {0, b, a};
      memcpy(t + 3 * k++, fl, sizeof fl);
      continue;
    }
    size_t ta = tip0 + (size_t)i, tb = tip0 + (size_t)((i + 1) % n);
    size_t tip_tri[3] = {0, tb, ta}; /* normal -z */
    size_t q1[3] = {ta, tb, b}, q2[3] = {ta, b, a};
    memcpy(t + 3 * k++, tip_tri, sizeof tip_tri);
    memcpy(t + 3 * k++, q1, sizeof q1);
    memcpy(t + 3 * k++, q2, sizeof q2);
  }
  *s = (TlSurfaceArrays){nv, x, nt, t};
  return TL_OK;
}

TlStatus tl_surface_box(const double lo[3], const double hi[3], int n, TlSurfaceArrays *s)
{
  for (int d = 0; d < 3; ++d)
    if (!(hi[d] > lo[d]) || !isfinite(hi[d] - lo[d]))
      TL_ERROR(TL_ERR_ARG, "box surface: side %d from %g to %g m is empty", d, lo[d], hi[d]);
  if (n < 1 || n > 1000) TL_ERROR(TL_ERR_ARG, "box surface: %d divisions outside [1, 1000]", n);
  /* The box's surface grid points: each face a (n+1)^2 grid, shared points
   * merged by their integer grid coordinates. */
  size_t np = (size_t)n + 1;
  size_t nv = np * np * np - (size_t)(n - 1) * (size_t)(n - 1) * (size_t)(n - 1); /* minus the interior */
  size_t nt = 12 * (size_t)n * (size_t)n;
  double *x = NULL;
  size_t *t = NULL, *id = NULL;
  TL_CHECK(surface_alloc(nv, nt, &x, &t));
  TlStatus st = tl_calloc(&id, np * np * np, sizeof *id);
  if (st) {
    tl_free(&x);
    tl_free(&t);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  size_t k = 0;
  for (size_t c = 0; c < np; ++c)
    for (size_t b = 0; b < np; ++b)
      for (size_t a = 0; a < np; ++a) {
        size_t g = a + np * (b + np * c);
        int on = a == 0 || b == 0 || c == 0 || a == (size_t)n || b == (size_t)n || c == (size_t)n;
        id[g] = SIZE_MAX;
        if (!on) continue;
        size_t ijk[3] = {a, b, c};
        for (int d = 0; d < 3; ++d) x[3 * k + d] = lo[d] + (hi[d] - lo[d]) * (double)ijk[d] / n;
        id[g] = k++;
      }
  size_t tt = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      int u = (axis + 1) % 3, v = (axis + 2) % 3; /* (u, v, axis) right-handed */
      for (size_t i = 0; i < (size_t)n; ++i)
        for (size_t j = 0; j < (size_t)n; ++j) {
          size_t q[4];
          size_t corners[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          for (int m = 0; m < 4; ++m) {
            size_t ijk[3];
            ijk[axis] = side ? (size_t)n : 0;
            ijk[u] = corners[m][0];
            ijk[v] = corners[m][1];
            q[m] = id[ijk[0] + np * (ijk[1] + np * ijk[2])];
          }
          /* u x v = +axis: counter-clockwise in (u, v) faces +axis. */
          if (side) {
            size_t tri[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
            memcpy(t + 3 * tt, tri, sizeof tri);
          } else {
            size_t tri[6] = {q[0], q[2], q[1], q[0], q[3], q[2]};
            memcpy(t + 3 * tt, tri, sizeof tri);
          }
          tt += 2;
        }
    }
  tl_free(&id);
  *s = (TlSurfaceArrays){k, x, nt, t};
  return TL_OK;
}
