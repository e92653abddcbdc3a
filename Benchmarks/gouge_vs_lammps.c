/* The DEM part of the gouge bar of seeds/000 (§4-5, S-B2) in Talus and in
 * LAMMPS, in one invocation: a 5 MPa packing made by periodic_compress
 * -protocol scripts (the checked-in 6 d0 cell by default) replicated
 * nx x ny x nz times (default 4 x 8 x 4: a 24 d0 x 48 d0 x 24 d0 bar of about
 * 29 000 grains, the paper's ≈ 24 x 44 x 24 d0 block), periodic in x and z,
 * open along y (the bar's axis), with the gouge law of Table 1: LAMMPS
 * pair_style gran/hertz/history 3.663e10 4.5249e10 0.2 NULL 0.5 1, fix
 * nve/sphere, dt = 1e-8 s = Talus lammps_hertz + lammps_history, the same
 * spheres (the data file LAMMPS reads is written from Talus's doubles with
 * %.17g), the same Verlet skin (0.1 d0).  Forces agree to round-off (the
 * ctest parity_lammps_gouge runs one cell of this scene).
 *
 * Prints µs per particle-step of the timed steps (after an untimed warm-up;
 * LAMMPS: its own "Loop time" of the second run) on 1 core and on 2 (Talus
 * with 2 OpenMP threads, LAMMPS with 2 MPI ranks), the median of -repeat
 * fresh runs per code, and ratio = talus/lammps, with the 1-minute load
 * average before and after (the machine is shared).  Last line: summary. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "talus.h"
#include "tl_dem.h"
#include "tl_dem_packing.h"
#include "tl_parallel.h"
#include "tl_bench.h"

typedef struct {
  size_t n;
  TlVec3 *x, *v;
  double *r;
  double lo[3], hi[3]; /* y: the replicated extent (open) */
} Bar;

static void repo_root(char *out, size_t cap)
{
  snprintf(out, cap, "%s", __FILE__);
  for (int k = 0; k < 2; ++k) {
    char *s = strrchr(out, '/');
    if (s) *s = '\0';
    else snprintf(out, cap, ".");
  }
}

/* The packing cell replicated rep[0] x rep[1] x rep[2] times; positions
 * wrapped into the cell first. */
static TlStatus make_bar(const char *path, const int rep[3], Bar *b)
{
  TlParticleSnapshot snap;
  TlVec3 o;
  TlMat3 h;
  TL_CHECK(tl_dem_packing_read(path, &snap, &o, &h));
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c)
      if (a != c && h.m[a][c] != 0.0) {
        tl_particle_snapshot_free(&snap);
        TL_ERROR(TL_ERR_UNSUPPORTED, "%s: the cell is not orthogonal (h[%d][%d] = %g)", path, a, c, h.m[a][c]);
      }
  const double L[3] = {h.m[0][0], h.m[1][1], h.m[2][2]}, lo[3] = {o.x, o.y, o.z};
  b->n = snap.n * (size_t)(rep[0] * rep[1] * rep[2]);
  b->x = calloc(b->n, sizeof *b->x);
  b->v = calloc(b->n, sizeof *b->v);
  b->r = calloc(b->n, sizeof *b->r);
  if (!b->x || !b->v || !b->r) {
    tl_particle_snapshot_free(&snap);
    TL_ERROR(TL_ERR_MEM, "no memory for %zu grains", b->n);
  }
  for (int k = 0; k < 3; ++k) b->lo[k] = lo[k], b->hi[k] = lo[k] + rep[k] * L[k];
  size_t q = 0;
  for (int iz = 0; iz < rep[2]; ++iz)
    for (int iy = 0; iy < rep[1]; ++iy)
      for (int ix = 0; ix < rep[0]; ++ix)
        for (size_t i = 0; i < snap.n; ++i, ++q) {
          const double p[3] = {snap.position[i].x, snap.position[i].y, snap.position[i].z};
          const int off[3] = {ix, iy, iz};
          double x[3];
          for (int k = 0; k < 3; ++k) {
            double u = (p[k] - lo[k]) / L[k];
            u -= floor(u);
            x[k] = lo[k] + L[k] * (u + off[k]);
            if (!(x[k] < b->hi[k])) x[k] = lo[k]; /* u rounded up to 1 in the last copy */
          }
          b->x[q] = tl_v3(x[0], x[1], x[2]);
          b->v[q] = snap.velocity ? snap.velocity[i] : tl_v3(0, 0, 0);
          b->r[q] = snap.radius[i];
        }
  tl_particle_snapshot_free(&snap);
  return TL_OK;
}

