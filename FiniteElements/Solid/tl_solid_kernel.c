/* The general element kernel: residual, tangent and stored energy of a
 * block, element by element in colours, for any dimension and material. */
#include "tl_solid_private.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"

/* Displacement gradients H = F - 1 at every stiffness point of element e
 * from its displacements ue.  The 3-D body is inlined with the node count
 * as a constant for the common element types (the loops then unroll: two
 * to three times faster than with a run-time count). */
static inline __attribute__((always_inline)) void gradients_3d(const double *restrict g, int nq, int nn,
                                                               const double *restrict ue, TlMat3 *restrict F)
{
  for (int p = 0; p < nq; ++p, g += 3 * nn) {
    double f[3][3] = {{0}};
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) f[i][j] += ue[3 * a + i] * g[3 * a + j];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F[p].m[i][j] = f[i][j];
  }
}

void tl_solid_deformation_gradients(const SolidBlock *B, int dim, size_t e, const double *ue, TlMat3 *F)
{
  const double *g0 = B->grad + e * (size_t)B->nq * (size_t)B->nn * (size_t)dim;
  if (dim == 3) {
    switch (B->nn) {
    case 8: gradients_3d(g0, B->nq, 8, ue, F); return;
    case 27: gradients_3d(g0, B->nq, 27, ue, F); return;
    case 4: gradients_3d(g0, B->nq, 4, ue, F); return;
    case 10: gradients_3d(g0, B->nq, 10, ue, F); return;
    default: gradients_3d(g0, B->nq, B->nn, ue, F); return;
    }
  }
  for (int p = 0; p < B->nq; ++p) {
    const double *g = g0 + (size_t)p * B->nn * dim;
    TlMat3 f = tl_m3_zero();
    for (int a = 0; a < B->nn; ++a)
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) f.m[i][j] += ue[a * dim + i] * g[a * dim + j];
    F[p] = f;
  }
}

/* Residual alone in 3-D, R_ai = sum_p w_p (F S)_ij dN_a/dX_j, with the node
 * count a constant as above. */
static inline __attribute__((always_inline)) void residual_3d(const double *restrict g, const double *restrict wdet,
                                                              int nq, int nn, const TlMat3 *restrict H,
                                                              const TlMat3 *restrict S, double *restrict fe)
{
  for (int k = 0; k < 3 * nn; ++k) fe[k] = 0.0;
  for (int p = 0; p < nq; ++p, g += 3 * nn) {
    double FS[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double v = S[p].m[i][j];
        for (int k = 0; k < 3; ++k) v += H[p].m[i][k] * S[p].m[k][j];
        FS[i][j] = wdet[p] * v;
      }
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < 3; ++i)
        fe[3 * a + i] += FS[i][0] * g[3 * a] + FS[i][1] * g[3 * a + 1] + FS[i][2] * g[3 * a + 2];
  }
}

static int residual_fixed(const SolidBlock *B, size_t e, const TlMat3 *H, const TlMat3 *S, double *fe)
{
  const double *g = B->grad + e * (size_t)B->nq * (size_t)B->nn * 3;
  const double *w = B->wdet + e * (size_t)B->nq;
  switch (B->nn) {
  case 8: residual_3d(g, w, B->nq, 8, H, S, fe); return 1;
  case 27: residual_3d(g, w, B->nq, 27, H, S, fe); return 1;
  case 4: residual_3d(g, w, B->nq, 4, H, S, fe); return 1;
  case 10: residual_3d(g, w, B->nq, 10, H, S, fe); return 1;
  default: return 0;
  }
}

/* Element residual fe and tangent Ke (either may be NULL) from the
 * displacement gradients H (F = 1 + H), S and D at its stiffness points. */
