/* Internal to Kernel/Contact. */
#ifndef TL_CONTACT_PRIVATE_H
#define TL_CONTACT_PRIVATE_H

#include "tl_contact_kernels.h"
#include "tl_contact_law.h"

/* Checks the optional parts shared by the laws (friction, rolling,
 * adhesion). */
TlStatus tl_contact_check_common(const TlContactParameters *p);


#endif
