/* The linear path (tl_mech_linear) and the input pulses (tl_pulse), each
 * against what it claims in its header.
 *
 *  1. Linear system about u_r of a small nonlinear inner system (two dofs,
 *     a pre-load a, a cubic spring and a coupling spring): f(u_r) = f_int(u_r)
 *     exactly, f(u_r + du) = f_r + K du with K the inner tangent at u_r
 *     (written out by hand below), without f_r when it is subtracted, and
 *     W = W_r + f_r.du + 1/2 du.K du.
 *  2. Pulses: velocity and acceleration are the exact derivatives (against
 *     central differences of u and du/dt, both shapes), u(t0) = I, the
 *     default centres, subtract_initial removes u(0), the Gaussian's peak
 *     strain is the largest |du/dt| / c, and bad input is refused. */
#include <math.h>
#include <string.h>
#include "talus.h"
#include "tl_math.h"
#include "tl_mech_linear.h"
#include "tl_memory.h"
#include "tl_pulse.h"
#include "tl_test.h"

/* f0 = a0 + k0 u0 + c u0^3 + s (u0 - u1), f1 = a1 + k1 u1 + s (u1 - u0). */
typedef struct {
  TlMechSystem base;
  double a[2], k[2], c, s, W_at;
} Toy;

static const TlSparseIndex toy_ptr[2] = {0, 2}, toy_dofs[2] = {0, 1};

static TlStatus toy_matrix(TlMechSystem *sys, int upper, TlSparse **K)
{
  (void)sys;
  return tl_sparse_create_from_elements(2, upper, 1, toy_ptr, toy_dofs, 0, K);
}

static TlStatus toy_force(TlMechSystem *sys, double t, const double *u, const double *v, double *f)
{
  (void)t, (void)v;
  const Toy *y = (const Toy *)sys;
  f[0] = y->a[0] + y->k[0] * u[0] + y->c * u[0] * u[0] * u[0] + y->s * (u[0] - u[1]);
  f[1] = y->a[1] + y->k[1] * u[1] + y->s * (u[1] - u[0]);
  return TL_OK;
}

static void toy_K(const Toy *y, const double *u, double Ke[4])
{
  Ke[0] = y->k[0] + 3.0 * y->c * u[0] * u[0] + y->s;
  Ke[1] = Ke[2] = -y->s;
  Ke[3] = y->k[1] + y->s;
}

static TlStatus toy_tangent(TlMechSystem *sys, double t, const double *u, const double *v, double c_u, double c_v,
                            TlSparse *K)
{
  (void)t, (void)v, (void)c_v;
  double Ke[4];
  toy_K((const Toy *)sys, u, Ke);
  return tl_sparse_add_element(K, 2, toy_dofs, c_u, Ke);
}

static TlStatus toy_external(TlMechSystem *sys, double t, const double *u, double *f)
{
  (void)sys, (void)t, (void)u;
  f[0] = f[1] = 0.0;
  return TL_OK;
}

static TlStatus toy_mass(TlMechSystem *sys, double *m)
{
  (void)sys;
  m[0] = m[1] = 1.0;
  return TL_OK;
}

static TlStatus toy_energy(TlMechSystem *sys, const double *u, double *W)
{
  (void)u;
  *W = ((const Toy *)sys)->W_at;
  return TL_OK;
}

static const TlMechSystemOps toy_ops = {
    .header = {"mech_system", "toy", "two nonlinear springs"},
    .create_matrix = toy_matrix,
    .internal_force = toy_force,
    .internal_tangent = toy_tangent,
    .external_force = toy_external,
    .lumped_mass = toy_mass,
    .strain_energy = toy_energy,
};

static void check_linear(void)
{
  Toy toy = {.base = {.ops = &toy_ops, .ndof = 2, .symmetric = 1},
             .a = {0.7, -1.3}, .k = {2.0, 5.0}, .c = 40.0, .s = 3.0, .W_at = 0.25};
  const double ur[2] = {0.1, -0.2}, du[2] = {0.03, -0.05};
  double fr[2], Ke[4];
  toy_force(&toy.base, 0.0, ur, NULL, fr);
  toy_K(&toy, ur, Ke);
  for (int sub = 0; sub < 2; ++sub) {
    TlMechSystem *lin = NULL;
    TL_TEST_STATUS(tl_mech_linear_create(&toy.base, 0.0, ur, sub, &lin), TL_OK);
    if (!lin) return;
    double f[2], u[2] = {ur[0] + du[0], ur[1] + du[1]}, W = 0.0;
    TL_TEST_STATUS(lin->ops->internal_force(lin, 0.0, ur, NULL, f), TL_OK);
    for (int i = 0; i < 2; ++i) {
      TL_TEST_ASSERT(tl_mech_linear_reference_force(lin)[i] == fr[i], "f_r[%d] = %.17g, inner f_int(u_r) %.17g", i,
                     tl_mech_linear_reference_force(lin)[i], fr[i]);
      /* at u_r: f_r itself, or nothing once subtracted */
      TL_TEST_REL(f[i] + (sub ? fr[i] : 0.0), fr[i], 1e-15);
    }
    TL_TEST_STATUS(lin->ops->internal_force(lin, 0.0, u, NULL, f), TL_OK);
    for (int i = 0; i < 2; ++i) {
      double Kdu = Ke[2 * i] * du[0] + Ke[2 * i + 1] * du[1];
      TL_TEST_REL(f[i], (sub ? 0.0 : fr[i]) + Kdu, 1e-13);
    }
    TL_TEST_STATUS(lin->ops->strain_energy(lin, u, &W), TL_OK);
    double quad = 0.5 * (du[0] * (Ke[0] * du[0] + Ke[1] * du[1]) + du[1] * (Ke[2] * du[0] + Ke[3] * du[1]));
    double lin_part = fr[0] * du[0] + fr[1] * du[1];
    TL_TEST_REL(W, sub ? quad : toy.W_at + lin_part + quad, 1e-13);
    printf("linear, reference force %s: f = (%.6g, %.6g) N at u_r + du, W = %.6g J\n", sub ? "subtracted" : "kept", f[0],
           f[1], W);
    tl_mech_system_destroy(&lin);
  }
  toy.base.damped = 1;
  TlMechSystem *lin = NULL;
  TL_TEST_STATUS(tl_mech_linear_create(&toy.base, 0.0, ur, 0, &lin), TL_ERR_UNSUPPORTED);
}

