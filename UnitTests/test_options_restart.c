/* The options as a checkpoint section: a restart with the same options, or
 * with only restart-safe ones changed (end time, output folder, a driver's
 * own safe option), loads; one with another physical value (-E, a count, a
 * choice, a flag), one that drops or adds an option, is refused naming the
 * option and both values.  Equal values written differently (1e8 and
 * 100000000) are the same value. */
#include <string.h>

#include "talus.h"
#include "tl_options_checkpoint.h"
#include "tl_test.h"

/* What a driver asks for; `extra` adds an option the first run did not have. */
static TlStatus parse(int argc, char **argv, int extra, TlOptions **o)
{
  TL_CHECK(tl_options_create(argc, argv, "restart test", o));
  double E, t_end;
  long n;
  int flag, choice;
  const char *dir;
  static const char *const laws[] = {"linear", "hertz", NULL};
  TL_CHECK(tl_options_get_real(*o, "-E", 1e8, 0.0, 1e15, "Pa", "modulus", &E));
  TL_CHECK(tl_options_get_int(*o, "-n", 300, 1, 100000, "count", &n));
  TL_CHECK(tl_options_get_bool(*o, "-one_way", 0, "flag", &flag));
  TL_CHECK(tl_options_get_choice(*o, "-contact", "linear", laws, "law", &choice));
  TL_CHECK(tl_options_get_real(*o, "-t_end", 1.0, 0.0, 1e6, "s", "end", &t_end));
  TL_CHECK(tl_options_get_real(*o, "-periods", 3.0, 0.0, 1e6, "", "driver's own safe option", &t_end));
  TL_CHECK(tl_options_get_string(*o, "-output_dir", "out", "folder", &dir));
  if (extra) TL_CHECK(tl_options_get_real(*o, "-new_physics", 1.0, 0.0, 2.0, "", "added later", &E));
  TL_CHECK(tl_options_set_restart_safe(*o, "-periods"));
  return tl_options_finish(*o, stdout);
}

/* Saves the options of argv_a, then loads them into a run with argv_b. */
static TlStatus restart(char **argv_a, int argc_a, char **argv_b, int argc_b, int extra_b, const char *path)
{
  TlOptions *a = NULL, *b = NULL;
  TlCheckpoint *cp = NULL;
  TlStatus s = parse(argc_a, argv_a, 0, &a);
  if (s == TL_OK) s = tl_checkpoint_create(&cp);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, a);
  if (s == TL_OK) s = tl_checkpoint_save(cp, path, 0.0, 0);
  tl_checkpoint_destroy(&cp);
  if (s == TL_OK) s = parse(argc_b, argv_b, extra_b, &b);
  if (s == TL_OK) s = tl_checkpoint_create(&cp);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, b);
  if (s == TL_OK) s = tl_checkpoint_load(cp, path, NULL, NULL);
  tl_checkpoint_destroy(&cp);
  tl_options_destroy(&a);
  tl_options_destroy(&b);
  return s;
}

#define N(a) ((int)(sizeof(a) / sizeof((a)[0])))

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const char *path = "test_options_restart.h5";
  char *base[] = {"drv", "-E", "1e8", "-n", "300", "-contact", "hertz"};
  char *same[] = {"drv", "-E", "100000000", "-n", "300", "-contact", "hertz", "-one_way", "false"};
  char *safe[] = {"drv", "-E", "1e8", "-n", "300", "-contact", "hertz", "-t_end", "5", "-periods", "7",
                  "-output_dir", "elsewhere"};
  TL_TEST_STATUS(restart(base, N(base), same, N(same), 0, path), TL_OK);
  TL_TEST_STATUS(restart(base, N(base), safe, N(safe), 0, path), TL_OK);

  char *other_E[] = {"drv", "-E", "2e8", "-n", "300", "-contact", "hertz"};
  TL_TEST_STATUS(restart(base, N(base), other_E, N(other_E), 0, path), TL_ERR_ARG);
  const char *msg = tl_error_message();
  TL_TEST_ASSERT(strstr(msg, "restart with -E 200000000, but the checkpoint was made with -E 100000000") != NULL,
                 "message '%s'", msg);
  char *other_n[] = {"drv", "-E", "1e8", "-n", "301", "-contact", "hertz"};
  TL_TEST_STATUS(restart(base, N(base), other_n, N(other_n), 0, path), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "-n 301") && strstr(tl_error_message(), "-n 300"), "message '%s'",
                 tl_error_message());
  char *other_law[] = {"drv", "-E", "1e8", "-n", "300"};
  TL_TEST_STATUS(restart(base, N(base), other_law, N(other_law), 0, path), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "-contact linear") != NULL, "message '%s'", tl_error_message());
  char *flag[] = {"drv", "-E", "1e8", "-n", "300", "-contact", "hertz", "-one_way"};
  TL_TEST_STATUS(restart(base, N(base), flag, N(flag), 0, path), TL_ERR_ARG);
  /* the continuing run has an option the checkpoint does not record */
  TL_TEST_STATUS(restart(base, N(base), base, N(base), 1, path), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "-new_physics") != NULL, "message '%s'", tl_error_message());
  remove(path);
  return tl_test_report();
}
