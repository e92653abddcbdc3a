#include "tl_progress.h"

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "tl_log.h"
#include "tl_timer.h"

void tl_progress_init(TlProgress *p, const char *label, double total)
{
  p->label = label;
  p->total = total > 0 ? total : 1.0;
  p->started = tl_wtime();
  p->last_drawn = 0.0;
  p->enabled = isatty(STDERR_FILENO) && getenv("CI") == NULL && tl_log_enabled(TL_LOG_INFO);
}

static void tl_format_seconds(double s, char *buf, size_t n)
{
  if (s < 0 || s > 1e7) s = 0;
  int h = (int)(s / 3600), m = (int)(s / 60) % 60, sec = (int)s % 60;
  if (h) snprintf(buf, n, "%dh%02dm", h, m);
  else snprintf(buf, n, "%dm%02ds", m, sec);
}

void tl_progress_update(TlProgress *p, double done)
{
  if (!p->enabled) return;
  double now = tl_wtime();
  if (now - p->last_drawn < 0.2 && done < p->total) return;
  p->last_drawn = now;
  double frac = done / p->total;
  if (frac < 0) frac = 0;
  if (frac > 1) frac = 1;
  const int width = 30;
  int filled = (int)(frac * width);
  char bar[64];
  for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
  bar[width] = '\0';
  double elapsed = now - p->started;
  char eta[32], spent[32];
  tl_format_seconds(frac > 0 ? elapsed * (1 - frac) / frac : 0, eta, sizeof eta);
  tl_format_seconds(elapsed, spent, sizeof spent);
  fprintf(stderr, "\r%s [%s] %5.1f%%  %s elapsed, ETA %s ", p->label, bar, 100 * frac, spent, eta);
  fflush(stderr);
}

void tl_progress_finish(TlProgress *p)
{
  if (!p->enabled) return;
  p->last_drawn = 0;
  tl_progress_update(p, p->total);
  fputc('\n', stderr);
}
