/* The algebra of the bridging-domain velocity correction: the lumped
 * diagonal, the Woodbury system of the consistent strong constraint and
 * the weak constraint's A^W, each built and factorised once. */
#include "tl_bdm_system.h"

#include <math.h>
#include <string.h>

#include "tl_linear_solver.h"
#include "tl_memory.h"

/* Entries of one row: the nodes of one element (hex27: 27). */
#define TL_BDM_MAX_ROW 64

struct TlBdmSystem {
  TlBdmConstraint constraint;
  TlBdmLumping lumping;
  int jacobi;
  size_t n_q, nnz;
  size_t *ptr;
  TlSparseIndex *dof;
  double *phi, *m;
  TlSparseIndex n_dof;
  double *M;
  unsigned char *fixed;
  /* free dofs the rows reach: local index of a dof (-1: none), the list */
  TlSparseIndex *free_loc, *free_dofs;
  size_t n_free;
  /* weak rows (every reached dof) */
  TlSparseIndex *row_loc, *rows;
  size_t n_rows;
  double *D;                /* lumped strong diagonal */
  TlSparse *S;              /* Woodbury system or A^W (upper storage) */
  TlLinearSolver *ls;
  double *w_free, *w_rows, *lambda_w, *r_q, *t_q; /* scratch */
};

/* Rows with their repeated dofs merged (dofs tied by a periodic condition
 * appear once, with the summed shape values). */
static TlStatus copy_operator(TlBdmSystem *s, const TlBdmOperator *op)
{
  size_t n_q = op->n_q, nnz = op->ptr[n_q];
  if (op->ptr[0] != 0) TL_ERROR(TL_ERR_ARG, "bdm: row pointer starts at %zu, not 0", op->ptr[0]);
  TL_CHECK(tl_calloc(&s->ptr, n_q + 1, sizeof *s->ptr));
  TL_CHECK(tl_calloc(&s->dof, nnz ? nnz : 1, sizeof *s->dof));
  TL_CHECK(tl_calloc(&s->phi, nnz ? nnz : 1, sizeof *s->phi));
  TL_CHECK(tl_calloc(&s->m, n_q, sizeof *s->m));
  size_t k = 0;
  for (size_t q = 0; q < n_q; ++q) {
    if (op->ptr[q + 1] < op->ptr[q]) TL_ERROR(TL_ERR_ARG, "bdm: row pointer decreases at row %zu", q);
    if (!(op->m[q] > 0.0) || !isfinite(op->m[q]))
      TL_ERROR(TL_ERR_ARG, "bdm: weighted particle mass %g at constraint %zu must be finite and > 0", op->m[q], q);
    s->m[q] = op->m[q];
    size_t start = k;
    for (size_t e = op->ptr[q]; e < op->ptr[q + 1]; ++e) {
      TlSparseIndex J = op->dof[e];
      if (J < 0 || J >= op->n_dof)
        TL_ERROR(TL_ERR_ARG, "bdm: dof %lld of constraint %zu outside [0, %lld)", (long long)J, q, (long long)op->n_dof);
      if (!isfinite(op->phi[e])) TL_ERROR(TL_ERR_ARG, "bdm: shape value %g of constraint %zu", op->phi[e], q);
      size_t f = start;
      while (f < k && s->dof[f] != J) ++f;
      if (f == k) {
        s->dof[k] = J;
        s->phi[k++] = 0.0;
      }
      s->phi[f] += op->phi[e];
    }
    if (k - start > TL_BDM_MAX_ROW)
      TL_ERROR(TL_ERR_ARG, "bdm: constraint %zu reaches %zu dofs, more than the %d of one element", q, k - start,
               TL_BDM_MAX_ROW);
    s->ptr[q + 1] = k;
  }
  s->n_q = n_q;
  s->nnz = k;
  s->n_dof = op->n_dof;
  TL_CHECK(tl_calloc(&s->M, (size_t)op->n_dof, sizeof *s->M));
  TL_CHECK(tl_calloc(&s->fixed, (size_t)op->n_dof, 1));
  memcpy(s->M, op->M, (size_t)op->n_dof * sizeof *s->M);
  if (op->fixed) memcpy(s->fixed, op->fixed, (size_t)op->n_dof);
  return TL_OK;
}

