/* Geometric predicates whose sign must be right: whether a point lies above,
 * on or below a plane through three points.  Used where a wrong sign changes
 * topology (classifying a shared edge of a triangulated wall as flat, convex
 * or concave).
 *
 * The sign is exact on both paths.  With TALUS_WITH_CGAL it comes from
 * CGAL's filtered exact predicates (a small C++ shim).  Without it, a
 * floating-point filter: the determinant in doubles with a forward error
 * bound proportional to its permanent decides every clear case (the
 * overwhelming majority, at the cost of about 30 flops); the few it cannot
 * decide (coplanar or nearly coplanar points) are re-evaluated exactly by
 * expansion arithmetic (error-free sums and products, each value carried as
 * an unevaluated sum of non-overlapping doubles), in the manner of adaptive
 * exact predicates.  Exact for every finite input whose products of three
 * coordinate differences neither overflow nor underflow the double range. */
#ifndef TL_PREDICATES_H
#define TL_PREDICATES_H

#include "tl_math.h"

/* Sign (+1, 0, -1) of det[b - a, c - a, d - a]: +1 when d lies on the side of
 * the plane (a, b, c) that its normal (b - a) x (c - a) points to. */
int tl_orient3d(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d);
/* The library's own filtered predicate (the path without CGAL), always
 * available: *exact_stage (may be NULL) is set to 1 when the filter could not
 * decide and the exact expansion stage ran. */
int tl_orient3d_filtered(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, int *exact_stage);
/* Sign of det[b - a, c - a] in the plane: +1 when (a, b, c) turn
 * counter-clockwise. */
int tl_orient2d(double ax, double ay, double bx, double by, double cx, double cy);
/* 1 when the three points lie exactly on one line (a zero-area triangle). */
int tl_collinear3d(TlVec3 a, TlVec3 b, TlVec3 c);
/* The library's own exact paths of the two (used without CGAL). */
int tl_orient2d_filtered(double ax, double ay, double bx, double by, double cx, double cy);
int tl_collinear3d_filtered(TlVec3 a, TlVec3 b, TlVec3 c);
/* 1: tl_orient3d is exact (both paths are). */
int tl_predicates_are_exact(void);
/* 1 when tl_orient3d goes through CGAL (built with TALUS_WITH_CGAL). */
int tl_predicates_use_cgal(void);

#endif
