/* Walls in the output: the walls of a world as an XDMF time series of
 * triangles beside the particle and mesh series, so ParaView shows the
 * floor, the hopper or the coupled beam surface with the grains.
 *
 * Each wall becomes one block of triangles in its current configuration
 * (no Warp By Vector needed): a triangulated surface as it stands, an
 * infinite plane as a finite rectangular patch covering the box of the
 * scene (the domain's cell together with the particles and the bounded
 * walls, fixed at the first write unless set with tl_wall_writer_set_box,
 * so a still plane is written once).  The writer is a mesh writer
 * (tl_mesh_snapshot.h): <dir>/<name>.xmf, <dir>/<name>_mesh_<m>.h5 (the
 * triangles, written again only when a wall moved) and <dir>/<name>_<k>.h5
 * per step with the cell fields
 *   normal         3  unit normal of the triangle (its + side)
 *   contact_force  3  force the particles exert on the triangle at the last
 *                     force evaluation (N; sums to the wall's TlWall.force)
 *   wall           1  index of the wall in the list written
 * Blocks are named wall<k>_<type> (wall0_plane, wall1_trisurface).
 *
 * How a wall type is drawn is a registered outline (kind "wall_outline",
 * named as the wall type), so a wall type defined outside the library is
 * written once it registers one; a wall without an outline is refused by
 * name.  The built-in outlines are those of "plane" and "trisurface". */
#ifndef TL_WALL_SNAPSHOT_H
#define TL_WALL_SNAPSHOT_H

#include <stddef.h>
#include <stdint.h>

#include "tl_checkpoint.h"
#include "tl_dem.h"
#include "tl_error.h"
#include "tl_math.h"
#include "tl_object.h"
#include "tl_particles.h"
#include "tl_wall.h"

/* The triangles of one wall: growing arrays the outline fills through
 * tl_wall_outline_reserve (counts set by the outline). */
typedef struct {
  size_t n_vertices, n_triangles;
  TlVec3 *x;           /* vertex positions */
  int *tri;            /* 3 vertex indices per triangle, counter-clockwise seen from the + side */
  TlVec3 *force;       /* per triangle: force of the particles on it (zeroed by reserve) */
  size_t cap_vertices, cap_triangles;
} TlWallOutline;

/* Room for n_vertices and n_triangles (contents kept only up to the
 * counts; forces zeroed). */
TlStatus tl_wall_outline_reserve(TlWallOutline *o, size_t n_vertices, size_t n_triangles);
void tl_wall_outline_free(TlWallOutline *o);

/* An outline draws wall w of its type: box_lo/box_hi bound the scene (what
 * an unbounded wall is cut to), P the particles the wall saw (for contact
 * forces). */
typedef struct {
  TlOpsHeader header; /* kind "wall_outline", name: the wall type */
  TlStatus (*outline)(const TlWall *w, const TlParticles *P, TlVec3 box_lo, TlVec3 box_hi, TlWallOutline *out);
} TlWallOutlineOps;

TlStatus tl_wall_outline_register(const TlWallOutlineOps *ops);
/* The outline of w through its type's registered op. */
TlStatus tl_wall_outline(const TlWall *w, const TlParticles *P, TlVec3 box_lo, TlVec3 box_hi, TlWallOutline *out);
TlStatus tl_wall_snapshot_register_all(void);

typedef struct TlWallWriter TlWallWriter;

/* A writer of <dir>/<name>.xmf and its files; creates dir if needed. */
TlStatus tl_wall_writer_create(const char *dir, const char *name, TlWallWriter **writer);
void tl_wall_writer_destroy(TlWallWriter **writer);
/* The box unbounded walls are cut to (lo < hi in every component, finite). */
TlStatus tl_wall_writer_set_box(TlWallWriter *writer, TlVec3 lo, TlVec3 hi);
/* Writes n walls (P: the particles they interact with, may be NULL when
 * the box is set) at simulation time `time` and step `step`. */
TlStatus tl_wall_writer_write(TlWallWriter *writer, int64_t step, double time, size_t n, TlWall *const *walls,
                              const TlParticles *P);
/* Writes every wall of a world at its current time. */
TlStatus tl_wall_writer_write_dem(TlWallWriter *writer, int64_t step, TlDem *dem);
size_t tl_wall_writer_count(const TlWallWriter *writer);
/* The last step file written ("" before any) and the current mesh file. */
const char *tl_wall_writer_last_path(const TlWallWriter *writer);
const char *tl_wall_writer_mesh_path(const TlWallWriter *writer);
/* The box in use (after the first write or set_box; 0 before). */
int tl_wall_writer_box(const TlWallWriter *writer, TlVec3 *lo, TlVec3 *hi);
/* Counters, box and XDMF list, so a restarted run continues the series. */
extern const TlCheckpointOps tl_wall_writer_checkpoint_ops;

#endif
