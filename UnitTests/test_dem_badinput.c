/* Bad input gets a clear error naming the value and the limit, never a
 * crash or silent NaNs: negative radius, zero density, bad law parameters,
 * a time step above the critical one (refused with both numbers; the
 * override runs and is logged), particles created overlapping by more than
 * half their radius (the default limit) or their radius, NaN from a prescribed motion, and a run that blows up. */
#include <math.h>
#include <string.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

static int mentions(const char *what)
{
  int ok = strstr(tl_error_message(), what) != NULL;
  if (!ok) fprintf(stderr, "message \"%s\" does not mention \"%s\"\n", tl_error_message(), what);
  return ok;
}

static TlStatus two_spheres(TlDem **out, double gap, double dt, int allow, TlVec3 v1)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "g", 2500, 0.01, 0.01, &sp));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0, 0, 0), tl_v3(0, 0, 0), 0.01, sp, NULL));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0.02 + gap, 0, 0), v1, 0.01, sp, NULL));
  TlContactLaw *law;
  TL_CHECK(tl_test_law(&law, "linear", "k_n", 1e5, NULL));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TL_CHECK(tl_dem_set_timestep(dem, dt, allow));
  *out = dem;
  return TL_OK;
}

static TlStatus nan_motion(void *ctx, double t, size_t n, const int64_t *id, const TlVec3 *x0, TlVec3 *x, TlVec3 *v)
{
  for (size_t k = 0; k < n; ++k) {
    x[k] = x0[k];
    v[k] = tl_v3(t > 2.5e-5 ? NAN : 0.0, 0, 0);
  }
  return TL_OK;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TlParticles *P;
  TL_TEST_STATUS(tl_particles_create(&P), TL_OK);
  int sp;
  /* zero density */
  TL_TEST_STATUS(tl_particles_add_species(P, "sand", 0.0, 0.01, 0.01, &sp), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("density 0"), "zero density not named");
  TL_TEST_STATUS(tl_particles_add_species(P, "sand", 2500, 0.02, 0.01, &sp), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("r_min <= r_max"), "radius range not explained");
  TL_TEST_STATUS(tl_particles_add_species(P, "sand", 2500, 0.01, 0.01, &sp), TL_OK);
  /* negative radius, NaN position */
  TL_TEST_STATUS(tl_particles_add(P, tl_v3(0, 0, 0), tl_v3(0, 0, 0), -0.5, sp, NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("radius -0.5"), "negative radius not named");
  TL_TEST_STATUS(tl_particles_add(P, tl_v3(NAN, 0, 0), tl_v3(0, 0, 0), 0.01, sp, NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("not finite"), "NaN position not reported");
  TL_TEST_STATUS(tl_particles_add(P, tl_v3(0, 0, 0), tl_v3(0, 0, 0), 0.01, 7, NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("species 7"), "unknown species not named");
  tl_particles_destroy(&P);

  /* bad law parameters */
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", -3.0, NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("k_n = -3"), "negative stiffness not named");
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e5, "restitution", 1.5, NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("restitution = 1.5"), "restitution not named");
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e5, "mu", -0.1, NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("mu = -0.1"), "friction not named");
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "E", 1e7, "nu", 0.7, NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("nu = 0.7"), "Poisson ratio not named");
  TlWall *w = NULL;
  TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 0), &w), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("normal (0, 0, 0)"), "zero plane normal not named");

  /* time step above the critical one: refused with both numbers */
  TlDem *dem;
  double m = 2500 * 4.0 / 3.0 * TL_PI * 1e-6, dtc = 0.5 * sqrt(m / 1e5);
  TL_TEST_STATUS(two_spheres(&dem, 0.001, 3 * dtc, 0, tl_v3(0, 0, 0)), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_ERR_UNSTABLE);
  char num[64];
  snprintf(num, sizeof num, "%g", 3 * dtc);
  TL_TEST_ASSERT(mentions(num), "dt not named");
  snprintf(num, sizeof num, "critical time step %g", dtc);
  TL_TEST_ASSERT(mentions(num), "critical step not named");
  tl_dem_destroy(&dem);
  /* with the override the run proceeds (and is logged) */
  TL_TEST_STATUS(two_spheres(&dem, 0.001, 1.5 * dtc, 1, tl_v3(0, 0, 0)), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TL_TEST_STATUS(tl_dem_step(dem, 10), TL_OK);
  tl_dem_destroy(&dem);
  /* a run that blows up stops with a diagnosis, not NaNs */
  TL_TEST_STATUS(two_spheres(&dem, -0.002, 40 * dtc, 1, tl_v3(-0.5, 0, 0)), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TlStatus s = tl_dem_step(dem, 200);
  TL_TEST_ASSERT(s == TL_ERR_UNSTABLE, "blow-up gave status %d", (int)s);
  TL_TEST_ASSERT(mentions("time step"), "blow-up diagnosis does not mention the time step");
  tl_dem_destroy(&dem);

  /* particles created overlapping by more than a radius */
  TL_TEST_STATUS(two_spheres(&dem, -0.012, 0.1 * dtc, 0, tl_v3(0, 0, 0)), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("overlap by 0.012"), "overlap not named");
  TL_TEST_ASSERT(mentions("id 0") && mentions("id 1"), "overlapping particles not named");
  tl_dem_destroy(&dem);
  /* beyond the default limit, half the smaller radius (0.6 of it), and
   * accepted once the limit is raised for a scene that wants it; the limit
   * itself is checked */
  TL_TEST_STATUS(two_spheres(&dem, -0.006, 0.1 * dtc, 0, tl_v3(0, 0, 0)), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("0.6 of the smaller radius") && mentions("beyond the limit 0.5"), "limit not named");
  tl_dem_destroy(&dem);
  TL_TEST_STATUS(two_spheres(&dem, -0.006, 0.1 * dtc, 0, tl_v3(0, 0, 0)), TL_OK);
  TL_TEST_STATUS(tl_dem_set_max_initial_overlap(dem, 1.5), TL_ERR_ARG);
  TL_TEST_STATUS(tl_dem_set_max_initial_overlap(dem, 0.0), TL_ERR_ARG);
  TL_TEST_STATUS(tl_dem_set_max_initial_overlap(dem, 0.7), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  tl_dem_destroy(&dem);
  TL_TEST_STATUS(two_spheres(&dem, -0.004, 0.1 * dtc, 0, tl_v3(0, 0, 0)), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK); /* 0.4 of a radius: within the default */
  tl_dem_destroy(&dem);

  /* NaN in a prescribed motion */
  TL_TEST_STATUS(two_spheres(&dem, 0.001, 0.1 * dtc, 0, tl_v3(0, 0, 0)), TL_OK);
  int64_t id = 1;
  TL_TEST_STATUS(tl_dem_prescribe(dem, 1, &id, nan_motion, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  s = tl_dem_step(dem, 100000);
  TL_TEST_ASSERT(s == TL_ERR_NUMERIC, "NaN motion gave status %d", (int)s);
  TL_TEST_ASSERT(mentions("prescribed motion of particle id 1"), "NaN motion not traced to its particle");
  TL_TEST_ASSERT(isfinite(tl_dem_particles(dem)->v[1].x), "a NaN reached the particle state");
  tl_dem_destroy(&dem);

  /* stepping before setup */
  TL_TEST_STATUS(two_spheres(&dem, 0.001, 0.1 * dtc, 0, tl_v3(0, 0, 0)), TL_OK);
  TL_TEST_STATUS(tl_dem_step(dem, 1), TL_ERR_STATE);
  tl_dem_destroy(&dem);
  return tl_test_report();
}
