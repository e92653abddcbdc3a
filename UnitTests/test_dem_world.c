/* The world's bookkeeping: laws chosen per species pair, a bonded pair
 * acting in tension (harmonic oscillation at sqrt(k/m_eff)), insertion and
 * removal during a run with contacts still equal to brute force, adhesion
 * and rolling resistance acting in the right sense, and a frictionless
 * scene allocating no rotation and no history. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

static TlContactLaw *linear(double kn, double e, double mu)
{
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", kn, "restitution", e, "mu", mu, NULL), TL_OK);
  return law;
}

/* Species 0 and 1 meet through law 1 (stiffer); 0-0 through law 0. */
static void test_pair_laws(void)
{
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int a, b, l0, l1;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", 2500, 0.01, 0.01, &a), TL_OK);
  TL_TEST_STATUS(tl_particles_add_species(P, "b", 2500, 0.01, 0.01, &b), TL_OK);
  double ov = 1e-4;
  /* a-a pair and a-b pair, far from each other, same overlap */
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0, 0, 0), tl_v3(0, 0, 0), 0.01, a, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.02 - ov, 0, 0), tl_v3(0, 0, 0), 0.01, a, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(1, 0, 0), tl_v3(0, 0, 0), 0.01, a, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(1.02 - ov, 0, 0), tl_v3(0, 0, 0), 0.01, b, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, linear(1e4, 1.0, 0.0), &l0), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, linear(3e4, 1.0, 0.3), &l1), TL_OK);
  TL_TEST_STATUS(tl_dem_set_pair_law(dem, a, b, l1), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 1e-6, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TL_TEST_ASSERT(P->w != NULL, "a frictional law in the scene must allocate rotation");
  double f[4];
  for (size_t i = 0; i < P->n; ++i) f[P->id[i]] = P->f[i].x;
  TL_TEST_REL(f[0], -1e4 * ov, 1e-9);
  TL_TEST_REL(f[2], -3e4 * ov, 1e-9);
  TL_TEST_REL(f[1], 1e4 * ov, 1e-9);
  TL_TEST_REL(f[3], 3e4 * ov, 1e-9);
  tl_dem_destroy(&dem);
}

/* A bonded pair started stretched oscillates harmonically through zero
 * overlap: tension and compression alike. */
static void test_bond(void)
{
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int a;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", 2500, 0.01, 0.01, &a), TL_OK);
  double stretch = 2e-4, kn = 1e5;
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0, 0, 0), tl_v3(0, 0, 0), 0.01, a, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.02 + stretch, 0, 0), tl_v3(0, 0, 0), 0.01, a, NULL), TL_OK);
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "bonded_linear", "k_n", kn, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_bond(dem, P->id[0], P->id[1]), TL_OK);
  double meff = 0.5 * P->mass[0], period = 2 * TL_PI * sqrt(meff / kn);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, period / 2000, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  double gap_min = INFINITY, gap_max = -INFINITY, t_min = 0;
  for (int s = 0; s < 2000; ++s) {
    TL_TEST_STATUS(tl_dem_step(dem, 1), TL_OK);
    double gap = P->x[1].x - P->x[0].x - 0.02;
    if (P->id[0] == 1) gap = -gap - 0.04;
    if (gap < gap_min) {
      gap_min = gap;
      t_min = tl_dem_time(dem);
    }
    gap_max = fmax(gap_max, gap);
  }
  printf("bond: gap from %.4e to %.4e m (expected +-%.1e), closest at t = %.5e s (half period %.5e s)\n", gap_max,
         gap_min, stretch, t_min, 0.5 * period);
  TL_TEST_REL(gap_min, -stretch, 1e-3);
  TL_TEST_CLOSE(t_min / (0.5 * period), 1.0, 2e-3);
  TlMat3 sc;
  TL_TEST_STATUS(tl_dem_stress(dem, &sc, NULL), TL_OK);
  tl_dem_destroy(&dem);
}

