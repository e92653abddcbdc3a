/* Internal to Coupling/Bridging: the coupling's state, shared by
 *   tl_bdm.c             life cycle, weights, N, the correction and its report
 *   tl_bdm_ghost.c       the ghost-force record and its subtraction
 *   tl_bdm_options.c     options, their check and the alpha profile
 *   tl_bdm_checkpoint.c  the checkpoint section
 *   tl_bdm_system.c      the algebra (tl_bdm_system.h) */
#ifndef TL_BDM_PRIVATE_H
#define TL_BDM_PRIVATE_H

#include <stdint.h>

#include "tl_bdm.h"
#include "tl_bdm_system.h"

#define TL_BDM_MAX_ZONES 8

struct TlBdm {
  TlSolid *solid;
  int block;
  TlDem *dem;
  TlStepper *st;
  TlBdmZone zones[TL_BDM_MAX_ZONES];
  int n_zones;
  TlBdmOptions opt;
  /* reference positions of every particle at creation, by id */
  size_t n_ref;
  int64_t *ref_id;
  TlVec3 *ref_x;   /* wrapped into the mesh's periodic section */
  double *ref_w;   /* 1 - alpha(X) */
  int64_t id_cap;  /* ids below it have a slot */
  size_t *slot_of_id; /* id -> reference slot (SIZE_MAX: none) */
  size_t *index_of_id; /* id -> current particle index (scratch of the remap) */
  double *alpha_nodes; /* n_nodes */
  /* coupled particles: reference slot and current index */
  size_t n_c, n_excluded;
  size_t *c_slot, *c_idx;
  /* particles whose initial forces are subtracted (-ghost_force dem|both):
   * every free particle a weighted contact can reach, i.e. whose reference
   * centre lies within the largest radius of a zone */
  size_t n_g;
  size_t *g_slot, *g_idx;
  /* N by rows q = 3k + c in the solid's dof numbering, weighted masses */
  size_t *ptr;
  TlSparseIndex *dof;
  double *phi, *m_q;
  unsigned char *fixed; /* per dof: Dirichlet */
  int *comp;            /* per dof: Cartesian component */
  TlBdmSystem *sys;
  double *v_q, *v_q0, *gdot, *mu, *g_w, *v_dof0;
  /* ghost forces: subtracted FE internal force at setup (node space, 3 per
   * node) and the coupled particles' initial weighted forces (3 each) */
  double *ghost_fe, *ghost_dem; /* ghost_dem: 3 per ghost-force particle */
  TlSolidWrapper *wrapper;
  /* report */
  TlBdmReport last;
  int state_diagnosed; /* last's rates, residual and momentum are of the current state */
  long steps;
  double removed_total;
  double t_setup, t_correct;
  int ready;
};

/* Records the ghost forces at the current state and installs their
 * subtraction (tl_bdm_ghost.c). */
TlStatus tl_bdm_ghost_setup(TlBdm *b);
/* Writes the recorded particle ghost forces into P->f_coupling (after a
 * restart or a renumbering of the particles). */
TlStatus tl_bdm_ghost_apply_dem(TlBdm *b);
/* Current indices of the coupled and ghost-force particles (after the DEM
 * renumbered). */
TlStatus tl_bdm_remap(TlBdm *b);

#endif
