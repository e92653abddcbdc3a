/* Coulomb friction part: the frame-invariant tangential spring of seeds/004
 * (Eqs. 22-26, tl_friction_force), cut to the cone mu <f_N>_+.  Its stiffness
 * and damping are scaled per contact by the normal part's tangential scale
 * (1 for a linear spring, sqrt(δ reff) for Hertz):
 *   k_T = k_t scale,  c_T = (gamma_t m_eff + c_t) scale,
 * with k_t = 0 meaning the normal part's default (2/7 k_n linear,
 * 2 E / ((1 + ν)(2 - ν)) Hertz).  mu = 0 switches the part off (no history).
 * `transport` chooses the time integration of the tangential force
 * (TlFrictionTransport, tl_contact_kernels.h): 0 project (Eq. 11, the
 * default), 1 rotate (Eq. 24; the history also keeps the last normal),
 * 2 implicit (Eq. 12).  Each scheme is its own chunk loop and ops table,
 * which setup puts in the part, so that the default's loop is compiled
 * exactly as it always was (its results stay bit for bit). */
#include <math.h>
#include <stddef.h>
#include "tl_contact_kernels.h"
#include "tl_contact_part.h"

typedef struct {
  TlContactPart base;
  double mu, k_t_given, gamma_t, c_t, transport_given;
  double k_t;    /* given or the normal part's default */
  int transport; /* TlFrictionTransport */
} Coulomb;

static const TlParam params[] = {
    {"mu", 0.5, 0.0, 1e300, "1", "Coulomb friction coefficient (0: no friction)", offsetof(Coulomb, mu)},
    {"k_t", 0.0, 0.0, 1e300, "N/m/scale",
     "tangential stiffness per unit of the normal part's scale (1 linear: N/m; sqrt(delta reff) hertz: Pa); "
     "0: the normal part's default", offsetof(Coulomb, k_t_given)},
    {"gamma_t", 0.0, 0.0, 1e300, "1/s/scale", "mass-proportional tangential damping, c_T = gamma_t m_eff scale",
     offsetof(Coulomb, gamma_t)},
    {"c_t", 0.0, 0.0, 1e300, "N s/m/scale", "tangential damping, c_T += c_t scale", offsetof(Coulomb, c_t)},
    {"transport", 0.0, 0.0, 2.0, "1",
     "time integration of the tangential force (Desrues et al. 2019): 0 project (Eq. 11), 1 rotate (Eq. 24, keeps |f_T| "
     "to second order in the tilt), 2 implicit (Eq. 12)", offsetof(Coulomb, transport_given)},
};

static const TlContactPartOps coulomb_ops, coulomb_rotate_ops, coulomb_implicit_ops;

static TlStatus coulomb_setup(TlContactPart *part, const TlContactPart *normal)
{
  Coulomb *f = (Coulomb *)part;
  part->active = f->mu > 0.0;
  if (f->transport_given != floor(f->transport_given))
    TL_ERROR(TL_ERR_ARG, "coulomb friction part: transport %g must be 0 (project), 1 (rotate) or 2 (implicit)",
             f->transport_given);
  f->transport = (int)f->transport_given;
  part->ops = f->transport == TL_FRICTION_ROTATE     ? &coulomb_rotate_ops
              : f->transport == TL_FRICTION_IMPLICIT ? &coulomb_implicit_ops
                                                     : &coulomb_ops;
  part->history_doubles = f->transport == TL_FRICTION_ROTATE ? TL_FRICTION_HISTORY_ROTATE : TL_FRICTION_HISTORY;
  part->needs_rotation = 1;
  if (!part->active) return TL_OK;
  f->k_t = f->k_t_given;
  if (!(f->k_t > 0.0) && normal->ops->tangential_stiffness) f->k_t = normal->ops->tangential_stiffness(normal);
  if (!(f->k_t > 0.0) || !isfinite(f->k_t))
    TL_ERROR(TL_ERR_ARG,
             "coulomb friction part: tangential stiffness k_t = %g must be positive and finite; the normal part "
             "'%s' gives no default (set k_t, or what the normal part derives it from)",
             f->k_t, normal->ops->header.name);
  return TL_OK;
}

/* The chunk loop of one scheme: KERNEL is tl_friction_force or one of its
 * variants (same arguments). */
#define COULOMB_LOOP(name, KERNEL)                                                                              \
  static inline void name##_loop(const TlContactPart *part, TlContactChunk *c)                                 \
  {                                                                                                            \
    const Coulomb *cf = (const Coulomb *)part;                                                                 \
    const double kt = cf->k_t, gamma_t = cf->gamma_t, c_t = cf->c_t, mu = cf->mu, dt = c->dt;                  \
    const size_t off = part->history_offset;                                                                   \
    const int want = c->want_energy;                                                                           \
    for (size_t q = 0; q < c->n; ++q) {                                                                        \
      if (!c->on[q]) continue;                                                                                 \
      const double fn = c->fn[q], s = c->scale[q];                                                             \
      const double fn_plus = fn > 0.0 ? fn : 0.0;                                                              \
      double ct = gamma_t > 0.0 ? gamma_t * c->meff[q] * s : 0.0, et = 0.0;                                    \
      if (c_t > 0.0) ct += c_t * s;                                                                            \
      c->force[q] = tl_v3_add(c->force[q], KERNEL(c->history[q] + off, c->normal[q], c->vrel[q],               \
                                                  c->spin_mean[q], kt * s, ct, mu, fn_plus, dt,                \
                                                  want ? &et : NULL));                                         \
      if (want) c->energy[q] += et;                                                                            \
    }                                                                                                          \
  }                                                                                                            \
  TL_CONTACT_PART_LOOPS(name, name##_loop)
COULOMB_LOOP(coulomb, tl_friction_force)
COULOMB_LOOP(coulomb_rotate, tl_friction_force_rotate)
COULOMB_LOOP(coulomb_implicit, tl_friction_force_implicit)

static double coulomb_max_stiffness(const TlContactPart *part, double reff, double overlap)
{
  const TlContactPart *n = part->normal;
  return ((const Coulomb *)part)->k_t * n->ops->tangential_scale(n, reff, overlap);
}

#define COULOMB_OPS(name, evaluate, evaluate_hot)                                                                 \
  static const TlContactPartOps name = {                                                                        \
      {"contact_friction", "coulomb", "Coulomb friction with the objective tangential history of Desrues et al. 2019"},   \
      sizeof(Coulomb), (int)(sizeof params / sizeof params[0]), params, coulomb_setup, evaluate, evaluate_hot,  \
      NULL, NULL, NULL, NULL, coulomb_max_stiffness, NULL}
COULOMB_OPS(coulomb_ops, coulomb_evaluate, coulomb_evaluate_hot);
COULOMB_OPS(coulomb_rotate_ops, coulomb_rotate_evaluate, coulomb_rotate_evaluate_hot);
COULOMB_OPS(coulomb_implicit_ops, coulomb_implicit_evaluate, coulomb_implicit_evaluate_hot);

TlStatus tl_contact_register_coulomb(void);
TlStatus tl_contact_register_coulomb(void) { return tl_contact_part_register(&coulomb_ops); }
