/* Linear spring-dashpot normal parts: "linear", and "bonded_linear", which
 * also acts in tension on bonded contacts (the lattice bar of seeds/001
 * §6.2).
 *
 *   f_n = k_n δ + c_n dδ/dt,  c_n = 2 η sqrt(k_n m_eff) from the restitution
 *   coefficient e (η = -ln e / sqrt(π² + ln² e)), or c_n = c_n^lin + γ_n m_eff
 *   when the restitution gives no damping (e = 1, or e <= 0: explicit
 *   damping, the LAMMPS form).
 * The normal force is not clamped at zero, so the analytic contact duration
 * π / sqrt(k/m_eff - (c/2m_eff)²) and restitution e hold exactly.  The
 * tangential scale is 1 and the default tangential stiffness 2/7 k_n. */
#include <math.h>
#include <stddef.h>
#include "tl_contact_kernels.h"
#include "tl_contact_part.h"

typedef struct {
  TlContactPart base;
  double k_n, restitution, c_n, gamma_n;
  double eta; /* damping ratio from the restitution */
} Linear;

static const TlParam params[] = {
    {"k_n", 0.0, 0.0, 1e300, "N/m", "normal stiffness (required, > 0)", offsetof(Linear, k_n)},
    {"restitution", 1.0, -1.0, 1.0, "1",
     "restitution e of a pair, giving the damping 2 eta sqrt(k_n m_eff); e = 1 or e <= 0: the explicit damping "
     "c_n + gamma_n m_eff instead", offsetof(Linear, restitution)},
    {"c_n", 0.0, 0.0, 1e300, "N s/m", "explicit normal damping (when the restitution gives none)",
     offsetof(Linear, c_n)},
    {"gamma_n", 0.0, 0.0, 1e300, "1/s",
     "explicit mass-proportional normal damping, c_n += gamma_n m_eff (when the restitution gives none)",
     offsetof(Linear, gamma_n)},
};

static TlStatus setup(TlContactPart *part, int bonded)
{
  Linear *l = (Linear *)part;
  if (!(l->k_n > 0.0) || !isfinite(l->k_n))
    TL_ERROR(TL_ERR_ARG, "%s normal part: k_n = %g N/m must be positive and finite", part->ops->header.name, l->k_n);
  l->eta = l->restitution > 0.0 ? tl_damping_ratio_from_restitution(l->restitution) : 0.0;
  part->bonded = bonded;
  part->active = 1;
  part->ignores_spins = 1; /* forces along n from the overlap and v_rel only */
  return TL_OK;
}
static TlStatus linear_setup(TlContactPart *part, const TlContactPart *normal) { (void)normal; return setup(part, 0); }
static TlStatus bonded_setup(TlContactPart *part, const TlContactPart *normal) { (void)normal; return setup(part, 1); }

static inline void linear_loop(const TlContactPart *part, TlContactChunk *c)
{
  const Linear *l = (const Linear *)part;
  const double kn = l->k_n, eta = l->eta, gamma_lin = l->c_n, gamma_n = l->gamma_n;
  const int bonded = part->bonded, want = c->want_energy;
  for (size_t q = 0; q < c->n; ++q) {
    const double delta = c->overlap[q];
    if (delta <= 0.0 && !(bonded && c->bonded[q])) {
      c->on[q] = 0;
      continue;
    }
    c->on[q] = 1;
    const double meff = c->meff[q];
    const double vn = tl_v3_dot(c->vrel[q], c->normal[q]); /* = -dδ/dt */
    const double cn = eta > 0.0 ? 2.0 * eta * sqrt(kn * meff) : gamma_lin + gamma_n * meff;
    c->fn[q] = kn * delta - cn * vn;
    c->scale[q] = 1.0;
    if (want) c->energy[q] = 0.5 * kn * delta * delta;
  }
}
TL_CONTACT_PART_LOOPS(linear, linear_loop)

static double linear_max_stiffness(const TlContactPart *part, double reff, double overlap)
{
  (void)reff, (void)overlap;
  return ((const Linear *)part)->k_n;
}

static double linear_max_damping(const TlContactPart *part, double meff, double reff, double overlap)
{
  const Linear *l = (const Linear *)part;
  (void)reff, (void)overlap;
  if (l->eta > 0.0) return 2.0 * l->eta * sqrt(l->k_n * meff);
  return l->c_n + l->gamma_n * meff;
}

static double linear_scale(const TlContactPart *part, double reff, double overlap)
{
  (void)part, (void)reff, (void)overlap;
  return 1.0;
}

static double linear_tangential(const TlContactPart *part) { return 2.0 / 7.0 * ((const Linear *)part)->k_n; }

static const TlContactPartOps linear_ops = {
    {"contact_normal", "linear", "linear spring-dashpot (restitution or explicit damping)"},
    sizeof(Linear), (int)(sizeof params / sizeof params[0]), params, linear_setup, linear_evaluate,
    linear_evaluate_hot, linear_max_stiffness, linear_max_damping, linear_scale, linear_tangential, NULL, NULL};

static const TlContactPartOps bonded_ops = {
    {"contact_normal", "bonded_linear", "linear spring-dashpot acting in tension too on bonded contacts"},
    sizeof(Linear), (int)(sizeof params / sizeof params[0]), params, bonded_setup, linear_evaluate,
    linear_evaluate_hot, linear_max_stiffness, linear_max_damping, linear_scale, linear_tangential, NULL, NULL};

TlStatus tl_contact_register_linear(void);
TlStatus tl_contact_register_linear(void)
{
  TL_CHECK(tl_contact_part_register(&linear_ops));
  return tl_contact_part_register(&bonded_ops);
}
