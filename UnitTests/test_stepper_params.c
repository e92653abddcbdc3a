/* The steppers' parameter tables and TlStepperOptions are one: the default
 * options equal every table's defaults field by field (read here from the
 * struct directly, not through the tables' offsets), every numeric field is
 * in some table, two tables that share a field agree on its default, the
 * defaults are the documented values, and settings by name and
 * tl_stepper_create refuse what the tables' ranges refuse. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_init.h"
#include "tl_registry.h"
#include "tl_spring_chain.h"
#include "tl_stepper.h"
#include "tl_test.h"

/* Every numeric field of TlStepperOptions by name, read from the struct. */
static int field(const TlStepperOptions *o, const char *name, double *v)
{
#define F(x)                                                                                                      \
  if (!strcmp(name, #x)) return (*v = (double)o->x), 1;
  F(beta) F(gamma) F(rtol) F(atol) F(max_iterations) F(reuse) F(keep_factors) F(line_search) F(nonlinear_solver)
  F(lumped) F(predictor) F(allow_unstable) F(blowup) F(critical_bound) F(ramp_time) F(max_cuts) F(convergence)
  F(ratio_tol) F(ratio_tol_post) F(accept_loose_after) F(peak_drop) F(ratio_diverge)
#undef F
  return 0;
}
static const char *const all_fields[] = {
    "beta", "gamma", "rtol", "atol", "max_iterations", "reuse", "keep_factors", "line_search", "nonlinear_solver",
    "lumped", "predictor", "allow_unstable", "blowup", "critical_bound", "ramp_time", "max_cuts", "convergence",
    "ratio_tol", "ratio_tol_post", "accept_loose_after", "peak_drop", "ratio_diverge"};

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TlStepperOptions o;
  memset(&o, 0x5a, sizeof o); /* the defaults must set every field */
  tl_stepper_options_default(&o);
  TL_TEST_ASSERT(o.solver == NULL, "default solver NULL");

  /* each registered stepper's table against the struct */
  size_t n_types = 0;
  int covered[sizeof all_fields / sizeof all_fields[0]] = {0};
  for (const TlTypeEntry *e; (e = tl_registry_entry("stepper", n_types)); ++n_types) {
    TL_TEST_ASSERT(e->n_params > 0, "stepper %s lists its parameters", e->name);
    for (int k = 0; k < e->n_params; ++k) {
      const TlParam *p = &e->params[k];
      double v = NAN;
      TL_TEST_ASSERT(field(&o, p->name, &v), "%s.%s is a TlStepperOptions field", e->name, p->name);
      TL_TEST_ASSERT(v == p->def, "%s.%s: default struct %g, table %g", e->name, p->name, v, p->def);
      TL_TEST_ASSERT(p->lo <= p->def && p->def <= p->hi, "%s.%s: default inside [%g, %g]", e->name, p->name, p->lo,
                     p->hi);
      TL_TEST_ASSERT(p->unit && p->unit[0] && p->help && p->help[0], "%s.%s: unit and help", e->name, p->name);
      for (size_t j = 0; j < sizeof all_fields / sizeof all_fields[0]; ++j) covered[j] += !strcmp(all_fields[j], p->name);
    }
  }
  TL_TEST_ASSERT(n_types == 3, "3 steppers registered (%zu)", n_types);
  for (size_t j = 0; j < sizeof all_fields / sizeof all_fields[0]; ++j)
    TL_TEST_ASSERT(covered[j] >= 1, "field %s is described by a stepper's table", all_fields[j]);

  /* the documented defaults (tl_stepper.h) */
  TL_TEST_ASSERT(o.beta == 0.25 && o.gamma == 0.5, "Newmark 1/4, 1/2");
  TL_TEST_ASSERT(o.rtol == 1e-10 && o.atol == 1e-14 && o.max_iterations == 30 && o.reuse == 1, "Newton");
  TL_TEST_ASSERT(o.nonlinear_solver == TL_NEWTON_KINSOL && o.predictor == TL_PREDICTOR_AUTO, "KINSOL, AUTO");
  TL_TEST_ASSERT(o.blowup == 1e6 && o.max_cuts == 10 && o.convergence == TL_CONVERGENCE_RESIDUAL, "explicit, static");
  TL_TEST_ASSERT(o.ratio_tol == 1e-3 && o.ratio_tol_post == 1e-2 && o.peak_drop == -1.0 && o.ratio_diverge == 10.0,
                 "force ratio");

  /* settings by name: the type's table, its ranges, whole values */
  TL_TEST_STATUS(tl_stepper_options_set(&o, "newmark", "max_iterations", 12), TL_OK);
  TL_TEST_ASSERT(o.max_iterations == 12, "max_iterations set (%ld)", o.max_iterations);
  TL_TEST_STATUS(tl_stepper_options_set(&o, "quasi_static", "ramp_time", 0.5), TL_OK);
  TL_TEST_ASSERT(o.ramp_time == 0.5, "ramp_time set");
  double got = 0;
  TL_TEST_STATUS(tl_stepper_options_get(&o, "max_iterations", &got), TL_OK);
  TL_TEST_ASSERT(got == 12, "get %g", got);
  TL_TEST_STATUS(tl_stepper_options_set(&o, "central_difference", "beta", 0.3), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(strstr(tl_error_message(), "'beta'") && strstr(tl_error_message(), "blowup"),
                 "names the setting and the type's settings: %s", tl_error_message());
  TL_TEST_STATUS(tl_stepper_options_set(&o, "newmark", "beta", 0.7), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "0.7") && strstr(tl_error_message(), "0.5"), "value and limit: %s",
                 tl_error_message());
  TL_TEST_STATUS(tl_stepper_options_set(&o, "newmark", "max_iterations", 2.5), TL_ERR_ARG);
  TL_TEST_STATUS(tl_stepper_options_set(&o, "newmark", "rtol", NAN), TL_ERR_ARG);
  TL_TEST_STATUS(tl_stepper_options_set(&o, "no_such_stepper", "rtol", 1e-8), TL_ERR_NOT_FOUND);
  TL_TEST_STATUS(tl_stepper_options_get(&o, "solver", &got), TL_ERR_NOT_FOUND);

  /* tl_stepper_create checks the type's ranges of a struct filled by hand */
  TlSpringChainParams cp = {.n = 4, .mass = 1.0, .k = 10.0};
  TlMechSystem *sys = NULL;
  TL_TEST_STATUS(tl_spring_chain_create(&cp, &sys), TL_OK);
  TlStepper *st = NULL;
  tl_stepper_options_default(&o);
  o.keep_factors = 2;
  TL_TEST_STATUS(tl_stepper_create("newmark", sys, &o, &st), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "keep_factors = 2"), "names the field: %s", tl_error_message());
  TL_TEST_STATUS(tl_stepper_create("central_difference", sys, &o, &st), TL_OK); /* it reads no keep_factors */
  tl_stepper_destroy(&st);
  tl_stepper_options_default(&o);
  TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, &o, &st), TL_OK);
  tl_stepper_destroy(&st);
  tl_mech_system_destroy(&sys);
  return tl_test_report();
}
