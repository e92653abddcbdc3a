/* Orientation predicate: clear cases, exactly coplanar points, and points a
 * hair off a plane where a naive double evaluation gets the sign wrong. */
#include "talus.h"
#include "tl_predicates.h"
#include "tl_test.h"

int main(void)
{
  TlVec3 a = tl_v3(0, 0, 0), b = tl_v3(1, 0, 0), c = tl_v3(0, 1, 0);
  TL_TEST_ASSERT(tl_orient3d(a, b, c, tl_v3(0.3, 0.3, 1)) == 1, "above");
  TL_TEST_ASSERT(tl_orient3d(a, b, c, tl_v3(0.3, 0.3, -1)) == -1, "below");
  TL_TEST_ASSERT(tl_orient3d(a, b, c, tl_v3(5, -7, 0)) == 0, "on the plane");
  /* A tilted plane whose points are exactly coplanar in binary: (t, t, t)
   * lies on the plane x + y - 2z = 0 through these points. */
  TlVec3 p = tl_v3(1, 1, 1), q = tl_v3(2, 0, 1), r = tl_v3(0, 2, 1);
  for (int k = 1; k < 50; ++k) {
    double t = 0.1 * k + 1e6;
    TL_TEST_ASSERT(tl_orient3d(p, q, r, tl_v3(t, t, t)) == 0, "coplanar point %d", k);
  }
  /* One ulp off a plane far from the origin. */
  double big = 1e8;
  TlVec3 A = tl_v3(big, big, big), B = tl_v3(big + 1, big, big), C = tl_v3(big, big + 1, big);
  TlVec3 up = tl_v3(big + 0.5, big + 0.5, nextafter(big, 2 * big));
  TlVec3 down = tl_v3(big + 0.5, big + 0.5, nextafter(big, 0));
  TL_TEST_ASSERT(tl_orient3d(A, B, C, up) == 1, "one ulp above");
  TL_TEST_ASSERT(tl_orient3d(A, B, C, down) == -1, "one ulp below");
  printf("exact predicates (CGAL): %s\n", tl_predicates_are_exact() ? "yes" : "no");
  return tl_test_report();
}
