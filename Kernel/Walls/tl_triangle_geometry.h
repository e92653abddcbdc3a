/* Geometry of one triangle against one sphere: the closest point, which
 * feature of the triangle it lies on (face, one of three edges, one of three
 * vertices), its barycentric coordinates, and the contact (point, unit normal
 * from wall to sphere centre, overlap).  One contact per triangle: a triangle
 * is convex, so the closest point is unique.
 *
 * Local numbering: vertex k is (a, b, c)[k]; edge k joins vertex k and
 * vertex (k+1) mod 3, so edge 0 = ab, edge 1 = bc, edge 2 = ca.
 *
 * Header-only and inline: this sits in the wall-contact loop. */
#ifndef TL_TRIANGLE_GEOMETRY_H
#define TL_TRIANGLE_GEOMETRY_H

#include <float.h>
#include <math.h>
#include "tl_math.h"
#include "tl_predicates.h"

typedef enum {
  TL_TRI_FACE = 0,
  TL_TRI_EDGE0 = 1, /* a-b */
  TL_TRI_EDGE1 = 2, /* b-c */
  TL_TRI_EDGE2 = 3, /* c-a */
  TL_TRI_VERTEX0 = 4,
  TL_TRI_VERTEX1 = 5,
  TL_TRI_VERTEX2 = 6
} TlTriFeature;

static inline int tl_tri_feature_is_edge(int f) { return f >= TL_TRI_EDGE0 && f <= TL_TRI_EDGE2; }
static inline int tl_tri_feature_is_vertex(int f) { return f >= TL_TRI_VERTEX0; }

/* Whether a point on feature f lies on local edge k (the edge itself or one
 * of its two end vertices). */
static inline int tl_tri_feature_on_edge(int f, int k)
{
  if (tl_tri_feature_is_edge(f)) return f - TL_TRI_EDGE0 == k;
  if (tl_tri_feature_is_vertex(f)) {
    int v = f - TL_TRI_VERTEX0;
    return v == k || v == (k + 1) % 3;
  }
  return 0;
}

#define TL_TRI_MAX(x, y) ((x) > (y) ? (x) : (y))
#define TL_TRI_AMAX(v) TL_TRI_MAX(fabs((v).x), TL_TRI_MAX(fabs((v).y), fabs((v).z)))
#if defined(__GNUC__)
#define TL_TRI_INLINE static inline __attribute__((always_inline))
#else
#define TL_TRI_INLINE static inline
#endif

/* The closest point of feature f of triangle (a, b, c) to p and its
 * barycentric coordinates, the feature being known (the exact path). */
static inline void tl_triangle_point_of_feature(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p, int f, TlVec3 *q,
                                                double bary[3])
{
  const TlVec3 v[3] = {a, b, c};
  bary[0] = bary[1] = bary[2] = 0.0;
  if (tl_tri_feature_is_vertex(f)) {
    bary[f - TL_TRI_VERTEX0] = 1.0;
    *q = v[f - TL_TRI_VERTEX0];
  } else if (tl_tri_feature_is_edge(f)) {
    int k = f - TL_TRI_EDGE0, k1 = (k + 1) % 3;
    TlVec3 e = tl_v3_sub(v[k1], v[k]);
    double t = tl_v3_dot(e, tl_v3_sub(p, v[k])) / tl_v3_norm2(e);
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    bary[k] = 1.0 - t, bary[k1] = t;
    *q = tl_v3_axpy(v[k], t, e);
  } else {
    TlVec3 ab = tl_v3_sub(b, a), ac = tl_v3_sub(c, a), n = tl_v3_cross(ab, ac), ap = tl_v3_sub(p, a);
    double s = 1.0 / tl_v3_norm2(n);
    double w1 = tl_v3_dot(n, tl_v3_cross(ap, ac)) * s, w2 = tl_v3_dot(n, tl_v3_cross(ab, ap)) * s;
    bary[0] = 1.0 - w1 - w2, bary[1] = w1, bary[2] = w2;
    *q = tl_v3_add(a, tl_v3_add(tl_v3_scale(ab, w1), tl_v3_scale(ac, w2)));
  }
}

