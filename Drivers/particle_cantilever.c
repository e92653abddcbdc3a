/* S1 of Cheng et al. 2022 (§6.1): two frictionless particles sliding
 * along an elastic cantilever, surface-coupled with CG width c.
 *
 * Beam: 2 x 30 x 2 hex8, 0.8 x 12 x 0.8 m (y along the beam, clamped at
 * y = 0, top face z = 0.4 m), E = 100 MPa, nu = 0, rho = 1309 kg/m^3, no
 * gravity on the beam.  Particles: d = 0.2 m, rho = 2e4 kg/m^3, linear
 * spring k_n = E d, no damping (-pair_restitution adds the dashpot of the published
 * runs), no friction, gravity on the particles only,
 * at (+-0.2, 0.2) over the top face with overlap m g / k_n, released with
 * v_y = 0.1 m/s.  dt = 0.01 pi sqrt(2 m / k_n) for both models.
 *
 * Output (under -output_dir): trajectory.csv (positions, the analytic path,
 * the error, the wall contacts and the active SCoupling elements: the
 * owners of the faces the contacts reached, with c > 0 their neighbours
 * within the kernel's reach), energy.csv (every energy term and the total),
 * reference_path.csv (the analytic path), beam_*.h5 + beam.xmf and
 * particles_*.h5 + particles.xmf.  Plots: tools/plot_particle_cantilever.py.
 *
 * Analytic path: quasi-static point load F = 2 m g at the particles' y on the
 * cantilever, z(y) = z0 - F y^3 / (3 E I), I = b h^3 / 12, x = +-0.2 m.
 * err(t) = sqrt(mean over the particles of (x - x0)^2 + (z - z_ref(y))^2);
 * err_avg is its time average until the particles leave the beam (both
 * beyond y = L, t_off).  E_total = particles' kinetic + contact elastic +
 * gravitational (relative to the start) + beam kinetic + strain. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include "talus.h"
#include "tl_papers.h"
#include "tl_options_checkpoint.h"
#include "tl_options_renamed.h"
#include "tl_series_sweep.h"
#include "tl_plot_hint.h"
#include "tl_cantilever.h"
#include "tl_coupled_loop.h"
#include "tl_io.h"
#include "tl_scoupling.h"
#include "tl_solid_output.h"

typedef struct {
  TlCantileverParams beam;
  double d, rho_g, kn, restitution, g, vy, x0, perturb, y0, cg_width, dt_factor, t_end, t_max, table_dt, snapshot_dt, newton_rtol, energy_limit;
  long substeps, reuse, cg_subdivisions, checkpoint_every, stop_step;
  const char *restart;
  int stepper, one_way, keep_factors, scheme, average_forces, predictor, newton, cg_support;
  const char *kernel;
  char *output_dir;
  TlOptions *options;
  TlContactLaw *law;
} Config;

static const char *const steppers[] = {"newmark", "central_difference", NULL};
static const char *const schemes[] = {"predict", "interpolate", "parallel", "lagged_walls", NULL}; /* TL_COUPLING_* order */
static const char *const predictors[] = {"auto", "last", "taylor", NULL}; /* TL_PREDICTOR_* order */
static const char *const kernels[] = {"lucy", "gaussian", "heaviside", NULL};

