/* The Saint Venant-Kirchhoff law: S = lambda tr(E) 1 + 2 mu E against the
 * formula on a general F, uniaxial stretch in closed form, the tangent
 * against central differences of the stress, the stress as the derivative
 * of the stored energy, frame indifference, the component-major path
 * equal to the batch path, agreement with "hooke" to first order only, and
 * refusal of bad parameters by name. */
#include <math.h>
#include <string.h>

#include "talus.h"
#include "tl_material.h"
#include "tl_test.h"

static TlMaterial *make(const char *name, double E, double nu)
{
  TlMaterial *m = NULL;
  TL_TEST_STATUS(tl_material_create(name, &m), TL_OK);
  TL_TEST_STATUS(tl_material_set(m, "E", E), TL_OK);
  TL_TEST_STATUS(tl_material_set(m, "nu", nu), TL_OK);
  TL_TEST_STATUS(tl_material_setup(m), TL_OK);
  return m;
}

static const TlMat3 F0 = {{{1.18, 0.09, -0.05}, {0.04, 0.87, 0.11}, {-0.07, 0.06, 1.09}}};

static TlMat3 green(TlMat3 F)
{
  TlMat3 C = tl_m3_mul(tl_m3_transpose(F), F);
  return tl_m3_scale(tl_m3_add(C, tl_m3_scale(tl_m3_identity(), -1.0)), 0.5);
}

static double max_abs_diff(TlMat3 a, TlMat3 b)
{
  double d = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) d = fmax(d, fabs(a.m[i][j] - b.m[i][j]));
  return d;
}

