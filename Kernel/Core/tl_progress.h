/* A progress bar with ETA on stderr, shown only on a terminal, never when
 * the environment variable CI is set, so logs stay clean, and, like every
 * informational line, never below the log level info (tl_log.h). */
#ifndef TL_PROGRESS_H
#define TL_PROGRESS_H

typedef struct {
  const char *label;
  double total, started, last_drawn;
  int enabled;
} TlProgress;

void tl_progress_init(TlProgress *p, const char *label, double total);
/* Redraws at most ~5 times a second. */
void tl_progress_update(TlProgress *p, double done);
void tl_progress_finish(TlProgress *p);

#endif
