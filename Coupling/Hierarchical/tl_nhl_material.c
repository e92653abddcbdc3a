/* The numerically homogenised law as a material: "dem_cell" (seeds/004
 * §2.2-2.5).  One DEM cell per Gauss point; evaluate() runs the cell's path
 * from its committed state to the solid's F, converts σ to S = J F⁻¹σF⁻ᵀ
 * and the operator's c to D = dS/dE (specs/fem-x-dem.md §6). */
#include "tl_nhl_material.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_nhl_operator.h"
#include "tl_timer.h"

/* Accumulated since the last tl_nhl_material_totals reset, per cell (each
 * cell is touched by one thread at a time, so no locks). */
typedef struct {
  TlNhlPointStats last;
  long evaluations, dem_steps, unconverged;
  double seconds, max_imbalance;
} CellRecord;

typedef struct {
  TlMaterial base;
  double inertial, tolerance, max_relax_steps, check_every, min_drive_steps, permissive;
  double pressure_tolerance, pressure_window, peak_drop, calibrate_steps;
  TlNhlCellSettings settings;
  TlNhlCell *model;       /* the prepared cell every point copies */
  TlNhlCell **cells;
  CellRecord *records;
  size_t n_cells, cap_cells;
  TlNhlOperator *op;
  int regime;             /* -1 each point decides, 0 post-peak, 1 pre-peak */
  TlNhlAnalyticFn analytic;
  void *analytic_ctx;
} DemCell;

static const TlMaterialParam params[] = {
    {"inertial", 1e-4, 1e-9, 1.0, "1", "inertial number I of the drive duration (seeds/004 Eq. 18; 1e-4)",
     offsetof(DemCell, inertial)},
    {"tolerance", 1e-3, 1e-12, 1.0, "1", "equilibrium tolerance eps_R on every particle's imbalance (Eq. 19; 1e-3)",
     offsetof(DemCell, tolerance)},
    {"max_relax_steps", 1e6, 0.0, 1e12, "DEM steps", "cap on the relaxation steps of one evaluation",
     offsetof(DemCell, max_relax_steps)},
    {"check_every", 20, 1, 1e6, "DEM steps", "steps between equilibrium checks", offsetof(DemCell, check_every)},
    {"min_drive_steps", 20, 1, 1e9, "DEM steps", "floor of the drive duration (an isotropic or vanishing increment)",
     offsetof(DemCell, min_drive_steps)},
    {"permissive", 0, 0, 1, "1", "1: the permissive criterion (cell pressure steady over a window) instead of Eq. 19",
     offsetof(DemCell, permissive)},
    {"pressure_tolerance", 1e-4, 1e-12, 0.5, "1", "permissive criterion: relative pressure spread over the window",
     offsetof(DemCell, pressure_tolerance)},
    {"pressure_window", 10, 2, 64, "checks", "permissive criterion: checks the pressure must stay steady over",
     offsetof(DemCell, pressure_window)},
    {"peak_drop", 0.02, 0.0, 1.0, "1",
     "a point is past its peak (aeo freezes its average) once |dev sigma| < (1 - peak_drop) x its largest (a reading)",
     offsetof(DemCell, peak_drop)},
    {"calibrate_steps", 1, 0, 1e9, "load steps", "load steps during which ucko / ucko_2dof fit their coefficients",
     offsetof(DemCell, calibrate_steps)},
};
enum { N_PARAMS = (int)(sizeof params / sizeof params[0]) };

extern const TlMaterialOps tl_nhl_dem_cell_ops;

int tl_nhl_material_is(const TlMaterial *m) { return m && m->ops == &tl_nhl_dem_cell_ops; }

static TlStatus check_is(const TlMaterial *m, const char *what)
{
  if (!tl_nhl_material_is(m))
    TL_ERROR(TL_ERR_ARG, "%s: material '%s' is not a dem_cell material", what, m ? m->ops->header.name : "(null)");
  return TL_OK;
}

