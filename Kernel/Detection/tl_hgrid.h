/* The hierarchical grid for polydisperse spheres (seeds/001 §5.1.1, refs.
 * 49-51).
 *
 * Particles are sorted into L grids of growing cell size s_1 < ... < s_L;
 * a particle of diameter d (plus the Verlet skin) lives on the first level
 * whose cell size is at least d + skin.  Levels are chosen from the size
 * distribution at build time: cell sizes double from the smallest diameter
 * up, and levels left empty are dropped, so a monodisperse packing has one
 * level.  Cells live in the domain's reduced frame (tl_domain.h), so
 * periodic and deformed cells are handled by wrapping cell indices; the
 * number of cells per direction is the face distance over the cell size,
 * which guarantees that two particles within s_l of each other sit in
 * neighbouring cells even in a sheared cell.
 *
 * The grid is a snapshot of the positions at the last build.  Between
 * builds every particle has moved by less than skin/2 (the world rebuilds
 * before that bound is exceeded), and every query below enlarges its search
 * by that amount, so a query made any time before the next build is exact.
 *
 * Pairs: for each particle, all particles whose centre distance may be
 * within r_i + r_j + skin are found in the 27 cells around it on its own
 * level and on every coarser level.  Brute force exists only as a test
 * oracle (tl_hgrid_pairs_brute_force).
 *
 * Walls with a bounding box find their particles through
 * tl_hgrid_query_box (seeds/001 Algorithm 2); only unbounded walls look at
 * every particle. */
#ifndef TL_HGRID_H
#define TL_HGRID_H

#include <stddef.h>
#include <stdint.h>
#include "tl_domain.h"
#include "tl_error.h"
#include "tl_math.h"

enum { TL_HGRID_MAX_LEVELS = 16, TL_HGRID_MAX_THREADS = 64 };

/* A pair of particle indices with i < j. */
typedef struct {
  uint32_t i, j;
} TlPair;

typedef struct {
  double cell_size;     /* s_l, real length */
  int n[3];             /* cells per reduced direction */
  size_t n_cells;
  size_t *cell_start;   /* n_cells + 1 offsets into `index` (counting sort) */
  size_t first, count;  /* this level's particles in hgrid->index[first ..) */
} TlHGridLevel;

typedef struct {
  int n_levels;
  TlHGridLevel level[TL_HGRID_MAX_LEVELS];
  double skin;          /* Verlet skin the grid was built with */
  double max_radius;
  size_t n_particles;
  size_t *index;        /* particle indices grouped by level, then by cell */
  int32_t *cell_of;     /* per particle: cell number within its level */
  uint8_t *level_of;    /* per particle: its level */
  TlVec3 frame_lo, frame_hi; /* open directions: reduced bounding box of the build */
  const TlDomain *domain;
  TlVec3 *reduced;      /* per particle: reduced coordinates at the build (wrapped) */
  TlVec3 cell_width[TL_HGRID_MAX_LEVELS]; /* reduced width of a cell per direction */
  /* per-thread pair buffers of tl_hgrid_pairs (scratch, reused) */
  TlPair *thread_pairs[TL_HGRID_MAX_THREADS];
  size_t thread_capacity[TL_HGRID_MAX_THREADS], thread_count[TL_HGRID_MAX_THREADS];
  size_t capacity_particles;
  size_t cell_capacity[TL_HGRID_MAX_LEVELS];
} TlHGrid;

TlStatus tl_hgrid_create(TlHGrid **grid);
void tl_hgrid_destroy(TlHGrid **grid);
/* (Re)builds from n centres and radii in `domain`, with the given skin.
 * Reuses its buffers; allocates only when the particle count or the cell
 * count grows.  Refuses non-finite positions and non-positive radii. */
TlStatus tl_hgrid_build(TlHGrid *grid, const TlDomain *domain, size_t n, const TlVec3 *x,
                        const double *radius, double skin);
/* All pairs with |branch| <= r_i + r_j + grid->skin (branch by
 * tl_domain_branch), i < j, each once; appended to *pairs (a growable
 * array of *capacity entries), *count set.  `skip` (may be NULL) excludes a
 * pair when both particles have skip[i] && skip[j] (frozen base).  Large
 * grids are scanned by the OpenMP threads in slabs of cells, each into its
 * own buffer kept in the grid, then concatenated in slab order; so two calls
 * on the same grid must not run at once. */
TlStatus tl_hgrid_pairs(const TlHGrid *grid, const TlVec3 *x, const double *radius,
                        const uint8_t *skip, TlPair **pairs, size_t *capacity, size_t *count);
/* The same set by comparing every pair (test oracle only). */
TlStatus tl_hgrid_pairs_brute_force(const TlDomain *domain, size_t n, const TlVec3 *x,
                                    const double *radius, double skin, const uint8_t *skip,
                                    TlPair **pairs, size_t *capacity, size_t *count);
/* Every particle whose cell may overlap the axis-aligned box [lo, hi]
 * (real coordinates) enlarged by the particle's level cell size and by
 * skin/2 — a superset of the particles that can touch anything inside the
 * box before the next build.  Indices appended to *out (growable, *capacity
 * entries), *count set.  Thread-safe (read-only on the grid). */
TlStatus tl_hgrid_query_box(const TlHGrid *grid, TlVec3 lo, TlVec3 hi, size_t **out,
                            size_t *capacity, size_t *count);

#endif
