/* A closed triangulated surface meshed into a tetrahedral solid.
 *
 * The surface is given as arrays (vertex coordinates, triangles as vertex
 * index triples), as a generator or a surface reader produces them.  It is
 * checked first, in C and with a message naming what is wrong:
 *   - every index in range, no triangle with a repeated vertex or zero area;
 *   - closed and manifold: every edge shared by exactly two triangles that
 *     traverse it in opposite directions (an open edge, a non-manifold edge
 *     or an inconsistently oriented pair is named by its two vertices and
 *     the triangles using it);
 *   - a positive enclosed volume (outward orientation; a surface given
 *     inside out is refused, not flipped, so a caller's normals keep their
 *     meaning);
 *   - not self-intersecting (two triangles that meet other than in a shared
 *     vertex or edge are named; through CGAL).
 * Then CGAL's Mesh_3 meshes the enclosed volume with a polyhedral domain
 * whose sharp edges (dihedral angle beyond feature_angle from flat) are
 * protected, so the apex and rim of a cone or the edges of a box are kept:
 * Delaunay refinement to the size and quality criteria below, then
 * sliver exudation.  CGAL's random choices are seeded from `seed`, so a
 * given surface and options give the same mesh on every run.
 *
 * The result is a TlMesh (dim 3) of one block "body" of Tet4 or Tet10
 * elements (Tet10 midside nodes at the edge midpoints: the mesh is the
 * piecewise-flat one of Tet4, exact for the patch test), finalized, with
 * the face set and node set "surface" holding every boundary face (the
 * mesh's surface triangles: what tl_scoupling_create_boundary couples).
 *
 * Without CGAL (-DTALUS_WITH_CGAL=OFF) the checks run and meshing returns
 * TL_ERR_UNSUPPORTED. */
#ifndef TL_MESH_FROM_SURFACE_H
#define TL_MESH_FROM_SURFACE_H

#include <stddef.h>
#include "tl_error.h"
#include "tl_mesh.h"
#include "tl_stl.h"

typedef struct {
  size_t n_vertices;
  const double *x;      /* 3 * n_vertices coordinates (m) */
  size_t n_triangles;
  const size_t *tri;    /* 3 * n_triangles vertex indices, counter-clockwise seen from outside */
} TlSurfaceArrays;

typedef struct {
  const TlElementType *type; /* tl_element_tet4 or tl_element_tet10 [tet4] */
  double cell_size;      /* largest circumradius of a tetrahedron (m) [required, > 0] */
  double facet_size;     /* largest circumradius of a surface triangle (m) [0: cell_size] */
  double facet_distance; /* largest distance of a surface triangle's circumcentre from the
                            input surface (m) [0: facet_size / 10] */
  double facet_angle;    /* smallest angle of a surface triangle (degrees, at most 30) [25] */
  double radius_edge;    /* largest circumradius over shortest edge of a tetrahedron (>= 2 for
                            guaranteed termination of refinement) [3] */
  double edge_size;      /* largest length of a protected sharp-edge segment (m) [0: facet_size] */
  double feature_angle;  /* dihedral angle from flat beyond which an edge is sharp (degrees) [60] */
  int exude;             /* sliver exudation after refinement [1] */
  unsigned seed;         /* seed of the mesher's random choices [0] */
} TlMeshFromSurfaceOptions;

typedef struct {
  double surface_volume; /* volume the input surface encloses (m^3) */
  double surface_area;   /* its area (m^2) */
  double mesh_volume;    /* volume of the tetrahedra (m^3) */
  size_t n_tetrahedra, n_nodes, n_boundary_faces;
  double min_dihedral, max_dihedral; /* over all tetrahedra (degrees) */
  double min_volume;     /* smallest tetrahedron volume (m^3) */
} TlMeshFromSurfaceInfo;

void tl_mesh_from_surface_options_default(TlMeshFromSurfaceOptions *o);

/* The checks above; *volume and *area (either may be NULL) receive the
 * enclosed volume and the area. */
TlStatus tl_surface_check(const TlSurfaceArrays *s, double *volume, double *area);

/* Meshes the volume enclosed by s.  info may be NULL. */
TlStatus tl_mesh_from_surface(const TlSurfaceArrays *s, const TlMeshFromSurfaceOptions *o,
                              TlMesh **mesh, TlMeshFromSurfaceInfo *info);

/* The same from a surface read from a file (tl_stl.h: STL or Gmsh; repair
 * it first when the file may have defects: tl_surface_mesh_repair). */
TlStatus tl_mesh_from_surface_mesh(const TlSurfaceMesh *surface, const TlMeshFromSurfaceOptions *o,
                                   TlMesh **mesh, TlMeshFromSurfaceInfo *info);

/* Adds the face set `name` (and a node set of the same name) of the
 * boundary faces lying in the plane through `point` with normal `normal`:
 * every node within tol of the plane and the face's outward normal within
 * 1e-6 rad of `normal` (the base of a cone, the top of a box).  Refuses an
 * empty set. */
TlStatus tl_mesh_add_face_set_on_plane(TlMesh *mesh, const char *name, const double point[3],
                                       const double normal[3], double tol);

/* Closed test surfaces (outward, counter-clockwise), allocated here and
 * freed with tl_surface_arrays_free: a sphere of radius r about c, an
 * icosahedron subdivided `level` times (20 * 4^level triangles, vertices
 * on the sphere); a cone with its apex at `apex`, axis +z, base of radius r
 * at height h above the apex, n segments round the rim (2 n triangles), or
 * with r_tip > 0 a truncated cone whose flat tip of radius r_tip lies at
 * the apex height (4 n triangles); a box [lo, hi] with n divisions per edge
 * (12 n^2 triangles). */
TlStatus tl_surface_sphere(const double c[3], double r, int level, TlSurfaceArrays *s);
TlStatus tl_surface_cone(const double apex[3], double r, double h, double r_tip, int n, TlSurfaceArrays *s);
TlStatus tl_surface_box(const double lo[3], const double hi[3], int n, TlSurfaceArrays *s);
void tl_surface_arrays_free(TlSurfaceArrays *s);

#endif