static size_t state_size_of(const DemCell *d)
{
  return TL_NHL_STATE_OPERATOR + (d->op ? tl_nhl_operator_state_size(d->op) : 0);
}

/* ---------------------------------------------------------------- setup */
static TlStatus setup(TlMaterial *m)
{
  DemCell *d = (DemCell *)m;
  TlNhlCellSettings *s = &d->settings;
  tl_nhl_cell_settings_default(s);
  s->inertial = d->inertial;
  s->tolerance = d->tolerance;
  s->max_relax_steps = (long)d->max_relax_steps;
  s->check_every = (long)d->check_every;
  s->min_drive_steps = (long)d->min_drive_steps;
  s->criterion = d->permissive > 0.5 ? TL_NHL_EQUILIBRIUM_PRESSURE : TL_NHL_EQUILIBRIUM_IMBALANCE;
  s->pressure_tolerance = d->pressure_tolerance;
  s->pressure_window = (long)d->pressure_window;
  TL_CHECK(tl_nhl_cell_settings_check(s));
  if (!d->model && !d->analytic)
    TL_ERROR(TL_ERR_STATE, "dem_cell material without a cell: give one with tl_nhl_material_set_packing or "
             "tl_nhl_material_set_cell (or an analytic stand-in)");
  if (!d->op) TL_CHECK(tl_nhl_material_set_operator(m, "cto"));
  TL_CHECK(tl_nhl_operator_setup(d->op));
  if (d->model) TL_CHECK(tl_nhl_cell_set_settings(d->model, s));
  for (size_t k = 0; k < d->n_cells; ++k) TL_CHECK(tl_nhl_cell_set_settings(d->cells[k], s));
  const size_t ss = state_size_of(d);
  if (d->n_cells && m->state_size && ss != m->state_size)
    TL_ERROR(TL_ERR_STATE, "dem_cell: the operator changed the per-point state from %zu to %zu doubles after the "
             "cells were made", m->state_size, ss);
  m->state_size = ss;
  return TL_OK;
}

static void destroy(TlMaterial *m)
{
  DemCell *d = (DemCell *)m;
  for (size_t k = 0; k < d->n_cells; ++k) tl_nhl_cell_destroy(&d->cells[k]);
  tl_free(&d->cells);
  tl_free(&d->records);
  tl_nhl_cell_destroy(&d->model);
  tl_nhl_operator_destroy(&d->op);
}

/* One cell per point, a copy of the prepared one: cell k is the k-th point
 * initialised.  (The ops table gives a const material: the cells are the
 * material's own storage, made here once per point.) */
static TlStatus init_state(const TlMaterial *mc, size_t npts, double *state)
{
  DemCell *d = (DemCell *)(TlMaterial *)mc;
  const size_t ss = mc->state_size;
  if (!d->analytic) {
    TL_CHECK(tl_array_reserve(&d->cells, &d->cap_cells, d->n_cells + npts, sizeof *d->cells));
    size_t cap = d->cap_cells;
    TL_CHECK(tl_realloc(&d->records, cap, sizeof *d->records));
  }
  for (size_t p = 0; p < npts; ++p) {
    double *st = state + p * ss;
    memset(st, 0, ss * sizeof *st);
    st[TL_NHL_STATE_F + 0] = st[TL_NHL_STATE_F + 4] = st[TL_NHL_STATE_F + 8] = 1.0;
    st[TL_NHL_STATE_CELL] = -1.0;
    if (d->analytic) continue;
    TL_CHECK(tl_nhl_cell_create_copy(d->model, &d->cells[d->n_cells]));
    memset(&d->records[d->n_cells], 0, sizeof d->records[d->n_cells]);
    st[TL_NHL_STATE_CELL] = (double)d->n_cells;
    d->n_cells++;
  }
  return TL_OK;
}

/* ---------------------------------------------------------------- evaluation */
/* What the operator's re-evaluations reach: the point's cell or the
 * analytic law. */
