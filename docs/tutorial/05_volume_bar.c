/* Tutorial 5: a volume-coupled bar.  A chain of bonded particles (y < 10 m)
 * and a hex8 bar (y > 8 m) overlap on 8 < y < 10, where the Arlequin weights
 * hand the bar from one model to the other and a penalty ties the
 * particles' homogenised displacement to the elements' (TlVCoupling).  A
 * compression pulse leaves the particles and must arrive in the elements
 * at the speed of sound sqrt(E / rho), unharmed.  Checks: the arrival time
 * and amplitude at y = 16.4 m, and the coupling forces' balance (Eq. 41)
 * at every step.  Output: particles.xmf, bar.xmf, pulse.csv. */
#include "talus.h"

static TlStatus run(const char *dir, double *t_ratio, double *v_ratio, double *eq41)
{
  const double d = 0.4, E = 1e8, rho = 1309, v0 = 0.01, c0 = sqrt(E / rho), y0 = 3.5, s = 1.2;
  TlMesh *mesh;
  TlMaterial *mat;
  TlSolid *bar;
  TL_CHECK(tl_mesh_create_box(&tl_element_hex8, (size_t[]){1, 30, 1}, (double[]){0, 8, 0}, (double[]){d, 20, d}, &mesh));
  TL_CHECK(tl_material_create_hooke(E, 0.0, rho, &mat));
  TL_CHECK(tl_api_solid_create(mesh, mat, "ymax", &bar)); /* the far end clamped */

  TlDem *dem; /* the chain: k_n = E d and rho_g = 6 rho / pi give sqrt(E / rho) */
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "chain", 6 * rho / TL_PI, d / 2, d / 2, &sp));
  for (int a = 0; a < 25; ++a) { /* a right-moving pulse: velocity v and strain -v / c0 */
    double y = (a + 0.5) * d, u = -v0 * s * sqrt(TL_PI) / (2 * c0) * (1 + erf((y - y0) / s));
    TL_CHECK(tl_dem_add_particle(dem, tl_v3(d / 2, y + u, d / 2), tl_v3(0, v0 * exp(-pow((y - y0) / s, 2)), 0), d / 2, sp, NULL));
    if (a > 0) TL_CHECK(tl_dem_add_bond(dem, P->id[a - 1], P->id[a]));
  }
  TL_CHECK(tl_api_dem_add_law(dem, "bonded_linear", NULL, NULL, NULL, 1, (TlSetting[]){{"k_n", E * d}}, NULL));
  TlVCouplingParams vp = {{1, 8.0, 10.0}, 0.0, "lucy", 1.6e9 / (d * d), 4, 0}; /* zone along y, c = 0, penalty */
  TlVCoupledLoop *loop; /* sets the bar up; each DEM step now steps the bar too */
  TL_CHECK(tl_api_vcoupled_create(dem, bar, &vp, "central_difference", &loop));
  TL_CHECK(tl_dem_set_timestep(dem, 0.05 * d / c0, 0));
  TL_CHECK(tl_dem_setup(dem));

  TlStepper *st = tl_api_vcoupled_stepper(loop);
  TlSceneWriter *out;
  TlTimeSeries *ts;
  const TlColumn cols[] = {{"t", "s"}, {"v_particle_7m", "m/s"}, {"v_bar_16.4m", "m/s"}};
  TL_CHECK(tl_api_scene_writer_create(dir, dem, bar, st, "bar", &out));
  TL_CHECK(tl_api_timeseries_create(dir, "pulse", 3, cols, &ts));
  size_t probe = 0, i7; /* a node at y = 16.4 m */
  while (fabs(mesh->x[3 * probe + 1] - 16.4) > 1e-9) ++probe;
  double v_peak = 0, t_peak = 0;
  const int64_t at7 = P->id[17]; /* the particle at y = 7 m, by its id: the world may renumber its arrays */
  for (long step = 0; tl_dem_time(dem) < 0.055; ++step) {
    TL_CHECK(tl_dem_step(dem, 1));
    TL_CHECK(tl_particles_find(P, at7, &i7));
    double v = st->v[tl_solid_dof(bar, probe, 1)], row[3] = {tl_dem_time(dem), P->v[i7].y, v};
    if (v > v_peak) v_peak = v, t_peak = tl_dem_time(dem);
    TL_CHECK(tl_timeseries_append(ts, row));
    if (step % 20 == 0) TL_CHECK(tl_api_scene_writer_write(out, step));
  }
  *t_ratio = t_peak / ((16.4 - y0) / c0), *v_ratio = v_peak / v0;
  tl_api_vcoupled_diag(loop, NULL, eq41);
  TL_CHECK(tl_timeseries_close(&ts));
  tl_api_scene_writer_destroy(&out);
  tl_api_vcoupled_destroy(&loop);
  tl_dem_destroy(&dem);
  tl_solid_destroy(&bar);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
  return TL_OK;
}

int main(int argc, char **argv)
{
  double t, v, eq41;
  if (tl_initialize() || run(argc > 1 ? argv[1] : "out_volume_bar", &t, &v, &eq41)) {
    fprintf(stderr, "error: %s\n", tl_error_message());
    return 1;
  }
  printf("pulse at y = 16.4 m: arrival %.4f of (16.4 - 3.5) / sqrt(E / rho), amplitude %.3f of the sent one; Eq. 41 "
         "defect %.1e\n", t, v, eq41);
  int ok = fabs(t - 1) <= 0.03 && v >= 0.8 && v <= 1.05 && eq41 <= 1e-12;
  printf("summary: arrival_ratio=%.5g amplitude_ratio=%.4g eq41=%.3g status=%s\n", t, v, eq41, ok ? "ok" : "failed");
  return ok ? 0 : 1;
}
