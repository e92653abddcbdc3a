/* What this machine allows a DEM step, measured, for the bound analysis of
 * the DEM kernel (bytes moved per particle-step against bandwidth, team
 * start-up per parallel region against the step time):
 *   (a) memory bandwidth: the STREAM triad a[i] = b[i] + s c[i] on arrays
 *       far larger than the last-level cache, on 1 thread and on
 *       -threads_max threads (GB/s counted as STREAM does, 24 bytes per
 *       element; the write-allocate read of a[] makes the traffic 32);
 *   (b) the cost of an empty parallel region on -threads_max threads, and
 *       of a barrier inside one, µs each, under the wait policy the DEM
 *       benchmarks use (OMP_WAIT_POLICY passive unless set: threads sleep
 *       between regions, so every region wakes its partner).
 * Medians of -repeat runs (and the best, as STREAM reports it); the load
 * average is printed beside every figure.  The second thread's gain on the
 * triad is the ratio printed: on a machine whose cores share one memory
 * path it stays near 1. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "tl_bench.h"
#include "tl_memory.h"
#include "tl_parallel.h"

static void sort(double *t, int n)
{
  for (int a = 1; a < n; ++a)
    for (int b = a; b > 0 && t[b - 1] > t[b]; --b) {
      const double s = t[b];
      t[b] = t[b - 1];
      t[b - 1] = s;
    }
}

/* The triad on nt threads: median and best GB/s over `repeat` passes. */
static void triad(double *a, const double *b, const double *c, size_t n, int nt, int repeat, double *median,
                  double *best)
{
  double t[64];
  const double s = 3.0;
  for (int r = 0; r < repeat; ++r) {
    const double t0 = tl_wtime();
#pragma omp parallel for num_threads(nt) schedule(static)
    for (size_t i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    t[r] = tl_wtime() - t0;
  }
  sort(t, repeat);
  *median = 24.0 * (double)n / t[repeat / 2] * 1e-9;
  *best = 24.0 * (double)n / t[0] * 1e-9;
}

/* µs per empty region and per barrier on nt threads, medians of `repeat`. */
static void team_costs(int nt, long count, int repeat, double *region_us, double *barrier_us)
{
  double tr[64], tb[64];
  for (int r = 0; r < repeat; ++r) {
    double t0 = tl_wtime();
    for (long k = 0; k < count; ++k) {
#pragma omp parallel num_threads(nt)
      {
        __asm__ volatile("" ::: "memory");
      }
    }
    tr[r] = (tl_wtime() - t0) / (double)count * 1e6;
    t0 = tl_wtime();
#pragma omp parallel num_threads(nt)
    {
      for (long k = 0; k < count; ++k) {
#pragma omp barrier
      }
    }
    tb[r] = (tl_wtime() - t0) / (double)count * 1e6;
  }
  sort(tr, repeat);
  sort(tb, repeat);
  *region_us = tr[repeat / 2];
  *barrier_us = tb[repeat / 2];
}

static TlStatus run(int argc, char **argv, TlSummary *sum)
{
  TlOptions *o;
  TL_CHECK(tl_options_create(argc, argv,
                             "The machine's bounds for the DEM kernel: STREAM triad bandwidth on 1 and N threads, "
                             "the cost of an empty parallel region and of a barrier.",
                             &o));
  long mb, repeat, tmax, count;
  TL_CHECK(tl_options_get_int(o, "-mb", 128, 1, 8192, "size of each of the triad's three arrays (1-3: resident in a 32 MiB last-level cache) [MiB]", &mb));
  TL_CHECK(tl_options_get_int(o, "-repeat", 7, 3, 64, "passes per measurement (median and best reported)", &repeat));
  TL_CHECK(tl_options_get_int(o, "-threads_max", 2, 1, 64, "threads of the second measurement", &tmax));
  TL_CHECK(tl_options_get_int(o, "-regions", 20000, 100, 100000000, "empty regions (and barriers) per pass", &count));
  TlStatus s = tl_options_finish(o, stdout);
  tl_options_destroy(&o);
  if (s != TL_OK) return s;
  const size_t n = (size_t)mb * 1024 * 1024 / sizeof(double);
  double *a = NULL, *b = NULL, *c = NULL;
  TL_CHECK(tl_realloc(&a, n, sizeof *a));
  TL_CHECK(tl_realloc(&b, n, sizeof *b));
  TL_CHECK(tl_realloc(&c, n, sizeof *c));
  const int nt = (int)tmax;
  /* first touch by the threads that use them */
#pragma omp parallel for num_threads(nt) schedule(static)
  for (size_t i = 0; i < n; ++i) {
    a[i] = 0.0;
    b[i] = 1.0;
    c[i] = 2.0;
  }
  const char *policy = getenv("OMP_WAIT_POLICY");
  printf("OMP_WAIT_POLICY=%s, arrays 3 x %ld MiB\n", policy ? policy : "(unset)", mb);
  double m1, b1, mt = NAN, bt = NAN;
  triad(a, b, c, n, 1, (int)repeat, &m1, &b1);
  printf("triad, 1 thread: %.2f GB/s median, %.2f best (load %.2f)\n", m1, b1, tl_bench_load_average());
  if (nt > 1) {
    triad(a, b, c, n, nt, (int)repeat, &mt, &bt);
    printf("triad, %d threads: %.2f GB/s median, %.2f best (load %.2f); gain from the threads %.2f\n", nt, mt, bt,
           tl_bench_load_average(), mt / m1);
  }
  int bad = 0;
  for (size_t i = 0; i < n; ++i) bad += a[i] != 7.0;
  tl_free(&a);
  tl_free(&b);
  tl_free(&c);
  if (bad) TL_ERROR(TL_ERR_NUMERIC, "triad: %d elements differ from 1 + 3 * 2", bad);
  tl_summary_real(sum, "triad_gbs_1t", m1);
  tl_summary_real(sum, "triad_gbs_best_1t", b1);
  if (nt > 1) {
    double region, barrier;
    team_costs(nt, count, (int)repeat, &region, &barrier);
    printf("%d threads: empty parallel region %.2f us, barrier %.2f us (load %.2f)\n", nt, region, barrier,
           tl_bench_load_average());
    tl_summary_real(sum, "triad_gbs_nt", mt);
    tl_summary_real(sum, "triad_gbs_best_nt", bt);
    tl_summary_real(sum, "triad_thread_gain", mt / m1);
    tl_summary_real(sum, "region_us", region);
    tl_summary_real(sum, "barrier_us", barrier);
  }
  tl_summary_int(sum, "threads", nt);
  const double load = tl_bench_load_average();
  if (isfinite(load)) tl_summary_real(sum, "load", load);
  return TL_OK;
}

int main(int argc, char **argv)
{
  tl_parallel_prefer_passive_wait(argv); /* the DEM benchmarks' policy */
  return tl_bench_main_summary(argc, argv, run);
}
