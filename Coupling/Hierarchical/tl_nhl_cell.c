/* A periodic DEM cell as a numerically homogenised law: the loading path
 * (Eqs. 3, 16-18), the relaxation (Eq. 19), the stress (Eq. 27) and the
 * committed and trial states, kept as checkpoints in memory. */
#include "tl_nhl_cell.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "tl_memory.h"
#include "tl_timer.h"

/* What the world holds at the moment (saves a restore when it already
 * holds the state asked for). */
enum { WORLD_OTHER = 0, WORLD_COMMITTED, WORLD_TRIAL };

/* A builder context shared by a cell and its copies. */
typedef struct {
  TlNhlBuildFn build;
  void *ctx;
  int refs;
  void (*free_ctx)(void *ctx);
} Builder;

struct TlNhlCell {
  Builder *builder;
  TlNhlWorld world;
  TlNhlCellSettings set;
  TlMat3 h_ref, h_ref_inv;
  double d_mean, rho;
  TlCheckpointMemory *committed, *trial;
  int has_trial, world_state;
  TlMat3 F_c, sigma_c, F_t, sigma_t;
};

void tl_nhl_cell_settings_default(TlNhlCellSettings *s)
{
  s->inertial = 1e-4;
  s->tolerance = 1e-3;
  s->max_relax_steps = 1000000;
  s->check_every = 20;
  s->min_drive_steps = 20;
  s->criterion = TL_NHL_EQUILIBRIUM_IMBALANCE;
  s->pressure_tolerance = 1e-4;
  s->pressure_window = 10;
}

TlStatus tl_nhl_cell_settings_check(const TlNhlCellSettings *s)
{
  if (!(s->inertial > 0.0 && s->inertial <= 1.0))
    TL_ERROR(TL_ERR_ARG, "NHL cell: inertial number I = %g outside (0, 1] (seeds/004 uses 1e-4)", s->inertial);
  if (!(s->tolerance > 0.0 && s->tolerance <= 1.0))
    TL_ERROR(TL_ERR_ARG, "NHL cell: equilibrium tolerance eps_R = %g outside (0, 1] (seeds/004 uses 1e-3)", s->tolerance);
  if (s->max_relax_steps < 0) TL_ERROR(TL_ERR_ARG, "NHL cell: max_relax_steps = %ld must be >= 0", s->max_relax_steps);
  if (s->check_every < 1 || s->check_every > 1000000)
    TL_ERROR(TL_ERR_ARG, "NHL cell: check_every = %ld outside [1, 1e6] steps", s->check_every);
  if (s->min_drive_steps < 1) TL_ERROR(TL_ERR_ARG, "NHL cell: min_drive_steps = %ld must be >= 1", s->min_drive_steps);
  if (s->criterion != TL_NHL_EQUILIBRIUM_IMBALANCE && s->criterion != TL_NHL_EQUILIBRIUM_PRESSURE)
    TL_ERROR(TL_ERR_ARG, "NHL cell: equilibrium criterion %d is neither 0 (Eq. 19) nor 1 (pressure window)", (int)s->criterion);
  if (!(s->pressure_tolerance > 0.0 && s->pressure_tolerance < 1.0))
    TL_ERROR(TL_ERR_ARG, "NHL cell: pressure_tolerance = %g outside (0, 1)", s->pressure_tolerance);
  if (s->pressure_window < 2 || s->pressure_window > 64)
    TL_ERROR(TL_ERR_ARG, "NHL cell: pressure_window = %ld outside [2, 64] checks", s->pressure_window);
  return TL_OK;
}

/* ---------------------------------------------------------------- helpers */
TlMat3 tl_nhl_cauchy_to_pk2(TlMat3 F, TlMat3 sigma)
{
  TlMat3 Fi;
  tl_m3_inverse(F, &Fi);
  return tl_m3_scale(tl_m3_mul(tl_m3_mul(Fi, sigma), tl_m3_transpose(Fi)), tl_m3_det(F));
}

