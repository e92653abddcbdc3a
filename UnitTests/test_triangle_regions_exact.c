/* The regions of a triangle's closest point (face, edge, vertex) decided
 * exactly.  Points are placed exactly on the region boundaries (the plane
 * through a vertex perpendicular to an edge; the plane through an edge
 * perpendicular to the triangle) and one ulp either side, with integer
 * coordinates in [2^52, 2^53) so that an ulp is 1 and an integer oracle
 * (__int128) knows every sign; the offsets between points are large enough
 * (2^26 and more) that the dot products round, so the previous
 * floating-point formula errs on a part of them, which the test counts and
 * requires to be non-zero (else the inputs would test nothing).  Checked:
 * the region against the oracle, for every rotation of the corner order;
 * the two triangles of an edge agree on where the vertex region starts; the
 * contact (point, overlap, normal) continuous across every boundary; the
 * predicates' two paths (CGAL's when built, the library's own) against the
 * oracle. */
#include <stdint.h>
#include "talus.h"
#include "tl_predicates.h"
#include "tl_test.h"
#include "tl_triangle_geometry.h"

typedef __int128 i128;
typedef struct {
  int64_t x[3];
} IVec;

static uint64_t rng(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return *s >> 11;
}

/* uniform in [-2^bits, 2^bits] */
static int64_t irand(uint64_t *s, int bits)
{
  return (int64_t)(rng(s) % ((2ULL << bits) + 1)) - ((int64_t)1 << bits);
}

static const int64_t ORIGIN = ((int64_t)1 << 52) + ((int64_t)1 << 51);

static IVec iv(int64_t x, int64_t y, int64_t z) { return (IVec){{x, y, z}}; }
static IVec iadd(IVec a, IVec b) { return iv(a.x[0] + b.x[0], a.x[1] + b.x[1], a.x[2] + b.x[2]); }
static IVec isub(IVec a, IVec b) { return iv(a.x[0] - b.x[0], a.x[1] - b.x[1], a.x[2] - b.x[2]); }
static IVec icross(IVec a, IVec b)
{
  return iv(a.x[1] * b.x[2] - a.x[2] * b.x[1], a.x[2] * b.x[0] - a.x[0] * b.x[2], a.x[0] * b.x[1] - a.x[1] * b.x[0]);
}
static TlVec3 dv(IVec a) { return tl_v3((double)a.x[0], (double)a.x[1], (double)a.x[2]); }
static int sgn(i128 v) { return (v > 0) - (v < 0); }

/* The oracle's signs: (u - v).(p - v) and ((b - a) x (c - a)).((b - a) x (p - a)). */
static int odot(IVec v, IVec u, IVec p)
{
  IVec e = isub(u, v), w = isub(p, v);
  i128 s = 0;
  for (int k = 0; k < 3; ++k) s += (i128)e.x[k] * w.x[k];
  return sgn(s);
}

static int oside(IVec a, IVec b, IVec c, IVec p)
{
  IVec e = isub(b, a), f = isub(c, a), w = isub(p, a);
  i128 n[3], m[3], s = 0;
  for (int i = 0; i < 3; ++i) {
    int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    n[i] = (i128)e.x[i1] * f.x[i2] - (i128)e.x[i2] * f.x[i1];
    m[i] = (i128)e.x[i1] * w.x[i2] - (i128)e.x[i2] * w.x[i1];
    s += n[i] * m[i];
  }
  return sgn(s);
}

/* The regions in the order and with the ties of tl_triangle_closest_point. */
static int oregion(IVec a, IVec b, IVec c, IVec p)
{
  if (odot(a, b, p) <= 0 && odot(a, c, p) <= 0) return TL_TRI_VERTEX0;
  if (odot(b, a, p) <= 0 && odot(b, c, p) <= 0) return TL_TRI_VERTEX1;
  if (oside(a, b, c, p) <= 0 && odot(a, b, p) >= 0 && odot(b, a, p) >= 0) return TL_TRI_EDGE0;
  if (odot(c, a, p) <= 0 && odot(c, b, p) <= 0) return TL_TRI_VERTEX2;
  if (oside(c, a, b, p) <= 0 && odot(a, c, p) >= 0 && odot(c, a, p) >= 0) return TL_TRI_EDGE2;
  if (oside(b, c, a, p) <= 0 && odot(b, c, p) >= 0 && odot(c, b, p) >= 0) return TL_TRI_EDGE1;
  return TL_TRI_FACE;
}

