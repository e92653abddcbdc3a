#include "tl_newton.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kinsol/kinsol.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>

#include "tl_memory.h"
#include "tl_timer.h"

struct TlNewton {
  TlSparseIndex n;
  TlSparse *J;
  TlLinearSolver *ls;
  TlNewtonOptions opt;
  TlNewtonResidual residual;
  TlNewtonJacobian jacobian;
  void *ctx;
  SUNContext sunctx;
  void *kin;
  N_Vector x, scale, uscale;
  SUNMatrix Jmat;
  SUNLinearSolver Lsol;
  TlNewtonStats stats;
  TlStatus callback_status; /* first callback error of the current solve */
  char callback_message[1024];
  double history[TL_NEWTON_HISTORY];
  int n_history;
  int factored; /* valid numeric factors exist */
  long since_factor; /* linear solves with the current factors */
  /* SUNNONLINSOL: the generic Newton solver on the correction ycor from
   * y0 = the start; xtrial = y0 + ycor, the last point F was evaluated at
   * (where a factorisation takes its Jacobian). */
  SUNNonlinearSolver nls;
  N_Vector y0, ycor, weight;
  double *xtrial, *r_start, *rows;
  int start_valid;  /* r_start = F(y0), evaluated before the iteration */
  double jnorm;     /* ||J||_inf of the current factors */
  double crate;     /* convergence-rate estimate, kept across solves */
  double delp;      /* |d_{m-1}| in the current solve */
  int diagnosis;    /* why the correction test gave up (CTEST_*) */
  double corrections[TL_NEWTON_HISTORY];
  int n_corrections;
  /* PLAIN: the residual and correction of the loop, the test's measures. */
  double *r_plain, *d_plain;
  double measures[TL_NEWTON_HISTORY];
  int n_measures;
};

enum { CTEST_NONE = 0, CTEST_DIVERGING = 1, CTEST_NOT_FINITE = 2 };
/* CVODE's constants: rate decay bound and divergence ratio. */
static const double CRDOWN = 0.3, RDIV = 2.0;

/* ------------------------------------------------ the SUNMatrix wrapper */
static SUNMatrix_ID mat_getid(SUNMatrix A)
{
  (void)A;
  return SUNMATRIX_CUSTOM;
}
static int mat_zero(SUNMatrix A)
{
  tl_sparse_zero(((TlNewton *)A->content)->J);
  return 0;
}
static void mat_destroy(SUNMatrix A)
{
  A->content = NULL;
  SUNMatFreeEmpty(A);
}

/* ---------------------------------------- the SUNLinearSolver wrapper */
static SUNLinearSolver_Type ls_gettype(SUNLinearSolver S)
{
  (void)S;
  return SUNLINEARSOLVER_DIRECT;
}
static SUNLinearSolver_ID ls_getid(SUNLinearSolver S)
{
  (void)S;
  return SUNLINEARSOLVER_CUSTOM;
}
static void record_callback_error(TlNewton *nw, TlStatus st)
{
  if (nw->callback_status != TL_OK) return;
  nw->callback_status = st;
  snprintf(nw->callback_message, sizeof nw->callback_message, "%s", tl_error_message());
}
static int ls_setup(SUNLinearSolver S, SUNMatrix A)
{
  (void)A;
  TlNewton *nw = S->content;
  nw->factored = 0;
  TlStatus st = tl_linear_solver_factor(nw->ls, nw->J);
  if (st != TL_OK) {
    record_callback_error(nw, st);
    return SUNLS_PACKAGE_FAIL_UNREC;
  }
  nw->factored = 1;
  nw->since_factor = 0;
  return SUNLS_SUCCESS;
}
static int ls_solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, realtype tol)
{
  (void)A;
  (void)tol;
  TlNewton *nw = S->content;
  TlStatus st = tl_linear_solver_solve(nw->ls, N_VGetArrayPointer(b), N_VGetArrayPointer(x));
  nw->since_factor++;
  if (st != TL_OK) {
    record_callback_error(nw, st);
    return SUNLS_PACKAGE_FAIL_UNREC;
  }
  return SUNLS_SUCCESS;
}
static int ls_free(SUNLinearSolver S)
{
  S->content = NULL;
  SUNLinSolFreeEmpty(S);
  return 0;
}

