/* The options database: typed getters, defaults, ranges, suffixes, files,
 * -help, and every rejection (unknown, duplicated, malformed, out of range). */
#include <math.h>
#include <stdio.h>
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

  /* An option given twice. */
  const char *dup[] = {"prog", "-t_end", "1", "-t_end", "2"};
  TlOptions *o = NULL;
  TL_TEST_STATUS(make(&o, 5, dup), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "given twice") != NULL, "%s", tl_error_message());
  TL_TEST_ASSERT(o == NULL, "a failed create leaves no object");

  /* A stray word that is not an option. */
  const char *stray[] = {"prog", "-t_end", "1", "2"};
  TL_TEST_STATUS(make(&o, 4, stray), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "'2' is not an option") != NULL, "%s", tl_error_message());

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

  /* Malformed and duplicated lines in a file name the file and line. */
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
  TL_TEST_STATUS(make(&o, 3, dup), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "given twice") != NULL, "%s", tl_error_message());
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
  TL_TEST_ASSERT(strstr(text, "-t_end <real>") && strstr(text, "end time [s] (default: 40)"), "help: %s", text);
  tl_options_destroy(&o);
}

int main(void)
{
  tl_log_set_level(TL_LOG_ERROR);
  test_values();
  test_rejections();
  test_file_and_help();
  return tl_test_report();
}
