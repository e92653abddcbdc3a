/* The DEM world: particles, contact laws, the persistent contact list,
 * walls, the domain and the hierarchical grid, and the time step.
 *
 * Life cycle:
 *   tl_dem_create(&dem)                      open domain by default
 *   tl_dem_set_domain / add species, particles, laws, walls, bonds
 *   tl_dem_set_timestep(dem, dt, override)   checked at setup
 *   tl_dem_setup(dem)                        allocates what the scene needs
 *                                            (rotation, history), checks the
 *                                            input, builds the grid
 *   tl_dem_step(dem, n) ...                  n Velocity-Verlet steps
 *   tl_dem_destroy(&dem)
 * Particles may be added or removed after setup through tl_dem_add_particle /
 * tl_dem_remove_particle (contacts and walls are kept consistent).
 *
 * Time step (seeds/001 Eqs. 1-2): Velocity-Verlet for translation; for
 * rotation of spheres the angular velocity is integrated the same way and the
 * orientation quaternion by dq/dt = ½ (0, ω) ⊗ q with the half-step spin,
 * renormalised.  Forces at t+dt use positions at t+dt and velocities at
 * t+dt/2.  Contact work is booked by the trapezoidal rule over each step, so
 * the energy balance (dissipation) is second-order accurate.
 *
 * Contacts: the neighbour list (pairs within r_i + r_j + skin, found with the
 * hierarchical grid) is the contact list; each entry holds the law's history.
 * It is rebuilt when some particle has moved more than skin/2 since the last
 * build (or the cell has deformed by as much); history moves to the new list
 * by a pair-keyed hash lookup.  Pairs of species are assigned laws with
 * tl_dem_set_pair_law (default: law 0 for all).  Contacts of each law are
 * evaluated in batches through its ops.
 *
 * Critical time step: the Velocity-Verlet stability limit 2/ω of the
 * stiffest mode, with ω² = 16 k_max / m_min (the lightest particle held by up
 * to eight contacts of the stiffest kind, its neighbours moving against it),
 * reduced by (sqrt(1 + ζ²) - ζ) for the largest damping ratio ζ:
 * dt_c = ½ sqrt(m_min / k_max) (sqrt(1 + ζ²) - ζ).  Hertz stiffness is taken
 * at an overlap of 10 % of the smallest radius.  A dt above dt_c is refused
 * with both
 * numbers unless the override is set, in which case it is logged.
 *
 * The implementation is split by concern over Kernel/DEM/tl_dem*.c; the
 * list is in tl_dem_private.h. */
#ifndef TL_DEM_H
#define TL_DEM_H

#include <stddef.h>
#include <stdint.h>
#include "tl_checkpoint.h"
#include "tl_contact_law.h"
#include "tl_domain.h"
#include "tl_error.h"
#include "tl_hgrid.h"
#include "tl_math.h"
#include "tl_particles.h"
#include "tl_wall.h"

typedef struct TlDem TlDem;

/* Energies and momenta of the current state (seeds/001 and DESIGN.md's
 * "every energy term"). */
typedef struct {
  double kinetic_translational; /* Σ ½ m v² over free particles (affine part excluded) */
  double kinetic_rotational;    /* Σ ½ I ω² */
  double elastic;               /* stored in particle-particle and wall contacts */
  double gravitational;         /* Σ -m g·x, free particles */
  double work_external;         /* cumulative work of f_ext, prescribed particles and moving walls */
  double dissipated;            /* cumulative: contact work - stored elastic energy */
  double total;                 /* kinetic + elastic + gravitational - work_external + dissipated */
  TlVec3 momentum;              /* Σ m v, free particles */
  TlVec3 angular_momentum;      /* Σ (x × m v + I ω) about the origin */
} TlDemEnergy;

/* Timings and counts. */
typedef struct {
  long steps;
  long rebuilds;
  size_t n_contacts;   /* touching pairs at the last step */
  size_t n_pairs;      /* neighbour-list pairs */
} TlDemStats;

/* Where the time of tl_dem_step goes: wall seconds per phase since the
 * last tl_dem_reset_phase_times, which also switches the timers on (off
 * until then: the clock is read a dozen times per step, tens of ns each),
 * and in the contact loop each thread's busy seconds.  The comments below
 * say which phases run threaded for a large scene; the rest is the serial
 * fraction. */