/* ------------------------------------------------- KINSOL callbacks */
/* fv = F(xv), its max norm appended to the history; 0, or -1 with the
 * error recorded. */
static int evaluate_residual(TlNewton *nw, const double *xv, double *fv)
{
  double t0 = tl_wtime();
  TlStatus st = nw->residual(nw->ctx, xv, fv);
  nw->stats.t_residual += tl_wtime() - t0;
  nw->stats.residual_evaluations++;
  if (st != TL_OK) {
    record_callback_error(nw, st);
    return -1;
  }
  double norm = 0.0;
  for (TlSparseIndex i = 0; i < nw->n; ++i) {
    double a = fabs(fv[i]);
    if (!(a <= HUGE_VAL) || a != a) {
      char msg[160];
      snprintf(msg, sizeof msg, "residual is not finite at dof %lld", (long long)i);
      tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "%s", msg);
      record_callback_error(nw, TL_ERR_NUMERIC);
      return -1;
    }
    if (a > norm) norm = a;
  }
  if (nw->n_history < TL_NEWTON_HISTORY) nw->history[nw->n_history++] = norm;
  else nw->history[TL_NEWTON_HISTORY - 1] = norm;
  return 0;
}

static int kin_residual(N_Vector x, N_Vector f, void *user)
{
  return evaluate_residual(user, N_VGetArrayPointer(x), N_VGetArrayPointer(f));
}

static int kin_jacobian(N_Vector x, N_Vector f, SUNMatrix J, void *user, N_Vector t1, N_Vector t2)
{
  (void)f;
  (void)J;
  (void)t1;
  (void)t2;
  TlNewton *nw = user;
  double t0 = tl_wtime();
  tl_sparse_zero(nw->J);
  TlStatus st = nw->jacobian(nw->ctx, N_VGetArrayPointer(x), nw->J);
  nw->stats.t_jacobian += tl_wtime() - t0;
  nw->stats.jacobian_evaluations++;
  if (st != TL_OK) {
    record_callback_error(nw, st);
    return -1;
  }
  return 0;
}

static void kin_silent(int code, const char *module, const char *function, char *msg, void *user)
{
  (void)code;
  (void)module;
  (void)function;
  (void)msg;
  (void)user; /* KINSOL's messages are folded into the returned error */
}

/* ----------------------------------------- SUNNonlinSol callbacks */
/* ||J||_inf, the largest absolute row sum (upper storage mirrored). */
static double jacobian_norm(const TlSparse *J, double *rows)
{
  memset(rows, 0, (size_t)J->n * sizeof *rows);
  for (TlSparseIndex j = 0; j < J->n; ++j)
    for (TlSparseIndex p = J->colptr[j]; p < J->colptr[j + 1]; ++p) {
      TlSparseIndex i = J->rowind[p];
      double a = fabs(J->values[p]);
      rows[i] += a;
      if (J->symmetric && i != j) rows[j] += a;
    }
  double m = 0.0;
  for (TlSparseIndex i = 0; i < J->n; ++i) m = fmax(m, rows[i]);
  return m;
}

/* Fresh factors of the Jacobian at x; the rate estimate starts again. */
static int factor_at(TlNewton *nw, const double *x)
{
  nw->factored = 0;
  double t0 = tl_wtime();
  tl_sparse_zero(nw->J);
  TlStatus st = nw->jacobian(nw->ctx, x, nw->J);
  nw->stats.t_jacobian += tl_wtime() - t0;
  nw->stats.jacobian_evaluations++;
  if (st == TL_OK) st = tl_linear_solver_factor(nw->ls, nw->J);
  if (st != TL_OK) {
    record_callback_error(nw, st);
    return -1;
  }
  nw->jnorm = jacobian_norm(nw->J, nw->rows);
  nw->factored = 1;
  nw->since_factor = 0;
  nw->crate = 1.0;
  return 0;
}

