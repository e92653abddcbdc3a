/* The coupled DEM–FEM loop: lock-step or sub-cycled, two-way or one-way. */
#include "tl_coupled_loop.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "tl_memory.h"

struct TlCoupledLoop {
  TlDem *dem;
  TlSolid *solid;
  TlStepper *stepper;
  TlMechSystem *sys;
  int n_couplings;
  TlSCoupling **couplings;
  TlCoupledLoopOptions o;
  size_t n_nodes;
  double *u_nodes, *v_nodes, *a_nodes, *u_prev, *u_mid, *v_mid; /* 3 n_nodes */
  double *u_back; /* u_{n-1}: where the lagged walls start a macro step (3 n_nodes) */
  /* The couplings' accumulated per-face forces assembled node-wise: those
   * applied in the last FE step and in the one before (work, energy and
   * momentum diagnostics; the solid takes them through the wrappers). */
  double *F_nodes, *F_prev; /* 3 n_nodes */
  TlVec3 wall_force, wall_acc;
  double t;
  double work_on_solid;
};

void tl_coupled_loop_options_default(TlCoupledLoopOptions *o)
{
  o->substeps = 1;
  o->one_way = 0;
  o->scheme = TL_COUPLING_PREDICT;
  o->average_forces = 0;
}

/* Starts a new accumulation of the couplings' forces. */
static void clear_forces(TlCoupledLoop *L)
{
  for (int c = 0; c < L->n_couplings; c++) tl_scoupling_clear_forces(L->couplings[c]);
  L->wall_acc = tl_v3(0, 0, 0);
}

/* Per-face coupling forces of the current DEM contacts, scaled, into the
 * couplings' accumulators. */
static TlStatus gather(TlCoupledLoop *L, double scale)
{
  for (int c = 0; c < L->n_couplings; c++) {
    TlVec3 w;
    TL_CHECK(tl_scoupling_accumulate_forces(L->couplings[c], scale, &w));
    L->wall_acc = tl_v3_axpy(L->wall_acc, scale, w);
  }
  return TL_OK;
}

/* The accumulated forces, node-wise, into F_nodes; their wall total. */
static void assemble_forces(TlCoupledLoop *L)
{
  memset(L->F_nodes, 0, 3 * L->n_nodes * sizeof(double));
  for (int c = 0; c < L->n_couplings; c++) tl_scoupling_assemble_forces(L->couplings[c], L->F_nodes);
  L->wall_force = L->wall_acc;
}

/* After DEM step j of k: accumulate the average, or keep the last step's. */
static TlStatus take_forces(TlCoupledLoop *L, int j)
{
  const int k = L->o.substeps;
  if (L->o.average_forces) return gather(L, 1.0 / (double)k);
  return j == k ? gather(L, 1.0) : TL_OK;
}

static TlStatus move_walls(TlCoupledLoop *L, const double *u, const double *v)
{
  for (int c = 0; c < L->n_couplings; c++) TL_CHECK(tl_scoupling_set_kinematics(L->couplings[c], u, v));
  return TL_OK;
}

