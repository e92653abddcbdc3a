/* Direct sparse linear solvers on TlSparse matrices, as ops types:
 * "cholmod" (symmetric positive definite; upper-triangle storage),
 * "klu" and "umfpack" (general; full storage).
 *
 * Life cycle: create with the matrix whose pattern will be factorised (the
 * symbolic analysis - fill-reducing ordering, elimination tree - is done
 * there, once per pattern); factor() for each new set of values (numeric
 * factorisation only); solve() as often as wanted with the last factors.
 * Keeping the factors across several Newton iterations or steps (modified
 * Newton) is the caller's choice: it simply does not call factor().
 * A failed factorisation (CHOLMOD: not positive definite; KLU/UMFPACK:
 * singular) returns TL_ERR_NUMERIC naming the pivot/column. */
#ifndef TL_LINEAR_SOLVER_H
#define TL_LINEAR_SOLVER_H

#include "tl_error.h"
#include "tl_object.h"
#include "tl_sparse.h"

typedef struct TlLinearSolver TlLinearSolver;

typedef struct {
  long n_symbolic, n_numeric, n_solve;
  double t_symbolic, t_numeric, t_solve; /* seconds */
} TlLinearSolverStats;

typedef struct {
  TlOpsHeader header; /* kind "linear_solver" */
  int needs_upper;    /* 1: matrix must be stored as upper triangle; 0: full */
  TlStatus (*setup)(TlLinearSolver *ls, const TlSparse *A);  /* symbolic analysis */
  TlStatus (*factor)(TlLinearSolver *ls, const TlSparse *A); /* numeric */
  TlStatus (*solve)(TlLinearSolver *ls, const double *b, double *x);
  void (*destroy)(TlLinearSolver *ls);
} TlLinearSolverOps;

struct TlLinearSolver {
  const TlLinearSolverOps *ops;
  TlSparseIndex n;
  TlLinearSolverStats stats;
  void *data; /* the backend's factorisation objects */
};

/* Registers "cholmod", "klu", "umfpack" (kind "linear_solver"). */
TlStatus tl_linear_solver_register_all(void);
/* Creates a solver of the named type and analyses A's pattern. */
TlStatus tl_linear_solver_create(const char *type, const TlSparse *A, TlLinearSolver **ls);
/* Whether the named type needs upper-triangle storage. */
TlStatus tl_linear_solver_needs_upper(const char *type, int *upper);
TlStatus tl_linear_solver_factor(TlLinearSolver *ls, const TlSparse *A);
/* x = A^-1 b with the last factors (x and b may alias). */
TlStatus tl_linear_solver_solve(TlLinearSolver *ls, const double *b, double *x);
void tl_linear_solver_destroy(TlLinearSolver **ls);

extern const TlLinearSolverOps tl_linear_solver_cholmod_ops;
extern const TlLinearSolverOps tl_linear_solver_klu_ops;
extern const TlLinearSolverOps tl_linear_solver_umfpack_ops;

#endif
