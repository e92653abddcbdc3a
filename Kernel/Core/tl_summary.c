#include "tl_summary.h"

#include <stdarg.h>
#include <string.h>

void tl_summary_init(TlSummary *s)
{
  s->text[0] = '\0';
  s->length = 0;
}

static void tl_summary_append(TlSummary *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void tl_summary_append(TlSummary *s, const char *fmt, ...)
{
  if (s->length >= sizeof s->text - 1) return;
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(s->text + s->length, sizeof s->text - s->length, fmt, ap);
  va_end(ap);
  if (n > 0) s->length += (size_t)n;
  if (s->length > sizeof s->text - 1) s->length = sizeof s->text - 1;
}

void tl_summary_real(TlSummary *s, const char *key, double value)
{
  tl_summary_append(s, " %s=%.6g", key, value);
}

void tl_summary_int(TlSummary *s, const char *key, long value) { tl_summary_append(s, " %s=%ld", key, value); }

void tl_summary_string(TlSummary *s, const char *key, const char *value)
{
  tl_summary_append(s, " %s=%s", key, value);
}

void tl_summary_print(const TlSummary *s, FILE *out)
{
  fprintf(out, "summary:%s\n", s->text);
  fflush(out);
}
