#include "tl_stepper.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_linear_solver.h"
#include "tl_math.h"
#include "tl_memory.h"
#include "tl_registry.h"
#include "tl_timer.h"

/* The stepper types whose tables define the options' defaults. */
static const TlStepperOps *const builtin_steppers[] = {&tl_stepper_newmark_ops, &tl_stepper_central_difference_ops,
                                                        &tl_stepper_quasi_static_ops};
enum { N_BUILTIN_STEPPERS = sizeof builtin_steppers / sizeof builtin_steppers[0] };

/* The C type of the integer fields of TlStepperOptions (the parameter
 * tables store doubles; every other numeric field is a double). */
static const struct {
  size_t offset;
  int is_long;
} integer_fields[] = {
    {offsetof(TlStepperOptions, max_iterations), 1}, {offsetof(TlStepperOptions, reuse), 1},
    {offsetof(TlStepperOptions, accept_loose_after), 1}, {offsetof(TlStepperOptions, keep_factors), 0},
    {offsetof(TlStepperOptions, line_search), 0},     {offsetof(TlStepperOptions, nonlinear_solver), 0},
    {offsetof(TlStepperOptions, lumped), 0},          {offsetof(TlStepperOptions, predictor), 0},
    {offsetof(TlStepperOptions, allow_unstable), 0},  {offsetof(TlStepperOptions, critical_bound), 0},
    {offsetof(TlStepperOptions, max_cuts), 0},        {offsetof(TlStepperOptions, convergence), 0},
};

/* -1: a double field; 0: int; 1: long. */
static int field_kind(size_t offset)
{
  for (size_t k = 0; k < sizeof integer_fields / sizeof integer_fields[0]; ++k)
    if (integer_fields[k].offset == offset) return integer_fields[k].is_long;
  return -1;
}

static double field_get(const TlStepperOptions *o, const TlParam *p)
{
  const char *at = (const char *)o + p->offset;
  switch (field_kind(p->offset)) {
  case 0: return (double)*(const int *)(const void *)at;
  case 1: return (double)*(const long *)(const void *)at;
  default: return *(const double *)(const void *)at;
  }
}

static void field_put(TlStepperOptions *o, const TlParam *p, double v)
{
  char *at = (char *)o + p->offset;
  switch (field_kind(p->offset)) {
  case 0: *(int *)(void *)at = (int)v; break;
  case 1: *(long *)(void *)at = (long)v; break;
  default: *(double *)(void *)at = v;
  }
}

void tl_stepper_options_default(TlStepperOptions *o)
{
  memset(o, 0, sizeof *o);
  o->solver = NULL;
  for (int k = 0; k < N_BUILTIN_STEPPERS; ++k)
    for (int j = 0; j < builtin_steppers[k]->n_params; ++j) field_put(o, &builtin_steppers[k]->params[j], builtin_steppers[k]->params[j].def);
}

static TlStatus find_stepper(const char *type, const TlStepperOps **ops)
{
  const TlOpsHeader *h = NULL;
  TL_CHECK(tl_stepper_register_all());
  TL_CHECK(tl_registry_find("stepper", type, &h));
  *ops = (const TlStepperOps *)h;
  return TL_OK;
}

static void param_names(const TlStepperOps *ops, char *list, size_t size)
{
  size_t len = 0;
  list[0] = '\0';
  for (int j = 0; j < ops->n_params && len < size; ++j)
    len += (size_t)snprintf(list + len, size - len, "%s%s", j ? ", " : "", ops->params[j].name);
}

/* A value for parameter p: inside its range, whole for an integer field. */
static TlStatus check_value(const char *type, const TlParam *p, double v)
{
  if (!(v >= p->lo && v <= p->hi))
    TL_ERROR(TL_ERR_ARG, "stepper '%s' setting %s = %g outside [%g, %g]", type, p->name, v, p->lo, p->hi);
  if (field_kind(p->offset) >= 0 && v != floor(v))
    TL_ERROR(TL_ERR_ARG, "stepper '%s' setting %s = %g is not an integer", type, p->name, v);
  return TL_OK;
}

