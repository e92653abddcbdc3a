/* Quasi-static equilibrium with load stepping:
 *
 *   R(u) = f_int(u, 0) - lambda(t) f_ext(t, u) = 0,
 *   lambda(t) = min(t / ramp_time, 1)  (1 when ramp_time = 0),
 *   dR/du = K - lambda K_ext,
 *
 * solved by Newton at t + dt from the previous equilibrium; when Newton
 * fails the increment is halved (up to max_cuts times) and the remaining
 * interval is covered in smaller increments. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_stepper.h"

typedef struct {
  double *x, *zero;
} QuasiStatic;

static double load_factor(const TlStepper *st, double t)
{
  if (st->opt.ramp_time <= 0.0) return 1.0;
  return fmin(t / st->opt.ramp_time, 1.0);
}

static TlStatus qs_residual(void *ctx, const double *x, double *r)
{
  TlStepper *st = ctx;
  TlMechSystem *sys = st->sys;
  QuasiStatic *qs = st->impl;
  TL_CHECK(sys->ops->internal_force(sys, st->t_new, x, qs->zero, st->f_int));
  TL_CHECK(sys->ops->external_force(sys, st->t_new, x, st->f_ext));
  for (TlSparseIndex i = 0; i < st->n; ++i)
    r[i] = st->f_int[i] - st->lambda * st->f_ext[i];
  for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) {
    TlSparseIndex i = sys->dirichlet_dofs[k];
    r[i] = x[i] - st->u[i];
  }
  return TL_OK;
}

static TlStatus qs_jacobian(void *ctx, const double *x, TlSparse *J)
{
  TlStepper *st = ctx;
  TlMechSystem *sys = st->sys;
  QuasiStatic *qs = st->impl;
  TL_CHECK(sys->ops->internal_tangent(sys, st->t_new, x, qs->zero, 1.0, 0.0, J));
  if (sys->ops->external_tangent)
    TL_CHECK(sys->ops->external_tangent(sys, st->t_new, x, -st->lambda, J));
  tl_sparse_constrain(J, sys->n_dirichlet, sys->dirichlet_dofs, 1.0);
  return TL_OK;
}

static TlStatus qs_setup(TlStepper *st)
{
  QuasiStatic *qs = NULL;
  TL_CHECK(TL_NEW(qs));
  st->impl = qs;
  TL_CHECK(tl_calloc(&qs->x, (size_t)st->n, sizeof *qs->x));
  TL_CHECK(tl_calloc(&qs->zero, (size_t)st->n, sizeof *qs->zero));
  TL_CHECK(tl_stepper_implicit_setup(st, qs_residual, qs_jacobian));
  return TL_OK;
}

static TlStatus qs_initialise(TlStepper *st)
{
  memset(st->v, 0, (size_t)st->n * sizeof(double));
  memset(st->a, 0, (size_t)st->n * sizeof(double));
  return TL_OK;
}

/* One increment t -> t + h from the current equilibrium. */
static TlStatus qs_increment(TlStepper *st, double h)
{
  TlMechSystem *sys = st->sys;
  QuasiStatic *qs = st->impl;
  size_t bytes = (size_t)st->n * sizeof(double);
  tl_stepper_save_start(st);
  st->t_new = st->t + h;
  st->lambda = load_factor(st, st->t_new);
  TL_CHECK(sys->ops->external_force(sys, st->t_new, st->u, st->f_ext));
  TL_CHECK(sys->ops->internal_force(sys, st->t, st->u, qs->zero, st->f_int));
  st->force_scale = fmax(st->lambda * tl_stepper_max_abs(st->f_ext, st->n),
                         tl_stepper_max_abs(st->f_int, st->n));
  memcpy(qs->x, st->u, bytes);
  if (sys->ops->dirichlet) TL_CHECK(sys->ops->dirichlet(sys, st->t_new, qs->x, NULL, NULL));
  memcpy(st->u, qs->x, bytes);
  double lambda0 = load_factor(st, st->t);
  TlStatus s = tl_stepper_newton_solve(st, qs->x);
  if (s != TL_OK) return tl_stepper_reject(st, s, "quasi-static", h);
  memcpy(st->u, qs->x, bytes);
  TL_CHECK(sys->ops->external_force(sys, st->t_new, st->u, st->f_ext));
  for (TlSparseIndex i = 0; i < st->n; ++i)
    st->W_ext += (st->u[i] - st->u0[i]) *
                 (0.5 * (lambda0 * st->f_ext0[i] + st->lambda * st->f_ext[i]));
  if (sys->ops->commit) TL_CHECK(sys->ops->commit(sys));
  st->t = st->t_new;
  return TL_OK;
}

static TlStatus qs_step(TlStepper *st, double dt)
{
  const double t_end = st->t + dt;
  double h = dt;
  int cuts = 0;
  while (st->t < t_end - 1e-14 * fabs(t_end)) {
    h = fmin(h, t_end - st->t);
    TlStatus s = qs_increment(st, h);
    if (s == TL_OK) continue;
    if (s != TL_ERR_CONVERGENCE && s != TL_ERR_NUMERIC) return tl_error_trace(s, __FILE__, __LINE__);
    if (cuts >= st->opt.max_cuts) {
      char why[3072];
      snprintf(why, sizeof why, "%s", tl_error_message());
      TL_ERROR(s, "%s\n  quasi-static load step still failing after %d halvings (increment %.3g)",
               why, cuts, h);
    }
    ++cuts;
    st->stats.rejected++;
    h *= 0.5;
    tl_newton_invalidate(st->newton);
  }
  st->t = t_end;
  return TL_OK;
}

static void qs_destroy(TlStepper *st)
{
  QuasiStatic *qs = st->impl;
  if (!qs) return;
  tl_free(&qs->x);
  tl_free(&qs->zero);
  tl_free(&st->impl);
}

const TlStepperOps tl_stepper_quasi_static_ops = {
    .header = {"stepper", "quasi_static", "quasi-static Newton with load stepping"},
    .implicit = 1,
    .setup = qs_setup,
    .initialise = qs_initialise,
    .step = qs_step,
    .destroy = qs_destroy,
};
