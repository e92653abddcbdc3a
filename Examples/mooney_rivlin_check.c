/* The compressible Mooney-Rivlin law (material_mooney_rivlin.c),
 * registered from outside the library and created by name:
 *   - S against central differences of the stored energy W, and the
 *     tangent D = dS/dE against central differences of S, at random finite
 *     deformations (relative errors printed and asserted);
 *   - with C01 = 0, C10 = mu/2 and kappa = lambda + 2 mu/3 it has the
 *     linearisation of the built-in neo_hookean law (same tangent at E = 0).
 *     The two differ beyond linear order: neo_hookean is
 *     W = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2, not the isochoric
 *     split, so C01 = 0 does not reproduce it at finite strain (printed);
 *   - the law in a solid: a uniform stretch of a hex8 cube, the Gauss-point
 *     stress equal to the law's.
 * Prints `summary:` and exits non-zero when a check fails. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "examples.h"
#include "tl_material.h"
#include "tl_mesh.h"
#include "tl_solid.h"

/* F with F^T F = C (Cholesky C = L L^T, F = L^T); 0 when C is not SPD. */
static int f_from_c(TlMat3 C, TlMat3 *F)
{
  double L[3][3] = {{0}};
  for (int j = 0; j < 3; ++j) {
    double d = C.m[j][j];
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    if (!(d > 0.0)) return 0;
    L[j][j] = sqrt(d);
    for (int i = j + 1; i < 3; ++i) {
      double v = C.m[i][j];
      for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
      L[i][j] = v / L[j][j];
    }
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) F->m[i][j] = L[j][i];
  return 1;
}

/* S, D and W at the Green strain E (through an F with F^T F = 1 + 2 E). */
static TlStatus at_strain(const TlMaterial *m, TlMat3 E, TlMat3 *S, double *D, double *W)
{
  TlMat3 F;
  if (!f_from_c(tl_m3_add(tl_m3_identity(), tl_m3_scale(E, 2.0)), &F))
    TL_ERROR(TL_ERR_ARG, "strain outside the admissible set (1 + 2E not positive definite)");
  TL_CHECK(tl_material_evaluate(m, 1, &F, NULL, NULL, S, D, W));
  return TL_OK;
}

/* Largest relative errors of S against dW/dE and of D against dS/dE by
 * central differences of step h along each Voigt strain, at E. */
static TlStatus fd_check(const TlMaterial *m, TlMat3 E, double h, double *err_S, double *err_D)
{
  TlMat3 S;
  double D[36], W, s[6];
  TL_CHECK(at_strain(m, E, &S, D, &W));
  tl_voigt_from_sym(S, s);
  double eS = 0.0, nS = 0.0, eD = 0.0, nD = 0.0;
  for (int J = 0; J < 6; ++J) {
    TlMat3 dE = tl_m3_scale(tl_voigt_unit_strain(J), h), Sp, Sm;
    double Wp, Wm, sp[6], sm[6];
    TL_CHECK(at_strain(m, tl_m3_add(E, dE), &Sp, NULL, &Wp));
    TL_CHECK(at_strain(m, tl_m3_add(E, tl_m3_scale(dE, -1.0)), &Sm, NULL, &Wm));
    tl_voigt_from_sym(Sp, sp);
    tl_voigt_from_sym(Sm, sm);
    eS = fmax(eS, fabs((Wp - Wm) / (2.0 * h) - s[J]));
    nS = fmax(nS, fabs(s[J]));
    for (int I = 0; I < 6; ++I) {
      eD = fmax(eD, fabs((sp[I] - sm[I]) / (2.0 * h) - D[6 * I + J]));
      nD = fmax(nD, fabs(D[6 * I + J]));
    }
  }
  *err_S = nS > 0.0 ? eS / nS : eS;
  *err_D = nD > 0.0 ? eD / nD : eD;
  return TL_OK;
}

/* Largest difference of the Gauss-point stresses of a hex8 cube under the
 * uniform gradient H from the law's stress, relative to |S|. */
