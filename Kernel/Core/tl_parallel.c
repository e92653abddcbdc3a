#include "tl_parallel.h"

#include <omp.h>
#include <stdlib.h>
#include <unistd.h>

#include "tl_config.h"
#if TALUS_WITH_MPI
#include <mpi.h>
static int tl_started_mpi = 0;
#endif

TlStatus tl_parallel_initialize(int *argc, char ***argv)
{
#if TALUS_WITH_MPI
  int running = 0;
  MPI_Initialized(&running);
  if (!running) {
    int provided;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
      TL_ERROR(TL_ERR_STATE, "MPI_Init_thread failed");
    tl_started_mpi = 1;
  }
#else
  (void)argc;
  (void)argv;
#endif
  return TL_OK;
}

TlStatus tl_parallel_finalize(void)
{
#if TALUS_WITH_MPI
  if (tl_started_mpi && MPI_Finalize() != MPI_SUCCESS) TL_ERROR(TL_ERR_STATE, "MPI_Finalize failed");
  tl_started_mpi = 0;
#endif
  return TL_OK;
}

int tl_parallel_rank(void)
{
#if TALUS_WITH_MPI
  int running = 0, rank = 0;
  MPI_Initialized(&running);
  if (running) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
#else
  return 0;
#endif
}

int tl_parallel_size(void)
{
#if TALUS_WITH_MPI
  int running = 0, size = 1;
  MPI_Initialized(&running);
  if (running) MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
#else
  return 1;
#endif
}

int tl_parallel_threads(void) { return omp_get_max_threads(); }

void tl_parallel_prefer_passive_wait(char **argv)
{
  if (getenv("OMP_WAIT_POLICY")) return;
  setenv("OMP_WAIT_POLICY", "passive", 1);
  execv("/proc/self/exe", argv);
}
