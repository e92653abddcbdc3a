/* Checkpoint and restart.
 *
 * A checkpoint is one HDF5 file, written atomically (temporary name, then
 * rename), holding the full state of a run: every module stores what it needs
 * to continue bit for bit (positions *and* histories: contact springs,
 * Newmark vectors, wall-group state, time-series buffers, ...).
 *
 * Low level: a writer and a reader of named arrays (double, int64, raw
 * bytes) and scalars (double, int64, string) under group paths.  Doubles are
 * stored in their native IEEE form, so they come back bit for bit (including
 * -0.0, subnormals, infinities and NaN payloads).  The reader checks sizes and
 * names the missing or mismatched dataset.
 *
 * High level: a module becomes checkpointable by a const TlCheckpointOps
 * {save, load} table; a driver adds each module object to a TlCheckpoint as a
 * named section, then writes all of them with tl_checkpoint_save() and
 * restores them with tl_checkpoint_load().
 *
 * Integrity: the file starts with a 512-byte block holding its size and a
 * checksum, verified before HDF5 reads anything (tl_hdf5_util.h); every array
 * also carries HDF5's Fletcher32 checksum; and every module's load() checks
 * the values it restores (tl_checkpoint_check_*).
 *
 * File layout (docs/output.md):
 *   /               attributes talus_checkpoint_version (int64), time
 *                   (double), step (int64), sections (string array)
 *   /<section>/     attribute type = the ops table's name; then whatever the
 *                   module's save() wrote, e.g. /dem/position (n x 3 doubles)
 */
#ifndef TL_CHECKPOINT_H
#define TL_CHECKPOINT_H

#include <stddef.h>
#include <stdint.h>

#include "tl_error.h"
#include "tl_object.h"

#define TL_CHECKPOINT_VERSION 1

typedef struct TlCheckpointWriter TlCheckpointWriter;
typedef struct TlCheckpointReader TlCheckpointReader;

/* ---------------------------------------------------------------- writer */
/* Starts a checkpoint file at `path` (written under a temporary name). */
TlStatus tl_checkpoint_writer_open(const char *path, TlCheckpointWriter **writer);
/* Closes and renames the file into place; frees *writer.  On failure the
 * previous file at path is untouched. */
TlStatus tl_checkpoint_writer_commit(TlCheckpointWriter **writer);
/* Discards the file being written; the previous file is untouched. */
void tl_checkpoint_writer_abort(TlCheckpointWriter **writer);

/* `group` is a path such as "dem" or "dem/contacts" (NULL or "" for the
 * root); `name` is the dataset's name inside it.  Writing a name twice is an
 * error.  Arrays of length 0 are allowed. */
TlStatus tl_checkpoint_write_doubles(TlCheckpointWriter *w, const char *group, const char *name, size_t n,
                                     const double *values);
TlStatus tl_checkpoint_write_int64s(TlCheckpointWriter *w, const char *group, const char *name, size_t n,
                                    const int64_t *values);
TlStatus tl_checkpoint_write_bytes(TlCheckpointWriter *w, const char *group, const char *name, size_t n,
                                   const void *bytes);
TlStatus tl_checkpoint_write_double(TlCheckpointWriter *w, const char *group, const char *name, double value);
TlStatus tl_checkpoint_write_int64(TlCheckpointWriter *w, const char *group, const char *name, int64_t value);
TlStatus tl_checkpoint_write_string(TlCheckpointWriter *w, const char *group, const char *name, const char *value);

/* ---------------------------------------------------------------- reader */
/* Opens a checkpoint; refuses a file without a supported format version. */
TlStatus tl_checkpoint_reader_open(const char *path, TlCheckpointReader **reader);
void tl_checkpoint_reader_close(TlCheckpointReader **reader);
/* The path being read (for messages). */
const char *tl_checkpoint_reader_path(const TlCheckpointReader *r);

/* Whether group/name exists. */
int tl_checkpoint_has(const TlCheckpointReader *r, const char *group, const char *name);
/* Number of elements of an array (bytes for a byte array): for sizing a
 * buffer before reading.  Error naming the dataset when absent. */
TlStatus tl_checkpoint_length(const TlCheckpointReader *r, const char *group, const char *name, size_t *n);
/* Reads an array that must hold exactly n elements of the right type; an
 * absent dataset, another length or another type is an error naming it. */
TlStatus tl_checkpoint_read_doubles(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                    double *values);
TlStatus tl_checkpoint_read_int64s(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                   int64_t *values);
TlStatus tl_checkpoint_read_bytes(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                  void *bytes);
TlStatus tl_checkpoint_read_double(const TlCheckpointReader *r, const char *group, const char *name, double *value);
TlStatus tl_checkpoint_read_int64(const TlCheckpointReader *r, const char *group, const char *name, int64_t *value);
/* *value is allocated (free with tl_free). */
TlStatus tl_checkpoint_read_string(const TlCheckpointReader *r, const char *group, const char *name, char **value);

