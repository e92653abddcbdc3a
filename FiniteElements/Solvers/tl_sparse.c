#include "tl_sparse.h"

#include <stdlib.h>
#include <string.h>

#include <cholmod.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "tl_memory.h"

static int compare_index(const void *a, const void *b)
{
  TlSparseIndex x = *(const TlSparseIndex *)a, y = *(const TlSparseIndex *)b;
  return (x > y) - (x < y);
}

/* Position of row i in column j, or -1. */
static inline TlSparseIndex find_slot(const TlSparse *A, TlSparseIndex i, TlSparseIndex j)
{
  TlSparseIndex lo = A->colptr[j], hi = A->colptr[j + 1] - 1;
  const TlSparseIndex *r = A->rowind;
  while (lo <= hi) {
    TlSparseIndex mid = lo + (hi - lo) / 2;
    if (r[mid] < i) lo = mid + 1;
    else if (r[mid] > i) hi = mid - 1;
    else return mid;
  }
  return -1;
}

static TlStatus build_positions(TlSparse *A, TlSparseIndex n_elements, const TlSparseIndex *elem_ptr,
                                const TlSparseIndex *elem_dofs)
{
  TlSparseIndex total = 0;
  TL_CHECK(tl_calloc(&A->elem_pos_ptr, (size_t)n_elements + 1, sizeof *A->elem_pos_ptr));
  for (TlSparseIndex e = 0; e < n_elements; ++e) {
    TlSparseIndex nd = elem_ptr[e + 1] - elem_ptr[e];
    A->elem_pos_ptr[e] = total;
    total += nd * nd;
  }
  A->elem_pos_ptr[n_elements] = total;
  TL_CHECK(tl_calloc(&A->elem_pos, (size_t)(total > 0 ? total : 1), sizeof *A->elem_pos));
  for (TlSparseIndex e = 0; e < n_elements; ++e) {
    const TlSparseIndex *d = elem_dofs + elem_ptr[e];
    TlSparseIndex nd = elem_ptr[e + 1] - elem_ptr[e], *pos = A->elem_pos + A->elem_pos_ptr[e];
    for (TlSparseIndex a = 0; a < nd; ++a)
      for (TlSparseIndex b = 0; b < nd; ++b) {
        TlSparseIndex i = d[a], j = d[b];
        pos[a * nd + b] = (i < 0 || j < 0 || (A->symmetric && i > j)) ? -1 : find_slot(A, i, j);
      }
  }
  A->n_elements = n_elements;
  return TL_OK;
}

