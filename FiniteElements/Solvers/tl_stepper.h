/* Time steppers for a TlMechSystem (M a + f_int(u, v) = f_ext(t, u)),
 * as ops types found by name:
 *
 *  "newmark"            implicit Newmark-beta (any beta, gamma; default the
 *                       average-acceleration rule 1/4, 1/2), Newton through
 *                       KINSOL or SUNNonlinSol_Newton at each step,
 *                       consistent mass when the system has one;
 *  "central_difference" explicit, lumped mass, one force evaluation per step;
 *                       a step above the critical one 2/omega_max is refused
 *                       (both numbers in the message) unless allow_unstable;
 *                       a run that blows up stops with TL_ERR_UNSTABLE;
 *  "quasi_static"       f_int(u) = lambda(t) f_ext(t, u) by Newton with load
 *                       stepping: lambda = min(t / ramp_time, 1) (1 when
 *                       ramp_time = 0), a failed step is halved up to
 *                       max_cuts times.  Two convergence tests: the
 *                       residual's max norm against rtol x force scale
 *                       (default, KINSOL or SUNNonlinSol), or the force
 *                       ratio of seeds/004 §2.5.3 (convergence =
 *                       TL_CONVERGENCE_FORCE_RATIO, plain Newton with the
 *                       material's operator as the Jacobian):
 *                         |F| / |R| <= ratio_tol (ratio_tol_post after the peak),
 *                       |F| = 2-norm of the residual over the free dofs,
 *                       |R| = 2-norm of the forces that balance the
 *                       internal ones: the reactions at the Dirichlet dofs
 *                       and the applied loads lambda f_ext at the free dofs
 *                       (the paper's "reactions"; with displacement control
 *                       alone exactly them).  Clamped dofs (tl_solid_fix)
 *                       are not in the system and carry no reaction here:
 *                       prescribe supports as zero displacements to count
 *                       them.  After accept_loose_after iterations an
 *                       iterate within ratio_tol_post is accepted before the
 *                       peak too ("convergence stops progressing after a
 *                       few iterations").  The peak: set by
 *                       tl_stepper_set_post_peak, or detected when |R| of
 *                       an accepted increment falls below (1 - peak_drop)
 *                       times its largest value so far (peak_drop >= 0).
 *                       An increment whose ratio grows ratio_diverge times
 *                       above its best is given up and halved.
 *
 * Life cycle: tl_stepper_create(type, sys, options) -> set_state(t, u, v)
 * (computes a consistent initial acceleration) -> step(dt) ... -> destroy.
 * A failed step leaves the state and the material state at the last
 * accepted step (rollback) and returns the error with Newton's residual
 * history.  Energies: kinetic 1/2 v.M v, strain from the system, external
 * work integrated by the trapezoidal rule over the accepted steps
 * (prescribed-displacement reactions excluded). */
#ifndef TL_STEPPER_H
#define TL_STEPPER_H

#include <stddef.h>

#include "tl_checkpoint.h"
#include "tl_error.h"
#include "tl_mech_system.h"
#include "tl_newton.h"
#include "tl_object.h"
#include "tl_registry.h"

/* The numeric fields below are described, with their defaults, ranges and
 * units, by the parameter tables of the stepper types that read them
 * (TlStepperOps.params, listed by the catalogue): tl_stepper_options_default
 * builds the defaults from those tables, and tl_stepper_create refuses a
 * field outside its type's ranges, so the documentation and the behaviour
 * are one.  The values in brackets are those defaults. */
