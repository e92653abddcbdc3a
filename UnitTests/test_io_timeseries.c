/* Time series: CSV parsed back and HDF5 read back exactly; names and units;
 * flushing by row count leaves complete files of the rows so far; appending
 * does not reallocate once reserved; a checkpointed table restarted midway
 * writes byte-identical files; bad column names refused. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "talus.h"
#include "tl_io.h"
#include "tl_test.h"

static const TlColumn columns[3] = {{"time", "s"}, {"kinetic_energy", "J"}, {"contacts", NULL}};

static void row_of(int i, double *r)
{
  r[0] = i * 1e-4;
  r[1] = (i % 7 == 0) ? -0.0 : 1.0 / (i + 3.0) * 1e-300 + (i == 5 ? 5e-324 : 0.0);
  r[2] = i % 13;
}

static int table_matches(const TlTable *t, size_t rows)
{
  if (t->rows != rows || t->cols != 3) return 0;
  for (size_t i = 0; i < rows; ++i) {
    double r[3];
    row_of((int)i, r);
    if (memcmp(r, t->data + 3 * i, sizeof r) != 0) return 0;
  }
  return 1;
}

static void test_round_trip(void)
{
  TlTimeSeries *ts;
  TL_TEST_STATUS(tl_timeseries_create("energy", TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, 3, columns, &ts), TL_OK);
  if (!ts) return;
  TL_TEST_STATUS(tl_timeseries_set_flush(ts, 100, 0.0), TL_OK);
  TL_TEST_STATUS(tl_timeseries_reserve(ts, 1000), TL_OK);
  const double *buffer = tl_timeseries_data(ts);
  TlTable t;
  for (int i = 0; i < 1000; ++i) {
    double r[3];
    row_of(i, r);
    TL_TEST_STATUS(tl_timeseries_append(ts, r), TL_OK);
    if (i == 249) { /* as a killed run would leave it: the rows up to the last flush */
      TL_TEST_STATUS(tl_table_read_csv("energy.csv", &t), TL_OK);
      TL_TEST_ASSERT(table_matches(&t, 200), "CSV after 250 rows holds %zu rows, expected 200", t.rows);
      tl_table_free(&t);
      TL_TEST_STATUS(tl_table_read_hdf5("energy.h5", &t), TL_OK);
      TL_TEST_ASSERT(table_matches(&t, 200), "HDF5 after 250 rows holds %zu rows, expected 200", t.rows);
      tl_table_free(&t);
    }
  }
  TL_TEST_ASSERT(tl_timeseries_data(ts) == buffer, "the row buffer moved although 1000 rows were reserved");
  TL_TEST_ASSERT(tl_timeseries_rows(ts) == 1000 && tl_timeseries_columns(ts) == 3, "size");
  TL_TEST_ASSERT(tl_timeseries_column(ts, "kinetic_energy") == 1 && tl_timeseries_column(ts, "nope") == -1, "lookup");
  TL_TEST_STATUS(tl_timeseries_close(&ts), TL_OK);
  TL_TEST_ASSERT(ts == NULL, "close must null");

  TL_TEST_STATUS(tl_table_read_csv("energy.csv", &t), TL_OK);
  TL_TEST_ASSERT(table_matches(&t, 1000), "CSV round trip: %zu rows", t.rows);
  if (t.cols == 3) {
    TL_TEST_ASSERT(strcmp(t.names[0], "time") == 0 && strcmp(t.units[0], "s") == 0, "column 0 '%s' '%s'", t.names[0], t.units[0]);
    TL_TEST_ASSERT(strcmp(t.names[1], "kinetic_energy") == 0 && strcmp(t.units[1], "J") == 0, "column 1");
    TL_TEST_ASSERT(strcmp(t.names[2], "contacts") == 0 && t.units[2][0] == '\0', "column 2");
  }
  tl_table_free(&t);
  TL_TEST_STATUS(tl_table_read_hdf5("energy.h5", &t), TL_OK);
  TL_TEST_ASSERT(table_matches(&t, 1000), "HDF5 round trip: %zu rows", t.rows);
  if (t.cols == 3)
    TL_TEST_ASSERT(strcmp(t.names[1], "kinetic_energy") == 0 && strcmp(t.units[1], "J") == 0, "HDF5 names/units");
  tl_table_free(&t);

  /* The provenance comment lines (tl_provenance.h), then the header. */
  char *csv = tl_test_read_file("energy.csv");
  const char *head = csv ? strstr(csv, "\ntime [s]") : NULL;
  TL_TEST_ASSERT(csv && strncmp(csv, "# talus_version: ", 17) == 0 && head &&
                     strncmp(head + 1, "time [s],kinetic_energy [J],contacts\n0,-0,0\n", 44) == 0,
                 "CSV head: %.300s", csv ? csv : "(none)");
  for (const char *c = csv; c && c < head; c = strchr(c, '\n') + 1)
    TL_TEST_ASSERT(*c == '#', "a line before the header that is not a comment: %.40s", c);
  free(csv);
}

