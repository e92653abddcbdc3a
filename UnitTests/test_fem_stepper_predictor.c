/* Newmark's predictors and the reuse of kept factors across steps.
 *
 * The cantilever of S1 (10 cells) under a suddenly applied tip load:
 *  - a step resolving every mode (omega_max dt <= 1): the Taylor predictor
 *    and the last displacement reach the same solution to the Newton
 *    tolerance, Taylor in fewer iterations, and AUTO takes Taylor;
 *  - a step leaving modes unresolved (omega_max dt >> 1): AUTO takes the
 *    last displacement (the same iterations and solution bit for bit);
 *  - with keep_factors and reuse = k, fresh factors come every k
 *    iterations across steps, not once for the whole run. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_cantilever.h"
#include "tl_stepper.h"
#include "tl_test.h"

typedef struct {
  double tip;       /* tip deflection at the end (m) */
  double umax;      /* largest |u| (m) */
  double *u;        /* final dofs (caller frees) */
  size_t n;         /* their number */
  long iterations, factorisations, steps;
  double omega2dt2; /* the bound's omega_max^2 dt^2 */
} Run;

static TlStatus run(int predictor, double dt_over_period, int steps, long reuse, Run *out)
{
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.ny = 10;
  TlCantilever *c = NULL;
  TlStepper *st = NULL;
  TL_CHECK(tl_cantilever_create(&p, &c));
  c->load_scale = 1.0;
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  o.predictor = predictor;
  o.reuse = reuse;
  o.keep_factors = reuse > 1;
  o.max_iterations = 100;
  TL_CHECK(tl_stepper_create("newmark", tl_solid_system(c->solid), &o, &st));
  TL_CHECK(tl_stepper_set_state(st, 0.0, NULL, NULL));
  const double dt = dt_over_period * 2.0 * M_PI / tl_cantilever_omega1(&p);
  for (int k = 0; k < steps; ++k) TL_CHECK(tl_stepper_step(st, dt));
  double tip[3];
  tl_cantilever_tip(c, st->u, tip);
  out->tip = tip[2];
  out->umax = 0.0;
  for (TlSparseIndex i = 0; i < st->n; ++i) out->umax = fmax(out->umax, fabs(st->u[i]));
  TL_CHECK(tl_calloc(&out->u, (size_t)st->n, sizeof *out->u));
  memcpy(out->u, st->u, (size_t)st->n * sizeof *out->u);
  out->n = (size_t)st->n;
  TlStepperStats s;
  tl_stepper_get_stats(st, &s);
  out->iterations = s.newton_iterations;
  out->factorisations = s.factorisations;
  out->steps = s.steps;
  out->omega2dt2 = st->omega2_bound * dt * dt;
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&c);
  return TL_OK;
}

static double max_diff(const Run *a, const Run *b)
{
  if (a->n != b->n) return INFINITY;
  double d = 0.0;
  for (size_t i = 0; i < a->n; ++i) d = fmax(d, fabs(a->u[i] - b->u[i]));
  return d;
}

int main(void)
{
  omp_set_num_threads(1);
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  /* Resolved: dt = T1 / 20000 on a 10-cell beam gives omega_max dt < 1. */
  Run last = {0}, taylor = {0}, autop = {0};
  TL_TEST_STATUS(run(TL_PREDICTOR_LAST, 5e-5, 200, 1, &last), TL_OK);
  TL_TEST_STATUS(run(TL_PREDICTOR_TAYLOR, 5e-5, 200, 1, &taylor), TL_OK);
  TL_TEST_STATUS(run(TL_PREDICTOR_AUTO, 5e-5, 200, 1, &autop), TL_OK);
  printf("resolved (omega_max^2 dt^2 = %.3g): iterations last %ld, taylor %ld, auto %ld; tip %.9g / %.9g m, "
         "largest difference %.3g m (|u| %.3g m)\n",
         autop.omega2dt2, last.iterations, taylor.iterations, autop.iterations, last.tip, taylor.tip,
         max_diff(&last, &taylor), last.umax);
  TL_TEST_ASSERT(autop.omega2dt2 > 0.0 && autop.omega2dt2 <= 1.0, "the step resolves every mode (%g)", autop.omega2dt2);
  TL_TEST_ASSERT(last.umax > 1e-6, "the load moved the beam (%g m)", last.umax);
  TL_TEST_ASSERT(max_diff(&last, &taylor) <= 1e-9 * last.umax, "predictors reach different solutions (%g m)",
                 max_diff(&last, &taylor));
  TL_TEST_ASSERT(taylor.iterations < last.iterations, "Taylor takes %ld iterations, the last displacement %ld",
                 taylor.iterations, last.iterations);
  TL_TEST_ASSERT(autop.iterations == taylor.iterations && max_diff(&autop, &taylor) == 0.0,
                 "AUTO did not take the Taylor predictor on a resolved step");

  /* Unresolved: dt = T1 / 20 leaves the element modes with omega dt >> 1. */
  Run last2 = {0}, auto2 = {0};
  TL_TEST_STATUS(run(TL_PREDICTOR_LAST, 0.05, 20, 1, &last2), TL_OK);
  TL_TEST_STATUS(run(TL_PREDICTOR_AUTO, 0.05, 20, 1, &auto2), TL_OK);
  printf("unresolved (omega_max^2 dt^2 = %.3g): iterations last %ld, auto %ld\n", auto2.omega2dt2,
         last2.iterations, auto2.iterations);
  TL_TEST_ASSERT(auto2.omega2dt2 > 1.0, "the coarse step leaves modes unresolved (%g)", auto2.omega2dt2);
  TL_TEST_ASSERT(auto2.iterations == last2.iterations && max_diff(&auto2, &last2) == 0.0,
                 "AUTO did not take the last displacement on an unresolved step");

  /* Kept factors renewed every `reuse` iterations across steps. */
  Run kept = {0};
  TL_TEST_STATUS(run(TL_PREDICTOR_AUTO, 5e-5, 200, 10, &kept), TL_OK);
  printf("keep factors, reuse 10: %ld iterations, %ld factorisations in %ld steps; largest difference %.3g m\n",
         kept.iterations, kept.factorisations, kept.steps, max_diff(&kept, &taylor));
  /* a solve started on factors with 9 iterations served may take a few more */
  TL_TEST_ASSERT(kept.factorisations >= kept.iterations / 15 && kept.factorisations <= kept.iterations / 10 + 2,
                 "%ld factorisations for %ld iterations with reuse 10", kept.factorisations, kept.iterations);
  TL_TEST_ASSERT(max_diff(&kept, &taylor) <= 1e-9 * taylor.umax, "kept factors change the solution (%g m)",
                 max_diff(&kept, &taylor));
  Run *all[] = {&last, &taylor, &autop, &last2, &auto2, &kept};
  for (size_t k = 0; k < sizeof all / sizeof *all; ++k) tl_free(&all[k]->u);
  return tl_test_report();
}
