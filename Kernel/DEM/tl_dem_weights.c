/* Weights of the DEM equations in a volume coupling (seeds/001 Eqs. 24-25). */
#include "tl_dem_private.h"

#include <math.h>
#include "tl_memory.h"

/* 1 / (w m) and 1 / (w I) from the particle weights (also after particles
 * came or went between evaluations; capacity kept, so the arrays stay put
 * within a step). */
TlStatus tl_dem_weighted_inverses(TlDem *d)
{
  TlParticles *P = d->P;
  const size_t n = P->n;
  TL_CHECK(tl_particles_enable_weights(P));
  TL_CHECK(tl_array_reserve(&d->im_w, &d->im_w_cap, P->capacity ? P->capacity : 1, sizeof *d->im_w));
  for (size_t i = 0; i < n; ++i) d->im_w[i] = P->inv_mass[i] / P->weight[i];
  if (P->inv_inertia) {
    TL_CHECK(tl_array_reserve(&d->ii_w, &d->ii_w_cap, P->capacity ? P->capacity : 1, sizeof *d->ii_w));
    for (size_t i = 0; i < n; ++i) d->ii_w[i] = P->inv_inertia[i] / P->weight[i];
  }
  return TL_OK;
}

/* Weights at the particle centres (seeds/001 Eq. 25) and 1 / (w m) for
 * the kicks. */
TlStatus tl_dem_particle_weights(TlDem *d)
{
  TlParticles *P = d->P;
  const size_t n = P->n;
  TL_CHECK(tl_particles_enable_weights(P));
  TL_CHECK(d->weight_fn(d->weight_ctx, n, P->x, P->weight));
  for (size_t i = 0; i < n; ++i) {
    double w = P->weight[i];
    if (!(w > 0.0) || !isfinite(w))
      TL_ERROR(TL_ERR_NUMERIC, "step %ld: particle id %lld at (%g, %g, %g) has weight %g; a weighted particle "
               "needs 0 < w (it has left the particle side of the overlap)", d->steps, (long long)P->id[i],
               P->x[i].x, P->x[i].y, P->x[i].z, w);
  }
  return tl_dem_weighted_inverses(d);
}

/* Weights of the contacts of a list at their contact points (seeds/001
 * Eq. 24): x_i + n (r_i - delta/2), on the line of centres. */
TlStatus tl_dem_contact_weights(TlDem *d, const TlContactList *L, double **cw, size_t *cap)
{
  const TlParticles *P = d->P;
  const size_t n = L->n;
  TL_CHECK(tl_array_reserve(cw, cap, n ? n : 1, sizeof **cw));
  TL_CHECK(tl_array_reserve(&d->cpoint, &d->cpoint_cap, n ? n : 1, sizeof *d->cpoint));
  for (size_t k = 0; k < n; ++k) {
    const uint32_t i = L->i[k], j = L->j[k];
    TlVec3 b = d->domain.any_periodic ? tl_domain_branch(&d->domain, P->x[i], P->x[j]) : tl_v3_sub(P->x[j], P->x[i]);
    double dist = tl_v3_norm(b), ri = P->radius[i];
    double li = ri - 0.5 * (ri + P->radius[j] - dist);
    d->cpoint[k] = dist > 0.0 ? tl_v3_axpy(P->x[i], li / dist, b) : P->x[i];
  }
  TL_CHECK(d->weight_fn(d->weight_ctx, n, d->cpoint, *cw));
  for (size_t k = 0; k < n; ++k)
    if (!((*cw)[k] >= 0.0) || !isfinite((*cw)[k]))
      TL_ERROR(TL_ERR_NUMERIC, "step %ld: contact of particles id %lld and id %lld at (%g, %g, %g) has weight %g; "
               "weights must be finite and >= 0", d->steps, (long long)P->id[L->i[k]], (long long)P->id[L->j[k]],
               d->cpoint[k].x, d->cpoint[k].y, d->cpoint[k].z, (*cw)[k]);
  return TL_OK;
}
