#include "tl_summary.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <string.h>

#include "tl_init.h"

void tl_summary_init(TlSummary *s)
{
  s->text[0] = '\0';
  s->length = 0;
  s->n_undefined = 0;
  s->undefined[0] = '\0';
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
  if (!isfinite(value)) {
    tl_summary_undefined(s, key, "the computed value is %s", isnan(value) ? "NaN" : "infinite");
    return;
  }
  tl_summary_append(s, " %s=%.6g", key, value);
}

void tl_summary_undefined(TlSummary *s, const char *key, const char *why_fmt, ...)
{
  tl_summary_append(s, " %s=undefined", key);
  size_t n = strlen(s->undefined);
  if (n + 4 < sizeof s->undefined) {
    int k = snprintf(s->undefined + n, sizeof s->undefined - n, "%s%s: ", n ? "; " : "", key);
    if (k > 0 && (size_t)k < sizeof s->undefined - n) {
      n += (size_t)k;
      va_list ap;
      va_start(ap, why_fmt);
      vsnprintf(s->undefined + n, sizeof s->undefined - n, why_fmt, ap);
      va_end(ap);
    }
  }
  s->n_undefined++;
}

void tl_summary_int(TlSummary *s, const char *key, long value) { tl_summary_append(s, " %s=%ld", key, value); }

void tl_summary_string(TlSummary *s, const char *key, const char *value)
{
  tl_summary_append(s, " %s=%s", key, value);
}

/* The status the last printed summary line reported (TL_OK, or
 * TL_ERR_NUMERIC for undefined figures), -1 before any: tl_summary_end()
 * adds a line only when that one does not already tell how the run ended. */
static int tl_summary_last = -1;

TlStatus tl_summary_print(const TlSummary *s, FILE *out)
{
  TlStatus status = s->n_undefined ? TL_ERR_NUMERIC : TL_OK;
  fprintf(out, "summary:%s status=%s", s->text, status == TL_OK ? "ok" : "undefined");
  if (status != TL_OK) fprintf(out, " exit=%d", tl_exit_code(status));
  fputc('\n', out);
  fflush(out);
  tl_summary_last = (int)status;
  if (s->n_undefined == 0) return TL_OK;
  return tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "%d summary figure%s undefined (%s)",
                      s->n_undefined, s->n_undefined > 1 ? "s" : "", s->undefined);
}

void tl_summary_end(TlStatus status, FILE *out)
{
  if (status == TL_OK || status == TL_HELP) return;
  if (tl_summary_last == (int)status) return;
  /* The status name as one word: "invalid argument" -> invalid_argument. */
  char word[64];
  snprintf(word, sizeof word, "%s", tl_status_name(status));
  for (char *c = word; *c; ++c)
    if (!isalnum((unsigned char)*c)) *c = '_';
  fprintf(out, "summary: status=%s exit=%d error=%s\n", tl_exit_word(status), tl_exit_code(status), word);
  fflush(out);
  tl_summary_last = (int)status;
}
