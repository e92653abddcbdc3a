/* Newmark (average acceleration) on the S1 beam (hex8 2 x 10 x 2, clamped at
 * y = 0, released with a tip velocity of 1 m/s in a y^2 profile): the two
 * failures once reported on it, and their cause.
 *
 * Both came from the constant-acceleration predictor
 *   x_pred = u_n + dt v_n + dt^2/2 a_n.
 * The trapezoidal rule does not damp the unresolved element modes
 * (omega_max dt ~ 55 at dt = T/100), so a_n carries them with
 * a = -omega^2 q, and the predictor moves them by omega^2 dt^2 / 2 times
 * their amplitude (~1500x).  The state it lands on is genuinely distorted:
 *  - at dt = T/100 the tangent K + M / (beta dt^2) there is indefinite (one
 *    negative pivot, in full and in upper-triangle storage alike), so
 *    CHOLMOD refused it at the first Newton iteration while LU went on;
 *  - at dt = T/40 with the consistent mass (higher omega_max) Newton started
 *    each step further off and diverged into inverted elements at step 5.
 * The tangent at the converged states is positive definite and was never
 * the problem.  The stepper predicts with the last displacement (its
 * inertia error in those modes is of the size of their amplitude); these
 * tests hold that: CHOLMOD and KLU give the same motion, the consistent
 * mass runs a whole period at T/40 in a few iterations per step, and the
 * distortion of the constant-acceleration predictor is shown directly. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_linear_solver.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_test.h"

static const double E_mod = 1e8, rho = 1309.0, L = 12.0;

typedef struct {
  TlMesh *mesh;
  TlMaterial *mat;
  TlSolid *solid;
  TlMechSystem *sys;
  double *v0; /* initial velocity */
  double T;   /* first bending period */
} Beam;

static TlStatus beam_create(Beam *bm)
{
  memset(bm, 0, sizeof *bm);
  size_t n[3] = {2, 10, 2};
  double lo[3] = {-0.4, 0.0, -0.4}, hi[3] = {0.4, L, 0.4};
  TL_CHECK(tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &bm->mesh));
  TL_CHECK(tl_material_create_hooke(E_mod, 0.0, rho, &bm->mat));
  TL_CHECK(tl_solid_create(bm->mesh, &bm->solid));
  TL_CHECK(tl_solid_set_material(bm->solid, NULL, bm->mat));
  TL_CHECK(tl_solid_fix(bm->solid, "ymin", 7));
  TL_CHECK(tl_solid_setup(bm->solid));
  bm->sys = tl_solid_system(bm->solid);
  TL_CHECK(tl_calloc(&bm->v0, (size_t)bm->sys->ndof, sizeof *bm->v0));
  for (size_t a = 0; a < bm->mesh->n_nodes; ++a) {
    double y = bm->mesh->x[3 * a + 1] / L;
    TlSparseIndex d = tl_solid_dof(bm->solid, a, 2);
    if (d >= 0) bm->v0[d] = y * y;
  }
  double I = pow(0.8, 4) / 12.0;
  bm->T = 2 * M_PI / (1.875 * 1.875 * sqrt(E_mod * I / (rho * 0.64 * pow(L, 4))));
  return TL_OK;
}

static void beam_destroy(Beam *bm)
{
  tl_free(&bm->v0);
  tl_solid_destroy(&bm->solid);
  tl_material_destroy(&bm->mat);
  tl_mesh_destroy(&bm->mesh);
}

/* Negative pivots of the unpivoted dense LDL^T of a symmetric matrix (its
 * number of negative eigenvalues, by Sylvester's law, when no pivot is 0). */
static int negative_pivots(const TlSparse *A, double *min_pivot)
{
  size_t n = (size_t)A->n;
  double *D = calloc(n * n, sizeof *D);
  for (TlSparseIndex j = 0; j < A->n; ++j)
    for (TlSparseIndex p = A->colptr[j]; p < A->colptr[j + 1]; ++p) {
      size_t i = (size_t)A->rowind[p];
      D[i * n + (size_t)j] = D[(size_t)j * n + i] = A->values[p];
    }
  int neg = 0;
  *min_pivot = HUGE_VAL;
  for (size_t k = 0; k < n; ++k) {
    double d = D[k * n + k];
    if (d < 0.0) ++neg;
    *min_pivot = fmin(*min_pivot, d);
    for (size_t r = k + 1; r < n; ++r) {
      double l = D[r * n + k] / d;
      if (l == 0.0) continue;
      for (size_t c = k + 1; c <= r; ++c) D[r * n + c] -= l * D[c * n + k];
    }
  }
  free(D);
  return neg;
}

