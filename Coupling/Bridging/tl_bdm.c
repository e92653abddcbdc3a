/* The bridging domain coupling (seeds/000 §2): weights of both models, the
 * interpolation matrix N at the reference centres, and the Lagrange
 * velocity correction after each explicit step with its report. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "tl_bdm_private.h"
#include "tl_element.h"
#include "tl_memory.h"
#include "tl_mesh_locator.h"
#include "tl_timer.h"

/* alpha of the masses (clamped inside a zone: the correction divides by
 * the weighted masses) and of the forces (the continuous profile: a clamp
 * would make a contact's weight jump by alpha_min where its contact point
 * crosses a zone's end, a kick the light particles there cannot take). */
static double alpha_mass(const TlBdm *b, const double x[3])
{
  return tl_bdm_alpha(b->zones, b->n_zones, b->opt.profile, b->opt.alpha_min, x);
}
static double alpha_force(const TlBdm *b, const double x[3])
{
  return tl_bdm_alpha(b->zones, b->n_zones, b->opt.profile, 0.0, x);
}

/* The DEM's weight field: at the particle centres (the world passes
 * P->x) the reference weight 1 - alpha(X_i) of each particle, by id, so a
 * particle's weighted mass is constant (particles inserted after the
 * coupling was built: at the current centre); at contact points 1 - alpha
 * of the continuous profile at the current point. */
static TlStatus dem_weight(void *ctx, size_t n, const TlVec3 *x, double *w)
{
  TlBdm *b = ctx;
  const TlParticles *P = tl_dem_particles(b->dem);
  const int centres = x == P->x && n == P->n;
  for (size_t i = 0; i < n; ++i) {
    if (centres) {
      int64_t id = P->id[i];
      size_t slot = id >= 0 && id < b->id_cap ? b->slot_of_id[id] : SIZE_MAX;
      if (slot != SIZE_MAX) {
        w[i] = b->ref_w[slot];
        continue;
      }
    }
    const double p[3] = {x[i].x, x[i].y, x[i].z};
    w[i] = 1.0 - (centres ? alpha_mass(b, p) : alpha_force(b, p));
  }
  return TL_OK;
}

/* X shifted by whole periods of the DEM's periodic box into the mesh's
 * section [lo, lo + L) along each periodic direction. */
static TlVec3 wrap_to_section(const TlDomain *d, const double lo[3], TlVec3 X)
{
  double *c = &X.x;
  if (d->kind != TL_DOMAIN_PERIODIC_BOX) return X;
  for (int k = 0; k < 3; ++k)
    if (d->periodic[k]) {
      double L = d->h.m[k][k];
      c[k] -= L * floor((c[k] - lo[k]) / L);
    }
  return X;
}

static TlStatus check_zones(const TlBdmZone *zones, int n)
{
  if (n < 1 || n > TL_BDM_MAX_ZONES) TL_ERROR(TL_ERR_ARG, "bdm: %d zones, expected 1 to %d", n, TL_BDM_MAX_ZONES);
  for (int z = 0; z < n; ++z) {
    const TlBdmZone *Z = &zones[z];
    if (Z->axis < 0 || Z->axis > 2) TL_ERROR(TL_ERR_ARG, "bdm: zone %d axis %d outside [0, 2]", z, Z->axis);
    if (!isfinite(Z->s_dem) || !isfinite(Z->s_fe) || !(fabs(Z->s_fe - Z->s_dem) > 0.0))
      TL_ERROR(TL_ERR_ARG, "bdm: zone %d from s_dem = %g to s_fe = %g is empty or not finite", z, Z->s_dem, Z->s_fe);
    for (int y = 0; y < z; ++y) {
      const TlBdmZone *Y = &zones[y];
      if (Y->axis != Z->axis) continue;
      double a0 = fmin(Z->s_dem, Z->s_fe), a1 = fmax(Z->s_dem, Z->s_fe);
      double b0 = fmin(Y->s_dem, Y->s_fe), b1 = fmax(Y->s_dem, Y->s_fe);
      if (a0 < b1 && b0 < a1)
        TL_ERROR(TL_ERR_ARG, "bdm: zones %d [%g, %g] and %d [%g, %g] overlap", y, b0, b1, z, a0, a1);
    }
  }
  return TL_OK;
}

