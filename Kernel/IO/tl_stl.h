/* Triangulated surfaces from files: ASCII and binary STL, Gmsh surface
 * meshes (.msh 2.2 and 4.1, ASCII), and their checks and repair.
 *
 * A TlSurfaceMesh is a plain indexed triangle list: what geometry files
 * hold, before it becomes a wall (tl_wall_trisurface_from_mesh) or the
 * boundary of a tetrahedral solid.  Triangle k of a mesh just read is facet
 * k of the file (counted from 0), so that every message names the facet as
 * the file numbers it.
 *
 *   TlSurfaceMesh *m = NULL;
 *   TL_CHECK(tl_surface_mesh_read("hopper.stl", &m));  // STL or Gmsh, by content
 *   TlSurfaceReport r;
 *   TL_CHECK(tl_surface_mesh_repair(m, NULL, &r));     // merge, clean, orient
 *   TL_CHECK(tl_surface_mesh_check(m, TL_SURFACE_CLOSED)); // refuse holes
 *   ... m->x[i], m->tri[t][0..2] ...
 *   tl_surface_mesh_destroy(&m);
 *
 * Reading refuses what cannot be a surface: a truncated file (naming the
 * facet it ends in), a non-finite coordinate (naming the facet and vertex),
 * a facet of other than three vertices, a malformed token (naming the line).
 * STL stores each facet's corners separately; the reader joins corners whose
 * coordinates are bit for bit equal (no tolerance), which makes the mesh
 * indexed.  Everything else is left to the check, which refuses, and to the
 * repair, which fixes and reports. */
#ifndef TL_STL_H
#define TL_STL_H

#include <stddef.h>
#include "tl_error.h"
#include "tl_math.h"

typedef struct {
  size_t n_vertices, n_triangles;
  TlVec3 *x;       /* n_vertices positions */
  int (*tri)[3];   /* n_triangles vertex triples */
  char name[64];   /* the STL solid's name, or "" */
} TlSurfaceMesh;

/* Reads an STL (ASCII or binary) or Gmsh surface file, told apart by content. */
TlStatus tl_surface_mesh_read(const char *path, TlSurfaceMesh **m);
/* Reads STL from a file or from memory (label names the source in messages).
 * Binary when the size is 84 + 50 n for the n the header declares, or when
 * the text does not begin with "solid" followed by printable text. */
TlStatus tl_stl_read(const char *path, TlSurfaceMesh **m);
TlStatus tl_stl_read_memory(const void *data, size_t size, const char *label, TlSurfaceMesh **m);
/* Reads the triangles (3-node, and the corners of 6-node ones) of a Gmsh
 * ASCII mesh; only the nodes they use are kept. */
TlStatus tl_gmsh_surface_read(const char *path, TlSurfaceMesh **m);
TlStatus tl_gmsh_surface_read_memory(const void *data, size_t size, const char *label, TlSurfaceMesh **m);
/* Writes binary (binary = 1) or ASCII STL, in single precision for binary. */
TlStatus tl_stl_write(const char *path, const TlSurfaceMesh *m, int binary);

/* A mesh from arrays (copied): x 3 doubles per vertex, tri 3 per triangle;
 * indices are checked. */
TlStatus tl_surface_mesh_create(size_t n_vertices, const double *x, size_t n_triangles, const int *tri,
                                TlSurfaceMesh **m);
void tl_surface_mesh_destroy(TlSurfaceMesh **m);
/* x <- R (scale x) + shift for every vertex; scale > 0, R a rotation (its
 * determinant 1 within 1e-9, else refused: a reflection would turn the
 * triangles inside out). */
TlStatus tl_surface_mesh_transform(TlSurfaceMesh *m, double scale, TlMat3 R, TlVec3 shift);
/* Reverses every triangle (the normals change side). */
void tl_surface_mesh_flip(TlSurfaceMesh *m);

/* What tl_surface_mesh_check requires beyond a valid triangulated surface
 * (indices in range; no triangle of zero area, needle or cap below the
 * quality 1e-6; every edge shared by at most two triangles traversing it
 * in opposite directions). */
enum {
  TL_SURFACE_CLOSED = 1 /* no boundary edge: the surface encloses a volume */
};
/* Refuses the first defect with its facet or edge named: degenerate facet
 * (its vertices and quality), non-manifold edge (its vertices and the
 * triangles sharing it), inconsistently oriented pair, and with
 * TL_SURFACE_CLOSED a boundary edge (the hole it belongs to, its length in
 * edges). */
