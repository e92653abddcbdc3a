/* Atomic files: write to a temporary name, then rename.
 *
 * Every output file of Talus is written under a temporary name in the same
 * folder (".<name>.<pid>.<counter>.tmp"), flushed and fsync'ed, then renamed
 * over the final name, and the folder is fsync'ed.  rename() is atomic on a
 * POSIX file system, so a reader sees either the old file or the complete new
 * one, never a partial one, even when the writer is killed midway.  A killed
 * writer may leave its temporary file behind; it is never mistaken for output
 * (hidden name, .tmp suffix) and the next run's files do not depend on it.
 *
 * Two ways to use it: a stream (tl_atomic_file_open, fprintf to
 * tl_atomic_file_stream, tl_atomic_file_commit), or a temporary name for a
 * library that creates the file itself, such as HDF5 (tl_atomic_temp_name,
 * write and close the file, tl_atomic_commit_path). */
#ifndef TL_ATOMIC_FILE_H
#define TL_ATOMIC_FILE_H

#include <stdio.h>
#include "tl_error.h"

typedef struct TlAtomicFile TlAtomicFile;

/* Opens a temporary file next to `path` for writing (binary). */
TlStatus tl_atomic_file_open(const char *path, TlAtomicFile **file);
/* The stdio stream to write to. */
FILE *tl_atomic_file_stream(TlAtomicFile *file);
/* Flushes, fsyncs, closes and renames the temporary file over the final
 * path; frees *file and sets it to NULL.  On failure the temporary file is
 * removed and the previous file at `path` is untouched. */
TlStatus tl_atomic_file_commit(TlAtomicFile **file);
/* Gives up: removes the temporary file, leaves `path` untouched. */
void tl_atomic_file_abort(TlAtomicFile **file);

/* Writes a whole file through a callback: open, write(stream, context),
 * commit.  If write fails the old file stays and the status is returned. */
typedef TlStatus (*TlAtomicWriteFn)(FILE *stream, void *context);
TlStatus tl_atomic_write(const char *path, TlAtomicWriteFn write, void *context);

/* A fresh temporary name for `path` in the same folder (allocated; free with
 * tl_free).  Unique per process and call. */
TlStatus tl_atomic_temp_name(const char *path, char **temp_name);
/* fsyncs the closed file `temp_name`, renames it to `path` and fsyncs the
 * folder.  On failure removes `temp_name`. */
TlStatus tl_atomic_commit_path(const char *temp_name, const char *path);

/* Creates folder `path` and its parents (like mkdir -p); an existing folder
 * is fine, an existing non-folder is an error. */
TlStatus tl_mkdir_p(const char *path);
/* Removes from folder `dir` the temporaries that killed writers left:
 * names of tl_atomic_temp_name's pattern ".<name>.<pid>.<counter>.tmp"
 * whose process no longer runs (a live writer's, this process's included,
 * are kept); nothing else is touched.  *removed (may be NULL) counts them.
 * A missing folder removes nothing. */
TlStatus tl_atomic_remove_stale(const char *dir, size_t *removed);
/* Allocated "<dir>/<name>" (just <name> when dir is NULL or empty). */
TlStatus tl_path_join(const char *dir, const char *name, char **path);

#endif
