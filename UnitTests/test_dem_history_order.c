/* Tangential history across neighbour-list rebuilds that renumber the
 * particles: particle 1 orbits particle 0 at a constant overlap (both
 * prescribed, no spin), so the contact slides at |f_t| = mu f_n against the
 * relative velocity once the spring is loaded.  The orbit takes the pair
 * through grid cells in both orders, and renumbering at every rebuild
 * stores the pair as (0, 1) and later as (1, 0): the history carried
 * over must follow (its sign flips with the order).  Asserted at every step
 * after the spring loads: the tangential force on particle 1 opposes its
 * velocity with magnitude mu f_n. */
#include <math.h>
#include <stdio.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

static const double r = 0.01, D = 1.98 * 0.01, Omega = 50.0;
/* far spectators (held in place) spread the grid over cells of about a
 * diameter, so the orbit crosses cells */
enum { NS = 6 };
static const TlVec3 spectator[NS] = {{0.1, 0.1, 0}, {-0.1, 0.1, 0}, {0.1, -0.1, 0}, {-0.1, -0.1, 0}, {0, 0, 0.1}, {0, 0, -0.1}};

static TlStatus orbit(void *ctx, double t, size_t n, const int64_t *id, const TlVec3 *x0, TlVec3 *x, TlVec3 *v)
{
  (void)ctx;
  (void)x0;
  for (size_t k = 0; k < n; ++k) {
    if (id[k] != 1) {
      x[k] = id[k] == 0 ? tl_v3(0.0013, 0.0017, 0.0011) : spectator[id[k] - 2];
      v[k] = tl_v3(0, 0, 0);
    } else {
      const double c = cos(Omega * t), s = sin(Omega * t);
      x[k] = tl_v3(0.0013 + D * c, 0.0017 + D * s, 0.0011);
      v[k] = tl_v3(-D * Omega * s, D * Omega * c, 0);
    }
  }
  return TL_OK;
}

typedef struct {
  int n;
  int64_t i, j;
  TlVec3 f;
} Seen;

static const TlParticles *particles;
static void grab(void *ctx, size_t i, size_t j, TlVec3 f, TlVec3 b, TlVec3 cp)
{
  (void)b;
  (void)cp;
  Seen *s = ctx;
  s->n++;
  s->i = particles->id[i];
  s->j = particles->id[j];
  s->f = f;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  particles = P;
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "g", 2500, r, r, &sp), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.0013, 0.0017, 0.0011), tl_v3(0, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.0013 + D, 0.0017, 0.0011), tl_v3(0, D * Omega, 0), r, sp, NULL), TL_OK);
  for (int k = 0; k < NS; ++k) TL_TEST_STATUS(tl_dem_add_particle(dem, spectator[k], tl_v3(0, 0, 0), r, sp, NULL), TL_OK);
  const double kn = 1e5, mu = 0.4;
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", kn, "mu", mu, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  tl_dem_skip_fixed_pairs(dem, 0);
  tl_dem_set_sort_interval(dem, 1);
  TL_TEST_STATUS(tl_dem_set_skin(dem, 0.02), TL_OK);
  TL_TEST_STATUS(tl_dem_prescribe(dem, 2 + NS, (int64_t[]){0, 1, 2, 3, 4, 5, 6, 7}, orbit, NULL), TL_OK);
  const double dt = 1e-5;
  TL_TEST_STATUS(tl_dem_set_timestep(dem, dt, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  const double fn = kn * (2 * r - D);
  const long steps = (long)(2.0 * 2.0 * TL_PI / Omega / dt); /* two orbits */
  long orders[2] = {0, 0}, flips = 0, bad = 0, checked = 0;
  int64_t last_i = -1;
  double worst = 0.0;
  for (long s = 0; s < steps; ++s) {
    TL_TEST_STATUS(tl_dem_step(dem, 1), TL_OK);
    Seen seen = {0};
    TL_TEST_STATUS(tl_dem_visit_contacts(dem, grab, &seen), TL_OK);
    if (seen.n != 1) {
      ++bad;
      continue;
    }
    orders[seen.i == 0]++;
    if (last_i >= 0 && seen.i != last_i) ++flips;
    last_i = seen.i;
    /* the force on particle 1, its tangential part against v1 */
    const TlVec3 f1 = seen.i == 1 ? seen.f : tl_v3_neg(seen.f);
    const double t = tl_dem_time(dem), c = cos(Omega * t), sn = sin(Omega * t);
    const TlVec3 n = tl_v3(c, sn, 0), e = tl_v3(-sn, c, 0);
    const TlVec3 ft = tl_v3_axpy(f1, -tl_v3_dot(f1, n), n);
    if (t > 0.05 * 2.0 * TL_PI / Omega) { /* the spring loads within a few degrees */
      ++checked;
      const double along = tl_v3_dot(ft, e) / (mu * fn), off = tl_v3_norm(tl_v3_axpy(ft, -tl_v3_dot(ft, e), e)) / (mu * fn);
      worst = fmax(worst, fmax(fabs(along + 1.0), off));
      if (!(fabs(along + 1.0) <= 1e-2 && off <= 1e-2)) ++bad;
    }
  }
  printf("two orbits, %ld steps: the pair stored %ld steps as (0, 1), %ld as (1, 0), %ld order flips; worst relative "
         "deviation of f_t from -mu f_n e_v %.3g over %ld steps\n",
         steps, orders[1], orders[0], flips, worst, checked);
  TL_TEST_ASSERT(orders[0] > 0 && orders[1] > 0 && flips >= 1, "the pair's order never flipped (%ld, %ld, %ld flips)",
                 orders[0], orders[1], flips);
  TL_TEST_ASSERT(bad == 0 && checked > steps / 2, "%ld steps with the tangential force off -mu f_n e_v (worst %g)", bad,
                 worst);
  tl_dem_destroy(&dem);
  return tl_test_report();
}