/* The previous region choice: the same formulas with plain floating-point
 * signs (kept here as the reference that rounding misleads). */
static int naive_region(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p)
{
  TlVec3 ab = tl_v3_sub(b, a), ac = tl_v3_sub(c, a), ap = tl_v3_sub(p, a);
  double d1 = tl_v3_dot(ab, ap), d2 = tl_v3_dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return TL_TRI_VERTEX0;
  TlVec3 bp = tl_v3_sub(p, b);
  double d3 = tl_v3_dot(ab, bp), d4 = tl_v3_dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return TL_TRI_VERTEX1;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return TL_TRI_EDGE0;
  TlVec3 cp = tl_v3_sub(p, c);
  double d5 = tl_v3_dot(ab, cp), d6 = tl_v3_dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return TL_TRI_VERTEX2;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return TL_TRI_EDGE2;
  double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) return TL_TRI_EDGE1;
  return TL_TRI_FACE;
}

/* The feature of rotation r of (a, b, c) mapped back to the numbering of
 * (a, b, c): vertex k of (v[r], v[r+1], v[r+2]) is vertex (k + r) mod 3. */
static int unrotate(int f, int r)
{
  if (f == TL_TRI_FACE) return f;
  if (tl_tri_feature_is_vertex(f)) return TL_TRI_VERTEX0 + (f - TL_TRI_VERTEX0 + r) % 3;
  return TL_TRI_EDGE0 + (f - TL_TRI_EDGE0 + r) % 3;
}

typedef struct {
  long cases, naive_wrong, exact_wrong, discontinuous;
  double worst_jump; /* largest jump of point or overlap over a one-ulp step, in ulps */
} Tally;

/* Checks p and its neighbours one ulp away along axis k against the oracle
 * in every rotation, and the contact's continuity over the two steps. */
static void check_point(IVec a, IVec b, IVec c, IVec p, int k, Tally *t)
{
  IVec v[3] = {a, b, c};
  TlTriContact con[3];
  int have[3] = {0, 0, 0};
  for (int s = -1; s <= 1; ++s) {
    IVec q = p;
    q.x[k] += s;
    int truth = oregion(a, b, c, q);
    for (int r = 0; r < 3; ++r) {
      IVec x0 = v[r], x1 = v[(r + 1) % 3], x2 = v[(r + 2) % 3];
      TlVec3 cq;
      double l[3];
      int f = unrotate((int)tl_triangle_closest_point(dv(x0), dv(x1), dv(x2), dv(q), &cq, l), r);
      int fn = unrotate(naive_region(dv(x0), dv(x1), dv(x2), dv(q)), r);
      ++t->cases;
      t->exact_wrong += f != truth;
      t->naive_wrong += fn != truth;
    }
    /* the contact of a sphere reaching past the closest point */
    TlVec3 n = tl_v3_normalize(tl_v3_cross(tl_v3_sub(dv(b), dv(a)), tl_v3_sub(dv(c), dv(a))));
    TlVec3 cq;
    double l[3];
    tl_triangle_closest_point(dv(a), dv(b), dv(c), dv(q), &cq, l);
    double r = 2.0 * tl_v3_norm(tl_v3_sub(dv(q), cq)) + 16.0;
    have[s + 1] = tl_triangle_sphere_contact(dv(a), dv(b), dv(c), n, dv(q), r, &con[s + 1]);
  }
  for (int s = 0; s < 2; ++s) {
    if (!have[s] || !have[s + 1]) {
      ++t->discontinuous;
      continue;
    }
    double jump = fmax(tl_v3_norm(tl_v3_sub(con[s].point, con[s + 1].point)), fabs(con[s].overlap - con[s + 1].overlap));
    /* the normal's turn, in ulps of the position at the contact distance */
    double dist = tl_v3_norm(tl_v3_sub(dv(p), con[s].point));
    jump = fmax(jump, dist * tl_v3_norm(tl_v3_sub(con[s].normal, con[s + 1].normal)));
    t->worst_jump = fmax(t->worst_jump, jump);
    /* a one-ulp move of the centre moves the closest point and the
     * distance by at most one ulp each, plus their rounding */
    if (!(jump <= 8.0)) ++t->discontinuous;
  }
}

static int largest_axis(IVec e)
{
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (llabs(e.x[i]) > llabs(e.x[k])) k = i;
  return k;
}

