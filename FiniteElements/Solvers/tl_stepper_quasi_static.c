/* Quasi-static equilibrium with load stepping:
 *
 *   R(u) = f_int(u, 0) - lambda(t) f_ext(t, u) = 0,
 *   lambda(t) = min(t / ramp_time, 1)  (1 when ramp_time = 0),
 *   dR/du = K - lambda K_ext,
 *
 * solved by Newton at t + dt from the previous equilibrium; when Newton
 * fails the increment is halved (up to max_cuts times) and the remaining
 * interval is covered in smaller increments.
 *
 * With convergence = TL_CONVERGENCE_FORCE_RATIO the iteration is the plain
 * Newton loop of the FE x DEM codes (seeds/004 §2.5.3), tested on
 * |F|/|R| (tl_stepper.h): the out-of-balance force over the forces that
 * balance the internal ones, both 2-norms, so the test does not depend on
 * the units or the size of the increment. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_stepper.h"

typedef struct {
  double *x, *zero;
  double *du;    /* the last accepted increment (TAYLOR predictor) */
  double h_prev; /* its size in t (0: none yet) */
  unsigned char *dirichlet; /* n: 1 at the Dirichlet dofs */
  double ratio, force, reaction; /* the force-ratio test at the last iterate */
  double best;                   /* the smallest ratio of the increment */
  int loose;                     /* ... passed at the loose tolerance only */
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
  TL_CHECK(tl_calloc(&qs->dirichlet, (size_t)st->n, sizeof *qs->dirichlet));
  TL_CHECK(tl_calloc(&qs->du, (size_t)st->n, sizeof *qs->du));
  for (TlSparseIndex k = 0; k < st->sys->n_dirichlet; ++k) qs->dirichlet[st->sys->dirichlet_dofs[k]] = 1;
  const TlStepperOptions *o = &st->opt;
  if (o->convergence != TL_CONVERGENCE_RESIDUAL && o->convergence != TL_CONVERGENCE_FORCE_RATIO)
    TL_ERROR(TL_ERR_ARG, "quasi-static convergence test %d is neither RESIDUAL (%d) nor FORCE_RATIO (%d)",
             o->convergence, TL_CONVERGENCE_RESIDUAL, TL_CONVERGENCE_FORCE_RATIO);
  if (o->convergence == TL_CONVERGENCE_FORCE_RATIO) {
    if (!(o->ratio_tol > 0.0 && o->ratio_tol < 1.0) || !(o->ratio_tol_post >= o->ratio_tol && o->ratio_tol_post < 1.0))
      TL_ERROR(TL_ERR_ARG, "force-ratio tolerances %g (before the peak) and %g (after) must satisfy 0 < %g <= %g < 1",
               o->ratio_tol, o->ratio_tol_post, o->ratio_tol, o->ratio_tol_post);
    if (o->accept_loose_after < 0)
      TL_ERROR(TL_ERR_ARG, "accept_loose_after = %ld must be >= 0", o->accept_loose_after);
    if (!(o->peak_drop < 1.0)) TL_ERROR(TL_ERR_ARG, "peak_drop = %g must be below 1", o->peak_drop);
    if (!(o->ratio_diverge == 0.0 || o->ratio_diverge > 1.0))
      TL_ERROR(TL_ERR_ARG, "ratio_diverge = %g must be 0 (never) or above 1", o->ratio_diverge);
    if (o->line_search) TL_ERROR(TL_ERR_ARG, "the force-ratio test runs plain Newton steps: no line search");
  }
  TL_CHECK(tl_stepper_implicit_setup(st, qs_residual, qs_jacobian));
  return TL_OK;
}

static TlStatus qs_initialise(TlStepper *st)
{
  memset(st->v, 0, (size_t)st->n * sizeof(double));
  memset(st->a, 0, (size_t)st->n * sizeof(double));
  return TL_OK;
}

/* The force-ratio test (tl_stepper.h) at iterate x with residual r; the
 * stepper's f_int and f_ext are those of this residual evaluation. */