TlStatus tl_coupled_loop_create(TlDem *dem, TlSolid *solid, TlStepper *stepper, int n_couplings,
                                TlSCoupling *const *couplings, const TlCoupledLoopOptions *options,
                                TlCoupledLoop **out)
{
  *out = NULL;
  if (!dem || !solid || !stepper || n_couplings < 1 || !couplings)
    TL_ERROR(TL_ERR_ARG, "coupled loop needs a world, a solid, a stepper and at least one coupling (got %d)", n_couplings);
  TlCoupledLoopOptions o;
  tl_coupled_loop_options_default(&o);
  if (options) o = *options;
  if (o.substeps < 1 || o.substeps > 100000) TL_ERROR(TL_ERR_ARG, "sub-steps %d outside [1, 100000]", o.substeps);
  if (o.scheme < TL_COUPLING_PREDICT || o.scheme > TL_COUPLING_LAGGED_WALLS)
    TL_ERROR(TL_ERR_ARG, "coupling scheme %d is none of PREDICT (0), INTERPOLATE (1), PARALLEL (2), LAGGED_WALLS (3)", o.scheme);
  for (int c = 0; c < n_couplings; c++) {
    if (!couplings[c]) TL_ERROR(TL_ERR_ARG, "coupling %d of %d is NULL", c, n_couplings);
    if (tl_scoupling_solid(couplings[c]) != solid) TL_ERROR(TL_ERR_ARG, "coupling %d couples another solid", c);
    for (int k = 0; k < c; k++)
      if (couplings[k] == couplings[c]) TL_ERROR(TL_ERR_ARG, "coupling %d is listed twice (also as %d)", c, k);
  }
  const TlMesh *mesh = tl_solid_mesh(solid);
  if (mesh->dim != 3) TL_ERROR(TL_ERR_ARG, "coupled loop needs a 3-D solid (dimension %d)", mesh->dim);
  TlCoupledLoop *L;
  TL_CHECK(TL_NEW(L));
  TlStatus s = TL_OK;
  L->dem = dem;
  L->solid = solid;
  L->stepper = stepper;
  L->sys = tl_solid_system(solid);
  L->o = o;
  L->n_couplings = n_couplings;
  L->n_nodes = mesh->n_nodes;
  size_t nn = 3 * L->n_nodes, nd = (size_t)L->sys->ndof;
  if ((s = tl_calloc(&L->couplings, (size_t)n_couplings, sizeof *L->couplings)) != TL_OK) goto fail;
  for (int c = 0; c < n_couplings; c++) L->couplings[c] = couplings[c];
  double **node_arrays[] = {&L->u_nodes, &L->v_nodes, &L->a_nodes, &L->u_prev, &L->u_mid, &L->v_mid, &L->F_nodes, &L->F_prev, &L->u_back};
  for (size_t k = 0; k < sizeof node_arrays / sizeof *node_arrays; k++)
    if ((s = tl_calloc(node_arrays[k], nn, sizeof(double))) != TL_OK) goto fail;
  L->t = tl_dem_time(dem);
  tl_solid_dofs_to_nodes(solid, stepper->u, L->u_nodes);
  tl_solid_dofs_to_nodes(solid, stepper->v, L->v_nodes);
  memcpy(L->u_prev, L->u_nodes, nn * sizeof(double));
  memcpy(L->u_back, L->u_nodes, nn * sizeof(double));
  tl_dem_track_energy(dem, 1);
  if ((s = move_walls(L, L->u_nodes, L->v_nodes)) != TL_OK) goto fail;
  if ((s = tl_dem_compute_forces(dem)) != TL_OK) goto fail;
  clear_forces(L);
  if ((s = gather(L, 1.0)) != TL_OK) goto fail;
  assemble_forces(L);
  /* The solid's initial acceleration with the coupling forces of t_0, which
   * the SCoupling elements now carry (the stepper's state was set before). */
  if (!o.one_way) {
    double *ucopy = NULL, *vcopy = NULL;
    if ((s = tl_calloc(&ucopy, nd ? nd : 1, sizeof *ucopy)) == TL_OK && (s = tl_calloc(&vcopy, nd ? nd : 1, sizeof *vcopy)) == TL_OK) {
      memcpy(ucopy, stepper->u, nd * sizeof(double));
      memcpy(vcopy, stepper->v, nd * sizeof(double));
      s = tl_stepper_set_state(stepper, stepper->t, ucopy, vcopy);
    }
    tl_free(&ucopy);
    tl_free(&vcopy);
    if (s != TL_OK) goto fail;
  }
  *out = L;
  return TL_OK;
fail:
  tl_coupled_loop_destroy(&L);
  return tl_error_trace(s, __FILE__, __LINE__);
}

