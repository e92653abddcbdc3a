/* The evaluator's state, shared by the files of Kernel/CG that implement
 * tl_cg_fields.h: tl_cg_evaluator.c (life cycle, sources and their bins),
 * tl_cg_points.c (gather at points), tl_cg_grid.c (cell averages and the
 * scatter onto grids).  Internal: no public API, and it may change. */
#ifndef TL_CG_PRIVATE_H
#define TL_CG_PRIVATE_H

#include <math.h>

#include "tl_cg_fields.h"

/* Entries gathered before one batch evaluation of the kernel. */
enum { TL_CG_CHUNK = 512, TL_CG_MAX_GAUSS = 10, TL_CG_MAX_CROSSINGS = 256 };

/* Sources sorted into a uniform grid of cells at least `reach` wide. */
typedef struct {
  TlVec3 lo, cell;
  int n[3];
  size_t n_cells, cap_cells, cap_index, n_src;
  size_t *start; /* n_cells + 1 */
  size_t *index; /* source indices by cell */
  size_t *cell_of;
  size_t cap_cell_of;
} TlCGBins;

typedef struct {
  double r2[TL_CG_CHUNK], w[TL_CG_CHUNK], aux[TL_CG_CHUNK];
  double lc[TL_CG_CHUNK], ls0[TL_CG_CHUNK], ls1[TL_CG_CHUNK]; /* line pieces: A = r2, B = aux, C, s0, s1 */
  size_t src[TL_CG_CHUNK];
  size_t count;
  size_t *cand, cap_cand; /* hierarchical-grid candidates */
} TlCGWork;

struct TlCG {
  const TlCGKernel *kernel;
  TlCGBox box;
  int has_box;
  TlVec3 length; /* box lengths along periodic directions */
  int n_gauss; /* line integrals of kernels without a closed form */
  TlCGParticleArrays particles;
  /* line sources: contacts, then wall contacts that carry a centre */
  size_t n_lines, cap_lines;
  TlVec3 *la, *lb, *lf, *lmid;
  double max_half_branch;
  TlCGWallContactArrays walls;
  TlCGBins bins[3]; /* particles, lines, wall points */
  int n_threads;
  TlCGWork *work;
  TlMat3 *mvv; /* grid scatter: sum m v v W per node */
  size_t cap_mvv;
  const TlHGrid *hgrid; /* particle candidates of point evaluations, if set */
};

/* Nearest image of a displacement along the periodic directions. */
static inline TlVec3 tl_cg_nearest_image(const TlCG *c, TlVec3 d)
{
  if (!c->has_box) return d;
  double *v = &d.x;
  const double *len = &c->length.x;
  for (int k = 0; k < 3; ++k)
    if (c->box.periodic[k]) v[k] -= len[k] * nearbyint(v[k] / len[k]);
  return d;
}

static inline int tl_cg_wrap_index(long i, int n) { return (int)(((i % n) + n) % n); }

/* Cell coordinate of a point along direction d (unwrapped, unclamped). */
static inline long tl_cg_bin_coord(const TlCG *c, const TlCGBins *b, int d, double x)
{
  const double *lo = &b->lo.x, *cell = &b->cell.x;
  if (c->has_box && c->box.periodic[d]) {
    double L = (&c->length.x)[d];
    double rel = x - lo[d];
    rel -= L * floor(rel / L);
    long i = (long)floor(rel / cell[d]);
    return i >= b->n[d] ? b->n[d] - 1 : i;
  }
  return (long)floor((x - lo[d]) / cell[d]);
}

/* The part of the segment s in [0, 1] where |d - s b| < c, as a line piece
 * |d - s b|^2 = A s^2 + B s + C on [s0, s1]; 0 when the segment misses the
 * support. */
static inline int tl_cg_line_piece(TlVec3 d, TlVec3 b, double c2, double *A, double *B, double *C, double *s0, double *s1)
{
  double bb = tl_v3_norm2(b), db = tl_v3_dot(d, b), dd = tl_v3_norm2(d);
  if (!(bb > 0.0)) return 0;
  double disc = db * db - bb * (dd - c2);
  if (!(disc > 0.0)) return 0;
  double sq = sqrt(disc);
  *s0 = fmax(0.0, (db - sq) / bb);
  *s1 = fmin(1.0, (db + sq) / bb);
  *A = bb;
  *B = -2.0 * db;
  *C = dd;
  return *s1 > *s0;
}

/* TL_ERR_NUMERIC naming the first of the n points `x` that is not finite. */
TlStatus tl_cg_check_finite(const char *what, size_t n, const TlVec3 *x);

#endif
