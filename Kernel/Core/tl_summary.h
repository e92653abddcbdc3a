/* The last line of every driver: "summary: key=value key=value ...", giving
 * its headline figures and wall time in a form scripts can parse. */
#ifndef TL_SUMMARY_H
#define TL_SUMMARY_H

#include <stdio.h>

typedef struct {
  char text[2048];
  size_t length;
} TlSummary;

void tl_summary_init(TlSummary *s);
void tl_summary_real(TlSummary *s, const char *key, double value);
void tl_summary_int(TlSummary *s, const char *key, long value);
void tl_summary_string(TlSummary *s, const char *key, const char *value);
void tl_summary_print(const TlSummary *s, FILE *out);

#endif
