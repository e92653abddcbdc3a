#include "tl_timeseries.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "tl_atomic_file.h"
#include "tl_hdf5_util.h"
#include "tl_memory.h"
#include "tl_provenance.h"

struct TlTimeSeries {
  char *csv_path, *h5_path; /* NULL when that format is off */
  size_t cols;
  char **names, **units;
  double *data;
  size_t rows, capacity; /* capacity in rows */
  size_t every_rows, rows_at_flush;
  double every_seconds, next_flush_time, last_flush_cost;
};

static double tl_now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static TlStatus tl_ts_concat(const char *a, const char *b, char **out)
{
  size_t na = strlen(a), nb = strlen(b);
  TL_CHECK(tl_calloc(out, na + nb + 1, 1));
  memcpy(*out, a, na);
  memcpy(*out + na, b, nb);
  return TL_OK;
}

static int tl_valid_name(const char *s)
{
  if (!s || !s[0]) return 0;
  for (; *s; ++s)
    if (!(isalnum((unsigned char)*s) || *s == '_' || *s == '.' || *s == '-')) return 0;
  return 1;
}

static int tl_valid_unit(const char *s)
{
  for (; s && *s; ++s)
    if (*s == ',' || *s == '[' || *s == ']' || *s == '\n' || *s == '\r' || *s == '"') return 0;
  return 1;
}

void tl_timeseries_destroy(TlTimeSeries **ts)
{
  if (!ts || !*ts) return;
  TlTimeSeries *t = *ts;
  for (size_t j = 0; j < t->cols; ++j) {
    if (t->names) tl_free(&t->names[j]);
    if (t->units) tl_free(&t->units[j]);
  }
  tl_free(&t->names);
  tl_free(&t->units);
  tl_free(&t->data);
  tl_free(&t->csv_path);
  tl_free(&t->h5_path);
  tl_free(ts);
}

TlStatus tl_timeseries_create(const char *base, int formats, size_t n_columns, const TlColumn *columns,
                              TlTimeSeries **ts)
{
  *ts = NULL;
  if (!base || !base[0]) TL_ERROR(TL_ERR_ARG, "time series: empty file base name");
  if (formats & ~(TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5))
    TL_ERROR(TL_ERR_ARG, "time series '%s': formats %d is not a combination of CSV (1) and HDF5 (2)", base, formats);
  if (n_columns == 0 || n_columns > 100000)
    TL_ERROR(TL_ERR_ARG, "time series '%s': %zu columns, expected 1 to 100000", base, n_columns);
  for (size_t j = 0; j < n_columns; ++j) {
    if (!tl_valid_name(columns[j].name))
      TL_ERROR(TL_ERR_ARG, "time series '%s': column %zu name '%s' must be letters, digits, '_', '.', '-'", base, j,
               columns[j].name ? columns[j].name : "(null)");
    if (!tl_valid_unit(columns[j].unit))
      TL_ERROR(TL_ERR_ARG, "time series '%s': unit '%s' of column '%s' contains one of , [ ] \" or a newline", base,
               columns[j].unit, columns[j].name);
    for (size_t k = 0; k < j; ++k)
      if (strcmp(columns[k].name, columns[j].name) == 0)
        TL_ERROR(TL_ERR_ARG, "time series '%s': column name '%s' used twice", base, columns[j].name);
  }
  {
    /* a folder that cannot take the files is reported now, not at the end of a long run */
    const char *slash = strrchr(base, '/');
    char dir[4096];
    snprintf(dir, sizeof dir, "%.*s", slash ? (slash == base ? 1 : (int)(slash - base)) : 1, slash ? base : ".");
    if (access(dir, W_OK | X_OK) != 0)
      TL_ERROR(TL_ERR_IO, "time series '%s': folder '%s' does not exist or is not writable", base, dir);
  }
  TlTimeSeries *t;
  TL_CHECK(TL_NEW(t));
  TlStatus s;
  t->cols = n_columns;
  TL_CHECK_GOTO(s, tl_calloc(&t->names, n_columns, sizeof *t->names), fail);
  TL_CHECK_GOTO(s, tl_calloc(&t->units, n_columns, sizeof *t->units), fail);
  for (size_t j = 0; j < n_columns; ++j) {
    TL_CHECK_GOTO(s, tl_strdup(columns[j].name, &t->names[j]), fail);
    TL_CHECK_GOTO(s, tl_strdup(columns[j].unit ? columns[j].unit : "", &t->units[j]), fail);
  }
  if (formats & TL_TIMESERIES_CSV) TL_CHECK_GOTO(s, tl_ts_concat(base, ".csv", &t->csv_path), fail);
  if (formats & TL_TIMESERIES_HDF5) TL_CHECK_GOTO(s, tl_ts_concat(base, ".h5", &t->h5_path), fail);
  t->every_seconds = 10.0;
  t->next_flush_time = tl_now() + t->every_seconds;
  *ts = t;
  return TL_OK;
fail:
  tl_timeseries_destroy(&t);
  return s;
}

