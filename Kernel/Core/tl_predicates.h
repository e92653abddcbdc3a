/* Geometric predicates whose sign must be right: whether a point lies above,
 * on or below a plane through three points.  Used where a wrong sign changes
 * topology (classifying a shared edge of a triangulated wall as flat, convex
 * or concave).  With TALUS_WITH_CGAL the sign is exact (CGAL's filtered exact
 * predicates, through a small C++ shim); without it a floating-point filter
 * decides the clear cases and ambiguous ones are re-evaluated in quadruple
 * precision (113-bit significand), exact unless the inputs differ in magnitude
 * by more than about 2^60. */
#ifndef TL_PREDICATES_H
#define TL_PREDICATES_H

#include "tl_math.h"

/* Sign (+1, 0, -1) of det[b - a, c - a, d - a]: +1 when d lies on the side of
 * the plane (a, b, c) that its normal (b - a) x (c - a) points to. */
int tl_orient3d(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d);
/* 1 when tl_orient3d is exact (built with CGAL), 0 otherwise. */
int tl_predicates_are_exact(void);

#endif
