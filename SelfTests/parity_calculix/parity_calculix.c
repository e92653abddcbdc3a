/* Talus against CalculiX on the same problem, answers to 1e-6 relative:
 *
 *  - the S1 cantilever (Hex8 / C3D8, 2 x 2 x 30, 0.8 x 0.8 x 12 m,
 *    E = 100 MPa, nu = 0.3 so that both Lame constants enter,
 *    rho = 1309 kg/m^3), clamped at y = 0, the same consistent nodal tip
 *    loads in both codes (peers/tl_peer_calculix.h writes CalculiX's deck
 *    from Talus's mesh);
 *  - linear static analysis under P = 1644 N: the weighted mean tip
 *    deflection;
 *  - geometrically nonlinear statics under the dead load P L^2/(E I) = 2
 *    (tip rotation about 35 degrees), Saint Venant-Kirchhoff in Talus,
 *    *ELASTIC under NLGEOM in CalculiX, 10 increments in each: the tip
 *    deflection w and shortening v;
 *  - the six lowest eigenfrequencies with the consistent mass (ARPACK in
 *    both codes);
 *  - Newmark (1/4, 1/2; CalculiX *DYNAMIC, ALPHA = 0) with NLGEOM, 40 steps
 *    of T1/200, the S1 tip load x 10 ramped from zero over the first 10
 *    (from a ramp both start at rest with zero acceleration; a sudden load
 *    would compare the codes' start-up conventions, which differ): the
 *    tip deflection at the end.
 *
 * CalculiX prints displacements with 7 significant digits: the rounding,
 * at most 5e-7 relative, is within the tolerance.  Eigenvalues are read at
 * full precision.  Skips (77) when ccx cannot be run or installed. */
#include <math.h>
#include <stdio.h>

#include "peers/tl_peer_calculix.h"
#include "tl_linear_static.h"
#include "tl_modal.h"
#include "tl_stepper.h"
#include "tl_test.h"

enum { N_MODES = 6 };
static const double tolerance = 1e-6;

static void compare(const char *what, double talus, double ccx)
{
  const double rel = fabs(talus - ccx) / fabs(ccx);
  printf("  %-22s Talus %.10e  CalculiX %.10e  relative difference %.2e\n", what, talus, ccx, rel);
  TL_TEST_ASSERT(rel <= tolerance, "%s: Talus %.12g, CalculiX %.12g, relative difference %.3g > %g", what, talus,
                 ccx, rel, tolerance);
}