static void test_restart(void)
{
  /* straight run */
  TlTimeSeries *a;
  TL_TEST_STATUS(tl_timeseries_create("straight", TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, 3, columns, &a), TL_OK);
  if (!a) return;
  for (int i = 0; i < 300; ++i) {
    double r[3];
    row_of(i, r);
    TL_TEST_STATUS(tl_timeseries_append(a, r), TL_OK);
  }
  TL_TEST_STATUS(tl_timeseries_close(&a), TL_OK);

  /* checkpoint at 120 rows, more rows lost in a crash, restart, finish */
  TlTimeSeries *b;
  TL_TEST_STATUS(tl_timeseries_create("restarted", TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, 3, columns, &b), TL_OK);
  TlCheckpoint *cp;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "energy", &tl_timeseries_checkpoint_ops, b), TL_OK);
  double r[3];
  for (int i = 0; i < 150; ++i) {
    row_of(i, r);
    TL_TEST_STATUS(tl_timeseries_append(b, r), TL_OK);
    if (i == 119) TL_TEST_STATUS(tl_checkpoint_save(cp, "ck.h5", 0.0, 120), TL_OK);
  }
  TL_TEST_STATUS(tl_timeseries_flush(b), TL_OK);
  tl_timeseries_destroy(&b);
  tl_checkpoint_destroy(&cp);

  TlTimeSeries *c;
  TL_TEST_STATUS(tl_timeseries_create("restarted", TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, 3, columns, &c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "energy", &tl_timeseries_checkpoint_ops, c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp, "ck.h5", NULL, NULL), TL_OK);
  TL_TEST_ASSERT(tl_timeseries_rows(c) == 120, "restored %zu rows", tl_timeseries_rows(c));
  for (int i = 120; i < 300; ++i) {
    row_of(i, r);
    TL_TEST_STATUS(tl_timeseries_append(c, r), TL_OK);
  }
  TL_TEST_STATUS(tl_timeseries_close(&c), TL_OK);
  char *x = tl_test_read_file("straight.csv"), *y = tl_test_read_file("restarted.csv");
  TL_TEST_ASSERT(x && y && strcmp(x, y) == 0, "restarted CSV differs from the straight run");
  free(x);
  free(y);
  TlTable t;
  TL_TEST_STATUS(tl_table_read_hdf5("restarted.h5", &t), TL_OK);
  TL_TEST_ASSERT(table_matches(&t, 300), "restarted HDF5 table");
  tl_table_free(&t);

  /* a table with other columns refuses the checkpoint, naming both */
  static const TlColumn other[3] = {{"time", "s"}, {"potential_energy", "J"}, {"contacts", NULL}};
  TlTimeSeries *d;
  TL_TEST_STATUS(tl_timeseries_create("other", TL_TIMESERIES_CSV, 3, other, &d), TL_OK);
  TlCheckpoint *cp2;
  TL_TEST_STATUS(tl_checkpoint_create(&cp2), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp2, "energy", &tl_timeseries_checkpoint_ops, d), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp2, "ck.h5", NULL, NULL), TL_ERR_FORMAT);
  TL_TEST_ASSERT(strstr(tl_error_message(), "potential_energy") != NULL, "message: %s", tl_error_message());
  tl_checkpoint_destroy(&cp);
  tl_checkpoint_destroy(&cp2);
  tl_timeseries_destroy(&d);
}

