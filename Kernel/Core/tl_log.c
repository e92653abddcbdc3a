#include "tl_log.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static int tl_log_level = -1; /* -1: not yet read from the environment */

static const char *const tl_log_names[] = {"error", "warn", "info", "debug"};

int tl_log_level_from_name(const char *name)
{
  for (int i = 0; i < 4; ++i)
    if (strcasecmp(name, tl_log_names[i]) == 0) return i;
  if (strcasecmp(name, "warning") == 0) return TL_LOG_WARN;
  return -1;
}

TlLogLevel tl_log_from_environment(void)
{
  const char *env = getenv("TALUS_LOG_LEVEL");
  int level = env && env[0] ? tl_log_level_from_name(env) : -1;
  tl_log_level = level >= 0 ? level : TL_LOG_INFO;
  if (env && env[0] && level < 0)
    fprintf(stderr, "warning: TALUS_LOG_LEVEL='%s' is not one of error|warn|info|debug: using info\n", env);
  return (TlLogLevel)tl_log_level;
}

TlLogLevel tl_log_get_level(void)
{
  if (tl_log_level < 0) return tl_log_from_environment();
  return (TlLogLevel)tl_log_level;
}

void tl_log_set_level(TlLogLevel level) { tl_log_level = (int)level; }

int tl_log_enabled(TlLogLevel level) { return (int)level <= (int)tl_log_get_level(); }

void tl_log(TlLogLevel level, const char *fmt, ...)
{
  if (!tl_log_enabled(level)) return;
  static const char *const prefix[] = {"error: ", "warning: ", "", "debug: "};
  va_list ap;
  va_start(ap, fmt);
  fputs(prefix[level], stderr);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
}

void tl_log_stdout(TlLogLevel level, const char *fmt, ...)
{
  if (!tl_log_enabled(level)) return;
  va_list ap;
  va_start(ap, fmt);
  vfprintf(stdout, fmt, ap);
  va_end(ap);
}
