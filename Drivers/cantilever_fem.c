/* The cantilever of S1 (Cheng et al. 2022, §6.1) (2 x 2 x 30 Hex8, 0.8 x 0.8 x 12 m,
 * E = 100 MPa, nu = 0, rho = 1309 kg/m^3, clamped at y = 0) on its own:
 *
 *   -mode small      a small tip load, quasi-statically; the tip deflection
 *                    against Timoshenko beam theory;
 *   -mode large      a large tip load in load steps (P L^2/(E I) up to
 *                    -load_parameter); the tip path against the
 *                    inextensible elastica;
 *   -mode vibration  released from the statically deflected shape, free
 *                    vibration with Newmark; period against the first
 *                    bending frequency, energy drift per period.
 *   -mode all        the three in turn (default);
 *   -mode linear     linear static analysis: K at the reference state, one
 *                    solve; the tip deflection against Timoshenko;
 *   -mode modal      the lowest -modes eigenpairs of K phi = omega^2 M phi
 *                    (consistent mass, or -lumped), ARPACK shift-invert;
 *                    the first against the Euler-Bernoulli frequency;
 *   -mode nlgeom     geometrically nonlinear static analysis under the dead
 *                    tip load P = -load_parameter E I / L^2 in -load_steps
 *                    increments (the tip reported in full; the elastica as
 *                    a reference).
 *
 * -material picks the law by its registered name (default hooke, the law
 * of Cheng et al. 2022; saint_venant_kirchhoff is CalculiX's and Abaqus's linear
 * elasticity under NLGEOM, for comparisons with them).
 *
 * Output: <output_dir>/<mode>.csv time series, and for the vibration of a
 * beam HDF5/XDMF snapshots with element stresses (beam.xmf, warp by "displacement" in
 * ParaView); last line `summary: ...`.
 *
 * Restart (vibration): -checkpoint_every n writes <output_dir>/checkpoint.h5
 * every n Newmark steps (the stepper with the solid's state, the table, the
 * snapshot writer and the driver's running diagnostics); -restart <file>,
 * with the same scene options, continues from it bit for bit (the static
 * deflection is not recomputed; restart in the same -output_dir to keep one
 * snapshot series); -stop_step n ends the run after step n. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_options_checkpoint.h"
#include "tl_options_renamed.h"
#include "tl_series_sweep.h"
#include "tl_plot_hint.h"
#include "tl_atomic_file.h"
#include "tl_cantilever.h"
#include "tl_checkpoint.h"
#include "tl_linear_static.h"
#include "tl_modal.h"
#include "tl_solid_output.h"
#include "tl_stepper.h"
#include "tl_timeseries.h"

typedef struct {
  TlCantileverParams beam;
  const char *solver, *output_dir, *restart, *material;
  double rtol, load_parameter, dt, periods;
  long load_steps, reuse, snapshot_every, checkpoint_every, stop_step, n_modes;
  int mode, check, lumped;
  double tolerance;
  TlOptions *options; /* holds the option strings until the end */
} Config;

enum { MODE_ALL, MODE_SMALL, MODE_LARGE, MODE_VIBRATION, MODE_LINEAR, MODE_MODAL, MODE_NLGEOM };
static const char *const modes[] = {"all", "small", "large", "vibration", "linear", "modal", "nlgeom", NULL};
static const char *const elements[] = {"hex8", "hex27", NULL};
static const char *const solvers[] = {"cholmod", "klu", "umfpack", NULL};

