/* The generalised Hooke law of seeds/001 Appendix A, Eq. 34:
 *
 *   sigma^ij = E / (2 (1 + nu)) (G^ik G^jl + G^il G^jk + 2 nu / (1 - 2 nu) G^ij G^kl) gamma_kl,
 *   gamma_kl = (G_kl - g_kl) / 2,
 *
 * with G the metric of the deformed configuration (G_kl = C = F^T F in
 * Lagrangian coordinates), g that of the stress-free one (g = 1 + 2 E0 with
 * an eigenstrain E0).  In matrix form, with the metric M used in the
 * constitutive tensor,
 *
 *   S = mu (2 M gamma M + c2 (M : gamma) M),  mu = E / (2 (1 + nu)),
 *   c2 = 2 nu / (1 - 2 nu).
 *
 * Eq. 34 prints lower indices; oomph-lib, whose results the paper reports,
 * evaluates the tensor with the contravariant metric M = C^-1.  Both
 * readings are provided: "hooke" (M = C^-1, the default, the published
 * runs) and "hooke_covariant" (M = C, the equation as printed).  They agree
 * to first order in the strain.
 *
 * The law is not hyperelastic unless nu = 0 (the tangent is then
 * symmetric): the stored energy is the closed-form potential when it
 * exists, and otherwise the stress work integrated along the committed
 * path with the trapezoidal rule (state: gamma, S, W of the last committed
 * step). */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "tl_material.h"

typedef struct {
  TlMaterial base;
  double E, nu;
  double mu, c2;
  int covariant;
  int potential; /* closed-form energy available */
} TlHooke;

static const TlMaterialParam params[] = {
    {"E", 1e8, 1e-300, 1e300, "Pa", "Young's modulus", offsetof(TlHooke, E)},
    {"nu", 0.0, -0.999999, 0.499999, "1", "Poisson's ratio", offsetof(TlHooke, nu)},
};

enum { STATE_GAMMA = 0, STATE_S = 6, STATE_W = 12, STATE_SIZE = 13 };

static TlStatus setup_common(TlMaterial *m, int covariant)
{
  TlHooke *h = (TlHooke *)m;
  if (!(h->E > 0.0))
    TL_ERROR(TL_ERR_ARG, "material %s: E = %g Pa must be > 0", m->ops->header.name, h->E);
  if (!(h->nu > -1.0 && h->nu < 0.5))
    TL_ERROR(TL_ERR_ARG, "material %s: nu = %g outside (-1, 0.5)", m->ops->header.name, h->nu);
  h->mu = h->E / (2.0 * (1.0 + h->nu));
  h->c2 = 2.0 * h->nu / (1.0 - 2.0 * h->nu);
  h->covariant = covariant;
  h->potential = h->nu == 0.0 && (!covariant || !m->has_eigenstrain);
  m->state_size = h->potential ? 0 : STATE_SIZE;
  return TL_OK;
}
static TlStatus setup_contravariant(TlMaterial *m) { return setup_common(m, 0); }
static TlStatus setup_covariant(TlMaterial *m) { return setup_common(m, 1); }

/* S = mu (2 M gamma M + c2 (M:gamma) M) */
static TlMat3 stress(const TlHooke *h, TlMat3 M, TlMat3 gamma)
{
  TlMat3 MgM = tl_m3_mul(tl_m3_mul(M, gamma), M);
  double tr = tl_m3_ddot(M, gamma);
  TlMat3 S;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) S.m[i][j] = h->mu * (2.0 * MgM.m[i][j] + h->c2 * tr * M.m[i][j]);
  return S;
}

/* Potential energy for nu = 0, in forms free of cancellation at small
 * strain (A = 2 gamma = C - g):
 *   contravariant: W = mu/2 (ln det C - ln det g + tr(g C^-1) - 3)
 *                    = mu/2 tr[log(1 + M) - M (1 + M)^-1],  M = g^-1 A;
 *   covariant (g = 1): W = mu/2 (tr C^4 / 4 - tr C^3 / 3 + 1/4)
 *                    = mu/2 (tr A^2 / 2 + 2 tr A^3 / 3 + tr A^4 / 4). */