void tl_coupled_loop_destroy(TlCoupledLoop **pL)
{
  TlCoupledLoop *L = *pL;
  if (!L) return;
  /* The load goes with the loop: the SCoupling elements carry none after it. */
  for (int c = 0; c < L->n_couplings && L->couplings; c++)
    if (L->couplings[c]) tl_scoupling_clear_forces(L->couplings[c]);
  tl_free(&L->couplings);
  tl_free(&L->u_nodes);
  tl_free(&L->v_nodes);
  tl_free(&L->a_nodes);
  tl_free(&L->u_prev);
  tl_free(&L->u_mid);
  tl_free(&L->v_mid);
  tl_free(&L->F_nodes);
  tl_free(&L->F_prev);
  tl_free(&L->u_back);
  tl_free(pL);
}

/* Staggered macro steps: the solid first, under the forces the couplings
 * carry from the last macro step (a lag of Dt), then the k DEM steps with
 * the walls interpolated between u_n and u_{n+1} (INTERPOLATE) or held
 * where they were at t_n and moved after (PARALLEL: both models advance
 * from the state at t_n, as Fig. 8 orders the solves). */
static TlStatus step_staggered(TlCoupledLoop *L)
{
  const int k = L->o.substeps, walls_at_start = L->o.scheme == TL_COUPLING_PARALLEL;
  const double dt = tl_dem_timestep(L->dem), Dt = k * dt;
  const size_t nn = 3 * L->n_nodes;
  TL_CHECK(tl_stepper_step(L->stepper, Dt));
  tl_solid_dofs_to_nodes(L->solid, L->stepper->u, L->u_nodes);
  tl_solid_dofs_to_nodes(L->solid, L->stepper->v, L->v_nodes);
  /* Work of the applied loads (F_prev before this step, F_nodes in it). */
  double w = 0.0;
  for (size_t i = 0; i < nn; i++) w += 0.5 * (L->F_prev[i] + L->F_nodes[i]) * (L->u_nodes[i] - L->u_prev[i]);
  L->work_on_solid += w;
  memcpy(L->F_prev, L->F_nodes, nn * sizeof(double));
  clear_forces(L);
  for (size_t i = 0; i < nn; i++) L->v_mid[i] = (L->u_nodes[i] - L->u_prev[i]) / Dt;
  for (int j = 1; j <= k; ++j) {
    if (!walls_at_start) {
      const double f = (double)j / (double)k;
      for (size_t i = 0; i < nn; i++) L->u_mid[i] = L->u_prev[i] + f * (L->u_nodes[i] - L->u_prev[i]);
      TL_CHECK(move_walls(L, L->u_mid, L->v_mid));
    }
    TL_CHECK(tl_dem_step(L->dem, 1));
    TL_CHECK(take_forces(L, j));
  }
  if (walls_at_start) TL_CHECK(move_walls(L, L->u_nodes, L->v_nodes));
  assemble_forces(L);
  memcpy(L->u_prev, L->u_nodes, nn * sizeof(double));
  L->t += Dt;
  return TL_OK;
}