TlStatus tl_stepper_options_set(TlStepperOptions *o, const char *type, const char *name, double value)
{
  const TlStepperOps *ops = NULL;
  TL_CHECK(find_stepper(type, &ops));
  const TlParam *p = tl_param_find(ops->params, ops->n_params, name ? name : "");
  if (!p) {
    char list[1024];
    param_names(ops, list, sizeof list);
    TL_ERROR(TL_ERR_NOT_FOUND, "stepper '%s' has no setting '%s' (settings: %s)", type, name ? name : "(null)", list);
  }
  TL_CHECK(check_value(type, p, value));
  field_put(o, p, value);
  return TL_OK;
}

TlStatus tl_stepper_options_get(const TlStepperOptions *o, const char *name, double *value)
{
  for (int k = 0; k < N_BUILTIN_STEPPERS; ++k) {
    const TlParam *p = tl_param_find(builtin_steppers[k]->params, builtin_steppers[k]->n_params, name ? name : "");
    if (p) return (*value = field_get(o, p)), TL_OK;
  }
  TL_ERROR(TL_ERR_NOT_FOUND, "no stepper reads an option '%s'", name ? name : "(null)");
}

static TlStatus register_stepper(const TlStepperOps *ops)
{
  const TlTypeEntry e = {"stepper", ops->header.name, ops->header.description, NULL, ops, ops->params, ops->n_params};
  TL_CHECK(tl_registry_register(&e));
  return TL_OK;
}

TlStatus tl_stepper_register_all(void)
{
  for (int k = 0; k < N_BUILTIN_STEPPERS; ++k) TL_CHECK(register_stepper(builtin_steppers[k]));
  TL_CHECK(tl_linear_solver_register_all());
  return TL_OK;
}

static TlStatus check_options(const TlStepperOptions *o)
{
  if (!(o->beta > 0.0 && o->beta <= 0.5))
    TL_ERROR(TL_ERR_ARG, "Newmark beta = %g outside (0, 0.5]", o->beta);
  if (!(o->gamma >= 0.0 && o->gamma <= 1.0))
    TL_ERROR(TL_ERR_ARG, "Newmark gamma = %g outside [0, 1]", o->gamma);
  if (!(o->rtol > 0.0) || !(o->atol >= 0.0))
    TL_ERROR(TL_ERR_ARG, "Newton tolerances rtol = %g (> 0), atol = %g (>= 0)", o->rtol, o->atol);
  if (o->max_iterations < 1 || o->reuse < 1)
    TL_ERROR(TL_ERR_ARG, "max_iterations = %ld and reuse = %ld must be >= 1", o->max_iterations,
             o->reuse);
  if (!(o->blowup > 1.0)) TL_ERROR(TL_ERR_ARG, "blow-up factor %g must exceed 1", o->blowup);
  if (!(o->ramp_time >= 0.0)) TL_ERROR(TL_ERR_ARG, "ramp_time = %g must be >= 0", o->ramp_time);
  if (o->predictor < TL_PREDICTOR_AUTO || o->predictor > TL_PREDICTOR_TAYLOR)
    TL_ERROR(TL_ERR_ARG, "Newmark predictor %d is none of AUTO (0), LAST (1), TAYLOR (2)", o->predictor);
  if (o->nonlinear_solver != TL_NEWTON_KINSOL && o->nonlinear_solver != TL_NEWTON_SUNNONLINSOL)
    TL_ERROR(TL_ERR_ARG, "nonlinear solver %d is neither KINSOL (%d) nor SUNNONLINSOL (%d)", o->nonlinear_solver,
             TL_NEWTON_KINSOL, TL_NEWTON_SUNNONLINSOL);
  if (o->nonlinear_solver == TL_NEWTON_SUNNONLINSOL && o->line_search)
    TL_ERROR(TL_ERR_ARG, "line search asked with the SUNNONLINSOL nonlinear solver; only KINSOL has one");
  if (o->max_cuts < 0 || o->max_cuts > 60)
    TL_ERROR(TL_ERR_ARG, "max_cuts = %d outside [0, 60]", o->max_cuts);
  return TL_OK;
}

