/* The coupled DEM–FEM time loop of surface coupling (seeds/001 §5.3.1, Fig. 8).
 *
 * One macro step of size Dt = k dt (k DEM steps of dt per FEM step; k = 1
 * is the paper's lock-step):
 *   1. the DEM world takes k steps; before the j-th, the walls are moved to
 *      the solid's Taylor predictor u_n + s v_n + s^2/2 a_n (velocities
 *      v_n + s a_n), s = j dt, and after it the coupling forces (Eq. 15 or
 *      16) are taken: F = those of the last step, at t_{n+1} (default), or
 *      their average over the k steps (average_forces);
 *   2. the solid advances t_n -> t_n + Dt with F as the coupling load at
 *      t_{n+1} (the SCoupling elements carry it in the solid's residual:
 *      tl_scoupling.h), and the walls are moved to the state it reached.
 * F is accumulated per (face, face node) in the couplings; the loop keeps
 * it assembled node-wise for the work, energy and momentum diagnostics.
 * Why the last step's forces: Newmark's trapezoidal rule and central
 * difference both want the load at t_{n+1}; the average is the load near
 * t_{n+1/2}, and applying it at t_{n+1} lags the coupling by Dt/2, which
 * feeds energy in: S1 with k = 5 (c = 0, Newmark) reaches 31 J after 3 s
 * with averages and stays at its 0.87 J with the last forces; with k = 2
 * averaging still grows past 10x by t = 10 s.
 * For the explicit stepper with k = 1 the predictor is the position the
 * solid reaches, so F is the force at t_{n+1} exactly where central
 * difference needs it (no lag: a lag of one step feeds energy into the
 * coupled system).  For Newmark the predictor is second-order accurate.
 * That is the default scheme, TL_COUPLING_PREDICT.  TL_COUPLING_INTERPOLATE
 * is the serial staggered one: the solid advances first under the average
 * coupling force of the previous macro step (a lag of Dt), then the k DEM
 * steps see the walls interpolated linearly between u_n and u_{n+1} (their
 * velocity (u_{n+1} - u_n) / Dt), and their average force is applied in the
 * next FE step.  TL_COUPLING_PARALLEL reads Fig. 8 literally: both models
 * advance from the state at t_n, the solid under the coupling forces of t_n
 * and the DEM steps with the walls where the solid was at t_n.  Both
 * staggered schemes lag the load by one macro step; with k = 1 and the
 * Dirac coupling (c = 0) that lag feeds energy into S1 (README, S1).
 * TL_COUPLING_LAGGED_WALLS orders the solves as the published code does
 * (MercuryDPM's surface coupling, whose runs the paper reports): the DEM
 * steps first, with the walls following the solid one macro step behind
 * (interpolated from u_{n-1} to u_n, velocity (u_n - u_{n-1}) / Dt), then
 * the solid under the forces so found.  The load is not lagged, the walls
 * are; at c = 0 this reproduces the published runs' energy growth.
 * One-way coupling keeps the solid rigid at its initial state (no FE step;
 * the particles see fixed walls).
 *
 * Energy bookkeeping (every call of tl_coupled_loop_energy): the DEM
 * world's kinetic, elastic (contacts, walls included) and gravitational
 * energies, the solid's kinetic and strain energies, the work the coupling
 * forces did on the solid (trapezoidal rule over each step) and the work the moving walls did on the particles
 * (from the walls' accounts).  With both sub-models undamped and no other
 * loads, total = DEM (kinetic + elastic + gravitational) + FE (kinetic +
 * strain) is conserved by the exact coupled problem; its drift is the
 * energy the coupling creates. */
#ifndef TL_COUPLED_LOOP_H
#define TL_COUPLED_LOOP_H

#include "tl_checkpoint.h"
#include "tl_dem.h"
#include "tl_scoupling.h"
#include "tl_solid.h"
#include "tl_stepper.h"

enum { TL_COUPLING_PREDICT = 0, TL_COUPLING_INTERPOLATE = 1, TL_COUPLING_PARALLEL = 2, TL_COUPLING_LAGGED_WALLS = 3 };

typedef struct {
  int substeps; /* k DEM steps per FEM step [1] */
  int one_way;  /* rigid solid: the FE model is not advanced [0] */
  int scheme;   /* TL_COUPLING_PREDICT (walls on the solid's Taylor predictor, forces at t_{n+1}) or
                 * TL_COUPLING_INTERPOLATE (FE first with the last forces, walls interpolated) or
                 * TL_COUPLING_PARALLEL (FE with the last forces, DEM with the walls at t_n) or
                 * TL_COUPLING_LAGGED_WALLS (DEM first, walls one FE step behind, then FE) [PREDICT] */
  int average_forces; /* apply the average of the k DEM steps' forces instead of the last one's [0] */
} TlCoupledLoopOptions;

typedef struct {
  double dem_kinetic, dem_elastic, dem_gravitational;
  double fem_kinetic, fem_strain;
  double work_on_solid;     /* cumulative work of the coupling forces on the solid */
  double work_on_particles; /* cumulative work of the moving walls on the particles */
  double total;             /* DEM kinetic + elastic + gravitational + FE kinetic + strain */
} TlCoupledEnergy;

typedef struct TlCoupledLoop TlCoupledLoop;

void tl_coupled_loop_options_default(TlCoupledLoopOptions *o);
/* Couples a set-up DEM world (whose walls include those of the couplings)
 * and a solid driven by a stepper (its state set).  All are borrowed.
 * Sets the walls to the solid's current state, evaluates the DEM forces
 * there, puts their coupling forces on the SCoupling elements and sets the
 * stepper's state again so that its initial acceleration balances them.
 * Destroying the loop clears the couplings' forces. */
TlStatus tl_coupled_loop_create(TlDem *dem, TlSolid *solid, TlStepper *stepper, int n_couplings,
                                TlSCoupling *const *couplings, const TlCoupledLoopOptions *options,
                                TlCoupledLoop **loop);
void tl_coupled_loop_destroy(TlCoupledLoop **loop);
/* One macro step: FE step of k dt, k DEM steps of dt (dt: the world's). */
TlStatus tl_coupled_loop_step(TlCoupledLoop *loop);
TlStatus tl_coupled_loop_energy(TlCoupledLoop *loop, TlCoupledEnergy *e);
double tl_coupled_loop_time(const TlCoupledLoop *loop);
/* Node-space displacements and velocities of the solid (n_nodes x 3), current. */
const double *tl_coupled_loop_u_nodes(const TlCoupledLoop *loop);
const double *tl_coupled_loop_v_nodes(const TlCoupledLoop *loop);
/* Coupling forces on the solid's nodes (n_nodes x 3) applied in the last FE
 * step (the couplings' per-face forces assembled), and the particle–wall
 * force total they balance. */
const double *tl_coupled_loop_forces(const TlCoupledLoop *loop);
TlVec3 tl_coupled_loop_wall_force(const TlCoupledLoop *loop);

/* Checkpoint section of the loop (object: the TlCoupledLoop).  Add it after
 * the stepper's (tl_stepper_checkpoint_ops) and the world's
 * (tl_dem_checkpoint_ops) sections: loading restores the coupling forces
 * and moves the walls to the restored solid, so a run continues bit for bit. */
extern const TlCheckpointOps tl_coupled_loop_checkpoint_ops;

#endif