TlMat3 tl_nhl_pk2_to_cauchy(TlMat3 F, TlMat3 S)
{
  return tl_m3_scale(tl_m3_mul(tl_m3_mul(F, S), tl_m3_transpose(F)), 1.0 / tl_m3_det(F));
}

/* Eigenvalues of a symmetric 3x3 matrix, descending (the trigonometric
 * closed form). */
static void sym_eigenvalues(TlMat3 a, double e[3])
{
  const double p1 = a.m[0][1] * a.m[0][1] + a.m[0][2] * a.m[0][2] + a.m[1][2] * a.m[1][2];
  const double q = tl_m3_trace(a) / 3.0;
  if (p1 <= 1e-300) {
    e[0] = a.m[0][0], e[1] = a.m[1][1], e[2] = a.m[2][2];
  } else {
    const double p2 = (a.m[0][0] - q) * (a.m[0][0] - q) + (a.m[1][1] - q) * (a.m[1][1] - q) +
                      (a.m[2][2] - q) * (a.m[2][2] - q) + 2.0 * p1;
    const double p = sqrt(p2 / 6.0);
    TlMat3 B = tl_m3_scale(tl_m3_add(a, tl_m3_scale(tl_m3_identity(), -q)), 1.0 / p);
    double r = 0.5 * tl_m3_det(B);
    r = r < -1.0 ? -1.0 : (r > 1.0 ? 1.0 : r);
    const double phi = acos(r) / 3.0;
    e[0] = q + 2.0 * p * cos(phi);
    e[2] = q + 2.0 * p * cos(phi + 2.0 * TL_PI / 3.0);
    e[1] = 3.0 * q - e[0] - e[2];
  }
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (e[j] > e[i]) {
        double t = e[i];
        e[i] = e[j], e[j] = t;
      }
}

static double frobenius(TlMat3 a)
{
  double s = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s += a.m[i][j] * a.m[i][j];
  return sqrt(s);
}

static double pressure_of(TlMat3 sigma, int dim)
{
  return dim == 2 ? -0.5 * (sigma.m[0][0] + sigma.m[1][1]) : -tl_m3_trace(sigma) / 3.0;
}

/* Keeps the out-of-plane components of a 2-D cell's stress at zero. */
static TlMat3 plane(TlMat3 a, int dim)
{
  if (dim == 2) a.m[0][2] = a.m[1][2] = a.m[2][0] = a.m[2][1] = a.m[2][2] = 0.0;
  return a;
}

static TlStatus restore(TlNhlCell *c, int which)
{
  if (c->world_state == which) return TL_OK;
  const TlCheckpointMemory *mem = which == WORLD_TRIAL ? c->trial : c->committed;
  TL_CHECK(tl_checkpoint_memory_load(mem, &tl_dem_checkpoint_ops, c->world.dem));
  c->world_state = which;
  return TL_OK;
}

/* Builds a world; one thread per cell without changing the caller's OpenMP
 * default (tl_dem_set_threads also sets omp_set_num_threads). */
