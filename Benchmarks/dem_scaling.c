/* Weak scaling of the DEM kernel with the particle count: µs per
 * particle-step from 10^3 to 10^6 particles on the same kind of scene (a
 * jittered simple cubic lattice of polydisperse spheres, d in [0.9, 1.1],
 * spacing 1, in a fully periodic box, random velocities, linear
 * spring-dashpot with Coulomb friction, dt = 0.1 of the critical step).
 * The cost per particle-step should stay flat (O(N) contact detection and
 * force loop); the summary gives each figure and flatness = max / min, and
 * with -threads above 1 the speed-up over one thread at each size. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "talus.h"
#include "tl_parallel.h"
#include "tl_dem.h"

/* One fresh scene of about n_target particles: 20 warm-up steps, then
 * `steps` timed ones; *seconds and *cpu receive the timed wall and CPU time. */
static TlStatus one_scene(long n_target, long steps, int threads, double *seconds, double *cpu_seconds,
                          size_t *n_out, size_t *contacts, size_t *pairs)
{
  int m = (int)lround(cbrt((double)n_target));
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  int per[3] = {1, 1, 1};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), tl_v3(m, m, m), per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  int sp;
  TL_CHECK(tl_particles_add_species(P, "g", 1.0, 0.45, 0.55, &sp));
  TL_CHECK(tl_particles_reserve(P, (size_t)m * m * m));
  uint64_t rng = 99;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) {
        TlVec3 x = {i + 0.5 + 0.05 * (tl_random_uniform(&rng) - 0.5), j + 0.5 + 0.05 * (tl_random_uniform(&rng) - 0.5),
                    k + 0.5 + 0.05 * (tl_random_uniform(&rng) - 0.5)};
        TlVec3 v = {0.1 * (tl_random_uniform(&rng) - 0.5), 0.1 * (tl_random_uniform(&rng) - 0.5),
                    0.1 * (tl_random_uniform(&rng) - 0.5)};
        TL_CHECK(tl_dem_add_particle(dem, x, v, tl_species_sample_radius(&P->species_table[sp], &rng), sp, NULL));
      }
  const TlContactValue lv[] = {{"k_n", 2e5}, {"restitution", 0.0}, {"gamma_n", 50.0}, {"mu", 0.5}};
  const TlContactSpec spec = {"linear", "coulomb", NULL, NULL, lv, 4};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  tl_dem_set_threads(dem, threads);
  tl_dem_track_energy(dem, 0);
  tl_dem_track_orientation(dem, 0);
  double dtc;
  TL_CHECK(tl_dem_critical_timestep(dem, &dtc, NULL, NULL));
  TL_CHECK(tl_dem_set_timestep(dem, 0.1 * dtc, 0));
  TL_CHECK(tl_dem_setup(dem));
  TL_CHECK(tl_dem_step(dem, 20));
  struct timespec c0, c1;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c0);
  double t0 = tl_wtime();
  TL_CHECK(tl_dem_step(dem, steps));
  double el = tl_wtime() - t0;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c1);
  double cpu = (double)(c1.tv_sec - c0.tv_sec) + 1e-9 * (double)(c1.tv_nsec - c0.tv_nsec);
  TlDemStats st;
  tl_dem_stats(dem, &st);
  *n_out = P->n;
  *seconds = el;
  *cpu_seconds = cpu;
  *contacts = st.n_contacts;
  *pairs = st.n_pairs;
  tl_dem_destroy(&dem);
  return TL_OK;
}

/* Every size runs the same physical window (the same steps of the same kind
 * of scene); small sizes repeat it on fresh scenes until `work`
 * particle-steps are timed. */
static TlStatus one_size(long n_target, long steps, long work, int threads, double *us)
{
  double el = 0.0, cpu = 0.0;
  size_t n = 0, contacts = 0, pairs = 0;
  long reps = work / (n_target * steps);
  if (reps < 1) reps = 1;
  for (long r = 0; r < reps; ++r) {
    double e = 0.0, c = 0.0;
    TL_CHECK(one_scene(n_target, steps, threads, &e, &c, &n, &contacts, &pairs));
    el += e;
    cpu += c;
  }
  *us = el * 1e6 / ((double)steps * (double)reps * (double)n);
  printf("n=%zu steps=%ld scenes=%ld time=%.3f s us_per_particle_step=%.4f cpu_share=%.2f contacts=%zu pairs=%zu\n", n,
         steps, reps, el, *us, cpu / (el * threads), contacts, pairs);
  fflush(stdout);
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o;
  TL_CHECK(tl_options_create(argc, argv,
                             "µs per particle-step of the DEM kernel from 10^3 to 10^6 particles (should be flat).", &o));
  long nmin, nmax, work, threads, steps;
  TL_CHECK(tl_options_get_int(o, "-n_min", 1000, 8, 100000000, "smallest particle count", &nmin));
  TL_CHECK(tl_options_get_int(o, "-n_max", 1000000, 8, 100000000, "largest particle count (x10 per size)", &nmax));
  TL_CHECK(tl_options_get_int(o, "-work", 20000000, 1000, 100000000000L, "particle-steps timed per size (at least)", &work));
  TL_CHECK(tl_options_get_int(o, "-steps", 40, 1, 100000000, "timed steps of each scene (after 20 warm-up steps)", &steps));
  TL_CHECK(tl_options_get_int(o, "-threads", 1, 1, 1024,
                              "OpenMP threads; above 1, each size is also run on one thread and the speed-up printed",
                              &threads));
  TlStatus s = tl_options_finish(o, stdout);
  if (s != TL_OK) {
    tl_options_destroy(&o);
    return s;
  }
  double wall0 = tl_wtime();
  TlSummary sum;
  tl_summary_init(&sum);
  double lo = INFINITY, hi = 0.0;
  for (long n = nmin; n <= nmax; n *= 10) {
    double us = NAN;
    TL_CHECK(one_size(n, steps, work, (int)threads, &us));
    char key[64];
    snprintf(key, sizeof key, "us_%ld", n);
    tl_summary_real(&sum, key, us);
    if (threads > 1) {
      /* the same size on one thread: the gain of the others at this size */
      double us1 = NAN;
      TL_CHECK(one_size(n, steps, work, 1, &us1));
      printf("n=%ld: speed-up of %ld threads over 1: %.2f\n", n, threads, us1 / us);
      snprintf(key, sizeof key, "speedup_%ld", n);
      tl_summary_real(&sum, key, us1 / us);
    }
    lo = fmin(lo, us);
    hi = fmax(hi, us);
  }
  tl_summary_int(&sum, "threads", threads);
  tl_summary_real(&sum, "flatness", hi / lo);
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
