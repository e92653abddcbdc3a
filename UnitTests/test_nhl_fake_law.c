/* F-U5: the plumbing of the numerically homogenised law with the cell
 * replaced by an analytic law (specs/fem-x-dem.md §13): a dem_cell material
 * whose "cell" returns the Cauchy stress of Hooke's law S = λ tr(E) 1 + 2μE, σ = J⁻¹ F S Fᵀ,
 * goes through the same σ -> S = J F⁻¹ σ F⁻ᵀ and c -> D conversions and the
 * same perturbation CTO as a DEM cell.  Checks:
 *   - S through the plumbing equals the law's S to round-off, and D from the
 *     CTO equals the law's D to the perturbation's truncation, along the 9
 *     directions of Eq. 30 and along the 6 Green-strain directions, which
 *     agree with each other;
 *   - a 2 x 2 Q8 plane-strain block under a large shear-tension load solves
 *     to the same displacements as the plain material (1e-8), with the
 *     same Newton iterations, converging quadratically. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_nhl_material.h"
#include "tl_nhl_operator.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_test.h"

static TlStatus hooke_cauchy(void *ctx, TlMat3 F, TlMat3 *sigma)
{
  TlMat3 S;
  TL_CHECK(tl_material_evaluate((const TlMaterial *)ctx, 1, &F, NULL, NULL, &S, NULL, NULL));
  *sigma = tl_nhl_pk2_to_cauchy(F, S);
  return TL_OK;
}

static TlMaterial *fake(TlMaterial *law, double directions, double eps)
{
  TlMaterial *m = NULL;
  TL_TEST_STATUS(tl_material_create("dem_cell", &m), TL_OK);
  if (!m) return NULL;
  TL_TEST_STATUS(tl_nhl_material_set_analytic(m, hooke_cauchy, law), TL_OK);
  TL_TEST_STATUS(tl_nhl_material_set_operator(m, "cto"), TL_OK);
  TL_TEST_STATUS(tl_nhl_operator_set(tl_nhl_material_operator(m), "directions", directions), TL_OK);
  TL_TEST_STATUS(tl_nhl_operator_set(tl_nhl_material_operator(m), "eps", eps), TL_OK);
  TL_TEST_STATUS(tl_material_setup(m), TL_OK);
  return m;
}

static double dmax(const double *a, const double *b, int n)
{
  double e = 0.0;
  for (int k = 0; k < n; ++k) e = fmax(e, fabs(a[k] - b[k]));
  return e;
}

/* One point: S and D of the plumbing against the law's. */
static void check_point(TlMaterial *law)
{
  const TlMat3 F = {{{1.06, 0.04, 0.0}, {-0.03, 0.97, 0.0}, {0.0, 0.0, 1.0}}};
  TlMat3 S0, S9, S6;
  double D0[36], D9[36], D6[36], st9[TL_NHL_STATE_OPERATOR], st6[TL_NHL_STATE_OPERATOR], sn[TL_NHL_STATE_OPERATOR];
  TL_TEST_STATUS(tl_material_evaluate(law, 1, &F, NULL, NULL, &S0, D0, NULL), TL_OK);
  TlMaterial *m9 = fake(law, 9, 1e-6), *m6 = fake(law, 6, 1e-6);
  if (!m9 || !m6) return;
  TL_TEST_ASSERT(m9->state_size == TL_NHL_STATE_OPERATOR, "cto keeps no state: %zu doubles per point", m9->state_size);
  TL_TEST_STATUS(m9->ops->init_state(m9, 1, st9), TL_OK);
  TL_TEST_STATUS(m6->ops->init_state(m6, 1, st6), TL_OK);
  TL_TEST_STATUS(tl_material_evaluate(m9, 1, &F, st9, sn, &S9, D9, NULL), TL_OK);
  TL_TEST_STATUS(tl_material_evaluate(m6, 1, &F, st6, sn, &S6, D6, NULL), TL_OK);
  double s0[6], s9[6], dbig = 0.0, sbig = 0.0;
  tl_voigt_from_sym(S0, s0);
  tl_voigt_from_sym(S9, s9);
  for (int k = 0; k < 36; ++k) dbig = fmax(dbig, fabs(D0[k]));
  for (int k = 0; k < 6; ++k) sbig = fmax(sbig, fabs(s0[k]));
  const double e9 = dmax(D9, D0, 36) / dbig, e6 = dmax(D6, D0, 36) / dbig, e96 = dmax(D9, D6, 36) / dbig;
  printf("point: |S - S_law| / |S| = %.2e; |D - D_law| / |D|: 9 directions %.2e, 6 directions %.2e, between them %.2e\n",
         dmax(s9, s0, 6) / sbig, e9, e6, e96);
  TL_TEST_ASSERT(dmax(s9, s0, 6) <= 1e-13 * sbig, "S through the plumbing off by %g of %g", dmax(s9, s0, 6), sbig);
  TL_TEST_ASSERT(e9 <= 1e-4, "9-direction CTO off the law's D by %g (relative)", e9);
  TL_TEST_ASSERT(e6 <= 1e-4, "6-direction CTO off the law's D by %g (relative)", e6);
  TL_TEST_ASSERT(e96 <= 1e-4, "6- and 9-direction CTO differ by %g (relative)", e96);
  /* the truncation error is first order in eps: ten times eps, about ten
   * times the error (the comparison measures something) */
  TlMaterial *m9b = fake(law, 9, 1e-5);
  double D9b[36];
  if (m9b) {
    TL_TEST_STATUS(m9b->ops->init_state(m9b, 1, st9), TL_OK);
    TL_TEST_STATUS(tl_material_evaluate(m9b, 1, &F, st9, sn, &S9, D9b, NULL), TL_OK);
    const double e9b = dmax(D9b, D0, 36) / dbig;
    TL_TEST_ASSERT(e9b > 3.0 * e9 && e9b < 30.0 * e9, "eps 1e-5: error %g, eps 1e-6: %g (first order expected)", e9b, e9);
  }
  tl_material_destroy(&m9b);
  tl_material_destroy(&m9);
  tl_material_destroy(&m6);
}

