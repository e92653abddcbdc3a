/* The VCoupling element type (seeds/001 §5.3.2): the solid side of a volume
 * coupling as a wrapper over the element block (tl_solid_add_wrapper).
 *
 * For the block a TlVCoupling was built on, it
 *   - weights the solid's equations by 1 - w (Eq. 26): the nodal particle
 *     weights w_i of the coupling, interpolated with the shape functions at
 *     the stiffness and mass points (tl_solid_set_node_weights), so internal
 *     force, tangent, stored energy, consistent and lumped mass carry the
 *     factor; the wrapper owns these weights;
 *   - adds the coupling body force b^C = eps (u^DE - u^FE) of Eq. 31,
 *     integrated against the shape functions, F_i = eps sum_j M_ij r_j, for
 *     its elements, as an internal term (-F in f_int) inside every
 *     evaluation of the block (so inside Newton iterations), with its
 *     derivative -eps M_ij in the tangent.  The
 *     mismatch is the paper's, Eq. 29, on the displacement over the step:
 *     r_j = u_j^DE - (u_j - u_j^start), u^DE = Pi du_p.
 * The particle side takes f_a^C = -sum_i Pi_ia F_i (Eq. 32) at the solid's
 * end-of-step displacement, so the two forces balance (Eq. 41).
 *
 * Life cycle:
 *   tl_vcoupling_element_create(vc, solid, &el)   before tl_solid_setup
 *   per step: tl_vcoupling_update(vc, ...) (Pi), then
 *             tl_vcoupling_element_set_step(el, du_p, u_start),
 *             the solid's step (the wrapper adds the coupling force),
 *             tl_vcoupling_element_particle_forces(el, u_end, f_p, &diag)
 *   tl_vcoupling_element_destroy(&el)             removes the wrapper
 * Until the first set_step the wrapper adds nothing. */
#ifndef TL_VCOUPLING_ELEMENT_H
#define TL_VCOUPLING_ELEMENT_H

#include "tl_error.h"
#include "tl_solid.h"
#include "tl_vcoupling.h"

typedef struct TlVCouplingElement TlVCouplingElement;

/* Wraps the coupling's block of `solid` (built on the coupling's mesh) and
 * sets its weights 1 - w_i; both objects are borrowed and must outlive the
 * element.  Refused after tl_solid_setup (the masses are built there). */
TlStatus tl_vcoupling_element_create(TlVCoupling *vc, TlSolid *solid, TlVCouplingElement **el);
/* Removes its wrapper from the block (in any order among wrappers). */
void tl_vcoupling_element_destroy(TlVCouplingElement **el);

/* The step's data for the coupling force: du_p, the particle displacements
 * over the step (3 per particle of the last tl_vcoupling_update), and
 * u_start, the solid's node-space displacements at the start of the step
 * (3 per mesh node); both copied. */
TlStatus tl_vcoupling_element_set_step(TlVCouplingElement *el, const double *du_p, const double *u_start);
/* The authors' published explicit order instead: the mismatch fixed before
 * the step, r = Pi du_p - du_n with du_p and du_n the particles' and the
 * solid's displacements over the previous step (both copied), so that the
 * solid takes a constant coupling load over its step (no tangent term) and
 * the particles its reaction (Eq. 41 as before); particle_forces ignores
 * its u_nodes.  Until the next set_step. */
TlStatus tl_vcoupling_element_set_step_lagged(TlVCouplingElement *el, const double *du_p, const double *du_n);
/* Switches the coupling force off (the weights stay) until the next set_step. */
void tl_vcoupling_element_clear(TlVCouplingElement *el);

/* Eq. 32 at the solid's node-space displacements u_nodes (the end of the
 * step): ADDS f_a^C to f_particles (3 per particle; may be NULL); diag (may
 * be NULL) gets the residual, both force sums and Eq. 41. */
TlStatus tl_vcoupling_element_particle_forces(TlVCouplingElement *el, const double *u_nodes, double *f_particles,
                                              TlVCouplingDiag *diag);

/* The nodal coupling forces F_i at u_nodes, ADDED to f_nodes (external sign:
 * the force on the solid; 3 per mesh node). */
TlStatus tl_vcoupling_element_nodal_forces(TlVCouplingElement *el, const double *u_nodes, double *f_nodes);

/* The solid weights 1 - w_i it set (one per mesh node). */
const double *tl_vcoupling_element_weights(const TlVCouplingElement *el);

#endif
