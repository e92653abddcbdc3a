/* The "mises_plastic" stand-in law: elastic below yield (S = SVK), the
 * returned stress on the yield surface q = sigma_y + H kappa, the plastic
 * strain increment along the deviatoric normal (no volume change), the
 * consistent tangent against central differences of the return mapping
 * (hardening, softening and on the residual plateau), the elastic operator
 * when asked, the committed state left untouched, and bad parameters
 * refused by name. */
#include <math.h>
#include <string.h>

#include "talus.h"
#include "tl_material.h"
#include "tl_test.h"

static TlMaterial *make(double H, double sigma_res, double op)
{
  TlMaterial *m = NULL;
  TL_TEST_STATUS(tl_material_create("mises_plastic", &m), TL_OK);
  if (!m) return NULL;
  TL_TEST_STATUS(tl_material_set(m, "E", 1e8), TL_OK);
  TL_TEST_STATUS(tl_material_set(m, "nu", 0.3), TL_OK);
  TL_TEST_STATUS(tl_material_set(m, "sigma_y", 1e5), TL_OK);
  TL_TEST_STATUS(tl_material_set(m, "H", H), TL_OK);
  TL_TEST_STATUS(tl_material_set(m, "sigma_res", sigma_res), TL_OK);
  TL_TEST_STATUS(tl_material_set(m, "operator", op), TL_OK);
  TL_TEST_STATUS(tl_material_setup(m), TL_OK);
  return m;
}

/* S and D at Green strain g (Voigt, tensor shear) from state so. */
static void eval(const TlMaterial *m, const double g[6], const double so[7], double sn[7], double S[6], double *D)
{
  TlMat3 F = tl_m3_identity(), G = tl_voigt_to_sym(g), Sm;
  TL_TEST_STATUS(m->ops->evaluate(m, 1, &F, &G, so, sn, &Sm, D, NULL), TL_OK);
  tl_voigt_from_sym(Sm, S);
}

static double mises(const double s[6])
{
  double p = (s[0] + s[1] + s[2]) / 3.0, j = 0.0;
  for (int I = 0; I < 6; ++I) {
    double d = s[I] - (I < 3 ? p : 0.0);
    j += (I < 3 ? 1.0 : 2.0) * d * d;
  }
  return sqrt(1.5 * j);
}