/* Runs n_steps of dt; returns the status of the first failure (TL_OK if
 * none), the largest Newton iteration count of a step, and the final u. */
static TlStatus run(Beam *bm, const char *solver, int lumped, double dt, int n_steps, long *max_iters,
                    double *u_end, double *drift)
{
  TlStepperOptions opt;
  tl_stepper_options_default(&opt);
  opt.solver = solver;
  opt.lumped = lumped;
  TlStepper *st = NULL;
  TL_CHECK(tl_stepper_create("newmark", bm->sys, &opt, &st));
  TlStatus s = tl_stepper_set_state(st, 0.0, NULL, bm->v0);
  TlEnergies e0, e;
  if (s == TL_OK) s = tl_stepper_energies(st, &e0);
  *max_iters = 0;
  *drift = 0.0;
  long before = 0;
  for (int k = 0; k < n_steps && s == TL_OK; ++k) {
    s = tl_stepper_step(st, dt);
    TlStepperStats stats;
    tl_stepper_get_stats(st, &stats);
    if (stats.newton_iterations - before > *max_iters) *max_iters = stats.newton_iterations - before;
    before = stats.newton_iterations;
    if (s == TL_OK) s = tl_stepper_energies(st, &e);
    if (s == TL_OK) *drift = fmax(*drift, fabs(e.kinetic + e.strain - e0.kinetic) / e0.kinetic);
  }
  if (u_end) memcpy(u_end, st->u, (size_t)st->n * sizeof *u_end);
  tl_stepper_destroy(&st);
  return s;
}

/* Bug 1: CHOLMOD and KLU on the same Newmark run (dt = T/100, a quarter
 * period) give the same motion, to Newton's tolerance. */
static void cholmod_matches_klu(Beam *bm)
{
  size_t n = (size_t)bm->sys->ndof;
  double *uc = calloc(n, sizeof *uc), *uk = calloc(n, sizeof *uk);
  long ic = 0, ik = 0;
  double dc = 0, dk = 0, dt = bm->T / 100.0;
  TL_TEST_STATUS(run(bm, "cholmod", 0, dt, 25, &ic, uc, &dc), TL_OK);
  TL_TEST_STATUS(run(bm, "klu", 0, dt, 25, &ik, uk, &dk), TL_OK);
  double diff = 0.0, size = 0.0;
  for (size_t i = 0; i < n; ++i) {
    diff = fmax(diff, fabs(uc[i] - uk[i]));
    size = fmax(size, fabs(uk[i]));
  }
  printf("T/100, 25 steps: cholmod %ld, klu %ld Newton iterations at most per step; max |u_chol - "
         "u_klu| = %.2e of |u| = %.3f m; energy drift %.2e / %.2e\n",
         ic, ik, diff, size, dc, dk);
  TL_TEST_ASSERT(size > 0.2, "the tip swung only %g m", size);
  TL_TEST_ASSERT(diff < 1e-9 * size, "cholmod and klu differ by %g (|u| %g)", diff, size);
  TL_TEST_ASSERT(ic <= 5 && ik <= 5, "Newton iterations per step: cholmod %ld, klu %ld", ic, ik);
  free(uc);
  free(uk);
}

/* Bug 2: the consistent mass at dt = T/40 over a whole period (and the
 * lumped one, for comparison), both with KLU and CHOLMOD. */
static void consistent_mass_large_step(Beam *bm)
{
  double dt = bm->T / 40.0;
  const char *solvers[2] = {"klu", "cholmod"};
  for (int s = 0; s < 2; ++s)
    for (int lumped = 0; lumped < 2; ++lumped) {
      long it = 0;
      double drift = 0.0;
      TL_TEST_STATUS(run(bm, solvers[s], lumped, dt, 40, &it, NULL, &drift), TL_OK);
      printf("T/40, one period, %s, %s mass: at most %ld Newton iterations per step, energy drift %.2e\n",
             solvers[s], lumped ? "lumped" : "consistent", it, drift);
      TL_TEST_ASSERT(it <= 6, "%s %s: %ld iterations in a step", solvers[s], lumped ? "lumped" : "consistent", it);
      /* The trapezoidal rule conserves energy up to the finite-strain terms. */
      TL_TEST_ASSERT(drift < 5e-4, "%s %s: energy drift %g", solvers[s], lumped ? "lumped" : "consistent", drift);
    }
}