TlStatus tl_sparse_create_from_elements(TlSparseIndex n, int symmetric, TlSparseIndex n_elements,
                                        const TlSparseIndex *elem_ptr,
                                        const TlSparseIndex *elem_dofs, int positions,
                                        TlSparse **Aout)
{
  *Aout = NULL;
  if (n <= 0) TL_ERROR(TL_ERR_ARG, "sparse matrix size n = %lld must be positive", (long long)n);
  if (n_elements < 0 || (n_elements > 0 && (!elem_ptr || !elem_dofs)))
    TL_ERROR(TL_ERR_ARG, "element lists missing (n_elements = %lld)", (long long)n_elements);
  for (TlSparseIndex e = 0; e < n_elements; ++e) {
    if (elem_ptr[e + 1] < elem_ptr[e])
      TL_ERROR(TL_ERR_ARG, "element %lld has a negative dof count", (long long)e);
    for (TlSparseIndex k = elem_ptr[e]; k < elem_ptr[e + 1]; ++k)
      if (elem_dofs[k] >= n)
        TL_ERROR(TL_ERR_ARG, "element %lld dof %lld is beyond the matrix size %lld", (long long)e,
                 (long long)elem_dofs[k], (long long)n);
  }
  /* Column j collects the rows of all elements holding j: count with
   * duplicates, fill, then sort and compact each column. */
  TlStatus st = TL_OK;
  TlSparseIndex *count = NULL, *start = NULL, *rows = NULL;
  TlSparse *A = NULL;
  TL_CHECK_GOTO(st, tl_calloc(&count, (size_t)n + 1, sizeof *count), fail);
  for (TlSparseIndex e = 0; e < n_elements; ++e) {
    TlSparseIndex nd = elem_ptr[e + 1] - elem_ptr[e];
    for (TlSparseIndex k = elem_ptr[e]; k < elem_ptr[e + 1]; ++k)
      if (elem_dofs[k] >= 0) count[elem_dofs[k]] += nd;
  }
  for (TlSparseIndex j = 0; j < n; ++j) count[j] += 1; /* the diagonal */
  TL_CHECK_GOTO(st, tl_calloc(&start, (size_t)n + 1, sizeof *start), fail);
  for (TlSparseIndex j = 0; j < n; ++j) start[j + 1] = start[j] + count[j];
  TL_CHECK_GOTO(st, tl_calloc(&rows, (size_t)start[n], sizeof *rows), fail);
  for (TlSparseIndex j = 0; j < n; ++j) {
    count[j] = start[j];
    rows[count[j]++] = j;
  }
  for (TlSparseIndex e = 0; e < n_elements; ++e)
    for (TlSparseIndex k = elem_ptr[e]; k < elem_ptr[e + 1]; ++k) {
      TlSparseIndex j = elem_dofs[k];
      if (j < 0) continue;
      for (TlSparseIndex l = elem_ptr[e]; l < elem_ptr[e + 1]; ++l) {
        TlSparseIndex i = elem_dofs[l];
        if (i < 0 || (symmetric && i > j)) continue;
        rows[count[j]++] = i;
      }
    }
  TL_CHECK_GOTO(st, TL_NEW(A), fail);
  A->n = n;
  A->symmetric = symmetric ? 1 : 0;
  TL_CHECK_GOTO(st, tl_calloc(&A->colptr, (size_t)n + 1, sizeof *A->colptr), fail);
  TlSparseIndex nnz = 0;
  for (TlSparseIndex j = 0; j < n; ++j) {
    TlSparseIndex *r = rows + start[j], m = count[j] - start[j], w = 0;
    qsort(r, (size_t)m, sizeof *r, compare_index);
    for (TlSparseIndex k = 0; k < m; ++k)
      if (w == 0 || r[k] != r[w - 1]) r[w++] = r[k];
    count[j] = w;
    nnz += w;
  }
  A->nnz = nnz;
  TL_CHECK_GOTO(st, tl_calloc(&A->rowind, (size_t)nnz, sizeof *A->rowind), fail);
  TL_CHECK_GOTO(st, tl_calloc(&A->values, (size_t)nnz, sizeof *A->values), fail);
  TL_CHECK_GOTO(st, tl_calloc(&A->diag, (size_t)n, sizeof *A->diag), fail);
  TL_CHECK_GOTO(st, tl_calloc(&A->mark, (size_t)n, sizeof *A->mark), fail);
  for (TlSparseIndex j = 0; j < n; ++j) {
    A->colptr[j + 1] = A->colptr[j] + count[j];
    memcpy(A->rowind + A->colptr[j], rows + start[j], (size_t)count[j] * sizeof *rows);
  }
  for (TlSparseIndex j = 0; j < n; ++j) A->diag[j] = find_slot(A, j, j);
  if (positions) TL_CHECK_GOTO(st, build_positions(A, n_elements, elem_ptr, elem_dofs), fail);
  tl_free(&count);
  tl_free(&start);
  tl_free(&rows);
  *Aout = A;
  return TL_OK;
fail:
  tl_free(&count);
  tl_free(&start);
  tl_free(&rows);
  tl_sparse_destroy(&A);
  return st;
}

