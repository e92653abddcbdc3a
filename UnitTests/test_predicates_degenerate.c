/* The exact predicates on exactly degenerate inputs, on both paths (CGAL's
 * and the library's own, which must agree with each other and with the
 * geometry): cospherical points (the corners of boxes of arbitrary double
 * coordinates lie on one sphere) and points one ulp off the sphere;
 * collinear points of large integer coordinates and points one unit off
 * their line, orient2d against an integer oracle; dihedral angles equal to, and one ulp of a
 * cosine away from, the given angle. */
#include <stdint.h>
#include "talus.h"
#include "tl_predicates.h"
#include "tl_test.h"

static uint64_t rng(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return *s >> 11;
}

static double urand(uint64_t *s) { return (double)rng(s) / 9007199254740992.0; }

static int insphere_naive(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, TlVec3 e)
{
  const TlVec3 p[4] = {a, b, c, d};
  double x[4][4], det = 0.0;
  for (int i = 0; i < 4; ++i) {
    TlVec3 q = tl_v3_sub(p[i], e);
    x[i][0] = q.x, x[i][1] = q.y, x[i][2] = q.z, x[i][3] = tl_v3_dot(q, q);
  }
  for (int i = 0; i < 4; ++i) {
    int r[3], n = 0;
    for (int j = 0; j < 4; ++j)
      if (j != i) r[n++] = j;
    double m = 0.0;
    for (int k = 0; k < 3; ++k)
      m += x[r[0]][k] * (x[r[1]][(k + 1) % 3] * x[r[2]][(k + 2) % 3] - x[r[1]][(k + 2) % 3] * x[r[2]][(k + 1) % 3]);
    det += (i % 2 ? -1.0 : 1.0) * x[i][3] * m;
  }
  return (det > 0) - (det < 0);
}

static void test_insphere(void)
{
  uint64_t seed = 7;
  int n = 0, zero = 0, zero_filtered = 0, naive_wrong = 0, exact_stage = 0, inside = 0, outside = 0, agree = 0;
  for (int trial = 0; trial < 300; ++trial) {
    /* a box of inexact coordinates, of random size and place */
    double scale = ldexp(1.0, (int)(rng(&seed) % 40) - 20);
    TlVec3 lo = tl_v3(scale * (urand(&seed) - 0.5) * 10, scale * (urand(&seed) - 0.5) * 10, scale * urand(&seed) * 1e3);
    TlVec3 hi = tl_v3_add(lo, tl_v3(scale * (0.1 + urand(&seed)), scale * (0.1 + urand(&seed)), scale * (0.1 + urand(&seed))));
    TlVec3 corner[8];
    for (int k = 0; k < 8; ++k) corner[k] = tl_v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
    TlVec3 a = corner[0], b = corner[1], c = corner[2], d = corner[4];
    if (tl_orient3d(a, b, c, d) < 0) {
      TlVec3 t = b;
      b = c, c = t;
    }
    TL_TEST_ASSERT(tl_orient3d(a, b, c, d) == 1, "positive tetrahedron");
    for (int k = 3; k < 8; ++k) {
      if (k == 4) continue;
      TlVec3 e = corner[k];
      int stage = 0;
      ++n;
      zero += tl_insphere(a, b, c, d, e) == 0;
      zero_filtered += tl_insphere_filtered(a, b, c, d, e, &stage) == 0;
      exact_stage += stage;
      naive_wrong += insphere_naive(a, b, c, d, e) != 0;
    }
    /* the far corner one ulp towards the centre and one ulp away */
    TlVec3 e = corner[7];
    TlVec3 in = tl_v3(nextafter(e.x, -INFINITY), nextafter(e.y, -INFINITY), nextafter(e.z, -INFINITY));
    TlVec3 out = tl_v3(nextafter(e.x, INFINITY), nextafter(e.y, INFINITY), nextafter(e.z, INFINITY));
    inside += tl_insphere(a, b, c, d, in) == 1 && tl_insphere_filtered(a, b, c, d, in, NULL) == 1;
    outside += tl_insphere(a, b, c, d, out) == -1 && tl_insphere_filtered(a, b, c, d, out, NULL) == -1;
    /* the swapped tetrahedron flips the sign */
    agree += tl_insphere(b, a, c, d, in) == -1 && tl_insphere_filtered(b, a, c, d, out, NULL) == 1;
  }
  printf("insphere: %d cospherical cases, %d zero (CGAL path %d), %d through the exact stage, naive doubles wrong in %d\n",
         n, zero_filtered, zero, exact_stage, naive_wrong);
  TL_TEST_ASSERT(zero == n, "tl_insphere: %d of %d cospherical points on the sphere", zero, n);
  TL_TEST_ASSERT(zero_filtered == n, "library path: %d of %d on the sphere", zero_filtered, n);
  TL_TEST_ASSERT(naive_wrong > 0, "the inputs are hard: the naive evaluation is never wrong");
  TL_TEST_ASSERT(inside == 300 && outside == 300 && agree == 300, "one ulp: inside %d, outside %d, swapped %d of 300",
                 inside, outside, agree);
  /* clear cases */
  TlVec3 a = tl_v3(0, 0, 0), b = tl_v3(1, 0, 0), c = tl_v3(0, 1, 0), d = tl_v3(0, 0, 1);
  TL_TEST_ASSERT(tl_insphere(a, b, c, d, tl_v3(0.2, 0.2, 0.2)) == 1, "centre inside");
  TL_TEST_ASSERT(tl_insphere(a, b, c, d, tl_v3(3, 3, 3)) == -1, "far outside");
  TL_TEST_ASSERT(tl_insphere_filtered(a, b, c, d, tl_v3(1, 1, 1), NULL) == 0, "cube corner on the sphere");
  /* general position: the two paths agree */
  int same = 0;
  for (int k = 0; k < 2000; ++k) {
    TlVec3 p[5];
    for (int i = 0; i < 5; ++i) p[i] = tl_v3(urand(&seed), urand(&seed), urand(&seed));
    same += tl_insphere(p[0], p[1], p[2], p[3], p[4]) == tl_insphere_filtered(p[0], p[1], p[2], p[3], p[4], NULL);
  }
  TL_TEST_ASSERT(same == 2000, "paths agree on %d of 2000 random inputs", same);
}

