/* Tangent operators of the numerically homogenised law (seeds/004 §2.5,
 * Table 1; the readings of specs/fem-x-dem.md §7): the linear map from an
 * increment of the cell's deformation to the increment of its Cauchy stress,
 * which the macro Newton loop uses as its Jacobian.
 *
 * Operators are registered by name under the registry kind "nhl_operator"
 * (tl_nhl_operator_register), so that a material or a driver picks one with
 * `-operator NAME`.  This module registers the network operators
 *   uko        upper-bound Kruyt (Voigt: every grain follows the macro field)
 *   ucko       uko scaled by one coefficient fitted against the CTO
 *   ucko_2dof  uko with its normal and tangential parts scaled separately
 *   kao        uko plus the pre-stress terms, grain rotations condensed
 *              contact by contact
 *   pstlo      the contact network as a pre-stressed truss with grain
 *              rotations: the fluctuations condensed by a sparse solve
 *   demqo      the DEM itself, sliding suppressed, probed by short steps
 *              from the equilibrated state (Eq. 32)
 * and the material of the cell (tl_nhl_material.c) registers the perturbation
 * operators that need its path evaluation ("cto", Eq. 31, and "aeo") with the
 * same tl_nhl_operator_register.
 *
 * CONVENTION.  Every operator returns c, 81 doubles, in the current
 * configuration:
 *     dσ_ij = c[TL_NHL_C(i, j, k, l)] G_kl,   G = dF F⁻¹,
 * σ the cell's Cauchy stress (Eq. 27, tension positive), G the increment of
 * the displacement gradient on the current cell (not necessarily
 * symmetric: the nine directions of Eq. 30 are G = Λ^{kl}).  For an operator
 * known only on symmetric G (six directions), the rotational part is
 * completed by objectivity, c : W = W σ − σ W for W antisymmetric.
 * The total-Lagrangian solid needs D = dS/dE (tl_material.h: Voigt 11, 22,
 * 33, 12, 23, 13, engineering shear); tl_nhl_operator_to_D converts (spec
 * §6): with G = d symmetric and dE = Fᵀ d F,
 *     dS = J F⁻¹ (c : d − d σ − σ d + tr(d) σ) F⁻ᵀ
 * (the Truesdell correction, O(σ / modulus), kept).  tl_nhl_operator_from_D
 * is its inverse, for an operator computed directly as D (the CTO along six
 * Green-strain directions).
 *
 * Two dimensions (disks in the x-y plane, stress per unit thickness): the
 * same c with every index restricted to {x, y} (components with a z index
 * are zero); the perturbation operators use the four (or three) in-plane
 * directions.
 *
 * Per-point state: an operator with memory (ucko's coefficient, aeo's
 * average of the pre-peak CTOs) declares state_size doubles per Gauss
 * point; the material keeps them beside its own committed and trial state
 * and hands compute() the committed (state_old) and trial (state_new)
 * copies, so commit and rollback cover them. */
#ifndef TL_NHL_OPERATOR_H
#define TL_NHL_OPERATOR_H

#include <stddef.h>
#include "tl_dem.h"
#include "tl_error.h"
#include "tl_math.h"
#include "tl_object.h"
#include "tl_registry.h"

/* Index of c_ijkl in the 81 doubles. */
#define TL_NHL_C(i, j, k, l) ((((i) * 3 + (j)) * 3 + (k)) * 3 + (l))

/* What one law evaluation (a full path or a probe) reports. */
typedef struct {
  long dem_steps;   /* DEM steps taken (drive + relaxation) */
  double tau;       /* drive duration (Eq. 18), s */
  double imbalance; /* final max Δ_n (Eq. 19) */
  double seconds;   /* wall time */
  int converged;    /* Eq. 19 met before the step cap */
} TlNhlEvalStats;

/* Kinds of re-evaluation the perturbation operators ask of the cell's owner. */
typedef enum {
  /* The full load step from the COMMITTED state at F^i to F_target
   * (Eqs. 3, 18, 19): the CTO's perturbations (Eq. 31). */
  TL_NHL_EVAL_PATH = 0,
  /* A new short step from the cell as it stands in the input (equilibrated
   * at F) to F_target with sliding suppressed (friction μ = ∞, tangential
   * histories kept), duration from Eq. 18 with γ the size of the increment,
   * relaxed to the same Eq. 19 tolerance (Eq. 32, DEMQO). */
  TL_NHL_EVAL_PROBE = 1
} TlNhlEvalMode;

/* A re-evaluation of the law by whoever owns the cell: returns the Cauchy
 * stress (contact part, Eq. 27) reached at F_target and leaves the input
 * cell exactly as it was (the probe's state is discarded). */
typedef TlStatus (*TlNhlEvalFn)(void *ctx, TlNhlEvalMode mode, TlMat3 F_target, TlMat3 *sigma,
                                TlNhlEvalStats *stats);

/* The cell as an operator sees it. */
typedef struct {
  TlDem *dem;   /* the cell at F, equilibrated, forces of the last evaluation current
                   (tl_dem_compute_forces or a step); operators read it and leave it as it was */
  int dim;      /* 3 spheres; 2 disks in the x-y plane */
  TlMat3 F;     /* cell deformation gradient: h = F h_R */
  TlMat3 sigma; /* Cauchy stress of that state (Eq. 27, contact part) */
  TlNhlEvalFn evaluate; /* NULL: operators that need it (demqo, cto, aeo, ucko's fit) refuse */
  void *ctx;
  /* The material's regime flags: calibrate = this point's first load
   * step(s) (ucko and ucko_2dof fit their coefficients, then keep them);
   * pre_peak = strain regime I (aeo perturbs and accumulates; after, it
   * returns the frozen average). */
  int calibrate, pre_peak;
} TlNhlOperatorInput;

