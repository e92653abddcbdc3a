/* Newton's method for F(x) = 0 with a sparse Jacobian, through SUNDIALS
 * KINSOL, the linear systems solved by a TlLinearSolver (CHOLMOD for SPD
 * Jacobians, KLU or UMFPACK otherwise).
 *
 * KINSOL drives the iteration (line search or plain Newton steps, stopping
 * tests, modified-Newton bookkeeping); it sees the Jacobian as a custom
 * SUNMatrix wrapping the TlSparse and the factorisation as a custom direct
 * SUNLinearSolver.  The symbolic analysis is done once at creation; each
 * KINSOL "setup" assembles the Jacobian at the current iterate and
 * refactorises numerically.  max_setup_calls = 1 is full Newton; k > 1 keeps
 * the factors for up to k iterations (modified Newton), and keep_factors
 * carries them across solve() calls (time steps) until KINSOL asks again.
 *
 * Convergence: ||F||_inf <= ftol (absolute; the caller scales it).  A solve
 * that fails returns TL_ERR_CONVERGENCE with KINSOL's reason and the
 * residual history; a callback error (inverted element, NaN residual) is
 * returned with its own message.  x is left at the last iterate.
 *
 * method = TL_NEWTON_SUNNONLINSOL runs the same modified Newton through
 * SUNDIALS' generic SUNNonlinSol_Newton (the iteration of CVODE and IDA)
 * with CVODE's convergence test on the correction d_m instead of a test on
 * the residual, so the accepted iterate is never evaluated: with a rate
 * estimate kept across solves,
 *
 *   crate = max(0.3 crate, |d_m| / |d_{m-1}|)  (m > 0; reset to 1 whenever
 *                                              the factors are renewed),
 *   converged when |d_m| min(1, crate) <= ftol / ||J||_inf,
 *
 * max norms throughout, J the matrix of the current factors.  Why that
 * tolerance: the residual at the accepted x_m is exactly -J d_{m+1}, the
 * next correction with the same factors, so ||F(x_m)|| <= ||J|| |d_{m+1}|
 * and crate |d_m| estimates |d_{m+1}|: the test asks the estimated
 * ||F(x_m)|| to be below ftol, at least as strict as the residual test of
 * KINSOL (||J|| |d| bounds ||J d|| from above).  The tolerance is floored at
 * step_tol u_scale, where a correction is round-off.  A residual at the
 * start already below ftol is accepted without a solve.  The iteration
 * stops as diverging when |d_m| > 2 |d_{m-1}|; with kept (stale) factors
 * SUNDIALS then starts again from x with fresh ones, as the KINSOL path
 * does.  Restrictions: no line search (refused); the residual at the
 * solution is not evaluated unless evaluate_solution is set, so without it
 * the callback must leave no side effect the caller reads after the solve. */
#ifndef TL_NEWTON_H
#define TL_NEWTON_H

#include "tl_error.h"
#include "tl_linear_solver.h"
#include "tl_sparse.h"

/* r = F(x). */
typedef TlStatus (*TlNewtonResidual)(void *ctx, const double *x, double *r);
/* J = dF/dx at x; J arrives zeroed. */
typedef TlStatus (*TlNewtonJacobian)(void *ctx, const double *x, TlSparse *J);

/* The nonlinear iteration.  TL_NEWTON_PLAIN is the textbook loop of the
 * FE codes FEM x DEM grew in (seeds/004 §2.5): evaluate F(x); stop when the
 * caller's test says so (TlNewtonOptions.test; without one, when
 * ||F||_inf <= ftol); otherwise J at x (fresh factors every max_setup_calls
 * iterations), x -= J^-1 F.  No line search, no step test: the residual at
 * the accepted iterate is always the last one evaluated, so a trial state
 * a callback leaves there is the accepted one. */
enum { TL_NEWTON_KINSOL = 0, TL_NEWTON_SUNNONLINSOL = 1, TL_NEWTON_PLAIN = 2 };

/* A caller's convergence test for TL_NEWTON_PLAIN, called after every
 * residual evaluation with r = F(x) and the number of corrections applied
 * so far (0 at the start).  Returns one of the verdicts below and may set
 * *measure (the quantity it tested, kept in the test history). */
