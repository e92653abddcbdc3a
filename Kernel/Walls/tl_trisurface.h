/* A triangulated surface: triangles sharing vertices, with the topology
 * (edges, neighbours across each edge) built once and the geometry (normals,
 * bounding boxes, the shape of every shared edge) recomputed whenever the
 * owner moves the vertices.
 *
 * Moving surfaces.  A coupling (seeds/001 §5.3.1) interpolates positions and
 * velocities of the vertices from finite-element nodes every DEM step:
 *
 *   tl_trisurface_set_vertices(s, x, v);   // or write s->x[i], s->v[i] directly
 *   tl_trisurface_update(s);               // normals, boxes, edge shapes
 *
 * The velocity of the wall at a contact point is interpolated from the vertex
 * velocities with the point's barycentric coordinates.
 *
 * Orientation.  Triangles are listed counter-clockwise seen from the + side
 * (their normal (b - a) x (c - a) points to it); triangles sharing an edge
 * must traverse it in opposite directions.  Edge shapes are stored as seen
 * from the + side; a particle on the - side of a two-sided surface sees them
 * inverted (tl_trisurface_edge_shape_seen_from).  The shape is decided by the
 * sign of an exact orientation predicate (tl_predicates.h) and the flat
 * tolerance; a folded edge is also sharp (edge_sharp) when its fold exceeds
 * the feature angle (the exact comparison of its dihedral angle with the
 * feature's, tl_dihedral_compare; the side of a face a particle is on is
 * also the exact predicate's).  Shapes and sharpness are refreshed with the rest of the
 * geometry by every update, of the whole surface or of the triangles a moving
 * surface's contacts touch (a fold may cross the feature angle as the
 * surface deforms; the predicate's floating-point filter keeps the refresh
 * as cheap as the fold itself).  Degenerate triangles
 * (zero-area slivers, exactly collinear corners whatever the tolerance, or
 * needles, quality below quality_tolerance) are refused
 * at creation and at every update, with the triangle and its quality named:
 * their normal is undefined. */
#ifndef TL_TRISURFACE_H
#define TL_TRISURFACE_H

#include <stddef.h>
#include <stdint.h>
#include "tl_domain.h"
#include "tl_error.h"
#include "tl_math.h"
#include "tl_triangle_geometry.h"

typedef enum {
  TL_EDGE_BOUNDARY = 0, /* one triangle only */
  TL_EDGE_FLAT = 1,
  TL_EDGE_CONVEX = 2,   /* a ridge seen from the + side */
  TL_EDGE_CONCAVE = 3   /* a valley seen from the + side */
} TlEdgeShape;

typedef struct {
  size_t n_vertices, n_triangles, n_edges;
  /* Vertex state, owned and written by the caller, read by update and by
   * the contact computation. */
  TlVec3 *x; /* positions */
  TlVec3 *v; /* velocities (zero unless set) */
  /* Topology, fixed at creation. */
  int *tri;         /* 3 vertex indices per triangle */
  int *edge_vertex; /* 2 per edge */
  int *edge_tri;    /* 2 per edge: the triangles on either side, -1 for none */
  int *tri_edge;    /* 3 per triangle: edge id of local edge k (vertex k to k+1) */
  int *tri_nbr;     /* 3 per triangle: neighbour across local edge k, or -1 */
  /* Geometry, recomputed by tl_trisurface_update. */
  TlVec3 *normal;         /* unit normal per triangle */
  double *area;           /* per triangle */
  TlVec3 *box_lo, *box_hi; /* axis-aligned bounding box per triangle */
  TlVec3 surface_lo, surface_hi; /* box of the whole surface */
  signed char *edge_shape; /* TlEdgeShape per edge, seen from the + side */
  double *edge_fold;       /* sine of the fold angle: > 0 concave, < 0 convex */
  unsigned char *edge_sharp; /* 1: folded by more than the feature angle (a corner of the design, not of the mesh) */
  /* Edges joined across a periodic face (tl_trisurface_link_periodic): the
   * vertex of the second triangle that is the image of edge_vertex[2e]
   * (-1 for ordinary edges), and the lattice translation from the first
   * triangle's frame to the second's, recomputed by update. */
  int *edge_twin;
  TlVec3 *edge_shift;
  unsigned long version;    /* incremented by every update and every move */
  int geometry_stale;       /* moved by tl_trisurface_move_vertices since the last full update */
  /* Classification tolerances. */
  double flat_tolerance;    /* |fold sine| below it counts as flat (default 1e-9) */
  double quality_tolerance; /* tl_triangle_quality below it is refused (default 1e-6) */
  /* Feature angle, degrees (default TL_TRISURFACE_FEATURE_ANGLE), and its
   * cosine: an edge whose faces' normals differ by more is sharp. */
  double feature_angle, feature_cos;
} TlTriSurface;

/* Default feature angle, degrees.  The triangle-edge corrections average the
 * contacts of a particle across a concave fold (seeds/001 §5.1.1,
 * Modification 2), which is right where the triangles discretise one smooth
 * surface and wrong where two different faces meet (a box, a hopper, a
 * blade), whose contacts add.  Mesh-processing codes separate the two by a
 * feature angle between 20 and 45 degrees.  35 sits between the round angles
 * of designs (30, 45, 60, 90) so that no common geometry lies on the
 * threshold, where round-off would decide: a cylinder of 12 or more
 * segments (folds of 30 degrees or less) and a deformed finite-element
 * surface (folds of a few degrees) stay smooth; an octagonal drum (45), a
 * box (90) and the corners of hoppers and mixers of 45 degrees or more are
 * faces.  A hopper whose transition folds by 30 degrees or less needs a
 * smaller angle (the wall parameter feature_angle). */
