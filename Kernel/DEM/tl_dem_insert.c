/* Insertion and removal of particles in a running DEM world. */
#include "tl_dem_private.h"

#include "tl_memory.h"

TlStatus tl_dem_add_particle(TlDem *d, TlVec3 x, TlVec3 v, double radius, int species, size_t *index)
{
  TL_CHECK(tl_particles_add(d->P, x, v, radius, species, index));
  if (d->setup_done) {
    double r = radius;
    if (2.0 * r + d->skin > d->max_cut) d->max_cut = 2.0 * r + d->skin;
    if (r < d->r_min) d->r_min = r;
    size_t n = d->P->n;
    if (n > d->x_build_cap) {
      TL_CHECK(tl_realloc(&d->x_build, n + n / 2 + 16, sizeof *d->x_build));
      d->x_build_cap = n + n / 2 + 16;
    }
    d->x_build[n - 1] = x;
    TL_CHECK(tl_dem_build_law_table(d));
    d->need_rebuild = 1;
  }
  return TL_OK;
}

TlStatus tl_dem_set_spin(TlDem *d, size_t index, TlVec3 w)
{
  TlParticles *P = d->P;
  if (index >= P->n) TL_ERROR(TL_ERR_ARG, "particle index %zu out of range (n = %zu)", index, P->n);
  if (!tl_v3_isfinite(w))
    TL_ERROR(TL_ERR_ARG, "spin of particle id %lld: (%g, %g, %g) rad/s is not finite", (long long)P->id[index], w.x,
             w.y, w.z);
  if (d->dim == 2 && (w.x != 0.0 || w.y != 0.0))
    TL_ERROR(TL_ERR_ARG, "2-D world: spin of particle id %lld is (%g, %g, %g) rad/s; disks spin about z only",
             (long long)P->id[index], w.x, w.y, w.z);
  /* the rotational state on first use, before or after set-up */
  TL_CHECK(tl_particles_enable_rotation(P));
  P->w[index] = w;
  return TL_OK;
}

TlStatus tl_dem_remove_particle(TlDem *d, size_t index)
{
  TlParticles *P = d->P;
  if (index >= P->n) TL_ERROR(TL_ERR_ARG, "particle index %zu out of range (n = %zu)", index, P->n);
  size_t n = P->n, last = n - 1;
  for (size_t g = 0; g < d->n_presc; ++g)
    for (size_t k = 0; k < d->presc[g].n; ++k)
      if (d->presc[g].idx[k] == index)
        TL_ERROR(TL_ERR_STATE, "particle id %lld has a prescribed motion and cannot be removed", (long long)P->id[index]);
  for (size_t k = 0; k < d->n_bond_ids; ++k)
    if (d->bond_ids[k] == P->id[index])
      TL_ERROR(TL_ERR_STATE, "particle id %lld is bonded and cannot be removed", (long long)P->id[index]);
  if (n > d->perm_cap) {
    TL_CHECK(tl_realloc(&d->perm, n, sizeof *d->perm));
    TL_CHECK(tl_realloc(&d->old_to_new, n, sizeof *d->old_to_new));
    d->perm_cap = n;
  }
  for (size_t k = 0; k < n; ++k) d->old_to_new[k] = k;
  d->old_to_new[index] = SIZE_MAX;
  if (index != last) d->old_to_new[last] = index;
  TL_CHECK(tl_particles_remove(P, index));
  if (d->setup_done) {
    TL_CHECK(tl_dem_remap(d, d->old_to_new, n));
    if (index != last && d->x_build) d->x_build[index] = d->x_build[last];
    d->need_rebuild = 1;
  }
  return TL_OK;
}