/* Local numberings of the reached free dofs and of every reached dof. */
static TlStatus number_dofs(TlBdmSystem *s)
{
  size_t nd = (size_t)s->n_dof;
  TL_CHECK(tl_calloc(&s->free_loc, nd, sizeof *s->free_loc));
  TL_CHECK(tl_calloc(&s->row_loc, nd, sizeof *s->row_loc));
  for (size_t J = 0; J < nd; ++J) s->free_loc[J] = s->row_loc[J] = -1;
  TL_CHECK(tl_calloc(&s->free_dofs, nd ? nd : 1, sizeof *s->free_dofs));
  TL_CHECK(tl_calloc(&s->rows, nd ? nd : 1, sizeof *s->rows));
  for (size_t e = 0; e < s->nnz; ++e) {
    TlSparseIndex J = s->dof[e];
    if (s->row_loc[J] < 0) {
      s->row_loc[J] = (TlSparseIndex)s->n_rows;
      s->rows[s->n_rows++] = J;
    }
    if (!s->fixed[J] && s->free_loc[J] < 0) {
      if (!(s->M[J] > 0.0) || !isfinite(s->M[J]))
        TL_ERROR(TL_ERR_ARG, "bdm: weighted mass %g of free dof %lld must be finite and > 0", s->M[J], (long long)J);
      s->free_loc[J] = (TlSparseIndex)s->n_free;
      s->free_dofs[s->n_free++] = J;
    }
  }
  return TL_OK;
}

static TlStatus build_lumped(TlBdmSystem *s)
{
  double *colsum = NULL;
  TL_CHECK(tl_calloc(&colsum, (size_t)s->n_dof, sizeof *colsum));
  for (size_t e = 0; e < s->nnz; ++e) colsum[s->dof[e]] += s->phi[e];
  TlStatus st = tl_calloc(&s->D, s->n_q, sizeof *s->D);
  if (st == TL_OK)
    for (size_t q = 0; q < s->n_q; ++q) {
      double d = 1.0 / s->m[q];
      for (size_t e = s->ptr[q]; e < s->ptr[q + 1]; ++e) {
        TlSparseIndex J = s->dof[e];
        if (s->free_loc[J] < 0) continue;
        d += s->phi[e] * (s->lumping == TL_BDM_LUMP_DIAG ? s->phi[e] : colsum[J]) / s->M[J];
      }
      s->D[q] = d;
    }
  tl_free(&colsum);
  return st;
}

/* A TlSparse (upper or full) over n local indices whose pattern holds the
 * cliques of `n_el` element lists (eptr, edofs). */
static TlStatus pattern(TlSparseIndex n, int upper, size_t n_el, const TlSparseIndex *eptr, const TlSparseIndex *edofs,
                        TlSparse **A)
{
  return tl_sparse_create_from_elements(n, upper, (TlSparseIndex)n_el, eptr, edofs, 0, A);
}

/* Element lists of the rows of N in a local numbering loc (entries with
 * loc < 0 left out). */
static TlStatus row_lists(const TlBdmSystem *s, const TlSparseIndex *loc, TlSparseIndex **eptr, TlSparseIndex **edofs)
{
  TL_CHECK(tl_calloc(eptr, s->n_q + 1, sizeof **eptr));
  TL_CHECK(tl_calloc(edofs, s->nnz ? s->nnz : 1, sizeof **edofs));
  size_t k = 0;
  for (size_t q = 0; q < s->n_q; ++q) {
    for (size_t e = s->ptr[q]; e < s->ptr[q + 1]; ++e)
      if (loc[s->dof[e]] >= 0) (*edofs)[k++] = loc[s->dof[e]];
    (*eptr)[q + 1] = (TlSparseIndex)k;
  }
  return TL_OK;
}

