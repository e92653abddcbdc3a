#include "tl_predicates.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "tl_config.h"

#if TALUS_WITH_CGAL
int tl_cgal_orient3d(const double a[3], const double b[3], const double c[3], const double d[3]);
int tl_cgal_orient2d(const double a[2], const double b[2], const double c[2]);
int tl_cgal_collinear3d(const double a[3], const double b[3], const double c[3]);
int tl_cgal_dihedral_compare(const double a[3], const double b[3], const double c[3], const double d[3], double cosine);
int tl_cgal_insphere(const double a[3], const double b[3], const double c[3], const double d[3], const double e[3]);
int tl_cgal_dot3_sign(const double v[3], const double u[3], const double p[3]);

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

/* c[0..n) += b in place: one pass of two-sums through the components
 * (nonoverlapping in, nonoverlapping out), zeros dropped; room for n + 1
 * components is the caller's.  Returns the new count. */
static int tl_components_grow(double *c, int n, double b)
{
  double q = b;
  int m = 0;
  for (int i = 0; i < n; ++i) {
    double s, e;
    tl_two_sum(q, c[i], &s, &e);
    q = s;
    if (e != 0.0) c[m++] = e;
  }
  if (q != 0.0) c[m++] = q;
  return m;
}

/* h += b. */
static void tl_expansion_grow(TlExpansion *h, double b)
{
  if (b == 0.0) return;
  h->n = tl_components_grow(h->c, h->n, b);
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

/* In-sphere.  Its exact stage needs expansions far longer than the fixed
 * ones above (a lifted coordinate times a 3 x 3 minor: up to 9216
 * components before compression), so they live on the heap and are
 * compressed after every product, which keeps them short for the inputs
 * that reach the stage (nearly cospherical points). */
typedef struct {
  int n, cap;
  double *c;
} TlBigExpansion;

static int big_reserve(TlBigExpansion *h, int n)
{
  if (n <= h->cap) return 1;
  int cap = n > 2 * h->cap ? n : 2 * h->cap;
  double *c = realloc(h->c, (size_t)cap * sizeof *c);
  if (!c) return 0;
  h->c = c;
  h->cap = cap;
  return 1;
}

static int big_grow(TlBigExpansion *h, double b)
{
  if (b == 0.0) return 1;
  if (!big_reserve(h, h->n + 1)) return 0;
  h->n = tl_components_grow(h->c, h->n, b);
  return 1;
}

/* Shortens h in place without changing its value (the components are
 * re-summed from the top so that each carries as many bits as it can). */
static void big_compress(TlBigExpansion *h)
{
  if (h->n < 2) return;
  double *e = h->c, q, qn;
  int bottom = h->n - 1;
  q = e[bottom];
  for (int i = h->n - 2; i >= 0; --i) {
    double enow = e[i];
    qn = q + enow;
    double r = enow - (qn - q);
    if (r != 0.0) {
      e[bottom--] = qn;
      q = r;
    } else {
      q = qn;
    }
  }
  int top = 0;
  for (int i = bottom + 1; i < h->n; ++i) {
    double hnow = e[i];
    qn = hnow + q;
    double r = q - (qn - hnow);
    if (r != 0.0) e[top++] = r;
    q = qn;
  }
  e[top++] = q;
  h->n = q == 0.0 && top == 1 ? 0 : top;
}

/* h += sign * e * f */
static int big_add_product(TlBigExpansion *h, const TlBigExpansion *e, const TlBigExpansion *f, double sign)
{
  for (int i = 0; i < e->n; ++i)
    for (int j = 0; j < f->n; ++j) {
      double p, err;
      tl_two_product(sign * e->c[i], f->c[j], &p, &err);
      if (!big_grow(h, err) || !big_grow(h, p)) return 0;
    }
  big_compress(h);
  return 1;
}

static int big_set_diff(TlBigExpansion *h, double b, double a)
{
  h->n = 0;
  return big_grow(h, b) && big_grow(h, -a);
}

/* Exact sign of the in-sphere determinant of the points relative to e;
 * -2 when memory ran out. */
static int tl_insphere_exact(const TlVec3 p[4], TlVec3 e)
{
  TlBigExpansion d[4][3], lift[4], m2, m3, det;
  memset(d, 0, sizeof d), memset(lift, 0, sizeof lift), memset(&m2, 0, sizeof m2), memset(&m3, 0, sizeof m3);
  memset(&det, 0, sizeof det);
  int ok = 1, sign = -2;
  for (int i = 0; i < 4 && ok; ++i) {
    ok = big_set_diff(&d[i][0], p[i].x, e.x) && big_set_diff(&d[i][1], p[i].y, e.y) && big_set_diff(&d[i][2], p[i].z, e.z);
    for (int k = 0; k < 3 && ok; ++k) ok = big_add_product(&lift[i], &d[i][k], &d[i][k], 1.0);
  }
  /* det = sum_i (-1)^i lift_i * M_i, M_i the 3 x 3 determinant of the
   * other three rows: minus the 4 x 4 determinant [d_i, lift_i] expanded
   * along its lifted column, the sign that makes +1 inside for a positive
   * tetrahedron */
  for (int i = 0; i < 4 && ok; ++i) {
    int r[3], n = 0;
    for (int j = 0; j < 4; ++j)
      if (j != i) r[n++] = j;
    m3.n = 0;
    for (int k = 0; k < 3 && ok; ++k) {
      int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      m2.n = 0;
      ok = big_add_product(&m2, &d[r[1]][k1], &d[r[2]][k2], 1.0) && big_add_product(&m2, &d[r[1]][k2], &d[r[2]][k1], -1.0) &&
           big_add_product(&m3, &d[r[0]][k], &m2, 1.0);
    }
    if (ok) ok = big_add_product(&det, &lift[i], &m3, i % 2 ? -1.0 : 1.0);
  }
  if (ok) sign = det.n == 0 ? 0 : (det.c[det.n - 1] > 0.0 ? 1 : -1);
  for (int i = 0; i < 4; ++i) {
    free(lift[i].c);
    for (int k = 0; k < 3; ++k) free(d[i][k].c);
  }
  free(m2.c), free(m3.c), free(det.c);
  return sign;
}

int tl_insphere_filtered(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, TlVec3 e, int *exact_stage)
{
  const TlVec3 p[4] = {a, b, c, d};
  double x[4][4], ax[4][4];
  for (int i = 0; i < 4; ++i) {
    TlVec3 q = tl_v3_sub(p[i], e);
    x[i][0] = q.x, x[i][1] = q.y, x[i][2] = q.z;
    x[i][3] = q.x * q.x + q.y * q.y + q.z * q.z;
    for (int k = 0; k < 4; ++k) ax[i][k] = fabs(x[i][k]);
  }
  double det = 0.0, perm = 0.0;
  for (int i = 0; i < 4; ++i) {
    int r[3], n = 0;
    for (int j = 0; j < 4; ++j)
      if (j != i) r[n++] = j;
    double m = 0.0, pm = 0.0;
    for (int k = 0; k < 3; ++k) {
      int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      m += x[r[0]][k] * (x[r[1]][k1] * x[r[2]][k2] - x[r[1]][k2] * x[r[2]][k1]);
      pm += ax[r[0]][k] * (ax[r[1]][k1] * ax[r[2]][k2] + ax[r[1]][k2] * ax[r[2]][k1]);
    }
    det += (i % 2 ? -1.0 : 1.0) * x[i][3] * m;
    perm += ax[i][3] * pm;
  }
  /* the rounded differences (1u), the lift (3u more), the minors (5u as in
   * orient3d), the product and the sum (3u): 12u, doubled for the rounding
   * of the permanent: 24u, and a margin of 4/3: 32u = 16 DBL_EPSILON */
  double bound = 16.0 * DBL_EPSILON * perm;
  if (exact_stage) *exact_stage = 0;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  if (perm == 0.0) return 0;
  if (exact_stage) *exact_stage = 1;
  return tl_insphere_exact(p, e);
}

int tl_insphere(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, TlVec3 e)
{
#if TALUS_WITH_CGAL
  double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z}, pd[3] = {d.x, d.y, d.z},
         pe[3] = {e.x, e.y, e.z};
  return tl_cgal_insphere(pa, pb, pc, pd, pe);
#else
  return tl_insphere_filtered(a, b, c, d, e, NULL);
#endif
}

