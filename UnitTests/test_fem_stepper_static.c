/* Quasi-static Newton (KINSOL) on the nonlinear spring chain: exact
 * equilibria with each linear solver, non-symmetric loads, prescribed
 * dofs, modified Newton, load stepping, and a Newton failure
 * that reports its residual history and leaves the state untouched. */
#include <math.h>
#include <string.h>

#include "tl_spring_chain.h"
#include "tl_stepper.h"
#include "tl_test.h"

static double max_error_linear(const TlStepper *st, double delta)
{
  double e = 0;
  for (TlSparseIndex i = 0; i < st->n; ++i) e = fmax(e, fabs(st->u[i] - (double)(i + 1) * delta));
  return e;
}

int main(void)
{
  TlSpringChainParams p;
  tl_spring_chain_params_default(&p);
  p.n = 20;
  p.alpha = 1.0;
  p.tip_force = 2.0; /* d + d^3 = 2: every spring stretches by exactly 1 */
  const char *solvers[3] = {"cholmod", "klu", "umfpack"};
  for (int s = 0; s < 3; ++s) {
    TlMechSystem *sys = NULL;
    TlStepper *st = NULL;
    TlStepperOptions o;
    tl_stepper_options_default(&o);
    o.solver = solvers[s];
    o.rtol = 1e-12;
    TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
    TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, &o, &st), TL_OK);
    if (!st) continue;
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
    TL_TEST_STATUS(tl_stepper_step(st, 1.0), TL_OK);
    TL_TEST_ASSERT(max_error_linear(st, 1.0) < 1e-10, "%s: error %g", solvers[s],
                   max_error_linear(st, 1.0));
    /* Energy: strain = n (1/2 + 1/4); external work by the trapezoidal rule
     * over one load jump is F * u_tip / 2 ... for a dead load applied at
     * once the rule is exact only for the final product; check the strain. */
    TlEnergies e;
    TL_TEST_STATUS(tl_stepper_energies(st, &e), TL_OK);
    TL_TEST_CLOSE(e.strain, 20.0 * 0.75, 1e-10);
    TlStepperStats ss;
    tl_stepper_get_stats(st, &ss);
    TL_TEST_ASSERT(ss.newton_iterations >= 3 && ss.newton_iterations < 30,
                   "%s: %ld Newton iterations", solvers[s], ss.newton_iterations);
    tl_stepper_destroy(&st);
    tl_mech_system_destroy(&sys);
    TL_TEST_ASSERT(sys == NULL && st == NULL, "destroy nulls");
  }

  /* Load stepping: ramp over 10 increments; work integrated along the path
   * approaches the strain energy (the trapezoidal error shrinks as h^2). */
  {
    TlMechSystem *sys = NULL;
    TlStepper *st = NULL;
    TlStepperOptions o;
    tl_stepper_options_default(&o);
    o.ramp_time = 1.0;
    TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
    TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, &o, &st), TL_OK);
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
    double mid_error = 0;
    for (int k = 0; k < 10; ++k) {
      TL_TEST_STATUS(tl_stepper_step(st, 0.1), TL_OK);
      if (k == 4) { /* lambda = 1/2: force 1, d + d^3 = 1 */
        double d = 0.6823278038280193;
        mid_error = max_error_linear(st, d);
      }
    }
    TL_TEST_ASSERT(mid_error < 1e-9, "half load error %g", mid_error);
    TL_TEST_ASSERT(max_error_linear(st, 1.0) < 1e-9, "full load error %g", max_error_linear(st, 1.0));
    TlEnergies e;
    TL_TEST_STATUS(tl_stepper_energies(st, &e), TL_OK);
    TL_TEST_ASSERT(fabs(e.external_work - e.strain) < 0.01 * e.strain,
                   "work %g vs strain energy %g", e.external_work, e.strain);
    tl_stepper_destroy(&st);
    tl_mech_system_destroy(&sys);
  }

  /* Non-symmetric load f_tip = 1.5 + 0.5 u_0: d^3 + 0.5 d = 1.5, d = 1.
   * CHOLMOD is refused for it; KLU and UMFPACK solve it. */
  {
    TlSpringChainParams q = p;
    q.tip_force = 1.5;
    q.kf = 0.5;
    TlMechSystem *sys = NULL;
    TlStepper *st = NULL;
    TlStepperOptions o;
    tl_stepper_options_default(&o);
    TL_TEST_STATUS(tl_spring_chain_create(&q, &sys), TL_OK);
    o.solver = "cholmod";
    TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, &o, &st), TL_ERR_ARG);
    for (int s = 1; s < 3; ++s) {
      o.solver = solvers[s];
      TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, &o, &st), TL_OK);
      TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
      TL_TEST_STATUS(tl_stepper_step(st, 1.0), TL_OK);
      TL_TEST_ASSERT(max_error_linear(st, 1.0) < 1e-9, "%s non-symmetric error %g", solvers[s],
                     max_error_linear(st, 1.0));
      tl_stepper_destroy(&st);
    }
    tl_mech_system_destroy(&sys);
  }

  /* Prescribed tip u = 2 t: uniform stretch 2 t / n. */
  {
    TlSpringChainParams q = p;
    q.tip_force = 0.0;
    q.prescribed_tip = 1;
    q.tip_velocity = 2.0;
    TlMechSystem *sys = NULL;
    TlStepper *st = NULL;
    TL_TEST_STATUS(tl_spring_chain_create(&q, &sys), TL_OK);
    TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, NULL, &st), TL_OK);
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
    TL_TEST_STATUS(tl_stepper_step(st, 0.5), TL_OK);
    TL_TEST_STATUS(tl_stepper_step(st, 0.5), TL_OK);
    TL_TEST_ASSERT(max_error_linear(st, 2.0 / 20.0) < 1e-9, "prescribed error %g",
                   max_error_linear(st, 0.1));
    tl_stepper_destroy(&st);
    tl_mech_system_destroy(&sys);
  }

  /* Modified Newton: same answer, fewer factorisations, more iterations. */
  {
    long it[2], fac[2];
    double err[2];
    for (int r = 0; r < 2; ++r) {
      TlMechSystem *sys = NULL;
      TlStepper *st = NULL;
      TlStepperOptions o;
      tl_stepper_options_default(&o);
      o.reuse = r ? 50 : 1;
      o.max_iterations = 200;
      o.ramp_time = 1.0;
      TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
      TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, &o, &st), TL_OK);
      TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
      for (int k = 0; k < 10; ++k) TL_TEST_STATUS(tl_stepper_step(st, 0.1), TL_OK);
      TlStepperStats ss;
      tl_stepper_get_stats(st, &ss);
      it[r] = ss.newton_iterations;
      fac[r] = ss.factorisations;
      err[r] = max_error_linear(st, 1.0);
      tl_stepper_destroy(&st);
      tl_mech_system_destroy(&sys);
    }
    TL_TEST_ASSERT(err[0] < 1e-9 && err[1] < 1e-9, "errors full %g modified %g", err[0], err[1]);
    TL_TEST_ASSERT(fac[1] < fac[0] && it[1] > it[0],
                   "full Newton %ld its / %ld factorisations; modified %ld / %ld", it[0], fac[0],
                   it[1], fac[1]);
    printf("full Newton: %ld iterations, %ld factorisations; modified: %ld, %ld\n", it[0], fac[0],
           it[1], fac[1]);
  }

  /* A load beyond the softening chain's limit force (s_max = 2/(3 sqrt 3) =
   * 0.385): Newton fails, the message carries the residual history, the
   * state stays at the last equilibrium with no NaN. */
  {
    TlSpringChainParams q = p;
    q.alpha = -1.0;
    q.tip_force = 1.0;
    TlMechSystem *sys = NULL;
    TlStepper *st = NULL;
    TlStepperOptions o;
    tl_stepper_options_default(&o);
    o.max_cuts = 2;
    o.max_iterations = 20;
    TL_TEST_STATUS(tl_spring_chain_create(&q, &sys), TL_OK);
    TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, &o, &st), TL_OK);
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
    TlStatus s = tl_stepper_step(st, 1.0);
    TL_TEST_ASSERT(s == TL_ERR_CONVERGENCE || s == TL_ERR_NUMERIC, "status %d: %s", (int)s,
                   tl_error_message());
    TL_TEST_ASSERT(strstr(tl_error_message(), "residual history") != NULL, "message: %s",
                   tl_error_message());
    TL_TEST_ASSERT(strstr(tl_error_message(), "halvings") != NULL, "message: %s",
                   tl_error_message());
    int clean = 1;
    for (TlSparseIndex i = 0; i < st->n; ++i)
      if (st->u[i] != 0.0 || !isfinite(st->u[i])) clean = 0;
    TL_TEST_ASSERT(clean && st->t == 0.0, "state restored after the failure (t = %g)", st->t);
    tl_stepper_destroy(&st);
    tl_mech_system_destroy(&sys);
  }

  /* Bad options are refused with the value. */
  {
    TlMechSystem *sys = NULL;
    TlStepper *st = NULL;
    TlStepperOptions o;
    tl_stepper_options_default(&o);
    o.beta = 0.7;
    TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
    TL_TEST_STATUS(tl_stepper_create("newmark", sys, &o, &st), TL_ERR_ARG);
    TL_TEST_ASSERT(strstr(tl_error_message(), "0.7") != NULL, "%s", tl_error_message());
    TL_TEST_STATUS(tl_stepper_create("runge_kutta", sys, NULL, &st), TL_ERR_NOT_FOUND);
    tl_mech_system_destroy(&sys);
  }
  return tl_test_report();
}
