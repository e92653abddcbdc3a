/* Talus against LAMMPS on the same DEM scenes, in one invocation:
 *   (a) LAMMPS's granular chute benchmark: 32 000 spheres (data.chute),
 *       Hooke with tangential history, a frozen rough base, gravity along a
 *       chute inclined at 26 degrees (LAMMPS: pair gran/hooke/history
 *       200000 NULL 50 NULL 0.5 0, neighbor 0.1, timestep 1e-4);
 *   (b) a dense Hertz-Mindlin packing of 10 000 polydisperse spheres settled
 *       in a 25 x 25 box with frictional walls (LAMMPS: pair
 *       gran/hertz/history 7.3e5 NULL 50 NULL 0.5 1, walls wall/gran).
 * Talus runs on exactly the particles the peer runs on (read from the peer's
 * data files) with the SAME law: the parts that reproduce LAMMPS's styles
 * (tl_contact_*_lammps_*.c, checked to round-off by the test parity_lammps),
 *   (a) lammps_hooke + lammps_history (k_n 2e5, gamma_n 50, mu 0.5, dampflag 0),
 *   (b) lammps_hertz + lammps_history (k_n 7.3e5, gamma_n 50, gamma_t 25, mu 0.5),
 *       walls with the same law (fix wall/gran hertz/history).
 * Prints µs per particle-step for both codes on 1 core and on 2 (Talus with
 * 2 OpenMP threads, LAMMPS with 2 MPI ranks) and the ratio talus/lammps,
 * each code's speed-up from its second core beside it (summary keys
 * <scene>_speedup_talus, <scene>_speedup_lammps), Talus's phase breakdown
 * of every timed run (tl_dem_phase_times: share of the wall time per phase,
 * each thread's busy time in the contact loop), whether the two-thread
 * answers are the one-thread answers to the last bit (<scene>_threads_identical), and
 * the answers: the translational and rotational kinetic energies after the
 * same number of steps (LAMMPS: its deck's warm-up run, then the timed run;
 * Talus: the same steps in one run).  They agree to about 1e-5, not to
 * round-off: LAMMPS's second `run` starts with one more setup evaluation
 * (no shear update, the full-step velocities in the dampers) that a single
 * run does not have, and these flows are chaotic.  (With the deck's two runs
 * made one of 1100 steps, LAMMPS's chute energies, 785702.569195 and
 * 1533.80182888, are Talus's to every digit printed.)  The last line is
 * the summary. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "peers/tl_peer.h"
#include "tl_bench.h"
#include "talus.h"
#include "tl_parallel.h"
#include "tl_dem.h"
#include "tl_lammps_data.h"

typedef struct {
  long steps, warmup;
  int repeat, peer, threads_max;
  const char *chute_path;
  int do_chute, do_hertz;
} Config;

/* The repository root, from this file's path (…/Benchmarks/dem_vs_lammps.c). */
static void repo_root(char *out, size_t cap)
{
  snprintf(out, cap, "%s", __FILE__);
  for (int k = 0; k < 2; ++k) {
    char *s = strrchr(out, '/');
    if (s) *s = '\0';
    else snprintf(out, cap, ".");
  }
}

/* Builds the Talus scene from a LAMMPS data file. */
static double g_skin = 0.1, g_mu = 0.5;
static long g_sort = 10;

static TlStatus build_chute(const TlLammpsData *data, int threads, TlDem **out)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  int per[3] = {1, 1, 0};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(data->lo[0], data->lo[1], data->lo[2]),
                                       tl_v3(data->hi[0], data->hi[1], data->hi[2]), per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  int sp;
  TL_CHECK(tl_particles_add_species(P, "chute", data->density[0], 0.5 * data->diameter[0], 0.5 * data->diameter[0], &sp));
  TL_CHECK(tl_particles_reserve(P, data->n));
  for (size_t i = 0; i < data->n; ++i) {
    size_t k;
    TL_CHECK(tl_dem_add_particle(dem, data->x[i], data->v[i], 0.5 * data->diameter[i], sp, &k));
    if (data->type[i] == 2) TL_CHECK(tl_particles_set_motion(P, k, TL_MOTION_FIXED));
  }
  /* the file's spins (a developed flow), as LAMMPS starts from them */
  TL_CHECK(tl_particles_enable_rotation(P));
  for (size_t k = 0; k < P->n; ++k) P->w[k] = data->omega[P->id[k]];
  /* LAMMPS gran/hooke/history 200000.0 NULL 50.0 NULL 0.5 0 */
  const TlContactValue lv[] = {{"k_n", 200000.0}, {"gamma_n", 50.0}, {"mu", g_mu}, {"dampflag", 0.0}};
  const TlContactSpec spec = {"lammps_hooke", "lammps_history", NULL, NULL, lv, 4};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  double a = 26.0 * TL_PI / 180.0;
  tl_dem_set_gravity(dem, tl_v3(sin(a), 0.0, -cos(a)));
  tl_dem_set_threads(dem, threads);
  tl_dem_track_energy(dem, 0);
  tl_dem_track_orientation(dem, 0); /* LAMMPS nve/sphere does not integrate orientations either */
  TL_CHECK(tl_dem_set_skin(dem, g_skin));
  tl_dem_set_sort_interval(dem, (int)g_sort);
  TL_CHECK(tl_dem_set_timestep(dem, 1e-4, 0));
  TL_CHECK(tl_dem_setup(dem));
  *out = dem;
  return TL_OK;
}