/* Dihedral angle against a cosine, exactly: with n1 = u x v, n2 = u x w
 * (u = b - a, v = c - a, w = d - a) the angle's cosine is
 * n1.n2 / (|n1| |n2|); its comparison with k is decided by the signs of
 * n1.n2 and k, else by (n1.n2)^2 against k^2 |n1|^2 |n2|^2 (degree 8 in
 * the coordinates, in expansions).  -2 if memory ran out. */
static int tl_dihedral_exact(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, double k)
{
  TlBigExpansion u[3], v[3], w[3], n1[3], n2[3], dot, q1, q2, lhs, rhs, kk, kexp;
  memset(u, 0, sizeof u), memset(v, 0, sizeof v), memset(w, 0, sizeof w), memset(n1, 0, sizeof n1);
  memset(n2, 0, sizeof n2), memset(&dot, 0, sizeof dot), memset(&q1, 0, sizeof q1), memset(&q2, 0, sizeof q2);
  memset(&lhs, 0, sizeof lhs), memset(&rhs, 0, sizeof rhs), memset(&kk, 0, sizeof kk), memset(&kexp, 0, sizeof kexp);
  const double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z}, pd[3] = {d.x, d.y, d.z};
  int ok = 1, result = -2;
  for (int i = 0; i < 3 && ok; ++i)
    ok = big_set_diff(&u[i], pb[i], pa[i]) && big_set_diff(&v[i], pc[i], pa[i]) && big_set_diff(&w[i], pd[i], pa[i]);
  for (int i = 0; i < 3 && ok; ++i) {
    int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    ok = big_add_product(&n1[i], &u[i1], &v[i2], 1.0) && big_add_product(&n1[i], &u[i2], &v[i1], -1.0) &&
         big_add_product(&n2[i], &u[i1], &w[i2], 1.0) && big_add_product(&n2[i], &u[i2], &w[i1], -1.0);
  }
  for (int i = 0; i < 3 && ok; ++i)
    ok = big_add_product(&dot, &n1[i], &n2[i], 1.0) && big_add_product(&q1, &n1[i], &n1[i], 1.0) &&
         big_add_product(&q2, &n2[i], &n2[i], 1.0);
  if (ok) {
    int sd = dot.n ? (dot.c[dot.n - 1] > 0 ? 1 : -1) : 0, sk = (k > 0) - (k < 0);
    if (sd >= 0 && sk < 0) result = -1;     /* cos >= 0 > k: the angle is smaller */
    else if (sd <= 0 && sk > 0) result = 1; /* cos <= 0 < k: larger */
    else if (sd == 0 && sk == 0) result = 0;
    else {
      ok = big_grow(&kexp, k) && big_add_product(&kk, &kexp, &kexp, 1.0) && big_add_product(&lhs, &dot, &dot, 1.0) &&
           big_add_product(&rhs, &q1, &q2, 1.0);
      if (ok) {
        TlBigExpansion diff;
        memset(&diff, 0, sizeof diff);
        ok = big_add_product(&diff, &kk, &rhs, -1.0);
        for (int i = 0; i < lhs.n && ok; ++i) ok = big_grow(&diff, lhs.c[i]);
        if (ok) {
          big_compress(&diff);
          int s = diff.n ? (diff.c[diff.n - 1] > 0 ? 1 : -1) : 0; /* sign of cos^2 - k^2 */
          result = sd > 0 ? -s : s;
        }
        free(diff.c);
      }
    }
  }
  for (int i = 0; i < 3; ++i) free(u[i].c), free(v[i].c), free(w[i].c), free(n1[i].c), free(n2[i].c);
  free(dot.c), free(q1.c), free(q2.c), free(lhs.c), free(rhs.c), free(kk.c), free(kexp.c);
  return result;
}