TlStatus tl_stepper_create(const char *type, TlMechSystem *sys, const TlStepperOptions *options,
                           TlStepper **out)
{
  const TlOpsHeader *h = NULL;
  TlStepper *st = NULL;
  TlStatus s = TL_OK;
  *out = NULL;
  TL_CHECK(tl_stepper_register_all());
  TL_CHECK(tl_registry_find("stepper", type, &h));
  if (!sys || sys->ndof <= 0) TL_ERROR(TL_ERR_ARG, "mechanical system missing or without dofs");
  const TlMechSystemOps *so = sys->ops;
  if (!so->create_matrix || !so->internal_force || !so->internal_tangent || !so->external_force ||
      !so->lumped_mass)
    TL_ERROR(TL_ERR_ARG, "system '%s' lacks a required op", so->header.name);
  TL_CHECK(TL_NEW(st));
  st->ops = (const TlStepperOps *)h;
  st->sys = sys;
  st->n = sys->ndof;
  if (options) st->opt = *options;
  else tl_stepper_options_default(&st->opt);
  TL_CHECK_GOTO(s, check_options(&st->opt), fail);
  for (int j = 0; j < st->ops->n_params; ++j)
    TL_CHECK_GOTO(s, check_value(type, &st->ops->params[j], field_get(&st->opt, &st->ops->params[j])), fail);
  size_t n = (size_t)st->n;
  double **vecs[] = {&st->u, &st->v, &st->a, &st->u0, &st->v0, &st->a0, &st->m,
                     &st->f_ext, &st->f_ext0, &st->f_int, &st->work};
  for (size_t k = 0; k < sizeof vecs / sizeof vecs[0]; ++k)
    TL_CHECK_GOTO(s, tl_calloc(vecs[k], n, sizeof(double)), fail);
  TL_CHECK_GOTO(s, so->lumped_mass(sys, st->m), fail);
  for (TlSparseIndex i = 0; i < st->n; ++i)
    if (!(st->m[i] > 0.0) || !isfinite(st->m[i])) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "lumped mass at dof %lld is %g; it must be positive", (long long)i, st->m[i]);
      goto fail;
    }
  TL_CHECK_GOTO(s, st->ops->setup(st), fail);
  *out = st;
  return TL_OK;
fail:
  tl_stepper_destroy(&st);
  return s;
}

void tl_stepper_mass_times(const TlStepper *st, const double *x, double *y)
{
  if (st->M) {
    tl_sparse_matvec(st->M_apply ? st->M_apply : st->M, x, y);
    return;
  }
  for (TlSparseIndex i = 0; i < st->n; ++i) y[i] = st->m[i] * x[i];
}

TlStatus tl_stepper_set_state(TlStepper *st, double t, const double *u, const double *v)
{
  size_t bytes = (size_t)st->n * sizeof(double);
  if (u) memcpy(st->u, u, bytes);
  else memset(st->u, 0, bytes);
  if (v) memcpy(st->v, v, bytes);
  else memset(st->v, 0, bytes);
  memset(st->a, 0, bytes);
  st->t = t;
  TlMechSystem *sys = st->sys;
  for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) {
    TlSparseIndex i = sys->dirichlet_dofs[k];
    st->u[i] = st->v[i] = 0.0;
  }
  if (sys->ops->dirichlet) TL_CHECK(sys->ops->dirichlet(sys, t, st->u, st->v, st->a));
  st->W_ext = 0.0;
  TL_CHECK(st->ops->initialise(st));
  TL_CHECK(sys->ops->external_force(sys, t, st->u, st->f_ext));
  return TL_OK;
}

