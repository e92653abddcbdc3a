/* Strain probing of a face-centred cubic Hertz lattice under pressure
 * (spec B-U4): the probe's C_iJ against the analytic stiffness of central
 * pair forces.
 *
 * With pair forces φ(r) along the branch vectors b = F B (φ > 0 repulsive,
 * g = φ/r) the Cauchy-Poisson stress of the deformed cell is
 *   σ_ab(F) = -(1/V(F)) Σ_c g(|F B|) (F B)_a (F B)_b,   V(F) = det F V0,
 * so at F = I its derivative along F_kl is
 *   ∂σ_ab/∂F_kl = -(1/V0) Σ_c [g'(R) B_a B_b B_k B_l / R
 *                  + g(R) (δ_ak B_l B_b + δ_bk B_l B_a)] - σ0_ab δ_kl,
 * Hertz φ = k_n sqrt(R_eff) δ^{3/2}, δ = d - r.  The first term is the
 * Cauchy-symmetric bond stiffness (C12 = C44 without pre-stress), the two
 * others are the pre-stress terms.  Checks:
 *   1. affine probe, ε = 1e-6: every C_iJ within 1e-7 of the analytic value
 *      (relative to the largest);
 *   2. ± averaging: at ε = 1e-4 the one-sided (σ+ - σ0)/ε is off by O(ε),
 *      the central difference by O(ε²): at least 30 times less;
 *   3. a Bravais lattice has no non-affine mode under central forces: a
 *      jiggled copy relaxed (reference and every probe) gives back the
 *      analytic tensor, to the relaxation tolerance;
 *   4. with tangential springs (lammps_history) the relaxed tensor is still
 *      the central one: in a centrosymmetric cubic lattice the torque of the
 *      tangential forces of a symmetric strain sums to zero (Σ n × (E n) = 0
 *      over the twelve neighbour directions), so the grains do not rotate and
 *      the relaxed C44 equals the affine one (the closed-form difference is
 *      zero); the probe's jump leaves the histories unloaded and the
 *      relaxation does not load them.  Jiggled first, the grains rotate while
 *      relaxing: the torques must come to balance (skew stress ~ 0) and the
 *      tensor stays near the central one (friction locks part of the jiggle).
 * The moduli and the Zener index follow from the tensor by the scripts'
 * formulas; checked against those of the analytic tensor. */
#include <math.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_dem_probe.h"
#include "tl_test.h"

enum { M = 4 };
static const double kn = 3.663e10, rho = 2500.0, R = 1.5e-3, delta = 1e-5;
static const int voigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};

static double lattice_a(void) { return (2.0 * R - delta) * sqrt(2.0); }

/* analytic C_iJ (Voigt, engineering shears, symmetric stress) and σ0 */
static void analytic(double C[6][6], double s0[6])
{
  static const double dir[6][3] = {{1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}};
  const double a = lattice_a(), r = a / sqrt(2.0), d = 2.0 * R;
  const double K = kn * sqrt(0.5 * R), dl = d - r;
  const double phi = K * pow(dl, 1.5), dphi = -1.5 * K * sqrt(dl);
  const double g = phi / r, dg = dphi / r - phi / (r * r);
  const double v = a * a * a / 4.0; /* volume per particle, six bonds each */
  double B[6][3];
  for (int c = 0; c < 6; ++c)
    for (int k = 0; k < 3; ++k) B[c][k] = 0.5 * a * dir[c][k];
  double sig[3][3] = {{0}};
  for (int c = 0; c < 6; ++c)
    for (int x = 0; x < 3; ++x)
      for (int y = 0; y < 3; ++y) sig[x][y] -= g * B[c][x] * B[c][y] / v;
  for (int i = 0; i < 6; ++i) s0[i] = sig[voigt[i][0]][voigt[i][1]];
  for (int i = 0; i < 6; ++i)
    for (int J = 0; J < 6; ++J) {
      const int p = voigt[i][0], q = voigt[i][1], k = voigt[J][0], l = voigt[J][1];
      double t = 0.0;
      for (int c = 0; c < 6; ++c) {
        const double *b = B[c];
        t -= dg * b[p] * b[q] * b[k] * b[l] / r;
        t -= g * ((p == k) * b[l] * b[q] + (q == k) * b[l] * b[p]);
      }
      C[i][J] = t / v - sig[p][q] * (k == l);
    }
}

