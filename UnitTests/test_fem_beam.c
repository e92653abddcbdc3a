/* The S1 beam (REFERENCE.md: 0.8 m x 0.8 m x 12 m, E = 100 MPa, nu = 0,
 * rho = 1309 kg/m^3, clamped at y = 0) through the solid and the steppers:
 * the static tip deflection under a small end load against Timoshenko beam
 * theory (27-node hexahedra; the paper's 8-node mesh is reported), and the
 * energy of free vibrations under implicit Newmark (average acceleration),
 * which must stay constant. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_test.h"

static const double E_mod = 1e8, rho = 1309.0, L = 12.0, b = 0.8;

static TlStatus build(const TlElementType *t, size_t ny, TlMesh **mesh, TlMaterial **mat, TlSolid **solid)
{
  size_t n[3] = {2, ny, 2};
  double lo[3] = {-0.4, 0.0, -0.4}, hi[3] = {0.4, L, 0.4};
  TL_CHECK(tl_mesh_create_box(t, n, lo, hi, mesh));
  TL_CHECK(tl_material_create_hooke(E_mod, 0.0, rho, mat));
  TL_CHECK(tl_solid_create(*mesh, solid));
  TL_CHECK(tl_solid_set_material(*solid, NULL, *mat));
  TL_CHECK(tl_solid_fix(*solid, "ymin", 7));
  return TL_OK;
}

/* Tip (centre of the free end) deflection along z. */
static double tip_w(const TlMesh *mesh, const TlSolid *solid, const double *u)
{
  double w = 0.0;
  int count = 0;
  for (size_t a = 0; a < mesh->n_nodes; ++a) {
    const double *X = mesh->x + 3 * a;
    if (fabs(X[1] - L) < 1e-9 && fabs(X[0]) < 1e-9) {
      w += u[tl_solid_dof(solid, a, 2)];
      ++count;
    }
  }
  return w / count;
}

/* The tip deflection's ratio to Timoshenko's must lie in [lo, hi]: two-sided,
 * around the measured value (NaN fails). */
static void static_deflection(const TlElementType *t, double lo, double hi)
{
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(build(t, 30, &mesh, &mat, &solid), TL_OK);
  if (!solid) return;
  double F = 71.1; /* total end load (N): tip deflection ~ L / 1000 */
  TL_TEST_STATUS(tl_solid_add_traction(solid, "ymax", tl_v3(0, 0, -F / (b * b)), NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TL_TEST_STATUS(tl_solid_check_constraints(solid), TL_OK);
  TlStepperOptions opt;
  tl_stepper_options_default(&opt);
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("quasi_static", tl_solid_system(solid), &opt, &st), TL_OK);
  if (!st) return;
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_stepper_step(st, 1.0), TL_OK);
  double I = b * b * b * b / 12.0, G = E_mod / 2.0, kappa = 5.0 / 6.0;
  double w_eb = F * L * L * L / (3 * E_mod * I), w_t = w_eb + F * L / (kappa * G * b * b);
  double w = -tip_w(mesh, solid, st->u);
  printf("%s 2x30x2: tip deflection %.6e m, Euler-Bernoulli %.6e, Timoshenko %.6e, ratio to Timoshenko %.4f\n",
         t->header.name, w, w_eb, w_t, w / w_t);
  TL_TEST_ASSERT(w / w_t >= lo && w / w_t <= hi, "%s tip deflection %g vs Timoshenko %g: ratio %g outside [%g, %g]",
                 t->header.name, w, w_t, w / w_t, lo, hi);
  /* External work of the (dead) end load equals the stored energy of the
   * linear-regime solution to second order: W = 1/2 F w. */
  double We = 0.0, *u0 = calloc((size_t)tl_solid_system(solid)->ndof, sizeof *u0);
  TL_TEST_STATUS(tl_solid_strain_energy(solid, st->u, &We), TL_OK);
  double Wx = 0.0;
  TL_TEST_STATUS(tl_solid_work_increment(solid, 1.0, u0, 1.0, st->u, &Wx), TL_OK);
  TL_TEST_ASSERT(fabs(We - 0.5 * Wx) < 1e-3 * We, "strain energy %g vs half the load work %g", We, 0.5 * Wx);
  /* Reactions at the clamp balance the load. */
  size_t nc = mesh->n_nodes * 3;
  double *R = calloc(nc, sizeof *R), Rz = 0.0;
  TL_TEST_STATUS(tl_solid_reactions(solid, 1.0, st->u, NULL, R), TL_OK);
  for (size_t a = 0; a < mesh->n_nodes; ++a) Rz += R[3 * a + 2];
  TL_TEST_CLOSE(Rz / F, 1.0, 1e-8);
  free(R);
  free(u0);
  tl_stepper_destroy(&st);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* Largest relative drift of kinetic + strain energy over a quarter period
 * with n_steps Newmark steps; *tip gets the largest tip deflection. */
static double vibration_drift(int n_steps, double amplitude, double *tip)
{
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  double worst = -1.0;
  TL_TEST_STATUS(build(&tl_element_hex8, 10, &mesh, &mat, &solid), TL_OK);
  if (!solid) return worst;
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *v = calloc(n, sizeof *v);
  /* Tip velocity `amplitude` (m/s); 1 m/s swings the tip by ~0.4 m. */
  for (size_t a = 0; a < mesh->n_nodes; ++a) {
    double y = mesh->x[3 * a + 1] / L;
    TlSparseIndex d = tl_solid_dof(solid, a, 2);
    if (d >= 0) v[d] = amplitude * y * y;
  }
  TlStepperOptions opt;
  tl_stepper_options_default(&opt);
  /* CHOLMOD: the Newmark tangent of this symmetric system is positive
   * definite along the path (test_fem_stepper_beam shows why an old
   * constant-acceleration predictor made it refuse one). */
  opt.solver = "cholmod";
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("newmark", sys, &opt, &st), TL_OK);
  if (st) {
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, v), TL_OK);
    TlEnergies e0, e;
    TL_TEST_STATUS(tl_stepper_energies(st, &e0), TL_OK);
    double Ek = 0.0;
    TL_TEST_STATUS(tl_solid_kinetic_energy(solid, v, &Ek), TL_OK);
    TL_TEST_CLOSE(e0.kinetic / Ek, 1.0, 1e-12);
    /* First bending period ~ 2 pi / (1.875^2 sqrt(E I / (rho A L^4))). */
    double I = b * b * b * b / 12.0;
    double T = 2 * M_PI / (1.875 * 1.875 * sqrt(E_mod * I / (rho * b * b * L * L * L * L)));
    double dt = 0.25 * T / n_steps;
    worst = 0.0;
    *tip = 0.0;
    for (int k = 0; k < n_steps; ++k) {
      TL_TEST_STATUS(tl_stepper_step(st, dt), TL_OK);
      TL_TEST_STATUS(tl_stepper_energies(st, &e), TL_OK);
      worst = fmax(worst, fabs(e.kinetic + e.strain - e0.kinetic) / e0.kinetic);
      *tip = fmax(*tip, fabs(tip_w(mesh, solid, st->u)));
    }
    tl_stepper_destroy(&st);
  }
  free(v);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
  return worst;
}

