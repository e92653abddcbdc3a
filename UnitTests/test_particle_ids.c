/* Particles keep their identity in the output: the DEM renumbers its arrays
 * in grid order (tl_dem_set_sort_interval), and the id written in a
 * snapshot (HDF5 and the XDMF attribute ParaView's pathlines read) follows
 * the particle, with its species: each particle is recognised after the
 * sort by its own radius and position; the particle CSV
 * (tl_particle_writer_set_csv) carries the same ids. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

enum { N = 24 };

int main(void)
{
  tl_log_set_level(TL_LOG_ERROR);
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int a, b;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", 2500, 0.001, 0.02, &a), TL_OK);
  TL_TEST_STATUS(tl_particles_add_species(P, "b", 2500, 0.001, 0.02, &b), TL_OK);
  /* Inserted against the grid's order (x decreasing), each with its own
   * radius and a speed along x, alternately of species a and b. */
  double radius[N], x0[N];
  for (int k = 0; k < N; ++k) {
    radius[k] = 0.005 + 0.0001 * k;
    x0[k] = 0.05 * (N - 1 - k);
    TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(x0[k], 0.1 * (k % 3), 0), tl_v3(0.01 * k, 0, 0), radius[k],
                                       k % 2 ? b : a, NULL),
                   TL_OK);
  }
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e3, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  tl_dem_set_sort_interval(dem, 1);
  TL_TEST_STATUS(tl_dem_set_skin(dem, 0.0), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 1e-4, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TL_TEST_STATUS(tl_dem_step(dem, 10), TL_OK);
  int moved = 0;
  for (size_t i = 0; i < P->n; ++i) moved += P->id[i] != (int64_t)i;
  TL_TEST_ASSERT(moved > N / 2, "the sort renumbered %d of %d particles (the test needs a renumbering)", moved, N);

  TlParticleWriter *w = NULL;
  TL_TEST_STATUS(tl_particle_writer_create("particle_ids_out", "p", &w), TL_OK);
  tl_particle_writer_set_csv(w, 1);
  TlParticleView view;
  tl_particle_view_of(P, &view);
  TL_TEST_STATUS(tl_particle_writer_write(w, 10, tl_dem_time(dem), &view), TL_OK);
  char path[512];
  snprintf(path, sizeof path, "%s", tl_particle_writer_last_path(w));
  tl_particle_writer_destroy(&w);

  TlParticleSnapshot snap;
  TL_TEST_STATUS(tl_particle_snapshot_read(path, &snap), TL_OK);
  TL_TEST_ASSERT(snap.n == N && snap.id && snap.species, "snapshot of %zu particles, ids %s, species %s", snap.n,
                 snap.id ? "written" : "absent", snap.species ? "written" : "absent");
  if (snap.id && snap.species && snap.n == N) {
    int seen[N] = {0};
    double t = tl_dem_time(dem);
    for (size_t i = 0; i < snap.n; ++i) {
      int64_t id = snap.id[i];
      TL_TEST_ASSERT(id >= 0 && id < N, "id %lld in range", (long long)id);
      if (id < 0 || id >= N) continue;
      seen[id]++;
      /* the particle at row i is the one inserted as id: its radius, its
       * species, and where its speed has taken it (no contact: free flight) */
      TL_TEST_ASSERT(snap.radius[i] == radius[id], "row %zu, id %lld: radius %g, the id's %g", i, (long long)id,
                     snap.radius[i], radius[id]);
      TL_TEST_ASSERT(snap.species[i] == (id % 2 ? b : a), "row %zu, id %lld: species %d", i, (long long)id,
                     snap.species[i]);
      TL_TEST_CLOSE(snap.position[i].x, x0[id] + 0.01 * (double)id * t, 1e-12);
    }
    for (int k = 0; k < N; ++k) TL_TEST_ASSERT(seen[k] == 1, "id %d written %d times", k, seen[k]);
  }
  tl_particle_snapshot_free(&snap);

  /* The particle CSV beside it: the same rows, each with its id. */
  TlTable t;
  TL_TEST_STATUS(tl_table_read_csv("particle_ids_out/p_000000.csv", &t), TL_OK);
  TL_TEST_ASSERT(t.rows == N && t.cols == 9 && strcmp(t.names[0], "id") == 0 && strcmp(t.names[1], "species") == 0 &&
                     strcmp(t.names[5], "radius") == 0 && strcmp(t.units[5], "m") == 0,
                 "particle CSV: %zu rows, %zu columns", t.rows, t.cols);
  if (t.rows == N && t.cols == 9)
    for (size_t i = 0; i < t.rows; ++i) {
      int64_t id = (int64_t)t.data[9 * i];
      TL_TEST_ASSERT(id >= 0 && id < N && t.data[9 * i + 5] == radius[id] && t.data[9 * i + 1] == (id % 2 ? b : a),
                     "CSV row %zu: id %lld, radius %g", i, (long long)id, t.data[9 * i + 5]);
    }
  tl_table_free(&t);

  /* The XDMF series names the id and species arrays, so ParaView reads them
   * as point data. */
  char *xmf = tl_test_read_file("particle_ids_out/p.xmf");
  TL_TEST_ASSERT(xmf && strstr(xmf, "<Attribute Name=\"id\"") && strstr(xmf, ":/particles/id") &&
                     strstr(xmf, "Precision=\"8\"") && strstr(xmf, "<Attribute Name=\"species\""),
                 "XDMF:\n%s", xmf ? xmf : "(unreadable)");
  free(xmf);
  tl_dem_destroy(&dem);
  return tl_test_report();
}