static TlStatus build(TlDem **out, const char *friction)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  const double a = lattice_a();
  TlDomain dom;
  TL_CHECK(tl_domain_init_cell(&dom, tl_v3(0, 0, 0), tl_m3_scale(tl_m3_identity(), M * a)));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  int sp;
  TL_CHECK(tl_particles_add_species(P, "g", rho, R, R, &sp));
  static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int i = 0; i < M; ++i)
    for (int j = 0; j < M; ++j)
      for (int k = 0; k < M; ++k)
        for (int q = 0; q < 4; ++q)
          TL_CHECK(tl_dem_add_particle(dem, tl_v3((i + 0.25 + basis[q][0]) * a, (j + 0.25 + basis[q][1]) * a,
                                                  (k + 0.25 + basis[q][2]) * a),
                                       tl_v3(0, 0, 0), R, sp, NULL));
  const TlContactValue values[] = {{"k_n", kn}, {"gamma_n", 0.2}, {"k_t", 4.5249e10}, {"mu", 0.5}};
  const TlContactSpec spec = {"lammps_hertz", friction, NULL, NULL, values, friction ? 4 : 2};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TL_CHECK(tl_dem_set_timestep(dem, 1e-7, 0));
  TL_CHECK(tl_dem_setup(dem));
  *out = dem;
  return TL_OK;
}

/* largest |A - B| over the 36 entries, relative to the largest |B| */
static double rel_diff(const double A[6][6], const double B[6][6])
{
  double e = 0.0, big = 0.0;
  for (int i = 0; i < 6; ++i)
    for (int J = 0; J < 6; ++J) {
      e = fmax(e, fabs(A[i][J] - B[i][J]));
      big = fmax(big, fabs(B[i][J]));
    }
  return e / big;
}

