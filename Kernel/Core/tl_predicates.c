#include "tl_predicates.h"

#include <float.h>
#include <math.h>

#include "tl_config.h"

#if TALUS_WITH_CGAL
int tl_cgal_orient3d(const double a[3], const double b[3], const double c[3], const double d[3]);
#endif

#if !TALUS_WITH_CGAL
static int tl_sign_quad(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d)
{
  __float128 u[3] = {(__float128)b.x - a.x, (__float128)b.y - a.y, (__float128)b.z - a.z};
  __float128 v[3] = {(__float128)c.x - a.x, (__float128)c.y - a.y, (__float128)c.z - a.z};
  __float128 w[3] = {(__float128)d.x - a.x, (__float128)d.y - a.y, (__float128)d.z - a.z};
  __float128 det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                   u[2] * (v[0] * w[1] - v[1] * w[0]);
  return (det > 0) - (det < 0);
}
#endif

int tl_orient3d(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d)
{
#if TALUS_WITH_CGAL
  double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z}, pd[3] = {d.x, d.y, d.z};
  return tl_cgal_orient3d(pa, pb, pc, pd);
#else
  TlVec3 u = tl_v3_sub(b, a), v = tl_v3_sub(c, a), w = tl_v3_sub(d, a);
  double t1 = u.x * (v.y * w.z - v.z * w.y), t2 = u.y * (v.x * w.z - v.z * w.x), t3 = u.z * (v.x * w.y - v.y * w.x);
  double det = t1 - t2 + t3;
  /* Forward error bound of the double evaluation (differences included). */
  double permanent = (fabs(u.x) * (fabs(v.y * w.z) + fabs(v.z * w.y)) + fabs(u.y) * (fabs(v.x * w.z) + fabs(v.z * w.x)) +
                      fabs(u.z) * (fabs(v.x * w.y) + fabs(v.y * w.x)));
  double bound = 16.0 * DBL_EPSILON * permanent;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return tl_sign_quad(a, b, c, d);
#endif
}

int tl_predicates_are_exact(void) { return TALUS_WITH_CGAL; }
