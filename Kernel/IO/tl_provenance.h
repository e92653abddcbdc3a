/* Provenance: what made an output file.
 *
 * Every HDF5 file the library creates (tl_h5_create: snapshots, meshes, CG
 * fields, tables, checkpoints) holds a group /provenance whose attributes
 * are
 *   talus_version   "0.1.0"                     (tl_version)
 *   talus_revision  "a533486f0c1d", "-dirty" appended for uncommitted
 *                   changes, "unknown" outside git (tl_revision)
 *   program         "settle"
 *   command_line    the whole command line, words with blanks quoted
 *   options         every option in force, defaults included, one
 *                   "-name value" a line (newline-separated)
 * and every CSV table (tl_timeseries) begins with the same as comment lines:
 *   # talus_version: 0.1.0
 *   # talus_revision: a533486f0c1d
 *   # program: settle
 *   # command_line: build/bin/settle -n 300
 *   # option: -n 300
 *   # option: -d_min 0.0025
 *   ...
 * then the header line.  The command line and options are those of the
 * running program's options database (tl_options_current: the last one
 * finished); a program without one records the version and revision, an
 * empty command line and no options.
 *
 * A restarted run records its own command line, so restart comparisons
 * leave /provenance and the comment lines out (h5diff --exclude-path
 * /provenance; SelfTests/compare_data.cmake). */
#ifndef TL_PROVENANCE_H
#define TL_PROVENANCE_H

#include <stdio.h>

#include "tl_error.h"

/* (tl_provenance_write_h5, which writes the group /provenance into a file
 * being created, is declared in tl_hdf5_util.h: this header needs no
 * HDF5 headers.) */
/* Writes the comment lines, each starting with `comment` ("# "). */
TlStatus tl_provenance_write_text(FILE *f, const char *comment);

/* ---------------------------------------------------------------- reading */
typedef struct {
  char *version, *revision, *program, *command_line;
  size_t n_options;
  char **options; /* "-name value" */
} TlProvenance;

/* From an HDF5 file's /provenance group (TL_ERR_NOT_FOUND when absent). */
TlStatus tl_provenance_read_h5(const char *path, TlProvenance *p);
/* From the leading "# key: value" lines of a text file such as a CSV
 * table (TL_ERR_NOT_FOUND when it has none). */
TlStatus tl_provenance_read_text(const char *path, TlProvenance *p);
/* The value of option `name` recorded in p, NULL when absent. */
const char *tl_provenance_option(const TlProvenance *p, const char *name);
void tl_provenance_free(TlProvenance *p);

#endif
