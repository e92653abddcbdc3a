#include "tl_spring_chain.h"

#include <math.h>
#include <string.h>

#include "tl_memory.h"

void tl_spring_chain_params_default(TlSpringChainParams *p)
{
  memset(p, 0, sizeof *p);
  p->n = 10;
  p->mass = 1.0;
  p->k = 1.0;
}

static inline double stretch(const TlSpringChain *ch, const double *u, TlSparseIndex e)
{
  return u[e] - (e > 0 ? u[e - 1] : 0.0);
}

static TlStatus chain_create_matrix(TlMechSystem *sys, int upper, TlSparse **K)
{
  TlSpringChain *ch = (TlSpringChain *)sys;
  TL_CHECK(tl_sparse_create_from_elements(sys->ndof, upper, ch->n_elem, ch->elem_ptr, ch->elem_dofs,
                                          1, K));
  return TL_OK;
}

static TlStatus chain_internal_force(TlMechSystem *sys, double t, const double *u, const double *v,
                                     double *f)
{
  (void)t;
  TlSpringChain *ch = (TlSpringChain *)sys;
  const TlSpringChainParams *p = &ch->p;
  memset(f, 0, (size_t)p->n * sizeof *f);
  for (TlSparseIndex e = 0; e < p->n; ++e) {
    double d = stretch(ch, u, e), dd = stretch(ch, v, e);
    double s = p->k * (d + p->alpha * d * d * d) + p->c * dd;
    f[e] += s;
    if (e > 0) f[e - 1] -= s;
  }
  return TL_OK;
}

static TlStatus chain_internal_tangent(TlMechSystem *sys, double t, const double *u, const double *v,
                                       double c_u, double c_v, TlSparse *K)
{
  (void)t;
  (void)v;
  TlSpringChain *ch = (TlSpringChain *)sys;
  const TlSpringChainParams *p = &ch->p;
  for (TlSparseIndex e = 0; e < p->n; ++e) {
    double d = stretch(ch, u, e);
    double kt = c_u * p->k * (1.0 + 3.0 * p->alpha * d * d) + c_v * p->c;
    double Ke[4] = {kt, -kt, -kt, kt};
    TL_CHECK(tl_sparse_add_element_indexed(K, e, 1.0, Ke));
  }
  return TL_OK;
}

static TlStatus chain_external_force(TlMechSystem *sys, double t, const double *u, double *f)
{
  (void)t;
  TlSpringChain *ch = (TlSpringChain *)sys;
  memset(f, 0, (size_t)ch->p.n * sizeof *f);
  f[ch->p.n - 1] = ch->p.tip_force + ch->p.kf * u[0];
  return TL_OK;
}

static TlStatus chain_external_tangent(TlMechSystem *sys, double t, const double *u, double c,
                                       TlSparse *K)
{
  (void)t;
  (void)u;
  TlSpringChain *ch = (TlSpringChain *)sys;
  if (ch->p.kf != 0.0) TL_CHECK(tl_sparse_add(K, ch->p.n - 1, 0, c * ch->p.kf));
  return TL_OK;
}

static TlStatus chain_lumped_mass(TlMechSystem *sys, double *m)
{
  TlSpringChain *ch = (TlSpringChain *)sys;
  for (TlSparseIndex i = 0; i < ch->p.n; ++i) m[i] = ch->p.mass;
  return TL_OK;
}

/* Bar elements of mass `mass` each, joining masses e-1 and e: element mass
 * mass/6 [2 1; 1 2]; rows sum to the lumped mass except at the free end,
 * which the last element's half completes (mass/2 there, as in a bar). */
static TlStatus chain_consistent_mass(TlMechSystem *sys, double c, TlSparse *M)
{
  TlSpringChain *ch = (TlSpringChain *)sys;
  const double m = ch->p.mass;
  for (TlSparseIndex e = 0; e < ch->p.n; ++e) {
    double Me[4] = {m / 3.0, m / 6.0, m / 6.0, m / 3.0};
    TL_CHECK(tl_sparse_add_element_indexed(M, e, c, Me));
  }
  /* Give the tip its missing half so the total matches the lumped mass. */
  TL_CHECK(tl_sparse_add(M, ch->p.n - 1, ch->p.n - 1, c * m / 2.0));
  return TL_OK;
}

