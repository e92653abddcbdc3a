/* CHOLMOD (Cholesky: simplicial for small systems, supernodal for large)
 * for symmetric positive-definite matrices stored as an upper triangle.  The analysis (AMD/METIS ordering, symbolic
 * factor) is done once; each factor() refactorises numerically in place.
 *
 * Small systems go through CHOLMOD's 32-bit interface: their solves stream
 * the factor from cache, and its 32-bit row indices are a third less data
 * than 64-bit ones (the S1 beam's factor, 32k entries: 384 against 512 kB
 * per sweep).  The matrix's pattern is copied to 32 bits once; its values
 * are read in place. */
#include <string.h>

#include <cholmod.h>

#include "tl_linear_solver.h"
#include "tl_memory.h"

enum { TL_CHOLMOD_SIMPLICIAL_MAX = 4096 };

typedef struct {
  cholmod_common common;
  cholmod_factor *L;
  cholmod_dense *X, *B, *Y, *E; /* solve workspaces, reused */
  int narrow;                   /* the 32-bit interface (cholmod_*, not cholmod_l_*) */
  int *p32, *i32;               /* the pattern in 32 bits */
} Cholmod;

/* The matrix as CHOLMOD sees it: in place, or with the 32-bit pattern. */
static void view(const Cholmod *c, const TlSparse *A, cholmod_sparse *S)
{
  tl_sparse_cholmod_view(A, S);
  if (!c->narrow) return;
  S->p = c->p32;
  S->i = c->i32;
  S->itype = CHOLMOD_INT;
}

static TlStatus cholmod_setup(TlLinearSolver *ls, const TlSparse *A)
{
  Cholmod *c = NULL;
  TL_CHECK(TL_NEW(c));
  ls->data = c;
  c->narrow = A->n <= TL_CHOLMOD_SIMPLICIAL_MAX;
  if (c->narrow) {
    TL_CHECK(tl_calloc(&c->p32, (size_t)A->n + 1, sizeof *c->p32));
    TL_CHECK(tl_calloc(&c->i32, (size_t)(A->nnz ? A->nnz : 1), sizeof *c->i32));
    for (TlSparseIndex j = 0; j <= A->n; ++j) c->p32[j] = (int)A->colptr[j];
    for (TlSparseIndex k = 0; k < A->nnz; ++k) c->i32[k] = (int)A->rowind[k];
    cholmod_start(&c->common);
  } else {
    cholmod_l_start(&c->common);
  }
  c->common.print = 0;
  c->common.error_handler = NULL;
  c->common.final_ll = 1; /* LL' in every mode, so an indefinite matrix is reported */
  /* A few thousand unknowns factor into supernodes too small for the BLAS
   * calls to pay: the simplicial factor solves faster there (the S1 beam,
   * 837 unknowns: 12 % less CPU per coupled step). */
  if (c->narrow) c->common.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_sparse S;
  view(c, A, &S);
  c->L = c->narrow ? cholmod_analyze(&S, &c->common) : cholmod_l_analyze(&S, &c->common);
  if (!c->L || c->common.status < CHOLMOD_OK)
    TL_ERROR(TL_ERR_NUMERIC, "CHOLMOD analysis failed (status %d, n = %lld)", c->common.status,
             (long long)A->n);
  c->B = c->narrow ? cholmod_zeros((size_t)A->n, 1, CHOLMOD_REAL, &c->common)
                   : cholmod_l_zeros((size_t)A->n, 1, CHOLMOD_REAL, &c->common);
  if (!c->B) TL_ERROR(TL_ERR_MEM, "CHOLMOD workspace of %lld rows", (long long)A->n);
  return TL_OK;
}

static TlStatus cholmod_factor_values(TlLinearSolver *ls, const TlSparse *A)
{
  Cholmod *c = ls->data;
  cholmod_sparse S;
  view(c, A, &S);
  if (c->narrow) cholmod_factorize(&S, c->L, &c->common);
  else cholmod_l_factorize(&S, c->L, &c->common);
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
  const int ok = c->narrow ? cholmod_solve2(CHOLMOD_A, c->L, c->B, NULL, &c->X, NULL, &c->Y, &c->E, &c->common)
                           : cholmod_l_solve2(CHOLMOD_A, c->L, c->B, NULL, &c->X, NULL, &c->Y, &c->E, &c->common);
  if (!ok) TL_ERROR(TL_ERR_NUMERIC, "CHOLMOD solve failed (status %d)", c->common.status);
  memcpy(x, c->X->x, (size_t)ls->n * sizeof(double));
  return TL_OK;
}

static void cholmod_destroy(TlLinearSolver *ls)
{
  Cholmod *c = ls->data;
  if (!c) return;
  if (c->narrow) {
    cholmod_free_factor(&c->L, &c->common);
    cholmod_free_dense(&c->X, &c->common);
    cholmod_free_dense(&c->B, &c->common);
    cholmod_free_dense(&c->Y, &c->common);
    cholmod_free_dense(&c->E, &c->common);
    cholmod_finish(&c->common);
  } else {
    cholmod_l_free_factor(&c->L, &c->common);
    cholmod_l_free_dense(&c->X, &c->common);
    cholmod_l_free_dense(&c->B, &c->common);
    cholmod_l_free_dense(&c->Y, &c->common);
    cholmod_l_free_dense(&c->E, &c->common);
    cholmod_l_finish(&c->common);
  }
  tl_free(&c->p32);
  tl_free(&c->i32);
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