TlStatus tl_coupled_loop_step(TlCoupledLoop *L)
{
  const int staggered = L->o.scheme == TL_COUPLING_INTERPOLATE || L->o.scheme == TL_COUPLING_PARALLEL;
  if (staggered && !L->o.one_way) return step_staggered(L);
  const int k = L->o.substeps, lagged = L->o.scheme == TL_COUPLING_LAGGED_WALLS;
  const double dt = tl_dem_timestep(L->dem);
  const size_t nn = 3 * L->n_nodes;
  /* 1. k DEM steps with the walls on the solid's Taylor predictor
   *    u_n + s v_n + s^2/2 a_n, v_n + s a_n (s = j dt): second order, and for
   *    the explicit stepper with k = 1 the very position it will reach.
   *    Lagged walls go from u_{n-1} to u_n instead. */
  if (!L->o.one_way) tl_solid_dofs_to_nodes(L->solid, L->stepper->a, L->a_nodes);
  clear_forces(L);
  for (int j = 1; j <= k; j++) {
    if (!L->o.one_way && lagged) {
      const double f = (double)j / (double)k, Dt = k * dt;
      for (size_t i = 0; i < nn; i++) {
        L->u_mid[i] = L->u_back[i] + f * (L->u_nodes[i] - L->u_back[i]);
        L->v_mid[i] = (L->u_nodes[i] - L->u_back[i]) / Dt;
      }
      TL_CHECK(move_walls(L, L->u_mid, L->v_mid));
    } else if (!L->o.one_way) {
      const double s = j * dt;
      for (size_t i = 0; i < nn; i++) {
        L->u_mid[i] = L->u_nodes[i] + s * (L->v_nodes[i] + 0.5 * s * L->a_nodes[i]);
        L->v_mid[i] = L->v_nodes[i] + s * L->a_nodes[i];
      }
      TL_CHECK(move_walls(L, L->u_mid, L->v_mid));
    }
    TL_CHECK(tl_dem_step(L->dem, 1));
    TL_CHECK(take_forces(L, j));
  }
  /* 2. The solid to t_n + k dt under the forces of step 1 (the last DEM
   *    step's, or their average), which the SCoupling elements put into
   *    its residual at every evaluation of the step: the load at t_{n+1}. */
  memcpy(L->F_prev, L->F_nodes, nn * sizeof(double));
  assemble_forces(L);
  if (!L->o.one_way) {
    TL_CHECK(tl_stepper_step(L->stepper, k * dt));
    tl_solid_dofs_to_nodes(L->solid, L->stepper->u, L->u_nodes);
    tl_solid_dofs_to_nodes(L->solid, L->stepper->v, L->v_nodes);
    /* Work of the coupling forces, trapezoidal over the step. */
    double w = 0.0;
    for (size_t i = 0; i < nn; i++) w += 0.5 * (L->F_prev[i] + L->F_nodes[i]) * (L->u_nodes[i] - L->u_prev[i]);
    L->work_on_solid += w;
    /* The walls stay where the DEM used them: the next step moves them
     * before its DEM step does (onto the predictor, or from u_{n-1}), and
     * a restart places them on the state (loop_load).  Moving them here as
     * well cost 5 % of the S1 run. */
  }
  memcpy(L->u_back, L->u_prev, nn * sizeof(double));
  memcpy(L->u_prev, L->u_nodes, nn * sizeof(double));
  L->t += k * dt;
  return TL_OK;
}

TlStatus tl_coupled_loop_energy(TlCoupledLoop *L, TlCoupledEnergy *e)
{
  memset(e, 0, sizeof *e);
  TlDemEnergy d;
  TL_CHECK(tl_dem_energy(L->dem, &d));
  e->dem_kinetic = d.kinetic_translational + d.kinetic_rotational;
  e->dem_elastic = d.elastic;
  e->dem_gravitational = d.gravitational;
  TlEnergies f;
  TL_CHECK(tl_stepper_energies(L->stepper, &f));
  e->fem_kinetic = f.kinetic;
  e->fem_strain = f.strain;
  e->work_on_solid = L->work_on_solid;
  for (int c = 0; c < L->n_couplings; c++) e->work_on_particles += tl_scoupling_wall(L->couplings[c])->work;
  e->total = e->dem_kinetic + e->dem_elastic + e->dem_gravitational + e->fem_kinetic + e->fem_strain;
  if (!isfinite(e->total)) TL_ERROR(TL_ERR_NUMERIC, "coupled total energy is not finite at t = %g", L->t);
  return TL_OK;
}

double tl_coupled_loop_time(const TlCoupledLoop *L) { return L->t; }
const double *tl_coupled_loop_u_nodes(const TlCoupledLoop *L) { return L->u_nodes; }
const double *tl_coupled_loop_v_nodes(const TlCoupledLoop *L) { return L->v_nodes; }
const double *tl_coupled_loop_forces(const TlCoupledLoop *L) { return L->F_nodes; }
TlVec3 tl_coupled_loop_wall_force(const TlCoupledLoop *L) { return L->wall_force; }

