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

#include "tl_stl.h"
#include "tl_trisurface.h"
#include "tl_trisurface_contacts.h"
#include "tl_wall.h"

/* A prescribed rigid motion: translation at constant velocity and rotation
 * at constant angular velocity omega (rad/s, its direction the axis, right
 * hand) about the point center, which moves with the translation, during
 * [start, stop); at rest before and after.  With X the vertex positions at
 * start and tau = clamp(t, start, stop) - start,
 *   x(t) = center + velocity tau + R(omega tau) (X - center),
 *   v(t) = velocity + omega x (x(t) - center - velocity tau)   (0 outside [start, stop)).
 * A rotating mixer blade is omega about the blade's shaft; a descending
 * piston is velocity (0, 0, -u) with stop at the end of its stroke. */
typedef struct {
  TlVec3 velocity;  /* m/s */
  TlVec3 omega;     /* rad/s */
  TlVec3 center;    /* m, a point of the rotation axis at start */
  double start, stop; /* s; stop may be INFINITY */
} TlRigidMotion;

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
/* Gives the wall a prescribed rigid motion (see TlRigidMotion): the current
 * vertex positions are those at motion->start; the surface is placed at
 * time t (the world's time, which advance receives) and moves with every
 * step.  Replaces drift.  The vertex velocities (the wall velocity at a
 * contact point, interpolated from them, is then exactly the rigid
 * velocity field there: it is affine) and the positions follow the motion;
 * the geometry of the triangles near particles is refreshed as for any
 * moving surface. */
TlStatus tl_wall_trisurface_set_motion(TlWall *w, const TlRigidMotion *motion, double t);
/* The wall's motion (zero velocities when none was set). */
TlStatus tl_wall_trisurface_get_motion(const TlWall *w, TlRigidMotion *motion);

/* A wall from a surface mesh (tl_stl.h), copied: the mesh must pass
 * tl_surface_mesh_check (degenerate facets and non-manifold edges are
 * refused with the facet or edge named; tl_surface_mesh_repair fixes
 * them). */
TlStatus tl_wall_trisurface_from_mesh(const TlSurfaceMesh *m, TlWall **w);
/* Placement of a surface file in the scene: x <- rotation (scale x) + shift. */
typedef struct {
  double scale;      /* > 0; 1e-3 for a file in millimetres */
  TlMat3 rotation;   /* a rotation */
  TlVec3 shift;      /* m */
  int repair;        /* 1: tl_surface_mesh_repair (orientation kept inward/outward as in the file's majority); 0: refuse defects */
  int require_closed; /* 1: refuse an open surface, naming a boundary edge */
} TlWallPlacement;
/* Defaults: scale 1, no rotation, no shift, repair on, open surfaces allowed. */
void tl_wall_placement_default(TlWallPlacement *p);
/* Reads an STL or Gmsh surface file (tl_surface_mesh_read), repairs or
 * checks it, places it and wraps it as a wall; report (may be NULL)
 * receives what repair did. */
TlStatus tl_wall_trisurface_from_file(const char *path, const TlWallPlacement *placement, TlWall **w,
                                      TlSurfaceReport *report);

/* Registers the type "trisurface" (parameters corrections, brute_force,
 * drift: switches 0 or 1, feature_angle in degrees, as the setters above;
 * and the rigid motion velocity_x/y/z, omega_x/y/z, center_x/y/z,
 * motion_start, motion_stop, applied when the surface is given). */
TlStatus tl_wall_register_trisurface(void);

#endif