static int cmp_pair(const void *a, const void *b)
{
  const uint64_t *p = a, *q = b;
  return *p < *q ? -1 : *p > *q;
}
typedef struct {
  size_t n;
  uint64_t *key;
  const int64_t *id;
} Keys;
static void collect(void *ctx, size_t i, size_t j, TlVec3 f, TlVec3 b, TlVec3 cp)
{
  Keys *k = ctx;
  uint64_t a = (uint64_t)k->id[i], c = (uint64_t)k->id[j];
  k->key[k->n++] = a < c ? (a << 32) | c : (c << 32) | a;
}

/* Particles inserted and removed during a run: contacts stay exact. */
static void test_insert_remove(void)
{
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  int per[3] = {1, 1, 0};
  TL_TEST_STATUS(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), tl_v3(0.2, 0.2, 0.4), per), TL_OK);
  TL_TEST_STATUS(tl_dem_set_domain(dem, &dom), TL_OK);
  int a;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", 2500, 0.005, 0.008, &a), TL_OK);
  uint64_t s = 3;
  for (int k = 0; k < 400; ++k) {
    TlVec3 x = {0.2 * tl_random_uniform(&s), 0.2 * tl_random_uniform(&s), 0.01 + 0.3 * tl_random_uniform(&s)};
    int ok = 1;
    for (size_t i = 0; i < P->n && ok; ++i) ok = tl_v3_norm(tl_domain_branch(&dom, P->x[i], x)) > 0.017;
    if (ok) TL_TEST_STATUS(tl_dem_add_particle(dem, x, tl_v3(0, 0, 0), tl_species_sample_radius(&P->species_table[a], &s), a, NULL), TL_OK);
  }
  TL_TEST_STATUS(tl_dem_add_law(dem, linear(2e3, 0.5, 0.4), NULL), TL_OK);
  TlWall *w;
  TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &w), TL_OK);
  TL_TEST_STATUS(tl_dem_add_wall(dem, w, 0), TL_OK);
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 1e-4, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  Keys K = {0, malloc(64 * 1000 * sizeof(uint64_t)), NULL};
  int mismatches = 0;
  size_t most = 0;
  for (int round = 0; round < 20; ++round) {
    TL_TEST_STATUS(tl_dem_step(dem, 150), TL_OK);
    /* remove three particles, insert two */
    for (int q = 0; q < 3 && P->n > 10; ++q)
      TL_TEST_STATUS(tl_dem_remove_particle(dem, (size_t)(tl_random_uniform(&s) * (double)P->n)), TL_OK);
    for (int q = 0; q < 2; ++q)
      TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.2 * tl_random_uniform(&s), 0.2 * tl_random_uniform(&s), 0.38),
                                         tl_v3(0, 0, -0.5), 0.006, a, NULL), TL_OK);
    TL_TEST_STATUS(tl_dem_step(dem, 30), TL_OK);
    K.n = 0;
    K.id = P->id;
    TL_TEST_STATUS(tl_dem_visit_contacts(dem, collect, &K), TL_OK);
    TlPair *b = NULL;
    size_t cb = 0, nb = 0;
    TL_TEST_STATUS(tl_hgrid_pairs_brute_force(tl_dem_domain(dem), P->n, P->x, P->radius, 0.0, NULL, &b, &cb, &nb), TL_OK);
    uint64_t *bk = malloc((nb + 1) * sizeof *bk);
    for (size_t k = 0; k < nb; ++k) {
      uint64_t x = (uint64_t)P->id[b[k].i], y = (uint64_t)P->id[b[k].j];
      bk[k] = x < y ? (x << 32) | y : (y << 32) | x;
    }
    qsort(K.key, K.n, sizeof *K.key, cmp_pair);
    qsort(bk, nb, sizeof *bk, cmp_pair);
    if (!(K.n == nb && (nb == 0 || memcmp(K.key, bk, nb * sizeof *bk) == 0))) ++mismatches;
    most = nb > most ? nb : most;
    free(bk);
    free(b);
    TL_TEST_STATUS(tl_particles_check_finite(P), TL_OK);
  }
  printf("insert/remove: %zu particles at the end, up to %zu contacts, %d mismatches over 20 rounds\n", P->n, most,
         mismatches);
  TL_TEST_ASSERT(mismatches == 0, "contacts differ from brute force after insertion/removal in %d rounds", mismatches);
  TL_TEST_ASSERT(most > 50, "too few contacts (%zu) to mean anything", most);
  free(K.key);
  tl_dem_destroy(&dem);
}

