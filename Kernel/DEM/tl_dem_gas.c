/* Random sequential insertion of a loose gas into the world's domain (2-D:
 * disks in the plane z = 0), the start of a packing made by compression. */
#include "tl_dem_private.h"

#include <math.h>

TlStatus tl_dem_insert_gas(TlDem *d, int species, size_t n, uint64_t seed, long max_attempts, size_t *placed)
{
  TlParticles *P = d->P;
  if (placed) *placed = 0;
  if (species < 0 || (size_t)species >= P->n_species)
    TL_ERROR(TL_ERR_ARG, "gas: species %d unknown (%zu species defined)", species, P->n_species);
  if (max_attempts < 1) TL_ERROR(TL_ERR_ARG, "gas: max_attempts %ld must be at least 1", max_attempts);
  const TlDomain *D = &d->domain;
  const int planar = d->dim == 2;
  const double cell = planar ? tl_domain_area(D) : tl_domain_volume(D);
  uint64_t rng = seed * 0x9e3779b97f4a7c15ULL + 1;
  TL_CHECK(tl_particles_reserve(P, P->n + n));
  const size_t first = P->n;
  double filled = 0.0;
  for (size_t i = 0; i < first; ++i)
    filled += planar ? TL_PI * P->radius[i] * P->radius[i] : 4.0 / 3.0 * TL_PI * pow(P->radius[i], 3);
  for (size_t k = 0; k < n; ++k) {
    const double r = tl_species_sample_radius(&P->species_table[species], &rng);
    int ok = 0;
    for (long a = 0; a < max_attempts && !ok; ++a) {
      TlVec3 s = {tl_random_uniform(&rng), tl_random_uniform(&rng), planar ? 0.0 : tl_random_uniform(&rng)};
      TlVec3 x = tl_domain_from_reduced(D, s);
      if (planar) x.z = 0.0;
      ok = 1;
      for (size_t i = 0; i < P->n && ok; ++i) {
        TlVec3 b = tl_domain_branch(D, P->x[i], x);
        const double c = P->radius[i] + r;
        ok = b.x * b.x + b.y * b.y + b.z * b.z > c * c;
      }
      if (ok) TL_CHECK(tl_dem_add_particle(d, x, tl_v3(0, 0, 0), r, species, NULL));
    }
    if (!ok)
      TL_ERROR(TL_ERR_ARG,
               "gas: particle %zu of %zu (radius %g) found no free place in %ld attempts; packing fraction %.4g "
               "reached: ask for fewer particles or a larger cell",
               k, n, r, max_attempts, filled / cell);
    filled += planar ? TL_PI * r * r : 4.0 / 3.0 * TL_PI * r * r * r;
    if (placed) *placed = k + 1;
  }
  return TL_OK;
}
