/* The numerically homogenised law as a material type: "dem_cell"
 * (`-material dem_cell`, seeds/004 §2.2-2.5, specs/fem-x-dem.md §14.1).
 *
 * Every Gauss point owns a periodic DEM cell (tl_nhl_cell.h).  evaluate()
 * drives the point's cell from its committed state at F^i to the solid's F
 * (Eq. 18), relaxes it (Eq. 19), converts the Cauchy-Poisson stress to
 * S = J F⁻¹ σ F⁻ᵀ and the chosen operator's c (dσ = c : G, G = dF F⁻¹,
 * tl_nhl_operator.h) to D = dS/dE (spec §6).  The solid's commit and
 * rollback reach the cells through the material's hooks; the solid's
 * checkpoint holds the committed cells (bit-for-bit restart).
 *
 * Making one (what a driver does):
 *   TlMaterial *m;
 *   tl_material_create("dem_cell", &m);
 *   tl_material_set(m, "inertial", 1e-4);       // parameters below
 *   TlNhlPacking p; tl_nhl_packing_default(&p); p.kind = "random"; p.dim = 2; p.n = 400;
 *   tl_nhl_material_set_packing(m, &p);          // or _set_cell(m, prepared_cell)
 *   tl_nhl_material_set_operator(m, "demqo");    // any registered nhl_operator
 *   ... tl_solid_create(mesh, m, ...) ...       // the solid calls setup/init_state
 * One cell per Gauss point is made at the solid's setup (init_state), as a
 * copy of the prepared one: cell k is the k-th point the solid initialises,
 * i.e. for one block element e, Gauss point q -> cell e nq + q.
 *
 * Threads: evaluate() may run on distinct points from several threads
 * (each cell single-threaded); commit, rollback, checkpoint from one.
 *
 * Parameters (tl_material_set; -help lists them with units):
 *   inertial          I of Eq. 18 (1e-4)
 *   tolerance         ε_R of Eq. 19 (1e-3)
 *   max_relax_steps   cap on relaxation steps per evaluation (1e6)
 *   check_every       steps between equilibrium checks (20)
 *   min_drive_steps   floor of τ in DEM steps (20)
 *   permissive        1: the pressure-window criterion instead of Eq. 19 (0)
 *   pressure_tolerance, pressure_window   the permissive criterion (1e-4, 10)
 *   peak_drop         a point is past its peak (AEO freezes) once its deviatoric
 *                     stress falls below (1 - peak_drop) times its largest (0.02)
 *   calibrate_steps   load steps during which ucko/ucko_2dof calibrate (1)
 * and "density" (the macro mass density, unused quasi-statically).
 *
 * Stand-in law (F-U5): tl_nhl_material_set_analytic replaces the cells by an
 * analytic σ(F) with the same conversions and operators (the CTO perturbs
 * it exactly as it perturbs a cell). */
#ifndef TL_NHL_MATERIAL_H
#define TL_NHL_MATERIAL_H

#include <stddef.h>
#include "tl_material.h"
#include "tl_nhl_cell.h"

/* Per-point state (doubles), the material's part; the operator's own state
 * (tl_nhl_operator_state_size) follows at TL_NHL_STATE_OPERATOR. */
enum {
  TL_NHL_STATE_F = 0,          /* 9: F of the state (row-major); committed: F^i */
  TL_NHL_STATE_CELL = 9,       /* cell index (-1: analytic law) */
  TL_NHL_STATE_STEPS = 10,     /* committed load steps of this point */
  TL_NHL_STATE_QMAX = 11,      /* largest deviatoric stress |s| reached (committed) */
  TL_NHL_STATE_POST_PEAK = 12, /* 1 once past the peak */
  TL_NHL_STATE_SECONDS = 13,   /* wall time of the last evaluation incl. operator (the cost an
                                  LPT schedule sorts by) */
  TL_NHL_STATE_DEM_STEPS = 14, /* DEM steps of the last evaluation incl. operator */
  TL_NHL_STATE_IMBALANCE = 15, /* final Δ_n of the last evaluation */
  TL_NHL_STATE_OPERATOR = 16
};

/* Per-evaluation diagnostics of a point: the path (cell) and the operator. */
typedef struct {
  TlNhlCellStats path;     /* the evaluation at F (drive + relaxation) */
  long operator_steps;     /* DEM steps the operator asked for (cto/demqo) */
  int operator_evaluations;
  double operator_seconds;
  double seconds;          /* whole point: path + operator + conversions */
} TlNhlPointStats;

/* The law's cells: a prepared cell whose committed state every Gauss point
 * copies (the material takes ownership), or a packing to prepare. */
TlStatus tl_nhl_material_set_cell(TlMaterial *m, TlNhlCell *prepared);
TlStatus tl_nhl_material_set_packing(TlMaterial *m, const TlNhlPacking *packing);
/* The tangent operator by registered name ("cto", "aeo", "uko", "demqo",
 * ...; default "cto"); its parameters through tl_nhl_material_operator. */
TlStatus tl_nhl_material_set_operator(TlMaterial *m, const char *name);
struct TlNhlOperator *tl_nhl_material_operator(TlMaterial *m);
/* Marks every point pre- or post-peak from outside (e.g. the macro
 * load-displacement curve): -1 (default) each point decides from its own
 * stress (peak_drop), 0 all post-peak, 1 all pre-peak. */
void tl_nhl_material_set_regime(TlMaterial *m, int pre_peak);

/* A stand-in for the cells: the Cauchy stress of an analytic law at F
 * (tension positive).  With it the material makes no cells. */
typedef TlStatus (*TlNhlAnalyticFn)(void *ctx, TlMat3 F, TlMat3 *sigma);
TlStatus tl_nhl_material_set_analytic(TlMaterial *m, TlNhlAnalyticFn fn, void *ctx);

/* Cells made so far (one per Gauss point after the solid's setup). */
size_t tl_nhl_material_n_cells(const TlMaterial *m);
TlNhlCell *tl_nhl_material_cell(TlMaterial *m, size_t k);
/* Diagnostics of the last evaluation of cell k. */
TlStatus tl_nhl_material_point_stats(const TlMaterial *m, size_t k, TlNhlPointStats *stats);
/* Sums over every cell since the last call with reset (evaluations, DEM
 * steps, seconds): the per-step totals a driver prints. */
typedef struct {
  long evaluations, dem_steps, unconverged;
  double seconds, max_imbalance;
} TlNhlMaterialTotals;
void tl_nhl_material_totals(TlMaterial *m, TlNhlMaterialTotals *t, int reset);

/* Whether m is a dem_cell material. */
int tl_nhl_material_is(const TlMaterial *m);

/* Registers "dem_cell" (material) and the operators "cto" and "aeo"
 * (nhl_operator). */
TlStatus tl_hierarchical_register_all(void);

#endif