static IVec small_vec(uint64_t *s)
{
  IVec r;
  do r = iv(irand(s, 2), irand(s, 2), irand(s, 2));
  while (!r.x[0] && !r.x[1] && !r.x[2]);
  return r;
}

/* Vertex-region boundaries: p - a = e x r (r small) is perpendicular to
 * e = b - a, so (b - a).(p - a) = 0 exactly. */
static void test_vertex_boundaries(void)
{
  uint64_t s = 7;
  Tally t = {0};
  for (int it = 0; it < 3000; ++it) {
    IVec a = iv(ORIGIN + irand(&s, 26), ORIGIN + irand(&s, 26), ORIGIN + irand(&s, 26));
    IVec e = iv(irand(&s, 26), irand(&s, 26), irand(&s, 26));
    IVec b = iadd(a, e), c = iadd(a, iv(irand(&s, 27), irand(&s, 27), irand(&s, 27)));
    IVec p = iadd(a, icross(e, small_vec(&s)));
    TL_TEST_ASSERT(odot(a, b, p) == 0, "construction: p on the plane through a perpendicular to ab");
    check_point(a, b, c, p, largest_axis(e), &t);
  }
  printf("vertex boundaries: %ld region answers, previous formula wrong on %ld, exact wrong on %ld; "
         "largest jump of the contact over one ulp %.3g ulp\n",
         t.cases, t.naive_wrong, t.exact_wrong, t.worst_jump);
  TL_TEST_ASSERT(t.exact_wrong == 0, "%ld exact region answers differ from the integer oracle", t.exact_wrong);
  TL_TEST_ASSERT(t.naive_wrong > 0, "the inputs do not mislead the floating-point formula: they test nothing");
  TL_TEST_ASSERT(t.discontinuous == 0, "%ld one-ulp steps change the contact by more than 8 ulps (worst %g)",
                 t.discontinuous, t.worst_jump);
}

/* Edge-region boundaries: with c - a = f perpendicular to e = b - a the
 * plane through ab perpendicular to the triangle is perpendicular to f, and
 * p - a = f x r + e/2 lies on it exactly (e even). */
static void test_edge_boundaries(void)
{
  uint64_t s = 11;
  Tally t = {0};
  for (int it = 0; it < 3000; ++it) {
    IVec a = iv(ORIGIN + irand(&s, 26), ORIGIN + irand(&s, 26), ORIGIN + irand(&s, 26));
    IVec e = iv(2 * irand(&s, 25), 2 * irand(&s, 25), 2 * irand(&s, 25));
    IVec f = icross(e, small_vec(&s));
    IVec b = iadd(a, e), c = iadd(a, f);
    IVec half = iv(e.x[0] / 2, e.x[1] / 2, e.x[2] / 2);
    IVec p = iadd(iadd(a, icross(f, small_vec(&s))), half);
    if (!f.x[0] && !f.x[1] && !f.x[2]) continue;
    TL_TEST_ASSERT(oside(a, b, c, p) == 0, "construction: p on the plane through ab perpendicular to the triangle");
    check_point(a, b, c, p, largest_axis(f), &t);
  }
  printf("edge boundaries: %ld region answers, previous formula wrong on %ld, exact wrong on %ld; "
         "largest jump of the contact over one ulp %.3g ulp\n",
         t.cases, t.naive_wrong, t.exact_wrong, t.worst_jump);
  TL_TEST_ASSERT(t.exact_wrong == 0, "%ld exact region answers differ from the integer oracle", t.exact_wrong);
  TL_TEST_ASSERT(t.naive_wrong > 0, "the inputs do not mislead the floating-point formula: they test nothing");
  TL_TEST_ASSERT(t.discontinuous == 0, "%ld one-ulp steps change the contact by more than 8 ulps (worst %g)",
                 t.discontinuous, t.worst_jump);
}

/* Two triangles of one edge ab, (a, b, c) and (d, b, a) (a is corner 0 of
 * one and corner 2 of the other), both on the far side of the plane through
 * a perpendicular to ab from p: for p on that plane and one ulp either
 * side, both must say "vertex a" or both "edge ab". */
