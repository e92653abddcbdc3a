/* Inline pieces of the built-in contact parts: the frame-invariant Coulomb
 * friction of seeds/004 (Eqs. 22-26), rolling resistance and the damping
 * ratio from a restitution coefficient.  A part's chunk loop calls them per
 * contact, so a part stays one tight loop; a part written elsewhere may use
 * them too. */
#ifndef TL_CONTACT_KERNELS_H
#define TL_CONTACT_KERNELS_H

#include <math.h>
#include "tl_contact_law.h"
#include "tl_math.h"

/* Damping ratio η of a linear spring-dashpot that gives restitution e for a
 * contact without attraction clamp: e = exp(-π η / sqrt(1 - η²)). */
static inline double tl_damping_ratio_from_restitution(double e)
{
  if (e >= 1.0) return 0.0;
  double l = log(e);
  return -l / sqrt(TL_PI * TL_PI + l * l);
}

/* Friction history: the stored tangential force (3 doubles); the rotating
 * transport also keeps the normal of the last step (3 more). */
enum { TL_FRICTION_HISTORY = 3, TL_FRICTION_HISTORY_ROTATE = 6 };

/* How the tangential force of the last step is carried to the current
 * contact plane and integrated (seeds/004 §2.3.3, §2.4.1; the coulomb part's
 * parameter `transport`):
 *   PROJECT   Eq. 11, semi-explicit, f_T^i projected on Π^f: (I - n^f⊗n^f)
 *             f_T^i; a tilt of the plane by θ shortens the force by cos θ
 *             (tl_friction_force; the default, today's results);
 *   ROTATE    Eq. 24-25, semi-explicit, f_T^i turned from the old plane to
 *             the new one to first order, (I - n^i⊗n^f) f_T^i =
 *             f_T^i - (f_T^i·n^f) n^i, then projected on Π^f to stay
 *             tangent; keeps ‖f_T‖ to O(θ²) (tl_friction_force_rotate);
 *   IMPLICIT  Eq. 12, fully implicit: spin term and Coulomb condition at the
 *             end of the step, solved in closed form
 *             (tl_friction_force_implicit). */
typedef enum { TL_FRICTION_PROJECT = 0, TL_FRICTION_ROTATE = 1, TL_FRICTION_IMPLICIT = 2 } TlFrictionTransport;

/* Frame-invariant tangential force, the semi-explicit scheme of seeds/004
 * that the paper's implementation uses (Eq. 11 with Eqs. 23 and 26):
 *   f_T^fe = (I - n^f ⊗ n^f) f_T^i + dt C_N^f n^f ∧ f_T^i + k_T Δu_T,
 *   Δu_T = dt P_Π V^r,  C_N = ½ (ω_i + ω_j) · n^f,
 * then cut to the Coulomb cone μ <f_N>_+.  The projection on the current
 * plane carries the stored force with the tilting contact plane and the
 * C_N term with the mean spin about the normal, which makes the law
 * objective (§2.3.2).
 *   h        history: f_T^i (zero at first touch), updated to f_T^f
 *   n        current normal n^f (i -> j)
 *   vrel     relative velocity of j w.r.t. i at the contact point
 *   spin     (ω_i + ω_j) / 2
 *   k_t      current tangential stiffness (N/m)
 *   c_t      tangential viscous coefficient (N s/m), 0 for none
 *   fn_plus  <f_N>_+, the repulsive normal force clamped at 0
 * Returns the tangential force on i; *elastic (if not NULL) receives the
 * energy stored in the tangential spring. */
