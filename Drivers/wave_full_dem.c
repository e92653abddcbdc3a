/* The full-DEM reference of V1 (Cheng et al. 2022 §6.2): the bonded simple-cubic
 * bar over its whole length, the same particles, excitation and fixed right
 * end as wave_volume_coupling.  Restart: -checkpoint_every n writes
 * <output_dir>/checkpoint.h5 every n steps (the options, the particles and
 * the recorded tables); -restart <file> continues from it bit for bit with
 * the same options; -stop_step n stops after step n. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_options_renamed.h"
#include "tl_plot_hint.h"
#include "tl_atomic_file.h"
#include "tl_output_dir.h"
#include "tl_timeseries.h"
#include "tl_vcoupling_wave.h"

/* The energy table and the velocity profiles through the documented table
 * writer (tl_timeseries.h): columns with units, 17 significant digits, CSV
 * and HDF5, written atomically; the column names are those of
 * wave_volume_coupling's DEM part, so tools/plot_wave.py reads both. */
static const TlColumn energy_columns[] = {{"t", "s"},       {"mass_dem", "kg"}, {"mom_dem", "kg m/s"},
                                          {"kin_dem", "J"}, {"pot_dem", "J"},   {"total", "J"}};
static const TlColumn profile_columns[] = {{"t", "s"}, {"y", "m"}, {"vy", "m/s"}};