/* Closest point q of triangle (a, b, c) to p, with its barycentric
 * coordinates (q = l0 a + l1 b + l2 c) and the feature it lies on.  Voronoi
 * regions tested in turn (vertex, edge, face), so that no point falls
 * between regions; a point on the boundary of a vertex and an edge region
 * goes to the vertex, of an edge and the face to the edge.
 *
 * Every region decision is an exact sign (tl_triangle_region in
 * tl_predicates.h): the vertex regions are bounded by the signs of
 * (u - v) . (p - v), the same polynomial from either triangle of an edge,
 * the edge regions by the side of the plane through the edge perpendicular
 * to the triangle.  The dot products d1..d6 and their 2 x 2 combinations
 * va, vb, vc are those polynomials in doubles; with one error bound for all
 * of them (below) the filter decides every clear case from the values the
 * point needs anyway; for a point within round-off of a region boundary
 * it returns -1 and the exact classification decides.  Valid for any
 * triangle with edges of non-zero length; callers refuse degenerate
 * triangles beforehand (tl_triangle_quality). */
TL_TRI_INLINE int tl_triangle_closest_point_filtered(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p, TlVec3 *q,
                                                     double bary[3])
{
  TlVec3 ab = tl_v3_sub(b, a), ac = tl_v3_sub(c, a), ap = tl_v3_sub(p, a);
  /* Round-off bounds.  Every d is a dot product of two rounded differences
   * with |d| <= D = 3 L (P + L) (L the largest component of ab and ac, P of
   * ap; bp = ap - ab and cp = ap - ac are no longer than P + L); its error
   * is at most 5u D (u = DBL_EPSILON / 2), that of a difference of two d's
   * 12u D, that of a 2 x 2 combination (va, vb, vc) 24u D^2.  The bounds
   * below double these (and cover the rounding of D itself).  A test is
   * true (T) or false (F) for certain when every value it reads is beyond
   * its bound on the side that decides it; otherwise it is undecided. */
  double L = TL_TRI_MAX(TL_TRI_AMAX(ab), TL_TRI_AMAX(ac));
  double D = 3.0 * L * (TL_TRI_AMAX(ap) + L);
  double ed = 5.0 * DBL_EPSILON * D, edd = 12.0 * DBL_EPSILON * D, ev = 24.0 * DBL_EPSILON * D * D;
  double d1 = tl_v3_dot(ab, ap), d2 = tl_v3_dot(ac, ap);
  /* vertex a: (b - a).(p - a) <= 0 and (c - a).(p - a) <= 0 */
  if (d1 < -ed && d2 < -ed) {
    bary[0] = 1.0, bary[1] = 0.0, bary[2] = 0.0;
    *q = a;
    return TL_TRI_VERTEX0;
  }
  if (!(d1 > ed || d2 > ed)) return -1;
  TlVec3 bp = tl_v3_sub(p, b);
  double d3 = tl_v3_dot(ab, bp), d4 = tl_v3_dot(ac, bp), e43 = d4 - d3;
  /* vertex b: (a - b).(p - b) = -d3 <= 0 and (c - b).(p - b) = d4 - d3 <= 0 */
  if (d3 > ed && e43 < -edd) {
    bary[0] = 0.0, bary[1] = 1.0, bary[2] = 0.0;
    *q = b;
    return TL_TRI_VERTEX1;
  }
  if (!(d3 < -ed || e43 > edd)) return -1;
  /* edge ab: beyond its perpendicular plane (vc <= 0), between those of a
   * and b */
  double vc = d1 * d4 - d3 * d2;
  if (vc < -ev && d1 > ed && d3 < -ed) {
    double t = d1 / (d1 - d3);
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t); /* the decision was exact, the division is not */
    bary[0] = 1.0 - t, bary[1] = t, bary[2] = 0.0;
    *q = tl_v3_axpy(a, t, ab);
    return TL_TRI_EDGE0;
  }
  if (!(vc > ev || d1 < -ed || d3 > ed)) return -1;
  TlVec3 cp = tl_v3_sub(p, c);
  double d5 = tl_v3_dot(ab, cp), d6 = tl_v3_dot(ac, cp), e56 = d5 - d6;
  /* vertex c: (a - c).(p - c) = -d6 <= 0 and (b - c).(p - c) = d5 - d6 <= 0 */
  if (d6 > ed && e56 < -edd) {
    bary[0] = 0.0, bary[1] = 0.0, bary[2] = 1.0;
    *q = c;
    return TL_TRI_VERTEX2;
  }
  if (!(d6 < -ed || e56 > edd)) return -1;
  double vb = d5 * d2 - d1 * d6;
  if (vb < -ev && d2 > ed && d6 < -ed) {
    double t = d2 / (d2 - d6);
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    bary[0] = 1.0 - t, bary[1] = 0.0, bary[2] = t;
    *q = tl_v3_axpy(a, t, ac);
    return TL_TRI_EDGE2;
  }
  if (!(vb > ev || d2 < -ed || d6 > ed)) return -1;
  double va = d3 * d6 - d5 * d4;
  if (va < -ev && e43 > edd && e56 > edd) {
    double t = e43 / (e43 + e56);
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    bary[0] = 0.0, bary[1] = 1.0 - t, bary[2] = t;
    *q = tl_v3_axpy(b, t, tl_v3_sub(c, b));
    return TL_TRI_EDGE1;
  }
  if (!(va > ev || e43 < -edd || e56 < -edd)) return -1;
  {
    double s = 1.0 / (va + vb + vc);
    double v = vb * s, w = vc * s;
    bary[0] = 1.0 - v - w, bary[1] = v, bary[2] = w;
    *q = tl_v3_add(a, tl_v3_add(tl_v3_scale(ab, v), tl_v3_scale(ac, w)));
    return TL_TRI_FACE;
  }
}

