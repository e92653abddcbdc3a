#include "tl_cg_fields.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "tl_memory.h"
#ifdef _OPENMP
#include <omp.h>
#endif

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

/* ---------------------------------------------------------------- fields */

TlStatus tl_cg_fields_create(size_t n, unsigned which, TlCGFields **fields)
{
  *fields = NULL;
  if (which == 0 || (which & ~(unsigned)TL_CG_ALL))
    TL_ERROR(TL_ERR_ARG, "field mask 0x%x is empty or has unknown bits (known 0x%x)", which, (unsigned)TL_CG_ALL);
  /* velocity needs the density, the kinetic stress the velocity */
  if (which & TL_CG_STRESS_KINETIC) which |= TL_CG_MOMENTUM;
  if (which & TL_CG_MOMENTUM) which |= TL_CG_DENSITY;
  TlCGFields *f;
  TL_CHECK(TL_NEW(f));
  f->n = n;
  f->which = which;
  TlStatus s = TL_OK;
  size_t m = n ? n : 1;
  if (which & TL_CG_DENSITY) TL_CHECK_GOTO(s, tl_calloc(&f->density, m, sizeof(double)), fail);
  if (which & TL_CG_MOMENTUM) {
    TL_CHECK_GOTO(s, tl_calloc(&f->momentum, m, sizeof(TlVec3)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&f->velocity, m, sizeof(TlVec3)), fail);
  }
  if (which & TL_CG_STRESS_KINETIC) TL_CHECK_GOTO(s, tl_calloc(&f->stress_kinetic, m, sizeof(TlMat3)), fail);
  if (which & TL_CG_STRESS_CONTACT) TL_CHECK_GOTO(s, tl_calloc(&f->stress_contact, m, sizeof(TlMat3)), fail);
  if (which & TL_CG_BOUNDARY_FORCE) TL_CHECK_GOTO(s, tl_calloc(&f->boundary_force, m, sizeof(TlVec3)), fail);
  if (which & TL_CG_FABRIC) TL_CHECK_GOTO(s, tl_calloc(&f->fabric, m, sizeof(TlMat3)), fail);
  *fields = f;
  return TL_OK;
fail:
  tl_cg_fields_destroy(&f);
  return s;
}

void tl_cg_fields_destroy(TlCGFields **fields)
{
  if (!fields || !*fields) return;
  TlCGFields *f = *fields;
  tl_free(&f->density);
  tl_free(&f->momentum);
  tl_free(&f->velocity);
  tl_free(&f->stress_kinetic);
  tl_free(&f->stress_contact);
  tl_free(&f->boundary_force);
  tl_free(&f->fabric);
  tl_free(fields);
}

void tl_cg_fields_zero(TlCGFields *f)
{
  size_t n = f->n;
  if (f->density) memset(f->density, 0, n * sizeof(double));
  if (f->momentum) memset(f->momentum, 0, n * sizeof(TlVec3));
  if (f->velocity) memset(f->velocity, 0, n * sizeof(TlVec3));
  if (f->stress_kinetic) memset(f->stress_kinetic, 0, n * sizeof(TlMat3));
  if (f->stress_contact) memset(f->stress_contact, 0, n * sizeof(TlMat3));
  if (f->boundary_force) memset(f->boundary_force, 0, n * sizeof(TlVec3));
  if (f->fabric) memset(f->fabric, 0, n * sizeof(TlMat3));
  f->weight = 0.0;
}

static void axpy_d(size_t n, double a, const double *x, double *y)
{
  for (size_t i = 0; i < n; ++i) y[i] += a * x[i];
}