static void test_collinear(void)
{
  uint64_t seed = 11;
  int n = 300, col = 0, col_f = 0, off = 0, naive_wrong = 0, orient_ok = 0;
  for (int k = 0; k < n; ++k) {
    /* integer points up to 2^40 scaled by 2^-20 */
    int64_t a[3], u[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = (int64_t)(rng(&seed) % (1ULL << 40)) - (1LL << 39);
      u[i] = (int64_t)(rng(&seed) % (1ULL << 20)) - (1LL << 19);
    }
    int64_t m = 1 + (int64_t)(rng(&seed) % 1000);
    TlVec3 pa = tl_v3(ldexp((double)a[0], -20), ldexp((double)a[1], -20), ldexp((double)a[2], -20));
    TlVec3 pb = tl_v3(ldexp((double)(a[0] + u[0]), -20), ldexp((double)(a[1] + u[1]), -20), ldexp((double)(a[2] + u[2]), -20));
    TlVec3 pc = tl_v3(ldexp((double)(a[0] + m * u[0]), -20), ldexp((double)(a[1] + m * u[1]), -20),
                      ldexp((double)(a[2] + m * u[2]), -20));
    col += tl_collinear3d(pa, pb, pc);
    col_f += tl_collinear3d_filtered(pa, pb, pc);
    TlVec3 pd = tl_v3(pc.x, pc.y, pc.z + ldexp(1.0, -20)); /* one unit off the line */
    off += !tl_collinear3d(pa, pb, pd) && !tl_collinear3d_filtered(pa, pb, pd);
    TlVec3 cr = tl_v3_cross(tl_v3_sub(pb, pa), tl_v3_sub(pc, pa));
    naive_wrong += tl_v3_norm(cr) != 0.0;
    /* orient2d against the sign of the integer determinant */
    __int128 det = (__int128)u[0] * (m * u[1] + 1) - (__int128)u[1] * (m * u[0]);
    TlVec3 pe = tl_v3(pc.x, ldexp((double)(a[1] + m * u[1] + 1), -20), 0);
    int want = (det > 0) - (det < 0);
    orient_ok += tl_orient2d(pa.x, pa.y, pb.x, pb.y, pe.x, pe.y) == want &&
                 tl_orient2d_filtered(pa.x, pa.y, pb.x, pb.y, pe.x, pe.y) == want &&
                 tl_orient2d(pa.x, pa.y, pb.x, pb.y, pc.x, pc.y) == 0 && tl_orient2d_filtered(pa.x, pa.y, pb.x, pb.y, pc.x, pc.y) == 0;
  }
  printf("collinear: %d of %d (library path %d), off-line refused %d, naive cross product nonzero in %d\n", col, n, col_f,
         off, naive_wrong);
  TL_TEST_ASSERT(col == n && col_f == n, "collinear %d, %d of %d", col, col_f, n);
  TL_TEST_ASSERT(off == n, "one unit off the line: %d of %d", off, n);
  TL_TEST_ASSERT(orient_ok == n, "orient2d right on %d of %d", orient_ok, n);
}

