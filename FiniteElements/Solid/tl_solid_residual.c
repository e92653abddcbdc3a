/* The component-major residual path of the general kernel. */
#include "tl_solid_private.h"

#include <omp.h>
#include <stdio.h>

/* ------------------------------------------------- residual-only path
 *
 * The residual of a 3-D block whose law keeps no state is the hot path of
 * implicit dynamics (every Newton iteration): chunks of elements run
 * gradients -> stress (one material call per chunk) -> nodal forces, with
 * the loops over an element's points innermost on contiguous data
 * (grad_t), where the compiler unrolls and vectorises them.  Elements are
 * taken in colour order, so the forces accumulate in the same order
 * whether the chunks of a colour run on one thread or several. */

/* The chunk's points are stored component-major (point p of element k at
 * k nq + p, stride ld = the chunk's points): H_ij in 9 arrays, S in 6
 * (Voigt order), so that every loop over points runs on contiguous data. */
static const int voigt[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};

/* H_p = sum_a ue_a (x) dN_a/dX at the nq points of one element. */
static inline __attribute__((always_inline)) void gradients_t(const double *restrict gt, int nq, int nn,
                                                              const double *restrict ue, double *restrict H,
                                                              size_t ld)
{
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double acc[TL_QUADRATURE_MAX];
      for (int p = 0; p < nq; ++p) acc[p] = 0.0;
      for (int a = 0; a < nn; ++a) {
        const double u = ue[3 * a + i], *g = gt + (3 * a + j) * nq;
        for (int p = 0; p < nq; ++p) acc[p] += u * g[p];
      }
      for (int p = 0; p < nq; ++p) H[(3 * i + j) * ld + p] = acc[p];
    }
}

/* R_ai = sum_p w_p ((1 + H_p) S_p)_ij dN_a/dX_j of one element; the sums
 * run over (p, j) with the element's nodes in the vector lanes (gn is
 * node-innermost). */
static inline __attribute__((always_inline)) void residual_t(const double *restrict gn, const double *restrict wdet,
                                                             int nq, int nn, const double *restrict H,
                                                             const double *restrict S, size_t ld,
                                                             double *restrict fe)
{
  double P[9][TL_QUADRATURE_MAX]; /* w (1 + H) S */
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double *h0 = H + (3 * i) * ld, *h1 = h0 + ld, *h2 = h1 + ld, *sij = S + voigt[i][j] * ld,
                   *s0j = S + voigt[0][j] * ld, *s1j = S + voigt[1][j] * ld, *s2j = S + voigt[2][j] * ld;
      for (int p = 0; p < nq; ++p)
        P[3 * i + j][p] = wdet[p] * (sij[p] + h0[p] * s0j[p] + h1[p] * s1j[p] + h2[p] * s2j[p]);
    }
  double f0[TL_ELEMENT_MAX_NODES], f1[TL_ELEMENT_MAX_NODES], f2[TL_ELEMENT_MAX_NODES];
  for (int a = 0; a < nn; ++a) f0[a] = f1[a] = f2[a] = 0.0;
  for (int p = 0; p < nq; ++p)
    for (int j = 0; j < 3; ++j) {
      const double *g = gn + ((size_t)j * nq + p) * nn;
      const double p0 = P[j][p], p1 = P[3 + j][p], p2 = P[6 + j][p];
      for (int a = 0; a < nn; ++a) {
        f0[a] += p0 * g[a];
        f1[a] += p1 * g[a];
        f2[a] += p2 * g[a];
      }
    }
  for (int a = 0; a < nn; ++a) fe[3 * a] = f0[a], fe[3 * a + 1] = f1[a], fe[3 * a + 2] = f2[a];
}

/* Gradients of the nk elements, then nodal forces; the common element
 * types get copies with their sizes known to the compiler. */
