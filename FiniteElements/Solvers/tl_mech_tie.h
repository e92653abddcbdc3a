/* A tied mechanical system: some dofs of an inner TlMechSystem are slaves
 * that move with a master dof (periodic boundaries, node merging), so the
 * tied system has one dof per master:
 *
 *     u_inner = P u,   f = P^T f_inner,   m = P^T m_inner,   K = P^T K_inner P,
 *
 * with P the 0/1 matrix that gives each inner dof the value of its master's
 * tied dof.  The steppers drive the tied system like any other; the inner
 * system never knows (its dof numbering, loads and wrappers are unchanged).
 *
 * The map: master[i] is the inner dof whose value inner dof i takes (i for
 * a free dof).  Chains (a corner slave of an edge slave) are followed to
 * their root; a cycle is refused.  Dirichlet dofs: a slave and its root must
 * be both prescribed or both free (the error names the pair); the tied
 * Dirichlet list is the image of the inner one, and the prescribed values
 * come from the inner system's dirichlet op at the root dofs.
 *
 * Tied dof numbering: the roots in increasing inner order, 0 .. ndof-1
 * (tl_mech_tie_dof maps an inner dof to it).  The inner system is borrowed
 * and must outlive the tie.  Every optional op of the inner system is
 * forwarded (consistent mass, strain energy, commit/rollback, the frequency
 * bound, which stays an upper bound of the tied system's, and the
 * checkpoint of the inner state).
 *
 * Periodic ties of a solid's node sets (pairs found by a translation) are
 * built by tl_solid_periodic_tie (tl_solid_tie.h). */
#ifndef TL_MECH_TIE_H
#define TL_MECH_TIE_H

#include "tl_error.h"
#include "tl_mech_system.h"

/* *tied = the tied view of inner; master has inner->ndof entries. */
TlStatus tl_mech_tie_create(TlMechSystem *inner, const TlSparseIndex *master, TlMechSystem **tied);
/* Tied dof of inner dof i (i in 0 .. inner ndof - 1). */
TlSparseIndex tl_mech_tie_dof(const TlMechSystem *tied, TlSparseIndex i);
/* The inner system. */
TlMechSystem *tl_mech_tie_inner(const TlMechSystem *tied);
/* u_inner = P u (scatter to every inner dof) and f = P^T f_inner (sum over
 * each root's slaves). */
void tl_mech_tie_expand(const TlMechSystem *tied, const double *u, double *u_inner);
void tl_mech_tie_reduce(const TlMechSystem *tied, const double *f_inner, double *f);
/* Number of inner dofs (for sizing u_inner). */
TlSparseIndex tl_mech_tie_inner_ndof(const TlMechSystem *tied);

#endif