static TlStatus configure(int argc, char **argv, Config *c)
{
  TlOptions *o = NULL;
  TlStatus s = TL_OK;
  TL_CHECK(tl_options_create(argc, argv,
                             "The S1 cantilever alone: static tip load (small and large deflection) "
                             "and free vibration, against beam theory and the elastica.  Paper: " TL_PAPER_CHENG_2022 ".",
                             &o));
  static const TlRenamedOption renamed[] = {
      {"-rtol", "-newton_rtol", NULL},
      {"-snapshot_every", "-snapshot_dt", "now a time interval in seconds, as in every time-stepping driver"}};
  TL_CHECK_GOTO(s, tl_options_refuse_renamed(o, renamed, (int)(sizeof renamed / sizeof renamed[0])), done);
  tl_cantilever_params_default(&c->beam);
  int mode = 0, elem = 0, solver = 0, check = 0;
  double snapshot_dt = 0.0;
  long nx, ny, nz;
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-mode", "all", modes, "what to run", &mode), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-elements", "hex8", elements, "element type", &elem), done);
  const char *mesh_file = "";
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-mesh", "",
                                         "the beam from a Gmsh mesh file (msh 4.1 or 2.2, ASCII or binary, any 3-D "
                                         "element type) instead of the -elements -nx x -ny x -nz box: it must span "
                                         "-width x -length x -height and name its clamped and loaded ends ymin and "
                                         "ymax (physical surfaces)",
                                         &mesh_file),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nx", 2, 1, 1000, "cells across x (width)", &nx), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-ny", 30, 1, 100000, "cells along y (length)", &ny), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nz", 2, 1, 1000, "cells across z (height)", &nz), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-width", 0.8, 1e-6, 1e6, "m", "beam width b (x)", &c->beam.b), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-height", 0.8, 1e-6, 1e6, "m", "beam height h (z)", &c->beam.h), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-length", 12.0, 1e-6, 1e6, "m", "beam length L (y)", &c->beam.L), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-E", 1e8, 1e-3, 1e15, "Pa", "Young's modulus", &c->beam.E), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-nu", 0.0, -0.99, 0.49, "", "Poisson's ratio", &c->beam.nu), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-rho", 1309.0, 1e-6, 1e6, "kg/m^3", "density", &c->beam.rho), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-material", "hooke",
                                         "law by registered name (hooke, hooke_covariant, neo_hookean, "
                                         "saint_venant_kirchhoff, ...), with -E and -nu",
                                         &c->material), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-modes", 6, 1, 1000, "modal mode: eigenpairs wanted", &c->n_modes), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-lumped", 0, "modal mode: lumped instead of consistent mass", &c->lumped),
                done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-tip_load", 1644.0, 0.0, 1e12, "N",
                                       "small tip load (2 m g of S1's particles)", &c->beam.load), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-load_parameter", 3.0, 0.0, 20.0, "",
                                       "large and nlgeom modes: final P L^2 / (E I)", &c->load_parameter), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-load_steps", 10, 1, 100000, "large and nlgeom modes: load steps", &c->load_steps), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-dt", 0.02, 1e-9, 10.0, "s", "vibration: Newmark time step", &c->dt), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-periods", 3.0, 0.1, 1e4, "", "vibration: duration in first-mode periods", &c->periods), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-solver", "cholmod", solvers, "sparse direct solver", &solver), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-reuse", 1, 1, 1000, "refactorise every n Newton iterations (1 = full Newton)", &c->reuse), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-newton_rtol", 1e-10, 1e-16, 1e-2, "", "Newton residual tolerance relative to the force scale", &c->rtol), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-output_dir", "results/cantilever_fem", "output folder", &c->output_dir), done);
  TL_CHECK_GOTO(s, tl_output_dir_check(c->output_dir), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-snapshot_dt", 0.2, 0.0, 1e6, "s",
                                       "vibration: HDF5/XDMF mesh snapshots every (rounded to whole steps; 0: none)",
                                       &snapshot_dt), done);
  /* Snapshots at whole steps: the nearest multiple of -dt, at least one step. */
  c->snapshot_every = snapshot_dt > 0.0 ? (long)fmax(1.0, round(snapshot_dt / c->dt)) : 0;
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-checkpoint_every", 0, 0, 100000000,
                                      "vibration, large, nlgeom: checkpoint every n (load) steps to <output_dir>/checkpoint.h5 (0: none)",
                                      &c->checkpoint_every), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-restart", "", "vibration, large, nlgeom: continue from this checkpoint file", &c->restart),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-stop_step", 0, 0, 100000000, "vibration, large, nlgeom: stop after this (load) step (0: run to the end)",
                                      &c->stop_step), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-check", 0, "exit with an error when a result misses -tolerance", &check), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-tolerance", 0.01, 0.0, 10.0, "", "relative tolerance for -check", &c->tolerance), done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  c->mode = mode;
  c->check = check;
  c->beam.type = elem ? &tl_element_hex27 : &tl_element_hex8;
  c->beam.material = c->material;
  c->beam.nx = (size_t)nx;
  c->beam.ny = (size_t)ny;
  c->beam.nz = (size_t)nz;
  c->beam.mesh_file = mesh_file;
  c->solver = solvers[solver];
  if ((mode == MODE_ALL || mode == MODE_SMALL || mode == MODE_VIBRATION) && !(c->beam.load > 0.0)) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                     "-tip_load %g N: the small mode compares the deflection under it with Timoshenko's and the "
                     "vibration mode releases the beam from it; it must be > 0", c->beam.load);
    goto done;
  }
  if (mode == MODE_ALL || mode == MODE_SMALL || mode == MODE_VIBRATION) {
    /* The small mode loads the beam in one step and compares it with linear
     * beam theory: a load beyond small deflection is the large mode's (a load
     * step far beyond it folds elements, "singular metric"). */
    const double I = c->beam.b * pow(c->beam.h, 3) / 12.0, EI = c->beam.E * I, L2 = c->beam.L * c->beam.L;
    const double k = c->beam.load * L2 / EI, k_max = 0.3;
    if (!(k <= k_max)) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "-tip_load %g N is a load parameter P L^2 / (E I) = %.3g, beyond the small-deflection limit %g "
                       "(tip deflection about L / 10): at most -tip_load %.4g N; large loads are -mode large with "
                       "-load_parameter", c->beam.load, k, k_max, k_max * EI / L2);
      goto done;
    }
  }
  if (mode == MODE_ALL || mode == MODE_VIBRATION) {
    /* Newmark is stable at any step, but a step that does not resolve the
     * first period measures nothing: at least 20 steps per period. */
    double T1 = 2.0 * M_PI / tl_cantilever_omega1(&c->beam);
    if (!(c->dt <= T1 / 20.0)) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "-dt %g s does not resolve the first bending period T1 = %.4g s: at most T1 / 20 = %.4g s",
                       c->dt, T1, T1 / 20.0);
      goto done;
    }
  }
  /* -periods is the vibration's end time */
  TL_CHECK_GOTO(s, tl_options_set_restart_safe(o, "-periods"), done);
  c->options = o;
  return TL_OK;