static TlStatus configure(int argc, char **argv, Config *c)
{
  TlOptions *o = NULL;
  TlStatus s = TL_OK;
  TL_CHECK(tl_options_create(argc, argv,
                             "S1 of Cheng et al. 2022, §6.1: two frictionless particles sliding along an elastic "
                             "cantilever, surface-coupled through coarse-grained contact forces.  Paper: " TL_PAPER_CHENG_2022 ".",
                             &o));
  static const TlRenamedOption renamed[] = {
      {"-rho_g", "-density", NULL},
      {"-restitution", "-pair_restitution", "one dashpot for every contact from a pair's restitution, "
                                            "not the contact law's -contact_restitution"},
      {"-g", "-gravity", NULL},
      {"-fem", "-stepper", NULL},
      {"-output_dt", "-table_dt", "table cadence: -table_dt seconds, -table_every steps, -table_rows a count"}};
  TL_CHECK_GOTO(s, tl_options_refuse_renamed(o, renamed, (int)(sizeof renamed / sizeof renamed[0])), done);
  tl_cantilever_params_default(&c->beam);
  c->beam.load = 0.0;
  long nx, ny, nz;
  int kernel = 0;
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nx", 2, 1, 1000, "beam cells across x", &nx), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-ny", 30, 1, 100000, "beam cells along y", &ny), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nz", 2, 1, 1000, "beam cells across z", &nz), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-width", 0.8, 1e-6, 1e6, "m", "beam width b (x)", &c->beam.b), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-height", 0.8, 1e-6, 1e6, "m", "beam height h (z)", &c->beam.h), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-length", 12.0, 1e-6, 1e6, "m", "beam length L (y)", &c->beam.L), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-E", 1e8, 1e-3, 1e15, "Pa", "beam Young's modulus", &c->beam.E), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-nu", 0.0, -0.99, 0.49, "", "beam Poisson's ratio", &c->beam.nu), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-rho", 1309.0, 1e-6, 1e6, "kg/m^3", "beam density", &c->beam.rho), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-d", 0.2, 1e-6, 1e3, "m", "particle diameter", &c->d), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-density", 2e4, 1e-6, 1e8, "kg/m^3", "particle density", &c->rho_g), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-pair_restitution", 1.0, 1e-3, 1.0, "",
                                       "normal restitution of a pair of grains (sets the viscous damping of every contact, "
                                       "walls included; the published runs used 0.99)", &c->restitution), done);
  {
    /* A linear spring k_n = E d with one damping coefficient for every
     * contact, set by the restitution of a pair of grains (m_eff = m / 2), as
     * the published runs do (their restitution 0.99 is a dashpot of
     * 185 N s/m; the paper's text calls the scene undamped, the default
     * here).  -contact_k_n and -contact_c_n override. */
    const double kn = c->beam.E * c->d, r = 0.5 * c->d, m = c->rho_g * 4.0 / 3.0 * M_PI * r * r * r;
    const double ln_e = log(c->restitution), eta = -ln_e / sqrt(M_PI * M_PI + ln_e * ln_e);
    const double gamma_n = 2.0 * eta * sqrt(kn * 0.5 * m);
    const TlContactValue law_values[] = {{"k_n", kn}, {"restitution", gamma_n > 0.0 ? -1.0 : 1.0}, {"c_n", gamma_n + 0.0 /* no -0 */}};
    const TlContactSpec law_spec = {"linear", NULL, NULL, NULL, law_values, 3};
    TL_CHECK_GOTO(s, tl_contact_law_from_options(o, &law_spec, &c->law), done);
    TL_CHECK_GOTO(s, tl_contact_law_get(c->law, "k_n", &c->kn), done);
  }
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-gravity", 9.81, 0.0, 1e4, "m/s^2", "gravity on the particles (-z)", &c->g), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-vy", 0.1, -1e3, 1e3, "m/s", "initial particle velocity along y", &c->vy), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-x0", 0.2, 0.0, 1e3, "m", "particles at x = +-x0", &c->x0), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-perturb", 0.0, -1.0, 1.0, "m",
                                       "shift of the second particle along x (seeds a symmetry break)", &c->perturb), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-y0", 0.2, 0.0, 1e6, "m", "particles' initial y", &c->y0), done);
  /* -cg_width needs d first */
  TlScale scale = {"d", c->d, "particle diameter"};
  TL_CHECK_GOTO(s, tl_options_get_scaled(o, "-cg_width", "0", 0.0, 1e6, "m", &scale, 1,
                                         "CG width c (0: Dirac, Eq. 16; '10d' = 10 particle diameters)", &c->cg_width), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-cg_kernel", "lucy", kernels, "CG kernel for c > 0", &kernel), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-cg_subdivisions", 0, 0, 64, "CG quadrature sub-cells per face direction (0: from c)",
                                      &c->cg_subdivisions), done);
  static const char *const supports[] = {"surface", "elements", NULL}; /* TL_SCOUPLING_SUPPORT_* order */
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-cg_support", "surface", supports,
                                         "c > 0: the kernel normalised and integrated over the coupled surface (Eq. 15) "
                                         "or over the SCoupling elements' integration points (the code of the "
                                         "published runs)", &c->cg_support), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-dt_factor", 0.01, 1e-6, 10.0, "",
                                       "dt = factor * pi * sqrt(2 m / k_n) (0.01 t_c: dt = 9.09e-5 s)", &c->dt_factor), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-stepper", "newmark", steppers, "FEM time stepper", &c->stepper), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-substeps", 1, 1, 100000, "DEM steps per FEM step (1: lock-step)", &c->substeps), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-one_way", 0, "rigid beam (one-way coupling)", &c->one_way), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-coupling", "predict", schemes,
                                         "walls on the beam's predictor with forces at t_n+1; FE first with the last "
                                         "forces and walls interpolated (serial staggered); both models from t_n "
                                         "(Fig. 8 read literally); or DEM first with the walls one step behind, then FE "
                                         "(the order of the published runs' code)", &c->scheme), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-average_forces", 0,
                                       "sub-cycling: load the beam with the average of the DEM steps' forces, not the "
                                       "last step's (lags by half a step: unstable)", &c->average_forces), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-reuse", 1000, 1, 100000, "Newmark: refactorise every n Newton iterations", &c->reuse), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-keep_factors", 1, "Newmark: keep the factors across steps", &c->keep_factors), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-predictor", "auto", predictors,
                                         "Newmark: Newton's start (auto: Taylor when the beam's modes are resolved, last: u_n)",
                                         &c->predictor), done);
  static const char *const newtons[] = {"kinsol", "sunnonlinsol", NULL}; /* TL_NEWTON_* order */
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-newton", "sunnonlinsol", newtons,
                                         "Newmark: Newton through KINSOL (converged on the residual, evaluated at every "
                                         "iterate) or SUNNonlinSol (CVODE's test on the correction with an estimated "
                                         "rate: the accepted iterate is not evaluated)", &c->newton), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-energy_limit", 10.0, 0.0, 1e12, "",
                                       "stop with a diagnosis when the total energy exceeds this multiple of its start (0: never)",
                                       &c->energy_limit), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-newton_rtol", 1e-6, 1e-16, 1e-2, "",
                                       "Newmark: Newton stops at |R| <= rtol x force scale (the default takes one "
                                       "correction per step; S1's figures agree with 1e-10 in every printed digit)",
                                       &c->newton_rtol), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-t_end", 0.0, 0.0, 1e6, "s", "end time (0: when the particles leave the beam)", &c->t_end), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-t_max", 80.0, 0.0, 1e6, "s", "end time if the particles never leave", &c->t_max), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-table_dt", 0.01, 0.0, 1e6, "s", "table rows every (0: every step)", &c->table_dt), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-snapshot_dt", 1.0, 0.0, 1e6, "s", "HDF5/XDMF snapshots every (0: none)", &c->snapshot_dt), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-checkpoint_every", 0, 0, 1000000000,
                                      "checkpoint every n coupled steps to <output_dir>/checkpoint.h5 (0: none)", &c->checkpoint_every), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-restart", "", "continue from this checkpoint file", &c->restart), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-stop_step", 0, 0, 1000000000, "stop after this coupled step (0: run to the end)",
                                      &c->stop_step), done);
  TL_CHECK_GOTO(s, tl_output_dir(o, &c->output_dir), done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  /* The particles must start on the beam, or the run measures nothing. */
  if (!(c->x0 + fabs(c->perturb) <= 0.5 * c->beam.b)) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                     "-x0 %g m (with -perturb %g m) puts a particle beside the beam: |x| must be at most half the "
                     "width, %g m", c->x0, c->perturb, 0.5 * c->beam.b);
    goto done;
  }
  if (!(c->y0 < c->beam.L)) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                     "-y0 %g m puts the particles beyond the beam's free end at y = L = %g m", c->y0, c->beam.L);
    goto done;
  }
  c->kernel = kernels[kernel];
  c->beam.nx = (size_t)nx;
  c->beam.ny = (size_t)ny;
  c->beam.nz = (size_t)nz;
  c->options = o;
  return TL_OK;
