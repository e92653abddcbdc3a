#include "tl_init.h"

#include <stdio.h>

#include "tl_config.h"
#include "tl_revision.h"
#include "tl_summary.h"

/* The registration function of every module, collected by the build from
 * the library's sources (tl_modules.inc: one TL_MODULE(fn) a line), so that
 * a new module registers its types without an edit here. */
#define TL_MODULE(fn) TlStatus fn(void);
#include "tl_modules.inc"
#undef TL_MODULE

typedef TlStatus (*TlRegisterAll)(void);
static const TlRegisterAll tl_modules[] = {
#define TL_MODULE(fn) fn,
#include "tl_modules.inc"
#undef TL_MODULE
    NULL, /* keeps the table non-empty */
};

/* 0: not yet, 1: registering (a module that looks a type up meanwhile must
 * not start again), 2: done. */
static int tl_init_state;

TlStatus tl_initialize(void)
{
  if (tl_init_state) return TL_OK;
  tl_init_state = 1;
  for (size_t i = 0; i < sizeof tl_modules / sizeof tl_modules[0]; ++i)
    if (tl_modules[i]) {
      TlStatus s = tl_modules[i]();
      if (s != TL_OK) {
        tl_init_state = 0;
        return tl_error_trace(s, __FILE__, __LINE__);
      }
    }
  tl_init_state = 2;
  return TL_OK;
}

void tl_initialize_forget(void) { tl_init_state = 0; }

const char *tl_version(void) { return TALUS_VERSION; }
const char *tl_revision(void) { return TALUS_REVISION; }

int tl_exit_code(TlStatus status)
{
  switch (status) {
  case TL_OK:
  case TL_HELP: return 0;
  case TL_ERR_ARG:
  case TL_ERR_FORMAT:
  case TL_ERR_IO:
  case TL_ERR_NOT_FOUND:
  case TL_ERR_UNSUPPORTED: return 2;
  default: return 1;
  }
}

const char *tl_exit_word(TlStatus status)
{
  switch (status) {
  case TL_OK:
  case TL_HELP: return "ok";
  case TL_ERR_NUMERIC:
  case TL_ERR_UNSTABLE:
  case TL_ERR_CONVERGENCE: return "stopped";
  default: return tl_exit_code(status) == 2 ? "refused" : "failed";
  }
}

int tl_driver_exit(TlStatus status)
{
  if (status == TL_OK || status == TL_HELP) return 0;
  fflush(stdout);
  fprintf(stderr, "error (%s): %s\n", tl_status_name(status), tl_error_message());
  fflush(stderr);
  tl_summary_end(status, stdout);
  return tl_exit_code(status);
}