done:
  tl_options_destroy(&o);
  return s;
}

static void stepper_options(const Config *c, TlStepperOptions *so)
{
  tl_stepper_options_default(so);
  so->solver = c->solver;
  so->rtol = c->rtol;
  so->reuse = c->reuse;
  so->max_iterations = c->reuse > 1 ? 200 : 30;
}

static TlStatus open_table(const Config *c, const char *name, size_t n, const TlColumn *cols,
                           TlTimeSeries **ts)
{
  char *base = NULL;
  TL_CHECK(tl_mkdir_p(c->output_dir));
  TL_CHECK(tl_path_join(c->output_dir, name, &base));
  TlStatus s = tl_timeseries_create(base, TL_TIMESERIES_CSV, n, cols, ts);
  tl_free(&base);
  return s;
}

/* Under -check: |value| within the tolerance (NaN fails); otherwise says
 * which check failed and sets *failed. */
static void check_within(const Config *c, const char *what, double value, int *failed)
{
  if (!c->check || fabs(value) <= c->tolerance) return;
  tl_log(TL_LOG_ERROR, "check failed: %s %.4g exceeds %.4g", what, value, c->tolerance);
  *failed = 1;
}

/* ------------------------------------------------------------ small */
static TlStatus run_small(const Config *c, TlSummary *sum, int *failed)
{
  TlCantilever *beam = NULL;
  TlStepper *st = NULL;
  TlStepperOptions so;
  stepper_options(c, &so);
  TL_CHECK(tl_cantilever_create(&c->beam, &beam));
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_stepper_create("quasi_static", tl_solid_system(beam->solid), &so, &st), done);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), done);
  double t0 = tl_wtime();
  TL_CHECK_GOTO(s, tl_stepper_step(st, 1.0), done);
  double wall = tl_wtime() - t0, tip[3];
  tl_cantilever_tip(beam, st->u, tip);
  double ref = tl_cantilever_timoshenko(&c->beam), err = (-tip[2] - ref) / ref;
  tl_printf("small load P = %g N on %s %zux%zux%zu (%lld dofs): tip deflection %.6e m, "
            "Timoshenko %.6e m, error %+.3f %% (%.3f s)\n",
            c->beam.load, c->beam.type->header.name, c->beam.nx, c->beam.ny, c->beam.nz,
            (long long)st->n, -tip[2], ref, 100.0 * err, wall);
  tl_summary_real(sum, "small_tip", -tip[2]);
  tl_summary_real(sum, "small_timoshenko", ref);
  tl_summary_real(sum, "small_error", err);
  check_within(c, "small-load error", err, failed);
done:
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&beam);
  return s;
}

/* ------------------------------------------------------------ large */
/* The load step reached and the Newton iterations so far (the stepper's
 * own counters start again at a restart), checkpointed with the run. */
typedef struct {
  int64_t step, newton;
} LoadProgress;

static TlStatus load_progress_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const LoadProgress *p = object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "load_step", p->step));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "newton_iterations", p->newton));
  return TL_OK;
}

static TlStatus load_progress_load(void *object, TlCheckpointReader *r, const char *group)
{
  LoadProgress *p = object;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "load_step", &p->step));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "newton_iterations", &p->newton));
  TL_CHECK(tl_checkpoint_check_count(r, group, "load_step", p->step, 0, INT64_MAX));
  TL_CHECK(tl_checkpoint_check_count(r, group, "newton_iterations", p->newton, 0, INT64_MAX));
  return TL_OK;
}

static const TlCheckpointOps load_progress_checkpoint_ops = {
    .header = {"checkpoint", "cantilever_load_steps_v1", "load step and Newton iterations of the large-deflection modes"},
    .save = load_progress_save,
    .load = load_progress_load,
};