/* What one operator evaluation reports. */
typedef struct {
  double seconds;      /* wall time of compute() */
  size_t contacts;     /* touching contacts used */
  size_t particles;    /* particles with contacts (non-rattlers, pstlo) */
  size_t rattlers;     /* particles left out (fewer than two contacts, pstlo) */
  size_t rigid_modes;  /* null modes removed: floating clusters' translations and
                          free rotations (pstlo), 0 otherwise */
  int evaluations;     /* law evaluations asked of input->evaluate */
  long dem_steps;      /* their DEM steps */
  double imbalance;    /* their largest final Δ_n */
  double residual;     /* pstlo: largest relative residual of the condensation solves */
  int symmetric;       /* the returned c has the major symmetry c_ijkl = c_klij */
} TlNhlOperatorStats;

typedef struct TlNhlOperator TlNhlOperator;

typedef struct {
  TlOpsHeader header; /* kind "nhl_operator"; name as given to -operator */
  size_t size;        /* sizeof the derived struct (>= sizeof(TlNhlOperator)) */
  const TlParam *params; /* the type's own parameters, doubles at offsets in the derived struct */
  int n_params;
  size_t state_size;  /* doubles of per-point state (0: none) */
  /* Optional: checks parameters, derives constants. */
  TlStatus (*setup)(TlNhlOperator *op);
  /* c (81 doubles, the convention above) of the cell in `in`.  state_old /
   * state_new: state_size doubles of this point (NULL when 0); state_new
   * starts as a copy of state_old.  Must be thread-safe for distinct
   * points (the macro loop calls it from several threads at once). */
  TlStatus (*compute)(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *state_old,
                      double *state_new, double c[81], TlNhlOperatorStats *stats);
  /* Optional: frees what the derived type owns. */
  void (*destroy)(TlNhlOperator *op);
} TlNhlOperatorOps;

/* The base every operator embeds first.  Its parameters (every type has
 * them, set by name like the type's own):
 *   eps         perturbation size of demqo / cto (default 1e-5; a reading:
 *               the paper gives none)
 *   directions  9 (Eq. 30, the default; 4 in 2-D) or 6 (symmetric G, 3 in
 *               2-D, the rotational part from objectivity)
 *   sliding_kt  1: sliding contacts keep k_t in uko/ucko/kao (the upper
 *               bound as printed, default); 0: they get k_t = 0
 *   symmetrise  1: pstlo drops the non-symmetric part of its geometric
 *               stiffness (CHOLMOD); 0 (default): full matrix (KLU) */
struct TlNhlOperator {
  const TlNhlOperatorOps *ops;
  double eps, directions, sliding_kt, symmetrise;
  int ready;
};

/* Registers an operator type (checks the table: kind, size, compute,
 * parameter offsets). */
TlStatus tl_nhl_operator_register(const TlNhlOperatorOps *ops);
/* Registers uko, ucko, ucko_2dof, kao, pstlo, demqo. */
TlStatus tl_nhl_operator_register_all(void);

TlStatus tl_nhl_operator_create(const char *name, TlNhlOperator **op);
/* Sets a base parameter or one of the type's; refuses a value out of range. */
TlStatus tl_nhl_operator_set(TlNhlOperator *op, const char *param, double value);
TlStatus tl_nhl_operator_get(const TlNhlOperator *op, const char *param, double *value);
TlStatus tl_nhl_operator_setup(TlNhlOperator *op);
void tl_nhl_operator_destroy(TlNhlOperator **op);
size_t tl_nhl_operator_state_size(const TlNhlOperator *op);
/* Calls compute (setting up first if needed), times it and checks that c is
 * finite.  stats may be NULL. */
TlStatus tl_nhl_operator_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *state_old,
                                 double *state_new, double c[81], TlNhlOperatorStats *stats);

/* ---- conversions ---- */
/* D = dS/dE (36 doubles, tl_material.h's Voigt with engineering shear) from
 * c at F with Cauchy stress sigma (spec §6). */
void tl_nhl_operator_to_D(const double c[81], TlMat3 F, TlMat3 sigma, double D[36]);
/* c from D (the symmetric part; the rotational part by objectivity). */
void tl_nhl_operator_from_D(const double D[36], TlMat3 F, TlMat3 sigma, double c[81]);
/* The 6x6 Voigt moduli of c on symmetric increments: C[I*6+J] = dσ_I for
 * d = the unit engineering strain J (tl_voigt_unit_strain), for printing
 * and for comparing with elastic constants (C11, C12, C44 ...). */
void tl_nhl_operator_voigt(const double c[81], double C[36]);
/* Completes c from its action on symmetric increments: sets c : W = W σ − σ W
 * for the antisymmetric W, keeping c : d. */
void tl_nhl_operator_objective(double c[81], TlMat3 sigma);

/* ---- the perturbation recipe shared by demqo, cto and aeo ----
 * c from (σ(F_target) − σ) / eps for F_target = (1 + eps Λ^{kl}) F along
 * 9 (4 in 2-D) directions, or the 6 (3) symmetric ones completed by
 * objectivity, each through in->evaluate(mode).  Fills the evaluation
 * counts of stats. */
TlStatus tl_nhl_operator_perturb(const TlNhlOperator *op, const TlNhlOperatorInput *in, TlNhlEvalMode mode,
                                 double c[81], TlNhlOperatorStats *stats);

/* Eigenvalues w (and eigenvectors V, columns, when not NULL) of the
 * symmetric n x n matrix A (n <= 6; Jacobi): rank checks and bounds. */
void tl_nhl_sym_eigen(int n, const double *A, double *w, double *V);

#endif