done:
  tl_contact_law_destroy(&c->law);
  tl_free(&c->output_dir);
  tl_options_destroy(&o);
  return s;
}

/* Snapshots: the beam through the solid's output (displacement, velocity,
 * element stresses) and the particles, HDF5 + XDMF. */
typedef struct {
  TlSolidOutput *beam;
  TlParticleWriter *part;
} Snapshots;

static TlStatus snapshots_open(const Config *c, TlSolid *solid, Snapshots *sn)
{
  memset(sn, 0, sizeof *sn);
  if (c->snapshot_dt <= 0.0) {
    size_t removed;
    if (c->restart && c->restart[0]) return TL_OK;
    /* a rerun with snapshots off: the earlier run's series would pass for this one's */
    TL_CHECK(tl_series_sweep_whole(c->output_dir, "beam", &removed));
    return tl_series_sweep_whole(c->output_dir, "particles", &removed);
  }
  TL_CHECK(tl_solid_output_create(solid, c->output_dir, "beam", &sn->beam));
  TL_CHECK(tl_particle_writer_create(c->output_dir, "particles", &sn->part));
  return TL_OK;
}

static TlStatus snapshots_write(Snapshots *sn, long step, double t, const TlStepper *st, TlParticles *P)
{
  if (!sn->beam) return TL_OK;
  TL_CHECK(tl_solid_output_write(sn->beam, step, t, st->u, st->v));
  TlParticleView pv = {.n = P->n, .position = P->x, .radius = P->radius, .velocity = P->v, .force = P->f,
                       .species = (const int *)P->species, .id = P->id};
  TL_CHECK(tl_particle_writer_write(sn->part, step, t, &pv));
  return TL_OK;
}

