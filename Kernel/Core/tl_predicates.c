#include "tl_predicates.h"

#include <float.h>
#include <math.h>
#include <stddef.h>

#include "tl_config.h"

#if TALUS_WITH_CGAL
int tl_cgal_orient3d(const double a[3], const double b[3], const double c[3], const double d[3]);
int tl_cgal_orient2d(const double a[2], const double b[2], const double c[2]);
int tl_cgal_collinear3d(const double a[3], const double b[3], const double c[3]);

#endif

/* Error bound of the double evaluation below, relative to its permanent
 * (the same expression with every product and sum taken in absolute value,
 * evaluated in doubles).  With u = DBL_EPSILON/2 the unit round-off: a
 * product of three differences carries 3u from its rounded factors and 2u
 * from its own two roundings, the difference of two such products 1u more
 * and the two additions of the cofactor expansion 2u more: 8u to first
 * order.  The bound 16u (8 DBL_EPSILON) leaves a factor of 2 for the
 * rounding of the permanent itself and the terms of order u^2, for any input
 * that neither overflows nor underflows. */
#define TL_ORIENT3D_BOUND (8.0 * DBL_EPSILON)

/* Expansion arithmetic: a real number as the exact sum of doubles whose
 * magnitudes increase and whose bits do not overlap, zeros dropped.  Every
 * operation below is a sequence of error-free transformations (the rounded
 * sum or product and its exact rounding error), so the result is the exact
 * value; its sign is the sign of its largest component.  Requires IEEE
 * round-to-nearest and no overflow or underflow of the products. */
/* Longest expansion below: differences of 2 components, products of two of
 * them 8, a cross-product component 16, its product with a difference 64,
 * the determinant 3 x 64 = 192. */
enum { TL_EXPANSION_MAX = 256 };

typedef struct {
  int n;
  double c[TL_EXPANSION_MAX];
} TlExpansion;

/* a + b = s + e exactly (s the rounded sum). */
static inline void tl_two_sum(double a, double b, double *s, double *e)
{
  double x = a + b, bv = x - a, av = x - bv;
  *s = x;
  *e = (a - av) + (b - bv);
}

/* a * b = p + e exactly (fma gives the rounding error). */
static inline void tl_two_product(double a, double b, double *p, double *e)
{
  double x = a * b;
  *p = x;
  *e = fma(a, b, -x);
}

/* h += b: one pass of two-sums through the components (nonoverlapping in,
 * nonoverlapping out), zeros dropped. */
static void tl_expansion_grow(TlExpansion *h, double b)
{
  if (b == 0.0) return;
  double q = b;
  int m = 0;
  for (int i = 0; i < h->n; ++i) {
    double s, e;
    tl_two_sum(q, h->c[i], &s, &e);
    q = s;
    if (e != 0.0) h->c[m++] = e;
  }
  if (q != 0.0) h->c[m++] = q;
  h->n = m;
}

static void tl_expansion_add(TlExpansion *h, const TlExpansion *f)
{
  for (int i = 0; i < f->n; ++i) tl_expansion_grow(h, f->c[i]);
}

/* h = e * f, the products of all component pairs and their errors grown
 * into an empty expansion. */
static void tl_expansion_mul(const TlExpansion *e, const TlExpansion *f, TlExpansion *h)
{
  h->n = 0;
  for (int i = 0; i < e->n; ++i)
    for (int j = 0; j < f->n; ++j) {
      double p, err;
      tl_two_product(e->c[i], f->c[j], &p, &err);
      tl_expansion_grow(h, err);
      tl_expansion_grow(h, p);
    }
}

static void tl_expansion_negate(TlExpansion *h)
{
  for (int i = 0; i < h->n; ++i) h->c[i] = -h->c[i];
}

/* b - a exactly, as an expansion of at most two components. */
static void tl_expansion_diff(double b, double a, TlExpansion *h)
{
  h->n = 0;
  tl_expansion_grow(h, b);
  tl_expansion_grow(h, -a);
}

static int tl_expansion_sign(const TlExpansion *h)
{
  if (h->n == 0) return 0;
  return h->c[h->n - 1] > 0.0 ? 1 : -1;
}

/* det[b - a, c - a, d - a] exactly: the differences as exact expansions
 * (one component each when they are exact in doubles, the common case of
 * nearby points, which keeps the expansions short), then u . (v x w). */