static void test_adhesion_rolling(void)
{
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e4, "adhesion_force", 0.5, "mu_roll", 0.1, "mu", 0.5, NULL), TL_OK);
  TL_TEST_ASSERT(law->needs_rotation && law->history_doubles == 3, "rolling and friction need rotation and history");
  double h[3] = {0, 0, 0};
  TlContactGeometry g;
  memset(&g, 0, sizeof g);
  g.normal = tl_v3(1, 0, 0);
  g.overlap = 1e-5; /* k δ = 0.1 N < adhesion 0.5 N: net attraction */
  g.meff = 0.01;
  g.reff = 0.005;
  g.history = h;
  g.spin_rel = tl_v3(0, 0, 3.0); /* j spins about z relative to i: rolling about z */
  TlContactResult r;
  TL_TEST_STATUS(tl_contact_law_evaluate_one(law, &g, 1e-5, &r), TL_OK);
  TL_TEST_REL(r.force.x, 0.4, 1e-12); /* force on i towards j (+x): attraction */
  TL_TEST_CLOSE(tl_v3_norm(r.couple), 0.0, 1e-15); /* net tension: no rolling couple */
  g.overlap = 2e-4; /* k δ = 2 N: 1.5 N of repulsion */
  TL_TEST_STATUS(tl_contact_law_evaluate_one(law, &g, 1e-5, &r), TL_OK);
  TL_TEST_REL(r.force.x, -1.5, 1e-12);
  /* the couple on i acts with ω_j - ω_i: it opposes i's rolling relative to j */
  TL_TEST_REL(r.couple.z, 0.1 * 0.005 * 1.5, 1e-12);
  TL_TEST_ASSERT(tl_v3_dot(r.couple, tl_v3_neg(g.spin_rel)) < 0.0, "rolling couple does not oppose the relative spin");
  tl_contact_law_destroy(&law);
  /* a frictionless scene pays for nothing it does not use */
  TlContactLaw *plain = linear(1e4, 0.8, 0.0);
  TL_TEST_ASSERT(!plain->needs_rotation && plain->history_doubles == 0, "frictionless law declares rotation %d, history %zu",
                 plain->needs_rotation, plain->history_doubles);
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  int a;
  TL_TEST_STATUS(tl_particles_add_species(tl_dem_particles(dem), "a", 2500, 0.01, 0.01, &a), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0, 0, 0), tl_v3(0, 0, 0), 0.01, a, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, plain, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 1e-6, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TL_TEST_ASSERT(tl_dem_particles(dem)->w == NULL && tl_dem_particles(dem)->q == NULL,
                 "a frictionless scene allocated rotational state");
  tl_dem_destroy(&dem);
}

/* A bonded chain moving and oscillating across many neighbour-list
 * rebuilds and renumberings: no pair may appear twice (once as a bond, once
 * as a plain contact). */