/* The cause: after four steps at T/100, the tangent K + M/(beta dt^2) is
 * positive definite at the converged state (the last-displacement
 * predictor) and indefinite at the constant-acceleration predictor, whose
 * residual is far larger. */
static void predictor_evidence(Beam *bm)
{
  TlMechSystem *sys = bm->sys;
  size_t n = (size_t)sys->ndof;
  double dt = bm->T / 100.0, c0 = 1.0 / (0.25 * dt * dt);
  TlStepperOptions opt;
  tl_stepper_options_default(&opt);
  opt.solver = "klu";
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("newmark", sys, &opt, &st), TL_OK);
  if (!st) return;
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, bm->v0), TL_OK);
  for (int k = 0; k < 4; ++k) TL_TEST_STATUS(tl_stepper_step(st, dt), TL_OK);
  double *x = calloc(n, sizeof *x), *acc = calloc(n, sizeof *acc), *vel = calloc(n, sizeof *vel);
  double *f = calloc(n, sizeof *f), *Ma = calloc(n, sizeof *Ma);
  TlSparse *M = NULL, *J = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 1, &M), TL_OK);
  TL_TEST_STATUS(sys->ops->consistent_mass(sys, 1.0, M), TL_OK);
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 1, &J), TL_OK);
  int neg[2] = {-1, -1};
  double pivot[2] = {0, 0}, resid[2] = {0, 0};
  for (int which = 0; which < 2; ++which) {
    for (size_t i = 0; i < n; ++i)
      x[i] = st->u[i] + (which ? dt * st->v[i] + 0.5 * dt * dt * st->a[i] : 0.0);
    for (size_t i = 0; i < n; ++i) {
      acc[i] = c0 * (x[i] - st->u[i]) - 4.0 / dt * st->v[i] - st->a[i];
      vel[i] = st->v[i] + 0.5 * dt * (st->a[i] + acc[i]);
    }
    TL_TEST_STATUS(sys->ops->internal_force(sys, st->t + dt, x, vel, f), TL_OK);
    tl_sparse_matvec(M, acc, Ma);
    for (size_t i = 0; i < n; ++i) resid[which] = fmax(resid[which], fabs(Ma[i] + f[i]));
    tl_sparse_zero(J);
    TL_TEST_STATUS(sys->ops->internal_tangent(sys, st->t + dt, x, vel, 1.0, 0.0, J), TL_OK);
    TL_TEST_STATUS(tl_sparse_axpy(c0, M, J), TL_OK);
    neg[which] = negative_pivots(J, &pivot[which]);
  }
  printf("step 5 at T/100: last-displacement predictor |R| %.3e, %d negative pivots (min %.3e); "
         "constant-acceleration predictor |R| %.3e, %d negative pivots (min %.3e)\n",
         resid[0], neg[0], pivot[0], resid[1], neg[1], pivot[1]);
  TL_TEST_ASSERT(neg[0] == 0, "tangent at the converged state has %d negative pivots", neg[0]);
  TL_TEST_ASSERT(neg[1] > 0, "tangent at the constant-acceleration predictor is positive definite");
  TL_TEST_ASSERT(resid[1] > 10.0 * resid[0], "predictor residuals %g (constant a) vs %g (last u)", resid[1],
                 resid[0]);
  /* CHOLMOD refuses exactly that matrix, naming it not positive definite. */
  TlLinearSolver *ls = NULL;
  TL_TEST_STATUS(tl_linear_solver_create("cholmod", J, &ls), TL_OK);
  if (ls) {
    TL_TEST_STATUS(tl_linear_solver_factor(ls, J), TL_ERR_NUMERIC);
    TL_TEST_ASSERT(strstr(tl_error_message(), "not positive definite") != NULL, "%s", tl_error_message());
  }
  tl_linear_solver_destroy(&ls);
  tl_sparse_destroy(&M);
  tl_sparse_destroy(&J);
  free(x), free(acc), free(vel), free(f), free(Ma);
  tl_stepper_destroy(&st);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  Beam bm;
  TL_TEST_STATUS(beam_create(&bm), TL_OK);
  if (bm.sys) {
    cholmod_matches_klu(&bm);
    consistent_mass_large_step(&bm);
    predictor_evidence(&bm);
  }
  beam_destroy(&bm);
  return tl_test_report();
}
