/* The wave-propagation scene of Cheng et al. 2022 §6.2 with the volume coupling,
 * on the library's models: TlDem (bonded lattice, weighted equations), the
 * finite-strain TlSolid with the VCoupling element type, and a library
 * stepper for the solid. */
#include "tl_vcoupling_wave.h"

#include <math.h>
#include <string.h>

#include "tl_dem.h"
#include "tl_element.h"
#include "tl_math.h"
#include "tl_memory.h"
#include "tl_mesh.h"
#include "tl_progress.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_timer.h"
#include "tl_vcoupling.h"
#include "tl_vcoupling_element.h"
#include "tl_options_checkpoint.h"
#include "tl_series_sweep.h"

struct TlWave {
  TlWaveParams p;
  double d, m, k, dt, t;
  long step;
  /* particles: layer j along y, (i, k) across; never renumbered */
  TlDem *dem;
  TlParticles *P;
  size_t np;
  int nxp, nyp, nyp_full;
  double *x0;        /* initial positions (spring variant), 3 np */
  double *xp, *mp;   /* positions and masses handed to the coupling */
  double *dup;       /* the particles' step displacements (or total, spring) */
  double *dup_prev, *du_prev, *u_before; /* lagged order: the previous step's displacements */
  double *ones;      /* unit weights of the full-DEM reference (snapshots) */
  int64_t *driven_ids;
  size_t n_driven;
  /* solid */
  TlMesh *mesh;
  TlMaterial *mat;
  TlSolid *solid;
  TlStepper *st;
  size_t nn;
  double *u, *vn;    /* node-space displacement and velocity (3 nn) */
  double *Mw;        /* weighted lumped mass per node (nn) */
  double *mdof;      /* lumped mass per dof (scratch) */
  double *Mv;        /* M v with the stepper's mass (scratch for the state) */
  char *fixed;
  TlVCoupling *vc;
  TlVCouplingElement *el;
  double eq41, residual, work, spring;
  double vmax_allowed, eps;
  /* snapshots */
  int *conn_int;
  /* penalty stability estimate: power-iteration vectors */
  double *pi_xp, *pi_xn, *pi_fp, *pi_fn;
};

void tl_wave_params_default(TlWaveParams *p)
{
  *p = (TlWaveParams){.n = 1, .dx = 0.4, .width = 0.8, .length = 20.0, .dem_end = 12.0, .fem_start = 8.0,
                      .E = 100e6, .nu = 0.0, .rho = 1309.0, .v0 = 0.1, .excitation = TL_WAVE_PULSE,
                      .omega = 1950.0, .cycles = 1, .dt_over_tc = 0.01, .c = 0.0, .kernel = "lucy",
                      .epsilon = 0.0, .quad_order = 4, .full_dem = 0, .variant = TL_WAVE_PAPER,
                      .fem = "central_difference"};
}

static TlStatus check_penalty(TlWave *w);

/* The resolution check of Pi (tl_vcoupling_check_resolution). */
static TlStatus check_resolution(TlWave *w, long step)
{
  if (w->p.resolution_limit < 0.0) return TL_OK;
  double lim = w->p.resolution_limit > 0.0 ? w->p.resolution_limit : TL_VCOUPLING_BIAS_LIMIT;
  TL_CHECK(tl_vcoupling_check_resolution(w->vc, w->xp, lim, step, NULL));
  return TL_OK;
}

static size_t pid(const TlWave *w, int i, int j, int k) { return ((size_t)j * w->nxp + k) * w->nxp + i; }

/* Prescribed velocity of the driven layer (Table 4); pulse: none.  The
 * position is its exact integral. */
static double driven_period(const TlWaveParams *p)
{
  return 2.0 * TL_PI * (p->excitation == TL_WAVE_CYCLES ? p->cycles : 1) / p->omega;
}

static TlStatus driven_motion(void *ctx, double t, size_t n, const int64_t *id, const TlVec3 *x0, TlVec3 *x, TlVec3 *v)
{
  (void)id;
  const TlWaveParams *p = ctx;
  double t0 = driven_period(p), tt = t < t0 ? t : t0;
  double vy = t <= t0 ? p->v0 * (cos(p->omega * t) - 1.0) : 0.0;
  double dy = p->v0 * (sin(p->omega * tt) / p->omega - tt);
  for (size_t k = 0; k < n; ++k) {
    x[k] = tl_v3(x0[k].x, x0[k].y + dy, x0[k].z);
    v[k] = tl_v3(0.0, vy, 0.0);
  }
  return TL_OK;
}

/* The weight field of the particle equations: w of the coupling
 * (interpolated from the nodes inside a coupling element). */
static TlStatus particle_weight_field(void *ctx, size_t n, const TlVec3 *x, double *wt)
{
  TlWave *w = ctx;
  return tl_vcoupling_point_weights(w->vc, n, (const double *)x, wt);
}

static void gather_particles(TlWave *w)
{
  const TlParticles *P = w->P;
  for (size_t a = 0; a < w->np; ++a) {
    w->xp[3 * a] = P->x[a].x;
    w->xp[3 * a + 1] = P->x[a].y;
    w->xp[3 * a + 2] = P->x[a].z;
  }
}

/* One coupled step, inside the DEM's: the particles have drifted to
 * t + dt (velocities at the half step); Pi at the new positions, the
 * solid's step with the coupling force of Eq. 31 (the VCoupling element),
 * then the particles' share of Eq. 32 as f^C before their forces at
 * t + dt are completed. */