int tl_dihedral_compare_filtered(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, double cosine, int *exact_stage)
{
  TlVec3 u = tl_v3_sub(b, a), v = tl_v3_sub(c, a), w = tl_v3_sub(d, a);
  TlVec3 n1 = tl_v3_cross(u, v), n2 = tl_v3_cross(u, w);
  double l1 = tl_v3_norm(n1), l2 = tl_v3_norm(n2);
  if (exact_stage) *exact_stage = 0;
  if (l1 > 0.0 && l2 > 0.0 && isfinite(l1 * l2)) {
    double cs = tl_v3_dot(n1, n2) / (l1 * l2);
    /* the rounding of each normal relative to its length (differences and
     * cross product: a few units in the last place of |u| |v|, which the
     * normal's length divides when the triangle is thin), doubled for the
     * cosine, with a margin of 8 */
    double nu = tl_v3_norm(u);
    double bound = 64.0 * DBL_EPSILON * (1.0 + nu * tl_v3_norm(v) / l1 + nu * tl_v3_norm(w) / l2);
    if (cs - cosine > bound) return -1;
    if (cosine - cs > bound) return 1;
  }
  if (exact_stage) *exact_stage = 1;
  return tl_dihedral_exact(a, b, c, d, cosine);
}

int tl_dihedral_compare(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, double cosine)
{
#if TALUS_WITH_CGAL
  double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z}, pd[3] = {d.x, d.y, d.z};
  return tl_cgal_dihedral_compare(pa, pb, pc, pd, cosine);
