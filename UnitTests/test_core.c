/* Error messages and traces, memory helpers, registry, timers, summary line. */
#include <stddef.h>
#include <string.h>

#include "talus.h"
#include "tl_parallel.h"
#include "tl_test.h"

static TlStatus inner(double radius)
{
  if (radius <= 0) TL_ERROR(TL_ERR_ARG, "radius %g m must be positive", radius);
  return TL_OK;
}
static TlStatus outer(double radius)
{
  TL_CHECK(inner(radius));
  return TL_OK;
}

typedef struct {
  TlOpsHeader header;
  double (*eval)(double);
} FakeOps;
static double twice(double x) { return 2 * x; }
static const FakeOps fake_a = {{"fake", "alpha", "doubles"}, twice};
static const FakeOps fake_b = {{"fake", "beta", "doubles too"}, twice};
static const FakeOps fake_dup = {{"fake", "alpha", "a second alpha"}, twice};

/* A kind with a constructor and a parameter table, as a type from outside
 * the library registers it. */
typedef struct {
  double gain;
} Widget;
typedef TlStatus (*WidgetCreate)(double gain, Widget *w);
static TlStatus widget_create(double gain, Widget *w)
{
  if (!(gain > 0)) TL_ERROR(TL_ERR_ARG, "widget gain %g must be positive", gain);
  w->gain = gain;
  return TL_OK;
}
static const TlParam widget_params[] = {{"gain", 2.0, 0.0, 10.0, "1", "amplification", offsetof(Widget, gain)}};

