/* Friction part "lammps_viscous": the history-free tangential force of
 * LAMMPS's pair style gran/hooke (and fix wall/gran hooke), a dashpot on
 * the tangential relative velocity u at the contact point, capped by
 * Coulomb:
 *
 *   f_t = min(μ |f_n|, s m_eff γ_t |u|) u / |u|   (0 when u = 0),
 *
 * s the normal part's tangential scale (1 for lammps_hooke), f_n the whole
 * normal force.  No spring, no history (history_doubles 0).  gamma_t < 0
 * takes half the normal part's gamma_n (LAMMPS's gamma_t NULL), dampflag 0
 * sets it to zero, which leaves no tangential force at all (the part is then
 * off, as mu = 0).  Lever arms: the radius. */
#include <math.h>
#include <stddef.h>
#include "tl_contact_part.h"
#include "tl_registry.h"

typedef struct {
  TlContactPart base;
  double gamma_t_given, mu, dampflag;
  double gamma_t;
} LammpsViscous;

static const TlParam params[] = {
    {"gamma_t", -1.0, -1.0, 1e300, "1/s/scale",
     "tangential damping per unit effective mass, LAMMPS gamma_t; < 0: gamma_n / 2", offsetof(LammpsViscous, gamma_t_given)},
    {"mu", 0.5, 0.0, 1e4, "1", "Coulomb friction coefficient, LAMMPS xmu (0: no friction)", offsetof(LammpsViscous, mu)},
    {"dampflag", 1.0, 0.0, 1.0, "1", "LAMMPS dampflag: 1 tangential damping on, 0 off (then no tangential force)",
     offsetof(LammpsViscous, dampflag)},
};

static TlStatus viscous_setup(TlContactPart *part, const TlContactPart *normal)
{
  LammpsViscous *f = (LammpsViscous *)part;
  if (f->dampflag != 0.0 && f->dampflag != 1.0)
    TL_ERROR(TL_ERR_ARG, "lammps_viscous friction part: dampflag = %g must be 0 or 1", f->dampflag);
  f->gamma_t = f->gamma_t_given;
  if (f->gamma_t < 0.0) {
    const TlParam *g = tl_param_find(normal->ops->params, normal->ops->n_params, "gamma_n");
    if (!g)
      TL_ERROR(TL_ERR_ARG, "lammps_viscous friction part: gamma_t < 0 means gamma_n / 2, but the normal part '%s' has "
               "no gamma_n; set gamma_t", normal->ops->header.name);
    f->gamma_t = 0.5 * *(const double *)((const char *)normal + g->offset);
  }
  if (f->dampflag == 0.0) f->gamma_t = 0.0;
  part->active = f->mu > 0.0 && f->gamma_t > 0.0;
  part->needs_rotation = 1;
  part->lever_radius = 1;
  part->ignores_spins = 1; /* the spins enter through v_rel only */
  return TL_OK;
}

static inline void viscous_loop(const TlContactPart *part, TlContactChunk *c)
{
  const LammpsViscous *f = (const LammpsViscous *)part;
  const double gamma_t = f->gamma_t, mu = f->mu;
  for (size_t q = 0; q < c->n; ++q) {
    if (!c->on[q]) continue;
    const TlVec3 n = c->normal[q], vr = c->vrel[q];
    const TlVec3 u = tl_v3_axpy(vr, -tl_v3_dot(vr, n), n);
    const double speed = tl_v3_norm(u);
    if (!(speed > 0.0)) continue;
    const double fs = c->scale[q] * c->meff[q] * gamma_t * speed, cap = mu * fabs(c->fn[q]);
    c->force[q] = tl_v3_axpy(c->force[q], (fs < cap ? fs : cap) / speed, u);
  }
}
TL_CONTACT_PART_LOOPS(lammps_viscous, viscous_loop)

static const TlContactPartOps ops = {
    {"contact_friction", "lammps_viscous",
     "LAMMPS gran/hooke tangential force: a dashpot m_eff gamma_t u capped at mu |f_n|, no history"},
    sizeof(LammpsViscous), (int)(sizeof params / sizeof params[0]), params, viscous_setup, lammps_viscous_evaluate,
    lammps_viscous_evaluate_hot, NULL, NULL, NULL, NULL, NULL, NULL};

TlStatus tl_contact_lammps_viscous_register_all(void);
TlStatus tl_contact_lammps_viscous_register_all(void) { return tl_contact_part_register(&ops); }
