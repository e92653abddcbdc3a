/* Input pulses (tl_pulse.h). */
#include "tl_pulse.h"

#include <math.h>

#include "tl_math.h"

static void raw(const TlPulse *p, double t, double out[3])
{
  double s = t - p->t0, I = p->amplitude;
  if (p->shape == TL_PULSE_RICKER) {
    double f = p->speed / p->wavelength, a = TL_PI * TL_PI * f * f, e = exp(-a * s * s);
    out[0] = I * (1.0 - 2.0 * a * s * s) * e;
    out[1] = I * (-6.0 * a * s + 4.0 * a * a * s * s * s) * e;
    out[2] = I * (-6.0 * a + 24.0 * a * a * s * s - 8.0 * a * a * a * s * s * s * s) * e;
  } else {
    double w = 2.0 * TL_PI * p->speed / p->wavelength, w2 = w * w, e = I * exp(-0.5 * w2 * s * s);
    out[0] = e;
    out[1] = -w2 * s * e;
    out[2] = (w2 * w2 * s * s - w2) * e;
  }
}

TlStatus tl_pulse_init(TlPulse *p, int shape, double amplitude, double wavelength, double speed)
{
  if (shape != TL_PULSE_GAUSSIAN && shape != TL_PULSE_RICKER)
    TL_ERROR(TL_ERR_ARG, "pulse: shape %d is neither gaussian (%d) nor ricker (%d)", shape, TL_PULSE_GAUSSIAN,
             TL_PULSE_RICKER);
  if (!isfinite(amplitude)) TL_ERROR(TL_ERR_ARG, "pulse: amplitude %g m is not finite", amplitude);
  if (!(wavelength > 0.0) || !isfinite(wavelength))
    TL_ERROR(TL_ERR_ARG, "pulse: wavelength %g m must be > 0 and finite", wavelength);
  if (!(speed > 0.0) || !isfinite(speed)) TL_ERROR(TL_ERR_ARG, "pulse: speed %g m/s must be > 0 and finite", speed);
  *p = (TlPulse){shape, amplitude, wavelength, speed, 0.0, 0, 0.0};
  p->t0 = shape == TL_PULSE_RICKER ? wavelength / speed : wavelength / (2.0 * speed);
  double o[3];
  raw(p, 0.0, o);
  p->u_initial = o[0];
  return TL_OK;
}

TlStatus tl_pulse_set_centre(TlPulse *p, double t0)
{
  if (!isfinite(t0)) TL_ERROR(TL_ERR_ARG, "pulse: centre %g s is not finite", t0);
  p->t0 = t0;
  double o[3];
  raw(p, 0.0, o);
  p->u_initial = o[0];
  return TL_OK;
}

void tl_pulse_eval(const TlPulse *p, double t, double out[3])
{
  raw(p, t, out);
  if (p->subtract_initial) out[0] -= p->u_initial;
}

double tl_pulse_peak_strain(const TlPulse *p)
{
  /* |u'(t)| / c at its maximum: Gaussian at s = 1/w; Ricker at the root of
   * d/ds (6 a s - 4 a^2 s^3) e^{-a s^2}, found by sampling finely. */
  if (p->shape == TL_PULSE_GAUSSIAN)
    return 2.0 * TL_PI / p->wavelength * fabs(p->amplitude) * exp(-0.5);
  double best = 0.0, span = 3.0 * p->wavelength / p->speed;
  for (int k = 0; k <= 20000; ++k) {
    double o[3];
    raw(p, p->t0 - span + 2.0 * span * k / 20000.0, o);
    best = fmax(best, fabs(o[1]));
  }
  return best / p->speed;
}

void tl_pulse_prescribed(double t, const double X[3], int component, void *ctx, double out[3])
{
  (void)X, (void)component;
  tl_pulse_eval((const TlPulse *)ctx, t, out);
}
