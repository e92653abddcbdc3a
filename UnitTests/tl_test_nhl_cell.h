/* Test support for the NHL tangent operators: a periodic cell rebuilt on
 * demand in one fixed state (a lattice, or a packing stored as positions),
 * and the evaluate callback of TlNhlOperatorInput implementing the DEMQO
 * probe of Eq. 32: sliding suppressed (μ = ∞), the cell driven at constant
 * ḣ from F to F_target over τ (Eq. 18 with γ the increment's largest
 * principal strain magnitude, at least ten steps), relaxed until the force
 * imbalance Δ_n (Eq. 19) and the torque imbalance are below tol, the stress
 * (Eq. 27) returned and the probe discarded. */
#ifndef TL_TEST_NHL_CELL_H
#define TL_TEST_NHL_CELL_H

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "tl_contact_law.h"
#include "tl_dem.h"
#include "tl_nhl_operator.h"
#include "tl_test.h"
#include "tl_timer.h"

typedef struct {
  /* builds the cell in its state at F = 1 (setup done, forces computed) */
  TlStatus (*build)(void *ctx, TlDem **dem);
  void *ctx;
  double dt, inertial, rho, d_mean; /* time step; Eq. 18 */
  double tol;                       /* relaxation tolerance (force and torque) */
  long max_steps;
  long last_steps;
} TestCell;

/* An empty periodic cell of edge vectors h: disks in the planar cell when
 * dim = 2, spheres otherwise. */
static inline TlStatus test_cell_create(int dim, TlMat3 h, TlDem **out)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlDomain dom;
  if (dim == 2) {
    TL_CHECK(tl_dem_set_dimension(dem, 2));
    TL_CHECK(tl_domain_init_cell_2d(&dom, tl_v3(0, 0, 0), h));
  } else TL_CHECK(tl_domain_init_cell(&dom, tl_v3(0, 0, 0), h));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  *out = dem;
  return TL_OK;
}

/* Completes a cell whose particles are placed: the linear law (k_n,
 * restitution; when k_t > 0 also Coulomb friction μ = 0.5 and tangential
 * springs k_t damped by γ_t = 0.1 √(k_t/m), m a grain's mass), a time step
 * of 0.3 of the critical one, setup and the forces of the state. */
static inline TlStatus test_cell_finish(TlDem *dem, double kn, double restitution, double kt, double m)
{
  TlContactLaw *law;
  if (kt > 0.0)
    TL_CHECK(tl_test_law(&law, "linear", "k_n", kn, "restitution", restitution, "mu", 0.5, "k_t", kt, "gamma_t",
                         0.1 * sqrt(kt / m), NULL));
  else TL_CHECK(tl_test_law(&law, "linear", "k_n", kn, "restitution", restitution, NULL));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  double dtc;
  TL_CHECK(tl_dem_critical_timestep(dem, &dtc, NULL, NULL));
  TL_CHECK(tl_dem_set_timestep(dem, 0.3 * dtc, 0));
  TL_CHECK(tl_dem_setup(dem));
  TL_CHECK(tl_dem_compute_forces(dem));
  return TL_OK;
}

/* Computes operator `name` on in ("name:sym": with symmetrise = 1;
 * "name:6": with directions = 6). */
static inline TlStatus test_operator_compute(const char *name, TlNhlOperatorInput *in, double c[81],
                                             TlNhlOperatorStats *st)
{
  TlNhlOperator *op;
  char base[32];
  snprintf(base, sizeof base, "%s", name);
  char *colon = strchr(base, ':');
  if (colon) *colon = '\0';
  TL_CHECK(tl_nhl_operator_create(base, &op));
  TlStatus s = TL_OK;
  if (colon && strcmp(colon + 1, "sym") == 0) s = tl_nhl_operator_set(op, "symmetrise", 1);
  if (colon && strcmp(colon + 1, "6") == 0) s = tl_nhl_operator_set(op, "directions", 6);
  if (s == TL_OK) s = tl_nhl_operator_setup(op);
  if (s == TL_OK) s = tl_nhl_operator_compute(op, in, NULL, NULL, c, st);
  tl_nhl_operator_destroy(&op);
  return s;
}

/* Largest torque on a free particle over (largest contact force × radius). */
static void test_torque_visit(void *ctx, size_t i, size_t j, TlVec3 f, TlVec3 b, TlVec3 cp)
{
  (void)i, (void)j, (void)b, (void)cp;
  double *fmax_ = ctx;
  double v = tl_v3_norm(f);
  if (v > *fmax_) *fmax_ = v;
}