static TlStatus build_hertz(const TlLammpsData *data, int threads, TlDem **out)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  TL_CHECK(tl_domain_init_open(&dom, tl_v3(0, 0, 0), tl_v3(25, 25, data->hi[2] > 1 ? data->hi[2] : 25)));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  double dmin = INFINITY, dmax = 0;
  for (size_t i = 0; i < data->n; ++i) {
    dmin = fmin(dmin, data->diameter[i]);
    dmax = fmax(dmax, data->diameter[i]);
  }
  int sp;
  TL_CHECK(tl_particles_add_species(P, "grains", data->density[0], 0.5 * dmin, 0.5 * dmax, &sp));
  TL_CHECK(tl_particles_reserve(P, data->n));
  for (size_t i = 0; i < data->n; ++i)
    TL_CHECK(tl_dem_add_particle(dem, data->x[i], data->v[i], 0.5 * data->diameter[i], sp, NULL));
  /* the file's spins, before the first force evaluation as in LAMMPS
   * (particles in file order: ids 0..n-1) */
  TL_CHECK(tl_particles_enable_rotation(P));
  for (size_t k = 0; k < P->n; ++k) P->w[k] = data->omega[P->id[k]];
  /* LAMMPS gran/hertz/history 7.3e5 NULL 50.0 NULL 0.5 1 (k_t 2/7 k_n, gamma_t 25) */
  const TlContactValue hv[] = {{"k_n", 7.3e5}, {"gamma_n", 50.0}, {"mu", g_mu}, {"dampflag", 1.0}};
  const TlContactSpec spec = {"lammps_hertz", "lammps_history", NULL, NULL, hv, 4};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TlWall *w;
  const TlVec3 pts[5] = {{0, 0, 0}, {25, 0, 0}, {0, 0, 0}, {0, 25, 0}, {0, 0, 0}};
  const TlVec3 nrm[5] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  for (int k = 0; k < 5; ++k) {
    TL_CHECK(tl_wall_plane_create(pts[k], nrm[k], &w));
    TL_CHECK(tl_dem_add_wall(dem, w, 0));
  }
  tl_dem_set_gravity(dem, tl_v3(0, 0, -1));
  tl_dem_set_threads(dem, threads);
  tl_dem_track_energy(dem, 0);
  tl_dem_track_orientation(dem, 0); /* LAMMPS nve/sphere does not integrate orientations either */
  TL_CHECK(tl_dem_set_skin(dem, g_skin));
  tl_dem_set_sort_interval(dem, (int)g_sort);
  TL_CHECK(tl_dem_set_timestep(dem, 1e-4, 0));
  TL_CHECK(tl_dem_setup(dem));
  *out = dem;
  return TL_OK;
}

typedef TlStatus (*Builder)(const TlLammpsData *, int, TlDem **);

/* Median over `repeat` fresh runs of µs per particle-step. */
/* Translational and rotational kinetic energy (LAMMPS's ke and erotate/sphere). */
static void kinetic(TlDem *dem, double *ke, double *erot)
{
  const TlParticles *P = tl_dem_particles(dem);
  double a = 0.0, b = 0.0;
  for (size_t i = 0; i < P->n; ++i) {
    a += 0.5 * P->mass[i] * tl_v3_norm2(P->v[i]);
    if (P->w) b += 0.5 * 0.4 * P->mass[i] * P->radius[i] * P->radius[i] * tl_v3_norm2(P->w[i]);
  }
  *ke = a;
  *erot = b;
}

/* The phase breakdown of a timed run: each phase's share of the wall time,
 * and the contact loop's threads (busy seconds, imbalance). */
