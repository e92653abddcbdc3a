/* Two-body impacts against analytic solutions: linear spring-dashpot
 * (contact duration and restitution), Hertz (Hertz's contact time and
 * maximum overlap), and an oblique frictional impact on a plane (rigid-body
 * sliding and rolling predictions, energy never increasing). */
#include <math.h>
#include <stdio.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

typedef struct {
  double t_first, t_last, max_overlap;
  int touching_seen;
} Track;

/* Two equal spheres approaching head-on along x with relative speed 2 v0. */
static TlStatus head_on(TlContactLaw *law, double r, double density, double v0, double dt, Track *tr,
                        double *v_after_rel)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "a", density, r, r, &sp));
  double gap = 0.01 * r;
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(-r - gap, 0, 0), tl_v3(v0, 0, 0), r, sp, NULL));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(r + gap, 0, 0), tl_v3(-v0, 0, 0), r, sp, NULL));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TL_CHECK(tl_dem_set_timestep(dem, dt, 0));
  TL_CHECK(tl_dem_setup(dem));
  tr->t_first = tr->t_last = -1.0;
  tr->max_overlap = 0.0;
  double prev_ov = -1.0, t_prev = 0.0;
  for (long s = 0; s < 10000000; ++s) {
    TL_CHECK(tl_dem_step(dem, 1));
    double ov = 2 * r - (P->x[1].x - P->x[0].x);
    double t = tl_dem_time(dem);
    if (ov > 0 && prev_ov <= 0) tr->t_first = t_prev + (t - t_prev) * (-prev_ov) / (ov - prev_ov);
    if (ov <= 0 && prev_ov > 0) {
      tr->t_last = t_prev + (t - t_prev) * prev_ov / (prev_ov - ov);
      break;
    }
    if (ov > tr->max_overlap) tr->max_overlap = ov;
    prev_ov = ov;
    t_prev = t;
  }
  *v_after_rel = P->v[1].x - P->v[0].x;
  tl_dem_destroy(&dem);
  return TL_OK;
}

static void test_linear(void)
{
  double r = 0.01, rho = 2500, v0 = 0.5, kn = 1e5, e = 0.7;
  double m = rho * 4.0 / 3.0 * TL_PI * r * r * r, meff = 0.5 * m;
  double eta = -log(e) / sqrt(TL_PI * TL_PI + log(e) * log(e));
  double w0 = sqrt(kn / meff), wd = w0 * sqrt(1 - eta * eta), tc = TL_PI / wd;
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", kn, "restitution", e, NULL), TL_OK);
  Track tr;
  double vr;
  TL_TEST_STATUS(head_on(law, r, rho, v0, tc / 2000, &tr, &vr), TL_OK);
  double duration = tr.t_last - tr.t_first;
  printf("linear: contact duration %.6e s (analytic %.6e), restitution %.6f (set %.6f)\n", duration, tc,
         vr / (2 * v0), e);
  TL_TEST_CLOSE(duration / tc, 1.0, 0.01);
  TL_TEST_CLOSE(vr / (2 * v0), e, 0.01);
}

static void test_hertz(void)
{
  double r = 0.01, rho = 2500, v0 = 0.5, E = 1e8, nu = 0.3;
  double m = rho * 4.0 / 3.0 * TL_PI * r * r * r, meff = 0.5 * m, reff = 0.5 * r;
  double kn = (2.0 / 3.0) * E / (1 - nu * nu);
  double kh = kn * sqrt(reff);
  double vrel = 2 * v0;
  double dmax = pow(5.0 * meff * vrel * vrel / (4.0 * kh), 0.4);
  double tc = 2.94328 * dmax / vrel;
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "E", E, "nu", nu, NULL), TL_OK);
  Track tr;
  double vr;
  TL_TEST_STATUS(head_on(law, r, rho, v0, tc / 2000, &tr, &vr), TL_OK);
  double duration = tr.t_last - tr.t_first;
  printf("hertz: contact time %.6e s (Hertz %.6e), max overlap %.6e m (Hertz %.6e), rebound %.6f\n", duration,
         tc, tr.max_overlap, dmax, vr / vrel);
  TL_TEST_CLOSE(duration / tc, 1.0, 0.01);
  TL_TEST_CLOSE(tr.max_overlap / dmax, 1.0, 0.01);
  TL_TEST_CLOSE(vr / vrel, 1.0, 1e-3);
}

/* A sphere hits a plane obliquely with normal speed vn and tangential speed
 * vt, no spin.  Returns the rebound normal and tangential speeds, spin (about
 * the axis that rolling forward would give), and the largest increase of
 * KE + stored elastic energy over its initial value. */
