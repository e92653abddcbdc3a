/* Hertz normal force with viscous damping and a Mindlin-type tangential
 * spring (seeds/000 supplementary Eqs. 18-20):
 *
 *   F = sqrt(δ reff) [ (k_n δ + γ_n m_eff dδ/dt) n_rep + (k_t δ_t + γ_t m_eff dδ_t/dt) t ],
 *   k_n = (2/3) E / (1 - ν²),  k_t = 2 E / ((1 + ν)(2 - ν))  (Pa)
 *
 * The tangential spring is integrated incrementally with the frame-invariant
 * scheme of seeds/004 (Eqs. 23-26) at the current stiffness
 * k_T = k_t sqrt(δ reff), and capped by Coulomb's law when mu > 0 (without
 * friction the tangential part is off, as in a frictionless scene). */
#include <math.h>
#include <stdio.h>
#include "tl_contact_kernels.h"
#include "tl_contact_law.h"
#include "tl_contact_private.h"
#include "tl_memory.h"

static TlStatus hertz_evaluate(const TlContactLaw *base, const TlContactBatch *b)
{
  const TlStdLaw *law = (const TlStdLaw *)base;
  for (size_t c = 0; c < b->n; ++c) {
    const TlContactGeometry *g = &b->geometry[c];
    TlContactResult *r = &b->result[c];
    double e = 0.0;
    if (!tl_hertz_contact(law, g->normal, g->overlap, g->vrel, g->spin_mean, g->spin_rel, g->meff, g->reff,
                          g->history, b->dt, b->want_energy, &r->force, &r->couple, &e)) {
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

/* dF/dδ = 1.5 k_n sqrt(reff δ) */
static double hertz_max_stiffness(const TlContactLaw *base, double reff, double overlap)
{
  const TlStdLaw *law = (const TlStdLaw *)base;
  double a = sqrt(reff * overlap);
  double k = 1.5 * law->k_n * a;
  double t = law->p.mu > 0.0 ? law->k_t * a : 0.0;
  return k > t ? k : t;
}

static double hertz_max_damping(const TlContactLaw *base, double meff, double reff, double overlap)
{
  const TlStdLaw *law = (const TlStdLaw *)base;
  return law->p.gamma_n * meff * sqrt(reff * overlap);
}

static void hertz_describe(const TlContactLaw *base, char *text, size_t size)
{
  const TlStdLaw *law = (const TlStdLaw *)base;
  const TlContactParameters *p = &law->p;
  snprintf(text, size, "hertz: k_n=%g Pa k_t=%g Pa gamma_n=%g 1/(m s) gamma_t=%g 1/(m s) mu=%g mu_roll=%g adhesion=%g N",
           law->k_n, law->k_t, p->gamma_n, p->gamma_t, p->mu, p->mu_roll, p->adhesion_force);
}

static void hertz_destroy(TlContactLaw *law) { tl_free(&law); }

const TlContactLawOps tl_contact_hertz_ops = {
    {"contact_law", "hertz", "Hertz with viscous damping and Mindlin tangential spring, Coulomb friction"},
    hertz_evaluate, hertz_max_stiffness, hertz_max_damping, hertz_describe, hertz_destroy};

TlStatus tl_contact_law_create_hertz(const TlContactParameters *p, TlContactLaw **out)
{
  double kn = p->hertz_k_n, kt = p->hertz_k_t;
  if (kn <= 0.0 || kt <= 0.0) {
    double E = p->youngs_modulus, nu = p->poisson_ratio;
    if (!(E > 0.0) || !isfinite(E))
      TL_ERROR(TL_ERR_ARG, "hertz law: Young's modulus %g Pa must be positive (or give hertz_k_n and hertz_k_t)", E);
    if (!(nu > -1.0 && nu < 0.5))
      TL_ERROR(TL_ERR_ARG, "hertz law: Poisson ratio %g must be in (-1, 0.5)", nu);
    if (kn <= 0.0) kn = (2.0 / 3.0) * E / (1.0 - nu * nu);
    if (kt <= 0.0) kt = 2.0 * E / ((1.0 + nu) * (2.0 - nu));
  }
  if (!isfinite(kn) || !isfinite(kt)) TL_ERROR(TL_ERR_ARG, "hertz law: k_n %g or k_t %g not finite", kn, kt);
  if (p->gamma_n < 0.0 || p->gamma_t < 0.0 || !isfinite(p->gamma_n) || !isfinite(p->gamma_t))
    TL_ERROR(TL_ERR_ARG, "hertz law: damping gamma_n %g, gamma_t %g (1/(m s)) must be >= 0", p->gamma_n, p->gamma_t);
  TL_CHECK(tl_contact_check_common(p));
  TlStdLaw *law;
  TL_CHECK(TL_NEW(law));
  law->base.ops = &tl_contact_hertz_ops;
  law->p = *p;
  law->k_n = kn;
  law->k_t = kt;
  law->base.history_doubles = p->mu > 0.0 ? TL_FRICTION_HISTORY : 0;
  law->base.needs_rotation = p->mu > 0.0 || p->mu_roll > 0.0;
  law->base.bonded = 0;
  *out = &law->base;
  return TL_OK;
}