/* The closest point, its feature and barycentric coordinates: the filter
 * above, else (-1: a point within round-off of a region boundary) the exact
 * classification, the point then computed for the feature it names. */
TL_TRI_INLINE TlTriFeature tl_triangle_closest_point(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p, TlVec3 *q, double bary[3])
{
  int f = tl_triangle_closest_point_filtered(a, b, c, p, q, bary);
  if (f >= 0) return (TlTriFeature)f;
  f = tl_triangle_region(a, b, c, p);
  tl_triangle_point_of_feature(a, b, c, p, f, q, bary);
  return (TlTriFeature)f;
}

/* Shape quality 4 sqrt(3) area / (sum of squared edge lengths): 1 for an
 * equilateral triangle, tending to 0 for zero-area slivers and needles alike.
 * Scale-free, so one tolerance serves every mesh size. */
static inline double tl_triangle_quality(TlVec3 a, TlVec3 b, TlVec3 c)
{
  TlVec3 ab = tl_v3_sub(b, a), bc = tl_v3_sub(c, b), ca = tl_v3_sub(a, c);
  double l2 = tl_v3_norm2(ab) + tl_v3_norm2(bc) + tl_v3_norm2(ca);
  if (!(l2 > 0.0)) return 0.0;
  double area = 0.5 * tl_v3_norm(tl_v3_cross(ab, tl_v3_sub(c, a)));
  return 4.0 * sqrt(3.0) * area / l2;
}

/* Contact of a sphere with a triangle. */
typedef struct {
  TlVec3 point;    /* closest point of the triangle to the centre */
  TlVec3 normal;   /* unit, from the wall towards the sphere centre */
  double overlap;  /* radius minus distance; positive in contact */
  double bary[3];  /* barycentric coordinates of point */
  int feature;     /* TlTriFeature */
} TlTriContact;

/* Fills *c and returns 1 when the sphere (centre x, radius r) overlaps the
 * triangle (a, b, c) with unit face normal n; returns 0 otherwise.  A centre
 * lying on the triangle itself takes the face normal on its side (on the
 * plane itself, n), so the normal is never NaN. */
static inline int tl_triangle_sphere_contact(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 n, TlVec3 x,
                                             double r, TlTriContact *con)
{
  TlVec3 q;
  double bary[3];
  int f = (int)tl_triangle_closest_point(a, b, c, x, &q, bary);
  TlVec3 d = tl_v3_sub(x, q);
  double dist2 = tl_v3_norm2(d);
  if (dist2 >= r * r) return 0;
  double dist = sqrt(dist2);
  con->point = q;
  con->overlap = r - dist;
  con->bary[0] = bary[0], con->bary[1] = bary[1], con->bary[2] = bary[2];
  con->feature = f;
  if (dist > 1e-12 * r) {
    con->normal = tl_v3_scale(d, 1.0 / dist);
  } else {
    /* the side of the face the centre is on, exactly (n's sense against
     * the corner order is no close call: |n . (ab x ac)| is twice the area) */
    int side = tl_orient3d(a, b, c, x);
    if (tl_v3_dot(n, tl_v3_cross(tl_v3_sub(b, a), tl_v3_sub(c, a))) < 0.0) side = -side;
    con->normal = side < 0 ? tl_v3_neg(n) : n;
  }
  return 1;
}

#endif
