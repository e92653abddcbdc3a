/* The V1 wave scene on TlDem, TlSolid and the library steppers (central
 * difference and Newmark): weighted mass of the coupled bar, momentum
 * balance and energy book-keeping of the coupled step, the spring variant conserving
 * energy, a divergent penalty stopped with a diagnosis, bad parameters. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_test.h"
#include "tl_vcoupling_wave.h"

/* The implicit runs take a bar of half the length, its overlap on [2, 6] m,
 * so that the wave is in the overlap after a few hundred steps. */
static void short_bar(TlWaveParams *p)
{
  p->length = 10.0;
  p->fem_start = 2.0;
  p->dem_end = 6.0;
}

static void test_mass_and_balance(int per_element, const char *fem)
{
  TlWaveParams p;
  tl_wave_params_default(&p);
  p.per_element = per_element;
  p.fem = fem;
  int implicit = strcmp(fem, "newmark") == 0;
  if (implicit) short_bar(&p);
  TlWave *w = NULL;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_OK);
  if (!w) return;
  TlWaveState s0, s;
  tl_wave_state(w, &s0);
  double M = p.rho * p.length * p.width * p.width;
  /* particles weighted by w, solid by 1 - w: the bar's mass, Eqs. 25-26 */
  TL_TEST_CLOSE((s0.mass_dem + s0.mass_fem) / M, 1.0, 1e-13);
  TL_TEST_ASSERT(s0.mass_dem > 0.5 * M * p.fem_start / p.length && s0.mass_fem > 0.5 * M * p.fem_start / p.length,
                 "both sub-models carry mass: %g %g", s0.mass_dem, s0.mass_fem);
  /* the left layer of 2 x 2 particles of mass rho d^3 moves at -v0 */
  TL_TEST_CLOSE(s0.mom_dem / (-p.v0 * 4.0 * p.rho * pow(p.dx, 3)), 1.0, 1e-13);
  /* 1400 steps (0.045 s; 400 on the short bar): the pulse is in the
   * overlap; total momentum is conserved (no reaction yet at the fixed
   * end), Eq. 41 to round-off */
  TlStatus st = TL_OK;
  double eq41 = 0.0;
  for (int k = 0; k < (implicit ? 400 : 1400) && st == TL_OK; ++k) {
    st = tl_wave_step(w);
    if (k % 100 == 99) {
      tl_wave_state(w, &s);
      eq41 = fmax(eq41, s.eq41);
    }
  }
  TL_TEST_STATUS(st, TL_OK);
  tl_wave_state(w, &s);
  TL_TEST_ASSERT(fabs(s.mom_fem) > 0.1 * fabs(s0.mom_dem), "the wave has reached the solid: %g", s.mom_fem);
  double drift = fabs(s.mom_dem + s.mom_fem - s0.mom_dem) / fabs(s0.mom_dem);
  TL_TEST_ASSERT(drift < 1e-3, "per_element %d, %s: total momentum drifts by %g", per_element, fem, drift);
  TL_TEST_ASSERT(eq41 < 1e-12, "Eq. 41 violated by %g", eq41);
  /* the paper's penalty only removes energy: what is lost equals the
   * penalty's work within the integration error (the solid's kinetic
   * energy with its stepper's mass: lumped, or consistent for Newmark) */
  double lost = s0.total - s.total;
  TL_TEST_ASSERT(lost > 0.0 && s.coupling_work < 0.0, "lost %g, penalty work %g", lost, s.coupling_work);
  printf("%s, per_element %d: energy lost %.6g J, penalty work %.6g J\n", fem, per_element, lost, -s.coupling_work);
  TL_TEST_ASSERT(fabs(lost + s.coupling_work) < 0.05 * lost, "%s: energy lost %g against penalty work %g", fem, lost,
                 -s.coupling_work);
  tl_wave_destroy(&w);
}

static void test_spring_conserves(void)
{
  TlWaveParams p;
  tl_wave_params_default(&p);
  p.variant = TL_WAVE_SPRING;
  TlWave *w = NULL;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_OK);
  if (!w) return;
  TlWaveState s0, s;
  tl_wave_state(w, &s0);
  TlStatus st = TL_OK;
  double dev = 0.0;
  for (int k = 0; k < 1800 && st == TL_OK; ++k) {
    st = tl_wave_step(w);
    if (k % 50 == 49) {
      tl_wave_state(w, &s);
      dev = fmax(dev, fabs(s.total - s0.total) / s0.total);
    }
  }
  TL_TEST_STATUS(st, TL_OK);
  tl_wave_state(w, &s);
  TL_TEST_ASSERT(s.kin_fem + s.pot_fem > 0.3 * s0.total, "energy reached the solid: %g of %g", s.kin_fem + s.pot_fem,
                 s0.total);
  TL_TEST_ASSERT(dev < 2e-3, "spring variant: total energy deviates by %g", dev);
  tl_wave_destroy(&w);
}