typedef enum {
  TL_DEM_PHASE_INTEGRATE, /* kicks, drift, spins, displacement check (threaded) */
  TL_DEM_PHASE_GRID,      /* neighbour search: hierarchical grid build, renumbering (serial) */
  TL_DEM_PHASE_PAIRS,     /* neighbour search: the grid's pair scan (threaded above 20000 particles) */
  TL_DEM_PHASE_LIST,      /* list build: laws, bonds, history carried over (serial) */
  TL_DEM_PHASE_BODY,      /* body forces, torques cleared, packed positions (threaded) */
  TL_DEM_PHASE_CONTACTS,  /* detection and force evaluation over the list (threaded) */
  TL_DEM_PHASE_REDUCE,    /* the threads' deferred contributions at the list's cuts (serial) */
  TL_DEM_PHASE_WALLS,     /* wall contacts */
  TL_DEM_PHASE_OTHER,     /* prescribed motion, walls' motion, hooks, checks */
  TL_DEM_N_PHASES
} TlDemPhase;

enum { TL_DEM_MAX_TIMED_THREADS = 64 };

typedef struct {
  double seconds[TL_DEM_N_PHASES];
  /* contact loop: per thread, seconds inside its share of the list */
  double thread_busy[TL_DEM_MAX_TIMED_THREADS];
  int threads;        /* threads of the contact loop at the last step */
  double imbalance;   /* Σ over evaluations of (slowest - mean) thread, s */
  long steps;
} TlDemPhaseTimes;

void tl_dem_phase_times(const TlDem *dem, TlDemPhaseTimes *t);
void tl_dem_reset_phase_times(TlDem *dem);
/* Short name of a phase ("integrate", "grid", ...). */
const char *tl_dem_phase_name(int phase);

TlStatus tl_dem_create(TlDem **dem);
void tl_dem_destroy(TlDem **dem);

TlParticles *tl_dem_particles(TlDem *dem);
TlDomain *tl_dem_domain(TlDem *dem);
const TlHGrid *tl_dem_grid(const TlDem *dem);
TlStatus tl_dem_set_domain(TlDem *dem, const TlDomain *domain);
/* Gravity (m/s², default zero).
 *
 * The particle force array P->f (tl_dem_particles) is the TOTAL force of
 * the last evaluation, gravity included: m g + f_ext (w (m g + f_ext) in a
 * weighted world) + f_coupling + the contact forces + the walls' forces, on every
 * particle, fixed and prescribed ones too.  The contact force alone is
 * P->f - m g - f_ext (- f_coupling); tl_dem_visit_contacts gives each
 * contact's.  P->torque holds the contact and wall torques only. */
void tl_dem_set_gravity(TlDem *dem, TlVec3 g);
/* Verlet skin as a fraction of the mean diameter (default 0.1; 0 rebuilds
 * every step). */
TlStatus tl_dem_set_skin(TlDem *dem, double skin_over_diameter);
/* Number of OpenMP threads (0: the OpenMP default).  A positive count also
 * becomes the OpenMP default (omp_set_num_threads), so walls, which thread
 * their own loops, follow it.  Small scenes run on one thread whatever the
 * setting (a parallel region costs more than it saves below ~8000 pairs). */
void tl_dem_set_threads(TlDem *dem, int threads);
/* Renumber particles in grid order every `rebuilds` neighbour-list rebuilds
 * for memory locality (default 10; 0 never). */
void tl_dem_set_sort_interval(TlDem *dem, int rebuilds);