/* FE weights: alpha at the block's stiffness points (and at its mass points
 * for quadrature mass weighting), the nodal alpha on the lumped mass. */
static TlStatus set_fe_weights(TlBdm *b)
{
  const TlMesh *mesh = tl_solid_mesh(b->solid);
  const TlElementBlock *blk = &mesh->blocks[b->block];
  const TlElementType *t = blk->type;
  for (size_t I = 0; I < mesh->n_nodes; ++I) b->alpha_nodes[I] = alpha_mass(b, mesh->x + 3 * I);
  TlQuadrature q, qm;
  TL_CHECK(tl_element_quadrature(t, t->order_stiffness, &q));
  TL_CHECK(tl_element_quadrature(t, t->order_mass, &qm));
  size_t ne = blk->n_elements;
  double *w = NULL, *wm = NULL, *xe = NULL;
  TlStatus s = tl_calloc(&w, ne * q.n + 1, sizeof *w);
  if (s == TL_OK) s = tl_calloc(&wm, ne * qm.n + 1, sizeof *wm);
  if (s == TL_OK) s = tl_calloc(&xe, 3 * (size_t)t->n_nodes, sizeof *xe);
  for (size_t e = 0; e < ne && s == TL_OK; ++e) {
    for (int a = 0; a < t->n_nodes; ++a) memcpy(xe + 3 * a, mesh->x + 3 * blk->conn[e * t->n_nodes + a], 3 * sizeof *xe);
    for (int p = 0; p < q.n; ++p) {
      double xp[3];
      tl_element_interpolate(t, xe, q.xi[p], xp);
      w[e * q.n + p] = alpha_force(b, xp);
    }
    for (int p = 0; p < qm.n; ++p) {
      double xp[3];
      tl_element_interpolate(t, xe, qm.xi[p], xp);
      wm[e * qm.n + p] = b->opt.mass_weight == TL_BDM_MASS_QUADRATURE ? alpha_mass(b, xp) : 1.0;
    }
  }
  if (s == TL_OK) s = tl_solid_set_point_weights(b->solid, b->block, w, wm);
  if (s == TL_OK && b->opt.mass_weight == TL_BDM_MASS_NODAL) {
    for (size_t I = 0; I < mesh->n_nodes && s == TL_OK; ++I)
      if (!(b->alpha_nodes[I] > 0.0))
        s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                         "bdm: mesh node %zu at (%g, %g, %g) lies on the DEM side of every zone (alpha = 0), so its "
                         "weighted mass alpha M would vanish: the FE must end at a zone's s_dem",
                         I, mesh->x[3 * I], mesh->x[3 * I + 1], mesh->x[3 * I + 2]);
    if (s == TL_OK) s = tl_solid_set_lumped_mass_weights(b->solid, b->alpha_nodes);
  }
  tl_free(&w);
  tl_free(&wm);
  tl_free(&xe);
  return s;
}