static TlStatus run_large(const Config *c, int nlgeom, TlSummary *sum, int *failed)
{
  TlCantileverParams p = c->beam;
  double I = p.b * p.h * p.h * p.h / 12.0;
  p.load = c->load_parameter * p.E * I / (p.L * p.L);
  TlCantilever *beam = NULL;
  TlStepper *st = NULL;
  TlTimeSeries *ts = NULL;
  TlCheckpoint *cp = NULL;
  char *cp_path = NULL;
  TlStepperOptions so;
  stepper_options(c, &so);
  so.ramp_time = 1.0;
  TL_CHECK(tl_cantilever_create(&p, &beam));
  TlStatus s = TL_OK;
  const TlColumn cols[] = {{"load_parameter", ""}, {"tip_w", "m"}, {"tip_v", "m"},
                           {"elastica_w", "m"}, {"elastica_v", "m"}, {"newton_iterations", ""}};
  TL_CHECK_GOTO(s, open_table(c, nlgeom ? "nlgeom" : "large", 6, cols, &ts), done);
  TL_CHECK_GOTO(s, tl_stepper_create("quasi_static", tl_solid_system(beam->solid), &so, &st), done);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), done);
  double tip[3] = {0, 0, 0}, we = 0, ve = 0, t0 = tl_wtime();
  /* Checkpoints (-checkpoint_every, -restart, -stop_step count load steps)
   * when this mode runs alone; in -mode all they are the vibration's. */
  const int own = c->mode == MODE_LARGE || c->mode == MODE_NLGEOM;
  LoadProgress lp = {0, 0};
  if (own && (c->checkpoint_every > 0 || (c->restart && c->restart[0]))) {
    TL_CHECK_GOTO(s, tl_checkpoint_create(&cp), done);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, c->options), done);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "quasi_static", &tl_stepper_checkpoint_ops, st), done);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "load_table", &tl_timeseries_checkpoint_ops, ts), done);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "driver", &load_progress_checkpoint_ops, &lp), done);
    TL_CHECK_GOTO(s, tl_path_join(c->output_dir, "checkpoint.h5", &cp_path), done);
    if (c->restart && c->restart[0]) {
      TL_CHECK_GOTO(s, tl_checkpoint_load(cp, c->restart, NULL, NULL), done);
      if (lp.step > c->load_steps)
        TL_CHECK_GOTO(s, tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "checkpoint '%s' is at load step %lld, beyond -load_steps %ld",
                                      c->restart, (long long)lp.step, c->load_steps), done);
      tl_printf("restarted from %s at load step %lld\n", c->restart, (long long)lp.step);
    }
  }
  const long newton0 = (long)lp.newton; /* the iterations before a restart */
  long prev_it = newton0;
  TlProgress bar;
  tl_progress_init(&bar, "load steps", (double)c->load_steps);
  for (long k = (long)lp.step + 1; k <= c->load_steps; ++k) {
    TL_CHECK_GOTO(s, tl_stepper_step(st, 1.0 / (double)c->load_steps), done);
    double lambda = (double)k / (double)c->load_steps;
    tl_cantilever_tip(beam, st->u, tip);
    TL_CHECK_GOTO(s, tl_cantilever_elastica(lambda * c->load_parameter, &we, &ve), done);
    TlStepperStats ss;
    tl_stepper_get_stats(st, &ss);
    const long total_it = newton0 + ss.newton_iterations;
    double row[6] = {lambda * c->load_parameter, -tip[2], -tip[1], we * p.L, ve * p.L, (double)(total_it - prev_it)};
    prev_it = total_it;
    TL_CHECK_GOTO(s, tl_timeseries_append(ts, row), done);
    tl_progress_update(&bar, (double)k);
    lp.step = k;
    lp.newton = total_it;
    if (cp && c->checkpoint_every > 0 && k % c->checkpoint_every == 0)
      TL_CHECK_GOTO(s, tl_checkpoint_save(cp, cp_path, st->t, k), done);
    if (own && c->stop_step > 0 && k >= c->stop_step && k < c->load_steps) {
      tl_progress_finish(&bar);
      tl_printf("stopped after load step %ld of %ld\n", k, c->load_steps);
      tl_summary_int(sum, "stopped_at_load_step", k);
      goto done;
    }
  }
  tl_progress_finish(&bar);
  /* the state at the full load (also when a restart began there) */
  tl_cantilever_tip(beam, st->u, tip);
  TL_CHECK_GOTO(s, tl_cantilever_elastica(c->load_parameter, &we, &ve), done);
  double wall = tl_wtime() - t0;
  double ew = (-tip[2] - we * p.L) / (we * p.L), ev = (-tip[1] - ve * p.L) / (ve * p.L);
  TlStepperStats ss;
  tl_stepper_get_stats(st, &ss);
  ss.newton_iterations += newton0;
  if (nlgeom) {
    tl_printf("nlgeom, %s, dead tip load P = %.10g N (P L^2/(E I) = %g) in %ld steps (%ld Newton iterations, "
              "%.3f s): tip w = %.10e m, shortening v = %.10e m, lateral u = %.3e m; elastica w %.6f m, "
              "difference %+.3f %%\n",
              c->material, p.load, c->load_parameter, c->load_steps, ss.newton_iterations, wall, -tip[2], -tip[1],
              tip[0], we * p.L, 100.0 * ew);
    tl_summary_real(sum, "nlgeom_tip_w", -tip[2]);
    tl_summary_real(sum, "nlgeom_tip_v", -tip[1]);
    tl_summary_real(sum, "nlgeom_elastica_w", we * p.L);
    tl_summary_int(sum, "nlgeom_newton", ss.newton_iterations);
  } else {
    tl_printf("large load P L^2/(E I) = %g in %ld steps (%ld Newton iterations, %.3f s): tip w = %.6f m, "
              "shortening = %.6f m; elastica %.6f m, %.6f m; differences %+.3f %%, %+.3f %%\n",
              c->load_parameter, c->load_steps, ss.newton_iterations, wall, -tip[2], -tip[1], we * p.L,
              ve * p.L, 100.0 * ew, 100.0 * ev);
    tl_summary_real(sum, "large_tip_w", -tip[2]);
    tl_summary_real(sum, "large_elastica_w", we * p.L);
    tl_summary_real(sum, "large_error_w", ew);
    tl_summary_int(sum, "large_newton", ss.newton_iterations);
  }
  check_within(c, "large-deflection difference", ew, failed);
