/* KLU (sparse LU for circuit-like and FEM matrices) on full storage.  The
 * ordering is computed once; after the first numeric factorisation the
 * pivot sequence is reused (klu_l_refactor) unless the reciprocal condition
 * estimate shows it went bad, in which case a fresh factorisation is done. */
#include <string.h>

#include <klu.h>

#include "tl_linear_solver.h"
#include "tl_memory.h"

typedef struct {
  klu_l_common common;
  klu_l_symbolic *symbolic;
  klu_l_numeric *numeric;
} Klu;

static TlStatus klu_setup(TlLinearSolver *ls, const TlSparse *A)
{
  Klu *k = NULL;
  TL_CHECK(TL_NEW(k));
  ls->data = k;
  klu_l_defaults(&k->common);
  k->symbolic = klu_l_analyze(A->n, (SuiteSparse_long *)A->colptr, (SuiteSparse_long *)A->rowind,
                              &k->common);
  if (!k->symbolic)
    TL_ERROR(TL_ERR_NUMERIC, "KLU analysis failed (status %ld, n = %lld)", k->common.status,
             (long long)A->n);
  return TL_OK;
}

static TlStatus klu_factor_values(TlLinearSolver *ls, const TlSparse *A)
{
  Klu *k = ls->data;
  SuiteSparse_long *p = (SuiteSparse_long *)A->colptr, *i = (SuiteSparse_long *)A->rowind;
  if (k->numeric) {
    if (klu_l_refactor(p, i, A->values, k->symbolic, k->numeric, &k->common) &&
        klu_l_rcond(k->symbolic, k->numeric, &k->common) && k->common.rcond > 1e-12)
      return TL_OK;
    klu_l_free_numeric(&k->numeric, &k->common);
  }
  k->numeric = klu_l_factor(p, i, A->values, k->symbolic, &k->common);
  if (!k->numeric || k->common.status == KLU_SINGULAR)
    TL_ERROR(TL_ERR_NUMERIC, "KLU factorisation failed: %s (status %ld, n = %lld)",
             k->common.status == KLU_SINGULAR ? "matrix singular" : "error", (long)k->common.status,
             (long long)A->n);
  return TL_OK;
}

static TlStatus klu_solve_values(TlLinearSolver *ls, const double *b, double *x)
{
  Klu *k = ls->data;
  if (x != b) memcpy(x, b, (size_t)ls->n * sizeof *x);
  if (!klu_l_solve(k->symbolic, k->numeric, ls->n, 1, x, &k->common))
    TL_ERROR(TL_ERR_NUMERIC, "KLU solve failed (status %ld)", (long)k->common.status);
  return TL_OK;
}

static void klu_destroy(TlLinearSolver *ls)
{
  Klu *k = ls->data;
  if (!k) return;
  if (k->numeric) klu_l_free_numeric(&k->numeric, &k->common);
  if (k->symbolic) klu_l_free_symbolic(&k->symbolic, &k->common);
  tl_free(&ls->data);
}

const TlLinearSolverOps tl_linear_solver_klu_ops = {
    .header = {"linear_solver", "klu", "KLU sparse LU (general matrices)"},
    .needs_upper = 0,
    .setup = klu_setup,
    .factor = klu_factor_values,
    .solve = klu_solve_values,
    .destroy = klu_destroy,
};
