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
    {"nu", 0.0, -0.999999, 0.499999, "", "Poisson's ratio", offsetof(TlHooke, nu)},
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
 * M gamma M formed with their symmetry (about half the flops of the
 * general products).  Branch-free, so the loop over points vectorises;
 * returns det C, which is not positive for a singular metric. */
static inline double stress_only(const TlHooke *h, const TlMat3 *g, TlMat3 *S)
{
  const TlMat3 *E0 = &h->base.eigenstrain;
  double c[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) c[i][j] = (i == j) + 2.0 * (g->m[i][j] + E0->m[i][j]);
  c[1][0] = c[0][1], c[2][0] = c[0][2], c[2][1] = c[1][2];
  const double a00 = c[1][1] * c[2][2] - c[1][2] * c[1][2], a01 = c[0][2] * c[1][2] - c[0][1] * c[2][2],
               a02 = c[0][1] * c[1][2] - c[0][2] * c[1][1];
  const double det = c[0][0] * a00 + c[0][1] * a01 + c[0][2] * a02;
  double M[3][3];
  if (h->covariant) {
    memcpy(M, c, sizeof M);
  } else {
    const double r = 1.0 / det;
    M[0][0] = a00 * r, M[0][1] = M[1][0] = a01 * r, M[0][2] = M[2][0] = a02 * r;
    M[1][1] = (c[0][0] * c[2][2] - c[0][2] * c[0][2]) * r;
    M[1][2] = M[2][1] = (c[0][1] * c[0][2] - c[0][0] * c[1][2]) * r;
    M[2][2] = (c[0][0] * c[1][1] - c[0][1] * c[0][1]) * r;
  }
  double P[3][3], tr = 0.0; /* P = M gamma */
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      P[i][j] = M[i][0] * g->m[0][j] + M[i][1] * g->m[1][j] + M[i][2] * g->m[2][j];
      tr += M[i][j] * g->m[i][j];
    }
  const double a = 2.0 * h->mu, b = h->mu * h->c2 * tr;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j)
      S->m[i][j] = S->m[j][i] = a * (P[i][0] * M[0][j] + P[i][1] * M[1][j] + P[i][2] * M[2][j]) + b * M[i][j];
  return det;
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
    .evaluate = evaluate, .symmetric_tangent = symmetric_tangent, .init_state = init_state};

const TlMaterialOps tl_material_hooke_covariant_ops = {
    .header = {"material", "hooke_covariant",
               "generalised Hooke law, seeds/001 Eq. 34 read with the covariant metric C"},
    .size = sizeof(TlHooke), .n_params = 2, .params = params, .setup = setup_covariant,
    .evaluate = evaluate, .symmetric_tangent = symmetric_tangent, .init_state = init_state};
