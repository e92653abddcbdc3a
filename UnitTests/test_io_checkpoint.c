/* Checkpoint round trip: doubles bit for bit (including -0, subnormals,
 * infinities and NaN payloads), int64, raw bytes, scalars and strings;
 * sections through TlCheckpointOps; errors for a missing dataset, a wrong
 * length, a wrong type, a missing section and a wrong section type. */
#include <stdint.h>
#include <string.h>

#include "talus.h"
#include "tl_checkpoint.h"
#include "tl_test.h"

static double from_bits(uint64_t b)
{
  double d;
  memcpy(&d, &b, sizeof d);
  return d;
}

/* A toy module with positions and a history of contact springs. */
typedef struct {
  size_t n;
  double x[7];
  int64_t pair[4];
  unsigned char flags[5];
  double time_step;
} Toy;

static TlStatus toy_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const Toy *t = object;
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "x", t->n, t->x));
  TL_CHECK(tl_checkpoint_write_int64s(w, group, "contacts/pair", 4, t->pair));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "contacts/flags", 5, t->flags));
  TL_CHECK(tl_checkpoint_write_double(w, group, "time_step", t->time_step));
  return TL_OK;
}

static TlStatus toy_load(void *object, TlCheckpointReader *r, const char *group)
{
  Toy *t = object;
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "x", t->n, t->x));
  TL_CHECK(tl_checkpoint_read_int64s(r, group, "contacts/pair", 4, t->pair));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "contacts/flags", 5, t->flags));
  TL_CHECK(tl_checkpoint_read_double(r, group, "time_step", &t->time_step));
  return TL_OK;
}

/* field by field: the struct has padding bytes */
static int toy_equal(const Toy *p, const Toy *q)
{
  return p->n == q->n && memcmp(p->x, q->x, sizeof p->x) == 0 && memcmp(p->pair, q->pair, sizeof p->pair) == 0 &&
         memcmp(p->flags, q->flags, sizeof p->flags) == 0 && memcmp(&p->time_step, &q->time_step, sizeof(double)) == 0;
}

static const TlCheckpointOps toy_ops = {{"checkpoint", "toy_v1", "test module"}, toy_save, toy_load};
static const TlCheckpointOps other_ops = {{"checkpoint", "other_v1", "test module"}, toy_save, toy_load};