static TlStatus coupled_step(void *ctx, TlDem *dem)
{
  TlWave *w = ctx;
  (void)dem;
  const TlParticles *P = w->P;
  const double dt = w->dt;
  gather_particles(w);
  if (w->p.variant == TL_WAVE_SPRING)
    for (size_t k = 0; k < 3 * w->np; ++k) w->dup[k] = w->xp[k] - w->x0[k];
  else
    for (size_t a = 0; a < w->np; ++a) {
      w->dup[3 * a] = dt * P->v[a].x;
      w->dup[3 * a + 1] = dt * P->v[a].y;
      w->dup[3 * a + 2] = dt * P->v[a].z;
    }
  TL_CHECK(tl_vcoupling_update(w->vc, w->u, w->np, w->xp, w->mp));
  if ((w->step + 1) % 100 == 0) TL_CHECK(check_resolution(w, w->step + 1));
  const int lagged = w->p.lagged && w->p.variant == TL_WAVE_PAPER;
  if (lagged) {
    TL_CHECK(tl_vcoupling_element_set_step_lagged(w->el, w->dup_prev, w->du_prev));
    memcpy(w->u_before, w->u, 3 * w->nn * sizeof *w->u);
  } else {
    TL_CHECK(tl_vcoupling_element_set_step(w->el, w->dup, w->p.variant == TL_WAVE_SPRING ? NULL : w->u));
  }
  TL_CHECK(tl_stepper_step(w->st, dt));
  tl_solid_dofs_to_nodes(w->solid, w->st->u, w->u);
  tl_solid_dofs_to_nodes(w->solid, w->st->v, w->vn);
  if (lagged) { /* this step's displacements drive the next step's forces */
    memcpy(w->dup_prev, w->dup, 3 * w->np * sizeof *w->dup);
    for (size_t k = 0; k < 3 * w->nn; ++k) w->du_prev[k] = w->u[k] - w->u_before[k];
  }
  memset(P->f_coupling, 0, w->np * sizeof *P->f_coupling);
  TlVCouplingDiag dg;
  TL_CHECK(tl_vcoupling_element_particle_forces(w->el, w->u, (double *)P->f_coupling, &dg));
  w->eq41 = dg.eq41;
  w->residual = dg.residual_max;
  if (w->p.variant == TL_WAVE_SPRING)
    w->spring = -0.5 * (dg.work_fem + dg.work_dem);
  else
    w->work += dg.work_fem + dg.work_dem;
  return TL_OK;
}

/* The solid: hex8 bar with the finite-strain Hooke law, the far end
 * clamped, the coupling block wrapped by the VCoupling element (weights
 * 1 - w, coupling force), and its stepper. */
static TlStatus build_solid(TlWave *w)
{
  const TlWaveParams *p = &w->p;
  TL_CHECK(tl_material_create("hooke", &w->mat));
  TL_CHECK(tl_material_set(w->mat, "E", p->E));
  TL_CHECK(tl_material_set(w->mat, "nu", p->nu));
  TL_CHECK(tl_material_set(w->mat, "density", p->rho));
  TL_CHECK(tl_material_setup(w->mat));
  TL_CHECK(tl_solid_create(w->mesh, &w->solid));
  TL_CHECK(tl_solid_set_material(w->solid, NULL, w->mat));
  TL_CHECK(tl_solid_fix(w->solid, "ymax", 7));
  TL_CHECK(tl_vcoupling_element_create(w->vc, w->solid, &w->el));
  TL_CHECK(tl_solid_setup(w->solid));
  TlMechSystem *sys = tl_solid_system(w->solid);
  TL_CHECK(tl_calloc(&w->mdof, (size_t)sys->ndof, sizeof *w->mdof));
  TL_CHECK(tl_calloc(&w->Mv, (size_t)sys->ndof, sizeof *w->Mv));
  TL_CHECK(sys->ops->lumped_mass(sys, w->mdof));
  /* node masses, clamped nodes included (the bar's mass), from the weighted
   * solid's lumped mass */
  double *mn = NULL;
  TL_CHECK(tl_calloc(&mn, 3 * w->nn, sizeof *mn));
  tl_solid_dofs_to_nodes(w->solid, w->mdof, mn);
  double total = tl_solid_total_mass(w->solid), free_sum = 0.0;
  for (size_t i = 0; i < w->nn; ++i) {
    w->fixed[i] = tl_solid_dof(w->solid, i, 1) < 0;
    w->Mw[i] = mn[3 * i + 1];
    free_sum += w->Mw[i];
  }
  tl_free(&mn);
  /* the clamped layer's share (not a dof): the total less the free nodes',
   * spread evenly over its nodes (uniform mesh) */
  size_t n_fixed = 0;
  for (size_t i = 0; i < w->nn; ++i) n_fixed += w->fixed[i] != 0;
  for (size_t i = 0; i < w->nn; ++i)
    if (w->fixed[i]) w->Mw[i] = n_fixed ? (total - free_sum) / (double)n_fixed : 0.0;
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  TL_CHECK(tl_stepper_create(p->fem, sys, &so, &w->st));
  TL_CHECK(tl_stepper_set_state(w->st, 0.0, NULL, NULL));
  return TL_OK;
}

