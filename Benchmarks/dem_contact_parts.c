/* The DEM contact loop with laws composed from parts, built in or not: CPU
 * time per particle-step of a dense periodic packing (a simple cubic lattice
 * at 2 % overlap, radii within ±0.5 %, small random velocities, one thread)
 * for the linear part alone and with Coulomb friction, Hertz with friction
 * and rolling, and a normal part defined here, outside the library (a spring
 * with a quadratic dashpot, registered from main, created by name).  With
 * its dashpot coefficient 0 the outside part computes the same forces as the
 * linear part with restitution 1, so the two runs follow the same
 * trajectory and their ratio is the cost of the path alone: any law goes
 * through the same chunk loop.  CPU time (not wall time) and the fastest of
 * -repeat timings, so that a busy machine disturbs the figures less; run the
 * same program of two builds alternately to compare the builds. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include "talus.h"
#include "tl_contact_part.h"
#include "tl_dem.h"
#include "tl_parallel.h"

/* ---- the outside part: f_n = k δ + c |dδ/dt| dδ/dt */
typedef struct {
  TlContactPart base;
  double k, c;
} Quadratic;

static const TlParam quadratic_params[] = {
    {"k_q", 1e4, 0.0, 1e300, "N/m", "spring stiffness", offsetof(Quadratic, k)},
    {"c_q", 0.0, 0.0, 1e300, "N s^2/m^2", "quadratic dashpot", offsetof(Quadratic, c)},
};

static TlStatus quadratic_setup(TlContactPart *part, const TlContactPart *normal)
{
  (void)normal;
  if (!(((Quadratic *)part)->k > 0.0)) TL_ERROR(TL_ERR_ARG, "quadratic_dashpot: k_q must be > 0");
  part->active = 1;
  return TL_OK;
}

static inline void quadratic_loop(const TlContactPart *part, TlContactChunk *c)
{
  const Quadratic *qd = (const Quadratic *)part;
  for (size_t q = 0; q < c->n; ++q) {
    const double delta = c->overlap[q];
    c->on[q] = delta > 0.0;
    if (!c->on[q]) continue;
    const double rate = -tl_v3_dot(c->vrel[q], c->normal[q]);
    c->fn[q] = qd->k * delta + qd->c * fabs(rate) * rate;
    c->scale[q] = 1.0;
    if (c->want_energy) c->energy[q] = 0.5 * qd->k * delta * delta;
  }
}
TL_CONTACT_PART_LOOPS(quadratic, quadratic_loop)

static double quadratic_stiffness(const TlContactPart *p, double reff, double overlap)
{
  (void)reff, (void)overlap;
  return ((const Quadratic *)p)->k;
}
static double quadratic_damping(const TlContactPart *p, double meff, double reff, double overlap)
{
  (void)p, (void)meff, (void)reff, (void)overlap;
  return 0.0;
}
static double quadratic_scale(const TlContactPart *p, double reff, double overlap)
{
  (void)p, (void)reff, (void)overlap;
  return 1.0;
}
static double quadratic_tangential(const TlContactPart *p) { return 2.0 / 7.0 * ((const Quadratic *)p)->k; }

static const TlContactPartOps quadratic_ops = {
    {"contact_normal", "quadratic_dashpot", "linear spring with a quadratic dashpot (defined in a benchmark)"},
    sizeof(Quadratic), 2, quadratic_params, quadratic_setup, quadratic_evaluate, quadratic_evaluate_hot,
    quadratic_stiffness, quadratic_damping, quadratic_scale, quadratic_tangential, NULL, NULL};

/* ---- the cases */
typedef struct {
  const char *name;
  TlContactSpec spec;
} Case;