TlStatus tl_timeseries_set_flush(TlTimeSeries *ts, size_t every_rows, double every_seconds)
{
  if (!(every_seconds >= 0.0) || every_seconds > 1e9)
    TL_ERROR(TL_ERR_ARG, "time series flush interval %g s outside [0, 1e9]", every_seconds);
  ts->every_rows = every_rows;
  ts->every_seconds = every_seconds;
  ts->next_flush_time = tl_now() + every_seconds;
  return TL_OK;
}

TlStatus tl_timeseries_reserve(TlTimeSeries *ts, size_t rows)
{
  if (rows <= ts->capacity) return TL_OK;
  if (rows > SIZE_MAX / ts->cols) TL_ERROR(TL_ERR_MEM, "time series of %zu rows overflows", rows);
  TL_CHECK(tl_realloc(&ts->data, rows * ts->cols, sizeof *ts->data));
  ts->capacity = rows;
  return TL_OK;
}

TlStatus tl_timeseries_append(TlTimeSeries *ts, const double *row)
{
  if (ts->rows == ts->capacity) TL_CHECK(tl_timeseries_reserve(ts, ts->capacity ? 2 * ts->capacity : 256));
  memcpy(ts->data + ts->rows * ts->cols, row, ts->cols * sizeof *row);
  ts->rows++;
  int due = ts->every_rows > 0 && ts->rows - ts->rows_at_flush >= ts->every_rows;
  if (!due && ts->every_seconds > 0.0 && tl_now() >= ts->next_flush_time) due = 1;
  if (due) TL_CHECK(tl_timeseries_flush(ts));
  return TL_OK;
}

static TlStatus tl_ts_write_csv(FILE *f, void *context)
{
  const TlTimeSeries *t = context;
  TL_CHECK(tl_provenance_write_text(f, "# "));
  for (size_t j = 0; j < t->cols; ++j) {
    fputs(j ? "," : "", f);
    if (t->units[j][0])
      fprintf(f, "%s [%s]", t->names[j], t->units[j]);
    else
      fputs(t->names[j], f);
  }
  fputc('\n', f);
  const double *x = t->data;
  for (size_t i = 0; i < t->rows; ++i) {
    for (size_t j = 0; j < t->cols; ++j) fprintf(f, j ? ",%.17g" : "%.17g", *x++);
    if (fputc('\n', f) == EOF) TL_ERROR(TL_ERR_IO, "write error in row %zu", i);
  }
  return TL_OK;
}

static TlStatus tl_ts_write_hdf5(const TlTimeSeries *t)
{
  TlH5File f;
  TL_CHECK(tl_h5_create(t->h5_path, &f));
  TlStatus s;
  hsize_t dims[2] = {t->rows, t->cols};
  TL_CHECK_GOTO(s, tl_h5_write(&f, "/table", H5T_NATIVE_DOUBLE, 2, dims, t->data), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_strings(&f, "/table", "columns", t->cols, (const char *const *)t->names), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_strings(&f, "/table", "units", t->cols, (const char *const *)t->units), fail);
  TL_CHECK(tl_h5_commit(&f));
  return TL_OK;
fail:
  tl_h5_abort(&f);
  return s;
}

TlStatus tl_timeseries_flush(TlTimeSeries *ts)
{
  double start = tl_now();
  if (ts->csv_path) TL_CHECK(tl_atomic_write(ts->csv_path, tl_ts_write_csv, ts));
  if (ts->h5_path) TL_CHECK(tl_ts_write_hdf5(ts));
  double end = tl_now();
  ts->rows_at_flush = ts->rows;
  /* the whole table is rewritten at each flush: keep that under ~5% of the
   * wall time however long the table grows */
  ts->last_flush_cost = end - start;
  double wait = ts->every_seconds;
  if (wait > 0.0 && wait < 20.0 * ts->last_flush_cost) wait = 20.0 * ts->last_flush_cost;
  ts->next_flush_time = end + wait;
  return TL_OK;
}

