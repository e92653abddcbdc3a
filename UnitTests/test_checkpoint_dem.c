/* A DEM checkpoint with one value changed is refused on load, with a message
 * naming the value, before the world uses it (it used to crash the wall
 * bins, the contact sort or the grid, hang the grid's cell-size loop, or run
 * time backwards):
 *  - a NaN velocity, an infinite position (1.8e308 in a text file), a
 *    position far outside the periodic cell, a negative radius, a mass that
 *    disagrees with its inverse;
 *  - a negative contact count, a negative touching count, a negative step
 *    count, particle and contact counts beyond the stored arrays (they
 *    sized allocations of tens of GB);
 *  - a negative time step, a time step above the critical one, a NaN time;
 *  - a flipped byte in a dataset's stored data: the whole-file checksum
 *    refuses it, and with that renewed, the dataset's Fletcher32 checksum.
 * The unchanged file loads.  Each change is written with HDF5 itself (so the
 * checksum is recomputed: the loader's checks, not the checksum, catch it). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_checkpoint.h"
#include "tl_dem.h"
#include "tl_test.h"
#include "tl_test_dem.h"
#include "tl_test_h5.h"

static TlStatus build(TlDem **out)
{
  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  const TlTestColumn column = {.L = 0.02, .n = 50, .r_min = 0.0014, .r_max = 0.0016, .z0 = 0.0017, .dz = 0.0033,
                               .v_z = -0.1, .seed = 77};
  TL_CHECK(tl_test_dem_column(dem, &column, NULL));
  TlContactLaw *law = NULL;
  TL_CHECK(tl_test_law(&law, "linear", "k_n", 200.0, "restitution", 0.3, "mu", 0.4, NULL));
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

/* Loads `file` into a freshly built world; returns the status. */
static TlStatus load(const char *file)
{
  TlDem *dem = NULL;
  TlCheckpoint *cp = NULL;
  TlStatus s = build(&dem);
  if (s == TL_OK) s = tl_checkpoint_create(&cp);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem);
  double t = 0;
  int64_t step = 0;
  if (s == TL_OK) s = tl_checkpoint_load(cp, file, &t, &step);
  /* a loaded world must also step */
  if (s == TL_OK) s = tl_dem_step(dem, 5);
  tl_checkpoint_destroy(&cp);
  tl_dem_destroy(&dem);
  return s;
}

static void refused(const char *dataset, size_t k, double value, int is_int, const char *fragment)
{
  tl_test_h5_refused(load, dataset, k, value, is_int, fragment);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  TlDem *dem = NULL;
  TlCheckpoint *cp = NULL;
  TL_TEST_STATUS(build(&dem), TL_OK);
  if (!dem) return tl_test_report();
  TL_TEST_STATUS(tl_dem_step(dem, 400), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, "good.h5", tl_dem_time(dem), 400), TL_OK);
  tl_checkpoint_destroy(&cp);
  tl_dem_destroy(&dem);

  TL_TEST_STATUS(load("good.h5"), TL_OK);
  refused("/dem/particles/v", 5, NAN, 0, "dem/particles/v[5] = nan is not a finite number");
  refused("/dem/particles/x", 0, INFINITY, 0, "dem/particles/x[0] = inf is not a finite number");
  refused("/dem/particles/x", 3, 1e300, 0, "periodic direction 0");
  refused("/dem/particles/radius", 3, -0.001, 0, "dem/particles/radius[3] = -0.001");
  refused("/dem/particles/mass", 7, 1.0, 0, "particle 7 has mass 1");
  refused("/dem/contacts/n", 0, -5, 1, "dem/contacts/n = -5 outside");
  refused("/dem/n_touching", 0, -1, 1, "n_touching");
  /* counts that used to size allocations of tens of GB (found by fuzzing) */
  refused("/dem/contacts/n", 0, 4e9, 1, "dem/contacts/n = 4000000000 does not match the stored force");
  refused("/dem/particles/n", 0, 4e9, 1, "dem/particles/n = 4000000000 does not match the stored x");
  refused("/dem/dt", 0, -4e-5, 0, "dem/dt = -4e-05 outside");
  refused("/dem/dt", 0, 1.0, 0, "exceeds the critical time step");
  refused("/dem/t", 0, NAN, 0, "dem/t = nan");
  refused("/dem/steps", 0, -3, 1, "dem/steps = -3");

  /* A flipped byte in stored data: the checksum. */
  /* A flipped byte in stored data: the whole-file checksum refuses it; with
   * that checksum renewed, the dataset's Fletcher32 checksum does. */
  tl_test_copy_file("good.h5", "flipped.h5");
  int flipped = tl_test_flip_stored_byte("flipped.h5", "/dem/particles/v");
  TL_TEST_ASSERT(flipped, "cannot locate the stored data of /dem/particles/v (not chunked?)");
  if (flipped) {
    TlStatus s = load("flipped.h5");
    TL_TEST_ASSERT(s != TL_OK && strstr(tl_error_message(), "flipped.h5' is corrupted"),
                   "a flipped byte: status %d, message '%s'", (int)s, tl_error_message());
    TL_TEST_STATUS(tl_h5_seal("flipped.h5"), TL_OK);
    s = load("flipped.h5");
    TL_TEST_ASSERT(s != TL_OK && strstr(tl_error_message(), "dem/particles/v") && strstr(tl_error_message(), "checksum"),
                   "a flipped byte, resealed: status %d, message '%s'", (int)s, tl_error_message());
  }
  return tl_test_report();
}