TlStatus tl_bdm_create(TlSolid *solid, int block, TlDem *dem, const TlBdmZone *zones, int n_zones,
                       const TlBdmOptions *opt, TlBdm **out)
{
  *out = NULL;
  if (!solid || !dem || !zones || !opt) TL_ERROR(TL_ERR_ARG, "bdm: NULL solid, DEM, zones or options");
  TL_CHECK(tl_bdm_options_check(opt));
  TL_CHECK(check_zones(zones, n_zones));
  const TlMesh *mesh = tl_solid_mesh(solid);
  if (mesh->dim != 3) TL_ERROR(TL_ERR_UNSUPPORTED, "bdm: the mesh is %d-D; the coupling needs a 3-D mesh", mesh->dim);
  if (block < 0 || block >= mesh->n_blocks) TL_ERROR(TL_ERR_ARG, "bdm: block %d outside [0, %d)", block, mesh->n_blocks);
  if (tl_dem_n_walls(dem) > 0)
    TL_ERROR(TL_ERR_UNSUPPORTED, "bdm: the DEM world has %zu walls; a weighted world cannot have walls",
             tl_dem_n_walls(dem));
  const TlDomain *dom = tl_dem_domain(dem);
  if (dom->kind == TL_DOMAIN_DEFORMABLE_CELL)
    TL_ERROR(TL_ERR_UNSUPPORTED, "bdm: the DEM domain is a deformable cell; the coupling needs an open or periodic box");
  TlBdm *b;
  TL_CHECK(TL_NEW(b));
  b->solid = solid;
  b->block = block;
  b->dem = dem;
  b->opt = *opt;
  b->n_zones = n_zones;
  memcpy(b->zones, zones, (size_t)n_zones * sizeof *zones);
  const TlParticles *P = tl_dem_particles(dem);
  TlStatus s = TL_OK;
  /* reference positions by id, wrapped into the mesh's section */
  double lo[3] = {INFINITY, INFINITY, INFINITY};
  for (size_t I = 0; I < mesh->n_nodes; ++I)
    for (int k = 0; k < 3; ++k) lo[k] = fmin(lo[k], mesh->x[3 * I + k]);
  b->n_ref = P->n;
  b->id_cap = P->next_id > 0 ? P->next_id : 1;
  TL_CHECK_GOTO(s, tl_calloc(&b->ref_id, P->n + 1, sizeof *b->ref_id), fail);
  TL_CHECK_GOTO(s, tl_calloc(&b->ref_x, P->n + 1, sizeof *b->ref_x), fail);
  TL_CHECK_GOTO(s, tl_calloc(&b->ref_w, P->n + 1, sizeof *b->ref_w), fail);
  TL_CHECK_GOTO(s, tl_calloc(&b->slot_of_id, (size_t)b->id_cap, sizeof *b->slot_of_id), fail);
  TL_CHECK_GOTO(s, tl_calloc(&b->index_of_id, (size_t)b->id_cap, sizeof *b->index_of_id), fail);
  TL_CHECK_GOTO(s, tl_calloc(&b->alpha_nodes, mesh->n_nodes + 1, sizeof *b->alpha_nodes), fail);
  for (int64_t id = 0; id < b->id_cap; ++id) b->slot_of_id[id] = SIZE_MAX;
  for (size_t i = 0; i < P->n; ++i) {
    if (P->id[i] < 0 || P->id[i] >= b->id_cap) {
      s = tl_error_set(TL_ERR_STATE, __FILE__, __LINE__, "bdm: particle id %lld outside [0, %lld)",
                       (long long)P->id[i], (long long)b->id_cap);
      goto fail;
    }
    b->ref_id[i] = P->id[i];
    b->ref_x[i] = wrap_to_section(dom, lo, P->x[i]);
    b->slot_of_id[P->id[i]] = i;
    const double X[3] = {b->ref_x[i].x, b->ref_x[i].y, b->ref_x[i].z};
    b->ref_w[i] = 1.0 - alpha_mass(b, X);
    if (!(b->ref_w[i] > 0.0)) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "bdm: particle id %lld at (%g, %g, %g) lies on the FE side of a zone (alpha = 1), so its "
                       "weighted mass (1 - alpha) m would vanish: the DEM must end at a zone's s_fe",
                       (long long)P->id[i], X[0], X[1], X[2]);
      goto fail;
    }
  }
  TL_CHECK_GOTO(s, set_fe_weights(b), fail);
  tl_dem_set_weight_field(dem, dem_weight, b);
  *out = b;
  return TL_OK;
fail:
  tl_bdm_destroy(&b);
  return s;
}

