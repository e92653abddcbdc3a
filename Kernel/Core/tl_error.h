/* Status codes and the thread-local error message.
 *
 * Every fallible function returns a TlStatus.  The function that detects a
 * problem records a message naming the offending value with TL_ERROR; callers
 * propagate with TL_CHECK, which appends "at file:line" so the message reads as
 * a short trace.  The library never exits: drivers decide what to do. */
#ifndef TL_ERROR_H
#define TL_ERROR_H

#include <stddef.h>

typedef enum {
  TL_OK = 0,
  TL_ERR_ARG,         /* invalid argument or option value */
  TL_ERR_MEM,         /* allocation failed */
  TL_ERR_IO,          /* file could not be read or written */
  TL_ERR_FORMAT,      /* malformed input file */
  TL_ERR_NOT_FOUND,   /* name not registered, key absent */
  TL_ERR_NUMERIC,     /* NaN/Inf, singular matrix, inverted element */
  TL_ERR_UNSTABLE,    /* time step beyond the stability limit, blow-up */
  TL_ERR_CONVERGENCE, /* Newton or iterative solver did not converge */
  TL_ERR_STATE,       /* call out of life-cycle order */
  TL_ERR_UNSUPPORTED, /* feature not compiled in or not implemented for a type */
  TL_HELP             /* not an error: -help was given, the driver should exit 0 */
} TlStatus;

/* Records status and a printf-style message (replacing any previous one), and
 * returns status so it can be used as `return tl_error_set(...)`. */
TlStatus tl_error_set(TlStatus status, const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Appends a trace line "  at file:line" to the current message. */
TlStatus tl_error_trace(TlStatus status, const char *file, int line);
/* The current message of this thread ("" when none). */
const char *tl_error_message(void);
/* Clears the message of this thread. */
void tl_error_clear(void);
/* A short name of a status code ("invalid argument", ...). */
const char *tl_status_name(TlStatus status);

#define TL_ERROR(status, ...) return tl_error_set((status), __FILE__, __LINE__, __VA_ARGS__)

#define TL_CHECK(call)                                                                  \
  do {                                                                                  \
    TlStatus tl_check_s_ = (call);                                                      \
    if (tl_check_s_ != TL_OK) return tl_error_trace(tl_check_s_, __FILE__, __LINE__);   \
  } while (0)

/* For cleanup paths: evaluate call, on failure jump to label with `status` set. */
#define TL_CHECK_GOTO(status, call, label)                                              \
  do {                                                                                  \
    (status) = (call);                                                                  \
    if ((status) != TL_OK) {                                                            \
      tl_error_trace((status), __FILE__, __LINE__);                                     \
      goto label;                                                                       \
    }                                                                                   \
  } while (0)

#endif