static void test_bond_rebuilds(void)
{
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int a;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", 2500, 0.01, 0.01, &a), TL_OK);
  /* a loose particle (id 0) that will be removed, moving the last chain
   * particle into its slot */
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0, 1.0, 0), tl_v3(0, 0, 0), 0.01, a, NULL), TL_OK);
  for (int k = 0; k < 8; ++k)
    TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.0199 * k, 0, 0), tl_v3(1.0, 0.05 * (k % 3), k == 0 ? 0.3 : 0.0),
                                       0.01, a, NULL), TL_OK);
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "bonded_linear", "k_n", 1e5, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  for (int k = 1; k < 8; ++k) TL_TEST_STATUS(tl_dem_add_bond(dem, k, k + 1), TL_OK);
  TL_TEST_STATUS(tl_dem_set_skin(dem, 0.002), TL_OK);
  tl_dem_set_sort_interval(dem, 0); /* removal alone renumbers: the bond hash must follow */
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 2e-6, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  Keys K = {0, malloc(256 * sizeof(uint64_t)), NULL};
  int dups = 0;
  for (int r = 0; r < 100; ++r) {
    TL_TEST_STATUS(tl_dem_step(dem, 20), TL_OK);
    if (r == 10) {
      size_t loose;
      TL_TEST_STATUS(tl_particles_find(P, 0, &loose), TL_OK);
      TL_TEST_STATUS(tl_dem_remove_particle(dem, loose), TL_OK);
    }
    K.n = 0;
    K.id = P->id;
    TL_TEST_STATUS(tl_dem_visit_contacts(dem, collect, &K), TL_OK);
    qsort(K.key, K.n, sizeof *K.key, cmp_pair);
    for (size_t q = 1; q < K.n; ++q) dups += K.key[q] == K.key[q - 1];
  }
  TlDemStats st;
  tl_dem_stats(dem, &st);
  printf("bonded chain: %ld rebuilds in %ld steps, %d duplicated pairs\n", st.rebuilds, st.steps, dups);
  TL_TEST_ASSERT(st.rebuilds > 50, "only %ld rebuilds", st.rebuilds);
  TL_TEST_ASSERT(dups == 0, "%d pairs counted both as bond and as contact", dups);
  free(K.key);
  tl_dem_destroy(&dem);
}

/* The thread count does not change the answers, bit for bit: the contact
 * loop shares the list so that every particle's forces are summed in list
 * order whatever the thread count (owners and deferred contributions), and
 * the energy sums go chunk by chunk.  A lattice large enough for the
 * threaded contact loop (more than 8192 pairs), with rotation, energy
 * tracking and, in the second scene (9261 particles: threaded integration
 * too), a pair of species with two laws and bonds.  The third and fourth
 * scenes add plane walls (a floor and a descending lid, evaluated by
 * particle ranges): without bonds they share the contact loop's region,
 * with bonds they have one of their own; the walls' forces, torques and
 * energies must not change either. */
typedef struct {
  TlVec3 x[9261], v[9261], w[9261], f[9261], t[9261];
  TlDemEnergy e;
  TlVec3 wall_f[2], wall_t[2];
  double wall_e[2][3];
  size_t n, contacts, wall_contacts;
} ThreadRun;