#else
  return tl_dihedral_compare_filtered(a, b, c, d, cosine, NULL);
#endif
}

/* (u - v) . (p - v) exactly: three products of two-component differences,
 * at most 24 components. */
static int tl_dot3_exact(TlVec3 v, TlVec3 u, TlVec3 p)
{
  const double pv[3] = {v.x, v.y, v.z}, pu[3] = {u.x, u.y, u.z}, pp[3] = {p.x, p.y, p.z};
  TlExpansion du, dp, term, sum;
  sum.n = 0;
  for (int k = 0; k < 3; ++k) {
    tl_expansion_diff(pu[k], pv[k], &du);
    tl_expansion_diff(pp[k], pv[k], &dp);
    tl_expansion_mul(&du, &dp, &term);
    tl_expansion_add(&sum, &term);
  }
  return tl_expansion_sign(&sum);
}

/* The filter: each term carries 2u from its rounded differences and 1u
 * from its product, the two sums 2u more: 5u of the permanent; 4
 * DBL_EPSILON (8u) bounds it with the permanent's own rounding. */
int tl_dot3_sign_filtered(TlVec3 v, TlVec3 u, TlVec3 p, int *exact_stage)
{
  TlVec3 e = tl_v3_sub(u, v), w = tl_v3_sub(p, v);
  double m0 = e.x * w.x, m1 = e.y * w.y, m2 = e.z * w.z;
  double dot = m0 + m1 + m2, permanent = fabs(m0) + fabs(m1) + fabs(m2);
  double bound = 4.0 * DBL_EPSILON * permanent;
  if (exact_stage) *exact_stage = 0;
  if (dot > bound) return 1;
  if (dot < -bound) return -1;
  /* a product of rounded differences is zero only when a difference is */
  if (permanent == 0.0) return 0;
  if (exact_stage) *exact_stage = 1;
  return tl_dot3_exact(v, u, p);
}

int tl_dot3_sign(TlVec3 v, TlVec3 u, TlVec3 p)
{
#if TALUS_WITH_CGAL
  double pv[3] = {v.x, v.y, v.z}, pu[3] = {u.x, u.y, u.z}, pp[3] = {p.x, p.y, p.z};
  return tl_cgal_dot3_sign(pv, pu, pp);
#else
  return tl_dot3_sign_filtered(v, u, p, NULL);
#endif
}

/* n . m exactly, n = e x f and m = e x w (e = b - a, f = c - a, w = p - a):
 * the cross products of the exact differences, then their dot product, on
 * the heap with compression (a degree-4 value: up to 3 x 16 x 16 x 2
 * components before compression).  -2 if memory ran out. */
/* The common case of nearby points, whose differences are exact doubles:
 * each cross-product component is an expansion of 4, each product of two
 * of 32, the sum of 96; no heap.  Returns 2 when a difference is inexact. */
static int tl_edge_side_short(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p)
{
  const double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z}, pp[3] = {p.x, p.y, p.z};
  double e[3], f[3], w[3], err;
  for (int i = 0; i < 3; ++i) {
    tl_two_sum(pb[i], -pa[i], &e[i], &err);
    if (err != 0.0) return 2;
    tl_two_sum(pc[i], -pa[i], &f[i], &err);
    if (err != 0.0) return 2;
    tl_two_sum(pp[i], -pa[i], &w[i], &err);
    if (err != 0.0) return 2;
  }
  TlExpansion n, m, term, dot;
  dot.n = 0;
  for (int i = 0; i < 3; ++i) {
    int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    double hi, lo;
    n.n = m.n = 0;
    tl_two_product(e[i1], f[i2], &hi, &lo);
    tl_expansion_grow(&n, lo), tl_expansion_grow(&n, hi);
    tl_two_product(-e[i2], f[i1], &hi, &lo);
    tl_expansion_grow(&n, lo), tl_expansion_grow(&n, hi);
    tl_two_product(e[i1], w[i2], &hi, &lo);
    tl_expansion_grow(&m, lo), tl_expansion_grow(&m, hi);
    tl_two_product(-e[i2], w[i1], &hi, &lo);
    tl_expansion_grow(&m, lo), tl_expansion_grow(&m, hi);
    tl_expansion_mul(&n, &m, &term);
    tl_expansion_add(&dot, &term);
  }
  return tl_expansion_sign(&dot);
}

