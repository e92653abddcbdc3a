/* Normal part "lammps_hooke": the normal force of LAMMPS's pair styles
 * gran/hooke and gran/hooke/history (and of fix wall/gran hooke,
 * hooke/history), with LAMMPS's parameters:
 *
 *   f_n = k_n δ - m_eff γ_n v_n     (v_n = (v_j - v_i)·n, the approach speed < 0),
 *
 * k_n in N/m (LAMMPS Kn, force/distance), γ_n in 1/s (LAMMPS gamma_n, per
 * unit effective mass), m_eff = m_i m_j/(m_i + m_j), the other body's mass
 * against a fixed body or a wall.  Not clamped: the force turns attractive
 * at the end of a damped contact, as in LAMMPS, unless limit_damping = 1
 * (LAMMPS's keyword of that name: f_n = max(f_n, 0)).  Its contacts use the
 * radius as lever arm (LAMMPS's semantics for the contact-point velocity
 * and the torque); its tangential scale is 1 and its default tangential
 * stiffness 2/7 k_n (LAMMPS's Kt NULL).  Compared with the part "linear": the
 * same spring and dashpot, without the restitution parameter and with
 * LAMMPS's lever arms. */
#include <math.h>
#include <stddef.h>
#include "tl_contact_part.h"

typedef struct {
  TlContactPart base;
  double k_n, gamma_n, limit_damping;
} LammpsHooke;

static const TlParam params[] = {
    {"k_n", 0.0, 0.0, 1e300, "N/m", "normal stiffness, LAMMPS Kn (required, > 0)", offsetof(LammpsHooke, k_n)},
    {"gamma_n", 0.0, 0.0, 1e300, "1/s", "normal damping per unit effective mass, LAMMPS gamma_n: f_n -= m_eff gamma_n v_n",
     offsetof(LammpsHooke, gamma_n)},
    {"limit_damping", 0.0, 0.0, 1.0, "1", "1: the normal force is clamped at zero (LAMMPS limit_damping); 0: not",
     offsetof(LammpsHooke, limit_damping)},
};

static TlStatus hooke_setup(TlContactPart *part, const TlContactPart *normal)
{
  LammpsHooke *h = (LammpsHooke *)part;
  (void)normal;
  if (!(h->k_n > 0.0) || !isfinite(h->k_n))
    TL_ERROR(TL_ERR_ARG, "lammps_hooke normal part: k_n = %g N/m must be positive and finite", h->k_n);
  if (h->limit_damping != 0.0 && h->limit_damping != 1.0)
    TL_ERROR(TL_ERR_ARG, "lammps_hooke normal part: limit_damping = %g must be 0 or 1", h->limit_damping);
  part->lever_radius = 1;
  part->active = 1;
  part->ignores_spins = 1; /* forces along n from the overlap and v_rel only */
  return TL_OK;
}

static inline void hooke_loop(const TlContactPart *part, TlContactChunk *c)
{
  const LammpsHooke *h = (const LammpsHooke *)part;
  const double kn = h->k_n, gamma_n = h->gamma_n;
  const int clamp = h->limit_damping != 0.0, want = c->want_energy;
  for (size_t q = 0; q < c->n; ++q) {
    const double delta = c->overlap[q];
    if (delta <= 0.0) {
      c->on[q] = 0;
      continue;
    }
    c->on[q] = 1;
    const double vn = tl_v3_dot(c->vrel[q], c->normal[q]);
    double fn = kn * delta - c->meff[q] * gamma_n * vn;
    if (clamp && fn < 0.0) fn = 0.0;
    c->fn[q] = fn;
    c->scale[q] = 1.0;
    if (want) c->energy[q] = 0.5 * kn * delta * delta;
  }
}
TL_CONTACT_PART_LOOPS(lammps_hooke, hooke_loop)

static double hooke_max_stiffness(const TlContactPart *part, double reff, double overlap)
{
  (void)reff, (void)overlap;
  return ((const LammpsHooke *)part)->k_n;
}

static double hooke_max_damping(const TlContactPart *part, double meff, double reff, double overlap)
{
  (void)reff, (void)overlap;
  return ((const LammpsHooke *)part)->gamma_n * meff;
}

static double hooke_scale(const TlContactPart *part, double reff, double overlap)
{
  (void)part, (void)reff, (void)overlap;
  return 1.0;
}

static double hooke_tangential(const TlContactPart *part) { return 2.0 / 7.0 * ((const LammpsHooke *)part)->k_n; }

static const TlContactPartOps ops = {
    {"contact_normal", "lammps_hooke", "LAMMPS gran/hooke normal force: k_n delta - m_eff gamma_n v_n, radius lever arms"},
    sizeof(LammpsHooke), (int)(sizeof params / sizeof params[0]), params, hooke_setup, lammps_hooke_evaluate,
    lammps_hooke_evaluate_hot, hooke_max_stiffness, hooke_max_damping, hooke_scale, hooke_tangential, NULL, NULL};

TlStatus tl_contact_lammps_hooke_register_all(void);
TlStatus tl_contact_lammps_hooke_register_all(void) { return tl_contact_part_register(&ops); }