static TlStatus write_tables(const char *dir, const TlWaveRecord *r, int n_snap)
{
  char base[4096];
  TlTimeSeries *ts = NULL;
  snprintf(base, sizeof base, "%s/energies", dir);
  TL_CHECK(tl_timeseries_create(base, TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, 6, energy_columns, &ts));
  TlStatus s = tl_timeseries_reserve(ts, r->n);
  for (size_t k = 0; s == TL_OK && k < r->n; ++k) {
    const TlWaveState *w = &r->state[k];
    const double row[6] = {w->t, w->mass_dem, w->mom_dem, w->kin_dem, w->pot_dem, w->total};
    s = tl_timeseries_append(ts, row);
  }
  if (s != TL_OK) {
    tl_timeseries_destroy(&ts);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  TL_CHECK(tl_timeseries_close(&ts));
  snprintf(base, sizeof base, "%s/profiles", dir);
  TL_CHECK(tl_timeseries_create(base, TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, 3, profile_columns, &ts));
  s = tl_timeseries_reserve(ts, (size_t)n_snap * r->ny);
  for (int q = 0; s == TL_OK && q < n_snap; ++q)
    for (size_t j = 0; s == TL_OK && j < r->ny; ++j) {
      const double row[3] = {r->snap_t[q], r->y[j], r->profile[(size_t)q * r->ny + j]};
      s = tl_timeseries_append(ts, row);
    }
  if (s != TL_OK) {
    tl_timeseries_destroy(&ts);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  TL_CHECK(tl_timeseries_close(&ts));
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv,
                             "The full-DEM reference of V1 (Cheng et al. 2022, §6.2): bonded simple-cubic particles over "
                             "the whole bar, right end fixed, left layer excited as in Table 4.  Paper: " TL_PAPER_CHENG_2022 ".",
                             &o));
  static const char *const cases[] = {"1P", "2P", "3P", "4P", NULL};
  static const char *const excitations[] = {"pulse", "cosine", "cycles", NULL};
  TlWaveParams p;
  tl_wave_params_default(&p);
  p.full_dem = 1;
  TlWaveRunOptions ro = {.t_end = 0.09, .every = 20, .n_snap = 0, .progress = 1};
  int icase = 0, iexc = 0, n_snap = 0;
  long cycles = 1, every = 0;
  double v0 = 0.0;
  char *dir = NULL;
  TlStatus s = TL_OK;
  static const TlRenamedOption renamed[] = {
      {"-snapshots", "-profile_times", "the times of the velocity profiles, which are not snapshots"},
      {"-record_every", "-table_every", "table cadence: -table_dt seconds, -table_every steps, -table_rows a count"}};
  TL_CHECK_GOTO(s, tl_options_refuse_renamed(o, renamed, (int)(sizeof renamed / sizeof renamed[0])), done);
  TL_CHECK_GOTO(s, tl_options_set_restart_safe(o, "-profile_times"), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-case", "1P", cases, "particles per element edge n: nP = n^3 (Table 6)", &icase), done);
  TL_CHECK_GOTO(s, tl_options_get_choice(o, "-excitation", "pulse", excitations, "Table 4 excitation", &iexc), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-omega", 1950.0, 1e-3, 1e9, "rad/s", "excitation angular frequency", &p.omega), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-cycles", 1, 1, 1000, "cycles M_c (-excitation cycles)", &cycles), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-v0", 0.0, 0.0, 1e3, "m/s", "amplitude (0: Table 4, 0.1 pulse, 0.05 otherwise)", &v0), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-dx", 0.4, 1e-3, 1e3, "m", "element size of the coupled model (d = dx / n)", &p.dx), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-E", 100e6, 1e-3, 1e15, "Pa", "Young's modulus (k_n = E d)", &p.E), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-rho", 1309.0, 1e-6, 1e6, "kg/m^3", "continuum density (particles 6 rho / pi)", &p.rho), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-length", 20.0, 1e-3, 1e6, "m", "bar length", &p.length), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-width", 0.8, 1e-3, 1e6, "m", "section side", &p.width), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-dt_over_tc", 0.01, 1e-6, 0.3, "", "time step / contact time", &p.dt_over_tc), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-t_end", 0.09, 1e-9, 1e3, "s", "end time", &ro.t_end), done);
  TL_CHECK_GOTO(s, tl_options_get_real_list(o, "-profile_times", "0.03,0.05", "s", "times of the velocity profiles",
                                            ro.snap, TL_WAVE_MAX_SNAPSHOTS, &n_snap), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-table_every", 0, 0, 1000000, "steps between table rows (0: about 1000 rows)", &every), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-progress", 1, "progress bar", &ro.progress), done);
  const char *restart = NULL;
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-checkpoint_every", 0, 0, 1000000000,
                                      "checkpoint every n steps to <output_dir>/checkpoint.h5 (0: none)", &ro.checkpoint_every),
                done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-restart", "", "continue from this checkpoint file (same options)", &restart),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-stop_step", 0, 0, 1000000000, "stop after this step (0: run to t_end)", &ro.stop_step),
                done);
  TL_CHECK_GOTO(s, tl_output_dir(o, &dir), done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  ro.output_dir = dir;
  ro.restart = restart;
  ro.options = o;
  p.n = icase + 1;
  p.excitation = (TlWaveExcitation)iexc;
  p.cycles = (int)cycles;
  p.v0 = v0 > 0 ? v0 : (iexc == 0 ? 0.1 : 0.05);
  ro.n_snap = n_snap;
  double wall0 = tl_wtime();
  TlWaveRecord r = {0};
  {
    TlWave *probe = NULL;
    TL_CHECK_GOTO(s, tl_wave_create(&p, &probe), done);
    double dt = tl_wave_dt(probe);
    tl_wave_destroy(&probe);
    ro.every = every > 0 ? every : (long)fmax(1.0, floor(ro.t_end / dt / 1000.0));
  }
  TL_CHECK_GOTO(s, tl_wave_run(&p, &ro, &r), out);
  if (r.stopped) { /* a run stopped to leave a checkpoint: its tables and figures are the restarted run's */
    tl_printf("full DEM stopped after step %ld; checkpoint in %s\n", r.steps, dir);
    TlSummary part;
    tl_summary_init(&part);
    tl_summary_int(&part, "stopped_at_step", r.steps);
    tl_summary_int(&part, "particles", (long)r.n_particles);
    tl_summary_real(&part, "wall", tl_wtime() - wall0);
    s = tl_summary_print(&part, stdout);
    goto out;
  }
  TL_CHECK_GOTO(s, write_tables(dir, &r, n_snap), out);
  /* energy is conserved once the excitation stops (t0 for the driven cases) */
  double t0 = p.excitation == TL_WAVE_PULSE ? 0.0 : 2.0 * 3.14159265358979323846 * p.cycles / p.omega;
  double e_ref = NAN, e_dev = 0.0;
  for (size_t k = 0; k < r.n; ++k) {
    if (r.state[k].t < t0 + r.dt) continue;
    if (isnan(e_ref)) e_ref = r.state[k].total;
    e_dev = tl_track_max(e_dev, fabs(r.state[k].total - e_ref) / e_ref);
  }
  tl_printf("full DEM %s %s: %zu particles, dt = %.4g s, %ld steps, energy %.6g J (largest relative deviation %.3g "
            "after the excitation); output in %s\n",
            cases[icase], excitations[iexc], r.n_particles, r.dt, r.steps, e_ref, e_dev, dir);
  {
    char plot_cmd[4200], plot_dir[4200];
    tl_printf("plots: %s %s\n", tl_plot_command(TALUS_TOOLS_DIR, "plot_wave.py", plot_cmd, sizeof plot_cmd),
              tl_plot_abs_dir(dir, plot_dir, sizeof plot_dir));
  }
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_string(&sum, "case", cases[icase]);
  tl_summary_string(&sum, "excitation", excitations[iexc]);
  tl_summary_int(&sum, "particles", (long)r.n_particles);
  tl_summary_real(&sum, "energy", e_ref);
  tl_summary_real(&sum, "energy_dev", e_dev);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  s = tl_summary_print(&sum, stdout);
out:
  tl_wave_record_free(&r);
done:
  tl_free(&dir);
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
