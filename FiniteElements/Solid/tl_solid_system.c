/* The solid as a TlMechSystem: the ops the steppers call. */
#include "tl_solid_private.h"

#include <math.h>
#include <string.h>

#include "tl_memory.h"

TlStatus tl_solid_internal_nodes(TlSolid *s, double t, const double *u, double *f_nodes, double c_u, TlSparse *K)
{
  tl_solid_dofs_to_nodes(s, u, s->un);
  if (f_nodes) memset(f_nodes, 0, s->n_nodes * s->dim * sizeof(double));
  for (int b = 0; b < s->mesh->n_blocks; ++b) TL_CHECK(tl_solid_block_evaluate(s, b, t, s->un, f_nodes, c_u, K, NULL));
  return TL_OK;
}

static TlStatus op_create_matrix(TlMechSystem *sys, int upper, TlSparse **K)
{
  TlSolid *s = (TlSolid *)sys;
  if (upper && !sys->symmetric)
    TL_ERROR(TL_ERR_ARG, "solid: upper-triangle storage asked for a non-symmetric system");
  TL_CHECK(tl_sparse_create_from_elements(sys->ndof, upper, (TlSparseIndex)s->n_pattern,
                                          s->elem_ptr, s->elem_dofs, 1, K));
  return TL_OK;
}

static TlStatus op_internal_force(TlMechSystem *sys, double t, const double *u, const double *v, double *f)
{
  (void)v;
  TlSolid *s = (TlSolid *)sys;
  TL_CHECK(tl_solid_internal_nodes(s, t, u, s->fn, 0.0, NULL));
  tl_solid_nodes_to_dofs(s, s->fn, f);
  return TL_OK;
}

static TlStatus op_internal_tangent(TlMechSystem *sys, double t, const double *u, const double *v,
                                    double c_u, double c_v, TlSparse *K)
{
  (void)v, (void)c_v;
  TlSolid *s = (TlSolid *)sys;
  TL_CHECK(tl_solid_internal_nodes(s, t, u, NULL, c_u, K));
  return TL_OK;
}

static TlStatus op_external_force(TlMechSystem *sys, double t, const double *u, double *f)
{
  TlSolid *s = (TlSolid *)sys;
  TL_CHECK(tl_solid_external_nodes(s, t, u, s->gn));
  tl_solid_nodes_to_dofs(s, s->gn, f);
  return TL_OK;
}

static TlStatus op_external_tangent(TlMechSystem *sys, double t, const double *u, double c, TlSparse *K)
{
  TlSolid *s = (TlSolid *)sys;
  tl_solid_dofs_to_nodes(s, u, s->un);
  TL_CHECK(tl_solid_pressure_loads(s, t, s->un, NULL, c, K));
  TL_CHECK(tl_solid_wrapper_loads(s, t, s->un, NULL, c, K));
  return TL_OK;
}

static TlStatus op_lumped_mass(TlMechSystem *sys, double *m)
{
  TlSolid *s = (TlSolid *)sys;
  tl_solid_nodes_to_dofs(s, s->lumped_nodes, m);
  return TL_OK;
}

/* Consistent mass of element e of block b: Me[a][b] = int rho N_a N_b. */
void tl_solid_element_mass(const TlSolid *s, int b, size_t e, double *Mab)
{
  const SolidBlock *B = &s->blocks[b];
  int nn = B->nn;
  double rho = B->material->density;
  memset(Mab, 0, (size_t)nn * nn * sizeof(double));
  for (int p = 0; p < B->qm.n; ++p) {
    double w = rho * B->wdetm[e * B->qm.n + p];
    const double *N = B->Nm + p * nn;
    for (int a = 0; a < nn; ++a)
      for (int c = 0; c < nn; ++c) Mab[a * nn + c] += w * N[a] * N[c];
  }
}