static void print_tensor(const char *what, const double C[6][6])
{
  printf("%s (GPa):\n", what);
  for (int i = 0; i < 6; ++i) {
    for (int J = 0; J < 6; ++J) printf(" %12.7f", C[i][J] * 1e-9);
    printf("\n");
  }
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  double Ca[6][6], s0[6];
  analytic(Ca, s0);
  print_tensor("analytic", Ca);
  TlElasticModuli ma;
  tl_elastic_moduli(Ca, &ma);
  printf("analytic: p = %.6g Pa, C11 %.6g C12 %.6g C44 %.6g Pa, K %.6g G1 %.6g G2 %.6g E %.6g nu %.6f Z %.6f\n",
         -s0[0], ma.C11, ma.C12, ma.C44, ma.K, ma.G1, ma.G2, ma.E, ma.nu, ma.zener);

  /* 1. affine probe */
  TlDem *dem = NULL;
  TL_TEST_STATUS(build(&dem, NULL), TL_OK);
  TlProbeSettings s;
  tl_probe_settings_default(&s);
  s.scratch = "test_elastic_probe_fcc_ref.h5";
  TlProbeResult r;
  TL_TEST_STATUS(tl_dem_probe_elastic(dem, &s, &r), TL_OK);
  print_tensor("affine probe, eps 1e-6", r.C);
  double e1 = rel_diff(r.C, Ca);
  printf("affine probe: largest difference %.3e of the largest C; reference pressure %.8g Pa (analytic %.8g)\n", e1,
         r.pressure0, -s0[0]);
  TL_TEST_ASSERT(e1 <= 1e-7, "affine probe differs from the analytic tensor by %g (relative)", e1);
  TL_TEST_REL(r.pressure0, -s0[0], 1e-12);
  TL_TEST_REL(r.moduli.E, ma.E, 1e-7);
  TL_TEST_REL(r.moduli.nu, ma.nu, 1e-7);
  TL_TEST_REL(r.moduli.zener, ma.zener, 1e-7);
  /* the lattice is cubic: C11 = C22 = C33, C44 = C55 = C66, the rest zero */
  TL_TEST_ASSERT(fabs(r.C[3][0]) <= 1e-7 * r.C[0][0], "C41 = %g in a cubic lattice", r.C[3][0]);

  /* 2. central against one-sided differences */
  s.strain = 1e-4;
  TL_TEST_STATUS(tl_dem_probe_elastic(dem, &s, &r), TL_OK);
  double ec = rel_diff(r.C, Ca), ep = rel_diff(r.C_pos, Ca), en = rel_diff(r.C_neg, Ca);
  printf("eps 1e-4: central %.3e, one-sided +: %.3e, -: %.3e (relative to the analytic tensor)\n", ec, ep, en);
  TL_TEST_ASSERT(ep >= 1e-4 && en >= 1e-4, "one-sided errors %g, %g: the curvature should show at eps 1e-4", ep, en);
  TL_TEST_ASSERT(ec * 30.0 <= fmin(ep, en), "central error %g is not well below the one-sided %g, %g", ec, ep, en);
  tl_dem_destroy(&dem);

  /* 3. jiggled and relaxed, frictionless */
  TL_TEST_STATUS(build(&dem, NULL), TL_OK);
  tl_probe_settings_default(&s);
  s.scratch = "test_elastic_probe_fcc_ref.h5";
  s.kind = TL_PROBE_RELAXED;
  s.jiggle = 2e-7;
  s.viscous = 2.0;
  s.tolerance = 1e-9;
  s.max_steps = 200000;
  s.check_every = 100;
  TL_TEST_STATUS(tl_dem_probe_elastic(dem, &s, &r), TL_OK);
  double e3 = rel_diff(r.C, Ca);
  printf("jiggled 2e-7 m and relaxed (frictionless): difference %.3e; relaxations: up to %ld steps, largest "
         "imbalance %.2e, converged %d\n",
         e3, r.relax_steps, r.relax_imbalance, r.relax_converged);
  TL_TEST_ASSERT(r.relax_converged, "relaxation did not reach the tolerance (imbalance %g)", r.relax_imbalance);
  TL_TEST_ASSERT(r.relax_steps > 0, "the jiggled reference needed no relaxation");
  TL_TEST_ASSERT(e3 <= 1e-5, "relaxed probe differs from the analytic affine tensor by %g", e3);
  /* without the relaxation the jiggled affine tensor is off */
  s.kind = TL_PROBE_AFFINE;
  TL_TEST_STATUS(tl_dem_probe_elastic(dem, &s, &r), TL_OK); /* the relaxed lattice, jiggled again */
  double e3a = rel_diff(r.C, Ca);
  printf("jiggled 2e-7 m, affine: difference %.3e\n", e3a);
  TL_TEST_ASSERT(e3a >= 10.0 * e3, "the jiggle should change the affine tensor (%g against %g relaxed)", e3a, e3);
  tl_dem_destroy(&dem);

  /* 4. tangential springs: relaxed = affine, unjiggled; jiggled, the grains
   * rotate while relaxing and the torques come to balance too */
  TL_TEST_STATUS(build(&dem, "lammps_history"), TL_OK);
  tl_probe_settings_default(&s);
  s.scratch = "test_elastic_probe_fcc_ref.h5";
  TlProbeResult ra;
  TL_TEST_STATUS(tl_dem_probe_elastic(dem, &s, &ra), TL_OK);
  s.kind = TL_PROBE_RELAXED;
  s.viscous = 2.0;
  s.tolerance = 1e-9;
  s.max_steps = 200000;
  TL_TEST_STATUS(tl_dem_probe_elastic(dem, &s, &r), TL_OK);
  double e4 = rel_diff(r.C, ra.C), e4a = rel_diff(ra.C, Ca);
  printf("with tangential springs: affine - analytic %.3e, relaxed - affine %.3e (C44 %.10g against %.10g Pa)\n", e4a,
         e4, r.C[3][3], ra.C[3][3]);
  TL_TEST_ASSERT(e4a <= 1e-7, "affine probe with tangential springs differs from the central tensor by %g", e4a);
  TL_TEST_ASSERT(e4 <= 1e-7, "relaxed C differs from the affine one by %g with tangential springs", e4);
  s.jiggle = 2e-7;
  TL_TEST_STATUS(tl_dem_probe_elastic(dem, &s, &r), TL_OK);
  double e4j = rel_diff(r.C, Ca);
  printf("with tangential springs, jiggled 2e-7 m and relaxed: up to %ld steps, imbalance %.2e, converged %d, largest skew "
         "stress %.3e Pa (of %.3e), difference to the analytic tensor %.3e (friction locks part of the jiggle)\n",
         r.relax_steps, r.relax_imbalance, r.relax_converged, r.max_skew, r.pressure0, e4j);
  TL_TEST_ASSERT(r.relax_converged, "relaxation with friction did not converge (imbalance %g)", r.relax_imbalance);
  TL_TEST_ASSERT(r.max_skew <= 1e-6 * r.pressure0, "torques out of balance: skew stress %g Pa", r.max_skew);
  TL_TEST_ASSERT(e4j <= 1e-4, "relaxed tensor with friction off the analytic by %g", e4j);
  tl_dem_destroy(&dem);

  /* refusals */
  TL_TEST_STATUS(build(&dem, NULL), TL_OK);
  tl_probe_settings_default(&s);
  s.strain = 0.5;
  TL_TEST_STATUS(tl_dem_probe_elastic(dem, &s, &r), TL_ERR_ARG);
  s.strain = 1e-6;
  s.jiggle = 1.0;
  TL_TEST_STATUS(tl_dem_probe_elastic(dem, &s, &r), TL_ERR_ARG);
  tl_dem_destroy(&dem);
  return tl_test_report();
}
