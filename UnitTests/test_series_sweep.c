/* A rerun into the same folder leaves no stale snapshots: a particle series
 * of 5 steps, then a second run of 2 steps under the same name in the same
 * folder; the second run's first step removes particles_000002..4.h5 (and
 * a stale extra mesh file), keeps its own two and every file of other
 * names or patterns.  A restarted series (steps loaded) keeps the files
 * before its next step. */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tl_particle_snapshot.h"
#include "tl_series_sweep.h"
#include "tl_test.h"
#include "tl_xdmf.h"

static const char *dir = "series_sweep_out";

static int exists(const char *name)
{
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return access(path, F_OK) == 0;
}

static void touch(const char *name)
{
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  TL_TEST_ASSERT(f != NULL, "cannot create %s", path);
  if (f) fclose(f);
}

static void run(int steps)
{
  enum { N = 3 };
  TlVec3 x[N] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  double r[N] = {0.5, 0.5, 0.5};
  TlParticleView pv = {.n = N, .position = x, .radius = r};
  TlParticleWriter *pw = NULL;
  TL_TEST_STATUS(tl_particle_writer_create(dir, "particles", &pw), TL_OK);
  for (int k = 0; pw && k < steps; ++k) TL_TEST_STATUS(tl_particle_writer_write(pw, k, 0.1 * k, &pv), TL_OK);
  tl_particle_writer_destroy(&pw);
}

int main(void)
{
  mkdir(dir, 0755);
  run(5);
  TL_TEST_ASSERT(exists("particles_000004.h5"), "the first run's last snapshot is missing");
  touch("particles_mesh_0001.h5");      /* a stale extra mesh file of the same series name */
  touch("particles_frozen_000003.h5");  /* another series whose name begins like this one */
  touch("particles_00003.h5");          /* not the 6-digit pattern */
  touch("grains_000007.h5");            /* another series */
  run(2);
  TL_TEST_ASSERT(exists("particles_000000.h5") && exists("particles_000001.h5"), "the second run's snapshots are missing");
  for (int k = 2; k < 5; ++k) {
    char name[64];
    snprintf(name, sizeof name, "particles_%06d.h5", k);
    TL_TEST_ASSERT(!exists(name), "stale %s left beside the new series", name);
  }
  TL_TEST_ASSERT(!exists("particles_mesh_0001.h5"), "stale mesh file left beside a new series");
  TL_TEST_ASSERT(exists("particles_frozen_000003.h5") && exists("particles_00003.h5") && exists("grains_000007.h5"),
                 "a file of another name or pattern was removed");
  /* a restarted series (3 steps loaded) keeps files 0..2 and the mesh files */
  touch("particles_000002.h5");
  touch("particles_000005.h5");
  touch("particles_mesh_0001.h5");
  char xmf[256];
  snprintf(xmf, sizeof xmf, "%s/particles.xmf", dir);
  size_t removed = 0;
  TL_TEST_STATUS(tl_series_sweep_stale(xmf, 3, 0, &removed), TL_OK);
  TL_TEST_ASSERT(removed == 1 && exists("particles_000002.h5") && !exists("particles_000005.h5") &&
                     exists("particles_mesh_0001.h5"),
                 "restarted series: removed %zu, expected only particles_000005.h5", removed);
  TL_TEST_STATUS(tl_series_sweep_stale("no_extension", 0, 1, &removed), TL_ERR_ARG);
  /* a fresh run with snapshots off removes the whole earlier series, its .xmf
   * and first mesh file included, and nothing of another name: here steps
   * 0-2, meshes 0-1 and the .xmf */
  touch("particles.xmf");
  touch("particles_mesh_0000.h5");
  TL_TEST_STATUS(tl_series_sweep_whole(dir, "particles", &removed), TL_OK);
  TL_TEST_ASSERT(removed == 6 && !exists("particles.xmf") && !exists("particles_000000.h5") &&
                     !exists("particles_000002.h5") && !exists("particles_mesh_0000.h5") &&
                     !exists("particles_mesh_0001.h5"),
                 "whole sweep: removed %zu of the 6 files of the earlier series (steps 0-2, meshes 0-1, .xmf)", removed);
  TL_TEST_ASSERT(exists("particles_frozen_000003.h5") && exists("particles_00003.h5") && exists("grains_000007.h5"),
                 "the whole sweep removed a file of another name or pattern");
  TL_TEST_STATUS(tl_series_sweep_whole(dir, "particles", &removed), TL_OK);
  TL_TEST_ASSERT(removed == 0, "a second whole sweep removed %zu files", removed);
  return tl_test_report();
}
