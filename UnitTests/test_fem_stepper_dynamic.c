/* Newmark and central difference on the spring chain: energy conservation
 * of the average-acceleration rule, second-order accuracy against the
 * exact harmonic oscillator, the consistent-mass path, damping, and the
 * explicit critical step against the chain's exact highest frequency
 * (stable just below, refused and then blowing up just above). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_spring_chain.h"
#include "tl_stepper.h"
#include "tl_test.h"

static const double PI = 3.14159265358979323846;

/* Max relative energy deviation over `steps` Newmark steps. */
static TlStatus newmark_energy_drift(const TlSpringChainParams *p, double dt, int steps,
                                     const TlStepperOptions *o, double *drift)
{
  TlMechSystem *sys = NULL;
  TlStepper *st = NULL;
  TL_CHECK(tl_spring_chain_create(p, &sys));
  TL_CHECK(tl_stepper_create("newmark", sys, o, &st));
  double u0[64];
  for (TlSparseIndex i = 0; i < p->n; ++i) u0[i] = 0.05 * (double)(i + 1) * (1.0 + 0.3 * sin((double)i));
  TL_CHECK(tl_stepper_set_state(st, 0.0, u0, NULL));
  TlEnergies e0, e;
  TL_CHECK(tl_stepper_energies(st, &e0));
  double d = 0;
  for (int k = 0; k < steps; ++k) {
    TL_CHECK(tl_stepper_step(st, dt));
    TL_CHECK(tl_stepper_energies(st, &e));
    d = fmax(d, fabs(e.total - e0.total) / e0.total);
  }
  *drift = d;
  tl_stepper_destroy(&st);
  tl_mech_system_destroy(&sys);
  return TL_OK;
}

