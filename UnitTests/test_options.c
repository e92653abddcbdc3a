/* The options database: typed getters, defaults, ranges, suffixes, files,
 * -help (grouped, with ranges, wrapped at 100 columns), --help, -version,
 * -options_left, -log_level, the last value of a repeated option winning,
 * suggestions only for close names, and every rejection (unknown,
 * malformed, out of range). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_test.h"

static TlStatus make(TlOptions **o, int argc, const char **argv)
{
  return tl_options_create(argc, (char **)argv, "test program", o);
}

static void test_values(void)
{
  const char *argv[] = {"prog", "-t_end", "40", "-n", "7", "-flag", "-name", "abc", "-neg", "-0.5",
                        "-mode", "cosine", "-width", "10d", "-list", "0,2,4.5", "-off", "false"};
  TlOptions *o;
  TL_TEST_STATUS(make(&o, 18, argv), TL_OK);
  double t, neg, width, list[8];
  long n;
  int flag, off, mode, count, absent;
  const char *name;
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 1.0, 0.0, INFINITY, "s", "end time", &t), TL_OK);
  TL_TEST_CLOSE(t, 40.0, 0);
  TL_TEST_STATUS(tl_options_get_real(o, "-neg", 0.0, -1.0, 1.0, "m", "a negative value", &neg), TL_OK);
  TL_TEST_CLOSE(neg, -0.5, 0);
  TL_TEST_STATUS(tl_options_get_int(o, "-n", 1, 0, 100, "count", &n), TL_OK);
  TL_TEST_ASSERT(n == 7, "n = %ld", n);
  TL_TEST_STATUS(tl_options_get_bool(o, "-flag", 0, "a flag", &flag), TL_OK);
  TL_TEST_ASSERT(flag == 1, "flag = %d", flag);
  TL_TEST_STATUS(tl_options_get_bool(o, "-off", 1, "a flag set false", &off), TL_OK);
  TL_TEST_ASSERT(off == 0, "off = %d", off);
  TL_TEST_STATUS(tl_options_get_bool(o, "-absent", 1, "default true", &absent), TL_OK);
  TL_TEST_ASSERT(absent == 1, "absent = %d", absent);
  TL_TEST_STATUS(tl_options_get_string(o, "-name", "x", "a name", &name), TL_OK);
  TL_TEST_ASSERT(strcmp(name, "abc") == 0, "name = %s", name);
  const char *const modes[] = {"pulse", "cosine", "cycles", NULL};
  TL_TEST_STATUS(tl_options_get_choice(o, "-mode", "pulse", modes, "excitation", &mode), TL_OK);
  TL_TEST_ASSERT(mode == 1, "mode = %d", mode);
  const TlScale scales[] = {{"d", 0.2, "particle diameter"}, {"h", 0.4, "element size"}};
  TL_TEST_STATUS(tl_options_get_scaled(o, "-width", "0", 0.0, INFINITY, "m", scales, 2, "CG width", &width), TL_OK);
  TL_TEST_CLOSE(width, 2.0, 1e-15);
  TL_TEST_STATUS(tl_options_get_real_list(o, "-list", "1", "m", "values", list, 8, &count), TL_OK);
  TL_TEST_ASSERT(count == 3 && list[2] == 4.5, "count = %d", count);
  double def;
  TL_TEST_STATUS(tl_options_get_real(o, "-dt", 1e-3, 0.0, INFINITY, "s", "time step", &def), TL_OK);
  TL_TEST_CLOSE(def, 1e-3, 0);
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
  tl_options_destroy(&o);
  TL_TEST_ASSERT(o == NULL, "destroy must null the handle");
}

/* Runs one getter on a one-option command line and expects a refusal whose
 * message contains `needle`. */