void tl_solid_element_forces(const SolidBlock *B, int dim, size_t e, const TlMat3 *F, const TlMat3 *S,
                           const double *D, double *fe, double *Ke, double *Bm, double *DB)
{
  /* With a symmetric material tangent only the upper triangle of B^T D B is
   * formed, then mirrored. */
  int sym = B->symmetric;
  int nn = B->nn, nd = B->nd;
  if (fe && !Ke && dim == 3 && residual_fixed(B, e, F, S, fe)) return;
  if (fe) memset(fe, 0, nd * sizeof(double));
  if (Ke) memset(Ke, 0, (size_t)nd * nd * sizeof(double));
  static const int vi[6] = {0, 1, 2, 0, 1, 0}, vj[6] = {0, 1, 2, 1, 2, 2};
  for (int p = 0; p < B->nq; ++p) {
    const double *g = B->grad + ((e * B->nq + p) * nn) * dim;
    double w = B->wdet[e * B->nq + p];
    TlMat3 Fp = F[p];
    for (int i = 0; i < 3; ++i) Fp.m[i][i] += 1.0;
    const TlMat3 *f = &Fp, *s = &S[p];
    if (fe) {
      /* R_ai = F_ik S_kj dN_a/dxi_j */
      double FS[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double v = 0.0;
          for (int k = 0; k < 3; ++k) v += f->m[i][k] * s->m[k][j];
          FS[i][j] = v;
        }
      for (int a = 0; a < nn; ++a)
        for (int i = 0; i < dim; ++i) {
          double v = 0.0;
          for (int j = 0; j < dim; ++j) v += FS[i][j] * g[a * dim + j];
          fe[a * dim + i] += w * v;
        }
    }
    if (!Ke) continue;
    /* B: engineering strain variation of dof (a, i):
     * dE_rs = (F_ir dN_a/dxi_s + F_is dN_a/dxi_r)/2, shear doubled. */
    for (int a = 0; a < nn; ++a) {
      double ga[3] = {0, 0, 0};
      for (int d = 0; d < dim; ++d) ga[d] = g[a * dim + d];
      for (int i = 0; i < dim; ++i) {
        int col = a * dim + i;
        for (int I = 0; I < 6; ++I) {
          int r = vi[I], c = vj[I];
          Bm[I * nd + col] = r == c ? f->m[i][r] * ga[r] : f->m[i][r] * ga[c] + f->m[i][c] * ga[r];
        }
      }
    }
    const double *Dp = D + 36 * p;
    for (int I = 0; I < 6; ++I)
      for (int col = 0; col < nd; ++col) {
        double v = 0.0;
        for (int J = 0; J < 6; ++J) v += Dp[6 * I + J] * Bm[J * nd + col];
        DB[I * nd + col] = v;
      }
    /* Ke += w B^T (D B), rows outer and the contiguous column loop inner
     * so the compiler vectorises it. */
    for (int I = 0; I < 6; ++I)
      for (int r = 0; r < nd; ++r) {
        double b = w * Bm[I * nd + r];
        if (b == 0.0) continue;
        const double *db = DB + I * nd;
        double *krow = Ke + r * nd;
        for (int c = sym ? r : 0; c < nd; ++c) krow[c] += b * db[c];
      }
    /* Geometric stiffness: (dN_a . S dN_b) delta_ik. */
    for (int a = 0; a < nn; ++a)
      for (int b = 0; b < nn; ++b) {
        double v = 0.0;
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) v += g[a * dim + i] * s->m[i][j] * g[b * dim + j];
        v *= w;
        for (int i = 0; i < dim; ++i) Ke[(a * dim + i) * nd + b * dim + i] += v;
      }
  }
  if (Ke && sym)
    for (int r = 0; r < nd; ++r)
      for (int c = 0; c < r; ++c) Ke[r * nd + c] = Ke[c * nd + r];
}

/* ------------------------------------------------ point-by-point path
 *
 * For laws that cost far more than the element arithmetic (a DEM cell per
 * Gauss point): the block's gradients first, then the points evaluated one
 * by one in parallel, the costliest first (LPT: with a dynamic schedule the
 * long tasks start early and the short ones fill the gaps at the end), then
 * the element forces in the colour order of the chunked path. */

