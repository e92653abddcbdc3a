/* The deformable periodic cell (seeds/004 Eqs. 13-21, 27): a face-centred
 * cubic lattice of touching spheres (a Bravais lattice, stable under
 * central springs) in a periodic cell is deformed affinely by driving h at
 * constant rate ḣ; by symmetry every particle follows the affine field, and
 * the Cauchy-Poisson stress must equal the one computed by hand from the
 * deformed lattice vectors.  Also checks that h reaches F h0, reduced
 * coordinates are kept and the kinetic stress stays zero. */
#include <math.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

/* Stress by hand: per particle six contacts along F (a/2) e with e the
 * half of the twelve FCC neighbour directions; a linear spring k_n pushes
 * with k_n (d - |b|) along -b̂ on the particle at the origin of b;
 * σ = (1/v) Σ f ⊗ b, v = det F a³/4 the volume per particle. */
static TlMat3 hand_stress(TlMat3 F, double a, double d, double kn)
{
  static const double dir[6][3] = {{1, 1, 0}, {1, -1, 0}, {1, 0, 1}, {1, 0, -1}, {0, 1, 1}, {0, 1, -1}};
  TlMat3 s = tl_m3_zero();
  for (int k = 0; k < 6; ++k) {
    TlVec3 e = {0.5 * a * dir[k][0], 0.5 * a * dir[k][1], 0.5 * a * dir[k][2]};
    TlVec3 b = tl_m3_mulv(F, e);
    double len = tl_v3_norm(b), ov = d - len;
    if (ov <= 0) continue;
    TlVec3 f = tl_v3_scale(b, -kn * ov / len);
    s = tl_m3_add(s, tl_m3_outer(f, b));
  }
  return tl_m3_scale(s, 4.0 / (a * a * a * tl_m3_det(F)));
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const int m = 3;
  const double a = 0.01, d = a / sqrt(2.0), kn = 1e5;
  static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  TlMat3 h0 = tl_m3_scale(tl_m3_identity(), m * a);
  TL_TEST_STATUS(tl_domain_init_cell(&dom, tl_v3(0, 0, 0), h0), TL_OK);
  TL_TEST_STATUS(tl_dem_set_domain(dem, &dom), TL_OK);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "g", 2500, 0.5 * d, 0.5 * d, &sp), TL_OK);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k)
        for (int q = 0; q < 4; ++q)
          TL_TEST_STATUS(tl_dem_add_particle(dem,
                                             tl_v3((i + 0.25 + basis[q][0]) * a, (j + 0.25 + basis[q][1]) * a,
                                                   (k + 0.25 + basis[q][2]) * a),
                                             tl_v3(0, 0, 0), 0.5 * d, sp, NULL), TL_OK);
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", kn, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  /* deformation gradient: compression with a small shear */
  TlMat3 F = {{{0.99, 0.004, 0.0}, {0.0, 0.995, 0.0}, {0.002, 0.0, 0.998}}};
  double T = 0.05;
  long steps = 5000;
  TlMat3 hdot = tl_m3_scale(tl_m3_mul(tl_m3_add(F, tl_m3_scale(tl_m3_identity(), -1.0)), h0), 1.0 / T);
  TL_TEST_STATUS(tl_domain_set_h_rate(tl_dem_domain(dem), hdot), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, T / (double)steps, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TlVec3 s0[4 * 27];
  for (size_t i = 0; i < P->n; ++i) s0[P->id[i]] = tl_domain_to_reduced(tl_dem_domain(dem), P->x[i]);
  TL_TEST_STATUS(tl_dem_step(dem, steps), TL_OK);
  TlDomain *D = tl_dem_domain(dem);
  /* h reached F h0 */
  TlMat3 hF = tl_m3_mul(F, h0);
  double herr = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) herr = fmax(herr, fabs(D->h.m[i][j] - hF.m[i][j]));
  TL_TEST_ASSERT(herr < 1e-12 * m * a, "h differs from F h0 by %g", herr);
  /* particles kept their reduced coordinates (affine motion) */
  double serr = 0.0;
  for (size_t i = 0; i < P->n; ++i) {
    TlVec3 ds = tl_v3_sub(tl_domain_to_reduced(D, P->x[i]), s0[P->id[i]]);
    ds = tl_v3(ds.x - nearbyint(ds.x), ds.y - nearbyint(ds.y), ds.z - nearbyint(ds.z));
    serr = fmax(serr, tl_v3_norm(ds));
  }
  printf("reduced coordinates: largest change %.2e over the deformation\n", serr);
  TL_TEST_ASSERT(serr < 1e-9, "particles left the affine field by %g (reduced)", serr);
  /* stress */
  TlMat3 sc, sk;
  TL_TEST_STATUS(tl_dem_stress(dem, &sc, &sk), TL_OK);
  TlMat3 sh = hand_stress(F, a, d, kn);
  double err = 0.0, big = 0.0, kin = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      err = fmax(err, fabs(sc.m[i][j] - sh.m[i][j]));
      big = fmax(big, fabs(sh.m[i][j]));
      kin = fmax(kin, fabs(sk.m[i][j]));
    }
  printf("stress (Pa): computed [%.6g %.6g %.6g; %.6g %.6g %.6g; %.6g %.6g %.6g]\n", sc.m[0][0], sc.m[0][1],
         sc.m[0][2], sc.m[1][0], sc.m[1][1], sc.m[1][2], sc.m[2][0], sc.m[2][1], sc.m[2][2]);
  printf("             by hand  [%.6g %.6g %.6g; %.6g %.6g %.6g; %.6g %.6g %.6g], largest difference %.2e relative\n",
         sh.m[0][0], sh.m[0][1], sh.m[0][2], sh.m[1][0], sh.m[1][1], sh.m[1][2], sh.m[2][0], sh.m[2][1],
         sh.m[2][2], err / big);
  TL_TEST_ASSERT(err <= 1e-8 * big, "stress differs from the hand computation by %g (scale %g)", err, big);
  TL_TEST_ASSERT(kin <= 1e-10 * big, "kinetic stress %g in an affine deformation", kin);
  TL_TEST_ASSERT(fabs(sh.m[0][1]) > 1e-3 * big, "the shear component %g should be non-zero", sh.m[0][1]);
  /* the affine relative velocity enters the contact law (Eq. 21): with
   * damping the stress while deforming exceeds the elastic one */
  tl_dem_destroy(&dem);
  return tl_test_report();
}