done:
  if (ts) {
    TlStatus s2 = tl_timeseries_close(&ts);
    if (s == TL_OK) s = s2;
  }
  tl_checkpoint_destroy(&cp);
  tl_free(&cp_path);
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&beam);
  return s;
}

/* ----------------------------------------------------------- linear */
static TlStatus run_linear(const Config *c, TlSummary *sum, int *failed)
{
  TlCantilever *beam = NULL;
  TL_CHECK(tl_cantilever_create(&c->beam, &beam));
  TlMechSystem *sys = tl_solid_system(beam->solid);
  double *u = NULL, tip[3];
  TlLinearStaticStats ls;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_calloc(&u, (size_t)sys->ndof, sizeof *u), done);
  TL_CHECK_GOTO(s, tl_linear_static_solve(sys, c->solver, 0.0, u, &ls), done);
  tl_cantilever_tip(beam, u, tip);
  double ref = tl_cantilever_timoshenko(&c->beam), err = (-tip[2] - ref) / ref;
  tl_printf("linear static, P = %g N on %s %zux%zux%zu (%lld dofs): tip deflection %.10e m, Timoshenko %.6e m, "
            "error %+.3f %% (assembly %.4f s, factorisation %.4f s, solve %.4f s, residual %.1e)\n",
            c->beam.load, c->beam.type->header.name, c->beam.nx, c->beam.ny, c->beam.nz, (long long)sys->ndof,
            -tip[2], ref, 100.0 * err, ls.t_assemble, ls.t_factor, ls.t_solve, ls.residual);
  tl_summary_real(sum, "linear_tip", -tip[2]);
  tl_summary_real(sum, "linear_timoshenko", ref);
  tl_summary_real(sum, "linear_error", err);
  check_within(c, "linear tip error", err, failed);
done:
  tl_free(&u);
  tl_cantilever_destroy(&beam);
  return s;
}

/* ------------------------------------------------------------ modal */
static TlStatus run_modal(const Config *c, TlSummary *sum, int *failed)
{
  TlCantilever *beam = NULL;
  TL_CHECK(tl_cantilever_create(&c->beam, &beam));
  TlMechSystem *sys = tl_solid_system(beam->solid);
  TlModalOptions mo;
  tl_modal_options_default(&mo);
  mo.n_modes = (int)c->n_modes;
  mo.lumped = c->lumped;
  TlModalStats ms;
  double *omega2 = NULL;
  TlTimeSeries *ts = NULL;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_calloc(&omega2, (size_t)mo.n_modes, sizeof *omega2), done);
  TL_CHECK_GOTO(s, tl_modal_solve(sys, &mo, omega2, NULL, &ms), done);
  const TlColumn cols[] = {{"mode", ""}, {"omega", "rad/s"}, {"frequency", "Hz"}};
  TL_CHECK_GOTO(s, open_table(c, "modal", 3, cols, &ts), done);
  double w1 = tl_cantilever_omega1(&c->beam);
  tl_printf("modal analysis on %s %zux%zux%zu (%lld dofs), %s mass: %d modes (ARPACK, %ld restarts, %ld "
            "operator applications; assembly %.4f s, factorisation %.4f s, Lanczos %.4f s; residual %.1e)\n",
            c->beam.type->header.name, c->beam.nx, c->beam.ny, c->beam.nz, (long long)sys->ndof,
            ms.consistent ? "consistent" : "lumped", mo.n_modes, ms.restarts, ms.operator_applications,
            ms.t_assemble, ms.t_factor, ms.t_lanczos, ms.residual);
  for (int k = 0; k < mo.n_modes; ++k) {
    double w = sqrt(omega2[k]);
    tl_printf("  mode %d: omega = %.10e rad/s, f = %.8g Hz\n", k + 1, w, w / (2.0 * M_PI));
    double row[3] = {(double)(k + 1), w, w / (2.0 * M_PI)};
    TL_CHECK_GOTO(s, tl_timeseries_append(ts, row), done);
    char key[32];
    snprintf(key, sizeof key, "modal_omega%d", k + 1);
    if (k < 6) tl_summary_real(sum, key, w);
  }
  double err = (sqrt(omega2[0]) - w1) / w1;
  tl_printf("  first bending frequency against Euler-Bernoulli %.6e rad/s: %+.3f %%\n", w1, 100.0 * err);
  tl_summary_real(sum, "modal_omega1_eb", w1);
  tl_summary_real(sum, "modal_residual", ms.residual);
  check_within(c, "first frequency error", err, failed);
