#include "tl_output_dir.h"

#include <stdio.h>
#include <string.h>

#include "tl_atomic_file.h"
#include "tl_log.h"
#include "tl_memory.h"

TlStatus tl_output_dir_check(const char *dir)
{
  if (!dir || !dir[0])
    TL_ERROR(TL_ERR_ARG, "option -output_dir '': empty folder name (give the folder the output files go to)");
  return TL_OK;
}

TlStatus tl_output_dir_prepare(const char *dir)
{
  TL_CHECK(tl_output_dir_check(dir));
  TL_CHECK(tl_mkdir_p(dir));
  size_t removed = 0;
  TL_CHECK(tl_atomic_remove_stale(dir, &removed));
  if (removed) tl_info("removed %zu stale temporary file%s of killed writes from %s", removed, removed > 1 ? "s" : "", dir);
  return TL_OK;
}

TlStatus tl_output_dir(TlOptions *options, char **dir)
{
  *dir = NULL;
  char def[512];
  const char *program = tl_options_program(options);
  snprintf(def, sizeof def, "results/%s", program && program[0] ? program : "talus");
  const char *value;
  TL_CHECK(tl_options_begin_group(options, "Output"));
  TlStatus sg = tl_options_get_string(options, "-output_dir", def, "folder for every output file", &value);
  tl_options_end_group(options);
  TL_CHECK(sg);
  TL_CHECK(tl_output_dir_check(value));
  size_t n = strlen(value);
  TL_CHECK(tl_calloc(dir, n + 1, 1));
  memcpy(*dir, value, n);
  TlStatus s = tl_output_dir_prepare(*dir);
  if (s != TL_OK) {
    tl_free(dir);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}
