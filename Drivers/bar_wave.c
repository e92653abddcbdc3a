/* A compression pulse along a hex bar (the FEM bar of the V1 wave test of
 * Cheng et al. 2022, CMAME 403, 115651, doi:10.1016/j.cma.2022.115651:
 * 0.8 m x 0.8 m section, along y, E = 100 MPa, nu = 0, rho = 1309 kg/m^3,
 * Hex8 of 0.4 m; the far end y = L fixed).  The end y = 0 is driven with
 * v_y(t) = v0 (cos(omega t) - 1) for t <= 2 pi / omega, then held, as in
 * V1's §6.2.3 loading; with nu = 0 the pulse travels at c = sqrt(E / rho).
 *
 * The arrival time at two node planes is the centroid of |v_y(t)| there;
 * the measured speed (y2 - y1) / (t2 - t1) is compared with c.  Explicit
 * central difference at -cfl times the critical step by default, or
 * Newmark.  Output: <output_dir>/stations.csv; last line `summary: ...`.
 *
 * Restart: -checkpoint_every n writes <output_dir>/checkpoint.h5 every n
 * steps (the options, the stepper, the station table and the arrival
 * integrals); -restart <file> continues from it bit for bit with the same
 * options; -stop_step n ends the run after step n. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_atomic_file.h"
#include "tl_checkpoint.h"
#include "tl_options_checkpoint.h"
#include "tl_element.h"
#include "tl_material.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_timeseries.h"

typedef struct {
  double v0, omega;
} Pulse;

static void drive(double t, const double X[3], int component, void *ctx, double out[3])
{
  (void)X;
  (void)component;
  const Pulse *p = ctx;
  double t0 = 2.0 * M_PI / p->omega, w = p->omega;
  if (t >= t0) {
    out[0] = -p->v0 * t0; /* integral of v over the pulse */
    out[1] = out[2] = 0.0;
    return;
  }
  out[0] = p->v0 * (sin(w * t) / w - t);
  out[1] = p->v0 * (cos(w * t) - 1.0);
  out[2] = -p->v0 * w * sin(w * t);
}

typedef struct {
  size_t n;
  size_t *nodes;
  double y;
} Station;

static TlStatus make_station(const TlMesh *mesh, double y_target, Station *s)
{
  /* The node plane nearest y_target. */
  double best = HUGE_VAL;
  for (size_t i = 0; i < mesh->n_nodes; ++i)
    if (fabs(mesh->x[3 * i + 1] - y_target) < fabs(best - y_target)) best = mesh->x[3 * i + 1];
  s->y = best;
  s->n = 0;
  TL_CHECK(tl_calloc(&s->nodes, mesh->n_nodes, sizeof *s->nodes));
  for (size_t i = 0; i < mesh->n_nodes; ++i)
    if (fabs(mesh->x[3 * i + 1] - best) < 1e-9 * (1.0 + fabs(best))) s->nodes[s->n++] = i;
  return TL_OK;
}

static double station_velocity(const TlSolid *solid, const Station *s, const double *v)
{
  double sum = 0.0;
  for (size_t k = 0; k < s->n; ++k) {
    TlSparseIndex i = tl_solid_dof(solid, s->nodes[k], 1);
    if (i >= 0) sum += v[i];
  }
  return sum / (double)s->n;
}

/* The arrival integrals and the loop's next step, checkpointed with the run. */
typedef struct {
  int64_t next_step;
  double m0[2], m1[2], peak[2];
} Progress;

static TlStatus progress_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const Progress *p = object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "next_step", p->next_step));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "m0", 2, p->m0));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "m1", 2, p->m1));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "peak", 2, p->peak));
  return TL_OK;
}

static TlStatus progress_load(void *object, TlCheckpointReader *r, const char *group)
{
  Progress *p = object;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "next_step", &p->next_step));
  TL_CHECK(tl_checkpoint_check_count(r, group, "next_step", p->next_step, 1, INT64_MAX));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "m0", 2, p->m0));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "m1", 2, p->m1));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "peak", 2, p->peak));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "m0", 2, p->m0));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "m1", 2, p->m1));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "peak", 2, p->peak));
  return TL_OK;
}