static void check_formula(double E, double nu)
{
  TlMaterial *m = make("saint_venant_kirchhoff", E, nu);
  const double mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  TlMat3 S, G = green(F0), Sref;
  double W, D[36];
  TL_TEST_STATUS(tl_material_evaluate(m, 1, &F0, NULL, NULL, &S, D, &W), TL_OK);
  const double tr = tl_m3_trace(G);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Sref.m[i][j] = lambda * tr * (i == j) + 2 * mu * G.m[i][j];
  TL_TEST_ASSERT(max_abs_diff(S, Sref) <= 1e-13 * E, "nu %g: S off the formula by %g", nu, max_abs_diff(S, Sref));
  TL_TEST_CLOSE(W, 0.5 * lambda * tr * tr + mu * tl_m3_ddot(G, G), 1e-13);
  TL_TEST_ASSERT(tl_material_symmetric_tangent(m) == 1, "symmetric tangent flag");
  /* Tangent: central differences along F' = F + h F^-T eps_J, with the
   * exact Green strain change of F' (tl_material.h's engineering shear). */
  TlMat3 Fi;
  tl_m3_inverse(F0, &Fi);
  TlMat3 FiT = tl_m3_transpose(Fi);
  double err = 0.0, scale = 0.0, werr = 0.0, wref = 0.0;
  for (int J = 0; J < 6; ++J) {
    const double h = 1e-6;
    TlMat3 dir = tl_m3_mul(FiT, tl_voigt_unit_strain(J));
    TlMat3 Fp = tl_m3_add(F0, tl_m3_scale(dir, h)), Fm = tl_m3_add(F0, tl_m3_scale(dir, -h)), Sp, Sm;
    double Wp, Wm;
    TL_TEST_STATUS(tl_material_evaluate(m, 1, &Fp, NULL, NULL, &Sp, NULL, &Wp), TL_OK);
    TL_TEST_STATUS(tl_material_evaluate(m, 1, &Fm, NULL, NULL, &Sm, NULL, &Wm), TL_OK);
    TlMat3 dG = tl_m3_add(green(Fp), tl_m3_scale(green(Fm), -1.0));
    double de[6], sp[6], sm[6];
    tl_voigt_from_sym(dG, de);
    for (int I = 3; I < 6; ++I) de[I] *= 2.0;
    tl_voigt_from_sym(Sp, sp);
    tl_voigt_from_sym(Sm, sm);
    for (int I = 0; I < 6; ++I) {
      double pred = 0.0;
      for (int K = 0; K < 6; ++K) pred += D[6 * I + K] * de[K];
      err = fmax(err, fabs(pred - (sp[I] - sm[I])));
      scale = fmax(scale, fabs(sp[I] - sm[I]));
    }
    /* dW = S : dE */
    werr = fmax(werr, fabs((Wp - Wm) - tl_m3_ddot(S, dG)));
    wref = fmax(wref, fabs(tl_m3_ddot(S, dG)));
  }
  TL_TEST_ASSERT(scale > 0.0 && err <= 1e-7 * scale, "nu %g: tangent off central differences by %g of %g", nu, err,
                 scale);
  TL_TEST_ASSERT(wref > 0.0 && werr <= 1e-7 * wref, "nu %g: S is not dW/dE (%g of %g)", nu, werr, wref);
  /* Frame indifference. */
  TlMat3 RF = tl_m3_mul(tl_m3_rotation(tl_v3(1, -2, 0.5), 1.1), F0), SR;
  TL_TEST_STATUS(tl_material_evaluate(m, 1, &RF, NULL, NULL, &SR, NULL, NULL), TL_OK);
  TL_TEST_ASSERT(max_abs_diff(SR, S) <= 1e-12 * E, "nu %g: S(R F) - S(F) = %g", nu, max_abs_diff(SR, S));
  /* Component-major path (the residual's) gives the batch path's bits. */
  enum { NP = 37 };
  TlMat3 H[NP], Sb[NP];
  double Hs[9 * NP], Ss[6 * NP];
  for (int p = 0; p < NP; ++p) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) H[p].m[i][j] = (F0.m[i][j] - (i == j)) * (0.2 + 0.05 * p);
    for (int k = 0; k < 9; ++k) Hs[k * NP + p] = H[p].m[k / 3][k % 3];
  }
  TL_TEST_STATUS(tl_material_evaluate_gradient(m, NP, H, NULL, NULL, Sb, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_material_stress_soa(m, NP, Hs, Ss, NP), TL_OK);
  int differ = 0;
  for (int p = 0; p < NP; ++p) {
    double v[6];
    tl_voigt_from_sym(Sb[p], v);
    for (int I = 0; I < 6; ++I) differ += v[I] != Ss[I * NP + p];
  }
  TL_TEST_ASSERT(differ == 0, "nu %g: %d stress components of the component-major path differ", nu, differ);
  tl_material_destroy(&m);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  check_formula(1e8, 0.0);
  check_formula(2.1e11, 0.3);
  check_formula(5e6, 0.45);

  /* Uniaxial stretch s with nu = 0: S11 = E (s^2 - 1) / 2, no other stress. */
  TlMaterial *svk = make("saint_venant_kirchhoff", 1e8, 0.0), *hooke = make("hooke", 1e8, 0.0);
  const double stretch = 1.3;
  TlMat3 F = tl_m3_identity(), S;
  F.m[0][0] = stretch;
  TL_TEST_STATUS(tl_material_evaluate(svk, 1, &F, NULL, NULL, &S, NULL, NULL), TL_OK);
  TL_TEST_CLOSE(S.m[0][0], 1e8 * (stretch * stretch - 1) / 2, 1e-14);
  TL_TEST_ASSERT(fabs(S.m[1][1]) + fabs(S.m[2][2]) + fabs(S.m[0][1]) == 0.0, "uniaxial: lateral stress");

  /* "hooke" (contravariant metric) agrees to first order: the relative
   * difference falls like the strain. */
  double rel[2];
  for (int k = 0; k < 2; ++k) {
    const double eps = k ? 1e-5 : 1e-2;
    TlMat3 Fe = tl_m3_add(tl_m3_identity(), tl_m3_scale(tl_m3_add(F0, tl_m3_scale(tl_m3_identity(), -1.0)), eps / 0.1));
    TlMat3 Sa, Sh;
    TL_TEST_STATUS(tl_material_evaluate(svk, 1, &Fe, NULL, NULL, &Sa, NULL, NULL), TL_OK);
    TL_TEST_STATUS(tl_material_evaluate(hooke, 1, &Fe, NULL, NULL, &Sh, NULL, NULL), TL_OK);
    rel[k] = max_abs_diff(Sa, Sh) / sqrt(tl_m3_ddot(Sa, Sa));
  }
  TL_TEST_ASSERT(rel[0] > 1e-3 && rel[1] < 1e-4 && rel[1] < 1e-2 * rel[0],
                 "svk - hooke: relative differences %g at strain 1e-2, %g at 1e-5", rel[0], rel[1]);
  tl_material_destroy(&svk);
  tl_material_destroy(&hooke);

  /* Bad parameters are refused with the parameter's name. */
  TlMaterial *m = NULL;
  TL_TEST_STATUS(tl_material_create("saint_venant_kirchhoff", &m), TL_OK);
  TL_TEST_STATUS(tl_material_set(m, "nu", 0.5), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "nu") != NULL, "message names nu: %s", tl_error_message());
  TL_TEST_STATUS(tl_material_set(m, "E", -1.0), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "E") != NULL, "message names E: %s", tl_error_message());
  tl_material_destroy(&m);
  return tl_test_report();
}
