/* Tutorial 2: a packing settling on a triangulated floor.  200 frictional
 * grains drop into a box whose floor is a triangulated surface and whose
 * sides are planes, and come to rest.  Checks: the grains stop (kinetic
 * energy down to a millionth of the potential energy released) and the
 * walls carry the whole weight.  Output: particles.xmf and walls.xmf (open
 * both in ParaView), settling.csv. */
#include "talus.h"

static TlStatus run(const char *dir, double *ke_ratio, double *load_ratio)
{
  const double r = 0.005, L = 0.06, g = 9.81; /* m, m, m/s^2 */
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  tl_dem_set_gravity(dem, tl_v3(0, 0, -g));
  TlParticles *P = tl_dem_particles(dem);
  int sand;
  TL_CHECK(tl_particles_add_species(P, "sand", 2500, 0.8 * r, r, &sand));
  uint64_t seed = 7;
  srand(1);
  for (int i = 0; i < 200; ++i) { /* a jittered 5 x 5 x 8 lattice, radii drawn from the species */
    double jx = 0.2 * r * (rand() / (double)RAND_MAX - 0.5), jy = 0.2 * r * (rand() / (double)RAND_MAX - 0.5);
    TlVec3 x = tl_v3((i % 5 + 0.5) * L / 5 + jx, (i / 5 % 5 + 0.5) * L / 5 + jy, 0.01 + (i / 25) * 2.4 * r);
    TL_CHECK(tl_dem_add_particle(dem, x, tl_v3(0, 0, 0), tl_species_sample_radius(&P->species_table[sand], &seed), sand, NULL));
  }
  const TlSetting sand_law[] = {{"k_n", 2000}, {"restitution", 0.3}, {"mu", 0.4}}; /* N/m, 1, 1 */
  TL_CHECK(tl_api_dem_add_law(dem, "linear", "coulomb", NULL, NULL, 3, sand_law, NULL)); /* law 0 */
  TlTriSurface *floor_surface; /* 8 x 8 squares, four triangles each, normal +z */
  TL_CHECK(tl_trisurface_create_rectangle(0, 0, L, L, 0, 8, 8, 2, &floor_surface));
  TlWall *w;
  TL_CHECK(tl_wall_trisurface_create(floor_surface, &w));
  TL_CHECK(tl_dem_add_wall(dem, w, 0));
  /* the scene's box, with planes of law 0 on its four sides (ParaView draws them over the box) */
  TL_CHECK(tl_api_dem_set_box_walls(dem, tl_v3(0, 0, 0), tl_v3(L, L, 0.1), "xmin xmax ymin ymax", 0));
  TL_CHECK(tl_dem_set_timestep(dem, 1e-4, 0));
  TL_CHECK(tl_dem_setup(dem));

  TlSceneWriter *out; /* particles.xmf (with ids and species), walls.xmf (the floor and the four sides) */
  TlTimeSeries *ts;
  const TlColumn cols[] = {{"t", "s"}, {"kinetic", "J"}, {"wall_load", "N"}, {"weight", "N"}};
  TL_CHECK(tl_api_scene_writer_create(dir, dem, NULL, NULL, NULL, &out));
  TL_CHECK(tl_api_timeseries_create(dir, "settling", 4, cols, &ts));
  double weight = 0, load = 0;
  for (size_t i = 0; i < P->n; ++i) weight += P->mass[i] * g;
  TlDemEnergy en;
  TL_CHECK(tl_dem_energy(dem, &en));
  const double e0 = en.gravitational;
  for (long step = 0; step <= 20000; ++step) {
    if (step % 500 == 0) TL_CHECK(tl_api_scene_writer_write(out, step));
    load = 0;
    for (size_t k = 0; k < tl_dem_n_walls(dem); ++k) load -= tl_dem_wall(dem, k)->force.z;
    TL_CHECK(tl_dem_energy(dem, &en));
    double row[4] = {tl_dem_time(dem), en.kinetic_translational + en.kinetic_rotational, load, weight};
    if (step % 50 == 0) TL_CHECK(tl_timeseries_append(ts, row));
    TL_CHECK(tl_dem_step(dem, 1));
  }
  *ke_ratio = (en.kinetic_translational + en.kinetic_rotational) / (e0 - en.gravitational);
  *load_ratio = load / weight;
  TL_CHECK(tl_timeseries_close(&ts));
  tl_api_scene_writer_destroy(&out);
  tl_dem_destroy(&dem);
  return TL_OK;
}

int main(int argc, char **argv)
{
  double ke, load;
  if (tl_initialize() || run(argc > 1 ? argv[1] : "out_settling", &ke, &load)) {
    fprintf(stderr, "error: %s\n", tl_error_message());
    return 1;
  }
  printf("kinetic energy %.2e of the energy released; the walls carry %.5f of the weight\n", ke, load);
  int ok = ke <= 1e-6 && fabs(load - 1) <= 0.005;
  printf("summary: kinetic_ratio=%.3g load_ratio=%.6g status=%s\n", ke, load, ok ? "ok" : "failed");
  return ok ? 0 : 1;
}