static TlStatus op_consistent_mass(TlMechSystem *sys, double c, TlSparse *M)
{
  TlSolid *s = (TlSolid *)sys;
  int dim = s->dim;
  int indexed = M->elem_pos_ptr && M->n_elements == (TlSparseIndex)s->n_pattern;
  double *Mab = s->scratch[0].DB, *Me = s->scratch[0].Ke; /* DB sized max(6 nd, nn^2) */
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    const SolidBlock *B = &s->blocks[b];
    int nn = B->nn, nd = B->nd;
    for (size_t e = 0; e < s->mesh->blocks[b].n_elements; ++e) {
      tl_solid_element_mass(s, b, e, Mab);
      memset(Me, 0, (size_t)nd * nd * sizeof(double));
      for (int a = 0; a < nn; ++a)
        for (int q = 0; q < nn; ++q)
          for (int i = 0; i < dim; ++i) Me[(a * dim + i) * nd + q * dim + i] = Mab[a * nn + q];
      size_t g = B->offset + e;
      if (indexed) TL_CHECK(tl_sparse_add_element_indexed(M, (TlSparseIndex)g, c, Me));
      else TL_CHECK(tl_sparse_add_element(M, nd, s->elem_dofs + s->elem_ptr[g], c, Me));
    }
  }
  return TL_OK;
}

static TlStatus op_dirichlet(TlMechSystem *sys, double t, double *u, double *v, double *a)
{
  TlSolid *s = (TlSolid *)sys;
  for (size_t i = 0; i < s->n_prescribed; ++i) {
    const Prescribed *p = &s->prescribed[i];
    double out[3] = {0, 0, 0};
    p->fn(t, s->mesh->x + 3 * p->node, p->component, p->ctx, out);
    for (int k = 0; k < 3; ++k)
      if (!isfinite(out[k]))
        TL_ERROR(TL_ERR_NUMERIC, "solid: prescribed value %d of node %zu component %d at t = %g is %g", k,
                 p->node, p->component, t, out[k]);
    TlSparseIndex d = s->dof[p->node * s->dim + p->component];
    if (u) u[d] = out[0];
    if (v) v[d] = out[1];
    if (a) a[d] = out[2];
  }
  return TL_OK;
}

TlStatus tl_solid_strain_energy(TlSolid *s, const double *u, double *W)
{
  tl_solid_dofs_to_nodes(s, u, s->un);
  *W = 0.0;
  for (int b = 0; b < s->mesh->n_blocks; ++b) TL_CHECK(tl_solid_block_evaluate(s, b, NAN, s->un, NULL, 0.0, NULL, W));
  return TL_OK;
}

static TlStatus op_strain_energy(TlMechSystem *sys, const double *u, double *W)
{
  return tl_solid_strain_energy((TlSolid *)sys, u, W);
}

static TlStatus op_commit(TlMechSystem *sys)
{
  TlSolid *s = (TlSolid *)sys;
  tl_solid_points_invalidate(s);
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    size_t ss = B->material->state_size, np = s->mesh->blocks[b].n_elements * B->nq;
    if (ss) {
      double *tmp = B->state_old;
      B->state_old = B->state_new;
      B->state_new = tmp;
      memcpy(B->state_new, B->state_old, np * ss * sizeof(double));
    }
    if (B->material->ops->commit) TL_CHECK(B->material->ops->commit(B->material, np, B->state_old));
  }
  return TL_OK;
}

static TlStatus op_rollback(TlMechSystem *sys)
{
  TlSolid *s = (TlSolid *)sys;
  tl_solid_points_invalidate(s);
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    size_t ss = B->material->state_size, np = s->mesh->blocks[b].n_elements * B->nq;
    if (ss) memcpy(B->state_new, B->state_old, np * ss * sizeof(double));
    if (B->material->ops->rollback) TL_CHECK(B->material->ops->rollback(B->material, np, B->state_old));
  }
  return TL_OK;
}

/* Element-by-element estimate of the largest eigenvalue of M^-1 K: the
 * largest element eigenvalue of M_e^-1/2 K_e M_e^-1/2 (the element
 * eigenvalue theorem makes it an upper bound of the assembled one),
 * estimated from above as described below. */
