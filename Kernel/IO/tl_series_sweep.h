/* Stale snapshot files of a series.
 *
 * A run into a folder that already holds a longer series of the same name
 * would leave the old run's later files (particles_000011.h5, ...) beside the
 * new series, where a glob or a reader of the folder takes them for part of
 * it.  The series removes them when it adds its first step in a process:
 * every "<name>_NNNNNN.h5" from the step index `first_free` on, and, for a
 * series that starts from its first step, every "<name>_mesh_NNNN.h5" but
 * the first (a restarted series keeps its mesh files).  Only those two
 * patterns are touched. */
#ifndef TL_SERIES_SWEEP_H
#define TL_SERIES_SWEEP_H

#include <stddef.h>

#include "tl_error.h"

/* `xmf_path` is the series file "<dir>/<name>.xmf"; *removed counts the
 * files removed. */
TlStatus tl_series_sweep_stale(const char *xmf_path, size_t first_free, int fresh, size_t *removed);
/* A fresh run that writes no step of the series `name` in `dir` (its
 * snapshots off) removes an earlier run's "<name>.xmf" and all its
 * "<name>_NNNNNN.h5" and "<name>_mesh_NNNN.h5", which would otherwise be
 * taken for this run's output.  *removed counts the files removed. */
TlStatus tl_series_sweep_whole(const char *dir, const char *name, size_t *removed);

#endif