/* The re-evaluation callback of a direct operator call: the analytic law. */
static TlStatus law_eval(void *ctx, TlNhlEvalMode mode, TlMat3 F, TlMat3 *sigma, TlNhlEvalStats *es)
{
  (void)mode, (void)es;
  return hooke_cauchy(ctx, F, sigma);
}

/* aeo: the cto while pre-peak, accumulated in the point's state across
 * committed steps; post-peak the average of those, whatever F. */
static void check_aeo(TlMaterial *law)
{
  TlMaterial *m = NULL;
  TL_TEST_STATUS(tl_material_create("dem_cell", &m), TL_OK);
  if (!m) return;
  TL_TEST_STATUS(tl_nhl_material_set_analytic(m, hooke_cauchy, law), TL_OK);
  TL_TEST_STATUS(tl_nhl_material_set_operator(m, "aeo"), TL_OK);
  TL_TEST_STATUS(tl_nhl_operator_set(tl_nhl_material_operator(m), "eps", 1e-6), TL_OK);
  TL_TEST_STATUS(tl_material_setup(m), TL_OK);
  TlNhlOperator *cto = NULL;
  TL_TEST_STATUS(tl_nhl_operator_create("cto", &cto), TL_OK);
  TL_TEST_STATUS(tl_nhl_operator_set(cto, "eps", 1e-6), TL_OK);
  TL_TEST_STATUS(tl_nhl_operator_setup(cto), TL_OK);
  const size_t ss = m->state_size;
  TL_TEST_ASSERT(ss == TL_NHL_STATE_OPERATOR + 82, "aeo keeps %zu doubles per point (82 expected)", ss - TL_NHL_STATE_OPERATOR);
  double *so = calloc(ss, sizeof *so), *sn = calloc(ss, sizeof *sn);
  TL_TEST_STATUS(m->ops->init_state(m, 1, so), TL_OK);
  TlMat3 Fk[4] = {tl_m3_identity(), tl_m3_identity(), tl_m3_identity(), tl_m3_identity()};
  Fk[0].m[0][0] = 0.99, Fk[1].m[0][0] = 0.97, Fk[1].m[0][1] = 0.02, Fk[2].m[0][0] = 0.95, Fk[3].m[1][1] = 1.04;
  double cavg[81] = {0}, D[4][36];
  TlMat3 S[4];
  tl_nhl_material_set_regime(m, 1);
  for (int k = 0; k < 2; ++k) {
    TL_TEST_STATUS(tl_material_evaluate(m, 1, &Fk[k], so, sn, &S[k], D[k], NULL), TL_OK);
    TL_TEST_STATUS(m->ops->commit(m, 1, sn), TL_OK);
    memcpy(so, sn, ss * sizeof *so);
    /* the cto at the same state, by a direct call */
    TlNhlOperatorInput in = {NULL, 3, Fk[k], tl_nhl_pk2_to_cauchy(Fk[k], S[k]), law_eval, law, 0, 1};
    double c[81];
    TlNhlOperatorStats ost;
    memset(&ost, 0, sizeof ost);
    TL_TEST_STATUS(cto->ops->compute(cto, &in, NULL, NULL, c, &ost), TL_OK);
    for (int q = 0; q < 81; ++q) cavg[q] += 0.5 * c[q];
  }
  TL_TEST_ASSERT(so[TL_NHL_STATE_OPERATOR + 81] == 2.0, "aeo counted %g pre-peak steps (2)", so[TL_NHL_STATE_OPERATOR + 81]);
  tl_nhl_material_set_regime(m, 0);
  double err = 0.0, big = 0.0;
  for (int k = 2; k < 4; ++k) {
    TL_TEST_STATUS(tl_material_evaluate(m, 1, &Fk[k], so, sn, &S[k], D[k], NULL), TL_OK);
    double Dexp[36];
    tl_nhl_operator_to_D(cavg, Fk[k], tl_nhl_pk2_to_cauchy(Fk[k], S[k]), Dexp);
    for (int q = 0; q < 36; ++q) err = fmax(err, fabs(D[k][q] - Dexp[q])), big = fmax(big, fabs(Dexp[q]));
  }
  TL_TEST_ASSERT(sn[TL_NHL_STATE_OPERATOR + 81] == 2.0, "post-peak aeo changed its count to %g", sn[TL_NHL_STATE_OPERATOR + 81]);
  printf("aeo: post-peak D against the average of the two pre-peak cto's: %.2e relative\n", err / big);
  /* the last cto alone differs from the average (the steps' strains) */
  double dlast = 0.0;
  double Dl[36];
  {
    TlNhlOperatorInput in = {NULL, 3, Fk[1], tl_nhl_pk2_to_cauchy(Fk[1], S[1]), law_eval, law, 0, 1};
    double c[81];
    TlNhlOperatorStats ost;
    memset(&ost, 0, sizeof ost);
    TL_TEST_STATUS(cto->ops->compute(cto, &in, NULL, NULL, c, &ost), TL_OK);
    tl_nhl_operator_to_D(c, Fk[2], tl_nhl_pk2_to_cauchy(Fk[2], S[2]), Dl);
    for (int q = 0; q < 36; ++q) dlast = fmax(dlast, fabs(D[2][q] - Dl[q]));
  }
  printf("aeo: the last pre-peak cto alone differs by %.2e relative\n", dlast / big);
  TL_TEST_ASSERT(dlast > 1e-4 * big, "the test cannot tell the average from the last cto (%g of %g)", dlast, big);
  TL_TEST_ASSERT(err <= 1e-9 * big, "post-peak aeo is not the average of the pre-peak cto's (%g of %g)", err, big);
  free(so), free(sn);
  tl_nhl_operator_destroy(&cto);
  tl_material_destroy(&m);
}

