/* Friction part "lammps_history": the tangential force of LAMMPS's pair
 * styles gran/hooke/history and gran/hertz/history (and of fix wall/gran
 * with those styles), with LAMMPS's parameters Kt, gamma_t, xmu, dampflag.
 *
 * The history is the accumulated tangential displacement ξ (3 doubles, of
 * j relative to i: minus LAMMPS's "shear" of i, so that it is odd under
 * exchange of i and j).  Each evaluation, with u the tangential relative
 * velocity at the contact point (spins with the radius as lever arm) and s
 * the normal part's tangential scale (1 Hooke, sqrt(δ R_eff) Hertz):
 *   ξ += u dt;  |ξ| is noted;  ξ -= (ξ·n) n   (projected on the current
 *   tangent plane, its length not restored);
 *   f_t = s (k_t ξ + m_eff γ_t u)             (spring and dashpot);
 *   if |f_t| > μ |f_n| (f_n the whole normal force, dashpot included, in
 *   absolute value): f_t is scaled to μ |f_n| and ξ reset so that the spring
 *   plus dashpot gives that force, ξ = r (ξ + m_eff γ_t u / k_t) - m_eff γ_t u / k_t
 *   with r = μ|f_n|/|f_t| (f_t = 0 if |ξ| was 0).
 * The contacts use the radius as lever arm (the torque on i is R_i n × f_t).
 *
 * Compared with "coulomb" (the objective law of seeds/004): the history is
 * a displacement, not a force built incrementally from k_t v_t dt, so a
 * stiffness that changes with the overlap (Hertz) acts on the whole
 * displacement at once; it is not rotated with the mean spin about the
 * normal (not objective); the cap acts on spring plus dashpot, with |f_n|
 * rather than its positive part; and the lever arms are R, not R - δ/2.
 *
 * k_t = 0 takes the normal part's default (2/7 k_n for lammps_hooke and
 * lammps_hertz, LAMMPS's Kt NULL); gamma_t < 0 takes half the normal part's
 * gamma_n (LAMMPS's gamma_t NULL); dampflag = 0 sets gamma_t to zero (LAMMPS
 * dampflag).  mu = 0 switches the part off (no history). */
#include <math.h>
#include <stddef.h>
#include "tl_contact_part.h"
#include "tl_registry.h"

typedef struct {
  TlContactPart base;
  double k_t_given, gamma_t_given, mu, dampflag;
  double k_t, gamma_t; /* as used */
} LammpsHistory;

static const TlParam params[] = {
    {"k_t", 0.0, 0.0, 1e300, "N/m/scale",
     "tangential stiffness, LAMMPS Kt (lammps_hooke: N/m; lammps_hertz: Pa); 0: the normal part's default, 2/7 k_n",
     offsetof(LammpsHistory, k_t_given)},
    {"gamma_t", -1.0, -1.0, 1e300, "1/s/scale",
     "tangential damping per unit effective mass, LAMMPS gamma_t (times the normal part's scale); < 0: gamma_n / 2",
     offsetof(LammpsHistory, gamma_t_given)},
    {"mu", 0.5, 0.0, 1e4, "1", "Coulomb friction coefficient, LAMMPS xmu (0: no friction)", offsetof(LammpsHistory, mu)},
    {"dampflag", 1.0, 0.0, 1.0, "1", "LAMMPS dampflag: 1 tangential damping on, 0 off (gamma_t = 0)",
     offsetof(LammpsHistory, dampflag)},
};

/* gamma_t from the parameters and the normal part, by LAMMPS's rules. */
static TlStatus lammps_gamma_t(const char *who, double given, double dampflag, const TlContactPart *normal,
                               double *gamma_t)
{
  if (dampflag != 0.0 && dampflag != 1.0)
    TL_ERROR(TL_ERR_ARG, "%s friction part: dampflag = %g must be 0 or 1", who, dampflag);
  *gamma_t = given;
  if (given < 0.0) {
    const TlParam *g = tl_param_find(normal->ops->params, normal->ops->n_params, "gamma_n");
    if (!g)
      TL_ERROR(TL_ERR_ARG, "%s friction part: gamma_t < 0 means gamma_n / 2, but the normal part '%s' has no gamma_n; "
               "set gamma_t", who, normal->ops->header.name);
    *gamma_t = 0.5 * *(const double *)((const char *)normal + g->offset);
  }
  if (dampflag == 0.0) *gamma_t = 0.0;
  return TL_OK;
}

