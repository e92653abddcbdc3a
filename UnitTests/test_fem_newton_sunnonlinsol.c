/* Newton through SUNNonlinSol_Newton with CVODE's test on the correction
 * (TL_NEWTON_SUNNONLINSOL) against the KINSOL path:
 *  - a nonlinear algebraic system solved again and again with kept (stale)
 *    factors: every answer's true residual, evaluated here, is within ftol
 *    although the solver never evaluated it; the rate estimate forces extra
 *    iterations when the factors are stale; one residual evaluation fewer
 *    per solve than KINSOL;
 *  - Newmark trajectories (nonlinear spring chain, the S1 beam with the
 *    consistent mass) equal to KINSOL's to within the Newton tolerance, over
 *    many steps with kept factors, at fewer residual evaluations;
 *  - a diverging iteration fails with the diagnosis and both histories,
 *    and a Newmark step that cannot converge is rolled back. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_mesh.h"
#include "tl_newton.h"
#include "tl_solid.h"
#include "tl_spring_chain.h"
#include "tl_stepper.h"
#include "tl_test.h"

/* ------------------------------------------- an algebraic system
 * F(x) = A x + beta x^3 - b, A = tridiag(-1, 4, -1): symmetric positive
 * definite tangent A + 3 beta diag(x^2). */
enum { N = 20 };

typedef struct {
  double beta, b[N];
  long evaluations;
} Cubic;

static TlStatus cubic_residual(void *ctx, const double *x, double *r)
{
  Cubic *c = ctx;
  c->evaluations++;
  for (int i = 0; i < N; ++i) {
    double v = 4.0 * x[i] + c->beta * x[i] * x[i] * x[i] - c->b[i];
    if (i > 0) v -= x[i - 1];
    if (i < N - 1) v -= x[i + 1];
    r[i] = v;
  }
  return TL_OK;
}

static TlStatus cubic_jacobian(void *ctx, const double *x, TlSparse *J)
{
  Cubic *c = ctx;
  for (int i = 0; i < N; ++i) {
    TL_CHECK(tl_sparse_add(J, i, i, 4.0 + 3.0 * c->beta * x[i] * x[i]));
    if (i < N - 1) TL_CHECK(tl_sparse_add(J, i, i + 1, -1.0));
  }
  return TL_OK;
}

static double cubic_norm(Cubic *c, const double *x)
{
  double r[N], m = 0.0;
  cubic_residual(c, x, r);
  c->evaluations--;
  for (int i = 0; i < N; ++i) m = fmax(m, fabs(r[i]));
  return m;
}

static TlStatus cubic_pattern(TlSparse **J)
{
  TlSparseIndex ptr[N], dofs[2 * (N - 1)];
  for (int e = 0; e < N - 1; ++e) {
    ptr[e] = 2 * e;
    dofs[2 * e] = e;
    dofs[2 * e + 1] = e + 1;
  }
  ptr[N - 1] = 2 * (N - 1);
  return tl_sparse_create_from_elements(N, 1, N - 1, ptr, dofs, 0, J);
}

/* 40 solves with slowly changing b from the last answer, factors kept for
 * up to 1000 iterations: the load path of an implicit time loop.  The
 * cubic term is weak against the linear one (3 beta x^2 / 4 ~ 2 %), so the
 * stale factors contract fast, as a mass-dominated Newmark tangent does. */
