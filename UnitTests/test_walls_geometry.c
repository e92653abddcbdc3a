/* Triangle geometry (closest point, face/edge/vertex contact), degenerate
 * triangles refused, surface topology and edge shapes (flat, convex,
 * concave) kept up to date as the surface moves. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "talus.h"
#include "tl_test.h"
#include "tl_trisurface.h"

static double urand(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

/* Independent oracle: the nearest of the face projection (if inside) and
 * the closest points of the three segments. */
static double oracle_distance(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p)
{
  TlVec3 v[3] = {a, b, c};
  double best = INFINITY;
  for (int k = 0; k < 3; ++k) {
    TlVec3 s0 = v[k], s1 = v[(k + 1) % 3], d = tl_v3_sub(s1, s0);
    double t = tl_v3_dot(tl_v3_sub(p, s0), d) / tl_v3_norm2(d);
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    best = fmin(best, tl_v3_norm(tl_v3_sub(p, tl_v3_axpy(s0, t, d))));
  }
  TlVec3 n = tl_v3_normalize(tl_v3_cross(tl_v3_sub(b, a), tl_v3_sub(c, a)));
  TlVec3 q = tl_v3_axpy(p, -tl_v3_dot(tl_v3_sub(p, a), n), n);
  int inside = 1;
  for (int k = 0; k < 3; ++k) {
    TlVec3 e = tl_v3_sub(v[(k + 1) % 3], v[k]);
    if (tl_v3_dot(tl_v3_cross(e, tl_v3_sub(q, v[k])), n) < 0) inside = 0;
  }
  if (inside) best = fmin(best, fabs(tl_v3_dot(tl_v3_sub(p, a), n)));
  return best;
}

static void test_closest_point_regions(void)
{
  TlVec3 a = tl_v3(0, 0, 0), b = tl_v3(1, 0, 0), c = tl_v3(0, 1, 0), q;
  double l[3];
  struct {
    TlVec3 p, q;
    int feature;
  } cases[] = {
      {{0.2, 0.2, 0.5}, {0.2, 0.2, 0}, TL_TRI_FACE},
      {{0.5, -0.3, 0.1}, {0.5, 0, 0}, TL_TRI_EDGE0},
      {{0.8, 0.8, -0.2}, {0.5, 0.5, 0}, TL_TRI_EDGE1},
      {{-0.2, 0.5, 0.0}, {0, 0.5, 0}, TL_TRI_EDGE2},
      {{-1, -1, 0.3}, {0, 0, 0}, TL_TRI_VERTEX0},
      {{2, -0.1, 0}, {1, 0, 0}, TL_TRI_VERTEX1},
      {{-0.1, 2, 1}, {0, 1, 0}, TL_TRI_VERTEX2},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
    int f = (int)tl_triangle_closest_point(a, b, c, cases[i].p, &q, l);
    TL_TEST_ASSERT(f == cases[i].feature, "case %zu: feature %d, expected %d", i, f, cases[i].feature);
    TL_TEST_CLOSE(tl_v3_norm(tl_v3_sub(q, cases[i].q)), 0.0, 1e-14);
  }
  TL_TEST_ASSERT(tl_tri_feature_on_edge(TL_TRI_VERTEX1, 0) && tl_tri_feature_on_edge(TL_TRI_VERTEX1, 1) &&
                     !tl_tri_feature_on_edge(TL_TRI_VERTEX1, 2),
                 "vertex 1 lies on edges 0 and 1 only");
  TL_TEST_ASSERT(!tl_tri_feature_on_edge(TL_TRI_FACE, 0), "the face is on no edge");

  /* random triangles and points against the oracle; bary reproduces q */
  uint64_t s = 42;
  int bad = 0, bad_bary = 0;
  for (int it = 0; it < 20000; ++it) {
    TlVec3 v[4];
    for (int k = 0; k < 4; ++k) v[k] = tl_v3(4 * urand(&s) - 2, 4 * urand(&s) - 2, 4 * urand(&s) - 2);
    if (tl_triangle_quality(v[0], v[1], v[2]) < 1e-3) continue;
    tl_triangle_closest_point(v[0], v[1], v[2], v[3], &q, l);
    double d = tl_v3_norm(tl_v3_sub(v[3], q)), d_oracle = oracle_distance(v[0], v[1], v[2], v[3]);
    if (fabs(d - d_oracle) > 1e-12 * (1 + d_oracle)) ++bad;
    TlVec3 r = tl_v3_add(tl_v3_scale(v[0], l[0]), tl_v3_add(tl_v3_scale(v[1], l[1]), tl_v3_scale(v[2], l[2])));
    if (tl_v3_norm(tl_v3_sub(r, q)) > 1e-12 || l[0] < -1e-15 || l[1] < -1e-15 || l[2] < -1e-15 ||
        fabs(l[0] + l[1] + l[2] - 1) > 1e-14)
      ++bad_bary;
  }
  TL_TEST_ASSERT(bad == 0, "%d random points disagree with the oracle distance", bad);
  TL_TEST_ASSERT(bad_bary == 0, "%d barycentric coordinates do not reproduce the point", bad_bary);
}

