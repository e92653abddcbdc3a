/* Orientation predicate: clear cases; exactly coplanar points (tilted planes,
 * coordinates of very different magnitudes whose differences are inexact in
 * doubles); points a hair off a plane, against an independent exact oracle
 * in 128-bit integers, on inputs where the naive double evaluation gets the
 * sign wrong; and the filter leaving the clear cases to doubles. */
#include <stdint.h>
#include "talus.h"
#include "tl_predicates.h"
#include "tl_test.h"

static uint64_t rng(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return *s >> 11;
}

/* A signed integer in (-2^bits, 2^bits). */
static int64_t irand(uint64_t *s, int bits)
{
  int64_t m = (int64_t)(rng(s) & ((1ULL << bits) - 1));
  return (rng(s) & 1) ? -m : m;
}

/* Exact sign of det[b - a, c - a, d - a] for integer points whose products
 * of three differences stay below 2^125 (they do here: at most 2^92). */
static int orient_int(const int64_t a[3], const int64_t b[3], const int64_t c[3], const int64_t d[3])
{
  __int128 u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) u[k] = b[k] - a[k], v[k] = c[k] - a[k], w[k] = d[k] - a[k];
  __int128 det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                 u[2] * (v[0] * w[1] - v[1] * w[0]);
  return (det > 0) - (det < 0);
}

/* The naive double evaluation, to show the inputs are hard. */
static int orient_naive(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d)
{
  TlVec3 u = tl_v3_sub(b, a), v = tl_v3_sub(c, a), w = tl_v3_sub(d, a);
  double det = tl_v3_dot(u, tl_v3_cross(v, w));
  return (det > 0) - (det < 0);
}

static TlVec3 to_vec(const int64_t p[3], double scale, double offset)
{
  return tl_v3((double)p[0] * scale + offset, (double)p[1] * scale + offset, (double)p[2] * scale + offset);
}

static void test_simple(void)
{
  TlVec3 a = tl_v3(0, 0, 0), b = tl_v3(1, 0, 0), c = tl_v3(0, 1, 0);
  TL_TEST_ASSERT(tl_orient3d(a, b, c, tl_v3(0.3, 0.3, 1)) == 1, "above");
  TL_TEST_ASSERT(tl_orient3d(a, b, c, tl_v3(0.3, 0.3, -1)) == -1, "below");
  TL_TEST_ASSERT(tl_orient3d(a, b, c, tl_v3(5, -7, 0)) == 0, "on the plane");
  TL_TEST_ASSERT(tl_orient3d(b, a, c, tl_v3(0.3, 0.3, 1)) == -1, "swapping two points flips the sign");
  TL_TEST_ASSERT(tl_orient3d(a, b, b, tl_v3(0.3, 0.3, 1)) == 0, "repeated point");
  /* the filter decides a clear case in doubles */
  int stage = -1;
  TL_TEST_ASSERT(tl_orient3d_filtered(a, b, c, tl_v3(0.3, 0.3, 1e-3), &stage) == 1 && stage == 0,
                 "clear case decided by the filter (stage %d)", stage);
}

/* A tilted plane whose points are exactly coplanar in binary: (t, t, t)
 * lies on the plane x + y - 2z = 0 through p, q, r. */
static void test_coplanar(void)
{
  TlVec3 p = tl_v3(1, 1, 1), q = tl_v3(2, 0, 1), r = tl_v3(0, 2, 1);
  for (int k = 1; k < 50; ++k) {
    double t = 0.1 * k + 1e6;
    TL_TEST_ASSERT(tl_orient3d(p, q, r, tl_v3(t, t, t)) == 0, "coplanar point %d", k);
  }
  /* The plane z = x holds (s, t, s) for any doubles s, t: coordinates spread
   * over 60 orders of magnitude, so that b - a, c - a, d - a are not exact
   * in doubles and the exact stage needs two-component differences. */
  const double mags[] = {3.1e-30, -7.7e-21, 1.3e-9, 0.7, -2.9e3, 5.3e11, -1.1e22, 6.1e29};
  const int nm = (int)(sizeof mags / sizeof mags[0]);
  int zeros = 0, exact_runs = 0, n = 0, up = 0, down = 0;
  for (int i = 0; i < nm; ++i)
    for (int j = 0; j < nm; ++j) {
      double s = mags[i], t = mags[(j + 3) % nm];
      TlVec3 a = tl_v3(mags[j] * 1e-3, 0.37, mags[j] * 1e-3);
      double h = fmax(1.0, fabs(a.x)); /* b.x != a.x whatever the magnitude */
      TlVec3 b = tl_v3(a.x + h, 0.37, a.x + h);
      TlVec3 c = tl_v3(a.x, 1.37, a.x);
      TlVec3 d = tl_v3(s, t, s);
      int stage = 0;
      zeros += tl_orient3d_filtered(a, b, c, d, &stage) == 0;
      exact_runs += stage;
      ++n;
      /* one ulp above or below z = x: det = (d.z - d.x) (u_x v_y - u_y v_x)
       * with u_x v_y - u_y v_x = (b.x - a.x)(c.y - a.y) > 0 here, so the sign
       * is that of the perturbation */
      up += tl_orient3d_filtered(a, b, c, tl_v3(s, t, nextafter(s, INFINITY)), NULL) == 1;
      down += tl_orient3d_filtered(a, b, c, tl_v3(s, t, nextafter(s, -INFINITY)), NULL) == -1;
    }
  printf("z = x plane: %d of %d exactly coplanar found (%d by the exact stage); one ulp off: %d up, %d down\n", zeros,
         n, exact_runs, up, down);
  TL_TEST_ASSERT(zeros == n, "%d of %d exactly coplanar quadruples classified as coplanar", zeros, n);
  TL_TEST_ASSERT(exact_runs > n / 2, "the exact stage ran only %d times of %d", exact_runs, n);
  TL_TEST_ASSERT(up == n && down == n, "one ulp off the plane: %d up and %d down right of %d", up, down, n);
  TL_TEST_ASSERT(tl_orient3d(tl_v3(0, 0.37, 0), tl_v3(1, 0.37, 1), tl_v3(0, 1.37, 0), tl_v3(6.1e29, 3.1e-30, 6.1e29)) ==
                     0,
                 "coplanar through tl_orient3d");
}