static void stale_factors(void)
{
  const double ftol = 1e-10;
  double x_end[2][N];
  long evaluations[2] = {0, 0}, iterations[2] = {0, 0}, most = 0;
  double worst = 0.0;
  for (int method = 0; method < 2; ++method) {
    Cubic c = {.beta = 0.1};
    TlSparse *J = NULL;
    TlNewton *nw = NULL;
    TL_TEST_STATUS(cubic_pattern(&J), TL_OK);
    TlNewtonOptions o;
    tl_newton_options_default(&o);
    o.method = method ? TL_NEWTON_SUNNONLINSOL : TL_NEWTON_KINSOL;
    o.ftol = ftol;
    o.max_setup_calls = 1000;
    o.keep_factors = 1;
    o.max_iterations = 100;
    TL_TEST_STATUS(tl_newton_create(N, J, "cholmod", &o, cubic_residual, cubic_jacobian, &c, &nw), TL_OK);
    if (!nw) return;
    double x[N] = {0};
    for (int k = 0; k < 40; ++k) {
      for (int i = 0; i < N; ++i) c.b[i] = (1.0 + 0.02 * k) * (1.0 + 0.5 * sin(0.7 * i));
      TL_TEST_STATUS(tl_newton_solve(nw, x), TL_OK);
      TlNewtonStats s;
      tl_newton_get_stats(nw, &s);
      if (method) {
        /* The answer's true residual, which the solver did not evaluate. */
        worst = fmax(worst, cubic_norm(&c, x));
        if (s.last_iterations > most) most = s.last_iterations;
      }
    }
    TlNewtonStats s;
    tl_newton_get_stats(nw, &s);
    evaluations[method] = c.evaluations;
    iterations[method] = s.iterations;
    if (method) {
      TL_TEST_ASSERT(s.linear.n_numeric == 1, "%ld factorisations for kept factors", s.linear.n_numeric);
      TL_TEST_ASSERT(tl_newton_convergence_rate(nw) < 0.3, "rate estimate %g after 40 solves",
                     tl_newton_convergence_rate(nw));
    }
    memcpy(x_end[method], x, sizeof x);
    tl_newton_destroy(&nw);
    tl_sparse_destroy(&J);
  }
  double diff = 0.0;
  for (int i = 0; i < N; ++i) diff = fmax(diff, fabs(x_end[0][i] - x_end[1][i]));
  printf("cubic system, 40 solves on one factorisation: KINSOL %ld iterations / %ld residuals, SUNNonlinSol %ld / "
         "%ld (at most %ld in a solve); true residual of the answers <= %.2e (ftol %.0e); |x_kinsol - x_sun| %.2e\n",
         iterations[0], evaluations[0], iterations[1], evaluations[1], most, worst, ftol, diff);
  TL_TEST_ASSERT(worst <= ftol, "an accepted answer has residual %g > ftol %g", worst, ftol);
  /* The rate test asked for more than one iteration with stale factors. */
  TL_TEST_ASSERT(most >= 2, "at most %ld iterations in a solve", most);
  /* One evaluation per iteration (the start's included, the answer's not),
   * where KINSOL also evaluates at the answer; the correction test, a bound,
   * may ask for an iteration more than the residual test. */
  TL_TEST_ASSERT(evaluations[1] == iterations[1] && evaluations[1] < evaluations[0],
                 "residual evaluations: KINSOL %ld, SUNNonlinSol %ld for %ld iterations", evaluations[0],
                 evaluations[1], iterations[1]);
  TL_TEST_ASSERT(diff <= 1e-10, "answers differ by %g", diff);
}

/* Newton on atan from x = 3 diverges (|x| > 1.39): the correction test
 * says so, with the histories; x is left at the last iterate. */
static TlStatus atan_residual(void *ctx, const double *x, double *r)
{
  (void)ctx;
  for (int i = 0; i < N; ++i) r[i] = atan(x[i]);
  return TL_OK;
}
static TlStatus atan_jacobian(void *ctx, const double *x, TlSparse *J)
{
  (void)ctx;
  for (int i = 0; i < N; ++i) TL_CHECK(tl_sparse_add(J, i, i, 1.0 / (1.0 + x[i] * x[i])));
  return TL_OK;
}