TlStatus tl_surface_mesh_check(const TlSurfaceMesh *m, int flags);

typedef struct {
  /* Needles (longest over shortest edge above needle_ratio, default 1e4)
   * and caps (an angle whose cosine is below cap_cosine, default -0.9999:
   * wider than 179.2 degrees) are removed by edge collapses and flips, which
   * keep a closed surface closed.  Zero-area triangles (exactly collinear
   * corners) are always removed. */
  double needle_ratio, cap_cosine;
  /* 1 (default): a closed surface is oriented with its normals pointing
   * out of the volume it encloses; 0: into it (a container seen from the
   * grains inside). */
  int outward;
} TlSurfaceRepairOptions;

typedef struct {
  size_t vertices_merged;       /* duplicate points joined */
  size_t triangles_removed;     /* degenerate (zero area, needle, cap) or repeated */
  size_t triangles_flipped;     /* reversed to orient the surface consistently */
  size_t vertices_split;        /* duplicated to undo non-manifold vertices or edges */
  size_t nonmanifold_edges;     /* edges shared by more than two triangles (before repair) */
  size_t holes;                 /* boundary cycles left (0: closed) */
  size_t boundary_edges;
  int closed;                   /* 1: no boundary edge */
  double volume;                /* enclosed volume when closed, else 0 */
  char first_nonmanifold[96];   /* "edge (a, b): triangles t1, t2, t3" or "" */
  char first_hole[96];          /* "hole of n edges through vertices a, b, ..." or "" */
} TlSurfaceReport;

/* Sets the defaults above. */
void tl_surface_repair_options_default(TlSurfaceRepairOptions *o);
/* Repairs in place through CGAL's polygon-mesh processing: merges
 * duplicate points, removes repeated, zero-area, needle and cap triangles,
 * orients consistently (splitting non-manifold vertices and edges where no
 * consistent orientation exists), orients a closed surface outward (or
 * inward) and reports holes and non-manifold edges by name.  options may be
 * NULL (defaults), report may be NULL.  Without CGAL: TL_ERR_UNSUPPORTED.
 * After it tl_surface_mesh_check passes, with TL_SURFACE_CLOSED when
 * report->closed. */
TlStatus tl_surface_mesh_repair(TlSurfaceMesh *m, const TlSurfaceRepairOptions *options, TlSurfaceReport *report);

/* 1 when every edge is shared by exactly two triangles. */
int tl_surface_mesh_is_closed(const TlSurfaceMesh *m);
/* Signed enclosed volume (divergence theorem): positive when the normals
 * point out.  Meaningful for closed surfaces only (refused otherwise, the
 * boundary edge named). */
TlStatus tl_surface_mesh_volume(const TlSurfaceMesh *m, double *volume);
/* The exact sign of that volume (tl_volume_sign): 1 normals out, -1 inside
 * out, 0 none; -2 if memory ran out.  For a closed, consistently oriented
 * surface; decisions take this, not the sign of the rounded volume. */
int tl_surface_mesh_volume_sign(const TlSurfaceMesh *m);
/* Area of the surface, and its bounding box (lo, hi may be NULL). */
double tl_surface_mesh_area(const TlSurfaceMesh *m);
void tl_surface_mesh_bounds(const TlSurfaceMesh *m, TlVec3 *lo, TlVec3 *hi);
/* Whether p lies inside the closed surface m: *inside = 1 inside, 0
 * outside, -1 on the surface.  Decided by the parity of the crossings of a
 * ray with exact orientation predicates (tl_predicates.h): a ray that meets
 * an edge or a vertex is replaced by another direction, so the answer is
 * exact.  O(triangles) per point. */
TlStatus tl_surface_mesh_contains(const TlSurfaceMesh *m, TlVec3 p, int *inside);
/* Insertion sites: the points of a cubic lattice of the given pitch (over
 * the surface's box, offset half a pitch from its low corner) strictly
 * inside the closed surface m, at most max of them, lowest first (z, then
 * y, then x); *points (3 doubles each) is allocated with tl_calloc, the
 * caller frees it with tl_free.  Insertion at a margin from the walls is a
 * surface shrunk by that margin. */
TlStatus tl_surface_mesh_lattice_inside(const TlSurfaceMesh *m, double pitch, size_t max, double **points,
                                        size_t *n);

#endif
