/* The Hertz part's restitution coefficient: Tsuji's dashpot
 * α(e) sqrt(m_eff K) δ^{1/4} gives the same restitution at very different
 * impact speeds.
 *
 *  - The law's own force f_n(δ, dδ/dt) (tl_contact_law_evaluate_one),
 *    integrated as m δ'' = -f_n by RK4 with 20 000 steps per contact time,
 *    from δ = 0 at speeds 0.01 and 10 m/s (1000 apart): e equals the one
 *    asked to 1e-5 at both, for e = 0.3, 0.5, 0.8, 0.95.
 *  - A sphere bouncing on a plane wall in a DEM world (velocity Verlet,
 *    about 1000 steps per contact) at the same two speeds: e to 1e-3 at both
 *    (the integrator's error; the two speeds agree to the same).
 *  - restitution with gamma_n too, and e outside [0.01, 1], are refused by
 *    name; restitution 1 leaves the part as before (no damping).
 * Tsuji et al.'s polynomial fit α(e) (LAMMPS's damping tsuji) is printed
 * beside the α found, for the record. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"
#include "tl_wall.h"

static const double E = 1e7, nu = 0.3, R = 0.01, rho = 2500.0;

/* e from integrating m δ'' = -f_n(δ, δ') with the law's force. */
static double restitution_ode(const TlContactLaw *law, double m, double v0, double *duration)
{
  const double kn = (2.0 / 3.0) * E / (1.0 - nu * nu), K = kn * sqrt(R);
  const double d0 = pow(m * v0 * v0 / K, 0.4), T = d0 / v0, h = T * 3.3 / 20000.0;
  double x = 0.0, v = v0, t = 0.0;
  double hist[8] = {0};
  TlContactGeometry g;
  memset(&g, 0, sizeof g);
  g.normal = tl_v3(0, 0, 1);
  g.meff = m;
  g.reff = R;
  g.history = hist;
#define ACC(xx, vv, out)                                                 \
  do {                                                                   \
    TlContactResult r_;                                                  \
    g.overlap = (xx);                                                    \
    g.vrel = tl_v3(0, 0, -(vv));                                         \
    if ((xx) <= 0.0) (out) = 0.0;                                        \
    else {                                                               \
      tl_contact_law_evaluate_one(law, &g, h, &r_);                      \
      (out) = r_.force.z / m;                                            \
    }                                                                    \
  } while (0)
  for (long k = 0; k < 10000000; ++k) {
    double a1, a2, a3, a4;
    ACC(x, v, a1);
    ACC(x + 0.5 * h * v, v + 0.5 * h * a1, a2);
    ACC(x + 0.5 * h * (v + 0.5 * h * a1), v + 0.5 * h * a2, a3);
    ACC(x + h * (v + 0.5 * h * a2), v + h * a3, a4);
    const double xn = x + h / 6.0 * (v + 2.0 * (v + 0.5 * h * a1) + 2.0 * (v + 0.5 * h * a2) + (v + h * a3));
    const double vn = v + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
    if (k > 0 && xn <= 0.0) {
      const double s = x / (x - xn);
      *duration = t + s * h;
      return -(v + s * (vn - v)) / v0;
    }
    x = xn, v = vn, t += h;
  }
#undef ACC
  return NAN;
}

