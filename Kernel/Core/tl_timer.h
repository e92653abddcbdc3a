/* Wall-clock timers with a per-phase breakdown printed at the end of a run. */
#ifndef TL_TIMER_H
#define TL_TIMER_H

#include <stdio.h>

enum { TL_TIMER_MAX_PHASES = 32 };

typedef struct {
  const char *name;
  double total, started;
  long count;
} TlPhase;

typedef struct {
  TlPhase phase[TL_TIMER_MAX_PHASES];
  int n;
  double created;
} TlTimers;

/* Seconds since an arbitrary origin (monotonic clock). */
double tl_wtime(void);
void tl_timers_init(TlTimers *t);
/* The index of phase `name` (a string literal), created on first use;
 * -1 when all slots are taken (timing then silently skips it). */
int tl_timers_phase(TlTimers *t, const char *name);
void tl_timers_start(TlTimers *t, int phase);
void tl_timers_stop(TlTimers *t, int phase);
/* Prints each phase's seconds, share of the wall time since init, and calls. */
void tl_timers_print(const TlTimers *t, FILE *out);
double tl_timers_elapsed(const TlTimers *t);

#endif