static TlStatus lattice_run(int threads, int scene, long steps, ThreadRun *out)
{
  const int mixed = scene & 1, walls = scene >= 2;
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  /* the second scene above 8192 particles: threaded integration and body
   * forces in the contact loop's region */
  int per[3] = {1, 1, !walls}, m = mixed || walls ? 21 : 16;
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), tl_v3(m, m, m), per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  int a, b;
  TL_CHECK(tl_particles_add_species(P, "a", 1.0, 0.45, 0.55, &a));
  TL_CHECK(tl_particles_add_species(P, "b", 2.0, 0.45, 0.55, &b));
  uint64_t s = 17;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) {
        int sp = mixed && (i + j + k) % 3 == 0 ? b : a;
        TL_CHECK(tl_dem_add_particle(dem, tl_v3(i + 0.5, j + 0.5, k + 0.5),
                                     tl_v3(0.1 * (tl_random_uniform(&s) - 0.5), 0.1 * (tl_random_uniform(&s) - 0.5),
                                           mixed ? 0.1 * (tl_random_uniform(&s) - 0.5) : 0.0),
                                     tl_species_sample_radius(&P->species_table[sp], &s), sp, NULL));
      }
  TlContactLaw *law;
  TL_CHECK(tl_test_law(&law, "linear", "k_n", 2e5, "restitution", 0.7, "mu", 0.5, NULL));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  if (mixed) {
    int l2;
    TL_CHECK(tl_test_law(&law, "hertz", "E", 1e7, "tsuji_restitution", 0.5, "mu", 0.3, NULL));
    TL_CHECK(tl_dem_add_law(dem, law, &l2));
    TL_CHECK(tl_dem_set_pair_law(dem, a, b, l2));
    /* bonds along a diagonal of the lattice (ids of neighbours in x) */
    for (int q = 0; q < 40; ++q) TL_CHECK(tl_dem_add_bond(dem, (int64_t)q * 97, (int64_t)q * 97 + m * m));
  }
  if (walls) {
    /* the bottom layer rests on the floor, the top one meets the lid */
    TlWall *w;
    TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0.05), tl_v3(0, 0, 1), &w));
    TL_CHECK(tl_dem_add_wall(dem, w, 0));
    TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, m - 0.05), tl_v3(0, 0, -1), &w));
    TL_CHECK(tl_wall_plane_set_velocity(w, tl_v3(0, 0, -0.5)));
    TL_CHECK(tl_dem_add_wall(dem, w, 0));
    tl_dem_set_gravity(dem, tl_v3(0, 0, -1));
  }
  tl_dem_set_threads(dem, threads);
  TL_CHECK(tl_dem_set_timestep(dem, 1e-4, 0));
  TL_CHECK(tl_dem_setup(dem));
  TL_CHECK(tl_dem_step(dem, steps));
  out->wall_contacts = 0;
  for (size_t k = 0; k < tl_dem_n_walls(dem) && k < 2; ++k) {
    const TlWall *w = tl_dem_wall(dem, k);
    out->wall_f[k] = w->force;
    out->wall_t[k] = w->torque;
    out->wall_e[k][0] = w->elastic_energy;
    out->wall_e[k][1] = w->contact_work;
    out->wall_e[k][2] = w->work;
    out->wall_contacts += w->n_contacts;
  }
  for (size_t i = 0; i < P->n; ++i) {
    size_t q = (size_t)P->id[i];
    out->x[q] = P->x[i];
    out->v[q] = P->v[i];
    out->w[q] = P->w[i];
    out->f[q] = P->f[i];
    out->t[q] = P->torque[i];
  }
  TL_CHECK(tl_dem_energy(dem, &out->e));
  TlDemStats st;
  tl_dem_stats(dem, &st);
  out->contacts = st.n_contacts;
  out->n = P->n;
  tl_dem_destroy(&dem);
  return TL_OK;
}

static void test_threads(void)
{
  static ThreadRun r1, rt;
  static const char *names[4] = {"one law", "two laws and bonds", "one law, two planes", "two laws, bonds, two planes"};
  for (int scene = 0; scene < 4; ++scene) {
    TL_TEST_STATUS(lattice_run(1, scene, 60, &r1), TL_OK);
    for (int threads = 2; threads <= 3; ++threads) {
      memset(&rt, 0, sizeof rt);
      TL_TEST_STATUS(lattice_run(threads, scene, 60, &rt), TL_OK);
      size_t bad = 0;
      double dx = 0.0, dw = 0.0;
      for (size_t i = 0; i < r1.n; ++i) {
        int same = !memcmp(&r1.x[i], &rt.x[i], sizeof r1.x[i]) && !memcmp(&r1.v[i], &rt.v[i], sizeof r1.v[i]) &&
                   !memcmp(&r1.w[i], &rt.w[i], sizeof r1.w[i]) && !memcmp(&r1.f[i], &rt.f[i], sizeof r1.f[i]) &&
                   !memcmp(&r1.t[i], &rt.t[i], sizeof r1.t[i]);
        bad += !same;
        dx = fmax(dx, tl_v3_norm(tl_v3_sub(r1.x[i], rt.x[i])));
        dw = fmax(dw, tl_v3_norm(tl_v3_sub(r1.w[i], rt.w[i])));
      }
      const int same_e = !memcmp(&r1.e, &rt.e, sizeof r1.e);
      const int same_w = !memcmp(r1.wall_f, rt.wall_f, sizeof r1.wall_f) &&
                         !memcmp(r1.wall_t, rt.wall_t, sizeof r1.wall_t) &&
                         !memcmp(r1.wall_e, rt.wall_e, sizeof r1.wall_e) && r1.wall_contacts == rt.wall_contacts;
      printf("1 vs %d threads, %s, %zu particles, %zu contacts, %zu wall contacts, 60 steps: %zu particles differ in "
             "x, v, w, f or torque (largest dx %.2e, dw %.2e), energies %s, walls %s\n",
             threads, names[scene], r1.n, r1.contacts, r1.wall_contacts, bad, dx, dw, same_e ? "identical" : "differ",
             same_w ? "identical" : "differ");
      TL_TEST_ASSERT(r1.n == rt.n && r1.contacts > 1000 && bad == 0 && same_e && same_w,
                     "%d threads change the answers of scene '%s': %zu particles differ (dx %g, dw %g), energies %s, "
                     "walls %s", threads, names[scene], bad, dx, dw, same_e ? "same" : "differ",
                     same_w ? "same" : "differ");
      if (scene >= 2)
        TL_TEST_ASSERT(r1.wall_contacts > 300 && r1.wall_f[0].z < 0.0 && r1.wall_f[1].z > 0.0,
                       "scene '%s': %zu wall contacts, floor force z %g, lid force z %g: the walls do not act",
                       names[scene], r1.wall_contacts, r1.wall_f[0].z, r1.wall_f[1].z);
    }
  }
}