static void check_pulse(int shape)
{
  const double I = 2e-4, lambda = 0.5, c = 2000.0;
  TlPulse p;
  TL_TEST_STATUS(tl_pulse_init(&p, shape, I, lambda, c), TL_OK);
  TL_TEST_REL(p.t0, shape == TL_PULSE_RICKER ? lambda / c : lambda / (2.0 * c), 1e-15);
  double o[3], lo[3], hi[3];
  tl_pulse_eval(&p, p.t0, o);
  TL_TEST_REL(o[0], I, 1e-15);
  /* derivative scales: I w and I w^2 with w = 2 pi c / lambda */
  const double w = 2.0 * TL_PI * c / lambda, T = lambda / c, h = 1e-5 * T;
  double worst1 = 0.0, worst2 = 0.0, peak = 0.0;
  for (int k = 0; k <= 40; ++k) {
    double t = p.t0 + (k - 20) * 0.05 * T;
    tl_pulse_eval(&p, t, o);
    tl_pulse_eval(&p, t - h, lo);
    tl_pulse_eval(&p, t + h, hi);
    worst1 = fmax(worst1, fabs(o[1] - (hi[0] - lo[0]) / (2.0 * h)) / (I * w));
    worst2 = fmax(worst2, fabs(o[2] - (hi[1] - lo[1]) / (2.0 * h)) / (I * w * w));
  }
  for (int k = 0; k <= 200000; ++k) {
    tl_pulse_eval(&p, p.t0 - 2.0 * T + 4.0 * T * k / 200000.0, o);
    peak = fmax(peak, fabs(o[1]));
  }
  printf("%s pulse: derivatives against central differences within %.2e (du/dt) and %.2e (d2u/dt2) of I w^k; "
         "sampled peak strain %.6g, tl_pulse_peak_strain %.6g\n",
         shape == TL_PULSE_RICKER ? "Ricker" : "Gaussian", worst1, worst2, peak / c, tl_pulse_peak_strain(&p));
  /* central differences err by h^2 w^2 / 6 ~ 7e-9 of the scale */
  TL_TEST_ASSERT(worst1 <= 1e-7, "du/dt differs from the difference quotient by %g of I w", worst1);
  TL_TEST_ASSERT(worst2 <= 1e-7, "d2u/dt2 differs from the difference quotient by %g of I w^2", worst2);
  TL_TEST_REL(tl_pulse_peak_strain(&p), peak / c, 1e-6);
  /* the velocity rises before the peak: sign of the derivative */
  tl_pulse_eval(&p, p.t0 - 0.1 * T, o);
  if (shape == TL_PULSE_GAUSSIAN) TL_TEST_ASSERT(o[1] > 0.0, "Gaussian: du/dt = %g before the peak, expected > 0", o[1]);
  else TL_TEST_ASSERT(o[1] > 0.0, "Ricker: du/dt = %g just before the peak, expected > 0", o[1]);
  p.subtract_initial = 1;
  tl_pulse_eval(&p, 0.0, o);
  TL_TEST_ASSERT(o[0] == 0.0, "subtract_initial: u(0) = %g, expected 0", o[0]);
  TL_TEST_ASSERT(p.u_initial != 0.0, "u(0) before the subtraction is %g (expected the pulse's small step)",
                 p.u_initial);
}

int main(void)
{
  check_linear();
  check_pulse(TL_PULSE_GAUSSIAN);
  check_pulse(TL_PULSE_RICKER);
  TlPulse p;
  TL_TEST_STATUS(tl_pulse_init(&p, 2, 1e-4, 0.5, 2000.0), TL_ERR_ARG);
  TL_TEST_STATUS(tl_pulse_init(&p, TL_PULSE_GAUSSIAN, 1e-4, 0.0, 2000.0), TL_ERR_ARG);
  TL_TEST_STATUS(tl_pulse_init(&p, TL_PULSE_GAUSSIAN, 1e-4, 0.5, -1.0), TL_ERR_ARG);
  TL_TEST_STATUS(tl_pulse_init(&p, TL_PULSE_GAUSSIAN, NAN, 0.5, 2000.0), TL_ERR_ARG);
  return tl_test_report();
}