done:
  if (ts) {
    TlStatus s2 = tl_timeseries_close(&ts);
    if (s == TL_OK) s = s2;
  }
  tl_free(&omega2);
  tl_cantilever_destroy(&beam);
  return s;
}

/* Mesh snapshots through the solid's output (HDF5 + XDMF, open beam.xmf
 * in ParaView and warp by "displacement"; element stresses too). */
typedef struct {
  TlSolidOutput *out;
} Snapshots;

static TlStatus snapshots_open(const Config *c, const TlCantilever *beam, Snapshots *sn)
{
  memset(sn, 0, sizeof *sn);
  if (c->snapshot_every <= 0) {
    size_t removed;
    if (c->restart && c->restart[0]) return TL_OK;
    /* a rerun with snapshots off: the earlier run's series would pass for this one's */
    return tl_series_sweep_whole(c->output_dir, "beam", &removed);
  }
  TL_CHECK(tl_solid_output_create(beam->solid, c->output_dir, "beam", &sn->out));
  return TL_OK;
}

static TlStatus snapshots_write(Snapshots *sn, long step, double t, const double *u, const double *v)
{
  if (!sn->out) return TL_OK;
  TL_CHECK(tl_solid_output_write(sn->out, step, t, u, v));
  return TL_OK;
}

static void snapshots_close(Snapshots *sn) { tl_solid_output_destroy(&sn->out); }

/* -------------------------------------------------------- vibration */
/* The driver's running diagnostics, checkpointed with the run. */
typedef struct {
  int64_t step;
  double e0[4]; /* kinetic, strain, external work, total at t = 0 */
  double prev_w, drift;
  int64_t n_cross;
  double t_cross[64];
} Vibration;

static TlStatus vibration_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const Vibration *v = object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "step", v->step));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "initial_energies", 4, v->e0));
  TL_CHECK(tl_checkpoint_write_double(w, group, "previous_tip_w", v->prev_w));
  TL_CHECK(tl_checkpoint_write_double(w, group, "drift", v->drift));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "zero_crossings", (size_t)v->n_cross, v->t_cross));
  return TL_OK;
}

static TlStatus vibration_load(void *object, TlCheckpointReader *r, const char *group)
{
  Vibration *v = object;
  size_t n = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "step", &v->step));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "initial_energies", 4, v->e0));
  TL_CHECK(tl_checkpoint_read_double(r, group, "previous_tip_w", &v->prev_w));
  TL_CHECK(tl_checkpoint_read_double(r, group, "drift", &v->drift));
  TL_CHECK(tl_checkpoint_length(r, group, "zero_crossings", &n));
  if (n > 64) TL_ERROR(TL_ERR_ARG, "%s: %zu zero crossings stored, at most 64", tl_checkpoint_reader_path(r), n);
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "zero_crossings", n, v->t_cross));
  v->n_cross = (int64_t)n;
  return TL_OK;
}

static const TlCheckpointOps vibration_checkpoint_ops = {
    .header = {"checkpoint", "cantilever_vibration_v1", "running diagnostics of the cantilever vibration"},
    .save = vibration_save,
    .load = vibration_load,
};

