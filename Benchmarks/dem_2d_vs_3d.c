/* What the two-dimensional world costs against the same packing run in 3-D
 * with its motion locked in the plane (tl_dem_set_dimension: a 2-D scene
 * should cost only what two dimensions use).
 *
 * A periodic packing of disks is prepared once: a random gas in a planar
 * cell (tl_dem_insert_gas), compressed to an area fraction -phi, relaxed.
 * From that state two worlds are built and sheared at the same rate ḣ for
 * -steps steps (linear springs with Coulomb friction and restitution 0.3):
 *   2-D   the disk world, planar cell (in-plane step and contact loop);
 *   3-D   the same particles as spheres in a 3-D cell periodic along z (height
 *         2.5 times the interaction range, the smallest the grid accepts),
 *         given the disks' masses and inertias, so that their motion stays in
 *         the plane by symmetry: the same run, computed in three dimensions.
 * Each world is timed -repeat times from the same state, the two worlds
 * alternating (a loaded machine's drift does not bias the ratio), the
 * fastest kept;
 * the two runs' final stresses (2-D per unit thickness, 3-D times the height)
 * are compared to show that they are the same computation.
 *
 * Last line: summary: n=... steps=... t2d_ns=... t3d_ns=... (per
 * particle-step) ratio=t3d/t2d stress_difference=... */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_bench.h"
#include "tl_bench.h"
#include "tl_dem.h"

typedef struct {
  long n, steps, repeat, seed;
  int threads;
  double phi, shear_rate;
} Settings;

typedef struct {
  size_t n;
  TlVec3 *x;
  double *radius;
  TlMat3 h;
  double rmax;
} Packing;

static const double R_MIN = 0.008, R_MAX = 0.012, RHO = 2500.0, K_N = 1e5, DT = 2e-4;

static TlStatus add_law(TlDem *dem)
{
  const TlContactValue v[] = {{"k_n", K_N}, {"restitution", 0.3}, {"mu", 0.4}};
  const TlContactSpec spec = {"linear", "coulomb", NULL, NULL, v, 3};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  return tl_dem_add_law(dem, law, NULL);
}

/* A world of dimension dim from the packing (or, pk->n == 0, a fresh gas). */
static TlStatus world(const Settings *s, int dim, const Packing *pk, TlDem **out)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TL_CHECK(tl_dem_set_dimension(dem, dim));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "disks", RHO, R_MIN, R_MAX, &sp));
  TlDomain D;
  TlMat3 h = pk->h;
  if (dim == 2) {
    TL_CHECK(tl_domain_init_cell_2d(&D, tl_v3(0, 0, 0), h));
  } else {
    h.m[2][2] = 2.5 * (2.0 * R_MAX + 0.2 * (R_MIN + R_MAX)); /* twice the range plus margin */
    TL_CHECK(tl_domain_init_cell(&D, tl_v3(0, 0, 0), h));
  }
  TL_CHECK(tl_dem_set_domain(dem, &D));
  if (pk->n) {
    TL_CHECK(tl_particles_reserve(P, pk->n));
    for (size_t i = 0; i < pk->n; ++i) TL_CHECK(tl_dem_add_particle(dem, pk->x[i], tl_v3(0, 0, 0), pk->radius[i], sp, NULL));
  } else {
    TL_CHECK(tl_dem_insert_gas(dem, sp, (size_t)s->n, (uint64_t)s->seed, 100000, NULL));
  }
  if (dim == 3)
    for (size_t i = 0; i < P->n; ++i) {
      P->mass[i] = RHO * TL_PI * P->radius[i] * P->radius[i];
      P->inv_mass[i] = 1.0 / P->mass[i];
    }
  TL_CHECK(add_law(dem));
  tl_dem_set_threads(dem, s->threads);
  tl_dem_track_energy(dem, 0);
  tl_dem_track_orientation(dem, 0);
  TL_CHECK(tl_dem_set_timestep(dem, DT, 0));
  TL_CHECK(tl_dem_setup(dem));
  if (dim == 3)
    for (size_t i = 0; i < P->n; ++i) P->inv_inertia[i] = 1.0 / (0.5 * P->mass[i] * P->radius[i] * P->radius[i]);
  *out = dem;
  return TL_OK;
}

static TlStatus set_rate(TlDem *dem, TlMat3 L)
{
  TlDomain *D = tl_dem_domain(dem);
  TlMat3 hd = tl_m3_mul(L, D->h);
  hd.m[0][2] = hd.m[1][2] = hd.m[2][0] = hd.m[2][1] = hd.m[2][2] = 0.0;
  return tl_domain_set_h_rate(D, hd);
}