typedef struct {
  const DemCell *d;
  TlNhlCell *cell;
} EvalCtx;

static TlStatus reevaluate(void *ctx, TlNhlEvalMode mode, TlMat3 F, TlMat3 *sigma, TlNhlEvalStats *es)
{
  EvalCtx *e = ctx;
  if (!e->cell) {
    TL_CHECK(e->d->analytic(e->d->analytic_ctx, F, sigma));
    return TL_OK;
  }
  return tl_nhl_cell_reevaluate(e->cell, mode, F, sigma, es);
}

/* |dev σ| (in-plane for disks). */
static double deviator_norm(TlMat3 s, int dim)
{
  const double p = dim == 2 ? 0.5 * (s.m[0][0] + s.m[1][1]) : tl_m3_trace(s) / 3.0;
  double q = 0.0;
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) {
      const double v = s.m[i][j] - (i == j ? p : 0.0);
      q += v * v;
    }
  return sqrt(q);
}

/* The operator without a world (the analytic stand-in): compute() direct,
 * with the checks tl_nhl_operator_compute makes. */
static TlStatus operator_compute(const DemCell *d, const TlNhlOperatorInput *in, const double *so, double *sn,
                                 double c[81], TlNhlOperatorStats *st)
{
  if (in->dem) return tl_nhl_operator_compute(d->op, in, so, sn, c, st);
  const size_t ns = tl_nhl_operator_state_size(d->op);
  memset(st, 0, sizeof *st);
  if (ns) memcpy(sn, so, ns * sizeof *sn);
  const double t0 = tl_wtime();
  TL_CHECK(d->op->ops->compute(d->op, in, so, sn, c, st));
  st->seconds = tl_wtime() - t0;
  for (int q = 0; q < 81; ++q)
    if (!isfinite(c[q]))
      TL_ERROR(TL_ERR_NUMERIC, "nhl operator '%s': component %d of c is %g", d->op->ops->header.name, q, c[q]);
  return TL_OK;
}

static TlStatus evaluate_point(const DemCell *d, TlMat3 F, const double *so, double *sn, TlMat3 *S, double *D)
{
  const double t0 = tl_wtime();
  const size_t ss = d->base.state_size;
  memcpy(sn, so, ss * sizeof *sn);
  const long idx = (long)so[TL_NHL_STATE_CELL];
  TlNhlCell *cell = NULL;
  if (idx >= 0) {
    if ((size_t)idx >= d->n_cells)
      TL_ERROR(TL_ERR_STATE, "dem_cell: point state names cell %ld; there are %zu", idx, d->n_cells);
    cell = d->cells[idx];
  } else if (!d->analytic) {
    TL_ERROR(TL_ERR_STATE, "dem_cell: a point without a cell (state not initialised by the material)");
  }
  const int dim = cell ? tl_nhl_cell_dim(cell) : 3;
  TlMat3 sigma;
  TlNhlCellStats cs;
  memset(&cs, 0, sizeof cs);
  if (cell) TL_CHECK(tl_nhl_cell_evaluate(cell, F, &sigma, &cs));
  else TL_CHECK(d->analytic(d->analytic_ctx, F, &sigma));
  *S = tl_nhl_cauchy_to_pk2(F, sigma);
  /* regime of the point: pre-peak while its deviatoric stress has not
   * dropped below (1 - peak_drop) of the largest it reached */
  const double q = deviator_norm(sigma, dim), qmax = so[TL_NHL_STATE_QMAX];
  const int was_post = so[TL_NHL_STATE_POST_PEAK] > 0.5;
  const int post = was_post || q < (1.0 - d->peak_drop) * qmax;
  sn[TL_NHL_STATE_QMAX] = fmax(qmax, q);
  sn[TL_NHL_STATE_POST_PEAK] = post;
  sn[TL_NHL_STATE_STEPS] = so[TL_NHL_STATE_STEPS] + 1.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) sn[TL_NHL_STATE_F + 3 * i + j] = F.m[i][j];
  TlNhlOperatorStats ost;
  memset(&ost, 0, sizeof ost);
  if (D) {
    EvalCtx ectx = {d, cell};
    TlNhlOperatorInput in = {cell ? tl_nhl_cell_dem(cell) : NULL, dim, F, sigma, reevaluate, &ectx,
                             so[TL_NHL_STATE_STEPS] < d->calibrate_steps, d->regime >= 0 ? d->regime : !post};
    double c[81];
    TL_CHECK(operator_compute(d, &in, so + TL_NHL_STATE_OPERATOR, sn + TL_NHL_STATE_OPERATOR, c, &ost));
    tl_nhl_operator_to_D(c, F, sigma, D);
  }
  const double seconds = tl_wtime() - t0;
  sn[TL_NHL_STATE_SECONDS] = seconds;
  sn[TL_NHL_STATE_DEM_STEPS] = (double)(cs.dem_steps + ost.dem_steps);
  sn[TL_NHL_STATE_IMBALANCE] = cs.imbalance;
  if (cell) {
    CellRecord *r = &d->records[idx];
    r->last.path = cs;
    r->last.operator_steps = ost.dem_steps;
    r->last.operator_evaluations = ost.evaluations;
    r->last.operator_seconds = ost.seconds;
    r->last.seconds = seconds;
    r->evaluations += 1 + ost.evaluations;
    r->dem_steps += cs.dem_steps + ost.dem_steps;
    r->unconverged += !cs.converged;
    r->seconds += seconds;
    r->max_imbalance = fmax(r->max_imbalance, fmax(cs.imbalance, ost.imbalance));
  }
  return TL_OK;
}