/* F(y0 + ycor).  The start's residual was evaluated before the iteration
 * (the zero correction, also after a restart with fresh factors). */
static int nls_sys(N_Vector ycor, N_Vector F, void *mem)
{
  TlNewton *nw = mem;
  const double *y0 = N_VGetArrayPointer(nw->y0), *c = N_VGetArrayPointer(ycor);
  double *f = N_VGetArrayPointer(F);
  int zero = 1;
  for (TlSparseIndex i = 0; i < nw->n; ++i) {
    nw->xtrial[i] = y0[i] + c[i];
    zero &= c[i] == 0.0;
  }
  if (zero && nw->start_valid) {
    memcpy(f, nw->r_start, (size_t)nw->n * sizeof *f);
    return SUN_NLS_SUCCESS;
  }
  return evaluate_residual(nw, nw->xtrial, f) ? -1 : SUN_NLS_SUCCESS;
}

static int nls_lsetup(booleantype jbad, booleantype *jcur, void *mem)
{
  (void)jbad; /* the Jacobian is always evaluated afresh */
  TlNewton *nw = mem;
  if (factor_at(nw, nw->xtrial)) return -1;
  *jcur = SUNTRUE;
  return SUN_NLS_SUCCESS;
}

/* b = J^-1 b; factors that have served max_setup_calls solves are renewed
 * at the current iterate first (max_setup_calls = 1: full Newton). */
static int nls_lsolve(N_Vector b, void *mem)
{
  TlNewton *nw = mem;
  if (!nw->factored || nw->since_factor >= nw->opt.max_setup_calls)
    if (factor_at(nw, nw->xtrial)) return -1;
  double *bv = N_VGetArrayPointer(b);
  TlStatus st = tl_linear_solver_solve(nw->ls, bv, bv);
  nw->since_factor++;
  if (st != TL_OK) {
    record_callback_error(nw, st);
    return -1;
  }
  return SUN_NLS_SUCCESS;
}

/* Correction tolerance in the unknown's units (tl_newton.h): the residual
 * tolerance over ||J||_inf, floored at round-off of the unknown. */
static double correction_tolerance(const TlNewton *nw)
{
  double tol = nw->jnorm > 0.0 ? nw->opt.ftol / nw->jnorm : 0.0;
  return fmax(tol, nw->opt.step_tol * nw->opt.u_scale);
}

/* CVODE's test on the correction d_m of iteration m (max norm). */
static int nls_ctest(SUNNonlinearSolver nls, N_Vector ycor, N_Vector del, realtype tol, N_Vector ewt,
                     void *data)
{
  (void)ycor, (void)tol, (void)ewt;
  TlNewton *nw = data;
  int m = 0;
  SUNNonlinSolGetCurIter(nls, &m);
  const double *dv = N_VGetArrayPointer(del);
  double d = 0.0;
  int finite = 1;
  for (TlSparseIndex i = 0; i < nw->n; ++i) {
    const double a = fabs(dv[i]);
    d = a > d ? a : d;
    finite &= a <= DBL_MAX;
  }
  if (!finite) d = NAN;
  if (nw->n_corrections < TL_NEWTON_HISTORY) nw->corrections[nw->n_corrections++] = d;
  else nw->corrections[TL_NEWTON_HISTORY - 1] = d;
  nw->stats.last_correction = d;
  if (!isfinite(d)) {
    nw->diagnosis = CTEST_NOT_FINITE;
    return SUN_NLS_CONV_RECVR;
  }
  if (m > 0) nw->crate = fmax(CRDOWN * nw->crate, nw->delp > 0.0 ? d / nw->delp : (d > 0.0 ? 1.0 : 0.0));
  if (d * fmin(1.0, nw->crate) <= correction_tolerance(nw)) return SUN_NLS_SUCCESS;
  if (m > 0 && d > RDIV * nw->delp) {
    nw->diagnosis = CTEST_DIVERGING;
    return SUN_NLS_CONV_RECVR;
  }
  nw->delp = d;
  return SUN_NLS_CONTINUE;
}

