/* A nonlinear spring-mass chain as a TlMechSystem, with answers known in
 * closed form: the reference system for the solver and stepper tests and
 * the small benchmark cases.
 *
 * n masses on a line, one dof each; spring e joins mass e-1 and mass e
 * (mass -1 is a fixed wall, an eliminated dof).  Spring force
 * s(d) = k (d + alpha d^3) on the stretch d, a parallel dashpot c d',
 * a dead tip load F on the last mass, and optionally
 *  - a consistent (bar-element) mass instead of the lumped one only;
 *  - a non-symmetric load f_ext[n-1] += kf * u[0] (a follower-like term);
 *  - the last mass prescribed: u = tip_velocity * t (a Dirichlet dof). */
#ifndef TL_SPRING_CHAIN_H
#define TL_SPRING_CHAIN_H

#include "tl_mech_system.h"

typedef struct {
  TlSparseIndex n;     /* masses */
  double mass;         /* per mass (lumped) */
  double k, alpha;     /* spring law */
  double c;            /* dashpot */
  double tip_force;    /* F */
  double kf;           /* non-symmetric load coefficient */
  int consistent_mass; /* provide a consistent mass matrix */
  int prescribed_tip;  /* last dof prescribed */
  double tip_velocity; /* of the prescribed tip */
} TlSpringChainParams;

typedef struct {
  TlMechSystem base;
  TlSpringChainParams p;
  TlSparseIndex dirichlet[1];
  TlSparseIndex *elem_ptr, *elem_dofs, n_elem;
} TlSpringChain;

void tl_spring_chain_params_default(TlSpringChainParams *p);
TlStatus tl_spring_chain_create(const TlSpringChainParams *p, TlMechSystem **sys);

#endif