TlStatus tl_sparse_duplicate(const TlSparse *A, TlSparse **Bout)
{
  TlStatus st = TL_OK;
  TlSparse *B = NULL;
  *Bout = NULL;
  TL_CHECK_GOTO(st, TL_NEW(B), fail);
  B->n = A->n;
  B->nnz = A->nnz;
  B->symmetric = A->symmetric;
  TL_CHECK_GOTO(st, tl_calloc(&B->colptr, (size_t)A->n + 1, sizeof *B->colptr), fail);
  TL_CHECK_GOTO(st, tl_calloc(&B->rowind, (size_t)A->nnz, sizeof *B->rowind), fail);
  TL_CHECK_GOTO(st, tl_calloc(&B->values, (size_t)A->nnz, sizeof *B->values), fail);
  TL_CHECK_GOTO(st, tl_calloc(&B->diag, (size_t)A->n, sizeof *B->diag), fail);
  TL_CHECK_GOTO(st, tl_calloc(&B->mark, (size_t)A->n, sizeof *B->mark), fail);
  memcpy(B->colptr, A->colptr, (size_t)(A->n + 1) * sizeof *B->colptr);
  memcpy(B->rowind, A->rowind, (size_t)A->nnz * sizeof *B->rowind);
  memcpy(B->diag, A->diag, (size_t)A->n * sizeof *B->diag);
  if (A->elem_pos_ptr) {
    TlSparseIndex total = A->elem_pos_ptr[A->n_elements];
    B->n_elements = A->n_elements;
    TL_CHECK_GOTO(st, tl_calloc(&B->elem_pos_ptr, (size_t)A->n_elements + 1, sizeof *B->elem_pos_ptr), fail);
    TL_CHECK_GOTO(st, tl_calloc(&B->elem_pos, (size_t)(total > 0 ? total : 1), sizeof *B->elem_pos), fail);
    memcpy(B->elem_pos_ptr, A->elem_pos_ptr, (size_t)(A->n_elements + 1) * sizeof *B->elem_pos_ptr);
    memcpy(B->elem_pos, A->elem_pos, (size_t)total * sizeof *B->elem_pos);
  }
  *Bout = B;
  return TL_OK;
fail:
  tl_sparse_destroy(&B);
  return st;
}

TlStatus tl_sparse_compress(const TlSparse *A, TlSparse **Bout)
{
  TlStatus st = TL_OK;
  TlSparse *B = NULL;
  *Bout = NULL;
  TlSparseIndex nnz = 0;
  for (TlSparseIndex j = 0; j < A->n; ++j)
    for (TlSparseIndex p = A->colptr[j]; p < A->colptr[j + 1]; ++p) nnz += A->values[p] != 0.0 || A->rowind[p] == j;
  TL_CHECK_GOTO(st, TL_NEW(B), fail);
  B->n = A->n;
  B->nnz = nnz;
  B->symmetric = A->symmetric;
  TL_CHECK_GOTO(st, tl_calloc(&B->colptr, (size_t)A->n + 1, sizeof *B->colptr), fail);
  TL_CHECK_GOTO(st, tl_calloc(&B->rowind, (size_t)(nnz ? nnz : 1), sizeof *B->rowind), fail);
  TL_CHECK_GOTO(st, tl_calloc(&B->values, (size_t)(nnz ? nnz : 1), sizeof *B->values), fail);
  TL_CHECK_GOTO(st, tl_calloc(&B->diag, (size_t)(A->n ? A->n : 1), sizeof *B->diag), fail);
  TL_CHECK_GOTO(st, tl_calloc(&B->mark, (size_t)(A->n ? A->n : 1), sizeof *B->mark), fail);
  TlSparseIndex k = 0;
  for (TlSparseIndex j = 0; j < A->n; ++j) {
    B->colptr[j] = k;
    B->diag[j] = -1;
    for (TlSparseIndex p = A->colptr[j]; p < A->colptr[j + 1]; ++p) {
      if (A->values[p] == 0.0 && A->rowind[p] != j) continue;
      if (A->rowind[p] == j) B->diag[j] = k;
      B->rowind[k] = A->rowind[p];
      B->values[k++] = A->values[p];
    }
  }
  B->colptr[A->n] = k;
  *Bout = B;
  return TL_OK;
fail:
  tl_sparse_destroy(&B);
  return st;
}

void tl_sparse_destroy(TlSparse **A)
{
  if (!A || !*A) return;
  tl_free(&(*A)->colptr);
  tl_free(&(*A)->rowind);
  tl_free(&(*A)->values);
  tl_free(&(*A)->diag);
  tl_free(&(*A)->mark);
  tl_free(&(*A)->elem_pos_ptr);
  tl_free(&(*A)->elem_pos);
  tl_free(A);
}

void tl_sparse_zero(TlSparse *A) { memset(A->values, 0, (size_t)A->nnz * sizeof *A->values); }

static TlStatus add_element(TlSparse *A, int nd, const TlSparseIndex *dofs, double scale,
                            const double *Ke, int atomic)
{
  for (int b = 0; b < nd; ++b) {
    TlSparseIndex j = dofs[b];
    if (j < 0) continue;
    for (int a = 0; a < nd; ++a) {
      TlSparseIndex i = dofs[a];
      if (i < 0 || (A->symmetric && i > j)) continue;
      TlSparseIndex p = find_slot(A, i, j);
      if (p < 0)
        TL_ERROR(TL_ERR_ARG, "entry (%lld, %lld) is not in the sparsity pattern (n = %lld)",
                 (long long)i, (long long)j, (long long)A->n);
      double add = scale * Ke[a * nd + b];
      if (atomic) {
#pragma omp atomic
        A->values[p] += add;
      } else {
        A->values[p] += add;
      }
    }
  }
  return TL_OK;
}