/* ---- two-dimensional (disk) mode ----
 * tl_dem_set_dimension(dem, 2), before tl_dem_setup, makes a world of disks
 * in the plane z = 0 (seeds/004's 2-D cells):
 *   - particles are disks, cylinders of unit thickness: mass per unit
 *     thickness m = ρ π r² (kg/m), inertia ½ m r² (tl_particles_set_disks;
 *     the existing particles are recomputed, later ones follow);
 *   - motion is in-plane translation (x, y) and rotation about z only: the
 *     step never changes z, v_z, ω_x, ω_y (forces along z and torques about
 *     x, y, from gravity or walls, are ignored); contacts use in-plane branch
 *     vectors, normals and relative velocities, so z stays exactly 0;
 *   - the domain is open, an orthogonal periodic box not periodic along z,
 *     or the planar cell of tl_domain_init_cell_2d (h with a 2 x 2 in-plane
 *     block, x and y periodic; a deformable cell periodic along z is
 *     refused);
 *   - forces, the laws' stiffnesses and energies are per unit thickness
 *     (N/m, N/m per m, J/m), and tl_dem_stress divides by the in-plane area
 *     (tl_domain_area): a stress per unit thickness (N/m) whose z row and
 *     column are zero;
 *   - checkpoints carry the dimension (loading into a world of the other
 *     dimension is refused).
 * Setup refuses a particle off the plane (z or v_z nonzero), naming it.  The
 * contact loop and the step have their own 2-D paths: a 2-D scene costs
 * what two dimensions need (Benchmarks/dem_2d_vs_3d). */
TlStatus tl_dem_set_dimension(TlDem *dem, int dimension);
int tl_dem_dimension(const TlDem *dem);

/* Random sequential insertion of n particles of `species` (radii drawn from
 * its distribution) without overlap, nearest periodic images included, at
 * uniform random positions in the domain's cell (x = o + h s, s uniform in
 * [0, 1)³; s_z = 0 in a 2-D world, so disks land in the plane z = 0), with
 * zero velocity: a loose gas to be compressed (e.g. by a shrinking cell).
 * Gives up after max_attempts tries of one particle (refused, naming the
 * count placed and the packing fraction reached); *placed (may be NULL)
 * receives the count.  `seed` fixes the sequence.  Brute force in n²:
 * meant for cells of up to some 10⁴ particles. */
TlStatus tl_dem_insert_gas(TlDem *dem, int species, size_t n, uint64_t seed, long max_attempts, size_t *placed);

/* Isotropic compression of a periodic cell (deformable or planar; set up)
 * to a mean pressure, then relaxation under a pressure servo, the way a
 * packing is prepared: the cell shrinks at ḣ = -rate h (rate_fast far below
 * the target, blended towards `rate` as the pressure rises); once the target
 * is reached the rate follows the pressure error (clamped to ±rate), until
 * the pressure is within pressure_tolerance of the target and every
 * particle's static balance Δ_n (seeds/004 Eq. 19) is below `tolerance`, or
 * max_steps.  The pressure is -tr(σ)/d with d the dimension, contact and
 * kinetic parts (N/m in 2-D, Pa in 3-D).  The cell's rate is zero on
 * return.  The servo settles when one control interval strains the cell by
 * much less than the packing's elastic strain at the target (about
 * overlap / diameter): rate · control_every · dt ≪ P / k_n (2-D, linear
 * springs); a faster rate makes it swing between compression and expansion
 * (seeds/004 Eq. 18 with I ≈ 1e-5 near the target and 3e-3 for the gas
 * suit 400 disks, Benchmarks/cell_vs_yade). */
typedef struct {
  double pressure;           /* target (Pa; N/m in 2-D), > 0 */
  double rate, rate_fast;    /* strain rates near and far from the target (1/s), > 0 */
  double tolerance;          /* Δ_n of every particle, e.g. 1e-3 */
  double pressure_tolerance; /* relative, e.g. 1e-2 */
  long control_every;        /* steps between servo updates, >= 1 */
  long max_steps;
} TlDemCompress;
typedef struct {
  long steps;
  int converged;
  double pressure, max_imbalance, solid_fraction, coordination;
} TlDemCompressResult;
TlStatus tl_dem_compress(TlDem *dem, const TlDemCompress *c, TlDemCompressResult *result);

/* Takes ownership of the law; *index receives its number. */
TlStatus tl_dem_add_law(TlDem *dem, TlContactLaw *law, int *index);
/* Contacts between species a and b use law `law`. */
TlStatus tl_dem_set_pair_law(TlDem *dem, int species_a, int species_b, int law);
/* The laws as added (read and parameter access: a tangent operator reads
 * their stiffness, a probe suppresses sliding through tl_contact_law_set),
 * and the law of a pair of species (the last tl_dem_set_pair_law naming
 * them, law 0 otherwise). */