TlStatus tl_cg_fields_accumulate(TlCGFields *avg, const TlCGFields *snap, double weight)
{
  if (avg->n != snap->n)
    TL_ERROR(TL_ERR_ARG, "average has %zu points, snapshot %zu", avg->n, snap->n);
  if ((avg->which & snap->which) != avg->which)
    TL_ERROR(TL_ERR_ARG, "average wants fields 0x%x, snapshot has only 0x%x", avg->which, snap->which);
  if (!(weight >= 0.0) || !isfinite(weight))
    TL_ERROR(TL_ERR_ARG, "time-average weight %g must be non-negative and finite", weight);
  size_t n = avg->n;
  if (avg->density) axpy_d(n, weight, snap->density, avg->density);
  if (avg->momentum) axpy_d(3 * n, weight, &snap->momentum[0].x, &avg->momentum[0].x);
  if (avg->stress_kinetic) axpy_d(9 * n, weight, &snap->stress_kinetic[0].m[0][0], &avg->stress_kinetic[0].m[0][0]);
  if (avg->stress_contact) axpy_d(9 * n, weight, &snap->stress_contact[0].m[0][0], &avg->stress_contact[0].m[0][0]);
  if (avg->boundary_force) axpy_d(3 * n, weight, &snap->boundary_force[0].x, &avg->boundary_force[0].x);
  if (avg->fabric) axpy_d(9 * n, weight, &snap->fabric[0].m[0][0], &avg->fabric[0].m[0][0]);
  avg->weight += weight;
  return TL_OK;
}

TlStatus tl_cg_fields_average_finish(TlCGFields *avg)
{
  if (!(avg->weight > 0.0)) TL_ERROR(TL_ERR_STATE, "time average has total weight %g: nothing accumulated", avg->weight);
  double s = 1.0 / avg->weight;
  size_t n = avg->n;
  if (avg->density) for (size_t i = 0; i < n; ++i) avg->density[i] *= s;
  if (avg->momentum) for (size_t i = 0; i < n; ++i) avg->momentum[i] = tl_v3_scale(avg->momentum[i], s);
  if (avg->stress_kinetic) for (size_t i = 0; i < n; ++i) avg->stress_kinetic[i] = tl_m3_scale(avg->stress_kinetic[i], s);
  if (avg->stress_contact) for (size_t i = 0; i < n; ++i) avg->stress_contact[i] = tl_m3_scale(avg->stress_contact[i], s);
  if (avg->boundary_force) for (size_t i = 0; i < n; ++i) avg->boundary_force[i] = tl_v3_scale(avg->boundary_force[i], s);
  if (avg->fabric) for (size_t i = 0; i < n; ++i) avg->fabric[i] = tl_m3_scale(avg->fabric[i], s);
  if (avg->velocity)
    for (size_t i = 0; i < n; ++i)
      avg->velocity[i] = avg->density && avg->density[i] > 0.0 ? tl_v3_scale(avg->momentum[i], 1.0 / avg->density[i])
                                                              : tl_v3(0, 0, 0);
  avg->weight = 1.0;
  return TL_OK;
}

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

/* Nearest image of a displacement along the periodic directions. */
static inline TlVec3 nearest_image(const TlCG *c, TlVec3 d)
{
  if (!c->has_box) return d;
  double *v = &d.x;
  const double *len = &c->length.x;
  for (int k = 0; k < 3; ++k)
    if (c->box.periodic[k]) v[k] -= len[k] * nearbyint(v[k] / len[k]);
  return d;
}

static inline int wrap_index(long i, int n) { return (int)(((i % n) + n) % n); }

/* Cell coordinate of a point along direction d (unwrapped, unclamped). */
static inline long bin_coord(const TlCG *c, const TlCGBins *b, int d, double x)
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
      ci[d] = bin_coord(c, b, d, (&centre[i].x)[d]);
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

static TlStatus check_finite_array(const char *what, size_t n, const TlVec3 *x)
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
  TL_CHECK(check_finite_array("particle position", p->n, p->x));
  for (size_t i = 0; i < p->n; ++i)
    if (!(p->mass[i] >= 0.0) || !isfinite(p->mass[i]))
      TL_ERROR(TL_ERR_ARG, "particle %zu has mass %g (must be non-negative and finite)", i, p->mass[i]);
  if (p->v) TL_CHECK(check_finite_array("particle velocity", p->n, p->v));
  TL_CHECK(check_finite_array("contact centre", k->n, k->x));
  TL_CHECK(check_finite_array("contact branch", k->n, k->branch));
  TL_CHECK(check_finite_array("contact force", k->n, k->force));
  TL_CHECK(check_finite_array("wall contact point", w->n, w->point));
  TL_CHECK(check_finite_array("wall contact force", w->n, w->force));
  if (w->centre) TL_CHECK(check_finite_array("wall contact centre", w->n, w->centre));
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
      c->lb[j] = nearest_image(c, tl_v3_sub(w->point[i], w->centre[i]));
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

