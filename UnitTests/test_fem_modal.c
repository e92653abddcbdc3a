/* Linear static and modal analyses (tl_linear_static.h, tl_modal.h) on
 * systems with answers in closed form:
 *  - a spring chain fixed at one end: under a tip force the linear static
 *    displacement is u_i = F (i + 1) / k whatever the springs' cubic term;
 *    with the tip prescribed (a Dirichlet dof) the displacement is linear
 *    between the wall and the tip;
 *  - its eigenvalues with lumped masses, fixed-free
 *    omega_j^2 = 4 k/m sin^2((2j - 1) pi / (2 (2n + 1))), and with the tip
 *    held (Dirichlet), fixed-fixed omega_j^2 = 4 k/m sin^2(j pi / (2n));
 *    the modes M-orthonormal; a shift below the spectrum gives the same
 *    pairs, a shift above the lowest eigenvalue is refused by name;
 *  - the S1 cantilever: the linear solution equals the Newton solution of
 *    the nonlinear problem at a vanishing load (scaled), and the consistent
 *    mass modes are M-orthonormal with small residuals;
 *  - bad options refused, and a build without ARPACK says so. */
#include <math.h>
#include <string.h>

#include "talus.h"
#include "tl_cantilever.h"
#include "tl_linear_static.h"
#include "tl_modal.h"
#include "tl_spring_chain.h"
#include "tl_stepper.h"
#include "tl_test.h"

static void check_linear_chain(void)
{
  TlSpringChainParams p;
  tl_spring_chain_params_default(&p);
  p.n = 50;
  p.k = 3.0;
  p.alpha = 5.0; /* the cubic term does not enter the reference stiffness */
  p.tip_force = 0.7;
  TlMechSystem *sys = NULL;
  TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
  double u[50];
  TlLinearStaticStats st;
  TL_TEST_STATUS(tl_linear_static_solve(sys, NULL, 0.0, u, &st), TL_OK);
  double err = 0.0;
  for (int i = 0; i < 50; ++i) err = fmax(err, fabs(u[i] - p.tip_force * (i + 1) / p.k));
  TL_TEST_ASSERT(err <= 1e-13, "chain, tip force: max error %g", err);
  TL_TEST_ASSERT(st.residual <= 1e-13, "chain: residual %g", st.residual);
  /* LU gives the same. */
  double u2[50];
  TL_TEST_STATUS(tl_linear_static_solve(sys, "klu", 0.0, u2, NULL), TL_OK);
  err = 0.0;
  for (int i = 0; i < 50; ++i) err = fmax(err, fabs(u2[i] - u[i]));
  TL_TEST_ASSERT(err <= 1e-13, "chain: klu differs from cholmod by %g", err);
  tl_mech_system_destroy(&sys);

  /* The tip prescribed: u = tip_velocity t; at t = 2 a linear field. */
  p.prescribed_tip = 1;
  p.tip_velocity = 0.25;
  TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
  TL_TEST_STATUS(tl_linear_static_solve(sys, NULL, 2.0, u, NULL), TL_OK);
  err = 0.0;
  for (int i = 0; i < 50; ++i) err = fmax(err, fabs(u[i] - 0.5 * (i + 1) / 50.0));
  TL_TEST_ASSERT(err <= 1e-13, "chain, prescribed tip: max error %g", err);
  tl_mech_system_destroy(&sys);
}

static double m_dot(const TlMechSystem *sys, const double *m, const double *a, const double *b)
{
  double s = 0.0;
  for (TlSparseIndex i = 0; i < sys->ndof; ++i) s += m[i] * a[i] * b[i];
  return s;
}