/* One ulp off a plane far from the origin. */
static void test_ulp(void)
{
  double big = 1e8;
  TlVec3 A = tl_v3(big, big, big), B = tl_v3(big + 1, big, big), C = tl_v3(big, big + 1, big);
  TlVec3 up = tl_v3(big + 0.5, big + 0.5, nextafter(big, 2 * big));
  TlVec3 down = tl_v3(big + 0.5, big + 0.5, nextafter(big, 0));
  TL_TEST_ASSERT(tl_orient3d(A, B, C, up) == 1, "one ulp above");
  TL_TEST_ASSERT(tl_orient3d(A, B, C, down) == -1, "one ulp below");
}

/* Random near-degenerate quadruples on an integer lattice (scaled by 2^-20
 * and offset by 1/2, so the doubles are not integers): a sliver triangle
 * (a, b = a + u, c = a + u + s with u ~ 2^20 and s a few units, so that the
 * normal u x s is short against |u| |u + s|), and d = a + alpha u + beta
 * (u + s) + e far away (alpha, beta ~ 2^29) nudged by e in {-1, 0, 1}^3:
 * the determinant (u x s) . e is 0 or about 2^22 against terms of 2^90, a
 * relative 2^-68, far inside the rounding error of doubles.  The exact
 * integer sign is the oracle. */
static void test_near_degenerate(void)
{
  uint64_t seed = 12345;
  const double scale = 0x1p-20, offset = 0.5;
  int n = 20000, wrong = 0, naive_wrong = 0, exact_runs = 0, zeros = 0;
  for (int k = 0; k < n; ++k) {
    int64_t a[3], b[3], c[3], d[3];
    int64_t alpha = irand(&seed, 29), beta = irand(&seed, 29);
    for (int m = 0; m < 3; ++m) {
      int64_t u = irand(&seed, 20), sl = irand(&seed, 2), e = (int64_t)(rng(&seed) % 3) - 1;
      a[m] = irand(&seed, 20);
      b[m] = a[m] + u;
      c[m] = b[m] + sl;
      d[m] = a[m] + alpha * u + beta * (u + sl) + e;
    }
    int exact = orient_int(a, b, c, d);
    TlVec3 A = to_vec(a, scale, offset), B = to_vec(b, scale, offset), C = to_vec(c, scale, offset),
           D = to_vec(d, scale, offset);
    int stage = 0;
    int got = tl_orient3d_filtered(A, B, C, D, &stage);
    wrong += got != exact;
    naive_wrong += orient_naive(A, B, C, D) != exact;
    exact_runs += stage;
    zeros += exact == 0;
    if (got != exact && wrong <= 3) printf("  case %d: sign %d, exact %d\n", k, got, exact);
  }
  printf("near-degenerate: %d cases (%d coplanar), %d wrong (naive doubles: %d wrong), exact stage %d times\n", n,
         zeros, wrong, naive_wrong, exact_runs);
  TL_TEST_ASSERT(wrong == 0, "%d of %d near-degenerate signs wrong", wrong, n);
  TL_TEST_ASSERT(naive_wrong > n / 4, "the inputs should defeat the naive evaluation (%d of %d wrong)", naive_wrong,
                 n);
  TL_TEST_ASSERT(zeros > 0 && zeros < n / 2, "%d coplanar cases of %d", zeros, n);
}

/* Random points in general position: the filter alone decides them, and
 * agrees with the exact stage. */
static void test_general_position(void)
{
  uint64_t seed = 777;
  int n = 20000, filtered = 0, agree = 0;
  for (int k = 0; k < n; ++k) {
    int64_t p[4][3];
    for (int i = 0; i < 4; ++i)
      for (int m = 0; m < 3; ++m) p[i][m] = irand(&seed, 30);
    int stage = 1;
    int got = tl_orient3d_filtered(to_vec(p[0], 0x1p-10, 0), to_vec(p[1], 0x1p-10, 0),
                                   to_vec(p[2], 0x1p-10, 0), to_vec(p[3], 0x1p-10, 0), &stage);
    filtered += stage == 0;
    agree += got == orient_int(p[0], p[1], p[2], p[3]);
  }
  printf("general position: %d of %d decided by the filter, %d right\n", filtered, n, agree);
  TL_TEST_ASSERT(agree == n, "%d of %d signs right in general position", agree, n);
  TL_TEST_ASSERT(filtered > n - n / 100, "the filter decided only %d of %d clear cases", filtered, n);
}

int main(void)
{
  test_simple();
  test_coplanar();
  test_ulp();
  test_near_degenerate();
  test_general_position();
  printf("exact predicates: %s (through CGAL: %s)\n", tl_predicates_are_exact() ? "yes" : "no",
         tl_predicates_use_cgal() ? "yes" : "no");
  return tl_test_report();
}
