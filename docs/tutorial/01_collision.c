/* Tutorial 1: two particles colliding.  A small and a large sphere meet
 * head on under a linear spring-dashpot law of restitution e = 0.8.  The
 * program checks what the law promises: the relative speed after the
 * impact is e times the one before, and the total momentum does not
 * change.  Output: particles.xmf (ParaView), collision.csv (plot.py). */
#include "talus.h"

static TlStatus run(const char *dir, double *e_measured, double *momentum_defect)
{
  const double r1 = 0.01, r2 = 0.015, rho = 2500, e = 0.8, k_n = 1e4; /* m, kg/m^3, -, N/m */
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  int glass;
  TL_CHECK(tl_particles_add_species(P, "glass", rho, r1, r2, &glass));
  size_t a, b; /* indices now; the world may renumber its arrays, ids stay */
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(-0.02, 0, 0), tl_v3(0.5, 0, 0), r1, glass, &a));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0.02, 0, 0), tl_v3(-0.2, 0, 0), r2, glass, &b));
  const int64_t id_a = P->id[a], id_b = P->id[b];
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_create("linear", NULL, NULL, NULL, &law));
  TL_CHECK(tl_contact_law_set(law, "k_n", k_n));
  TL_CHECK(tl_contact_law_set(law, "restitution", e));
  TL_CHECK(tl_contact_law_setup(law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL)); /* the world owns the law now */
  double dt_c;
  TL_CHECK(tl_dem_critical_timestep(dem, &dt_c, NULL, NULL));
  TL_CHECK(tl_dem_set_timestep(dem, 0.05 * dt_c, 0));
  TL_CHECK(tl_dem_setup(dem));

  TlParticleWriter *pw;
  TL_CHECK(tl_particle_writer_create(dir, "particles", &pw));
  const TlColumn cols[] = {{"t", "s"}, {"x1", "m"}, {"x2", "m"}, {"v1", "m/s"}, {"v2", "m/s"}, {"momentum", "kg m/s"}};
  char csv[4096];
  snprintf(csv, sizeof csv, "%s/collision", dir);
  TlTimeSeries *ts;
  TL_CHECK(tl_timeseries_create(csv, TL_TIMESERIES_CSV, 6, cols, &ts));
  TlVec3 p0 = tl_v3_add(tl_v3_scale(P->v[a], P->mass[a]), tl_v3_scale(P->v[b], P->mass[b]));
  double v_before = P->v[b].x - P->v[a].x;
  for (long step = 0; tl_dem_time(dem) < 0.12; ++step) {
    TL_CHECK(tl_dem_step(dem, 1));
    TL_CHECK(tl_particles_find(P, id_a, &a));
    TL_CHECK(tl_particles_find(P, id_b, &b));
    double p = P->mass[a] * P->v[a].x + P->mass[b] * P->v[b].x;
    double row[6] = {tl_dem_time(dem), P->x[a].x, P->x[b].x, P->v[a].x, P->v[b].x, p};
    TL_CHECK(tl_timeseries_append(ts, row));
    if (step % 200 == 0) {
      TlParticleView view;
      tl_particle_view_of(P, &view); /* with ids and species */
      TL_CHECK(tl_particle_writer_write(pw, step, tl_dem_time(dem), &view));
    }
  }
  TlVec3 p1 = tl_v3_add(tl_v3_scale(P->v[a], P->mass[a]), tl_v3_scale(P->v[b], P->mass[b]));
  *e_measured = -(P->v[b].x - P->v[a].x) / v_before;
  *momentum_defect = tl_v3_norm(tl_v3_sub(p1, p0)) / tl_v3_norm(p0);
  TL_CHECK(tl_timeseries_close(&ts));
  tl_particle_writer_destroy(&pw);
  tl_dem_destroy(&dem);
  return TL_OK;
}

int main(int argc, char **argv)
{
  double e, dp;
  if (tl_initialize() || run(argc > 1 ? argv[1] : "out_collision", &e, &dp)) {
    fprintf(stderr, "error: %s\n", tl_error_message());
    return 1;
  }
  printf("restitution %.5f (law: 0.8), relative momentum change %.2e\n", e, dp);
  /* written so that NaN fails */
  int ok = fabs(e - 0.8) <= 0.005 && dp <= 1e-12;
  printf("summary: restitution=%.6g momentum_defect=%.3g status=%s\n", e, dp, ok ? "ok" : "failed");
  return ok ? 0 : 1;
}
