/* Periodic ties of a solid: the nodes of a slave node set move with the
 * nodes of a master set found by a translation (x_slave = x_master +
 * offset), component by component, through the tied system of
 * tl_mech_tie.h.  Any block, any element type: pairs are found from the
 * node coordinates only.  Several pairs of sets (x, then z) compose; a node
 * in two slave sets (an edge) keeps its first master and the chain reaches
 * the same root.  Clamped components must match on both sides (the error
 * names the node). */
#ifndef TL_SOLID_TIE_H
#define TL_SOLID_TIE_H

#include "tl_mech_tie.h"
#include "tl_solid.h"

typedef struct {
  const char *master; /* node set names */
  const char *slave;
  double offset[3];   /* x_slave - x_master (m) */
} TlPeriodicPair;

/* *tied = the solid's system (after tl_solid_setup) with every pair tied;
 * tol (m) is the distance within which a translated master matches a
 * slave.  The solid must outlive the tie. */
TlStatus tl_solid_periodic_tie(TlSolid *solid, int n_pairs, const TlPeriodicPair *pairs, double tol,
                               TlMechSystem **tied);

#endif