static TlStatus build_particles(TlWave *w)
{
  const TlWaveParams *p = &w->p;
  TL_CHECK(tl_dem_create(&w->dem));
  w->P = tl_dem_particles(w->dem);
  TlParticles *P = w->P;
  int sp;
  TL_CHECK(tl_particles_add_species(P, "grains", 6.0 * p->rho / TL_PI, 0.5 * w->d, 0.5 * w->d, &sp));
  TL_CHECK(tl_particles_reserve(P, w->np));
  for (int j = 0; j < w->nyp; ++j)
    for (int k = 0; k < w->nxp; ++k)
      for (int i = 0; i < w->nxp; ++i) {
        double vy = j == 0 && p->excitation == TL_WAVE_PULSE ? (p->pulse_in ? p->v0 : -p->v0) : 0.0;
        TL_CHECK(tl_dem_add_particle(w->dem, tl_v3((i + 0.5) * w->d, (j + 0.5) * w->d, (k + 0.5) * w->d),
                                     tl_v3(0, vy, 0), 0.5 * w->d, sp, NULL));
      }
  /* bonds to the +x, +y, +z neighbours (ids are the lattice indices) */
  for (int j = 0; j < w->nyp; ++j)
    for (int k = 0; k < w->nxp; ++k)
      for (int i = 0; i < w->nxp; ++i) {
        int64_t a = (int64_t)pid(w, i, j, k);
        if (i + 1 < w->nxp) TL_CHECK(tl_dem_add_bond(w->dem, a, (int64_t)pid(w, i + 1, j, k)));
        if (j + 1 < w->nyp) TL_CHECK(tl_dem_add_bond(w->dem, a, (int64_t)pid(w, i, j + 1, k)));
        if (k + 1 < w->nxp) TL_CHECK(tl_dem_add_bond(w->dem, a, (int64_t)pid(w, i, j, k + 1)));
      }
  /* push-only ("linear": the bonds stay contacts, without tension) for the
   * published runs' species, or bonds in tension and compression */
  const TlContactValue kv[] = {{"k_n", w->k}};
  const TlContactSpec spec = {p->compression_only ? "linear" : "bonded_linear", NULL, NULL, NULL, kv, 1};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TL_CHECK(tl_dem_add_law(w->dem, law, NULL));
  /* the lattice keeps its numbering: the layers are index ranges */
  tl_dem_set_sort_interval(w->dem, 0);
  size_t per = (size_t)w->nxp * w->nxp;
  if (p->excitation != TL_WAVE_PULSE) {
    w->n_driven = per;
    TL_CHECK(tl_calloc(&w->driven_ids, per, sizeof *w->driven_ids));
    for (size_t q = 0; q < per; ++q) w->driven_ids[q] = (int64_t)q;
    TL_CHECK(tl_dem_prescribe(w->dem, per, w->driven_ids, driven_motion, &w->p));
  }
  if (p->full_dem) /* the reference bar's far end is clamped */
    for (size_t q = 0; q < per; ++q) TL_CHECK(tl_particles_set_motion(P, (size_t)(w->nyp - 1) * per + q, TL_MOTION_FIXED));
  TL_CHECK(tl_dem_set_timestep(w->dem, w->dt, 0));
  return TL_OK;
}

/* The bar is built of whole elements (and n particles per element edge):
 * each length must be a whole multiple of dx, or the mesh and the particles
 * would not cover the same bar (and a section narrower than dx would hold
 * no element and no particle at all). */
static TlStatus check_whole_elements(const char *what, double len, double dx, int may_be_zero)
{
  double r = len / dx;
  if (!(r >= (may_be_zero ? 0.0 : 1.0) - 1e-6) || !(fabs(r - (double)lround(r)) <= 1e-6 * fmax(1.0, r)))
    TL_ERROR(TL_ERR_ARG, "%s = %g m is not a whole %smultiple of the element size dx = %g m (it is %.6g dx)", what, len,
             may_be_zero ? "" : "positive ", dx, r);
  if (r > 1e5) TL_ERROR(TL_ERR_ARG, "%s = %g m is %.3g elements of dx = %g m; at most 1e5", what, len, r, dx);
  return TL_OK;
}