static TlStatus evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma, const double *state_old,
                         double *state_new, TlMat3 *S, double *D, double *W)
{
  (void)gamma; /* the cell sees F; an eigenstrain has no meaning for it */
  const DemCell *d = (const DemCell *)m;
  if (!state_old || !state_new) TL_ERROR(TL_ERR_ARG, "dem_cell: evaluate needs the per-point state arrays");
  const size_t ss = m->state_size;
  for (size_t p = 0; p < npts; ++p) {
    TL_CHECK(evaluate_point(d, F[p], state_old + p * ss, state_new + p * ss, &S[p], D ? D + 36 * p : NULL));
    if (W) W[p] = 0.0; /* no stored energy: the law is dissipative */
  }
  return TL_OK;
}

static TlStatus commit(TlMaterial *m, size_t npts, const double *state)
{
  DemCell *d = (DemCell *)m;
  for (size_t p = 0; p < npts; ++p) {
    const long idx = (long)state[p * m->state_size + TL_NHL_STATE_CELL];
    if (idx >= 0 && (size_t)idx < d->n_cells) TL_CHECK(tl_nhl_cell_commit(d->cells[idx]));
  }
  return TL_OK;
}

static TlStatus rollback(TlMaterial *m, size_t npts, const double *state)
{
  DemCell *d = (DemCell *)m;
  for (size_t p = 0; p < npts; ++p) {
    const long idx = (long)state[p * m->state_size + TL_NHL_STATE_CELL];
    if (idx >= 0 && (size_t)idx < d->n_cells) TL_CHECK(tl_nhl_cell_rollback(d->cells[idx]));
  }
  return TL_OK;
}

/* ---------------------------------------------------------------- checkpoint */
static TlStatus cells_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  DemCell *d = (DemCell *)object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_cells", (int64_t)d->n_cells));
  for (size_t k = 0; k < d->n_cells; ++k) {
    char sub[600];
    snprintf(sub, sizeof sub, "%s/cell_%zu", group ? group : "", k);
    TL_CHECK(tl_nhl_cell_save(d->cells[k], w, sub));
  }
  return TL_OK;
}

