/* The CG evaluator's life cycle, its sources (particles, contact branch
 * lines, wall contacts) and their bins (tl_cg_fields.h). */
#include "tl_cg_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"
#ifdef _OPENMP
#include <omp.h>
#endif

/* ------------------------------------------------------------ evaluator */

TlStatus tl_cg_create(const TlCGKernel *kernel, const TlCGBox *box, int gauss_points, TlCG **cg)
{
  *cg = NULL;
  if (!kernel) TL_ERROR(TL_ERR_ARG, "no kernel given");
  if (gauss_points == 0) gauss_points = 6;
  if (gauss_points < 1 || gauss_points > TL_CG_MAX_GAUSS)
    TL_ERROR(TL_ERR_ARG, "branch-line Gauss points %d outside [1, %d]", gauss_points, TL_CG_MAX_GAUSS);
  if (box) {
    const double *lo = &box->lo.x, *hi = &box->hi.x;
    for (int d = 0; d < 3; ++d)
      if (box->periodic[d] && !(hi[d] > lo[d]))
        TL_ERROR(TL_ERR_ARG, "periodic box direction %d has hi %g <= lo %g", d, hi[d], lo[d]);
  }
  TlCG *c;
  TL_CHECK(TL_NEW(c));
  c->kernel = kernel;
  if (box) {
    c->box = *box;
    c->has_box = 1;
    c->length = tl_v3_sub(box->hi, box->lo);
  }
  c->n_gauss = gauss_points;
#ifdef _OPENMP
  c->n_threads = omp_get_max_threads();
#else
  c->n_threads = 1;
#endif
  TlStatus s = tl_calloc(&c->work, (size_t)c->n_threads, sizeof(TlCGWork));
  if (s != TL_OK) {
    tl_free(&c);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  *cg = c;
  return TL_OK;
}

static void bins_free(TlCGBins *b)
{
  tl_free(&b->start);
  tl_free(&b->index);
  tl_free(&b->cell_of);
}

void tl_cg_destroy(TlCG **cg)
{
  if (!cg || !*cg) return;
  TlCG *c = *cg;
  for (int k = 0; k < 3; ++k) bins_free(&c->bins[k]);
  tl_free(&c->la);
  tl_free(&c->lb);
  tl_free(&c->lf);
  tl_free(&c->lmid);
  for (int t = 0; t < c->n_threads; ++t) tl_free(&c->work[t].cand);
  tl_free(&c->work);
  tl_free(&c->mvv);
  tl_free(cg);
}

static TlStatus bins_build(const TlCG *c, TlCGBins *b, size_t n, const TlVec3 *centre, double reach)
{
  b->n_src = n;
  /* extent */
  TlVec3 lo = tl_v3(0, 0, 0), hi = tl_v3(0, 0, 0);
  if (n > 0) lo = hi = centre[0];
  for (size_t i = 1; i < n; ++i) {
    lo = tl_v3(fmin(lo.x, centre[i].x), fmin(lo.y, centre[i].y), fmin(lo.z, centre[i].z));
    hi = tl_v3(fmax(hi.x, centre[i].x), fmax(hi.y, centre[i].y), fmax(hi.z, centre[i].z));
  }
  double size = reach;
  size_t limit = 4 * n + 64;
  for (;;) {
    size_t total = 1;
    for (int d = 0; d < 3; ++d) {
      double *blo = &b->lo.x, *bcell = &b->cell.x;
      if (c->has_box && c->box.periodic[d]) {
        double L = (&c->length.x)[d];
        int m = (int)fmax(1.0, floor(L / size));
        blo[d] = (&c->box.lo.x)[d];
        bcell[d] = L / m;
        b->n[d] = m;
      } else {
        double ext = (&hi.x)[d] - (&lo.x)[d];
        double m = floor(ext / size) + 1.0;
        if (m > 1e6) m = 1e6;
        blo[d] = (&lo.x)[d];
        bcell[d] = size;
        b->n[d] = (int)m;
      }
      total *= (size_t)b->n[d];
    }
    if (total <= limit) {
      b->n_cells = total;
      break;
    }
    size *= 1.25;
  }
  TL_CHECK(tl_array_reserve(&b->start, &b->cap_cells, b->n_cells + 1, sizeof(size_t)));
  TL_CHECK(tl_array_reserve(&b->index, &b->cap_index, n ? n : 1, sizeof(size_t)));
  TL_CHECK(tl_array_reserve(&b->cell_of, &b->cap_cell_of, n ? n : 1, sizeof(size_t)));
  memset(b->start, 0, (b->n_cells + 1) * sizeof(size_t));
  for (size_t i = 0; i < n; ++i) {
    long ci[3];
    for (int d = 0; d < 3; ++d) {
      ci[d] = tl_cg_bin_coord(c, b, d, (&centre[i].x)[d]);
      if (ci[d] < 0) ci[d] = 0;
      if (ci[d] >= b->n[d]) ci[d] = b->n[d] - 1;
    }
    size_t cell = (size_t)ci[0] + (size_t)b->n[0] * ((size_t)ci[1] + (size_t)b->n[1] * (size_t)ci[2]);
    b->cell_of[i] = cell;
    b->start[cell + 1]++;
  }
  for (size_t k = 0; k < b->n_cells; ++k) b->start[k + 1] += b->start[k];
  for (size_t i = 0; i < n; ++i) b->index[b->start[b->cell_of[i]]++] = i;
  for (size_t k = b->n_cells; k > 0; --k) b->start[k] = b->start[k - 1];
  b->start[0] = 0;
  return TL_OK;
}

TlStatus tl_cg_check_finite(const char *what, size_t n, const TlVec3 *x)
{
  for (size_t i = 0; i < n; ++i)
    if (!tl_v3_isfinite(x[i]))
      TL_ERROR(TL_ERR_NUMERIC, "%s %zu is not finite (%g, %g, %g)", what, i, x[i].x, x[i].y, x[i].z);
  return TL_OK;
}

TlStatus tl_cg_set_data(TlCG *c, const TlCGParticleArrays *particles, const TlCGContactArrays *contacts,
                        const TlCGWallContactArrays *walls)
{
  static const TlCGParticleArrays no_particles;
  static const TlCGContactArrays no_contacts;
  static const TlCGWallContactArrays no_walls;
  const TlCGParticleArrays *p = particles ? particles : &no_particles;
  const TlCGContactArrays *k = contacts ? contacts : &no_contacts;
  const TlCGWallContactArrays *w = walls ? walls : &no_walls;
  if ((p->n && (!p->x || !p->mass)) || (k->n && (!k->x || !k->branch || !k->force)) ||
      (w->n && (!w->point || !w->force)))
    TL_ERROR(TL_ERR_ARG, "CG data: a non-empty set lacks positions, masses, branches or forces");
  TL_CHECK(tl_cg_check_finite("particle position", p->n, p->x));
  for (size_t i = 0; i < p->n; ++i)
    if (!(p->mass[i] >= 0.0) || !isfinite(p->mass[i]))
      TL_ERROR(TL_ERR_ARG, "particle %zu has mass %g (must be non-negative and finite)", i, p->mass[i]);
  if (p->v) TL_CHECK(tl_cg_check_finite("particle velocity", p->n, p->v));
  TL_CHECK(tl_cg_check_finite("contact centre", k->n, k->x));
  TL_CHECK(tl_cg_check_finite("contact branch", k->n, k->branch));
  TL_CHECK(tl_cg_check_finite("contact force", k->n, k->force));
  TL_CHECK(tl_cg_check_finite("wall contact point", w->n, w->point));
  TL_CHECK(tl_cg_check_finite("wall contact force", w->n, w->force));
  if (w->centre) TL_CHECK(tl_cg_check_finite("wall contact centre", w->n, w->centre));
  c->particles = *p;
  c->walls = *w;

  /* line sources: contacts, then wall contacts with a centre */
  size_t nl = k->n + (w->centre ? w->n : 0);
  if (nl > c->cap_lines) {
    size_t cap = c->cap_lines;
    TL_CHECK(tl_array_reserve(&c->la, &cap, nl, sizeof(TlVec3)));
    cap = c->cap_lines;
    TL_CHECK(tl_array_reserve(&c->lb, &cap, nl, sizeof(TlVec3)));
    cap = c->cap_lines;
    TL_CHECK(tl_array_reserve(&c->lf, &cap, nl, sizeof(TlVec3)));
    cap = c->cap_lines;
    TL_CHECK(tl_array_reserve(&c->lmid, &cap, nl, sizeof(TlVec3)));
    c->cap_lines = cap;
  }
  c->n_lines = nl;
  double hb = 0.0;
  for (size_t i = 0; i < k->n; ++i) {
    c->la[i] = k->x[i];
    c->lb[i] = k->branch[i];
    c->lf[i] = k->force[i];
  }
  if (w->centre)
    for (size_t i = 0; i < w->n; ++i) {
      size_t j = k->n + i;
      c->la[j] = w->centre[i];
      c->lb[j] = tl_cg_nearest_image(c, tl_v3_sub(w->point[i], w->centre[i]));
      c->lf[j] = w->force[i];
    }
  for (size_t i = 0; i < nl; ++i) {
    c->lmid[i] = tl_v3_axpy(c->la[i], 0.5, c->lb[i]);
    hb = fmax(hb, 0.5 * tl_v3_norm(c->lb[i]));
  }
  c->max_half_branch = hb;

  if (tl_cg_kernel_is_dirac(c->kernel)) return TL_OK; /* grid deposits need no bins */
  double cw = c->kernel->c;
  if (c->has_box)
    for (int d = 0; d < 3; ++d)
      if (c->box.periodic[d] && (&c->length.x)[d] < 2.0 * (cw + hb))
        TL_ERROR(TL_ERR_ARG,
                 "periodic length %g along direction %d is below 2 (c + |b|max/2) = %g: a source would meet itself",
                 (&c->length.x)[d], d, 2.0 * (cw + hb));
  if (c->hgrid && c->hgrid->n_particles != p->n)
    TL_ERROR(TL_ERR_ARG, "the hierarchical grid holds %zu particles, the CG data %zu", c->hgrid->n_particles, p->n);
  if (!c->hgrid) TL_CHECK(bins_build(c, &c->bins[0], p->n, p->x, cw));
  else c->bins[0].n_src = p->n; /* the brute-force oracle still visits them all */
  TL_CHECK(bins_build(c, &c->bins[1], nl, c->lmid, cw + hb));
  TL_CHECK(bins_build(c, &c->bins[2], w->n, w->point, cw));
  return TL_OK;
}

TlStatus tl_cg_use_hgrid(TlCG *c, const TlHGrid *grid)
{
  c->hgrid = grid;
  return TL_OK;
}
