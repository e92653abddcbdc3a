/* The DEM world's state and the functions its files share; private to
 * Kernel/DEM.  The world is split by concern:
 *   tl_dem.c             life cycle, configuration, setup, time-step limit
 *   tl_dem_neighbours.c  neighbour list: rebuild, renumbering, remap, bonds
 *   tl_dem_contacts.c    the contact loop: force evaluation
 *   tl_dem_weights.c     weights of the equations (volume coupling)
 *   tl_dem_step.c        time integration
 *   tl_dem_insert.c      insertion and removal of particles
 *   tl_dem_gas.c         random sequential insertion of a loose gas
 *   tl_dem_compress.c    isotropic compression of a cell to a pressure
 *   tl_dem_diagnostics.c energy, stress, coordination, visitors, statistics
 *   tl_dem_checkpoint.c  checkpoint save and load */
#ifndef TL_DEM_PRIVATE_H
#define TL_DEM_PRIVATE_H

#include <stdint.h>
#include "tl_contact_list.h"
#include "tl_dem.h"
#include "tl_timer.h"

enum { TL_DEM_MAX_LAWS = 16, CHUNK = 64 };

typedef struct {
  size_t start, end;
  int law;
} Chunk;

typedef struct {
  TlPrescribedEval eval;
  void *ctx;
  size_t n;
  int64_t *ids;
  size_t *idx;
  TlVec3 *x0, *xs, *vs;
} Prescribed;

typedef struct {
  int a, b, law;
} PairLaw;

/* A contribution to a particle's force and torque held back by a thread
 * that does not own the particle (Split). */
typedef struct {
  uint32_t p;
  TlVec3 f, t;
} Deferred;

/* How one contact list's loop is shared between threads so that every
 * particle receives its contacts' forces in list order whatever the thread
 * count (results bit for bit independent of it).  Thread t takes chunks
 * [first[t], first[t+1]), cut so that the threads' estimated costs (pairs
 * plus touching contacts) are equal.  A particle belongs to the first
 * thread whose contacts reach it, which adds into the world's force and
 * torque arrays directly; later threads defer their share of it, applied
 * after the loop in thread order, then list order: the sums one thread
 * makes.  No per-thread force arrays to clear and reduce; only the few
 * particles at the cuts pay.  Recomputed when the list or the thread count
 * changes. */
typedef struct {
  int nt;
  size_t n; /* particles when computed */
  unsigned long version;
  size_t first[TL_DEM_MAX_TIMED_THREADS + 1];
  uint8_t *owner; /* per particle: owning thread, 0xff none */
  size_t owner_cap;
  Deferred *def[TL_DEM_MAX_TIMED_THREADS];
  size_t def_cap[TL_DEM_MAX_TIMED_THREADS], n_def[TL_DEM_MAX_TIMED_THREADS];
  double *chunk_el, *chunk_pw; /* energy and power per chunk, summed in chunk order */
  size_t chunk_cap;
} Split;

struct TlDem {
  TlParticles *P;
  TlDomain domain;
  TlVec3 gravity;
  double skin_factor, skin, max_cut;
  int threads, sort_every, skip_fixed, track_energy;
  TlContactLaw *laws[TL_DEM_MAX_LAWS];
  int n_laws;
  PairLaw *pair_laws;
  size_t n_pair_laws, pair_laws_cap;
  int *law_table;
  size_t law_table_n;
  TlWall **walls;
  size_t n_walls, walls_cap;
  size_t hd; /* history stride */
  TlContactList list, old, bonds;
  int64_t *bond_ids;
  size_t n_bond_ids, bond_ids_cap;
  Chunk *chunks, *bond_chunks;
  size_t n_chunks, chunks_cap, n_bond_chunks, bond_chunks_cap;
  TlPair *pairs;
  size_t pairs_cap, n_pairs;
  TlHGrid *grid;
  TlVec3 *x_build;
  size_t x_build_cap;
  TlMat3 h_build_inv;
  uint8_t *skip;
  size_t skip_cap;
  size_t *perm, *old_to_new;
  size_t perm_cap;
  double (*xr)[4]; /* position and radius packed: one cache line per neighbour in the pair scan */
  size_t xr_cap;
  int nt, nt_now;
  Prescribed *presc;
  size_t n_presc, presc_cap;
  double dt, t, disp2max, r_min;
  double max_initial_overlap; /* of the smaller radius, checked by tl_dem_setup */
  int allow_above, setup_done, need_rebuild, rotation, orientation;
  int dim; /* 3, or 2: disks in the plane z = 0 (tl_dem_set_dimension) */
  long steps, rebuilds;
  int kick_pending; /* the last step's second half kick is still to do (tl_dem_step) */
  int in_steps;     /* inside tl_dem_step: the displacement check has just run, so every particle is within
                       half the skin of its build position (the walls' candidates may be kept); not so
                       for an evaluation on its own (tl_dem_compute_forces) */
  size_t n_touching;
  /* energy bookkeeping */
  double elastic_pp, contact_work_pp, work_ext;
  double *scratch;
  size_t scratch_cap;
  /* weights of the equations (volume coupling), all unused without a field */
  TlDemWeightFn weight_fn;
  void *weight_ctx;
  double *cw_list, *cw_bonds; /* per-contact weights of the last evaluation */
  size_t cw_list_cap, cw_bonds_cap;
  TlVec3 *cpoint;             /* contact points, scratch */
  size_t cpoint_cap;
  double *im_w, *ii_w;        /* 1 / (w m), 1 / (w I): the kicks of a weighted world */
  size_t im_w_cap, ii_w_cap;
  TlDemStepHook hook;
  void *hook_ctx;
  TlDemPhaseTimes prof; /* tl_dem_phase_times */
  int profile;          /* clocks read: on from the first tl_dem_reset_phase_times */
  Split split_list, split_bonds;
  TlWallStep *wall_steps; /* each wall's step, this evaluation */
  size_t wall_steps_cap;
  TlWallSums *wall_sums;  /* walls by particle ranges: per block, per wall of a run */
  size_t wall_sums_cap;
  unsigned long list_version; /* bumped whenever a list or the particle order changes */
};

/* The clock of the phase timers; 0 while they are off (small scenes of
 * many steps do not pay a dozen clock reads per step unasked). */
static inline double tl_dem_clock(const TlDem *d) { return d->profile ? tl_wtime() : 0.0; }

/* Books the time since *t0 to a phase and restarts the clock. */
static inline void tl_dem_tick(TlDem *d, int phase, double *t0)
{
  if (!d->profile) return;
  double t = tl_wtime();
  d->prof.seconds[phase] += t - *t0;
  *t0 = t;
}

/* tl_dem_neighbours.c */
TlStatus tl_dem_build_law_table(TlDem *d);
TlStatus tl_dem_make_chunks(const TlContactList *L, Chunk **chunks, size_t *cap, size_t *n);
TlStatus tl_dem_remap(TlDem *d, const size_t *old_to_new, size_t n_old);
TlStatus tl_dem_rebuild(TlDem *d);
int tl_dem_needs_rebuild(TlDem *d);
/* tl_dem_contacts.c */
TlStatus tl_dem_eval_forces(TlDem *d);
/* tl_dem_weights.c */
TlStatus tl_dem_weighted_inverses(TlDem *d);
TlStatus tl_dem_particle_weights(TlDem *d);
TlStatus tl_dem_contact_weights(TlDem *d, const TlContactList *L, double **cw, size_t *cap);

#endif