static const TlCheckpointOps progress_checkpoint_ops = {
    .header = {"checkpoint", "bar_wave_progress_v1", "next step and arrival integrals of the bar_wave driver"},
    .save = progress_save,
    .load = progress_load,
};

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv,
                             "A compression pulse along a Hex8 bar (V1's FEM bar); the measured wave "
                             "speed against sqrt(E/rho).  Paper: " TL_PAPER_CHENG_2022 ".",
                             &o));
  static const char *const steppers[] = {"central_difference", "newmark", NULL};
  static const char *const elements[] = {"hex8", "hex27", NULL};
  long nx, ny, nz;
  int stepper = 0, elem = 0, check = 0;
  double L, a, E, rho, cfl, dt_opt, tol, y1f, y2f;
  Pulse pulse;
  const char *output_dir, *restart;
  long checkpoint_every, stop_step;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-length", 20.0, 1e-3, 1e6, "m", "bar length (y)", &L), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-width", 0.8, 1e-4, 1e6, "m", "bar section side", &a), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nx", 2, 1, 1000, "cells across x", &nx), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-ny", 50, 2, 1000000, "cells along y", &ny), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nz", 2, 1, 1000, "cells across z", &nz), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-elements", "hex8", elements, "element type", &elem), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-E", 1e8, 1e-3, 1e15, "Pa", "Young's modulus", &E), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-rho", 1309.0, 1e-6, 1e6, "kg/m^3", "density", &rho), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-v0", 0.05, 0.0, 1e3, "m/s", "pulse amplitude", &pulse.v0), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-omega", 300.0, 1e-3, 1e9, "rad/s",
                                       "pulse angular frequency (duration 2 pi / omega)", &pulse.omega), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-stepper", "central_difference", steppers, "time stepper", &stepper), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-cfl", 0.9, 1e-3, 1.0, "", "explicit: dt / dt_crit", &cfl), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-dt", 0.0, 0.0, 10.0, "s", "time step (0: cfl x dt_crit)", &dt_opt), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-station1", 0.25, 0.0, 1.0, "", "first station, fraction of L", &y1f), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-station2", 0.5, 0.0, 1.0, "", "second station, fraction of L", &y2f), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-output_dir", "results/bar_wave", "output folder", &output_dir), done);
  TL_CHECK_GOTO(s, tl_output_dir_check(output_dir), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-check", 0, "exit with an error when the speed misses -tolerance", &check), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-tolerance", 0.01, 0.0, 1.0, "", "relative tolerance for -check", &tol), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-checkpoint_every", 0, 0, 1000000000,
                                      "write <output_dir>/checkpoint.h5 every n steps (0: never)", &checkpoint_every), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-restart", "", "continue from this checkpoint file (same options)", &restart), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-stop_step", 0, 0, 1000000000, "stop after this step (0: run to the end)", &stop_step),
                done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  if (!(pulse.v0 > 0.0)) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "-v0 %g m/s: a pulse of zero amplitude makes no wave to time", pulse.v0);
    goto done;
  }
  {
    /* The pulse must span a few elements, or no wave the mesh can carry is
     * timed (the arrival is then a numerical precursor). */
    const double dy = L / (double)ny / (elem ? 2.0 : 1.0), span = sqrt(E / rho) * 2.0 * M_PI / pulse.omega;
    if (!(span >= 4.0 * dy)) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "-omega %g rad/s: the pulse is %.3g m long, under 4 node spacings of %.3g m; at most -omega %.4g "
                       "rad/s on this mesh",
                       pulse.omega, span, dy, 2.0 * M_PI * sqrt(E / rho) / (4.0 * dy));
      goto done;
    }
  }
  if (!(y2f > y1f)) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "-station2 %g must exceed -station1 %g", y2f, y1f);
    goto done;
  }

  double wall0 = tl_wtime(), c = sqrt(E / rho), t0 = 2.0 * M_PI / pulse.omega;
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TlStepper *st = NULL;
  TlTimeSeries *ts = NULL;
  TlCheckpoint *cp = NULL;
  char *cp_path = NULL;
  Station s1 = {0}, s2 = {0};
  const size_t n[3] = {(size_t)nx, (size_t)ny, (size_t)nz};
  const double lo[3] = {-0.5 * a, 0.0, -0.5 * a}, hi[3] = {0.5 * a, L, 0.5 * a};
  TL_CHECK_GOTO(s, tl_mesh_create_box(elem ? &tl_element_hex27 : &tl_element_hex8, n, lo, hi, &mesh), out);
  TL_CHECK_GOTO(s, tl_material_create_hooke(E, 0.0, rho, &mat), out);
  TL_CHECK_GOTO(s, tl_solid_create(mesh, &solid), out);
  TL_CHECK_GOTO(s, tl_solid_set_material(solid, NULL, mat), out);
  TL_CHECK_GOTO(s, tl_solid_fix(solid, "ymax", 7), out);
  TL_CHECK_GOTO(s, tl_solid_prescribe(solid, "ymin", 1, drive, &pulse), out);
  TL_CHECK_GOTO(s, tl_solid_setup(solid), out);
  TL_CHECK_GOTO(s, make_station(mesh, y1f * L, &s1), out);
  TL_CHECK_GOTO(s, make_station(mesh, y2f * L, &s2), out);
  /* Run until the pulse has passed station 2, before the reflection from
   * the fixed end comes back to it. */
  double t_end = s2.y / c + 2.0 * t0, t_reflect = (2.0 * L - s2.y) / c;
  if (t_end > t_reflect) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                     "pulse of %.3g s too long: it has not passed station 2 (y = %g m) before the "
                     "reflection returns at %.3g s; raise -omega or -length",
                     t0, s2.y, t_reflect);
    goto out;
  }
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  TL_CHECK_GOTO(s, tl_stepper_create(steppers[stepper], tl_solid_system(solid), &so, &st), out);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), out);
  double dt = dt_opt;
  if (dt <= 0.0) {
    double dtc = st->dt_crit;
    if (stepper == 1) TL_CHECK_GOTO(s, tl_stepper_critical_dt(st, &dtc), out);
    dt = cfl * dtc;
  }
  long steps = (long)ceil(t_end / dt);
  {
    char *base = NULL;
    TL_CHECK_GOTO(s, tl_output_dir_prepare(output_dir), out);
    TL_CHECK_GOTO(s, tl_path_join(output_dir, "stations", &base), out);
    const TlColumn cols[] = {{"t", "s"}, {"v_station1", "m/s"}, {"v_station2", "m/s"}};
    s = tl_timeseries_create(base, TL_TIMESERIES_CSV, 3, cols, &ts);
    tl_free(&base);
    if (s != TL_OK) goto out;
    TL_CHECK_GOTO(s, tl_timeseries_reserve(ts, (size_t)steps + 1), out);
  }
  Progress pr = {1, {0, 0}, {0, 0}, {0, 0}};
  double *m0 = pr.m0, *m1 = pr.m1, *peak = pr.peak;
  TL_CHECK_GOTO(s, tl_checkpoint_create(&cp), out);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, o), out);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "fem", &tl_stepper_checkpoint_ops, st), out);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "stations", &tl_timeseries_checkpoint_ops, ts), out);
  TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "driver", &progress_checkpoint_ops, &pr), out);
  TL_CHECK_GOTO(s, tl_path_join(output_dir, "checkpoint.h5", &cp_path), out);
  if (restart[0]) {
    TL_CHECK_GOTO(s, tl_checkpoint_load(cp, restart, NULL, NULL), out);
    tl_printf("restarted from %s at step %lld, t = %.9g s\n", restart, (long long)pr.next_step, st->t);
  }
  TlProgress bar;
  tl_progress_init(&bar, "steps", (double)steps);
  double t_loop = tl_wtime();
  for (long k = (long)pr.next_step; k <= steps; ++k) {
    TL_CHECK_GOTO(s, tl_stepper_step(st, dt), out);
    double v[2] = {station_velocity(solid, &s1, st->v), station_velocity(solid, &s2, st->v)};
    for (int j = 0; j < 2; ++j) {
      m0[j] += fabs(v[j]) * dt;
      m1[j] += st->t * fabs(v[j]) * dt;
      peak[j] = tl_track_max(peak[j], fabs(v[j]));
    }
    double row[3] = {st->t, v[0], v[1]};
    TL_CHECK_GOTO(s, tl_timeseries_append(ts, row), out);
    tl_progress_update(&bar, (double)k);
    pr.next_step = k + 1;
    if (checkpoint_every > 0 && k % checkpoint_every == 0) TL_CHECK_GOTO(s, tl_checkpoint_save(cp, cp_path, st->t, k), out);
    if (stop_step > 0 && k >= stop_step && k < steps) {
      tl_progress_finish(&bar);
      tl_printf("stopped after step %ld of %ld (t = %.9g s)\n", k, steps, st->t);
      TlSummary part; /* the speed needs the whole run: only what was done */
      tl_summary_init(&part);
      tl_summary_int(&part, "stopped_at_step", k);
      tl_summary_int(&part, "steps", steps);
      tl_summary_real(&part, "t", st->t);
      tl_summary_real(&part, "wall", tl_wtime() - wall0);
      s = tl_summary_print(&part, stdout);
      goto out;
    }
  }
  tl_progress_finish(&bar);
  t_loop = tl_wtime() - t_loop;
  double ta = m1[0] / m0[0], tb = m1[1] / m0[1];
  double speed = (s2.y - s1.y) / (tb - ta), err = (speed - c) / c;
  size_t n_elem = mesh->blocks[0].n_elements;
  tl_printf("bar %g m, %s %ldx%ldx%ld, %s dt = %.4g s (%ld steps): arrival %.6f s at y = %g m, %.6f s "
            "at y = %g m; speed %.4f m/s, sqrt(E/rho) = %.4f m/s (%+.3f %%); peak |v| %.4f, %.4f m/s "
            "(the pulse's peak 2 v0 = %g m/s); %.1f ns per element-step\n",
            L, elem ? "hex27" : "hex8", nx, ny, nz, steppers[stepper], dt, steps, ta, s1.y, tb, s2.y,
            speed, c, 100.0 * err, peak[0], peak[1], 2.0 * pulse.v0,
            1e9 * t_loop / ((double)steps * (double)n_elem));
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_real(&sum, "speed", speed);
  tl_summary_real(&sum, "c", c);
  tl_summary_real(&sum, "error", err);
  tl_summary_real(&sum, "dt", dt);
  tl_summary_int(&sum, "steps", steps);
  tl_summary_real(&sum, "v0", pulse.v0);
  tl_summary_real(&sum, "pulse_peak", 2.0 * pulse.v0); /* |v0 (cos - 1)| at omega t = pi */
  tl_summary_real(&sum, "peak_station1", peak[0]);
  tl_summary_real(&sum, "peak_station2", peak[1]);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  s = tl_summary_print(&sum, stdout);
  if (check && !(fabs(err) <= tol)) {
    s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__,
                     "measured speed %.6g differs from sqrt(E/rho) = %.6g by %.3g (tolerance %g)",
                     speed, c, err, tol);
  }
out:
  if (ts) {
    TlStatus s2s = tl_timeseries_close(&ts);
    if (s == TL_OK) s = s2s;
  }
  tl_checkpoint_destroy(&cp);
  tl_free(&cp_path);
  tl_free(&s1.nodes);
  tl_free(&s2.nodes);
  tl_stepper_destroy(&st);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
done:
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