void tl_bdm_destroy(TlBdm **pb)
{
  TlBdm *b = *pb;
  if (!b) return;
  if (b->wrapper) tl_solid_remove_wrapper(b->solid, &b->wrapper);
  tl_bdm_system_destroy(&b->sys);
  void *arr[] = {&b->ref_id, &b->ref_x, &b->ref_w, &b->slot_of_id, &b->index_of_id, &b->alpha_nodes, &b->c_slot,
                 &b->c_idx, &b->g_slot, &b->g_idx, &b->ptr, &b->dof, &b->phi, &b->m_q, &b->fixed, &b->comp, &b->v_q, &b->v_q0, &b->gdot,
                 &b->mu, &b->g_w, &b->v_dof0, &b->ghost_fe, &b->ghost_dem};
  for (size_t k = 0; k < sizeof arr / sizeof arr[0]; ++k) tl_free(arr[k]);
  tl_free(pb);
}

/* Current indices of a list of particles (reference slots): checked
 * cheaply each step, rebuilt through an id table when the world renumbered
 * them. */
static TlStatus remap_list(TlBdm *b, size_t n, const size_t *slot, size_t *idx, int *table_built)
{
  const TlParticles *P = tl_dem_particles(b->dem);
  int ok = 1;
  for (size_t k = 0; k < n && ok; ++k) ok = idx[k] < P->n && P->id[idx[k]] == b->ref_id[slot[k]];
  if (ok) return TL_OK;
  if (!*table_built) {
    for (int64_t id = 0; id < b->id_cap; ++id) b->index_of_id[id] = SIZE_MAX;
    for (size_t i = 0; i < P->n; ++i)
      if (P->id[i] >= 0 && P->id[i] < b->id_cap) b->index_of_id[P->id[i]] = i;
    *table_built = 1;
  }
  for (size_t k = 0; k < n; ++k) {
    int64_t id = b->ref_id[slot[k]];
    size_t i = b->index_of_id[id];
    if (i == SIZE_MAX)
      TL_ERROR(TL_ERR_STATE, "bdm: coupled particle id %lld is no longer in the DEM world", (long long)id);
    idx[k] = i;
  }
  return TL_OK;
}

TlStatus tl_bdm_remap(TlBdm *b)
{
  int built = 0;
  TL_CHECK(remap_list(b, b->n_c, b->c_slot, b->c_idx, &built));
  if (b->n_g) TL_CHECK(remap_list(b, b->n_g, b->g_slot, b->g_idx, &built));
  return TL_OK;
}