static void expect_refusal(const char *opt, const char *value, int kind, const char *needle)
{
  const char *argv[] = {"prog", opt, value};
  TlOptions *o;
  TL_TEST_STATUS(make(&o, value ? 3 : 2, argv), TL_OK);
  TlStatus s = TL_OK;
  double r;
  long i;
  int b, c;
  const char *const choices[] = {"a", "b", NULL};
  const TlScale scales[] = {{"d", 1.0, "diameter"}};
  switch (kind) {
  case 0: s = tl_options_get_real(o, opt, 1.0, 0.0, 10.0, "m", "r", &r); break;
  case 1: s = tl_options_get_int(o, opt, 1, 0, 10, "i", &i); break;
  case 2: s = tl_options_get_bool(o, opt, 0, "b", &b); break;
  case 3: s = tl_options_get_choice(o, opt, "a", choices, "c", &c); break;
  case 4: s = tl_options_get_scaled(o, opt, "1", 0.0, 10.0, "m", scales, 1, "s", &r); break;
  }
  TL_TEST_ASSERT(s == TL_ERR_ARG, "%s %s accepted (status %d)", opt, value ? value : "", (int)s);
  TL_TEST_ASSERT(strstr(tl_error_message(), needle) != NULL, "message '%s' lacks '%s'", tl_error_message(), needle);
  tl_options_destroy(&o);
}