TlStatus tl_solid_set_evaluation(TlSolid *s, int mode, int n_threads)
{
  if (mode != TL_SOLID_EVAL_AUTO && mode != TL_SOLID_EVAL_CHUNKED && mode != TL_SOLID_EVAL_POINTS)
    TL_ERROR(TL_ERR_ARG, "solid: evaluation mode %d is none of AUTO (%d), CHUNKED (%d), POINTS (%d)", mode,
             TL_SOLID_EVAL_AUTO, TL_SOLID_EVAL_CHUNKED, TL_SOLID_EVAL_POINTS);
  if (n_threads > 4096) TL_ERROR(TL_ERR_ARG, "solid: %d evaluation threads, at most 4096", n_threads);
  s->eval_mode = mode;
  s->eval_threads = n_threads;
  tl_solid_points_invalidate(s);
  return TL_OK;
}

int tl_solid_points_mode(const TlSolid *s, int b)
{
  if (s->eval_mode == TL_SOLID_EVAL_POINTS) return 1;
  if (s->eval_mode == TL_SOLID_EVAL_CHUNKED) return 0;
  const TlMaterialOps *o = s->blocks[b].material->ops;
  return o->commit != NULL || o->rollback != NULL;
}

void tl_solid_points_invalidate(TlSolid *s)
{
  if (!s->blocks) return;
  for (int b = 0; b < s->mesh->n_blocks; ++b) s->blocks[b].p_valid = 0;
}

void tl_solid_points_free(SolidBlock *B)
{
  tl_free(&B->pH);
  tl_free(&B->pS);
  tl_free(&B->pD);
  tl_free(&B->pcost);
  tl_free(&B->porder);
  tl_free(&B->pu);
}

void tl_solid_get_evaluation_stats(const TlSolid *s, TlSolidEvalStats *stats)
{
  *stats = s->eval_stats;
  stats->threads = s->eval_threads > 0 ? s->eval_threads : s->n_threads;
}

TlStatus tl_solid_point_data(const TlSolid *s, int b, const TlMat3 **F, const TlMat3 **S, const double **cost,
                             const double **state, int *nq)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: point data before tl_solid_setup");
  if (b < 0 || b >= s->mesh->n_blocks) TL_ERROR(TL_ERR_ARG, "solid: no block %d (%d blocks)", b, s->mesh->n_blocks);
  const SolidBlock *B = &s->blocks[b];
  if (F) *F = B->pH;
  if (S) *S = B->pS;
  if (cost) *cost = B->pcost;
  if (state) *state = B->material->state_size ? B->state_old : NULL;
  if (nq) *nq = B->nq;
  return TL_OK;
}

typedef struct {
  double cost;
  size_t index;
} PointCost;

/* Decreasing cost, ties by index: a total order, so the schedule is the
 * same on every run. */
static int by_cost(const void *a, const void *b)
{
  const PointCost *x = a, *y = b;
  if (x->cost != y->cost) return x->cost < y->cost ? 1 : -1;
  return x->index < y->index ? -1 : x->index > y->index;
}

static TlStatus points_allocate(TlSolid *s, SolidBlock *B, size_t np)
{
  if (B->pH) return TL_OK;
  TL_CHECK(tl_calloc(&B->pH, np, sizeof *B->pH));
  TL_CHECK(tl_calloc(&B->pS, np, sizeof *B->pS));
  TL_CHECK(tl_calloc(&B->pD, 36 * np, sizeof *B->pD));
  TL_CHECK(tl_calloc(&B->pcost, np, sizeof *B->pcost));
  TL_CHECK(tl_calloc(&B->porder, np, sizeof *B->porder));
  TL_CHECK(tl_calloc(&B->pu, s->n_nodes * (size_t)s->dim, sizeof *B->pu));
  for (size_t p = 0; p < np; ++p) B->porder[p] = p;
  return TL_OK;
}