enum { TL_NEWTON_CONTINUE = 0, TL_NEWTON_CONVERGED = 1, TL_NEWTON_FAILED = 2 };
typedef int (*TlNewtonTest)(void *ctx, const double *x, const double *r, long iteration, double *measure);

typedef struct {
  int method;           /* TL_NEWTON_KINSOL or TL_NEWTON_SUNNONLINSOL [KINSOL] */
  double ftol;          /* absolute residual tolerance, ||F||_inf */
  double step_tol;      /* stop when max |dx| / (|x| + u_scale) is below this [1e-14] */
  double u_scale;       /* typical size of x (step test, line search) [1] */
  long max_iterations;  /* [50] */
  long max_setup_calls; /* 1 = full Newton; > 1 modified Newton [1] */
  int keep_factors;     /* reuse factors across solve() calls [0] */
  int line_search;      /* KINSOL line search on ||F||_2, else plain Newton steps [0]: the
                         * residual norm of a stiff structure often rises on a good step */
  int evaluate_solution; /* SUNNONLINSOL: evaluate F once more at the accepted iterate, for a
                          * callback whose side effects the caller reads (trial material
                          * state to commit) [0] */
  TlNewtonTest test;     /* PLAIN: the convergence test (NULL: ||F||_inf <= ftol) [NULL] */
  void *test_ctx;
} TlNewtonOptions;

typedef struct {
  long solves, iterations, residual_evaluations, jacobian_evaluations;
  long last_iterations;
  double last_residual; /* ||F||_inf at the last evaluation of the last solve */
  double last_correction; /* SUNNONLINSOL: max |d| of the last correction of the last solve */
  double t_residual, t_jacobian;
  TlLinearSolverStats linear;
} TlNewtonStats;

enum { TL_NEWTON_HISTORY = 64 };

typedef struct TlNewton TlNewton;

void tl_newton_options_default(TlNewtonOptions *o);
/* J gives the pattern (kept by pointer: it must outlive the solver);
 * solver_type names a TlLinearSolver ("cholmod", "klu", "umfpack"). */
TlStatus tl_newton_create(TlSparseIndex n, TlSparse *J, const char *solver_type,
                          const TlNewtonOptions *options, TlNewtonResidual residual,
                          TlNewtonJacobian jacobian, void *ctx, TlNewton **newton);
TlStatus tl_newton_set_options(TlNewton *newton, const TlNewtonOptions *options);
/* Solves F(x) = 0 starting from x (in/out). */
TlStatus tl_newton_solve(TlNewton *newton, double *x);
/* Forgets the kept factors: the next solve refactorises first. */
void tl_newton_invalidate(TlNewton *newton);
/* Whether valid factors are kept; they are those of the Jacobian's current
 * values (J is only written by the Jacobian callback just before each
 * factorisation), so a restart restores them by writing the saved values
 * into J and calling tl_newton_refactor(). */
int tl_newton_has_factors(const TlNewton *newton);
TlStatus tl_newton_refactor(TlNewton *newton);
/* Newton iterations served by the kept factors (with keep_factors, fresh
 * ones are made once this reaches max_setup_calls); restored on restart. */
long tl_newton_iterations_since_factor(const TlNewton *newton);
void tl_newton_set_iterations_since_factor(TlNewton *newton, long n);
void tl_newton_get_stats(const TlNewton *newton, TlNewtonStats *stats);
/* Residual norms of the last solve (one per evaluation), count returned. */
int tl_newton_history(const TlNewton *newton, const double **norms);
/* PLAIN with a test: the measures the test returned in the last solve, count returned. */
int tl_newton_test_history(const TlNewton *newton, const double **measures);
/* SUNNONLINSOL: correction norms max |d_m| of the last solve, count returned. */
int tl_newton_correction_history(const TlNewton *newton, const double **norms);
/* SUNNONLINSOL: the convergence-rate estimate crate kept across solves (1
 * after each factorisation, tl_newton_refactor included).  A restart that
 * must continue bit for bit saves it with the factors and sets it after
 * tl_newton_refactor(). */
double tl_newton_convergence_rate(const TlNewton *newton);
void tl_newton_set_convergence_rate(TlNewton *newton, double crate);
void tl_newton_destroy(TlNewton **newton);

#endif
