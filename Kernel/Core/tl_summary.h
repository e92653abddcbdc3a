/* The last line of every driver: "summary: key=value key=value ...
 * status=ok", giving its headline figures and wall time in a form scripts
 * can parse, and how the run ended.
 *
 * Every run's last summary line carries status=: "ok" (exit 0), "undefined"
 * (exit 1: a figure could not be computed), and, printed by tl_driver_exit
 * when a run fails before or after its summary, "refused" (exit 2: an
 * option or input refused), "stopped" (exit 1: a physical diagnosis such as
 * a blow-up or the energy guard) or "failed" (exit 1: any other error), with
 * exit=<code> and error=<the status name>, so scripts need not read stderr.
 *
 * A summary never prints NaN: a figure that cannot be computed is recorded
 * with tl_summary_undefined() and the reason, printed as key=undefined, and
 * tl_summary_print() then names it with its reason on stderr and returns an
 * error, so that the run exits non-zero.  A non-finite value given to
 * tl_summary_real() is recorded the same way.
 *
 * The summary is the run's result, printed at every log level (tl_log.h):
 * with -log_level error a run that goes well prints this one line. */
#ifndef TL_SUMMARY_H
#define TL_SUMMARY_H

#include <stdio.h>

#include "tl_error.h"

typedef struct {
  char text[2048];
  size_t length;
  int n_undefined;
  char undefined[1024]; /* "key: reason; ..." */
} TlSummary;

void tl_summary_init(TlSummary *s);
void tl_summary_real(TlSummary *s, const char *key, double value);
void tl_summary_int(TlSummary *s, const char *key, long value);
void tl_summary_string(TlSummary *s, const char *key, const char *value);
/* A figure the run could not compute, with why (printf-style). */
void tl_summary_undefined(TlSummary *s, const char *key, const char *why_fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Prints the line (status=ok, or status=undefined exit=1); TL_ERR_NUMERIC
 * naming the undefined figures if any. */
TlStatus tl_summary_print(const TlSummary *s, FILE *out);
/* After a failed run (called by tl_driver_exit): prints
 * "summary: status=<word> exit=<code> error=<status>" unless the last
 * summary printed already reported this status.  Nothing for TL_OK and
 * TL_HELP. */
void tl_summary_end(TlStatus status, FILE *out);

#endif
