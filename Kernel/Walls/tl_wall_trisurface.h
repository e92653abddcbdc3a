/* Triangle walls and triangulated surfaces as walls of the DEM world.
 *
 * A triangulated surface wall owns a TlTriSurface.  Detection follows
 * seeds/001 Algorithm 2 with a Verlet skin: the triangles near some particle
 * (tl_trisurface_bins.h) send their bounding boxes to the hierarchical grid
 * (tl_hgrid_query_box), and every (triangle, particle) pair closer than
 * radius + skin is listed; the list is reused until a particle has moved
 * more than skin/2, the particles were renumbered, or the surface moved.
 * Each step the listed pairs are tested exactly: one contact per touching
 * triangle (face, edge or vertex); then the triangle-edge corrections of
 * Algorithm 1 (tl_trisurface_contacts.h), and the contact law in one batch
 * per thread.  The cost per step is O(particles + pairs), whatever the size
 * of the surface.  A single triangle is the surface of one triangle.
 *
 * Coupling (seeds/001 §5.3.1): the owner of the surface writes vertex
 * positions and velocities before a step,
 *
 *   TlTriSurface *s = tl_wall_trisurface_surface(w);
 *   tl_trisurface_set_vertices(s, x, v);      // updates normals, boxes, edges
 *
 * and after the step reads the contacts kept in it,
 *
 *   const TlTriContactSet *c = tl_wall_trisurface_contacts(w);
 *   for k < c->count: c->c[k].triangle, .point, .bary, .force (on the
 *   particle; the surface receives -force at .point)
 *
 * to spread the forces over the finite-element nodes.  The velocity of the
 * wall at a contact point is interpolated from the vertex velocities.
 *
 * Surfaces are two-sided: a particle may touch either side; edge shapes are
 * read from the particle's side.  As for the plane, only free particles
 * touch the wall (fixed and prescribed ones are held anyway). */
#ifndef TL_WALL_TRISURFACE_H
#define TL_WALL_TRISURFACE_H

#include "tl_trisurface.h"
#include "tl_trisurface_contacts.h"
#include "tl_wall.h"

/* Wraps a surface (the wall takes ownership, also on failure): the wall
 * type "trisurface" by name with its defaults, given the surface, whose own
 * feature angle is kept. */
TlStatus tl_wall_trisurface_create(TlTriSurface *surface, TlWall **w);
/* A single triangle (a, b, c); refused if degenerate. */
TlStatus tl_wall_triangle_create(TlVec3 a, TlVec3 b, TlVec3 c, TlWall **w);
/* The surface, for the owner to move. */
TlTriSurface *tl_wall_trisurface_surface(TlWall *w);
/* Contacts kept at the last interact (after the corrections). */
const TlTriContactSet *tl_wall_trisurface_contacts(const TlWall *w);
/* Algorithm 1's modifications on (default) or off (the naive sum of every
 * triangle's force, for comparison). */
TlStatus tl_wall_trisurface_set_corrections(TlWall *w, int on);
/* Detection by the grid (default) or by testing every particle against
 * every triangle (test oracle). */
TlStatus tl_wall_trisurface_set_brute_force(TlWall *w, int on);
/* Feature angle of the surface, degrees in [0, 180] (tl_trisurface.h:
 * concave folds sharper than it separate faces whose contacts add). */
TlStatus tl_wall_trisurface_set_feature_angle(TlWall *w, double degrees);
/* When on, advance moves every vertex by dt times its velocity (a surface
 * moving on its own); off (default) when the owner sets the vertices. */
TlStatus tl_wall_trisurface_set_drift(TlWall *w, int on);
/* Gives a wall created by name ("trisurface", tl_wall_create) its surface,
 * once; the wall takes ownership, also on failure. */
TlStatus tl_wall_trisurface_set_surface(TlWall *w, TlTriSurface *surface);
/* Registers the type "trisurface" (parameters corrections, brute_force,
 * drift: switches 0 or 1, and feature_angle in degrees, as the setters
 * above). */
TlStatus tl_wall_register_trisurface(void);

#endif