TlStatus tl_timeseries_close(TlTimeSeries **ts)
{
  if (!*ts) return TL_OK;
  TlStatus s = tl_timeseries_flush(*ts);
  tl_timeseries_destroy(ts);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}

size_t tl_timeseries_rows(const TlTimeSeries *ts) { return ts->rows; }
size_t tl_timeseries_columns(const TlTimeSeries *ts) { return ts->cols; }
const double *tl_timeseries_data(const TlTimeSeries *ts) { return ts->data; }

int tl_timeseries_column(const TlTimeSeries *ts, const char *name)
{
  for (size_t j = 0; j < ts->cols; ++j)
    if (strcmp(ts->names[j], name) == 0) return (int)j;
  return -1;
}

/* ---------------------------------------------------------------- checkpoint */
static TlStatus tl_ts_joined_names(const TlTimeSeries *t, char **out)
{
  size_t n = 1;
  for (size_t j = 0; j < t->cols; ++j) n += strlen(t->names[j]) + 1;
  TL_CHECK(tl_calloc(out, n, 1));
  char *p = *out;
  for (size_t j = 0; j < t->cols; ++j) {
    if (j) *p++ = ',';
    size_t k = strlen(t->names[j]);
    memcpy(p, t->names[j], k);
    p += k;
  }
  return TL_OK;
}

static TlStatus tl_ts_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlTimeSeries *t = object;
  char *names;
  TL_CHECK(tl_ts_joined_names(t, &names));
  TlStatus s = tl_checkpoint_write_string(w, group, "columns", names);
  tl_free(&names);
  TL_CHECK(s);
  TL_CHECK(tl_checkpoint_write_int64(w, group, "rows", (int64_t)t->rows));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "data", t->rows * t->cols, t->data));
  return TL_OK;
}

static TlStatus tl_ts_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlTimeSeries *t = object;
  char *mine = NULL, *theirs = NULL;
  TL_CHECK(tl_ts_joined_names(t, &mine));
  TlStatus s;
  TL_CHECK_GOTO(s, tl_checkpoint_read_string(r, group, "columns", &theirs), done);
  if (strcmp(mine, theirs) != 0) {
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                     "checkpoint '%s': time series '%s' has columns '%s', this run has '%s'",
                     tl_checkpoint_reader_path(r), group, theirs, mine);
    goto done;
  }
  int64_t rows = 0;
  TL_CHECK_GOTO(s, tl_checkpoint_read_int64(r, group, "rows", &rows), done);
  if (rows < 0) {
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "checkpoint '%s': time series '%s' has %lld rows",
                     tl_checkpoint_reader_path(r), group, (long long)rows);
    goto done;
  }
  TL_CHECK_GOTO(s, tl_timeseries_reserve(t, (size_t)rows), done);
  TL_CHECK_GOTO(s, tl_checkpoint_read_doubles(r, group, "data", (size_t)rows * t->cols, t->data), done);
  t->rows = t->rows_at_flush = (size_t)rows;
done:
  tl_free(&mine);
  tl_free(&theirs);
  return s;
}

const TlCheckpointOps tl_timeseries_checkpoint_ops = {
    {"checkpoint", "timeseries_v1", "rows and column names of a time-series table"}, tl_ts_save, tl_ts_load};

/* ---------------------------------------------------------------- reading */
void tl_table_free(TlTable *table)
{
  for (size_t j = 0; j < table->cols; ++j) {
    if (table->names) tl_free(&table->names[j]);
    if (table->units) tl_free(&table->units[j]);
  }
  tl_free(&table->names);
  tl_free(&table->units);
  tl_free(&table->data);
  table->rows = table->cols = 0;
}

/* Splits "name [unit]" into its parts. */
static TlStatus tl_table_set_header(TlTable *t, size_t j, const char *cell, size_t len)
{
  while (len > 0 && isspace((unsigned char)cell[len - 1])) --len;
  while (len > 0 && isspace((unsigned char)*cell)) ++cell, --len;
  size_t name_len = len, unit_at = len, unit_len = 0;
  if (len > 0 && cell[len - 1] == ']') {
    const char *open = memchr(cell, '[', len);
    if (open) {
      name_len = (size_t)(open - cell);
      while (name_len > 0 && cell[name_len - 1] == ' ') --name_len;
      unit_at = (size_t)(open - cell) + 1;
      unit_len = len - 1 - unit_at;
    }
  }
  TL_CHECK(tl_calloc(&t->names[j], name_len + 1, 1));
  memcpy(t->names[j], cell, name_len);
  TL_CHECK(tl_calloc(&t->units[j], unit_len + 1, 1));
  memcpy(t->units[j], cell + unit_at, unit_len);
  return TL_OK;
}