/* Records the error of point p with its element and Gauss point. */
static void point_error(const TlElementBlock *blk, int nq, size_t p, TlStatus st, ParallelError *pe)
{
  const size_t e = p / (size_t)nq;
  tl_error_trace(st, __FILE__, __LINE__);
  char msg[900];
  snprintf(msg, sizeof msg, "%s", tl_error_message());
  tl_error_set(st, __FILE__, __LINE__, "block %s element %zu (tag %ld) Gauss point %d: %s", blk->name, e,
               blk->tags ? blk->tags[e] : (long)e, (int)(p % (size_t)nq), msg);
  tl_solid_parallel_error_record(pe, st);
}

/* S and D at every point of block b for u_nodes, unless kept from the last
 * evaluation at the same displacements. */
static TlStatus points_evaluate(TlSolid *s, int b, const double *u_nodes)
{
  const TlElementBlock *blk = &s->mesh->blocks[b];
  SolidBlock *B = &s->blocks[b];
  const int dim = s->dim, nn = B->nn, nq = B->nq;
  const size_t np = blk->n_elements * (size_t)nq, nu = s->n_nodes * (size_t)dim;
  const TlMaterial *mat = B->material;
  const size_t ss = mat->state_size;
  TL_CHECK(points_allocate(s, B, np));
  if (B->p_valid && !memcmp(B->pu, u_nodes, nu * sizeof *u_nodes)) {
    s->eval_stats.reuses++;
    return TL_OK;
  }
  B->p_valid = 0;
  double *ue = s->scratch[0].ue;
  for (size_t e = 0; e < blk->n_elements; ++e) {
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < dim; ++i) ue[a * dim + i] = u_nodes[blk->conn[e * nn + a] * dim + i];
    tl_solid_deformation_gradients(B, dim, e, ue, B->pH + e * nq);
    for (int q = 0; q < nq; ++q) {
      TlMat3 Fq = B->pH[e * nq + q];
      for (int i = 0; i < 3; ++i) Fq.m[i][i] += 1.0;
      double J = tl_m3_det(Fq);
      if (!(J > 0.0))
        TL_ERROR(TL_ERR_NUMERIC,
                 "block %s element %zu (tag %ld): det F = %g at Gauss point %d; the element is inverted "
                 "(displacements too large or unstable run)",
                 blk->name, e, blk->tags ? blk->tags[e] : (long)e, J, q);
    }
  }
  const int nt = s->eval_threads > 0 ? s->eval_threads : s->n_threads;
  /* How the last evaluation says to schedule this one: points of 5 us or
   * more on average (a DEM cell takes milliseconds to seconds) one by one,
   * longest first, each timed; cheap points (Hooke's law, a fraction of a
   * microsecond) in static blocks of consecutive points, untimed, in
   * parallel when there is 1 ms of work in all, else on this thread.  The
   * first evaluation of a block takes the first way to measure.  Every
   * point is the same call on the same data whichever way: the same bits. */
  const double mean = np ? B->p_total / (double)np : 0.0;
  const int lpt = nt > 1 && np > 1 && (B->p_total == 0.0 || mean >= 5e-6);
  const int blocks = !lpt && nt > 1 && B->p_total > 1e-3;
  ParallelError pe = {TL_OK, ""};
  double total = 0.0, worst = 0.0, t0 = omp_get_wtime();
  if (!lpt) {
#pragma omp parallel for schedule(static) if (blocks) num_threads(nt)
    for (long k = 0; k < (long)np; ++k) {
      const size_t p = (size_t)k;
      TlStatus st = tl_material_evaluate_gradient(mat, 1, B->pH + p, ss ? B->state_old + p * ss : NULL,
                                                  ss ? B->state_new + p * ss : NULL, B->pS + p, B->pD + 36 * p, NULL);
      if (st != TL_OK) {
#pragma omp critical(tl_solid_error)
        point_error(blk, nq, p, st, &pe);
      }
    }
    /* The mean cost (CPU time across the threads) stands for every point. */
    total = (omp_get_wtime() - t0) * (blocks ? nt : 1);
    for (size_t p = 0; p < np; ++p) B->pcost[p] = total / (double)np;
    worst = np ? total / (double)np : 0.0;
  } else {
    /* LPT order from the last measured costs. */
    PointCost *pc = NULL;
    TL_CHECK(tl_calloc(&pc, np, sizeof *pc));
    for (size_t p = 0; p < np; ++p) pc[p] = (PointCost){B->pcost[p], p};
    qsort(pc, np, sizeof *pc, by_cost);
    for (size_t p = 0; p < np; ++p) B->porder[p] = pc[p].index;
    tl_free(&pc);
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : total) reduction(max : worst) num_threads(nt)
    for (long k = 0; k < (long)np; ++k) {
      TlStatus seen;
#pragma omp critical(tl_solid_error)
      seen = pe.status;
      if (seen != TL_OK) continue;
      const size_t p = B->porder[k];
      const double tp = omp_get_wtime();
      TlStatus st = tl_material_evaluate_gradient(mat, 1, B->pH + p, ss ? B->state_old + p * ss : NULL,
                                                  ss ? B->state_new + p * ss : NULL, B->pS + p, B->pD + 36 * p, NULL);
      const double c = omp_get_wtime() - tp;
      B->pcost[p] = c;
      total += c;
      worst = c > worst ? c : worst;
      if (st != TL_OK) point_error(blk, nq, p, st, &pe);
    }
  }
  s->eval_stats.t_wall += omp_get_wtime() - t0;
  TL_CHECK(tl_solid_parallel_error_raise(&pe));
  B->p_total = total;
  s->eval_stats.evaluations++;
  s->eval_stats.points += (long)np;
  s->eval_stats.t_points += total;
  s->eval_stats.t_last_max = worst;
  memcpy(B->pu, u_nodes, nu * sizeof *u_nodes);
  B->p_valid = 1;
  return TL_OK;
}

