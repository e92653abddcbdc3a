/* Inputs the checkpoint fuzz harness (Fuzz/fuzz_checkpoint.c) found, each
 * replayed on the harness's world: the edits of the finding applied to a
 * memory checkpoint, which must then be refused with a message (not hang,
 * not crash).
 *  - timeout-553ba857: the neighbour-list build positions x_build[...] =
 *    -1.14669e308 (finite) in a 1 cm periodic cell: in cell lengths the
 *    position overflowed to -inf and the grid enlarged its cells forever.
 *  - a position of the same size: x.z = -1e308 along the open direction
 *    loads (it is finite) and must stop the first step's grid build by name
 *    (there the step has made it -inf), not hang it.
 * An alarm ends the test if a load or step hangs again. */
#include <signal.h>
#include <string.h>
#include <unistd.h>

#include "talus.h"
#include "tl_checkpoint.h"
#include "tl_dem.h"
#include "tl_test.h"
#include "../Fuzz/fuzz_checkpoint_world.h" /* the harness's own world */


/* Sets element k of the double entry at path; 0 when there is none. */
static int set_double(TlCheckpointMemory *mem, const char *path, size_t k, double v)
{
  for (size_t i = 0; i < tl_checkpoint_memory_count(mem); ++i) {
    TlCheckpointEntry e;
    if (tl_checkpoint_memory_entry(mem, i, &e) != TL_OK) return 0;
    if (strcmp(e.path, path) == 0 && e.kind == 'd' && k < e.n) {
      ((double *)e.data)[k] = v;
      return 1;
    }
  }
  return 0;
}

/* Loads mem into a fresh world and steps it: the status of the first
 * failure, its message in msg. */
static TlStatus load_and_step(const TlCheckpointMemory *mem, char *msg, size_t len)
{
  TlDem *dem = NULL;
  TlStatus s = fuzz_checkpoint_world(&dem);
  if (s == TL_OK) s = tl_checkpoint_memory_load(mem, &tl_dem_checkpoint_ops, dem);
  if (s == TL_OK) s = tl_dem_step(dem, 3);
  snprintf(msg, len, "%s", s == TL_OK ? "" : tl_error_message());
  tl_dem_destroy(&dem);
  return s;
}

int main(void)
{
  alarm(60);
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  tl_log_set_level(TL_LOG_ERROR);
  TlDem *dem = NULL;
  TlCheckpointMemory *good = NULL, *edited = NULL;
  TL_TEST_STATUS(fuzz_checkpoint_world(&dem), TL_OK);
  if (!dem) return tl_test_report();
  TL_TEST_STATUS(tl_dem_step(dem, 200), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_memory_create(&good), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_memory_create(&edited), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_memory_save(good, &tl_dem_checkpoint_ops, dem), TL_OK);
  tl_dem_destroy(&dem);
  char msg[2048];

  /* unchanged: loads and steps (the checks below could fail) */
  TL_TEST_STATUS(tl_checkpoint_memory_copy(edited, good), TL_OK);
  TlStatus s = load_and_step(edited, msg, sizeof msg);
  TL_TEST_ASSERT(s == TL_OK, "the unchanged checkpoint: status %d, '%s'", (int)s, msg);

  /* the finding: element 28262 % 24 = 14 of x_build, particle 4's z */
  TL_TEST_STATUS(tl_checkpoint_memory_copy(edited, good), TL_OK);
  TL_TEST_ASSERT(set_double(edited, "/x_build", 28262 % 24, -1.14669e308), "no /x_build of 24 doubles");
  s = load_and_step(edited, msg, sizeof msg);
  TL_TEST_ASSERT(s != TL_OK && strstr(msg, "beyond the range of a double"),
                 "x_build z = -1.14669e308: status %d, '%s'", (int)s, msg);

  /* the same overflow from a position along the open direction */
  TL_TEST_STATUS(tl_checkpoint_memory_copy(edited, good), TL_OK);
  TL_TEST_ASSERT(set_double(edited, "/particles/x", 3 * 5 + 2, -1e308), "no /particles/x");
  s = load_and_step(edited, msg, sizeof msg);
  TL_TEST_ASSERT(s != TL_OK && strstr(msg, "grid: particle 5"), "x z = -1e308: status %d, '%s'", (int)s, msg);

  tl_checkpoint_memory_destroy(&good);
  tl_checkpoint_memory_destroy(&edited);
  return tl_test_report();
}