/* A penalty beyond the explicit stable range: refused at creation with the
 * ratio, the limit and the largest stable eps; run anyway (check off) it
 * diverges, and the run stops with a diagnosis before any NaN.  The ratio
 * scales with eps, and the limit it predicts brackets the observed one. */
static void test_divergence_stops(void)
{
  TlWaveParams p;
  tl_wave_params_default(&p);
  TlWave *w = NULL;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_OK);
  if (!w) return;
  double r1, r2;
  size_t a, i;
  TL_TEST_STATUS(tl_wave_penalty_ratio(w, 200, &r1, &a, &i), TL_OK);
  tl_wave_destroy(&w);
  TL_TEST_ASSERT(r1 > 0.1 && r1 < 2.0, "Table 6 penalty is stable: ratio %g", r1);
  p.epsilon = 2.0e10;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_OK);
  if (!w) return;
  TL_TEST_STATUS(tl_wave_penalty_ratio(w, 200, &r2, &a, &i), TL_OK);
  TL_TEST_CLOSE(r2 / r1, 2.0e10 / (1.6e9 / (0.4 * 0.4)), 1e-3); /* Table 6, 1P: eps = 1.6e9 Pa / d^2 */
  /* just below the predicted limit: runs 600 steps */
  double eps_lim = 2.0e10 * 2.0 / r2;
  TlStatus st = TL_OK;
  for (int k = 0; k < 600 && st == TL_OK; ++k) st = tl_wave_step(w);
  TL_TEST_STATUS(st, TL_OK);
  tl_wave_destroy(&w);
  p.epsilon = 0.97 * eps_lim;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_OK);
  for (int k = 0; w && k < 600 && st == TL_OK; ++k) st = tl_wave_step(w);
  TL_TEST_STATUS(st, TL_OK);
  tl_wave_destroy(&w);

  p.epsilon = 4e10;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_UNSTABLE);
  TL_TEST_ASSERT(w == NULL, "no half-built scene");
  const char *m = tl_error_message();
  TL_TEST_ASSERT(strstr(m, "penalty eps = 4e+10") && strstr(m, "at step 0") && strstr(m, "over the limit 2 "),
                 "diagnosis names eps, the step and the limit: %s", m);
  /* 10 % above the predicted limit, run anyway: it blows up and stops */
  p.epsilon = 1.1 * eps_lim;
  p.no_penalty_check = 1;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_OK);
  if (!w) return;
  int k = 0;
  for (; k < 3000 && st == TL_OK; ++k) st = tl_wave_step(w);
  TL_TEST_STATUS(st, TL_ERR_UNSTABLE);
  TL_TEST_ASSERT(strstr(tl_error_message(), "diverged") != NULL, "runtime diagnosis: %s", tl_error_message());
  TlWaveState s;
  tl_wave_state(w, &s);
  TL_TEST_ASSERT(isfinite(s.total), "state still finite when stopped (%g)", s.total);
  tl_wave_destroy(&w);
}

/* A CG width beyond what the mesh resolves stops at creation with a
 * diagnosis naming c, the limit and the step; the widest accepted width runs;
 * the check can be switched off. */
static void test_width_beyond_range(void)
{
  TlWaveParams p;
  tl_wave_params_default(&p);
  TlWave *w = NULL;
  p.c = 3.0 * p.dx;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_UNSTABLE);
  TL_TEST_ASSERT(w == NULL, "no half-built scene");
  const char *m = tl_error_message();
  TL_TEST_ASSERT(strstr(m, "c = 1.2 m (3 element sizes)") && strstr(m, "at step 0") &&
                     strstr(m, "limit of 0.5 element sizes"),
                 "diagnosis names c, the step and the limit: %s", m);
  p.resolution_limit = -1.0;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_OK);
  tl_wave_destroy(&w);
  /* the paper's widest stable width passes the check at the start and at
   * steps 100 and 200 */
  p.resolution_limit = 0.0;
  p.c = 2.5 * p.dx;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_OK);
  if (!w) return;
  TlStatus st = TL_OK;
  for (int k = 0; k < 201 && st == TL_OK; ++k) st = tl_wave_step(w);
  TL_TEST_STATUS(st, TL_OK);
  tl_wave_destroy(&w);
}

/* N steps in one go against N/2 steps, a checkpoint, a scene built afresh
 * and loaded from it, and N/2 steps: the same state bit for bit. */
