// CGAL shim: exact orientation through CGAL's filtered exact predicates.
// Compiled only with -DTALUS_WITH_CGAL=ON.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

extern "C" int tl_cgal_orient3d(const double a[3], const double b[3], const double c[3], const double d[3])
{
  Kernel::Point_3 pa(a[0], a[1], a[2]), pb(b[0], b[1], b[2]), pc(c[0], c[1], c[2]), pd(d[0], d[1], d[2]);
  // CGAL's sign convention is Talus's: the sign of det[b - a, c - a, d - a].
  CGAL::Orientation o = CGAL::orientation(pa, pb, pc, pd);
  return o == CGAL::POSITIVE ? 1 : (o == CGAL::NEGATIVE ? -1 : 0);
}

extern "C" int tl_cgal_orient2d(const double a[2], const double b[2], const double c[2])
{
  CGAL::Orientation o = CGAL::orientation(Kernel::Point_2(a[0], a[1]), Kernel::Point_2(b[0], b[1]), Kernel::Point_2(c[0], c[1]));
  return o == CGAL::POSITIVE ? 1 : (o == CGAL::NEGATIVE ? -1 : 0);
}

extern "C" int tl_cgal_collinear3d(const double a[3], const double b[3], const double c[3])
{
  return CGAL::collinear(Kernel::Point_3(a[0], a[1], a[2]), Kernel::Point_3(b[0], b[1], b[2]),
                         Kernel::Point_3(c[0], c[1], c[2]))
             ? 1
             : 0;
}