static TlStatus run_vibration(const Config *c, TlSummary *sum, int *failed)
{
  TlCantilever *beam = NULL;
  TlStepper *qs = NULL, *nm = NULL;
  TlTimeSeries *ts = NULL;
  TlCheckpoint *cp = NULL;
  char *cp_path = NULL;
  Snapshots sn;
  memset(&sn, 0, sizeof sn);
  Vibration vs;
  memset(&vs, 0, sizeof vs);
  int restart = c->restart && c->restart[0];
  TlStepperOptions so;
  stepper_options(c, &so);
  TL_CHECK(tl_cantilever_create(&c->beam, &beam));
  TlStatus s = TL_OK;
  TlMechSystem *sys = tl_solid_system(beam->solid);
  TL_CHECK_GOTO(s, snapshots_open(c, beam, &sn), done);
  beam->load_scale = 0.0; /* released */
  so.rtol = fmin(c->rtol, 1e-12);
  TL_CHECK_GOTO(s, tl_stepper_create("newmark", sys, &so, &nm), done);
  const TlColumn cols[] = {{"t", "s"}, {"tip_w", "m"}, {"kinetic", "J"}, {"strain", "J"},
                           {"total", "J"}};
  TL_CHECK_GOTO(s, open_table(c, "vibration", 5, cols, &ts), done);
  TL_CHECK_GOTO(s, tl_checkpoint_create(&cp), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, c->options), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "newmark", &tl_stepper_checkpoint_ops, nm), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "vibration_table", &tl_timeseries_checkpoint_ops, ts), done);
  if (sn.out) TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "snapshots", &tl_solid_output_checkpoint_ops, sn.out), done);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "driver", &vibration_checkpoint_ops, &vs), done);
  TL_CHECK_GOTO(s, tl_path_join(c->output_dir, "checkpoint.h5", &cp_path), done);
  double T1 = 2.0 * M_PI / tl_cantilever_omega1(&c->beam);
  long steps = lround(c->periods * T1 / c->dt);
  TlEnergies e;
  double tip[3];
  if (restart) {
    TL_CHECK_GOTO(s, tl_checkpoint_load(cp, c->restart, NULL, NULL), done);
    tl_printf("restarted from %s at step %lld, t = %.9g s\n", c->restart, (long long)vs.step, nm->t);
  } else {
    /* The static deflection under the tip load is the initial shape. */
    beam->load_scale = 1.0;
    TL_CHECK_GOTO(s, tl_stepper_create("quasi_static", sys, &so, &qs), done);
    TL_CHECK_GOTO(s, tl_stepper_set_state(qs, 0.0, NULL, NULL), done);
    TL_CHECK_GOTO(s, tl_stepper_step(qs, 1.0), done);
    beam->load_scale = 0.0; /* released */
    TL_CHECK_GOTO(s, tl_stepper_set_state(nm, 0.0, qs->u, NULL), done);
    TL_CHECK_GOTO(s, tl_stepper_energies(nm, &e), done);
    vs.e0[0] = e.kinetic, vs.e0[1] = e.strain, vs.e0[2] = e.external_work, vs.e0[3] = e.total;
    tl_cantilever_tip(beam, nm->u, tip);
    vs.prev_w = -tip[2];
    TL_CHECK_GOTO(s, tl_timeseries_reserve(ts, (size_t)steps + 1), done);
    double row0[5] = {0.0, vs.prev_w, e.kinetic, e.strain, e.total};
    TL_CHECK_GOTO(s, tl_timeseries_append(ts, row0), done);
    TL_CHECK_GOTO(s, snapshots_write(&sn, 0, 0.0, nm->u, nm->v), done);
  }
  double t0 = tl_wtime();
  TlProgress bar;
  tl_progress_init(&bar, "Newmark steps", (double)steps);
  long last = c->stop_step > 0 && c->stop_step < steps ? c->stop_step : steps;
  for (long k = (long)vs.step + 1; k <= last; ++k) {
    TL_CHECK_GOTO(s, tl_stepper_step(nm, c->dt), done);
    TL_CHECK_GOTO(s, tl_stepper_energies(nm, &e), done);
    tl_cantilever_tip(beam, nm->u, tip);
    double w = -tip[2];
    if ((vs.prev_w < 0.0) != (w < 0.0) && vs.n_cross < 64) /* zero crossing, either way */
      vs.t_cross[vs.n_cross++] = nm->t - c->dt * w / (w - vs.prev_w);
    vs.prev_w = w;
    vs.drift = tl_track_max(vs.drift, fabs(e.total - vs.e0[3]) / fabs(vs.e0[3]));
    double row[5] = {nm->t, w, e.kinetic, e.strain, e.total};
    TL_CHECK_GOTO(s, tl_timeseries_append(ts, row), done);
    if (c->snapshot_every > 0 && k % c->snapshot_every == 0)
      TL_CHECK_GOTO(s, snapshots_write(&sn, k, nm->t, nm->u, nm->v), done);
    vs.step = k;
    if (c->checkpoint_every > 0 && k % c->checkpoint_every == 0)
      TL_CHECK_GOTO(s, tl_checkpoint_save(cp, cp_path, nm->t, vs.step), done);
    tl_progress_update(&bar, (double)k);
  }
  tl_progress_finish(&bar);
  double *t_cross = vs.t_cross, drift = vs.drift;
  long n_cross = (long)vs.n_cross;
  double wall = tl_wtime() - t0;
  /* Successive zero crossings are half a period apart: two are needed. */
  int have_period = n_cross >= 2;
  double period = have_period ? 2.0 * (t_cross[n_cross - 1] - t_cross[0]) / (n_cross - 1) : 0.0;
  /* drift: the largest |E(t) - E(0)| / E(0) over the run; per period: that
   * divided by the number of periods run (at least one). */
  double periods_run = (double)vs.step * c->dt / T1;
  double drift_per_period = drift / fmax(periods_run, 1.0);
  TlStepperStats ss;
  tl_stepper_get_stats(nm, &ss);
  tl_printf("free vibration: %ld Newmark steps of %g s (%.2f s wall, %ld Newton iterations, %ld "
            "factorisations); ",
            (long)vs.step, c->dt, wall, ss.newton_iterations, ss.factorisations);
  if (have_period)
    tl_printf("period %.5f s, Euler-Bernoulli %.5f s (%+.2f %%)", period, T1, 100.0 * (period - T1) / T1);
  else
    tl_printf("period undefined (the tip crossed zero %ld time%s in %.3g s; two crossings are needed: "
              "-periods 1 or more), Euler-Bernoulli %.5f s",
              n_cross, n_cross == 1 ? "" : "s", (double)vs.step * c->dt, T1);
  tl_printf("; largest energy deviation %.2e (%.2e per period)\n", drift, drift_per_period);
  int stopped = vs.step < steps; /* -stop_step: a part of a run, to be continued by -restart */
  if (stopped)
    tl_summary_int(sum, "stopped_at", vs.step);
  else if (have_period)
    tl_summary_real(sum, "period", period);
  else
    tl_summary_undefined(sum, "period", "the tip crossed zero %ld time%s; two crossings are needed (-periods 1 or more)",
                         n_cross, n_cross == 1 ? "" : "s");
  tl_summary_real(sum, "period_eb", T1);
  tl_summary_real(sum, "energy_error_max", drift);
  tl_summary_real(sum, "energy_error_per_period", drift_per_period);
  if (c->check && !(drift_per_period <= 1e-8)) {
    tl_log(TL_LOG_ERROR, "check failed: energy drift per period %.3g exceeds 1e-8", drift_per_period);
    *failed = 1;
  }