/* D against central differences in the engineering strains, from so. */
static void check_tangent(const TlMaterial *m, const double g[6], const double so[7], double tol, const char *what)
{
  double S[6], D[36], sn[7], Sp[6], Sm[6], Dx[36];
  eval(m, g, so, sn, S, D);
  double worst = 0.0, scale = 0.0;
  for (int k = 0; k < 36; ++k) scale = fmax(scale, fabs(D[k]));
  for (int J = 0; J < 6; ++J) {
    const double h = 1e-7;
    double gp[6], gm[6];
    memcpy(gp, g, sizeof gp);
    memcpy(gm, g, sizeof gm);
    gp[J] += J < 3 ? h : 0.5 * h; /* engineering shear eps = 2 E */
    gm[J] -= J < 3 ? h : 0.5 * h;
    eval(m, gp, so, sn, Sp, Dx);
    eval(m, gm, so, sn, Sm, Dx);
    for (int I = 0; I < 6; ++I) worst = fmax(worst, fabs((Sp[I] - Sm[I]) / (2.0 * h) - D[6 * I + J]));
  }
  TL_TEST_ASSERT(worst <= tol * scale, "%s: tangent off central differences by %.3e (scale %.3e)", what, worst, scale);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const double zero[7] = {0};
  /* A strain that yields: mostly deviatoric, with some shear. */
  const double g[6] = {-3e-3, 1.2e-3, 0.4e-3, 0.8e-3, -0.3e-3, 0.2e-3};
  const double small[6] = {-1e-4, 0.5e-4, 0, 0.2e-4, 0, 0};

  TlMaterial *hard = make(2e6, 0.0, 0.0), *soft = make(-5e6, 3e4, 0.0), *elastic_op = make(2e6, 0.0, 1.0),
             *svk = NULL;
  TL_TEST_STATUS(tl_material_create("saint_venant_kirchhoff", &svk), TL_OK);
  if (!hard || !soft || !elastic_op || !svk) return tl_test_report();
  TL_TEST_STATUS(tl_material_set(svk, "E", 1e8), TL_OK);
  TL_TEST_STATUS(tl_material_set(svk, "nu", 0.3), TL_OK);
  TL_TEST_STATUS(tl_material_setup(svk), TL_OK);

  /* Elastic below yield: the SVK stress, state unchanged. */
  double S[6], D[36], sn[7], Sref[6];
  eval(hard, small, zero, sn, S, D);
  TlMat3 F = tl_m3_identity(), G = tl_voigt_to_sym(small), Sm;
  TL_TEST_STATUS(svk->ops->evaluate(svk, 1, &F, &G, NULL, NULL, &Sm, NULL, NULL), TL_OK);
  tl_voigt_from_sym(Sm, Sref);
  for (int I = 0; I < 6; ++I) TL_TEST_CLOSE(S[I], Sref[I], 1e-9);
  for (int k = 0; k < 7; ++k) TL_TEST_ASSERT(sn[k] == 0.0, "elastic step changed state %d to %g", k, sn[k]);
  check_tangent(hard, small, zero, 1e-6, "elastic");

  /* Plastic: on the yield surface, plastic strain deviatoric, consistency. */
  eval(hard, g, zero, sn, S, D);
  TL_TEST_ASSERT(sn[6] > 0.0, "no plastic flow at a strain 30 times yield (kappa %g)", sn[6]);
  TL_TEST_REL(mises(S), 1e5 + 2e6 * sn[6], 1e-12);
  TL_TEST_CLOSE((sn[0] + sn[1] + sn[2]) / 1e-3, 0.0, 1e-12);
  check_tangent(hard, g, zero, 1e-5, "hardening");
  check_tangent(soft, g, zero, 1e-5, "softening");
  /* From a state on the residual plateau. */
  double plateau[7] = {0};
  eval(soft, g, zero, plateau, S, D);
  const double g2[6] = {-4e-2, 1.6e-2, 0.9e-3, 1.0e-3, -0.3e-3, 0.2e-3};
  double s2[7];
  eval(soft, g2, plateau, s2, S, D);
  TL_TEST_ASSERT(1e5 - 5e6 * s2[6] < 3e4, "not on the plateau: kappa %g", s2[6]);
  TL_TEST_REL(mises(S), 3e4, 1e-12);
  check_tangent(soft, g2, plateau, 1e-5, "residual plateau");
  /* The elastic operator: same stress, the elastic D. */
  double Se[6], De[36];
  eval(elastic_op, g, zero, sn, Se, De);
  eval(hard, g, zero, sn, S, D);
  for (int I = 0; I < 6; ++I) TL_TEST_ASSERT(Se[I] == S[I], "operator changed the stress S[%d]: %g vs %g", I, Se[I], S[I]);
  double Del[36];
  eval(hard, small, zero, sn, Sref, Del);
  for (int k = 0; k < 36; ++k) TL_TEST_ASSERT(De[k] == Del[k], "elastic operator D[%d] = %g, elastic %g", k, De[k], Del[k]);
  /* Path dependence: unloading from a plastic state is elastic. */
  double s1[7], Su[6], Du[36];
  eval(hard, g, zero, s1, S, D);
  double gu[6];
  for (int I = 0; I < 6; ++I) gu[I] = 0.9 * g[I];
  eval(hard, gu, s1, sn, Su, Du);
  TL_TEST_ASSERT(sn[6] == s1[6], "unloading flowed: kappa %g -> %g", s1[6], sn[6]);

  /* Bad parameters by name. */
  TlMaterial *bad = NULL;
  TL_TEST_STATUS(tl_material_create("mises_plastic", &bad), TL_OK);
  if (bad) {
    TL_TEST_STATUS(tl_material_set(bad, "H", -1e9), TL_OK);
    TL_TEST_STATUS(tl_material_setup(bad), TL_ERR_ARG);
    TL_TEST_ASSERT(strstr(tl_error_message(), "H = ") != NULL, "message: %s", tl_error_message());
    TL_TEST_STATUS(tl_material_set(bad, "operator", 0.5), TL_OK);
    TL_TEST_STATUS(tl_material_set(bad, "H", 0.0), TL_OK);
    TL_TEST_STATUS(tl_material_setup(bad), TL_ERR_ARG);
    TL_TEST_ASSERT(strstr(tl_error_message(), "operator = 0.5") != NULL, "message: %s", tl_error_message());
    tl_material_destroy(&bad);
  }
  tl_material_destroy(&hard);
  tl_material_destroy(&soft);
  tl_material_destroy(&elastic_op);
  tl_material_destroy(&svk);
  return tl_test_report();
}