static TlStatus in_solid(TlMaterial *m, TlMat3 H, double *err)
{
  const size_t n[3] = {2, 2, 2};
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  TlMesh *mesh = NULL;
  TlSolid *solid = NULL;
  double *u = NULL;
  TlStatus s = TL_OK;
  const TlElementType *hex8 = NULL;
  TL_CHECK(tl_element_type_find("hex8", &hex8));
  TL_CHECK_GOTO(s, tl_mesh_create_box(hex8, n, lo, hi, &mesh), done);
  TL_CHECK_GOTO(s, tl_solid_create(mesh, &solid), done);
  TL_CHECK_GOTO(s, tl_solid_set_material(solid, NULL, m), done);
  TL_CHECK_GOTO(s, tl_solid_setup(solid), done);
  TL_CHECK_GOTO(s, tl_calloc(&u, 3 * mesh->n_nodes, sizeof *u), done);
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) u[3 * a + i] += H.m[i][j] * mesh->x[3 * a + j];
  TlMat3 F = tl_m3_add(tl_m3_identity(), H), S_law, Fq, Sq;
  TL_CHECK_GOTO(s, tl_material_evaluate(m, 1, &F, NULL, NULL, &S_law, NULL, NULL), done);
  double e = 0.0, scale = 0.0;
  for (size_t el = 0; el < mesh->blocks[0].n_elements; ++el)
    for (int q = 0; q < 8; ++q) {
      TL_CHECK_GOTO(s, tl_solid_gauss_stress(solid, 0, el, q, u, &Fq, &Sq), done);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          e = fmax(e, fabs(Sq.m[i][j] - S_law.m[i][j]));
          scale = fmax(scale, fabs(S_law.m[i][j]));
        }
    }
  *err = e / scale;