static inline __attribute__((always_inline)) void chunk_gradients(const SolidBlock *B, const TlElementBlock *blk,
                                                                  const size_t *elements, size_t nk, int nq, int nn,
                                                                  const double *u_nodes, double *ue, double *H,
                                                                  size_t ld)
{
  for (size_t k = 0; k < nk; ++k) {
    const size_t *conn = blk->conn + elements[k] * nn;
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < 3; ++i) ue[3 * a + i] = u_nodes[conn[a] * 3 + i];
    gradients_t(B->grad_t + elements[k] * (size_t)nn * 3 * (size_t)nq, nq, nn, ue, H + k * nq, ld);
  }
}

static inline __attribute__((always_inline)) void chunk_forces(const SolidBlock *B, const TlElementBlock *blk,
                                                               const size_t *elements, size_t nk, int nq, int nn,
                                                               const double *H, const double *S, size_t ld,
                                                               double *fe, double *f_nodes)
{
  for (size_t k = 0; k < nk; ++k) {
    const size_t e = elements[k];
    residual_t(B->grad_n + e * (size_t)nn * 3 * (size_t)nq, B->wdet + e * (size_t)nq, nq, nn, H + k * nq,
               S + k * nq, ld, fe);
    const size_t *conn = blk->conn + e * nn;
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < 3; ++i) f_nodes[conn[a] * 3 + i] += fe[3 * a + i];
  }
}

TL_VECTOR_CLONES
static void kernel_gradients(const SolidBlock *B, const TlElementBlock *blk, const size_t *elements, size_t nk,
                             const double *u_nodes, double *ue, double *H, size_t ld)
{
  if (B->nn == 8 && B->nq == 8) chunk_gradients(B, blk, elements, nk, 8, 8, u_nodes, ue, H, ld);
  else if (B->nn == 27 && B->nq == 27) chunk_gradients(B, blk, elements, nk, 27, 27, u_nodes, ue, H, ld);
  else if (B->nn == 10 && B->nq == 4) chunk_gradients(B, blk, elements, nk, 4, 10, u_nodes, ue, H, ld);
  else if (B->nn == 4 && B->nq == 1) chunk_gradients(B, blk, elements, nk, 1, 4, u_nodes, ue, H, ld);
  else chunk_gradients(B, blk, elements, nk, B->nq, B->nn, u_nodes, ue, H, ld);
}

TL_VECTOR_CLONES
static void kernel_forces(const SolidBlock *B, const TlElementBlock *blk, const size_t *elements, size_t nk,
                          const double *H, const double *S, size_t ld, double *fe, double *f_nodes)
{
  if (B->nn == 8 && B->nq == 8) chunk_forces(B, blk, elements, nk, 8, 8, H, S, ld, fe, f_nodes);
  else if (B->nn == 27 && B->nq == 27) chunk_forces(B, blk, elements, nk, 27, 27, H, S, ld, fe, f_nodes);
  else if (B->nn == 10 && B->nq == 4) chunk_forces(B, blk, elements, nk, 4, 10, H, S, ld, fe, f_nodes);
  else if (B->nn == 4 && B->nq == 1) chunk_forces(B, blk, elements, nk, 1, 4, H, S, ld, fe, f_nodes);
  else chunk_forces(B, blk, elements, nk, B->nq, B->nn, H, S, ld, fe, f_nodes);
}

/* Flags points with det(1 + H) <= 0 (or NaN). */
TL_VECTOR_CLONES
static int any_inverted(const double *restrict H, size_t np, size_t ld)
{
  int bad = 0;
  for (size_t p = 0; p < np; ++p) {
    const double h00 = H[p], h01 = H[ld + p], h02 = H[2 * ld + p], h10 = H[3 * ld + p], h12 = H[5 * ld + p],
                 h20 = H[6 * ld + p], h21 = H[7 * ld + p];
    const double a00 = 1.0 + h00, a11 = 1.0 + H[4 * ld + p], a22 = 1.0 + H[8 * ld + p];
    const double J = a00 * (a11 * a22 - h12 * h21) - h01 * (h10 * a22 - h12 * h20) + h02 * (h10 * h21 - a11 * h20);
    bad |= !(J > 0.0);
  }
  return bad;
}