static void test_sphere_contact(void)
{
  TlVec3 a = tl_v3(0, 0, 0), b = tl_v3(1, 0, 0), c = tl_v3(0, 1, 0), n = tl_v3(0, 0, 1);
  TlTriContact con;
  /* face */
  TL_TEST_ASSERT(tl_triangle_sphere_contact(a, b, c, n, tl_v3(0.3, 0.3, 0.08), 0.1, &con), "face contact");
  TL_TEST_CLOSE(con.overlap, 0.02, 1e-14);
  TL_TEST_CLOSE(con.normal.z, 1.0, 1e-14);
  /* below the face: normal points down, towards the centre */
  TL_TEST_ASSERT(tl_triangle_sphere_contact(a, b, c, n, tl_v3(0.3, 0.3, -0.05), 0.1, &con), "face from below");
  TL_TEST_CLOSE(con.normal.z, -1.0, 1e-14);
  /* edge bc at 45 degrees */
  double h = 0.05;
  TlVec3 x = tl_v3(0.5 + h, 0.5 + h, 0);
  TL_TEST_ASSERT(tl_triangle_sphere_contact(a, b, c, n, x, 0.1, &con), "edge contact");
  TL_TEST_ASSERT(con.feature == TL_TRI_EDGE1, "feature %d, expected edge 1", con.feature);
  TL_TEST_CLOSE(con.overlap, 0.1 - sqrt(2) * h, 1e-14);
  TL_TEST_CLOSE(con.normal.x, sqrt(0.5), 1e-14);
  /* vertex */
  TL_TEST_ASSERT(tl_triangle_sphere_contact(a, b, c, n, tl_v3(-0.03, -0.04, 0), 0.1, &con), "vertex contact");
  TL_TEST_ASSERT(con.feature == TL_TRI_VERTEX0, "feature %d, expected vertex 0", con.feature);
  TL_TEST_CLOSE(con.overlap, 0.05, 1e-14);
  TL_TEST_CLOSE(con.normal.y, -0.8, 1e-14);
  /* no contact */
  TL_TEST_ASSERT(!tl_triangle_sphere_contact(a, b, c, n, tl_v3(0.3, 0.3, 0.1), 0.1, &con), "touching only");
  /* centre exactly on the face: the face normal, never NaN */
  TL_TEST_ASSERT(tl_triangle_sphere_contact(a, b, c, n, tl_v3(0.2, 0.2, 0), 0.1, &con), "centre on face");
  TL_TEST_ASSERT(tl_v3_isfinite(con.normal) && fabs(tl_v3_norm(con.normal) - 1) < 1e-14,
                 "normal (%g, %g, %g)", con.normal.x, con.normal.y, con.normal.z);
  TL_TEST_CLOSE(con.overlap, 0.1, 1e-15);
}