static void test_errors(void)
{
  TlTimeSeries *ts;
  static const TlColumn comma[1] = {{"a,b", NULL}};
  TL_TEST_STATUS(tl_timeseries_create("bad", TL_TIMESERIES_CSV, 1, comma, &ts), TL_ERR_ARG);
  static const TlColumn twice[2] = {{"a", NULL}, {"a", "m"}};
  TL_TEST_STATUS(tl_timeseries_create("bad", TL_TIMESERIES_CSV, 2, twice, &ts), TL_ERR_ARG);
  static const TlColumn bad_unit[1] = {{"a", "m[2]"}};
  TL_TEST_STATUS(tl_timeseries_create("bad", TL_TIMESERIES_CSV, 1, bad_unit, &ts), TL_ERR_ARG);
  TL_TEST_STATUS(tl_timeseries_create("bad", TL_TIMESERIES_CSV, 0, columns, &ts), TL_ERR_ARG);
  TL_TEST_STATUS(tl_timeseries_create("bad", 8, 3, columns, &ts), TL_ERR_ARG);
  /* a missing folder is reported when the table is created, not at its first flush */
  TL_TEST_STATUS(tl_timeseries_create("nodir/x", TL_TIMESERIES_CSV, 3, columns, &ts), TL_ERR_IO);
  TL_TEST_ASSERT(strstr(tl_error_message(), "'nodir'") != NULL, "message: %s", tl_error_message());
  TL_TEST_STATUS(tl_mkdir_p("later"), TL_OK);
  TL_TEST_STATUS(tl_timeseries_create("later/x", TL_TIMESERIES_CSV, 3, columns, &ts), TL_OK);
  TL_TEST_STATUS(tl_timeseries_set_flush(ts, 0, -1.0), TL_ERR_ARG);
  rmdir("later"); /* removed during the run: close reports it and still frees */
  TL_TEST_STATUS(tl_timeseries_close(&ts), TL_ERR_IO);
  TL_TEST_ASSERT(ts == NULL, "close must free even on failure");
  FILE *f = fopen("garbage.csv", "w");
  fputs("a [m],b\n1,2\n3,x\n", f);
  fclose(f);
  TlTable t;
  TL_TEST_STATUS(tl_table_read_csv("garbage.csv", &t), TL_ERR_FORMAT);
  TL_TEST_ASSERT(strstr(tl_error_message(), "line 3") && strstr(tl_error_message(), "'b'"), "message: %s",
                 tl_error_message());
}

/* A table closed before any row still writes valid files with the header. */
static void test_empty(void)
{
  TlTimeSeries *ts;
  TL_TEST_STATUS(tl_timeseries_create("empty", TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, 3, columns, &ts), TL_OK);
  TL_TEST_STATUS(tl_timeseries_close(&ts), TL_OK);
  TlTable t;
  TL_TEST_STATUS(tl_table_read_csv("empty.csv", &t), TL_OK);
  TL_TEST_ASSERT(t.rows == 0 && t.cols == 3, "empty CSV: %zu x %zu", t.rows, t.cols);
  tl_table_free(&t);
  TL_TEST_STATUS(tl_table_read_hdf5("empty.h5", &t), TL_OK);
  TL_TEST_ASSERT(t.rows == 0 && t.cols == 3, "empty HDF5: %zu x %zu", t.rows, t.cols);
  tl_table_free(&t);
}

int main(void)
{
  test_empty();
  test_round_trip();
  test_restart();
  test_errors();
  return tl_test_report();
}