static TlStatus cells_load(void *object, TlCheckpointReader *r, const char *group)
{
  DemCell *d = object;
  int64_t n = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_cells", &n));
  if (n != (int64_t)d->n_cells)
    TL_ERROR(TL_ERR_ARG, "%s: %s holds %lld cells; this material has %zu", tl_checkpoint_reader_path(r), group,
             (long long)n, d->n_cells);
  for (size_t k = 0; k < d->n_cells; ++k) {
    char sub[600];
    snprintf(sub, sizeof sub, "%s/cell_%zu", group ? group : "", k);
    TL_CHECK(tl_nhl_cell_load(d->cells[k], r, sub));
  }
  return TL_OK;
}

static const TlCheckpointOps cells_checkpoint_ops = {
    .header = {"checkpoint", "dem_cell_v1", "committed DEM cells of a dem_cell material, one per Gauss point"},
    .save = cells_save,
    .load = cells_load,
};

const TlMaterialOps tl_nhl_dem_cell_ops = {
    .header = {"material", "dem_cell",
               "numerically homogenised law: a periodic DEM cell per Gauss point driven to F (seeds/004 Eqs. 18, 19, "
               "27); tangent from the chosen nhl_operator"},
    .size = sizeof(DemCell),
    .n_params = N_PARAMS,
    .params = params,
    .setup = setup,
    .evaluate = evaluate,
    .init_state = init_state,
    .commit = commit,
    .rollback = rollback,
    .destroy = destroy,
    .checkpoint = &cells_checkpoint_ops,
};

/* ---------------------------------------------------------------- API */
TlStatus tl_nhl_material_set_cell(TlMaterial *m, TlNhlCell *prepared)
{
  TL_CHECK(check_is(m, "tl_nhl_material_set_cell"));
  DemCell *d = (DemCell *)m;
  if (d->n_cells) TL_ERROR(TL_ERR_STATE, "dem_cell: the cell is set before the solid makes the points' cells");
  tl_nhl_cell_destroy(&d->model);
  d->model = prepared;
  d->analytic = NULL;
  m->ready = 0;
  return TL_OK;
}

TlStatus tl_nhl_material_set_packing(TlMaterial *m, const TlNhlPacking *packing)
{
  TL_CHECK(check_is(m, "tl_nhl_material_set_packing"));
  DemCell *d = (DemCell *)m;
  TlNhlCellSettings s;
  tl_nhl_cell_settings_default(&s);
  s.inertial = d->inertial;
  s.tolerance = d->tolerance;
  TlNhlCell *cell = NULL;
  TL_CHECK(tl_nhl_cell_create_packing(packing, &s, &cell));
  TlStatus st = tl_nhl_material_set_cell(m, cell);
  if (st != TL_OK) tl_nhl_cell_destroy(&cell);
  return st;
}

TlStatus tl_nhl_material_set_operator(TlMaterial *m, const char *name)
{
  TL_CHECK(check_is(m, "tl_nhl_material_set_operator"));
  DemCell *d = (DemCell *)m;
  TlNhlOperator *op = NULL;
  TL_CHECK(tl_nhl_operator_create(name, &op));
  if (d->n_cells && tl_nhl_operator_state_size(op) != (d->op ? tl_nhl_operator_state_size(d->op) : 0)) {
    tl_nhl_operator_destroy(&op);
    TL_ERROR(TL_ERR_STATE, "dem_cell: operator '%s' keeps another per-point state than the one the points were made "
             "with; choose it before the solid's setup", name);
  }
  tl_nhl_operator_destroy(&d->op);
  d->op = op;
  m->ready = 0;
  return TL_OK;
}

TlNhlOperator *tl_nhl_material_operator(TlMaterial *m)
{
  return tl_nhl_material_is(m) ? ((DemCell *)m)->op : NULL;
}

void tl_nhl_material_set_regime(TlMaterial *m, int pre_peak)
{
  if (tl_nhl_material_is(m)) ((DemCell *)m)->regime = pre_peak < 0 ? -1 : (pre_peak ? 1 : 0);
}

