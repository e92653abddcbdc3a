/* A periodic DEM cell as a numerically homogenised law (NHL, seeds/004
 * §2.2-2.4; specs/fem-x-dem.md §3, §5): the cell is driven from its
 * committed state at F^i to F^f at constant ḣ over the duration τ of the
 * inertial number (Eq. 18), relaxed until every particle's imbalance is
 * below ε_R (Eq. 19), and its Cauchy stress is the Cauchy-Poisson sum of
 * Eq. 27 (the contact part; the kinetic part is returned as a check).
 *
 * State.  A cell is one DEM world plus two saved states, COMMITTED (the end
 * of the last accepted load step, F^i) and TRIAL (the end of the last
 * evaluation).  Both are checkpoints in memory (tl_checkpoint.h), taken and
 * restored through tl_dem_checkpoint_ops, so they hold everything the world
 * reads and a restore is bit for bit.  An evaluation always starts by
 * restoring the committed state, so it depends only on (committed state,
 * F^f): the Newton iterations of a step and the perturbations of a CTO each
 * integrate the whole path, as the paper does.
 *
 * Deformation: h = F h_R, h_R the cell matrix at creation (the reference
 * configuration of the macro problem), so F = h h_R⁻¹ at any time.
 *
 * Two dimensions: a cell of disks (dim 2) uses the x-y block of F and of
 * σ (stress per unit thickness); the out-of-plane components of F must be
 * those of plane strain (F_33 = 1, F_13 = F_23 = F_31 = F_32 = 0).
 *
 * Units: SI (m, s, kg, Pa; in 2-D forces per unit thickness N/m and stress
 * N/m per m = Pa).  A cell is single-threaded (tl_dem_set_threads 1):
 * distinct cells may be evaluated from distinct threads at once. */
#ifndef TL_NHL_CELL_H
#define TL_NHL_CELL_H

#include <stddef.h>
#include "tl_checkpoint.h"
#include "tl_contact_law.h"
#include "tl_dem.h"
#include "tl_error.h"
#include "tl_math.h"
#include "tl_nhl_operator.h"

typedef struct TlNhlCell TlNhlCell;

/* Equilibrium criterion after the drive (Eq. 19 or the permissive one). */
typedef enum {
  TL_NHL_EQUILIBRIUM_IMBALANCE = 0, /* max_n Δ_n < tolerance (Eq. 19) */
  TL_NHL_EQUILIBRIUM_PRESSURE = 1   /* the text's permissive criterion: the cell
                                       pressure steady to pressure_tolerance
                                       (relative) over pressure_window checks */
} TlNhlEquilibrium;

/* Settings of the NHL path.  Defaults (tl_nhl_cell_settings_default): the
 * paper's I = 1e-4, ε_R = 1e-3. */
typedef struct {
  double inertial;           /* I of Eq. 18 (1e-4) */
  double tolerance;          /* ε_R of Eq. 19 (1e-3) */
  long max_relax_steps;      /* cap on DEM steps of relaxation after τ (1e6) */
  long check_every;          /* DEM steps between equilibrium checks (20) */
  long min_drive_steps;      /* floor of τ in DEM steps (spec §12.12: an isotropic
                                or vanishing increment gives γ = 0) (20) */
  TlNhlEquilibrium criterion;
  double pressure_tolerance; /* permissive criterion: relative pressure change (1e-4) */
  long pressure_window;      /* ... over this many checks (10, at most 64) */
} TlNhlCellSettings;

void tl_nhl_cell_settings_default(TlNhlCellSettings *s);
/* Checks the ranges; the error names the value and its limit. */
TlStatus tl_nhl_cell_settings_check(const TlNhlCellSettings *s);

/* What one evaluation (or one drive, probe or relaxation) did. */
typedef struct {
  long dem_steps;       /* drive + relaxation */
  long drive_steps, relax_steps;
  double tau;           /* s, drive duration (Eq. 18, after the floor) */
  double gamma;         /* γ_eff of the increment (Eq. 17, spec §12.12) */
  double h_error;       /* max |h - F^f h_R| / max |F^f h_R| at the end of the constant-ḣ
                           drive, before h is set to F^f h_R exactly */
  double imbalance;     /* final max_n Δ_n (Eq. 19) */
  double kinetic_ratio; /* |σ_kinetic| / |σ_contact| (Frobenius) at the end */
  double pressure;      /* -tr σ / dim at the end, Pa */
  size_t contacts;      /* touching contacts at the end */
  double seconds;       /* wall time */
  int converged;        /* the criterion was met before the cap */
} TlNhlCellStats;