int tl_dem_n_laws(const TlDem *dem);
TlContactLaw *tl_dem_law(TlDem *dem, int k);
int tl_dem_pair_law(const TlDem *dem, int species_a, int species_b);
/* Takes ownership of the wall; its contacts use law `law`. */
TlStatus tl_dem_add_wall(TlDem *dem, TlWall *wall, int law);
size_t tl_dem_n_walls(const TlDem *dem);
TlWall *tl_dem_wall(TlDem *dem, size_t k);
/* A permanent bond between particles with ids a and b (its contact is kept
 * and evaluated whatever the distance; the law decides about tension). */
TlStatus tl_dem_add_bond(TlDem *dem, int64_t id_a, int64_t id_b);
/* Weighted equations (seeds/001 Eqs. 24-25, the particle side of a volume
 * coupling):  w_a m_a dv_a/dt = sum_b w_ab f_ab + w_a (m_a g + f_ext,a)
 * + f^C_a, with the spins likewise (w_a I_a, w_ab on the contact's torque).
 * `fn` evaluates the weight field at n points; the world calls it at every
 * force evaluation, once with the particle centres (into P->weight) and
 * once per contact list with the contact points x_i + n (r_i - delta/2)
 * (w_ab: Eq. 24 evaluated where the contact acts).  Particle weights must
 * be > 0, contact weights >= 0 (the error names the particle or pair).  The
 * contact laws see the plain kinematics and keep the plain force and
 * history; the weight scales what the contact gives the two particles and
 * the energy it stores and dissipates; tl_dem_energy then reports the
 * weighted energies and momenta.  Walls are not weighted: a weighted world
 * with walls is refused.  NULL fn: unweighted (the default; no cost).
 * f^C_a is P->f_coupling (tl_particles_enable_coupling_force), added as it
 * is; a coupling fills it in the step hook. */
typedef TlStatus (*TlDemWeightFn)(void *ctx, size_t n, const TlVec3 *x, double *w);
void tl_dem_set_weight_field(TlDem *dem, TlDemWeightFn fn, void *ctx);
/* Called in every step after the drift (positions at t + dt, velocities
 * at the half step, the neighbour list rebuilt if due, particles possibly
 * renumbered) and before the forces at t + dt are evaluated: where a
 * coupling advances its other model and sets P->f_coupling.  NULL: none. */
typedef TlStatus (*TlDemStepHook)(void *ctx, TlDem *dem);
void tl_dem_set_step_hook(TlDem *dem, TlDemStepHook hook, void *ctx);
/* Pairs where both particles are fixed are never evaluated (default on). */
void tl_dem_skip_fixed_pairs(TlDem *dem, int skip);

/* Prescribed motion for the particles with the given ids (copied). */
TlStatus tl_dem_prescribe(TlDem *dem, size_t n, const int64_t *ids, TlPrescribedEval eval, void *ctx);

TlStatus tl_dem_set_timestep(TlDem *dem, double dt, int allow_above_critical);
double tl_dem_timestep(const TlDem *dem);
double tl_dem_time(const TlDem *dem);
/* The critical time step estimate and what it was computed from. */
TlStatus tl_dem_critical_timestep(TlDem *dem, double *dt_critical, double *k_max, double *m_min);

/* The largest overlap of a pair at set-up, as a fraction of the smaller
 * radius (default TL_DEM_MAX_INITIAL_OVERLAP = 0.5; at most 1): beyond it
 * tl_dem_setup refuses the scene, naming the pair.  A preparation that
 * inserts grains overlapping on purpose (periodic_compress
 * -max_initial_overlap) sets it to what it allows. */
#define TL_DEM_MAX_INITIAL_OVERLAP 0.5
TlStatus tl_dem_set_max_initial_overlap(TlDem *dem, double fraction);
/* Checks the scene (radii, densities, initial overlaps, dt) and allocates
 * its state; must precede tl_dem_step. */
TlStatus tl_dem_setup(TlDem *dem);
/* n steps; stops with TL_ERR_UNSTABLE and a diagnosis (which particle, what
 * value) when a position or velocity becomes non-finite or a particle moves
 * more than its radius in one step. */
TlStatus tl_dem_step(TlDem *dem, long n);
/* Recomputes forces at the current state without moving (after edits). */
TlStatus tl_dem_compute_forces(TlDem *dem);

