/* Normal part "lammps_hertz": the normal force of LAMMPS's pair style
 * gran/hertz/history (and fix wall/gran hertz/history), with LAMMPS's
 * parameters:
 *
 *   f_n = sqrt(δ R_eff) (k_n δ - m_eff γ_n v_n)   (v_n = (v_j - v_i)·n),
 *
 * k_n in Pa (LAMMPS Kn, force/area: LAMMPS divides it by nktv2p, 1 in SI
 * and lj units), γ_n in 1/(m s) (LAMMPS gamma_n, per unit effective mass and
 * contact radius), R_eff = R_i R_j/(R_i + R_j) (R_i for a flat wall).  Not
 * clamped unless limit_damping = 1.  Its tangential scale is the contact
 * radius sqrt(δ R_eff) (LAMMPS's polyhertz multiplies k_t and γ_t too), its
 * default tangential stiffness 2/7 k_n (LAMMPS's Kt NULL), its lever arms
 * the radius.  Compared with the part "hertz": the same normal force with
 * k_n and gamma_n given, but LAMMPS's default k_t (2/7 k_n, not Mindlin's
 * 2E/((1+ν)(2-ν))) and lever arms. */
#include <math.h>
#include <stddef.h>
#include "tl_contact_part.h"

typedef struct {
  TlContactPart base;
  double k_n, gamma_n, limit_damping;
} LammpsHertz;

static const TlParam params[] = {
    {"k_n", 0.0, 0.0, 1e300, "Pa", "normal stiffness, LAMMPS Kn: f_n = k_n sqrt(reff) delta^1.5 (required, > 0)",
     offsetof(LammpsHertz, k_n)},
    {"gamma_n", 0.0, 0.0, 1e300, "1/(m s)",
     "normal damping, LAMMPS gamma_n: f_n -= sqrt(delta reff) m_eff gamma_n v_n", offsetof(LammpsHertz, gamma_n)},
    {"limit_damping", 0.0, 0.0, 1.0, "1", "1: the normal force is clamped at zero (LAMMPS limit_damping); 0: not",
     offsetof(LammpsHertz, limit_damping)},
};

static TlStatus hertz_setup(TlContactPart *part, const TlContactPart *normal)
{
  LammpsHertz *h = (LammpsHertz *)part;
  (void)normal;
  if (!(h->k_n > 0.0) || !isfinite(h->k_n))
    TL_ERROR(TL_ERR_ARG, "lammps_hertz normal part: k_n = %g Pa must be positive and finite", h->k_n);
  if (h->limit_damping != 0.0 && h->limit_damping != 1.0)
    TL_ERROR(TL_ERR_ARG, "lammps_hertz normal part: limit_damping = %g must be 0 or 1", h->limit_damping);
  part->lever_radius = 1;
  part->active = 1;
  part->ignores_spins = 1; /* forces along n from the overlap and v_rel only */
  return TL_OK;
}

static inline void hertz_loop(const TlContactPart *part, TlContactChunk *c)
{
  const LammpsHertz *h = (const LammpsHertz *)part;
  const double kn = h->k_n, gamma_n = h->gamma_n;
  const int clamp = h->limit_damping != 0.0, want = c->want_energy;
  for (size_t q = 0; q < c->n; ++q) {
    const double delta = c->overlap[q];
    if (delta <= 0.0) {
      c->on[q] = 0;
      continue;
    }
    c->on[q] = 1;
    const double a = sqrt(delta * c->reff[q]);
    const double vn = tl_v3_dot(c->vrel[q], c->normal[q]);
    double fn = a * (kn * delta - c->meff[q] * gamma_n * vn);
    if (clamp && fn < 0.0) fn = 0.0;
    c->fn[q] = fn;
    c->scale[q] = a;
    if (want) c->energy[q] = 0.4 * kn * a * delta * delta;
  }
}
TL_CONTACT_PART_LOOPS(lammps_hertz, hertz_loop)

static double hertz_max_stiffness(const TlContactPart *part, double reff, double overlap)
{
  return 1.5 * ((const LammpsHertz *)part)->k_n * sqrt(reff * overlap);
}

static double hertz_max_damping(const TlContactPart *part, double meff, double reff, double overlap)
{
  return ((const LammpsHertz *)part)->gamma_n * meff * sqrt(reff * overlap);
}

static double hertz_scale(const TlContactPart *part, double reff, double overlap)
{
  (void)part;
  return sqrt(reff * overlap);
}

static double hertz_tangential(const TlContactPart *part) { return 2.0 / 7.0 * ((const LammpsHertz *)part)->k_n; }

static const TlContactPartOps ops = {
    {"contact_normal", "lammps_hertz",
     "LAMMPS gran/hertz/history normal force: sqrt(delta reff) (k_n delta - m_eff gamma_n v_n), radius lever arms"},
    sizeof(LammpsHertz), (int)(sizeof params / sizeof params[0]), params, hertz_setup, lammps_hertz_evaluate,
    lammps_hertz_evaluate_hot, hertz_max_stiffness, hertz_max_damping, hertz_scale, hertz_tangential, NULL, NULL};

TlStatus tl_contact_lammps_hertz_register_all(void);
TlStatus tl_contact_lammps_hertz_register_all(void) { return tl_contact_part_register(&ops); }