static int ratio_test(void *ctx, const double *x, const double *r, long k, double *measure)
{
  (void)x;
  TlStepper *st = ctx;
  QuasiStatic *qs = st->impl;
  const TlStepperOptions *o = &st->opt;
  double F2 = 0.0, R2 = 0.0;
  for (TlSparseIndex i = 0; i < st->n; ++i) {
    const double g = st->lambda * st->f_ext[i];
    if (qs->dirichlet[i]) {
      const double R = st->f_int[i] - g;
      R2 += R * R;
    } else {
      F2 += r[i] * r[i];
      R2 += g * g;
    }
  }
  qs->force = sqrt(F2);
  qs->reaction = sqrt(R2);
  /* Nothing loaded and nothing out of balance: equilibrium. */
  qs->ratio = F2 == 0.0 ? 0.0 : qs->force / qs->reaction;
  *measure = qs->ratio;
  qs->loose = 0;
  if (!isfinite(qs->ratio)) return R2 > 0.0 || !(F2 <= 0.0) ? TL_NEWTON_FAILED : TL_NEWTON_CONVERGED;
  if (qs->ratio <= (st->post_peak ? o->ratio_tol_post : o->ratio_tol)) {
    qs->loose = st->post_peak;
    return TL_NEWTON_CONVERGED;
  }
  if (!st->post_peak && o->accept_loose_after > 0 && k >= o->accept_loose_after && qs->ratio <= o->ratio_tol_post) {
    qs->loose = 1;
    return TL_NEWTON_CONVERGED;
  }
  if (k == 0 || qs->ratio < qs->best) qs->best = qs->ratio;
  if (o->ratio_diverge > 0.0 && k >= 2 && qs->ratio > o->ratio_diverge * qs->best) return TL_NEWTON_FAILED;
  return TL_NEWTON_CONTINUE;
}

static TlStatus ratio_solve(TlStepper *st, double *x)
{
  TlNewtonOptions no;
  tl_newton_options_default(&no);
  no.method = TL_NEWTON_PLAIN;
  no.max_iterations = st->opt.max_iterations;
  no.max_setup_calls = st->opt.reuse;
  no.keep_factors = st->opt.keep_factors;
  no.test = ratio_test;
  no.test_ctx = st;
  TL_CHECK(tl_newton_set_options(st->newton, &no));
  TL_CHECK(tl_newton_solve(st->newton, x));
  return TL_OK;
}

void tl_stepper_set_post_peak(TlStepper *st, int on) { st->post_peak = on != 0; }

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
  /* The residual test's scale; the force ratio needs none (and the internal
   * force at the last equilibrium would cost a DEM cell a relaxation). */
  if (st->opt.convergence != TL_CONVERGENCE_FORCE_RATIO) {
    TL_CHECK(sys->ops->internal_force(sys, st->t, st->u, qs->zero, st->f_int));
    st->force_scale = fmax(st->lambda * tl_stepper_max_abs(st->f_ext, st->n), tl_stepper_max_abs(st->f_int, st->n));
  }
  memcpy(qs->x, st->u, bytes);
  /* TAYLOR: the free dofs continue along the last increment (the path of a
   * monotonic load is smooth), which spares the law an iterate where only
   * the prescribed dofs have moved. */
  if (st->opt.predictor == TL_PREDICTOR_TAYLOR && qs->h_prev > 0.0)
    for (TlSparseIndex i = 0; i < st->n; ++i)
      if (!qs->dirichlet[i]) qs->x[i] += h / qs->h_prev * qs->du[i];
  if (sys->ops->dirichlet) TL_CHECK(sys->ops->dirichlet(sys, st->t_new, qs->x, NULL, NULL));
  memcpy(st->u, qs->x, bytes);
  double lambda0 = load_factor(st, st->t);
  const int ratio = st->opt.convergence == TL_CONVERGENCE_FORCE_RATIO;
  TlStatus s = ratio ? ratio_solve(st, qs->x) : tl_stepper_newton_solve(st, qs->x);
  TlNewtonStats ns;
  tl_newton_get_stats(st->newton, &ns);
  if (s != TL_OK) {
    st->last_step.failed_iterations += ns.last_iterations;
    return tl_stepper_reject(st, s, "quasi-static", h);
  }
  for (TlSparseIndex i = 0; i < st->n; ++i) qs->du[i] = qs->x[i] - st->u0[i];
  qs->h_prev = h;
  st->last_step.iterations += ns.last_iterations;
  st->last_step.increments++;
  if (ratio) {
    st->last_step.ratio = qs->ratio;
    st->last_step.force = qs->force;
    st->last_step.reaction = qs->reaction;
    st->last_step.loose += qs->loose;
    /* The peak of the reaction norm: from the next increment on, the loose tolerance. */
    if (st->opt.peak_drop >= 0.0 && qs->reaction < (1.0 - st->opt.peak_drop) * st->reaction_max) st->post_peak = 1;
    st->reaction_max = fmax(st->reaction_max, qs->reaction);
  }
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
  memset(&st->last_step, 0, sizeof st->last_step);
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
    st->last_step.cuts++;
    st->stats.rejected++;
    h *= 0.5;
    tl_newton_invalidate(st->newton);
  }
  st->t = t_end;
  st->last_step.post_peak = st->post_peak;
  return TL_OK;
}

