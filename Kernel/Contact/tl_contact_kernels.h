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

/* Friction history: the stored tangential force (3 doubles). */
enum { TL_FRICTION_HISTORY = 3 };

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