/* A world in its reference state, as a builder returns it: configured and
 * set up (tl_dem_setup), on a deformable periodic cell domain
 * (tl_domain_init_cell).  `law` is the world's particle-particle law
 * (borrowed: the world owns it), through which a probe suspends sliding
 * (friction μ = ∞); `dim` is 3 for spheres, 2 for disks. */
typedef struct {
  TlDem *dem;
  TlContactLaw *law;
  int dim;
} TlNhlWorld;

/* Builds a world: every cell of a material comes from the same builder, so
 * the cells have identical configuration (laws, species) and a saved state
 * of one loads into another. */
typedef TlStatus (*TlNhlBuildFn)(void *ctx, TlNhlWorld *world);

/* ---- packings the library builds ----
 * Linear contacts with Coulomb friction (the paper's law; F1: k_t/k_n = 1,
 * μ = 0.5), damping by restitution.  Kinds:
 *   "fcc"    3-D face-centred cubic lattice of touching spheres, n_side^3
 *            cubic cells of 4 (a Bravais lattice: the motion stays affine),
 *            pre-compressed isotropically to `pressure` by shrinking the
 *            lattice (no relaxation needed);
 *   "random" n spheres (dim 3) or disks (dim 2, needs the 2-D DEM mode)
 *            with radii uniform in [radius_min, radius_max], placed as a
 *            gas and compressed isotropically to `pressure`, then relaxed
 *            to Eq. 19 (the preparation of seeds/004 §2.4).
 * Stiffness: k_n = kappa σ0 (2-D, per unit thickness: κ = k_n/σ0, F1's 500)
 * or kappa σ0 <d> (3-D: κ = k_n/(σ0 <d>), spec §12.10), σ0 = pressure. */
typedef struct {
  const char *kind;     /* "fcc" | "random" */
  int dim;              /* 3 | 2 */
  long n_side;          /* fcc: cubic cells per side */
  long n;               /* random: particles */
  double radius_min, radius_max; /* m */
  double density;       /* kg/m^3 */
  double pressure;      /* σ0, Pa */
  double kappa;         /* stiffness level κ (500) */
  double kt_over_kn;    /* k_t / k_n (1) */
  double mu;            /* Coulomb friction (0.5) */
  double restitution;   /* normal restitution, sets the damping ratio (0.1) */
  double dt_fraction;   /* time step / critical time step (0.2) */
  double skin;          /* Verlet skin / mean diameter (0.1) */
  long seed;            /* random: gas placement */
} TlNhlPacking;

void tl_nhl_packing_default(TlNhlPacking *p);
/* Creates the reference cell of a packing (for "random" this runs the
 * compression; it takes seconds for a few hundred particles). */
TlStatus tl_nhl_cell_create_packing(const TlNhlPacking *p, const TlNhlCellSettings *s, TlNhlCell **cell);

/* ---- life cycle ---- */
/* A cell from a builder, in the builder's state, which becomes committed
 * (F = 1: that state is the macro reference).  The builder and ctx must
 * outlive the cell and its copies. */
TlStatus tl_nhl_cell_create(TlNhlBuildFn build, void *ctx, const TlNhlCellSettings *s, TlNhlCell **cell);
/* A new cell built like `model` whose committed state is a copy of model's
 * committed state (each Gauss point's cell starts as the prepared one). */
TlStatus tl_nhl_cell_create_copy(const TlNhlCell *model, TlNhlCell **cell);
void tl_nhl_cell_destroy(TlNhlCell **cell);
/* Makes the world as it stands the reference (h_R = h, F = 1) and the
 * committed state, dropping any trial: the end of a preparation. */
TlStatus tl_nhl_cell_rebase(TlNhlCell *cell);
/* Called with the builder's ctx when the last cell built by it goes (for a
 * ctx the cells own). */
void tl_nhl_cell_set_free_ctx(TlNhlCell *cell, void (*free_ctx)(void *ctx));

TlStatus tl_nhl_cell_set_settings(TlNhlCell *cell, const TlNhlCellSettings *s);
const TlNhlCellSettings *tl_nhl_cell_settings(const TlNhlCell *cell);
/* The world, as the last operation left it (after tl_nhl_cell_evaluate: the
 * trial state, forces current). */
TlDem *tl_nhl_cell_dem(TlNhlCell *cell);
TlContactLaw *tl_nhl_cell_law(TlNhlCell *cell);
int tl_nhl_cell_dim(const TlNhlCell *cell);
size_t tl_nhl_cell_n_particles(const TlNhlCell *cell);
TlMat3 tl_nhl_cell_reference_h(const TlNhlCell *cell);
/* F = h h_R⁻¹ of the world as it stands. */
TlMat3 tl_nhl_cell_current_F(const TlNhlCell *cell);
/* F and σ (contact part of Eq. 27) of the committed state. */
TlMat3 tl_nhl_cell_committed_F(const TlNhlCell *cell);
TlMat3 tl_nhl_cell_committed_stress(const TlNhlCell *cell);
/* Mean particle diameter <d> and grain density ρ of Eq. 18. */
double tl_nhl_cell_mean_diameter(const TlNhlCell *cell);
double tl_nhl_cell_grain_density(const TlNhlCell *cell);