static TlCantileverParams beam_params(double load_parameter)
{
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.nu = 0.3;
  p.material = "saint_venant_kirchhoff";
  if (load_parameter > 0.0) p.load = load_parameter * p.E * (p.b * p.h * p.h * p.h / 12.0) / (p.L * p.L);
  return p;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TlStatus have = tl_ccx_ensure();
  if (have != TL_OK) {
    printf("SKIP: CalculiX cannot be run here: %s\n", tl_error_message());
    return 77;
  }
  const char *dir = "ccx";
  double seconds = 0.0, tip_t[3], tip_c[3], t_end = 0.0;

  /* Linear static. */
  TlCantileverParams p = beam_params(0.0);
  TlCantilever *beam = NULL;
  TL_TEST_STATUS(tl_cantilever_create(&p, &beam), TL_OK);
  if (!beam) return tl_test_report();
  TlMechSystem *sys = tl_solid_system(beam->solid);
  double *u = calloc((size_t)sys->ndof, sizeof *u);
  TL_TEST_STATUS(tl_linear_static_solve(sys, NULL, 0.0, u, NULL), TL_OK);
  tl_cantilever_tip(beam, u, tip_t);
  TL_TEST_STATUS(tl_ccx_write_model(dir, beam), TL_OK);
  TL_TEST_STATUS(tl_ccx_run(dir, "cantilever_linear", &seconds), TL_OK);
  TL_TEST_STATUS(tl_ccx_read_tip(dir, "cantilever_linear", beam, tip_c, &t_end), TL_OK);
  printf("linear static, P = %g N, %lld dofs:\n", p.load, (long long)sys->ndof);
  compare("tip deflection w (m)", -tip_t[2], -tip_c[2]);

  /* Modal, consistent mass (the same beam). */
  int modal = tl_modal_available();
  if (modal) {
    TlModalOptions mo;
    tl_modal_options_default(&mo);
    mo.n_modes = N_MODES;
    double w2_t[N_MODES] = {0}, w2_c[N_MODES] = {0};
    TL_TEST_STATUS(tl_modal_solve(sys, &mo, w2_t, NULL, NULL), TL_OK);
    char line[32];
    snprintf(line, sizeof line, "%d", N_MODES);
    TL_TEST_STATUS(tl_ccx_write_line(dir, "modes.inp", line), TL_OK);
    TL_TEST_STATUS(tl_ccx_run(dir, "cantilever_modal", &seconds), TL_OK);
    TL_TEST_STATUS(tl_ccx_read_eigenvalues(dir, "cantilever_modal", N_MODES, w2_c), TL_OK);
    printf("modal, consistent mass:\n");
    for (int k = 0; k < N_MODES; ++k) {
      char what[64];
      snprintf(what, sizeof what, "omega_%d (rad/s)", k + 1);
      compare(what, sqrt(w2_t[k]), sqrt(w2_c[k]));
    }
  }
  free(u);
  tl_cantilever_destroy(&beam);

  /* NLGEOM, dead load P L^2 / (E I) = 2 in 10 increments. */
  const long increments = 10;
  p = beam_params(2.0);
  TL_TEST_STATUS(tl_cantilever_create(&p, &beam), TL_OK);
  if (!beam) return tl_test_report();
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  so.ramp_time = 1.0;
  so.rtol = 1e-12;
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("quasi_static", tl_solid_system(beam->solid), &so, &st), TL_OK);
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
  for (long i = 0; i < increments; ++i) TL_TEST_STATUS(tl_stepper_step(st, 1.0 / (double)increments), TL_OK);
  tl_cantilever_tip(beam, st->u, tip_t);
  char line[64];
  snprintf(line, sizeof line, "%.17g, 1.0", 1.0 / (double)increments);
  TL_TEST_STATUS(tl_ccx_write_model(dir, beam), TL_OK);
  TL_TEST_STATUS(tl_ccx_write_line(dir, "increment.inp", line), TL_OK);
  TL_TEST_STATUS(tl_ccx_run(dir, "cantilever_nlgeom", &seconds), TL_OK);
  TL_TEST_STATUS(tl_ccx_read_tip(dir, "cantilever_nlgeom", beam, tip_c, &t_end), TL_OK);
  TL_TEST_ASSERT(fabs(t_end - 1.0) <= 1e-12, "CalculiX's last tip block is at step time %g, not 1", t_end);
  printf("NLGEOM, Saint Venant-Kirchhoff, dead load P = %.6g N (P L^2/(E I) = 2):\n", p.load);
  compare("tip deflection w (m)", -tip_t[2], -tip_c[2]);
  compare("tip shortening v (m)", -tip_t[1], -tip_c[1]);
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&beam);

  /* Newmark, NLGEOM, ramped load. */
  p = beam_params(0.0);
  p.load *= 10.0;
  const long steps = 40, ramp_steps = 10;
  const double dt = 2.0 * M_PI / tl_cantilever_omega1(&p) / 200.0, t_ramp = (double)ramp_steps * dt;
  TL_TEST_STATUS(tl_cantilever_create(&p, &beam), TL_OK);
  if (!beam) return tl_test_report();
  tl_stepper_options_default(&so);
  so.rtol = 1e-12;
  beam->load_scale = tl_ccx_amplitude(0.0, t_ramp);
  TL_TEST_STATUS(tl_stepper_create("newmark", tl_solid_system(beam->solid), &so, &st), TL_OK);
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
  for (long i = 0; i < steps; ++i) {
    beam->load_scale = tl_ccx_amplitude((double)(i + 1) * dt, t_ramp);
    TL_TEST_STATUS(tl_stepper_step(st, dt), TL_OK);
  }
  tl_cantilever_tip(beam, st->u, tip_t);
  snprintf(line, sizeof line, "%.17g, %.17g", dt, (double)steps * dt);
  TL_TEST_STATUS(tl_ccx_write_model(dir, beam), TL_OK);
  TL_TEST_STATUS(tl_ccx_write_line(dir, "increment.inp", line), TL_OK);
  TL_TEST_STATUS(tl_ccx_write_amplitude(dir, t_ramp), TL_OK);
  TL_TEST_STATUS(tl_ccx_run(dir, "cantilever_dynamic", &seconds), TL_OK);
  TL_TEST_STATUS(tl_ccx_read_tip(dir, "cantilever_dynamic", beam, tip_c, &t_end), TL_OK);
  TL_TEST_ASSERT(fabs(t_end - (double)steps * dt) <= 1e-6 * (double)steps * dt,
                 "CalculiX's last tip block is at t = %g s, not %g s", t_end, (double)steps * dt);
  printf("Newmark, NLGEOM, Saint Venant-Kirchhoff, P = %g N ramped over %ld of %ld steps of %.6g s:\n", p.load,
         ramp_steps, steps, dt);
  compare("tip deflection w (m)", -tip_t[2], -tip_c[2]);
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&beam);

  int failed = tl_test_report();
  if (failed == 0 && !modal) {
    printf("SKIP: linear and NLGEOM agree; this build has no ARPACK, the frequencies were not compared\n");
    return 77;
  }
  return failed;
}