static double potential_energy(const TlHooke *h, TlMat3 gamma)
{
  TlMat3 A = tl_m3_scale(gamma, 2.0);
  if (h->covariant) {
    TlMat3 A2 = tl_m3_mul(A, A), A3 = tl_m3_mul(A2, A), A4 = tl_m3_mul(A2, A2);
    return 0.5 * h->mu * (0.5 * tl_m3_trace(A2) + 2.0 * tl_m3_trace(A3) / 3.0 + 0.25 * tl_m3_trace(A4));
  }
  TlMat3 g = tl_m3_identity(), gi = tl_m3_identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) g.m[i][j] += 2.0 * h->base.eigenstrain.m[i][j];
  tl_m3_inverse(g, &gi);
  return 0.5 * h->mu * tl_material_trace_series(tl_m3_mul(gi, A), 0);
}

/* The stress alone (no tangent), the residual's hot path: C = g + 2 gamma
 * (g = 1 + 2 E0) from the strain the law already has, its inverse and
 * M gamma M with their symmetry, written out on scalars (the compiler
 * keeps them in registers; about a fifth of the instructions of the loop
 * form).  Branch-free apart from the metric's variant; returns det C, not
 * positive for a singular metric. */
static inline __attribute__((always_inline)) double stress6(const TlHooke *h, int covariant, const double g[6],
                                                            double o[6])
{
  const double(*e0)[3] = h->base.eigenstrain.m;
  const double g00 = g[0], g11 = g[1], g22 = g[2], g01 = g[3], g12 = g[4], g02 = g[5];
  const double c00 = 1.0 + 2.0 * (g00 + e0[0][0]), c11 = 1.0 + 2.0 * (g11 + e0[1][1]),
               c22 = 1.0 + 2.0 * (g22 + e0[2][2]), c01 = 2.0 * (g01 + e0[0][1]), c12 = 2.0 * (g12 + e0[1][2]),
               c02 = 2.0 * (g02 + e0[0][2]);
  const double a00 = c11 * c22 - c12 * c12, a01 = c02 * c12 - c01 * c22, a02 = c01 * c12 - c02 * c11;
  const double det = c00 * a00 + c01 * a01 + c02 * a02;
  double m00, m11, m22, m01, m12, m02;
  if (covariant) {
    m00 = c00, m11 = c11, m22 = c22, m01 = c01, m12 = c12, m02 = c02;
  } else {
    const double r = 1.0 / det;
    m00 = a00 * r, m01 = a01 * r, m02 = a02 * r;
    m11 = (c00 * c22 - c02 * c02) * r;
    m12 = (c01 * c02 - c00 * c12) * r;
    m22 = (c00 * c11 - c01 * c01) * r;
  }
  /* P = M gamma */
  const double p00 = m00 * g00 + m01 * g01 + m02 * g02, p01 = m00 * g01 + m01 * g11 + m02 * g12,
               p02 = m00 * g02 + m01 * g12 + m02 * g22;
  const double p10 = m01 * g00 + m11 * g01 + m12 * g02, p11 = m01 * g01 + m11 * g11 + m12 * g12,
               p12 = m01 * g02 + m11 * g12 + m12 * g22;
  const double p20 = m02 * g00 + m12 * g01 + m22 * g02, p21 = m02 * g01 + m12 * g11 + m22 * g12,
               p22 = m02 * g02 + m12 * g12 + m22 * g22;
  const double tr = p00 + p11 + p22; /* M : gamma */
  const double a = 2.0 * h->mu, b = h->mu * h->c2 * tr;
  o[0] = a * (p00 * m00 + p01 * m01 + p02 * m02) + b * m00;
  o[1] = a * (p10 * m01 + p11 * m11 + p12 * m12) + b * m11;
  o[2] = a * (p20 * m02 + p21 * m12 + p22 * m22) + b * m22;
  o[3] = a * (p00 * m01 + p01 * m11 + p02 * m12) + b * m01;
  o[4] = a * (p10 * m02 + p11 * m12 + p12 * m22) + b * m12;
  o[5] = a * (p00 * m02 + p01 * m12 + p02 * m22) + b * m02;
  return det;
}

