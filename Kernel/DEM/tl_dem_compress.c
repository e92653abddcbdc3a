/* Isotropic compression of a periodic cell to a mean pressure and its
 * relaxation under a pressure servo (tl_dem_compress): the preparation of a
 * packing, in 2-D (planar cell) or 3-D (deformable cell). */
#include "tl_dem_private.h"

#include <math.h>

static TlStatus pressure_of(TlDem *d, double *p)
{
  TlMat3 sc, sk;
  TL_CHECK(tl_dem_stress(d, &sc, &sk));
  double tr = 0.0;
  for (int k = 0; k < d->dim; ++k) tr += sc.m[k][k] + sk.m[k][k];
  *p = -tr / d->dim;
  return TL_OK;
}

/* ḣ = -rate h with the inert z row and column of a planar cell left zero. */
static TlStatus set_rate(TlDem *d, double rate)
{
  TlMat3 hd = tl_m3_scale(d->domain.h, -rate);
  if (d->domain.planar) hd.m[0][2] = hd.m[1][2] = hd.m[2][0] = hd.m[2][1] = hd.m[2][2] = 0.0;
  return tl_domain_set_h_rate(&d->domain, hd);
}

TlStatus tl_dem_compress(TlDem *d, const TlDemCompress *c, TlDemCompressResult *r)
{
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "compress: tl_dem_setup must come first");
  if (d->domain.kind != TL_DOMAIN_DEFORMABLE_CELL)
    TL_ERROR(TL_ERR_ARG, "compress: the domain must be a deformable (or planar) cell (kind %d)", (int)d->domain.kind);
  if (!(c->pressure > 0.0) || !isfinite(c->pressure)) TL_ERROR(TL_ERR_ARG, "compress: pressure %g must be > 0", c->pressure);
  if (!(c->rate > 0.0) || !(c->rate_fast > 0.0) || !isfinite(c->rate) || !isfinite(c->rate_fast))
    TL_ERROR(TL_ERR_ARG, "compress: rates %g and %g 1/s must be positive", c->rate, c->rate_fast);
  if (!(c->tolerance > 0.0) || !(c->pressure_tolerance > 0.0))
    TL_ERROR(TL_ERR_ARG, "compress: tolerances %g (balance) and %g (pressure) must be positive", c->tolerance,
             c->pressure_tolerance);
  if (c->control_every < 1 || c->max_steps < 0)
    TL_ERROR(TL_ERR_ARG, "compress: control_every %ld must be >= 1 and max_steps %ld >= 0", c->control_every,
             c->max_steps);
  const TlParticles *P = d->P;
  double solid = 0.0;
  for (size_t i = 0; i < P->n; ++i)
    solid += d->dim == 2 ? TL_PI * P->radius[i] * P->radius[i] : 4.0 / 3.0 * TL_PI * pow(P->radius[i], 3);
  int reached = 0, converged = 0;
  double p = 0.0, imbalance = 1.0;
  long k = 0;
  for (;; k += c->control_every) {
    TL_CHECK(pressure_of(d, &p));
    TL_CHECK(tl_dem_max_force_imbalance(d, &imbalance));
    const double err = (p - c->pressure) / c->pressure;
    if (!reached && p >= c->pressure) reached = 1;
    if (reached && fabs(err) < c->pressure_tolerance && imbalance < c->tolerance) {
      converged = 1;
      break;
    }
    if (k >= c->max_steps) break;
    double rate;
    if (!reached) {
      /* fast while the pressure is far below the target, slower near it */
      const double frac = fmax(p, 0.0) / c->pressure;
      rate = c->rate_fast * (1.0 - frac) + c->rate * frac;
    } else {
      /* servo: compress below the target, expand above */
      rate = fmax(-c->rate, fmin(c->rate, -c->rate * 2.0 * err));
    }
    TL_CHECK(set_rate(d, rate));
    TL_CHECK(tl_dem_step(d, c->control_every));
  }
  TL_CHECK(tl_domain_set_h_rate(&d->domain, tl_m3_zero()));
  r->steps = k;
  r->converged = converged;
  r->pressure = p;
  r->max_imbalance = imbalance;
  r->solid_fraction = solid / (d->dim == 2 ? tl_domain_area(&d->domain) : tl_domain_volume(&d->domain));
  TL_CHECK(tl_dem_coordination(d, &r->coordination, NULL));
  return TL_OK;
}