/* Adds element e's forces w->fe into f_nodes and c_u times its matrix w->Ke
 * into K (through the element's pattern positions when indexed); the
 * colouring keeps two threads from touching the same node. */
static inline void scatter_element(const TlSolid *s, const SolidBlock *B, const TlElementBlock *blk, size_t e,
                                   const Scratch *w, double *f_nodes, double c_u, TlSparse *K, int indexed,
                                   ParallelError *pe)
{
  const int dim = s->dim, nn = B->nn;
  if (f_nodes)
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < dim; ++i) f_nodes[blk->conn[e * nn + a] * dim + i] += w->fe[a * dim + i];
  if (K) {
    size_t g = B->offset + e;
    TlStatus sk = indexed ? tl_sparse_add_element_indexed(K, (TlSparseIndex)g, c_u, w->Ke)
                          : tl_sparse_add_element(K, B->nd, s->elem_dofs + s->elem_ptr[g], c_u, w->Ke);
    if (sk != TL_OK) tl_solid_parallel_error_record(pe, sk);
  }
}

static TlStatus block_forces_points(TlSolid *s, int b, const double *u_nodes, double *f_nodes, double c_u,
                                    TlSparse *K)
{
  TL_CHECK(points_evaluate(s, b, u_nodes));
  const TlElementBlock *blk = &s->mesh->blocks[b];
  SolidBlock *B = &s->blocks[b];
  const int dim = s->dim, nq = B->nq;
  const int indexed = K && K->elem_pos_ptr && K->n_elements == (TlSparseIndex)s->n_pattern;
  ParallelError pe = {TL_OK, ""};
  for (int colour = 0; colour < B->n_colours; ++colour) {
    size_t first = B->colour_ptr[colour], count = B->colour_ptr[colour + 1] - first;
    long n_chunks = (long)((count + CHUNK - 1) / CHUNK);
#pragma omp parallel for schedule(dynamic) if (n_chunks >= 4) num_threads(s->n_threads)
    for (long ch = 0; ch < n_chunks; ++ch) {
      Scratch *w = &s->scratch[omp_get_thread_num()];
      size_t c0 = first + (size_t)ch * CHUNK;
      size_t nk = count - (size_t)ch * CHUNK < CHUNK ? count - (size_t)ch * CHUNK : CHUNK;
      for (size_t k = 0; k < nk; ++k) {
        size_t e = B->colour_elements[c0 + k];
        tl_solid_element_forces(B, dim, e, B->pH + e * nq, B->pS + e * nq, K ? B->pD + 36 * e * nq : NULL,
                                f_nodes ? w->fe : NULL, K ? w->Ke : NULL, w->B, w->DB);
        scatter_element(s, B, blk, e, w, f_nodes, c_u, K, indexed, &pe);
      }
    }
  }
  TL_CHECK(tl_solid_parallel_error_raise(&pe));
  return TL_OK;
}

