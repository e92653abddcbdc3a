/* The Hertz normal part's dashpot and the tangential spring it scales,
 * against the same equations integrated here by RK4 (an independent
 * reference):
 *  - a damped head-on impact: restitution of
 *      m_eff δ'' = -sqrt(δ R) (k_n δ + γ_n m_eff δ')
 *    at two speeds (the model's restitution depends on speed), and the
 *    kinetic energy lost = the dashpot's work, summed here from the
 *    trajectory, = the library's dissipation bookkeeping;
 *  - a sticking oblique impact on a plane: the contact point's slip speed
 *    after the impact, from dF_t/dt = k_t sqrt(δ R) u along the Hertz normal
 *    motion (the tangential period is near the contact time for any speed,
 *    so the slip after the impact is a sensitive measure of k_T). */
#include <math.h>
#include <stdio.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

static const double r = 0.01, rho = 2500.0, E = 1e8, nu = 0.3;

/* RK4 from contact to separation on y = (δ, δ', F, v, ω): the normal
 * motion δ'' = -a δ^1.5 - b δ^0.5 δ', and for a sphere on a plane the
 * tangential force F, growing at the rate k_T u = kt δ^0.5 u (the friction
 * part's incremental spring; kt holds sqrt(R)), against the slip speed
 * u = v - l ω of the contact point at the lever arm l = r - δ/2:
 * v' = -F / m, ω' = l F / I.  Returns δ' and u at the separation
 * (interpolated to δ = 0). */
typedef struct { double a, b, kt, m, inertia, radius; } Ode;
static void rhs(const Ode *o, const double *z, double *k)
{
  const double d = z[0] > 0.0 ? z[0] : 0.0, sd = sqrt(d), l = o->radius - 0.5 * d;
  k[0] = z[1];
  k[1] = -o->a * d * sd - o->b * sd * z[1];
  k[2] = o->kt * sd * (z[3] - l * z[4]);
  k[3] = -z[2] / o->m;
  k[4] = l * z[2] / o->inertia;
}
static void reference(const Ode *o, double v_n, double v_t, double h, double *dv_out, double *u_out)
{
  double y[5] = {0.0, v_n, 0.0, v_t, 0.0};
  for (long s = 0; s < 100000000; ++s) {
    double k[4][5], z[5], y1[5];
    for (int st = 0; st < 4; ++st) {
      const double w = st == 0 ? 0.0 : (st == 3 ? 1.0 : 0.5);
      for (int q = 0; q < 5; ++q) z[q] = y[q] + (st ? w * h * k[st - 1][q] : 0.0);
      rhs(o, z, k[st]);
    }
    for (int q = 0; q < 5; ++q) y1[q] = y[q] + h / 6.0 * (k[0][q] + 2 * k[1][q] + 2 * k[2][q] + k[3][q]);
    if (s > 0 && y1[0] <= 0.0) {
      const double f = y[0] / (y[0] - y1[0]);
      *dv_out = y[1] + f * (y1[1] - y[1]);
      *u_out = (y[3] - o->radius * y[4]) + f * ((y1[3] - o->radius * y1[4]) - (y[3] - o->radius * y[4]));
      return;
    }
    for (int q = 0; q < 5; ++q) y[q] = y1[q];
  }
  *dv_out = *u_out = NAN;
}

static double mass(void) { return rho * 4.0 / 3.0 * TL_PI * r * r * r; }
static double k_n(void) { return (2.0 / 3.0) * E / (1.0 - nu * nu); }
static double hertz_time(double meff, double reff, double v) /* Hertz's contact time */
{
  double dmax = pow(5.0 * meff * v * v / (4.0 * k_n() * sqrt(reff)), 0.4);
  return 2.94328 * dmax / v;
}