/* ------------------------------------------------------------ API */
void tl_newton_options_default(TlNewtonOptions *o)
{
  o->method = TL_NEWTON_KINSOL;
  o->ftol = 1e-8;
  o->step_tol = 1e-14;
  o->u_scale = 1.0;
  o->max_iterations = 50;
  o->max_setup_calls = 1;
  o->keep_factors = 0;
  o->line_search = 0;
  o->evaluate_solution = 0;
}

static TlStatus apply_options(TlNewton *nw, const TlNewtonOptions *o)
{
  if (!(o->ftol > 0.0) || !(o->step_tol >= 0.0) || !(o->u_scale > 0.0))
    TL_ERROR(TL_ERR_ARG, "Newton tolerances must be positive (ftol = %g, step_tol = %g, u_scale = %g)",
             o->ftol, o->step_tol, o->u_scale);
  if (o->max_iterations < 1 || o->max_setup_calls < 1)
    TL_ERROR(TL_ERR_ARG, "max_iterations = %ld and max_setup_calls = %ld must be >= 1",
             o->max_iterations, o->max_setup_calls);
  if (o->method != TL_NEWTON_KINSOL && o->method != TL_NEWTON_SUNNONLINSOL && o->method != TL_NEWTON_PLAIN)
    TL_ERROR(TL_ERR_ARG, "Newton method %d is none of KINSOL (%d), SUNNONLINSOL (%d), PLAIN (%d)", o->method,
             TL_NEWTON_KINSOL, TL_NEWTON_SUNNONLINSOL, TL_NEWTON_PLAIN);
  if (o->method != TL_NEWTON_KINSOL && o->line_search)
    TL_ERROR(TL_ERR_ARG, "the %s Newton has no line search; use the KINSOL method for it",
             o->method == TL_NEWTON_PLAIN ? "plain" : "SUNNonlinSol");
  nw->opt = *o;
  if (SUNNonlinSolSetMaxIters(nw->nls, o->max_iterations > 1000000 ? 1000000 : (int)o->max_iterations))
    TL_ERROR(TL_ERR_ARG, "SUNNonlinSol rejected max_iterations = %ld", o->max_iterations);
  int f = 0;
  f |= KINSetFuncNormTol(nw->kin, o->ftol);
  f |= KINSetScaledStepTol(nw->kin, o->step_tol);
  f |= KINSetNumMaxIters(nw->kin, o->max_iterations);
  f |= KINSetMaxSetupCalls(nw->kin, o->max_setup_calls);
  /* KINSOL caps a step at 1000 |u0| (1 when u0 = 0), which would throttle
   * Newton from a zero start: no cap, the line search guards instead. */
  f |= KINSetMaxNewtonStep(nw->kin, 1e300);
  if (f) TL_ERROR(TL_ERR_ARG, "KINSOL rejected the Newton options");
  return TL_OK;
}

