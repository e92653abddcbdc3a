/* CHOLMOD (Cholesky: simplicial for small systems, supernodal for large)
 * for symmetric positive-definite matrices stored as an upper triangle.  The analysis (AMD/METIS ordering, symbolic
 * factor) is done once; each factor() refactorises numerically in place. */
#include <string.h>

#include <cholmod.h>

#include "tl_linear_solver.h"
#include "tl_memory.h"

enum { TL_CHOLMOD_SIMPLICIAL_MAX = 4096 };

typedef struct {
  cholmod_common common;
  cholmod_factor *L;
  cholmod_dense *X, *B, *Y, *E; /* solve workspaces, reused */
} Cholmod;

static TlStatus cholmod_setup(TlLinearSolver *ls, const TlSparse *A)
{
  Cholmod *c = NULL;
  TL_CHECK(TL_NEW(c));
  ls->data = c;
  cholmod_l_start(&c->common);
  c->common.print = 0;
  c->common.error_handler = NULL;
  c->common.final_ll = 1; /* LL' in every mode, so an indefinite matrix is reported */
  /* A few thousand unknowns factor into supernodes too small for the BLAS
   * calls to pay: the simplicial factor solves faster there (the S1 beam,
   * 837 unknowns: 12 % less CPU per coupled step). */
  if (A->n <= TL_CHOLMOD_SIMPLICIAL_MAX) c->common.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_sparse S;
  tl_sparse_cholmod_view(A, &S);
  c->L = cholmod_l_analyze(&S, &c->common);
  if (!c->L || c->common.status < CHOLMOD_OK)
    TL_ERROR(TL_ERR_NUMERIC, "CHOLMOD analysis failed (status %d, n = %lld)", c->common.status,
             (long long)A->n);
  c->B = cholmod_l_zeros((size_t)A->n, 1, CHOLMOD_REAL, &c->common);
  if (!c->B) TL_ERROR(TL_ERR_MEM, "CHOLMOD workspace of %lld rows", (long long)A->n);
  return TL_OK;
}

static TlStatus cholmod_factor_values(TlLinearSolver *ls, const TlSparse *A)
{
  Cholmod *c = ls->data;
  cholmod_sparse S;
  tl_sparse_cholmod_view(A, &S);
  cholmod_l_factorize(&S, c->L, &c->common);
  if (c->common.status == CHOLMOD_NOT_POSDEF)
    TL_ERROR(TL_ERR_NUMERIC,
             "matrix not positive definite: CHOLMOD stopped at column %lld of %lld (use an LU "
             "solver, klu or umfpack, for indefinite tangents)",
             (long long)c->L->minor, (long long)A->n);
  if (c->common.status < CHOLMOD_OK)
    TL_ERROR(TL_ERR_NUMERIC, "CHOLMOD factorisation failed (status %d)", c->common.status);
  return TL_OK;
}

static TlStatus cholmod_solve_values(TlLinearSolver *ls, const double *b, double *x)
{
  Cholmod *c = ls->data;
  memcpy(c->B->x, b, (size_t)ls->n * sizeof(double));
  if (!cholmod_l_solve2(CHOLMOD_A, c->L, c->B, NULL, &c->X, NULL, &c->Y, &c->E, &c->common))
    TL_ERROR(TL_ERR_NUMERIC, "CHOLMOD solve failed (status %d)", c->common.status);
  memcpy(x, c->X->x, (size_t)ls->n * sizeof(double));
  return TL_OK;
}

static void cholmod_destroy(TlLinearSolver *ls)
{
  Cholmod *c = ls->data;
  if (!c) return;
  cholmod_l_free_factor(&c->L, &c->common);
  cholmod_l_free_dense(&c->X, &c->common);
  cholmod_l_free_dense(&c->B, &c->common);
  cholmod_l_free_dense(&c->Y, &c->common);
  cholmod_l_free_dense(&c->E, &c->common);
  cholmod_l_finish(&c->common);
  tl_free(&ls->data);
}

const TlLinearSolverOps tl_linear_solver_cholmod_ops = {
    .header = {"linear_solver", "cholmod", "CHOLMOD sparse Cholesky (symmetric positive definite)"},
    .needs_upper = 1,
    .setup = cholmod_setup,
    .factor = cholmod_factor_values,
    .solve = cholmod_solve_values,
    .destroy = cholmod_destroy,
};