static inline double stress_only(const TlHooke *h, const TlMat3 *gm, TlMat3 *S)
{
  double g[6], o[6];
  tl_voigt_from_sym(*gm, g);
  const double det = stress6(h, h->covariant, g, o);
  *S = tl_voigt_to_sym(o);
  return det;
}

/* The same on points stored component-major (tl_material.h); each lane of
 * the vectorised loop is one point, with the arithmetic of stress_only.
 * One restrict pointer per component: the compiler then needs no run-time
 * overlap checks between them.  Returns whether some metric was singular. */
static inline __attribute__((always_inline)) int stress_loop(
    const TlHooke *h, int covariant, size_t npts, const double *restrict g0, const double *restrict g1,
    const double *restrict g2, const double *restrict g3, const double *restrict g4, const double *restrict g5,
    double *restrict s0, double *restrict s1, double *restrict s2, double *restrict s3, double *restrict s4,
    double *restrict s5)
{
  long bad = 0; /* as wide as a double: one vector lane per point */
  for (size_t p = 0; p < npts; ++p) {
    const double g[6] = {g0[p], g1[p], g2[p], g3[p], g4[p], g5[p]};
    double o[6];
    bad |= !(stress6(h, covariant, g, o) > 0.0);
    s0[p] = o[0], s1[p] = o[1], s2[p] = o[2], s3[p] = o[3], s4[p] = o[4], s5[p] = o[5];
  }
  return bad != 0;
}

TL_VECTOR_CLONES
static int stress_soa_kernel(const TlHooke *h, size_t npts, const double *gamma, size_t ldg, double *S,
                             size_t lds)
{
  const double *g = gamma;
  double *o = S;
  if (h->covariant)
    return stress_loop(h, 1, npts, g, g + ldg, g + 2 * ldg, g + 3 * ldg, g + 4 * ldg, g + 5 * ldg, o, o + lds,
                       o + 2 * lds, o + 3 * lds, o + 4 * lds, o + 5 * lds);
  return stress_loop(h, 0, npts, g, g + ldg, g + 2 * ldg, g + 3 * ldg, g + 4 * ldg, g + 5 * ldg, o, o + lds,
                     o + 2 * lds, o + 3 * lds, o + 4 * lds, o + 5 * lds);
}

static TlStatus stress_soa(const TlMaterial *m, size_t npts, const double *gamma, size_t ldg, double *S, size_t lds)
{
  const TlHooke *h = (const TlHooke *)m;
  if (stress_soa_kernel(h, npts, gamma, ldg, S, lds))
    for (size_t p = 0; p < npts; ++p) {
      double g[6], o[6];
      for (int I = 0; I < 6; ++I) g[I] = gamma[I * ldg + p];
      if (!(stress6(h, h->covariant, g, o) > 0.0))
        TL_ERROR(TL_ERR_NUMERIC, "material %s: singular metric at point %zu", m->ops->header.name, p);
    }
  return TL_OK;
}

