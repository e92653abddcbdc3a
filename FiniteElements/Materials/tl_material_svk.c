/* The Saint Venant-Kirchhoff law: Hooke's law between the second
 * Piola-Kirchhoff stress and the Green strain,
 *
 *   S = lambda tr(gamma) 1 + 2 mu gamma,   W = lambda/2 tr(gamma)^2 + mu gamma : gamma,
 *
 * with the Lame constants from E and nu and D = dS/dgamma constant.  It is
 * what CalculiX and Abaqus use for a linear-elastic material under NLGEOM,
 * so a comparison with them at finite strain needs this law rather than
 * "hooke" (seeds/001 Eq. 34), which agrees with it to first order only.
 * Hyperelastic: symmetric tangent, closed-form energy.  The law is not
 * polyconvex and softens in compression (S -> 0 as a fibre collapses);
 * tl_material_evaluate still refuses det F <= 0. */
#include <stddef.h>

#include "tl_material.h"

typedef struct {
  TlMaterial base;
  double E, nu;
  double lambda, mu;
} TlSaintVenantKirchhoff;

static const TlMaterialParam params[] = {
    {"E", 1e8, 1e-300, 1e300, "Pa", "Young's modulus", offsetof(TlSaintVenantKirchhoff, E)},
    {"nu", 0.0, -0.999999, 0.499999, "1", "Poisson's ratio", offsetof(TlSaintVenantKirchhoff, nu)},
};

static TlStatus setup(TlMaterial *m)
{
  TlSaintVenantKirchhoff *h = (TlSaintVenantKirchhoff *)m;
  if (!(h->E > 0.0)) TL_ERROR(TL_ERR_ARG, "material %s: E = %g Pa must be > 0", m->ops->header.name, h->E);
  if (!(h->nu > -1.0 && h->nu < 0.5))
    TL_ERROR(TL_ERR_ARG, "material %s: nu = %g outside (-1, 0.5)", m->ops->header.name, h->nu);
  h->mu = h->E / (2.0 * (1.0 + h->nu));
  h->lambda = h->E * h->nu / ((1.0 + h->nu) * (1.0 - 2.0 * h->nu));
  m->state_size = 0;
  return TL_OK;
}

/* S (Voigt) from gamma (Voigt, tensor shear components). */
static inline void stress6(const TlSaintVenantKirchhoff *h, const double g[6], double s[6])
{
  const double a = h->lambda * (g[0] + g[1] + g[2]), b = 2.0 * h->mu;
  s[0] = a + b * g[0], s[1] = a + b * g[1], s[2] = a + b * g[2];
  s[3] = b * g[3], s[4] = b * g[4], s[5] = b * g[5];
}

static TlStatus evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma,
                         const double *state_old, double *state_new, TlMat3 *S, double *D, double *W)
{
  (void)F, (void)state_old, (void)state_new;
  const TlSaintVenantKirchhoff *h = (const TlSaintVenantKirchhoff *)m;
  for (size_t p = 0; p < npts; ++p) {
    double g[6], s[6];
    tl_voigt_from_sym(gamma[p], g);
    stress6(h, g, s);
    S[p] = tl_voigt_to_sym(s);
    if (W) {
      const double tr = g[0] + g[1] + g[2];
      const double gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2] + 2.0 * (g[3] * g[3] + g[4] * g[4] + g[5] * g[5]);
      W[p] = 0.5 * h->lambda * tr * tr + h->mu * gg;
    }
    if (D) {
      /* dS_I / d eps_J with engineering shear eps_J = 2 gamma_J (J >= 3). */
      double *d = D + 36 * p;
      for (int k = 0; k < 36; ++k) d[k] = 0.0;
      for (int I = 0; I < 3; ++I) {
        for (int J = 0; J < 3; ++J) d[6 * I + J] = h->lambda;
        d[6 * I + I] += 2.0 * h->mu;
        d[6 * (I + 3) + I + 3] = h->mu;
      }
    }
  }
  return TL_OK;
}

static TlStatus stress_soa(const TlMaterial *m, size_t npts, const double *gamma, size_t ldg, double *S, size_t lds)
{
  const TlSaintVenantKirchhoff *h = (const TlSaintVenantKirchhoff *)m;
  for (size_t p = 0; p < npts; ++p) {
    double g[6], s[6];
    for (int I = 0; I < 6; ++I) g[I] = gamma[I * ldg + p];
    stress6(h, g, s);
    for (int I = 0; I < 6; ++I) S[I * lds + p] = s[I];
  }
  return TL_OK;
}

static int symmetric_tangent(const TlMaterial *m)
{
  (void)m;
  return 1;
}

static const TlMaterialOps saint_venant_kirchhoff_ops = {
    .header = {"material", "saint_venant_kirchhoff",
               "Saint Venant-Kirchhoff: S = lambda tr(E) 1 + 2 mu E (CalculiX's and Abaqus's linear "
               "elasticity under NLGEOM)"},
    .size = sizeof(TlSaintVenantKirchhoff), .n_params = 2, .params = params, .setup = setup,
    .evaluate = evaluate, .stress_soa = stress_soa, .symmetric_tangent = symmetric_tangent};

TlStatus tl_material_svk_register_all(void)
{
  TL_CHECK(tl_material_register(&saint_venant_kirchhoff_ops));
  return TL_OK;
}