TlStatus tl_newton_create(TlSparseIndex n, TlSparse *J, const char *solver_type,
                          const TlNewtonOptions *options, TlNewtonResidual residual,
                          TlNewtonJacobian jacobian, void *ctx, TlNewton **out)
{
  TlNewton *nw = NULL;
  TlStatus st = TL_OK;
  *out = NULL;
  if (!J || J->n != n)
    TL_ERROR(TL_ERR_ARG, "Jacobian pattern of size %lld for %lld unknowns",
             J ? (long long)J->n : -1LL, (long long)n);
  TL_CHECK(TL_NEW(nw));
  nw->n = n;
  nw->J = J;
  nw->residual = residual;
  nw->jacobian = jacobian;
  nw->ctx = ctx;
  TL_CHECK_GOTO(st, tl_linear_solver_create(solver_type, J, &nw->ls), fail);
  if (SUNContext_Create(NULL, &nw->sunctx)) {
    st = tl_error_set(TL_ERR_MEM, __FILE__, __LINE__, "SUNContext_Create failed");
    goto fail;
  }
  nw->x = N_VNew_Serial((sunindextype)n, nw->sunctx);
  nw->scale = N_VNew_Serial((sunindextype)n, nw->sunctx);
  nw->uscale = N_VNew_Serial((sunindextype)n, nw->sunctx);
  nw->kin = KINCreate(nw->sunctx);
  nw->Jmat = SUNMatNewEmpty(nw->sunctx);
  nw->Lsol = SUNLinSolNewEmpty(nw->sunctx);
  nw->y0 = N_VNew_Serial((sunindextype)n, nw->sunctx);
  nw->ycor = N_VNew_Serial((sunindextype)n, nw->sunctx);
  nw->weight = N_VNew_Serial((sunindextype)n, nw->sunctx);
  nw->nls = nw->y0 ? SUNNonlinSol_Newton(nw->y0, nw->sunctx) : NULL;
  TL_CHECK_GOTO(st, tl_calloc(&nw->xtrial, (size_t)n, sizeof *nw->xtrial), fail);
  TL_CHECK_GOTO(st, tl_calloc(&nw->r_start, (size_t)n, sizeof *nw->r_start), fail);
  TL_CHECK_GOTO(st, tl_calloc(&nw->rows, (size_t)n, sizeof *nw->rows), fail);
  TL_CHECK_GOTO(st, tl_calloc(&nw->r_plain, (size_t)n, sizeof *nw->r_plain), fail);
  TL_CHECK_GOTO(st, tl_calloc(&nw->d_plain, (size_t)n, sizeof *nw->d_plain), fail);
  if (!nw->x || !nw->scale || !nw->uscale || !nw->kin || !nw->Jmat || !nw->Lsol || !nw->ycor ||
      !nw->weight || !nw->nls) {
    st = tl_error_set(TL_ERR_MEM, __FILE__, __LINE__, "KINSOL objects for %lld unknowns",
                      (long long)n);
    goto fail;
  }
  N_VConst(1.0, nw->scale);
  nw->Jmat->content = nw;
  nw->Jmat->ops->getid = mat_getid;
  nw->Jmat->ops->zero = mat_zero;
  nw->Jmat->ops->destroy = mat_destroy;
  nw->Lsol->content = nw;
  nw->Lsol->ops->gettype = ls_gettype;
  nw->Lsol->ops->getid = ls_getid;
  nw->Lsol->ops->setup = ls_setup;
  nw->Lsol->ops->solve = ls_solve;
  nw->Lsol->ops->free = ls_free;
  int f = 0;
  f |= KINInit(nw->kin, kin_residual, nw->x);
  f |= KINSetUserData(nw->kin, nw);
  f |= KINSetLinearSolver(nw->kin, nw->Lsol, nw->Jmat);
  f |= KINSetJacFn(nw->kin, kin_jacobian);
  f |= KINSetErrHandlerFn(nw->kin, kin_silent, NULL);
  f |= KINSetPrintLevel(nw->kin, 0);
  if (f) {
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "KINSOL set-up failed");
    goto fail;
  }
  N_VConst(1.0, nw->weight);
  f |= SUNNonlinSolSetSysFn(nw->nls, nls_sys);
  f |= SUNNonlinSolSetLSetupFn(nw->nls, nls_lsetup);
  f |= SUNNonlinSolSetLSolveFn(nw->nls, nls_lsolve);
  f |= SUNNonlinSolSetConvTestFn(nw->nls, nls_ctest, nw);
  f |= SUNNonlinSolInitialize(nw->nls);
  if (f) {
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "SUNNonlinSol set-up failed");
    goto fail;
  }
  nw->crate = 1.0;
  TlNewtonOptions def;
  tl_newton_options_default(&def);
  TL_CHECK_GOTO(st, apply_options(nw, options ? options : &def), fail);
  *out = nw;
  return TL_OK;
fail:
  tl_newton_destroy(&nw);
  return st;
}

TlStatus tl_newton_set_options(TlNewton *nw, const TlNewtonOptions *o)
{
  return apply_options(nw, o);
}

void tl_newton_invalidate(TlNewton *nw) { nw->factored = 0; }

int tl_newton_has_factors(const TlNewton *nw) { return nw->factored; }

