#include "tl_mech_system.h"

#include "tl_memory.h"

void tl_mech_system_destroy(TlMechSystem **sys)
{
  if (!sys || !*sys) return;
  if ((*sys)->ops && (*sys)->ops->destroy) (*sys)->ops->destroy(*sys);
  tl_free(sys);
}
