/* The state of a triangulated surface wall, shared by the files that
 * implement the type (tl_wall_trisurface.c: detection and forces;
 * tl_wall_trisurface_checkpoint.c: checkpoints).  Not part of the API. */
#ifndef TL_WALL_TRISURFACE_PRIVATE_H
#define TL_WALL_TRISURFACE_PRIVATE_H

#include <stddef.h>
#include <stdint.h>
#include "tl_trisurface_bins.h"
#include "tl_wall_trisurface.h"

/* Per-thread detection buffers, so that candidate lists grow without locks
 * and are reused from step to step. */
typedef struct {
  TlTriContactSet *found;
  size_t *candidates;
  size_t candidate_capacity, n_candidates;
  int32_t *pairs; /* (triangle, particle) candidate pairs found by this thread */
  size_t pair_capacity, n_pairs;
} TlTriThread;

typedef struct {
  TlWall base;
  TlTriSurface *surface;
  TlTriContactSet *current, *previous;
  int corrections, brute_force, drift;
  double feature_angle; /* degrees, given to the surface */
  int n_threads;
  TlTriThread *thread;
  /* law input and output, aligned with current->c */
  TlContactGeometry *geometry;
  TlContactResult *result;
  size_t geometry_capacity, result_capacity;
  TlTriBins bins; /* triangles near particles */
  /* Candidate pairs (triangle, particle) within radius + skin, found through
   * the grid (Algorithm 2) and kept until some particle has moved more than
   * skin/2 or the surface has moved, as a Verlet list */
  int32_t *pair;
  size_t n_pairs, pair_capacity;
  TlVec3 *x_list;
  size_t n_list, x_list_capacity;
  TlVec3 *vertex_list; /* vertex positions at the list build */
  size_t vertex_list_capacity;
  unsigned long list_version;
  double list_skin;
  int list_valid;
  long list_builds;
  /* Distinct triangles of the list, for partial geometry updates. */
  int32_t *listed;
  size_t n_listed, listed_capacity;
  unsigned char *seen; /* per triangle, scratch of the above */
  size_t seen_capacity;
  unsigned long listed_version; /* list build they belong to (0: none) */
  /* Prescribed rigid motion (tl_wall_trisurface_set_motion): the vertex
   * positions at motion.start, from which advance places the surface at
   * every time (positions from time, not accumulated: no drift). */
  TlRigidMotion motion;
  int moving;
  TlVec3 *x_ref;
} TlWallTriSurface;

/* Places the surface of a moving wall at time `time` (tl_wall_trisurface_motion.c). */
TlStatus tl_wall_trisurface_place(TlWallTriSurface *t, double time);

#define TL_REQUIRE_SURFACE(t)                                                                 \
  do {                                                                                        \
    if (!(t)->surface)                                                                        \
      TL_ERROR(TL_ERR_STATE, "wall '%s' has no surface yet (tl_wall_trisurface_set_surface)",  \
               (t)->base.name);                                                               \
  } while (0)

/* The wall's checkpoint ops (TlWallOps). */
size_t tl_wall_trisurface_checkpoint_size(const TlWall *w);
TlStatus tl_wall_trisurface_checkpoint_save(const TlWall *w, void *buffer, size_t size);
TlStatus tl_wall_trisurface_checkpoint_load(TlWall *w, const void *buffer, size_t size);

#endif
