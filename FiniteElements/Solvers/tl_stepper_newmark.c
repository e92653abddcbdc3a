/* Implicit Newmark-beta.  The unknown of each step is u = u_{n+1}:
 *
 *   a(u) = (u - u_n - dt v_n) / (beta dt^2) - (1/(2 beta) - 1) a_n
 *   v(u) = v_n + dt ((1 - gamma) a_n + gamma a(u))
 *   R(u) = M a(u) + f_int(u, v(u)) - f_ext(t_{n+1}, u) = 0
 *   dR/du = M / (beta dt^2) + gamma / (beta dt) C + K - K_ext
 *
 * Prescribed dofs carry R = u - u_prescribed(t_{n+1}) and identity rows and
 * columns (the predictor already holds the prescribed value, so the Newton
 * correction there is zero and symmetric elimination is exact). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "tl_linear_solver.h"
#include "tl_math.h"
#include "tl_memory.h"
#include "tl_stepper.h"

static void newmark_kinematics(const TlStepper *st, const double *u, double *a, double *v)
{
  const double b = st->opt.beta, g = st->opt.gamma, dt = st->dt;
  const double c0 = 1.0 / (b * dt * dt), c1 = 1.0 / (b * dt), c2 = 0.5 / b - 1.0;
  for (TlSparseIndex i = 0; i < st->n; ++i) {
    a[i] = c0 * (u[i] - st->u0[i]) - c1 * st->v0[i] - c2 * st->a0[i];
    v[i] = st->v0[i] + dt * ((1.0 - g) * st->a0[i] + g * a[i]);
  }
}

typedef struct {
  double *x;  /* Newton unknown */
  double *r0; /* residual at the predictor, computed for the force scale */
  int r0_valid;
} Newmark;

static TlStatus newmark_residual(void *ctx, const double *x, double *r)
{
  TlStepper *st = ctx;
  TlMechSystem *sys = st->sys;
  Newmark *nm = st->impl;
  /* Newton's first evaluation is at the predictor, where the step already
   * evaluated the residual for its force scale. */
  if (nm->r0_valid) {
    nm->r0_valid = 0;
    if (memcmp(x, nm->x, (size_t)st->n * sizeof *x) == 0) {
      memcpy(r, nm->r0, (size_t)st->n * sizeof *r);
      return TL_OK;
    }
  }
  newmark_kinematics(st, x, st->a, st->v);
  st->stats.residual_evaluations++;
  TL_CHECK(sys->ops->internal_force(sys, st->t_new, x, st->v, st->f_int));
  TL_CHECK(sys->ops->external_force(sys, st->t_new, x, st->f_ext));
  tl_stepper_mass_times(st, st->a, r);
  for (TlSparseIndex i = 0; i < st->n; ++i) r[i] += st->f_int[i] - st->f_ext[i];
  for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) {
    TlSparseIndex i = sys->dirichlet_dofs[k];
    r[i] = x[i] - st->u[i]; /* st->u holds the prescribed values during the step */
  }
  return TL_OK;
}

static TlStatus newmark_jacobian(void *ctx, const double *x, TlSparse *J)
{
  TlStepper *st = ctx;
  TlMechSystem *sys = st->sys;
  const double b = st->opt.beta, g = st->opt.gamma, dt = st->dt;
  const double c0 = 1.0 / (b * dt * dt);
  newmark_kinematics(st, x, st->a, st->v);
  TL_CHECK(sys->ops->internal_tangent(sys, st->t_new, x, st->v, 1.0, g / (b * dt), J));
  if (sys->ops->external_tangent) TL_CHECK(sys->ops->external_tangent(sys, st->t_new, x, -1.0, J));
  if (st->M) {
    TL_CHECK(tl_sparse_axpy(c0, st->M, J));
  } else {
    for (TlSparseIndex i = 0; i < st->n; ++i) J->values[J->diag[i]] += c0 * st->m[i];
  }
  tl_sparse_constrain(J, sys->n_dirichlet, sys->dirichlet_dofs, 1.0);
  return TL_OK;
}

static TlStatus newmark_setup(TlStepper *st)
{
  Newmark *nm = NULL;
  TL_CHECK(TL_NEW(nm));
  st->impl = nm;
  TL_CHECK(tl_calloc(&nm->x, (size_t)st->n, sizeof *nm->x));
  TL_CHECK(tl_calloc(&nm->r0, (size_t)st->n, sizeof *nm->r0));
  TL_CHECK(tl_stepper_implicit_setup(st, newmark_residual, newmark_jacobian));
  return TL_OK;
}