static void diverging(void)
{
  TlSparse *J = NULL;
  TlNewton *nw = NULL;
  TL_TEST_STATUS(cubic_pattern(&J), TL_OK);
  TlNewtonOptions o;
  tl_newton_options_default(&o);
  o.method = TL_NEWTON_SUNNONLINSOL;
  o.ftol = 1e-12;
  TL_TEST_STATUS(tl_newton_create(N, J, "cholmod", &o, atan_residual, atan_jacobian, NULL, &nw), TL_OK);
  if (!nw) return;
  double x[N];
  for (int i = 0; i < N; ++i) x[i] = 3.0;
  TL_TEST_STATUS(tl_newton_solve(nw, x), TL_ERR_CONVERGENCE);
  const char *msg = tl_error_message();
  printf("atan from 3: %s\n", msg);
  TL_TEST_ASSERT(strstr(msg, "corrections growing") && strstr(msg, "residual history") &&
                     strstr(msg, "corrections (max norm)"),
                 "diagnosis: %s", msg);
  const double *d = NULL;
  int nd = tl_newton_correction_history(nw, &d);
  TL_TEST_ASSERT(nd >= 2 && d[nd - 1] > 2.0 * d[nd - 2], "%d corrections, the last two %g, %g", nd,
                 nd >= 2 ? d[nd - 2] : 0.0, nd >= 1 ? d[nd - 1] : 0.0);
  TL_TEST_ASSERT(!tl_newton_has_factors(nw), "factors kept after a failure");
  /* A line search is KINSOL's alone. */
  o.line_search = 1;
  TL_TEST_STATUS(tl_newton_set_options(nw, &o), TL_ERR_ARG);
  tl_newton_destroy(&nw);
  tl_sparse_destroy(&J);
}

/* ------------------------------------------------ Newmark trajectories */
typedef struct {
  double u[4096];
  long residuals, iterations, solves, steps;
  double size;
} Run;

static TlStatus newmark_run(TlMechSystem *sys, const TlStepperOptions *o, const double *v0, double dt, int steps,
                            Run *r)
{
  TlStepper *st = NULL;
  TL_CHECK(tl_stepper_create("newmark", sys, o, &st));
  TlStatus s = tl_stepper_set_state(st, 0.0, NULL, v0);
  r->size = 0.0;
  for (int k = 0; k < steps && s == TL_OK; ++k) {
    s = tl_stepper_step(st, dt);
    for (TlSparseIndex i = 0; i < st->n && s == TL_OK; ++i) r->size = fmax(r->size, fabs(st->u[i]));
  }
  memcpy(r->u, st->u, (size_t)st->n * sizeof *st->u);
  TlStepperStats ss;
  tl_stepper_get_stats(st, &ss);
  r->residuals = ss.residual_evaluations;
  r->iterations = ss.newton_iterations;
  r->solves = ss.linear_solves;
  r->steps = ss.steps;
  tl_stepper_destroy(&st);
  return s;
}

static void compare(const char *what, TlMechSystem *sys, TlStepperOptions o, const double *v0, double dt, int steps,
                    double tol, int fewer_residuals)
{
  static Run r[2];
  for (int m = 0; m < 2; ++m) {
    o.nonlinear_solver = m ? TL_NEWTON_SUNNONLINSOL : TL_NEWTON_KINSOL;
    TL_TEST_STATUS(newmark_run(sys, &o, v0, dt, steps, &r[m]), TL_OK);
  }
  double diff = 0.0;
  for (TlSparseIndex i = 0; i < sys->ndof; ++i) diff = fmax(diff, fabs(r[0].u[i] - r[1].u[i]));
  printf("%s, %d steps: |u_kinsol - u_sun| = %.2e of |u| %.3g; per step KINSOL %.2f residuals, %.2f solves; "
         "SUNNonlinSol %.2f residuals, %.2f solves\n",
         what, steps, diff, r[0].size, (double)r[0].residuals / steps, (double)r[0].solves / steps,
         (double)r[1].residuals / steps, (double)r[1].solves / steps);
  TL_TEST_ASSERT(r[0].steps == steps && r[1].steps == steps, "%s: %ld and %ld steps", what, r[0].steps, r[1].steps);
  TL_TEST_ASSERT(r[0].size > 0.0 && diff <= tol * r[0].size, "%s: trajectories differ by %g (|u| %g, tol %g)", what,
                 diff, r[0].size, tol);
  if (fewer_residuals)
    TL_TEST_ASSERT(r[1].residuals < r[0].residuals, "%s: %ld residuals (SUNNonlinSol) vs %ld (KINSOL)", what,
                   r[1].residuals, r[0].residuals);
}

static void spring_chain(void)
{
  TlSpringChainParams p;
  tl_spring_chain_params_default(&p);
  p.n = 10;
  p.alpha = 1.0;
  TlMechSystem *sys = NULL;
  TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
  if (!sys) return;
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  o.rtol = 1e-12;
  o.reuse = 30;
  o.keep_factors = 1;
  o.max_iterations = 200;
  double v0[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0.2};
  double T1 = 2.0 * M_PI / (2.0 * sin(M_PI / 42.0));
  compare("nonlinear spring chain, kept factors (reuse 30)", sys, o, v0, T1 / 100.0, 300, 1e-9, 1);
  tl_mech_system_destroy(&sys);
}