/* N at the reference centres of the free particles inside a zone. */
static TlStatus build_operator(TlBdm *b)
{
  const TlMesh *mesh = tl_solid_mesh(b->solid);
  const TlParticles *P = tl_dem_particles(b->dem);
  const TlElementType *t = mesh->blocks[b->block].type;
  const int nn = t->n_nodes;
  TlMeshLocator *loc = NULL;
  TL_CHECK(tl_mesh_locator_create(mesh, NULL, &loc));
  TlStatus s = TL_OK;
  size_t cap = b->n_ref ? b->n_ref : 1;
  s = tl_calloc(&b->c_slot, cap, sizeof *b->c_slot);
  if (s == TL_OK) s = tl_calloc(&b->c_idx, cap, sizeof *b->c_idx);
  if (s == TL_OK) s = tl_calloc(&b->ptr, 3 * cap + 1, sizeof *b->ptr);
  if (s == TL_OK) s = tl_calloc(&b->dof, 3 * cap * (size_t)nn, sizeof *b->dof);
  if (s == TL_OK) s = tl_calloc(&b->phi, 3 * cap * (size_t)nn, sizeof *b->phi);
  if (s == TL_OK) s = tl_calloc(&b->m_q, 3 * cap, sizeof *b->m_q);
  double N[64];
  size_t k = 0, e = 0;
  for (size_t i = 0; i < P->n && s == TL_OK; ++i) {
    int64_t id = P->id[i];
    size_t slot = id >= 0 && id < b->id_cap ? b->slot_of_id[id] : SIZE_MAX;
    if (slot == SIZE_MAX) continue; /* inserted after the coupling was built */
    const double X[3] = {b->ref_x[slot].x, b->ref_x[slot].y, b->ref_x[slot].z};
    int in_zone = 0;
    for (int z = 0; z < b->n_zones; ++z) {
      const TlBdmZone *Z = &b->zones[z];
      double a0 = fmin(Z->s_dem, Z->s_fe), a1 = fmax(Z->s_dem, Z->s_fe);
      in_zone |= X[Z->axis] >= a0 && X[Z->axis] <= a1;
    }
    if (!in_zone) continue;
    if (P->motion[i] != TL_MOTION_FREE) {
      b->n_excluded++;
      continue;
    }
    TlFaceRef where;
    double xi[3];
    TlStatus ls = tl_mesh_locate(loc, X, b->opt.locate_tol, &where, xi);
    if (ls != TL_OK || where.block != b->block) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "bdm: particle id %lld at reference (%g, %g, %g), inside a bridging zone, lies %s of the "
                       "coupled mesh block %d (tolerance %g)", (long long)id, X[0], X[1], X[2],
                       ls != TL_OK ? "outside every element" : "in another block than that", b->block,
                       b->opt.locate_tol);
      break;
    }
    t->eval(1, xi, N, NULL);
    const size_t *conn = mesh->blocks[b->block].conn + where.element * (size_t)nn;
    double mbar = b->ref_w[slot] * P->mass[i];
    for (int c = 0; c < 3; ++c) {
      size_t q = 3 * k + (size_t)c;
      b->ptr[q] = e;
      for (int a = 0; a < nn; ++a) {
        TlSparseIndex J = tl_solid_dof(b->solid, conn[a], c);
        if (J < 0 || N[a] == 0.0) continue; /* clamped: no velocity to interpolate */
        b->dof[e] = J;
        b->phi[e++] = N[a];
      }
      b->m_q[q] = mbar;
    }
    b->c_slot[k] = slot;
    b->c_idx[k] = i;
    ++k;
  }
  b->n_c = k;
  if (s == TL_OK) b->ptr[3 * k] = e;
  tl_mesh_locator_destroy(&loc);
  TL_CHECK(s);
  if (k == 0)
    TL_ERROR(TL_ERR_ARG, "bdm: no free particle lies in the bridging zones (%d zones, %zu particles at creation)",
             b->n_zones, b->n_ref);
  return TL_OK;
}

TlStatus tl_bdm_setup(TlBdm *b, TlStepper *st)
{
  if (b->ready) TL_ERROR(TL_ERR_STATE, "bdm: set up twice");
  if (!st || st->ops->implicit)
    TL_ERROR(TL_ERR_ARG, "bdm: the FE stepper must be explicit (its lumped mass is the FE side of the correction)%s%s",
             st ? ": got " : "", st ? st->ops->header.name : "");
  double t0 = tl_wtime();
  b->st = st;
  TL_CHECK(build_operator(b));
  const TlSparseIndex nd = st->n;
  TL_CHECK(tl_calloc(&b->fixed, (size_t)nd + 1, 1));
  TL_CHECK(tl_calloc(&b->comp, (size_t)nd + 1, sizeof *b->comp));
  const TlMechSystem *sys = st->sys;
  for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) b->fixed[sys->dirichlet_dofs[k]] = 1;
  const TlMesh *mesh = tl_solid_mesh(b->solid);
  for (size_t I = 0; I < mesh->n_nodes; ++I)
    for (int c = 0; c < 3; ++c) {
      TlSparseIndex J = tl_solid_dof(b->solid, I, c);
      if (J >= 0) b->comp[J] = c;
    }
  TlBdmOperator op = {3 * b->n_c, b->ptr, b->dof, b->phi, b->m_q, nd, st->m, b->fixed};
  TL_CHECK(tl_bdm_system_create(&op, b->opt.constraint, b->opt.lumping, b->opt.jacobi, &b->sys));
  size_t nq = 3 * b->n_c;
  TL_CHECK(tl_calloc(&b->v_q, nq, sizeof *b->v_q));
  TL_CHECK(tl_calloc(&b->v_q0, nq, sizeof *b->v_q0));
  TL_CHECK(tl_calloc(&b->gdot, nq, sizeof *b->gdot));
  TL_CHECK(tl_calloc(&b->mu, nq, sizeof *b->mu));
  TL_CHECK(tl_calloc(&b->g_w, (size_t)nd + 1, sizeof *b->g_w));
  TL_CHECK(tl_calloc(&b->v_dof0, (size_t)nd + 1, sizeof *b->v_dof0));
  TL_CHECK(tl_bdm_ghost_setup(b));
  b->ready = 1;
  b->t_setup = tl_wtime() - t0;
  return TL_OK;
}

