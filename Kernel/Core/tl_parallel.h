/* Process-level parallelism: MPI when built with TALUS_WITH_MPI, one process
 * otherwise.  Threads (OpenMP) are independent of this. */
#ifndef TL_PARALLEL_H
#define TL_PARALLEL_H

#include "tl_error.h"

/* Starts MPI (if built with it and not yet started). */
TlStatus tl_parallel_initialize(int *argc, char ***argv);
/* Stops MPI if tl_parallel_initialize started it. */
TlStatus tl_parallel_finalize(void);
int tl_parallel_rank(void);
int tl_parallel_size(void);
/* For main() of programs that time themselves on shared machines: unless
 * OMP_WAIT_POLICY is set, sets it to "passive" and restarts the program (the
 * OpenMP runtime reads it only at start-up), so threads waiting at a barrier
 * sleep instead of spinning on the core their partner needs.  Returns only
 * when the variable was already set or the restart failed. */
void tl_parallel_prefer_passive_wait(char **argv);
/* Number of OpenMP threads a parallel region will use. */
int tl_parallel_threads(void);

/* The statement (a loop or block under the OpenMP directive, given as a
 * string) on the threads when `cond` holds, otherwise as plain code.  A
 * region whose `if` clause is false still sets up a team of one in the
 * runtime (0.4 us), which small scenes pay at every step.  Directives
 * inside the statement are written as _Pragma("omp ..."). */
#define TL_PARALLEL_IF(cond, directive, ...) \
  do {                                       \
    if (cond) {                              \
      _Pragma(directive) __VA_ARGS__         \
    } else {                                 \
      __VA_ARGS__                            \
    }                                        \
  } while (0)

#endif
