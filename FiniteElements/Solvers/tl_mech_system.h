/* The abstract mechanical system the time steppers drive:
 *
 *     M a + f_int(u, v) = f_ext(t, u)
 *
 * over ndof unknowns u (displacements), v = du/dt, a = dv/dt.
 *
 * Contract (the solid implements it; couplings load the solid through its
 * wrappers, tl_solid.h, which enter f_int and f_ext)
 * - Dof numbering is the system's own: 0 .. ndof-1.  Dofs clamped at zero
 *   for all time may simply be left out of the numbering (negative dof in
 *   the element lists of tl_sparse.h).  Dofs with a prescribed, possibly
 *   time-dependent value stay in the numbering and are listed in
 *   dirichlet_dofs; the steppers set u, v, a there from ops->dirichlet and
 *   replace their equations by identities (symmetric elimination), so
 *   f_int / f_ext values at those dofs are ignored (they are reactions).
 * - All vectors are full length ndof, caller-allocated.  Force routines
 *   overwrite their output; matrix routines ADD into a TlSparse created by
 *   ops->create_matrix (one pattern for stiffness, damping, mass and load
 *   tangents), so a stepper assembles  c_m M + c_v C + c_u (K - K_ext)  in
 *   one matrix with no copy.  A matrix routine is one call per batch of
 *   elements, never per element.
 * - symmetric = 1 promises that every matrix added is symmetric (then the
 *   stepper may ask for upper-triangle storage and use CHOLMOD);
 *   follower loads or non-symmetric damping need symmetric = 0.
 * - Material state: internal_force and internal_tangent evaluate TRIAL state
 *   from the last COMMITTED state (path-dependent materials, a DEM cell as a
 *   material).  commit() is called once per accepted step; rollback() when a
 *   step is rejected (Newton failure).  Both optional (NULL = elastic).
 * - Errors: any op may fail (inverted element, NaN); the stepper stops and
 *   propagates the message. */
#ifndef TL_MECH_SYSTEM_H
#define TL_MECH_SYSTEM_H

#include "tl_checkpoint.h"
#include "tl_error.h"
#include "tl_object.h"
#include "tl_sparse.h"

typedef struct TlMechSystem TlMechSystem;

typedef struct {
  TlOpsHeader header; /* kind "mech_system" */
  /* Required. */
  /* *K = new matrix with the pattern of all the system's matrices, values
   * zero; upper-triangle storage when upper = 1 (asked only when
   * sys->symmetric), full storage otherwise (KLU, UMFPACK). */
  TlStatus (*create_matrix)(TlMechSystem *sys, int upper, TlSparse **K);
  /* f = f_int(u, v). */
  TlStatus (*internal_force)(TlMechSystem *sys, double t, const double *u, const double *v,
                             double *f);
  /* K += c_u * d f_int/du + c_v * d f_int/dv (c_v term only if damped). */
  TlStatus (*internal_tangent)(TlMechSystem *sys, double t, const double *u, const double *v,
                               double c_u, double c_v, TlSparse *K);
  /* f = f_ext(t, u) (dead and follower loads, body forces). */
  TlStatus (*external_force)(TlMechSystem *sys, double t, const double *u, double *f);
  /* m = diagonal (lumped) mass, m[i] > 0 at every dof. */
  TlStatus (*lumped_mass)(TlMechSystem *sys, double *m);
  /* Optional (NULL: default behaviour in brackets). */
  /* K += c * d f_ext/du  [dead loads: zero]. */
  TlStatus (*external_tangent)(TlMechSystem *sys, double t, const double *u, double c, TlSparse *K);
  /* M += c * consistent mass  [the lumped mass is used]. */
  TlStatus (*consistent_mass)(TlMechSystem *sys, double c, TlSparse *M);
  /* Writes u, v, a (any may be NULL) at the Dirichlet dofs only, at time t
   * [prescribed values are zero]. */
  TlStatus (*dirichlet)(TlMechSystem *sys, double t, double *u, double *v, double *a);
  /* *W = stored (strain) energy at u  [energy checks unavailable]. */
  TlStatus (*strain_energy)(TlMechSystem *sys, const double *u, double *W);
  /* Accept / discard the trial material state  [no internal state]. */
  TlStatus (*commit)(TlMechSystem *sys);
  TlStatus (*rollback)(TlMechSystem *sys);
  /* Largest eigenvalue bound of M_lumped^-1 K (e.g. max over elements of the
   * element bound); used by the explicit stepper when asked to take the
   * conservative bound  [Lanczos on M^-1 K]. */
  TlStatus (*max_frequency_squared)(TlMechSystem *sys, const double *u, double *omega2);
  /* Saves / restores the system's own evolving state (committed material
   * state) under a checkpoint group; the steppers' checkpoint section calls
   * it  [no state beyond what the stepper holds]. */
  const TlCheckpointOps *checkpoint;
  void (*destroy)(TlMechSystem *sys); /* frees the derived type's content */
} TlMechSystemOps;

struct TlMechSystem {
  const TlMechSystemOps *ops;
  TlSparseIndex ndof;
  int symmetric; /* all matrices symmetric: upper storage, CHOLMOD usable */
  int damped;    /* f_int depends on v */
  TlSparseIndex n_dirichlet;
  TlSparseIndex *dirichlet_dofs; /* owned by the derived type */
};

/* Calls ops->destroy, frees the object and nulls *sys.  The derived type is
 * allocated as one block whose first member is the TlMechSystem. */
void tl_mech_system_destroy(TlMechSystem **sys);

#endif