#define TL_TRISURFACE_FEATURE_ANGLE 35.0

/* Builds a surface from n_vertices positions (x: 3 doubles each) and
 * n_triangles vertex triples, checks the topology (indices in range, no
 * repeated vertex in a triangle, every edge shared by at most two triangles
 * with consistent orientation) and computes the geometry. */
TlStatus tl_trisurface_create(size_t n_vertices, const double *x, size_t n_triangles,
                              const int *tri, TlTriSurface **surface);
void tl_trisurface_destroy(TlTriSurface **surface);

/* Copies new vertex positions and, if v is not NULL, velocities (3 doubles
 * per vertex), then calls tl_trisurface_update. */
TlStatus tl_trisurface_set_vertices(TlTriSurface *s, const double *x, const double *v);
/* Recomputes normals, areas, bounding boxes and edge shapes from s->x.
 * Refuses non-finite positions and degenerate triangles. */
TlStatus tl_trisurface_update(TlTriSurface *s);
/* Moving surfaces whose contacts touch a few triangles (a coupled solid):
 * copies positions and velocities (v may be NULL) and refreshes only the
 * surface's box, leaving the per-triangle geometry stale (geometry_stale
 * set).  The owner of the surface then refreshes what it reads:
 * tl_trisurface_update (everything) or tl_trisurface_update_triangles (the
 * given triangles, their neighbours' normals and the shapes of their
 * edges), so that a step costs O(triangles touched) instead of
 * O(triangles).  Both compute the same numbers bit for bit. */
TlStatus tl_trisurface_move_vertices(TlTriSurface *s, const double *x, const double *v);
TlStatus tl_trisurface_update_triangles(TlTriSurface *s, size_t n, const int32_t *triangles);
/* The owner wrote s->x and s->v in place: as tl_trisurface_move_vertices
 * without the copy. */
TlStatus tl_trisurface_vertices_moved(TlTriSurface *s);
/* Sets the feature angle (degrees, in [0, 180]; 180: no edge is sharp, the
 * corrections of seeds/001 alone) and reclassifies the sharpness of every
 * edge from the current normals. */
TlStatus tl_trisurface_set_feature_angle(TlTriSurface *s, double degrees);
/* Changes the tolerances (positive, below 1) and reclassifies. */
TlStatus tl_trisurface_set_tolerances(TlTriSurface *s, double flat_tolerance,
                                      double quality_tolerance);

/* Shape of edge e as seen by a sphere whose centre is x, given in the frame
 * of triangle t, one of the edge's two triangles (it matters only for edges
 * joined across a periodic face): a two-sided surface
 * looks inverted from its - side.  The outside of a convex ridge is the union
 * of the two half-spaces above its faces, the outside of a concave valley
 * their intersection; a centre outside in that sense sees the stored shape. */
TlEdgeShape tl_trisurface_edge_shape_seen_from(const TlTriSurface *s, int e, TlVec3 x, int t);

/* A surface that crosses the faces of a periodic domain (a floor spanning a
 * periodic box) has boundary edges on one face whose images by a lattice
 * vector are boundary edges on the opposite face.  This joins each such pair
 * into one shared edge, so that the triangle-edge corrections, the edge
 * shapes and the history carry-over work across the periodic faces as
 * anywhere else.  Two edges are images when their end points differ by the
 * same lattice vector within tolerance (relative to the cell size); they
 * must be traversed in opposite directions.  Call once after creation (the
 * pairing is topological; the translation is recomputed by every update);
 * *n_linked (may be NULL) receives the number of joined edges.  O(B^2) in
 * the number B of boundary edges. */
TlStatus tl_trisurface_link_periodic(TlTriSurface *s, const TlDomain *domain, double tolerance, size_t *n_linked);

/* Velocity of triangle t at the point with barycentric coordinates bary. */
static inline TlVec3 tl_trisurface_velocity_at(const TlTriSurface *s, int t, const double bary[3])
{
  const int *v = s->tri + 3 * (size_t)t;
  TlVec3 u = tl_v3_scale(s->v[v[0]], bary[0]);
  u = tl_v3_axpy(u, bary[1], s->v[v[1]]);
  return tl_v3_axpy(u, bary[2], s->v[v[2]]);
}

/* Contact of a sphere with triangle t of s (see tl_triangle_sphere_contact). */
static inline int tl_trisurface_sphere_contact(const TlTriSurface *s, int t, TlVec3 x, double r,
                                               TlTriContact *c)
{
  const int *v = s->tri + 3 * (size_t)t;
  return tl_triangle_sphere_contact(s->x[v[0]], s->x[v[1]], s->x[v[2]], s->normal[t], x, r, c);
}

/* Builders for tests, drivers and benchmarks. */
/* A flat rectangle in the plane z = z0 over [x0, x0 + lx] x [y0, y0 + ly],
 * nx by ny squares; pattern 0 splits every square along one diagonal,
 * pattern 1 alternates the diagonals, pattern 2 splits every square into four
 * triangles around its centre (the paper's choice for quadrilateral faces).
 * Normal +z. */
TlStatus tl_trisurface_create_rectangle(double x0, double y0, double lx, double ly, double z0,
                                        int nx, int ny, int pattern, TlTriSurface **surface);
/* The inside of the box [lo, hi] as a closed surface of 12 triangles (two per
 * face), normals pointing inwards. */
TlStatus tl_trisurface_create_box(TlVec3 lo, TlVec3 hi, TlTriSurface **surface);

#endif
