/* CG fields gathered at points: every source within reach of a point, through
 * the bins or the hierarchical grid (tl_cg_fields.h). */
#include "tl_cg_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"
#ifdef _OPENMP
#include <omp.h>
#endif

/* Candidate cells of a point: up to 3 per direction, deduplicated. */
static int neighbour_cells(const TlCG *c, const TlCGBins *b, TlVec3 x, size_t *cells)
{
  int list[3][3], cnt[3];
  for (int d = 0; d < 3; ++d) {
    long i0 = tl_cg_bin_coord(c, b, d, (&x.x)[d]);
    cnt[d] = 0;
    int periodic = c->has_box && c->box.periodic[d];
    for (long di = -1; di <= 1; ++di) {
      long i = i0 + di;
      if (periodic) i = tl_cg_wrap_index(i, b->n[d]);
      else if (i < 0 || i >= b->n[d]) continue;
      int dup = 0;
      for (int q = 0; q < cnt[d]; ++q) dup |= list[d][q] == (int)i;
      if (!dup) list[d][cnt[d]++] = (int)i;
    }
  }
  int m = 0;
  for (int a = 0; a < cnt[0]; ++a)
    for (int bb = 0; bb < cnt[1]; ++bb)
      for (int k = 0; k < cnt[2]; ++k)
        cells[m++] = (size_t)list[0][a] + (size_t)b->n[0] * ((size_t)list[1][bb] + (size_t)b->n[1] * (size_t)list[2][k]);
  return m;
}

/* Accumulators of one point. */
typedef struct {
  double rho;
  TlVec3 j;
  TlMat3 mvv, sc, fab;
  TlVec3 bf;
} TlCGAcc;

static TlStatus flush_particles(const TlCG *c, TlCGWork *w, TlCGAcc *a)
{
  if (!w->count) return TL_OK;
  TL_CHECK(tl_cg_kernel_eval(c->kernel, w->count, w->r2, w->w, NULL));
  const TlCGParticleArrays *p = &c->particles;
  for (size_t e = 0; e < w->count; ++e) {
    size_t i = w->src[e];
    double mw = p->mass[i] * w->w[e];
    a->rho += mw;
    if (p->v) {
      TlVec3 v = p->v[i];
      a->j = tl_v3_axpy(a->j, mw, v);
      a->mvv = tl_m3_add(a->mvv, tl_m3_scale(tl_m3_outer(v, v), mw));
    }
  }
  w->count = 0;
  return TL_OK;
}

static TlStatus flush_lines(const TlCG *c, TlCGWork *w, TlCGAcc *a, unsigned which)
{
  if (!w->count) return TL_OK;
  TL_CHECK(tl_cg_kernel_line_integral(c->kernel, w->count, w->r2, w->aux, w->lc, w->ls0, w->ls1, c->n_gauss, w->w));
  for (size_t e = 0; e < w->count; ++e) {
    size_t i = w->src[e];
    double s = w->w[e];
    if (which & TL_CG_STRESS_CONTACT) a->sc = tl_m3_add(a->sc, tl_m3_scale(tl_m3_outer(c->lf[i], c->lb[i]), s));
    if (which & TL_CG_FABRIC) {
      TlVec3 n = tl_v3_normalize(c->lb[i]);
      a->fab = tl_m3_add(a->fab, tl_m3_scale(tl_m3_outer(n, n), s));
    }
  }
  w->count = 0;
  return TL_OK;
}

static TlStatus flush_walls(const TlCG *c, TlCGWork *w, TlCGAcc *a)
{
  if (!w->count) return TL_OK;
  TL_CHECK(tl_cg_kernel_eval(c->kernel, w->count, w->r2, w->w, NULL));
  for (size_t e = 0; e < w->count; ++e) a->bf = tl_v3_axpy(a->bf, -w->w[e], c->walls.force[w->src[e]]);
  w->count = 0;
  return TL_OK;
}

/* Iterates the candidates of set `set` for point x: all sources (brute) or
 * those in the neighbouring cells. */
#define TL_CG_FOR_CANDIDATES(c, set, x, brute, i, ...)                                        \
  do {                                                                                        \
    const TlCGBins *b_ = &(c)->bins[set];                                                     \
    if (brute) {                                                                              \
      for (size_t i = 0; i < b_->n_src; ++i) __VA_ARGS__                                      \
    } else {                                                                                  \
      size_t cells_[27];                                                                      \
      int nc_ = neighbour_cells((c), b_, (x), cells_);                                        \
      for (int q_ = 0; q_ < nc_; ++q_)                                                        \
        for (size_t e_ = b_->start[cells_[q_]]; e_ < b_->start[cells_[q_] + 1]; ++e_) {       \
          size_t i = b_->index[e_];                                                           \
          __VA_ARGS__                                                                         \
        }                                                                                     \
    }                                                                                         \
  } while (0)