done:
  if (ts) {
    TlStatus s2 = tl_timeseries_close(&ts);
    if (s == TL_OK) s = s2;
  }
  tl_checkpoint_destroy(&cp);
  tl_free(&cp_path);
  snapshots_close(&sn);
  tl_stepper_destroy(&qs);
  tl_stepper_destroy(&nm);
  tl_cantilever_destroy(&beam);
  return s;
}

static TlStatus run(int argc, char **argv)
{
  Config c;
  memset(&c, 0, sizeof c);
  TL_CHECK(tl_initialize());
  TL_CHECK(configure(argc, argv, &c));
  TL_CHECK(tl_output_dir_prepare(c.output_dir));
  TlSummary sum;
  tl_summary_init(&sum);
  double t0 = tl_wtime();
  int failed = 0;
  TlStatus s = TL_OK;
  if (c.mode == MODE_ALL || c.mode == MODE_SMALL) TL_CHECK_GOTO(s, run_small(&c, &sum, &failed), done);
  if (c.mode == MODE_ALL || c.mode == MODE_LARGE) TL_CHECK_GOTO(s, run_large(&c, 0, &sum, &failed), done);
  if (c.mode == MODE_ALL || c.mode == MODE_VIBRATION) TL_CHECK_GOTO(s, run_vibration(&c, &sum, &failed), done);
  if (c.mode == MODE_LINEAR) TL_CHECK_GOTO(s, run_linear(&c, &sum, &failed), done);
  if (c.mode == MODE_MODAL) TL_CHECK_GOTO(s, run_modal(&c, &sum, &failed), done);
  if (c.mode == MODE_NLGEOM) TL_CHECK_GOTO(s, run_large(&c, 1, &sum, &failed), done);
  {
    char plot_cmd[4200], plot_dir[4200];
    tl_printf("plots: %s %s\n", tl_plot_command(TALUS_TOOLS_DIR, "plot_cantilever_fem.py", plot_cmd, sizeof plot_cmd),
              tl_plot_abs_dir(c.output_dir, plot_dir, sizeof plot_dir));
  }
  tl_summary_real(&sum, "wall", tl_wtime() - t0);
  s = tl_summary_print(&sum, stdout);
  if (failed) s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "a -check criterion failed (see above)");
done:
  tl_options_destroy(&c.options);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