static double cpu_now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static TlStatus one_case(const Case *cs, int m, long steps, long repeat, double *ns)
{
  TlContactLaw *law = NULL;
  TL_CHECK(tl_contact_law_build(&cs->spec, &law));
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  const double d = 1e-3, a = 0.98 * d;
  TlDomain dom;
  int per[3] = {1, 1, 1};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), tl_v3(m * a, m * a, m * a), per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  int sp;
  TL_CHECK(tl_particles_add_species(tl_dem_particles(dem), "g", 2500, 0.49 * d, 0.51 * d, &sp));
  uint64_t rng = 12345;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) {
        double u = tl_random_uniform(&rng);
        TL_CHECK(tl_dem_add_particle(dem, tl_v3((i + 0.5) * a, (j + 0.5) * a, (k + 0.5) * a),
                                     tl_v3(0.01 * (u - 0.5), 0.01 * u, -0.005), 0.5 * d * (1.0 + 0.01 * (u - 0.5)), sp,
                                     NULL));
      }
  tl_dem_set_threads(dem, 1);
  tl_dem_track_energy(dem, 0);
  TL_CHECK(tl_dem_set_timestep(dem, 1e-6, 0));
  TL_CHECK(tl_dem_setup(dem));
  TL_CHECK(tl_dem_step(dem, 50));
  double best = INFINITY;
  for (long r = 0; r < repeat; ++r) {
    double t0 = cpu_now();
    TL_CHECK(tl_dem_step(dem, steps));
    best = fmin(best, cpu_now() - t0);
  }
  *ns = 1e9 * best / ((double)steps * m * m * m);
  tl_dem_destroy(&dem);
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o;
  TL_CHECK(tl_options_create(argc, argv,
                             "CPU ns per particle-step of the DEM contact loop for built-in compositions of contact "
                             "parts and a normal part defined outside the library.", &o));
  long m, steps, repeat;
  TL_CHECK(tl_options_get_int(o, "-m", 24, 4, 1000, "lattice side (m^3 particles)", &m));
  TL_CHECK(tl_options_get_int(o, "-steps", 200, 1, 100000000, "steps per timing", &steps));
  TL_CHECK(tl_options_get_int(o, "-repeat", 7, 1, 1000, "timings per case (the fastest is kept)", &repeat));
  TlStatus s = tl_options_finish(o, stdout);
  tl_options_destroy(&o);
  if (s != TL_OK) return s;
  TL_CHECK(tl_contact_part_register(&quadratic_ops));
  const TlContactValue lin[] = {{"k_n", 1e4}, {"restitution", 0.3}, {"mu", 0.5}};
  const TlContactValue el[] = {{"k_n", 1e4}, {"restitution", 1.0}, {"mu", 0.5}};
  const TlContactValue hz[] = {{"E", 1e7}, {"mu", 0.5}, {"mu_roll", 0.05}};
  const TlContactValue qd[] = {{"k_q", 1e4}, {"c_q", 0.0}, {"mu", 0.5}};
  const Case cases[] = {
      {"linear", {"linear", NULL, NULL, NULL, lin, 2}},
      {"linear_coulomb", {"linear", "coulomb", NULL, NULL, lin, 3}},
      {"hertz_coulomb_rolling", {"hertz", "coulomb", "constant", NULL, hz, 3}},
      {"linear_e1", {"linear", NULL, NULL, NULL, el, 2}},
      {"outside_quadratic", {"quadratic_dashpot", NULL, NULL, NULL, qd, 2}},
      {"linear_e1_coulomb", {"linear", "coulomb", NULL, NULL, el, 3}},
      {"outside_quadratic_coulomb", {"quadratic_dashpot", "coulomb", NULL, NULL, qd, 3}},
  };
  const int n = (int)(sizeof cases / sizeof cases[0]);
  double ns[16];
  TlSummary sum;
  tl_summary_init(&sum);
  printf("%-28s %12s\n", "law", "ns/(p step)");
  for (int k = 0; k < n; ++k) {
    TL_CHECK(one_case(&cases[k], (int)m, steps, repeat, &ns[k]));
    printf("%-28s %12.2f\n", cases[k].name, ns[k]);
    tl_summary_real(&sum, cases[k].name, ns[k]);
  }
  printf("outside part / linear part (same forces): %.3f alone, %.3f with Coulomb friction\n", ns[4] / ns[3],
         ns[6] / ns[5]);
  tl_summary_real(&sum, "outside_over_builtin", ns[4] / ns[3]);
  tl_summary_real(&sum, "outside_over_builtin_coulomb", ns[6] / ns[5]);
  return tl_summary_print(&sum, stdout);
}

int main(int argc, char **argv)
{
  tl_parallel_prefer_passive_wait(argv); /* timings on a shared machine */
  TlStatus s = tl_initialize();
  if (s == TL_OK) s = run(argc, argv);
  return tl_driver_exit(s);
}
