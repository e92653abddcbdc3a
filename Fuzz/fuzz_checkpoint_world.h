/* The harness's world: 8 particles in a box periodic in x and y, on a plane
 * floor, after set-up.  Shared by fuzz_checkpoint.c and the unit test that
 * replays its findings (UnitTests/test_checkpoint_fuzz_findings.c), so a
 * finding replays on the world it was found on. */
#ifndef FUZZ_CHECKPOINT_WORLD_H
#define FUZZ_CHECKPOINT_WORLD_H

#include "tl_contact_law.h"
#include "tl_dem.h"

static inline TlStatus fuzz_checkpoint_world(TlDem **out)
{
  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  const double L = 0.01;
  TlDomain dom;
  int per[3] = {1, 1, 0};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, -0.002), tl_v3(L, L, 0.03), per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "glass", 2500, 0.0014, 0.0016, &sp));
  for (int k = 0; k < 8; ++k) {
    TlVec3 x = tl_v3((k % 2 + 0.5) * L / 2, (k / 2 % 2 + 0.5) * L / 2, 0.0016 + 0.0033 * (k / 4));
    TL_CHECK(tl_dem_add_particle(dem, x, tl_v3(0, 0, -0.1), 0.0015, sp, NULL));
  }
  TlContactLaw *law = NULL;
  TL_CHECK(tl_contact_law_create("linear", "coulomb", "constant", "constant", &law));
  TL_CHECK(tl_contact_law_set(law, "k_n", 200.0));
  TL_CHECK(tl_contact_law_set(law, "mu", 0.4));
  TL_CHECK(tl_contact_law_setup(law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  TlWall *floor_ = NULL;
  TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &floor_));
  TL_CHECK(tl_dem_add_wall(dem, floor_, 0));
  TL_CHECK(tl_dem_set_timestep(dem, 4e-5, 0));
  TL_CHECK(tl_dem_setup(dem));
  *out = dem;
  return TL_OK;
}

#endif
