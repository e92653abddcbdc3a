#include "tl_init.h"

#include <stdio.h>

/* Each module's registration function.  A module that adds a registered type
 * adds it to its own tl_<module>_register_all(); a new module adds one line
 * here. */
typedef TlStatus (*TlRegisterAll)(void);
TlStatus tl_cg_register_all(void);
TlStatus tl_fem_register_all(void);
TlStatus tl_stepper_register_all(void);
TlStatus tl_dem_register_all(void);
TlStatus tl_walls_register_all(void);
static const TlRegisterAll tl_modules[] = {
    tl_cg_register_all,
    tl_fem_register_all,
    tl_stepper_register_all,
    tl_dem_register_all,
    tl_walls_register_all,
    NULL, /* keeps the table non-empty before any module registers */
};

TlStatus tl_initialize(void)
{
  static int done = 0;
  if (done) return TL_OK;
  for (size_t i = 0; i < sizeof tl_modules / sizeof tl_modules[0]; ++i)
    if (tl_modules[i]) TL_CHECK(tl_modules[i]());
  done = 1;
  return TL_OK;
}

int tl_driver_exit(TlStatus status)
{
  if (status == TL_OK || status == TL_HELP) return 0;
  fprintf(stderr, "error (%s): %s\n", tl_status_name(status), tl_error_message());
  return 1;
}