static void qs_destroy(TlStepper *st)
{
  QuasiStatic *qs = st->impl;
  if (!qs) return;
  tl_free(&qs->x);
  tl_free(&qs->zero);
  tl_free(&qs->dirichlet);
  tl_free(&qs->du);
  tl_free(&st->impl);
}

static const TlParam qs_params[] = {
    {"ramp_time", 0, 0, 1e300, "s", "load ramp: lambda = min(t / ramp_time, 1); 0: the full load at once",
     offsetof(TlStepperOptions, ramp_time)},
    {"max_cuts", 10, 0, 60, "1", "halvings of a failed step before giving up (integer)",
     offsetof(TlStepperOptions, max_cuts)},
    {"predictor", 0, 0, 2, "1",
     "Newton's start: 2 the last increment extrapolated; 0 and 1 the last equilibrium",
     offsetof(TlStepperOptions, predictor)},
    {"convergence", 0, 0, 1, "1", "0: the residual's max norm against rtol; 1: the force ratio |F|/|R| of hierarchical FEM x DEM (Desrues et al.)",
     offsetof(TlStepperOptions, convergence)},
    {"ratio_tol", 1e-3, 0, 1e300, "1", "force ratio: |F|/|R| before the peak", offsetof(TlStepperOptions, ratio_tol)},
    {"ratio_tol_post", 1e-2, 0, 1e300, "1", "force ratio: |F|/|R| after the peak",
     offsetof(TlStepperOptions, ratio_tol_post)},
    {"accept_loose_after", 0, 0, 1e9, "1",
     "force ratio: accept within ratio_tol_post after this many iterations before the peak too; 0: never (integer)",
     offsetof(TlStepperOptions, accept_loose_after)},
    {"peak_drop", -1, -1e300, 1, "1",
     "force ratio: relative drop of |R| that marks the peak; negative: only tl_stepper_set_post_peak",
     offsetof(TlStepperOptions, peak_drop)},
    {"ratio_diverge", 10, 0, 1e300, "1",
     "force ratio: halve an increment once |F|/|R| exceeds this factor times its best (from the second iteration); "
     "0: never",
     offsetof(TlStepperOptions, ratio_diverge)},
    TL_STEPPER_NEWTON_PARAMS,
};

const TlStepperOps tl_stepper_quasi_static_ops = {
    .header = {"stepper", "quasi_static", "quasi-static Newton with load stepping"},
    .implicit = 1,
    .setup = qs_setup,
    .initialise = qs_initialise,
    .step = qs_step,
    .destroy = qs_destroy,
    .params = qs_params,
    .n_params = (int)(sizeof qs_params / sizeof qs_params[0]),
};