TlStatus tl_stepper_step(TlStepper *st, double dt)
{
  if (!(dt > 0.0) || !isfinite(dt)) TL_ERROR(TL_ERR_ARG, "time step dt = %g must be positive", dt);
  double t0 = tl_wtime();
  TlStatus s = st->ops->step(st, dt);
  st->stats.t_step += tl_wtime() - t0;
  if (s != TL_OK) {
    st->stats.rejected++;
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  st->stats.steps++;
  return TL_OK;
}

TlStatus tl_stepper_energies(TlStepper *st, TlEnergies *e)
{
  tl_stepper_mass_times(st, st->v, st->work);
  double k = 0.0;
  for (TlSparseIndex i = 0; i < st->n; ++i) k += st->v[i] * st->work[i];
  e->kinetic = 0.5 * k;
  e->strain = 0.0;
  if (st->sys->ops->strain_energy) TL_CHECK(st->sys->ops->strain_energy(st->sys, st->u, &e->strain));
  e->external_work = st->W_ext;
  e->total = e->kinetic + e->strain - e->external_work;
  return TL_OK;
}

void tl_stepper_get_stats(const TlStepper *st, TlStepperStats *stats)
{
  *stats = st->stats;
  if (st->newton) {
    TlNewtonStats ns;
    tl_newton_get_stats(st->newton, &ns);
    stats->newton_iterations = ns.iterations;
    stats->factorisations = ns.linear.n_numeric;
    stats->linear_solves = ns.linear.n_solve;
    stats->t_factor = ns.linear.t_numeric + ns.linear.t_symbolic;
    stats->t_solve = ns.linear.t_solve;
    stats->t_residual = ns.t_residual;
    stats->t_jacobian = ns.t_jacobian;
  }
}

void tl_stepper_destroy(TlStepper **stp)
{
  if (!stp || !*stp) return;
  TlStepper *st = *stp;
  if (st->ops && st->ops->destroy) st->ops->destroy(st);
  tl_newton_destroy(&st->newton);
  tl_sparse_destroy(&st->J);
  tl_sparse_destroy(&st->M);
  tl_sparse_destroy(&st->M_apply);
  double **vecs[] = {&st->u, &st->v, &st->a, &st->u0, &st->v0, &st->a0, &st->m,
                     &st->f_ext, &st->f_ext0, &st->f_int, &st->work};
  for (size_t k = 0; k < sizeof vecs / sizeof vecs[0]; ++k) tl_free(vecs[k]);
  tl_free(stp);
}

/* ------------------------------------------------ implicit helpers */
static const char *solver_name(const TlStepper *st)
{
  if (st->opt.solver) return st->opt.solver;
  return st->sys->symmetric ? "cholmod" : "klu";
}

TlStatus tl_stepper_implicit_setup(TlStepper *st, TlNewtonResidual residual,
                                   TlNewtonJacobian jacobian)
{
  const char *name = solver_name(st);
  int upper = 0;
  TL_CHECK(tl_linear_solver_needs_upper(name, &upper));
  if (upper && !st->sys->symmetric)
    TL_ERROR(TL_ERR_ARG, "solver '%s' needs a symmetric tangent; system '%s' is not symmetric",
             name, st->sys->ops->header.name);
  TL_CHECK(st->sys->ops->create_matrix(st->sys, upper, &st->J));
  if (st->J->n != st->n)
    TL_ERROR(TL_ERR_ARG, "system matrix has %lld rows for %lld dofs", (long long)st->J->n,
             (long long)st->n);
  /* The consistent mass shares the Jacobian's pattern (one matrix, one axpy). */
  if (st->sys->ops->consistent_mass && !st->opt.lumped && st->ops->consistent_mass) {
    TL_CHECK(tl_sparse_duplicate(st->J, &st->M));
    TL_CHECK(st->sys->ops->consistent_mass(st->sys, 1.0, st->M));
    TL_CHECK(tl_sparse_compress(st->M, &st->M_apply));
  }
  TlNewtonOptions no;
  tl_newton_options_default(&no);
  no.method = st->opt.nonlinear_solver;
  no.max_iterations = st->opt.max_iterations;
  no.max_setup_calls = st->opt.reuse;
  no.keep_factors = st->opt.keep_factors;
  no.line_search = st->opt.line_search;
  TL_CHECK(tl_newton_create(st->n, st->J, name, &no, residual, jacobian, st, &st->newton));
  return TL_OK;
}

/* Solves with the tolerance max(atol, rtol * force_scale). */
TlStatus tl_stepper_newton_solve(TlStepper *st, double *x)
{
  TlNewtonOptions no;
  tl_newton_options_default(&no);
  no.ftol = fmax(fmax(st->opt.atol, st->opt.rtol * st->force_scale), st->force_floor);
  if (!(no.ftol > 0.0)) no.ftol = 1e-300;
  no.max_iterations = st->opt.max_iterations;
  no.max_setup_calls = st->opt.reuse;
  no.keep_factors = st->opt.keep_factors;
  no.line_search = st->opt.line_search;
  no.method = st->opt.nonlinear_solver;
  /* A system that commits trial state needs it from the accepted iterate. */
  no.evaluate_solution = st->sys->ops->commit != NULL;
  double us = 0.0;
  for (TlSparseIndex i = 0; i < st->n; ++i) us = tl_max(us, fabs(x[i]));
  no.u_scale = fmax(st->u_scale, us) > 0.0 ? fmax(st->u_scale, us) : 1.0;
  TL_CHECK(tl_newton_set_options(st->newton, &no));
  TL_CHECK(tl_newton_solve(st->newton, x));
  return TL_OK;
}

/* ----------------------------------------- largest eigenvalue of M^-1 K */
TlStatus tl_stepper_max_omega2(TlStepper *st, double *omega2)
{
  TlMechSystem *sys = st->sys;
  if (st->opt.critical_bound && sys->ops->max_frequency_squared) {
    TL_CHECK(sys->ops->max_frequency_squared(sys, st->u, omega2));
    return TL_OK;
  }
  /* Lanczos on the symmetric form S = D^-1/2 K D^-1/2 (D = lumped mass),
   * Dirichlet dofs removed; the largest Ritz value (largest eigenvalue of
   * the tridiagonal T_j, by Sturm bisection) rises to the largest
   * eigenvalue from below and converges far faster than power iteration. */
  enum { MAX_LANCZOS = 600 };
  TlSparse *K = NULL;
  TlStatus s = TL_OK;
  double *q = NULL, *qp = NULL, *w = NULL, *isd = NULL;
  double alpha[MAX_LANCZOS], beta[MAX_LANCZOS];
  TL_CHECK(sys->ops->create_matrix(sys, sys->symmetric, &K));
  TL_CHECK_GOTO(s, sys->ops->internal_tangent(sys, st->t, st->u, st->v, 1.0, 0.0, K), done);
  if (sys->ops->external_tangent)
    TL_CHECK_GOTO(s, sys->ops->external_tangent(sys, st->t, st->u, -1.0, K), done);
  tl_sparse_constrain(K, sys->n_dirichlet, sys->dirichlet_dofs, 0.0);
  TL_CHECK_GOTO(s, tl_calloc(&q, (size_t)st->n, sizeof *q), done);
  TL_CHECK_GOTO(s, tl_calloc(&qp, (size_t)st->n, sizeof *qp), done);
  TL_CHECK_GOTO(s, tl_calloc(&w, (size_t)st->n, sizeof *w), done);
  TL_CHECK_GOTO(s, tl_calloc(&isd, (size_t)st->n, sizeof *isd), done);
  for (TlSparseIndex i = 0; i < st->n; ++i) isd[i] = 1.0 / sqrt(st->m[i]);
  /* A deterministic, non-smooth start vector reaches the high modes. */
  double nq = 0.0;
  for (TlSparseIndex i = 0; i < st->n; ++i) {
    q[i] = (i % 2 ? 1.0 : -1.0) * (1.0 + 0.37 * (double)(i % 7));
    nq += q[i] * q[i];
  }
  for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) q[sys->dirichlet_dofs[k]] = 0.0;
  nq = 0.0;
  for (TlSparseIndex i = 0; i < st->n; ++i) nq += q[i] * q[i];
  for (TlSparseIndex i = 0; i < st->n; ++i) q[i] /= sqrt(nq);
  double lambda = 0.0, prev = -1.0;
  int j = 0;
  for (; j < MAX_LANCZOS; ++j) {
    for (TlSparseIndex i = 0; i < st->n; ++i) w[i] = q[i] * isd[i];
    tl_sparse_matvec(K, w, st->work);
    double a = 0.0;
    for (TlSparseIndex i = 0; i < st->n; ++i) {
      w[i] = st->work[i] * isd[i] - (j > 0 ? beta[j - 1] * qp[i] : 0.0);
      a += q[i] * w[i];
    }
    double b = 0.0;
    for (TlSparseIndex i = 0; i < st->n; ++i) {
      w[i] -= a * q[i];
      b += w[i] * w[i];
    }
    alpha[j] = a;
    beta[j] = sqrt(b);
    /* Largest eigenvalue of T (j+1 x j+1) by bisection on the Sturm count. */
    double hi = 0.0, lo = 0.0;
    for (int i = 0; i <= j; ++i) {
      double r = fabs(i > 0 ? beta[i - 1] : 0.0) + fabs(i < j ? beta[i] : 0.0);
      hi = fmax(hi, alpha[i] + r);
      lo = fmin(lo, alpha[i] - r);
    }
    for (int it = 0; it < 200 && hi - lo > 1e-15 * fabs(hi); ++it) {
      double x = 0.5 * (lo + hi), d = 1.0;
      int below = 0;
      for (int i = 0; i <= j; ++i) {
        d = alpha[i] - x - (i > 0 ? beta[i - 1] * beta[i - 1] / d : 0.0);
        if (d == 0.0) d = -1e-300;
        if (d < 0.0) ++below;
      }
      if (below == j + 1) hi = x; /* every eigenvalue below x */
      else lo = x;
    }
    lambda = 0.5 * (lo + hi);
    if (j > 4 && fabs(lambda - prev) <= 1e-13 * fabs(lambda)) break;
    prev = lambda;
    if (!(beta[j] > 1e-14 * fabs(lambda))) break; /* invariant subspace found */
    for (TlSparseIndex i = 0; i < st->n; ++i) {
      qp[i] = q[i];
      q[i] = w[i] / beta[j];
    }
  }
  if (!(lambda > 0.0) || !isfinite(lambda)) {
    s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__,
                     "largest eigenvalue of M^-1 K is %g; the stiffness is not positive", lambda);
    goto done;
  }
  *omega2 = lambda;