/* The S1 beam (hex8 2 x 10 x 2, E = 100 MPa, nu = 0, clamped at y = 0),
 * released with a tip velocity of 1 m/s in a y^2 profile, consistent mass,
 * CHOLMOD, factors kept across steps as the S1 scene keeps them. */
static void beam(void)
{
  const double L = 12.0, E = 1e8, rho = 1309.0;
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  size_t n[3] = {2, 10, 2};
  double lo[3] = {-0.4, 0.0, -0.4}, hi[3] = {0.4, L, 0.4};
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &mesh), TL_OK);
  TL_TEST_STATUS(tl_material_create_hooke(E, 0.0, rho, &mat), TL_OK);
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  if (!mesh || !mat || !solid) return;
  TL_TEST_STATUS(tl_solid_set_material(solid, NULL, mat), TL_OK);
  TL_TEST_STATUS(tl_solid_fix(solid, "ymin", 7), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  TL_TEST_ASSERT(!sys->ops->commit, "an elastic solid offers a commit");
  double *v0 = calloc((size_t)sys->ndof, sizeof *v0);
  for (size_t a = 0; a < mesh->n_nodes; ++a) {
    double y = mesh->x[3 * a + 1] / L;
    TlSparseIndex d = tl_solid_dof(solid, a, 2);
    if (d >= 0) v0[d] = y * y;
  }
  double I = pow(0.8, 4) / 12.0;
  double T = 2 * M_PI / (1.875 * 1.875 * sqrt(E * I / (rho * 0.64 * pow(L, 4))));
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  o.reuse = 1000;
  o.keep_factors = 1;
  o.max_iterations = 200;
  /* A swing of 0.4 m on factors kept from the start: they contract
   * slowly, where the conservative correction test costs iterations. */
  compare("S1 beam, consistent mass, kept factors", sys, o, v0, T / 400.0, 200, 1e-9, 0);
  free(v0);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* A softening chain pulled beyond its strength: no equilibrium near the
 * start, Newton (KLU, the tangent turns indefinite) cannot converge in a
 * long step; the step is rejected, the state rolled back, and a short step
 * from there succeeds. */
static void rollback(void)
{
  TlSpringChainParams p;
  tl_spring_chain_params_default(&p);
  p.n = 4;
  p.alpha = -1.0;
  p.tip_force = 5.0;
  TlMechSystem *sys = NULL;
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  o.solver = "klu";
  o.nonlinear_solver = TL_NEWTON_SUNNONLINSOL;
  o.max_iterations = 40;
  TL_TEST_STATUS(tl_stepper_create("newmark", sys, &o, &st), TL_OK);
  if (!st) {
    tl_mech_system_destroy(&sys);
    return;
  }
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_stepper_step(st, 0.01), TL_OK);
  double u[4], v[4], t = st->t;
  memcpy(u, st->u, sizeof u);
  memcpy(v, st->v, sizeof v);
  TlStatus s = tl_stepper_step(st, 100.0);
  const char *msg = tl_error_message();
  printf("softening chain, dt = 100: %s\n", msg);
  TL_TEST_ASSERT(s == TL_ERR_CONVERGENCE || s == TL_ERR_NUMERIC, "status %d", (int)s);
  TL_TEST_ASSERT(strstr(msg, "residual history") && strstr(msg, "rejected"), "message: %s", msg);
  TL_TEST_ASSERT(memcmp(u, st->u, sizeof u) == 0 && memcmp(v, st->v, sizeof v) == 0 && st->t == t,
                 "state not rolled back (t %g vs %g)", st->t, t);
  TL_TEST_STATUS(tl_stepper_step(st, 0.01), TL_OK);
  tl_stepper_destroy(&st);
  tl_mech_system_destroy(&sys);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  stale_factors();
  diverging();
  spring_chain();
  beam();
  rollback();
  return tl_test_report();
}