/* Spins can be given before set-up, on a law that needs no rotation, and
 * the force array holds gravity (the header says so): two free spheres
 * apart, no contact, so f = m g exactly and the spins stay. */
static void test_spin_before_setup(void)
{
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int a;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", 2500.0, 0.01, 0.01, &a), TL_OK);
  size_t i0, i1;
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.2, 0.5, 0.5), tl_v3(0, 0, 0), 0.01, a, &i0), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.8, 0.5, 0.5), tl_v3(0, 0, 0), 0.01, a, &i1), TL_OK);
  TL_TEST_STATUS(tl_dem_set_spin(dem, i0, tl_v3(1.0, -2.0, 3.0)), TL_OK);
  TL_TEST_STATUS(tl_dem_set_spin(dem, 7, tl_v3(0, 0, 0)), TL_ERR_ARG);
  TL_TEST_STATUS(tl_dem_set_spin(dem, i1, tl_v3(NAN, 0, 0)), TL_ERR_ARG);
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e4, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  const TlVec3 g = {0.0, 0.0, -9.81};
  tl_dem_set_gravity(dem, g);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 1e-5, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TL_TEST_STATUS(tl_dem_step(dem, 10), TL_OK);
  size_t k0, k1;
  TL_TEST_STATUS(tl_particles_find(P, 0, &k0), TL_OK);
  TL_TEST_STATUS(tl_particles_find(P, 1, &k1), TL_OK);
  TL_TEST_ASSERT(P->w && P->w[k0].x == 1.0 && P->w[k0].y == -2.0 && P->w[k0].z == 3.0 && P->w[k1].x == 0.0,
                 "spin set before set-up lost: (%g, %g, %g)", P->w ? P->w[k0].x : NAN, P->w ? P->w[k0].y : NAN,
                 P->w ? P->w[k0].z : NAN);
  const TlVec3 mg = tl_v3_scale(g, P->mass[k0]);
  TL_TEST_ASSERT(P->f[k0].x == mg.x && P->f[k0].y == mg.y && P->f[k0].z == mg.z,
                 "force array (%g, %g, %g) is not m g = (%g, %g, %g) without contacts", P->f[k0].x, P->f[k0].y,
                 P->f[k0].z, mg.x, mg.y, mg.z);
  /* and after set-up */
  TL_TEST_STATUS(tl_dem_set_spin(dem, k1, tl_v3(0.0, 0.0, -4.0)), TL_OK);
  TL_TEST_STATUS(tl_dem_step(dem, 1), TL_OK);
  TL_TEST_STATUS(tl_particles_find(P, 1, &k1), TL_OK);
  TL_TEST_ASSERT(P->w[k1].z == -4.0, "spin set after set-up lost: %g", P->w[k1].z);
  tl_dem_destroy(&dem);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_pair_laws();
  test_bond();
  test_bond_rebuilds();
  test_insert_remove();
  test_adhesion_rolling();
  test_threads();
  test_spin_before_setup();
  return tl_test_report();
}