TlStatus tl_wave_create(const TlWaveParams *p, TlWave **out)
{
  *out = NULL;
  if (p->n < 1 || p->n > 16) TL_ERROR(TL_ERR_ARG, "particles per element edge n = %d outside [1, 16]", p->n);
  if (!(p->dx > 0) || !(p->width > 0) || !(p->length > 0))
    TL_ERROR(TL_ERR_ARG, "dx = %g, width = %g, length = %g must be > 0", p->dx, p->width, p->length);
  if (!p->full_dem && !(p->fem_start < p->dem_end && p->dem_end <= p->length && p->fem_start >= 0))
    TL_ERROR(TL_ERR_ARG, "overlap [%g, %g] must lie inside the bar [0, %g] with fem_start < dem_end", p->fem_start,
             p->dem_end, p->length);
  TL_CHECK(check_whole_elements("the section side (width)", p->width, p->dx, 0));
  TL_CHECK(check_whole_elements("the bar length", p->length, p->dx, 0));
  if (!p->full_dem) {
    TL_CHECK(check_whole_elements("the start of the FE bar (fem_start)", p->fem_start, p->dx, 1));
    TL_CHECK(check_whole_elements("the end of the DEM bar (dem_end)", p->dem_end, p->dx, 0));
  }
  if (!(p->E > 0) || !(p->rho > 0) || !(p->nu >= 0 && p->nu < 0.5))
    TL_ERROR(TL_ERR_ARG, "E = %g, rho = %g must be > 0 and nu = %g in [0, 0.5)", p->E, p->rho, p->nu);
  if (!(p->dt_over_tc > 0 && p->dt_over_tc <= 0.3))
    TL_ERROR(TL_ERR_ARG, "dt / t_c = %g outside (0, 0.3]", p->dt_over_tc);
  if (p->excitation != TL_WAVE_PULSE && !(p->omega > 0))
    TL_ERROR(TL_ERR_ARG, "omega = %g rad/s must be > 0", p->omega);
  if (p->excitation == TL_WAVE_CYCLES && p->cycles < 1) TL_ERROR(TL_ERR_ARG, "cycles = %d must be >= 1", p->cycles);
  TlWave *w;
  TL_CHECK(TL_NEW(w));
  TlStatus s = TL_OK;
  w->p = *p;
  if (!w->p.fem) w->p.fem = "central_difference";
  w->d = p->dx / p->n;
  double rho_g = 6.0 * p->rho / TL_PI;
  w->m = rho_g * TL_PI * w->d * w->d * w->d / 6.0;
  w->k = p->E * w->d;
  double tc = TL_PI * sqrt(0.5 * w->m / w->k);
  w->dt = p->dt_over_tc * tc;
  w->nxp = (int)lround(p->width / w->d);
  w->nyp_full = (int)lround(p->length / w->d);
  w->nyp = p->full_dem ? w->nyp_full : (int)lround(p->dem_end / w->d);
  w->np = (size_t)w->nxp * w->nxp * w->nyp;
  w->vmax_allowed = 100.0 * fmax(p->v0, 1e-12) * 2.0;
  size_t np = w->np;
  TL_CHECK_GOTO(s, tl_calloc(&w->x0, 3 * np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->xp, 3 * np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->mp, np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->dup, 3 * np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->ones, np, sizeof(double)), fail);
  for (size_t a = 0; a < np; ++a) w->ones[a] = 1.0;
  TL_CHECK_GOTO(s, build_particles(w), fail);
  gather_particles(w);
  memcpy(w->x0, w->xp, 3 * np * sizeof(double));
  for (size_t a = 0; a < np; ++a) w->mp[a] = w->P->mass[a];
  if (!p->full_dem) {
    size_t ncell[3] = {(size_t)lround(p->width / p->dx), (size_t)lround((p->length - p->fem_start) / p->dx),
                       (size_t)lround(p->width / p->dx)};
    double lo[3] = {0, p->fem_start, 0}, hi[3] = {p->width, p->length, p->width};
    TL_CHECK_GOTO(s, tl_mesh_create_box(&tl_element_hex8, ncell, lo, hi, &w->mesh), fail);
    w->nn = w->mesh->n_nodes;
    TL_CHECK_GOTO(s, tl_calloc(&w->u, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->vn, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->Mw, w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->fixed, w->nn, 1), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->dup_prev, 3 * np, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->du_prev, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->u_before, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->pi_xp, 3 * np, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->pi_fp, 3 * np, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->pi_xn, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->pi_fn, 3 * w->nn, sizeof(double)), fail);
    /* hex8 node order is VTK's */
    TL_CHECK_GOTO(s, tl_calloc(&w->conn_int, w->mesh->blocks[0].n_elements * 8, sizeof(int)), fail);
    for (size_t k = 0; k < w->mesh->blocks[0].n_elements * 8; ++k) w->conn_int[k] = (int)w->mesh->blocks[0].conn[k];
    double eps = p->epsilon > 0 ? p->epsilon : 1.6e9 / (w->d * w->d);
    w->eps = eps;
    TlVCouplingParams cp = {{1, p->fem_start, p->dem_end}, p->c, p->kernel, eps, p->quad_order, p->per_element};
    TL_CHECK_GOTO(s, tl_vcoupling_create(w->mesh, 0, &cp, &w->vc), fail);
    TL_CHECK_GOTO(s, tl_vcoupling_set_profile(w->vc, p->linear_weight ? TL_VCOUPLING_LINEAR : TL_VCOUPLING_COSINE), fail);
    TL_CHECK_GOTO(s, tl_vcoupling_set_weight_min(w->vc, p->weight_min), fail);
    TL_CHECK_GOTO(s, tl_vcoupling_set_lumped_penalty(w->vc, p->lumped_penalty), fail);
    TL_CHECK_GOTO(s, tl_vcoupling_set_reach_shrink(w->vc, p->cg_reach_less_d ? w->d : 0.0), fail);
    TL_CHECK_GOTO(s, build_solid(w), fail);
    TL_CHECK_GOTO(s, tl_vcoupling_update(w->vc, w->u, np, w->xp, w->mp), fail);
    TL_CHECK_GOTO(s, check_resolution(w, 0), fail);
    /* the particle side: weighted equations and the coupling force */
    TL_CHECK_GOTO(s, tl_particles_enable_coupling_force(w->P), fail);
    tl_dem_set_weight_field(w->dem, particle_weight_field, w);
    tl_dem_set_step_hook(w->dem, coupled_step, w);
  }
  TL_CHECK_GOTO(s, tl_dem_setup(w->dem), fail);
  if (!p->full_dem && !p->no_penalty_check) TL_CHECK_GOTO(s, check_penalty(w), fail);
  *out = w;
  return TL_OK;
fail:
  tl_wave_destroy(&w);
  return s;
}

void tl_wave_destroy(TlWave **pw)
{
  TlWave *w = *pw;
  if (!w) return;
  double **arr[] = {&w->x0, &w->xp, &w->mp, &w->dup, &w->ones, &w->u, &w->vn, &w->Mw, &w->mdof, &w->Mv,
                    &w->pi_xp, &w->pi_xn, &w->pi_fp, &w->pi_fn, &w->dup_prev, &w->du_prev, &w->u_before};
  for (size_t k = 0; k < sizeof arr / sizeof arr[0]; ++k) tl_free(arr[k]);
  tl_free(&w->fixed);
  tl_free(&w->conn_int);
  tl_free(&w->driven_ids);
  tl_stepper_destroy(&w->st);
  tl_vcoupling_element_destroy(&w->el);
  tl_solid_destroy(&w->solid);
  tl_material_destroy(&w->mat);
  tl_dem_destroy(&w->dem);
  tl_vcoupling_destroy(&w->vc);
  tl_mesh_destroy(&w->mesh);
  tl_free(pw);
}

double tl_wave_dt(const TlWave *w) { return w->dt; }
size_t tl_wave_n_particles(const TlWave *w) { return w->np; }

TlStatus tl_wave_step(TlWave *w)
{
  TL_CHECK(tl_dem_step(w->dem, 1));
  w->t = tl_dem_time(w->dem);
  w->step++;
  double vmax = 0.0;
  const TlParticles *P = w->P;
  for (size_t a = 0; a < w->np; ++a) {
    const double *v = &P->v[a].x;
    for (int d = 0; d < 3; ++d) {
      double s = fabs(v[d]);
      vmax = s > vmax || s != s ? (s != s ? INFINITY : s) : vmax;
    }
  }
  for (size_t k = 0; k < 3 * w->nn; ++k) {
    double s = fabs(w->vn[k]);
    vmax = s > vmax || s != s ? (s != s ? INFINITY : s) : vmax;
  }
  if (!(vmax <= w->vmax_allowed))
    TL_ERROR(TL_ERR_UNSTABLE,
             "the wave run diverged at t = %g s (step %ld): largest speed %g m/s, over 100 times the amplitude "
             "%g m/s, with CG width c = %g m (%.3g element sizes) and penalty eps = %g Pa/m^2 (eps d^2 = %g Pa). "
             "The explicit penalty acts as a damper eps M dt on the step displacement; its stable range is "
             "checked at creation (tl_wave_penalty_ratio) unless -penalty_check 0",
             w->t, w->step, vmax, w->p.v0, w->p.c, w->p.c / w->p.dx, w->eps, w->eps * w->d * w->d);
  return TL_OK;
}