typedef struct {
  const char *solver;  /* "cholmod", "klu", "umfpack"; NULL: cholmod if symmetric, else klu */
  double beta, gamma;  /* Newmark [0.25, 0.5] */
  double rtol;         /* Newton: ||R||_inf <= max(atol, rtol * force scale) [1e-10] */
  double atol;         /* [1e-14] */
  long max_iterations; /* Newton [30] */
  long reuse;          /* Newton: refactorise every `reuse` iterations (1 = full Newton) [1] */
  int keep_factors;    /* keep the factors across steps (modified Newton) [0] */
  int line_search;     /* KINSOL line search [0] */
  int nonlinear_solver; /* implicit: Newton through KINSOL (test on the residual) or through
                         * SUNNonlinSol_Newton (CVODE's test on the correction, which spares
                         * the residual at the accepted iterate): TL_NEWTON_KINSOL or
                         * TL_NEWTON_SUNNONLINSOL (tl_newton.h) [KINSOL] */
  int lumped;          /* implicit: use the lumped mass even if a consistent one exists [0] */
  int predictor;       /* Newmark's Newton start, TL_PREDICTOR_* [AUTO]; quasi-static: TAYLOR
                        * starts Newton from the last increment extrapolated (u + h du/h_prev
                        * at the free dofs), AUTO and LAST from the last equilibrium */
  int allow_unstable;  /* explicit: run above the critical step (for tests) [0] */
  double blowup;       /* explicit: kinetic energy beyond blowup x energy budget = unstable [1e6] */
  int critical_bound;  /* explicit: take omega_max^2 from the system's (conservative) bound
                        * instead of Lanczos on M^-1 K (sharp, from below) [0] */
  double ramp_time;    /* quasi-static load ramp [0] */
  int max_cuts;        /* quasi-static step halvings [10] */
  int convergence;     /* quasi-static test, TL_CONVERGENCE_* [RESIDUAL] */
  double ratio_tol;    /* FORCE_RATIO: |F|/|R| before the peak [1e-3] */
  double ratio_tol_post; /* FORCE_RATIO: after the peak [1e-2] */
  long accept_loose_after; /* FORCE_RATIO: accept at ratio_tol_post after this many
                            * iterations even before the peak (0: never) [0] */
  double peak_drop;    /* FORCE_RATIO: relative drop of |R| that marks the peak
                        * (negative: only tl_stepper_set_post_peak) [-1] */
  double ratio_diverge; /* FORCE_RATIO: give the increment up (halve it) once |F|/|R|
                         * exceeds this factor times its smallest value in the
                         * increment, from the second iteration on: a diverging
                         * iterate would drive the law (a DEM cell) far off its
                         * path (0: never) [10] */
} TlStepperOptions;

/* Quasi-static convergence tests (see "quasi_static" above). */
enum { TL_CONVERGENCE_RESIDUAL = 0, TL_CONVERGENCE_FORCE_RATIO = 1 };

/* What the last tl_stepper_step did (quasi-static only). */
typedef struct {
  long increments;        /* accepted increments (1 unless halved) */
  long cuts;              /* halvings */
  long iterations;        /* Newton iterations of the accepted increments */
  long failed_iterations; /* Newton iterations of the rejected attempts */
  long loose;             /* increments accepted at ratio_tol_post */
  double ratio;           /* FORCE_RATIO: |F|/|R| of the last accepted iterate */
  double reaction;        /* FORCE_RATIO: |R| there */
  double force;           /* FORCE_RATIO: |F| there */
  int post_peak;          /* the loose tolerance applied at the end of the step */
} TlStepInfo;

/* Newmark predictors: the last displacement u_n (safe when the step leaves
 * element modes unresolved, omega dt >> 1: their undamped parts in v_n, a_n
 * would be amplified onto distorted states), the Taylor one
 * u_n + dt v_n + dt^2/2 a_n (second order: one Newton iteration usually
 * suffices when every mode is resolved), or AUTO: Taylor when the system's
 * bound on omega_max (taken at the initial state) gives omega_max dt <= 1,
 * else the last displacement. */
enum { TL_PREDICTOR_AUTO = 0, TL_PREDICTOR_LAST = 1, TL_PREDICTOR_TAYLOR = 2 };

typedef struct {
  double kinetic, strain, external_work, total; /* total = kinetic + strain - external_work */
} TlEnergies;

