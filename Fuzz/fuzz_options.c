/* libFuzzer harness of the options parser: the input is read both as an
 * options file (-options_file) and, split at newlines, spaces and NULs, as a
 * command line; then every getter reads the options a driver would. */
#include <string.h>

#include "fuzz_common.h"

static void query(TlOptions *o)
{
  double r, list[8];
  long n;
  int b, count, choice;
  const char *s;
  static const char *const modes[] = {"pulse", "cosine", NULL};
  static const TlScale scales[] = {{"d", 1e-3, "diameters"}};
  (void)tl_options_get_real(o, "-E", 1e8, 0.0, INFINITY, "Pa", "modulus", &r);
  (void)tl_options_get_real(o, "-dt", 1e-5, -1.0, 1.0, "s", "step", &r);
  (void)tl_options_get_int(o, "-n", 10, 0, 1000, "count", &n);
  (void)tl_options_get_bool(o, "-flag", 0, "a flag", &b);
  (void)tl_options_get_string(o, "-output_dir", "out", "folder", &s);
  (void)tl_options_get_choice(o, "-mode", "pulse", modes, "mode", &choice);
  (void)tl_options_get_scaled(o, "-width", "2d", 0.0, 10.0, "m", scales, 1, "width", &r);
  (void)tl_options_get_real_list(o, "-snapshots", "0.03,0.05", "s", "times", list, 8, &count);
  (void)tl_options_has(o, "-restart");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  tl_fuzz_init();
  /* as a file */
  const char *path = tl_fuzz_file("fuzz_options", data, size);
  if (path) {
    const char *argv[] = {"prog", "-options_file", path};
    TlOptions *o = NULL;
    if (tl_options_create(3, (char **)argv, "fuzz", &o) == TL_OK) query(o);
    tl_options_destroy(&o);
  }
  /* as a command line */
  if (size > 4096) return 0;
  char *text = malloc(size + 1);
  if (!text) return 0;
  memcpy(text, data, size);
  text[size] = '\0';
  char *argv[512];
  int argc = 0;
  argv[argc++] = "prog";
  for (char *p = text, *end = text + size; p < end && argc < 511;) {
    while (p < end && (*p == '\0' || *p == '\n' || *p == ' ')) *p++ = '\0';
    if (p >= end) break;
    argv[argc++] = p;
    while (p < end && *p != '\0' && *p != '\n' && *p != ' ') ++p;
  }
  argv[argc] = NULL;
  TlOptions *o = NULL;
  if (tl_options_create(argc, argv, "fuzz", &o) == TL_OK) query(o);
  tl_options_destroy(&o);
  free(text);
  return 0;
}
