/* The ghost-force correction of seeds/000 §4.2 (after Shenoy et al.): the
 * forces of the weighted, pre-stressed overlap at the onset are recorded
 * and subtracted for the whole run, so the coupled system starts in
 * equilibrium.  FE: the internal nodal forces at the setup displacements
 * (the eigenstrain forces on the mesh's free end inside the DEM and those
 * of the weighted elements) enter as a constant external load through a
 * wrapper over the coupled block, so the stepper books their work.
 * Particles: the initial weighted force of each particle the weighting
 * reaches (coupled, or with a weighted contact: centre within the largest
 * radius of a zone), minus, in P->f_coupling (added to the particle's
 * force as it is). */
#include <math.h>
#include <string.h>

#include "tl_bdm_private.h"
#include "tl_memory.h"

static TlStatus ghost_external(void *ctx, TlSolid *solid, int blk, double t, const double *u_nodes, double *f_nodes,
                               double c, TlSparse *K)
{
  (void)solid, (void)blk, (void)t, (void)u_nodes, (void)c, (void)K;
  const TlBdm *b = ctx;
  if (!f_nodes) return TL_OK;
  const size_t n = 3 * tl_solid_mesh(b->solid)->n_nodes;
  for (size_t k = 0; k < n; ++k) f_nodes[k] += b->ghost_fe[k];
  return TL_OK;
}

static const TlSolidWrapperOps ghost_ops = {
    .header = {"solid_wrapper", "bdm_ghost_force", "bridging domain: initial internal forces subtracted"},
    .internal = NULL,
    .external = ghost_external,
};

/* The FE's internal nodal forces at the stepper's displacements, zero at
 * clamped and prescribed components (reactions, not unbalance). */
static TlStatus record_fe(TlBdm *b)
{
  const TlMesh *mesh = tl_solid_mesh(b->solid);
  const size_t nc = 3 * mesh->n_nodes;
  double *u = NULL;
  TL_CHECK(tl_calloc(&b->ghost_fe, nc, sizeof *b->ghost_fe));
  TL_CHECK(tl_calloc(&u, nc, sizeof *u));
  tl_solid_dofs_to_nodes(b->solid, b->st->u, u);
  TlStatus s = TL_OK;
  for (int blk = 0; blk < mesh->n_blocks && s == TL_OK; ++blk)
    s = tl_solid_block_forces(b->solid, blk, u, b->ghost_fe, 0.0, NULL, NULL);
  tl_free(&u);
  TL_CHECK(s);
  for (size_t I = 0; I < mesh->n_nodes; ++I)
    for (int c = 0; c < 3; ++c) {
      TlSparseIndex J = tl_solid_dof(b->solid, I, c);
      if (J < 0 || b->fixed[J]) b->ghost_fe[3 * I + (size_t)c] = 0.0;
    }
  TL_CHECK(tl_solid_add_wrapper(b->solid, b->block, &ghost_ops, b, &b->wrapper));
  /* the accelerations of the set-up state with the correction in place
   * (copies: set_state copies its arguments into the stepper's arrays) */
  const size_t n = (size_t)b->st->n;
  double *u0 = NULL, *v0 = NULL;
  s = tl_calloc(&u0, n + 1, sizeof *u0);
  if (s == TL_OK) s = tl_calloc(&v0, n + 1, sizeof *v0);
  if (s == TL_OK) {
    memcpy(u0, b->st->u, n * sizeof *u0);
    memcpy(v0, b->st->v, n * sizeof *v0);
    s = tl_stepper_set_state(b->st, b->st->t, u0, v0);
  }
  tl_free(&u0);
  tl_free(&v0);
  return s;
}

/* Whether the DEM's last forces were evaluated with the coupling's
 * weights (tl_bdm_create before tl_dem_setup); otherwise they are
 * evaluated once more. */
static int forces_weighted(const TlBdm *b)
{
  const TlParticles *P = tl_dem_particles(b->dem);
  if (!P->weight) return 0;
  for (size_t i = 0; i < P->n; ++i) {
    int64_t id = P->id[i];
    size_t slot = id >= 0 && id < b->id_cap ? b->slot_of_id[id] : SIZE_MAX;
    if (slot != SIZE_MAX && P->weight[i] != b->ref_w[slot]) return 0;
  }
  return 1;
}