typedef struct {
  long steps, rejected, newton_iterations, factorisations, linear_solves;
  long residual_evaluations; /* Newmark: residuals evaluated (internal forces), reuses not counted */
  double t_step, t_factor, t_solve, t_residual, t_jacobian; /* seconds */
} TlStepperStats;

typedef struct TlStepper TlStepper;

typedef struct {
  TlOpsHeader header; /* kind "stepper" */
  int implicit;
  int consistent_mass; /* integrates with the system's consistent mass when it has one (unless
                        * options.lumped): tl_stepper_implicit_setup assembles it */
  TlStatus (*setup)(TlStepper *st);               /* allocate, analyse */
  TlStatus (*initialise)(TlStepper *st);          /* a at t from u, v */
  TlStatus (*step)(TlStepper *st, double dt);     /* t -> t + dt */
  void (*destroy)(TlStepper *st);
  /* The TlStepperOptions fields the type reads: TlParam.offset is the
   * field's offset in TlStepperOptions (int, long or double fields; the
   * table stores doubles).  Registered with the type. */
  const TlParam *params;
  int n_params;
} TlStepperOps;

/* Entries of the implicit steppers' tables for the Newton settings they
 * share (read by tl_stepper.c): one definition for both tables. */
#define TL_STEPPER_NEWTON_PARAMS                                                                                     \
  {"rtol", 1e-10, 0, 1e300, "1", "Newton: converged when ||R||_inf <= max(atol, rtol x force scale); > 0",          \
   offsetof(TlStepperOptions, rtol)},                                                                                \
  {"atol", 1e-14, 0, 1e300, "N", "Newton: absolute floor of that test (residual force)",                           \
   offsetof(TlStepperOptions, atol)},                                                                                \
  {"max_iterations", 30, 1, 1e9, "1", "Newton iterations allowed per step (integer)",                              \
   offsetof(TlStepperOptions, max_iterations)},                                                                      \
  {"reuse", 1, 1, 1e9, "1", "refactorise the Jacobian every `reuse` Newton iterations; 1: full Newton (integer)",  \
   offsetof(TlStepperOptions, reuse)},                                                                               \
  {"keep_factors", 0, 0, 1, "1", "1: keep the factors across steps (modified Newton); 0: refactorise each step",   \
   offsetof(TlStepperOptions, keep_factors)},                                                                        \
  {"line_search", 0, 0, 1, "1", "1: KINSOL's line search (nonlinear_solver 0 only)",                              \
   offsetof(TlStepperOptions, line_search)},                                                                         \
  {"nonlinear_solver", 0, 0, 1, "1",                                                                               \
   "0: Newton through KINSOL (test on the residual); 1: SUNNonlinSol_Newton (test on the correction, sparing the "   \
   "residual at the accepted iterate)",                                                                             \
   offsetof(TlStepperOptions, nonlinear_solver)}

struct TlStepper {
  const TlStepperOps *ops;
  TlMechSystem *sys;
  TlStepperOptions opt;
  TlSparseIndex n;
  double t;
  double *u, *v, *a;             /* state at t */
  double *u0, *v0, *a0;          /* state at the start of the step (rollback) */
  double *m;                     /* lumped mass */
  double *f_ext, *f_ext0, *f_int, *work;
  TlSparse *M;                   /* consistent mass, NULL when lumped */
  TlSparse *M_apply;             /* M without its structural zeros, for products */
  TlSparse *J;                   /* Jacobian (implicit) */
  TlNewton *newton;              /* implicit */
  double W_ext;
  double dt_crit;                /* explicit: 2 / omega_max at the initial state */
  double energy_budget;          /* explicit blow-up test */
  /* Current implicit step: */
  double t_new, dt, lambda;
  double force_scale;
  double force_floor; /* round-off level of the residual (inertia terms) */
  double u_scale;     /* displacement size for Newton's step test */
  double omega2_bound; /* implicit, predictor AUTO: the system's bound on omega_max^2 at the initial state (0: none) */
  TlStepperStats stats;
  TlStepInfo last_step;
  int post_peak;       /* quasi-static FORCE_RATIO: past the peak */
  double reaction_max; /* the largest |R| of an accepted increment */
  void *impl;
};