TlStatus tl_sparse_add_element(TlSparse *A, int nd, const TlSparseIndex *dofs, double scale,
                               const double *Ke)
{
  return add_element(A, nd, dofs, scale, Ke, 0);
}

TlStatus tl_sparse_add_element_atomic(TlSparse *A, int nd, const TlSparseIndex *dofs, double scale,
                                      const double *Ke)
{
  return add_element(A, nd, dofs, scale, Ke, 1);
}

TlStatus tl_sparse_add_element_indexed(TlSparse *A, TlSparseIndex e, double scale, const double *Ke)
{
  if (!A->elem_pos_ptr)
    TL_ERROR(TL_ERR_STATE, "element positions were not built (create with positions = 1)");
  if (e < 0 || e >= A->n_elements)
    TL_ERROR(TL_ERR_ARG, "element %lld out of range [0, %lld)", (long long)e, (long long)A->n_elements);
  const TlSparseIndex *pos = A->elem_pos + A->elem_pos_ptr[e];
  TlSparseIndex m = A->elem_pos_ptr[e + 1] - A->elem_pos_ptr[e];
  double *v = A->values;
  for (TlSparseIndex k = 0; k < m; ++k)
    if (pos[k] >= 0) v[pos[k]] += scale * Ke[k];
  return TL_OK;
}

TlStatus tl_sparse_add(TlSparse *A, TlSparseIndex i, TlSparseIndex j, double value)
{
  if (i < 0 || j < 0 || i >= A->n || j >= A->n)
    TL_ERROR(TL_ERR_ARG, "entry (%lld, %lld) outside the %lld x %lld matrix", (long long)i,
             (long long)j, (long long)A->n, (long long)A->n);
  if (A->symmetric && i > j) {
    TlSparseIndex t = i;
    i = j;
    j = t;
  }
  TlSparseIndex p = find_slot(A, i, j);
  if (p < 0)
    TL_ERROR(TL_ERR_ARG, "entry (%lld, %lld) is not in the sparsity pattern", (long long)i,
             (long long)j);
  A->values[p] += value;
  return TL_OK;
}

TlStatus tl_sparse_axpy(double alpha, const TlSparse *X, TlSparse *Y)
{
  if (X->n != Y->n || X->nnz != Y->nnz || X->symmetric != Y->symmetric)
    TL_ERROR(TL_ERR_ARG, "axpy on different patterns (n %lld vs %lld, nnz %lld vs %lld)",
             (long long)X->n, (long long)Y->n, (long long)X->nnz, (long long)Y->nnz);
  for (TlSparseIndex k = 0; k < X->nnz; ++k) Y->values[k] += alpha * X->values[k];
  return TL_OK;
}

void tl_sparse_matvec(const TlSparse *A, const double *x, double *y)
{
  const TlSparseIndex n = A->n, *cp = A->colptr, *ri = A->rowind;
  const double *v = A->values;
  memset(y, 0, (size_t)n * sizeof *y);
  if (!A->symmetric) {
    for (TlSparseIndex j = 0; j < n; ++j) {
      double xj = x[j];
      for (TlSparseIndex p = cp[j]; p < cp[j + 1]; ++p) y[ri[p]] += v[p] * xj;
    }
    return;
  }
  for (TlSparseIndex j = 0; j < n; ++j) {
    double xj = x[j], s = 0.0;
    for (TlSparseIndex p = cp[j]; p < cp[j + 1]; ++p) {
      TlSparseIndex i = ri[p];
      y[i] += v[p] * xj;
      if (i != j) s += v[p] * x[i];
    }
    y[j] += s;
  }
}

