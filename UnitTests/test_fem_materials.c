/* Constitutive laws: tangent against finite differences of the stress,
 * frame indifference (rigid rotations give zero stress, rotated F the same
 * S), the small-strain limit of Hooke's law, stress as the derivative of
 * the stored energy where a potential exists, eigenstrain and initial
 * stress, and refusal of bad parameters. */
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
  TL_TEST_STATUS(tl_material_set(m, "density", 1309.0), TL_OK);
  TL_TEST_STATUS(tl_material_setup(m), TL_OK);
  return m;
}

static TlMat3 sample_F(void)
{
  return (TlMat3){{{1.08, 0.05, -0.03}, {0.02, 0.95, 0.06}, {-0.04, 0.03, 1.03}}};
}

/* S from a Green strain perturbation: F' with F'^T F' = F^T F + 2 dE is
 * F' = R-free square root route avoided: perturb C directly through
 * F' = F (1 + 2 F^-T ... ); simpler: use F' = sqrt-free map F' = F + dF with
 * dF = F^-T dE (first order) is not exact, so tangents are checked against
 * differences in the Green strain computed from F' itself. */
static void check_tangent(TlMaterial *m, const char *label)
{
  size_t ss = m->state_size;
  double st_old[64] = {0}, st_new[64] = {0};
  if (ss && m->ops->init_state) m->ops->init_state(m, 1, st_old);
  TlMat3 F = sample_F(), S;
  double D[36], W;
  TL_TEST_STATUS(tl_material_evaluate(m, 1, &F, ss ? st_old : NULL, ss ? st_new : NULL, &S, D, &W), TL_OK);
  /* The stress alone (the residual's path, which a law may compute
   * differently) equals the stress evaluated with the tangent. */
  {
    TlMat3 S1;
    double W1 = 0.0, ds = 0.0, sn = 0.0;
    TL_TEST_STATUS(tl_material_evaluate(m, 1, &F, ss ? st_old : NULL, ss ? st_new : NULL, &S1, NULL, &W1), TL_OK);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) ds = fmax(ds, fabs(S1.m[i][j] - S.m[i][j])), sn = fmax(sn, fabs(S.m[i][j]));
    TL_TEST_ASSERT(ds <= 1e-14 * sn, "%s: stress without tangent differs by %g of %g", label, ds, sn);
    TL_TEST_CLOSE(W1, W, 1e-14 * fabs(W) + 1e-300);
  }
  /* Perturb F along directions whose Green-strain change is known exactly:
   * F' = F + h F^-T eps_J (eps_J symmetric) gives dE = h eps_J + O(h^2);
   * central differences cancel the O(h^2) term. */
  TlMat3 Fi = tl_m3_identity();
  tl_m3_inverse(F, &Fi);
  TlMat3 FiT = tl_m3_transpose(Fi);
  double err = 0.0, scale = 0.0;
  for (int J = 0; J < 6; ++J) {
    double h = 1e-6;
    TlMat3 dir = tl_m3_mul(FiT, tl_voigt_unit_strain(J));
    TlMat3 Fp = tl_m3_add(F, tl_m3_scale(dir, h)), Fm = tl_m3_add(F, tl_m3_scale(dir, -h));
    /* Exact Green strain differences (not first order). */
    TlMat3 Cp = tl_m3_mul(tl_m3_transpose(Fp), Fp), Cm = tl_m3_mul(tl_m3_transpose(Fm), Fm);
    double dE[6];
    tl_voigt_from_sym(tl_m3_scale(tl_m3_add(Cp, tl_m3_scale(Cm, -1.0)), 0.25), dE);
    for (int I = 3; I < 6; ++I) dE[I] *= 2.0; /* engineering */
    TlMat3 Sp, Sm;
    tl_material_evaluate(m, 1, &Fp, ss ? st_old : NULL, ss ? st_new : NULL, &Sp, NULL, NULL);
    tl_material_evaluate(m, 1, &Fm, ss ? st_old : NULL, ss ? st_new : NULL, &Sm, NULL, NULL);
    double dS[6], sp[6], sm[6];
    tl_voigt_from_sym(Sp, sp);
    tl_voigt_from_sym(Sm, sm);
    for (int I = 0; I < 6; ++I) {
      dS[I] = 0.5 * (sp[I] - sm[I]);
      double pred = 0.0;
      for (int K = 0; K < 6; ++K) pred += D[6 * I + K] * dE[K];
      err = fmax(err, fabs(pred - dS[I]));
      scale = fmax(scale, fabs(dS[I]));
    }
  }
  TL_TEST_ASSERT(err <= 1e-6 * scale, "%s: tangent differs from finite differences by %g (scale %g)", label,
                 err, scale);
  /* Frame indifference: S(R F) = S(F). */
  TlMat3 R = tl_m3_rotation(tl_v3(1, 2, 3), 0.7), RF = tl_m3_mul(R, F), S2;
  tl_material_evaluate(m, 1, &RF, ss ? st_old : NULL, ss ? st_new : NULL, &S2, NULL, NULL);
  double d = 0.0, n = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      d = fmax(d, fabs(S2.m[i][j] - S.m[i][j]));
      n = fmax(n, fabs(S.m[i][j]));
    }
  TL_TEST_ASSERT(d <= 1e-12 * n, "%s: S(R F) differs from S(F) by %g", label, d);
}

