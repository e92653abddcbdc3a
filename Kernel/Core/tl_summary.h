/* The last line of every driver: "summary: key=value key=value ...", giving
 * its headline figures and wall time in a form scripts can parse.
 *
 * A summary never prints NaN: a figure that cannot be computed is recorded
 * with tl_summary_undefined() and the reason, printed as key=undefined, and
 * tl_summary_print() then names it with its reason on stderr and returns an
 * error, so that the run exits non-zero.  A non-finite value given to
 * tl_summary_real() is recorded the same way. */
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
/* Prints the line; TL_ERR_NUMERIC naming the undefined figures if any. */
TlStatus tl_summary_print(const TlSummary *s, FILE *out);

#endif
