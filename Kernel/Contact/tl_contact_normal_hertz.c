/* Hertz normal part with viscous damping (seeds/000 supplementary
 * Eqs. 18-20):
 *
 *   f_n = sqrt(δ reff) (k_n δ + γ_n m_eff dδ/dt),  k_n = (2/3) E / (1 - ν²) (Pa)
 *
 * or, given a restitution coefficient e < 1 instead of γ_n, the dashpot of
 * Tsuji, Tanaka & Ishida (Powder Technol. 71 (1992) 239, Eq. 11) that gives
 * e independently of the impact speed:
 *
 *   f_n = K δ^{3/2} + α sqrt(m_eff K) δ^{1/4} dδ/dt,   K = k_n sqrt(reff).
 *
 * With δ = δ0 x, t = (δ0/v0) τ and δ0 = (m_eff v0²/K)^{2/5} the impact
 * becomes x'' = -x^{3/2} - α x^{1/4} x', x(0) = 0, x'(0) = 1, free of v0 and
 * of every parameter but α; e = -x' when x returns to 0 (no clamping, as the
 * linear part).  Setup finds α(e) by bisection on that equation, integrated
 * by RK4 (e(α) decreases; Antypov & Elliott, EPL 94 (2011) 50004, study the
 * same relation analytically: their closed form is an approximation, the
 * integral is not).  Both given is refused.  The parameter is named
 * tsuji_restitution, not restitution: it sets a different dashpot from the
 * linear part's restitution.
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
  double k_n_given, E, nu, gamma_n, restitution;
  double k_n;   /* given or from E and ν */
  double alpha; /* Tsuji's coefficient from the restitution (0: none) */
} Hertz;

static const TlParam params[] = {
    {"k_n", 0.0, 0.0, 1e300, "Pa", "normal stiffness, F_n = k_n sqrt(reff) delta^1.5 (0: (2/3) E / (1 - nu^2))",
     offsetof(Hertz, k_n_given)},
    {"E", 0.0, 0.0, 1e300, "Pa", "Young's modulus of the grains (gives k_n and the default k_t)", offsetof(Hertz, E)},
    {"nu", 0.3, -0.999999, 0.499999, "1", "Poisson's ratio of the grains", offsetof(Hertz, nu)},
    {"gamma_n", 0.0, 0.0, 1e300, "1/(m s)", "viscous normal damping, F_n += sqrt(delta reff) gamma_n m_eff d(delta)/dt",
     offsetof(Hertz, gamma_n)},
    {"tsuji_restitution", 1.0, 0.0, 1.0, "1",
     "restitution e of a pair, independent of the impact speed (Tsuji's dashpot alpha(e) sqrt(m_eff K) delta^1/4); "
     "1: none (gamma_n instead)", offsetof(Hertz, restitution)},
};

/* The restitution of x'' = -x^{3/2} - α x^{1/4} x' from x = 0, x' = 1: RK4
 * with step h until x returns to 0, the crossing found by linear
 * interpolation of the last step. */
static double hertz_rhs(double x, double v, double alpha)
{
  const double xp = x > 0.0 ? x : 0.0;
  return -xp * sqrt(xp) - alpha * sqrt(sqrt(xp)) * v;
}

static double hertz_restitution_of(double alpha)
{
  const double h = 2e-4;
  double x = 0.0, v = 1.0;
  for (long k = 0; k < 2000000; ++k) {
    const double k1x = v, k1v = hertz_rhs(x, v, alpha);
    const double k2x = v + 0.5 * h * k1v, k2v = hertz_rhs(x + 0.5 * h * k1x, v + 0.5 * h * k1v, alpha);
    const double k3x = v + 0.5 * h * k2v, k3v = hertz_rhs(x + 0.5 * h * k2x, v + 0.5 * h * k2v, alpha);
    const double k4x = v + h * k3v, k4v = hertz_rhs(x + h * k3x, v + h * k3v, alpha);
    const double xn = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
    const double vn = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    if (k > 0 && xn <= 0.0) {
      const double s = x / (x - xn);
      return -(v + s * (vn - v));
    }
    x = xn;
    v = vn;
  }
  return 0.0; /* never returned: as good as fully damped */
}

/* α with e(α) = e, by bisection (e(α) decreases from 1 at α = 0). */
static TlStatus hertz_alpha(double e, double *alpha)
{
  double lo = 0.0, hi = 1.0;
  while (hertz_restitution_of(hi) > e) {
    hi *= 2.0;
    if (hi > 1e3) TL_ERROR(TL_ERR_ARG, "hertz normal part: tsuji_restitution %g is too small (alpha > 1000)", e);
  }
  for (int k = 0; k < 60 && hi - lo > 1e-12 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (hertz_restitution_of(mid) > e) lo = mid;
    else hi = mid;
  }
  *alpha = 0.5 * (lo + hi);
  return TL_OK;
}

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
  h->alpha = 0.0;
  if (h->restitution < 1.0) {
    if (!(h->restitution >= 0.01))
      TL_ERROR(TL_ERR_ARG, "hertz normal part: tsuji_restitution = %g must be in [0.01, 1]", h->restitution);
    if (h->gamma_n > 0.0)
      TL_ERROR(TL_ERR_ARG, "hertz normal part: tsuji_restitution = %g and gamma_n = %g 1/(m s) both set; give one damping",
               h->restitution, h->gamma_n);
    TL_CHECK(hertz_alpha(h->restitution, &h->alpha));
  }
  part->bonded = 0;
  part->active = 1;
  part->ignores_spins = 1; /* forces along n from the overlap and v_rel only */
  return TL_OK;
}

static inline void hertz_loop(const TlContactPart *part, TlContactChunk *c)
{
  const Hertz *h = (const Hertz *)part;
  const double kn = h->k_n, gamma_n = h->gamma_n, alpha = h->alpha;
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
    if (alpha > 0.0) {
      /* Tsuji: α sqrt(m_eff K) δ^{1/4}, K = k_n sqrt(reff) */
      const double cn = alpha * sqrt(c->meff[q] * kn * sqrt(c->reff[q])) * sqrt(sqrt(delta));
      c->fn[q] = a * kn * delta - cn * vn;
    } else {
      c->fn[q] = a * (kn * delta - gamma_n * c->meff[q] * vn);
    }
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
  const Hertz *h = (const Hertz *)part;
  if (h->alpha > 0.0) return h->alpha * sqrt(meff * h->k_n * sqrt(reff)) * sqrt(sqrt(overlap));
  return h->gamma_n * meff * sqrt(reff * overlap);
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
