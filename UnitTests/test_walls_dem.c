/* A triangulated floor in the DEM world: polydisperse spheres poured on a
 * floor of triangles, periodic in x and y (the floor crosses the periodic
 * faces), with the world's grid rebuilds and particle reordering (the wall
 * remaps its contacts).  Checks: nobody falls through; at rest the floor
 * carries the weight of the pile; energy is booked as by the plane; the pile
 * settles as on a plane (same height, same number of floor contacts within
 * the scatter of a chaotic pour); a checkpoint of the wall restores it. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"
#include "tl_test_dem.h"
#include "tl_wall_trisurface.h"

static double urand(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

typedef struct {
  double mean_height, weight, floor_force, energy_drift, energy_scale, kinetic;
  double lowest; /* min (z - r) / r */
  size_t floor_contacts;
  long rebuilds;
} PourResult;

static TlStatus pour(int triangles, PourResult *out)
{
  const double L = 0.02;
  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  TlDomain dom;
  const TlTestColumn column = {.L = L, .n = 150, .r_min = 0.0008, .r_max = 0.0016, .z0 = 0.003, .dz = 0.0036,
                               .v_jitter = 0.05, .seed = 2024, .uniform = urand};
  TL_CHECK(tl_test_dem_column(dem, &column, &dom));
  const TlParticles *P = tl_dem_particles(dem);
  TlContactLaw *law = NULL;
  TL_CHECK(tl_test_law(&law, "linear", "k_n", 200.0, "restitution", 0.3, "mu", 0.4, NULL));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TlWall *floor_ = NULL;
  if (triangles) {
    TlTriSurface *s = NULL;
    TL_CHECK(tl_trisurface_create_rectangle(0, 0, L, L, 0, 7, 7, 2, &s));
    size_t linked = 0;
    TL_CHECK(tl_trisurface_link_periodic(s, &dom, 1e-9, &linked));
    TL_TEST_ASSERT(linked == 14, "floor edges joined across the periodic faces: %zu, expected 14", linked);
    TL_CHECK(tl_wall_trisurface_create(s, &floor_));
  } else {
    TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &floor_));
  }
  TlWall *w = floor_;
  TL_CHECK(tl_dem_add_wall(dem, floor_, 0));
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  tl_dem_track_energy(dem, 1);
  TL_CHECK(tl_dem_set_timestep(dem, 4e-5, 0));
  TL_CHECK(tl_dem_setup(dem));
  TlDemEnergy e0, e;
  TL_CHECK(tl_dem_energy(dem, &e0));
  out->lowest = INFINITY;
  for (int chunk = 0; chunk < 20; ++chunk) {
    TL_CHECK(tl_dem_step(dem, 500));
    for (size_t i = 0; i < P->n; ++i) out->lowest = fmin(out->lowest, P->x[i].z / P->radius[i] - 1.0);
  }
  TL_CHECK(tl_dem_energy(dem, &e));
  out->energy_drift = fabs(e.total - e0.total);
  out->energy_scale = fabs(e0.gravitational - e.gravitational);
  out->kinetic = e.kinetic_translational + e.kinetic_rotational;
  out->mean_height = 0;
  out->weight = 0;
  for (size_t i = 0; i < P->n; ++i) {
    out->mean_height += P->x[i].z / (double)P->n;
    out->weight += P->mass[i] * 9.81;
  }
  out->floor_force = w->force.z;
  out->floor_contacts = w->n_contacts;
  TlDemStats st;
  tl_dem_stats(dem, &st);
  out->rebuilds = st.rebuilds;

  if (triangles) {
    /* checkpoint round trip: saved state loads back byte for byte */
    size_t size = w->ops->checkpoint_size(w);
    unsigned char *a = NULL, *b = NULL;
    TL_CHECK(tl_calloc(&a, size, 1));
    TL_CHECK(tl_calloc(&b, size, 1));
    TL_CHECK(w->ops->checkpoint_save(w, a, size));
    TL_CHECK(w->ops->checkpoint_load(w, a, size));
    TL_CHECK(w->ops->checkpoint_save(w, b, size));
    int same = memcmp(a, b, size) == 0;
    TL_TEST_ASSERT(same && size > 1000, "checkpoint round trip (%zu bytes)", size);
    TL_TEST_STATUS(w->ops->checkpoint_load(w, a, size / 2), TL_ERR_FORMAT);
    tl_free(&a);
    tl_free(&b);
  }
  tl_dem_destroy(&dem);
  return TL_OK;
}

int main(void)
{
  PourResult tri, plane;
  TL_TEST_STATUS(pour(1, &tri), TL_OK);
  TL_TEST_STATUS(pour(0, &plane), TL_OK);
  printf("triangles: mean height %.5g m, floor force %.6g N, weight %.6g N, %zu floor contacts, kinetic %.3g J, "
         "energy drift %.3g of %.3g J, lowest (z-r)/r %.4f, %ld rebuilds\n",
         tri.mean_height, tri.floor_force, tri.weight, tri.floor_contacts, tri.kinetic, tri.energy_drift,
         tri.energy_scale, tri.lowest, tri.rebuilds);
  printf("plane:     mean height %.5g m, floor force %.6g N, weight %.6g N, %zu floor contacts, kinetic %.3g J, "
         "energy drift %.3g of %.3g J\n",
         plane.mean_height, plane.floor_force, plane.weight, plane.floor_contacts, plane.kinetic, plane.energy_drift,
         plane.energy_scale);
  TL_TEST_ASSERT(tri.rebuilds > 10, "the grid was rebuilt (and particles reordered) %ld times", tri.rebuilds);
  TL_TEST_ASSERT(tri.lowest > -0.2, "a particle sank %.3f radii into the floor", -tri.lowest);
  TL_TEST_ASSERT(tri.kinetic < 1e-3 * tri.energy_scale, "the pile has settled (kinetic %g)", tri.kinetic);
  /* at rest the floor carries the weight (force on the wall is downwards) */
  TL_TEST_REL(-tri.floor_force, tri.weight, 0.02);
  /* the wall books energy as the plane does: the balance closes to 1 % of
   * the energy released, and to the same residual as with the plane */
  TL_TEST_ASSERT(tri.energy_drift < 1e-2 * tri.energy_scale, "energy balance off by %g of %g J", tri.energy_drift,
                 tri.energy_scale);
  TL_TEST_ASSERT(fabs(tri.energy_drift - plane.energy_drift) < 0.1 * plane.energy_drift + 1e-4 * tri.energy_scale,
                 "energy residual %g J with triangles, %g J with the plane", tri.energy_drift, plane.energy_drift);
  TL_TEST_REL(tri.mean_height, plane.mean_height, 0.05);
  TL_TEST_ASSERT(labs((long)tri.floor_contacts - (long)plane.floor_contacts) <= 0.25 * (double)plane.floor_contacts,
                 "floor contacts %zu (triangles) vs %zu (plane)", tri.floor_contacts, plane.floor_contacts);
  return tl_test_report();
}
