/* The types the examples add to Talus from outside the library, one file
 * each; a driver registers the ones it uses, then creates them by name
 * exactly like built-in ones. */
#ifndef EXAMPLES_H
#define EXAMPLES_H

#include "talus.h"

/* contact_viscoelastic_hertz.c: normal contact part "viscoelastic_hertz". */
TlStatus example_viscoelastic_hertz_register(void);
/* element_hex20.c: element type "hex20" (Gmsh type 17). */
TlStatus example_hex20_register(void);
/* material_mooney_rivlin.c: material "mooney_rivlin". */
TlStatus example_mooney_rivlin_register(void);

#endif