TlStatus tl_nhl_material_set_analytic(TlMaterial *m, TlNhlAnalyticFn fn, void *ctx)
{
  TL_CHECK(check_is(m, "tl_nhl_material_set_analytic"));
  DemCell *d = (DemCell *)m;
  if (!fn) TL_ERROR(TL_ERR_ARG, "dem_cell: NULL analytic law");
  if (d->n_cells) TL_ERROR(TL_ERR_STATE, "dem_cell: the analytic law replaces the cells before they are made");
  tl_nhl_cell_destroy(&d->model);
  d->analytic = fn;
  d->analytic_ctx = ctx;
  m->ready = 0;
  return TL_OK;
}

TlStatus tl_nhl_material_compare(TlMaterial *m, size_t k, const TlNhlOperator *op, double c[81], TlNhlOperatorStats *stats)
{
  TL_CHECK(check_is(m, "tl_nhl_material_compare"));
  DemCell *d = (DemCell *)m;
  if (k >= d->n_cells) TL_ERROR(TL_ERR_ARG, "dem_cell: cell %zu asked for; there are %zu", k, d->n_cells);
  TlNhlCell *cell = d->cells[k];
  if (!tl_nhl_cell_has_trial(cell))
    TL_ERROR(TL_ERR_STATE, "dem_cell: cell %zu has no evaluation to compare operators on (evaluate, then compare, "
             "then commit)", k);
  TlMat3 sigma;
  TL_CHECK(tl_nhl_cell_stress(cell, &sigma, NULL));
  EvalCtx ectx = {d, cell};
  TlNhlOperatorInput in = {tl_nhl_cell_dem(cell), tl_nhl_cell_dim(cell), tl_nhl_cell_current_F(cell), sigma,
                           reevaluate, &ectx, 1, 1};
  const size_t ns = tl_nhl_operator_state_size(op);
  double *so = NULL, *sn = NULL;
  if (ns) {
    TL_CHECK(tl_calloc(&so, ns, sizeof *so));
    TlStatus s = tl_calloc(&sn, ns, sizeof *sn);
    if (s != TL_OK) {
      tl_free(&so);
      return tl_error_trace(s, __FILE__, __LINE__);
    }
  }
  TlStatus s = tl_nhl_operator_compute(op, &in, so, sn, c, stats);
  tl_free(&so);
  tl_free(&sn);
  TL_CHECK(s);
  return TL_OK;
}

size_t tl_nhl_material_n_cells(const TlMaterial *m) { return tl_nhl_material_is(m) ? ((const DemCell *)m)->n_cells : 0; }

TlNhlCell *tl_nhl_material_cell(TlMaterial *m, size_t k)
{
  if (!tl_nhl_material_is(m)) return NULL;
  DemCell *d = (DemCell *)m;
  return k < d->n_cells ? d->cells[k] : NULL;
}

TlStatus tl_nhl_material_point_stats(const TlMaterial *m, size_t k, TlNhlPointStats *stats)
{
  TL_CHECK(check_is(m, "tl_nhl_material_point_stats"));
  const DemCell *d = (const DemCell *)m;
  if (k >= d->n_cells) TL_ERROR(TL_ERR_ARG, "dem_cell: cell %zu asked for; there are %zu", k, d->n_cells);
  *stats = d->records[k].last;
  return TL_OK;
}

void tl_nhl_material_totals(TlMaterial *m, TlNhlMaterialTotals *t, int reset)
{
  memset(t, 0, sizeof *t);
  if (!tl_nhl_material_is(m)) return;
  DemCell *d = (DemCell *)m;
  for (size_t k = 0; k < d->n_cells; ++k) {
    CellRecord *r = &d->records[k];
    t->evaluations += r->evaluations;
    t->dem_steps += r->dem_steps;
    t->unconverged += r->unconverged;
    t->seconds += r->seconds;
    t->max_imbalance = fmax(t->max_imbalance, r->max_imbalance);
    if (reset) r->evaluations = r->dem_steps = r->unconverged = 0, r->seconds = r->max_imbalance = 0.0;
  }
}