static void check_rotation_zero(TlMaterial *m, const char *label)
{
  size_t ss = m->state_size;
  double st_old[64] = {0}, st_new[64] = {0};
  if (ss && m->ops->init_state) m->ops->init_state(m, 1, st_old);
  TlMat3 R[2] = {tl_m3_rotation(tl_v3(0, 0, 1), M_PI / 2), tl_m3_rotation(tl_v3(-0.3, 0.8, 0.5), 2.1)};
  for (int k = 0; k < 2; ++k) {
    TlMat3 S;
    double W;
    TL_TEST_STATUS(tl_material_evaluate(m, 1, &R[k], ss ? st_old : NULL, ss ? st_new : NULL, &S, NULL, &W), TL_OK);
    double smax = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) smax = fmax(smax, fabs(S.m[i][j]));
    TL_TEST_ASSERT(smax < 1e-15 * 1e8 * 10, "%s: rotation %d gives stress %g", label, k, smax);
    TL_TEST_ASSERT(fabs(W) < 1e-6, "%s: rotation %d gives energy %g", label, k, W);
  }
}

/* Small strain: S = lambda tr(E) 1 + 2 mu E to first order. */
static void check_small_strain(TlMaterial *m, double E, double nu, const char *label)
{
  double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  double eps = 1e-7;
  TlMat3 H = {{{0.3, 0.1, -0.2}, {0.05, -0.4, 0.15}, {0.1, 0.2, 0.25}}};
  TlMat3 F = tl_m3_add(tl_m3_identity(), tl_m3_scale(H, eps)), S;
  double st[64] = {0}, st2[64] = {0};
  if (m->state_size && m->ops->init_state) m->ops->init_state(m, 1, st);
  tl_material_evaluate(m, 1, &F, m->state_size ? st : NULL, m->state_size ? st2 : NULL, &S, NULL, NULL);
  TlMat3 e = tl_m3_scale(tl_m3_add(H, tl_m3_transpose(H)), 0.5 * eps);
  double err = 0.0, ref = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double lin = lambda * tl_m3_trace(e) * (i == j) + 2 * mu * e.m[i][j];
      err = fmax(err, fabs(S.m[i][j] - lin));
      ref = fmax(ref, fabs(lin));
    }
  TL_TEST_ASSERT(err < 1e-5 * ref, "%s: small-strain stress off classical Hooke by %g of %g", label, err, ref);
}

