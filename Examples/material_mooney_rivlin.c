/* A new constitutive law from outside the library: the compressible
 * Mooney-Rivlin solid, in one file.
 *
 *   W = C10 (I1b - 3) + C01 (I2b - 3) + kappa/2 (J - 1)^2,
 *   I1b = J^(-2/3) I1,  I2b = J^(-4/3) I2,  J = sqrt(det C),
 *
 * on the elastic right Cauchy-Green tensor C = 1 + 2 gamma, with
 *
 *   S = 2 dW/dC = 2 C10 J^(-2/3) (1 - I1/3 C^-1)
 *               + 2 C01 J^(-4/3) (I1 1 - C - 2/3 I2 C^-1)
 *               + kappa J (J - 1) C^-1,
 *
 * and the tangent D = dS/dE = 2 dS/dC evaluated as the exact directional
 * derivative of S along each Voigt unit strain.  At C = 1 it is the linear
 * law with shear modulus 2 (C10 + C01) and bulk modulus kappa.
 *
 * A law is a TlMaterialOps table (tl_material.h): a parameter table
 * (TlParam: name, default, range, unit, help, offset in the derived
 * struct), setup (checks, derived constants) and a batched evaluate. */
#include <math.h>
#include <stddef.h>

#include "examples.h"
#include "tl_material.h"

typedef struct {
  TlMaterial base; /* first: the library allocates sizeof(MooneyRivlin) and fills base */
  double C10, C01, kappa;
} MooneyRivlin;

static const TlParam params[] = {
    {"C10", 0.4e6, 0.0, 1e300, "Pa", "coefficient of I1b - 3", offsetof(MooneyRivlin, C10)},
    {"C01", 0.1e6, 0.0, 1e300, "Pa", "coefficient of I2b - 3", offsetof(MooneyRivlin, C01)},
    {"kappa", 100e6, 1e-300, 1e300, "Pa", "bulk modulus (volumetric penalty)", offsetof(MooneyRivlin, kappa)},
};

static TlStatus setup(TlMaterial *m)
{
  MooneyRivlin *h = (MooneyRivlin *)m;
  if (!(h->C10 + h->C01 > 0.0))
    TL_ERROR(TL_ERR_ARG, "material mooney_rivlin: C10 + C01 = %g Pa must be > 0 (shear modulus)", h->C10 + h->C01);
  m->state_size = 0;
  return TL_OK;
}

static TlStatus evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma,
                         const double *state_old, double *state_new, TlMat3 *S, double *D, double *W)
{
  (void)F, (void)state_old, (void)state_new;
  const MooneyRivlin *h = (const MooneyRivlin *)m;
  const TlMat3 one = tl_m3_identity();
  for (size_t p = 0; p < npts; ++p) {
    TlMat3 C = tl_m3_add(one, tl_m3_scale(gamma[p], 2.0)), Ci;
    double detC = tl_m3_det(C);
    if (!(detC > 0.0) || !tl_m3_inverse(C, &Ci))
      TL_ERROR(TL_ERR_NUMERIC, "material mooney_rivlin: det C = %g at point %zu", detC, p);
    double J = sqrt(detC), I1 = tl_m3_trace(C), I2 = 0.5 * (I1 * I1 - tl_m3_ddot(C, C));
    double a = pow(J, -2.0 / 3.0), b = a * a;
    /* S = s1 + s2 + s3 as above. */
    TlMat3 A1, A2;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        A1.m[i][j] = (i == j) - I1 / 3.0 * Ci.m[i][j];
        A2.m[i][j] = I1 * (i == j) - C.m[i][j] - 2.0 / 3.0 * I2 * Ci.m[i][j];
        S[p].m[i][j] = 2.0 * h->C10 * a * A1.m[i][j] + 2.0 * h->C01 * b * A2.m[i][j] +
                       h->kappa * J * (J - 1.0) * Ci.m[i][j];
      }
    if (W) W[p] = h->C10 * (a * I1 - 3.0) + h->C01 * (b * I2 - 3.0) + 0.5 * h->kappa * (J - 1.0) * (J - 1.0);
    if (!D) continue;
    for (int K = 0; K < 6; ++K) {
      /* Along dgamma = unit strain K: dC = 2 dgamma. */
      TlMat3 dC = tl_m3_scale(tl_voigt_unit_strain(K), 2.0);
      TlMat3 dCi = tl_m3_scale(tl_m3_mul(tl_m3_mul(Ci, dC), Ci), -1.0);
      double dI1 = tl_m3_trace(dC), dI2 = I1 * dI1 - tl_m3_ddot(C, dC), dJ = 0.5 * J * tl_m3_ddot(Ci, dC);
      double da = -2.0 / 3.0 * a * dJ / J, db = -4.0 / 3.0 * b * dJ / J;
      TlMat3 dS;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double dA1 = -dI1 / 3.0 * Ci.m[i][j] - I1 / 3.0 * dCi.m[i][j];
          double dA2 = dI1 * (i == j) - dC.m[i][j] - 2.0 / 3.0 * (dI2 * Ci.m[i][j] + I2 * dCi.m[i][j]);
          dS.m[i][j] = 2.0 * h->C10 * (da * A1.m[i][j] + a * dA1) + 2.0 * h->C01 * (db * A2.m[i][j] + b * dA2) +
                       h->kappa * ((2.0 * J - 1.0) * dJ * Ci.m[i][j] + J * (J - 1.0) * dCi.m[i][j]);
        }
      double v[6];
      tl_voigt_from_sym(dS, v);
      for (int I = 0; I < 6; ++I) D[36 * p + 6 * I + K] = v[I];
    }
  }
  return TL_OK;
}

static int symmetric_tangent(const TlMaterial *m)
{
  (void)m;
  return 1; /* hyperelastic */
}

static const TlMaterialOps mooney_rivlin = {
    .header = {"material", "mooney_rivlin", "compressible Mooney-Rivlin solid (isochoric invariants)"},
    .size = sizeof(MooneyRivlin), .n_params = 3, .params = params, .setup = setup, .evaluate = evaluate,
    .symmetric_tangent = symmetric_tangent};

TlStatus example_mooney_rivlin_register(void)
{
  TL_CHECK(tl_material_register(&mooney_rivlin));
  return TL_OK;
}