/* Residual of the nk elements `elements` (disjoint nodes unless run
 * serially) added into f_nodes. */
static TlStatus residual_chunk(const TlSolid *s, int b, const size_t *elements, size_t nk, const double *u_nodes,
                               double *f_nodes, Scratch *w)
{
  const TlElementBlock *blk = &s->mesh->blocks[b];
  const SolidBlock *B = &s->blocks[b];
  const int nq = B->nq;
  const size_t np = nk * (size_t)nq, ld = np;
  double *H = w->Hsoa, *S = w->Ssoa;
  kernel_gradients(B, blk, elements, nk, u_nodes, w->ue, H, ld);
  if (any_inverted(H, np, ld))
    for (size_t p = 0; p < np; ++p) {
      TlMat3 Fq;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) Fq.m[i][j] = (i == j ? 1.0 : 0.0) + H[(3 * i + j) * ld + p];
      double J = tl_m3_det(Fq);
      if (!(J > 0.0)) {
        size_t e = elements[p / (size_t)nq];
        TL_ERROR(TL_ERR_NUMERIC,
                 "block %s element %zu (tag %ld): det F = %g at Gauss point %d; the element is inverted "
                 "(displacements too large or unstable run)",
                 blk->name, e, blk->tags ? blk->tags[e] : (long)e, J, (int)(p % (size_t)nq));
      }
    }
  TlStatus st = tl_material_stress_soa(B->material, np, H, S, ld);
  if (st != TL_OK) {
    tl_error_trace(st, __FILE__, __LINE__);
    char msg[900];
    snprintf(msg, sizeof msg, "%s", tl_error_message());
    TL_ERROR(st, "block %s, elements from %zu (chunk of %zu, %d points each): %s", blk->name, elements[0], nk, nq,
             msg);
  }
  kernel_forces(B, blk, elements, nk, H, S, ld, w->fe, f_nodes);
  return TL_OK;
}

TlStatus tl_solid_block_residual(TlSolid *s, int b, const double *u_nodes, double *f_nodes)
{
  const SolidBlock *B = &s->blocks[b];
  int parallel = 0;
  for (int c = 0; c < B->n_colours && s->n_threads > 1; ++c)
    parallel |= B->colour_ptr[c + 1] - B->colour_ptr[c] >= 4 * (size_t)CHUNK;
  if (!parallel) {
    /* One thread: chunks may span colours (same accumulation order). */
    size_t total = B->colour_ptr[B->n_colours];
    for (size_t c0 = 0; c0 < total; c0 += CHUNK)
      TL_CHECK(residual_chunk(s, b, B->colour_elements + c0, total - c0 < CHUNK ? total - c0 : CHUNK, u_nodes,
                              f_nodes, &s->scratch[0]));
    return TL_OK;
  }
  ParallelError pe = {TL_OK, ""};
  for (int colour = 0; colour < B->n_colours; ++colour) {
    size_t first = B->colour_ptr[colour], count = B->colour_ptr[colour + 1] - first;
    long n_chunks = (long)((count + CHUNK - 1) / CHUNK);
#pragma omp parallel for schedule(dynamic) if (n_chunks >= 4) num_threads(s->n_threads)
    for (long ch = 0; ch < n_chunks; ++ch) {
      TlStatus seen;
#pragma omp critical(tl_solid_error)
      seen = pe.status;
      if (seen != TL_OK) continue;
      size_t c0 = first + (size_t)ch * CHUNK, nk = count - (size_t)ch * CHUNK < CHUNK ? count - (size_t)ch * CHUNK : CHUNK;
      TlStatus st = residual_chunk(s, b, B->colour_elements + c0, nk, u_nodes, f_nodes, &s->scratch[omp_get_thread_num()]);
      if (st != TL_OK) tl_solid_parallel_error_record(&pe, st);
    }
    TL_CHECK(tl_solid_parallel_error_raise(&pe));
  }
  return TL_OK;
}