static TlStatus build_world(Builder *b, TlNhlWorld *w)
{
  memset(w, 0, sizeof *w);
#ifdef _OPENMP
  const int nt = omp_get_max_threads();
#endif
  TlStatus s = b->build(b->ctx, w);
  if (s == TL_OK && w->dem) {
    tl_dem_set_threads(w->dem, 1);
    tl_dem_track_energy(w->dem, 0);
  }
#ifdef _OPENMP
  omp_set_num_threads(nt);
#endif
  if (s != TL_OK) {
    tl_dem_destroy(&w->dem);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  if (!w->dem || !w->law) TL_ERROR(TL_ERR_ARG, "NHL cell builder returned %s", w->dem ? "no contact law" : "no world");
  if (w->dim != 2 && w->dim != 3) TL_ERROR(TL_ERR_ARG, "NHL cell builder returned dimension %d (2 or 3)", w->dim);
  const TlDomain *D = tl_dem_domain(w->dem);
  if (D->kind != TL_DOMAIN_DEFORMABLE_CELL)
    TL_ERROR(TL_ERR_ARG, "NHL cell: the world's domain is of kind %d; a cell needs a deformable periodic cell "
             "(tl_domain_init_cell)", (int)D->kind);
  return TL_OK;
}

static TlStatus alloc_cell(Builder *b, const TlNhlCellSettings *s, TlNhlCell **cell)
{
  TL_CHECK(tl_nhl_cell_settings_check(s));
  TlNhlCell *c;
  TL_CHECK(TL_NEW(c));
  c->builder = b;
  b->refs++;
  c->set = *s;
  TlStatus st;
  TL_CHECK_GOTO(st, tl_checkpoint_memory_create(&c->committed), fail);
  TL_CHECK_GOTO(st, tl_checkpoint_memory_create(&c->trial), fail);
  TL_CHECK_GOTO(st, build_world(b, &c->world), fail);
  *cell = c;
  return TL_OK;
fail:
  tl_nhl_cell_destroy(&c);
  return st;
}

/* <d>, ρ and h_R from the world as built. */
static TlStatus measure(TlNhlCell *c)
{
  const TlParticles *P = tl_dem_particles(c->world.dem);
  if (P->n == 0) TL_ERROR(TL_ERR_ARG, "NHL cell: the world has no particles");
  double dsum = 0.0, msum = 0.0, vsum = 0.0;
  for (size_t i = 0; i < P->n; ++i) {
    const double r = P->radius[i];
    dsum += 2.0 * r;
    msum += P->mass[i];
    vsum += c->world.dim == 2 ? TL_PI * r * r : 4.0 / 3.0 * TL_PI * r * r * r;
  }
  c->d_mean = dsum / (double)P->n;
  c->rho = msum / vsum;
  return TL_OK;
}

TlStatus tl_nhl_cell_create(TlNhlBuildFn build, void *ctx, const TlNhlCellSettings *s, TlNhlCell **cell)
{
  if (!build || !s || !cell) TL_ERROR(TL_ERR_ARG, "tl_nhl_cell_create: NULL argument");
  *cell = NULL;
  Builder *b;
  TL_CHECK(TL_NEW(b));
  b->build = build, b->ctx = ctx;
  TlNhlCell *c = NULL;
  TlStatus st = alloc_cell(b, s, &c);
  if (st != TL_OK) {
    if (b->refs == 0) tl_free(&b);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  TL_CHECK_GOTO(st, measure(c), fail);
  TL_CHECK_GOTO(st, tl_dem_compute_forces(c->world.dem), fail);
  TL_CHECK_GOTO(st, tl_nhl_cell_rebase(c), fail);
  *cell = c;
  return TL_OK;
fail:
  tl_nhl_cell_destroy(&c);
  return st;
}

TlStatus tl_nhl_cell_rebase(TlNhlCell *cell)
{
  TlDem *dem = cell->world.dem;
  TlDomain *D = tl_dem_domain(dem);
  TL_CHECK(tl_domain_set_h_rate(D, tl_m3_zero()));
  cell->h_ref = D->h;
  cell->h_ref_inv = D->h_inv;
  cell->F_c = tl_m3_identity();
  TlMat3 sk;
  TL_CHECK(tl_dem_stress(dem, &cell->sigma_c, &sk));
  cell->sigma_c = plane(cell->sigma_c, cell->world.dim);
  TL_CHECK(tl_checkpoint_memory_save(cell->committed, &tl_dem_checkpoint_ops, dem));
  cell->has_trial = 0;
  cell->world_state = WORLD_COMMITTED;
  return TL_OK;
}

void tl_nhl_cell_set_free_ctx(TlNhlCell *cell, void (*free_ctx)(void *ctx)) { cell->builder->free_ctx = free_ctx; }

TlStatus tl_nhl_cell_create_copy(const TlNhlCell *model, TlNhlCell **cell)
{
  if (!model || !cell) TL_ERROR(TL_ERR_ARG, "tl_nhl_cell_create_copy: NULL argument");
  *cell = NULL;
  TlNhlCell *c = NULL;
  TL_CHECK(alloc_cell(model->builder, &model->set, &c));
  TlStatus st;
  c->h_ref = model->h_ref, c->h_ref_inv = model->h_ref_inv;
  c->d_mean = model->d_mean, c->rho = model->rho;
  c->F_c = model->F_c, c->sigma_c = model->sigma_c;
  TL_CHECK_GOTO(st, tl_checkpoint_memory_copy(c->committed, model->committed), fail);
  c->world_state = WORLD_OTHER;
  TL_CHECK_GOTO(st, restore(c, WORLD_COMMITTED), fail);
  *cell = c;
  return TL_OK;
fail:
  tl_nhl_cell_destroy(&c);
  return st;
}

void tl_nhl_cell_destroy(TlNhlCell **cell)
{
  if (!cell || !*cell) return;
  TlNhlCell *c = *cell;
  tl_dem_destroy(&c->world.dem);
  tl_checkpoint_memory_destroy(&c->committed);
  tl_checkpoint_memory_destroy(&c->trial);
  if (c->builder && --c->builder->refs == 0) {
    if (c->builder->free_ctx) c->builder->free_ctx(c->builder->ctx);
    tl_free(&c->builder);
  }
  tl_free(cell);
}

TlStatus tl_nhl_cell_set_settings(TlNhlCell *cell, const TlNhlCellSettings *s)
{
  TL_CHECK(tl_nhl_cell_settings_check(s));
  cell->set = *s;
  return TL_OK;
}

const TlNhlCellSettings *tl_nhl_cell_settings(const TlNhlCell *cell) { return &cell->set; }
TlDem *tl_nhl_cell_dem(TlNhlCell *cell) { return cell->world.dem; }
TlContactLaw *tl_nhl_cell_law(TlNhlCell *cell) { return cell->world.law; }
int tl_nhl_cell_dim(const TlNhlCell *cell) { return cell->world.dim; }
size_t tl_nhl_cell_n_particles(const TlNhlCell *cell) { return tl_dem_particles(cell->world.dem)->n; }
TlMat3 tl_nhl_cell_reference_h(const TlNhlCell *cell) { return cell->h_ref; }
TlMat3 tl_nhl_cell_current_F(const TlNhlCell *cell)
{
  return tl_m3_mul(tl_dem_domain(cell->world.dem)->h, cell->h_ref_inv);
}
TlMat3 tl_nhl_cell_committed_F(const TlNhlCell *cell) { return cell->F_c; }
TlMat3 tl_nhl_cell_committed_stress(const TlNhlCell *cell) { return cell->sigma_c; }
double tl_nhl_cell_mean_diameter(const TlNhlCell *cell) { return cell->d_mean; }
double tl_nhl_cell_grain_density(const TlNhlCell *cell) { return cell->rho; }
int tl_nhl_cell_has_trial(const TlNhlCell *cell) { return cell->has_trial; }

/* ---------------------------------------------------------------- path */
TlStatus tl_nhl_cell_duration(const TlNhlCell *cell, TlMat3 F_i, TlMat3 sigma_i, TlMat3 F_f, double *tau,
                              double *gamma)
{
  TlMat3 Fi_inv;
  if (!tl_m3_inverse(F_i, &Fi_inv)) TL_ERROR(TL_ERR_ARG, "NHL cell: F^i is singular (det %g)", tl_m3_det(F_i));
  /* Eq. 16-17: the small strain of the increment F^f (F^i)^-1 - 1 */
  TlMat3 g = tl_m3_add(tl_m3_mul(F_f, Fi_inv), tl_m3_scale(tl_m3_identity(), -1.0));
  TlMat3 e = tl_m3_scale(tl_m3_add(g, tl_m3_transpose(g)), 0.5);
  double ev[3];
  if (cell->world.dim == 2) {
    const double m = 0.5 * (e.m[0][0] + e.m[1][1]), d = 0.5 * (e.m[0][0] - e.m[1][1]);
    const double r = sqrt(d * d + e.m[0][1] * e.m[0][1]);
    ev[0] = m + r, ev[2] = m - r;
  } else {
    sym_eigenvalues(e, ev);
  }
  /* spec §12.12: an isotropic increment has e1 = e3 */
  const double gam = fmax(ev[0] - ev[2], fmax(fabs(ev[0]), fabs(ev[2])));
  const double P = pressure_of(sigma_i, cell->world.dim);
  /* Eq. 18; a cell without pressure has no inertial time: the floor */
  *tau = P > 0.0 ? gam * cell->d_mean / (cell->set.inertial * sqrt(P / cell->rho)) : 0.0;
  if (gamma) *gamma = gam;
  return TL_OK;
}

/* Drives from the world's F to F_f over τ of Eq. 18 computed with
 * (F_from, sigma_from). */
static TlStatus drive(TlNhlCell *c, TlMat3 F_from, TlMat3 sigma_from, TlMat3 F_f, TlNhlCellStats *st)
{
  TlDem *dem = c->world.dem;
  if (!(tl_m3_det(F_f) > 0.0)) TL_ERROR(TL_ERR_ARG, "NHL cell: det F^f = %g must be > 0", tl_m3_det(F_f));
  if (c->world.dim == 2) {
    const double off = fabs(F_f.m[0][2]) + fabs(F_f.m[1][2]) + fabs(F_f.m[2][0]) + fabs(F_f.m[2][1]);
    if (off != 0.0 || F_f.m[2][2] != 1.0)
      TL_ERROR(TL_ERR_ARG, "NHL cell of disks: F^f must be plane strain (F_33 = 1, F_13 = F_23 = F_31 = F_32 = 0); "
               "F_33 = %g, sum of |out-of-plane shear| = %g", F_f.m[2][2], off);
  }
  double tau, gamma;
  TL_CHECK(tl_nhl_cell_duration(c, F_from, sigma_from, F_f, &tau, &gamma));
  const double dt = tl_dem_timestep(dem);
  TlDomain *D = tl_dem_domain(dem);
  const TlMat3 h_f = tl_m3_mul(F_f, c->h_ref);
  long n = 0;
  if (gamma > 0.0) {
    const double steps = ceil(tau / dt);
    if (!(steps < 1e12))
      TL_ERROR(TL_ERR_ARG, "NHL cell: the drive would take %g DEM steps (tau = %g s, dt = %g s, gamma = %g)", steps, tau,
               dt, gamma);
    n = (long)steps;
    if (n < c->set.min_drive_steps) n = c->set.min_drive_steps;
    /* constant ḣ landing on h_f after n steps (Eq. 3) */
    const TlMat3 hdot = tl_m3_scale(tl_m3_add(h_f, tl_m3_scale(D->h, -1.0)), 1.0 / ((double)n * dt));
    TL_CHECK(tl_domain_set_h_rate(D, hdot));
    TL_CHECK(tl_dem_step(dem, n));
  }
  TL_CHECK(tl_domain_set_h_rate(D, tl_m3_zero()));
  /* h = F^f h_R exactly (the n increments leave round-off; how much is
   * reported) */
  double herr = 0.0, hbig = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) herr = fmax(herr, fabs(D->h.m[i][j] - h_f.m[i][j])), hbig = fmax(hbig, fabs(h_f.m[i][j]));
  TL_CHECK(tl_domain_set_h(D, h_f));
  /* one step at the held F, so that the forces the stress and the balance
   * read are those of ḣ = 0 (the drive's last forces carry the damping of
   * the affine velocity L b) */
  if (n > 0) TL_CHECK(tl_dem_step(dem, 1));
  if (st) {
    st->relax_steps += n > 0;
    st->dem_steps += n > 0;
    st->drive_steps += n;
    st->dem_steps += n;
    st->tau = (double)n * dt;
    st->gamma = gamma;
    st->h_error = herr / hbig;
  }
  return TL_OK;
}

TlStatus tl_nhl_cell_drive(TlNhlCell *cell, TlMat3 F_f, TlNhlCellStats *stats)
{
  TlMat3 sc, sk;
  TL_CHECK(tl_dem_stress(cell->world.dem, &sc, &sk));
  TL_CHECK(drive(cell, tl_nhl_cell_current_F(cell), plane(sc, cell->world.dim), F_f, stats));
  cell->world_state = WORLD_OTHER;
  return TL_OK;
}

TlStatus tl_nhl_cell_stress(TlNhlCell *cell, TlMat3 *contact, TlMat3 *kinetic)
{
  TlMat3 sc, sk;
  TL_CHECK(tl_dem_stress(cell->world.dem, &sc, &sk));
  if (contact) *contact = plane(sc, cell->world.dim);
  if (kinetic) *kinetic = plane(sk, cell->world.dim);
  return TL_OK;
}

TlStatus tl_nhl_cell_relax(TlNhlCell *cell, TlNhlCellStats *st)
{
  TlDem *dem = cell->world.dem;
  const TlNhlCellSettings *s = &cell->set;
  double window[64];
  long nwin = 0, steps = 0;
  double delta = 0.0;
  int ok = 0;
  for (;;) {
    TL_CHECK(tl_dem_max_force_imbalance(dem, &delta));
    if (s->criterion == TL_NHL_EQUILIBRIUM_IMBALANCE) {
      ok = delta < s->tolerance;
    } else {
      TlMat3 sc;
      TL_CHECK(tl_nhl_cell_stress(cell, &sc, NULL));
      const double p = pressure_of(sc, cell->world.dim);
      window[nwin % s->pressure_window] = p;
      nwin++;
      if (nwin >= s->pressure_window) {
        double lo = DBL_MAX, hi = -DBL_MAX;
        for (long k = 0; k < s->pressure_window; ++k) lo = fmin(lo, window[k]), hi = fmax(hi, window[k]);
        ok = p > 0.0 && (hi - lo) <= s->pressure_tolerance * p;
      }
    }
    if (ok || steps >= s->max_relax_steps) break;
    long n = s->check_every;
    if (steps + n > s->max_relax_steps) n = s->max_relax_steps - steps;
    TL_CHECK(tl_dem_step(dem, n));
    steps += n;
  }
  cell->world_state = steps ? WORLD_OTHER : cell->world_state;
  if (st) {
    st->relax_steps += steps;
    st->dem_steps += steps;
    st->imbalance = delta;
    st->converged = ok;
  }
  return TL_OK;
}

/* The end of an evaluation: stress and the diagnostics of the end state. */
static TlStatus finish(TlNhlCell *c, TlMat3 *sigma, TlNhlCellStats *st, double t0)
{
  TlMat3 sc, sk;
  TL_CHECK(tl_nhl_cell_stress(c, &sc, &sk));
  *sigma = sc;
  if (st) {
    const double big = frobenius(sc);
    st->kinetic_ratio = big > 0.0 ? frobenius(sk) / big : (frobenius(sk) > 0.0 ? INFINITY : 0.0);
    st->pressure = pressure_of(sc, c->world.dim);
    TlDemStats ds;
    tl_dem_stats(c->world.dem, &ds);
    st->contacts = ds.n_contacts;
    st->seconds = tl_wtime() - t0;
  }
  return TL_OK;
}

/* Drive from the committed state to F_f and relax. */
static TlStatus path(TlNhlCell *c, TlMat3 F_f, TlMat3 *sigma, TlNhlCellStats *st)
{
  const double t0 = tl_wtime();
  TlNhlCellStats local;
  if (!st) st = &local;
  memset(st, 0, sizeof *st);
  TL_CHECK(restore(c, WORLD_COMMITTED));
  c->world_state = WORLD_OTHER;
  TL_CHECK(drive(c, c->F_c, c->sigma_c, F_f, st));
  TL_CHECK(tl_nhl_cell_relax(c, st));
  c->world_state = WORLD_OTHER;
  TL_CHECK(finish(c, sigma, st, t0));
  return TL_OK;
}

TlStatus tl_nhl_cell_evaluate(TlNhlCell *cell, TlMat3 F_f, TlMat3 *sigma, TlNhlCellStats *stats)
{
  cell->has_trial = 0;
  TL_CHECK(path(cell, F_f, sigma, stats));
  TL_CHECK(tl_checkpoint_memory_save(cell->trial, &tl_dem_checkpoint_ops, cell->world.dem));
  cell->F_t = F_f;
  cell->sigma_t = *sigma;
  cell->has_trial = 1;
  cell->world_state = WORLD_TRIAL;
  return TL_OK;
}

TlStatus tl_nhl_cell_evaluate_aside(TlNhlCell *cell, TlMat3 F_f, TlMat3 *sigma, TlNhlCellStats *stats)
{
  TL_CHECK(path(cell, F_f, sigma, stats));
  TL_CHECK(restore(cell, cell->has_trial ? WORLD_TRIAL : WORLD_COMMITTED));
  return TL_OK;
}

/* Very high friction for a probe: no contact slides (μ f_N stays finite for
 * any force a cell reaches). */
#define TL_NHL_PROBE_MU 1e15

TlStatus tl_nhl_cell_probe(TlNhlCell *cell, TlMat3 F_f, TlMat3 *sigma, TlNhlCellStats *stats)
{
  const double t0 = tl_wtime();
  TlNhlCellStats local;
  if (!stats) stats = &local;
  memset(stats, 0, sizeof *stats);
  const int back = cell->world_state;
  TlMat3 F0 = tl_nhl_cell_current_F(cell), s0;
  TL_CHECK(tl_nhl_cell_stress(cell, &s0, NULL));
  /* every law of the world with friction sticks; a frictionless one stays
   * so (it has no history to keep) */
  enum { MAX_LAWS = 64 };
  const int nl = tl_dem_n_laws(cell->world.dem);
  if (nl > MAX_LAWS) TL_ERROR(TL_ERR_ARG, "NHL cell probe: %d contact laws (at most %d)", nl, MAX_LAWS);
  double mu[MAX_LAWS];
  for (int k = 0; k < nl; ++k) {
    TlContactLaw *law = tl_dem_law(cell->world.dem, k);
    mu[k] = 0.0;
    if (tl_contact_law_get(law, "mu", &mu[k]) != TL_OK) { /* a law without friction */
      mu[k] = 0.0;
      tl_error_clear();
    }
    if (mu[k] > 0.0) {
      TL_CHECK(tl_contact_law_set(law, "mu", TL_NHL_PROBE_MU));
      TL_CHECK(tl_contact_law_setup(law));
    }
  }
  cell->world_state = WORLD_OTHER;
  TlStatus s = drive(cell, F0, s0, F_f, stats);
  if (s == TL_OK) s = tl_nhl_cell_relax(cell, stats);
  cell->world_state = WORLD_OTHER;
  if (s == TL_OK) s = finish(cell, sigma, stats, t0);
  for (int k = 0; k < nl; ++k)
    if (mu[k] > 0.0) {
      TlContactLaw *law = tl_dem_law(cell->world.dem, k);
      TlStatus s2 = tl_contact_law_set(law, "mu", mu[k]);
      if (s2 == TL_OK) s2 = tl_contact_law_setup(law);
      if (s == TL_OK) s = s2;
    }
  TL_CHECK(s);
  /* back to where the probe started: the trial (or committed) state */
  if (back == WORLD_TRIAL || back == WORLD_COMMITTED) TL_CHECK(restore(cell, back));
  else TL_ERROR(TL_ERR_STATE, "NHL cell probe: the world holds neither the committed nor the trial state");
  return TL_OK;
}

TlStatus tl_nhl_cell_reevaluate(void *cell, TlNhlEvalMode mode, TlMat3 F_f, TlMat3 *sigma, TlNhlEvalStats *es)
{
  TlNhlCellStats cs;
  if (mode == TL_NHL_EVAL_PROBE) TL_CHECK(tl_nhl_cell_probe(cell, F_f, sigma, &cs));
  else TL_CHECK(tl_nhl_cell_evaluate_aside(cell, F_f, sigma, &cs));
  if (es) {
    es->dem_steps = cs.dem_steps;
    es->tau = cs.tau;
    es->imbalance = cs.imbalance;
    es->seconds = cs.seconds;
    es->converged = cs.converged;
  }
  return TL_OK;
}

/* ---------------------------------------------------------------- states */
TlStatus tl_nhl_cell_commit(TlNhlCell *cell)
{
  if (!cell->has_trial) return TL_OK;
  TlCheckpointMemory *t = cell->committed;
  cell->committed = cell->trial;
  cell->trial = t;
  cell->F_c = cell->F_t;
  cell->sigma_c = cell->sigma_t;
  cell->has_trial = 0;
  if (cell->world_state == WORLD_TRIAL) cell->world_state = WORLD_COMMITTED;
  else if (cell->world_state == WORLD_COMMITTED) cell->world_state = WORLD_OTHER;
  return TL_OK;
}

TlStatus tl_nhl_cell_rollback(TlNhlCell *cell)
{
  cell->has_trial = 0;
  if (cell->world_state == WORLD_TRIAL) cell->world_state = WORLD_OTHER;
  TL_CHECK(restore(cell, WORLD_COMMITTED));
  return TL_OK;
}

TlStatus tl_nhl_cell_restore_committed(TlNhlCell *cell)
{
  cell->world_state = WORLD_OTHER;
  return restore(cell, WORLD_COMMITTED);
}

TlStatus tl_nhl_cell_save(TlNhlCell *cell, TlCheckpointWriter *w, const char *group)
{
  char sub[512];
  snprintf(sub, sizeof sub, "%s/dem", group ? group : "");
  const int back = cell->world_state;
  TL_CHECK(restore(cell, WORLD_COMMITTED));
  TL_CHECK(tl_dem_checkpoint_ops.save(cell->world.dem, w, sub));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "F", 9, &cell->F_c.m[0][0]));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "sigma", 9, &cell->sigma_c.m[0][0]));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "h_ref", 9, &cell->h_ref.m[0][0]));
  if (back == WORLD_TRIAL && cell->has_trial) TL_CHECK(restore(cell, WORLD_TRIAL));
  return TL_OK;
}

