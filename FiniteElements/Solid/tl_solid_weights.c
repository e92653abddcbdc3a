/* Weights of a block's equations (seeds/001 Eq. 26). */
#include "tl_solid_private.h"

#include <math.h>
#include <string.h>

#include "tl_memory.h"

static TlStatus check_weights(const TlSolid *s, int b, const char *where, size_t n, int per, const double *w)
{
  for (size_t k = 0; k < n; ++k)
    if (!(w[k] >= 0.0) || !isfinite(w[k]))
      TL_ERROR(TL_ERR_ARG, "solid: block %s weight %g at element %zu, %s point %d: weights must be finite and >= 0",
               s->mesh->blocks[b].name, w[k], k / (size_t)per, where, (int)(k % (size_t)per));
  return TL_OK;
}

static TlStatus weights_block(TlSolid *s, int b, const char *what)
{
  TL_CHECK(tl_solid_not_after_setup(s, what));
  if (b < 0 || b >= s->mesh->n_blocks) TL_ERROR(TL_ERR_ARG, "solid: block %d outside [0, %d)", b, s->mesh->n_blocks);
  SolidBlock *B = &s->blocks[b];
  tl_free(&B->pw);
  tl_free(&B->pw_mass);
  tl_free(&B->w_nodes);
  return TL_OK;
}

TlStatus tl_solid_weight_points(const TlSolid *s, int b, int *nq, int *nq_mass)
{
  if (b < 0 || b >= s->mesh->n_blocks) TL_ERROR(TL_ERR_ARG, "solid: block %d outside [0, %d)", b, s->mesh->n_blocks);
  const TlElementType *t = s->mesh->blocks[b].type;
  TlQuadrature q;
  TL_CHECK(tl_element_quadrature(t, t->order_stiffness, &q));
  if (nq) *nq = q.n;
  TL_CHECK(tl_element_quadrature(t, t->order_mass, &q));
  if (nq_mass) *nq_mass = q.n;
  return TL_OK;
}

TlStatus tl_solid_set_point_weights(TlSolid *s, int b, const double *w, const double *w_mass)
{
  TL_CHECK(weights_block(s, b, "set_point_weights"));
  if (!w && !w_mass) return TL_OK;
  if (!w || !w_mass)
    TL_ERROR(TL_ERR_ARG, "solid: block %s needs weights at both the stiffness and the mass points (or neither)",
             s->mesh->blocks[b].name);
  int nq, nqm;
  TL_CHECK(tl_solid_weight_points(s, b, &nq, &nqm));
  size_t ne = s->mesh->blocks[b].n_elements;
  TL_CHECK(check_weights(s, b, "stiffness", ne * nq, nq, w));
  TL_CHECK(check_weights(s, b, "mass", ne * nqm, nqm, w_mass));
  SolidBlock *B = &s->blocks[b];
  TL_CHECK(tl_calloc(&B->pw, ne ? ne * nq : 1, sizeof(double)));
  TL_CHECK(tl_calloc(&B->pw_mass, ne ? ne * nqm : 1, sizeof(double)));
  memcpy(B->pw, w, ne * nq * sizeof(double));
  memcpy(B->pw_mass, w_mass, ne * nqm * sizeof(double));
  return TL_OK;
}

TlStatus tl_solid_set_node_weights(TlSolid *s, int b, const double *w_nodes)
{
  TL_CHECK(weights_block(s, b, "set_node_weights"));
  if (!w_nodes) return TL_OK;
  for (size_t i = 0; i < s->n_nodes; ++i)
    if (!(w_nodes[i] >= 0.0) || !isfinite(w_nodes[i]))
      TL_ERROR(TL_ERR_ARG, "solid: block %s nodal weight %g at node %zu: weights must be finite and >= 0",
               s->mesh->blocks[b].name, w_nodes[i], i);
  SolidBlock *B = &s->blocks[b];
  TL_CHECK(tl_calloc(&B->w_nodes, s->n_nodes ? s->n_nodes : 1, sizeof(double)));
  memcpy(B->w_nodes, w_nodes, s->n_nodes * sizeof(double));
  return TL_OK;
}

TlStatus tl_solid_set_lumped_mass_weights(TlSolid *s, const double *w_nodes)
{
  TL_CHECK(tl_solid_not_after_setup(s, "set_lumped_mass_weights"));
  tl_free(&s->lumped_weights);
  if (!w_nodes) return TL_OK;
  for (size_t i = 0; i < s->n_nodes; ++i)
    if (!(w_nodes[i] > 0.0) || !isfinite(w_nodes[i]))
      TL_ERROR(TL_ERR_ARG, "solid: lumped-mass weight %g at node %zu: weights of the lumped mass must be finite and > 0",
               w_nodes[i], i);
  TL_CHECK(tl_calloc(&s->lumped_weights, s->n_nodes ? s->n_nodes : 1, sizeof(double)));
  memcpy(s->lumped_weights, w_nodes, s->n_nodes * sizeof(double));
  return TL_OK;
}

/* The nodal weight field at the stiffness points (shape values Nq) and the
 * mass points (B->Nm), at setup. */
TlStatus tl_solid_interpolate_weights(TlSolid *s, int b, const double *Nq)
{
  const TlElementBlock *blk = &s->mesh->blocks[b];
  SolidBlock *B = &s->blocks[b];
  int nn = B->nn, nq = B->q.n, nqm = B->qm.n;
  size_t ne = blk->n_elements ? blk->n_elements : 1;
  TL_CHECK(tl_calloc(&B->pw, ne * nq, sizeof(double)));
  TL_CHECK(tl_calloc(&B->pw_mass, ne * nqm, sizeof(double)));
  for (size_t e = 0; e < blk->n_elements; ++e)
    for (int pass = 0; pass < 2; ++pass) {
      int np = pass ? nqm : nq;
      const double *N = pass ? B->Nm : Nq;
      double *out = (pass ? B->pw_mass : B->pw) + e * np;
      for (int p = 0; p < np; ++p) {
        double v = 0.0;
        for (int a = 0; a < nn; ++a) v += N[p * nn + a] * B->w_nodes[blk->conn[e * nn + a]];
        /* shape functions that dip below zero (quadratic types) must not
         * make a weight of a non-negative field negative */
        out[p] = v > 0.0 ? v : 0.0;
      }
    }
  return TL_OK;
}