static TlStatus evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma,
                         const double *state_old, double *state_new, TlMat3 *S, double *D,
                         double *W)
{
  const TlHooke *h = (const TlHooke *)m;
  if (!D) {
    int bad = 0;
    for (size_t p = 0; p < npts; ++p) bad |= !(stress_only(h, &gamma[p], &S[p]) > 0.0);
    if (bad)
      for (size_t p = 0; p < npts; ++p)
        if (!(stress_only(h, &gamma[p], &S[p]) > 0.0))
          TL_ERROR(TL_ERR_NUMERIC, "material %s: singular metric at point %zu", m->ops->header.name, p);
    if (!W && h->potential) return TL_OK;
  }
  for (size_t p = 0; p < npts; ++p) {
    TlMat3 g = gamma[p];
    if (D) {
      TlMat3 C = tl_m3_mul(tl_m3_transpose(F[p]), F[p]), Ci;
      if (!tl_m3_inverse(C, &Ci))
        TL_ERROR(TL_ERR_NUMERIC, "material %s: singular metric at point %zu", m->ops->header.name, p);
      TlMat3 M = h->covariant ? C : Ci;
      S[p] = stress(h, M, g);
      for (int J = 0; J < 6; ++J) {
        TlMat3 dg = tl_voigt_unit_strain(J);
        /* dC = 2 dgamma; dM = 2 dgamma (covariant) or -2 C^-1 dgamma C^-1. */
        TlMat3 dM = h->covariant ? tl_m3_scale(dg, 2.0)
                                 : tl_m3_scale(tl_m3_mul(tl_m3_mul(Ci, dg), Ci), -2.0);
        TlMat3 t1 = tl_m3_mul(tl_m3_mul(dM, g), M);
        TlMat3 t2 = tl_m3_mul(tl_m3_mul(M, dg), M);
        TlMat3 t3 = tl_m3_mul(tl_m3_mul(M, g), dM);
        double tr = tl_m3_ddot(M, g), dtr = tl_m3_ddot(dM, g) + tl_m3_ddot(M, dg);
        TlMat3 dS;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            dS.m[i][j] = h->mu * (2.0 * (t1.m[i][j] + t2.m[i][j] + t3.m[i][j]) +
                                  h->c2 * (dtr * M.m[i][j] + tr * dM.m[i][j]));
        double v[6];
        tl_voigt_from_sym(dS, v);
        for (int I = 0; I < 6; ++I) D[36 * p + 6 * I + J] = v[I];
      }
    }
    if (h->potential) {
      if (W) W[p] = potential_energy(h, g);
    } else {
      /* Trapezoidal stress work from the committed point. */
      const double *so = state_old + STATE_SIZE * p;
      double *sn = state_new + STATE_SIZE * p;
      double gv[6], sv[6];
      tl_voigt_from_sym(g, gv);
      tl_voigt_from_sym(S[p], sv);
      double w = so[STATE_W];
      for (int I = 0; I < 6; ++I) {
        double factor = I < 3 ? 1.0 : 2.0;
        w += 0.5 * factor * (so[STATE_S + I] + sv[I]) * (gv[I] - so[STATE_GAMMA + I]);
      }
      for (int I = 0; I < 6; ++I) {
        sn[STATE_GAMMA + I] = gv[I];
        sn[STATE_S + I] = sv[I];
      }
      sn[STATE_W] = w;
      if (W) W[p] = w;
    }
  }
  return TL_OK;
}

/* The state of the undeformed body (F = 1): gamma = -E0, its stress, W = 0. */
static TlStatus init_state(const TlMaterial *m, size_t npts, double *state)
{
  const TlHooke *h = (const TlHooke *)m;
  if (h->potential) return TL_OK;
  TlMat3 g = tl_m3_scale(m->eigenstrain, -1.0);
  TlMat3 S = stress(h, tl_m3_identity(), g);
  for (size_t p = 0; p < npts; ++p) {
    double *s = state + STATE_SIZE * p;
    tl_voigt_from_sym(g, s + STATE_GAMMA);
    tl_voigt_from_sym(S, s + STATE_S);
    s[STATE_W] = 0.0;
  }
  return TL_OK;
}

static int symmetric_tangent(const TlMaterial *m) { return ((const TlHooke *)m)->potential; }

const TlMaterialOps tl_material_hooke_ops = {
    .header = {"material", "hooke",
               "generalised Hooke law, seeds/001 Eq. 34, contravariant deformed metric "
               "(oomph-lib's reading)"},
    .size = sizeof(TlHooke), .n_params = 2, .params = params, .setup = setup_contravariant,
    .evaluate = evaluate, .stress_soa = stress_soa, .symmetric_tangent = symmetric_tangent,
    .init_state = init_state};

const TlMaterialOps tl_material_hooke_covariant_ops = {
    .header = {"material", "hooke_covariant",
               "generalised Hooke law, seeds/001 Eq. 34 read with the covariant metric C"},
    .size = sizeof(TlHooke), .n_params = 2, .params = params, .setup = setup_covariant,
    .evaluate = evaluate, .stress_soa = stress_soa, .symmetric_tangent = symmetric_tangent,
    .init_state = init_state};