/* M a = f_ext - f_int at t (prescribed accelerations at Dirichlet dofs). */
static TlStatus newmark_initialise(TlStepper *st)
{
  TlMechSystem *sys = st->sys;
  double *r = st->work;
  TL_CHECK(sys->ops->internal_force(sys, st->t, st->u, st->v, st->f_int));
  TL_CHECK(sys->ops->external_force(sys, st->t, st->u, st->f_ext));
  for (TlSparseIndex i = 0; i < st->n; ++i) r[i] = st->f_ext[i] - st->f_int[i];
  if (!st->M) {
    for (TlSparseIndex i = 0; i < st->n; ++i) st->a[i] = r[i] / st->m[i];
  } else {
    /* Known accelerations move to the right-hand side, then the constrained
     * mass is factorised once. */
    double *ab = st->f_int;
    memset(ab, 0, (size_t)st->n * sizeof *ab);
    for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k)
      ab[sys->dirichlet_dofs[k]] = st->a[sys->dirichlet_dofs[k]];
    tl_sparse_matvec(st->M, ab, st->f_ext0);
    for (TlSparseIndex i = 0; i < st->n; ++i) r[i] -= st->f_ext0[i];
    for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k)
      r[sys->dirichlet_dofs[k]] = ab[sys->dirichlet_dofs[k]];
    TlSparse *Mc = NULL;
    TlLinearSolver *ls = NULL;
    TlStatus s = TL_OK;
    TL_CHECK_GOTO(s, tl_sparse_duplicate(st->M, &Mc), done);
    memcpy(Mc->values, st->M->values, (size_t)Mc->nnz * sizeof *Mc->values);
    tl_sparse_constrain(Mc, sys->n_dirichlet, sys->dirichlet_dofs, 1.0);
    TL_CHECK_GOTO(s, tl_linear_solver_create(Mc->symmetric ? "cholmod" : "klu", Mc, &ls), done);
    TL_CHECK_GOTO(s, tl_linear_solver_factor(ls, Mc), done);
    TL_CHECK_GOTO(s, tl_linear_solver_solve(ls, r, st->a), done);
  done:
    tl_linear_solver_destroy(&ls);
    tl_sparse_destroy(&Mc);
    if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  }
  for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) {
    TlSparseIndex i = sys->dirichlet_dofs[k];
    if (!st->M) st->a[i] = 0.0;
  }
  if (sys->ops->dirichlet) TL_CHECK(sys->ops->dirichlet(sys, st->t, NULL, NULL, st->a));
  st->omega2_bound = 0.0;
  if (st->opt.predictor == TL_PREDICTOR_AUTO && sys->ops->max_frequency_squared)
    TL_CHECK(sys->ops->max_frequency_squared(sys, st->u, &st->omega2_bound));
  return TL_OK;
}