static TlStatus history_setup(TlContactPart *part, const TlContactPart *normal)
{
  LammpsHistory *f = (LammpsHistory *)part;
  part->active = f->mu > 0.0;
  part->history_doubles = 3;
  part->needs_rotation = 1;
  part->lever_radius = 1;
  part->ignores_spins = 1; /* the spins enter through v_rel only */
  if (!part->active) return TL_OK;
  TL_CHECK(lammps_gamma_t("lammps_history", f->gamma_t_given, f->dampflag, normal, &f->gamma_t));
  f->k_t = f->k_t_given;
  if (!(f->k_t > 0.0) && normal->ops->tangential_stiffness) f->k_t = normal->ops->tangential_stiffness(normal);
  if (!(f->k_t > 0.0) || !isfinite(f->k_t))
    TL_ERROR(TL_ERR_ARG, "lammps_history friction part: k_t = %g must be positive and finite; the normal part '%s' "
             "gives no default (set k_t)", f->k_t, normal->ops->header.name);
  return TL_OK;
}

static inline void history_loop(const TlContactPart *part, TlContactChunk *c)
{
  const LammpsHistory *f = (const LammpsHistory *)part;
  const double kt = f->k_t, gamma_t = f->gamma_t, mu = f->mu, dt = c->dt;
  const size_t off = part->history_offset;
  const int want = c->want_energy;
  for (size_t q = 0; q < c->n; ++q) {
    if (!c->on[q]) continue;
    double *h = c->history[q] + off;
    const TlVec3 n = c->normal[q], vr = c->vrel[q];
    const double vn = tl_v3_dot(vr, n);
    const TlVec3 u = tl_v3_axpy(vr, -vn, n);
    TlVec3 xi = {h[0] + u.x * dt, h[1] + u.y * dt, h[2] + u.z * dt};
    const double xi_len2 = tl_v3_norm2(xi);
    xi = tl_v3_axpy(xi, -tl_v3_dot(xi, n), n);
    const double s = c->scale[q], damp = c->meff[q] * gamma_t;
    TlVec3 ft = tl_v3_scale(tl_v3_axpy(tl_v3_scale(xi, kt), damp, u), s);
    const double fs = tl_v3_norm(ft), cap = mu * fabs(c->fn[q]);
    if (fs > cap) {
      if (xi_len2 != 0.0) {
        const double r = cap / fs, d = damp / kt;
        xi = tl_v3_sub(tl_v3_scale(tl_v3_axpy(xi, d, u), r), tl_v3_scale(u, d));
        ft = tl_v3_scale(ft, r);
      } else {
        ft = tl_v3(0, 0, 0);
      }
    }
    h[0] = xi.x;
    h[1] = xi.y;
    h[2] = xi.z;
    c->force[q] = tl_v3_add(c->force[q], ft);
    if (want) c->energy[q] += 0.5 * kt * s * tl_v3_norm2(xi);
  }
}
TL_CONTACT_PART_LOOPS(lammps_history, history_loop)

static double history_max_stiffness(const TlContactPart *part, double reff, double overlap)
{
  const TlContactPart *n = part->normal;
  return ((const LammpsHistory *)part)->k_t * n->ops->tangential_scale(n, reff, overlap);
}

static const TlContactPartOps ops = {
    {"contact_friction", "lammps_history",
     "LAMMPS gran/*/history tangential force: displacement history, spring + dashpot capped at mu |f_n|"},
    sizeof(LammpsHistory), (int)(sizeof params / sizeof params[0]), params, history_setup, lammps_history_evaluate,
    lammps_history_evaluate_hot, NULL, NULL, NULL, NULL, history_max_stiffness, NULL};

TlStatus tl_contact_lammps_history_register_all(void);
TlStatus tl_contact_lammps_history_register_all(void) { return tl_contact_part_register(&ops); }
