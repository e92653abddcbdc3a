/* Continuum fields coarse-grained from particle data (seeds/001 §4).
 *
 * The fields take plain arrays, so the DEM world, the couplings and a
 * post-processor all call them alike:
 *   particles      centres x_a, masses m_a, velocities v_a (may be absent)
 *   contacts       per contact: the centre x_i of the particle that feels
 *                  the force, the branch vector b = x_j - x_i (nearest
 *                  image) and the force f on i from j
 *   wall contacts  contact point x^c, force f^w on the particle from the
 *                  wall, and optionally the particle centre
 *
 * Fields at a point x (tension positive, as the Cauchy-Poisson stress of
 * seeds/004 Eq. 27):
 *   density          rho(x) = sum_a m_a W(x - x_a)                    Eq. 8
 *   momentum         j(x)   = sum_a m_a v_a W(x - x_a)                Eq. 11
 *   velocity         V = j / rho (0 where rho = 0)                     Eq. 11
 *   kinetic stress   s^k = -sum_a m_a v'_a (x) v'_a W(x - x_a), v'_a = v_a - V(x)
 *   contact stress   s^c = sum_c f_c (x) b_c  int_0^1 W(x - x_i - s b_c) ds
 *                    (wall contacts given with a centre add f^w (x) (x^c - x_a)
 *                    the same way), whose volume integral is sum_c f_c (x) b_c:
 *                    the Cauchy-Poisson stress times the volume
 *   boundary force   b^BC(x) = sum -f^w W(x - x^c)                     Eq. 12
 *   fabric           F(x) = sum_c n_c (x) n_c int_0^1 W(x - x_i - s b_c) ds,
 *                    n_c = b_c / |b_c|; its trace is the contact density.
 * The branch-line integral runs over the part of the segment inside the
 * kernel's support (found in closed form), and is itself in closed form for
 * the built-in kernels (tl_cg_kernel_line_integral).
 *
 * Neighbour search.  At arbitrary points (gather): particles come from the
 * DEM world's hierarchical grid when one is given (tl_cg_use_hgrid), else
 * from bins of the evaluator's own; contacts (by branch midpoint) and wall
 * contacts always from its own bins, cells as wide as the kernel's reach.
 * On a grid (scatter): every source visits the nodes within c of it, found
 * by index arithmetic, threads owning slabs of node layers.  Either way a
 * field on P points costs O(P x neighbours);
 * tl_cg_evaluate_points_brute_force is the test oracle.  Periodic
 * (orthogonal) boxes are handled by nearest images (the box must be at
 * least 2c long along each periodic direction).
 *
 * The Dirac kernel has no point values; on a grid its closed form is the
 * cell average (each node owns the cell of size h around it): particles and
 * wall contacts deposit into their cell, a branch segment into the cells it
 * crosses in proportion to its length in each. */
#ifndef TL_CG_FIELDS_H
#define TL_CG_FIELDS_H

#include <stddef.h>
#include "tl_cg_kernel.h"
#include "tl_error.h"
#include "tl_hgrid.h"
#include "tl_math.h"

typedef struct {
  size_t n;
  const TlVec3 *x;
  const double *mass;
  const TlVec3 *v; /* may be NULL: no momentum, velocity or kinetic stress */
} TlCGParticleArrays;

typedef struct {
  size_t n;
  const TlVec3 *x;      /* centre of the particle that feels `force` */
  const TlVec3 *branch; /* x_j - x_i, nearest image */
  const TlVec3 *force;  /* force on i from j */
} TlCGContactArrays;

typedef struct {
  size_t n;
  const TlVec3 *point;  /* contact point x^c */
  const TlVec3 *force;  /* f^w, force on the particle from the wall */
  const TlVec3 *centre; /* may be NULL; with it the contact adds to the stress */
} TlCGWallContactArrays;

/* Box for nearest images; directions not flagged periodic are open. */
typedef struct {
  TlVec3 lo, hi;
  int periodic[3];
} TlCGBox;

/* A regular grid of nodes lo + (i h_x, j h_y, k h_z), node index
 * i + n[0] (j + n[1] k). */
