/* Post-processing of a solid: stresses, energies, work, reactions, mass. */
#include "tl_solid_private.h"

#include <string.h>

#include "tl_memory.h"

double tl_solid_total_mass(const TlSolid *s)
{
  double m = 0.0;
  for (size_t i = 0; i < s->n_nodes; ++i) m += s->lumped_nodes[i * s->dim];
  return m;
}

/* Element e of block b at u_nodes: the displacement gradients F - I
 * (w->F) and second Piola-Kirchhoff stresses (w->S) at its Gauss points,
 * from the state of the last commit (left as it is). */
static TlStatus element_points(TlSolid *s, int b, size_t e, const double *u_nodes, Scratch *w)
{
  const TlElementBlock *blk = &s->mesh->blocks[b];
  const SolidBlock *B = &s->blocks[b];
  int dim = s->dim;
  for (int a = 0; a < B->nn; ++a)
    for (int i = 0; i < dim; ++i) w->ue[a * dim + i] = u_nodes[blk->conn[e * B->nn + a] * dim + i];
  tl_solid_deformation_gradients(B, dim, e, w->ue, w->F);
  size_t ss = B->material->state_size;
  if (ss) memcpy(w->state_old, B->state_old + e * B->nq * ss, B->nq * ss * sizeof(double));
  TL_CHECK(tl_material_evaluate_gradient(B->material, B->nq, w->F, ss ? w->state_old : NULL,
                                         ss ? w->state_new : NULL, w->S, NULL, NULL));
  return TL_OK;
}

TlStatus tl_solid_gauss_stress(TlSolid *s, int b, size_t e, int q, const double *u_nodes, TlMat3 *F, TlMat3 *S)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: stress before tl_solid_setup");
  const SolidBlock *B = &s->blocks[b];
  if (q < 0 || q >= B->nq) TL_ERROR(TL_ERR_ARG, "solid: Gauss point %d outside [0, %d)", q, B->nq);
  Scratch *w = &s->scratch[0];
  TL_CHECK(element_points(s, b, e, u_nodes, w));
  *F = w->F[q];
  for (int i = 0; i < 3; ++i) F->m[i][i] += 1.0;
  *S = w->S[q];
  return TL_OK;
}

TlStatus tl_solid_element_stress(TlSolid *s, int b, size_t e, const double *u_nodes, TlMat3 *S_avg,
                                 TlMat3 *sigma_avg)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: stress before tl_solid_setup");
  if (b < 0 || b >= s->mesh->n_blocks || e >= s->mesh->blocks[b].n_elements)
    TL_ERROR(TL_ERR_ARG, "solid: no element %zu in block %d", e, b);
  const SolidBlock *B = &s->blocks[b];
  Scratch *w = &s->scratch[0];
  TL_CHECK(element_points(s, b, e, u_nodes, w));
  TlMat3 Ssum = tl_m3_zero(), csum = tl_m3_zero();
  double V = 0.0;
  for (int p = 0; p < B->nq; ++p) {
    double wv = (B->wdet_plain ? B->wdet_plain : B->wdet)[e * B->nq + p];
    TlMat3 F = w->F[p];
    for (int i = 0; i < 3; ++i) F.m[i][i] += 1.0;
    TlMat3 sigma = tl_m3_scale(tl_m3_mul(tl_m3_mul(F, w->S[p]), tl_m3_transpose(F)), 1.0 / tl_m3_det(F));
    Ssum = tl_m3_add(Ssum, tl_m3_scale(w->S[p], wv));
    csum = tl_m3_add(csum, tl_m3_scale(sigma, wv));
    V += wv;
  }
  if (S_avg) *S_avg = tl_m3_scale(Ssum, 1.0 / V);
  if (sigma_avg) *sigma_avg = tl_m3_scale(csum, 1.0 / V);
  return TL_OK;
}

/* out_nodes = M a_nodes with the consistent mass, element by element. */
static void mass_times(const TlSolid *s, const double *a_nodes, double *out_nodes)
{
  int dim = s->dim;
  double Mab[TL_ELEMENT_MAX_NODES * TL_ELEMENT_MAX_NODES];
  memset(out_nodes, 0, s->n_nodes * dim * sizeof(double));
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &s->mesh->blocks[b];
    int nn = blk->type->n_nodes;
    for (size_t e = 0; e < blk->n_elements; ++e) {
      tl_solid_element_mass(s, b, e, Mab);
      for (int a = 0; a < nn; ++a)
        for (int q = 0; q < nn; ++q)
          for (int i = 0; i < dim; ++i)
            out_nodes[blk->conn[e * nn + a] * dim + i] += Mab[a * nn + q] * a_nodes[blk->conn[e * nn + q] * dim + i];
    }
  }
}

TlStatus tl_solid_kinetic_energy(TlSolid *s, const double *v, double *K)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: kinetic energy before tl_solid_setup");
  tl_solid_dofs_to_nodes(s, v, s->un);
  mass_times(s, s->un, s->gn);
  double k = 0.0;
  for (size_t i = 0; i < s->n_nodes * s->dim; ++i) k += s->un[i] * s->gn[i];
  *K = 0.5 * k;
  return TL_OK;
}

TlStatus tl_solid_work_increment(TlSolid *s, double t0, const double *u0, double t1, const double *u1, double *dW)
{
  size_t nc = s->n_nodes * s->dim;
  double w = 0.0;
  TL_CHECK(tl_solid_external_nodes(s, t0, u0, s->fn));
  double *d = s->gn;
  tl_solid_dofs_to_nodes(s, u1, d);
  tl_solid_dofs_to_nodes(s, u0, s->un);
  for (size_t i = 0; i < nc; ++i) d[i] -= s->un[i];
  for (size_t i = 0; i < nc; ++i) w += 0.5 * s->fn[i] * d[i];
  TL_CHECK(tl_solid_external_nodes(s, t1, u1, s->fn));
  tl_solid_dofs_to_nodes(s, u1, d);
  tl_solid_dofs_to_nodes(s, u0, s->un);
  for (size_t i = 0; i < nc; ++i) w += 0.5 * s->fn[i] * (d[i] - s->un[i]);
  *dW = w;
  return TL_OK;
}

TlStatus tl_solid_reactions(TlSolid *s, double t, const double *u, const double *a, double *R)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: reactions before tl_solid_setup");
  size_t nc = s->n_nodes * s->dim;
  TL_CHECK(tl_solid_internal_nodes(s, t, u, R, 0.0, NULL));
  TL_CHECK(tl_solid_external_nodes(s, t, u, s->fn));
  for (size_t i = 0; i < nc; ++i) R[i] -= s->fn[i];
  if (a) {
    double *an = NULL, *ma = NULL;
    TL_CHECK(tl_calloc(&an, nc, sizeof(double)));
    TlStatus st = tl_calloc(&ma, nc, sizeof(double));
    if (st == TL_OK) {
      tl_solid_dofs_to_nodes(s, a, an);
      mass_times(s, an, ma);
      for (size_t i = 0; i < nc; ++i) R[i] += ma[i];
    }
    tl_free(&an);
    tl_free(&ma);
    if (st != TL_OK) return tl_error_trace(st, __FILE__, __LINE__);
  }
  for (size_t i = 0; i < nc; ++i)
    if (!s->constraint[i]) R[i] = 0.0;
  return TL_OK;
}
