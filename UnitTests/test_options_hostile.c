/* The options parser on values that used to be accepted silently or refused
 * for the wrong reason:
 *  - -options_file . (a directory, read as an empty file) is refused;
 *  - lists: -snapshots -0.01 (negative), "," and "" (empty), 0.005,,0.006
 *    and 0.1, (empty fields) are refused by name; a good list reads;
 *  - booleans take true/false, yes/no, 1/0 (and a bare flag), refuse others;
 *  - -E -nan and -E -inf are refused as not finite numbers, not as options
 *    that "need a value"; -E -0.5 is still a value. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_test.h"

static TlStatus make(TlOptions **o, int argc, const char **argv)
{
  return tl_options_create(argc, (char **)argv, "test program", o);
}

static void list_refused(const char *text, const char *fragment)
{
  const char *argv[] = {"prog", "-snapshots", text};
  TlOptions *o = NULL;
  TL_TEST_STATUS(make(&o, 3, argv), TL_OK);
  double v[8];
  int n = -1;
  TlStatus s = o ? tl_options_get_real_list(o, "-snapshots", "0.03,0.05", "s", "times", v, 8, &n) : TL_ERR_ARG;
  TL_TEST_ASSERT(s == TL_ERR_ARG && strstr(tl_error_message(), "-snapshots") && strstr(tl_error_message(), fragment),
                 "-snapshots '%s': status %d, message '%s' (expected '%s')", text, (int)s, tl_error_message(), fragment);
  tl_options_destroy(&o);
}

static void boolean(const char *text, int expect_status_ok, int expect)
{
  const char *argv[] = {"prog", "-flag", text};
  TlOptions *o = NULL;
  TL_TEST_STATUS(make(&o, text ? 3 : 2, argv), TL_OK);
  int v = -1;
  TlStatus s = o ? tl_options_get_bool(o, "-flag", expect ? 0 : 1, "a flag", &v) : TL_ERR_ARG;
  if (expect_status_ok)
    TL_TEST_ASSERT(s == TL_OK && v == expect, "-flag %s: status %d, value %d (expected %d)", text ? text : "(bare)",
                   (int)s, v, expect);
  else
    TL_TEST_ASSERT(s == TL_ERR_ARG && strstr(tl_error_message(), "not a boolean"), "-flag %s: status %d, message '%s'",
                   text, (int)s, tl_error_message());
  tl_options_destroy(&o);
}

static void real_refused(const char *text)
{
  const char *argv[] = {"prog", "-E", text};
  TlOptions *o = NULL;
  TL_TEST_STATUS(make(&o, 3, argv), TL_OK);
  double E = 0;
  TlStatus s = o ? tl_options_get_real(o, "-E", 1e8, 0.0, INFINITY, "Pa", "modulus", &E) : TL_ERR_ARG;
  TL_TEST_ASSERT(s == TL_ERR_ARG && strstr(tl_error_message(), "not a finite real number"),
                 "-E %s: status %d, message '%s'", text, (int)s, tl_error_message());
  tl_options_destroy(&o);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  /* A directory as options file. */
  const char *dir[] = {"prog", "-options_file", "."};
  TlOptions *o = NULL;
  TlStatus s = make(&o, 3, dir);
  TL_TEST_ASSERT(s == TL_ERR_IO && strstr(tl_error_message(), "'.' is a directory"), "-options_file .: status %d, '%s'",
                 (int)s, tl_error_message());
  tl_options_destroy(&o);

  /* Lists. */
  list_refused("-0.01", "below its lower limit 0");
  list_refused(",", "value 1 of ',' is empty");
  list_refused("", "empty list");
  list_refused("0.005,,0.006", "value 2 of '0.005,,0.006' is empty");
  list_refused("0.1,", "value 2 of '0.1,' is empty");
  list_refused("0.1,abc", "'abc' is not a finite real number");
  const char *good[] = {"prog", "-snapshots", "0.005,0.006,1e-2"};
  TL_TEST_STATUS(make(&o, 3, good), TL_OK);
  double v[8];
  int n = 0;
  if (o) TL_TEST_STATUS(tl_options_get_real_list(o, "-snapshots", "0.03", "s", "times", v, 8, &n), TL_OK);
  TL_TEST_ASSERT(n == 3 && v[0] == 0.005 && v[1] == 0.006 && v[2] == 0.01, "list read %d values", n);
  tl_options_destroy(&o);
  const char *neg[] = {"prog", "-g", "0,0,-9.81"};
  TL_TEST_STATUS(make(&o, 3, neg), TL_OK);
  if (o) TL_TEST_STATUS(tl_options_get_real_list_range(o, "-g", "0,0,0", -INFINITY, INFINITY, "m/s^2", "g", v, 3, &n), TL_OK);
  TL_TEST_ASSERT(n == 3 && v[2] == -9.81, "signed list read %d values", n);
  tl_options_destroy(&o);

  /* Booleans. */
  boolean("true", 1, 1);
  boolean("yes", 1, 1);
  boolean("1", 1, 1);
  boolean(NULL, 1, 1);
  boolean("false", 1, 0);
  boolean("no", 1, 0);
  boolean("0", 1, 0);
  boolean("maybe", 0, 0);
  boolean("2", 0, 0);

  /* Non-finite reals. */
  real_refused("-nan");
  real_refused("-inf");
  real_refused("nan");
  const char *minus[] = {"prog", "-E", "-0.5"};
  TL_TEST_STATUS(make(&o, 3, minus), TL_OK);
  double E = 0;
  if (o) TL_TEST_STATUS(tl_options_get_real(o, "-E", 1.0, -1.0, 1.0, "Pa", "modulus", &E), TL_OK);
  TL_TEST_ASSERT(E == -0.5, "-E -0.5 read as %g", E);
  tl_options_destroy(&o);
  /* "-nan" is not taken for an option: the next option still reads. */
  const char *next[] = {"prog", "-E", "-nan", "-n", "3"};
  TL_TEST_STATUS(make(&o, 5, next), TL_OK);
  long k = 0;
  if (o) TL_TEST_STATUS(tl_options_get_int(o, "-n", 1, 0, 10, "count", &k), TL_OK);
  TL_TEST_ASSERT(k == 3, "-n read as %ld", k);
  tl_options_destroy(&o);
  return tl_test_report();
}