void tl_wave_state(const TlWave *w, TlWaveState *s)
{
  memset(s, 0, sizeof *s);
  s->t = w->t;
  const TlParticles *P = w->P;
  const double *wt = P->weight ? P->weight : w->ones;
  for (size_t a = 0; a < w->np; ++a) {
    double mw = wt[a] * P->mass[a], v2 = tl_v3_norm2(P->v[a]);
    s->mass_dem += mw;
    s->mom_dem += mw * P->v[a].y;
    s->kin_dem += 0.5 * mw * v2;
  }
  /* the bonds' (weighted) stored energy of the last force evaluation */
  TlDemEnergy e;
  tl_dem_energy(w->dem, &e);
  s->pot_dem = e.elastic;
  if (w->mesh) {
    /* momentum and kinetic energy with the stepper's own mass (lumped for
     * central differences, consistent for Newmark): the ones it conserves */
    const TlStepper *st = w->st;
    tl_stepper_mass_times(st, st->v, w->Mv);
    for (TlSparseIndex k = 0; k < st->n; ++k) s->kin_fem += 0.5 * st->v[k] * w->Mv[k];
    for (size_t i = 0; i < w->nn; ++i) {
      TlSparseIndex k = tl_solid_dof(w->solid, i, 1);
      s->mass_fem += w->Mw[i];
      if (k >= 0) s->mom_fem += w->Mv[k];
    }
    double W = 0.0;
    if (tl_solid_strain_energy(w->solid, w->st->u, &W) == TL_OK) s->pot_fem = W;
  }
  s->pot_coupling = w->spring;
  s->total = s->kin_dem + s->pot_dem + s->kin_fem + s->pot_fem + s->pot_coupling;
  s->eq41 = w->eq41;
  s->residual = w->residual;
  s->coupling_work = w->work;
}

/* Power iteration on W^-1 K, K = eps B^T M B applied through the coupling
 * forces; the Rayleigh quotient in the W inner product bounds lambda_max
 * from below. */
TlStatus tl_wave_penalty_ratio(TlWave *w, int iterations, double *ratio, size_t *particle, size_t *node)
{
  *ratio = 0.0;
  if (particle) *particle = 0;
  if (node) *node = 0;
  if (!w->vc) return TL_OK;
  const size_t np = w->np, nn = w->nn;
  const double *wt = w->P->weight, *mass = w->P->mass;
  if (!wt) TL_ERROR(TL_ERR_STATE, "the particle weights are set at tl_dem_setup, before the penalty ratio");
  double *xp = w->pi_xp, *xn = w->pi_xn, *fp = w->pi_fp, *fn = w->pi_fn;
  unsigned seed = 2463534242u;
  for (size_t k = 0; k < 3 * np; ++k) {
    seed ^= seed << 13, seed ^= seed >> 17, seed ^= seed << 5;
    xp[k] = (double)(seed & 0xffff) / 65536.0 - 0.5;
  }
  for (size_t k = 0; k < 3 * nn; ++k) {
    seed ^= seed << 13, seed ^= seed >> 17, seed ^= seed << 5;
    xn[k] = w->fixed[k / 3] ? 0.0 : (double)(seed & 0xffff) / 65536.0 - 0.5;
  }
  double lambda = 0.0;
  for (int it = 0; it < iterations; ++it) {
    memset(fp, 0, 3 * np * sizeof *fp);
    memset(fn, 0, 3 * nn * sizeof *fn);
    TL_CHECK(tl_vcoupling_forces(w->vc, xp, xn, fn, fp, NULL));
    /* K x = -(f_p, f_n); Rayleigh quotient x.Kx / x.Wx, then x <- W^-1 K x */
    double xkx = 0.0, xwx = 0.0;
    for (size_t k = 0; k < 3 * np; ++k) {
      double m = wt[k / 3] * mass[k / 3];
      xkx -= xp[k] * fp[k];
      xwx += xp[k] * m * xp[k];
    }
    for (size_t k = 0; k < 3 * nn; ++k) {
      if (w->fixed[k / 3]) continue;
      xkx -= xn[k] * fn[k];
      xwx += xn[k] * w->Mw[k / 3] * xn[k];
    }
    lambda = xwx > 0.0 ? xkx / xwx : 0.0;
    double norm = 0.0;
    for (size_t k = 0; k < 3 * np; ++k) {
      xp[k] = -fp[k] / (wt[k / 3] * mass[k / 3]);
      norm = fmax(norm, fabs(xp[k]));
    }
    for (size_t k = 0; k < 3 * nn; ++k) {
      xn[k] = w->fixed[k / 3] ? 0.0 : -fn[k] / w->Mw[k / 3];
      norm = fmax(norm, fabs(xn[k]));
    }
    if (!(norm > 0.0)) break;
    for (size_t k = 0; k < 3 * np; ++k) xp[k] /= norm;
    for (size_t k = 0; k < 3 * nn; ++k) xn[k] /= norm;
  }
  *ratio = w->dt * w->dt * lambda; /* lambda carries eps (the forces do) */
  double big = -1.0;
  for (size_t k = 0; k < 3 * np; ++k)
    if (fabs(xp[k]) > big) big = fabs(xp[k]), particle ? (void)(*particle = k / 3) : (void)0;
  big = -1.0;
  for (size_t k = 0; k < 3 * nn; ++k)
    if (fabs(xn[k]) > big) big = fabs(xn[k]), node ? (void)(*node = k / 3) : (void)0;
  return TL_OK;
}

/* 200 power iterations converge to well under 1 % for V1 (0.2 % between
 * 80 and 160 at 1P). */