/* Insertion and removal at run time. */
TlStatus tl_dem_add_particle(TlDem *dem, TlVec3 x, TlVec3 v, double radius, int species, size_t *index);
/* Angular velocity (rad/s) of the particle at `index`, before or after
 * tl_dem_setup: the rotational state (tl_particles_enable_rotation) is
 * allocated on first use, so initial spins can be given with the particles.
 * The index is the current one (tl_particles_find maps an id to it; set-up
 * and rebuilds renumber).  A 2-D world takes spins about z only. */
TlStatus tl_dem_set_spin(TlDem *dem, size_t index, TlVec3 w);
TlStatus tl_dem_remove_particle(TlDem *dem, size_t index);

/* ---- diagnostics ---- */
/* Energies; energy bookkeeping (work, dissipation) is accumulated only after
 * tl_dem_track_energy(dem, 1) (it costs a little per contact). */
void tl_dem_track_energy(TlDem *dem, int on);
/* Whether sphere orientations (quaternions) are integrated (default on).  No
 * contact law between spheres depends on them: they serve output only, so a
 * scene that never writes them may switch them off. */
void tl_dem_track_orientation(TlDem *dem, int on);
TlStatus tl_dem_energy(TlDem *dem, TlDemEnergy *e);
/* Cauchy-Poisson stress of the contacts (seeds/004 Eq. 27, walls excluded)
 * and the kinetic part -Σ m v⊗v / V, both over the domain volume (the cell
 * volume for periodic domains, the given h for open ones). */
TlStatus tl_dem_stress(TlDem *dem, TlMat3 *contact_stress, TlMat3 *kinetic_stress);
/* Mean number of touching contacts per free particle (walls excluded), and
 * the same with rattlers (fewer than two contacts) removed. */
TlStatus tl_dem_coordination(TlDem *dem, double *z, double *z_no_rattlers);
/* Per-particle static balance Δ_n of seeds/004 Eq. 19, maximum over free
 * particles with contacts. */
TlStatus tl_dem_max_force_imbalance(TlDem *dem, double *delta);
void tl_dem_stats(const TlDem *dem, TlDemStats *s);

/* ---- contacts (read access, for tests, CG and output) ---- */
/* Visits every touching particle-particle contact: i, j, force on i, branch
 * vector from i to j, contact point. */
typedef void (*TlContactVisitor)(void *ctx, size_t i, size_t j, TlVec3 force_on_i, TlVec3 branch,
                                 TlVec3 contact_point);
TlStatus tl_dem_visit_contacts(TlDem *dem, TlContactVisitor visit, void *ctx);
/* Visits every wall contact of the last force evaluation with the force the
 * DEM computed: wall index, particle i, force on the particle, contact point
 * on the wall surface, and the particle centre the contact was computed with
 * (the nearest periodic image for walls that see images), through each
 * wall's visit_contacts op (tl_wall.h); a wall type without the op is
 * refused with its name. */
typedef void (*TlWallContactVisitor)(void *ctx, size_t wall, size_t i, TlVec3 force_on_particle, TlVec3 contact_point,
                                     TlVec3 particle_center);
TlStatus tl_dem_visit_wall_contacts(TlDem *dem, TlWallContactVisitor visit, void *ctx);

/* ---- checkpoint and restart (tl_checkpoint.h; object: the TlDem) ----
 * Saves everything a later step reads: the particle arrays (with rotation
 * state, forces and torques of the last evaluation, species, motion kinds,
 * ids and the next id), the contact list as it stands (pair order, law,
 * touching flag, last force, every history double) and the bonded contacts,
 * the build positions and counters of the neighbour list (the list is not
 * rebuilt on load: a rebuild at another step would reorder pairs and change
 * round-off), the domain (h, h⁻¹, ḣ, L), time, step and energy accumulators,
 * the prescribed-motion indices and attach positions, and each wall through
 * its checkpoint hooks plus its accounting fields.  Load into a world built
 * the same way and set up (tl_dem_setup); the scene's laws, species, walls
 * and prescribed groups must match in number and kind.  The grid is rebuilt
 * on load from the saved build positions (walls query it between rebuilds). */
extern const TlCheckpointOps tl_dem_checkpoint_ops;

#endif
