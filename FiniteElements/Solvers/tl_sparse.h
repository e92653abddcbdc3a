/* A square sparse matrix in compressed-sparse-column form whose pattern is
 * built once from element dof lists and never changes afterwards.
 *
 * Contract
 * - Indices are TlSparseIndex (64-bit), the same type as SuiteSparse_long
 *   and SUNDIALS' sunindextype, so CHOLMOD (cholmod_l_*), KLU (klu_l_*),
 *   UMFPACK (umfpack_dl_*) and SUNMatrix sparse all see the arrays without
 *   a copy.
 * - Pattern: tl_sparse_create_from_elements() takes, for every element, the
 *   list of its global dofs; a negative dof is a constrained (eliminated)
 *   dof and is skipped.  Every pair (i, j) of dofs of one element becomes a
 *   stored entry.  Row indices are sorted within each column and the
 *   diagonal is always stored (so Dirichlet rows can be replaced by 1).
 * - Symmetric storage (symmetric = 1) keeps the upper triangle only
 *   (row <= column), CHOLMOD's stype = +1 convention; add_element then takes
 *   a full symmetric element matrix and keeps its upper-triangular part.
 * - Element matrices are dense, row-major, nd x nd, in the order of the
 *   element's dof list (constrained dofs included in the dense matrix, they
 *   are skipped on assembly).
 * - Adding is O(1) per entry with precomputed positions
 *   (tl_sparse_add_element_indexed, element e of the creation list; the map
 *   costs one index per element-matrix entry, built on request) and
 *   O(log column length) per entry otherwise (tl_sparse_add_element, any dof
 *   list whose pairs are in the pattern; a pair outside it is an error).
 * - Adding is not thread-safe for elements sharing dofs; the _atomic variant
 *   is, or colour the elements (tl_sparse_colour_elements) and add one colour
 *   per parallel loop.
 * - tl_sparse_zero() clears values without touching the pattern. */
#ifndef TL_SPARSE_H
#define TL_SPARSE_H

#include <stdint.h>
#include "tl_error.h"

typedef int64_t TlSparseIndex;

typedef struct {
  TlSparseIndex n;      /* rows = columns */
  TlSparseIndex nnz;    /* stored entries */
  int symmetric;        /* 1: upper triangle only (row <= col) */
  TlSparseIndex *colptr; /* n + 1 */
  TlSparseIndex *rowind; /* nnz, sorted in each column */
  double *values;        /* nnz */
  TlSparseIndex *diag;   /* n: position of the diagonal entry of each column */
  /* Optional precomputed positions: elem_pos[elem_pos_ptr[e] + i*nd + j] is
   * the slot of entry (i, j) of element e, or -1 (skipped). */
  TlSparseIndex n_elements;
  TlSparseIndex *elem_pos_ptr; /* n_elements + 1, NULL when not built */
  TlSparseIndex *elem_pos;
  unsigned char *mark; /* n bytes of scratch (tl_sparse_constrain) */
} TlSparse;

/* Builds the pattern of an n x n matrix from n_elements dof lists: element e
 * has dofs elem_dofs[elem_ptr[e] .. elem_ptr[e+1]-1] (values >= n are an
 * error, negative ones are skipped).  With positions = 1 the O(1) map for
 * tl_sparse_add_element_indexed is built too.  Values start at zero. */
TlStatus tl_sparse_create_from_elements(TlSparseIndex n, int symmetric, TlSparseIndex n_elements,
                                        const TlSparseIndex *elem_ptr,
                                        const TlSparseIndex *elem_dofs, int positions,
                                        TlSparse **A);
/* A deep copy of the pattern (values zero; the position map is shared by
 * value, i.e. copied). */
TlStatus tl_sparse_duplicate(const TlSparse *A, TlSparse **B);
void tl_sparse_destroy(TlSparse **A);
/* A copy of A without its exact zeros (the diagonal is always kept): for
 * products with a matrix whose element pattern is wider than its values,
 * such as a mass matrix that couples no two components.  No position map. */
TlStatus tl_sparse_compress(const TlSparse *A, TlSparse **B);

void tl_sparse_zero(TlSparse *A);
/* A(dofs, dofs) += scale * Ke (nd x nd row-major); O(log) search per entry. */
TlStatus tl_sparse_add_element(TlSparse *A, int nd, const TlSparseIndex *dofs, double scale,
                               const double *Ke);
/* The same with `#pragma omp atomic` updates: safe from parallel loops. */
TlStatus tl_sparse_add_element_atomic(TlSparse *A, int nd, const TlSparseIndex *dofs, double scale,
                                      const double *Ke);
/* Element e of the creation list, through the precomputed map; O(1). */
TlStatus tl_sparse_add_element_indexed(TlSparse *A, TlSparseIndex e, double scale, const double *Ke);
/* A(i, j) += value (for symmetric storage, (i, j) and (j, i) name the same
 * entry).  Error when (i, j) is not in the pattern. */
TlStatus tl_sparse_add(TlSparse *A, TlSparseIndex i, TlSparseIndex j, double value);
/* Y = alpha * X + Y on values; X and Y must share the pattern. */
TlStatus tl_sparse_axpy(double alpha, const TlSparse *X, TlSparse *Y);
/* y = A x (symmetric storage expanded). */
void tl_sparse_matvec(const TlSparse *A, const double *x, double *y);
/* Zeroes row and column of each listed dof and puts `diag` on its diagonal
 * (Dirichlet conditions with symmetric elimination). */
void tl_sparse_constrain(TlSparse *A, TlSparseIndex count, const TlSparseIndex *dofs, double diag);

/* Greedy colouring: colour[e] in 0..n_colours-1 such that no two elements of
 * one colour share a (non-negative) dof. */
TlStatus tl_sparse_colour_elements(TlSparseIndex n, TlSparseIndex n_elements,
                                   const TlSparseIndex *elem_ptr, const TlSparseIndex *elem_dofs,
                                   int *colour, int *n_colours);

/* Views without copy.  The CHOLMOD view is a cholmod_sparse (64-bit indices,
 * use the cholmod_l_* functions) whose arrays are A's; it lives as long as A
 * and must not be freed by CHOLMOD.  `view` points to a cholmod_sparse. */
void tl_sparse_cholmod_view(const TlSparse *A, void *view);
/* A SUNMatrix sparse (CSC_MAT) whose arrays are A's (full storage only: a
 * symmetric A is refused).  Destroy it with tl_sparse_sunmatrix_destroy,
 * never SUNMatDestroy, so A's arrays are not freed twice.  `sunctx` is a
 * SUNContext; the result is a SUNMatrix. */
TlStatus tl_sparse_sunmatrix_view(TlSparse *A, void *sunctx, void **sunmatrix);
void tl_sparse_sunmatrix_destroy(void **sunmatrix);

#endif
