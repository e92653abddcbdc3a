/* Talus against CalculiX on the same beam, mesh, loads and steps, in one
 * invocation: answers and times side by side.
 *
 * The S1 cantilever (Hex8 / C3D8, 2 x 2 x 30 by default; C3D8 integrates
 * stiffness and mass with 2 x 2 x 2 Gauss points, as Talus's hex8 does),
 * clamped at y = 0, the tip load given to both codes as Talus's consistent
 * nodal forces (peers/tl_peer_calculix.h writes CalculiX's mesh and loads;
 * the decks are in peers/calculix/):
 *
 *  linear:  linear static analysis, P = -tip_load;
 *  modal:   the -modes lowest frequencies, consistent mass (ARPACK in both);
 *  static:  geometrically nonlinear statics under the dead load
 *           P = -load_parameter E I / L^2 in -increments equal increments
 *           (Talus quasi-static Newton; CalculiX *STATIC, NLGEOM, DIRECT);
 *  dynamic: the tip load 10 x -tip_load ramped up from zero over the
 *           first -ramp_steps steps (0: applied suddenly at t = 0), Newmark
 *           beta = 1/4, gamma = 1/2 with the same step (CalculiX *DYNAMIC,
 *           ALPHA = 0), NLGEOM, consistent mass in both.  A sudden load
 *           differs at the start: CalculiX's initial acceleration is not
 *           Talus's consistent M^-1 (f_ext(0) - f_int(0)) (1 % in the tip
 *           after one step, decaying to 1e-6 after 100), while from a ramp
 *           the two integrations agree to CalculiX's print.
 *
 * The material is -material in Talus (default saint_venant_kirchhoff,
 * which is what CalculiX's *ELASTIC means under NLGEOM: the same law) and
 * *ELASTIC in CalculiX.  Both Newton iterations are driven to 1e-10-level
 * residuals (the deck's *CONTROLS), so the answers are the same discrete
 * solution; CalculiX prints displacements with 7 significant digits.
 *
 * Times: Talus's from building the beam to the answer, CalculiX's own
 * "Total CalculiX Time" (input to output), both single-threaded, the best
 * of -repeat runs.  When ccx is missing and the program runs as root it
 * installs the Debian package calculix-ccx. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "peers/tl_peer_calculix.h"
#include "talus.h"
#include "tl_linear_static.h"
#include "tl_modal.h"
#include "tl_stepper.h"

enum { MAX_MODES = 32 };

typedef struct {
  TlCantileverParams p;
  const char *dir;
  long increments, steps, repeat, n_modes, ramp_steps;
  double load_parameter, periods;
} Bench;

typedef struct {
  double talus, ccx; /* answers */
  double t_talus, t_ccx; /* seconds, best of the repeats */
} Result;

static double rel(double a, double b) { return fabs(a - b) / fabs(b); }

static void best(double *t, double x) { *t = (*t == 0.0 || x < *t) ? x : *t; }

/* ------------------------------------------------------------ linear */
static TlStatus bench_linear(const Bench *b, Result *r)
{
  TlCantilever *beam = NULL;
  double *u = NULL, tip[3] = {0, 0, 0}, tip_c[3], t_c = 0.0, sec = 0.0;
  TlStatus s = TL_OK;
  for (long k = 0; k < b->repeat; ++k) {
    tl_cantilever_destroy(&beam);
    tl_free(&u);
    double t0 = tl_wtime();
    TL_CHECK_GOTO(s, tl_cantilever_create(&b->p, &beam), done);
    TlMechSystem *sys = tl_solid_system(beam->solid);
    TL_CHECK_GOTO(s, tl_calloc(&u, (size_t)sys->ndof, sizeof *u), done);
    TL_CHECK_GOTO(s, tl_linear_static_solve(sys, "cholmod", 0.0, u, NULL), done);
    tl_cantilever_tip(beam, u, tip);
    best(&r->t_talus, tl_wtime() - t0);
  }
  TL_CHECK_GOTO(s, tl_ccx_write_model(b->dir, beam), done);
  for (long k = 0; k < b->repeat; ++k) {
    TL_CHECK_GOTO(s, tl_ccx_run(b->dir, "cantilever_linear", &sec), done);
    best(&r->t_ccx, sec);
  }
  TL_CHECK_GOTO(s, tl_ccx_read_tip(b->dir, "cantilever_linear", beam, tip_c, &t_c), done);
  r->talus = -tip[2];
  r->ccx = -tip_c[2];
done:
  tl_free(&u);
  tl_cantilever_destroy(&beam);
  return s;
}