static inline TlStatus test_cell_imbalance(TlDem *dem, double *force, double *torque)
{
  TL_CHECK(tl_dem_max_force_imbalance(dem, force));
  double fm = 0.0;
  TL_CHECK(tl_dem_visit_contacts(dem, test_torque_visit, &fm));
  TlParticles *P = tl_dem_particles(dem);
  double t = 0.0;
  if (P->torque)
    for (size_t i = 0; i < P->n; ++i)
      if (P->motion[i] == TL_MOTION_FREE) t = fmax(t, tl_v3_norm(P->torque[i]) / (fm * P->radius[i]));
  *torque = fm > 0.0 ? t : 0.0;
  return TL_OK;
}

/* Relaxes until both imbalances are below tol (checked every 10 steps). */
static inline TlStatus test_cell_relax(TlDem *dem, double tol, long max_steps, long *steps, double *imb)
{
  long n = 0;
  double f = 0.0, t = 0.0;
  for (;;) {
    TL_CHECK(test_cell_imbalance(dem, &f, &t));
    if ((f <= tol && t <= tol) || n >= max_steps) break;
    TL_CHECK(tl_dem_step(dem, 10));
    n += 10;
  }
  *steps += n;
  *imb = fmax(f, t);
  return TL_OK;
}

static inline TlStatus test_cell_evaluate(void *ctx, TlNhlEvalMode mode, TlMat3 Ft, TlMat3 *sigma, TlNhlEvalStats *st)
{
  TestCell *C = ctx;
  if (mode != TL_NHL_EVAL_PROBE) TL_ERROR(TL_ERR_ARG, "the test cell implements the probe only (mode %d)", (int)mode);
  double t0 = tl_wtime();
  TlDem *dem;
  TL_CHECK(C->build(C->ctx, &dem));
  TlStatus s = TL_OK;
  /* μ = ∞: sliding suppressed, histories kept */
  for (int k = 0; k < tl_dem_n_laws(dem) && s == TL_OK; ++k) {
    double mu;
    TlContactLaw *law = tl_dem_law(dem, k);
    if (tl_contact_law_get(law, "mu", &mu) == TL_OK && mu > 0.0) {
      s = tl_contact_law_set(law, "mu", 1e300);
      if (s == TL_OK) s = tl_contact_law_setup(law);
    }
  }
  TlDomain *D = tl_dem_domain(dem);
  TlMat3 h0 = D->h, Gu = tl_m3_add(Ft, tl_m3_scale(tl_m3_identity(), -1.0)); /* F = 1 at the state */
  double w[3], S[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) S[3 * i + j] = 0.5 * (Gu.m[i][j] + Gu.m[j][i]);
  tl_nhl_sym_eigen(3, S, w, NULL);
  double gmax = fmax(fabs(w[0]), fmax(fabs(w[1]), fabs(w[2])));
  double ga = fmax(fabs(Gu.m[0][1] - Gu.m[1][0]), fmax(fabs(Gu.m[0][2] - Gu.m[2][0]), fabs(Gu.m[1][2] - Gu.m[2][1])));
  gmax = fmax(gmax, ga);
  TlMat3 sc, sk;
  if (s == TL_OK) s = tl_dem_stress(dem, &sc, &sk);
  double p = fabs(tl_m3_trace(sc)) / 3.0;
  double tau = gmax * C->d_mean / (C->inertial * sqrt(p / C->rho));
  long n = (long)ceil(tau / C->dt);
  if (n < 10) n = 10;
  long steps = 0;
  if (s == TL_OK) s = tl_domain_set_h_rate(D, tl_m3_scale(tl_m3_mul(Gu, h0), 1.0 / (n * C->dt)));
  if (s == TL_OK) s = tl_dem_step(dem, n);
  steps += n;
  if (s == TL_OK) s = tl_domain_set_h_rate(D, tl_m3_zero());
  if (s == TL_OK) s = tl_domain_set_h(D, tl_m3_mul(Ft, h0));
  if (s == TL_OK) s = tl_dem_compute_forces(dem);
  double imb = 0.0;
  if (s == TL_OK) s = test_cell_relax(dem, C->tol, C->max_steps, &steps, &imb);
  if (s == TL_OK) s = tl_dem_stress(dem, sigma, &sk);
  tl_dem_destroy(&dem);
  C->last_steps = steps;
  if (st) {
    st->dem_steps = steps;
    st->tau = n * C->dt;
    st->imbalance = imb;
    st->converged = imb <= C->tol;
    st->seconds = tl_wtime() - t0;
  }
  return s;
}

#endif