static void test_rejections(void)
{
  expect_refusal("-radius", "abc", 0, "'abc' is not a finite real number");
  expect_refusal("-radius", "1.5x", 0, "not a finite real number");
  expect_refusal("-radius", "nan", 0, "not a finite real number");
  expect_refusal("-radius", "-0.1", 0, "outside [0, 10]");
  expect_refusal("-radius", "11", 0, "outside [0, 10]");
  expect_refusal("-radius", NULL, 0, "needs a value");
  expect_refusal("-count", "3.5", 1, "'3.5' is not an integer");
  expect_refusal("-count", "99", 1, "outside [0, 10]");
  expect_refusal("-flag", "maybe", 2, "'maybe' is not a boolean");
  expect_refusal("-mode", "z", 3, "'z' is not one of <a|b>");
  expect_refusal("-width", "3q", 4, "unknown unit suffix 'q'");
  expect_refusal("-width", "20d", 4, "outside [0, 10]");

  /* An option given twice: the last value wins (driver $DEFAULTS "$@"). */
  const char *dup[] = {"prog", "-t_end", "1", "-flag", "-t_end", "2", "-flag", "no"};
  TlOptions *o = NULL;
  TL_TEST_STATUS(make(&o, 8, dup), TL_OK);
  double t_dup = 0;
  int flag_dup = -1;
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 5, 0, INFINITY, "s", "end time", &t_dup), TL_OK);
  TL_TEST_STATUS(tl_options_get_bool(o, "-flag", 1, "a flag", &flag_dup), TL_OK);
  TL_TEST_ASSERT(t_dup == 2.0 && flag_dup == 0, "repeated options: -t_end %g (expected 2), -flag %d (expected 0)",
                 t_dup, flag_dup);
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
  tl_options_destroy(&o);

  /* A stray word that is not an option. */
  const char *stray[] = {"prog", "-t_end", "1", "2"};
  TL_TEST_STATUS(make(&o, 4, stray), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "'2' is not an option") != NULL, "%s", tl_error_message());
  TL_TEST_ASSERT(o == NULL, "a failed create leaves no object");

  /* A typo is refused with a suggestion, never ignored. */
  const char *typo[] = {"prog", "-t_ned", "5"};
  TL_TEST_STATUS(make(&o, 3, typo), TL_OK);
  double t;
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 1, 0, INFINITY, "s", "end time", &t), TL_OK);
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "unknown option -t_ned") && strstr(tl_error_message(), "did you mean -t_end"),
                 "%s", tl_error_message());
  tl_options_destroy(&o);

  /* An unrelated unknown option is refused too. */
  const char *unknown[] = {"prog", "-zzzzzzzz", "5"};
  TL_TEST_STATUS(make(&o, 3, unknown), TL_OK);
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "unknown option -zzzzzzzz") != NULL, "%s", tl_error_message());
  tl_options_destroy(&o);

  /* A suggestion only for a close name: -foo is two edits from -rho, too
   * far for a three-letter name; -dencity is one from -density; a
   * transposition counts as one edit. */
  static const struct {
    const char *typed, *expect;
  } near[] = {{"-foo", NULL},        {"-rhoo", "-rho"},  {"-dencity", "-density"}, {"-desnity", "-density"},
              {"-t_ned", "-t_end"},  {"-xyz", NULL},     {"-cg_widht", "-cg_width"}, {"-hepl", "-help"},
              {"-density_x", "-density"}};
  const char *known[] = {"prog"};
  TL_TEST_STATUS(make(&o, 1, known), TL_OK);
  double r;
  TL_TEST_STATUS(tl_options_get_real(o, "-rho", 1, 0, INFINITY, "kg/m^3", "density", &r), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-density", 1, 0, INFINITY, "kg/m^3", "density", &r), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 1, 0, INFINITY, "s", "end time", &r), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-cg_width", 1, 0, INFINITY, "m", "width", &r), TL_OK);
  for (size_t i = 0; i < sizeof near / sizeof near[0]; ++i) {
    const char *got = tl_options_suggest(o, near[i].typed);
    TL_TEST_ASSERT((got == NULL && near[i].expect == NULL) ||
                       (got && near[i].expect && strcmp(got, near[i].expect) == 0),
                   "suggestion for %s: %s (expected %s)", near[i].typed, got ? got : "none",
                   near[i].expect ? near[i].expect : "none");
  }
  tl_options_destroy(&o);
  const char *foo[] = {"prog", "-foo", "1", "-t_edn", "2"};
  TL_TEST_STATUS(make(&o, 5, foo), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-rho", 1, 0, INFINITY, "kg/m^3", "density", &r), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 1, 0, INFINITY, "s", "end time", &r), TL_OK);
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_ERR_ARG);
  const char *m = tl_error_message();
  TL_TEST_ASSERT(strstr(m, "-foo (command line, argument 1);") && !strstr(m, "did you mean -rho") &&
                     strstr(m, "-t_edn (command line, argument 3), did you mean -t_end?"),
                 "both unknown options named, a suggestion only for the close one: %s", m);
  tl_options_destroy(&o);

  /* -options_left: the unread options are listed, not refused. */
  const char *left[] = {"prog", "-options_left", "-unread", "3", "-t_end", "1"};
  TL_TEST_STATUS(make(&o, 6, left), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 5, 0, INFINITY, "s", "end time", &r), TL_OK);
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
  tl_options_destroy(&o);
  const char *left_no[] = {"prog", "-options_left", "false", "-unread", "3"};
  TL_TEST_STATUS(make(&o, 5, left_no), TL_OK);
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_ERR_ARG);
  tl_options_destroy(&o);

  /* -log_level sets the logger's level; an unknown level is refused. */
  TlLogLevel before = tl_log_get_level();
  const char *lv[] = {"prog", "-log_level", "debug"};
  TL_TEST_STATUS(make(&o, 3, lv), TL_OK);
  TL_TEST_ASSERT(tl_log_get_level() == TL_LOG_DEBUG, "-log_level debug: level %d", (int)tl_log_get_level());
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
  tl_options_destroy(&o);
  const char *lv_bad[] = {"prog", "-log_level", "loud"};
  TL_TEST_STATUS(make(&o, 3, lv_bad), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "'loud' is not one of error|warn|info|debug"), "%s", tl_error_message());
  setenv("TALUS_LOG_LEVEL", "warn", 1);
  TL_TEST_ASSERT(tl_log_from_environment() == TL_LOG_WARN && tl_log_get_level() == TL_LOG_WARN,
                 "TALUS_LOG_LEVEL=warn");
  setenv("TALUS_LOG_LEVEL", "ERROR", 1);
  TL_TEST_ASSERT(tl_log_from_environment() == TL_LOG_ERROR, "TALUS_LOG_LEVEL=ERROR");
  unsetenv("TALUS_LOG_LEVEL");
  tl_log_set_level(before);

  /* Booleans in any case; an integer option is not a boolean. */
  const char *bools[] = {"prog", "-a", "TRUE", "-b", "No", "-c", "on", "-d", "0"};
  TL_TEST_STATUS(make(&o, 9, bools), TL_OK);
  int a, b, c, d;
  TL_TEST_STATUS(tl_options_get_bool(o, "-a", 0, "a", &a), TL_OK);
  TL_TEST_STATUS(tl_options_get_bool(o, "-b", 1, "b", &b), TL_OK);
  TL_TEST_STATUS(tl_options_get_bool(o, "-c", 0, "c", &c), TL_OK);
  TL_TEST_STATUS(tl_options_get_bool(o, "-d", 1, "d", &d), TL_OK);
  TL_TEST_ASSERT(a == 1 && b == 0 && c == 1 && d == 0, "booleans %d %d %d %d", a, b, c, d);
  TL_TEST_ASSERT(strcmp(tl_options_value(o, "-a"), "true") == 0, "canonical value %s", tl_options_value(o, "-a"));
  tl_options_destroy(&o);
}

