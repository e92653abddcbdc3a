#include "tl_newton.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include <kinsol/kinsol.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

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
};

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
static int kin_residual(N_Vector x, N_Vector f, void *user)
{
  TlNewton *nw = user;
  double t0 = tl_wtime();
  const double *xv = N_VGetArrayPointer(x);
  double *fv = N_VGetArrayPointer(f);
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

/* ------------------------------------------------------------ API */
void tl_newton_options_default(TlNewtonOptions *o)
{
  o->ftol = 1e-8;
  o->step_tol = 1e-14;
  o->u_scale = 1.0;
  o->max_iterations = 50;
  o->max_setup_calls = 1;
  o->keep_factors = 0;
  o->line_search = 0;
}

static TlStatus apply_options(TlNewton *nw, const TlNewtonOptions *o)
{
  if (!(o->ftol > 0.0) || !(o->step_tol >= 0.0) || !(o->u_scale > 0.0))
    TL_ERROR(TL_ERR_ARG, "Newton tolerances must be positive (ftol = %g, step_tol = %g, u_scale = %g)",
             o->ftol, o->step_tol, o->u_scale);
  if (o->max_iterations < 1 || o->max_setup_calls < 1)
    TL_ERROR(TL_ERR_ARG, "max_iterations = %ld and max_setup_calls = %ld must be >= 1",
             o->max_iterations, o->max_setup_calls);
  nw->opt = *o;
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
  if (!nw->x || !nw->scale || !nw->uscale || !nw->kin || !nw->Jmat || !nw->Lsol) {
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
  nw->factored = 1;
  nw->since_factor = 0;
  return TL_OK;
}

long tl_newton_iterations_since_factor(const TlNewton *nw) { return nw->since_factor; }
void tl_newton_set_iterations_since_factor(TlNewton *nw, long n) { nw->since_factor = n; }

static int history_text(const TlNewton *nw, char *buf, size_t size)
{
  int w = snprintf(buf, size, "residual history (max norm):");
  for (int i = 0; i < nw->n_history && (size_t)w < size; ++i)
    w += snprintf(buf + w, size - (size_t)w, " %.3e", nw->history[i]);
  return w;
}

TlStatus tl_newton_solve(TlNewton *nw, double *x)
{
  nw->callback_status = TL_OK;
  nw->callback_message[0] = '\0';
  nw->n_history = 0;
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
  if (p->sunctx) SUNContext_Free(&p->sunctx);
  tl_linear_solver_destroy(&p->ls);
  tl_free(nw);
}
