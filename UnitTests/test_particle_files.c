/* Particles from files: a LAMMPS data file (atom types as species, or one
 * species for all) and a Talus snapshot written by a world, read into a new
 * world with their positions, radii, velocities and species; files whose
 * types the world lacks, and missing files, are refused by name. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_dem.h"
#include "tl_particle_files.h"
#include "tl_test.h"

static const char data[] =
    "LAMMPS data file for the test\n\n5 atoms\n2 atom types\n\n"
    "0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n\nAtoms # sphere\n\n"
    "1 1 0.02 2500 0.1 0.1 0.1\n2 2 0.04 2500 0.3 0.1 0.1\n3 1 0.03 2500 0.5 0.1 0.1\n"
    "4 2 0.05 2500 0.7 0.1 0.1\n5 1 0.02 2500 0.9 0.1 0.1\n\n"
    "Velocities\n\n1 0.5 0 0 0 0 0\n2 0 -0.5 0 0 0 0\n3 0 0 0 0 0 0\n4 0 0 1 0 0 0\n5 0 0 0 0 0 0\n";

static TlDem *world(int n_species)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  int sp;
  for (int k = 0; k < n_species; ++k) {
    char name[16];
    snprintf(name, sizeof name, "s%d", k);
    TL_TEST_STATUS(tl_particles_add_species(tl_dem_particles(dem), name, 2500, 0.005, 0.05, &sp), TL_OK);
  }
  return dem;
}

int main(void)
{
  tl_log_set_level(TL_LOG_ERROR);
  FILE *f = fopen("particles.data", "w");
  if (f) {
    fputs(data, f);
    fclose(f);
  }
  /* LAMMPS: atom type t is species t - 1. */
  TlDem *dem = world(2);
  size_t n = 0;
  TL_TEST_STATUS(tl_dem_add_particles_from_file(dem, "particles.data", -1, &n), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  const double d[5] = {0.02, 0.04, 0.03, 0.05, 0.02};
  const int type[5] = {1, 2, 1, 2, 1};
  TL_TEST_ASSERT(n == 5 && P->n == 5, "%zu added, %zu in the world", n, P->n);
  for (size_t i = 0; i < P->n && i < 5; ++i) {
    TL_TEST_CLOSE(P->radius[i], 0.5 * d[i], 1e-15);
    TL_TEST_CLOSE(P->x[i].x, 0.1 + 0.2 * (double)i, 1e-15);
    TL_TEST_ASSERT(P->species[i] == type[i] - 1, "atom %zu: species %d, type %d", i + 1, P->species[i], type[i]);
  }
  TL_TEST_CLOSE(P->v[0].x, 0.5, 0);
  TL_TEST_CLOSE(P->v[1].y, -0.5, 0);
  TL_TEST_CLOSE(P->v[3].z, 1.0, 0);
  TL_TEST_CLOSE(P->mass[1], 2500 * 4.0 / 3.0 * TL_PI * pow(0.02, 3), 1e-15);

  /* A snapshot of that world, into another world. */
  TlParticleWriter *w = NULL;
  TL_TEST_STATUS(tl_particle_writer_create("particle_files_out", "p", &w), TL_OK);
  TlParticleView view;
  tl_particle_view_of(P, &view);
  TL_TEST_STATUS(tl_particle_writer_write(w, 0, 0.0, &view), TL_OK);
  char path[512];
  snprintf(path, sizeof path, "%s", tl_particle_writer_last_path(w));
  tl_particle_writer_destroy(&w);
  TlDem *again = world(2);
  TL_TEST_STATUS(tl_dem_add_particles_from_file(again, path, -1, &n), TL_OK);
  TlParticles *Q = tl_dem_particles(again);
  TL_TEST_ASSERT(n == 5 && Q->n == 5, "%zu from the snapshot", n);
  for (size_t i = 0; i < Q->n && i < 5; ++i) {
    TL_TEST_ASSERT(Q->radius[i] == P->radius[i] && Q->x[i].x == P->x[i].x && Q->v[i].z == P->v[i].z &&
                       Q->species[i] == P->species[i],
                   "snapshot particle %zu differs", i);
  }
  tl_dem_destroy(&again);
  tl_dem_destroy(&dem);

  /* One species for all. */
  dem = world(1);
  TL_TEST_STATUS(tl_dem_add_particles_from_file(dem, "particles.data", 0, &n), TL_OK);
  P = tl_dem_particles(dem);
  int all0 = n == 5;
  for (size_t i = 0; i < P->n; ++i) all0 &= P->species[i] == 0;
  TL_TEST_ASSERT(all0, "every particle of species 0");
  tl_dem_destroy(&dem);

  /* Types the world lacks; a missing file. */
  dem = world(1);
  TL_TEST_STATUS(tl_dem_add_particles_from_file(dem, "particles.data", -1, &n), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "'particles.data', particle 2: atom type - 1 1 is not a species") &&
                     strstr(tl_error_message(), "it has 1"),
                 "%s", tl_error_message());
  TL_TEST_STATUS(tl_dem_add_particles_from_file(dem, "no_such.data", 0, &n), TL_ERR_IO);
  TL_TEST_ASSERT(strstr(tl_error_message(), "no_such.data"), "%s", tl_error_message());
  tl_dem_destroy(&dem);
  return tl_test_report();
}
