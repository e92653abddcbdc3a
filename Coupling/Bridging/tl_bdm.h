/* The bridging domain method (seeds/000 §2): a finite-element block and a
 * DEM world overlapping in one or more bridging zones, their energies
 * blended by a weight alpha (Eq. 1) and their velocities tied by Lagrange
 * multipliers after each explicit step (Eqs. 5-14, with the plus sign of
 * the constraint matrix that makes the constraint rate vanish; see
 * ../shared/specs/bridging-domain.md §3 E4-E9 for the notation).
 *
 * Weighting (Eq. 1).  alpha(X) = 1 on the FE side of a zone, 0 on its DEM
 * side, a linear or half-cosine ramp across it.  The weighted masses take
 * alpha clamped inside the closed zone to [alpha_min, 1 - alpha_min]
 * because the correction divides by them; the forces take the continuous
 * profile (a clamped contact weight would jump by alpha_min where a
 * contact point crosses a zone's end: a kick to the light particles
 * there, measured to ruin the weak coupling at rest).  The coupling sets,
 * at creation (before tl_solid_setup):
 *   - the FE internal forces weighted by alpha at the block's stiffness
 *     points (tl_solid_set_point_weights);
 *   - the FE masses: nodal, Mbar_I = alpha(X_I) M_I as the paper prints
 *     (tl_solid_set_lumped_mass_weights; the mass points unweighted), or
 *     weighted at the mass points (TL_BDM_MASS_QUADRATURE);
 *   - the DEM equations weighted by 1 - alpha (tl_dem_set_weight_field):
 *     the particle masses by 1 - alpha(X_i) of the reference centre (by
 *     particle id, constant), the contact forces by 1 - alpha at the
 *     current contact point.
 *
 * Constraint.  N_Ii = phi_I(X_i), shape functions at the reference
 * centres (particles wrapped into the mesh's periodic section first),
 * built once through the mesh locator.  Everything is done in the
 * solid's dof numbering, one scalar constraint per particle and component,
 * so dofs tied by a periodic condition are one unknown.  Dofs whose
 * velocity is prescribed (Dirichlet) enter the rate but are not corrected
 * (infinite mass); clamped components are absent.  Only free particles
 * are coupled (fixed or prescribed ones in a zone are left out and
 * counted).
 *   strong (Eqs. 7-10):  gdot = N^T udot* - ddot*,
 *     A = N^T Mbar^-1 N + mbar^-1, lambda = A^-1 gdot,
 *     udot = udot* - Mbar^-1 N lambda,  ddot = ddot* + mbar^-1 lambda.
 *     Lumped A (default row sum, or its diagonal) with optional Jacobi
 *     sweeps, or consistent A through Woodbury:
 *     lambda = mbar gdot - mbar N^T y,  (Mbar + N mbar N^T) y = N mbar gdot,
 *     a node-sized SPD system, constant in time, factorised once (CHOLMOD).
 *   weak (Eqs. 11-14): gdot^W = N gdot on the dofs reached by particles,
 *     A^W = N A N^T (never lumped), factorised once (CHOLMOD),
 *     udot = udot* - Mbar^-1 N N^T lambda^W, ddot = ddot* + mbar^-1 N^T lambda^W.
 * Weighted momentum sum Mbar udot + sum mbar ddot is unchanged by any
 * lambda (partition of unity) where the particles' elements have no
 * constrained node; with the consistent A the correction removes kinetic
 * energy 1/2 lambda^T A lambda >= 0.
 *
 * Ghost forces (§4.2).  At setup the initial internal nodal forces of the
 * FE (tl_solid_block_forces at the current displacements) and/or the
 * initial weighted forces of the particles the weighting reaches (centre
 * within the largest radius of a zone: a particle just outside a zone has
 * weighted contacts inside it) are recorded and
 * subtracted for the whole run: the FE through a solid wrapper adding the
 * recorded force as an external load (the stepper counts its work), the
 * particles through P->f_coupling.
 *
 * The coupled step is a driver-level loop, the positions never corrected:
 *   tl_dem_step(dem, 1);            particles -> ddot*
 *   tl_stepper_step(st, dt);        FE (explicit central difference) -> udot*
 *   tl_bdm_correct(bdm, &report);   writes P->v and st->v
 * Both models use the same dt (the paper's single step). */
