/* libFuzzer harness of the checkpoint loader, on a DEM world (particles in
 * a periodic box on a plane floor) in two ways:
 *  - an input that starts with the seal's magic is a whole checkpoint file:
 *    loaded as it stands (the seal must refuse what was damaged);
 *  - any other input is a list of edits of 12 bytes (entry, kind, element,
 *    8 bytes of value) applied to a good checkpoint of the world held in
 *    memory, which is then loaded: the module's checks must refuse every
 *    value the world cannot use, and a world that loads must step.
 * The edits go to a memory checkpoint (tl_checkpoint_memory_*) rather than
 * through HDF5 into a file: the module's load() sees the same values through
 * the same reader (its checks are the target), at some 50 times the rate (a
 * file cost two HDF5 opens, a seal and four lookups per dataset, ~15 ms an
 * input under ASan); the whole-file inputs keep the file path fuzzed.
 * The good checkpoint is made at start-up. */
#include <string.h>

#include "fuzz_checkpoint_world.h"
#include "fuzz_common.h"
#include "tl_contact_law.h"
#include "tl_dem.h"


/* A file: through the seal, HDF5 and the reader into the module. */
static TlStatus load_file(const char *path)
{
  TlDem *dem = NULL;
  TlCheckpoint *cp = NULL;
  TlStatus s = fuzz_checkpoint_world(&dem);
  if (s == TL_OK) s = tl_checkpoint_create(&cp);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem);
  if (s == TL_OK) s = tl_checkpoint_load(cp, path, NULL, NULL);
  if (s == TL_OK) s = tl_dem_step(dem, 3);
  tl_checkpoint_destroy(&cp);
  tl_dem_destroy(&dem);
  return s;
}

static TlStatus load_memory(const TlCheckpointMemory *mem)
{
  TlDem *dem = NULL;
  TlStatus s = fuzz_checkpoint_world(&dem);
  if (s == TL_OK) s = tl_checkpoint_memory_load(mem, &tl_dem_checkpoint_ops, dem);
  if (s == TL_OK) s = tl_dem_step(dem, 3);
  tl_dem_destroy(&dem);
  return s;
}

static TlCheckpointMemory *good, *edited;
static void release(void)
{
  tl_checkpoint_memory_destroy(&good);
  tl_checkpoint_memory_destroy(&edited);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc, (void)argv;
  tl_fuzz_init();
  TlDem *dem = NULL;
  if (fuzz_checkpoint_world(&dem) != TL_OK || tl_dem_step(dem, 200) != TL_OK || tl_checkpoint_memory_create(&good) != TL_OK ||
      tl_checkpoint_memory_create(&edited) != TL_OK ||
      tl_checkpoint_memory_save(good, &tl_dem_checkpoint_ops, dem) != TL_OK || tl_checkpoint_memory_count(good) == 0)
    abort();
  tl_dem_destroy(&dem);
  atexit(release);
  return 0;
}

/* Edit r of the input: entry data[r] (modulo the count), element data[r+2..3]
 * (modulo its length), value the 8 bytes data[r+4..11]; data[r+1] & 1 puts an
 * integer's value into a double (the bits otherwise).  Bytes and strings get
 * the value's bytes at that offset (a string keeps its terminating NUL). */
static void edit(TlCheckpointMemory *mem, const uint8_t *data)
{
  TlCheckpointEntry e;
  if (tl_checkpoint_memory_entry(mem, data[0] % tl_checkpoint_memory_count(mem), &e) != TL_OK) abort();
  const int as_int = data[1] & 1;
  const size_t k = (size_t)data[2] | (size_t)data[3] << 8;
  uint64_t bits;
  memcpy(&bits, data + 4, 8);
  if (e.kind == 'd' && e.n > 0) {
    double v;
    if (as_int) v = (double)(int64_t)bits;
    else memcpy(&v, &bits, 8);
    memcpy((double *)e.data + k % e.n, &v, 8);
  } else if (e.kind == 'i' && e.n > 0) {
    memcpy((int64_t *)e.data + k % e.n, &bits, 8);
  } else if (e.kind == 'b' || e.kind == 's') {
    size_t len = e.kind == 'b' ? e.n : strlen(e.data), m = len < 8 ? len : 8;
    if (m > 0) memcpy((char *)e.data + k % (len - m + 1), &bits, m);
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static const char magic[] = "talus-seal-1";
  if (size >= sizeof magic - 1 && memcmp(data, magic, sizeof magic - 1) == 0) {
    const char *path = tl_fuzz_file("fuzz_ckpt", data, size);
    if (path) (void)load_file(path);
    return 0;
  }
  if (tl_checkpoint_memory_copy(edited, good) != TL_OK) abort();
  for (size_t r = 0; r + 12 <= size && r < 12 * 16; r += 12) edit(edited, data + r);
  (void)load_memory(edited);
  return 0;
}
