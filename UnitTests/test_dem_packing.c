/* Packing files (tl_dem_packing.h): a world in a periodic cell written as a
 * snapshot with its cell and as a LAMMPS data file, read back bit for bit,
 * loaded into a new world; a plain snapshot (no cell), a world that is not
 * periodic and a sheared cell for LAMMPS are refused by name. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_dem.h"
#include "tl_dem_packing.h"
#include "tl_lammps_data.h"
#include "tl_test.h"

static TlDem *small_world(TlMat3 h, TlVec3 o)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlDomain dom;
  TL_TEST_STATUS(tl_domain_init_cell(&dom, o, h), TL_OK);
  TL_TEST_STATUS(tl_dem_set_domain(dem, &dom), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "g", 2500.0, 1.25e-3, 1.75e-3, &sp), TL_OK);
  /* centres inside and outside the cell (the LAMMPS copy wraps them) */
  const double xs[5][3] = {{1e-3, 2e-3, 3e-3}, {9e-3, 1e-3, 5e-3}, {-2e-3, 4e-3, 8e-3}, {5e-3, 11e-3, 2e-3},
                           {3e-3, 6e-3, 9.5e-3}};
  for (int k = 0; k < 5; ++k)
    TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(xs[k][0], xs[k][1], xs[k][2]), tl_v3(0.1 * k, -0.2, 0.3 / (k + 1)),
                                       k % 2 ? 1.75e-3 : 1.25e-3, sp, NULL),
                   TL_OK);
  TL_TEST_STATUS(tl_particles_enable_rotation(P), TL_OK);
  for (size_t i = 0; i < P->n; ++i) P->w[i] = tl_v3(1.0 + (double)i, -2.0, 0.5);
  return dem;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const char *dir = "test_dem_packing.out";
  TL_TEST_STATUS(tl_mkdir_p(dir), TL_OK);
  const TlMat3 h = {{{10e-3, 0, 0}, {0, 11e-3, 0}, {0, 0, 10.5e-3}}};
  const TlVec3 o = tl_v3(-1e-3, 0.5e-3, 0);
  TlDem *dem = small_world(h, o);
  TlParticles *P = tl_dem_particles(dem);

  TlParticleWriter *w;
  TL_TEST_STATUS(tl_particle_writer_create(dir, "packing", &w), TL_OK);
  const char *file = NULL;
  TL_TEST_STATUS(tl_dem_packing_write(dem, w, 7, &file), TL_OK);
  char path[512];
  snprintf(path, sizeof path, "%s", file ? file : "");

  /* read back: the snapshot and the cell, bit for bit */
  TlParticleSnapshot s;
  TlVec3 o2;
  TlMat3 h2;
  TL_TEST_STATUS(tl_dem_packing_read(path, &s, &o2, &h2), TL_OK);
  TL_TEST_ASSERT(s.n == P->n, "%zu particles read, %zu written", s.n, P->n);
  TL_TEST_ASSERT(memcmp(&h2, &h, sizeof h) == 0 && o2.x == o.x && o2.y == o.y && o2.z == o.z, "cell changed");
  for (size_t i = 0; i < s.n && i < P->n; ++i) {
    TL_TEST_ASSERT(memcmp(&s.position[i], &P->x[i], sizeof(TlVec3)) == 0 && s.radius[i] == P->radius[i],
                   "particle %zu changed", i);
    TL_TEST_ASSERT(s.angular_velocity && memcmp(&s.angular_velocity[i], &P->w[i], sizeof(TlVec3)) == 0,
                   "spin %zu changed", i);
  }
  tl_particle_snapshot_free(&s);

  /* loaded into a new world: the cell, the particles, their velocities and spins */
  TlDem *d2;
  TL_TEST_STATUS(tl_dem_create(&d2), TL_OK);
  int sp = -1;
  TL_TEST_STATUS(tl_dem_packing_load(d2, path, 2500.0, &sp), TL_OK);
  TlParticles *Q = tl_dem_particles(d2);
  const TlDomain *D2 = tl_dem_domain(d2);
  TL_TEST_ASSERT(Q->n == P->n && sp == 0, "loaded %zu particles, species %d", Q->n, sp);
  TL_TEST_ASSERT(D2->periodic[0] && D2->periodic[1] && D2->periodic[2] && memcmp(&D2->h, &h, sizeof h) == 0,
                 "loaded cell differs");
  for (size_t i = 0; i < Q->n && i < P->n; ++i) {
    TL_TEST_ASSERT(memcmp(&Q->x[i], &P->x[i], sizeof(TlVec3)) == 0 && memcmp(&Q->v[i], &P->v[i], sizeof(TlVec3)) == 0 &&
                       Q->w && memcmp(&Q->w[i], &P->w[i], sizeof(TlVec3)) == 0,
                   "loaded particle %zu differs", i);
    TL_TEST_REL(Q->mass[i], P->mass[i], 1e-15);
  }
  /* a world that already holds particles, a bad density */
  TL_TEST_STATUS(tl_dem_packing_load(d2, path, 2500.0, NULL), TL_ERR_STATE);
  TlDem *d3;
  TL_TEST_STATUS(tl_dem_create(&d3), TL_OK);
  TL_TEST_STATUS(tl_dem_packing_load(d3, path, -1.0, NULL), TL_ERR_ARG);
  tl_dem_destroy(&d3);
  tl_dem_destroy(&d2);

  /* a plain snapshot has no cell: refused as not a packing */
  TlParticleView view = {.n = P->n, .position = P->x, .radius = P->radius};
  TL_TEST_STATUS(tl_particle_writer_write(w, 8, 0.0, &view), TL_OK);
  TL_TEST_STATUS(tl_dem_packing_read(tl_particle_writer_last_path(w), &s, &o2, &h2), TL_ERR_FORMAT);
  TL_TEST_ASSERT(strstr(tl_error_message(), "not a packing") != NULL, "message: %s", tl_error_message());
  tl_particle_writer_destroy(&w);

  /* the LAMMPS copy: same box, diameters, wrapped positions, velocities */
  char data[512];
  snprintf(data, sizeof data, "%s/packing.data", dir);
  TL_TEST_STATUS(tl_dem_packing_write_lammps(dem, 2500.0, data), TL_OK);
  TlLammpsData *L;
  TL_TEST_STATUS(tl_lammps_data_read(data, &L), TL_OK);
  if (L) {
    TL_TEST_ASSERT(L->n == P->n && L->lo[0] == o.x && L->hi[1] == o.y + h.m[1][1], "LAMMPS box or count differs");
    for (size_t i = 0; i < L->n && i < P->n; ++i) {
      TL_TEST_ASSERT(L->diameter[i] == 2.0 * P->radius[i] && L->density[i] == 2500.0, "atom %zu", i);
      TL_TEST_ASSERT(memcmp(&L->v[i], &P->v[i], sizeof(TlVec3)) == 0, "velocity of atom %zu", i);
      const double x[3] = {L->x[i].x, L->x[i].y, L->x[i].z}, p[3] = {P->x[i].x, P->x[i].y, P->x[i].z};
      const double lo[3] = {o.x, o.y, o.z};
      for (int k = 0; k < 3; ++k) {
        const double Lk = h.m[k][k], shift = (x[k] - p[k]) / Lk;
        TL_TEST_ASSERT(x[k] >= lo[k] && x[k] < lo[k] + Lk && fabs(shift - round(shift)) < 1e-9,
                       "atom %zu axis %d: %g is not %g wrapped into [%g, %g)", i, k, x[k], p[k], lo[k], lo[k] + Lk);
      }
    }
    tl_lammps_data_destroy(&L);
  }
  tl_dem_destroy(&dem);

  /* a sheared cell is refused for LAMMPS; an open domain for both */
  TlMat3 hs = h;
  hs.m[0][1] = 1e-3;
  dem = small_world(hs, o);
  TL_TEST_STATUS(tl_dem_packing_write_lammps(dem, 2500.0, data), TL_ERR_UNSUPPORTED);
  tl_dem_destroy(&dem);
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlDomain open;
  TL_TEST_STATUS(tl_domain_init_open(&open, tl_v3(0, 0, 0), tl_v3(1, 1, 1)), TL_OK);
  TL_TEST_STATUS(tl_dem_set_domain(dem, &open), TL_OK);
  TL_TEST_STATUS(tl_dem_packing_write_lammps(dem, 2500.0, data), TL_ERR_ARG);
  tl_dem_destroy(&dem);
  return tl_test_report();
}
