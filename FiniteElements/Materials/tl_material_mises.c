/* "mises_plastic": von Mises plasticity on the total-Lagrangian pair
 * (S, E), an analytic stand-in for a sub-scale law at the Gauss points of a
 * FEM x DEM run (seeds/004): path dependent, a peak and, with H < 0, a
 * softening branch down to a residual strength, so the macro loop's
 * history, step halving and loose post-peak tolerance are tested on a law
 * whose answer is known.
 *
 *   E = E_e + E_p,  S = lambda tr(E_e) 1 + 2 mu E_e,
 *   f = q(S) - max(sigma_y + H kappa, sigma_res) <= 0,  q = sqrt(3/2 dev S : dev S),
 *
 * integrated by the radial return (backward Euler, exact for this linear
 * hardening), with the consistent tangent
 *   D = K 1(x)1 + 2 mu (1 - 3 mu dg / q_tr) I_dev + 6 mu^2 (dg / q_tr - 1/(3 mu + H)) n(x)n
 * (n = dev S_tr / |dev S_tr|).  `operator` chooses what the solid gets as D:
 *   0  the consistent tangent (quadratic Newton);
 *   1  the elastic tangent, an upper bound like the Kruyt operator UKO of a
 *      DEM cell (Newton converges linearly, more iterations).
 * State per point (7 doubles): E_p (Voigt, tensor shear components) and the
 * accumulated plastic multiplier kappa. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "tl_material.h"

typedef struct {
  TlMaterial base;
  double E, nu, sigma_y, H, sigma_res, op;
  double lambda, mu, K;
} TlMises;

static const TlMaterialParam params[] = {
    {"E", 1e8, 1e-300, 1e300, "Pa", "Young's modulus", offsetof(TlMises, E)},
    {"nu", 0.3, -0.999999, 0.499999, "1", "Poisson's ratio", offsetof(TlMises, nu)},
    {"sigma_y", 1e5, 0.0, 1e300, "Pa", "initial yield stress (von Mises q)", offsetof(TlMises, sigma_y)},
    {"H", 0.0, -1e300, 1e300, "Pa", "hardening modulus dq/dkappa (negative: softening)", offsetof(TlMises, H)},
    {"sigma_res", 0.0, 0.0, 1e300, "Pa", "residual strength: the yield stress never falls below it",
     offsetof(TlMises, sigma_res)},
    {"operator", 0.0, 0.0, 1.0, "1", "tangent handed to the solid: 0 consistent, 1 elastic (upper bound)",
     offsetof(TlMises, op)},
};

static TlStatus setup(TlMaterial *m)
{
  TlMises *h = (TlMises *)m;
  const char *name = m->ops->header.name;
  if (!(h->E > 0.0)) TL_ERROR(TL_ERR_ARG, "material %s: E = %g Pa must be > 0", name, h->E);
  if (!(h->nu > -1.0 && h->nu < 0.5)) TL_ERROR(TL_ERR_ARG, "material %s: nu = %g outside (-1, 0.5)", name, h->nu);
  h->mu = h->E / (2.0 * (1.0 + h->nu));
  h->lambda = h->E * h->nu / ((1.0 + h->nu) * (1.0 - 2.0 * h->nu));
  h->K = h->lambda + 2.0 * h->mu / 3.0;
  if (!(h->H > -3.0 * h->mu))
    TL_ERROR(TL_ERR_ARG, "material %s: H = %g Pa must exceed -3 mu = %g Pa (the return mapping has no solution)",
             name, h->H, -3.0 * h->mu);
  if (h->sigma_res > h->sigma_y)
    TL_ERROR(TL_ERR_ARG, "material %s: sigma_res = %g Pa above sigma_y = %g Pa", name, h->sigma_res, h->sigma_y);
  if (h->op != 0.0 && h->op != 1.0)
    TL_ERROR(TL_ERR_ARG, "material %s: operator = %g is neither 0 (consistent) nor 1 (elastic)", name, h->op);
  m->state_size = 7;
  return TL_OK;
}

static void elastic_tangent(const TlMises *h, double *d)
{
  memset(d, 0, 36 * sizeof *d);
  for (int I = 0; I < 3; ++I) {
    for (int J = 0; J < 3; ++J) d[6 * I + J] = h->lambda;
    d[6 * I + I] += 2.0 * h->mu;
    d[6 * (I + 3) + I + 3] = h->mu;
  }
}

static TlStatus evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma,
                         const double *state_old, double *state_new, TlMat3 *S, double *D, double *W)
{
  (void)F;
  const TlMises *h = (const TlMises *)m;
  const double mu = h->mu, K = h->K;
  for (size_t p = 0; p < npts; ++p) {
    const double *so = state_old + 7 * p;
    double *sn = state_new + 7 * p;
    double g[6], ee[6];
    tl_voigt_from_sym(gamma[p], g);
    for (int I = 0; I < 6; ++I) ee[I] = g[I] - so[I];
    const double tr = ee[0] + ee[1] + ee[2];
    /* Trial deviatoric stress s = 2 mu dev E_e (tensor components). */
    double s[6];
    for (int I = 0; I < 6; ++I) s[I] = 2.0 * mu * (ee[I] - (I < 3 ? tr / 3.0 : 0.0));
    const double ss = s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]);
    const double norm = sqrt(ss), q_tr = sqrt(1.5) * norm, kappa = so[6];
    const double y_n = fmax(h->sigma_y + h->H * kappa, h->sigma_res);
    double dg = 0.0, Hef = h->H;
    memcpy(sn, so, 7 * sizeof *sn);
    if (q_tr > y_n) {
      /* On the residual plateau (or reaching it in this step) the slope is 0. */
      dg = (q_tr - h->sigma_y - h->H * kappa) / (3.0 * mu + h->H);
      if (h->sigma_y + h->H * (kappa + dg) < h->sigma_res || h->sigma_y + h->H * kappa <= h->sigma_res) {
        Hef = 0.0;
        dg = (q_tr - h->sigma_res) / (3.0 * mu);
      }
      const double shrink = 1.0 - 3.0 * mu * dg / q_tr;
      for (int I = 0; I < 6; ++I) {
        sn[I] = so[I] + dg * 1.5 * s[I] / q_tr; /* dE_p = dg (3/2) s / q */
        s[I] *= shrink;
      }
      sn[6] = kappa + dg;
    }
    double sv[6];
    for (int I = 0; I < 6; ++I) sv[I] = s[I] + (I < 3 ? K * tr : 0.0);
    S[p] = tl_voigt_to_sym(sv);
    if (W) {
      double e2 = 0.0;
      for (int I = 0; I < 6; ++I) {
        const double e = ee[I] - (I < 3 ? tr / 3.0 : 0.0);
        e2 += (I < 3 ? 1.0 : 2.0) * e * e;
      }
      W[p] = 0.5 * K * tr * tr + mu * e2; /* elastic energy of E_e */
    }
    if (!D) continue;
    double *d = D + 36 * p;
    elastic_tangent(h, d);
    if (dg == 0.0 || h->op == 1.0) continue;
    /* Consistent tangent: the deviatoric part scaled, minus the n (x) n part. */
    const double beta = 3.0 * mu * dg / q_tr, c = 6.0 * mu * mu * (dg / q_tr - 1.0 / (3.0 * mu + Hef));
    for (int I = 0; I < 6; ++I)
      for (int J = 0; J < 6; ++J) {
        double idev = I == J ? (I < 3 ? 1.0 : 0.5) : 0.0;
        if (I < 3 && J < 3) idev -= 1.0 / 3.0;
        d[6 * I + J] -= 2.0 * mu * beta * idev;
      }
    double n[6]; /* dev S_tr / |dev S_tr| = s / |s| (s is parallel to the trial) */
    for (int I = 0; I < 6; ++I) n[I] = s[I] / ((1.0 - beta) * norm);
    for (int I = 0; I < 6; ++I)
      for (int J = 0; J < 6; ++J) d[6 * I + J] += c * n[I] * n[J];
  }
  return TL_OK;
}

static int symmetric_tangent(const TlMaterial *m)
{
  (void)m;
  return 1;
}

static const TlMaterialOps mises_ops = {
    .header = {"material", "mises_plastic",
               "von Mises plasticity on (S, E) with linear hardening or softening to a residual strength; "
               "consistent or elastic (upper-bound) tangent: a stand-in for a DEM cell"},
    .size = sizeof(TlMises), .n_params = 6, .params = params, .setup = setup, .evaluate = evaluate,
    .symmetric_tangent = symmetric_tangent};

TlStatus tl_material_mises_register_all(void)
{
  TL_CHECK(tl_material_register(&mises_ops));
  return TL_OK;
}