int main(void)
{
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  o.rtol = 1e-13;

  /* Linear chain: the trapezoidal rule conserves energy exactly, so over a
   * period of the fundamental (omega_1 = 2 sin(pi/42) for n = 10) the drift
   * is Newton-tolerance small; likewise with the consistent mass. */
  TlSpringChainParams p;
  tl_spring_chain_params_default(&p);
  p.n = 10;
  double T1 = 2.0 * PI / (2.0 * sin(PI / 42.0));
  double drift = 1;
  TL_TEST_STATUS(newmark_energy_drift(&p, T1 / 100.0, 100, &o, &drift), TL_OK);
  TL_TEST_ASSERT(drift < 1e-10, "linear chain, lumped mass: energy drift %g per period", drift);
  printf("Newmark linear lumped: drift %.3e per period\n", drift);
  p.consistent_mass = 1;
  TL_TEST_STATUS(newmark_energy_drift(&p, T1 / 100.0, 100, &o, &drift), TL_OK);
  TL_TEST_ASSERT(drift < 1e-10, "linear chain, consistent mass: energy drift %g per period", drift);
  printf("Newmark linear consistent: drift %.3e per period\n", drift);
  p.consistent_mass = 0;

  /* Nonlinear (hardening) chain: the rule is no longer exactly
   * conservative; the drift is bounded and falls as dt^2. */
  p.alpha = 5.0;
  double d1 = 1, d2 = 1;
  TL_TEST_STATUS(newmark_energy_drift(&p, T1 / 100.0, 100, &o, &d1), TL_OK);
  TL_TEST_STATUS(newmark_energy_drift(&p, T1 / 200.0, 200, &o, &d2), TL_OK);
  TL_TEST_ASSERT(d1 < 5e-3 && d2 < d1 / 3.0, "nonlinear drift %g (dt) %g (dt/2)", d1, d2);
  printf("Newmark nonlinear: drift %.3e (dt), %.3e (dt/2)\n", d1, d2);
  p.alpha = 0.0;

  /* Harmonic oscillator m = k = 1, u(0) = 1: the error at t = 2 pi falls
   * by 4 when dt halves (second order), for Newmark and central difference. */
  const char *types[2] = {"newmark", "central_difference"};
  for (int s = 0; s < 2; ++s) {
    double err[2];
    for (int r = 0; r < 2; ++r) {
      TlSpringChainParams q;
      tl_spring_chain_params_default(&q);
      q.n = 1;
      TlMechSystem *sys = NULL;
      TlStepper *st = NULL;
      TL_TEST_STATUS(tl_spring_chain_create(&q, &sys), TL_OK);
      TL_TEST_STATUS(tl_stepper_create(types[s], sys, &o, &st), TL_OK);
      double u0 = 1.0;
      TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, &u0, NULL), TL_OK);
      int steps = r ? 400 : 200;
      for (int k = 0; k < steps; ++k) TL_TEST_STATUS(tl_stepper_step(st, 2.0 * PI / steps), TL_OK);
      err[r] = fabs(st->u[0] - 1.0) + fabs(st->v[0]);
      tl_stepper_destroy(&st);
      tl_mech_system_destroy(&sys);
    }
    double ratio = err[0] / err[1];
    TL_TEST_ASSERT(ratio > 3.6 && ratio < 4.4, "%s: errors %g, %g, ratio %g", types[s], err[0],
                   err[1], ratio);
    printf("%s oscillator: error %.3e -> %.3e (ratio %.2f)\n", types[s], err[0], err[1], ratio);
  }

  /* Factorisation reuse across steps (modified Newton): the same answer as
   * full Newton with far fewer factorisations. */
  {
    TlSpringChainParams q = p;
    q.alpha = 1.0;
    double u_end[2][10];
    long fac[2], its[2];
    for (int r = 0; r < 2; ++r) {
      TlMechSystem *sys = NULL;
      TlStepper *st = NULL;
      TlStepperOptions m = o;
      m.rtol = 1e-12;
      m.reuse = r ? 30 : 1;
      m.keep_factors = r;
      m.max_iterations = 200;
      TL_TEST_STATUS(tl_spring_chain_create(&q, &sys), TL_OK);
      TL_TEST_STATUS(tl_stepper_create("newmark", sys, &m, &st), TL_OK);
      double v0[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0.2};
      TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, v0), TL_OK);
      for (int k = 0; k < 100; ++k) TL_TEST_STATUS(tl_stepper_step(st, T1 / 100.0), TL_OK);
      TlStepperStats ss;
      tl_stepper_get_stats(st, &ss);
      fac[r] = ss.factorisations;
      its[r] = ss.newton_iterations;
      memcpy(u_end[r], st->u, sizeof u_end[r]);
      tl_stepper_destroy(&st);
      tl_mech_system_destroy(&sys);
    }
    double diff = 0;
    for (int i = 0; i < 10; ++i) diff = fmax(diff, fabs(u_end[0][i] - u_end[1][i]));
    TL_TEST_ASSERT(diff < 1e-9 && fac[1] * 5 < fac[0],
                   "reuse: |du| %g, factorisations %ld vs %ld", diff, fac[1], fac[0]);
    printf("Newmark 100 steps: full Newton %ld iterations / %ld factorisations; kept factors %ld / %ld\n",
           its[0], fac[0], its[1], fac[1]);
  }

  /* Other (beta, gamma): gamma > 1/2 with beta = (gamma + 1/2)^2 / 4 damps
   * numerically, so the linear chain's energy falls and never rises. */
  {
    TlStepperOptions m = o;
    m.gamma = 0.6;
    m.beta = 0.3025;
    TlMechSystem *sys = NULL;
    TlStepper *st = NULL;
    TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
    TL_TEST_STATUS(tl_stepper_create("newmark", sys, &m, &st), TL_OK);
    double u0[10];
    for (int i = 0; i < 10; ++i) u0[i] = 0.01 * (i % 2 ? 1.0 : -1.0);
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, u0, NULL), TL_OK);
    TlEnergies e;
    TL_TEST_STATUS(tl_stepper_energies(st, &e), TL_OK);
    double e0 = e.total, prev = e.total;
    int monotone = 1;
    for (int k = 0; k < 100; ++k) {
      TL_TEST_STATUS(tl_stepper_step(st, 0.5), TL_OK);
      TL_TEST_STATUS(tl_stepper_energies(st, &e), TL_OK);
      if (e.total > prev * (1 + 1e-12)) monotone = 0;
      prev = e.total;
    }
    TL_TEST_ASSERT(monotone && prev < 0.5 * e0, "beta 0.3025, gamma 0.6: energy %g from %g", prev, e0);
    tl_stepper_destroy(&st);
    tl_mech_system_destroy(&sys);
  }

  /* Damping: energy decreases every step. */
  {
    TlSpringChainParams q = p;
    q.c = 0.05;
    TlMechSystem *sys = NULL;
    TlStepper *st = NULL;
    TL_TEST_STATUS(tl_spring_chain_create(&q, &sys), TL_OK);
    TL_TEST_STATUS(tl_stepper_create("newmark", sys, &o, &st), TL_OK);
    double v0[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, v0), TL_OK);
    TlEnergies e;
    TL_TEST_STATUS(tl_stepper_energies(st, &e), TL_OK);
    double prev = e.total, e0 = e.total;
    int monotone = 1;
    for (int k = 0; k < 200; ++k) {
      TL_TEST_STATUS(tl_stepper_step(st, T1 / 50.0), TL_OK);
      TL_TEST_STATUS(tl_stepper_energies(st, &e), TL_OK);
      if (e.total > prev * (1 + 1e-12)) monotone = 0;
      prev = e.total;
    }
    TL_TEST_ASSERT(monotone && prev < 0.9 * e0, "damped energy %g from %g, monotone %d", prev, e0,
                   monotone);
    tl_stepper_destroy(&st);
    tl_mech_system_destroy(&sys);
  }

  /* Central difference: fixed-free chain, omega_max^2 = 4 k/m sin^2((2n-1) pi
   * / (4n+2)); the estimate matches, a step just below runs stable, a step
   * just above is refused (both numbers named), and when forced blows up. */
  {
    TlSpringChainParams q;
    tl_spring_chain_params_default(&q);
    q.n = 10;
    double w2 = 4.0 * pow(sin((2.0 * 10 - 1.0) * PI / (4.0 * 10 + 2.0)), 2);
    double dt_exact = 2.0 / sqrt(w2);
    TlMechSystem *sys = NULL;
    TlStepper *st = NULL;
    TL_TEST_STATUS(tl_spring_chain_create(&q, &sys), TL_OK);
    TL_TEST_STATUS(tl_stepper_create("central_difference", sys, NULL, &st), TL_OK);
    double u0[10];
    for (int i = 0; i < 10; ++i) u0[i] = 0.01 * (i % 2 ? 1.0 : -1.0) + 0.002 * i;
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, u0, NULL), TL_OK);
    TL_TEST_CLOSE(st->dt_crit, dt_exact, 1e-8);
    TlStatus s = TL_OK;
    double umax = 0;
    for (int k = 0; k < 20000 && s == TL_OK; ++k) {
      s = tl_stepper_step(st, 0.99 * dt_exact);
      for (int i = 0; i < 10; ++i) umax = fmax(umax, fabs(st->u[i]));
    }
    TL_TEST_ASSERT(s == TL_OK && umax < 1.0, "0.99 dt_crit: status %d, max |u| %g", (int)s, umax);
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, u0, NULL), TL_OK);
    TL_TEST_STATUS(tl_stepper_step(st, 1.01 * dt_exact), TL_ERR_UNSTABLE);
    char crit[64];
    snprintf(crit, sizeof crit, "%.6g", dt_exact);
    TL_TEST_ASSERT(strstr(tl_error_message(), crit) != NULL, "message names %s: %s", crit,
                   tl_error_message());
    tl_stepper_destroy(&st);
    TlStepperOptions f;
    tl_stepper_options_default(&f);
    f.allow_unstable = 1;
    TL_TEST_STATUS(tl_stepper_create("central_difference", sys, &f, &st), TL_OK);
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, u0, NULL), TL_OK);
    s = TL_OK;
    int k = 0;
    for (; k < 20000 && s == TL_OK; ++k) s = tl_stepper_step(st, 1.01 * dt_exact);
    TL_TEST_ASSERT(s == TL_ERR_UNSTABLE && strstr(tl_error_message(), "blow-up") != NULL,
                   "1.01 dt_crit: status %d after %d steps: %s", (int)s, k, tl_error_message());
    int finite = 1;
    for (int i = 0; i < 10; ++i) finite &= isfinite(st->u[i]);
    TL_TEST_ASSERT(finite, "state kept finite after the blow-up stop");
    printf("central difference: dt_crit %.9g (exact %.9g); blow-up after %d steps at 1.01 dt_crit\n",
           st->dt_crit, dt_exact, k);
    tl_stepper_destroy(&st);
    tl_mech_system_destroy(&sys);
  }
  return tl_test_report();
}