static void test_dihedral(void)
{
  /* edge along x; half-planes through (0, 1, 0) and (0, 3, 4) (rotated and
   * shifted: inexact coordinates): the dihedral angle has cosine exactly
   * 3/5, which no double is */
  TlMat3 R = tl_m3_rotation(tl_v3(0.3, -0.5, 0.8), 1.1);
  TlVec3 o = tl_v3(0.1, 0.7, -2.3);
  TlVec3 a = o, b = tl_v3_add(o, tl_v3(1, 0, 0)), c = tl_v3_add(o, tl_v3(0.5, 1, 0)), d = tl_v3_add(o, tl_v3(-2, 3, 4));
  double k = 0.6; /* 0.59999999999999997780: the angle of this cosine is a hair larger */
  TL_TEST_ASSERT(tl_dihedral_compare(a, b, c, d, k) == -1 && tl_dihedral_compare_filtered(a, b, c, d, k, NULL) == -1,
                 "acos(3/5) < acos(0.6 rounded down)");
  double k2 = nextafter(0.6, 1.0);
  TL_TEST_ASSERT(tl_dihedral_compare(a, b, c, d, k2) == 1 && tl_dihedral_compare_filtered(a, b, c, d, k2, NULL) == 1,
                 "acos(3/5) > acos(0.6 rounded up)");
  int stage = 0;
  (void)tl_dihedral_compare_filtered(a, b, c, d, k, &stage);
  TL_TEST_ASSERT(stage == 1, "a hair away: decided by the exact stage");
  /* exactly 90 degrees against cosine 0: equal, on both paths */
  TL_TEST_ASSERT(tl_dihedral_compare(a, b, c, tl_v3_add(o, tl_v3(7, 0, 2)), 0.0) == 0 &&
                     tl_dihedral_compare_filtered(a, b, c, tl_v3_add(o, tl_v3(7, 0, 2)), 0.0, NULL) == 0,
                 "right angle equals acos(0)");
  /* flat (180) and folded back (0) */
  TL_TEST_ASSERT(tl_dihedral_compare_filtered(a, b, c, tl_v3_add(o, tl_v3(3, -2, 0)), -1.0, NULL) == 0, "flat = 180");
  TL_TEST_ASSERT(tl_dihedral_compare_filtered(a, b, c, tl_v3_add(o, tl_v3(3, 2, 0)), 1.0, NULL) == 0, "closed = 0");
  /* rotated: the two paths agree with the geometry for a clear fold */
  TlVec3 ra = tl_m3_mulv(R, a), rb = tl_m3_mulv(R, b), rc = tl_m3_mulv(R, c), rd = tl_m3_mulv(R, d);
  TL_TEST_ASSERT(tl_dihedral_compare(ra, rb, rc, rd, 0.7) == 1 && tl_dihedral_compare_filtered(ra, rb, rc, rd, 0.7, NULL) == 1,
                 "53 degrees > acos 0.7 = 45.6");
  TL_TEST_ASSERT(tl_dihedral_compare(ra, rb, rc, rd, 0.5) == -1 && tl_dihedral_compare_filtered(ra, rb, rc, rd, 0.5, NULL) == -1,
                 "53 degrees < 60");
  /* random: the paths agree */
  uint64_t seed = 5;
  int same = 0;
  for (int k3 = 0; k3 < 2000; ++k3) {
    TlVec3 p[4];
    for (int i = 0; i < 4; ++i) p[i] = tl_v3(urand(&seed), urand(&seed), urand(&seed));
    double cs = 2 * urand(&seed) - 1;
    same += tl_dihedral_compare(p[0], p[1], p[2], p[3], cs) == tl_dihedral_compare_filtered(p[0], p[1], p[2], p[3], cs, NULL);
  }
  TL_TEST_ASSERT(same == 2000, "dihedral paths agree on %d of 2000", same);
}

int main(void)
{
  test_insphere();
  test_collinear();
  test_dihedral();
  printf("through CGAL: %s\n", tl_predicates_use_cgal() ? "yes" : "no");
  return tl_test_report();
}