TlStatus tl_newton_refactor(TlNewton *nw)
{
  nw->factored = 0;
  TL_CHECK(tl_linear_solver_factor(nw->ls, nw->J));
  nw->jnorm = jacobian_norm(nw->J, nw->rows);
  nw->factored = 1;
  nw->since_factor = 0;
  nw->crate = 1.0;
  return TL_OK;
}

double tl_newton_convergence_rate(const TlNewton *nw) { return nw->crate; }
void tl_newton_set_convergence_rate(TlNewton *nw, double crate) { nw->crate = crate; }

long tl_newton_iterations_since_factor(const TlNewton *nw) { return nw->since_factor; }
void tl_newton_set_iterations_since_factor(TlNewton *nw, long n) { nw->since_factor = n; }

static int history_text(const TlNewton *nw, char *buf, size_t size)
{
  int w = snprintf(buf, size, "residual history (max norm):");
  for (int i = 0; i < nw->n_history && (size_t)w < size; ++i)
    w += snprintf(buf + w, size - (size_t)w, " %.3e", nw->history[i]);
  if (nw->opt.method == TL_NEWTON_SUNNONLINSOL && (size_t)w < size) {
    w += snprintf(buf + w, size - (size_t)w, "; corrections (max norm):");
    for (int i = 0; i < nw->n_corrections && (size_t)w < size; ++i)
      w += snprintf(buf + w, size - (size_t)w, " %.3e", nw->corrections[i]);
  }
  return w;
}

/* The SUNNonlinSol path (tl_newton.h). */
static TlStatus solve_sunnonlinsol(TlNewton *nw, double *x)
{
  size_t bytes = (size_t)nw->n * sizeof *x;
  double *y0 = N_VGetArrayPointer(nw->y0), *ycor = N_VGetArrayPointer(nw->ycor);
  nw->n_corrections = 0;
  nw->diagnosis = CTEST_NONE;
  nw->delp = 0.0;
  memcpy(y0, x, bytes);
  memcpy(nw->xtrial, x, bytes);
  int flag = evaluate_residual(nw, y0, nw->r_start);
  long iters = 0;
  int callLSetup = !(nw->opt.keep_factors && nw->factored && nw->since_factor < nw->opt.max_setup_calls);
  if (flag == 0 && nw->history[nw->n_history - 1] > nw->opt.ftol) {
    nw->start_valid = 1;
    memset(ycor, 0, bytes);
    flag = SUNNonlinSolSolve(nw->nls, nw->y0, nw->ycor, nw->weight, nw->opt.ftol,
                             callLSetup ? SUNTRUE : SUNFALSE, nw);
    nw->start_valid = 0;
    SUNNonlinSolGetNumIters(nw->nls, &iters);
    for (TlSparseIndex i = 0; i < nw->n; ++i) x[i] = y0[i] + ycor[i];
  }
  if (flag == SUN_NLS_SUCCESS && iters > 0 && nw->opt.evaluate_solution)
    flag = evaluate_residual(nw, x, nw->r_start);
  nw->stats.last_iterations = iters;
  nw->stats.iterations += iters;
  nw->stats.solves++;
  nw->stats.last_residual = nw->n_history ? nw->history[nw->n_history - 1] : NAN;
  if (flag == SUN_NLS_SUCCESS) return TL_OK;
  nw->factored = 0;
  char hist[900];
  history_text(nw, hist, sizeof hist);
  if (nw->callback_status != TL_OK)
    TL_ERROR(nw->callback_status, "%s; Newton stopped after %ld iterations; %s", nw->callback_message, iters, hist);
  const char *why = nw->diagnosis == CTEST_DIVERGING   ? "corrections growing (|d_m| > 2 |d_m-1|)"
                    : nw->diagnosis == CTEST_NOT_FINITE ? "correction not finite"
                    : flag == SUN_NLS_CONV_RECVR         ? "iteration limit reached"
                                                         : "SUNNonlinSol failure";
  TL_ERROR(TL_ERR_CONVERGENCE,
           "Newton did not converge: %s (SUNNonlinSol flag %d) after %ld iterations, fresh factors included; "
           "correction tolerance %.3e (ftol %.3e / ||J||_inf %.3e), rate estimate %.3e; %s",
           why, flag, iters, correction_tolerance(nw), nw->opt.ftol, nw->jnorm, nw->crate, hist);
}

