/* Time-series tables: named columns with units, appended row by row.
 *
 * Rows live in one growing buffer (amortised doubling, and
 * tl_timeseries_reserve() to size it up front), so appending allocates
 * nothing once the buffer has reached its working size.  The whole table is
 * written atomically as <base>.csv and/or <base>.h5 at flush points: every
 * `every_rows` rows, every `every_seconds` of wall time, on
 * tl_timeseries_flush() and on tl_timeseries_close().  An interrupted run
 * therefore leaves complete files holding the rows up to the last flush.
 *
 * CSV: the provenance as comment lines "# key: value" (tl_provenance.h:
 * version, git revision, command line, every option), one header line
 * "name [unit],name [unit],..." (a dimensionless column is just "name"),
 * then one line per row, values printed with 17 significant digits so they
 * read back exactly.  Readers skip the leading '#' lines (numpy.loadtxt and
 * genfromtxt do by default; pandas with comment='#').
 * HDF5: dataset /table (rows x columns, double) with string-array attributes
 * "columns" and "units".
 *
 * A table is checkpointable (tl_timeseries_checkpoint_ops): a run restarted
 * from a checkpoint continues the same table and rewrites identical files. */
#ifndef TL_TIMESERIES_H
#define TL_TIMESERIES_H

#include <stddef.h>

#include "tl_checkpoint.h"
#include "tl_error.h"

typedef struct {
  const char *name; /* letters, digits, '_', '.', '-'; unique in the table */
  const char *unit; /* "J", "m/s", ...; NULL or "" when dimensionless */
} TlColumn;

typedef struct TlTimeSeries TlTimeSeries;

/* Which files a table writes. */
typedef enum { TL_TIMESERIES_CSV = 1, TL_TIMESERIES_HDF5 = 2 } TlTimeSeriesFormat;

/* A table writing `base`.csv and/or `base`.h5 (formats: a bitwise or of
 * TlTimeSeriesFormat).  Nothing is written until the first flush.  Default
 * flushing: every 10 s of wall time, no row count. */
TlStatus tl_timeseries_create(const char *base, int formats, size_t n_columns, const TlColumn *columns,
                              TlTimeSeries **ts);
/* Flush every `every_rows` rows (0: never by count) and every
 * `every_seconds` seconds of wall time (0: never by time). */
TlStatus tl_timeseries_set_flush(TlTimeSeries *ts, size_t every_rows, double every_seconds);
/* Sizes the row buffer for `rows` rows up front. */
TlStatus tl_timeseries_reserve(TlTimeSeries *ts, size_t rows);
/* Appends one row of n_columns values; may flush. */
TlStatus tl_timeseries_append(TlTimeSeries *ts, const double *row);
/* Writes the files now. */
TlStatus tl_timeseries_flush(TlTimeSeries *ts);
/* Flushes, then frees *ts (also on a failed flush) and sets it to NULL. */
TlStatus tl_timeseries_close(TlTimeSeries **ts);
/* Frees without writing (after an error, or when the files are not wanted). */
void tl_timeseries_destroy(TlTimeSeries **ts);

size_t tl_timeseries_rows(const TlTimeSeries *ts);
size_t tl_timeseries_columns(const TlTimeSeries *ts);
/* Row-major values, rows x columns. */
const double *tl_timeseries_data(const TlTimeSeries *ts);
/* Index of a column by name, -1 when absent. */
int tl_timeseries_column(const TlTimeSeries *ts, const char *name);

/* Saves the rows and column names; load checks the names and restores the
 * rows, so the table continues where the checkpoint left it. */
extern const TlCheckpointOps tl_timeseries_checkpoint_ops;

/* ---------------------------------------------------------------- reading */
typedef struct {
  size_t rows, cols;
  double *data; /* row-major */
  char **names; /* cols names */
  char **units; /* cols units ("" when dimensionless) */
} TlTable;

/* Reads a CSV or HDF5 table written by a TlTimeSeries (or any CSV whose
 * first line not starting with '#' is the header described above). */
TlStatus tl_table_read_csv(const char *path, TlTable *table);
TlStatus tl_table_read_hdf5(const char *path, TlTable *table);
void tl_table_free(TlTable *table);

#endif