TlStatus tl_nhl_cell_load(TlNhlCell *cell, TlCheckpointReader *r, const char *group)
{
  char sub[512];
  snprintf(sub, sizeof sub, "%s/dem", group ? group : "");
  TlMat3 F, sigma, h_ref;
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "F", 9, &F.m[0][0]));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "sigma", 9, &sigma.m[0][0]));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "h_ref", 9, &h_ref.m[0][0]));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "F", 9, &F.m[0][0]));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "sigma", 9, &sigma.m[0][0]));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (h_ref.m[i][j] != cell->h_ref.m[i][j])
        TL_ERROR(TL_ERR_ARG, "%s: %s/h_ref[%d][%d] = %.17g; this cell's reference is %.17g (not built the same way)",
                 tl_checkpoint_reader_path(r), group, i, j, h_ref.m[i][j], cell->h_ref.m[i][j]);
  if (!(tl_m3_det(F) > 0.0))
    TL_ERROR(TL_ERR_FORMAT, "%s: %s/F has det %g (must be > 0)", tl_checkpoint_reader_path(r), group, tl_m3_det(F));
  cell->world_state = WORLD_OTHER;
  TL_CHECK(tl_dem_checkpoint_ops.load(cell->world.dem, r, sub));
  TL_CHECK(tl_checkpoint_memory_save(cell->committed, &tl_dem_checkpoint_ops, cell->world.dem));
  cell->F_c = F;
  cell->sigma_c = sigma;
  cell->has_trial = 0;
  cell->world_state = WORLD_COMMITTED;
  return TL_OK;
}