static void test_shared_edge(void)
{
  uint64_t s = 13;
  long cases = 0, naive_split = 0, exact_split = 0, wrong = 0;
  for (int it = 0; it < 3000; ++it) {
    IVec a = iv(ORIGIN + irand(&s, 26), ORIGIN + irand(&s, 26), ORIGIN + irand(&s, 26));
    IVec e = iv(irand(&s, 26), irand(&s, 26), irand(&s, 26));
    IVec w = icross(e, small_vec(&s));
    IVec h = icross(e, w);
    for (int k = 0; k < 3; ++k) h.x[k] >>= 27; /* a fold direction of the size of w */
    IVec b = iadd(a, e);
    IVec c = isub(iadd(a, h), w), d = isub(isub(a, h), w);
    IVec p = iadd(a, w);
    int k = largest_axis(e);
    for (int st = -1; st <= 1; ++st) {
      IVec q = p;
      q.x[k] += st;
      int t1 = oregion(a, b, c, q), t2 = oregion(d, b, a, q);
      /* only points whose truth is on edge ab in both (its end a included) */
      int on1 = t1 == TL_TRI_VERTEX0 || t1 == TL_TRI_EDGE0, on2 = t2 == TL_TRI_VERTEX2 || t2 == TL_TRI_EDGE1;
      if (!on1 || !on2) continue;
      TlVec3 cq;
      double l[3];
      int f1 = (int)tl_triangle_closest_point(dv(a), dv(b), dv(c), dv(q), &cq, l);
      int f2 = (int)tl_triangle_closest_point(dv(d), dv(b), dv(a), dv(q), &cq, l);
      int n1 = naive_region(dv(a), dv(b), dv(c), dv(q)), n2 = naive_region(dv(d), dv(b), dv(a), dv(q));
      ++cases;
      wrong += f1 != t1 || f2 != t2;
      exact_split += (f1 == TL_TRI_VERTEX0) != (f2 == TL_TRI_VERTEX2);
      naive_split += (n1 == TL_TRI_VERTEX0) != (n2 == TL_TRI_VERTEX2);
    }
  }
  printf("shared edge: %ld points on or one ulp off the start of vertex a's region; the two triangles disagree on "
         "%ld with the previous formula, %ld exactly\n",
         cases, naive_split, exact_split);
  TL_TEST_ASSERT(cases > 1000, "only %ld usable points", cases);
  TL_TEST_ASSERT(wrong == 0 && exact_split == 0, "%ld wrong regions, %ld disagreements", wrong, exact_split);
  TL_TEST_ASSERT(naive_split > 0, "the inputs do not split the floating-point formula: they test nothing");
}

/* The predicates themselves, both paths, against the oracle, on the exact
 * zeros above and one unit off them and on random inputs. */
static void test_predicate_paths(void)
{
  uint64_t s = 17;
  long bad = 0, exact_stages = 0, n = 0;
  for (int it = 0; it < 4000; ++it) {
    IVec a = iv(ORIGIN + irand(&s, 26), ORIGIN + irand(&s, 26), ORIGIN + irand(&s, 26));
    IVec e = iv(2 * irand(&s, 25), 2 * irand(&s, 25), 2 * irand(&s, 25));
    IVec f = it % 2 ? icross(e, small_vec(&s)) : iv(irand(&s, 27), irand(&s, 27), irand(&s, 27));
    IVec b = iadd(a, e), c = iadd(a, f);
    IVec p = it % 2 ? iadd(a, icross(f, small_vec(&s))) : iadd(a, icross(e, small_vec(&s)));
    p.x[it % 3] += (it / 3) % 3 - 1;
    int st1 = 0, st2 = 0;
    int o1 = odot(a, b, p), o2 = oside(a, b, c, p);
    int s1 = tl_dot3_sign_filtered(dv(a), dv(b), dv(p), &st1), s2 = tl_edge_side_filtered(dv(a), dv(b), dv(c), dv(p), &st2);
    int g1 = tl_dot3_sign(dv(a), dv(b), dv(p)), g2 = tl_edge_side(dv(a), dv(b), dv(c), dv(p));
    bad += (s1 != o1) + (s2 != o2) + (g1 != o1) + (g2 != o2);
    exact_stages += st1 + st2;
    n += 2;
  }
  printf("predicates: %ld signs on each path (%s), %ld reached the exact stage, %ld wrong\n", n,
         tl_predicates_use_cgal() ? "CGAL and the library's own" : "the library's own", exact_stages, bad);
  TL_TEST_ASSERT(bad == 0, "%ld predicate signs differ from the integer oracle", bad);
  TL_TEST_ASSERT(exact_stages > 0, "no input reached the exact stage");
}

int main(void)
{
  test_vertex_boundaries();
  test_edge_boundaries();
  test_shared_edge();
  test_predicate_paths();
  return tl_test_report();
}
