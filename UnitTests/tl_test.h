/* A minimal test harness: each check prints what failed with its values; the
 * program's exit code is the number of failed checks (capped), and its last
 * line is "N passed, M failed". */
#ifndef TL_TEST_H
#define TL_TEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int tl_test_passed, tl_test_failed;

#define TL_TEST_ASSERT(cond, ...)                                                      \
  do {                                                                                 \
    if (cond) {                                                                        \
      ++tl_test_passed;                                                                \
    } else {                                                                           \
      ++tl_test_failed;                                                                \
      fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #cond);                  \
      fprintf(stderr, __VA_ARGS__);                                                    \
      fputc('\n', stderr);                                                             \
    }                                                                                  \
  } while (0)

/* |a - b| <= tol * max(1, |b|).  Below |b| = 1 the tolerance is absolute:
 * with TL_TEST_AUDIT set in the environment, every comparison against a
 * non-zero reference below 1 whose tolerance exceeds 5 % of it is printed
 * ("AUDIT file:line a b tol"), the way a loose check is found. */
#define TL_TEST_CLOSE(a, b, tol)                                                       \
  do {                                                                                 \
    double tl_a_ = (a), tl_b_ = (b);                                                   \
    if (tl_b_ != 0.0 && fabs(tl_b_) < 1.0 && (double)(tol) > 0.05 * fabs(tl_b_) &&     \
        getenv("TL_TEST_AUDIT"))                                                       \
      fprintf(stderr, "AUDIT %s:%d %s: a = %.6g, b = %.6g, absolute tol %g\n", __FILE__, \
              __LINE__, #a, tl_a_, tl_b_, (double)(tol));                              \
    TL_TEST_ASSERT(fabs(tl_a_ - tl_b_) <= (tol) * fmax(1.0, fabs(tl_b_)),            \
                   "%s = %.17g, expected %.17g (tol %g)", #a, tl_a_, tl_b_, (double)(tol)); \
  } while (0)

/* |a - b| <= tol |b|: for values of any size (TL_TEST_CLOSE turns absolute
 * below 1).  Written so that a NaN on either side fails. */
#define TL_TEST_REL(a, b, tol)                                                         \
  do {                                                                                 \
    double tl_a_ = (a), tl_b_ = (b);                                                   \
    TL_TEST_ASSERT(fabs(tl_a_ - tl_b_) <= (tol) * fabs(tl_b_),                         \
                   "%s = %.17g, expected %.17g (relative tol %g)", #a, tl_a_, tl_b_, (double)(tol)); \
  } while (0)

/* Asserts that a call returns the given status. */
#define TL_TEST_STATUS(call, expected)                                                 \
  do {                                                                                 \
    TlStatus tl_s_ = (call);                                                           \
    TL_TEST_ASSERT(tl_s_ == (expected), "status %d (%s), expected %d; message: %s",  \
                   (int)tl_s_, tl_status_name(tl_s_), (int)(expected), tl_error_message()); \
  } while (0)

/* The whole file as a NUL-terminated string (free it), or NULL. */
static inline char *tl_test_read_file(const char *path)
{
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *s = calloc((size_t)n + 1, 1);
  if (s && fread(s, 1, (size_t)n, f) != (size_t)n) s[0] = '\0';
  fclose(f);
  return s;
}

/* How many times `what` occurs in `text`. */
static inline int tl_test_count(const char *text, const char *what)
{
  int n = 0;
  for (const char *p = text; (p = strstr(p, what)); p += strlen(what)) ++n;
  return n;
}

/* A contact law for tests: the normal part `normal` ("linear", "hertz",
 * "bonded_linear") with Coulomb friction, constant rolling and constant
 * adhesion parts, each off (mu, mu_roll, adhesion_force = 0) unless set by
 * the name, value pairs that follow (ended by NULL); set up.  Defined only
 * where tl_contact_law.h is included first. */
#ifdef TL_CONTACT_LAW_H
#include <stdarg.h>
static inline TlStatus tl_test_law(TlContactLaw **law, const char *normal, ...)
{
  TL_CHECK(tl_contact_law_create(normal, "coulomb", "constant", "constant", law));
  TlStatus s = tl_contact_law_set(*law, "mu", 0.0);
  if (s == TL_OK) s = tl_contact_law_set(*law, "mu_roll", 0.0);
  va_list ap;
  va_start(ap, normal);
  for (const char *name; s == TL_OK && (name = va_arg(ap, const char *));) s = tl_contact_law_set(*law, name, va_arg(ap, double));
  va_end(ap);
  if (s == TL_OK) s = tl_contact_law_setup(*law);
  if (s != TL_OK) tl_contact_law_destroy(law);
  return s;
}
#endif

/* ctest's skip code (SKIP_RETURN_CODE of every unit test): a test that
 * cannot run its check says why and ends with tl_test_skip, so ctest reports
 * a skip, never a pass; checks that already failed still fail the test. */
#define TL_TEST_SKIP_CODE 77
static inline int tl_test_skip(const char *why)
{
  printf("SKIPPED: %s\n%d passed, %d failed\n", why, tl_test_passed, tl_test_failed);
  return tl_test_failed ? (tl_test_failed > 100 ? 100 : tl_test_failed) : TL_TEST_SKIP_CODE;
}

static inline int tl_test_report(void)
{
  printf("%d passed, %d failed\n", tl_test_passed, tl_test_failed);
  return tl_test_failed > 100 ? 100 : tl_test_failed;
}

#endif