/* ---- the law ---- */
/* The NHL evaluation: restores the committed state, drives to F_f over τ
 * (Eq. 18 with P^i of the committed stress), relaxes (Eq. 19 or the
 * permissive criterion, up to the cap), returns σ (contact part of Eq. 27,
 * tension positive) and keeps the end state as TRIAL.  A cap reached is not
 * an error: stats->converged says it.  stats may be NULL. */
TlStatus tl_nhl_cell_evaluate(TlNhlCell *cell, TlMat3 F_f, TlMat3 *sigma, TlNhlCellStats *stats);
/* The same path from the committed state without keeping it as trial, and
 * the world restored to the trial state afterwards (what a CTO perturbation
 * needs: the cell is left as the evaluation left it). */
TlStatus tl_nhl_cell_evaluate_aside(TlNhlCell *cell, TlMat3 F_f, TlMat3 *sigma, TlNhlCellStats *stats);
/* A DEMQO probe (Eq. 32, spec §7): from the world as it stands (the trial
 * state), sliding suppressed (μ = ∞, tangential histories kept), a new short
 * step to F_f with τ from Eq. 18 for the increment's own γ, relaxed to the
 * same tolerance; returns σ and restores the world to the trial state. */
TlStatus tl_nhl_cell_probe(TlNhlCell *cell, TlMat3 F_f, TlMat3 *sigma, TlNhlCellStats *stats);
/* The re-evaluation an operator asks of a cell (a TlNhlEvalFn, ctx the
 * cell): TL_NHL_EVAL_PROBE a probe, TL_NHL_EVAL_PATH the path aside from the
 * committed state; its statistics in es (may be NULL). */
TlStatus tl_nhl_cell_reevaluate(void *cell, TlNhlEvalMode mode, TlMat3 F_f, TlMat3 *sigma, TlNhlEvalStats *es);

/* ---- the pieces (from the world as it stands; for drivers and tests) ---- */
/* Drives to F_f at constant ḣ over τ (Eq. 18; gamma > 0 overrides γ_eff),
 * then sets h = F_f h_R exactly and ḣ = 0. */
TlStatus tl_nhl_cell_drive(TlNhlCell *cell, TlMat3 F_f, TlNhlCellStats *stats);
/* Steps with F held until the criterion holds or the cap. */
TlStatus tl_nhl_cell_relax(TlNhlCell *cell, TlNhlCellStats *stats);
/* Contact (Eq. 27) and kinetic stress of the world as it stands. */
TlStatus tl_nhl_cell_stress(TlNhlCell *cell, TlMat3 *contact, TlMat3 *kinetic);
/* τ of Eq. 18 for the increment from the committed state to F_f (s), and
 * its γ_eff. */
TlStatus tl_nhl_cell_duration(const TlNhlCell *cell, TlMat3 F_i, TlMat3 sigma_i, TlMat3 F_f, double *tau,
                              double *gamma);

/* ---- committed and trial states ---- */
/* committed <- trial when an evaluation happened since the last commit or
 * rollback (otherwise nothing changes); the trial is then spent. */
TlStatus tl_nhl_cell_commit(TlNhlCell *cell);
/* Drops the trial state and restores the world to the committed one. */
TlStatus tl_nhl_cell_rollback(TlNhlCell *cell);
/* Whether a trial state is pending. */
int tl_nhl_cell_has_trial(const TlNhlCell *cell);
/* The world <- the committed state (bit for bit). */
TlStatus tl_nhl_cell_restore_committed(TlNhlCell *cell);
/* The committed state of the cell in a checkpoint file under `group` (the
 * world's state by tl_dem_checkpoint_ops plus F and σ); load restores it
 * into a cell built the same way and drops any trial. */
TlStatus tl_nhl_cell_save(TlNhlCell *cell, TlCheckpointWriter *w, const char *group);
TlStatus tl_nhl_cell_load(TlNhlCell *cell, TlCheckpointReader *r, const char *group);

/* ---- conversions used by the material (spec §6) ---- */
/* S = J F⁻¹ σ F⁻ᵀ. */
TlMat3 tl_nhl_cauchy_to_pk2(TlMat3 F, TlMat3 sigma);
TlMat3 tl_nhl_pk2_to_cauchy(TlMat3 F, TlMat3 S);

#endif