/* Two equal spheres head-on at relative speed v. */
static void damped_head_on(double v, double gamma_n)
{
  const double m = mass(), meff = 0.5 * m, reff = 0.5 * r, tc = hertz_time(meff, reff, v);
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "E", E, "nu", nu, "gamma_n", gamma_n, NULL), TL_OK);
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", rho, r, r, &sp), TL_OK);
  const double gap = 1e-3 * r;
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(-r - gap, 0, 0), tl_v3(0.5 * v, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(r + gap, 0, 0), tl_v3(-0.5 * v, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, tc / 4000, 0), TL_OK);
  tl_dem_track_energy(dem, 1);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TlDemEnergy e0, e1;
  TL_TEST_STATUS(tl_dem_energy(dem, &e0), TL_OK);
  /* the dashpot's work sqrt(δ R) γ m_eff δ'² dt, trapezoidal over steps */
  double work = 0.0, p_prev = 0.0, dt = tc / 4000;
  int touched = 0;
  for (long s = 0; s < 1000000; ++s) {
    TL_TEST_STATUS(tl_dem_step(dem, 1), TL_OK);
    const double d = 2 * r - (P->x[1].x - P->x[0].x), dd = P->v[0].x - P->v[1].x;
    const double p = d > 0.0 ? sqrt(d * reff) * gamma_n * meff * dd * dd : 0.0;
    work += 0.5 * (p + p_prev) * dt;
    p_prev = p;
    if (d > 0.0) touched = 1;
    if (touched && d < -gap) break;
  }
  TL_TEST_STATUS(tl_dem_energy(dem, &e1), TL_OK);
  const double e_dem = (P->v[1].x - P->v[0].x) / v;
  double dv, du;
  const Ode o = {k_n() * sqrt(reff) / meff, gamma_n * sqrt(reff), 0.0, 1.0, 1.0, r};
  reference(&o, v, 0.0, tc / 200000, &dv, &du);
  const double e_ref = -dv / v;
  const double lost = e0.kinetic_translational - e1.kinetic_translational;
  printf("damped hertz v = %g m/s: restitution %.6f (integrated equation %.6f), kinetic energy lost %.6e J, "
         "dashpot work %.6e J, library's dissipation %.6e J\n",
         v, e_dem, e_ref, lost, work, e1.dissipated);
  TL_TEST_ASSERT(touched && e_ref > 0.3 && e_ref < 0.95, "the reference restitution %g is meant to be a damped one", e_ref);
  TL_TEST_ASSERT(fabs(e_dem - e_ref) <= 1e-4 * e_ref, "restitution %.8f against %.8f", e_dem, e_ref);
  TL_TEST_ASSERT(fabs(lost - work) <= 5e-4 * lost, "kinetic energy lost %.8e J, dashpot work %.8e J", lost, work);
  TL_TEST_ASSERT(fabs(e1.dissipated - lost) <= 5e-5 * lost, "dissipation %.8e J, kinetic energy lost %.8e J",
                 e1.dissipated, lost);
  tl_dem_destroy(&dem);
}

/* A sphere hits a plane with normal speed vn and tangential speed vt, no
 * spin, friction high enough to stick throughout. */
static void sticking_oblique(double vn, double vt)
{
  const double m = mass(), tc = hertz_time(m, r, vn);
  const double kt = 2.0 * E / ((1.0 + nu) * (2.0 - nu)); /* the Hertz part's default */
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "E", E, "nu", nu, "mu", 1e3, NULL), TL_OK);
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", rho, r, r, &sp), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0, 0, r * 1.0001), tl_v3(vt, 0, -vn), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  TlWall *w;
  TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &w), TL_OK);
  TL_TEST_STATUS(tl_dem_add_wall(dem, w, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, tc / 4000, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  int touched = 0;
  for (long s = 0; s < 1000000; ++s) {
    TL_TEST_STATUS(tl_dem_step(dem, 1), TL_OK);
    if (P->x[0].z < r) touched = 1;
    else if (touched) break;
  }
  const double u_dem = P->v[0].x - r * P->w[0].y; /* the contact point's slip speed */
  double dv, du;
  const Ode o = {k_n() * sqrt(r) / m, 0.0, kt * sqrt(r), m, 0.4 * m * r * r, r};
  reference(&o, vn, vt, tc / 200000, &dv, &du);
  printf("sticking hertz impact vn = %g, vt = %g m/s: contact point's speed after %.6f m/s (integrated "
         "equation %.6f), rebound %.6f (%.6f)\n", vn, vt, u_dem, du, P->v[0].z / vn, -dv / vn);
  /* the spring reverses the contact point's speed partly: a value that
   * tells the sqrt(δ R) scaling (a constant k_t gives many oscillations) */
  TL_TEST_ASSERT(touched && fabs(du) > 0.05 * vt, "the reference %g is meant to be away from zero", du);
  TL_TEST_ASSERT(fabs(u_dem - du) <= 2e-3 * vt, "slip speed %.8f m/s against %.8f", u_dem, du);
  TL_TEST_ASSERT(fabs(P->v[0].z + dv) <= 1e-4 * vn, "rebound speed %.8f m/s against %.8f", P->v[0].z, -dv);
  tl_dem_destroy(&dem);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  damped_head_on(1.0, 1e6);
  damped_head_on(0.2, 1e6);
  sticking_oblique(0.5, 0.1);
  return tl_test_report();
}