static inline TlVec3 tl_friction_force(double *h, TlVec3 n, TlVec3 vrel, TlVec3 spin, double k_t,
                                       double c_t, double mu, double fn_plus, double dt,
                                       double *elastic)
{
  TlVec3 f = {h[0], h[1], h[2]};
  /* Eq. 23: tangential relative velocity */
  double vn = tl_v3_dot(vrel, n);
  TlVec3 vt = tl_v3_axpy(vrel, -vn, n);
  /* Eq. 11 */
  TlVec3 trial = tl_v3_axpy(f, -tl_v3_dot(f, n), n);
  double cn = dt * tl_v3_dot(spin, n);
  trial = tl_v3_add(trial, tl_v3_scale(tl_v3_cross(n, f), cn));
  trial = tl_v3_axpy(trial, k_t * dt, vt);
  double cap = mu * fn_plus;
  TlVec3 total;
  double t2 = tl_v3_norm2(trial);
  if (t2 > cap * cap) {
    /* Eq. 26: the spring is cut to the Coulomb cone and the contact slides;
     * no viscous part while sliding, so the cut never stores energy */
    double s = t2 > 0.0 ? cap / sqrt(t2) : 0.0;
    trial = tl_v3_scale(trial, s);
    total = trial;
  } else {
    /* sticking: the viscous part acts on top of the spring, the sum kept
     * inside the cone without changing the stored spring force */
    total = tl_v3_axpy(trial, c_t, vt);
    double q2 = tl_v3_norm2(total);
    if (c_t > 0.0 && q2 > cap * cap) total = tl_v3_scale(total, cap / sqrt(q2));
  }
  h[0] = trial.x; h[1] = trial.y; h[2] = trial.z;
  if (elastic) *elastic = k_t > 0.0 ? 0.5 * tl_v3_norm2(trial) / k_t : 0.0;
  return total;
}

/* The end of a step of the rotating and implicit schemes: `spring` is the
 * tangential spring force, already within the cone μ <f_N>_+ (cap); the
 * viscous part acts on top while sticking, the sum kept inside the cone
 * without changing the spring (as tl_friction_force does). */
static inline TlVec3 tl_friction_viscous(TlVec3 spring, TlVec3 vt, double c_t, double cap, int sliding)
{
  if (sliding || !(c_t > 0.0)) return spring;
  TlVec3 total = tl_v3_axpy(spring, c_t, vt);
  double q2 = tl_v3_norm2(total);
  return q2 > cap * cap ? tl_v3_scale(total, cap / sqrt(q2)) : total;
}

/* The semi-explicit scheme with the transport of Eq. 24 (ROTATE above):
 *   f_T^fe = P_Π^f [(I - n^i⊗n^f) f_T^i] + dt C_N^f n^f ∧ f_T^i + k_T Δu_T,
 * then the cut of Eq. 26.  h holds f_T^i (h[0..2]) and n^i (h[3..5]; zero at
 * first touch, when f_T^i is zero too) and receives f_T^f and n^f.  Other
 * arguments and the result as tl_friction_force. */
static inline TlVec3 tl_friction_force_rotate(double *h, TlVec3 n, TlVec3 vrel, TlVec3 spin, double k_t,
                                              double c_t, double mu, double fn_plus, double dt,
                                              double *elastic)
{
  const TlVec3 f = {h[0], h[1], h[2]}, ni = {h[3], h[4], h[5]};
  const double vn = tl_v3_dot(vrel, n);
  const TlVec3 vt = tl_v3_axpy(vrel, -vn, n);
  /* Eq. 24: f - (f·n^f) n^i, a first-order rotation of the old plane onto
   * the new one; the projection removes the O(θ³) normal remainder */
  TlVec3 q = tl_v3_axpy(f, -tl_v3_dot(f, n), ni);
  TlVec3 trial = tl_v3_axpy(q, -tl_v3_dot(q, n), n);
  const double cn = dt * tl_v3_dot(spin, n);
  trial = tl_v3_add(trial, tl_v3_scale(tl_v3_cross(n, f), cn));
  trial = tl_v3_axpy(trial, k_t * dt, vt);
  const double cap = mu * fn_plus;
  const double t2 = tl_v3_norm2(trial);
  const int sliding = t2 > cap * cap;
  if (sliding) trial = tl_v3_scale(trial, t2 > 0.0 ? cap / sqrt(t2) : 0.0);
  h[0] = trial.x; h[1] = trial.y; h[2] = trial.z;
  h[3] = n.x; h[4] = n.y; h[5] = n.z;
  if (elastic) *elastic = k_t > 0.0 ? 0.5 * tl_v3_norm2(trial) / k_t : 0.0;
  return tl_friction_viscous(trial, vt, c_t, cap, sliding);
}