int main(void)
{
  TL_TEST_STATUS(outer(1.0), TL_OK);
  TL_TEST_STATUS(outer(-2.0), TL_ERR_ARG);
  const char *m = tl_error_message();
  TL_TEST_ASSERT(strstr(m, "radius -2 m must be positive") && strstr(m, "test_core.c"), "message: %s", m);
  TL_TEST_ASSERT(strstr(m, "at test_core.c") && strchr(strchr(m, '\n') + 1, '\n'), "no two-level trace: %s", m);
  tl_error_clear();
  TL_TEST_ASSERT(tl_error_message()[0] == '\0', "clear left a message");

  double *v = NULL;
  size_t cap = 0;
  TL_TEST_STATUS(tl_array_reserve(&v, &cap, 100, sizeof *v), TL_OK);
  TL_TEST_ASSERT(cap >= 100 && v[99] == 0.0, "capacity %zu", cap);
  size_t cap_before = cap;
  TL_TEST_STATUS(tl_array_reserve(&v, &cap, 50, sizeof *v), TL_OK);
  TL_TEST_ASSERT(cap == cap_before, "shrinking request reallocated");
  tl_free(&v);
  TL_TEST_ASSERT(v == NULL, "tl_free must null");
  TL_TEST_STATUS(tl_calloc(&v, (size_t)-1 / 4, 16), TL_ERR_MEM);

  TL_TEST_STATUS(tl_registry_add(&fake_a.header), TL_OK);
  TL_TEST_STATUS(tl_registry_add(&fake_b.header), TL_OK);
  TL_TEST_STATUS(tl_registry_add(&fake_a.header), TL_OK); /* idempotent */
  TL_TEST_STATUS(tl_registry_add(&fake_dup.header), TL_ERR_ARG);
  const TlOpsHeader *found;
  TL_TEST_STATUS(tl_registry_find("fake", "beta", &found), TL_OK);
  TL_TEST_ASSERT(found == &fake_b.header && ((const FakeOps *)found)->eval(2) == 4, "wrong ops found");
  TL_TEST_STATUS(tl_registry_find("fake", "gamma", &found), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(strstr(tl_error_message(), "known: alpha, beta") != NULL, "%s", tl_error_message());
  const char *names[4];
  TL_TEST_ASSERT(tl_registry_list("fake", names, 4) == 2, "list count");
  const FakeOps *obj_ops = &fake_a;
  TL_TEST_ASSERT(strcmp(tl_type_name(&obj_ops), "alpha") == 0, "type name");

  TlTypeEntry we = {"widget", "amplifier", "a widget", (TlConstructor)widget_create, NULL, widget_params, 1};
  TL_TEST_STATUS(tl_registry_register(&we), TL_OK);
  TL_TEST_STATUS(tl_registry_register(&we), TL_OK); /* idempotent */
  TlTypeEntry other = we;
  other.create = (TlConstructor)twice;
  TL_TEST_STATUS(tl_registry_register(&other), TL_ERR_ARG);
  const TlTypeEntry *e;
  TL_TEST_STATUS(tl_registry_lookup("widget", "amplifier", &e), TL_OK);
  const TlParam *gp = tl_param_find(e->params, e->n_params, "gain");
  TL_TEST_ASSERT(gp && gp->def == 2.0 && !tl_param_find(e->params, e->n_params, "loss"), "parameter table");
  Widget w;
  TL_TEST_STATUS(((WidgetCreate)e->create)(gp->def, &w), TL_OK);
  TL_TEST_ASSERT(w.gain == 2.0, "constructor by name");
  TL_TEST_STATUS(tl_registry_find("widget", "amplifier", &found), TL_ERR_UNSUPPORTED); /* no ops table */
  TL_TEST_ASSERT(tl_registry_entry("widget", 0) == e && tl_registry_entry("widget", 1) == NULL, "entries");
  /* the built-ins are registered by the modules themselves, found without
   * an explicit tl_initialize(), and again after the registry was emptied */
  TL_TEST_STATUS(tl_registry_find("cg_kernel", "lucy", &found), TL_OK);
  tl_registry_clear();
  TL_TEST_STATUS(tl_registry_lookup("widget", "amplifier", &e), TL_ERR_NOT_FOUND);
  TL_TEST_STATUS(tl_registry_find("material", "hooke", &found), TL_OK);
  TL_TEST_STATUS(tl_initialize(), TL_OK);

  TlTimers t;
  tl_timers_init(&t);
  int p = tl_timers_phase(&t, "work");
  TL_TEST_ASSERT(tl_timers_phase(&t, "work") == p, "phase looked up twice gives two slots");
  tl_timers_start(&t, p);
  volatile double s = 0;
  for (int i = 0; i < 100000; ++i) s += i;
  tl_timers_stop(&t, p);
  TL_TEST_ASSERT(t.phase[p].count == 1 && t.phase[p].total >= 0, "timer");

  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_real(&sum, "err_avg", 0.125);
  tl_summary_int(&sum, "steps", 42);
  tl_summary_string(&sum, "case", "1P");
  TL_TEST_ASSERT(strcmp(sum.text, " err_avg=0.125 steps=42 case=1P") == 0, "summary '%s'", sum.text);
  TL_TEST_ASSERT(tl_driver_exit(TL_HELP) == 0 && tl_driver_exit(TL_OK) == 0, "exit codes");
  FILE *devnull = fopen("/dev/null", "w");
  TL_TEST_ASSERT(devnull != NULL, "/dev/null");
  TL_TEST_STATUS(tl_summary_print(&sum, devnull), TL_OK);
  /* No summary prints NaN: a non-finite value and a figure declared
   * undefined are printed as "undefined", and printing then fails, naming
   * them with their reasons. */
  tl_summary_real(&sum, "period", NAN);
  tl_summary_real(&sum, "ratio", INFINITY);
  tl_summary_undefined(&sum, "speed", "no crossing in %d steps", 7);
  TL_TEST_ASSERT(strstr(sum.text, "nan") == NULL && strstr(sum.text, "inf") == NULL &&
                     strstr(sum.text, " period=undefined ratio=undefined speed=undefined") != NULL,
                 "summary '%s'", sum.text);
  TL_TEST_STATUS(tl_summary_print(&sum, devnull), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(sum.n_undefined == 3 && strstr(sum.undefined, "period: the computed value is NaN") &&
                     strstr(sum.undefined, "ratio: the computed value is infinite") &&
                     strstr(sum.undefined, "speed: no crossing in 7 steps"),
                 "reasons '%s'", sum.undefined);
  if (devnull) fclose(devnull);

  /* Exit status: 0 success, 2 a refusal, 1 a diagnosis; every failure's
   * last summary line carries status= (and no second line when the summary
   * itself already reported the failure). */
  TL_TEST_ASSERT(tl_exit_code(TL_ERR_ARG) == 2 && tl_exit_code(TL_ERR_FORMAT) == 2 && tl_exit_code(TL_ERR_IO) == 2 &&
                     tl_exit_code(TL_ERR_NOT_FOUND) == 2 && tl_exit_code(TL_ERR_UNSTABLE) == 1 &&
                     tl_exit_code(TL_ERR_NUMERIC) == 1 && tl_exit_code(TL_ERR_CONVERGENCE) == 1 &&
                     tl_exit_code(TL_ERR_MEM) == 1 && tl_exit_code(TL_OK) == 0 && tl_exit_code(TL_HELP) == 0,
                 "exit codes");
  TL_TEST_ASSERT(strcmp(tl_exit_word(TL_ERR_ARG), "refused") == 0 && strcmp(tl_exit_word(TL_ERR_UNSTABLE), "stopped") == 0 &&
                     strcmp(tl_exit_word(TL_ERR_STATE), "failed") == 0 && strcmp(tl_exit_word(TL_OK), "ok") == 0,
                 "exit words");
  FILE *lines = tmpfile();
  TL_TEST_ASSERT(lines != NULL, "tmpfile");
  if (lines) {
    TlSummary ok;
    tl_summary_init(&ok);
    tl_summary_int(&ok, "steps", 3);
    TL_TEST_STATUS(tl_summary_print(&ok, lines), TL_OK);
    tl_summary_end(TL_ERR_UNSTABLE, lines);  /* a failure after the summary: a final line */
    TL_TEST_STATUS(tl_summary_print(&sum, lines), TL_ERR_NUMERIC);
    tl_summary_end(TL_ERR_NUMERIC, lines);   /* already reported: nothing more */
    tl_summary_end(TL_ERR_ARG, lines);
    tl_summary_end(TL_OK, lines);
    char text[4096];
    rewind(lines);
    size_t n = fread(text, 1, sizeof text - 1, lines);
    text[n] = '\0';
    fclose(lines);
    TL_TEST_ASSERT(strcmp(text, "summary: steps=3 status=ok\n"
                                "summary: status=stopped exit=1 error=unstable\n"
                                "summary: err_avg=0.125 steps=42 case=1P period=undefined ratio=undefined "
                                "speed=undefined status=undefined exit=1\n"
                                "summary: status=refused exit=2 error=invalid_argument\n") == 0,
                   "summary lines:\n%s(%zu characters)", text, strlen(text));
  }

  int argc = 1;
  char *args[] = {"test_core", NULL}, **argv = args;
  TL_TEST_STATUS(tl_parallel_initialize(&argc, &argv), TL_OK);
  TL_TEST_ASSERT(tl_parallel_rank() == 0 && tl_parallel_size() >= 1, "rank %d of %d", tl_parallel_rank(),
                 tl_parallel_size());
  TL_TEST_ASSERT(tl_parallel_threads() >= 1, "threads");
  TL_TEST_STATUS(tl_parallel_finalize(), TL_OK);
  return tl_test_report();
}