static void check_modal_chain(int prescribed)
{
  enum { N = 200, NEV = 6 };
  TlSpringChainParams p;
  tl_spring_chain_params_default(&p);
  p.n = N;
  p.k = 4.0e3;
  p.mass = 0.3;
  p.prescribed_tip = prescribed;
  TlMechSystem *sys = NULL;
  TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
  TlModalOptions o;
  tl_modal_options_default(&o);
  o.n_modes = NEV;
  o.lumped = 1;
  double w2[NEV], *phi = calloc((size_t)N * NEV, sizeof *phi), m[N];
  TlModalStats st;
  TL_TEST_STATUS(tl_modal_solve(sys, &o, w2, phi, &st), TL_OK);
  double err = 0.0;
  for (int j = 1; j <= NEV; ++j) {
    double arg = prescribed ? j * M_PI / (2.0 * N) : (2 * j - 1) * M_PI / (2.0 * (2 * N + 1));
    double ref = 4.0 * p.k / p.mass * sin(arg) * sin(arg);
    err = fmax(err, fabs(w2[j - 1] - ref) / ref);
  }
  TL_TEST_ASSERT(err <= 1e-10, "chain (%s): eigenvalues off the closed form by %g", prescribed ? "fixed-fixed" : "fixed-free",
                 err);
  TL_TEST_ASSERT(st.residual <= 1e-8 && st.consistent == 0, "chain: residual %g, consistent %d", st.residual,
                 st.consistent);
  for (int i = 0; i < N; ++i) m[i] = p.mass;
  if (prescribed) m[N - 1] = 0.0;
  double orth = 0.0;
  for (int a = 0; a < NEV; ++a)
    for (int b = 0; b <= a; ++b) orth = fmax(orth, fabs(m_dot(sys, m, phi + a * N, phi + b * N) - (a == b)));
  TL_TEST_ASSERT(orth <= 1e-10, "chain: modes not M-orthonormal (%g)", orth);
  if (prescribed) TL_TEST_ASSERT(phi[N - 1] == 0.0, "the held tip moves in mode 1: %g", phi[N - 1]);
  /* A shift below the spectrum: the same eigenvalues. */
  double w2s[NEV];
  o.shift = 0.5 * w2[0];
  TL_TEST_STATUS(tl_modal_solve(sys, &o, w2s, NULL, NULL), TL_OK);
  err = 0.0;
  for (int j = 0; j < NEV; ++j) err = fmax(err, fabs(w2s[j] - w2[j]) / w2[j]);
  TL_TEST_ASSERT(err <= 1e-10, "chain: shifted eigenvalues differ by %g", err);
  /* A shift above the lowest eigenvalue makes K - sigma M indefinite. */
  o.shift = 1.5 * w2[0];
  TL_TEST_STATUS(tl_modal_solve(sys, &o, w2s, NULL, NULL), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(strstr(tl_error_message(), "shift") != NULL, "message names the shift: %s", tl_error_message());
  free(phi);
  tl_mech_system_destroy(&sys);
}

static void check_cantilever(void)
{
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.nu = 0.3;
  p.material = "saint_venant_kirchhoff";
  p.load = 1e-3; /* tip deflection ~ 1e-7 of the length: linear to ~1e-7 */
  TlCantilever *beam = NULL;
  TL_TEST_STATUS(tl_cantilever_create(&p, &beam), TL_OK);
  if (!beam) return;
  TlMechSystem *sys = tl_solid_system(beam->solid);
  double *u = calloc((size_t)sys->ndof, sizeof *u), tip[3], tip_n[3];
  TL_TEST_STATUS(tl_linear_static_solve(sys, NULL, 0.0, u, NULL), TL_OK);
  tl_cantilever_tip(beam, u, tip);
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  so.rtol = 1e-13;
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, &so, &st), TL_OK);
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_stepper_step(st, 1.0), TL_OK);
  tl_cantilever_tip(beam, st->u, tip_n);
  double rel = fabs(tip[2] - tip_n[2]) / fabs(tip_n[2]);
  TL_TEST_ASSERT(tip[2] < 0.0 && rel <= 1e-6, "cantilever: linear tip %.12g, Newton %.12g (relative %g)", tip[2],
                 tip_n[2], rel);
  tl_stepper_destroy(&st);
  if (tl_modal_available()) {
    enum { NEV = 4 };
    TlModalOptions o;
    tl_modal_options_default(&o);
    o.n_modes = NEV;
    double w2[NEV], *phi = calloc((size_t)sys->ndof * NEV, sizeof *phi), *Mphi = calloc((size_t)sys->ndof, sizeof *Mphi);
    TlModalStats ms;
    TL_TEST_STATUS(tl_modal_solve(sys, &o, w2, phi, &ms), TL_OK);
    TL_TEST_ASSERT(ms.consistent == 1 && ms.residual <= 1e-8, "cantilever: consistent %d, residual %g", ms.consistent,
                   ms.residual);
    /* M-orthonormality with the consistent mass. */
    TlSparse *M = NULL;
    TL_TEST_STATUS(sys->ops->create_matrix(sys, 1, &M), TL_OK);
    TL_TEST_STATUS(sys->ops->consistent_mass(sys, 1.0, M), TL_OK);
    double orth = 0.0;
    for (int a = 0; a < NEV; ++a) {
      tl_sparse_matvec(M, phi + (size_t)a * sys->ndof, Mphi);
      for (int b = 0; b < NEV; ++b) {
        double s = 0.0;
        for (TlSparseIndex i = 0; i < sys->ndof; ++i) s += phi[(size_t)b * sys->ndof + i] * Mphi[i];
        orth = fmax(orth, fabs(s - (a == b)));
      }
    }
    TL_TEST_ASSERT(orth <= 1e-10, "cantilever: modes not M-orthonormal (%g)", orth);
    /* Ascending, the square section's bending pair degenerate. */
    TL_TEST_ASSERT(w2[0] > 0.0 && w2[0] <= w2[1] && w2[1] < w2[2] && w2[2] <= w2[3], "order %g %g %g %g", w2[0], w2[1],
                   w2[2], w2[3]);
    TL_TEST_ASSERT(fabs(w2[1] - w2[0]) <= 1e-9 * w2[0], "bending pair %.15g %.15g", w2[0], w2[1]);
    tl_sparse_destroy(&M);
    free(phi);
    free(Mphi);
  }
  free(u);
  tl_cantilever_destroy(&beam);
}