/* The fully implicit scheme of Eq. 12: with φ = P_Π^f f_T^i + k_T Δu_T,
 * c = dt C_N^f and x = dt k_T λ^f,
 *   (1 + x) f_T^f - c n^f ∧ f_T^f = φ,
 * solved in closed form: elastic (x = 0) f_T^fe = (φ + c n∧φ) / (1 + c²); if
 * ‖f_T^fe‖ > μ <f_N>_+, 1 + x = sqrt(1 + A) with A = (1 + c²)(‖f_T^fe‖² /
 * (μ f_N)² - 1) (the text's (A + |A|)/2 with A > 0), and
 * f_T^f = ((1 + x) φ + c n∧φ) / ((1 + x)² + c²), on the cone.  History and
 * arguments as tl_friction_force (3 doubles). */
static inline TlVec3 tl_friction_force_implicit(double *h, TlVec3 n, TlVec3 vrel, TlVec3 spin, double k_t,
                                                double c_t, double mu, double fn_plus, double dt,
                                                double *elastic)
{
  const TlVec3 f = {h[0], h[1], h[2]};
  const double vn = tl_v3_dot(vrel, n);
  const TlVec3 vt = tl_v3_axpy(vrel, -vn, n);
  TlVec3 phi = tl_v3_axpy(f, -tl_v3_dot(f, n), n);
  phi = tl_v3_axpy(phi, k_t * dt, vt);
  const double c = dt * tl_v3_dot(spin, n), c2 = c * c;
  const TlVec3 nphi = tl_v3_cross(n, phi);
  const double cap = mu * fn_plus;
  /* ‖f_T^fe‖² = ‖φ‖² / (1 + c²) */
  const double fe2 = tl_v3_norm2(phi) / (1.0 + c2);
  TlVec3 out;
  int sliding = fe2 > cap * cap;
  if (!sliding) {
    out = tl_v3_scale(tl_v3_axpy(phi, c, nphi), 1.0 / (1.0 + c2));
  } else if (!(cap > 0.0)) {
    out = tl_v3(0, 0, 0);
  } else {
    const double a = (1.0 + c2) * (fe2 / (cap * cap) - 1.0);
    const double onex = sqrt(1.0 + a);
    out = tl_v3_scale(tl_v3_axpy(tl_v3_scale(phi, onex), c, nphi), 1.0 / (onex * onex + c2));
  }
  h[0] = out.x; h[1] = out.y; h[2] = out.z;
  if (elastic) *elastic = k_t > 0.0 ? 0.5 * tl_v3_norm2(out) / k_t : 0.0;
  return tl_friction_viscous(out, vt, c_t, cap, sliding);
}

/* Rolling resistance: a couple on i of magnitude mu_r reff fn_plus opposing
 * the relative rolling spin of i with respect to j (the part of ω_i - ω_j
 * perpendicular to n). */
static inline TlVec3 tl_rolling_couple(TlVec3 n, TlVec3 spin_rel, double mu_r, double reff,
                                       double fn_plus)
{
  TlVec3 w = tl_v3_axpy(spin_rel, -tl_v3_dot(spin_rel, n), n);
  double wn = tl_v3_norm(w);
  if (!(wn > 1e-300)) return (TlVec3){0, 0, 0};
  return tl_v3_scale(w, mu_r * reff * fn_plus / wn);
}

#endif