typedef struct {
  TlVec3 lo, h;
  int n[3];
} TlCGGrid;

enum {
  TL_CG_DENSITY = 1u << 0,
  TL_CG_MOMENTUM = 1u << 1,        /* momentum and velocity */
  TL_CG_STRESS_KINETIC = 1u << 2,
  TL_CG_STRESS_CONTACT = 1u << 3,
  TL_CG_BOUNDARY_FORCE = 1u << 4,
  TL_CG_FABRIC = 1u << 5,
  TL_CG_ALL = (1u << 6) - 1
};

/* Fields on n points; arrays of the fields not requested are NULL.  The
 * kinetic stress brings the momentum and velocity with it, and those the
 * density (each is computed from the previous). */
typedef struct {
  size_t n;
  unsigned which;
  double *density;
  TlVec3 *momentum, *velocity;
  TlMat3 *stress_kinetic, *stress_contact;
  TlVec3 *boundary_force;
  TlMat3 *fabric;
  double weight; /* time averaging: total weight accumulated */
} TlCGFields;

TlStatus tl_cg_fields_create(size_t n, unsigned which, TlCGFields **fields);
void tl_cg_fields_destroy(TlCGFields **fields);
void tl_cg_fields_zero(TlCGFields *fields);
/* Time averaging: avg += weight * snapshot (same n, which a subset of the
 * snapshot's); tl_cg_fields_average_finish divides by the total weight and
 * recomputes the velocity as <j>/<rho>, the mass-weighted mean. */
TlStatus tl_cg_fields_accumulate(TlCGFields *avg, const TlCGFields *snapshot, double weight);
TlStatus tl_cg_fields_average_finish(TlCGFields *avg);

typedef struct TlCG TlCG;

/* An evaluator for one kernel (borrowed, must outlive it) and an optional
 * periodic box (NULL: open space).  gauss_points: points of the branch-line
 * integral for kernels without a closed form (1..10; 0 picks 6). */
TlStatus tl_cg_create(const TlCGKernel *kernel, const TlCGBox *box, int gauss_points, TlCG **cg);
/* The evaluator keeps one workspace per OpenMP thread of omp_get_max_threads()
 * at creation and never runs more threads than that. */
void tl_cg_destroy(TlCG **cg);
/* Sets the data (arrays are borrowed until the next set or evaluation; any
 * may be NULL for "none") and rebuilds the bins.  Allocates only when the
 * data outgrow the buffers, so calling it every step is cheap. */
TlStatus tl_cg_set_data(TlCG *cg, const TlCGParticleArrays *particles, const TlCGContactArrays *contacts,
                        const TlCGWallContactArrays *walls);
/* Point evaluations take their particle candidates from the DEM world's
 * hierarchical grid (tl_hgrid_query_box) instead of bins of their own
 * (NULL: back to the own bins).  The grid must have been built on the same
 * particle arrays (same indices) and within the last rebuild, which the
 * DEM world guarantees between its steps; set it before tl_cg_set_data,
 * which then builds bins for contacts and wall contacts only.  The
 * domain's periodicity must be the CG box's (orthogonal boxes). */
TlStatus tl_cg_use_hgrid(TlCG *cg, const TlHGrid *grid);
/* Fields `out->which` at n points (not for the Dirac kernel). */
TlStatus tl_cg_evaluate_points(TlCG *cg, size_t n, const TlVec3 *points, TlCGFields *out);
/* The same by visiting every source for every point (test oracle). */
TlStatus tl_cg_evaluate_points_brute_force(TlCG *cg, size_t n, const TlVec3 *points, TlCGFields *out);
/* Fields on the grid's nodes (out->n == nodes); the Dirac kernel gives cell
 * averages. */
TlStatus tl_cg_evaluate_grid(TlCG *cg, const TlCGGrid *grid, TlCGFields *out);
/* Node position of a grid. */
static inline TlVec3 tl_cg_grid_node(const TlCGGrid *g, int i, int j, int k)
{
  return tl_v3(g->lo.x + i * g->h.x, g->lo.y + j * g->h.y, g->lo.z + k * g->h.z);
}

#endif