static TlStatus check_penalty(TlWave *w)
{
  double ratio, lim = TL_WAVE_PENALTY_LIMIT(w->p.variant);
  size_t a, i;
  TL_CHECK(tl_wave_penalty_ratio(w, 200, &ratio, &a, &i));
  if (!(ratio <= lim))
    TL_ERROR(TL_ERR_UNSTABLE,
             "penalty eps = %g Pa/m^2 (eps d^2 = %g Pa) with CG width c = %g m is beyond the explicit stable range "
             "for dt = %.4g s, at step %ld: eps dt^2 lambda_max(W^-1 M_C) = %.4g over the limit %g of the %s (W: "
             "the weighted masses; the stiffest mode sits where a weight goes to zero, near particle %zu at y = %g m "
             "with w = %.3g and node %zu at y = %g m with 1 - w = %.3g). The largest stable penalty is about %.3g Pa/m^2",
             w->eps, w->eps * w->d * w->d, w->p.c, w->dt, w->step, ratio, lim,
             w->p.variant == TL_WAVE_SPRING ? "penalty spring under central differences" : "penalty damper eps M dt",
             a, w->xp[3 * a + 1], w->P->weight[a], i, w->mesh->x[3 * i + 1], 1.0 - tl_vcoupling_node_weights(w->vc)[i],
             w->eps * lim / ratio);
  return TL_OK;
}

size_t tl_wave_profile_size(const TlWave *w) { return (size_t)w->nyp_full; }

/* v_y of the solid at y: the mean over a node layer, linear between layers. */
static double solid_vy(const TlWave *w, double y)
{
  int nyn = (int)lround((w->p.length - w->p.fem_start) / w->p.dx) + 1;
  double r = (y - w->p.fem_start) / w->p.dx;
  int l = (int)floor(r);
  if (l < 0) l = 0;
  if (l >= nyn - 1) l = nyn - 2;
  double f = r - l, avg[2] = {0, 0};
  for (int side = 0; side < 2; ++side) {
    double yl = w->p.fem_start + (l + side) * w->p.dx;
    int cnt = 0;
    for (size_t i = 0; i < w->nn; ++i)
      if (fabs(w->mesh->x[3 * i + 1] - yl) < 1e-9) {
        avg[side] += w->vn[3 * i + 1];
        ++cnt;
      }
    avg[side] /= cnt > 0 ? cnt : 1;
  }
  return (1 - f) * avg[0] + f * avg[1];
}

static void profile(const TlWave *w, int blend, double *y, double *vy)
{
  size_t per = (size_t)w->nxp * w->nxp;
  const TlParticles *P = w->P;
  const double *wt = P->weight ? P->weight : w->ones;
  for (int j = 0; j < w->nyp_full; ++j) {
    y[j] = (j + 0.5) * w->d;
    if (j < w->nyp) {
      double s = 0.0, sw = 0.0;
      for (size_t q = 0; q < per; ++q) {
        s += P->v[j * per + q].y;
        sw += wt[j * per + q];
      }
      vy[j] = s / (double)per;
      /* the Arlequin field in the overlap: w v_particles + (1 - w) v_solid */
      if (blend && w->mesh && y[j] > w->p.fem_start) {
        double wl = sw / (double)per;
        vy[j] = wl * vy[j] + (1.0 - wl) * solid_vy(w, y[j]);
      }
      continue;
    }
    vy[j] = solid_vy(w, y[j]);
  }
}

void tl_wave_profile(const TlWave *w, double *y, double *vy) { profile(w, 0, y, vy); }
void tl_wave_profile_weighted(const TlWave *w, double *y, double *vy) { profile(w, 1, y, vy); }

/* ------------------------------------------------------------ checkpoint */
/* The scene's own figures, then the DEM world and the solid's stepper
 * through their checkpoint sections (Pi and the coupling force follow from
 * them in the next step). */
static TlStatus wave_save(const void *object, TlCheckpointWriter *cw, const char *g)
{
  const TlWave *w = object;
  char sub[512];
  TL_CHECK(tl_checkpoint_write_int64(cw, g, "step", w->step));
  TL_CHECK(tl_checkpoint_write_double(cw, g, "time", w->t));
  double sc[4] = {w->eq41, w->residual, w->work, w->spring};
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "diagnostics", 4, sc));
  snprintf(sub, sizeof sub, "%s/dem", g ? g : "");
  TL_CHECK(tl_dem_checkpoint_ops.save(w->dem, cw, sub));
  if (w->mesh) {
    snprintf(sub, sizeof sub, "%s/solid", g ? g : "");
    TL_CHECK(tl_stepper_checkpoint_ops.save(w->st, cw, sub));
    if (w->p.lagged) { /* the next step's forces come from these */
      TL_CHECK(tl_checkpoint_write_doubles(cw, g, "lagged_particle_displacement", 3 * w->np, w->dup_prev));
      TL_CHECK(tl_checkpoint_write_doubles(cw, g, "lagged_solid_displacement", 3 * w->nn, w->du_prev));
    }
  }
  return TL_OK;
}