static void snapshots_close(Snapshots *sn)
{
  tl_solid_output_destroy(&sn->beam);
  tl_particle_writer_destroy(&sn->part);
}

/* Running diagnostics, checkpointed with the run. */
typedef struct {
  int64_t step;
  double err_int, err_time, sym_dev, E_max, t_off;
  double e0[6]; /* initial energies: kinetic, elastic, gravitational, beam kinetic, strain, total */
} Diagnostics;

static TlStatus diag_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const Diagnostics *d = object;
  double v[5] = {d->err_int, d->err_time, d->sym_dev, d->E_max, d->t_off};
  TL_CHECK(tl_checkpoint_write_int64(w, group, "step", d->step));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "running", 5, v));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "initial_energies", 6, d->e0));
  return TL_OK;
}

static TlStatus diag_load(void *object, TlCheckpointReader *r, const char *group)
{
  Diagnostics *d = object;
  double v[5];
  TL_CHECK(tl_checkpoint_read_int64(r, group, "step", &d->step));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "running", 5, v));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "initial_energies", 6, d->e0));
  d->err_int = v[0], d->err_time = v[1], d->sym_dev = v[2], d->E_max = v[3], d->t_off = v[4];
  return TL_OK;
}

static const TlCheckpointOps diag_checkpoint_ops = {
    .header = {"checkpoint", "particle_cantilever_v1", "running diagnostics of the S1 run"},
    .save = diag_save,
    .load = diag_load,
};

static TlStatus open_table(const Config *c, const char *name, size_t n, const TlColumn *cols, TlTimeSeries **ts)
{
  char *base = NULL;
  TL_CHECK(tl_path_join(c->output_dir, name, &base));
  TlStatus s = tl_timeseries_create(base, TL_TIMESERIES_CSV, n, cols, ts);
  tl_free(&base);
  return s;
}

