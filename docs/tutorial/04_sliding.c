/* Tutorial 4: a particle sliding on a deformable beam (surface coupling).
 * A heavy grain slides without friction along the top of an elastic,
 * weightless cantilever (hex8, clamped at y = 0); the beam's free surface
 * is a wall of the DEM world, moved with the beam, and the contact forces
 * load the beam through its SCoupling elements (Dirac limit, c = 0).
 * Checks: the force on the beam is minus the force on the grain at every
 * step, the coupled energy (grain + beam) is kept, the beam bends under the
 * grain.  Output: particles.xmf, beam.xmf, walls.xmf, sliding.csv. */
#include "talus.h"

static TlStatus run(const char *dir, double *balance, double *drift, double *tip_ratio)
{
  const double r = 0.1, k_n = 2e7, v0 = 3.0, g = 9.81; /* m, N/m, m/s, m/s^2 */
  TlMesh *mesh;
  TlMaterial *rubber;
  TlSolid *beam;
  TL_CHECK(tl_mesh_create_box(&tl_element_hex8, (size_t[]){2, 12, 2}, (double[]){-0.4, 0, -0.4}, (double[]){0.4, 4.8, 0.4}, &mesh));
  TL_CHECK(tl_material_create_hooke(1e8, 0.0, 1309.0, &rubber)); /* E (Pa), nu, density (kg/m^3) */
  TL_CHECK(tl_api_solid_create(mesh, rubber, "ymin", &beam)); /* clamped at y = 0 */
  TL_CHECK(tl_solid_setup(beam));

  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  tl_dem_set_gravity(dem, tl_v3(0, 0, -g));
  TlParticles *P = tl_dem_particles(dem);
  int steel;
  TL_CHECK(tl_particles_add_species(P, "steel", 2e4, r, r, &steel));
  const double m = 2e4 * 4.0 / 3.0 * TL_PI * r * r * r; /* kg */
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0, 0.4, 0.4 + r - m * g / k_n), tl_v3(0, v0, 0), r, steel, NULL));
  TL_CHECK(tl_api_dem_add_law(dem, "linear", NULL, NULL, NULL, 1, (TlSetting[]){{"k_n", k_n}}, NULL));
  TL_CHECK(tl_dem_set_timestep(dem, 0.02 * TL_PI * sqrt(m / k_n), 0));
  TlSCoupledLoop *sc; /* the beam's surface but the clamped end becomes a wall of law 0; one FE step per DEM step */
  TL_CHECK(tl_api_scoupled_create(dem, beam, "ymin", 0, "central_difference", &sc));
  TlCoupledLoop *loop = tl_api_scoupled_loop(sc);

  TlSceneWriter *out; /* particles.xmf, walls.xmf (the beam's surface as the grain sees it), beam.xmf */
  TlTimeSeries *ts;
  TL_CHECK(tl_api_scene_writer_create(dir, dem, beam, tl_api_scoupled_stepper(sc), "beam", &out));
  TL_CHECK(tl_api_timeseries_create(dir, "sliding", 4, (TlColumn[]){{"t", "s"}, {"y", "m"}, {"tip_w", "m"}, {"energy", "J"}}, &ts));
  TlCoupledEnergy e;
  TL_CHECK(tl_coupled_loop_energy(loop, &e));
  const double e0 = e.total, ke0 = 0.5 * m * v0 * v0;
  double tip_min = *balance = *drift = 0;
  for (long step = 1; P->x[0].y < 4.0; ++step) {
    TL_CHECK(tl_coupled_loop_step(loop));
    *balance = fmax(*balance, tl_v3_norm(tl_api_coupled_loop_imbalance(loop, mesh->n_nodes)) / (m * g)); /* Eq. 41 */
    TL_CHECK(tl_coupled_loop_energy(loop, &e));
    *drift = fmax(*drift, fabs(e.total - e0) / ke0);
    const double tip = tl_coupled_loop_u_nodes(loop)[3 * (mesh->n_nodes - 1) + 2]; /* the last node: free end */
    tip_min = fmin(tip_min, tip);
    double row[4] = {tl_coupled_loop_time(loop), P->x[0].y, tip, e.total};
    if (step % 20 == 0) TL_CHECK(tl_timeseries_append(ts, row));
    if (step % 500 == 0) TL_CHECK(tl_api_scene_writer_write(out, step));
  }
  /* against the static deflection under the grain's weight at the free end, m g L^3 / (3 E I) */
  *tip_ratio = -tip_min / (m * g * pow(4.8, 3) / (3 * 1e8 * pow(0.8, 4) / 12));
  TL_CHECK(tl_timeseries_close(&ts));
  tl_api_scene_writer_destroy(&out);
  tl_api_scoupled_destroy(&sc);
  tl_dem_destroy(&dem);
  tl_solid_destroy(&beam);
  tl_material_destroy(&rubber);
  tl_mesh_destroy(&mesh);
  return TL_OK;
}

int main(int argc, char **argv)
{
  double balance, drift, tip;
  if (tl_initialize() || run(argc > 1 ? argv[1] : "out_sliding", &balance, &drift, &tip)) {
    fprintf(stderr, "error: %s\n", tl_error_message());
    return 1;
  }
  printf("force balance beam + grain %.2e of the weight, energy drift %.2e of the grain's kinetic energy, largest tip "
         "deflection %.3f of the static one under the grain at the free end\n", balance, drift, tip);
  int ok = balance <= 1e-12 && drift <= 1e-3 && tip >= 0.3 && tip <= 1.5;
  printf("summary: force_balance=%.3g energy_drift=%.3g tip_ratio=%.4g status=%s\n", balance, drift, tip,
         ok ? "ok" : "failed");
  return ok ? 0 : 1;
}
