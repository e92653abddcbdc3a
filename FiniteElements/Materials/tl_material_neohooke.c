/* The compressible Neo-Hookean law on the elastic right Cauchy-Green tensor
 * Ce = 1 + 2 gamma:
 *
 *   W = mu/2 (tr Ce - 3) - mu ln J + lambda/2 (ln J)^2,  J = sqrt(det Ce),
 *   S = mu (1 - Ce^-1) + lambda ln J Ce^-1,
 *
 * with lambda and mu from E and nu.  Hyperelastic: symmetric tangent. */
#include <math.h>
#include <stddef.h>

#include "tl_material.h"

typedef struct {
  TlMaterial base;
  double E, nu;
  double lambda, mu;
} TlNeoHookean;

static const TlMaterialParam params[] = {
    {"E", 1e8, 1e-300, 1e300, "Pa", "Young's modulus", offsetof(TlNeoHookean, E)},
    {"nu", 0.3, -0.999999, 0.499999, "1", "Poisson's ratio", offsetof(TlNeoHookean, nu)},
};

static TlStatus setup(TlMaterial *m)
{
  TlNeoHookean *h = (TlNeoHookean *)m;
  if (!(h->E > 0.0)) TL_ERROR(TL_ERR_ARG, "material neo_hookean: E = %g Pa must be > 0", h->E);
  if (!(h->nu > -1.0 && h->nu < 0.5))
    TL_ERROR(TL_ERR_ARG, "material neo_hookean: nu = %g outside (-1, 0.5)", h->nu);
  h->mu = h->E / (2.0 * (1.0 + h->nu));
  h->lambda = h->E * h->nu / ((1.0 + h->nu) * (1.0 - 2.0 * h->nu));
  m->state_size = 0;
  return TL_OK;
}

static TlStatus evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma,
                         const double *state_old, double *state_new, TlMat3 *S, double *D,
                         double *W)
{
  (void)F, (void)state_old, (void)state_new;
  const TlNeoHookean *h = (const TlNeoHookean *)m;
  for (size_t p = 0; p < npts; ++p) {
    TlMat3 Ce = tl_m3_add(tl_m3_identity(), tl_m3_scale(gamma[p], 2.0)), Ci;
    double detC = tl_m3_det(Ce);
    if (!(detC > 0.0) || !tl_m3_inverse(Ce, &Ci))
      TL_ERROR(TL_ERR_NUMERIC, "material neo_hookean: det Ce = %g at point %zu", detC, p);
    double lnJ = 0.5 * log(detC);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        S[p].m[i][j] = h->mu * ((i == j) - Ci.m[i][j]) + h->lambda * lnJ * Ci.m[i][j];
    if (W) {
      /* mu/2 (tr Ce - 3) - mu ln J = mu/2 tr[A - log(1 + A)], A = 2 gamma,
       * summed without cancellation at small strain. */
      TlMat3 A = tl_m3_scale(gamma[p], 2.0);
      double dev = tl_material_trace_series(A, 1);
      double lnJ2 = 0.5 * (tl_m3_trace(A) - dev);
      W[p] = 0.5 * h->mu * dev + 0.5 * h->lambda * lnJ2 * lnJ2;
    }
    if (D) {
      for (int J = 0; J < 6; ++J) {
        TlMat3 dg = tl_voigt_unit_strain(J);
        /* dCe = 2 dgamma, dCi = -Ci dCe Ci, d ln J = Ci : dgamma. */
        TlMat3 dCi = tl_m3_scale(tl_m3_mul(tl_m3_mul(Ci, dg), Ci), -2.0);
        double dlnJ = tl_m3_ddot(Ci, dg);
        double v[6];
        TlMat3 dS;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            dS.m[i][j] = (h->lambda * lnJ - h->mu) * dCi.m[i][j] + h->lambda * dlnJ * Ci.m[i][j];
        tl_voigt_from_sym(dS, v);
        for (int I = 0; I < 6; ++I) D[36 * p + 6 * I + J] = v[I];
      }
    }
  }
  return TL_OK;
}

static int symmetric_tangent(const TlMaterial *m)
{
  (void)m;
  return 1;
}

const TlMaterialOps tl_material_neo_hookean_ops = {
    .header = {"material", "neo_hookean", "compressible Neo-Hookean law"},
    .size = sizeof(TlNeoHookean), .n_params = 2, .params = params, .setup = setup,
    .evaluate = evaluate, .symmetric_tangent = symmetric_tangent};