static TlStatus tl_table_read_csv_stream(FILE *f, const char *path, TlTable *t)
{
  char *line = NULL;
  size_t cap = 0;
  size_t lineno = 1;
  ssize_t len = getline(&line, &cap, f);
  /* Comment lines before the header (the provenance) are skipped. */
  while (len > 0 && line[0] == '#') {
    len = getline(&line, &cap, f);
    ++lineno;
  }
  TlStatus s = TL_OK;
  if (len <= 0) {
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "'%s' is empty: no header line", path);
    goto done;
  }
  size_t cols = 1;
  for (ssize_t i = 0; i < len; ++i) cols += line[i] == ',';
  TL_CHECK_GOTO(s, tl_calloc(&t->names, cols, sizeof *t->names), done);
  TL_CHECK_GOTO(s, tl_calloc(&t->units, cols, sizeof *t->units), done);
  t->cols = cols;
  {
    const char *cell = line;
    for (size_t j = 0; j < cols; ++j) {
      const char *end = strchr(cell, ',');
      if (!end) end = cell + strlen(cell);
      TL_CHECK_GOTO(s, tl_table_set_header(t, j, cell, (size_t)(end - cell)), done);
      cell = end + 1;
    }
  }
  size_t capacity = 0;
  while ((len = getline(&line, &cap, f)) > 0) {
    ++lineno;
    if (len == 1 && line[0] == '\n') continue;
    TL_CHECK_GOTO(s, tl_array_reserve(&t->data, &capacity, (t->rows + 1) * cols, sizeof *t->data), done);
    char *p = line;
    for (size_t j = 0; j < cols; ++j) {
      char *end;
      errno = 0;
      double v = strtod(p, &end);
      if (end == p || (j + 1 < cols && *end != ',') || (j + 1 == cols && *end != '\n' && *end != '\0' && *end != '\r')) {
        s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "'%s' line %zu: column %zu ('%s') is not a number: '%.40s'",
                         path, lineno, j + 1, t->names[j], p);
        goto done;
      }
      t->data[t->rows * cols + j] = v;
      p = end + 1;
    }
    t->rows++;
  }
done:
  free(line);
  return s;
}

TlStatus tl_table_read_csv(const char *path, TlTable *table)
{
  memset(table, 0, sizeof *table);
  FILE *f = fopen(path, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot open '%s': %s", path, strerror(errno));
  TlStatus s = tl_table_read_csv_stream(f, path, table);
  fclose(f);
  if (s != TL_OK) {
    tl_table_free(table);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}

TlStatus tl_table_read_hdf5(const char *path, TlTable *table)
{
  memset(table, 0, sizeof *table);
  TlH5File f;
  TL_CHECK(tl_h5_open(path, &f));
  TlStatus s;
  int rank;
  hsize_t dims[TL_H5_MAX_RANK];
  size_t n_names = 0, n_units = 0;
  TL_CHECK_GOTO(s, tl_h5_dims(&f, "/table", &rank, dims), fail);
  if (rank != 2) {
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "'%s': /table has rank %d, expected 2", path, rank);
    goto fail;
  }
  TL_CHECK_GOTO(s, tl_h5_attr_read_strings(&f, "/table", "columns", &n_names, &table->names), fail);
  table->cols = n_names;
  TL_CHECK_GOTO(s, tl_h5_attr_read_strings(&f, "/table", "units", &n_units, &table->units), fail);
  if (n_names != dims[1] || n_units != dims[1]) {
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "'%s': /table has %llu columns but %zu names and %zu units",
                     path, (unsigned long long)dims[1], n_names, n_units);
    goto fail;
  }
  table->rows = (size_t)dims[0];
  TL_CHECK_GOTO(s, tl_calloc(&table->data, table->rows * table->cols, sizeof *table->data), fail);
  TL_CHECK_GOTO(s, tl_h5_read(&f, "/table", H5T_NATIVE_DOUBLE, 2, dims, table->data), fail);
  tl_h5_close(&f);
  return TL_OK;
fail:
  if (table->units && n_units != table->cols) tl_h5_free_strings(n_units, &table->units);
  tl_table_free(table);
  tl_h5_close(&f);
  return s;
}