/* The PLAIN loop (tl_newton.h). */
static TlStatus solve_plain(TlNewton *nw, double *x)
{
  const TlNewtonOptions *o = &nw->opt;
  double *r = nw->r_plain, *d = nw->d_plain;
  nw->n_measures = 0;
  long k = 0;
  int verdict = TL_NEWTON_CONTINUE, reused = 0;
  TlStatus st = TL_OK;
  for (;; ++k) {
    if (evaluate_residual(nw, x, r)) {
      st = nw->callback_status;
      break;
    }
    double measure = nw->history[nw->n_history - 1];
    if (o->test) verdict = o->test(o->test_ctx, x, r, k, &measure);
    else verdict = measure <= o->ftol ? TL_NEWTON_CONVERGED : TL_NEWTON_CONTINUE;
    if (nw->n_measures < TL_NEWTON_HISTORY) nw->measures[nw->n_measures++] = measure;
    else nw->measures[TL_NEWTON_HISTORY - 1] = measure;
    if (verdict != TL_NEWTON_CONTINUE || k >= o->max_iterations) break;
    /* Fresh factors at x unless kept ones may serve another iteration. */
    reused = nw->factored && nw->since_factor < o->max_setup_calls && (k > 0 || o->keep_factors);
    if (!reused && factor_at(nw, x)) {
      st = nw->callback_status;
      break;
    }
    st = tl_linear_solver_solve(nw->ls, r, d);
    nw->since_factor++;
    if (st != TL_OK) break;
    for (TlSparseIndex i = 0; i < nw->n; ++i) x[i] -= d[i];
  }
  nw->stats.last_iterations = k;
  nw->stats.iterations += k;
  nw->stats.solves++;
  nw->stats.last_residual = nw->n_history ? nw->history[nw->n_history - 1] : NAN;
  if (st == TL_OK && verdict == TL_NEWTON_CONVERGED) return TL_OK;
  nw->factored = 0;
  char hist[700];
  history_text(nw, hist, sizeof hist);
  if (st != TL_OK) {
    char why[1024];
    snprintf(why, sizeof why, "%s", nw->callback_status != TL_OK ? nw->callback_message : tl_error_message());
    TL_ERROR(st, "%s; Newton stopped after %ld iterations; %s", why, k, hist);
  }
  int w = 0;
  char meas[600];
  meas[0] = '\0';
  for (int i = 0; i < nw->n_measures && (size_t)w < sizeof meas; ++i)
    w += snprintf(meas + w, sizeof meas - (size_t)w, " %.3e", nw->measures[i]);
  TL_ERROR(TL_ERR_CONVERGENCE, "Newton did not converge: %s after %ld iterations (limit %ld); test measures:%s; %s",
           verdict == TL_NEWTON_FAILED ? "the convergence test gave up" : "iteration limit reached", k,
           o->max_iterations, meas, hist);
}

int tl_newton_test_history(const TlNewton *nw, const double **measures)
{
  *measures = nw->measures;
  return nw->n_measures;
}