/* Validation of what was read, as the creating API would check it: an error
 * names the file, the dataset, the index and the value.  A checkpoint is
 * input like any other: every module's load() checks the values it restores
 * before the scene uses them. */
/* Every value finite. */
TlStatus tl_checkpoint_check_finite(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                    const double *values);
/* Every value finite and > 0 (strictly), or >= 0 when allow_zero. */
TlStatus tl_checkpoint_check_positive(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                      const double *values, int allow_zero);
/* A finite scalar in [lo, hi]. */
TlStatus tl_checkpoint_check_range(const TlCheckpointReader *r, const char *group, const char *name, double value,
                                   double lo, double hi);
/* An integer scalar in [lo, hi]. */
TlStatus tl_checkpoint_check_count(const TlCheckpointReader *r, const char *group, const char *name, int64_t value,
                                   int64_t lo, int64_t hi);

/* ---------------------------------------------------------------- sections */
/* What a module provides to be checkpointed.  save() writes the object's
 * full state under `group`; load() restores it from `group`, checking sizes
 * against the object as built by the driver (the driver rebuilds the scene
 * from its options, then load() overwrites the state). */
typedef struct {
  TlOpsHeader header; /* kind "checkpoint"; name identifies the data format */
  TlStatus (*save)(const void *object, TlCheckpointWriter *w, const char *group);
  TlStatus (*load)(void *object, TlCheckpointReader *r, const char *group);
} TlCheckpointOps;

typedef struct TlCheckpoint TlCheckpoint;

TlStatus tl_checkpoint_create(TlCheckpoint **checkpoint);
void tl_checkpoint_destroy(TlCheckpoint **checkpoint);
/* Adds a section: `name` is its group in the file (unique, no '/'), object
 * is what ops->save/load receive.  The object must outlive the checkpoint. */
TlStatus tl_checkpoint_add(TlCheckpoint *cp, const char *name, const TlCheckpointOps *ops, void *object);
/* Writes every section, plus the time and step, atomically to path.  With
 * TALUS_CHECKPOINT_KILL_AT=n in the environment the n-th save of the process
 * kills it (SIGKILL) after its data reached the temporary file and before
 * the rename: the kill-during-write self-tests. */
TlStatus tl_checkpoint_save(const TlCheckpoint *cp, const char *path, double time, int64_t step);
/* Restores every section from path; every added section must be present
 * with the same type.  time and step may be NULL. */
TlStatus tl_checkpoint_load(TlCheckpoint *cp, const char *path, double *time, int64_t *step);

/* ---------------------------------------------------------------- memory */
/* A checkpoint held in memory: the same writer and reader, so any module's
 * save() and load() work on it unchanged, without a file or HDF5 (a DEM
 * cell's committed state, saved and restored many times per load step).
 * Values come back bit for bit; load() checks them as from a file.  The
 * buffers are kept from one save to the next.  A memory checkpoint is used
 * by one thread at a time; distinct ones may be used concurrently. */
typedef struct TlCheckpointMemory TlCheckpointMemory;
TlStatus tl_checkpoint_memory_create(TlCheckpointMemory **mem);
void tl_checkpoint_memory_destroy(TlCheckpointMemory **mem);
/* Bytes of data it holds (the dataset payloads). */
size_t tl_checkpoint_memory_bytes(const TlCheckpointMemory *mem);
/* Whether nothing has been saved into it (or the last save was aborted). */
int tl_checkpoint_memory_empty(const TlCheckpointMemory *mem);
/* Empties mem and writes into it (commit finishes, abort leaves it empty);
 * reads from it.  Group paths work as in a file. */
TlStatus tl_checkpoint_writer_open_memory(TlCheckpointMemory *mem, TlCheckpointWriter **writer);
TlStatus tl_checkpoint_reader_open_memory(const TlCheckpointMemory *mem, TlCheckpointReader **reader);
/* object's state through ops->save into mem (replacing what it held), and
 * back through ops->load; the group is the root. */
TlStatus tl_checkpoint_memory_save(TlCheckpointMemory *mem, const TlCheckpointOps *ops, const void *object);
TlStatus tl_checkpoint_memory_load(const TlCheckpointMemory *mem, const TlCheckpointOps *ops, void *object);
/* dst = a copy of src. */
TlStatus tl_checkpoint_memory_copy(TlCheckpointMemory *dst, const TlCheckpointMemory *src);
/* The datasets of a memory checkpoint, in the order written: for a test that
 * alters stored values in place and loads them again (the fuzz harness of
 * the loaders; no HDF5 between the edit and the module's checks).  kind is
 * 'd' (n doubles), 'i' (n int64), 'b' (n bytes) or 's' (a string of n - 1
 * characters); data stays valid until mem is written again. */
typedef struct {
  const char *path;
  char kind;
  size_t n;
  void *data;
} TlCheckpointEntry;
size_t tl_checkpoint_memory_count(const TlCheckpointMemory *mem);
TlStatus tl_checkpoint_memory_entry(TlCheckpointMemory *mem, size_t k, TlCheckpointEntry *entry);

#endif