#ifndef TL_BDM_H
#define TL_BDM_H

#include <stddef.h>

#include "tl_checkpoint.h"
#include "tl_dem.h"
#include "tl_error.h"
#include "tl_options.h"
#include "tl_solid.h"
#include "tl_stepper.h"

typedef enum { TL_BDM_STRONG = 0, TL_BDM_WEAK } TlBdmConstraint;
/* Strong constraint only (weak: A^W is always consistent, paper §2.2). */
typedef enum { TL_BDM_LUMP_ROWSUM = 0, TL_BDM_LUMP_DIAG, TL_BDM_LUMP_NONE } TlBdmLumping;
typedef enum { TL_BDM_ALPHA_LINEAR = 0, TL_BDM_ALPHA_COSINE } TlBdmProfile;
typedef enum { TL_BDM_GHOST_NONE = 0, TL_BDM_GHOST_FE, TL_BDM_GHOST_DEM, TL_BDM_GHOST_BOTH } TlBdmGhost;
typedef enum { TL_BDM_MASS_NODAL = 0, TL_BDM_MASS_QUADRATURE } TlBdmMassWeight;

/* A bridging zone along `axis`: alpha = 0 at coordinate s_dem (the FE end
 * face, inside the DEM), 1 at s_fe (the DEM's free surface, inside the
 * FE); s_dem < s_fe or s_dem > s_fe.  Beyond s_fe alpha = 1, before s_dem
 * alpha = 0 (pure DEM).  Several zones (one per FE bar) must not overlap;
 * alpha at a point is the largest of the zones' values. */
typedef struct {
  int axis;
  double s_dem, s_fe;
} TlBdmZone;

typedef struct {
  TlBdmConstraint constraint; /* -bdm strong|weak [strong] */
  TlBdmLumping lumping;       /* -bdm_lumped rowsum|diag|none [rowsum] */
  int jacobi;                 /* -bdm_jacobi: Jacobi sweeps on a lumped A towards the consistent lambda [0] */
  TlBdmProfile profile;       /* -bdm_alpha linear|cosine [linear] */
  double alpha_min;           /* -bdm_alpha_min, in [0, 0.5) but > 0 for the coupled masses [1e-3] */
  TlBdmGhost ghost;           /* -ghost_force none|fe|dem|both [both]: the paper's text names
                                 the FE nodes only; with both models' forces weighted, the FE's
                                 initial unbalance and the particles' cancel over the overlap,
                                 and subtracting one alone leaves the other unopposed (measured
                                 on the 6 d0 gouge at rest after 5000 steps: section noise
                                 5.4e-6 m with fe, 1.7e-7 m with none, 3.4e-17 m with both) */
  TlBdmMassWeight mass_weight; /* -bdm_mass_weight nodal|quadrature [nodal] */
  double locate_tol;          /* tolerance of the mesh locator, reference coordinates [1e-9] */
} TlBdmOptions;

void tl_bdm_options_default(TlBdmOptions *o);
/* Refuses values out of range, naming the value and the limit. */
TlStatus tl_bdm_options_check(const TlBdmOptions *o);
/* Reads the options above from the database (defaults from *o, so a driver
 * may change them first), with -help text; checks them. */
TlStatus tl_bdm_options_from_db(TlOptions *db, TlBdmOptions *o);
/* Names of the choices, for summaries ("strong", "rowsum", ...). */
const char *tl_bdm_constraint_name(TlBdmConstraint c);
const char *tl_bdm_lumping_name(TlBdmLumping l);
const char *tl_bdm_ghost_name(TlBdmGhost g);

/* alpha at point x for the zones: the clamp to [alpha_min, 1 - alpha_min]
 * applies inside a closed zone (alpha_min = 0: the continuous profile). */
double tl_bdm_alpha(const TlBdmZone *zones, int n_zones, TlBdmProfile profile, double alpha_min, const double x[3]);

