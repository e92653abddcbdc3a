/* libFuzzer harness of the checkpoint loader, on a DEM world (particles in
 * a periodic box on a plane floor) in two ways:
 *  - an input that starts with the seal's magic is a whole checkpoint file:
 *    loaded as it stands (the seal must refuse what was damaged);
 *  - any other input is a list of edits of 12 bytes (dataset, kind, element,
 *    8 bytes of value) applied through HDF5 to a good checkpoint, which is
 *    then resealed and loaded: the module's checks must refuse every value
 *    the world cannot use, and a world that loads must step.
 * The good checkpoint is written at start-up. */
#include <hdf5.h>
#include <string.h>

#include "fuzz_common.h"
#include "tl_contact_law.h"
#include "tl_dem.h"
#include "tl_hdf5_util.h"

static TlStatus build(TlDem **out)
{
  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  const double L = 0.01;
  TlDomain dom;
  int per[3] = {1, 1, 0};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, -0.002), tl_v3(L, L, 0.03), per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "glass", 2500, 0.0014, 0.0016, &sp));
  for (int k = 0; k < 8; ++k) {
    TlVec3 x = tl_v3((k % 2 + 0.5) * L / 2, (k / 2 % 2 + 0.5) * L / 2, 0.0016 + 0.0033 * (k / 4));
    TL_CHECK(tl_dem_add_particle(dem, x, tl_v3(0, 0, -0.1), 0.0015, sp, NULL));
  }
  TlContactLaw *law = NULL;
  TL_CHECK(tl_contact_law_create("linear", "coulomb", "constant", "constant", &law));
  TL_CHECK(tl_contact_law_set(law, "k_n", 200.0));
  TL_CHECK(tl_contact_law_set(law, "mu", 0.4));
  TL_CHECK(tl_contact_law_setup(law));
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

static TlStatus load(const char *path)
{
  TlDem *dem = NULL;
  TlCheckpoint *cp = NULL;
  TlStatus s = build(&dem);
  if (s == TL_OK) s = tl_checkpoint_create(&cp);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem);
  if (s == TL_OK) s = tl_checkpoint_load(cp, path, NULL, NULL);
  if (s == TL_OK) s = tl_dem_step(dem, 3);
  tl_checkpoint_destroy(&cp);
  tl_dem_destroy(&dem);
  return s;
}

/* The numeric datasets of the good file, in visiting order. */
static char names[256][128];
static int n_names;

static herr_t collect(hid_t obj, const char *name, const H5O_info_t *info, void *ctx)
{
  (void)ctx;
  if (info->type != H5O_TYPE_DATASET || n_names >= 256) return 0;
  hid_t d = H5Dopen2(obj, name, H5P_DEFAULT);
  hid_t t = H5Dget_type(d);
  H5T_class_t c = H5Tget_class(t);
  if ((c == H5T_FLOAT || c == H5T_INTEGER) && strlen(name) + 2 < sizeof names[0])
    snprintf(names[n_names++], sizeof names[0], "/%s", name);
  H5Tclose(t);
  H5Dclose(d);
  return 0;
}

static char good[64], edited[64];
static void remove_files(void)
{
  unlink(good);
  unlink(edited);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc, (void)argv;
  tl_fuzz_init();
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  snprintf(good, sizeof good, "fuzz_ckpt_good.%ld", (long)getpid());
  snprintf(edited, sizeof edited, "fuzz_ckpt_edit.%ld", (long)getpid());
  atexit(remove_files);
  TlDem *dem = NULL;
  TlCheckpoint *cp = NULL;
  if (build(&dem) != TL_OK || tl_dem_step(dem, 200) != TL_OK || tl_checkpoint_create(&cp) != TL_OK ||
      tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem) != TL_OK ||
      tl_checkpoint_save(cp, good, tl_dem_time(dem), 200) != TL_OK)
    abort();
  tl_checkpoint_destroy(&cp);
  tl_dem_destroy(&dem);
  hid_t f = H5Fopen(good, H5F_ACC_RDONLY, H5P_DEFAULT);
  H5Ovisit(f, H5_INDEX_NAME, H5_ITER_NATIVE, collect, NULL);
  H5Fclose(f);
  if (n_names == 0) abort();
  return 0;
}

static void copy(const char *from, const char *to)
{
  FILE *a = fopen(from, "rb"), *b = fopen(to, "wb");
  char buf[65536];
  size_t n;
  while (a && b && (n = fread(buf, 1, sizeof buf, a)) > 0) fwrite(buf, 1, n, b);
  if (a) fclose(a);
  if (b) fclose(b);
}

static void edit(const char *path, const uint8_t *data, size_t size)
{
  hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
  if (f < 0) return;
  for (size_t r = 0; r + 12 <= size && r < 12 * 16; r += 12) {
    const char *name = names[data[r] % n_names];
    int as_int = data[r + 1] & 1;
    size_t k = (size_t)data[r + 2] | (size_t)data[r + 3] << 8;
    uint64_t bits;
    memcpy(&bits, data + r + 4, 8);
    hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
    if (d < 0) continue;
    hid_t sp = H5Dget_space(d);
    hssize_t n = H5Sget_simple_extent_npoints(sp);
    H5Sclose(sp);
    hid_t type = as_int ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE;
    uint64_t *buf = n > 0 ? calloc((size_t)n, 8) : NULL;
    if (buf && H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) >= 0) {
      buf[k % (size_t)n] = bits;
      H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
    }
    free(buf);
    H5Dclose(d);
  }
  H5Fclose(f);
  tl_h5_seal(path);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static const char magic[] = "talus-seal-1";
  if (size >= sizeof magic - 1 && memcmp(data, magic, sizeof magic - 1) == 0) {
    const char *path = tl_fuzz_file("fuzz_ckpt", data, size);
    if (path) (void)load(path);
    return 0;
  }
  copy(good, edited);
  edit(edited, data, size);
  (void)load(edited);
  return 0;
}