static int tl_orient3d_exact(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d)
{
  TlExpansion u[3], v[3], w[3], p, q, cross, term, det;
  const double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z}, pd[3] = {d.x, d.y, d.z};
  for (int k = 0; k < 3; ++k) {
    tl_expansion_diff(pb[k], pa[k], &u[k]);
    tl_expansion_diff(pc[k], pa[k], &v[k]);
    tl_expansion_diff(pd[k], pa[k], &w[k]);
  }
  det.n = 0;
  for (int k = 0; k < 3; ++k) {
    int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    /* (v x w)_k = v_k1 w_k2 - v_k2 w_k1 */
    tl_expansion_mul(&v[k1], &w[k2], &p);
    tl_expansion_mul(&v[k2], &w[k1], &q);
    tl_expansion_negate(&q);
    cross = p;
    tl_expansion_add(&cross, &q);
    tl_expansion_mul(&u[k], &cross, &term);
    tl_expansion_add(&det, &term);
  }
  return tl_expansion_sign(&det);
}

int tl_orient3d_filtered(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, int *exact_stage)
{
  TlVec3 u = tl_v3_sub(b, a), v = tl_v3_sub(c, a), w = tl_v3_sub(d, a);
  double m1 = v.y * w.z, m2 = v.z * w.y, m3 = v.z * w.x, m4 = v.x * w.z, m5 = v.x * w.y, m6 = v.y * w.x;
  double det = u.x * (m1 - m2) + u.y * (m3 - m4) + u.z * (m5 - m6);
  double permanent = fabs(u.x) * (fabs(m1) + fabs(m2)) + fabs(u.y) * (fabs(m3) + fabs(m4)) +
                     fabs(u.z) * (fabs(m5) + fabs(m6));
  double bound = TL_ORIENT3D_BOUND * permanent;
  if (exact_stage) *exact_stage = 0;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  /* every product is zero (an axis-aligned plane through the four points):
   * so is the determinant */
  if (permanent == 0.0) return 0;
  if (exact_stage) *exact_stage = 1;
  return tl_orient3d_exact(a, b, c, d);
}

int tl_orient3d(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d)
{
#if TALUS_WITH_CGAL
  double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z}, pd[3] = {d.x, d.y, d.z};
  return tl_cgal_orient3d(pa, pb, pc, pd);
#else
  return tl_orient3d_filtered(a, b, c, d, NULL);
#endif
}

/* det[b - a, c - a] exactly: two products of two-component differences. */
static int tl_orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy)
{
  TlExpansion ux, uy, vx, vy, p, q;
  tl_expansion_diff(bx, ax, &ux);
  tl_expansion_diff(by, ay, &uy);
  tl_expansion_diff(cx, ax, &vx);
  tl_expansion_diff(cy, ay, &vy);
  tl_expansion_mul(&ux, &vy, &p);
  tl_expansion_mul(&uy, &vx, &q);
  tl_expansion_negate(&q);
  tl_expansion_add(&p, &q);
  return tl_expansion_sign(&p);
}

/* The same filter as orient3d: the 2 x 2 determinant carries 3u from its
 * differences and products and 1u from its difference; 4 DBL_EPSILON (8u)
 * bounds it with the rounding of the permanent. */
int tl_orient2d_filtered(double ax, double ay, double bx, double by, double cx, double cy)
{
  double m1 = (bx - ax) * (cy - ay), m2 = (by - ay) * (cx - ax);
  double det = m1 - m2, bound = 4.0 * DBL_EPSILON * (fabs(m1) + fabs(m2));
  if (det > bound) return 1;
  if (det < -bound) return -1;
  if (m1 == 0.0 && m2 == 0.0) return 0;
  return tl_orient2d_exact(ax, ay, bx, by, cx, cy);
}

int tl_orient2d(double ax, double ay, double bx, double by, double cx, double cy)
{
#if TALUS_WITH_CGAL
  double pa[2] = {ax, ay}, pb[2] = {bx, by}, pc[2] = {cx, cy};
  return tl_cgal_orient2d(pa, pb, pc);
#else
  return tl_orient2d_filtered(ax, ay, bx, by, cx, cy);
#endif
}

int tl_collinear3d_filtered(TlVec3 a, TlVec3 b, TlVec3 c)
{
  /* collinear in space iff collinear in the three coordinate planes */
  return tl_orient2d_filtered(a.x, a.y, b.x, b.y, c.x, c.y) == 0 && tl_orient2d_filtered(a.y, a.z, b.y, b.z, c.y, c.z) == 0 &&
         tl_orient2d_filtered(a.z, a.x, b.z, b.x, c.z, c.x) == 0;
}

int tl_collinear3d(TlVec3 a, TlVec3 b, TlVec3 c)
{
#if TALUS_WITH_CGAL
  double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z};
  return tl_cgal_collinear3d(pa, pb, pc);
#else
  return tl_collinear3d_filtered(a, b, c);
#endif
}

int tl_predicates_are_exact(void) { return 1; }

int tl_predicates_use_cgal(void) { return TALUS_WITH_CGAL; }
