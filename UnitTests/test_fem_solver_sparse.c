/* Sparse matrix pattern, assembly, products, constraints, and the three
 * direct solvers against dense references. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "tl_linear_solver.h"
#include "tl_sparse.h"
#include "tl_test.h"

/* A 2D grid of bilinear "elements" (4 dofs each) on (nx+1) x (ny+1) nodes,
 * some nodes constrained (negative dof). */
enum { NX = 6, NY = 5 };

static double rnd(unsigned *s)
{
  *s = *s * 1664525u + 1013904223u;
  return (double)(*s >> 8) / (double)(1u << 24) - 0.5;
}

int main(void)
{
  TlSparseIndex dof_of[(NX + 1) * (NY + 1)], n = 0;
  for (int j = 0; j <= NY; ++j)
    for (int i = 0; i <= NX; ++i) dof_of[j * (NX + 1) + i] = (i == 0) ? -1 : n++;
  TlSparseIndex ne = NX * NY, ptr[NX * NY + 1], dofs[4 * NX * NY];
  for (int j = 0; j < NY; ++j)
    for (int i = 0; i < NX; ++i) {
      TlSparseIndex e = j * NX + i, *d = dofs + 4 * e;
      ptr[e] = 4 * e;
      d[0] = dof_of[j * (NX + 1) + i];
      d[1] = dof_of[j * (NX + 1) + i + 1];
      d[2] = dof_of[(j + 1) * (NX + 1) + i + 1];
      d[3] = dof_of[(j + 1) * (NX + 1) + i];
    }
  ptr[ne] = 4 * ne;

  /* Dense reference: SPD element matrices (a graph Laplacian + a diagonal). */
  double *dense = calloc((size_t)(n * n), sizeof *dense);
  double Ke[16];
  unsigned seed = 7;
  TlSparse *A = NULL, *U = NULL, *Ui = NULL;
  TL_TEST_STATUS(tl_sparse_create_from_elements(n, 0, ne, ptr, dofs, 1, &A), TL_OK);
  TL_TEST_STATUS(tl_sparse_create_from_elements(n, 1, ne, ptr, dofs, 0, &U), TL_OK);
  TL_TEST_STATUS(tl_sparse_create_from_elements(n, 1, ne, ptr, dofs, 1, &Ui), TL_OK);
  /* Pattern: every column holds its diagonal and sorted rows; full nnz
   * equals 2 * upper nnz - n (structural symmetry). */
  int sorted = 1;
  for (TlSparseIndex j = 0; j < n; ++j)
    for (TlSparseIndex p = A->colptr[j] + 1; p < A->colptr[j + 1]; ++p)
      if (A->rowind[p] <= A->rowind[p - 1]) sorted = 0;
  TL_TEST_ASSERT(sorted, "row indices sorted and unique in each column");
  TL_TEST_ASSERT(A->nnz == 2 * U->nnz - n, "full nnz %lld vs upper nnz %lld, n %lld",
                 (long long)A->nnz, (long long)U->nnz, (long long)n);
  /* Interior node of a structured grid couples to 9 nodes. */
  TlSparseIndex mid = dof_of[2 * (NX + 1) + 3];
  TL_TEST_ASSERT(A->colptr[mid + 1] - A->colptr[mid] == 9, "interior column has %lld entries",
                 (long long)(A->colptr[mid + 1] - A->colptr[mid]));

  for (TlSparseIndex e = 0; e < ne; ++e) {
    double s = 1.0 + 0.5 * rnd(&seed);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) Ke[a * 4 + b] = (a == b ? 3.0 * s : -s) + (a == b ? 0.1 : 0.0);
    TL_TEST_STATUS(tl_sparse_add_element_indexed(A, e, 1.0, Ke), TL_OK);
    TL_TEST_STATUS(tl_sparse_add_element(U, 4, dofs + 4 * e, 1.0, Ke), TL_OK);
    TL_TEST_STATUS(tl_sparse_add_element_atomic(Ui, 4, dofs + 4 * e, 0.5, Ke), TL_OK);
    TL_TEST_STATUS(tl_sparse_add_element_indexed(Ui, e, 0.5, Ke), TL_OK);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        TlSparseIndex i = dofs[4 * e + a], j = dofs[4 * e + b];
        if (i >= 0 && j >= 0) dense[i * n + j] += Ke[a * 4 + b];
      }
  }
  /* Products against the dense reference. */
  double *x = calloc((size_t)n, sizeof *x), *y = calloc((size_t)n, sizeof *y),
         *z = calloc((size_t)n, sizeof *z), *w = calloc((size_t)n, sizeof *w),
         *ref = calloc((size_t)n, sizeof *ref);
  for (TlSparseIndex i = 0; i < n; ++i) x[i] = rnd(&seed);
  for (TlSparseIndex i = 0; i < n; ++i) {
    ref[i] = 0.0;
    for (TlSparseIndex j = 0; j < n; ++j) ref[i] += dense[i * n + j] * x[j];
  }
  tl_sparse_matvec(A, x, y);
  tl_sparse_matvec(U, x, z);
  tl_sparse_matvec(Ui, x, w);
  double e1 = 0, e2 = 0, e3 = 0;
  for (TlSparseIndex i = 0; i < n; ++i) {
    e1 = fmax(e1, fabs(y[i] - ref[i]));
    e2 = fmax(e2, fabs(z[i] - ref[i]));
    e3 = fmax(e3, fabs(w[i] - ref[i]));
  }
  TL_TEST_ASSERT(e1 < 1e-13 && e2 < 1e-13 && e3 < 1e-13,
                 "matvec errors full %g upper %g mixed %g", e1, e2, e3);
  /* Compressing drops exact zeros (not the diagonal) and keeps the product. */
  {
    TlSparse *Z = NULL, *C = NULL;
    TL_TEST_STATUS(tl_sparse_duplicate(U, &Z), TL_OK);
    memcpy(Z->values, U->values, (size_t)U->nnz * sizeof *U->values);
    TlSparseIndex zeros = 0;
    for (TlSparseIndex j = 0; j < Z->n; ++j)
      for (TlSparseIndex p = Z->colptr[j]; p < Z->colptr[j + 1]; ++p)
        if ((p + j) % 3 == 0) Z->values[p] = 0.0, zeros += Z->rowind[p] != j;
    TL_TEST_STATUS(tl_sparse_compress(Z, &C), TL_OK);
    TL_TEST_ASSERT(C && C->nnz == Z->nnz - zeros, "compressed %lld entries, expected %lld",
                   C ? (long long)C->nnz : -1LL, (long long)(Z->nnz - zeros));
    double *zc = calloc((size_t)n, sizeof *zc), *zz = calloc((size_t)n, sizeof *zz), ec = 0.0;
    tl_sparse_matvec(Z, x, zz);
    tl_sparse_matvec(C, x, zc);
    for (TlSparseIndex i = 0; i < n; ++i) {
      ec = fmax(ec, fabs(zc[i] - zz[i]));
      TL_TEST_ASSERT(C->rowind[C->diag[i]] == i, "diagonal of column %lld kept", (long long)i);
    }
    TL_TEST_ASSERT(ec == 0.0, "compressed product differs by %g", ec);
    free(zc), free(zz);
    tl_sparse_destroy(&Z);
    tl_sparse_destroy(&C);
  }
  /* The SUNMatrix view multiplies like the matrix, shares its arrays, and
   * is refused for upper-triangle storage. */
  {
    SUNContext ctx = NULL;
    SUNContext_Create(NULL, &ctx);
    void *view = NULL;
    TL_TEST_STATUS(tl_sparse_sunmatrix_view(A, ctx, &view), TL_OK);
    N_Vector xv = N_VMake_Serial((sunindextype)n, x, ctx), yv = N_VNew_Serial((sunindextype)n, ctx);
    TL_TEST_ASSERT(SUNMatMatvec((SUNMatrix)view, xv, yv) == 0, "SUNMatMatvec");
    double ev = 0;
    for (TlSparseIndex i = 0; i < n; ++i) ev = fmax(ev, fabs(N_VGetArrayPointer(yv)[i] - ref[i]));
    TL_TEST_ASSERT(ev < 1e-13 && SUNSparseMatrix_Data((SUNMatrix)view) == A->values,
                   "SUNMatrix view error %g", ev);
    N_VDestroy(xv);
    N_VDestroy(yv);
    tl_sparse_sunmatrix_destroy(&view);
    TL_TEST_ASSERT(view == NULL && A->values != NULL, "view destroyed, arrays kept");
    TL_TEST_STATUS(tl_sparse_sunmatrix_view(U, ctx, &view), TL_ERR_ARG);
    SUNContext_Free(&ctx);
  }
  /* Entries outside the pattern are refused; the error names them. */
  TL_TEST_STATUS(tl_sparse_add(A, 0, n - 1, 1.0), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "not in the sparsity pattern") != NULL, "%s",
                 tl_error_message());
  TlSparseIndex bad[2] = {0, n};
  TlSparseIndex bptr[2] = {0, 2};
  TlSparse *B = NULL;
  TL_TEST_STATUS(tl_sparse_create_from_elements(n, 0, 1, bptr, bad, 0, &B), TL_ERR_ARG);
  TL_TEST_ASSERT(B == NULL, "no half-built matrix");

  /* The three solvers reproduce x from b = A x. */
  const char *names[3] = {"cholmod", "klu", "umfpack"};
  for (int s = 0; s < 3; ++s) {
    TlSparse *M = s == 0 ? U : A;
    TlLinearSolver *ls = NULL;
    TL_TEST_STATUS(tl_linear_solver_create(names[s], M, &ls), TL_OK);
    if (!ls) continue;
    TL_TEST_STATUS(tl_linear_solver_factor(ls, M), TL_OK);
    TL_TEST_STATUS(tl_linear_solver_solve(ls, ref, z), TL_OK);
    double err = 0;
    for (TlSparseIndex i = 0; i < n; ++i) err = fmax(err, fabs(z[i] - x[i]));
    TL_TEST_ASSERT(err < 1e-10, "%s solve error %g", names[s], err);
    /* Numeric refactorisation with new values, symbolic analysis kept. */
    for (TlSparseIndex k = 0; k < M->nnz; ++k) M->values[k] *= 2.0;
    TL_TEST_STATUS(tl_linear_solver_factor(ls, M), TL_OK);
    TL_TEST_STATUS(tl_linear_solver_solve(ls, ref, z), TL_OK);
    err = 0;
    for (TlSparseIndex i = 0; i < n; ++i) err = fmax(err, fabs(2.0 * z[i] - x[i]));
    TL_TEST_ASSERT(err < 1e-10, "%s refactorised solve error %g", names[s], err);
    TL_TEST_ASSERT(ls->stats.n_symbolic == 1 && ls->stats.n_numeric == 2,
                   "%s: %ld symbolic, %ld numeric", names[s], ls->stats.n_symbolic,
                   ls->stats.n_numeric);
    for (TlSparseIndex k = 0; k < M->nnz; ++k) M->values[k] *= 0.5;
    tl_linear_solver_destroy(&ls);
    TL_TEST_ASSERT(ls == NULL, "destroy nulls");
  }
  /* Wrong storage is refused; an indefinite matrix fails in CHOLMOD with a
   * message, not a crash. */
  TlLinearSolver *ls = NULL;
  TL_TEST_STATUS(tl_linear_solver_create("cholmod", A, &ls), TL_ERR_ARG);
  TL_TEST_STATUS(tl_linear_solver_create("klu", U, &ls), TL_ERR_ARG);
  TL_TEST_STATUS(tl_linear_solver_create("cholmod", U, &ls), TL_OK);
  U->values[U->diag[3]] = -100.0;
  TL_TEST_STATUS(tl_linear_solver_factor(ls, U), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(strstr(tl_error_message(), "not positive definite") != NULL, "%s",
                 tl_error_message());
  tl_linear_solver_destroy(&ls);

  /* Constraining: rows and columns zeroed, unit diagonal, symmetry kept. */
  TlSparseIndex con[2] = {2, mid};
  tl_sparse_constrain(A, 2, con, 1.0);
  /* The upper-triangle copy, constrained the same way, is the same matrix
   * (row `mid` has entries in later columns there). */
  tl_sparse_constrain(Ui, 2, con, 1.0);
  for (TlSparseIndex i = 0; i < n; ++i) x[i] = rnd(&seed);
  tl_sparse_matvec(A, x, y);
  tl_sparse_matvec(Ui, x, z);
  double eu = 0;
  for (TlSparseIndex i = 0; i < n; ++i) eu = fmax(eu, fabs(y[i] - z[i]));
  TL_TEST_ASSERT(eu < 1e-13, "constrained full vs upper storage differ by %g", eu);
  memset(x, 0, (size_t)n * sizeof *x);
  x[mid] = 1.0;
  tl_sparse_matvec(A, x, y);
  double off = 0;
  for (TlSparseIndex i = 0; i < n; ++i)
    if (i != mid) off = fmax(off, fabs(y[i]));
  TL_TEST_ASSERT(off == 0.0 && y[mid] == 1.0, "constrained column: off %g diag %g", off, y[mid]);
  double rowsum = 0;
  for (TlSparseIndex j = 0; j < n; ++j)
    for (TlSparseIndex p = A->colptr[j]; p < A->colptr[j + 1]; ++p)
      if (A->rowind[p] == mid && j != mid) rowsum += fabs(A->values[p]);
  TL_TEST_ASSERT(rowsum == 0.0, "constrained row off-diagonal sum %g", rowsum);

  /* Colouring: no two elements of a colour share a dof. */
  int colour[NX * NY], nc = 0;
  TL_TEST_STATUS(tl_sparse_colour_elements(n, ne, ptr, dofs, colour, &nc), TL_OK);
  int clash = 0;
  for (TlSparseIndex e = 0; e < ne; ++e)
    for (TlSparseIndex f = e + 1; f < ne; ++f)
      if (colour[e] == colour[f])
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b)
            if (dofs[4 * e + a] >= 0 && dofs[4 * e + a] == dofs[4 * f + b]) clash = 1;
  TL_TEST_ASSERT(!clash && nc >= 4 && nc <= 8, "colouring: %d colours, clash %d", nc, clash);

  /* Zeroing keeps the pattern. */
  TlSparseIndex nnz = A->nnz;
  tl_sparse_zero(A);
  double s2 = 0;
  for (TlSparseIndex k = 0; k < A->nnz; ++k) s2 += fabs(A->values[k]);
  TL_TEST_ASSERT(s2 == 0.0 && A->nnz == nnz, "zeroed");

  tl_sparse_destroy(&A);
  tl_sparse_destroy(&U);
  tl_sparse_destroy(&Ui);
  TL_TEST_ASSERT(A == NULL, "destroy nulls");
  free(dense);
  free(x);
  free(y);
  free(z);
  free(w);
  free(ref);
  return tl_test_report();
}
