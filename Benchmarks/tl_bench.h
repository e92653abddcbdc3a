/* What the benchmark programs share: their main, and the load average
 * printed beside a timing so that a run on a busy machine is seen as one. */
#ifndef TL_BENCH_H
#define TL_BENCH_H

#include <math.h>
#include <stdio.h>
#include "talus.h"

/* The machine's load average over the last minute; NaN where
 * /proc/loadavg cannot be read. */
static inline double tl_bench_load_average(void)
{
  double l = NAN;
  FILE *fp = fopen("/proc/loadavg", "r");
  if (fp) {
    if (fscanf(fp, "%lf", &l) != 1) l = NAN;
    fclose(fp);
  }
  return l;
}

/* main of a benchmark whose run prints its own summary: the library
 * initialised, run, the exit code of its status. */
static inline int tl_bench_main(int argc, char **argv, TlStatus (*run)(int argc, char **argv))
{
  TlStatus s = tl_initialize();
  if (s == TL_OK) s = run(argc, argv);
  return tl_driver_exit(s);
}

/* main of a benchmark whose run fills the summary: when it succeeds, the
 * wall time of the whole program is added and the summary printed. */
static inline int tl_bench_main_summary(int argc, char **argv, TlStatus (*run)(int argc, char **argv, TlSummary *sum))
{
  double t0 = tl_wtime();
  TlSummary sum;
  tl_summary_init(&sum);
  TlStatus s = run(argc, argv, &sum);
  if (s == TL_OK) {
    tl_summary_real(&sum, "wall", tl_wtime() - t0);
    s = tl_summary_print(&sum, stdout);
  }
  return tl_driver_exit(s);
}

#endif