void tl_sparse_constrain(TlSparse *A, TlSparseIndex count, const TlSparseIndex *dofs, double diag)
{
  if (count <= 0) return;
  /* One pass over the stored entries zeroes every entry in a marked row or
   * column; this covers both triangles of a full matrix and the entries of
   * row c kept in later columns of an upper-triangle one. */
  for (TlSparseIndex k = 0; k < count; ++k)
    if (dofs[k] >= 0 && dofs[k] < A->n) A->mark[dofs[k]] = 1;
  for (TlSparseIndex j = 0; j < A->n; ++j) {
    if (A->mark[j]) {
      for (TlSparseIndex p = A->colptr[j]; p < A->colptr[j + 1]; ++p) A->values[p] = 0.0;
      A->values[A->diag[j]] = diag;
      continue;
    }
    for (TlSparseIndex p = A->colptr[j]; p < A->colptr[j + 1]; ++p)
      if (A->mark[A->rowind[p]]) A->values[p] = 0.0;
  }
  for (TlSparseIndex k = 0; k < count; ++k)
    if (dofs[k] >= 0 && dofs[k] < A->n) A->mark[dofs[k]] = 0;
}

TlStatus tl_sparse_colour_elements(TlSparseIndex n, TlSparseIndex n_elements,
                                   const TlSparseIndex *elem_ptr, const TlSparseIndex *elem_dofs,
                                   int *colour, int *n_colours)
{
  /* last[d] bit c set: colour c already touches dof d.  64 colours suffice
   * for any conforming hex or tet mesh. */
  uint64_t *used = NULL;
  TL_CHECK(tl_calloc(&used, (size_t)n, sizeof *used));
  int nc = 0;
  for (TlSparseIndex e = 0; e < n_elements; ++e) {
    uint64_t busy = 0;
    for (TlSparseIndex k = elem_ptr[e]; k < elem_ptr[e + 1]; ++k)
      if (elem_dofs[k] >= 0) busy |= used[elem_dofs[k]];
    int c = 0;
    while (c < 64 && (busy >> c & 1u)) ++c;
    if (c == 64) {
      tl_free(&used);
      TL_ERROR(TL_ERR_ARG, "element %lld needs more than 64 colours", (long long)e);
    }
    colour[e] = c;
    if (c + 1 > nc) nc = c + 1;
    for (TlSparseIndex k = elem_ptr[e]; k < elem_ptr[e + 1]; ++k)
      if (elem_dofs[k] >= 0) used[elem_dofs[k]] |= (uint64_t)1 << c;
  }
  tl_free(&used);
  *n_colours = nc;
  return TL_OK;
}

void tl_sparse_cholmod_view(const TlSparse *A, void *view)
{
  cholmod_sparse *S = view;
  memset(S, 0, sizeof *S);
  S->nrow = (size_t)A->n;
  S->ncol = (size_t)A->n;
  S->nzmax = (size_t)A->nnz;
  S->p = A->colptr;
  S->i = A->rowind;
  S->x = A->values;
  S->stype = A->symmetric ? 1 : 0;
  S->itype = CHOLMOD_LONG;
  S->xtype = CHOLMOD_REAL;
  S->dtype = CHOLMOD_DOUBLE;
  S->sorted = 1;
  S->packed = 1;
}

TlStatus tl_sparse_sunmatrix_view(TlSparse *A, void *sunctx, void **out)
{
  *out = NULL;
  if (A->symmetric)
    TL_ERROR(TL_ERR_ARG, "a SUNMatrix view needs full storage; this matrix stores the upper triangle");
  SUNMatrix M = SUNSparseMatrix((sunindextype)A->n, (sunindextype)A->n, 1, CSC_MAT, (SUNContext)sunctx);
  if (!M) TL_ERROR(TL_ERR_MEM, "SUNSparseMatrix(%lld) failed", (long long)A->n);
  SUNMatrixContent_Sparse c = SM_CONTENT_S(M);
  free(c->data);
  free(c->indexvals);
  free(c->indexptrs);
  c->NNZ = (sunindextype)A->nnz;
  c->data = A->values;
  c->indexvals = (sunindextype *)A->rowind;
  c->indexptrs = (sunindextype *)A->colptr;
  c->rowvals = &c->indexvals;
  c->colptrs = &c->indexptrs;
  *out = M;
  return TL_OK;
}

void tl_sparse_sunmatrix_destroy(void **sunmatrix)
{
  if (!sunmatrix || !*sunmatrix) return;
  SUNMatrix M = *sunmatrix;
  SUNMatrixContent_Sparse c = SM_CONTENT_S(M);
  c->data = NULL;
  c->indexvals = NULL;
  c->indexptrs = NULL;
  SUNMatDestroy(M);
  *sunmatrix = NULL;
}