static void test_restart(TlWaveVariant variant, double c, const char *fem)
{
  TlWaveParams p;
  tl_wave_params_default(&p);
  p.variant = variant;
  p.c = c;
  p.fem = fem;
  int implicit = strcmp(fem, "newmark") == 0;
  if (implicit) short_bar(&p);
  const int N = implicit ? 300 : 600;
  TlWave *a = NULL, *b = NULL;
  TL_TEST_STATUS(tl_wave_create(&p, &a), TL_OK);
  TL_TEST_STATUS(tl_wave_create(&p, &b), TL_OK);
  if (!a || !b) {
    tl_wave_destroy(&a);
    tl_wave_destroy(&b);
    return;
  }
  TlStatus st = TL_OK;
  for (int k = 0; k < N && st == TL_OK; ++k) st = tl_wave_step(a);
  for (int k = 0; k < N / 2 && st == TL_OK; ++k) st = tl_wave_step(b);
  TL_TEST_STATUS(st, TL_OK);
  TlCheckpoint *cp = NULL;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "wave", &tl_wave_checkpoint_ops, b), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, "wave_restart.h5", 0.0, N / 2), TL_OK);
  tl_checkpoint_destroy(&cp);
  tl_wave_destroy(&b);
  TL_TEST_STATUS(tl_wave_create(&p, &b), TL_OK);
  if (!b) {
    tl_wave_destroy(&a);
    return;
  }
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "wave", &tl_wave_checkpoint_ops, b), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp, "wave_restart.h5", NULL, NULL), TL_OK);
  tl_checkpoint_destroy(&cp);
  for (int k = 0; k < N / 2 && st == TL_OK; ++k) st = tl_wave_step(b);
  TL_TEST_STATUS(st, TL_OK);
  TlWaveState sa, sb;
  tl_wave_state(a, &sa);
  tl_wave_state(b, &sb);
  TL_TEST_ASSERT(sa.kin_fem > 0.0 || variant == TL_WAVE_SPRING || sa.kin_dem > 0.0, "the wave moves");
  TL_TEST_ASSERT(memcmp(&sa, &sb, sizeof sa) == 0, "variant %d, c = %g, %s: restarted state differs (total %.17g / "
                 "%.17g, t %.17g / %.17g)", (int)variant, c, fem, sa.total, sb.total, sa.t, sb.t);
  size_t ny = tl_wave_profile_size(a);
  double ya[512], va[512], yb[512], vb[512];
  if (ny <= 512) {
    tl_wave_profile(a, ya, va);
    tl_wave_profile(b, yb, vb);
    TL_TEST_ASSERT(memcmp(va, vb, ny * sizeof *va) == 0, "restarted velocity profile differs");
  }
  tl_wave_destroy(&a);
  tl_wave_destroy(&b);
  remove("wave_restart.h5");
}

static void test_bad_params(void)
{
  TlWaveParams p;
  TlWave *w = NULL;
  tl_wave_params_default(&p);
  p.n = 0;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_ARG);
  tl_wave_params_default(&p);
  p.fem_start = 13.0;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_ARG);
  /* A section narrower than an element (no element, no particle) and a bar
   * that is not a whole number of elements are refused. */
  tl_wave_params_default(&p);
  p.dx = 100.0;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_ARG);
  p.full_dem = 1;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_ARG);
  tl_wave_params_default(&p);
  p.width = 1e-3;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_ARG);
  tl_wave_params_default(&p);
  p.dx = 0.3;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_ARG);
  tl_wave_params_default(&p);
  p.dt_over_tc = 0.5;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_ARG);
  tl_wave_params_default(&p);
  p.c = -1.0;
  TL_TEST_STATUS(tl_wave_create(&p, &w), TL_ERR_ARG);
  TL_TEST_ASSERT(w == NULL, "failed create leaves NULL");
  tl_wave_params_default(&p);
  p.fem = "leapfrog";
  TL_TEST_ASSERT(tl_wave_create(&p, &w) != TL_OK && w == NULL, "unknown stepper refused");
  TL_TEST_ASSERT(strstr(tl_error_message(), "leapfrog") != NULL, "message names the stepper: %s", tl_error_message());
}

int main(void)
{
  if (tl_initialize() != TL_OK) {
    fprintf(stderr, "%s\n", tl_error_message());
    return 1;
  }
  test_mass_and_balance(1, "central_difference");
  test_mass_and_balance(0, "central_difference");
  test_mass_and_balance(1, "newmark");
  test_spring_conserves();
  test_divergence_stops();
  test_width_beyond_range();
  test_restart(TL_WAVE_PAPER, 0.0, "central_difference");
  test_restart(TL_WAVE_PAPER, 0.6, "central_difference");
  test_restart(TL_WAVE_SPRING, 0.0, "central_difference");
  test_restart(TL_WAVE_PAPER, 0.0, "newmark");
  test_bad_params();
  return tl_test_report();
}
