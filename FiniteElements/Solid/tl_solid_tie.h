/* Periodic ties of a solid: the nodes of a slave node set are numbered as
 * the nodes of a master set found by a translation (x_slave = x_master +
 * offset), so each pair is one unknown per component (the solid's dof
 * numbering, tl_solid_dof, gives both the same dof; forces and masses of
 * the pair are summed into it).  Any block, any element type: pairs are
 * found from the node coordinates only.  Several ties compose (x, then z):
 * a node in two slave sets (an edge) keeps its first master and the chain
 * reaches the same root node.  At tl_solid_setup a tied node and its root
 * must carry the same boundary condition per component (clamped, prescribed
 * or free; the error names both nodes); a prescribed pair takes its value
 * from either node's prescription, so they must agree. */
#ifndef TL_SOLID_TIE_H
#define TL_SOLID_TIE_H

#include "tl_solid.h"

/* Ties every node of node set `slave` to the node of set `master` at its
 * position minus `offset` (m), within distance tol (m); before
 * tl_solid_setup.  A slave with no master within tol is refused with its
 * node number and position. */
TlStatus tl_solid_tie(TlSolid *solid, const char *master, const char *slave, const double offset[3], double tol);
/* Number of nodes tied to another (0 without ties). */
size_t tl_solid_n_tied(const TlSolid *solid);

#endif