/* Per-step report of tl_bdm_correct. */
typedef struct {
  long step;                 /* corrections applied so far */
  double rate_before;        /* max |gdot*_i| over coupled particle components (m/s) */
  double rate_after;         /* max |gdot_i| after the correction (strong constraint, m/s) */
  double rate_weak_after;    /* max |(N gdot)_I| after (the weak constraint, m/s; 0 for strong) */
  double velocity_scale;     /* max |velocity| of the coupled particles and dofs before (m/s) */
  double residual_max;       /* max |g_i| = |N^T u - d_i| (m), positions at the step's end */
  double residual_rms;
  double momentum[3];        /* weighted momentum after: all free FE dofs + all free particles (kg m/s) */
  double momentum_change[3]; /* its change by this correction */
  double energy_removed;     /* kinetic energy removed by this correction (J; >= 0 with consistent A) */
  double energy_removed_total; /* cumulative over the run (J) */
} TlBdmReport;

typedef struct TlBdm TlBdm;

/* Coupling of block `block` of `solid` (created, NOT set up) and the
 * particles of `dem` (the reference positions X_i are the particles'
 * positions now, kept by id).  Sets the weights of both models (see
 * above), so call it before tl_solid_setup; the DEM may be set up or not.
 * Refuses an empty zone list, a bad axis, an empty zone, overlapping
 * zones, options out of range, and a zone the mesh block does not reach.
 * solid and dem are borrowed and must outlive the coupling. */
TlStatus tl_bdm_create(TlSolid *solid, int block, TlDem *dem, const TlBdmZone *zones, int n_zones,
                       const TlBdmOptions *opt, TlBdm **bdm);
/* After tl_solid_setup, the stepper's creation and tl_stepper_set_state,
 * and tl_dem_setup: builds N (locates every free particle whose reference
 * centre lies in a zone; one that lies outside the mesh is refused with its
 * id and position), the weighted masses from the stepper's lumped mass,
 * the factorisations, records and installs the ghost-force correction
 * (then sets the coupled particles' current forces and the stepper's
 * accelerations as they are with it; the DEM forces are evaluated once
 * more only when they were not evaluated with the coupling's weights,
 * i.e. when tl_dem_setup came before tl_bdm_create).  st is borrowed (an
 * explicit stepper: its lumped mass is used). */
TlStatus tl_bdm_setup(TlBdm *bdm, TlStepper *st);
/* The velocity correction after both models stepped; rep may be NULL.
 * With rep NULL the rates after the correction, the residual and the total
 * momentum (three passes over N and one over every dof and particle) are
 * left to tl_bdm_last_report, which computes them from the current state:
 * call it before the next step to get those of this correction. */
TlStatus tl_bdm_correct(TlBdm *bdm, TlBdmReport *rep);
/* The report of the last correction (zeros before the first). */
void tl_bdm_last_report(TlBdm *bdm, TlBdmReport *rep);
void tl_bdm_destroy(TlBdm **bdm);

/* Sizes: coupled particles, constrained particle components (3 per
 * particle), FE dofs the particles reach, and the free particles of the
 * zones left out (not free). */
typedef struct {
  size_t n_particles, n_constraints, n_dofs, n_rows_weak, n_excluded;
  size_t n_ghost_particles; /* particles whose initial forces are subtracted (dem|both) */
  size_t n_nonzeros; /* entries of N */
  double t_setup;    /* seconds spent in tl_bdm_setup (factorisation included) */
  double t_correct;  /* cumulative seconds in tl_bdm_correct */
} TlBdmInfo;
void tl_bdm_info(const TlBdm *bdm, TlBdmInfo *info);

/* alpha at every mesh node (n_nodes), at setup. */
const double *tl_bdm_node_alpha(const TlBdm *bdm);
/* The recorded ghost forces: FE node-space (3 per mesh node, NULL unless
 * fe/both) and per ghost-force particle (3 each, NULL unless dem/both; the
 * free particles a weighted contact reaches: reference centre within the
 * largest radius of a zone, n_ghost_particles of tl_bdm_info). */
const double *tl_bdm_ghost_fe(const TlBdm *bdm);
const double *tl_bdm_ghost_dem(const TlBdm *bdm);

/* Checkpoint section (object: the TlBdm): the reference positions by id
 * (checked against the ones of the rebuilt scene: a coupling built on
 * other positions is refused), the recorded ghost forces, the step count
 * and the energy removed so far.  Restart: build the same scene, call
 * tl_bdm_setup, then load the DEM, the stepper and this section. */
extern const TlCheckpointOps tl_bdm_checkpoint_ops;

#endif