/* ------------------------------------------------------------- modal */
static TlStatus bench_modal(const Bench *b, Result *r)
{
  TlCantilever *beam = NULL;
  double w2[MAX_MODES], w2_c[MAX_MODES], sec = 0.0, t_talus = 0.0, t_ccx = 0.0;
  TlModalOptions mo;
  tl_modal_options_default(&mo);
  mo.n_modes = (int)b->n_modes;
  TlStatus s = TL_OK;
  for (long k = 0; k < b->repeat; ++k) {
    tl_cantilever_destroy(&beam);
    double t0 = tl_wtime();
    TL_CHECK_GOTO(s, tl_cantilever_create(&b->p, &beam), done);
    TL_CHECK_GOTO(s, tl_modal_solve(tl_solid_system(beam->solid), &mo, w2, NULL, NULL), done);
    best(&t_talus, tl_wtime() - t0);
  }
  char line[32];
  snprintf(line, sizeof line, "%ld", b->n_modes);
  TL_CHECK_GOTO(s, tl_ccx_write_model(b->dir, beam), done);
  TL_CHECK_GOTO(s, tl_ccx_write_line(b->dir, "modes.inp", line), done);
  for (long k = 0; k < b->repeat; ++k) {
    TL_CHECK_GOTO(s, tl_ccx_run(b->dir, "cantilever_modal", &sec), done);
    best(&t_ccx, sec);
  }
  TL_CHECK_GOTO(s, tl_ccx_read_eigenvalues(b->dir, "cantilever_modal", mo.n_modes, w2_c), done);
  for (int k = 0; k < mo.n_modes; ++k) {
    r[k].talus = sqrt(w2[k]);
    r[k].ccx = sqrt(w2_c[k]);
    r[k].t_talus = t_talus;
    r[k].t_ccx = t_ccx;
  }
done:
  tl_cantilever_destroy(&beam);
  return s;
}

/* ----------------------------------------------------- static, NLGEOM */
static TlStatus bench_static(const Bench *b, Result *w, Result *v, long *newton)
{
  TlCantileverParams p = b->p;
  p.load = b->load_parameter * p.E * (p.b * p.h * p.h * p.h / 12.0) / (p.L * p.L);
  TlCantilever *beam = NULL;
  TlStepper *st = NULL;
  double tip[3] = {0, 0, 0}, tip_c[3], t_c = 0.0, sec = 0.0;
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  so.ramp_time = 1.0;
  so.rtol = 1e-12;
  TlStatus s = TL_OK;
  for (long k = 0; k < b->repeat; ++k) {
    tl_stepper_destroy(&st);
    tl_cantilever_destroy(&beam);
    double t0 = tl_wtime();
    TL_CHECK_GOTO(s, tl_cantilever_create(&p, &beam), done);
    TL_CHECK_GOTO(s, tl_stepper_create("quasi_static", tl_solid_system(beam->solid), &so, &st), done);
    TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), done);
    for (long i = 0; i < b->increments; ++i) TL_CHECK_GOTO(s, tl_stepper_step(st, 1.0 / (double)b->increments), done);
    tl_cantilever_tip(beam, st->u, tip);
    best(&w->t_talus, tl_wtime() - t0);
  }
  TlStepperStats ss;
  tl_stepper_get_stats(st, &ss);
  *newton = ss.newton_iterations;
  char line[64];
  snprintf(line, sizeof line, "%.17g, 1.0", 1.0 / (double)b->increments);
  TL_CHECK_GOTO(s, tl_ccx_write_model(b->dir, beam), done);
  TL_CHECK_GOTO(s, tl_ccx_write_line(b->dir, "increment.inp", line), done);
  for (long k = 0; k < b->repeat; ++k) {
    TL_CHECK_GOTO(s, tl_ccx_run(b->dir, "cantilever_nlgeom", &sec), done);
    best(&w->t_ccx, sec);
  }
  TL_CHECK_GOTO(s, tl_ccx_read_tip(b->dir, "cantilever_nlgeom", beam, tip_c, &t_c), done);
  if (!(fabs(t_c - 1.0) <= 1e-9)) {
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "CalculiX's last NLGEOM result is at step time %g, not 1", t_c);
    goto done;
  }
  w->talus = -tip[2], w->ccx = -tip_c[2];
  v->talus = -tip[1], v->ccx = -tip_c[1];
  v->t_talus = w->t_talus, v->t_ccx = w->t_ccx;
done:
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&beam);
  return s;
}