static TlStatus wave_load(void *object, TlCheckpointReader *cr, const char *g)
{
  TlWave *w = object;
  char sub[512];
  int64_t step;
  double sc[4];
  TL_CHECK(tl_checkpoint_read_int64(cr, g, "step", &step));
  TL_CHECK(tl_checkpoint_read_double(cr, g, "time", &w->t));
  w->step = (long)step;
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "diagnostics", 4, sc));
  w->eq41 = sc[0];
  w->residual = sc[1];
  w->work = sc[2];
  w->spring = sc[3];
  snprintf(sub, sizeof sub, "%s/solid", g ? g : "");
  int has_solid = tl_checkpoint_has(cr, sub, "t");
  if (w->mesh && !has_solid)
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s' holds a full-DEM scene, this one is coupled", tl_checkpoint_reader_path(cr));
  if (!w->mesh && has_solid)
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s' holds a coupled scene, this one is full DEM", tl_checkpoint_reader_path(cr));
  snprintf(sub, sizeof sub, "%s/dem", g ? g : "");
  TL_CHECK(tl_dem_checkpoint_ops.load(w->dem, cr, sub));
  if (w->mesh) {
    snprintf(sub, sizeof sub, "%s/solid", g ? g : "");
    TL_CHECK(tl_stepper_checkpoint_ops.load(w->st, cr, sub));
    tl_solid_dofs_to_nodes(w->solid, w->st->u, w->u);
    tl_solid_dofs_to_nodes(w->solid, w->st->v, w->vn);
    if (w->p.lagged) {
      TL_CHECK(tl_checkpoint_read_doubles(cr, g, "lagged_particle_displacement", 3 * w->np, w->dup_prev));
      TL_CHECK(tl_checkpoint_read_doubles(cr, g, "lagged_solid_displacement", 3 * w->nn, w->du_prev));
    }
  }
  return TL_OK;
}

const TlCheckpointOps tl_wave_checkpoint_ops = {
    {"checkpoint", "wave_volume_coupling", "V1 wave scene: particles, solid, coupling work"}, wave_save, wave_load};

/* ------------------------------------------------------------- snapshots */
TlStatus tl_wave_write_snapshot(const TlWave *w, TlParticleWriter *pw, TlMeshWriter *mw)
{
  const TlParticles *P = w->P;
  TlField pf[1] = {{"weight", 1, P->weight ? P->weight : w->ones}};
  TlParticleView pv = {.n = w->np, .position = P->x, .radius = P->radius, .velocity = P->v, .force = P->f,
                       .species = (const int *)P->species, .n_fields = 1, .fields = pf, .id = P->id};
  if (pw) TL_CHECK(tl_particle_writer_write(pw, w->step, w->t, &pv));
  if (!mw || !w->mesh) return TL_OK;
  const TlElementBlock *B = &w->mesh->blocks[0];
  TlField nf[3] = {{"velocity", 3, w->vn}, {"particle_weight", 1, tl_vcoupling_node_weights(w->vc)},
                   {"weighted_mass", 1, w->Mw}};
  TlMeshBlock block = {.name = "bar", .type = TL_CELL_HEX8, .n_cells = B->n_elements, .connectivity = w->conn_int};
  TlMeshView mv = {.n_nodes = w->nn, .reference = (const TlVec3 *)w->mesh->x, .displacement = (const TlVec3 *)w->u,
                   .n_node_fields = 3, .node_fields = nf, .n_blocks = 1, .blocks = &block};
  TL_CHECK(tl_mesh_writer_write(mw, w->step, w->t, &mv));
  return TL_OK;
}

void tl_wave_record_free(TlWaveRecord *r)
{
  tl_free(&r->state);
  tl_free(&r->y);
  tl_free(&r->profile);
  tl_free(&r->profile_weighted);
  memset(r, 0, sizeof *r);
}

/* What a run records, checkpointed with the scene so that a restarted run
 * writes the same tables as one run in one go. */
typedef struct {
  TlWaveRecord *r;
  size_t cap;
  int n_snap, *next;
} RecordSection;

static TlStatus record_save(const void *object, TlCheckpointWriter *cw, const char *g)
{
  const RecordSection *R = object;
  const size_t per = sizeof(TlWaveState) / sizeof(double);
  TL_CHECK(tl_checkpoint_write_int64(cw, g, "rows", (int64_t)R->r->n));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "states", R->r->n * per, (const double *)R->r->state));
  TL_CHECK(tl_checkpoint_write_int64(cw, g, "profiles_taken", *R->next));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "profile_times", TL_WAVE_MAX_SNAPSHOTS, R->r->snap_t));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "profiles", (size_t)(R->n_snap ? R->n_snap : 1) * R->r->ny, R->r->profile));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "profiles_weighted", (size_t)(R->n_snap ? R->n_snap : 1) * R->r->ny,
                                       R->r->profile_weighted));
  return TL_OK;
}

static TlStatus record_load(void *object, TlCheckpointReader *cr, const char *g)
{
  RecordSection *R = object;
  const size_t per = sizeof(TlWaveState) / sizeof(double);
  int64_t n, next;
  TL_CHECK(tl_checkpoint_read_int64(cr, g, "rows", &n));
  if (n < 1 || (size_t)n > R->cap)
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s' holds %lld recorded rows, this run records at most %zu (same -t_end "
             "and -table_every?)", tl_checkpoint_reader_path(cr), (long long)n, R->cap);
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "states", (size_t)n * per, (double *)R->r->state));
  R->r->n = (size_t)n;
  TL_CHECK(tl_checkpoint_read_int64(cr, g, "profiles_taken", &next));
  if (next < 0 || next > R->n_snap)
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s' has taken %lld profiles, this run takes %d (same -profile_times?)",
             tl_checkpoint_reader_path(cr), (long long)next, R->n_snap);
  *R->next = (int)next;
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "profile_times", TL_WAVE_MAX_SNAPSHOTS, R->r->snap_t));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "profiles", (size_t)(R->n_snap ? R->n_snap : 1) * R->r->ny, R->r->profile));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "profiles_weighted", (size_t)(R->n_snap ? R->n_snap : 1) * R->r->ny,
                                      R->r->profile_weighted));
  return TL_OK;
}

static const TlCheckpointOps record_checkpoint_ops = {
    {"checkpoint", "wave_record", "recorded states and velocity profiles of a V1 run"}, record_save, record_load};