static void print_phases(const char *name, int threads, TlDem *dem, double wall)
{
  TlDemPhaseTimes pt;
  tl_dem_phase_times(dem, &pt);
  const double per = 1e6 / ((double)pt.steps * (double)tl_dem_particles(dem)->n);
  printf("talus phases: scene=%s threads=%d (us per particle-step, share of wall)", name, threads);
  double sum = 0.0;
  for (int p = 0; p < TL_DEM_N_PHASES; ++p) {
    printf(" %s=%.4f(%.0f%%)", tl_dem_phase_name(p), pt.seconds[p] * per, 100.0 * pt.seconds[p] / wall);
    sum += pt.seconds[p];
  }
  printf(" untimed=%.0f%%\n", 100.0 * (wall - sum) / wall);
  if (pt.threads > 1) {
    printf("talus contact loop: scene=%s threads=%d busy", name, pt.threads);
    for (int t = 0; t < pt.threads && t < TL_DEM_MAX_TIMED_THREADS; ++t) printf(" t%d=%.3fs", t, pt.thread_busy[t]);
    printf(" of %.3fs, imbalance %.3fs (slowest - mean)\n", pt.seconds[TL_DEM_PHASE_CONTACTS], pt.imbalance);
  }
}

static TlStatus time_talus(const char *name, Builder build, const TlLammpsData *data, int threads, const Config *c,
                           long warmup, double *us_median, double *us_min, double *ke, double *erot)
{
  double t[16];
  int r = c->repeat < 16 ? c->repeat : 16;
  for (int k = 0; k < r; ++k) {
    TlDem *dem;
    TL_CHECK(build(data, threads, &dem));
    TL_CHECK(tl_dem_step(dem, warmup));
    tl_dem_reset_phase_times(dem);
    struct timespec c0, c1;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
    double t0 = tl_wtime();
    TL_CHECK(tl_dem_step(dem, c->steps));
    double el = tl_wtime() - t0;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
    double cpu = (double)(c1.tv_sec - c0.tv_sec) + 1e-9 * (double)(c1.tv_nsec - c0.tv_nsec);
    TlDemStats st;
    tl_dem_stats(dem, &st);
    t[k] = el * 1e6 / ((double)c->steps * (double)tl_dem_particles(dem)->n);
    printf("talus run %d/%d: scene=%s threads=%d particles=%zu steps=%ld time=%.3f s us_per_particle_step=%.4f "
           "cpu_share=%.2f contacts=%zu pairs=%zu rebuilds=%ld\n",
           k + 1, r, name, threads, tl_dem_particles(dem)->n, c->steps, el, t[k], cpu / (el * threads), st.n_contacts,
           st.n_pairs, st.rebuilds);
    print_phases(name, threads, dem, el);
    kinetic(dem, ke, erot);
    printf("talus answers: scene=%s threads=%d kinetic=%.17g rotational=%.17g\n", name, threads, *ke, *erot);
    fflush(stdout);
    tl_dem_destroy(&dem);
  }
  for (int a = 1; a < r; ++a)
    for (int b = a; b > 0 && t[b - 1] > t[b]; --b) {
      double s = t[b];
      t[b] = t[b - 1];
      t[b - 1] = s;
    }
  *us_min = t[0];
  *us_median = t[r / 2];
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o;
  TL_CHECK(tl_options_create(argc, argv,
                             "Talus against LAMMPS on the chute benchmark and a dense Hertz-Mindlin packing, "
                             "same particles, same laws, µs per particle-step and their ratio.  The last lines "
                             "before the summary are the table of both scenes (medians of -repeat runs): "
                             "`dem_vs_lammps -repeat 3` from build/Benchmarks gives it in one command.",
                             &o));
  char root[4096], def_chute[4200];
  repo_root(root, sizeof root);
  snprintf(def_chute, sizeof def_chute, "%s/../shared/peers/chute/data.chute", root);
  Config c;
  const char *scene;
  long tmax, rep, warm;
  TL_CHECK(tl_options_get_int(o, "-steps", 1000, 1, 100000000, "timed steps per run (LAMMPS: 1000 chute, 2000 packing)", &c.steps));
  TL_CHECK(tl_options_get_int(o, "-warmup", -1, -1, 100000000,
                              "untimed steps before timing (-1: the LAMMPS deck's, 100 chute, 200 packing)", &warm));
  TL_CHECK(tl_options_get_int(o, "-repeat", 3, 1, 16, "runs per code and configuration (median reported)", &rep));
  TL_CHECK(tl_options_get_bool(o, "-peer", 1, "also run LAMMPS (through Benchmarks/peers/run_peer.sh)", &c.peer));
  TL_CHECK(tl_options_get_int(o, "-threads_max", 2, 1, 64, "largest thread / rank count measured (1, then this)", &tmax));
  TL_CHECK(tl_options_get_string(o, "-chute_data", def_chute, "LAMMPS data file of the chute scene", &c.chute_path));
  TL_CHECK(tl_options_get_string(o, "-scene", "both", "chute, hertz or both", &scene));
  TL_CHECK(tl_options_get_real(o, "-mu", 0.5, 0.0, 10.0, "",
                               "friction coefficient (0: frictionless, no history, no rotation; Talus only)", &g_mu));
  TL_CHECK(tl_options_get_int(o, "-sort", 10, 0, 1000000, "renumber particles in grid order every this many list rebuilds (0: never)", &g_sort));
  TL_CHECK(tl_options_get_real(o, "-skin", 0.1, 0.0, 1.0, "mean diameters",
                               "Verlet skin of Talus (LAMMPS runs with 0.1 diameters)", &g_skin));
  TlStatus s = tl_options_finish(o, stdout);
  if (s != TL_OK) {
    tl_options_destroy(&o);
    return s;
  }
  c.warmup = warm;
  c.repeat = (int)rep;
  c.threads_max = (int)tmax;
  c.do_chute = !strcmp(scene, "both") || !strcmp(scene, "chute");
  c.do_hertz = !strcmp(scene, "both") || !strcmp(scene, "hertz");
  if (!c.do_chute && !c.do_hertz) TL_ERROR(TL_ERR_ARG, "-scene %s: expected chute, hertz or both", scene);
  TlSummary sum;
  tl_summary_init(&sum);
  double wall0 = tl_wtime();
  int nthr = c.threads_max > 1 ? 2 : 1;
  int thr[2] = {1, c.threads_max};
  const char *names[2] = {"chute", "hertz"};
  /* the final table: per scene, Talus and LAMMPS on 1 and 2 cores, and
   * whether the threads gave the one-thread answers */
  double tab_t[2][2] = {{NAN, NAN}, {NAN, NAN}}, tab_p[2][2] = {{NAN, NAN}, {NAN, NAN}};
  int tab_same[2] = {-1, -1};
  for (int sc = 0; sc < 2; ++sc) {
    if ((sc == 0 && !c.do_chute) || (sc == 1 && !c.do_hertz)) continue;
    char path[4096], stl[16];
    if (sc == 0) snprintf(path, sizeof path, "%s", c.chute_path);
    else TL_CHECK(tl_peer_prepare("hertz_lammps_classic", path, sizeof path, stl, sizeof stl));
    TlLammpsData *data;
    TL_CHECK(tl_lammps_data_read(path, &data));
    long steps_save = c.steps;
    double t1 = NAN, p1 = NAN, ke1 = NAN, erot1 = NAN; /* the one-thread figures and answers */
    for (int k = 0; k < nthr; ++k) {
      double tm = NAN, tmin = NAN, pm = NAN, ke = NAN, erot = NAN;
      const long warmup = c.warmup >= 0 ? c.warmup : (sc == 0 ? 100 : 200);
      if (k == 0)
        printf("%s: the same law in both codes: %s\n", names[sc],
               sc == 0 ? "LAMMPS gran/hooke/history 200000 NULL 50 NULL 0.5 0 = Talus lammps_hooke + lammps_history"
                       : "LAMMPS gran/hertz/history 7.3e5 NULL 50 NULL 0.5 1 (walls fix wall/gran, same) = Talus "
                         "lammps_hertz + lammps_history");
      TL_CHECK(time_talus(names[sc], sc == 0 ? build_chute : build_hertz, data, thr[k], &c, warmup, &tm, &tmin, &ke,
                          &erot));
      char key[64];
      snprintf(key, sizeof key, "%s_talus_%dc", names[sc], thr[k]);
      tl_summary_real(&sum, key, tm);
      if (c.peer) {
        TlPeerResult peer;
        TL_CHECK(tl_peer_run(sc == 0 ? "chute_lammps" : "hertz_lammps_classic", thr[k], c.steps, c.repeat, &peer));
        pm = peer.us_median;
        snprintf(key, sizeof key, "%s_lammps_%dc", names[sc], thr[k]);
        tl_summary_real(&sum, key, pm);
        snprintf(key, sizeof key, "%s_ratio_%dc", names[sc], thr[k]);
        tl_summary_real(&sum, key, tm / pm);
        if (k == 0) {
          snprintf(key, sizeof key, "ratio_%s", names[sc]);
          tl_summary_real(&sum, key, tm / pm);
        }
        /* the answers after the same steps (the deck's warm-up + timed run) */
        if (warmup == (sc == 0 ? 100 : 200) && isfinite(peer.ke) && isfinite(peer.erot)) {
          const double dk = fabs(ke - peer.ke) / fabs(peer.ke), dr = fabs(erot - peer.erot) / fabs(peer.erot);
          printf("%s, %d core%s, after %ld steps: kinetic energy talus %.10g lammps %.8g (relative %.2e), rotational "
                 "talus %.10g lammps %.8g (relative %.2e)\n", names[sc], thr[k], thr[k] > 1 ? "s" : "",
                 warmup + c.steps, ke, peer.ke, dk, erot, peer.erot, dr);
          snprintf(key, sizeof key, "%s_ke_rel_%dc", names[sc], thr[k]);
          tl_summary_real(&sum, key, dk);
          snprintf(key, sizeof key, "%s_erot_rel_%dc", names[sc], thr[k]);
          tl_summary_real(&sum, key, dr);
        }
      }
      tab_t[sc][k] = tm;
      tab_p[sc][k] = pm;
      printf("%s, %d core%s: talus %.4f us/particle-step (min %.4f)", names[sc], thr[k], thr[k] > 1 ? "s" : "", tm, tmin);
      if (c.peer) printf(", lammps %.4f, ratio talus/lammps = %.3f", pm, tm / pm);
      if (k == 0) {
        t1 = tm;
        p1 = pm;
        ke1 = ke;
        erot1 = erot;
      } else {
        /* each code's gain from its threads or ranks, beside the ratio */
        printf(", speed-up over 1 core: talus %.2f", t1 / tm);
        if (c.peer) printf(", lammps %.2f", p1 / pm);
        snprintf(key, sizeof key, "%s_speedup_talus", names[sc]);
        tl_summary_real(&sum, key, t1 / tm);
        if (c.peer) {
          snprintf(key, sizeof key, "%s_speedup_lammps", names[sc]);
          tl_summary_real(&sum, key, p1 / pm);
        }
        /* the answers do not depend on the thread count, to the last bit */
        const int same = ke == ke1 && erot == erot1;
        tab_same[sc] = same;
        printf(", answers %s", same ? "identical to 1 thread" : "DIFFER from 1 thread");
        snprintf(key, sizeof key, "%s_threads_identical", names[sc]);
        tl_summary_int(&sum, key, same);
      }
      printf("\n");
    }
    c.steps = steps_save;
    tl_lammps_data_destroy(&data);
  }
  /* the table (NaN columns: not measured, printed as -) */
  printf("\n| scene | Talus 1 thread | LAMMPS 1 rank | ratio | Talus %d threads | LAMMPS %d ranks | ratio | "
         "speed-up Talus / LAMMPS | same answers on %d threads |\n|---|---|---|---|---|---|---|---|---|\n",
         thr[nthr - 1], thr[nthr - 1], thr[nthr - 1]);
  for (int sc = 0; sc < 2; ++sc) {
    if ((sc == 0 && !c.do_chute) || (sc == 1 && !c.do_hertz)) continue;
    char cell[8][32];
    const double v[8] = {tab_t[sc][0], tab_p[sc][0], tab_t[sc][0] / tab_p[sc][0], tab_t[sc][1], tab_p[sc][1],
                         tab_t[sc][1] / tab_p[sc][1], tab_t[sc][0] / tab_t[sc][1], tab_p[sc][0] / tab_p[sc][1]};
    for (int q = 0; q < 8; ++q) {
      if (isfinite(v[q])) snprintf(cell[q], sizeof cell[q], q == 2 || q >= 5 ? "%.2f" : "%.4f us", v[q]);
      else snprintf(cell[q], sizeof cell[q], "-");
    }
    printf("| %s | %s | %s | %s | %s | %s | %s | %s / %s | %s |\n", names[sc], cell[0], cell[1], cell[2], cell[3],
           cell[4], cell[5], cell[6], cell[7], tab_same[sc] < 0 ? "-" : tab_same[sc] ? "yes" : "NO");
  }
  printf("(µs per particle-step, medians of %d runs; load average now %.2f)\n\n", c.repeat, tl_bench_load_average());
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  TlStatus s_sum = tl_summary_print(&sum, stdout);
  tl_options_destroy(&o);
  return s_sum;
}

int main(int argc, char **argv)
{
  tl_parallel_prefer_passive_wait(argv); /* timings on a shared machine */
  TlStatus s = tl_initialize();
  if (s == TL_OK) s = run(argc, argv);
  return tl_driver_exit(s);
}