static double amax(double a, double x)
{
  double f = fabs(x);
  return f > a || f != f ? (f != f ? INFINITY : f) : a;
}

/* Weighted momentum of every free FE dof and every free particle. */
static void total_momentum(const TlBdm *b, double P3[3])
{
  const TlStepper *st = b->st;
  P3[0] = P3[1] = P3[2] = 0.0;
  for (TlSparseIndex J = 0; J < st->n; ++J)
    if (!b->fixed[J]) P3[b->comp[J]] += st->m[J] * st->v[J];
  const TlParticles *P = tl_dem_particles(b->dem);
  for (size_t i = 0; i < P->n; ++i) {
    if (P->motion[i] != TL_MOTION_FREE) continue;
    double m = P->mass[i] * (P->weight ? P->weight[i] : 1.0);
    P3[0] += m * P->v[i].x;
    P3[1] += m * P->v[i].y;
    P3[2] += m * P->v[i].z;
  }
}

/* The diagnostics of the current state (after a correction): constraint
 * rates, the displacement residual and the total weighted momentum. */
static void diagnose(TlBdm *b)
{
  const TlParticles *P = tl_dem_particles(b->dem);
  const TlStepper *st = b->st;
  const size_t nq = 3 * b->n_c;
  b->last.rate_after = b->last.rate_weak_after = b->last.residual_max = 0.0;
  if (tl_bdm_remap(b) != TL_OK) { /* a coupled particle was removed: nothing to measure */
    b->last.rate_after = b->last.rate_weak_after = b->last.residual_max = b->last.residual_rms = NAN;
    return;
  }
  for (size_t k = 0; k < b->n_c; ++k) {
    const TlVec3 v = P->v[b->c_idx[k]];
    b->v_q[3 * k] = v.x;
    b->v_q[3 * k + 1] = v.y;
    b->v_q[3 * k + 2] = v.z;
  }
  tl_bdm_system_rate(b->sys, st->v, b->v_q, b->gdot);
  for (size_t q = 0; q < nq; ++q) b->last.rate_after = amax(b->last.rate_after, b->gdot[q]);
  size_t n_rows;
  tl_bdm_system_rows(b->sys, &n_rows);
  if (n_rows) { /* the weak constraint's own rate (0 for the strong one) */
    tl_bdm_system_weak_rate(b->sys, b->gdot, b->g_w);
    for (size_t k = 0; k < n_rows; ++k) b->last.rate_weak_after = amax(b->last.rate_weak_after, b->g_w[k]);
  }
  /* displacement residual g = N^T u - d, d unwrapped to the nearest image */
  const TlDomain *dom = tl_dem_domain(b->dem);
  for (size_t k = 0; k < b->n_c; ++k) {
    TlVec3 d = tl_domain_branch(dom, b->ref_x[b->c_slot[k]], P->x[b->c_idx[k]]);
    b->v_q0[3 * k] = d.x;
    b->v_q0[3 * k + 1] = d.y;
    b->v_q0[3 * k + 2] = d.z;
  }
  tl_bdm_system_rate(b->sys, st->u, b->v_q0, b->gdot);
  double ss = 0.0;
  for (size_t q = 0; q < nq; ++q) {
    b->last.residual_max = amax(b->last.residual_max, b->gdot[q]);
    ss += b->gdot[q] * b->gdot[q];
  }
  b->last.residual_rms = sqrt(ss / (double)nq);
  total_momentum(b, b->last.momentum);
  b->state_diagnosed = 1;
}

