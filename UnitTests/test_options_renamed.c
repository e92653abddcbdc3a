/* tl_options_refuse_renamed: an old option name is refused with a message
 * naming the new one (and the note, when given); the new name, and a run
 * that gives neither, pass; a malformed table is refused. */
#include <string.h>

#include "tl_options_renamed.h"
#include "tl_test.h"

static const TlRenamedOption table[] = {{"-fem", "-stepper", NULL},
                                        {"-snapshots", "-snapshot_dt", "now in seconds"}};

static TlOptions *make(int argc, const char **argv)
{
  TlOptions *o = NULL;
  TL_TEST_STATUS(tl_options_create(argc, (char **)argv, "test", &o), TL_OK);
  return o;
}

int main(void)
{
  const char *old[] = {"prog", "-fem", "newmark"};
  TlOptions *o = make(3, old);
  if (o) {
    TL_TEST_STATUS(tl_options_refuse_renamed(o, table, 2), TL_ERR_ARG);
    const char *m = tl_error_message();
    TL_TEST_ASSERT(strstr(m, "-fem") && strstr(m, "give -stepper instead"), "message '%s'", m);
    tl_options_destroy(&o);
  }
  const char *noted[] = {"prog", "-snapshots", "10"};
  o = make(3, noted);
  if (o) {
    TL_TEST_STATUS(tl_options_refuse_renamed(o, table, 2), TL_ERR_ARG);
    const char *m = tl_error_message();
    TL_TEST_ASSERT(strstr(m, "-snapshot_dt") && strstr(m, "now in seconds"), "message '%s'", m);
    tl_options_destroy(&o);
  }
  const char *fresh[] = {"prog", "-stepper", "newmark"};
  o = make(3, fresh);
  if (o) {
    TL_TEST_STATUS(tl_options_refuse_renamed(o, table, 2), TL_OK);
    int k = 0;
    static const char *const choices[] = {"central_difference", "newmark", NULL};
    TL_TEST_STATUS(tl_options_get_choice(o, "-stepper", "central_difference", choices, "stepper", &k), TL_OK);
    TL_TEST_ASSERT(k == 1, "-stepper newmark read as %d", k);
    TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
    tl_options_destroy(&o);
  }
  const char *none[] = {"prog"};
  o = make(1, none);
  if (o) {
    TL_TEST_STATUS(tl_options_refuse_renamed(o, table, 2), TL_OK);
    const TlRenamedOption bad[] = {{"-x", NULL, NULL}};
    TL_TEST_STATUS(tl_options_refuse_renamed(o, bad, 1), TL_ERR_ARG);
    tl_options_destroy(&o);
  }
  return tl_test_report();
}