static TlStatus evaluate_one(const TlCG *c, TlCGWork *w, TlVec3 x, int brute, TlCGFields *out, size_t slot)
{
  unsigned which = out->which;
  double c2 = c->kernel->c * c->kernel->c;
  TlCGAcc a;
  memset(&a, 0, sizeof a);
  if (which & (TL_CG_DENSITY | TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC)) {
    const TlCGParticleArrays *p = &c->particles;
    w->count = 0;
#define TL_CG_PARTICLE_BODY                                                     \
  {                                                                             \
    TlVec3 d = tl_cg_nearest_image(c, tl_v3_sub(x, p->x[i]));                         \
    double r2 = tl_v3_norm2(d);                                                 \
    if (r2 < c2) {                                                              \
      if (w->count == TL_CG_CHUNK) TL_CHECK(flush_particles(c, w, &a));         \
      w->r2[w->count] = r2;                                                     \
      w->src[w->count++] = i;                                                   \
    }                                                                           \
  }
    if (c->hgrid && !brute) {
      size_t nc = 0;
      double cw = c->kernel->c;
      TL_CHECK(tl_hgrid_query_box(c->hgrid, tl_v3(x.x - cw, x.y - cw, x.z - cw), tl_v3(x.x + cw, x.y + cw, x.z + cw),
                                  &w->cand, &w->cap_cand, &nc));
      for (size_t e = 0; e < nc; ++e) {
        size_t i = w->cand[e];
        TL_CG_PARTICLE_BODY
      }
    } else {
      TL_CG_FOR_CANDIDATES(c, 0, x, brute, i, TL_CG_PARTICLE_BODY);
    }
#undef TL_CG_PARTICLE_BODY
    TL_CHECK(flush_particles(c, w, &a));
  }
  if (which & (TL_CG_STRESS_CONTACT | TL_CG_FABRIC)) {
    w->count = 0;
    TL_CG_FOR_CANDIDATES(c, 1, x, brute, i, {
      /* x - a - s b with the nearest image taken at the midpoint */
      TlVec3 b = c->lb[i];
      TlVec3 d = tl_v3_axpy(tl_cg_nearest_image(c, tl_v3_sub(x, c->lmid[i])), 0.5, b);
      double A, B, C, s0, s1;
      if (tl_cg_line_piece(d, b, c2, &A, &B, &C, &s0, &s1)) {
        if (w->count == TL_CG_CHUNK) TL_CHECK(flush_lines(c, w, &a, which));
        w->r2[w->count] = A;
        w->aux[w->count] = B;
        w->lc[w->count] = C;
        w->ls0[w->count] = s0;
        w->ls1[w->count] = s1;
        w->src[w->count++] = i;
      }
    });
    TL_CHECK(flush_lines(c, w, &a, which));
  }
  if (which & TL_CG_BOUNDARY_FORCE) {
    w->count = 0;
    TL_CG_FOR_CANDIDATES(c, 2, x, brute, i, {
      double r2 = tl_v3_norm2(tl_cg_nearest_image(c, tl_v3_sub(x, c->walls.point[i])));
      if (r2 < c2) {
        if (w->count == TL_CG_CHUNK) TL_CHECK(flush_walls(c, w, &a));
        w->r2[w->count] = r2;
        w->src[w->count++] = i;
      }
    });
    TL_CHECK(flush_walls(c, w, &a));
  }
  if (out->density) out->density[slot] = a.rho;
  TlVec3 V = a.rho > 0.0 ? tl_v3_scale(a.j, 1.0 / a.rho) : tl_v3(0, 0, 0);
  if (out->momentum) {
    out->momentum[slot] = a.j;
    out->velocity[slot] = V;
  }
  if (out->stress_kinetic) /* -sum m (v - V)(v - V) W = -(sum m v v W - rho V V) */
    out->stress_kinetic[slot] = tl_m3_add(tl_m3_scale(a.mvv, -1.0), tl_m3_outer(a.j, V));
  if (out->stress_contact) out->stress_contact[slot] = a.sc;
  if (out->boundary_force) out->boundary_force[slot] = a.bf;
  if (out->fabric) out->fabric[slot] = a.fab;
  return TL_OK;
}

static TlStatus evaluate_points(TlCG *c, size_t n, const TlVec3 *points, const TlCGGrid *grid, int brute,
                                TlCGFields *out)
{
  if (tl_cg_kernel_is_dirac(c->kernel))
    TL_ERROR(TL_ERR_UNSUPPORTED, "the dirac kernel has no point values: evaluate it on a grid (cell averages)");
  if (out->n != n) TL_ERROR(TL_ERR_ARG, "fields hold %zu points, asked for %zu", out->n, n);
  if ((out->which & (TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC)) && c->particles.n && !c->particles.v)
    TL_ERROR(TL_ERR_ARG, "momentum or kinetic stress asked for, but no particle velocities were given");
  TlStatus status = TL_OK;
  long long count = (long long)n;
#pragma omp parallel for schedule(dynamic, 64) num_threads(c->n_threads)
  for (long long q = 0; q < count; ++q) {
    int t = 0;
#ifdef _OPENMP
    t = omp_get_thread_num();
#endif
    TlStatus s;
#pragma omp atomic read
    s = status;
    if (s != TL_OK) continue;
    TlVec3 x;
    if (grid) {
      long long i = q % grid->n[0], r = q / grid->n[0];
      x = tl_cg_grid_node(grid, (int)i, (int)(r % grid->n[1]), (int)(r / grid->n[1]));
    } else {
      x = points[q];
    }
    s = evaluate_one(c, &c->work[t], x, brute, out, (size_t)q);
    if (s != TL_OK) {
#pragma omp critical(tl_cg_error)
      if (status == TL_OK) status = s;
    }
  }
  if (status != TL_OK) return tl_error_trace(status, __FILE__, __LINE__);
  return TL_OK;
}

TlStatus tl_cg_evaluate_points(TlCG *c, size_t n, const TlVec3 *points, TlCGFields *out)
{
  TL_CHECK(tl_cg_check_finite("evaluation point", n, points));
  TL_CHECK(evaluate_points(c, n, points, NULL, 0, out));
  return TL_OK;
}

TlStatus tl_cg_evaluate_points_brute_force(TlCG *c, size_t n, const TlVec3 *points, TlCGFields *out)
{
  TL_CHECK(tl_cg_check_finite("evaluation point", n, points));
  TL_CHECK(evaluate_points(c, n, points, NULL, 1, out));
  return TL_OK;
}