TlStatus tl_solid_block_forces(TlSolid *s, int b, const double *u_nodes, double *f_nodes, double c_u,
                               TlSparse *K, double *W)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: block forces before tl_solid_setup");
  if ((f_nodes || K) && !W && tl_solid_points_mode(s, b))
    return block_forces_points(s, b, u_nodes, f_nodes, c_u, K);
  if (f_nodes && !K && !W && s->dim == 3 && s->blocks[b].material->state_size == 0)
    return tl_solid_block_residual(s, b, u_nodes, f_nodes);
  const TlElementBlock *blk = &s->mesh->blocks[b];
  SolidBlock *B = &s->blocks[b];
  int dim = s->dim, nn = B->nn, nq = B->nq;
  const TlMaterial *mat = B->material;
  size_t ss = mat->state_size;
  int indexed = K && K->elem_pos_ptr && K->n_elements == (TlSparseIndex)s->n_pattern;
  ParallelError pe = {TL_OK, ""};
  double energy = 0.0;
  for (int colour = 0; colour < B->n_colours; ++colour) {
    size_t first = B->colour_ptr[colour], count = B->colour_ptr[colour + 1] - first;
    long n_chunks = (long)((count + CHUNK - 1) / CHUNK);
/* Threads only where a colour holds several chunks: below that the
     * fork and barrier cost more than the work.  Never more threads than
     * the scratch areas sized at setup (the thread count may have been
     * raised since). */
#pragma omp parallel for schedule(dynamic) reduction(+ : energy) if (n_chunks >= 4) num_threads(s->n_threads)
    for (long ch = 0; ch < n_chunks; ++ch) {
      TlStatus seen;
#pragma omp critical(tl_solid_error)
      seen = pe.status;
      if (seen != TL_OK) continue;
      Scratch *w = &s->scratch[omp_get_thread_num()];
      size_t c0 = first + (size_t)ch * CHUNK;
      size_t nk = count - (size_t)ch * CHUNK < CHUNK ? count - (size_t)ch * CHUNK : CHUNK;
      for (size_t k = 0; k < nk; ++k) {
        size_t e = B->colour_elements[c0 + k];
        for (int a = 0; a < nn; ++a)
          for (int i = 0; i < dim; ++i) w->ue[a * dim + i] = u_nodes[blk->conn[e * nn + a] * dim + i];
        tl_solid_deformation_gradients(B, dim, e, w->ue, w->F + k * nq);
        for (int q = 0, bad = 0; q < nq && !bad; ++q) {
          TlMat3 Fq = w->F[k * nq + q];
          for (int i = 0; i < 3; ++i) Fq.m[i][i] += 1.0;
          double J = tl_m3_det(Fq);
          if (!(J > 0.0)) {
            TlStatus se = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__,
                                       "block %s element %zu (tag %ld): det F = %g at Gauss point %d; the "
                                       "element is inverted (displacements too large or unstable run)",
                                       blk->name, e, blk->tags ? blk->tags[e] : (long)e, J, q);
            tl_solid_parallel_error_record(&pe, se);
            bad = 1;
          }
        }
        if (ss) memcpy(w->state_old + k * nq * ss, B->state_old + e * nq * ss, nq * ss * sizeof(double));
      }
#pragma omp critical(tl_solid_error)
      seen = pe.status;
      if (seen != TL_OK) continue;
      TlStatus st = tl_material_evaluate_gradient(mat, nk * nq, w->F, ss ? w->state_old : NULL,
                                         ss ? w->state_new : NULL, w->S, K ? w->D : NULL,
                                         W ? w->W : NULL);
      if (st != TL_OK) {
        size_t e = B->colour_elements[c0];
        tl_error_trace(st, __FILE__, __LINE__);
        char msg[900];
        snprintf(msg, sizeof msg, "%s", tl_error_message());
        tl_error_set(st, __FILE__, __LINE__, "block %s, elements from %zu (chunk of %zu, %d points each): %s",
                     blk->name, e, nk, nq, msg);
        tl_solid_parallel_error_record(&pe, st);
        continue;
      }
      for (size_t k = 0; k < nk; ++k) {
        size_t e = B->colour_elements[c0 + k];
        if (ss) memcpy(B->state_new + e * nq * ss, w->state_new + k * nq * ss, nq * ss * sizeof(double));
        if (W)
          for (int p = 0; p < nq; ++p) energy += B->wdet[e * nq + p] * w->W[k * nq + p];
        if (!f_nodes && !K) continue;
        tl_solid_element_forces(B, dim, e, w->F + k * nq, w->S + k * nq, K ? w->D + 36 * k * nq : NULL,
                       f_nodes ? w->fe : NULL, K ? w->Ke : NULL, w->B, w->DB);
        scatter_element(s, B, blk, e, w, f_nodes, c_u, K, indexed, &pe);
      }
    }
  }
  TL_CHECK(tl_solid_parallel_error_raise(&pe));
  if (W) *W += energy;
  return TL_OK;
}