/* Reads a temporary file whole. */
static void slurp(FILE *f, char *text, size_t cap)
{
  rewind(f);
  size_t n = fread(text, 1, cap - 1, f);
  text[n] = '\0';
  fclose(f);
}

static void test_help_layout(void)
{
  /* --help as well as -help; the page groups options by module, shows
   * ranges, and no line is longer than 100 columns. */
  const char *help[] = {"prog", "--help"};
  TlOptions *o;
  TL_TEST_STATUS(make(&o, 2, help), TL_OK);
  double t;
  long n;
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 40, 0, INFINITY, "s", "end time", &t), TL_OK);
  TL_TEST_STATUS(tl_options_get_int(o, "-n", 7, 1, 100, "number of particles", &n), TL_OK);
  TL_TEST_STATUS(tl_options_begin_group(o, "Contact law"), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-contact_E", 1e8, 0, INFINITY, "Pa",
                                     "Young's modulus of the grains, a long description that has to be wrapped "
                                     "because it runs well beyond the hundred columns of a terminal line",
                                     &t),
                 TL_OK);
  tl_options_end_group(o);
  TL_TEST_STATUS(tl_options_get_real(o, "-dt", 1e-3, 1e-9, 1, "s", "time step", &t), TL_OK);
  FILE *f = tmpfile();
  TL_TEST_STATUS(tl_options_finish(o, f), TL_HELP);
  char text[8192];
  slurp(f, text, sizeof text);
  const char *own = strstr(text, "prog options:"), *contact = strstr(text, "Contact law:");
  const char *dt = strstr(text, "-dt <real>"), *E = strstr(text, "-contact_E <real>");
  TL_TEST_ASSERT(own && contact && dt && E && own < dt && dt < contact && contact < E,
                 "the program's options (-dt among them) before the Contact law group: %s", text);
  TL_TEST_ASSERT(strstr(text, "end time [s] (default: 40; range >= 0)") &&
                     strstr(text, "number of particles (default: 7; range [1, 100])") &&
                     strstr(text, "time step [s] (default: 0.001; range [1e-09, 1])"),
                 "ranges: %s", text);
  TL_TEST_ASSERT(strstr(text, "-version") && strstr(text, "-options_left") && strstr(text, "-log_level"),
                 "general options listed: %s", text);
  int longest = 0, lines = 0;
  for (const char *p = text; *p;) {
    int len = (int)strcspn(p, "\n");
    if (len > longest) longest = len;
    ++lines;
    p += len + (p[len] == '\n');
  }
  TL_TEST_ASSERT(longest <= 100 && lines > 10, "longest help line %d columns (at most 100), %d lines", longest, lines);
  tl_options_destroy(&o);

  /* -version prints the version and revision and ends like -help. */
  const char *version[] = {"prog", "-version"};
  TL_TEST_STATUS(make(&o, 2, version), TL_OK);
  f = tmpfile();
  TL_TEST_STATUS(tl_options_finish(o, f), TL_HELP);
  slurp(f, text, sizeof text);
  char expect[256];
  snprintf(expect, sizeof expect, "prog (Talus %s, revision %s)", tl_version(), tl_revision());
  TL_TEST_ASSERT(strstr(text, expect) && tl_revision()[0], "-version: '%s' (expected '%s')", text, expect);
  tl_options_destroy(&o);
}