static int tl_edge_side_exact(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p)
{
  int quick = tl_edge_side_short(a, b, c, p);
  if (quick != 2) return quick;
  TlBigExpansion e[3], f[3], w[3], n[3], m[3], dot;
  memset(e, 0, sizeof e), memset(f, 0, sizeof f), memset(w, 0, sizeof w), memset(n, 0, sizeof n);
  memset(m, 0, sizeof m), memset(&dot, 0, sizeof dot);
  const double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z}, pp[3] = {p.x, p.y, p.z};
  int ok = 1, sign = -2;
  for (int i = 0; i < 3 && ok; ++i)
    ok = big_set_diff(&e[i], pb[i], pa[i]) && big_set_diff(&f[i], pc[i], pa[i]) && big_set_diff(&w[i], pp[i], pa[i]);
  for (int i = 0; i < 3 && ok; ++i) {
    int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    ok = big_add_product(&n[i], &e[i1], &f[i2], 1.0) && big_add_product(&n[i], &e[i2], &f[i1], -1.0) &&
         big_add_product(&m[i], &e[i1], &w[i2], 1.0) && big_add_product(&m[i], &e[i2], &w[i1], -1.0);
  }
  for (int i = 0; i < 3 && ok; ++i) ok = big_add_product(&dot, &n[i], &m[i], 1.0);
  if (ok) sign = dot.n == 0 ? 0 : (dot.c[dot.n - 1] > 0.0 ? 1 : -1);
  for (int i = 0; i < 3; ++i) free(e[i].c), free(f[i].c), free(w[i].c), free(n[i].c), free(m[i].c);
  free(dot.c);
  return sign;
}

/* The filter: a cross-product component carries 4u of its permanent (two
 * rounded differences, the product, the difference), each term of the dot
 * product 4u + 4u + 1u of the product of the two permanents, the two sums
 * 2u: 11u; 8 DBL_EPSILON (16u) bounds it with the permanents' rounding. */
int tl_edge_side_filtered(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p, int *exact_stage)
{
  TlVec3 e = tl_v3_sub(b, a), f = tl_v3_sub(c, a), w = tl_v3_sub(p, a);
  double n1 = e.y * f.z, n2 = e.z * f.y, n3 = e.z * f.x, n4 = e.x * f.z, n5 = e.x * f.y, n6 = e.y * f.x;
  double m1 = e.y * w.z, m2 = e.z * w.y, m3 = e.z * w.x, m4 = e.x * w.z, m5 = e.x * w.y, m6 = e.y * w.x;
  double dot = (n1 - n2) * (m1 - m2) + (n3 - n4) * (m3 - m4) + (n5 - n6) * (m5 - m6);
  double permanent = (fabs(n1) + fabs(n2)) * (fabs(m1) + fabs(m2)) + (fabs(n3) + fabs(n4)) * (fabs(m3) + fabs(m4)) +
                     (fabs(n5) + fabs(n6)) * (fabs(m5) + fabs(m6));
  double bound = 8.0 * DBL_EPSILON * permanent;
  if (exact_stage) *exact_stage = 0;
  if (dot > bound) return 1;
  if (dot < -bound) return -1;
  if (permanent == 0.0) return 0;
  if (exact_stage) *exact_stage = 1;
  return tl_edge_side_exact(a, b, c, p);
}

int tl_edge_side(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p)
{
#if TALUS_WITH_CGAL
  /* n_abc . n_abp has the sign of the cosine of the dihedral angle at ab
   * between the half-planes through c and p: CGAL's comparison of that
   * angle with 90 degrees (cosine 0), which needs p off the line ab (there
   * the sign is 0).  c is off it: the triangle is not degenerate. */
  if (tl_collinear3d(a, b, p)) return 0;
  return -tl_dihedral_compare(a, b, c, p, 0.0);
#else
  return tl_edge_side_filtered(a, b, c, p, NULL);
#endif
}