/* The free particles a weighted contact reaches: reference centre within
 * the largest radius of a zone (a contact point lies within its
 * particle's radius of the centre). */
static TlStatus ghost_particles(TlBdm *b)
{
  const TlParticles *P = tl_dem_particles(b->dem);
  double r_max = 0.0;
  for (size_t i = 0; i < P->n; ++i) r_max = fmax(r_max, P->radius[i]);
  const double reach = r_max * (1.0 + 1e-9);
  TL_CHECK(tl_calloc(&b->g_slot, b->n_ref + 1, sizeof *b->g_slot));
  TL_CHECK(tl_calloc(&b->g_idx, b->n_ref + 1, sizeof *b->g_idx));
  b->n_g = 0;
  for (size_t i = 0; i < P->n; ++i) {
    int64_t id = P->id[i];
    size_t slot = id >= 0 && id < b->id_cap ? b->slot_of_id[id] : SIZE_MAX;
    if (slot == SIZE_MAX || P->motion[i] != TL_MOTION_FREE) continue;
    const double *X = &b->ref_x[slot].x;
    int near = 0;
    for (int z = 0; z < b->n_zones && !near; ++z) {
      const TlBdmZone *Z = &b->zones[z];
      double a0 = fmin(Z->s_dem, Z->s_fe) - reach, a1 = fmax(Z->s_dem, Z->s_fe) + reach;
      near = X[Z->axis] >= a0 && X[Z->axis] <= a1;
    }
    if (!near) continue;
    b->g_slot[b->n_g] = slot;
    b->g_idx[b->n_g++] = i;
  }
  return TL_OK;
}

static TlStatus record_dem(TlBdm *b)
{
  TlParticles *P = tl_dem_particles(b->dem);
  TL_CHECK(tl_particles_enable_coupling_force(P));
  if (!forces_weighted(b)) TL_CHECK(tl_dem_compute_forces(b->dem));
  TL_CHECK(ghost_particles(b));
  TL_CHECK(tl_calloc(&b->ghost_dem, 3 * b->n_g + 1, sizeof *b->ghost_dem));
  for (size_t k = 0; k < b->n_g; ++k) {
    size_t i = b->g_idx[k];
    /* the force the particle had, less any coupling force already there */
    TlVec3 f = tl_v3_sub(P->f[i], P->f_coupling[i]);
    b->ghost_dem[3 * k] = f.x;
    b->ghost_dem[3 * k + 1] = f.y;
    b->ghost_dem[3 * k + 2] = f.z;
  }
  TL_CHECK(tl_bdm_ghost_apply_dem(b));
  /* the current force as the next evaluation will give it (no second
   * evaluation: a history law would book another increment) */
  for (size_t k = 0; k < b->n_g; ++k) {
    size_t i = b->g_idx[k];
    TlVec3 f0 = {b->ghost_dem[3 * k], b->ghost_dem[3 * k + 1], b->ghost_dem[3 * k + 2]};
    P->f[i] = tl_v3_add(f0, P->f_coupling[i]);
  }
  return TL_OK;
}

TlStatus tl_bdm_ghost_apply_dem(TlBdm *b)
{
  TlParticles *P = tl_dem_particles(b->dem);
  if (!b->ghost_dem) return TL_OK;
  TL_CHECK(tl_particles_enable_coupling_force(P));
  TL_CHECK(tl_bdm_remap(b));
  for (size_t k = 0; k < b->n_g; ++k)
    P->f_coupling[b->g_idx[k]] = (TlVec3){-b->ghost_dem[3 * k], -b->ghost_dem[3 * k + 1], -b->ghost_dem[3 * k + 2]};
  return TL_OK;
}

TlStatus tl_bdm_ghost_setup(TlBdm *b)
{
  const TlBdmGhost g = b->opt.ghost;
  if (g == TL_BDM_GHOST_FE || g == TL_BDM_GHOST_BOTH) TL_CHECK(record_fe(b));
  if (g == TL_BDM_GHOST_DEM || g == TL_BDM_GHOST_BOTH) TL_CHECK(record_dem(b));
  return TL_OK;
}
