/* Shared by the fuzz harnesses: the readers take a path, so each input is
 * written to a file of this process (in the working folder) first. */
#ifndef TL_FUZZ_COMMON_H
#define TL_FUZZ_COMMON_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "talus.h"

static char tl_fuzz_path[256];
static void tl_fuzz_remove(void) { unlink(tl_fuzz_path); }

/* Writes the input to "<stem>.<pid>" and returns that name (static; removed
 * at exit). */
static const char *tl_fuzz_file(const char *stem, const uint8_t *data, size_t size)
{
  char *path = tl_fuzz_path;
  if (!path[0]) atexit(tl_fuzz_remove);
  snprintf(path, sizeof tl_fuzz_path, "%s.%ld", stem, (long)getpid());
  FILE *f = fopen(path, "wb");
  if (!f) return NULL;
  if (size) fwrite(data, 1, size, f);
  fclose(f);
  return path;
}

/* Once per process: the registry (element types, laws) and quiet logs. */
static void tl_fuzz_init(void)
{
  static int done;
  if (done) return;
  done = 1;
  if (tl_initialize() != TL_OK) abort();
  tl_log_set_level(TL_LOG_ERROR);
}

#endif
