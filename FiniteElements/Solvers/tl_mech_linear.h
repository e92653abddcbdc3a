/* A linearised mechanical system: the small-strain view of any TlMechSystem
 * about a reference state u_r (the pre-stressed rest state of a bar),
 *
 *     f_int(u) = f_r + K (u - u_r),   K = d f_int / du at u_r, assembled once,
 *
 * with the inner system's lumped mass, external force and Dirichlet values.
 * For a total-Lagrangian solid pre-stressed by an eigenstrain, K carries the
 * material and the geometric (pre-stress) stiffness, so the linear system
 * agrees with the solid to second order in u - u_r; it costs one sparse
 * product per force evaluation instead of an element loop with a
 * constitutive call per Gauss point (the fast path of explicit runs whose
 * step is set by another model, such as a DEM).  Optionally f_r is dropped
 * (subtract_reference = 1): the rest forces are removed once for all (the
 * ghost-force correction of seeds/000 §4.2 applied to the whole bar).
 *
 * Stored energy W(u) = W_r + f_r.(u - u_r) + 1/2 (u - u_r).K(u - u_r)
 * (without the f_r term when it is subtracted).  The inner system is
 * borrowed and must outlive the linear one; its material state is not
 * advanced (the system is elastic by construction), so no commit, rollback
 * or checkpoint is forwarded. */
#ifndef TL_MECH_LINEAR_H
#define TL_MECH_LINEAR_H

#include "tl_error.h"
#include "tl_mech_system.h"

/* u_ref may be NULL (zero); t is the time at which the tangent is taken. */
TlStatus tl_mech_linear_create(TlMechSystem *inner, double t, const double *u_ref, int subtract_reference,
                               TlMechSystem **linear);
/* The assembled K (owned by the linear system). */
const TlSparse *tl_mech_linear_matrix(const TlMechSystem *linear);
/* f_r, the inner internal force at u_ref (ndof; owned). */
const double *tl_mech_linear_reference_force(const TlMechSystem *linear);

#endif