/* ---- checkpoint: the couplings' per-face forces, the coupling forces of
 * the last step node-wise and their previous value (the trapezoidal work),
 * where lagged walls start the next step, the work so far, the time and the wall total; the solid's state comes
 * from the stepper's section and the walls' from the world's, both
 * restored before this one. */
static TlStatus loop_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlCoupledLoop *L = object;
  const size_t nn = 3 * L->n_nodes;
  double misc[5] = {L->t, L->work_on_solid, L->wall_force.x, L->wall_force.y, L->wall_force.z};
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "forces", nn, L->F_nodes));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "previous_forces", nn, L->F_prev));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "lagged_walls_start", nn, L->u_back));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "time_work_wall_force", 5, misc));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "substeps", L->o.substeps));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "one_way", L->o.one_way));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "scheme", L->o.scheme + 4 * L->o.average_forces));
  /* The per-face forces the SCoupling elements carry: the load of the next
   * FE step in the staggered schemes (which step the solid first). */
  TL_CHECK(tl_checkpoint_write_int64(w, group, "couplings", L->n_couplings));
  for (int c = 0; c < L->n_couplings; c++) {
    char prefix[32];
    snprintf(prefix, sizeof prefix, "coupling%d_", c);
    TL_CHECK(tl_scoupling_save_forces(L->couplings[c], w, group, prefix));
  }
  return TL_OK;
}

static TlStatus loop_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlCoupledLoop *L = object;
  const size_t nn = 3 * L->n_nodes;
  size_t n = 0;
  int64_t k = 0, one_way = 0;
  TL_CHECK(tl_checkpoint_length(r, group, "forces", &n));
  if (n != nn) TL_ERROR(TL_ERR_ARG, "checkpoint holds coupling forces for %zu node components, this solid has %zu", n, nn);
  TL_CHECK(tl_checkpoint_read_int64(r, group, "substeps", &k));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "one_way", &one_way));
  int64_t scheme = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "scheme", &scheme));
  if (scheme != L->o.scheme + 4 * L->o.average_forces)
    TL_ERROR(TL_ERR_ARG, "checkpoint was written with coupling scheme %lld, this run has %d", (long long)scheme, L->o.scheme);
  if (k != L->o.substeps || one_way != L->o.one_way)
    TL_ERROR(TL_ERR_ARG, "checkpoint was written with %lld DEM steps per FEM step and one_way = %lld, this run has %d and %d",
             (long long)k, (long long)one_way, L->o.substeps, L->o.one_way);
  int64_t nc = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "couplings", &nc));
  if (nc != L->n_couplings)
    TL_ERROR(TL_ERR_ARG, "checkpoint was written with %lld surface couplings, this run has %d", (long long)nc, L->n_couplings);
  for (int c = 0; c < L->n_couplings; c++) {
    char prefix[32];
    snprintf(prefix, sizeof prefix, "coupling%d_", c);
    TL_CHECK(tl_scoupling_load_forces(L->couplings[c], r, group, prefix));
  }
  double misc[5];
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "forces", nn, L->F_nodes));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "previous_forces", nn, L->F_prev));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "lagged_walls_start", nn, L->u_back));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "time_work_wall_force", 5, misc));
  L->t = misc[0];
  L->work_on_solid = misc[1];
  L->wall_force = tl_v3(misc[2], misc[3], misc[4]);
  tl_solid_dofs_to_nodes(L->solid, L->stepper->u, L->u_nodes);
  tl_solid_dofs_to_nodes(L->solid, L->stepper->v, L->v_nodes);
  memcpy(L->u_prev, L->u_nodes, nn * sizeof(double));
  TL_CHECK(move_walls(L, L->u_nodes, L->v_nodes));
  return TL_OK;
}

const TlCheckpointOps tl_coupled_loop_checkpoint_ops = {
    .header = {"checkpoint", "coupled_loop_v3", "surface-coupling loop: per-face and nodal coupling forces, lagged walls, work, time"},
    .save = loop_save,
    .load = loop_load,
};