TlStatus tl_solid_element_matrices(TlSolid *s, int b, size_t e, const double *ue, double *fe, double *Ke,
                                   double *Me)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: element matrices before tl_solid_setup");
  if (b < 0 || b >= s->mesh->n_blocks || e >= s->mesh->blocks[b].n_elements)
    TL_ERROR(TL_ERR_ARG, "solid: no element %zu in block %d", e, b);
  const SolidBlock *B = &s->blocks[b];
  Scratch *w = &s->scratch[0];
  size_t ss = B->material->state_size;
  tl_solid_deformation_gradients(B, s->dim, e, ue, w->F);
  if (ss) memcpy(w->state_old, B->state_old + e * B->nq * ss, B->nq * ss * sizeof(double));
  TL_CHECK(tl_material_evaluate_gradient(B->material, B->nq, w->F, ss ? w->state_old : NULL, ss ? w->state_new : NULL,
                                w->S, w->D, NULL));
  if (fe || Ke) tl_solid_element_forces(B, s->dim, e, w->F, w->S, w->D, fe, Ke, w->B, w->DB);
  if (Me) {
    int nn = B->nn, nd = B->nd, dim = s->dim;
    double Mab[TL_ELEMENT_MAX_NODES * TL_ELEMENT_MAX_NODES];
    tl_solid_element_mass(s, b, e, Mab);
    memset(Me, 0, (size_t)nd * nd * sizeof(double));
    for (int a = 0; a < nn; ++a)
      for (int q = 0; q < nn; ++q)
        for (int i = 0; i < dim; ++i) Me[(a * dim + i) * nd + q * dim + i] = Mab[a * nn + q];
  }
  return TL_OK;
}