static TlStatus run(int argc, char **argv)
{
  Config c;
  memset(&c, 0, sizeof c);
  TL_CHECK(tl_initialize());
  TL_CHECK(configure(argc, argv, &c));
  const double wall0 = tl_wtime();
  const clock_t cpu0 = clock();
  TlStatus s = TL_OK;
  TlCantilever *beam = NULL;
  TlSCoupling *sc = NULL;
  TlDem *dem = NULL;
  TlStepper *st = NULL;
  TlCoupledLoop *loop = NULL;
  TlTimeSeries *traj = NULL, *energy = NULL, *path = NULL;
  TlCheckpoint *cp = NULL;
  char *cp_path = NULL;
  Snapshots sn;
  memset(&sn, 0, sizeof sn);
  TL_CHECK_GOTO(s, tl_cantilever_create(&c.beam, &beam), done);
  beam->load_scale = 0.0;
  /* Coupled boundary: every free face (all but the clamped end). */
  TlSCouplingOptions so;
  tl_scoupling_options_default(&so);
  so.width = c.cg_width;
  so.kernel = c.kernel;
  so.subdivisions = (int)c.cg_subdivisions;
  so.support = c.cg_support;
  const char *clamped[] = {"ymin"};
  TL_CHECK_GOTO(s, tl_scoupling_create_boundary(beam->solid, 1, clamped, &so, &sc), done);
  /* The particles. */
  const double r = 0.5 * c.d, m = c.rho_g * 4.0 / 3.0 * M_PI * r * r * r;
  const double overlap = m * c.g / c.kn, z0 = 0.5 * c.beam.h + r - overlap;
  const double dt = c.dt_factor * M_PI * sqrt(2.0 * m / c.kn);
  TL_CHECK_GOTO(s, tl_dem_create(&dem), done);
  int sp;
  TL_CHECK_GOTO(s, tl_particles_add_species(tl_dem_particles(dem), "grain", c.rho_g, r, r, &sp), done);
  double gamma_n; /* the contact dashpot, N s/m */
  TL_CHECK_GOTO(s, tl_contact_law_get(c.law, "c_n", &gamma_n), done);
  TL_CHECK_GOTO(s, tl_dem_add_law(dem, c.law, NULL), done);
  c.law = NULL; /* the world owns it */
  size_t idx;
  int64_t id[2];
  for (int k = 0; k < 2; k++) {
    TL_CHECK_GOTO(s, tl_dem_add_particle(dem, tl_v3(k ? -c.x0 + c.perturb : c.x0, c.y0, z0), tl_v3(0, c.vy, 0), r, sp, &idx), done);
    id[k] = tl_dem_particles(dem)->id[idx];
  }
  tl_dem_set_gravity(dem, tl_v3(0, 0, -c.g));
  TL_CHECK_GOTO(s, tl_scoupling_add_to_dem(sc, dem, 0), done);
  TL_CHECK_GOTO(s, tl_dem_set_timestep(dem, dt, 0), done);
  TL_CHECK_GOTO(s, tl_dem_setup(dem), done);
  TlStepperOptions sto;
  tl_stepper_options_default(&sto);
  sto.reuse = c.reuse;
  sto.keep_factors = c.keep_factors;
  sto.rtol = c.newton_rtol;
  sto.predictor = c.predictor;
  sto.nonlinear_solver = c.newton;
  sto.max_iterations = c.reuse > 1 ? 200 : 30;
  TL_CHECK_GOTO(s, tl_stepper_create(steppers[c.stepper], tl_solid_system(beam->solid), &sto, &st), done);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), done);
  if (c.stepper == 1 && !c.one_way) {
    double dt_crit;
    TL_CHECK_GOTO(s, tl_stepper_critical_dt(st, &dt_crit), done);
    if (c.substeps * dt > dt_crit)
      TL_CHECK_GOTO(s, tl_error_set(TL_ERR_UNSTABLE, __FILE__, __LINE__,
                                    "FEM step %ld x %g s = %g s is beyond the explicit critical step %g s: lower -substeps or use -stepper newmark",
                                    c.substeps, dt, c.substeps * dt, dt_crit), done);
  }
  if (!c.one_way) {
    /* A FEM step beyond a fraction of the beam's first bending period lets
     * the beam swing through its walls between two updates (the coupled
     * surface then folds); refuse it by the period. */
    const double T1 = 2.0 * M_PI / tl_cantilever_omega1(&c.beam);
    if (!(c.substeps * dt <= T1 / 20.0))
      TL_CHECK_GOTO(s, tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                                    "-substeps %ld makes the FEM step %ld x %g s = %g s, beyond T1 / 20 = %g s of the beam's "
                                    "first bending period T1 = %g s: at most -substeps %ld",
                                    c.substeps, c.substeps, dt, c.substeps * dt, T1 / 20.0, T1, (long)floor(T1 / 20.0 / dt)), done);
  }
  TlCoupledLoopOptions lo;
  tl_coupled_loop_options_default(&lo);
  lo.substeps = (int)c.substeps;
  lo.one_way = c.one_way;
  lo.scheme = c.scheme;
  lo.average_forces = c.average_forces;
  TL_CHECK_GOTO(s, tl_coupled_loop_create(dem, beam->solid, st, 1, &sc, &lo, &loop), done);
  /* Tables and the analytic path. */
  const double I = c.beam.b * pow(c.beam.h, 3) / 12.0, F = 2.0 * m * c.g;
  const TlColumn pcols[] = {{"y", "m"}, {"z_ref", "m"}, {"x_ref", "m"}};
  TL_CHECK_GOTO(s, open_table(&c, "reference_path", 3, pcols, &path), done);
  for (int k = 0; k <= 600; k++) {
    double y = c.beam.L * k / 600.0, row[3] = {y, z0 - F * y * y * y / (3.0 * c.beam.E * I), c.x0};
    TL_CHECK_GOTO(s, tl_timeseries_append(path, row), done);
  }
  TL_CHECK_GOTO(s, tl_timeseries_close(&path), done);
  const TlColumn tcols[] = {{"t", "s"}, {"x1", "m"}, {"y1", "m"}, {"z1", "m"}, {"x2", "m"}, {"y2", "m"}, {"z2", "m"},
                            {"z_ref1", "m"}, {"z_ref2", "m"}, {"err", "m"}, {"contacts", ""}, {"active_scoupling_elements", ""}};
  TL_CHECK_GOTO(s, open_table(&c, "trajectory", 12, tcols, &traj), done);
  const TlColumn ecols[] = {{"t", "s"}, {"dem_kinetic", "J"}, {"dem_elastic", "J"}, {"gravitational", "J"},
                            {"fem_kinetic", "J"}, {"fem_strain", "J"}, {"work_on_solid", "J"}, {"work_on_particles", "J"},
                            {"total", "J"}};
  TL_CHECK_GOTO(s, open_table(&c, "energy", 9, ecols, &energy), done);
  TL_CHECK_GOTO(s, snapshots_open(&c, beam->solid, &sn), done);
  TlCoupledEnergy e;
  Diagnostics d;
  memset(&d, 0, sizeof d);
  d.E_max = -INFINITY;
  d.t_off = NAN;
  TL_CHECK_GOTO(s, tl_coupled_loop_energy(loop, &e), done);
  d.e0[0] = e.dem_kinetic, d.e0[1] = e.dem_elastic, d.e0[2] = e.dem_gravitational;
  d.e0[3] = e.fem_kinetic, d.e0[4] = e.fem_strain, d.e0[5] = e.dem_kinetic + e.dem_elastic + e.fem_kinetic + e.fem_strain;
  /* Checkpoint: the beam's stepper, the world, the loop, the tables, the
   * snapshot series and the running diagnostics. */
  TL_CHECK_GOTO(s, tl_checkpoint_create(&cp), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, c.options), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "fem", &tl_stepper_checkpoint_ops, st), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "coupling", &tl_coupled_loop_checkpoint_ops, loop), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "trajectory", &tl_timeseries_checkpoint_ops, traj), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "energy", &tl_timeseries_checkpoint_ops, energy), done);
  if (sn.beam) {
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "beam_snapshots", &tl_solid_output_checkpoint_ops, sn.beam), done);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "particle_snapshots", &tl_particle_writer_checkpoint_ops, sn.part), done);
  }
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "driver", &diag_checkpoint_ops, &d), done);
  TL_CHECK_GOTO(s, tl_path_join(c.output_dir, "checkpoint.h5", &cp_path), done);
  int resumed = 0;
  if (c.restart && c.restart[0]) {
    TL_CHECK_GOTO(s, tl_checkpoint_load(cp, c.restart, NULL, NULL), done);
    tl_printf("restarted from %s at step %lld, t = %.9g s\n", c.restart, (long long)d.step, tl_coupled_loop_time(loop));
    resumed = 1;
  }
  const double Dt = c.substeps * dt;
  const double t_stop = c.t_end > 0.0 ? c.t_end : c.t_max;
  const long n_macro = (long)ceil(t_stop / Dt - 1e-9);
  const long out_every = c.table_dt > 0.0 ? (long)fmax(1.0, floor(c.table_dt / Dt + 0.5)) : 1;
  const long snap_every = c.snapshot_dt > 0.0 ? (long)fmax(1.0, floor(c.snapshot_dt / Dt + 0.5)) : 0;
  tl_printf("S1: c = %g m (%g d), dt = %.4g s, %s FEM%s, %ld DEM steps per FEM step (%s), %zu SCoupling elements, "
            "contact damping %g N s/m\n", c.cg_width, c.cg_width / c.d, dt, steppers[c.stepper], c.one_way ? " (rigid, one-way)" : "",
            c.substeps, schemes[c.scheme], tl_scoupling_n_elements(sc), gamma_n + 0.0 /* no -0 */);
  /* Progress: the time fraction to -t_end, or, when the run ends as the
   * particles leave the beam, the larger of the fraction of -t_max and the
   * distance the slower particle has travelled along the beam. */
  TlProgress bar;
  tl_progress_init(&bar, c.t_end > 0.0 ? "S1 (time)" : "S1 (along the beam)", 1.0);
  long step = (long)d.step;
  for (;; step++) {
    if (resumed) {
      /* The state of step d.step was recorded before the checkpoint. */
      resumed = 0;
      TL_CHECK_GOTO(s, tl_coupled_loop_step(loop), done);
      continue;
    }
    const double t = tl_coupled_loop_time(loop);
    TlParticles *P = tl_dem_particles(dem);
    TlVec3 xp[2];
    for (int k = 0; k < 2; k++) {
      TL_CHECK_GOTO(s, tl_particles_find(P, id[k], &idx), done);
      xp[k] = P->x[idx];
    }
    double zr[2], e2 = 0.0;
    for (int k = 0; k < 2; k++) {
      double y = fmin(fmax(xp[k].y, 0.0), c.beam.L);
      zr[k] = z0 - F * y * y * y / (3.0 * c.beam.E * I);
      double dx = xp[k].x - (k ? -c.x0 : c.x0), dz = xp[k].z - zr[k];
      e2 += 0.5 * (dx * dx + dz * dz);
    }
    const double err = sqrt(e2);
    const int on_beam = !(xp[0].y > c.beam.L && xp[1].y > c.beam.L);
    if (!on_beam && isnan(d.t_off)) d.t_off = t;
    if (on_beam) {
      d.sym_dev = tl_track_max(d.sym_dev, fabs(xp[0].x + xp[1].x));
      if (step > 0) d.err_int += err * Dt, d.err_time += Dt;
    }
    const int last = step >= n_macro || (c.t_end <= 0.0 && !on_beam);
    if (step % out_every == 0 || last) {
      TL_CHECK_GOTO(s, tl_coupled_loop_energy(loop, &e), done);
      const double grav = e.dem_gravitational - d.e0[2];
      const double total = e.dem_kinetic + e.dem_elastic + grav + e.fem_kinetic + e.fem_strain;
      if (on_beam) d.E_max = tl_track_max(d.E_max, total);
      /* The undamped coupled system conserves energy: growth far beyond
       * the start is the coupling going unstable; stop before it runs away. */
      if (c.energy_limit > 0.0 && !(total <= c.energy_limit * fmax(d.e0[5], 1e-300))) {
        /* Advice for what this run did: sub-cycling, a lagged order, or
         * (lock-step, predictor order) the step and the CG width. */
        char advice[256];
        if (c.substeps > 1)
          snprintf(advice, sizeof advice, "fewer DEM steps per FEM step (-substeps, down to lock-step 1) may keep it stable");
        else if (c.scheme != TL_COUPLING_PREDICT)
          snprintf(advice, sizeof advice,
                   "the run is lock-step; -coupling %s lags one model by a step, the default -coupling predict does not",
                   schemes[c.scheme]);
        else
          snprintf(advice, sizeof advice,
                   "the run is lock-step with the predictor order; a smaller step (-dt_factor) or another CG width "
                   "(-cg_width) may keep it stable");
        s = tl_error_set(TL_ERR_UNSTABLE, __FILE__, __LINE__,
                         "coupled total energy %.4g J at t = %.4g s exceeds %g x its start %.4g J: the coupling is "
                         "unstable with c = %g m, %s FEM, %ld DEM step%s per FEM step, -coupling %s (%s; -energy_limit 0 "
                         "runs on)",
                         total, t, c.energy_limit, d.e0[5], c.cg_width, steppers[c.stepper], c.substeps,
                         c.substeps == 1 ? "" : "s", schemes[c.scheme], advice);
        goto done;
      }
      double erow[9] = {t, e.dem_kinetic, e.dem_elastic, grav, e.fem_kinetic, e.fem_strain, e.work_on_solid,
                        e.work_on_particles, total};
      TL_CHECK_GOTO(s, tl_timeseries_append(energy, erow), done);
      double trow[12] = {t, xp[0].x, xp[0].y, xp[0].z, xp[1].x, xp[1].y, xp[1].z, zr[0], zr[1], err,
                         (double)tl_scoupling_n_contacts(sc), (double)tl_scoupling_n_active_elements(sc)};
      TL_CHECK_GOTO(s, tl_timeseries_append(traj, trow), done);
      double done_frac = (double)step / (double)(n_macro > 0 ? n_macro : 1);
      if (c.t_end <= 0.0) {
        const double along = (fmin(xp[0].y, xp[1].y) - c.y0) / fmax(c.beam.L - c.y0, 1e-300);
        done_frac = fmax(done_frac, fmin(fmax(along, 0.0), 1.0));
      }
      tl_progress_update(&bar, done_frac);
    }
    if (snap_every > 0 && (step % snap_every == 0 || last))
      TL_CHECK_GOTO(s, snapshots_write(&sn, step, t, st, P), done);
    if (last) break;
    d.step = step;
    if (c.checkpoint_every > 0 && step > 0 && step % c.checkpoint_every == 0)
      TL_CHECK_GOTO(s, tl_checkpoint_save(cp, cp_path, t, d.step), done);
    if (c.stop_step > 0 && step >= c.stop_step) break;
    TL_CHECK_GOTO(s, tl_coupled_loop_step(loop), done);
  }
  tl_progress_finish(&bar);
  const double err_int = d.err_int, err_time = d.err_time, sym_dev = d.sym_dev, E_max = d.E_max, t_off = d.t_off;
  const double err_avg = err_time > 0.0 ? err_int / err_time : NAN;
  const double wall = tl_wtime() - wall0;
  const double cpu = (double)(clock() - cpu0) / CLOCKS_PER_SEC;
  char off[64];
  if (isnan(t_off))
    snprintf(off, sizeof off, "particles stay on the beam");
  else
    snprintf(off, sizeof off, "particles leave the beam at t = %.4g s", t_off);
  tl_printf("%ld coupled steps to t = %.4g s; %s; err_avg = %.4g m, "
            "largest |x1 + x2| = %.3g m, largest total energy %.4g J (start %.4g J)\n",
            step, tl_coupled_loop_time(loop), off, err_avg, sym_dev, E_max, d.e0[5]);
  TlStepperStats fs;
  tl_stepper_get_stats(st, &fs);
  tl_printf("FEM: %ld steps, %.3g Newton iterations per step, %ld factorisations; %.3g s in FE steps, %.3g s elsewhere (DEM, walls, CG, output)\n",
            fs.steps, fs.steps ? (double)fs.newton_iterations / (double)fs.steps : 0.0, fs.factorisations, fs.t_step,
            wall - fs.t_step);
  {
    char plot_cmd[4200], plot_dir[4200];
    tl_plot_abs_dir(c.output_dir, plot_dir, sizeof plot_dir);
    tl_printf("files: %s/trajectory.csv, energy.csv, reference_path.csv%s\n", plot_dir,
              sn.beam ? ", beam.xmf, particles.xmf" : "");
    tl_printf("plots: %s %s\n", tl_plot_command(TALUS_TOOLS_DIR, "plot_particle_cantilever.py", plot_cmd, sizeof plot_cmd),
              plot_dir);
  }
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_real(&sum, "c", c.cg_width);
  tl_summary_real(&sum, "err_avg", err_avg);
  tl_summary_real(&sum, "sym_dev", sym_dev);
  tl_summary_real(&sum, "E_max", E_max);
  if (isnan(t_off))
    tl_summary_string(&sum, "t_off", "none"); /* the particles stay on the beam to the end */
  else
    tl_summary_real(&sum, "t_off", t_off);
  tl_summary_real(&sum, "cpu", cpu);
  tl_summary_real(&sum, "wall", wall);
  s = tl_summary_print(&sum, stdout);
done:
  if (traj) {
    TlStatus s2 = tl_timeseries_close(&traj);
    if (s == TL_OK) s = s2;
  }
  if (energy) {
    TlStatus s2 = tl_timeseries_close(&energy);
    if (s == TL_OK) s = s2;
  }
  tl_timeseries_destroy(&path);
  tl_checkpoint_destroy(&cp);
  tl_free(&cp_path);
  snapshots_close(&sn);
  tl_coupled_loop_destroy(&loop);
  tl_stepper_destroy(&st);
  tl_dem_destroy(&dem);
  tl_contact_law_destroy(&c.law);
  tl_scoupling_destroy(&sc);
  tl_cantilever_destroy(&beam);
  tl_free(&c.output_dir);
  tl_options_destroy(&c.options);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