static TlStatus prepare(const Settings *s, Packing *pk)
{
  /* a cell holding n disks at area fraction 0.42, sheared by 0.1 from the start */
  const double mean_area = TL_PI * (R_MIN * R_MIN + R_MIN * R_MAX + R_MAX * R_MAX) / 3.0;
  const double L = sqrt((double)s->n * mean_area / 0.42);
  pk->h = tl_m3_identity();
  pk->h.m[0][0] = pk->h.m[1][1] = L;
  pk->h.m[0][1] = 0.1 * L;
  pk->n = 0;
  TlDem *dem;
  TL_CHECK(world(s, 2, pk, &dem));
  TlParticles *P = tl_dem_particles(dem);
  double area = 0.0;
  for (size_t i = 0; i < P->n; ++i) area += TL_PI * P->radius[i] * P->radius[i];
  const double phi0 = area / tl_domain_area(tl_dem_domain(dem));
  const long steps = 4000;
  TlMat3 c = tl_m3_zero();
  /* constant ḣ: h shrinks linearly, by sqrt(phi0 / phi) per direction */
  c.m[0][0] = c.m[1][1] = -(1.0 - sqrt(phi0 / s->phi)) / (steps * DT);
  TL_CHECK(set_rate(dem, c));
  TL_CHECK(tl_dem_step(dem, steps));
  TL_CHECK(set_rate(dem, tl_m3_zero()));
  TL_CHECK(tl_dem_step(dem, 2000));
  pk->n = P->n;
  TL_CHECK(tl_calloc(&pk->x, P->n, sizeof *pk->x));
  TL_CHECK(tl_calloc(&pk->radius, P->n, sizeof *pk->radius));
  memcpy(pk->x, P->x, P->n * sizeof *P->x);
  memcpy(pk->radius, P->radius, P->n * sizeof *P->radius);
  pk->h = tl_dem_domain(dem)->h;
  double z;
  TL_CHECK(tl_dem_coordination(dem, &z, NULL));
  printf("packing: %zu disks, area fraction %.3f, coordination %.2f, cell %.4g m\n", P->n,
         area / tl_domain_area(tl_dem_domain(dem)), z, pk->h.m[0][0]);
  tl_dem_destroy(&dem);
  return TL_OK;
}

/* One sheared run of dimension dim from the packing: its time, the final
 * stress per unit thickness in *sigma and the touching contacts. */
static TlStatus timed(const Settings *s, int dim, const Packing *pk, double *seconds, TlMat3 *sigma, double *contacts)
{
  TlDem *dem;
  TL_CHECK(world(s, dim, pk, &dem));
  TlMat3 shear = tl_m3_zero();
  shear.m[0][1] = s->shear_rate;
  TL_CHECK(set_rate(dem, shear));
  double t0 = tl_wtime();
  TL_CHECK(tl_dem_step(dem, s->steps));
  *seconds = tl_wtime() - t0;
  TL_CHECK(tl_dem_stress(dem, sigma, NULL));
  if (dim == 3) *sigma = tl_m3_scale(*sigma, tl_dem_domain(dem)->h.m[2][2]);
  TlDemStats st;
  tl_dem_stats(dem, &st);
  *contacts = (double)st.n_contacts;
  tl_dem_destroy(&dem);
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  double wall0 = tl_wtime();
  TlOptions *o;
  Settings s;
  TL_CHECK(tl_options_create(argc, argv,
                             "The 2-D (disk) world against the same packing run in 3-D with its motion locked in the "
                             "plane: time per particle-step of a sheared periodic cell, and their ratio.",
                             &o));
  TL_CHECK(tl_options_get_int(o, "-n", 4000, 10, 10000000, "disks", &s.n));
  TL_CHECK(tl_options_get_int(o, "-steps", 2000, 1, 100000000, "timed steps (dt = 2e-4 s)", &s.steps));
  TL_CHECK(tl_options_get_int(o, "-repeat", 3, 1, 1000, "timed runs of each world (alternating), the fastest kept", &s.repeat));
  TL_CHECK(tl_options_get_int(o, "-seed", 1, 0, 1000000000, "random seed of the gas", &s.seed));
  long th;
  TL_CHECK(tl_options_get_int(o, "-threads", 1, 0, 1024, "OpenMP threads (0: the OpenMP default)", &th));
  s.threads = (int)th;
  TL_CHECK(tl_options_get_real(o, "-phi", 0.84, 0.55, 0.9, "", "area fraction of the packing", &s.phi));
  TL_CHECK(tl_options_get_real(o, "-shear_rate", 0.5, 0.0, 100.0, "1/s", "shear rate of the timed runs (h_xy rate / h_yy)",
                               &s.shear_rate));
  TL_CHECK(tl_options_finish(o, stdout));
  Packing pk = {0};
  TL_CHECK(prepare(&s, &pk));
  /* the two worlds alternate, so that a change of the machine's load
   * between them does not bias the ratio; the fastest run of each is kept */
  double t2 = INFINITY, t3 = INFINITY, c2, c3;
  TlMat3 s2, s3;
  for (long r = 0; r < s.repeat; ++r) {
    double t;
    TL_CHECK(timed(&s, 2, &pk, &t, &s2, &c2));
    t2 = fmin(t2, t);
    TL_CHECK(timed(&s, 3, &pk, &t, &s3, &c3));
    t3 = fmin(t3, t);
  }
  double d = 0.0, nrm = 0.0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      d = fmax(d, fabs(s2.m[i][j] - s3.m[i][j]));
      nrm = fmax(nrm, fabs(s2.m[i][j]));
    }
  const double ps = (double)pk.n * (double)s.steps;
  printf("2-D: %.3f s, %.1f ns per particle-step, %.0f contacts\n", t2, 1e9 * t2 / ps, c2);
  printf("3-D locked: %.3f s, %.1f ns per particle-step, %.0f contacts\n", t3, 1e9 * t3 / ps, c3);
  printf("ratio 3-D / 2-D = %.3f; final stresses differ by %.2e of %.4g N/m\n", t3 / t2, d / nrm, nrm);
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "n", (long)pk.n);
  tl_summary_int(&sum, "steps", s.steps);
  tl_summary_int(&sum, "threads", s.threads);
  tl_summary_real(&sum, "t2d_ns", 1e9 * t2 / ps);
  tl_summary_real(&sum, "t3d_ns", 1e9 * t3 / ps);
  tl_summary_real(&sum, "ratio", t3 / t2);
  tl_summary_real(&sum, "stress_difference", d / nrm);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  TlStatus s_sum = tl_summary_print(&sum, stdout);
  tl_free(&pk.x);
  tl_free(&pk.radius);
  tl_options_destroy(&o);
  return s_sum;
}

int main(int argc, char **argv) { return tl_bench_main(argc, argv, run); }
