/* Hertz normal part with viscous damping (seeds/000 supplementary
 * Eqs. 18-20):
 *
 *   f_n = sqrt(δ reff) (k_n δ + γ_n m_eff dδ/dt),  k_n = (2/3) E / (1 - ν²) (Pa)
 *
 * Its tangential scale is the contact radius sqrt(δ reff), so a friction
 * part's stiffness and damping grow with it (the Mindlin-type spring
 * k_T = k_t sqrt(δ reff)); its default tangential stiffness is
 * k_t = 2 E / ((1 + ν)(2 - ν)) (Pa). */
#include <math.h>
#include <stddef.h>
#include "tl_contact_part.h"

typedef struct {
  TlContactPart base;
  double k_n_given, E, nu, gamma_n;
  double k_n; /* given or from E and ν */
} Hertz;

static const TlParam params[] = {
    {"k_n", 0.0, 0.0, 1e300, "Pa", "normal stiffness, F_n = k_n sqrt(reff) delta^1.5 (0: (2/3) E / (1 - nu^2))",
     offsetof(Hertz, k_n_given)},
    {"E", 0.0, 0.0, 1e300, "Pa", "Young's modulus of the grains (gives k_n and the default k_t)", offsetof(Hertz, E)},
    {"nu", 0.3, -0.999999, 0.499999, "", "Poisson's ratio of the grains", offsetof(Hertz, nu)},
    {"gamma_n", 0.0, 0.0, 1e300, "1/(m s)", "viscous normal damping, F_n += sqrt(delta reff) gamma_n m_eff d(delta)/dt",
     offsetof(Hertz, gamma_n)},
};

static TlStatus hertz_setup(TlContactPart *part, const TlContactPart *normal)
{
  Hertz *h = (Hertz *)part;
  (void)normal;
  h->k_n = h->k_n_given;
  if (!(h->k_n > 0.0)) {
    if (!(h->E > 0.0) || !isfinite(h->E))
      TL_ERROR(TL_ERR_ARG, "hertz normal part: Young's modulus E = %g Pa must be positive (or give k_n)", h->E);
    h->k_n = (2.0 / 3.0) * h->E / (1.0 - h->nu * h->nu);
  }
  if (!isfinite(h->k_n)) TL_ERROR(TL_ERR_ARG, "hertz normal part: k_n = %g Pa is not finite", h->k_n);
  part->bonded = 0;
  part->active = 1;
  return TL_OK;
}

static inline void hertz_loop(const TlContactPart *part, TlContactChunk *c)
{
  const Hertz *h = (const Hertz *)part;
  const double kn = h->k_n, gamma_n = h->gamma_n;
  const int want = c->want_energy;
  for (size_t q = 0; q < c->n; ++q) {
    const double delta = c->overlap[q];
    if (delta <= 0.0) {
      c->on[q] = 0;
      continue;
    }
    c->on[q] = 1;
    const double a = sqrt(delta * c->reff[q]);
    const double vn = tl_v3_dot(c->vrel[q], c->normal[q]); /* = -dδ/dt */
    c->fn[q] = a * (kn * delta - gamma_n * c->meff[q] * vn);
    c->scale[q] = a;
    if (want) c->energy[q] = 0.4 * kn * a * delta * delta;
  }
}
TL_CONTACT_PART_LOOPS(hertz, hertz_loop)

/* dF/dδ = 1.5 k_n sqrt(reff δ) */
static double hertz_max_stiffness(const TlContactPart *part, double reff, double overlap)
{
  return 1.5 * ((const Hertz *)part)->k_n * sqrt(reff * overlap);
}

static double hertz_max_damping(const TlContactPart *part, double meff, double reff, double overlap)
{
  return ((const Hertz *)part)->gamma_n * meff * sqrt(reff * overlap);
}

static double hertz_scale(const TlContactPart *part, double reff, double overlap)
{
  (void)part;
  return sqrt(reff * overlap);
}

static double hertz_tangential(const TlContactPart *part)
{
  const Hertz *h = (const Hertz *)part;
  return h->E > 0.0 ? 2.0 * h->E / ((1.0 + h->nu) * (2.0 - h->nu)) : 0.0;
}

static const TlContactPartOps hertz_ops = {
    {"contact_normal", "hertz", "Hertz with viscous damping; scales the tangential spring by sqrt(delta reff)"},
    sizeof(Hertz), (int)(sizeof params / sizeof params[0]), params, hertz_setup, hertz_evaluate, hertz_evaluate_hot,
    hertz_max_stiffness, hertz_max_damping, hertz_scale, hertz_tangential, NULL, NULL};

TlStatus tl_contact_register_hertz(void);
TlStatus tl_contact_register_hertz(void) { return tl_contact_part_register(&hertz_ops); }