/* Adds c phi phi^T of each row (local numbering loc) into A. */
static TlStatus add_rows(const TlBdmSystem *s, const TlSparseIndex *loc, int by_mass, TlSparse *A, double *Ke,
                         TlSparseIndex *ids)
{
  for (size_t q = 0; q < s->n_q; ++q) {
    int nd = 0;
    double v[TL_BDM_MAX_ROW];
    for (size_t e = s->ptr[q]; e < s->ptr[q + 1]; ++e)
      if (loc[s->dof[e]] >= 0 && nd < TL_BDM_MAX_ROW) {
        ids[nd] = loc[s->dof[e]];
        v[nd++] = s->phi[e];
      }
    double c = by_mass ? s->m[q] : 1.0 / s->m[q];
    for (int a = 0; a < nd; ++a)
      for (int b = 0; b < nd; ++b) Ke[a * nd + b] = c * v[a] * v[b];
    if (nd) TL_CHECK(tl_sparse_add_element(A, nd, ids, 1.0, Ke));
  }
  return TL_OK;
}

/* Factorises S once.  A singular S may still pass Cholesky on round-off
 * pivots, so the factors are probed: S x = S 1 must give x = 1. */
static TlStatus factorise(TlBdmSystem *s, const char *what)
{
  const char *hint = s->constraint == TL_BDM_WEAK
                         ? ": some node's support holds too few particles to fix its multiplier (N has dependent "
                           "rows); use the strong constraint or a finer packing"
                         : "";
  const TlSparseIndex n = s->S->n;
  TL_CHECK(tl_linear_solver_create("cholmod", s->S, &s->ls));
  TlStatus st = tl_linear_solver_factor(s->ls, s->S);
  if (st != TL_OK)
    TL_ERROR(TL_ERR_NUMERIC, "bdm: the %s (%lld x %lld) is not positive definite%s", what, (long long)n, (long long)n,
             hint);
  double *x = NULL, *b = NULL;
  st = tl_calloc(&x, (size_t)n, sizeof *x);
  if (st == TL_OK) st = tl_calloc(&b, (size_t)n, sizeof *b);
  double err = 0.0;
  if (st == TL_OK) {
    for (TlSparseIndex i = 0; i < n; ++i) x[i] = 1.0;
    tl_sparse_matvec(s->S, x, b);
    st = tl_linear_solver_solve(s->ls, b, x);
    for (TlSparseIndex i = 0; i < n && st == TL_OK; ++i) {
      double e = fabs(x[i] - 1.0);
      err = e > err || e != e ? (e != e ? INFINITY : e) : err;
    }
  }
  tl_free(&x);
  tl_free(&b);
  TL_CHECK(st);
  if (!(err <= 1e-6))
    TL_ERROR(TL_ERR_NUMERIC, "bdm: the %s (%lld x %lld) is singular to working precision (the probe S x = S 1 "
             "returns x off by %.3g, limit 1e-6)%s", what, (long long)n, (long long)n, err, hint);
  return TL_OK;
}

/* Woodbury: S = Mbar_f + N_f mbar N_f^T on the free reached dofs. */
static TlStatus build_woodbury(TlBdmSystem *s)
{
  TlSparseIndex *eptr = NULL, *edofs = NULL, ids[TL_BDM_MAX_ROW];
  double *Ke = NULL;
  TlStatus st = row_lists(s, s->free_loc, &eptr, &edofs);
  if (st == TL_OK) st = pattern((TlSparseIndex)s->n_free, 1, s->n_q, eptr, edofs, &s->S);
  if (st == TL_OK) st = tl_calloc(&Ke, TL_BDM_MAX_ROW * TL_BDM_MAX_ROW, sizeof *Ke);
  if (st == TL_OK) st = add_rows(s, s->free_loc, 1, s->S, Ke, ids);
  for (size_t f = 0; f < s->n_free && st == TL_OK; ++f)
    st = tl_sparse_add(s->S, (TlSparseIndex)f, (TlSparseIndex)f, s->M[s->free_dofs[f]]);
  tl_free(&eptr);
  tl_free(&edofs);
  tl_free(&Ke);
  TL_CHECK(st);
  return factorise(s, "Woodbury system Mbar + N mbar N^T");
}

