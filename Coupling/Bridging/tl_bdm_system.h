/* The algebra of the bridging-domain velocity correction (seeds/000
 * Eqs. 7-14, the plus sign), on plain arrays: what tl_bdm.c builds from a
 * mesh and a DEM world, and what the algebra test drives with a random
 * operator.
 *
 * The unknowns are scalar: n_dof FE dofs (velocities udot, weighted
 * lumped masses Mbar) and n_q particle components (velocities ddot,
 * weighted masses mbar), one constraint per particle component q,
 *   g_q = sum_J N_Jq u_J - d_q,
 * with N given by rows q (the entries (dof, phi) of one particle component;
 * rows of one particle sum to one over its element's dofs).  Dofs flagged
 * `fixed` (a prescribed velocity) enter the rate but are never corrected,
 * i.e. their Mbar^-1 is 0.  Let f be the free dofs some row reaches.
 *   strong, lumped: A_qq = 1/mbar_q + sum_J phi_Jq S_J / Mbar_J,
 *     S_J = sum_q' phi_Jq' (row sum) or phi_Jq (diagonal), plus k Jacobi
 *     sweeps lambda += D^-1 (gdot - A lambda) towards the consistent one;
 *   strong, consistent: Woodbury, S = Mbar_f + N_f mbar N_f^T factorised
 *     once (CHOLMOD), lambda = mbar gdot - mbar N_f^T S^-1 N_f mbar gdot;
 *   weak: rows R = every dof some row reaches (free or fixed),
 *     A^W = (N N^T)_Rf Mbar_f^-1 (N N^T)_fR + N_R mbar^-1 N_R^T,
 *     factorised once (CHOLMOD; a rank-deficient N_R, fewer particles than
 *     nodes around some node, is refused), gdot^W = N_R gdot, and the
 *     particle-space multiplier mu = N_R^T lambda^W.
 * The correction with a particle-space multiplier mu (strong: lambda):
 *   udot_J -= (N_f mu)_J / Mbar_J,  ddot_q += mu_q / mbar_q. */
#ifndef TL_BDM_SYSTEM_H
#define TL_BDM_SYSTEM_H

#include <stddef.h>

#include "tl_bdm.h"
#include "tl_sparse.h"

typedef struct {
  size_t n_q;               /* constrained particle components */
  const size_t *ptr;        /* n_q + 1: row q holds entries ptr[q] .. ptr[q+1]-1 */
  const TlSparseIndex *dof; /* dof of each entry, in [0, n_dof) */
  const double *phi;        /* shape value of each entry */
  const double *m;          /* mbar per row (> 0) */
  TlSparseIndex n_dof;
  const double *M;          /* Mbar per dof (> 0 at every free dof a row reaches) */
  const unsigned char *fixed; /* per dof, 1: prescribed velocity (not corrected); NULL: none */
} TlBdmOperator;

typedef struct TlBdmSystem TlBdmSystem;

/* Copies the operator, builds the lumped diagonal or factorises the
 * constant system.  Errors name a non-positive mass, a dof out of range,
 * an empty operator, a system CHOLMOD cannot factorise. */
TlStatus tl_bdm_system_create(const TlBdmOperator *op, TlBdmConstraint constraint, TlBdmLumping lumping, int jacobi,
                              TlBdmSystem **sys);
void tl_bdm_system_destroy(TlBdmSystem **sys);

/* gdot_q = sum_J N_Jq v_dof[J] - v_q[q] (n_q values). */
void tl_bdm_system_rate(const TlBdmSystem *sys, const double *v_dof, const double *v_q, double *gdot);
/* The weak rate gdot^W = N_R gdot (n_rows values, rows in the order of
 * tl_bdm_system_rows). */
void tl_bdm_system_weak_rate(const TlBdmSystem *sys, const double *gdot, double *gdot_w);
/* The particle-space multiplier mu for the rate gdot (n_q values each):
 * strong lambda = A^-1 gdot (lumped: its approximation), weak N_R^T lambda^W. */
TlStatus tl_bdm_system_solve(TlBdmSystem *sys, const double *gdot, double *mu);
/* Applies the correction of mu to the velocities (in place). */
void tl_bdm_system_apply(const TlBdmSystem *sys, const double *mu, double *v_dof, double *v_q);
/* y = A x for the consistent strong A = N_f^T Mbar_f^-1 N_f + mbar^-1
 * (n_q values; for checks and the Jacobi sweeps). */
void tl_bdm_system_apply_A(const TlBdmSystem *sys, const double *x, double *y);

/* The weak constraint's rows (dofs; NULL and 0 for the strong one), and
 * the free dofs the rows reach. */
const TlSparseIndex *tl_bdm_system_rows(const TlBdmSystem *sys, size_t *n_rows);
const TlSparseIndex *tl_bdm_system_free_dofs(const TlBdmSystem *sys, size_t *n_free);
/* The last weak multiplier lambda^W (n_rows; NULL for strong). */
const double *tl_bdm_system_weak_multiplier(const TlBdmSystem *sys);

#endif