static void bar_free(Bar *b) { free(b->x), free(b->v), free(b->r); }

/* ----------------------------------------------------------------- Talus */

static TlStatus build_talus(const Bar *b, int threads, TlDem **out)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  const int per[3] = {1, 0, 1};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(b->lo[0], b->lo[1], b->lo[2]), tl_v3(b->hi[0], b->hi[1], b->hi[2]),
                                       per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  double rmin = INFINITY, rmax = 0.0;
  for (size_t i = 0; i < b->n; ++i) rmin = fmin(rmin, b->r[i]), rmax = fmax(rmax, b->r[i]);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "gouge", 2500.0, rmin, rmax, &sp));
  TL_CHECK(tl_particles_reserve(P, b->n));
  for (size_t i = 0; i < b->n; ++i) TL_CHECK(tl_dem_add_particle(dem, b->x[i], b->v[i], b->r[i], sp, NULL));
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&tl_gouge_law_spec, &law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  tl_dem_set_threads(dem, threads);
  tl_dem_track_energy(dem, 0);
  tl_dem_track_orientation(dem, 0); /* nve/sphere integrates no orientation either */
  TL_CHECK(tl_dem_set_skin(dem, 0.1));
  TL_CHECK(tl_dem_set_timestep(dem, 1e-8, 0));
  TL_CHECK(tl_dem_setup(dem));
  *out = dem;
  return TL_OK;
}