/* e of a sphere bouncing on the floor in a DEM world. */
static double restitution_dem(double e, double v0)
{
  TlDem *dem;
  if (tl_dem_create(&dem) != TL_OK) return NAN;
  TlDomain dom;
  tl_domain_init_open(&dom, tl_v3(-1, -1, -1), tl_v3(1, 1, 1));
  tl_dem_set_domain(dem, &dom);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  tl_particles_add_species(P, "s", rho, R, R, &sp);
  const double m = rho * 4.0 / 3.0 * TL_PI * R * R * R;
  const double kn = (2.0 / 3.0) * E / (1.0 - nu * nu), K = kn * sqrt(R);
  const double d0 = pow(m * v0 * v0 / K, 0.4), T = d0 / v0;
  size_t k;
  tl_dem_add_particle(dem, tl_v3(0, 0, R + 0.2 * d0), tl_v3(0, 0, -v0), R, sp, &k);
  TlContactLaw *law;
  if (tl_test_law(&law, "hertz", "E", E, "nu", nu, "tsuji_restitution", e, (const char *)NULL) != TL_OK) return NAN;
  tl_dem_add_law(dem, law, NULL);
  TlWall *w;
  tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &w);
  tl_dem_add_wall(dem, w, 0);
  tl_dem_set_gravity(dem, tl_v3(0, 0, 0));
  const double dt = 3.3 * T / 1000.0;
  if (tl_dem_set_timestep(dem, dt, 0) != TL_OK || tl_dem_setup(dem) != TL_OK) return NAN;
  long steps = 0;
  while (!(P->x[0].z > R + 0.2 * d0 && P->v[0].z > 0.0) && steps < 100000) {
    if (tl_dem_step(dem, 1) != TL_OK) return NAN;
    ++steps;
  }
  const double out = P->v[0].z / v0;
  tl_dem_destroy(&dem);
  return out;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const double m = rho * 4.0 / 3.0 * TL_PI * R * R * R;
  const double es[] = {0.3, 0.5, 0.8, 0.95}, speeds[] = {0.01, 10.0};
  for (int a = 0; a < 4; ++a) {
    TlContactLaw *law = NULL;
    TL_TEST_STATUS(tl_test_law(&law, "hertz", "E", E, "nu", nu, "tsuji_restitution", es[a], (const char *)NULL), TL_OK);
    if (!law) continue;
    const double c = es[a];
    const double tsuji = 1.2728 - 4.2783 * c + 11.087 * c * c - 22.348 * pow(c, 3) + 27.467 * pow(c, 4) -
                         18.022 * pow(c, 5) + 4.8218 * pow(c, 6);
    for (int s = 0; s < 2; ++s) {
      double tc = 0.0;
      const double e_ode = restitution_ode(law, m, speeds[s], &tc);
      const double e_dem = restitution_dem(c, speeds[s]);
      printf("e = %.2f, v0 = %5.2f m/s: contact %.4e s, e (law integrated by RK4) = %.8f (|diff| %.1e), "
             "e (DEM world) = %.6f (|diff| %.1e)\n", c, speeds[s], tc, e_ode, fabs(e_ode - c), e_dem, fabs(e_dem - c));
      TL_TEST_ASSERT(fabs(e_ode - c) <= 1e-5, "e = %g at %g m/s: the law's force gives %.8f", c, speeds[s], e_ode);
      TL_TEST_ASSERT(fabs(e_dem - c) <= 1e-3, "e = %g at %g m/s: the DEM bounce gives %.6f", c, speeds[s], e_dem);
    }
    printf("  (Tsuji's fit alpha(%.2f) = %.5f, for comparison)\n", c, tsuji);
    tl_contact_law_destroy(&law);
  }
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "E", E, "tsuji_restitution", 0.5, "gamma_n", 10.0, (const char *)NULL),
                 TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "restitution") && strstr(tl_error_message(), "gamma_n"),
                 "the refusal names both: %s", tl_error_message());
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "E", E, "tsuji_restitution", 0.001, (const char *)NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "restitution") != NULL, "names the value: %s", tl_error_message());
  /* e = 1: undamped, the same force as without the parameter */
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "E", E, "nu", nu, "tsuji_restitution", 1.0, (const char *)NULL), TL_OK);
  if (law) {
    double tc;
    const double e1 = restitution_ode(law, m, 1.0, &tc);
    printf("e = 1: e (law integrated) = %.10f\n", e1);
    TL_TEST_ASSERT(fabs(e1 - 1.0) <= 1e-6, "restitution 1 gives %.10f", e1);
    tl_contact_law_destroy(&law);
  }
  return tl_test_report();
}
