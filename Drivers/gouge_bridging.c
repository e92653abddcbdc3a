/* gouge_bridging: the pre-stressed granular gouge between two elastic bars
 * of Voisin-Leprince et al. 2023 (§4-5), coupled by the bridging
 * domain method (Scenes/tl_gouge_bridging.h, Coupling/Bridging/tl_bdm.h).
 *
 *   -mode rest   the coupled bar at rest (Fig. 4): section-averaged
 *                displacement of the monitored planes, whose largest value
 *                is the noise level;
 *   -mode wave   a P or S pulse (Eq. 15) from the left far end through the
 *                gouge (Figs. 5-8): incident, reflected and transmitted
 *                peaks at the middle planes of the two bars.
 *
 * Output in -output_dir: history.csv/.h5 (time, the monitored planes' u,
 * the coupling's report), ct_ux|ct_uy|ct_uz.csv/.h5 (the ct diagram: the
 * section average at every node plane, one row per sample; plane
 * positions in planes.csv), snapshots particles_*.h5/bars_*.h5 + .xmf,
 * checkpoint.h5.  A run restarted (-restart) extends the snapshot series
 * and writes its tables from the restart step as history_restart<step>.*,
 * ct_*_restart<step>.*.  Last line: summary: key=value ... */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_options_renamed.h"
#include "tl_series_sweep.h"
#include "tl_plot_hint.h"
#include "tl_gouge_bridging.h"
#include "tl_memory.h"
#include "tl_output_dir.h"
#include "tl_progress.h"
#include "tl_pulse.h"
#include "tl_timeseries.h"
#include "tl_timer.h"

#define D0 0.003 /* mean grain diameter (m), the unit "d" */

typedef struct {
  TlGougeParams p;
  long steps, table_every, snapshot_every, checkpoint_every, stop_step;
  const char *restart;
  int progress;
} Run;