static void test_file_and_help(void)
{
  FILE *f = fopen("opts.txt", "w");
  fprintf(f, "# a comment\n-t_end 12   # trailing comment\n\n-dt 0.5\n");
  fclose(f);
  const char *argv[] = {"prog", "-options_file", "opts.txt", "-dt", "0.25"};
  TlOptions *o;
  TL_TEST_STATUS(make(&o, 5, argv), TL_OK);
  double t, dt;
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 1, 0, INFINITY, "s", "end time", &t), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-dt", 1, 0, INFINITY, "s", "time step", &dt), TL_OK);
  TL_TEST_CLOSE(t, 12.0, 0);
  TL_TEST_CLOSE(dt, 0.25, 0); /* the command line wins over the file */
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
  tl_options_destroy(&o);

  /* ... even when the file comes after it; a second file overrides the first. */
  f = fopen("opts2.txt", "w");
  fprintf(f, "-t_end 13\n-dt 0.75\n");
  fclose(f);
  const char *after[] = {"prog", "-dt", "0.25", "-options_file", "opts.txt", "-options_file", "opts2.txt"};
  TL_TEST_STATUS(make(&o, 7, after), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 1, 0, INFINITY, "s", "end time", &t), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-dt", 1, 0, INFINITY, "s", "time step", &dt), TL_OK);
  TL_TEST_ASSERT(t == 13.0 && dt == 0.25, "-t_end %g (expected 13 from the second file), -dt %g (0.25)", t, dt);
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
  tl_options_destroy(&o);

  /* Malformed lines in a file name the file and line; a repeated option in
   * a file takes its last value. */
  f = fopen("bad.txt", "w");
  fprintf(f, "-t_end 1\nt_end 2\n");
  fclose(f);
  const char *bad[] = {"prog", "-options_file", "bad.txt"};
  TL_TEST_STATUS(make(&o, 3, bad), TL_ERR_FORMAT);
  TL_TEST_ASSERT(strstr(tl_error_message(), "bad.txt:2") != NULL, "%s", tl_error_message());
  f = fopen("dup.txt", "w");
  fprintf(f, "-t_end 1\n-t_end 2\n");
  fclose(f);
  const char *dup[] = {"prog", "-options_file", "dup.txt"};
  TL_TEST_STATUS(make(&o, 3, dup), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 5, 0, INFINITY, "s", "end time", &t), TL_OK);
  TL_TEST_ASSERT(t == 2.0, "-t_end %g from a file that gives it twice (expected the last, 2)", t);
  tl_options_destroy(&o);
  const char *missing[] = {"prog", "-options_file", "no_such_file.txt"};
  TL_TEST_STATUS(make(&o, 3, missing), TL_ERR_IO);
  TL_TEST_ASSERT(strstr(tl_error_message(), "no_such_file.txt") != NULL, "%s", tl_error_message());

  /* -help lists every option asked for, with default and unit. */
  const char *help[] = {"prog", "-help"};
  TL_TEST_STATUS(make(&o, 2, help), TL_OK);
  TL_TEST_STATUS(tl_options_get_real(o, "-t_end", 40, 0, INFINITY, "s", "end time", &t), TL_OK);
  FILE *out = fopen("help.txt", "w+");
  TL_TEST_STATUS(tl_options_finish(o, out), TL_HELP);
  rewind(out);
  char text[4096] = "";
  size_t n = fread(text, 1, sizeof text - 1, out);
  text[n] = '\0';
  fclose(out);
  TL_TEST_ASSERT(strstr(text, "-t_end <real>") && strstr(text, "end time [s] (default: 40; range >= 0)"), "help: %s",
                 text);
  tl_options_destroy(&o);
}

int main(void)
{
  tl_log_set_level(TL_LOG_ERROR);
  test_values();
  test_rejections();
  test_file_and_help();
  test_help_layout();
  return tl_test_report();
}
