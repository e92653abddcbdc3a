#include "tl_error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

enum { TL_ERROR_CAPACITY = 4096 };

static _Thread_local char tl_message[TL_ERROR_CAPACITY];

static const char *tl_basename(const char *path)
{
  const char *slash = strrchr(path, '/');
  return slash ? slash + 1 : path;
}

TlStatus tl_error_set(TlStatus status, const char *file, int line, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(tl_message, sizeof tl_message, fmt, ap);
  va_end(ap);
  if (n >= 0 && (size_t)n < sizeof tl_message)
    snprintf(tl_message + n, sizeof tl_message - (size_t)n, "\n  at %s:%d", tl_basename(file), line);
  return status;
}

TlStatus tl_error_trace(TlStatus status, const char *file, int line)
{
  size_t n = strlen(tl_message);
  if (n == 0) /* a status returned without a message: say at least what it was */
    n = (size_t)snprintf(tl_message, sizeof tl_message, "%s", tl_status_name(status));
  if (n < sizeof tl_message)
    snprintf(tl_message + n, sizeof tl_message - n, "\n  at %s:%d", tl_basename(file), line);
  return status;
}

const char *tl_error_message(void) { return tl_message; }

void tl_error_clear(void) { tl_message[0] = '\0'; }

const char *tl_status_name(TlStatus status)
{
  switch (status) {
  case TL_OK: return "ok";
  case TL_ERR_ARG: return "invalid argument";
  case TL_ERR_MEM: return "out of memory";
  case TL_ERR_IO: return "input/output error";
  case TL_ERR_FORMAT: return "malformed input";
  case TL_ERR_NOT_FOUND: return "not found";
  case TL_ERR_NUMERIC: return "numerical error";
  case TL_ERR_UNSTABLE: return "unstable";
  case TL_ERR_CONVERGENCE: return "no convergence";
  case TL_ERR_STATE: return "invalid state";
  case TL_ERR_UNSUPPORTED: return "unsupported";
  case TL_HELP: return "help requested";
  }
  return "unknown status";
}