static TlStatus newmark_step(TlStepper *st, double dt)
{
  TlMechSystem *sys = st->sys;
  Newmark *nm = st->impl;
  size_t bytes = (size_t)st->n * sizeof(double);
  tl_stepper_save_start(st);
  /* Kept factors hold M / (beta dt^2): a new step size needs new ones. */
  if (dt != st->dt) tl_newton_invalidate(st->newton);
  st->dt = dt;
  st->t_new = st->t + dt;
  /* Predictor; prescribed values at t_{n+1}.  The last displacement unless
   * every mode is resolved: the trapezoidal rule keeps the unresolved
   * element modes (omega dt >> 1) in a_n undamped, and dt^2/2 a_n moves them
   * by omega^2 dt^2 / 2 times their amplitude, onto distorted states where
   * K + M/(beta dt^2) is indefinite (CHOLMOD refuses it) or Newton diverges
   * into inverted elements (test_fem_stepper_beam).  With omega_max dt <= 1
   * the Taylor predictor is second order and saves an iteration. */
  const int taylor = st->opt.predictor == TL_PREDICTOR_TAYLOR ||
                     (st->opt.predictor == TL_PREDICTOR_AUTO && st->omega2_bound > 0.0 &&
                      st->omega2_bound * dt * dt <= 1.0);
  if (taylor)
    for (TlSparseIndex i = 0; i < st->n; ++i) nm->x[i] = st->u0[i] + dt * (st->v0[i] + 0.5 * dt * st->a0[i]);
  else
    memcpy(nm->x, st->u0, bytes);
  if (sys->ops->dirichlet) TL_CHECK(sys->ops->dirichlet(sys, st->t_new, nm->x, NULL, NULL));
  memcpy(st->u, nm->x, bytes); /* prescribed values for the residual */
  /* Force scale for the tolerance: inertia at the start (with the lumped
   * mass: a size, which needs no product with M), and the internal,
   * applied and residual forces at the predictor (which carries the
   * prescribed motion of the step). */
  double inertia = 0.0;
  for (TlSparseIndex i = 0; i < st->n; ++i) inertia = tl_max(inertia, fabs(st->m[i] * st->a0[i]));
  double scale = fmax(inertia, tl_stepper_max_abs(st->f_ext0, st->n));
  TL_CHECK(newmark_residual(st, nm->x, st->work));
  scale = fmax(scale, fmax(tl_stepper_max_abs(st->work, st->n), fmax(tl_stepper_max_abs(st->f_int, st->n), tl_stepper_max_abs(st->f_ext, st->n))));
  st->force_scale = scale;
  /* The residual cannot be resolved below the round-off of its inertia term
   * M (u - u_pred) / (beta dt^2), whose parts are of size m |u| / (beta dt^2). */
  double mmax = tl_stepper_max_abs(st->m, st->n), umax = 0.0;
  for (TlSparseIndex i = 0; i < st->n; ++i)
    umax = tl_max(umax, tl_max(fabs(st->u0[i]), fabs(nm->x[i])));
  st->force_floor = 64.0 * DBL_EPSILON * (mmax * umax / (st->opt.beta * dt * dt) + st->force_scale);
  st->u_scale = umax;
  memcpy(nm->r0, st->work, bytes);
  nm->r0_valid = 1;
  memcpy(st->v, st->v0, bytes);
  memcpy(st->a, st->a0, bytes);
  TlStatus s = tl_stepper_newton_solve(st, nm->x);
  nm->r0_valid = 0;
  if (s != TL_OK) return tl_stepper_reject(st, s, "Newmark", dt);
  memcpy(st->u, nm->x, bytes);
  newmark_kinematics(st, st->u, st->a, st->v);
  TL_CHECK(sys->ops->external_force(sys, st->t_new, st->u, st->f_ext));
  for (TlSparseIndex i = 0; i < st->n; ++i)
    st->W_ext += (st->u[i] - st->u0[i]) * (0.5 * (st->f_ext0[i] + st->f_ext[i]));
  if (sys->ops->commit) TL_CHECK(sys->ops->commit(sys));
  st->t = st->t_new;
  return TL_OK;
}

static void newmark_destroy(TlStepper *st)
{
  Newmark *nm = st->impl;
  if (!nm) return;
  tl_free(&nm->x);
  tl_free(&nm->r0);
  tl_free(&st->impl);
}

static const TlParam newmark_params[] = {
    {"beta", 0.25, 0, 0.5, "1", "Newmark beta (> 0); 1/4 with gamma 1/2: the average-acceleration rule",
     offsetof(TlStepperOptions, beta)},
    {"gamma", 0.5, 0, 1, "1", "Newmark gamma; above 1/2 damps the high modes", offsetof(TlStepperOptions, gamma)},
    {"predictor", 0, 0, 2, "1",
     "Newton's start: 0 auto (Taylor when omega_max dt <= 1, else the last displacement), 1 the last "
     "displacement, 2 Taylor u + dt v + dt^2/2 a",
     offsetof(TlStepperOptions, predictor)},
    {"lumped", 0, 0, 1, "1", "1: the lumped mass even where the system has a consistent one",
     offsetof(TlStepperOptions, lumped)},
    TL_STEPPER_NEWTON_PARAMS,
};

const TlStepperOps tl_stepper_newmark_ops = {
    .header = {"stepper", "newmark", "implicit Newmark-beta with Newton iterations (KINSOL or SUNNonlinSol_Newton)"},
    .implicit = 1,
    .consistent_mass = 1,
    .setup = newmark_setup,
    .initialise = newmark_initialise,
    .step = newmark_step,
    .destroy = newmark_destroy,
    .params = newmark_params,
    .n_params = (int)(sizeof newmark_params / sizeof newmark_params[0]),
};