/* A^W = B_Rf Mbar_f^-1 B_fR + N_R mbar^-1 N_R^T with B = N N^T. */
static TlStatus build_weak(TlBdmSystem *s)
{
  TlSparseIndex *eptr = NULL, *edofs = NULL, ids[TL_BDM_MAX_ROW], *wptr = NULL, *wdofs = NULL;
  double *Ke = NULL;
  TlSparse *B = NULL;
  const TlSparseIndex nR = (TlSparseIndex)s->n_rows;
  TlStatus st = row_lists(s, s->row_loc, &eptr, &edofs);
  if (st == TL_OK) st = pattern(nR, 0, s->n_q, eptr, edofs, &B);
  if (st == TL_OK) st = tl_calloc(&Ke, TL_BDM_MAX_ROW * TL_BDM_MAX_ROW, sizeof *Ke);
  if (st == TL_OK) {
    /* B = N_R N_R^T */
    for (size_t q = 0; q < s->n_q && st == TL_OK; ++q) {
      int nd = 0;
      double v[TL_BDM_MAX_ROW];
      for (size_t e = s->ptr[q]; e < s->ptr[q + 1] && nd < TL_BDM_MAX_ROW; ++e) {
        ids[nd] = s->row_loc[s->dof[e]];
        v[nd++] = s->phi[e];
      }
      for (int a = 0; a < nd; ++a)
        for (int b = 0; b < nd; ++b) Ke[a * nd + b] = v[a] * v[b];
      st = tl_sparse_add_element(B, nd, ids, 1.0, Ke);
    }
  }
  /* pattern of A^W: the rows' cliques and, per free dof, the clique of
   * its column of B */
  size_t n_el = s->n_q + s->n_free;
  if (st == TL_OK) st = tl_calloc(&wptr, n_el + 1, sizeof *wptr);
  if (st == TL_OK) st = tl_calloc(&wdofs, (size_t)eptr[s->n_q] + (size_t)B->nnz + 1, sizeof *wdofs);
  if (st == TL_OK) {
    size_t k = 0;
    for (size_t q = 0; q < s->n_q; ++q) {
      for (TlSparseIndex e = eptr[q]; e < eptr[q + 1]; ++e) wdofs[k++] = edofs[e];
      wptr[q + 1] = (TlSparseIndex)k;
    }
    for (size_t f = 0; f < s->n_free; ++f) {
      TlSparseIndex c = s->row_loc[s->free_dofs[f]];
      for (TlSparseIndex p = B->colptr[c]; p < B->colptr[c + 1]; ++p) wdofs[k++] = B->rowind[p];
      wptr[s->n_q + f + 1] = (TlSparseIndex)k;
    }
    st = pattern(nR, 1, n_el, wptr, wdofs, &s->S);
  }
  if (st == TL_OK) st = add_rows(s, s->row_loc, 0, s->S, Ke, ids);
  for (size_t f = 0; f < s->n_free && st == TL_OK; ++f) {
    TlSparseIndex J = s->free_dofs[f], c = s->row_loc[J];
    TlSparseIndex p0 = B->colptr[c], nd = B->colptr[c + 1] - p0;
    double *Kb = NULL;
    st = tl_calloc(&Kb, (size_t)(nd * nd), sizeof *Kb);
    if (st != TL_OK) break;
    for (TlSparseIndex a = 0; a < nd; ++a)
      for (TlSparseIndex b = 0; b < nd; ++b) Kb[a * nd + b] = B->values[p0 + a] * B->values[p0 + b] / s->M[J];
    st = tl_sparse_add_element(s->S, (int)nd, B->rowind + p0, 1.0, Kb);
    tl_free(&Kb);
  }
  tl_sparse_destroy(&B);
  tl_free(&eptr);
  tl_free(&edofs);
  tl_free(&wptr);
  tl_free(&wdofs);
  tl_free(&Ke);
  TL_CHECK(st);
  return factorise(s, "weak constraint matrix A^W = N A N^T");
}

