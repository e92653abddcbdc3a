/* Types registered by name so drivers and options choose them without a
 * switch statement in the kernel.  Each module registers its types in a
 * tl_<module>_register_all() that tl_initialize() calls once. */
#ifndef TL_REGISTRY_H
#define TL_REGISTRY_H

#include <stddef.h>
#include "tl_error.h"
#include "tl_object.h"

/* Registers an ops table (its header gives kind and name).  Registering the
 * same table again is harmless; another table under a taken name is an error. */
TlStatus tl_registry_add(const TlOpsHeader *ops);
/* Finds the ops table of `kind` named `name`; the error lists the known names. */
TlStatus tl_registry_find(const char *kind, const char *name, const TlOpsHeader **ops);
/* Copies up to max names of `kind` into names; returns how many exist. */
size_t tl_registry_list(const char *kind, const char **names, size_t max);
/* Empties the registry (tests). */
void tl_registry_clear(void);

#endif