static TlStatus oblique(double vt, double vn, double mu, double e, double k_t, double gamma_t, double *vn_out,
                        double *vt_out, double *wr_out, double *max_rise)
{
  double r = 0.01, rho = 2500, kn = 1e6;
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "a", rho, r, r, &sp));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0, 0, r * 1.001), tl_v3(vt, 0, -vn), r, sp, NULL));
  TlContactLaw *law;
  TL_CHECK(tl_test_law(&law, "linear", "k_n", kn, "restitution", e, "mu", mu, "c_t", gamma_t, "k_t", k_t, NULL));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TlWall *w;
  TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &w));
  TL_CHECK(tl_dem_add_wall(dem, w, 0));
  double m = P->mass[0];
  double tc = TL_PI / sqrt(kn / m);
  TL_CHECK(tl_dem_set_timestep(dem, tc / 1000, 0));
  TL_CHECK(tl_dem_setup(dem));
  TlDemEnergy en;
  TL_CHECK(tl_dem_energy(dem, &en));
  double e0 = en.kinetic_translational + en.kinetic_rotational + en.elastic, rise = -INFINITY;
  int was = 0;
  for (long s = 0; s < 100000; ++s) {
    TL_CHECK(tl_dem_step(dem, 1));
    TL_CHECK(tl_dem_energy(dem, &en));
    double e1 = en.kinetic_translational + en.kinetic_rotational + en.elastic;
    if (e1 - e0 > rise) rise = e1 - e0;
    int touching = P->x[0].z < r;
    if (was && !touching) break;
    was |= touching;
  }
  *vn_out = P->v[0].z;
  *vt_out = P->v[0].x;
  *wr_out = P->w[0].y * r; /* rolling forward along +x spins about +y */
  *max_rise = rise / e0;
  tl_dem_destroy(&dem);
  return TL_OK;
}

static void test_oblique(void)
{
  double vn = 0.5, mu = 0.3, e = 0.8;
  double crit = 3.5 * mu * (1 + e); /* vt/vn above which the sphere slides throughout */
  /* sliding regime: vt - mu (1+e) vn, spin 2.5 mu (1+e) vn / r */
  double ratios[3] = {1.5 * crit, 2.0 * crit, 4.0 * crit};
  for (int k = 0; k < 3; ++k) {
    double vt = ratios[k] * vn, vno, vto, wr, rise;
    TL_TEST_STATUS(oblique(vt, vn, mu, e, 0.0, 0.0, &vno, &vto, &wr, &rise), TL_OK);
    double vt_pred = vt - mu * (1 + e) * vn, wr_pred = 2.5 * mu * (1 + e) * vn;
    double ang = atan2(vto, vno), ang_pred = atan2(vt_pred, e * vn);
    printf("oblique sliding vt/vn=%.3f: vt_out %.5f (rigid %.5f), w r %.5f (rigid %.5f), rebound angle %.4f (rigid %.4f) rad, energy rise %.2e\n",
           vt / vn, vto, vt_pred, wr, wr_pred, ang, ang_pred, rise);
    TL_TEST_CLOSE(vto / vt_pred, 1.0, 0.01);
    TL_TEST_CLOSE(wr / wr_pred, 1.0, 0.01);
    TL_TEST_CLOSE(ang, ang_pred, 0.01);
    TL_TEST_CLOSE(vno / (e * vn), 1.0, 0.01);
    TL_TEST_ASSERT(rise <= 1e-9, "energy rose by %g of its initial value", rise);
  }
  /* rolling regime (below the transition): the rigid-body limit needs a
   * tangential spring much stiffer than the normal one and critically
   * damped, so that sticking is immediate; the contact point then ends at
   * rest: vt_out = 5/7 vt */
  double r = 0.01, m = 2500 * 4.0 / 3.0 * TL_PI * r * r * r, kt = 50 * 1e6;
  double gamma_t = 2.0 * sqrt(kt * m / 3.5);
  double lows[2] = {0.3 * crit, 0.6 * crit};
  for (int k = 0; k < 2; ++k) {
    double vt = lows[k] * vn, vno, vto, wr, rise;
    TL_TEST_STATUS(oblique(vt, vn, mu, e, kt, gamma_t, &vno, &vto, &wr, &rise), TL_OK);
    printf("oblique rolling vt/vn=%.3f: vt_out %.5f (rigid 5/7 vt = %.5f), w r %.5f, slip %.2e, energy rise %.2e\n",
           vt / vn, vto, 5.0 / 7.0 * vt, wr, vto - wr, rise);
    TL_TEST_CLOSE(vto / (5.0 / 7.0 * vt), 1.0, 0.02);
    TL_TEST_ASSERT(fabs(vto - wr) < 0.02 * vt, "slip %g after a rolling impact (vt %g)", vto - wr, vt);
    TL_TEST_ASSERT(rise <= 1e-9, "energy rose by %g of its initial value", rise);
  }
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_linear();
  test_hertz();
  test_oblique();
  return tl_test_report();
}