typedef struct {
  double u[200];
  int n;
  long iterations;
  double history[64];
  int n_history;
} Solution;

/* A 2 x 2 Q8 plane-strain block, clamped at x = 0, pulled and sheared at
 * x = 1 by a dead traction, one load step. */
static void solve(TlMaterial *m, Solution *out)
{
  memset(out, 0, sizeof *out);
  size_t n[2] = {2, 2};
  double lo[2] = {0, 0}, hi[2] = {1.0, 1.0};
  TlMesh *mesh = NULL;
  TL_TEST_STATUS(tl_mesh_create_rectangle(&tl_element_quad8, n, lo, hi, &mesh), TL_OK);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  if (!solid) return;
  TL_TEST_STATUS(tl_solid_set_material(solid, NULL, m), TL_OK);
  TL_TEST_STATUS(tl_solid_fix(solid, "xmin", 3), TL_OK);
  TL_TEST_STATUS(tl_solid_add_traction(solid, "xmax", tl_v3(8e5, 3e5, 0), NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlStepperOptions opt;
  tl_stepper_options_default(&opt);
  opt.rtol = 1e-12;
  opt.solver = "klu";
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("quasi_static", tl_solid_system(solid), &opt, &st), TL_OK);
  if (st) {
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
    TL_TEST_STATUS(tl_stepper_step(st, 1.0), TL_OK);
    out->n = st->n < 200 ? (int)st->n : 200;
    memcpy(out->u, st->u, (size_t)out->n * sizeof *out->u);
    TlStepperStats ss;
    tl_stepper_get_stats(st, &ss);
    out->iterations = ss.newton_iterations;
    const double *h = NULL;
    out->n_history = tl_newton_history(st->newton, &h);
    if (out->n_history > 64) out->n_history = 64;
    if (h) memcpy(out->history, h, (size_t)out->n_history * sizeof *h);
  }
  tl_stepper_destroy(&st);
  tl_solid_destroy(&solid);
  tl_mesh_destroy(&mesh);
}

static void print_history(const char *label, const Solution *s)
{
  printf("%s: %ld Newton iterations, residuals", label, s->iterations);
  for (int k = 0; k < s->n_history; ++k) printf(" %.2e", s->history[k]);
  printf("\n");
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TlMaterial *law = NULL;
  /* Hooke's law between S and E (stateless; "hooke" keeps an energy state
   * for nu != 0) */
  TL_TEST_STATUS(tl_material_create("saint_venant_kirchhoff", &law), TL_OK);
  if (!law) return tl_test_report();
  TL_TEST_STATUS(tl_material_set(law, "E", 1e7), TL_OK);
  TL_TEST_STATUS(tl_material_set(law, "nu", 0.3), TL_OK);
  TL_TEST_STATUS(tl_material_setup(law), TL_OK);
  check_point(law);
  check_aeo(law);

  Solution plain, plumbed;
  solve(law, &plain);
  TlMaterial *m = fake(law, 9, 1e-6);
  if (m) solve(m, &plumbed);
  print_history("saint_venant_kirchhoff", &plain);
  print_history("dem_cell (analytic, cto 9)", &plumbed);
  double umax = 0.0;
  for (int k = 0; k < plain.n; ++k) umax = fmax(umax, fabs(plain.u[k]));
  const double du = dmax(plain.u, plumbed.u, plain.n);
  printf("largest displacement %.4g m, difference %.2e m (%.2e relative)\n", umax, du, du / umax);
  TL_TEST_ASSERT(plain.n > 0 && plain.n == plumbed.n, "dof counts %d and %d", plain.n, plumbed.n);
  TL_TEST_ASSERT(umax > 0.05, "the load is too small to test the finite-strain plumbing (u_max %g m)", umax);
  TL_TEST_ASSERT(du <= 1e-8 * umax, "displacements differ by %g (largest %g)", du, umax);
  TL_TEST_ASSERT(labs(plumbed.iterations - plain.iterations) <= 1 && plumbed.iterations <= 8,
                 "Newton took %ld iterations with the CTO, %ld with the exact tangent", plumbed.iterations,
                 plain.iterations);
  /* quadratic convergence: log(r_{k+1}/r_0) / log(r_k/r_0) near 2 while
   * the residual is above the perturbation's noise */
  int checked = 0;
  for (int k = 1; k + 1 < plumbed.n_history; ++k) {
    const double r0 = plumbed.history[0], a = plumbed.history[k] / r0, b = plumbed.history[k + 1] / r0;
    if (!(a < 0.3 && a > 1e-5)) continue;
    const double order = log(b) / log(a);
    printf("  iteration %d: relative residual %.2e -> %.2e, order %.2f\n", k, a, b, order);
    TL_TEST_ASSERT(order > 1.7, "iteration %d: convergence order %.2f (%.2e -> %.2e)", k, order, a, b);
    checked++;
  }
  TL_TEST_ASSERT(checked >= 1, "no iteration in the quadratic range to check (%d residuals)", plumbed.n_history);
  tl_material_destroy(&m);
  tl_material_destroy(&law);
  return tl_test_report();
}