static int cmp_double(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static TlStatus time_talus(const Bar *b, int threads, long warmup, long steps, int repeat, double *median)
{
  double t[16];
  for (int k = 0; k < repeat; ++k) {
    TlDem *dem;
    TL_CHECK(build_talus(b, threads, &dem));
    TL_CHECK(tl_dem_step(dem, warmup));
    const double t0 = tl_wtime();
    TL_CHECK(tl_dem_step(dem, steps));
    const double el = tl_wtime() - t0;
    TlDemStats st;
    tl_dem_stats(dem, &st);
    t[k] = el * 1e6 / ((double)steps * (double)b->n);
    printf("talus run %d/%d: threads=%d particles=%zu steps=%ld time=%.3f s us_per_particle_step=%.4f contacts=%zu "
           "rebuilds=%ld load=%.2f\n", k + 1, repeat, threads, b->n, steps, el, t[k], st.n_contacts, st.rebuilds,
           tl_bench_load_average());
    fflush(stdout);
    tl_dem_destroy(&dem);
  }
  qsort(t, (size_t)repeat, sizeof *t, cmp_double);
  *median = t[repeat / 2];
  return TL_OK;
}

/* ---------------------------------------------------------------- LAMMPS */

static int have(const char *exe)
{
  char cmd[256];
  snprintf(cmd, sizeof cmd, "command -v %s > /dev/null 2>&1", exe);
  return system(cmd) == 0;
}

static TlStatus write_lammps(const Bar *b, const char *dir, long warmup, long steps)
{
  char path[4200];
  snprintf(path, sizeof path, "%s/gouge_bar.data", dir);
  FILE *f = fopen(path, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write %s", path);
  fprintf(f, "LAMMPS data file of the gouge bar (Talus benchmark)\n\n%zu atoms\n1 atom types\n\n", b->n);
  const char *ax[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) fprintf(f, "%.17g %.17g %slo %shi\n", b->lo[k], b->hi[k], ax[k], ax[k]);
  fprintf(f, "\nAtoms # sphere\n\n");
  for (size_t i = 0; i < b->n; ++i)
    fprintf(f, "%zu 1 %.17g 2500 %.17g %.17g %.17g\n", i + 1, 2.0 * b->r[i], b->x[i].x, b->x[i].y, b->x[i].z);
  fprintf(f, "\nVelocities\n\n");
  for (size_t i = 0; i < b->n; ++i) fprintf(f, "%zu %.17g %.17g %.17g 0 0 0\n", i + 1, b->v[i].x, b->v[i].y, b->v[i].z);
  if (fclose(f) != 0) TL_ERROR(TL_ERR_IO, "error writing %s", path);
  double d0 = 0.0;
  for (size_t i = 0; i < b->n; ++i) d0 += 2.0 * b->r[i];
  d0 /= (double)b->n;
  snprintf(path, sizeof path, "%s/in.gouge_bar", dir);
  f = fopen(path, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write %s", path);
  const TlContactValue *v = tl_gouge_law_spec.values; /* k_n, gamma_n, k_t, mu */
  fprintf(f, "units si\natom_style sphere\nboundary p s p\ncomm_modify vel yes\nread_data gouge_bar.data\n"
             "pair_style gran/hertz/history %.17g %.17g %.17g NULL %.17g 1\npair_coeff * *\n"
             "neighbor %.17g bin\nneigh_modify delay 0 every 1 check yes\nfix integrate all nve/sphere\n"
             "timestep 1e-8\nthermo_style custom step atoms ke\nthermo %ld\nrun %ld\nrun %ld\n",
          v[0].value, v[2].value, v[1].value, v[3].value, 0.1 * d0, warmup > 0 ? warmup : 1, warmup, steps);
  if (fclose(f) != 0) TL_ERROR(TL_ERR_IO, "error writing %s", path);
  return TL_OK;
}

/* One LAMMPS run on `ranks` MPI ranks; µs per particle-step of its last run
 * from its own "Loop time of T on P procs for S steps with N atoms". */
static TlStatus run_lammps_once(const char *dir, int ranks, double *us)
{
  char cmd[8400];
  const char *root = geteuid() == 0 ? " --allow-run-as-root" : "";
  if (ranks > 1)
    snprintf(cmd, sizeof cmd, "cd '%s' && OMP_NUM_THREADS=1 mpirun -np %d --oversubscribe%s lmp -in in.gouge_bar -log "
             "gouge_bar.log -screen none -echo none -nocite > gouge_bar.out 2>&1", dir, ranks, root);
  else
    snprintf(cmd, sizeof cmd, "cd '%s' && OMP_NUM_THREADS=1 lmp -in in.gouge_bar -log gouge_bar.log -screen none "
             "-echo none -nocite > gouge_bar.out 2>&1", dir);
  if (system(cmd) != 0) TL_ERROR(TL_ERR_IO, "LAMMPS failed (see %s/gouge_bar.log and gouge_bar.out)", dir);
  char path[4200], line[1024];
  snprintf(path, sizeof path, "%s/gouge_bar.log", dir);
  FILE *f = fopen(path, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "LAMMPS wrote no %s", path);
  double t = NAN;
  long steps = 0, atoms = 0;
  int procs = 0;
  while (fgets(line, sizeof line, f)) {
    double tt;
    int pp;
    long ss, aa;
    if (sscanf(line, "Loop time of %lf on %d procs for %ld steps with %ld atoms", &tt, &pp, &ss, &aa) == 4)
      t = tt, procs = pp, steps = ss, atoms = aa;
  }
  fclose(f);
  if (!(t > 0.0) || steps <= 0 || atoms <= 0 || procs != ranks)
    TL_ERROR(TL_ERR_FORMAT, "%s: no Loop time line of a %d-rank run", path, ranks);
  *us = t * 1e6 / ((double)steps * (double)atoms);
  return TL_OK;
}

static TlStatus time_lammps(const char *dir, size_t n, int ranks, long steps, int repeat, double *median)
{
  double t[16];
  for (int k = 0; k < repeat; ++k) {
    TL_CHECK(run_lammps_once(dir, ranks, &t[k]));
    printf("lammps run %d/%d: ranks=%d particles=%zu steps=%ld us_per_particle_step=%.4f load=%.2f\n", k + 1, repeat,
           ranks, n, steps, t[k], tl_bench_load_average());
    fflush(stdout);
  }
  qsort(t, (size_t)repeat, sizeof *t, cmp_double);
  *median = t[repeat / 2];
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o;
  TL_CHECK(tl_options_create(argc, argv,
                             "The DEM part of seeds/000's gouge bar (a 5 MPa packing replicated, periodic in x and "
                             "z, Table 1's gran/hertz/history law) in Talus and LAMMPS: µs per particle-step on 1 and "
                             "2 cores and ratio = talus/lammps.",
                             &o));
  char root[4096], def_packing[4200];
  repo_root(root, sizeof root);
  snprintf(def_packing, sizeof def_packing, "%s/SelfTests/data/gouge_6d0.h5", root);
  const char *packing, *workdir;
  long steps, warmup, repeat, tmax;
  double reps[3];
  int nrep, peer;
  TL_CHECK(tl_options_get_string(o, "-packing", def_packing, "packing file (periodic_compress, with its cell)", &packing));
  TL_CHECK(tl_options_get_real_list_range(o, "-replicate", "4,8,4", 1, 1000, "",
                                          "copies of the cell along x, y (the bar axis), z", reps, 3, &nrep));
  TL_CHECK(tl_options_get_int(o, "-steps", 1000, 1, 100000000, "timed steps per run", &steps));
  TL_CHECK(tl_options_get_int(o, "-warmup", 100, 0, 100000000, "untimed steps before the timed ones", &warmup));
  TL_CHECK(tl_options_get_int(o, "-repeat", 3, 1, 16, "fresh runs per code and core count (median reported)", &repeat));
  TL_CHECK(tl_options_get_int(o, "-threads_max", 2, 1, 64, "core count of the second measurement (OpenMP threads, MPI ranks)", &tmax));
  TL_CHECK(tl_options_get_bool(o, "-peer", 1, "also run LAMMPS (lmp; mpirun for more than one rank)", &peer));
  TL_CHECK(tl_options_get_string(o, "-workdir", "results/gouge_vs_lammps", "folder of LAMMPS's data file, deck and logs", &workdir));
  TlStatus s = tl_options_finish(o, stdout);
  if (s == TL_OK && nrep != 3) s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "-replicate: %d values, expected 3 (nx,ny,nz)", nrep);
  int rep[3] = {0, 0, 0};
  for (int k = 0; k < 3 && s == TL_OK; ++k) {
    rep[k] = (int)reps[k];
    if ((double)rep[k] != reps[k])
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "-replicate value %g is not a whole number", reps[k]);
  }
  if (s != TL_OK) {
    tl_options_destroy(&o);
    return s;
  }
  if (peer && !have("lmp")) TL_ERROR(TL_ERR_IO, "lmp (Debian package lammps) is not installed; install it or run with -peer 0");
  if (peer && tmax > 1 && !have("mpirun"))
    TL_ERROR(TL_ERR_IO, "mpirun (Debian package openmpi-bin) is not installed; install it or run with -threads_max 1");
  const double wall0 = tl_wtime(), load0 = tl_bench_load_average();
  Bar b = {0, NULL, NULL, NULL, {0, 0, 0}, {0, 0, 0}};
  TL_CHECK(make_bar(packing, rep, &b));
  printf("gouge bar: %zu grains (%d x %d x %d copies of %s), %.4g x %.4g x %.4g m, periodic x and z; law "
         "gran/hertz/history 3.663e10 4.5249e10 0.2 NULL 0.5 1 = lammps_hertz + lammps_history; load %.2f\n",
         b.n, rep[0], rep[1], rep[2], packing, b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2], load0);
  if (peer) {
    TL_CHECK(tl_mkdir_p(workdir));
    TL_CHECK(write_lammps(&b, workdir, warmup, steps));
  }
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "particles", (long)b.n);
  const int cores[2] = {1, (int)tmax};
  for (int k = 0; k < (tmax > 1 ? 2 : 1); ++k) {
    double tt = NAN, tp = NAN;
    TL_CHECK(time_talus(&b, cores[k], warmup, steps, (int)repeat, &tt));
    char key[64];
    snprintf(key, sizeof key, "talus_%dc", cores[k]);
    tl_summary_real(&sum, key, tt);
    if (peer) {
      TL_CHECK(time_lammps(workdir, b.n, cores[k], steps, (int)repeat, &tp));
      snprintf(key, sizeof key, "lammps_%dc", cores[k]);
      tl_summary_real(&sum, key, tp);
      snprintf(key, sizeof key, "ratio_%dc", cores[k]);
      tl_summary_real(&sum, key, tt / tp);
    }
    printf("%d core%s: talus %.4f us/particle-step", cores[k], cores[k] > 1 ? "s" : "", tt);
    if (peer) printf(", lammps %.4f, ratio=talus/lammps=%.3f", tp, tt / tp);
    printf(" (load %.2f)\n", tl_bench_load_average());
  }
  const double load1 = tl_bench_load_average();
  if (isfinite(load0)) tl_summary_real(&sum, "load_before", load0);
  if (isfinite(load1)) tl_summary_real(&sum, "load_after", load1);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  TlStatus s_sum = tl_summary_print(&sum, stdout);
  bar_free(&b);
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