done:
  tl_free(&q);
  tl_free(&qp);
  tl_free(&w);
  tl_free(&isd);
  tl_sparse_destroy(&K);
  return s;
}

TlStatus tl_stepper_critical_dt(TlStepper *st, double *dt_crit)
{
  double w2 = 0.0;
  TL_CHECK(tl_stepper_max_omega2(st, &w2));
  *dt_crit = 2.0 / sqrt(w2);
  return TL_OK;
}

TlStatus tl_stepper_reject(TlStepper *st, TlStatus s, const char *what, double dt)
{
  size_t bytes = (size_t)st->n * sizeof(double);
  memcpy(st->u, st->u0, bytes);
  memcpy(st->v, st->v0, bytes);
  memcpy(st->a, st->a0, bytes);
  memcpy(st->f_ext, st->f_ext0, bytes);
  if (st->sys->ops->rollback) st->sys->ops->rollback(st->sys);
  char why[3072];
  snprintf(why, sizeof why, "%s", tl_error_message());
  return tl_error_set(s, __FILE__, __LINE__, "%s\n  %s step t = %.9g -> %.9g (dt = %.3g) rejected",
                      why, what, st->t, st->t + dt, dt);
}

void tl_stepper_save_start(TlStepper *st)
{
  size_t bytes = (size_t)st->n * sizeof(double);
  memcpy(st->u0, st->u, bytes);
  memcpy(st->v0, st->v, bytes);
  memcpy(st->a0, st->a, bytes);
  memcpy(st->f_ext0, st->f_ext, bytes);
}

double tl_stepper_max_abs(const double *x, TlSparseIndex n)
{
  double m = 0.0;
  for (TlSparseIndex i = 0; i < n; ++i) m = tl_max(m, fabs(x[i]));
  return m;
}