static void check_refusals(void)
{
  TlSpringChainParams p;
  tl_spring_chain_params_default(&p);
  TlMechSystem *sys = NULL;
  TL_TEST_STATUS(tl_spring_chain_create(&p, &sys), TL_OK);
  TlModalOptions o;
  tl_modal_options_default(&o);
  double w2[16];
  o.n_modes = 0;
  TL_TEST_STATUS(tl_modal_solve(sys, &o, w2, NULL, NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "n_modes") != NULL, "%s", tl_error_message());
  o.n_modes = 10; /* = ndof */
  TL_TEST_STATUS(tl_modal_solve(sys, &o, w2, NULL, NULL), TL_ERR_ARG);
  o.n_modes = 3;
  o.ncv = 3; /* not more Lanczos vectors than modes */
  TL_TEST_STATUS(tl_modal_solve(sys, &o, w2, NULL, NULL), tl_modal_available() ? TL_ERR_ARG : TL_ERR_UNSUPPORTED);
  if (!tl_modal_available()) {
    o.ncv = 0;
    TL_TEST_STATUS(tl_modal_solve(sys, &o, w2, NULL, NULL), TL_ERR_UNSUPPORTED);
    TL_TEST_ASSERT(strstr(tl_error_message(), "ARPACK") != NULL, "%s", tl_error_message());
  }
  double u[10];
  TL_TEST_STATUS(tl_linear_static_solve(sys, "nonexistent", 0.0, u, NULL), TL_ERR_NOT_FOUND);
  tl_mech_system_destroy(&sys);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  check_linear_chain();
  if (tl_modal_available()) {
    check_modal_chain(0);
    check_modal_chain(1);
  } else {
    printf("this build has no ARPACK: the chain's eigenvalues are not checked\n");
  }
  check_cantilever();
  check_refusals();
  return tl_test_report();
}