static void test_low_level(void)
{
  const double special[] = {0.1, -0.0, 1e-310 /* subnormal */, 1.0 / 3.0, INFINITY, -INFINITY,
                            from_bits(0x7ff8000000000123ULL) /* quiet NaN with payload */,
                            from_bits(0x7ff0000000000001ULL) /* signalling NaN */, 6.02214076e23, -4.9e-324};
  enum { ND = sizeof special / sizeof special[0] };
  const int64_t ints[] = {INT64_MIN, -1, 0, 1, INT64_MAX};
  unsigned char bytes[256];
  for (int i = 0; i < 256; ++i) bytes[i] = (unsigned char)(255 - i);

  TlCheckpointWriter *w;
  TL_TEST_STATUS(tl_checkpoint_writer_open("low.h5", &w), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_write_doubles(w, "a/b", "special", ND, special), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_write_int64s(w, "a", "ints", 5, ints), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_write_bytes(w, NULL, "bytes", 256, bytes), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_write_doubles(w, "a", "empty", 0, NULL), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_write_double(w, "s", "dt", 1e-6 / 3.0), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_write_int64(w, "s", "step", 123456789012LL), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_write_string(w, "s", "law", "hertz_mindlin"), TL_OK);
  /* a name written twice is refused */
  TL_TEST_STATUS(tl_checkpoint_write_int64(w, "s", "step", 1), TL_ERR_ARG);
  TL_TEST_STATUS(tl_checkpoint_writer_commit(&w), TL_OK);
  TL_TEST_ASSERT(w == NULL, "writer not nulled");

  TlCheckpointReader *r;
  TL_TEST_STATUS(tl_checkpoint_reader_open("low.h5", &r), TL_OK);
  if (!r) return;
  double back[ND];
  TL_TEST_STATUS(tl_checkpoint_read_doubles(r, "a/b", "special", ND, back), TL_OK);
  TL_TEST_ASSERT(memcmp(back, special, sizeof special) == 0, "doubles not bit-identical");
  int64_t iback[5];
  TL_TEST_STATUS(tl_checkpoint_read_int64s(r, "/a", "ints", 5, iback), TL_OK);
  TL_TEST_ASSERT(memcmp(iback, ints, sizeof ints) == 0, "int64 values differ");
  unsigned char bback[256] = {0};
  size_t n = 0;
  TL_TEST_STATUS(tl_checkpoint_length(r, "", "bytes", &n), TL_OK);
  TL_TEST_ASSERT(n == 256, "byte length %zu", n);
  TL_TEST_STATUS(tl_checkpoint_read_bytes(r, "", "bytes", 256, bback), TL_OK);
  TL_TEST_ASSERT(memcmp(bback, bytes, 256) == 0, "bytes differ");
  TL_TEST_STATUS(tl_checkpoint_length(r, "a", "empty", &n), TL_OK);
  TL_TEST_ASSERT(n == 0, "empty length %zu", n);
  TL_TEST_STATUS(tl_checkpoint_read_doubles(r, "a", "empty", 0, NULL), TL_OK);
  double dt = 0;
  int64_t step = 0;
  char *law = NULL;
  TL_TEST_STATUS(tl_checkpoint_read_double(r, "s", "dt", &dt), TL_OK);
  TL_TEST_ASSERT(dt == 1e-6 / 3.0, "dt %.17g", dt);
  TL_TEST_STATUS(tl_checkpoint_read_int64(r, "s", "step", &step), TL_OK);
  TL_TEST_ASSERT(step == 123456789012LL, "step %lld", (long long)step);
  TL_TEST_STATUS(tl_checkpoint_read_string(r, "s", "law", &law), TL_OK);
  TL_TEST_ASSERT(law && strcmp(law, "hertz_mindlin") == 0, "law '%s'", law ? law : "(null)");
  tl_free(&law);
  TL_TEST_ASSERT(tl_checkpoint_has(r, "a", "ints") && !tl_checkpoint_has(r, "a", "nothing"), "has()");

  /* errors name the dataset */
  TL_TEST_STATUS(tl_checkpoint_read_doubles(r, "a", "missing", 3, back), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(strstr(tl_error_message(), "/a/missing") != NULL, "message: %s", tl_error_message());
  TL_TEST_STATUS(tl_checkpoint_read_doubles(r, "a/b", "special", ND - 1, back), TL_ERR_FORMAT);
  TL_TEST_ASSERT(strstr(tl_error_message(), "/a/b/special") && strstr(tl_error_message(), "expected 9"),
                 "message: %s", tl_error_message());
  TL_TEST_STATUS(tl_checkpoint_read_doubles(r, "a", "ints", 5, back), TL_ERR_FORMAT);
  TL_TEST_STATUS(tl_checkpoint_read_double(r, "a", "ints", &dt), TL_ERR_FORMAT);
  TL_TEST_STATUS(tl_checkpoint_read_int64s(r, "s", "step", 1, iback), TL_ERR_FORMAT);
  tl_checkpoint_reader_close(&r);
  TL_TEST_ASSERT(r == NULL, "reader not nulled");

  /* not a checkpoint */
  FILE *f = fopen("junk.h5", "w");
  fputs("not hdf5\n", f);
  fclose(f);
  TL_TEST_STATUS(tl_checkpoint_reader_open("junk.h5", &r), TL_ERR_FORMAT);
  TL_TEST_STATUS(tl_checkpoint_reader_open("absent.h5", &r), TL_ERR_IO);
}

static void test_sections(void)
{
  Toy a = {.n = 7, .x = {1.5, -2.25, 3e-300, 0.1, 0.2, 0.3, -0.0}, .pair = {3, 9, 11, 12},
           .flags = {1, 0, 255, 7, 9}, .time_step = 2.5e-7};
  Toy b = a;
  for (int i = 0; i < 7; ++i) b.x[i] = 1.0 / (i + 1.0);
  TlCheckpoint *cp;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "dem", &toy_ops, &a), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "fem", &toy_ops, &b), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "dem", &toy_ops, &b), TL_ERR_ARG);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "a/b", &toy_ops, &b), TL_ERR_ARG);
  TL_TEST_STATUS(tl_checkpoint_save(cp, "run.h5", 0.125, 4242), TL_OK);

  Toy a2 = {.n = 7}, b2 = {.n = 7};
  TlCheckpoint *cp2;
  TL_TEST_STATUS(tl_checkpoint_create(&cp2), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp2, "dem", &toy_ops, &a2), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp2, "fem", &toy_ops, &b2), TL_OK);
  double t = 0;
  int64_t step = 0;
  TL_TEST_STATUS(tl_checkpoint_load(cp2, "run.h5", &t, &step), TL_OK);
  TL_TEST_ASSERT(t == 0.125 && step == 4242, "time %g step %lld", t, (long long)step);
  TL_TEST_ASSERT(toy_equal(&a2, &a), "section dem differs after load");
  TL_TEST_ASSERT(toy_equal(&b2, &b), "section fem differs after load");

  /* a section the file lacks, and a section of another type */
  Toy c = {.n = 7};
  TL_TEST_STATUS(tl_checkpoint_add(cp2, "walls", &toy_ops, &c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp2, "run.h5", NULL, NULL), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(strstr(tl_error_message(), "walls") != NULL, "message: %s", tl_error_message());
  TlCheckpoint *cp3;
  TL_TEST_STATUS(tl_checkpoint_create(&cp3), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp3, "dem", &other_ops, &c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp3, "run.h5", NULL, NULL), TL_ERR_FORMAT);
  TL_TEST_ASSERT(strstr(tl_error_message(), "toy_v1") != NULL, "message: %s", tl_error_message());
  /* a module whose size changed: the load names the dataset */
  Toy d = {.n = 6};
  TlCheckpoint *cp4;
  TL_TEST_STATUS(tl_checkpoint_create(&cp4), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp4, "fem", &toy_ops, &d), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp4, "run.h5", NULL, NULL), TL_ERR_FORMAT);
  TL_TEST_ASSERT(strstr(tl_error_message(), "/fem/x") != NULL, "message: %s", tl_error_message());
  tl_checkpoint_destroy(&cp);
  tl_checkpoint_destroy(&cp2);
  tl_checkpoint_destroy(&cp3);
  tl_checkpoint_destroy(&cp4);
  TL_TEST_ASSERT(cp == NULL && cp4 == NULL, "destroy must null");
}

/* A checkpoint with no section is valid (a driver before any module is added). */
static void test_empty(void)
{
  TlCheckpoint *cp;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, "empty.h5", -1.5, -3), TL_OK);
  double t = 0;
  int64_t step = 0;
  TL_TEST_STATUS(tl_checkpoint_load(cp, "empty.h5", &t, &step), TL_OK);
  TL_TEST_ASSERT(t == -1.5 && step == -3, "time %g step %lld", t, (long long)step);
  tl_checkpoint_destroy(&cp);
}

int main(void)
{
  test_empty();
  test_low_level();
  test_sections();
  return tl_test_report();
}
