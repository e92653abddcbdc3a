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
 * returned with its own message.  x is left at the last iterate. */
#ifndef TL_NEWTON_H
#define TL_NEWTON_H

#include "tl_error.h"
#include "tl_linear_solver.h"
#include "tl_sparse.h"

/* r = F(x). */
typedef TlStatus (*TlNewtonResidual)(void *ctx, const double *x, double *r);
/* J = dF/dx at x; J arrives zeroed. */
typedef TlStatus (*TlNewtonJacobian)(void *ctx, const double *x, TlSparse *J);

typedef struct {
  double ftol;          /* absolute residual tolerance, ||F||_inf */
  double step_tol;      /* stop when max |dx| / (|x| + u_scale) is below this [1e-14] */
  double u_scale;       /* typical size of x (step test, line search) [1] */
  long max_iterations;  /* [50] */
  long max_setup_calls; /* 1 = full Newton; > 1 modified Newton [1] */
  int keep_factors;     /* reuse factors across solve() calls [0] */
  int line_search;      /* KINSOL line search on ||F||_2, else plain Newton steps [0]: the
                         * residual norm of a stiff structure often rises on a good step */
} TlNewtonOptions;

typedef struct {
  long solves, iterations, residual_evaluations, jacobian_evaluations;
  long last_iterations;
  double last_residual; /* ||F||_inf at the end of the last solve */
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
void tl_newton_destroy(TlNewton **newton);

#endif