TlStatus tl_bdm_system_create(const TlBdmOperator *op, TlBdmConstraint constraint, TlBdmLumping lumping, int jacobi,
                              TlBdmSystem **out)
{
  *out = NULL;
  if (!op || !op->ptr || op->n_q == 0) TL_ERROR(TL_ERR_ARG, "bdm: the constraint has no particle (n_q = 0)");
  if (constraint != TL_BDM_STRONG && constraint != TL_BDM_WEAK)
    TL_ERROR(TL_ERR_ARG, "bdm: constraint %d is neither strong (0) nor weak (1)", (int)constraint);
  if (lumping < TL_BDM_LUMP_ROWSUM || lumping > TL_BDM_LUMP_NONE)
    TL_ERROR(TL_ERR_ARG, "bdm: lumping %d outside [0, 2]", (int)lumping);
  if (jacobi < 0 || jacobi > 1000) TL_ERROR(TL_ERR_ARG, "bdm: Jacobi sweeps %d outside [0, 1000]", jacobi);
  TlBdmSystem *s;
  TL_CHECK(TL_NEW(s));
  s->constraint = constraint;
  s->lumping = constraint == TL_BDM_WEAK ? TL_BDM_LUMP_NONE : lumping;
  s->jacobi = jacobi;
  TlStatus st = copy_operator(s, op);
  if (st == TL_OK) st = number_dofs(s);
  if (st == TL_OK && s->n_free == 0 && constraint == TL_BDM_STRONG && lumping == TL_BDM_LUMP_NONE) {
    /* nothing on the FE side to correct: A = mbar^-1 (exact as lumped) */
    s->lumping = TL_BDM_LUMP_DIAG;
  }
  if (st == TL_OK) st = tl_calloc(&s->w_free, s->n_free ? s->n_free : 1, sizeof(double));
  if (st == TL_OK) st = tl_calloc(&s->w_rows, s->n_rows ? s->n_rows : 1, sizeof(double));
  if (st == TL_OK) st = tl_calloc(&s->lambda_w, s->n_rows ? s->n_rows : 1, sizeof(double));
  if (st == TL_OK) st = tl_calloc(&s->r_q, s->n_q, sizeof(double));
  if (st == TL_OK) st = tl_calloc(&s->t_q, s->n_q, sizeof(double));
  if (st == TL_OK) {
    if (constraint == TL_BDM_WEAK) st = build_weak(s);
    else if (s->lumping == TL_BDM_LUMP_NONE) st = build_woodbury(s);
    else st = build_lumped(s);
  }
  if (st != TL_OK) {
    tl_bdm_system_destroy(&s);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  *out = s;
  return TL_OK;
}

void tl_bdm_system_destroy(TlBdmSystem **ps)
{
  TlBdmSystem *s = *ps;
  if (!s) return;
  tl_linear_solver_destroy(&s->ls);
  tl_sparse_destroy(&s->S);
  void *arr[] = {&s->ptr, &s->dof, &s->phi, &s->m, &s->M, &s->fixed, &s->free_loc, &s->free_dofs, &s->row_loc,
                 &s->rows, &s->D, &s->w_free, &s->w_rows, &s->lambda_w, &s->r_q, &s->t_q};
  for (size_t k = 0; k < sizeof arr / sizeof arr[0]; ++k) tl_free(arr[k]);
  tl_free(ps);
}

void tl_bdm_system_rate(const TlBdmSystem *s, const double *v_dof, const double *v_q, double *gdot)
{
  for (size_t q = 0; q < s->n_q; ++q) {
    double g = -v_q[q];
    for (size_t e = s->ptr[q]; e < s->ptr[q + 1]; ++e) g += s->phi[e] * v_dof[s->dof[e]];
    gdot[q] = g;
  }
}

void tl_bdm_system_weak_rate(const TlBdmSystem *s, const double *gdot, double *gw)
{
  memset(gw, 0, s->n_rows * sizeof *gw);
  for (size_t q = 0; q < s->n_q; ++q)
    for (size_t e = s->ptr[q]; e < s->ptr[q + 1]; ++e) gw[s->row_loc[s->dof[e]]] += s->phi[e] * gdot[q];
}

/* w_free = N_f x (free local numbering). */
static void gather_free(const TlBdmSystem *s, const double *x, double *w)
{
  memset(w, 0, s->n_free * sizeof *w);
  for (size_t q = 0; q < s->n_q; ++q)
    for (size_t e = s->ptr[q]; e < s->ptr[q + 1]; ++e) {
      TlSparseIndex f = s->free_loc[s->dof[e]];
      if (f >= 0) w[f] += s->phi[e] * x[q];
    }
}

void tl_bdm_system_apply_A(const TlBdmSystem *s, const double *x, double *y)
{
  double *w = s->w_free;
  gather_free(s, x, w);
  for (size_t f = 0; f < s->n_free; ++f) w[f] /= s->M[s->free_dofs[f]];
  for (size_t q = 0; q < s->n_q; ++q) {
    double v = x[q] / s->m[q];
    for (size_t e = s->ptr[q]; e < s->ptr[q + 1]; ++e) {
      TlSparseIndex f = s->free_loc[s->dof[e]];
      if (f >= 0) v += s->phi[e] * w[f];
    }
    y[q] = v;
  }
}

/* Woodbury: x = A^-1 b = mbar b - mbar N_f^T S^-1 N_f mbar b (x may be b). */
static TlStatus woodbury(TlBdmSystem *s, const double *b, double *x)
{
  for (size_t q = 0; q < s->n_q; ++q) s->t_q[q] = s->m[q] * b[q];
  gather_free(s, s->t_q, s->w_free);
  TL_CHECK(tl_linear_solver_solve(s->ls, s->w_free, s->w_free));
  for (size_t q = 0; q < s->n_q; ++q) {
    double v = 0.0;
    for (size_t e = s->ptr[q]; e < s->ptr[q + 1]; ++e) {
      TlSparseIndex f = s->free_loc[s->dof[e]];
      if (f >= 0) v += s->phi[e] * s->w_free[f];
    }
    x[q] = s->t_q[q] - s->m[q] * v;
  }
  return TL_OK;
}

TlStatus tl_bdm_system_solve(TlBdmSystem *s, const double *gdot, double *mu)
{
  const size_t n_q = s->n_q;
  if (s->constraint == TL_BDM_WEAK) {
    tl_bdm_system_weak_rate(s, gdot, s->w_rows);
    TL_CHECK(tl_linear_solver_solve(s->ls, s->w_rows, s->lambda_w));
    for (size_t q = 0; q < n_q; ++q) {
      double v = 0.0;
      for (size_t e = s->ptr[q]; e < s->ptr[q + 1]; ++e) v += s->phi[e] * s->lambda_w[s->row_loc[s->dof[e]]];
      mu[q] = v;
    }
    return TL_OK;
  }
  if (s->lumping == TL_BDM_LUMP_NONE) {
    TL_CHECK(woodbury(s, gdot, mu));
    /* one step of iterative refinement on the residual of A (applied
     * matrix-free): Woodbury's cancellation between mbar gdot and its
     * projection costs digits when the masses span decades */
    tl_bdm_system_apply_A(s, mu, s->r_q);
    for (size_t q = 0; q < n_q; ++q) s->r_q[q] = gdot[q] - s->r_q[q];
    TL_CHECK(woodbury(s, s->r_q, s->r_q));
    for (size_t q = 0; q < n_q; ++q) mu[q] += s->r_q[q];
    return TL_OK;
  }
  for (size_t q = 0; q < n_q; ++q) mu[q] = gdot[q] / s->D[q];
  for (int k = 0; k < s->jacobi; ++k) {
    tl_bdm_system_apply_A(s, mu, s->r_q);
    for (size_t q = 0; q < n_q; ++q) mu[q] += (gdot[q] - s->r_q[q]) / s->D[q];
  }
  return TL_OK;
}

void tl_bdm_system_apply(const TlBdmSystem *s, const double *mu, double *v_dof, double *v_q)
{
  double *w = s->w_free;
  gather_free(s, mu, w);
  for (size_t f = 0; f < s->n_free; ++f) {
    TlSparseIndex J = s->free_dofs[f];
    v_dof[J] -= w[f] / s->M[J];
  }
  for (size_t q = 0; q < s->n_q; ++q) v_q[q] += mu[q] / s->m[q];
}

const TlSparseIndex *tl_bdm_system_rows(const TlBdmSystem *s, size_t *n)
{
  int weak = s->constraint == TL_BDM_WEAK;
  if (n) *n = weak ? s->n_rows : 0;
  return weak ? s->rows : NULL;
}

const TlSparseIndex *tl_bdm_system_free_dofs(const TlBdmSystem *s, size_t *n)
{
  if (n) *n = s->n_free;
  return s->free_dofs;
}

const double *tl_bdm_system_weak_multiplier(const TlBdmSystem *s)
{
  return s->constraint == TL_BDM_WEAK ? s->lambda_w : NULL;
}