TlStatus tl_bdm_correct(TlBdm *b, TlBdmReport *rep)
{
  if (!b->ready) TL_ERROR(TL_ERR_STATE, "bdm: tl_bdm_setup must precede tl_bdm_correct");
  double t0 = tl_wtime();
  TL_CHECK(tl_bdm_remap(b));
  TlParticles *P = tl_dem_particles(b->dem);
  TlStepper *st = b->st;
  const size_t nq = 3 * b->n_c;
  for (size_t k = 0; k < b->n_c; ++k) {
    const TlVec3 v = P->v[b->c_idx[k]];
    b->v_q[3 * k] = v.x;
    b->v_q[3 * k + 1] = v.y;
    b->v_q[3 * k + 2] = v.z;
  }
  memcpy(b->v_q0, b->v_q, nq * sizeof *b->v_q);
  size_t n_free;
  const TlSparseIndex *free_dofs = tl_bdm_system_free_dofs(b->sys, &n_free);
  for (size_t f = 0; f < n_free; ++f) b->v_dof0[f] = st->v[free_dofs[f]];
  tl_bdm_system_rate(b->sys, st->v, b->v_q, b->gdot);
  TL_CHECK(tl_bdm_system_solve(b->sys, b->gdot, b->mu));
  tl_bdm_system_apply(b->sys, b->mu, st->v, b->v_q);
  for (size_t k = 0; k < b->n_c; ++k)
    P->v[b->c_idx[k]] = (TlVec3){b->v_q[3 * k], b->v_q[3 * k + 1], b->v_q[3 * k + 2]};
  /* the report: rates, energy and momentum of what changed, residual */
  TlBdmReport r = {0};
  double dK = 0.0, dP[3] = {0, 0, 0}, vs = 0.0;
  for (size_t q = 0; q < nq; ++q) {
    r.rate_before = amax(r.rate_before, b->gdot[q]);
    vs = amax(vs, b->v_q0[q]);
    double m = b->m_q[q], v0 = b->v_q0[q], v1 = b->v_q[q];
    dK += 0.5 * m * (v0 - v1) * (v0 + v1);
    dP[q % 3] += m * (v1 - v0);
  }
  for (size_t f = 0; f < n_free; ++f) {
    TlSparseIndex J = free_dofs[f];
    double m = st->m[J], v0 = b->v_dof0[f], v1 = st->v[J];
    vs = amax(vs, v0);
    dK += 0.5 * m * (v0 - v1) * (v0 + v1);
    dP[b->comp[J]] += m * (v1 - v0);
  }
  r.velocity_scale = vs;
  for (int c = 0; c < 3; ++c) r.momentum_change[c] = dP[c];
  r.energy_removed = dK;
  b->removed_total += dK;
  r.energy_removed_total = b->removed_total;
  r.step = ++b->steps;
  b->last = r;
  b->state_diagnosed = 0;
  if (rep) {
    diagnose(b);
    *rep = b->last;
  }
  b->t_correct += tl_wtime() - t0;
  return TL_OK;
}

void tl_bdm_last_report(TlBdm *b, TlBdmReport *rep)
{
  if (b->ready && b->steps > 0 && !b->state_diagnosed) diagnose(b);
  *rep = b->last;
}

void tl_bdm_info(const TlBdm *b, TlBdmInfo *info)
{
  memset(info, 0, sizeof *info);
  info->n_particles = b->n_c;
  info->n_constraints = 3 * b->n_c;
  info->n_excluded = b->n_excluded;
  info->n_ghost_particles = b->n_g;
  if (b->sys) {
    tl_bdm_system_free_dofs(b->sys, &info->n_dofs);
    tl_bdm_system_rows(b->sys, &info->n_rows_weak);
  }
  info->n_nonzeros = b->ptr ? b->ptr[3 * b->n_c] : 0;
  info->t_setup = b->t_setup;
  info->t_correct = b->t_correct;
}

const double *tl_bdm_node_alpha(const TlBdm *b) { return b->alpha_nodes; }
const double *tl_bdm_ghost_fe(const TlBdm *b) { return b->ghost_fe; }
const double *tl_bdm_ghost_dem(const TlBdm *b) { return b->ghost_dem; }
