#include "tl_linear_solver.h"

#include "tl_memory.h"
#include "tl_registry.h"
#include "tl_timer.h"

TlStatus tl_linear_solver_register_all(void)
{
  TL_CHECK(tl_registry_add(&tl_linear_solver_cholmod_ops.header));
  TL_CHECK(tl_registry_add(&tl_linear_solver_klu_ops.header));
  TL_CHECK(tl_registry_add(&tl_linear_solver_umfpack_ops.header));
  return TL_OK;
}

static TlStatus find_ops(const char *type, const TlLinearSolverOps **ops)
{
  const TlOpsHeader *h = NULL;
  TL_CHECK(tl_linear_solver_register_all());
  TL_CHECK(tl_registry_find("linear_solver", type, &h));
  *ops = (const TlLinearSolverOps *)h;
  return TL_OK;
}

TlStatus tl_linear_solver_needs_upper(const char *type, int *upper)
{
  const TlLinearSolverOps *ops = NULL;
  TL_CHECK(find_ops(type, &ops));
  *upper = ops->needs_upper;
  return TL_OK;
}

TlStatus tl_linear_solver_create(const char *type, const TlSparse *A, TlLinearSolver **out)
{
  const TlLinearSolverOps *ops = NULL;
  TlLinearSolver *ls = NULL;
  *out = NULL;
  TL_CHECK(find_ops(type, &ops));
  if (ops->needs_upper != A->symmetric)
    TL_ERROR(TL_ERR_ARG, "linear solver '%s' needs %s storage, the matrix has %s storage", type,
             ops->needs_upper ? "upper-triangle" : "full", A->symmetric ? "upper-triangle" : "full");
  TL_CHECK(TL_NEW(ls));
  ls->ops = ops;
  ls->n = A->n;
  double t0 = tl_wtime();
  TlStatus st = ops->setup(ls, A);
  if (st != TL_OK) {
    tl_linear_solver_destroy(&ls);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  ls->stats.t_symbolic += tl_wtime() - t0;
  ls->stats.n_symbolic++;
  *out = ls;
  return TL_OK;
}

TlStatus tl_linear_solver_factor(TlLinearSolver *ls, const TlSparse *A)
{
  if (A->n != ls->n)
    TL_ERROR(TL_ERR_ARG, "matrix size %lld differs from the analysed size %lld", (long long)A->n,
             (long long)ls->n);
  double t0 = tl_wtime();
  TL_CHECK(ls->ops->factor(ls, A));
  ls->stats.t_numeric += tl_wtime() - t0;
  ls->stats.n_numeric++;
  return TL_OK;
}

TlStatus tl_linear_solver_solve(TlLinearSolver *ls, const double *b, double *x)
{
  if (ls->stats.n_numeric == 0) TL_ERROR(TL_ERR_STATE, "solve called before any factorisation");
  double t0 = tl_wtime();
  TL_CHECK(ls->ops->solve(ls, b, x));
  ls->stats.t_solve += tl_wtime() - t0;
  ls->stats.n_solve++;
  return TL_OK;
}

void tl_linear_solver_destroy(TlLinearSolver **ls)
{
  if (!ls || !*ls) return;
  if ((*ls)->ops && (*ls)->ops->destroy) (*ls)->ops->destroy(*ls);
  tl_free(ls);
}