/* The defaults: every field at the default of the parameter tables of
 * the registered steppers (solver NULL). */
void tl_stepper_options_default(TlStepperOptions *o);
/* Sets the field `name` of `o` as stepper type `type` reads it: a name
 * that is not in the type's table is refused with the table's names, a
 * value outside the range or a fraction for an integer field with the
 * value and the limit. */
TlStatus tl_stepper_options_set(TlStepperOptions *o, const char *type, const char *name, double value);
/* The field `name` of `o` as a double (any stepper's table; NOT_FOUND
 * otherwise). */
TlStatus tl_stepper_options_get(const TlStepperOptions *o, const char *name, double *value);
/* Registers the three steppers (kind "stepper"). */
TlStatus tl_stepper_register_all(void);
TlStatus tl_stepper_create(const char *type, TlMechSystem *sys, const TlStepperOptions *options,
                           TlStepper **st);
/* Sets t, u, v (NULL = zero); Dirichlet values are applied; computes a. */
TlStatus tl_stepper_set_state(TlStepper *st, double t, const double *u, const double *v);
TlStatus tl_stepper_step(TlStepper *st, double dt);
TlStatus tl_stepper_energies(TlStepper *st, TlEnergies *e);
/* Explicit: the critical step 2 / omega_max, omega_max^2 from Lanczos
 * iteration on M^-1 K at the current state (the largest Ritz value converges
 * from below: sharp), or from the system's own upper bound when
 * critical_bound is set (conservative, cheaper on big meshes). */
TlStatus tl_stepper_critical_dt(TlStepper *st, double *dt_crit);
void tl_stepper_get_stats(const TlStepper *st, TlStepperStats *stats);
/* Quasi-static FORCE_RATIO: from now on (on != 0) the loose tolerance
 * ratio_tol_post applies. */
void tl_stepper_set_post_peak(TlStepper *st, int on);
void tl_stepper_destroy(TlStepper **st);

/* Checkpoint section of a stepper (tl_checkpoint.h; object: the TlStepper):
 * t, u, v, a, the last external force, the external work, the last step
 * size, the step counters, the explicit stepper's critical step and energy
 * budget, and kept Newton factors (the Jacobian values they were computed
 * from; refactorised on load, which gives the same factors).  The system's
 * own state (sys->ops->checkpoint: committed material state) goes under
 * <group>/system.  Restart: build the same scene and stepper (no
 * set_state), load, and step on: the run continues bit for bit.  The
 * step counters carry over; Newton iteration, factorisation and timing
 * counters count the restarted process only.  A material whose state lives
 * outside the solid's per-point arrays (material commit/rollback callbacks)
 * must checkpoint that state itself. */
extern const TlCheckpointOps tl_stepper_checkpoint_ops;

extern const TlStepperOps tl_stepper_newmark_ops;
extern const TlStepperOps tl_stepper_central_difference_ops;
extern const TlStepperOps tl_stepper_quasi_static_ops;

/* Shared by the implementations. */
TlStatus tl_stepper_implicit_setup(TlStepper *st, TlNewtonResidual residual,
                                   TlNewtonJacobian jacobian);
TlStatus tl_stepper_newton_solve(TlStepper *st, double *x);
TlStatus tl_stepper_max_omega2(TlStepper *st, double *omega2);
void tl_stepper_mass_times(const TlStepper *st, const double *x, double *y);
/* Saves the state at the start of a step (u, v, a, f_ext into u0, v0, a0,
 * f_ext0), which tl_stepper_reject restores. */
void tl_stepper_save_start(TlStepper *st);
/* max |x_i| of a dof vector. */
double tl_stepper_max_abs(const double *x, TlSparseIndex n);
/* Restores the state saved at the start of the step (u0, v0, a0, f_ext0),
 * rolls the material state back and appends what failed to the message. */
TlStatus tl_stepper_reject(TlStepper *st, TlStatus s, const char *what, double dt);

#endif
