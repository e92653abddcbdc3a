/* The coupled DEM–FEM time loop of surface coupling (seeds/001 §5.3.1, Fig. 8).
 *
 * One macro step of size Dt = k dt (k DEM steps of dt per FEM step; k = 1
 * is the paper's lock-step):
 *   1. the solid advances t_n -> t_n + Dt under the coupling forces F (held
 *      constant over the step, entered through the system's step hook):
 *      the average of the nodal coupling forces over the previous k DEM
 *      steps (for k = 1: the forces of the last DEM force evaluation);
 *   2. the DEM world takes k steps; before the j-th, the walls are moved to
 *      u_n + (j/k)(u_{n+1} - u_n), with velocities interpolated likewise
 *      (linear in time between the FE states); after each, the coupling
 *      forces (Eq. 15 or 16) are accumulated into the next F.
 * One-way coupling keeps the solid rigid at its initial state (no FE step;
 * the particles see fixed walls).
 *
 * Energy bookkeeping (every call of tl_coupled_loop_energy): the DEM
 * world's kinetic, elastic (contacts, walls included) and gravitational
 * energies, the solid's kinetic and strain energies, the work the coupling
 * forces did on the solid (sum of F . (u_{n+1} - u_n), exact for a force
 * constant over the step) and the work the moving walls did on the particles
 * (from the walls' accounts).  With both sub-models undamped and no other
 * loads, total = DEM (kinetic + elastic + gravitational) + FE (kinetic +
 * strain) is conserved by the exact coupled problem; its drift is the
 * energy the coupling creates. */
#ifndef TL_COUPLED_LOOP_H
#define TL_COUPLED_LOOP_H

#include "tl_dem.h"
#include "tl_scoupling.h"
#include "tl_solid.h"
#include "tl_stepper.h"

typedef struct {
  int substeps; /* k DEM steps per FEM step [1] */
  int one_way;  /* rigid solid: the FE model is not advanced [0] */
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
 * there and takes the step hook of the solid's system. */
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
 * step, and the particle–wall force total they balance. */
const double *tl_coupled_loop_forces(const TlCoupledLoop *loop);
TlVec3 tl_coupled_loop_wall_force(const TlCoupledLoop *loop);

#endif