/* S_I = dW/d eps_I where a potential exists. */
static void check_energy(TlMaterial *m, const char *label)
{
  TlMat3 F = sample_F(), S;
  double W0;
  tl_material_evaluate(m, 1, &F, NULL, NULL, &S, NULL, &W0);
  TlMat3 Fi = tl_m3_identity();
  tl_m3_inverse(F, &Fi);
  TlMat3 FiT = tl_m3_transpose(Fi);
  double s[6], err = 0.0, ref = 0.0;
  tl_voigt_from_sym(S, s);
  for (int J = 0; J < 6; ++J) {
    double h = 1e-6, Wp, Wm;
    TlMat3 dir = tl_m3_mul(FiT, tl_voigt_unit_strain(J));
    TlMat3 Fp = tl_m3_add(F, tl_m3_scale(dir, h)), Fm = tl_m3_add(F, tl_m3_scale(dir, -h)), Sx;
    tl_material_evaluate(m, 1, &Fp, NULL, NULL, &Sx, NULL, &Wp);
    tl_material_evaluate(m, 1, &Fm, NULL, NULL, &Sx, NULL, &Wm);
    /* dW = S : dE, dE exact to O(h^2) symmetric part: central difference. */
    TlMat3 Cp = tl_m3_mul(tl_m3_transpose(Fp), Fp), Cm = tl_m3_mul(tl_m3_transpose(Fm), Fm);
    TlMat3 dE = tl_m3_scale(tl_m3_add(Cp, tl_m3_scale(Cm, -1.0)), 0.25);
    double pred = tl_m3_ddot(S, dE);
    err = fmax(err, fabs(0.5 * (Wp - Wm) - pred));
    ref = fmax(ref, fabs(pred));
  }
  TL_TEST_ASSERT(err < 1e-6 * ref, "%s: stress is not dW/dE (error %g of %g)", label, err, ref);
}

/* tl_material_stress_soa against tl_material_evaluate_gradient on 150
 * points (two internal chunks and a remainder): the same bits.  The law
 * keeps no state (a law that does is refused); with `eigen` an eigenstrain
 * and an initial stress. */