static TlStatus read_options(TlOptions *o, Run *r)
{
  TlGougeParams *p = &r->p;
  tl_gouge_params_default(p);
  const TlScale d[] = {{"d", D0, "mean grain diameter d0 = 3 mm"}};
  static const char *modes[] = {"rest", "wave", NULL}, *waves[] = {"P", "S", NULL},
                    *shapes[] = {"gaussian", "ricker", NULL}, *fes[] = {"solid", "linear", NULL},
                    *couplings[] = {"strong", "weak", NULL};
  int mode = 0, wave = 0, shape = 0, fe = 0, coupling = 0;
  static const TlRenamedOption renamed[] = {
      {"-density", "-rho", "the finite elements' density, as in every FEM driver"},
      {"-k_n", "-contact_k_n", NULL},
      {"-k_t", "-contact_k_t", NULL},
      {"-gamma_n", "-contact_gamma_n", NULL},
      {"-gamma_t", "-contact_gamma_t", NULL},
      {"-mu", "-contact_mu", NULL},
      {"-snapshot_every", "-snapshot_dt", "now a time interval in seconds, as in every time-stepping driver"},
      {"-record_every", "-table_every", "table cadence: -table_dt seconds, -table_every steps, -table_rows a count"}};
  TL_CHECK(tl_options_refuse_renamed(o, renamed, (int)(sizeof renamed / sizeof renamed[0])));
  TL_CHECK(tl_options_get_string(o, "-packing", "",
                                 "packing file (.h5, with its cell) or LAMMPS data file of the relaxed periodic cell (cubic; e.g. "
                                 "SelfTests/data/gouge_6d0.h5, a packing file, or its .data copy)",
                                 &p->packing));
  TL_CHECK(tl_options_get_choice(o, "-mode", "rest", modes, "rest: noise at rest (Fig. 4); wave: a pulse (Figs. 5-8)", &mode));
  TL_CHECK(tl_options_get_choice(o, "-wave", "P", waves, "P: u_y pulse, S: u_x pulse", &wave));
  TL_CHECK(tl_options_get_choice(o, "-pulse", "gaussian", shapes,
                                 "gaussian: Eq. 15 as printed (the paper's \"Ricker\"); ricker: the true Ricker wavelet", &shape));
  TL_CHECK(tl_options_get_scaled(o, "-wavelength", "200d", 1e-6, 1e3, "m", d, 1, "pulse wavelength lambda (Table 3)",
                                 &p->wavelength));
  TL_CHECK(tl_options_get_real(o, "-intensity", 5e-4, -1.0, 1.0, "m", "pulse intensity I (Table 3)", &p->intensity));
  TL_CHECK(tl_options_get_bool(o, "-pulse_subtract_initial", 0, "impose u(t) - u(0) (removes the step of 7.2e-3 I at t = 0)",
                               &p->subtract_initial));
  TL_CHECK(tl_options_get_scaled(o, "-mesh_h", "12d", 1e-6, 10.0, "m", d, 1,
                                 "FE element size h asked for (paper 12d or 3d; rounded to fit the periodic section; -h is -help)", &p->h));
  TL_CHECK(tl_options_get_scaled(o, "-bridge", "0", 0.0, 10.0, "m", d, 1,
                                 "bridging zone length (0: the packing cell side, the scripts' bridging_12_d0)", &p->bridge));
  double fe_len = 0.0;
  TL_CHECK(tl_options_get_scaled(o, "-fe_length", "0", 0.0, 100.0, "m", d, 1,
                                 "length of each FE bar (0: 0.4 m at rest, 36 h in wave mode, the scripts')", &fe_len));
  long cs = 2, cy = 4;
  TL_CHECK(tl_options_get_int(o, "-cells_section", 2, 1, 64, "packing cells across x and z (section)", &cs));
  TL_CHECK(tl_options_get_int(o, "-cells_y", 4, 2, 256, "packing cells along y (DEM bar length)", &cy));
  p->cells_section = (int)cs, p->cells_y = (int)cy;
  TL_CHECK(tl_options_get_real(o, "-E", p->E, 1.0, 1e15, "Pa", "FE Young's modulus (Table 2)", &p->E));
  TL_CHECK(tl_options_get_real(o, "-nu", p->nu, -0.99, 0.49, "", "FE Poisson's ratio (Table 2)", &p->nu));
  TL_CHECK(tl_options_get_real(o, "-rho", p->rho, 1e-3, 1e6, "kg/m^3",
                               "FE density (the scripts' 1643; Table 2 prints 1543)", &p->rho));
  TL_CHECK(tl_options_get_real(o, "-eigenstrain", p->eigenstrain, -0.1, 0.1, "",
                               "isotropic FE eigenstrain (scripts' eigen_grad_u 0.0025: -4.98 MPa)", &p->eigenstrain));
  TL_CHECK(tl_options_get_choice(o, "-fe", "solid", fes,
                                 "solid: the finite-strain solid every step (the paper); linear: K assembled once about "
                                 "the pre-stressed rest state",
                                 &fe));
  TL_CHECK(tl_options_get_real(o, "-contact_k_n", p->k_n, 0.0, 1e20, "Pa", "grains: Hertz normal constant (Table 1)", &p->k_n));
  TL_CHECK(tl_options_get_real(o, "-contact_k_t", p->k_t, 0.0, 1e20, "Pa", "grains: tangential constant (Table 1)", &p->k_t));
  TL_CHECK(tl_options_get_real(o, "-contact_gamma_n", p->gamma_n, 0.0, 1e10, "1/(m s)", "grains: normal damping (Table 1)",
                               &p->gamma_n));
  TL_CHECK(tl_options_get_real(o, "-contact_gamma_t", p->gamma_t, -1.0, 1e10, "1/(m s)",
                               "grains: tangential damping (-1: gamma_n / 2, LAMMPS NULL; Table 1: 0.1)", &p->gamma_t));
  TL_CHECK(tl_options_get_real(o, "-contact_mu", p->mu, 0.0, 10.0, "", "grains: friction coefficient (Table 1)", &p->mu));
  TL_CHECK(tl_options_get_real(o, "-grain_density", p->grain_density, 1e-3, 1e6, "kg/m^3", "grain density (Table 1)",
                               &p->grain_density));
  TL_CHECK(tl_options_get_real(o, "-dt", p->dt, 1e-15, 1.0, "s", "time step of both models (Table 1)", &p->dt));
  long th = 0;
  TL_CHECK(tl_options_get_int(o, "-threads", 0, 0, 1024, "DEM OpenMP threads (0: default)", &th));
  p->threads = (int)th;
  TL_CHECK(tl_options_get_choice(o, "-coupling", "strong", couplings,
                                 "constraint (the paper's name; the same as -bdm): strong, Eqs. 7-10; weak, Eqs. 11-14",
                                 &coupling));
  p->bdm.constraint = coupling ? TL_BDM_WEAK : TL_BDM_STRONG;
  TL_CHECK(tl_bdm_options_from_db(o, &p->bdm));
  if ((p->bdm.constraint == TL_BDM_WEAK) != (coupling == 1))
    TL_ERROR(TL_ERR_ARG, "-coupling %s and -bdm %s disagree", couplings[coupling], tl_bdm_constraint_name(p->bdm.constraint));
  TL_CHECK(tl_options_get_int(o, "-steps", 0, 0, 1000000000L,
                              "steps (0: 5e5 at rest, the paper's; in wave mode until the transmitted pulse has passed)",
                              &r->steps));
  TL_CHECK(tl_options_get_int(o, "-table_every", 5000, 1, 1000000000L,
                              "steps between samples of the histories and the ct diagram (paper: 5000)", &r->table_every));
  double snapshot_dt = 0.0;
  TL_CHECK(tl_options_get_real(o, "-snapshot_dt", 0.0, 0.0, 1e6, "s",
                               "HDF5 + XDMF snapshots every (rounded to whole steps; 0: none)", &snapshot_dt));
  r->snapshot_every = snapshot_dt > 0.0 ? (long)fmax(1.0, round(snapshot_dt / p->dt)) : 0;
  TL_CHECK(tl_options_get_int(o, "-checkpoint_every", 0, 0, 1000000000L, "steps between checkpoints (0: none)",
                              &r->checkpoint_every));
  TL_CHECK(tl_options_get_string(o, "-restart", "", "continue from this checkpoint", &r->restart));
  TL_CHECK(tl_options_get_int(o, "-stop_step", 0, 0, 1000000000L, "stop after this step (0: run to the end)", &r->stop_step));
  TL_CHECK(tl_options_get_bool(o, "-progress", 1, "progress bar on stderr", &r->progress));
  p->mode = mode ? TL_GOUGE_WAVE : TL_GOUGE_REST;
  p->wave_component = wave ? 0 : 1;
  p->pulse_shape = shape ? TL_PULSE_RICKER : TL_PULSE_GAUSSIAN;
  p->linear_fe = fe;
  p->fe_length = fe_len > 0 ? fe_len : (p->mode == TL_GOUGE_WAVE ? 36.0 * p->h : 0.4);
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  Run r;
  char *dir = NULL;
  TlGouge *g = NULL;
  TlTimeSeries *hist = NULL, *ct[3] = {NULL, NULL, NULL};
  TlColumn *cols = NULL;
  char *names = NULL;
  double *y = NULL, *u = NULL, *row = NULL, *ctrow = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv,
                             "The bridging domain method on a pre-stressed granular gouge between two elastic bars "
                             "(Voisin-Leprince et al. 2023): noise at rest (Fig. 4) or a P/S pulse through the "
                             "gouge (Figs. 5-8).  Paper: " TL_PAPER_VOISIN_LEPRINCE_2023 ".",
                             &o));
  TlStatus s = read_options(o, &r);
  if (s == TL_OK) s = tl_output_dir(o, &dir);
  if (s == TL_OK) s = tl_options_finish(o, stdout);
  if (s) goto done;
  if (!r.p.packing[0]) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                     "no -packing given: a packing or LAMMPS data file of the periodic cell (SelfTests/data/gouge_6d0.h5 "
                     "is a 228-grain 6 d0 cell at 5 MPa, at rest)");
    goto done;
  }
  double wall0 = tl_wtime();
  TL_CHECK_GOTO(s, tl_gouge_create(&r.p, &g), done);
  TlGougeInfo in;
  tl_gouge_info(g, &in);
  tl_printf("gouge_bridging: %zu grains (cell %.5g m = %.3f d0, %d x %d x %d cells), %zu coupled; FE %d x %d x %d hex8 per bar "
            "(h %.4g x %.4g m), %zu dofs, %s path; sigma0 %.4g Pa; c_P %.1f m/s, c_S %.1f m/s; dt %g s (DEM critical %.3g s)\n",
            in.n_particles, in.a, in.a / D0, r.p.cells_section, r.p.cells_y, r.p.cells_section, in.n_coupled, in.n_section,
            in.n_bar, in.n_section, in.hx, in.hy, in.n_dofs, r.p.linear_fe ? "linear" : "finite-strain", in.sigma0, in.c_p,
            in.c_s, r.p.dt, in.dem_dt_critical);
  /* Wave windows: the incident pulse passes the left monitor at t_i, the
   * transmitted one the right monitor at t_T (FE speed). */
  double y_end = in.fe_start + in.n_bar * in.hy, lam_c = r.p.wavelength / in.c;
  double t0 = 0.0;
  {
    TlPulse pl;
    if (r.p.mode == TL_GOUGE_WAVE && tl_pulse_init(&pl, r.p.pulse_shape, r.p.intensity, r.p.wavelength, in.c) == TL_OK)
      t0 = pl.t0;
  }
  double t_i = t0 + (in.y_monitor[0] + y_end) / in.c, t_T = t0 + (in.y_monitor[1] + y_end) / in.c;
  long steps = r.steps;
  if (steps == 0) steps = r.p.mode == TL_GOUGE_WAVE ? (long)ceil((t_T + 0.8 * lam_c) / r.p.dt) : 500000;
  if (r.snapshot_every > 0) {
    TL_CHECK_GOTO(s, tl_gouge_open_snapshots(g, dir), done);
  } else if (!r.restart[0]) { /* a rerun with snapshots off: the earlier run's series would pass for this one's */
    size_t removed;
    TL_CHECK_GOTO(s, tl_series_sweep_whole(dir, "particles", &removed), done);
  }
  if (r.restart[0]) {
    TL_CHECK_GOTO(s, tl_gouge_checkpoint_load(g, r.restart), done);
    tl_printf("restarted from %s at step %ld\n", r.restart, tl_gouge_steps(g));
  }
  /* Tables: history (monitored planes + report), ct diagrams, planes. */
  size_t np = in.n_planes;
  TL_CHECK_GOTO(s, tl_calloc(&y, np, sizeof *y), done);
  TL_CHECK_GOTO(s, tl_calloc(&u, 3 * np, sizeof *u), done);
  TL_CHECK_GOTO(s, tl_calloc(&ctrow, np + 2, sizeof *ctrow), done);
  TL_CHECK_GOTO(s, tl_calloc(&cols, np + 16, sizeof *cols), done);
  TL_CHECK_GOTO(s, tl_calloc(&names, (np + 16) * 32, 1), done);
  tl_gouge_planes(g, y, u);
  {
    char path[4096];
    snprintf(path, sizeof path, "%s/planes.csv", dir);
    FILE *f = fopen(path, "w");
    if (!f) {
      s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "cannot write %s", path);
      goto done;
    }
    fprintf(f, "plane,y [m]\n");
    for (size_t k = 0; k < np; ++k) fprintf(f, "%zu,%.17g\n", k, y[k]);
    fclose(f);
  }
  const char *hnames[] = {"t", "step", "ux_0", "uy_0", "uz_0", "ux_1", "uy_1", "uz_1", "ux_2", "uy_2", "uz_2",
                          "rate_after", "residual_max", "momentum_y", "energy_removed_total"};
  const char *hunits[] = {"s", "", "m", "m", "m", "m", "m", "m", "m", "m", "m", "m/s", "m", "kg m/s", "J"};
  enum { NH = 15 };
  for (int k = 0; k < NH; ++k) cols[k] = (TlColumn){hnames[k], hunits[k]};
  char base[4096];
  /* A restarted run writes its tables beside the first run's, from the
   * restart step (history_restart<step>.csv ...), never over them. */
  char tag[64] = "";
  if (r.restart[0]) snprintf(tag, sizeof tag, "_restart%ld", tl_gouge_steps(g));
  snprintf(base, sizeof base, "%s/history%s", dir, tag);
  TL_CHECK_GOTO(s, tl_timeseries_create(base, TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, NH, cols, &hist), done);
  cols[0] = (TlColumn){"t", "s"};
  for (size_t k = 0; k < np; ++k) {
    snprintf(names + 32 * k, 32, "plane%zu", k);
    cols[k + 1] = (TlColumn){names + 32 * k, "m"};
  }
  const char *ctn[3] = {"ct_ux", "ct_uy", "ct_uz"};
  for (int c = 0; c < 3; ++c) {
    snprintf(base, sizeof base, "%s/%s%s", dir, ctn[c], tag);
    TL_CHECK_GOTO(s, tl_timeseries_create(base, TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, np + 1, cols, &ct[c]), done);
  }
  TL_CHECK_GOTO(s, tl_calloc(&row, NH, sizeof *row), done);
  size_t mon[3];
  for (int m = 0; m < 3; ++m) {
    mon[m] = 0;
    for (size_t k = 1; k < np; ++k)
      if (fabs(y[k] - in.y_monitor[m]) < fabs(y[mon[m]] - in.y_monitor[m])) mon[m] = k;
  }
  /* Measures. */
  double noise[2] = {0, 0}, noise_c[3] = {0, 0, 0}, inc = 0, refl = 0, trans = 0, t_trans = 0;
  int wc = r.p.wave_component;
  TlProgress bar;
  if (r.progress) tl_progress_init(&bar, "gouge_bridging", (double)steps);
  long stop = r.stop_step > 0 && r.stop_step < steps ? r.stop_step : steps;
  double wall_steps = tl_wtime();
  long first = tl_gouge_steps(g);
  for (long k = tl_gouge_steps(g); k <= stop; ++k) {
    if (k > tl_gouge_steps(g)) TL_CHECK_GOTO(s, tl_gouge_step(g), done);
    long step = tl_gouge_steps(g);
    double t = tl_gouge_time(g);
    int sample = step % r.table_every == 0 || step == stop;
    if (sample || r.p.mode == TL_GOUGE_WAVE) tl_gouge_planes(g, NULL, u);
    for (int side = 0; side < 2; ++side)
      for (int c = 0; c < 3; ++c) {
        double v = fabs(u[3 * mon[side] + c]);
        noise[side] = fmax(noise[side], v);
        if (side == 0) noise_c[c] = fmax(noise_c[c], v);
      }
    if (r.p.mode == TL_GOUGE_WAVE) {
      double ui = u[3 * mon[0] + wc], ut = u[3 * mon[1] + wc];
      if (t <= t_i + 0.5 * lam_c) inc = fmax(inc, ui);
      else refl = fmax(refl, fabs(ui));
      if (ut > trans) trans = ut, t_trans = t;
    }
    if (sample) {
      TlBdmReport rep;
      tl_gouge_report(g, &rep);
      row[0] = t, row[1] = (double)step;
      for (int m = 0; m < 3; ++m)
        for (int c = 0; c < 3; ++c) row[2 + 3 * m + c] = u[3 * mon[m] + c];
      row[11] = rep.rate_after, row[12] = rep.residual_max, row[13] = rep.momentum[1], row[14] = rep.energy_removed_total;
      TL_CHECK_GOTO(s, tl_timeseries_append(hist, row), done);
      for (int c = 0; c < 3; ++c) {
        ctrow[0] = t;
        for (size_t q = 0; q < np; ++q) ctrow[q + 1] = u[3 * q + c];
        TL_CHECK_GOTO(s, tl_timeseries_append(ct[c], ctrow), done);
      }
    }
    /* (the restart step's snapshot is the first run's last) */
    if (r.snapshot_every > 0 && step % r.snapshot_every == 0 && !(r.restart[0] && step == first))
      TL_CHECK_GOTO(s, tl_gouge_snapshot(g, dir), done);
    if (r.checkpoint_every > 0 && step > first && step % r.checkpoint_every == 0) {
      snprintf(base, sizeof base, "%s/checkpoint.h5", dir);
      TL_CHECK_GOTO(s, tl_gouge_checkpoint_save(g, base), done);
    }
    if (r.progress && step % 1000 == 0) tl_progress_update(&bar, (double)step);
  }
  if (r.progress) tl_progress_finish(&bar);
  double wall_loop = tl_wtime() - wall_steps;
  for (int c = 0; c < 3; ++c) TL_CHECK_GOTO(s, tl_timeseries_close(&ct[c]), done);
  TL_CHECK_GOTO(s, tl_timeseries_close(&hist), done);
  TlGougeTimes tm;
  tl_gouge_times(g, &tm);
  TlBdmReport rep;
  tl_gouge_report(g, &rep);
  long done_steps = tl_gouge_steps(g) - first;
  double per = done_steps > 0 ? 1e6 / (double)done_steps : 0.0;
  tl_gouge_planes(g, NULL, u);
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_string(&sum, "mode", r.p.mode == TL_GOUGE_WAVE ? "wave" : "rest");
  tl_summary_string(&sum, "coupling", tl_bdm_constraint_name(r.p.bdm.constraint));
  tl_summary_string(&sum, "lumping", tl_bdm_lumping_name(r.p.bdm.lumping));
  tl_summary_string(&sum, "ghost_force", tl_bdm_ghost_name(r.p.bdm.ghost));
  tl_summary_string(&sum, "fe", r.p.linear_fe ? "linear" : "solid");
  tl_summary_int(&sum, "particles", (long)in.n_particles);
  tl_summary_int(&sum, "coupled", (long)in.n_coupled);
  tl_summary_int(&sum, "fe_dofs", (long)in.n_dofs);
  tl_summary_int(&sum, "steps", tl_gouge_steps(g));
  tl_summary_real(&sum, "t", tl_gouge_time(g));
  tl_summary_real(&sum, "y_monitor", in.y_monitor[0]);
  if (r.p.mode == TL_GOUGE_REST) {
    tl_summary_real(&sum, "noise", fmax(noise[0], noise[1]));
    tl_summary_real(&sum, "noise_right", noise[0]);
    tl_summary_real(&sum, "noise_left", noise[1]);
    tl_summary_real(&sum, "noise_x", noise_c[0]);
    tl_summary_real(&sum, "noise_y", noise_c[1]);
    tl_summary_real(&sum, "noise_z", noise_c[2]);
    tl_summary_real(&sum, "noise_d0", fmax(noise[0], noise[1]) / D0);
  } else {
    double I = fabs(r.p.intensity) > 0 ? fabs(r.p.intensity) : 1.0;
    tl_summary_real(&sum, "incident", inc / I);
    tl_summary_real(&sum, "transmitted", trans / I);
    tl_summary_real(&sum, "reflected", refl / I);
    tl_summary_real(&sum, "T", inc > 0 ? trans / inc : 0.0);
    tl_summary_real(&sum, "R", inc > 0 ? refl / inc : 0.0);
    tl_summary_real(&sum, "t_transmitted", t_trans);
    tl_summary_real(&sum, "t_transmitted_fe", t_T);
    tl_summary_real(&sum, "y_transmitted", in.y_monitor[1]);
  }
  tl_summary_real(&sum, "final_uy", u[3 * mon[0] + 1]);
  tl_summary_real(&sum, "rate_after", rep.rate_after);
  tl_summary_real(&sum, "residual_max", rep.residual_max);
  tl_summary_real(&sum, "energy_removed", rep.energy_removed_total);
  tl_summary_real(&sum, "us_dem", tm.t_dem * per);
  tl_summary_real(&sum, "us_fe", tm.t_fe * per);
  tl_summary_real(&sum, "us_correct", tm.t_correct * per);
  tl_summary_real(&sum, "wall_loop", wall_loop);
  {
    char plot_cmd[4200], plot_dir[4200];
    const char *mode = r.p.mode == TL_GOUGE_WAVE ? "wave" : "rest";
    tl_plot_abs_dir(dir, plot_dir, sizeof plot_dir);
    tl_printf("plots: %s %s %s/%s.png %s\n", tl_plot_command(TALUS_TOOLS_DIR, "plot_gouge_bridging.py", plot_cmd, sizeof plot_cmd),
              mode, plot_dir, mode, plot_dir);
  }
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  s = tl_summary_print(&sum, stdout);
done:
  for (int c = 0; c < 3; ++c) tl_timeseries_destroy(&ct[c]);
  tl_timeseries_destroy(&hist);
  tl_gouge_destroy(&g);
  tl_free(&y);
  tl_free(&u);
  tl_free(&row);
  tl_free(&ctrow);
  tl_free(&cols);
  tl_free(&names);
  tl_free(&dir);
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