static void test_degenerate(void)
{
  TlTriSurface *s = NULL;
  double collinear[9] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  int t012[3] = {0, 1, 2};
  TL_TEST_STATUS(tl_trisurface_create(3, collinear, 1, t012, &s), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(s == NULL, "no half-built surface");
  double needle[9] = {0, 0, 0, 1, 0, 0, 1, 1e-9, 0};
  TL_TEST_STATUS(tl_trisurface_create(3, needle, 1, t012, &s), TL_ERR_NUMERIC);
  double coincident[9] = {0, 0, 0, 1, 0, 0, 0, 0, 0};
  TL_TEST_STATUS(tl_trisurface_create(3, coincident, 1, t012, &s), TL_ERR_NUMERIC);
  int repeated[3] = {0, 1, 1};
  double ok[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  TL_TEST_STATUS(tl_trisurface_create(3, ok, 1, repeated, &s), TL_ERR_ARG);
  int out_of_range[3] = {0, 1, 3};
  TL_TEST_STATUS(tl_trisurface_create(3, ok, 1, out_of_range, &s), TL_ERR_ARG);
  double nan_x[9] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
  TL_TEST_STATUS(tl_trisurface_create(3, nan_x, 1, t012, &s), TL_ERR_NUMERIC);
  /* three triangles on one edge; two traversing an edge the same way */
  double fan[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
  int nonmanifold[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  TL_TEST_STATUS(tl_trisurface_create(5, fan, 3, nonmanifold, &s), TL_ERR_ARG);
  int flipped[6] = {0, 1, 2, 0, 1, 3};
  TL_TEST_STATUS(tl_trisurface_create(5, fan, 2, flipped, &s), TL_ERR_ARG);

  /* a valid surface moved into a degenerate shape is refused at update */
  TL_TEST_STATUS(tl_trisurface_create(3, ok, 1, t012, &s), TL_OK);
  TL_TEST_STATUS(tl_trisurface_set_vertices(s, collinear, NULL), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(strstr(tl_error_message(), "triangle 0") != NULL, "message names the triangle: %s",
                 tl_error_message());
  tl_trisurface_destroy(&s);
  TL_TEST_ASSERT(s == NULL, "destroy nulls");
}

static void test_topology_and_shapes(void)
{
  TlTriSurface *s = NULL;
  TL_TEST_STATUS(tl_trisurface_create_rectangle(0, 0, 2, 2, 0, 2, 2, 0, &s), TL_OK);
  TL_TEST_ASSERT(s->n_vertices == 9 && s->n_triangles == 8 && s->n_edges == 16, "V %zu T %zu E %zu",
                 s->n_vertices, s->n_triangles, s->n_edges);
  int flat = 0, boundary = 0;
  for (size_t e = 0; e < s->n_edges; ++e) {
    flat += s->edge_shape[e] == TL_EDGE_FLAT;
    boundary += s->edge_shape[e] == TL_EDGE_BOUNDARY;
  }
  TL_TEST_ASSERT(flat == 8 && boundary == 8, "flat %d boundary %d", flat, boundary);
  for (size_t t = 0; t < s->n_triangles; ++t) TL_TEST_CLOSE(s->normal[t].z, 1.0, 1e-15);
  /* neighbour relation is symmetric and agrees with the edges */
  int sym = 1;
  for (size_t t = 0; t < s->n_triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      int nb = s->tri_nbr[3 * t + k], e = s->tri_edge[3 * t + k];
      if (nb < 0) continue;
      int back = 0;
      for (int kk = 0; kk < 3; ++kk) back |= s->tri_nbr[3 * nb + kk] == (int)t && s->tri_edge[3 * nb + kk] == e;
      sym &= back;
    }
  TL_TEST_ASSERT(sym, "neighbours are symmetric");
  tl_trisurface_destroy(&s);

  /* the inside of a box: normals inwards, cube edges concave (valleys seen
   * from inside), face diagonals flat; from outside the same edges look
   * convex */
  TL_TEST_STATUS(tl_trisurface_create_box(tl_v3(0, 0, 0), tl_v3(1, 2, 3), &s), TL_OK);
  TL_TEST_ASSERT(s->n_edges == 18, "box has %zu edges", s->n_edges);
  int concave = 0;
  flat = 0;
  for (size_t e = 0; e < s->n_edges; ++e) {
    concave += s->edge_shape[e] == TL_EDGE_CONCAVE;
    flat += s->edge_shape[e] == TL_EDGE_FLAT;
  }
  TL_TEST_ASSERT(concave == 12 && flat == 6, "concave %d flat %d", concave, flat);
  int inward = 1;
  for (size_t t = 0; t < s->n_triangles; ++t) {
    const int *v = s->tri + 3 * t;
    TlVec3 centroid = tl_v3_scale(tl_v3_add(s->x[v[0]], tl_v3_add(s->x[v[1]], s->x[v[2]])), 1.0 / 3);
    inward &= tl_v3_dot(s->normal[t], tl_v3_sub(tl_v3(0.5, 1, 1.5), centroid)) > 0;
  }
  TL_TEST_ASSERT(inward, "box normals point inwards");
  int seen_ok = 1;
  for (size_t e = 0; e < s->n_edges; ++e) {
    if (s->edge_shape[e] != TL_EDGE_CONCAVE) continue;
    /* just inside and just outside the middle of the edge */
    TlVec3 m = tl_v3_scale(tl_v3_add(s->x[s->edge_vertex[2 * e]], s->x[s->edge_vertex[2 * e + 1]]), 0.5);
    TlVec3 in = tl_v3_normalize(tl_v3_add(s->normal[s->edge_tri[2 * e]], s->normal[s->edge_tri[2 * e + 1]]));
    seen_ok &= tl_trisurface_edge_shape_seen_from(s, (int)e, tl_v3(0.5, 1, 1.5), s->edge_tri[2 * e]) == TL_EDGE_CONCAVE;
    seen_ok &= tl_trisurface_edge_shape_seen_from(s, (int)e, tl_v3_axpy(m, 0.1, in), s->edge_tri[2 * e]) == TL_EDGE_CONCAVE;
    seen_ok &= tl_trisurface_edge_shape_seen_from(s, (int)e, tl_v3_axpy(m, -0.1, in), s->edge_tri[2 * e]) == TL_EDGE_CONVEX;
  }
  TL_TEST_ASSERT(seen_ok, "box edges concave from inside, convex from outside");
  tl_trisurface_destroy(&s);
}

/* Two triangles sharing the y axis; the second folded by angle theta about
 * it: up (valley, concave), down (ridge, convex), zero (flat).  Moving the
 * vertices and updating reclassifies. */
static void test_fold_follows_motion(void)
{
  int tri[6] = {0, 1, 2, 1, 0, 3};
  double x[12] = {0, -1, 0, 0, 1, 0, -1, 0, 0, 1, 0, 0};
  TlTriSurface *s = NULL;
  TL_TEST_STATUS(tl_trisurface_create(4, x, 2, tri, &s), TL_OK);
  if (!s) return;
  TL_TEST_ASSERT(s->n_edges == 5, "edges %zu", s->n_edges);
  int shared = -1;
  for (size_t e = 0; e < s->n_edges; ++e)
    if (s->edge_tri[2 * e + 1] >= 0) shared = (int)e;
  TL_TEST_ASSERT(shared >= 0, "one shared edge");
  TL_TEST_ASSERT(s->normal[0].z > 0 && s->normal[1].z > 0, "both normals +z");
  TL_TEST_ASSERT(s->edge_shape[shared] == TL_EDGE_FLAT, "flat: %d", s->edge_shape[shared]);
  double angles[] = {0.3, -0.3, 1e-3, -1e-3, 1e-12, 2.5};
  int expect[] = {TL_EDGE_CONCAVE, TL_EDGE_CONVEX, TL_EDGE_CONCAVE, TL_EDGE_CONVEX, TL_EDGE_FLAT, TL_EDGE_CONCAVE};
  for (int i = 0; i < 6; ++i) {
    double y[12];
    for (int k = 0; k < 12; ++k) y[k] = x[k];
    y[9] = cos(angles[i]);
    y[11] = sin(angles[i]);
    double v[12] = {0};
    v[11] = 2.0; /* vertex 3 moving up */
    TL_TEST_STATUS(tl_trisurface_set_vertices(s, y, v), TL_OK);
    TL_TEST_ASSERT(s->edge_shape[shared] == expect[i], "angle %g: shape %d, expected %d", angles[i],
                   s->edge_shape[shared], expect[i]);
    if (fabs(angles[i]) > 1e-6) TL_TEST_CLOSE(s->edge_fold[shared], sin(angles[i]), 1e-12);
    TL_TEST_CLOSE(s->box_hi[1].z, fmax(0.0, sin(angles[i])), 1e-15);
  }
  /* wall velocity at a point: barycentric interpolation */
  double bary[3] = {0.25, 0.25, 0.5};
  int k3 = 0;
  for (int k = 0; k < 3; ++k)
    if (s->tri[3 + k] == 3) k3 = k;
  double b2[3] = {0, 0, 0};
  b2[k3] = 0.5;
  b2[(k3 + 1) % 3] = 0.5;
  TL_TEST_CLOSE(tl_trisurface_velocity_at(s, 1, b2).z, 1.0, 1e-15);
  TL_TEST_CLOSE(tl_trisurface_velocity_at(s, 0, bary).z, 0.0, 1e-15);
  tl_trisurface_destroy(&s);
}

int main(void)
{
  test_closest_point_regions();
  test_sphere_contact();
  test_degenerate();
  test_topology_and_shapes();
  test_fold_follows_motion();
  return tl_test_report();
}