int tl_triangle_region(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p)
{
  /* (-2, a failed allocation of an exact stage, reads as negative) */
  if (tl_dot3_sign(a, b, p) <= 0 && tl_dot3_sign(a, c, p) <= 0) return 4;
  if (tl_dot3_sign(b, a, p) <= 0 && tl_dot3_sign(b, c, p) <= 0) return 5;
  if (tl_edge_side(a, b, c, p) <= 0 && tl_dot3_sign(a, b, p) >= 0 && tl_dot3_sign(b, a, p) >= 0) return 1;
  if (tl_dot3_sign(c, a, p) <= 0 && tl_dot3_sign(c, b, p) <= 0) return 6;
  if (tl_edge_side(c, a, b, p) <= 0 && tl_dot3_sign(a, c, p) >= 0 && tl_dot3_sign(c, a, p) >= 0) return 3;
  if (tl_edge_side(b, c, a, p) <= 0 && tl_dot3_sign(b, c, p) >= 0 && tl_dot3_sign(c, b, p) >= 0) return 2;
  return 0;
}

int tl_predicates_are_exact(void) { return 1; }

int tl_predicates_use_cgal(void) { return TALUS_WITH_CGAL; }

/* The sign of the enclosed volume.  The double sum is taken about the centre
 * of the corners' bounding box (small terms); each term carries at most 16u
 * of its permanent (the orient3d bound above, differences included) and the
 * running sum of n terms (n - 1)u of the sum of their magnitudes, so
 * (16 + 2n) DBL_EPSILON times the sum of the permanents bounds the error
 * with a factor of two to spare.  Within that bound the sum about the origin
 * is taken exactly: each term x0 . (x1 x x2) is six products of three
 * doubles, four components each; for a closed surface it has the same
 * value as the sum about any other point. */
int tl_volume_sign(size_t n_triangles, void (*corners)(const void *ctx, size_t t, TlVec3 c[3]), const void *ctx)
{
  if (n_triangles == 0) return 0;
  TlVec3 lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY}, c[3];
  for (size_t t = 0; t < n_triangles; ++t) {
    corners(ctx, t, c);
    for (int k = 0; k < 3; ++k) {
      lo = tl_v3(fmin(lo.x, c[k].x), fmin(lo.y, c[k].y), fmin(lo.z, c[k].z));
      hi = tl_v3(fmax(hi.x, c[k].x), fmax(hi.y, c[k].y), fmax(hi.z, c[k].z));
    }
  }
  const TlVec3 o = tl_v3(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), 0.5 * (lo.z + hi.z));
  double sum = 0.0, permanent = 0.0;
  for (size_t t = 0; t < n_triangles; ++t) {
    corners(ctx, t, c);
    const TlVec3 a = tl_v3_sub(c[0], o), b = tl_v3_sub(c[1], o), d = tl_v3_sub(c[2], o);
    sum += a.x * (b.y * d.z - b.z * d.y) + a.y * (b.z * d.x - b.x * d.z) + a.z * (b.x * d.y - b.y * d.x);
    permanent += fabs(a.x) * (fabs(b.y * d.z) + fabs(b.z * d.y)) + fabs(a.y) * (fabs(b.z * d.x) + fabs(b.x * d.z)) +
                 fabs(a.z) * (fabs(b.x * d.y) + fabs(b.y * d.x));
  }
  const double bound = (16.0 + 2.0 * (double)n_triangles) * DBL_EPSILON * permanent;
  if (sum > bound) return 1;
  if (sum < -bound) return -1;
  TlBigExpansion v = {0, 0, NULL};
  int ok = 1;
  for (size_t t = 0; t < n_triangles && ok; ++t) {
    corners(ctx, t, c);
    const double x0[3] = {c[0].x, c[0].y, c[0].z}, x1[3] = {c[1].x, c[1].y, c[1].z}, x2[3] = {c[2].x, c[2].y, c[2].z};
    for (int k = 0; k < 3 && ok; ++k) {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      for (int s = 0; s < 2 && ok; ++s) { /* + x0_k x1_k1 x2_k2, - x0_k x1_k2 x2_k1 */
        double p, e, pp, pe, ep, ee;
        tl_two_product(x1[s ? k2 : k1], x2[s ? k1 : k2], &p, &e);
        const double f = s ? -x0[k] : x0[k];
        tl_two_product(f, p, &pp, &pe);
        tl_two_product(f, e, &ep, &ee);
        ok = big_grow(&v, ee) && big_grow(&v, ep) && big_grow(&v, pe) && big_grow(&v, pp);
      }
    }
    if (ok && v.n > 64) big_compress(&v);
  }
  int sign = -2;
  if (ok) {
    big_compress(&v);
    sign = v.n == 0 ? 0 : (v.c[v.n - 1] > 0.0 ? 1 : -1);
  }
  free(v.c);
  return sign;
}