done:
  tl_free(&u);
  tl_solid_destroy(&solid);
  tl_mesh_destroy(&mesh);
  return s;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  TlMaterial *m = NULL, *lin = NULL, *nh = NULL;
  const char *name;
  double C10, C01, kappa, amp, tol;
  long samples;
  TL_CHECK(tl_initialize());
  TL_CHECK(example_mooney_rivlin_register());
  TL_CHECK(tl_options_create(argc, argv,
                             "A compressible Mooney-Rivlin law defined outside the library: stress and tangent "
                             "against finite differences, linearisation against neo_hookean, use in a solid.",
                             &o));
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-material", "mooney_rivlin", "law under test (by name)", &name), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-C10", 0.4e6, 0.0, 1e12, "Pa", "Mooney-Rivlin C10", &C10), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-C01", 0.1e6, 0.0, 1e12, "Pa", "Mooney-Rivlin C01", &C01), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-kappa", 20e6, 1e-6, 1e14, "Pa", "bulk modulus", &kappa), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-strain", 0.3, 0.0, 1.0, "", "amplitude of the random strains", &amp), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-samples", 20, 1, 100000, "random strain states", &samples), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-tolerance", 1e-6, 0.0, 1.0, "", "largest relative FD error", &tol), done);
  if ((s = tl_options_finish(o, stdout)) != TL_OK) goto done;
  double t0 = tl_wtime();
  TL_CHECK_GOTO(s, tl_material_create(name, &m), done);
  TL_CHECK_GOTO(s, tl_material_set(m, "C10", C10), done);
  TL_CHECK_GOTO(s, tl_material_set(m, "C01", C01), done);
  TL_CHECK_GOTO(s, tl_material_set(m, "kappa", kappa), done);
  TL_CHECK_GOTO(s, tl_material_setup(m), done);

  /* Finite differences at random strains of amplitude `amp`. */
  srand(11);
  double err_S = 0.0, err_D = 0.0, h = 1e-6;
  for (long k = 0; k < samples; ++k) {
    double v[6];
    for (int I = 0; I < 6; ++I) v[I] = amp * (2.0 * rand() / RAND_MAX - 1.0) * (I < 3 ? 1.0 : 0.5);
    TlMat3 E = tl_voigt_to_sym(v), F;
    if (!f_from_c(tl_m3_add(tl_m3_identity(), tl_m3_scale(E, 2.0)), &F)) { --k; continue; }
    double eS = 1.0, eD = 1.0;
    TL_CHECK_GOTO(s, fd_check(m, E, h, &eS, &eD), done);
    err_S = fmax(err_S, eS);
    err_D = fmax(err_D, eD);
  }

  /* Linearisation: C01 = 0, C10 = mu/2, kappa = lambda + 2 mu/3 against neo_hookean(E, nu). */
  const double E_mod = 1e8, nu = 0.3, mu = E_mod / (2.0 * (1.0 + nu)), lambda = E_mod * nu / ((1 + nu) * (1 - 2 * nu));
  TL_CHECK_GOTO(s, tl_material_create(name, &lin), done);
  TL_CHECK_GOTO(s, tl_material_set(lin, "C10", 0.5 * mu), done);
  TL_CHECK_GOTO(s, tl_material_set(lin, "C01", 0.0), done);
  TL_CHECK_GOTO(s, tl_material_set(lin, "kappa", lambda + 2.0 * mu / 3.0), done);
  TL_CHECK_GOTO(s, tl_material_setup(lin), done);
  TL_CHECK_GOTO(s, tl_material_create("neo_hookean", &nh), done);
  TL_CHECK_GOTO(s, tl_material_set(nh, "E", E_mod), done);
  TL_CHECK_GOTO(s, tl_material_set(nh, "nu", nu), done);
  TL_CHECK_GOTO(s, tl_material_setup(nh), done);
  TlMat3 S1, S2;
  double D1[36], D2[36], W1, W2, err_lin = 0.0, nD = 0.0;
  TL_CHECK_GOTO(s, at_strain(lin, tl_m3_zero(), &S1, D1, &W1), done);
  TL_CHECK_GOTO(s, at_strain(nh, tl_m3_zero(), &S2, D2, &W2), done);
  for (int k = 0; k < 36; ++k) err_lin = fmax(err_lin, fabs(D1[k] - D2[k])), nD = fmax(nD, fabs(D2[k]));
  err_lin /= nD;
  double ev[6] = {0.1, -0.03, 0.02, 0.04, 0.0, -0.02}, s1[6], s2[6], diff = 0.0, ns = 0.0;
  TL_CHECK_GOTO(s, at_strain(lin, tl_voigt_to_sym(ev), &S1, NULL, NULL), done);
  TL_CHECK_GOTO(s, at_strain(nh, tl_voigt_to_sym(ev), &S2, NULL, NULL), done);
  tl_voigt_from_sym(S1, s1);
  tl_voigt_from_sym(S2, s2);
  for (int I = 0; I < 6; ++I) diff = fmax(diff, fabs(s1[I] - s2[I])), ns = fmax(ns, fabs(s2[I]));

  /* In a solid, by name: the solid's Gauss-point stress is the law's. */
  TlMat3 H = {{{0.2, 0.05, 0.0}, {0.0, -0.1, 0.03}, {0.02, 0.0, 0.15}}};
  double err_solid = 1.0;
  TL_CHECK_GOTO(s, in_solid(m, H, &err_solid), done);

  printf("%s (C10 %g Pa, C01 %g Pa, kappa %g Pa), %ld strains of amplitude %g, step %g:\n", name, C10, C01, kappa,
         samples, amp, h);
  printf("  S vs dW/dE: relative error %.2e; D vs dS/dE: relative error %.2e\n", err_S, err_D);
  printf("  C01 = 0 against neo_hookean: tangent at E = 0 differs by %.2e; at |E| = 0.1 the stresses differ by "
         "%.1f %% (different large-strain forms)\n", err_lin, 100.0 * diff / ns);
  printf("  in a hex8 solid: Gauss-point stress against the law %.2e\n", err_solid);
  int ok = err_S < tol && err_D < tol && err_lin < 1e-12 && err_solid < 1e-12;
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_string(&sum, "material", name);
  tl_summary_real(&sum, "err_stress", err_S);
  tl_summary_real(&sum, "err_tangent", err_D);
  tl_summary_real(&sum, "err_linearisation", err_lin);
  tl_summary_real(&sum, "err_solid", err_solid);
  tl_summary_string(&sum, "check", ok ? "pass" : "fail");
  tl_summary_real(&sum, "wall", tl_wtime() - t0);
  s = tl_summary_print(&sum, stdout);
  if (!ok) s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "mooney_rivlin example: a check failed (see above)");
done:
  tl_material_destroy(&m);
  tl_material_destroy(&lin);
  tl_material_destroy(&nh);
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
