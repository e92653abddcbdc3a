/* Geometric predicates whose sign must be right: whether a point lies above,
 * on or below a plane through three points (orient3d), on which side of a
 * line in the plane (orient2d), whether three points are collinear (a
 * zero-area triangle), inside or outside a sphere through four (insphere),
 * and whether a dihedral angle exceeds a given one.  Used wherever the
 * library takes a discrete decision from geometry: the flat, convex or
 * concave shape of a shared edge of a triangulated wall and whether its fold
 * exceeds the feature angle (tl_trisurface.c), zero-area facets
 * (tl_surface_mesh_check), a point inside a closed surface
 * (tl_surface_mesh_contains, for particle insertion), the face, edge or
 * vertex a sphere touches on a triangle (tl_triangle_closest_point), the
 * side of a face a centre on it lies on, the corner order of a meshed
 * tetrahedron (tl_mesh_from_surface).
 *
 * Every sign is exact on both paths.  With TALUS_WITH_CGAL it comes from
 * CGAL's filtered exact predicates (a small C++ shim).  Without it, a
 * floating-point filter: the determinant in doubles with a forward error
 * bound proportional to its permanent decides every clear case (the
 * overwhelming majority, at the cost of about 30 flops); the few it cannot
 * decide (coplanar or nearly coplanar points) are re-evaluated exactly by
 * expansion arithmetic (error-free sums and products, each value carried as
 * an unevaluated sum of non-overlapping doubles), in the manner of adaptive
 * exact predicates.  Exact for every finite input whose products of three
 * coordinate differences neither overflow nor underflow the double range
 * (for insphere and the dihedral comparison, products of five and eight).
 * The exact stages of insphere and of the dihedral comparison keep their
 * longer expansions on the heap.  The path without CGAL stays as the
 * fallback of builds without it (-DTALUS_WITH_CGAL=OFF) and as the
 * independent check of the CGAL path in the tests. */
#ifndef TL_PREDICATES_H
#define TL_PREDICATES_H

#include <stddef.h>
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
/* In-sphere: +1 when e lies inside the sphere through a, b, c, d, -1
 * outside, 0 on it, for a positively oriented tetrahedron
 * (tl_orient3d(a, b, c, d) = +1); the sign flips with the orientation. */
int tl_insphere(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, TlVec3 e);
/* The library's own exact path (filter, then expansions on the heap: the
 * one predicate whose exact stage allocates; -2 if that allocation fails). */
int tl_insphere_filtered(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, TlVec3 e, int *exact_stage);
/* The dihedral angle at edge (a, b) between the half-planes (a, b, c) and
 * (a, b, d), in [0, 180] degrees, against the angle whose cosine is
 * `cosine` (in [-1, 1]): -1 smaller, 0 equal, +1 larger.  Exact for the
 * given double cosine: decides whether a fold exceeds a feature angle.
 * Degenerate half-planes (c or d on the line ab) are the caller's to avoid. */
int tl_dihedral_compare(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, double cosine);
int tl_dihedral_compare_filtered(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 d, double cosine, int *exact_stage);
/* The library's own exact paths of the two (used without CGAL). */
int tl_orient2d_filtered(double ax, double ay, double bx, double by, double cx, double cy);
int tl_collinear3d_filtered(TlVec3 a, TlVec3 b, TlVec3 c);
/* The two signs that decide which part of a triangle (face, edge, vertex)
 * is closest to a point (tl_triangle_closest_point):
 *
 * tl_dot3_sign: sign of (u - v) . (p - v), degree 2: +1 when p lies on u's
 * side of the plane through v perpendicular to the segment vu, 0 on it.
 * The vertex regions of a triangle are bounded by these planes; the same
 * call from both triangles of an edge gives the same answer.
 *
 * tl_edge_side: sign of ((b - a) x (c - a)) . ((b - a) x (p - a)), degree 4:
 * +1 when p lies on c's side of the plane through the edge ab perpendicular
 * to the triangle (a, b, c), 0 on it.  The edge regions are bounded by
 * these planes.
 *
 * With CGAL both are CGAL's filtered exact predicates (CGAL::angle; the
 * comparison of the dihedral angle at ab between the half-planes through c
 * and p with 90 degrees); without it, a floating-point filter and
 * expansion arithmetic.  The floating-point filters of the contact loop are
 * inline in tl_triangle_geometry.h and call these only for the inputs they
 * cannot decide. */
int tl_dot3_sign(TlVec3 v, TlVec3 u, TlVec3 p);
int tl_edge_side(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p);
/* The part of triangle (a, b, c) closest to p, exactly, from the two signs
 * above: 0 the face, 1 + k edge k (vertex k to vertex k + 1 mod 3), 4 + k
 * vertex k (TlTriFeature of tl_triangle_geometry.h).  Regions tested in
 * the order vertex a, vertex b, edge ab, vertex c, edge ca, edge bc, face;
 * a point on a boundary takes the first.  The contact loop's filter calls
 * this only for points within round-off of a boundary. */
int tl_triangle_region(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p);
/* The library's own paths (filter, then expansions): always available, the
 * fallback without CGAL and the independent check of the CGAL path.  The
 * exact stage of tl_edge_side_filtered keeps its expansions on the heap;
 * -2 if that allocation fails. */
int tl_dot3_sign_filtered(TlVec3 v, TlVec3 u, TlVec3 p, int *exact_stage);
int tl_edge_side_filtered(TlVec3 a, TlVec3 b, TlVec3 c, TlVec3 p, int *exact_stage);
/* Exact sign of the sum over the triangles of det(c0, c1, c2), six times the
 * volume a closed, consistently oriented surface encloses: 1 when its
 * triangles turn counter-clockwise seen from outside (normals out), -1 inside
 * out, 0 for zero volume; -2 if memory ran out.  corners(ctx, t, c) gives
 * triangle t's corners.  A floating-point filter decides unless the sum lies
 * within its round-off bound; then expansions.  (The coordinates' products
 * must neither overflow nor underflow.) */
int tl_volume_sign(size_t n_triangles, void (*corners)(const void *ctx, size_t t, TlVec3 c[3]), const void *ctx);
/* 1: tl_orient3d is exact (both paths are). */
int tl_predicates_are_exact(void);
/* 1 when tl_orient3d goes through CGAL (built with TALUS_WITH_CGAL). */
int tl_predicates_use_cgal(void);

#endif