TlStatus tl_newton_solve(TlNewton *nw, double *x)
{
  nw->callback_status = TL_OK;
  nw->callback_message[0] = '\0';
  nw->n_history = 0;
  if (nw->opt.method == TL_NEWTON_SUNNONLINSOL) return solve_sunnonlinsol(nw, x);
  if (nw->opt.method == TL_NEWTON_PLAIN) return solve_plain(nw, x);
  memcpy(N_VGetArrayPointer(nw->x), x, (size_t)nw->n * sizeof *x);
  /* KINSOL scales steps by uscale: 1 / u_scale makes the step test relative
   * to the problem's displacement size; residuals stay unscaled. */
  N_VConst(1.0 / nw->opt.u_scale, nw->uscale);
  /* Reusing factors across solves: tell KINSOL not to set up at the start
   * when valid factors are kept and have served fewer than max_setup_calls
   * iterations (KINSOL counts within one solve only).  If the stale factors
   * do not converge, start again from x with fresh ones. */
  int stale = nw->opt.keep_factors && nw->factored && nw->since_factor < nw->opt.max_setup_calls;
  int flag = 0;
  long iters = 0;
  for (int attempt = 0; attempt < 2; ++attempt) {
    KINSetNoInitSetup(nw->kin, stale ? SUNTRUE : SUNFALSE);
    flag = KINSol(nw->kin, nw->x, nw->opt.line_search ? KIN_LINESEARCH : KIN_NONE, nw->uscale,
                  nw->scale);
    long it = 0;
    KINGetNumNonlinSolvIters(nw->kin, &it);
    iters += it;
    int ok = flag == KIN_SUCCESS || flag == KIN_INITIAL_GUESS_OK ||
             (flag == KIN_STEP_LT_STPTOL && nw->n_history &&
              nw->history[nw->n_history - 1] <= 1e3 * nw->opt.ftol);
    if (ok || !stale || nw->callback_status != TL_OK) break;
    stale = 0;
    nw->factored = 0;
    memcpy(N_VGetArrayPointer(nw->x), x, (size_t)nw->n * sizeof *x);
  }
  nw->stats.last_iterations = iters;
  nw->stats.iterations += iters;
  nw->stats.solves++;
  nw->stats.last_residual = nw->n_history ? nw->history[nw->n_history - 1] : NAN;
  memcpy(x, N_VGetArrayPointer(nw->x), (size_t)nw->n * sizeof *x);
  if (nw->callback_status != TL_OK) {
    char hist[700];
    history_text(nw, hist, sizeof hist);
    nw->factored = 0;
    TL_ERROR(nw->callback_status, "%s; Newton stopped after %ld iterations; %s",
             nw->callback_message, iters, hist);
  }
  if (flag == KIN_SUCCESS || flag == KIN_INITIAL_GUESS_OK) return TL_OK;
  if (flag == KIN_STEP_LT_STPTOL && nw->stats.last_residual <= 1e3 * nw->opt.ftol) return TL_OK;
  char hist[700];
  history_text(nw, hist, sizeof hist);
  nw->factored = 0;
  TL_ERROR(TL_ERR_CONVERGENCE,
           "Newton did not converge: KINSOL %s after %ld iterations, ||F||_inf = %.3e > ftol = "
           "%.3e; %s",
           KINGetReturnFlagName(flag), iters, nw->stats.last_residual, nw->opt.ftol, hist);
}

void tl_newton_get_stats(const TlNewton *nw, TlNewtonStats *stats)
{
  *stats = nw->stats;
  stats->linear = nw->ls->stats;
}

int tl_newton_history(const TlNewton *nw, const double **norms)
{
  *norms = nw->history;
  return nw->n_history;
}

int tl_newton_correction_history(const TlNewton *nw, const double **norms)
{
  *norms = nw->corrections;
  return nw->n_corrections;
}

void tl_newton_destroy(TlNewton **nw)
{
  if (!nw || !*nw) return;
  TlNewton *p = *nw;
  if (p->kin) KINFree(&p->kin);
  if (p->Lsol) SUNLinSolFree(p->Lsol);
  if (p->Jmat) SUNMatDestroy(p->Jmat);
  if (p->x) N_VDestroy(p->x);
  if (p->scale) N_VDestroy(p->scale);
  if (p->uscale) N_VDestroy(p->uscale);
  if (p->nls) SUNNonlinSolFree(p->nls);
  if (p->y0) N_VDestroy(p->y0);
  if (p->ycor) N_VDestroy(p->ycor);
  if (p->weight) N_VDestroy(p->weight);
  tl_free(&p->xtrial);
  tl_free(&p->r_start);
  tl_free(&p->rows);
  tl_free(&p->r_plain);
  tl_free(&p->d_plain);
  if (p->sunctx) SUNContext_Free(&p->sunctx);
  tl_linear_solver_destroy(&p->ls);
  tl_free(nw);
}
