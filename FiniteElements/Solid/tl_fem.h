/* The finite-element module: registration of its built-in types. */
#ifndef TL_FEM_H
#define TL_FEM_H

#include "tl_error.h"

/* Registers the element types (kind "element") and the constitutive laws
 * (kind "material"). */
TlStatus tl_fem_register_all(void);

#endif
