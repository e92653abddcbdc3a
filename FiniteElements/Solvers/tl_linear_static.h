/* Linear static analysis of a mechanical system (tl_mech_system.h):
 *
 *     K u = f_ext(t, 0),   K = d f_int / du at u = 0, v = 0,
 *
 * the stiffness assembled once at the reference state, one factorisation,
 * one solve: small-displacement elasticity, whatever law the system's
 * material follows at finite strain (every law here reduces to Hooke's law
 * at the reference).  Dirichlet dofs take their prescribed values at t by
 * symmetric elimination (their columns move to the right-hand side).  Load
 * stiffness (follower loads, d f_ext/du) is left out, as linear analyses
 * do: the loads are taken in the reference configuration. */
#ifndef TL_LINEAR_STATIC_H
#define TL_LINEAR_STATIC_H

#include "tl_error.h"
#include "tl_mech_system.h"

typedef struct {
  TlSparseIndex ndof;
  double t_assemble, t_factor, t_solve; /* seconds */
  double residual; /* ||K u - f||_inf / max(||f||_inf, tiny) on the free dofs, after the solve */
} TlLinearStaticStats;

/* u (ndof, caller-allocated) from the loads at time t.  `solver`: "cholmod",
 * "klu", "umfpack", or NULL (CHOLMOD when the system is symmetric, KLU
 * otherwise).  stats may be NULL. */
TlStatus tl_linear_static_solve(TlMechSystem *sys, const char *solver, double t, double *u,
                                TlLinearStaticStats *stats);

#endif