static void check_stress_soa(const char *name, int eigen)
{
  enum { NP = 150, LD = 157 };
  TlMaterial *m = make(name, 1e8, 0.0);
  if (eigen) {
    TL_TEST_STATUS(tl_material_set_eigenstrain(m, (TlMat3){{{0.01, 0.002, 0}, {0.002, -0.005, 0}, {0, 0, 0.003}}}),
                   TL_OK);
    TL_TEST_STATUS(tl_material_set_initial_stress(m, (TlMat3){{{5e6, 1e5, 0}, {1e5, -2e6, 3e4}, {0, 3e4, 1e6}}}),
                   TL_OK);
    TL_TEST_STATUS(tl_material_setup(m), TL_OK);
  }
  static TlMat3 H[NP], S[NP];
  static double Hs[9 * LD], Ss[6 * LD];
  if (m->state_size) {
    /* the covariant law with an eigenstrain has no potential: path state */
    TL_TEST_STATUS(tl_material_stress_soa(m, 1, Hs, Ss, LD), TL_ERR_ARG);
    tl_material_destroy(&m);
    return;
  }
  const TlMat3 H0 = tl_m3_add(sample_F(), tl_m3_scale(tl_m3_identity(), -1.0));
  for (int p = 0; p < NP; ++p) {
    H[p] = tl_m3_scale(H0, sin(0.37 * p + 0.1) * (p % 7 == 3 ? 1e-7 : 1.0));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Hs[(3 * i + j) * LD + p] = H[p].m[i][j];
  }
  TL_TEST_STATUS(tl_material_evaluate_gradient(m, NP, H, NULL, NULL, S, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_material_stress_soa(m, NP, Hs, Ss, LD), TL_OK);
  static const int row[6] = {0, 1, 2, 0, 1, 0}, col[6] = {0, 1, 2, 1, 2, 2};
  int differ = 0;
  for (int p = 0; p < NP; ++p)
    for (int I = 0; I < 6; ++I) differ += Ss[I * LD + p] != S[p].m[row[I]][col[I]];
  TL_TEST_ASSERT(differ == 0, "%s%s: %d stress components differ from the batch path", name,
                 eigen ? " (eigenstrain, initial stress)" : "", differ);
  /* Hooke's own op refuses a singular metric (F = 0 at one point), naming
   * the law (the solid refuses det F <= 0 before any law sees it). */
  if (!m->ops->stress_soa) {
    tl_material_destroy(&m);
    return;
  }
  for (int i = 0; i < 3; ++i) Hs[(3 * i + i) * LD + 77] = -1.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j) Hs[(3 * i + j) * LD + 77] = 0.0;
  TlStatus st = tl_material_stress_soa(m, NP, Hs, Ss, LD);
  TL_TEST_ASSERT(st == TL_ERR_NUMERIC && strstr(tl_error_message(), name), "%s: F = 0 gives %d (%s)", name, st,
                 tl_error_message());
  tl_material_destroy(&m);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const char *laws[3] = {"hooke", "hooke_covariant", "neo_hookean"};
  const double nus[2] = {0.0, 0.3};
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k < 2; ++k) {
      char label[64];
      snprintf(label, sizeof label, "%s nu=%g", laws[l], nus[k]);
      TlMaterial *m = make(laws[l], 1e8, nus[k]);
      if (!m) continue;
      check_tangent(m, label);
      check_rotation_zero(m, label);
      check_small_strain(m, 1e8, nus[k], label);
      if (m->state_size == 0) check_energy(m, label);
      int sym = tl_material_symmetric_tangent(m);
      TL_TEST_ASSERT(sym == (l == 2 || nus[k] == 0.0), "%s: symmetric flag %d", label, sym);
      /* Eigenstrain: F with E = E0 is stress free; initial stress adds. */
      TlMat3 E0 = {{{0.01, 0.002, 0}, {0.002, -0.005, 0}, {0, 0, 0.003}}};
      TL_TEST_STATUS(tl_material_set_eigenstrain(m, E0), TL_OK);
      TL_TEST_STATUS(tl_material_setup(m), TL_OK);
      /* F = sqrt(1 + 2 E0) by Newton on the symmetric square root. */
      TlMat3 C = tl_m3_add(tl_m3_identity(), tl_m3_scale(E0, 2.0)), U = tl_m3_identity();
      for (int it = 0; it < 30; ++it) {
        TlMat3 Ui = tl_m3_identity();
        tl_m3_inverse(U, &Ui);
        U = tl_m3_scale(tl_m3_add(U, tl_m3_mul(Ui, C)), 0.5);
      }
      TlMat3 S;
      double st[64] = {0}, st2[64] = {0};
      if (m->state_size && m->ops->init_state) m->ops->init_state(m, 1, st);
      TL_TEST_STATUS(tl_material_evaluate(m, 1, &U, m->state_size ? st : NULL, m->state_size ? st2 : NULL, &S, NULL, NULL), TL_OK);
      double smax = 0.0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) smax = fmax(smax, fabs(S.m[i][j]));
      TL_TEST_ASSERT(smax < 1e-6, "%s: stress %g at the eigenstrain", label, smax);
      check_tangent(m, label);
      TlMat3 S0 = {{{5e6, 0, 0}, {0, 5e6, 0}, {0, 0, 5e6}}};
      TL_TEST_STATUS(tl_material_set_initial_stress(m, S0), TL_OK);
      TL_TEST_STATUS(tl_material_evaluate(m, 1, &U, m->state_size ? st : NULL, m->state_size ? st2 : NULL, &S, NULL, NULL), TL_OK);
      TL_TEST_CLOSE(S.m[0][0], 5e6, 1e-13);
      TL_TEST_CLOSE(S.m[0][1], 0.0, 1e-6); /* Pa, round-off of E = 1e8 */
      tl_material_destroy(&m);
      TL_TEST_ASSERT(m == NULL, "destroy nulls");
    }
  /* Trapezoidal energy of a non-potential law agrees with the stress work
   * along a straight path to second order. */
  {
    TlMaterial *m = make("hooke", 1e8, 0.3);
    double st[13] = {0}, st2[13] = {0};
    m->ops->init_state(m, 1, st);
    int n = 200;
    double W = 0.0;
    for (int k = 1; k <= n; ++k) {
      TlMat3 F = tl_m3_add(tl_m3_identity(), tl_m3_scale(tl_m3_add(sample_F(), tl_m3_scale(tl_m3_identity(), -1.0)), (double)k / n)), S;
      tl_material_evaluate(m, 1, &F, st, st2, &S, NULL, &W);
      memcpy(st, st2, sizeof st);
    }
    TlMaterial *m0 = make("hooke", 1e8, 0.3);
    double st_a[13] = {0}, st_b[13] = {0}, W1 = 0.0;
    m0->ops->init_state(m0, 1, st_a);
    for (int k = 1; k <= 2 * n; ++k) {
      TlMat3 F = tl_m3_add(tl_m3_identity(), tl_m3_scale(tl_m3_add(sample_F(), tl_m3_scale(tl_m3_identity(), -1.0)), (double)k / (2 * n))), S;
      tl_material_evaluate(m0, 1, &F, st_a, st_b, &S, NULL, &W1);
      memcpy(st_a, st_b, sizeof st_a);
    }
    TL_TEST_ASSERT(W > 0 && fabs(W - W1) < 1e-4 * W, "path energy %g vs refined %g", W, W1);
    tl_material_destroy(&m);
    tl_material_destroy(&m0);
  }
  /* The residual's component-major path: Hooke through its own op, the
   * neo-Hookean law through evaluate(). */
  for (int l = 0; l < 3; ++l)
    for (int eigen = 0; eigen < 2; ++eigen) check_stress_soa(laws[l], eigen);
  {
    TlMaterial *ms = make("hooke", 1e8, 0.3);
    double Hs[9] = {0}, Ss[6];
    TL_TEST_STATUS(tl_material_stress_soa(ms, 1, Hs, Ss, 1), TL_ERR_ARG); /* keeps state at nu != 0 */
    tl_material_destroy(&ms);
  }
  /* Bad parameters and types. */
  TlMaterial *m = NULL;
  TL_TEST_STATUS(tl_material_create("no_such_law", &m), TL_ERR_NOT_FOUND);
  TL_TEST_STATUS(tl_material_create("hooke", &m), TL_OK);
  TL_TEST_STATUS(tl_material_set(m, "nu", 0.5), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "nu") != NULL, "message names nu: %s", tl_error_message());
  TL_TEST_STATUS(tl_material_set(m, "E", -1.0), TL_ERR_ARG);
  TL_TEST_STATUS(tl_material_set(m, "density", 0.0), TL_ERR_ARG);
  TL_TEST_STATUS(tl_material_set(m, "bulk", 1.0), TL_ERR_NOT_FOUND);
  TlMat3 F = tl_m3_identity(), S;
  TL_TEST_STATUS(tl_material_evaluate(m, 1, &F, NULL, NULL, &S, NULL, NULL), TL_ERR_STATE);
  TL_TEST_STATUS(tl_material_setup(m), TL_OK);
  F.m[2][2] = -1.0;
  TL_TEST_STATUS(tl_material_evaluate(m, 1, &F, NULL, NULL, &S, NULL, NULL), TL_ERR_NUMERIC);
  TlMat3 asym = tl_m3_zero();
  asym.m[0][1] = 1e-3;
  TL_TEST_STATUS(tl_material_set_eigenstrain(m, asym), TL_ERR_ARG);
  tl_material_destroy(&m);
  return tl_test_report();
}
