/* UMFPACK (multifrontal sparse LU) on full storage: symbolic analysis once,
 * numeric factorisation per factor(), solves with preallocated workspace.
 * The matrix given to factor() must stay alive until the next factor()
 * (UMFPACK's iterative refinement reads it). */
#include <umfpack.h>

#include "tl_linear_solver.h"
#include "tl_memory.h"

typedef struct {
  void *symbolic, *numeric;
  double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
  const TlSparse *A;
  SuiteSparse_long *wi;
  double *w;
} Umfpack;

static TlStatus umfpack_setup(TlLinearSolver *ls, const TlSparse *A)
{
  Umfpack *u = NULL;
  TL_CHECK(TL_NEW(u));
  ls->data = u;
  umfpack_dl_defaults(u->control);
  TL_CHECK(tl_calloc(&u->wi, (size_t)A->n, sizeof *u->wi));
  TL_CHECK(tl_calloc(&u->w, 5 * (size_t)A->n, sizeof *u->w));
  SuiteSparse_long s = umfpack_dl_symbolic(A->n, A->n, (const SuiteSparse_long *)A->colptr,
                                           (const SuiteSparse_long *)A->rowind, A->values,
                                           &u->symbolic, u->control, u->info);
  if (s != UMFPACK_OK)
    TL_ERROR(TL_ERR_NUMERIC, "UMFPACK symbolic analysis failed (status %ld, n = %lld)", (long)s,
             (long long)A->n);
  return TL_OK;
}

static TlStatus umfpack_factor_values(TlLinearSolver *ls, const TlSparse *A)
{
  Umfpack *u = ls->data;
  if (u->numeric) umfpack_dl_free_numeric(&u->numeric);
  SuiteSparse_long s = umfpack_dl_numeric((const SuiteSparse_long *)A->colptr,
                                          (const SuiteSparse_long *)A->rowind, A->values,
                                          u->symbolic, &u->numeric, u->control, u->info);
  if (s != UMFPACK_OK)
    TL_ERROR(TL_ERR_NUMERIC, "UMFPACK factorisation failed: %s (status %ld, n = %lld)",
             s == UMFPACK_WARNING_singular_matrix ? "matrix singular" : "error", (long)s,
             (long long)A->n);
  u->A = A;
  return TL_OK;
}

static TlStatus umfpack_solve_values(TlLinearSolver *ls, const double *b, double *x)
{
  Umfpack *u = ls->data;
  const TlSparse *A = u->A;
  SuiteSparse_long s = umfpack_dl_wsolve(UMFPACK_A, (const SuiteSparse_long *)A->colptr,
                                         (const SuiteSparse_long *)A->rowind, A->values, x, b,
                                         u->numeric, u->control, u->info, u->wi, u->w);
  if (s != UMFPACK_OK) TL_ERROR(TL_ERR_NUMERIC, "UMFPACK solve failed (status %ld)", (long)s);
  return TL_OK;
}

static void umfpack_destroy(TlLinearSolver *ls)
{
  Umfpack *u = ls->data;
  if (!u) return;
  if (u->numeric) umfpack_dl_free_numeric(&u->numeric);
  if (u->symbolic) umfpack_dl_free_symbolic(&u->symbolic);
  tl_free(&u->wi);
  tl_free(&u->w);
  tl_free(&ls->data);
}

const TlLinearSolverOps tl_linear_solver_umfpack_ops = {
    .header = {"linear_solver", "umfpack", "UMFPACK multifrontal sparse LU (general matrices)"},
    .needs_upper = 0,
    .setup = umfpack_setup,
    .factor = umfpack_factor_values,
    .solve = umfpack_solve_values,
    .destroy = umfpack_destroy,
};