TlStatus tl_wave_run(const TlWaveParams *p, const TlWaveRunOptions *o, TlWaveRecord *r)
{
  memset(r, 0, sizeof *r);
  if (!(o->t_end > 0)) TL_ERROR(TL_ERR_ARG, "t_end = %g s must be > 0", o->t_end);
  if (o->every < 1) TL_ERROR(TL_ERR_ARG, "recording interval %ld steps must be >= 1", o->every);
  if (o->n_snap < 0 || o->n_snap > TL_WAVE_MAX_SNAPSHOTS)
    TL_ERROR(TL_ERR_ARG, "%d snapshots outside [0, %d]", o->n_snap, TL_WAVE_MAX_SNAPSHOTS);
  if (o->snapshot_dt < 0 || o->checkpoint_every < 0 || o->stop_step < 0)
    TL_ERROR(TL_ERR_ARG, "snapshot_dt = %g s, checkpoint_every = %ld, stop_step = %ld must be >= 0", o->snapshot_dt,
             o->checkpoint_every, o->stop_step);
  const int restart = o->restart && o->restart[0];
  if (!o->output_dir && (o->snapshot_dt > 0 || o->checkpoint_every > 0 || restart))
    TL_ERROR(TL_ERR_ARG, "snapshots, checkpoints and restarts need an output folder");
  double wall0 = tl_wtime();
  TlWave *w = NULL;
  TL_CHECK(tl_wave_create(p, &w));
  TlStatus s = TL_OK;
  TlParticleWriter *pw = NULL;
  TlMeshWriter *mw = NULL;
  TlCheckpoint *cp = NULL;
  char ckpt[4096] = "";
  long steps = (long)ceil(o->t_end / w->dt - 1e-9);
  size_t cap = (size_t)(steps / o->every) + 3;
  int next = 0;
  RecordSection R = {r, cap, o->n_snap, &next};
  r->ny = tl_wave_profile_size(w);
  r->dt = w->dt;
  r->n_particles = w->np;
  TL_CHECK_GOTO(s, tl_calloc(&r->state, cap, sizeof *r->state), out);
  TL_CHECK_GOTO(s, tl_calloc(&r->y, r->ny, sizeof *r->y), out);
  TL_CHECK_GOTO(s, tl_calloc(&r->profile, (size_t)(o->n_snap ? o->n_snap : 1) * r->ny, sizeof *r->profile), out);
  TL_CHECK_GOTO(s, tl_calloc(&r->profile_weighted, (size_t)(o->n_snap ? o->n_snap : 1) * r->ny,
                             sizeof *r->profile_weighted), out);
  tl_wave_profile(w, r->y, r->profile); /* the layer positions; the profile itself is overwritten */
  if (o->snapshot_dt > 0) {
    TL_CHECK_GOTO(s, tl_particle_writer_create(o->output_dir, "particles", &pw), out);
    if (!p->full_dem) TL_CHECK_GOTO(s, tl_mesh_writer_create(o->output_dir, "solid", &mw), out);
  } else if (o->output_dir && !restart) { /* a rerun with snapshots off: the earlier run's series would pass for this one's */
    size_t removed;
    TL_CHECK_GOTO(s, tl_series_sweep_whole(o->output_dir, "particles", &removed), out);
    TL_CHECK_GOTO(s, tl_series_sweep_whole(o->output_dir, "solid", &removed), out);
  }
  if (o->checkpoint_every > 0 || restart) {
    snprintf(ckpt, sizeof ckpt, "%s/checkpoint.h5", o->output_dir);
    TL_CHECK_GOTO(s, tl_checkpoint_create(&cp), out);
    if (o->options) TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, o->options), out);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "wave", &tl_wave_checkpoint_ops, w), out);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "record", &record_checkpoint_ops, &R), out);
    if (pw) TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "particle_snapshots", &tl_particle_writer_checkpoint_ops, pw), out);
    if (mw) TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "solid_snapshots", &tl_mesh_writer_checkpoint_ops, mw), out);
  }
  if (restart) {
    TL_CHECK_GOTO(s, tl_checkpoint_load(cp, o->restart, NULL, NULL), out);
    r->start_step = w->step;
  } else {
    tl_wave_state(w, &r->state[r->n++]);
    if (pw) TL_CHECK_GOTO(s, tl_wave_write_snapshot(w, pw, mw), out);
  }
  TlProgress bar;
  if (o->progress) tl_progress_init(&bar, p->full_dem ? "full DEM" : "coupled", (double)steps);
  for (long k = w->step + 1; k <= steps; ++k) {
    TL_CHECK_GOTO(s, tl_wave_step(w), out);
    if ((k % o->every == 0 || k == steps) && r->n < cap) tl_wave_state(w, &r->state[r->n++]);
    while (next < o->n_snap && w->t >= o->snap[next] - 1e-12) {
      tl_wave_profile(w, r->y, r->profile + (size_t)next * r->ny);
      tl_wave_profile_weighted(w, r->y, r->profile_weighted + (size_t)next * r->ny);
      r->snap_t[next++] = w->t;
    }
    /* snapshot n at the first step at or after n snapshot_dt */
    if (pw && w->t >= (double)tl_particle_writer_count(pw) * o->snapshot_dt - 1e-12 * o->snapshot_dt)
      TL_CHECK_GOTO(s, tl_wave_write_snapshot(w, pw, mw), out);
    if (cp && o->checkpoint_every > 0 && k % o->checkpoint_every == 0)
      TL_CHECK_GOTO(s, tl_checkpoint_save(cp, ckpt, w->t, k), out);
    if (o->progress && k % 200 == 0) tl_progress_update(&bar, (double)k);
    if (o->stop_step > 0 && k == o->stop_step && k < steps) {
      r->stopped = 1;
      break;
    }
  }
  if (o->progress) tl_progress_finish(&bar);
  r->steps = w->step;
  r->n_snapshots = pw ? tl_particle_writer_count(pw) : 0;
  if (!r->stopped && next < o->n_snap) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "snapshot time %g s lies beyond t_end = %g s",
                     o->snap[next], o->t_end);
    goto out;
  }
out:
  tl_checkpoint_destroy(&cp);
  tl_particle_writer_destroy(&pw);
  tl_mesh_writer_destroy(&mw);
  tl_wave_destroy(&w);
  r->wall = tl_wtime() - wall0;
  /* on failure what was recorded stays for the diagnosis; the caller frees */
  return s;
}
