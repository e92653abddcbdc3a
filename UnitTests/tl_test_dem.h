/* Test support for DEM worlds: a loose column of glass spheres in a box
 * periodic in x and y, on a 5 x 5 lattice per layer (so nothing overlaps at
 * the start), shared by the checkpoint, restart and wall tests. */
#ifndef TL_TEST_DEM_H
#define TL_TEST_DEM_H

#include <stdint.h>
#include "tl_dem.h"
#include "tl_test.h"

typedef struct {
  double L;                       /* side of the periodic square, m; the box spans z in [-0.002, 0.03] */
  int n;                          /* spheres, 25 a layer */
  double r_min, r_max;            /* radii drawn uniformly in [r_min, r_max], m */
  double z0, dz;                  /* centre height of the first layer and the layer spacing, m */
  double v_jitter;                /* horizontal velocity components drawn in [-v_jitter/2, v_jitter/2] m/s; 0: none drawn */
  double v_z;                     /* vertical velocity, m/s */
  uint64_t seed;                  /* state of uniform */
  double (*uniform)(uint64_t *s); /* the test's generator in [0, 1) (tl_random_uniform when NULL) */
} TlTestColumn;

/* Sets the periodic domain of dem (returned in dom when not NULL) and adds
 * the column's species and spheres. */
static inline TlStatus tl_test_dem_column(TlDem *dem, const TlTestColumn *c, TlDomain *dom)
{
  TlDomain d;
  int per[3] = {1, 1, 0};
  TL_CHECK(tl_domain_init_periodic_box(&d, tl_v3(0, 0, -0.002), tl_v3(c->L, c->L, 0.03), per));
  TL_CHECK(tl_dem_set_domain(dem, &d));
  int sp;
  TL_CHECK(tl_particles_add_species(tl_dem_particles(dem), "glass", 2500, c->r_min, c->r_max, &sp));
  double (*uniform)(uint64_t *) = c->uniform ? c->uniform : tl_random_uniform;
  uint64_t seed = c->seed;
  for (int k = 0; k < c->n; ++k) {
    double r = c->r_min + (c->r_max - c->r_min) * uniform(&seed);
    int i = k % 25, layer = k / 25;
    TlVec3 x = tl_v3((i % 5 + 0.5) * c->L / 5, (i / 5 + 0.5) * c->L / 5, c->z0 + c->dz * layer);
    TlVec3 v = tl_v3(0, 0, c->v_z);
    if (c->v_jitter > 0) {
      v.x = c->v_jitter * (uniform(&seed) - 0.5);
      v.y = c->v_jitter * (uniform(&seed) - 0.5);
    }
    TL_CHECK(tl_dem_add_particle(dem, x, v, r, sp, NULL));
  }
  if (dom) *dom = d;
  return TL_OK;
}

#endif