/* The trapezoidal (average-acceleration) rule conserves energy exactly for
 * linear systems: at small amplitude the drift is at the solver's
 * tolerance; at large amplitude (geometrically nonlinear) it is small and
 * falls with the step. */
static void vibration_energy(void)
{
  double tip0 = 0.0, tip1 = 0.0, tip2 = 0.0;
  double d0 = vibration_drift(25, 1e-3, &tip0);
  double d1 = vibration_drift(25, 1.0, &tip1), d2 = vibration_drift(50, 1.0, &tip2);
  printf("free vibration (quarter period): energy drift %.2e at 1 mm/s (T/100); at 1 m/s %.2e (T/100), "
         "%.2e (T/200), tip %.3f m\n", d0, d1, d2, tip2);
  TL_TEST_ASSERT(tip2 > 0.3 && tip0 > 0.0, "tip moved only %g m", tip2);
  TL_TEST_ASSERT(d0 < 1e-8, "small-amplitude energy drift %g", d0);
  TL_TEST_ASSERT(d2 < 1e-4 && d2 < d1, "large-amplitude energy drift %g (T/200), %g (T/100)", d2, d1);
}

/* The system's bound of the largest eigenvalue of M^-1 K (explicit critical
 * step): at least the assembled eigenvalue (power iterations), and tight. */
static void frequency_bound(const TlElementType *t)
{
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(build(t, 10, &mesh, &mat, &solid), TL_OK);
  if (!solid) return;
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *x = calloc(n, sizeof *x), *y = calloc(n, sizeof *y), *m = calloc(n, sizeof *m);
  sys->ops->lumped_mass(sys, m);
  TlSparse *K = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 0, &K), TL_OK);
  TL_TEST_STATUS(sys->ops->internal_tangent(sys, 0.0, u, NULL, 1.0, 0.0, K), TL_OK);
  for (size_t i = 0; i < n; ++i) x[i] = sin(0.7 * i) + 0.3;
  double lam = 0.0;
  for (int it = 0; it < 3000; ++it) {
    double nrm = 0.0;
    for (size_t i = 0; i < n; ++i) nrm += x[i] * x[i];
    nrm = sqrt(nrm);
    for (size_t i = 0; i < n; ++i) y[i] = x[i] / nrm / sqrt(m[i]);
    tl_sparse_matvec(K, y, u);
    lam = 0.0;
    for (size_t i = 0; i < n; ++i) {
      x[i] = u[i] / sqrt(m[i]);
      lam += x[i] * y[i] * sqrt(m[i]);
    }
  }
  memset(u, 0, n * sizeof *u);
  double bound = 0.0;
  TL_TEST_STATUS(sys->ops->max_frequency_squared(sys, u, &bound), TL_OK);
  printf("%s: omega_max^2 %.4e (power iterations), system bound %.4e (ratio %.3f)\n", t->header.name, lam, bound,
         bound / lam);
  TL_TEST_ASSERT(bound >= lam * (1 - 1e-9) && bound < 1.2 * lam, "%s: bound %g vs omega^2 %g", t->header.name, bound, lam);
  tl_sparse_destroy(&K);
  free(u), free(x), free(y), free(m);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  double t0 = omp_get_wtime();
  static_deflection(&tl_element_hex27, 0.99, 1.01); /* measured 1.0000 */
  double t1 = omp_get_wtime();
  static_deflection(&tl_element_hex8, 0.878, 0.898); /* measured 0.8885: shear locking, 2x30x2 */
  double t2 = omp_get_wtime();
  vibration_energy();
  frequency_bound(&tl_element_hex8);
  frequency_bound(&tl_element_hex27);
  printf("wall: hex27 static %.2f s, hex8 static %.2f s, vibration %.2f s\n", t1 - t0, t2 - t1, omp_get_wtime() - t2);
  return tl_test_report();
}
