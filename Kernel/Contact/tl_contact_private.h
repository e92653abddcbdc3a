/* The object behind the built-in laws (linear, Hertz): their parameters and
 * what is precomputed from them.  Internal to Kernel/Contact. */
#ifndef TL_CONTACT_PRIVATE_H
#define TL_CONTACT_PRIVATE_H

#include "tl_contact_law.h"

typedef struct {
  TlContactLaw base;
  TlContactParameters p;
  double k_t;       /* linear: tangential stiffness (N/m); Hertz: k_t (Pa) */
  double k_n;       /* Hertz: normal k_n (Pa) */
  double eta;       /* linear: damping ratio from restitution */
  double gamma_lin; /* linear: explicit damping N s/m */
} TlStdLaw;

/* Checks the optional parts shared by the laws (friction, rolling,
 * adhesion). */
TlStatus tl_contact_check_common(const TlContactParameters *p);

extern const TlContactLawOps tl_contact_linear_ops;
extern const TlContactLawOps tl_contact_hertz_ops;

#endif
