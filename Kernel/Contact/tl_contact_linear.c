/* Linear spring-dashpot normal force, optionally bonded (acting in tension
 * on bonded contacts: the lattice bar of seeds/001 §6.2), with optional
 * frame-invariant Coulomb friction (seeds/004 Eqs. 22-26), rolling
 * resistance and constant adhesion.
 *
 *   f_n = k_n δ + c_n dδ/dt,  c_n = 2 η sqrt(k_n m_eff) from the restitution
 *   coefficient e (η = -ln e / sqrt(π² + ln² e)), or c_n = γ_n^lin + γ_n m_eff
 *   when e <= 0 is given (explicit damping, the LAMMPS form).
 * The normal force is not clamped at zero, so the analytic contact duration
 * π / sqrt(k/m_eff - (c/2m_eff)²) and restitution e hold exactly. */
#include <math.h>
#include <stdio.h>
#include "tl_contact_kernels.h"
#include "tl_contact_law.h"
#include "tl_contact_private.h"
#include "tl_memory.h"

static TlStatus linear_evaluate(const TlContactLaw *base, const TlContactBatch *b)
{
  const TlStdLaw *law = (const TlStdLaw *)base;
  for (size_t c = 0; c < b->n; ++c) {
    const TlContactGeometry *g = &b->geometry[c];
    TlContactResult *r = &b->result[c];
    double e = 0.0;
    if (!tl_linear_contact(law, g->normal, g->overlap, g->vrel, g->spin_mean, g->spin_rel, g->meff, g->reff,
                           g->history, g->bonded, b->dt, b->want_energy, &r->force, &r->couple, &e)) {
      r->force = r->couple = (TlVec3){0, 0, 0};
      r->elastic_energy = r->power = 0.0;
      continue;
    }
    if (b->want_energy) {
      r->elastic_energy = e;
      r->power = tl_v3_dot(r->force, g->vrel) + tl_v3_dot(r->couple, g->spin_rel);
    }
  }
  return TL_OK;
}

static double linear_max_stiffness(const TlContactLaw *base, double reff, double overlap)
{
  const TlStdLaw *law = (const TlStdLaw *)base;
  return law->p.k_n > law->k_t ? law->p.k_n : law->k_t;
}

static double linear_max_damping(const TlContactLaw *base, double meff, double reff, double overlap)
{
  const TlStdLaw *law = (const TlStdLaw *)base;
  if (law->eta > 0.0) return 2.0 * law->eta * sqrt(law->p.k_n * meff);
  return law->gamma_lin + law->p.gamma_n * meff;
}

static void linear_describe(const TlContactLaw *base, char *text, size_t size)
{
  const TlStdLaw *law = (const TlStdLaw *)base;
  const TlContactParameters *p = &law->p;
  snprintf(text, size, "linear: k_n=%g N/m e=%g k_t=%g N/m mu=%g mu_roll=%g adhesion=%g N%s", p->k_n,
           p->restitution, law->k_t, p->mu, p->mu_roll, p->adhesion_force, p->bonded ? " bonded" : "");
}

static void std_destroy(TlContactLaw *law) { tl_free(&law); }

const TlContactLawOps tl_contact_linear_ops = {
    {"contact_law", "linear", "linear spring-dashpot, optional bonds, Coulomb friction, rolling, adhesion"},
    linear_evaluate, linear_max_stiffness, linear_max_damping, linear_describe, std_destroy};

TlStatus tl_contact_law_create_linear(const TlContactParameters *p, TlContactLaw **out)
{
  if (!(p->k_n > 0.0) || !isfinite(p->k_n))
    TL_ERROR(TL_ERR_ARG, "linear law: k_n = %g N/m must be positive and finite", p->k_n);
  if (p->restitution > 1.0 || !isfinite(p->restitution))
    TL_ERROR(TL_ERR_ARG, "linear law: restitution %g must be in (0, 1] (or <= 0 for explicit damping)",
             p->restitution);
  if (p->k_t < 0.0) TL_ERROR(TL_ERR_ARG, "linear law: k_t = %g N/m must be >= 0", p->k_t);
  if (p->gamma_n < 0.0 || p->gamma_n_linear < 0.0 || p->gamma_t_linear < 0.0)
    TL_ERROR(TL_ERR_ARG, "linear law: damping coefficients (gamma_n %g, gamma_n_linear %g, gamma_t_linear %g) must be >= 0",
             p->gamma_n, p->gamma_n_linear, p->gamma_t_linear);
  TL_CHECK(tl_contact_check_common(p));
  TlStdLaw *law;
  TL_CHECK(TL_NEW(law));
  law->base.ops = &tl_contact_linear_ops;
  law->p = *p;
  law->k_t = p->k_t > 0.0 ? p->k_t : 2.0 / 7.0 * p->k_n;
  law->eta = p->restitution > 0.0 ? tl_damping_ratio_from_restitution(p->restitution) : 0.0;
  law->gamma_lin = p->gamma_n_linear;
  law->base.history_doubles = p->mu > 0.0 ? TL_FRICTION_HISTORY : 0;
  law->base.needs_rotation = p->mu > 0.0 || p->mu_roll > 0.0;
  law->base.bonded = p->bonded;
  *out = &law->base;
  return TL_OK;
}
