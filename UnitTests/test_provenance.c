/* Provenance: an HDF5 particle snapshot and a CSV table written by a
 * program record the Talus version, the git revision, the command line and
 * every option in force (defaults included), read back with the library's
 * readers; the CSV still reads as a table; a file written with no options
 * database records the version alone. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_provenance.h"
#include "tl_test.h"

static void check(const TlProvenance *p, const char *what)
{
  TL_TEST_ASSERT(p->version && strcmp(p->version, tl_version()) == 0, "%s: version %s", what,
                 p->version ? p->version : "(none)");
  TL_TEST_ASSERT(p->revision && strcmp(p->revision, tl_revision()) == 0 && p->revision[0], "%s: revision %s", what,
                 p->revision ? p->revision : "(none)");
  TL_TEST_ASSERT(p->program && strcmp(p->program, "prov_prog") == 0, "%s: program %s", what,
                 p->program ? p->program : "(none)");
  TL_TEST_ASSERT(p->command_line && strcmp(p->command_line, "dir/prov_prog -t_end 2 -label 'two words' -t_end 3") == 0,
                 "%s: command line '%s'", what, p->command_line ? p->command_line : "(none)");
  const char *t_end = tl_provenance_option(p, "-t_end"), *dt = tl_provenance_option(p, "-dt");
  const char *label = tl_provenance_option(p, "-label"), *mode = tl_provenance_option(p, "-mode");
  TL_TEST_ASSERT(p->n_options == 4, "%s: %zu options recorded (expected 4)", what, p->n_options);
  TL_TEST_ASSERT(t_end && strcmp(t_end, "3") == 0, "%s: -t_end %s (the last value given)", what, t_end ? t_end : "absent");
  TL_TEST_ASSERT(dt && strcmp(dt, "0.001") == 0, "%s: -dt %s (the default, never given)", what, dt ? dt : "absent");
  TL_TEST_ASSERT(label && strcmp(label, "two words") == 0, "%s: -label %s", what, label ? label : "absent");
  TL_TEST_ASSERT(mode && strcmp(mode, "fast") == 0, "%s: -mode %s", what, mode ? mode : "absent");
}

int main(void)
{
  tl_log_set_level(TL_LOG_ERROR);
  const char *argv[] = {"dir/prov_prog", "-t_end", "2", "-label", "two words", "-t_end", "3"};
  TlOptions *o = NULL;
  TL_TEST_STATUS(tl_options_create(7, (char **)argv, "provenance test", &o), TL_OK);
  double t_end, dt;
  const char *label;
  int mode;
  const char *const modes[] = {"fast", "slow", NULL};
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 1, 0, INFINITY, "s", "end time", &t_end), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-dt", 1e-3, 0, INFINITY, "s", "time step", &dt), TL_OK);
  TL_TEST_STATUS(tl_options_get_string(o, "-label", "", "a label", &label), TL_OK);
  TL_TEST_STATUS(tl_options_get_choice(o, "-mode", "fast", modes, "mode", &mode), TL_OK);
  TL_TEST_ASSERT(tl_options_current() == NULL, "no current database before finish");
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
  TL_TEST_ASSERT(tl_options_current() == o, "the finished database is the current one");

  /* An HDF5 snapshot. */
  TlParticleWriter *w = NULL;
  TL_TEST_STATUS(tl_particle_writer_create("provenance_out", "p", &w), TL_OK);
  TlVec3 x[2] = {{0, 0, 0}, {1, 0, 0}};
  double r[2] = {0.5, 0.5};
  TlParticleView view = {.n = 2, .position = x, .radius = r};
  TL_TEST_STATUS(tl_particle_writer_write(w, 0, 0.0, &view), TL_OK);
  char h5[512];
  snprintf(h5, sizeof h5, "%s", tl_particle_writer_last_path(w));
  tl_particle_writer_destroy(&w);
  TlProvenance p;
  TL_TEST_STATUS(tl_provenance_read_h5(h5, &p), TL_OK);
  check(&p, h5);
  tl_provenance_free(&p);

  /* A CSV table (and its HDF5 twin). */
  const TlColumn cols[] = {{"t", "s"}, {"e", "J"}};
  TlTimeSeries *ts = NULL;
  TL_TEST_STATUS(tl_timeseries_create("provenance_out/table", TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, 2, cols, &ts),
                 TL_OK);
  double row[2] = {0.5, 1.25};
  TL_TEST_STATUS(tl_timeseries_append(ts, row), TL_OK);
  TL_TEST_STATUS(tl_timeseries_close(&ts), TL_OK);
  TL_TEST_STATUS(tl_provenance_read_text("provenance_out/table.csv", &p), TL_OK);
  check(&p, "table.csv");
  tl_provenance_free(&p);
  TL_TEST_STATUS(tl_provenance_read_h5("provenance_out/table.h5", &p), TL_OK);
  check(&p, "table.h5");
  tl_provenance_free(&p);
  char *text = tl_test_read_file("provenance_out/table.csv");
  TL_TEST_ASSERT(text && strncmp(text, "# talus_version: ", 17) == 0 && strstr(text, "\n# option: -dt 0.001\n") &&
                     strstr(text, "\nt [s],e [J]\n0.5,1.25\n"),
                 "CSV layout:\n%s", text ? text : "(unreadable)");
  free(text);
  TlTable table;
  TL_TEST_STATUS(tl_table_read_csv("provenance_out/table.csv", &table), TL_OK);
  TL_TEST_ASSERT(table.rows == 1 && table.cols == 2 && table.data[1] == 1.25 && strcmp(table.units[1], "J") == 0,
                 "the CSV reads as a table past its comment lines: %zu x %zu", table.rows, table.cols);
  tl_table_free(&table);

  /* Without an options database: the version and revision alone. */
  tl_options_destroy(&o);
  TL_TEST_ASSERT(tl_options_current() == NULL, "destroy forgets the current database");
  TL_TEST_STATUS(tl_timeseries_create("provenance_out/bare", TL_TIMESERIES_CSV, 2, cols, &ts), TL_OK);
  TL_TEST_STATUS(tl_timeseries_append(ts, row), TL_OK);
  TL_TEST_STATUS(tl_timeseries_close(&ts), TL_OK);
  TL_TEST_STATUS(tl_provenance_read_text("provenance_out/bare.csv", &p), TL_OK);
  TL_TEST_ASSERT(p.version && strcmp(p.version, tl_version()) == 0 && p.command_line && p.command_line[0] == '\0' &&
                     p.n_options == 0,
                 "bare provenance: version %s, command line '%s', %zu options", p.version ? p.version : "(none)",
                 p.command_line ? p.command_line : "(none)", p.n_options);
  tl_provenance_free(&p);
  /* A file that is not a Talus output says so. */
  FILE *f = fopen("provenance_out/plain.csv", "w");
  if (f) {
    fputs("a,b\n1,2\n", f);
    fclose(f);
  }
  TL_TEST_STATUS(tl_provenance_read_text("provenance_out/plain.csv", &p), TL_ERR_NOT_FOUND);
  return tl_test_report();
}