/* ---------------------------------------------------- dynamic, Newmark */
static TlStatus bench_dynamic(const Bench *b, Result *w, double *dt_out, double *t_end_out, double *load)
{
  TlCantileverParams p = b->p;
  p.load *= 10.0;
  *load = p.load;
  TlCantilever *beam = NULL;
  TlStepper *st = NULL;
  const double T1 = 2.0 * M_PI / tl_cantilever_omega1(&p), t_end = b->periods * T1, dt = t_end / (double)b->steps;
  const double t_ramp = (double)b->ramp_steps * dt;
  double tip[3] = {0, 0, 0}, tip_c[3], t_c = 0.0, sec = 0.0;
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  so.rtol = 1e-12;
  TlStatus s = TL_OK;
  for (long k = 0; k < b->repeat; ++k) {
    tl_stepper_destroy(&st);
    tl_cantilever_destroy(&beam);
    double t0 = tl_wtime();
    TL_CHECK_GOTO(s, tl_cantilever_create(&p, &beam), done);
    beam->load_scale = tl_ccx_amplitude(0.0, t_ramp);
    TL_CHECK_GOTO(s, tl_stepper_create("newmark", tl_solid_system(beam->solid), &so, &st), done);
    TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), done);
    for (long i = 0; i < b->steps; ++i) {
      beam->load_scale = tl_ccx_amplitude((double)(i + 1) * dt, t_ramp);
      TL_CHECK_GOTO(s, tl_stepper_step(st, dt), done);
    }
    tl_cantilever_tip(beam, st->u, tip);
    best(&w->t_talus, tl_wtime() - t0);
  }
  char line[96];
  snprintf(line, sizeof line, "%.17g, %.17g", dt, t_end);
  TL_CHECK_GOTO(s, tl_ccx_write_model(b->dir, beam), done);
  TL_CHECK_GOTO(s, tl_ccx_write_line(b->dir, "increment.inp", line), done);
  TL_CHECK_GOTO(s, tl_ccx_write_amplitude(b->dir, t_ramp), done);
  for (long k = 0; k < b->repeat; ++k) {
    TL_CHECK_GOTO(s, tl_ccx_run(b->dir, "cantilever_dynamic", &sec), done);
    best(&w->t_ccx, sec);
  }
  TL_CHECK_GOTO(s, tl_ccx_read_tip(b->dir, "cantilever_dynamic", beam, tip_c, &t_c), done);
  if (!(fabs(t_c - t_end) <= 1e-6 * t_end)) { /* the .dat prints 7 digits */
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "CalculiX's last dynamic result is at t = %.9g s, not %.9g s",
                     t_c, t_end);
    goto done;
  }
  w->talus = -tip[2], w->ccx = -tip_c[2];
  *dt_out = dt, *t_end_out = t_end;
done:
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&beam);
  return s;
}

