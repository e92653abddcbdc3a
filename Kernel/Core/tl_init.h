/* Library start-up: registers every built-in type (contact-law parts,
 * walls, element types, materials, steppers, CG kernels, ...) so they can be
 * found by name.  Idempotent; registry look-ups call it themselves. */
#ifndef TL_INIT_H
#define TL_INIT_H

#include "tl_error.h"

TlStatus tl_initialize(void);
/* After tl_registry_clear(): the next tl_initialize() registers again. */
void tl_initialize_forget(void);

/* For main(): prints the error of a failed run to stderr and returns the
 * process exit code (0 for TL_OK and TL_HELP, 1 otherwise). */
int tl_driver_exit(TlStatus status);

#endif
