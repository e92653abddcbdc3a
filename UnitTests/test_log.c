/* The logger's two channels and one level: what tl_printf (stdout) and
 * tl_warn/tl_info/tl_debug (stderr) print at each level, that the summary
 * and an error print at every level, and TALUS_LOG_LEVEL against an
 * explicit level. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "talus.h"
#include "tl_test.h"

/* Runs emit() with stdout and stderr sent to files, then reads them back. */
static void capture(void (*emit)(void), char *out, size_t n_out, char *err, size_t n_err)
{
  char po[] = "/tmp/talus_test_log_outXXXXXX", pe[] = "/tmp/talus_test_log_errXXXXXX";
  int fo = mkstemp(po), fe = mkstemp(pe);
  TL_TEST_ASSERT(fo >= 0 && fe >= 0, "temporary files");
  if (fo < 0 || fe < 0) return;
  fflush(stdout);
  fflush(stderr);
  int so = dup(STDOUT_FILENO), se = dup(STDERR_FILENO);
  dup2(fo, STDOUT_FILENO);
  dup2(fe, STDERR_FILENO);
  emit();
  fflush(stdout);
  fflush(stderr);
  dup2(so, STDOUT_FILENO);
  dup2(se, STDERR_FILENO);
  close(so);
  close(se);
  char *buf[2] = {out, err};
  size_t cap[2] = {n_out, n_err};
  int fd[2] = {fo, fe};
  for (int k = 0; k < 2; ++k) {
    lseek(fd[k], 0, SEEK_SET);
    ssize_t m = read(fd[k], buf[k], cap[k] - 1);
    buf[k][m > 0 ? m : 0] = '\0';
    close(fd[k]);
  }
  unlink(po);
  unlink(pe);
}

static void emit_all(void)
{
  tl_printf("report %d", 1);
  tl_printf(" continued\n");
  tl_info("library info");
  tl_warn("a warning");
  tl_debug("detail");
  tl_log(TL_LOG_ERROR, "an error");
  TlSummary s;
  tl_summary_init(&s);
  tl_summary_int(&s, "n", 3);
  tl_summary_print(&s, stdout);
}

int main(void)
{
  TlLogLevel before = tl_log_get_level();
  char out[4096], err[4096];

  tl_log_set_level(TL_LOG_ERROR);
  capture(emit_all, out, sizeof out, err, sizeof err);
  TL_TEST_ASSERT(strcmp(out, "summary: n=3 status=ok\n") == 0, "stdout at error: '%s'", out);
  TL_TEST_ASSERT(strcmp(err, "error: an error\n") == 0, "stderr at error: '%s'", err);

  tl_log_set_level(TL_LOG_WARN);
  capture(emit_all, out, sizeof out, err, sizeof err);
  TL_TEST_ASSERT(strcmp(out, "summary: n=3 status=ok\n") == 0, "stdout at warn: '%s'", out);
  TL_TEST_ASSERT(strcmp(err, "warning: a warning\nerror: an error\n") == 0, "stderr at warn: '%s'", err);

  tl_log_set_level(TL_LOG_INFO);
  capture(emit_all, out, sizeof out, err, sizeof err);
  TL_TEST_ASSERT(strcmp(out, "report 1 continued\nsummary: n=3 status=ok\n") == 0, "stdout at info: '%s'", out);
  TL_TEST_ASSERT(strcmp(err, "library info\nwarning: a warning\nerror: an error\n") == 0, "stderr at info: '%s'", err);

  tl_log_set_level(TL_LOG_DEBUG);
  capture(emit_all, out, sizeof out, err, sizeof err);
  TL_TEST_ASSERT(strcmp(out, "report 1 continued\nsummary: n=3 status=ok\n") == 0, "stdout at debug: '%s'", out);
  TL_TEST_ASSERT(strcmp(err, "library info\nwarning: a warning\ndebug: detail\nerror: an error\n") == 0,
                 "stderr at debug: '%s'", err);
  TL_TEST_ASSERT(tl_log_enabled(TL_LOG_DEBUG) && tl_log_enabled(TL_LOG_ERROR), "tl_log_enabled at debug");

  /* The environment sets the level when read; an explicit level then stays. */
  setenv("TALUS_LOG_LEVEL", "warn", 1);
  TL_TEST_ASSERT(tl_log_from_environment() == TL_LOG_WARN && !tl_log_enabled(TL_LOG_INFO), "TALUS_LOG_LEVEL=warn");
  tl_log_set_level(TL_LOG_INFO);
  TL_TEST_ASSERT(tl_log_get_level() == TL_LOG_INFO, "set after the environment: %d", (int)tl_log_get_level());
  unsetenv("TALUS_LOG_LEVEL");

  tl_log_set_level(before);
  return tl_test_report();
}