static void row(const char *what, const char *unit, const Result *r)
{
  printf("  %-24s %-6s %18.10e %18.10e %10.2e %9.4f %9.4f %7.3f\n", what, unit, r->talus, r->ccx, rel(r->talus, r->ccx),
         r->t_talus, r->t_ccx, r->t_talus / r->t_ccx);
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv,
                             "The S1 cantilever in Talus and in CalculiX on the same mesh, loads and steps: linear "
                             "statics, frequencies, NLGEOM statics and Newmark dynamics; answers, times, ratios.",
                             &o));
  Bench b;
  memset(&b, 0, sizeof b);
  tl_cantilever_params_default(&b.p);
  long nx, ny, threads;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nx", 2, 1, 100, "cells across x and z", &nx), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-ny", 30, 1, 10000, "cells along the beam", &ny), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-material", "saint_venant_kirchhoff",
                                         "Talus's law (CalculiX's *ELASTIC under NLGEOM is saint_venant_kirchhoff)",
                                         &b.p.material), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-nu", 0.0, -0.99, 0.49, "", "Poisson's ratio", &b.p.nu), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-tip_load", 1644.0, 0.0, 1e12, "N", "linear: tip load P", &b.p.load), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-modes", 6, 1, MAX_MODES, "modal: frequencies compared", &b.n_modes), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-load_parameter", 1.0, 0.0, 20.0, "", "static: P L^2 / (E I)",
                                       &b.load_parameter), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-increments", 10, 1, 10000, "static load increments", &b.increments), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-steps", 100, 1, 1000000, "dynamic: Newmark steps", &b.steps), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-ramp_steps", 10, 0, 1000000,
                                      "dynamic: steps over which the load rises from zero (0: sudden load)",
                                      &b.ramp_steps), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-periods", 0.5, 0.01, 100.0, "",
                                       "dynamic: duration in first-mode periods", &b.periods), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-repeat", 3, 1, 100, "runs of each code, the fastest timed", &b.repeat),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-threads", 1, 1, 256, "OpenMP threads for Talus", &threads), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-output_dir", "results/fem_vs_calculix", "output folder", &b.dir), done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  omp_set_num_threads((int)threads);
  TL_CHECK_GOTO(s, tl_ccx_ensure(), done);
  TL_CHECK_GOTO(s, tl_mkdir_p(b.dir), done);
  b.p.nx = b.p.nz = (size_t)nx;
  b.p.ny = (size_t)ny;
  TlSummary sum;
  tl_summary_init(&sum);
  double wall0 = tl_wtime();

  Result lin = {0}, modes[MAX_MODES], w = {0}, v = {0}, dyn = {0};
  memset(modes, 0, sizeof modes);
  long newton = 0;
  double dt = 0, t_end = 0, dyn_load = 0;
  TL_CHECK_GOTO(s, bench_linear(&b, &lin), done);
  int modal = tl_modal_available();
  if (modal) TL_CHECK_GOTO(s, bench_modal(&b, modes), done);
  TL_CHECK_GOTO(s, bench_static(&b, &w, &v, &newton), done);
  TL_CHECK_GOTO(s, bench_dynamic(&b, &dyn, &dt, &t_end, &dyn_load), done);

  printf("S1 cantilever, hex8 = C3D8 %zux%zux%zu, E = %g Pa, nu = %g, rho = %g kg/m^3; Talus law %s, CalculiX "
         "*ELASTIC; times: best of %ld, one thread each\n",
         b.p.nx, b.p.ny, b.p.nz, b.p.E, b.p.nu, b.p.rho, b.p.material, b.repeat);
  printf("  %-24s %-6s %18s %18s %10s %9s %9s %7s\n", "quantity", "unit", "Talus", "CalculiX", "rel.diff", "Talus s",
         "ccx s", "ratio");
  char what[64];
  snprintf(what, sizeof what, "linear tip w, P=%g N", b.p.load);
  row(what, "m", &lin);
  for (long k = 0; modal && k < b.n_modes; ++k) {
    snprintf(what, sizeof what, "omega_%ld", k + 1);
    row(what, "rad/s", &modes[k]);
  }
  snprintf(what, sizeof what, "NLGEOM tip w, k=%g", b.load_parameter);
  row(what, "m", &w);
  row("NLGEOM tip shortening v", "m", &v);
  snprintf(what, sizeof what, "Newmark tip w, t=%.3g s", t_end);
  row(what, "m", &dyn);
  printf("  (NLGEOM: %ld increments, %ld Talus Newton iterations; Newmark: %ld steps of %.4g s, tip load %g N, "
         "%s)\n",
         b.increments, newton, b.steps, dt, dyn_load,
         b.ramp_steps > 0 ? "ramped from zero over the first -ramp_steps steps" : "applied suddenly at t = 0");
  if (!modal) printf("  (modal: this build has no ARPACK; frequencies not compared)\n");

  double modal_diff = 0.0, modal_t = modal ? modes[0].t_talus / modes[0].t_ccx : 0.0;
  for (long k = 0; modal && k < b.n_modes; ++k) modal_diff = fmax(modal_diff, rel(modes[k].talus, modes[k].ccx));
  tl_summary_real(&sum, "linear_talus_w", lin.talus);
  tl_summary_real(&sum, "linear_ccx_w", lin.ccx);
  tl_summary_real(&sum, "linear_diff", rel(lin.talus, lin.ccx));
  tl_summary_real(&sum, "linear_time_ratio", lin.t_talus / lin.t_ccx);
  if (modal) {
    tl_summary_real(&sum, "modal_talus_omega1", modes[0].talus);
    tl_summary_real(&sum, "modal_ccx_omega1", modes[0].ccx);
    tl_summary_real(&sum, "modal_diff_max", modal_diff);
    tl_summary_real(&sum, "modal_time_ratio", modal_t);
  }
  tl_summary_real(&sum, "static_talus_w", w.talus);
  tl_summary_real(&sum, "static_ccx_w", w.ccx);
  tl_summary_real(&sum, "static_diff", rel(w.talus, w.ccx));
  tl_summary_real(&sum, "static_diff_v", rel(v.talus, v.ccx));
  tl_summary_real(&sum, "static_time_ratio", w.t_talus / w.t_ccx);
  tl_summary_real(&sum, "dynamic_talus_w", dyn.talus);
  tl_summary_real(&sum, "dynamic_ccx_w", dyn.ccx);
  tl_summary_real(&sum, "dynamic_diff", rel(dyn.talus, dyn.ccx));
  tl_summary_real(&sum, "dynamic_time_ratio", dyn.t_talus / dyn.t_ccx);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  s = tl_summary_print(&sum, stdout);
done:
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
