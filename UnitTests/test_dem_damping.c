/* The linear normal part's two viscous parameters, each on its own: a
 * head-on impact with c_n (N s/m) or gamma_n (1/s, times m_eff) gives the
 * damped oscillator's restitution e = exp(-zeta pi / sqrt(1 - zeta^2)),
 * zeta = c / (2 sqrt(k_n m_eff)), c = c_n + gamma_n m_eff (the contact ends
 * when the overlap returns to zero; the part does not clip f_n). */
#include <math.h>
#include <stdio.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

static double restitution(const char *param, double value, double kn, double r, double rho, double v)
{
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", kn, param, value, NULL), TL_OK);
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", rho, r, r, &sp), TL_OK);
  const double gap = 1e-3 * r;
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(-r - gap, 0, 0), tl_v3(0.5 * v, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(r + gap, 0, 0), tl_v3(-0.5 * v, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  const double m = rho * 4.0 / 3.0 * TL_PI * r * r * r, tc = TL_PI * sqrt(0.5 * m / kn);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, tc / 4000, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  int touched = 0;
  for (long s = 0; s < 1000000; ++s) {
    TL_TEST_STATUS(tl_dem_step(dem, 1), TL_OK);
    const double d = 2 * r - (P->x[1].x - P->x[0].x);
    if (d > 0.0) touched = 1;
    else if (touched && d < -gap) break;
  }
  const double e = (P->v[1].x - P->v[0].x) / v;
  tl_dem_destroy(&dem);
  return touched ? e : NAN;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const double kn = 1e5, r = 0.01, rho = 2500, v = 0.5;
  const double m = rho * 4.0 / 3.0 * TL_PI * r * r * r, meff = 0.5 * m, crit = 2.0 * sqrt(kn * meff);
  /* zeta = 0.2 through either parameter */
  const double c = 0.2 * crit;
  const double zeta = c / crit, e_ref = exp(-zeta * TL_PI / sqrt(1.0 - zeta * zeta));
  const double e_c = restitution("c_n", c, kn, r, rho, v), e_g = restitution("gamma_n", c / meff, kn, r, rho, v);
  printf("linear, zeta = %g: restitution with c_n %.6f, with gamma_n %.6f (damped oscillator %.6f)\n", zeta, e_c, e_g,
         e_ref);
  TL_TEST_REL(e_c, e_ref, 1e-4);
  TL_TEST_REL(e_g, e_ref, 1e-4);
  return tl_test_report();
}
