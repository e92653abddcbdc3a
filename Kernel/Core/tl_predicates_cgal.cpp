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

extern "C" int tl_cgal_insphere(const double a[3], const double b[3], const double c[3], const double d[3],
                                const double e[3])
{
  // ON_POSITIVE_SIDE: e inside the sphere of a positively oriented (a, b, c, d).
  CGAL::Oriented_side s = CGAL::side_of_oriented_sphere(
      Kernel::Point_3(a[0], a[1], a[2]), Kernel::Point_3(b[0], b[1], b[2]), Kernel::Point_3(c[0], c[1], c[2]),
      Kernel::Point_3(d[0], d[1], d[2]), Kernel::Point_3(e[0], e[1], e[2]));
  return s == CGAL::ON_POSITIVE_SIDE ? 1 : (s == CGAL::ON_NEGATIVE_SIDE ? -1 : 0);
}

extern "C" int tl_cgal_dihedral_compare(const double a[3], const double b[3], const double c[3], const double d[3],
                                        double cosine)
{
  CGAL::Comparison_result r = CGAL::compare_dihedral_angle(
      Kernel::Point_3(a[0], a[1], a[2]), Kernel::Point_3(b[0], b[1], b[2]), Kernel::Point_3(c[0], c[1], c[2]),
      Kernel::Point_3(d[0], d[1], d[2]), cosine);
  return r == CGAL::SMALLER ? -1 : (r == CGAL::LARGER ? 1 : 0);
}

extern "C" int tl_cgal_dot3_sign(const double v[3], const double u[3], const double p[3])
{
  // angle(u, v, p) is the sign of (u - v) . (p - v): acute, right or obtuse at v.
  CGAL::Angle r = CGAL::angle(Kernel::Point_3(u[0], u[1], u[2]), Kernel::Point_3(v[0], v[1], v[2]),
                              Kernel::Point_3(p[0], p[1], p[2]));
  return r == CGAL::ACUTE ? 1 : (r == CGAL::OBTUSE ? -1 : 0);
}