static TlStatus chain_dirichlet(TlMechSystem *sys, double t, double *u, double *v, double *a)
{
  TlSpringChain *ch = (TlSpringChain *)sys;
  if (!ch->p.prescribed_tip) return TL_OK;
  TlSparseIndex i = ch->p.n - 1;
  if (u) u[i] = ch->p.tip_velocity * t;
  if (v) v[i] = ch->p.tip_velocity;
  if (a) a[i] = 0.0;
  return TL_OK;
}

static TlStatus chain_strain_energy(TlMechSystem *sys, const double *u, double *W)
{
  TlSpringChain *ch = (TlSpringChain *)sys;
  double w = 0.0;
  for (TlSparseIndex e = 0; e < ch->p.n; ++e) {
    double d = stretch(ch, u, e);
    w += ch->p.k * (0.5 * d * d + 0.25 * ch->p.alpha * d * d * d * d);
  }
  *W = w;
  return TL_OK;
}

static void chain_destroy(TlMechSystem *sys)
{
  TlSpringChain *ch = (TlSpringChain *)sys;
  tl_free(&ch->elem_ptr);
  tl_free(&ch->elem_dofs);
}

static const TlMechSystemOps chain_ops = {
    .header = {"mech_system", "spring_chain", "nonlinear spring-mass chain (tests)"},
    .create_matrix = chain_create_matrix,
    .internal_force = chain_internal_force,
    .internal_tangent = chain_internal_tangent,
    .external_force = chain_external_force,
    .lumped_mass = chain_lumped_mass,
    .external_tangent = chain_external_tangent,
    .consistent_mass = NULL,
    .dirichlet = chain_dirichlet,
    .strain_energy = chain_strain_energy,
    .destroy = chain_destroy,
};

static const TlMechSystemOps chain_consistent_ops = {
    .header = {"mech_system", "spring_chain_consistent", "spring-mass chain, consistent mass"},
    .create_matrix = chain_create_matrix,
    .internal_force = chain_internal_force,
    .internal_tangent = chain_internal_tangent,
    .external_force = chain_external_force,
    .lumped_mass = chain_lumped_mass,
    .external_tangent = chain_external_tangent,
    .consistent_mass = chain_consistent_mass,
    .dirichlet = chain_dirichlet,
    .strain_energy = chain_strain_energy,
    .destroy = chain_destroy,
};

TlStatus tl_spring_chain_create(const TlSpringChainParams *p, TlMechSystem **out)
{
  TlSpringChain *ch = NULL;
  TlStatus s = TL_OK;
  *out = NULL;
  if (p->n < 1) TL_ERROR(TL_ERR_ARG, "chain of %lld masses", (long long)p->n);
  if (!(p->mass > 0.0) || !(p->k > 0.0))
    TL_ERROR(TL_ERR_ARG, "mass = %g and k = %g must be positive", p->mass, p->k);
  if (p->n < 2 && p->kf != 0.0) TL_ERROR(TL_ERR_ARG, "kf needs at least two masses");
  TL_CHECK(TL_NEW(ch));
  ch->p = *p;
  ch->base.ops = p->consistent_mass ? &chain_consistent_ops : &chain_ops;
  ch->base.ndof = p->n;
  ch->base.symmetric = p->kf == 0.0;
  ch->base.damped = p->c != 0.0;
  if (p->prescribed_tip) {
    ch->dirichlet[0] = p->n - 1;
    ch->base.n_dirichlet = 1;
    ch->base.dirichlet_dofs = ch->dirichlet;
  }
  /* Springs, then (when kf != 0) one extra "element" {0, n-1} for the load
   * coupling. */
  ch->n_elem = p->n + (p->kf != 0.0);
  TL_CHECK_GOTO(s, tl_calloc(&ch->elem_ptr, (size_t)ch->n_elem + 1, sizeof *ch->elem_ptr), fail);
  TL_CHECK_GOTO(s, tl_calloc(&ch->elem_dofs, 2 * (size_t)ch->n_elem, sizeof *ch->elem_dofs), fail);
  for (TlSparseIndex e = 0; e < ch->n_elem; ++e) {
    ch->elem_ptr[e + 1] = 2 * (e + 1);
    ch->elem_dofs[2 * e] = e < p->n ? e - 1 : 0;
    ch->elem_dofs[2 * e + 1] = e < p->n ? e : p->n - 1;
  }
  *out = &ch->base;
  return TL_OK;
fail:
  chain_destroy(&ch->base);
  tl_free(&ch);
  return s;
}