static TlStatus op_max_frequency_squared(TlMechSystem *sys, const double *u, double *omega2)
{
  TlSolid *s = (TlSolid *)sys;
  tl_solid_dofs_to_nodes(s, u, s->un);
  double best = 0.0;
  double *ue = NULL, *Ke = NULL;
  TL_CHECK(tl_calloc(&ue, s->max_nd, sizeof(double)));
  TlStatus st = tl_calloc(&Ke, (size_t)s->max_nd * s->max_nd, sizeof(double));
  for (int b = 0; b < s->mesh->n_blocks && st == TL_OK; ++b) {
    const TlElementBlock *blk = &s->mesh->blocks[b];
    const SolidBlock *B = &s->blocks[b];
    int nn = B->nn, nd = B->nd, dim = s->dim;
    for (size_t e = 0; e < blk->n_elements && st == TL_OK; ++e) {
      for (int a = 0; a < nn; ++a)
        for (int i = 0; i < dim; ++i) ue[a * dim + i] = s->un[blk->conn[e * nn + a] * dim + i];
      int massless = 0;
      for (int a = 0; a < nn; ++a) massless |= !(B->lumped[e * nn + a] > 0.0);
      if (massless) continue; /* weighted out: no mass, no stiffness of its own */
      st = tl_solid_element_matrices(s, b, e, ue, NULL, Ke, NULL);
      if (st != TL_OK) break;
      /* A = M^-1/2 K M^-1/2 (similar to M^-1 K).  Gershgorin bounds its
       * largest eigenvalue; for a symmetric tangent power iterations
       * tighten it: the Rayleigh quotient rho plus the residual norm |r|
       * brackets the top eigenvalue once converged, and is capped by the
       * Gershgorin bound. */
      double gersh = 0.0;
      for (int r = 0; r < nd; ++r) {
        double row = 0.0, sr = 1.0 / sqrt(B->lumped[e * nn + r / dim]);
        for (int c = 0; c < nd; ++c) {
          Ke[r * nd + c] *= sr / sqrt(B->lumped[e * nn + c / dim]);
          row += fabs(Ke[r * nd + c]);
        }
        gersh = fmax(gersh, row);
      }
      double lam = gersh;
      if (B->symmetric) {
        double *x = ue, y[3 * TL_ELEMENT_MAX_NODES], rho = 0.0, res = 0.0;
        for (int r = 0; r < nd; ++r) x[r] = 1.0 + 0.5 * sin(1.7 * r + 0.3);
        for (int it = 0; it < 60; ++it) {
          double nx = 0.0;
          for (int r = 0; r < nd; ++r) nx += x[r] * x[r];
          nx = 1.0 / sqrt(nx);
          for (int r = 0; r < nd; ++r) x[r] *= nx;
          rho = 0.0;
          for (int r = 0; r < nd; ++r) {
            double a = 0.0;
            for (int c = 0; c < nd; ++c) a += Ke[r * nd + c] * x[c];
            y[r] = a;
            rho += x[r] * a;
          }
          res = 0.0;
          for (int r = 0; r < nd; ++r) res += (y[r] - rho * x[r]) * (y[r] - rho * x[r]);
          res = sqrt(res);
          for (int r = 0; r < nd; ++r) x[r] = y[r];
          if (res <= 1e-3 * rho) break;
        }
        lam = fmin(gersh, rho + res);
      }
      best = fmax(best, lam);
    }
  }
  tl_free(&ue);
  tl_free(&Ke);
  if (st != TL_OK) return tl_error_trace(st, __FILE__, __LINE__);
  *omega2 = best;
  return TL_OK;
}

/* The solid's ops, with and without commit and rollback (see setup). */
#define SOLID_OPS_COMMON                                                                    \
  .header = {"mech_system", "solid", "total-Lagrangian finite-strain solid"},               \
  .create_matrix = op_create_matrix, .internal_force = op_internal_force,                  \
  .internal_tangent = op_internal_tangent, .external_force = op_external_force,            \
  .lumped_mass = op_lumped_mass, .external_tangent = op_external_tangent,                  \
  .consistent_mass = op_consistent_mass, .dirichlet = op_dirichlet,                        \
  .strain_energy = op_strain_energy, .max_frequency_squared = op_max_frequency_squared,    \
  .checkpoint = &tl_solid_checkpoint_ops, .destroy = tl_solid_destroy_content

const TlMechSystemOps tl_solid_ops_stateful = {SOLID_OPS_COMMON, .commit = op_commit, .rollback = op_rollback};
const TlMechSystemOps tl_solid_ops_elastic = {SOLID_OPS_COMMON};
#undef SOLID_OPS_COMMON
