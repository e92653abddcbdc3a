/* Thin HDF5 helpers shared by the IO module: files created under a
 * temporary name and renamed on commit, datasets and attributes addressed by
 * absolute path ("/particles/position"; missing groups are created), exact
 * size checks on reading, and every HDF5 failure turned into a TlStatus whose
 * message names the file and the dataset.  HDF5's own error printing is
 * silenced; the innermost HDF5 error is quoted in our message instead.
 *
 * HDF5 is used from one thread at a time (the library is built without its
 * thread-safety option): call output from the main thread, outside parallel
 * regions. */
#ifndef TL_HDF5_UTIL_H
#define TL_HDF5_UTIL_H

#include <hdf5.h>
#include <stddef.h>
#include <stdint.h>

#include "tl_error.h"

enum { TL_H5_MAX_RANK = 4 };

typedef struct {
  hid_t id;   /* HDF5 file id, H5I_INVALID_HID when closed */
  char *path; /* the final path, named in messages */
  char *temp; /* the temporary name while writing, NULL when reading */
  int sealed; /* whole-file checksum in the user block (tl_h5_create_sealed) */
} TlH5File;

/* Creates a new file under a temporary name next to `path`. */
TlStatus tl_h5_create(const char *path, TlH5File *file);
/* Closes the file and renames it to its final path (atomic). */
TlStatus tl_h5_commit(TlH5File *file);
/* Closes the file and removes the temporary; `path` keeps its old content. */
void tl_h5_abort(TlH5File *file);
/* Opens an existing file read-only. */
TlStatus tl_h5_open(const char *path, TlH5File *file);
/* Sealed files: the first TL_H5_SEAL_BYTES (an HDF5 user block) hold the
 * size and a 64-bit FNV-1a checksum of the rest, written at commit and
 * verified by tl_h5_open_sealed before HDF5 parses anything, so a damaged
 * file is refused by name instead of reaching the HDF5 library's own
 * parsers.  tl_h5_seal (re)writes the block of a closed file. */
#define TL_H5_SEAL_BYTES 512
TlStatus tl_h5_create_sealed(const char *path, TlH5File *file);
TlStatus tl_h5_open_sealed(const char *path, TlH5File *file);
TlStatus tl_h5_seal(const char *path);
/* Writes the group /provenance (tl_provenance.h) into a file being
 * created; tl_h5_create and tl_h5_create_sealed call it. */
TlStatus tl_provenance_write_h5(TlH5File *file);
/* Closes a file opened for reading (harmless on a closed one). */
void tl_h5_close(TlH5File *file);

/* Whether an object (group or dataset) exists at the absolute path. */
int tl_h5_exists(const TlH5File *file, const char *path);
/* Creates the group at path (and its parents) if absent. */
TlStatus tl_h5_group(TlH5File *file, const char *path);

/* Writes a dataset of `rank` dimensions (rank 0: a scalar).  memtype is an
 * HDF5 native type (H5T_NATIVE_DOUBLE, H5T_NATIVE_INT64, ...); the file type
 * is the same type, so values are stored bit for bit. */
TlStatus tl_h5_write(TlH5File *file, const char *path, hid_t memtype, int rank, const hsize_t *dims,
                     const void *data);
/* Rank and dimensions of a dataset; error naming it when absent. */
TlStatus tl_h5_dims(const TlH5File *file, const char *path, int *rank, hsize_t dims[TL_H5_MAX_RANK]);
/* Reads a dataset whose rank and dimensions must equal the expected ones;
 * a mismatch is an error naming the dataset and both shapes. */
TlStatus tl_h5_read(const TlH5File *file, const char *path, hid_t memtype, int rank, const hsize_t *dims,
                    void *data);
/* A scalar string dataset. */
TlStatus tl_h5_write_string(TlH5File *file, const char *path, const char *value);
/* Reads a string dataset into an allocated string (free with tl_free). */
TlStatus tl_h5_read_string(const TlH5File *file, const char *path, char **value);

/* Attributes of the object at `object` (a group or dataset path, "/" for the
 * file).  Strings are fixed-length and NUL-terminated, so h5dump prints them. */
TlStatus tl_h5_attr_write_double(TlH5File *file, const char *object, const char *name, double value);
TlStatus tl_h5_attr_write_int64(TlH5File *file, const char *object, const char *name, int64_t value);
TlStatus tl_h5_attr_write_string(TlH5File *file, const char *object, const char *name, const char *value);
TlStatus tl_h5_attr_write_strings(TlH5File *file, const char *object, const char *name, size_t n,
                                  const char *const *values);
TlStatus tl_h5_attr_read_double(const TlH5File *file, const char *object, const char *name, double *value);
TlStatus tl_h5_attr_read_int64(const TlH5File *file, const char *object, const char *name, int64_t *value);
/* Allocated copy (free with tl_free). */
TlStatus tl_h5_attr_read_string(const TlH5File *file, const char *object, const char *name, char **value);
/* *values: n allocated strings (free with tl_h5_free_strings). */
TlStatus tl_h5_attr_read_strings(const TlH5File *file, const char *object, const char *name, size_t *n,
                                 char ***values);
void tl_h5_free_strings(size_t n, char ***values);

#endif