/* Candidate cells of a point: up to 3 per direction, deduplicated. */
static int neighbour_cells(const TlCG *c, const TlCGBins *b, TlVec3 x, size_t *cells)
{
  int list[3][3], cnt[3];
  for (int d = 0; d < 3; ++d) {
    long i0 = bin_coord(c, b, d, (&x.x)[d]);
    cnt[d] = 0;
    int periodic = c->has_box && c->box.periodic[d];
    for (long di = -1; di <= 1; ++di) {
      long i = i0 + di;
      if (periodic) i = wrap_index(i, b->n[d]);
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

/* The part of the segment s in [0, 1] where |d - s b| < c, as a line piece
 * |d - s b|^2 = A s^2 + B s + C on [s0, s1]; 0 when the segment misses the
 * support. */
static inline int line_piece(TlVec3 d, TlVec3 b, double c2, double *A, double *B, double *C, double *s0, double *s1)
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
    TlVec3 d = nearest_image(c, tl_v3_sub(x, p->x[i]));                         \
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
      TlVec3 d = tl_v3_axpy(nearest_image(c, tl_v3_sub(x, c->lmid[i])), 0.5, b);
      double A, B, C, s0, s1;
      if (line_piece(d, b, c2, &A, &B, &C, &s0, &s1)) {
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
      double r2 = tl_v3_norm2(nearest_image(c, tl_v3_sub(x, c->walls.point[i])));
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

TlStatus tl_cg_use_hgrid(TlCG *c, const TlHGrid *grid)
{
  c->hgrid = grid;
  return TL_OK;
}

TlStatus tl_cg_evaluate_points(TlCG *c, size_t n, const TlVec3 *points, TlCGFields *out)
{
  TL_CHECK(check_finite_array("evaluation point", n, points));
  TL_CHECK(evaluate_points(c, n, points, NULL, 0, out));
  return TL_OK;
}

TlStatus tl_cg_evaluate_points_brute_force(TlCG *c, size_t n, const TlVec3 *points, TlCGFields *out)
{
  TL_CHECK(check_finite_array("evaluation point", n, points));
  TL_CHECK(evaluate_points(c, n, points, NULL, 1, out));
  return TL_OK;
}

/* ------------------------------------------------ Dirac: cell averages */

typedef struct {
  const TlCGGrid *g;
  int wrap[3]; /* periodic direction that the grid spans exactly */
  double inv_volume;
} TlCGDeposit;

/* Node owning point x, or -1 outside the grid. */
static long long deposit_node(const TlCGDeposit *dp, TlVec3 x)
{
  const TlCGGrid *g = dp->g;
  long idx[3];
  for (int d = 0; d < 3; ++d) {
    long i = (long)floor(((&x.x)[d] - (&g->lo.x)[d]) / (&g->h.x)[d] + 0.5);
    if (dp->wrap[d]) i = wrap_index(i, g->n[d]);
    if (i < 0 || i >= g->n[d]) return -1;
    idx[d] = i;
  }
  return idx[0] + (long long)g->n[0] * (idx[1] + (long long)g->n[1] * idx[2]);
}

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static TlStatus evaluate_dirac_grid(TlCG *c, const TlCGGrid *g, TlCGFields *out)
{
  TlCGDeposit dp = {g, {0, 0, 0}, 1.0 / (g->h.x * g->h.y * g->h.z)};
  if (c->has_box)
    for (int d = 0; d < 3; ++d)
      dp.wrap[d] = c->box.periodic[d] &&
                   fabs(g->n[d] * (&g->h.x)[d] - (&c->length.x)[d]) <= 1e-12 * (&c->length.x)[d];
  unsigned which = out->which;
  const TlCGParticleArrays *p = &c->particles;
  TlMat3 *mvv = NULL;
  if (which & TL_CG_STRESS_KINETIC) TL_CHECK(tl_calloc(&mvv, out->n, sizeof(TlMat3)));
  double *rho = out->density;
  if (!rho && (which & (TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC))) {
    tl_free(&mvv);
    TL_ERROR(TL_ERR_ARG, "velocity and kinetic stress on a grid need the density field as well (TL_CG_DENSITY)");
  }
  for (size_t i = 0; i < p->n; ++i) {
    long long node = deposit_node(&dp, p->x[i]);
    if (node < 0) continue;
    double m = p->mass[i] * dp.inv_volume;
    if (rho) rho[node] += m;
    if (p->v && out->momentum) out->momentum[node] = tl_v3_axpy(out->momentum[node], m, p->v[i]);
    if (p->v && mvv) mvv[node] = tl_m3_add(mvv[node], tl_m3_scale(tl_m3_outer(p->v[i], p->v[i]), m));
  }
  for (size_t n = 0; n < out->n; ++n) {
    TlVec3 V = rho && rho[n] > 0.0 && out->momentum ? tl_v3_scale(out->momentum[n], 1.0 / rho[n]) : tl_v3(0, 0, 0);
    if (out->velocity) out->velocity[n] = V;
    if (mvv && rho[n] > 0.0) {
      TlVec3 j = tl_v3_scale(V, rho[n]);
      out->stress_kinetic[n] = tl_m3_add(tl_m3_scale(mvv[n], -1.0), tl_m3_outer(j, V));
    }
  }
  tl_free(&mvv);
  if (out->boundary_force)
    for (size_t i = 0; i < c->walls.n; ++i) {
      long long node = deposit_node(&dp, c->walls.point[i]);
      if (node >= 0) out->boundary_force[node] = tl_v3_axpy(out->boundary_force[node], -dp.inv_volume, c->walls.force[i]);
    }
  if (which & (TL_CG_STRESS_CONTACT | TL_CG_FABRIC)) {
    double t[TL_CG_MAX_CROSSINGS];
    for (size_t i = 0; i < c->n_lines; ++i) {
      TlVec3 a = c->la[i], b = c->lb[i];
      int m = 0;
      t[m++] = 0.0;
      t[m++] = 1.0;
      for (int d = 0; d < 3; ++d) {
        double bd = (&b.x)[d], ad = (&a.x)[d], h = (&g->h.x)[d], lo = (&g->lo.x)[d] - 0.5 * h;
        if (bd == 0.0) continue;
        double u0 = (ad - lo) / h, u1 = (ad + bd - lo) / h; /* cell-boundary coordinate */
        for (double k = ceil(fmin(u0, u1)); k <= floor(fmax(u0, u1)); k += 1.0) {
          if (m == TL_CG_MAX_CROSSINGS)
            TL_ERROR(TL_ERR_ARG, "contact %zu: branch vector of length %g crosses more than %d grid cells",
                     i, tl_v3_norm(b), TL_CG_MAX_CROSSINGS);
          double s = (lo + k * h - ad) / bd;
          if (s > 0.0 && s < 1.0) t[m++] = s;
        }
      }
      qsort(t, (size_t)m, sizeof(double), cmp_double);
      TlMat3 fb = tl_m3_outer(c->lf[i], b);
      TlVec3 nb = tl_v3_normalize(b);
      TlMat3 nn = tl_m3_outer(nb, nb);
      for (int k = 0; k + 1 < m; ++k) {
        double len = t[k + 1] - t[k];
        if (len <= 0.0) continue;
        long long node = deposit_node(&dp, tl_v3_axpy(a, 0.5 * (t[k] + t[k + 1]), b));
        if (node < 0) continue;
        if (out->stress_contact) out->stress_contact[node] = tl_m3_add(out->stress_contact[node], tl_m3_scale(fb, len * dp.inv_volume));
        if (out->fabric) out->fabric[node] = tl_m3_add(out->fabric[node], tl_m3_scale(nn, len * dp.inv_volume));
      }
    }
  }
  return TL_OK;
}

/* ------------------------------------------- smooth kernels on a grid */

/* Grid scatter: every source visits the nodes within its reach (its
 * bounding box enlarged by c, for each periodic image that reaches the
 * grid), so a grid costs O(sources x nodes per kernel) with no search.
 * Threads own slabs of node layers along z and each visits every source
 * whose box meets its slab: no two threads write the same node. */
typedef struct {
  int i0[3], i1[3];
  TlVec3 shift;
} TlCGImageBox;

static int image_boxes(const TlCG *c, const TlCGGrid *g, TlVec3 blo, TlVec3 bhi, int k0, int k1, TlCGImageBox *out)
{
  int span[3];
  for (int d = 0; d < 3; ++d) span[d] = c->has_box && c->box.periodic[d] ? 1 : 0;
  int m = 0;
  for (int sz = -span[2]; sz <= span[2]; ++sz)
    for (int sy = -span[1]; sy <= span[1]; ++sy)
      for (int sx = -span[0]; sx <= span[0]; ++sx) {
        TlVec3 sh = tl_v3(sx * c->length.x, sy * c->length.y, sz * c->length.z);
        TlCGImageBox b;
        b.shift = sh;
        int empty = 0;
        for (int d = 0; d < 3 && !empty; ++d) {
          double glo = (&g->lo.x)[d], h = (&g->h.x)[d];
          double a = ceil(((&blo.x)[d] + (&sh.x)[d] - glo) / h), z = floor(((&bhi.x)[d] + (&sh.x)[d] - glo) / h);
          double lo_lim = d == 2 ? k0 : 0, hi_lim = d == 2 ? k1 - 1 : g->n[d] - 1;
          a = fmax(a, lo_lim);
          z = fmin(z, hi_lim);
          if (!(a <= z)) empty = 1;
          else {
            b.i0[d] = (int)a;
            b.i1[d] = (int)z;
          }
        }
        if (!empty) out[m++] = b;
      }
  return m;
}

static TlStatus scatter_particle(const TlCG *c, TlCGWork *w, size_t i, TlCGFields *out, TlMat3 *mvv)
{
  if (!w->count) return TL_OK;
  TL_CHECK(tl_cg_kernel_eval(c->kernel, w->count, w->r2, w->w, NULL));
  const TlCGParticleArrays *p = &c->particles;
  double m = p->mass[i];
  TlVec3 v = p->v ? p->v[i] : tl_v3(0, 0, 0);
  TlMat3 vv = tl_m3_outer(v, v);
  for (size_t e = 0; e < w->count; ++e) {
    size_t n = w->src[e];
    double mw = m * w->w[e];
    if (out->density) out->density[n] += mw;
    if (out->momentum) out->momentum[n] = tl_v3_axpy(out->momentum[n], mw, v);
    if (mvv) mvv[n] = tl_m3_add(mvv[n], tl_m3_scale(vv, mw));
  }
  w->count = 0;
  return TL_OK;
}

static TlStatus scatter_line(const TlCG *c, TlCGWork *w, size_t i, TlCGFields *out)
{
  if (!w->count) return TL_OK;
  TL_CHECK(tl_cg_kernel_line_integral(c->kernel, w->count, w->r2, w->aux, w->lc, w->ls0, w->ls1, c->n_gauss, w->w));
  TlMat3 fb = tl_m3_outer(c->lf[i], c->lb[i]);
  TlVec3 nb = tl_v3_normalize(c->lb[i]);
  TlMat3 nn = tl_m3_outer(nb, nb);
  for (size_t e = 0; e < w->count; ++e) {
    size_t n = w->src[e];
    double s = w->w[e];
    if (out->stress_contact) out->stress_contact[n] = tl_m3_add(out->stress_contact[n], tl_m3_scale(fb, s));
    if (out->fabric) out->fabric[n] = tl_m3_add(out->fabric[n], tl_m3_scale(nn, s));
  }
  w->count = 0;
  return TL_OK;
}

static TlStatus scatter_wall(const TlCG *c, TlCGWork *w, size_t i, TlCGFields *out)
{
  if (!w->count) return TL_OK;
  TL_CHECK(tl_cg_kernel_eval(c->kernel, w->count, w->r2, w->w, NULL));
  for (size_t e = 0; e < w->count; ++e)
    out->boundary_force[w->src[e]] = tl_v3_axpy(out->boundary_force[w->src[e]], -w->w[e], c->walls.force[i]);
  w->count = 0;
  return TL_OK;
}

#define TL_CG_FOR_BOX_NODES(g, b, node, pos, ...)                                                  \
  for (int k_ = (b).i0[2]; k_ <= (b).i1[2]; ++k_)                                                  \
    for (int j_ = (b).i0[1]; j_ <= (b).i1[1]; ++j_)                                                \
      for (int i_ = (b).i0[0]; i_ <= (b).i1[0]; ++i_) {                                            \
        size_t node = (size_t)i_ + (size_t)(g)->n[0] * ((size_t)j_ + (size_t)(g)->n[1] * (size_t)k_); \
        TlVec3 pos = tl_cg_grid_node((g), i_, j_, k_);                                             \
        __VA_ARGS__                                                                                \
      }

static TlStatus scatter_slab(const TlCG *c, TlCGWork *w, const TlCGGrid *g, int k0, int k1, TlCGFields *out,
                             TlMat3 *mvv)
{
  unsigned which = out->which;
  const double cw = c->kernel->c, c2 = cw * cw;
  TlCGImageBox boxes[27];
  if (which & (TL_CG_DENSITY | TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC)) {
    const TlCGParticleArrays *p = &c->particles;
    for (size_t i = 0; i < p->n; ++i) {
      TlVec3 x = p->x[i];
      int nb = image_boxes(c, g, tl_v3(x.x - cw, x.y - cw, x.z - cw), tl_v3(x.x + cw, x.y + cw, x.z + cw), k0, k1, boxes);
      w->count = 0;
      for (int q = 0; q < nb; ++q) {
        TlVec3 xs = tl_v3_add(x, boxes[q].shift);
        TL_CG_FOR_BOX_NODES(g, boxes[q], node, pos, {
          double r2 = tl_v3_norm2(tl_v3_sub(pos, xs));
          if (r2 < c2) {
            if (w->count == TL_CG_CHUNK) TL_CHECK(scatter_particle(c, w, i, out, mvv));
            w->r2[w->count] = r2;
            w->src[w->count++] = node;
          }
        })
      }
      TL_CHECK(scatter_particle(c, w, i, out, mvv));
    }
  }
  if (which & (TL_CG_STRESS_CONTACT | TL_CG_FABRIC)) {
    for (size_t i = 0; i < c->n_lines; ++i) {
      TlVec3 a = c->la[i], b = c->lb[i], e = tl_v3_add(a, b);
      if (!(tl_v3_norm2(b) > 0.0)) continue;
      TlVec3 blo = tl_v3(fmin(a.x, e.x) - cw, fmin(a.y, e.y) - cw, fmin(a.z, e.z) - cw);
      TlVec3 bhi = tl_v3(fmax(a.x, e.x) + cw, fmax(a.y, e.y) + cw, fmax(a.z, e.z) + cw);
      int nb = image_boxes(c, g, blo, bhi, k0, k1, boxes);
      w->count = 0;
      for (int q = 0; q < nb; ++q) {
        TlVec3 as = tl_v3_add(a, boxes[q].shift);
        TL_CG_FOR_BOX_NODES(g, boxes[q], node, pos, {
          double A, B, C, s0, s1;
          if (line_piece(tl_v3_sub(pos, as), b, c2, &A, &B, &C, &s0, &s1)) {
            if (w->count == TL_CG_CHUNK) TL_CHECK(scatter_line(c, w, i, out));
            w->r2[w->count] = A;
            w->aux[w->count] = B;
            w->lc[w->count] = C;
            w->ls0[w->count] = s0;
            w->ls1[w->count] = s1;
            w->src[w->count++] = node;
          }
        })
      }
      TL_CHECK(scatter_line(c, w, i, out));
    }
  }
  if (which & TL_CG_BOUNDARY_FORCE) {
    for (size_t i = 0; i < c->walls.n; ++i) {
      TlVec3 x = c->walls.point[i];
      int nb = image_boxes(c, g, tl_v3(x.x - cw, x.y - cw, x.z - cw), tl_v3(x.x + cw, x.y + cw, x.z + cw), k0, k1, boxes);
      w->count = 0;
      for (int q = 0; q < nb; ++q) {
        TlVec3 xs = tl_v3_add(x, boxes[q].shift);
        TL_CG_FOR_BOX_NODES(g, boxes[q], node, pos, {
          double r2 = tl_v3_norm2(tl_v3_sub(pos, xs));
          if (r2 < c2) {
            if (w->count == TL_CG_CHUNK) TL_CHECK(scatter_wall(c, w, i, out));
            w->r2[w->count] = r2;
            w->src[w->count++] = node;
          }
        })
      }
      TL_CHECK(scatter_wall(c, w, i, out));
    }
  }
  /* velocity and kinetic stress of the slab's nodes */
  size_t layer = (size_t)g->n[0] * (size_t)g->n[1];
  for (size_t n = (size_t)k0 * layer; n < (size_t)k1 * layer; ++n) {
    double rho = out->density ? out->density[n] : 0.0;
    if (!out->momentum) continue;
    TlVec3 V = rho > 0.0 ? tl_v3_scale(out->momentum[n], 1.0 / rho) : tl_v3(0, 0, 0);
    out->velocity[n] = V;
    if (mvv) out->stress_kinetic[n] = tl_m3_add(tl_m3_scale(mvv[n], -1.0), tl_m3_outer(out->momentum[n], V));
  }
  return TL_OK;
}

static TlStatus evaluate_grid_scatter(TlCG *c, const TlCGGrid *g, TlCGFields *out)
{
  unsigned which = out->which;
  if ((which & (TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC)) && c->particles.n && !c->particles.v)
    TL_ERROR(TL_ERR_ARG, "momentum or kinetic stress asked for, but no particle velocities were given");
  TlMat3 *mvv = NULL;
  if (which & TL_CG_STRESS_KINETIC) {
    TL_CHECK(tl_array_reserve(&c->mvv, &c->cap_mvv, out->n, sizeof(TlMat3)));
    memset(c->mvv, 0, out->n * sizeof(TlMat3));
    mvv = c->mvv;
  }
  TlStatus status = TL_OK;
  int nz = g->n[2];
#pragma omp parallel num_threads(c->n_threads)
  {
    int t = 0, nt = 1;
#ifdef _OPENMP
    t = omp_get_thread_num();
    nt = omp_get_num_threads();
#endif
    if (t < c->n_threads) {
      int used = nt < c->n_threads ? nt : c->n_threads;
      int k0 = (int)((long)nz * t / used), k1 = (int)((long)nz * (t + 1) / used);
      TlStatus s = k1 > k0 ? scatter_slab(c, &c->work[t], g, k0, k1, out, mvv) : TL_OK;
      if (s != TL_OK) {
#pragma omp critical(tl_cg_error)
        if (status == TL_OK) status = s;
      }
    }
  }
  if (status != TL_OK) return tl_error_trace(status, __FILE__, __LINE__);
  return TL_OK;
}

TlStatus tl_cg_evaluate_grid(TlCG *c, const TlCGGrid *g, TlCGFields *out)
{
  for (int d = 0; d < 3; ++d) {
    if (g->n[d] < 1) TL_ERROR(TL_ERR_ARG, "grid has %d nodes along direction %d (need >= 1)", g->n[d], d);
    if (!((&g->h.x)[d] > 0.0) || !isfinite((&g->h.x)[d]))
      TL_ERROR(TL_ERR_ARG, "grid spacing %g along direction %d must be positive", (&g->h.x)[d], d);
  }
  size_t nodes = (size_t)g->n[0] * (size_t)g->n[1] * (size_t)g->n[2];
  if (out->n != nodes) TL_ERROR(TL_ERR_ARG, "fields hold %zu points, the grid has %zu nodes", out->n, nodes);
  tl_cg_fields_zero(out);
  if (tl_cg_kernel_is_dirac(c->kernel)) {
    TL_CHECK(evaluate_dirac_grid(c, g, out));
  } else {
    TL_CHECK(evaluate_grid_scatter(c, g, out));
  }
  out->weight = 1.0;
  return TL_OK;
}
