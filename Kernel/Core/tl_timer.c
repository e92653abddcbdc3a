#include "tl_timer.h"

#include <string.h>
#include <time.h>

double tl_wtime(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void tl_timers_init(TlTimers *t)
{
  memset(t, 0, sizeof *t);
  t->created = tl_wtime();
}

int tl_timers_phase(TlTimers *t, const char *name)
{
  for (int i = 0; i < t->n; ++i)
    if (strcmp(t->phase[i].name, name) == 0) return i;
  if (t->n == TL_TIMER_MAX_PHASES) return -1;
  t->phase[t->n].name = name;
  return t->n++;
}

void tl_timers_start(TlTimers *t, int phase)
{
  if (phase >= 0) t->phase[phase].started = tl_wtime();
}

void tl_timers_stop(TlTimers *t, int phase)
{
  if (phase < 0) return;
  t->phase[phase].total += tl_wtime() - t->phase[phase].started;
  t->phase[phase].count++;
}

double tl_timers_elapsed(const TlTimers *t) { return tl_wtime() - t->created; }

void tl_timers_print(const TlTimers *t, FILE *out)
{
  double wall = tl_timers_elapsed(t);
  fprintf(out, "timing: %-22s %10s %7s %10s\n", "phase", "seconds", "share", "calls");
  for (int i = 0; i < t->n; ++i)
    fprintf(out, "timing: %-22s %10.4f %6.1f%% %10ld\n", t->phase[i].name, t->phase[i].total,
            wall > 0 ? 100.0 * t->phase[i].total / wall : 0.0, t->phase[i].count);
  fprintf(out, "timing: %-22s %10.4f\n", "wall", wall);
}
