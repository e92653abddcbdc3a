/* Input pulses for wave tests, prescribed as a displacement history at a
 * boundary (tl_solid_prescribe through tl_pulse_prescribed).
 *
 *  TL_PULSE_GAUSSIAN  seeds/000 Eq. 15, which the paper calls a Ricker
 *                     wavelet but is a single positive Gaussian lobe:
 *                       u(t) = I exp(-1/2 (w (t - t0))^2),  w = 2 pi c / lambda,
 *                     t0 = lambda / (2 c) by default.  u(0) = I exp(-pi^2/2)
 *                     = 7.2e-3 I: a small step at t = 0, removed by
 *                     subtract_initial (u(t) - u(0) for all t, which leaves
 *                     -u(0) after the pulse).
 *  TL_PULSE_RICKER    the true Ricker wavelet (second derivative of a
 *                     Gaussian, zero mean) with peak frequency f = c / lambda:
 *                       u(t) = I (1 - 2 a s^2) exp(-a s^2),  a = (pi f)^2,  s = t - t0,
 *                     t0 = lambda / c by default (u(0) = -1.0e-3 I).
 * Velocity and acceleration are the exact derivatives.  The peak strain of
 * the travelling Gaussian is (2 pi / lambda) I exp(-1/2) = 3.81 I / lambda
 * (tl_pulse_peak_strain), not the I / lambda of the paper's Eq. 17. */
#ifndef TL_PULSE_H
#define TL_PULSE_H

#include "tl_error.h"

enum { TL_PULSE_GAUSSIAN = 0, TL_PULSE_RICKER = 1 };

typedef struct {
  int shape;            /* TL_PULSE_GAUSSIAN or TL_PULSE_RICKER */
  double amplitude;     /* I (m) */
  double wavelength;    /* lambda (m) */
  double speed;         /* c (m/s) */
  double t0;            /* centre (s) */
  int subtract_initial; /* u(t) - u(0) */
  double u_initial;     /* u(0) before the subtraction (set by tl_pulse_init) */
} TlPulse;

/* Fills p with the default centre; refuses non-positive wavelength or speed
 * and non-finite values, naming them. */
TlStatus tl_pulse_init(TlPulse *p, int shape, double amplitude, double wavelength, double speed);
/* Sets a centre other than the default (s, finite). */
TlStatus tl_pulse_set_centre(TlPulse *p, double t0);
/* out = (u, du/dt, d2u/dt2) at time t. */
void tl_pulse_eval(const TlPulse *p, double t, double out[3]);
/* Largest |du/dy| of the travelling pulse u(t - y/c) (its peak strain). */
double tl_pulse_peak_strain(const TlPulse *p);
/* TlPrescribed adaptor (tl_solid.h): ctx is a TlPulse; the same history at
 * every node of the set. */
void tl_pulse_prescribed(double t, const double X[3], int component, void *ctx, double out[3]);

#endif
