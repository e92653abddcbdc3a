/* The steppers on the finite-strain solid: the S1 cantilever under a small
 * tip load converges to the Timoshenko deflection under refinement (Hex8)
 * and Hex27 on the S1 mesh is close to it; the elastica reference is
 * checked against Mattiasson's published values; Newmark free vibration
 * conserves energy; the explicit critical step holds on the beam.
 *
 * The unit run (no argument) takes a 20-cell beam and 600 explicit steps
 * (~1 s); `test_fem_stepper_cantilever long` (ctest label long,
 * SelfTests/fem_steppers) runs the S1 meshes with the same assertions. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_cantilever.h"
#include "tl_stepper.h"
#include "tl_test.h"

static TlStatus small_error(const TlElementType *type, size_t nx, size_t ny, double *err)
{
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.type = type;
  p.nx = p.nz = nx;
  p.ny = ny;
  TlCantilever *c = NULL;
  TlStepper *st = NULL;
  TL_CHECK(tl_cantilever_create(&p, &c));
  TL_CHECK(tl_stepper_create("quasi_static", tl_solid_system(c->solid), NULL, &st));
  TL_CHECK(tl_stepper_set_state(st, 0.0, NULL, NULL));
  TL_CHECK(tl_stepper_step(st, 1.0));
  double tip[3];
  tl_cantilever_tip(c, st->u, tip);
  *err = (-tip[2] - tl_cantilever_timoshenko(&p)) / tl_cantilever_timoshenko(&p);
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&c);
  return TL_OK;
}

/* Mesh sizes and step counts: the unit run takes a shorter beam
 * discretisation of the same S1 cantilever; `long` (registered under the
 * label long) runs the S1 meshes. */
typedef struct {
  size_t ny;          /* cells along the beam (S1: 30) */
  int newmark_steps;  /* per period (S1 run: 100) */
  int explicit_steps; /* central-difference steps (S1 run: 2000) */
} Sizes;

int main(int argc, char **argv)
{
  int full = argc > 1 && strcmp(argv[1], "long") == 0;
  const Sizes sz = full ? (Sizes){30, 100, 2000} : (Sizes){20, 100, 600};
  double t_start = omp_get_wtime(), t_mark = t_start;
  /* One thread: CI machines are shared and this test times the solvers'
   * logic, not the parallel assembly (the solid's own tests cover that). */
  omp_set_num_threads(1);
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  /* Elastica against Mattiasson (1981): k = 1: w/L = 0.30172, shortening
   * 0.05643; k = 3: 0.60325, 0.25442. */
  double w = 0, v = 0;
  TL_TEST_STATUS(tl_cantilever_elastica(1.0, &w, &v), TL_OK);
  TL_TEST_CLOSE(w, 0.30172, 2e-5);
  TL_TEST_CLOSE(v, 0.05643, 2e-5);
  TL_TEST_STATUS(tl_cantilever_elastica(3.0, &w, &v), TL_OK);
  TL_TEST_CLOSE(w, 0.60325, 2e-5);
  TL_TEST_CLOSE(v, 0.25442, 2e-5);

  /* Small load: Hex8 S1 mesh, refined twice over, and Hex27. */
  double e8 = 1, e8r = 1, e27 = 1;
  TL_TEST_STATUS(small_error(&tl_element_hex8, 2, sz.ny, &e8), TL_OK);
  TL_TEST_STATUS(small_error(&tl_element_hex8, 4, 2 * sz.ny, &e8r), TL_OK);
  TL_TEST_STATUS(small_error(&tl_element_hex27, 2, sz.ny, &e27), TL_OK);
  printf("tip deflection error vs Timoshenko: hex8 2x2x%zu %+.3f %%, hex8 4x4x%zu %+.3f %%, "
         "hex27 2x2x%zu %+.3f %% (%.2f s)\n", sz.ny, 100 * e8, 2 * sz.ny, 100 * e8r, sz.ny, 100 * e27,
         omp_get_wtime() - t_mark);
  t_mark = omp_get_wtime();
  TL_TEST_ASSERT(fabs(e8r) < fabs(e8) / 3.0, "hex8 refinement: %g -> %g", e8, e8r);
  TL_TEST_ASSERT(fabs(e27) < 0.005, "hex27 S1 mesh error %g", e27);

  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.ny = sz.ny;
  /* Newmark (1/4, 1/2) free vibration from a static deflection under a
   * tenth of the S1 load: the energy drift over one first-mode period.
   * The rule conserves energy exactly only for linear systems (the chain
   * test holds it to 1e-10); here the finite-strain terms give an O(dt^2)
   * error (~2e-8 at dt = T/100), and the solid's strain energy carries an
   * absolute round-off of ~2e-8 J (its value at u = 1e-9 is -1.9e-8 J),
   * ~1e-8 of this motion's 2 J. */
  {
    p.load = 164.4;
    TlCantilever *c = NULL;
    TlStepper *qs = NULL, *nm = NULL;
    TL_TEST_STATUS(tl_cantilever_create(&p, &c), TL_OK);
    TlMechSystem *sys = tl_solid_system(c->solid);
    TL_TEST_STATUS(tl_stepper_create("quasi_static", sys, NULL, &qs), TL_OK);
    TL_TEST_STATUS(tl_stepper_set_state(qs, 0.0, NULL, NULL), TL_OK);
    TL_TEST_STATUS(tl_stepper_step(qs, 1.0), TL_OK);
    c->load_scale = 0.0;
    TlStepperOptions o;
    tl_stepper_options_default(&o);
    o.rtol = 1e-13;
    TL_TEST_STATUS(tl_stepper_create("newmark", sys, &o, &nm), TL_OK);
    TL_TEST_STATUS(tl_stepper_set_state(nm, 0.0, qs->u, NULL), TL_OK);
    TlEnergies e0, e;
    TL_TEST_STATUS(tl_stepper_energies(nm, &e0), TL_OK);
    double T1 = 2.0 * M_PI / tl_cantilever_omega1(&p), drift = 0, wmin = 0;
    for (int k = 0; k < sz.newmark_steps; ++k) {
      TL_TEST_STATUS(tl_stepper_step(nm, T1 / sz.newmark_steps), TL_OK);
      TL_TEST_STATUS(tl_stepper_energies(nm, &e), TL_OK);
      drift = fmax(drift, fabs(e.total - e0.total) / e0.total);
      double tip[3];
      tl_cantilever_tip(c, nm->u, tip);
      wmin = fmin(wmin, tip[2]);
    }
    double tip0[3];
    tl_cantilever_tip(c, qs->u, tip0);
    printf("Newmark free vibration (%zu cells, T/%d): energy drift %.3e over one period (E = %.4g J, %.2f s)\n", sz.ny,
           sz.newmark_steps, drift, e0.total, omp_get_wtime() - t_mark);
    t_mark = omp_get_wtime();
    TL_TEST_ASSERT(drift < 1e-7, "energy drift %g per period", drift);
    p.load = 1644.0;
    /* It did vibrate: the tip swung to the other side. */
    TL_TEST_ASSERT(wmin < 0.5 * tip0[2] && e0.total > 0, "tip from %g reached %g", tip0[2], wmin);
    tl_stepper_destroy(&qs);
    tl_stepper_destroy(&nm);
    tl_cantilever_destroy(&c);
  }

  /* Central difference on the beam: stable just below the estimated
   * critical step, refused and (forced) blowing up just above it. */
  {
    TlCantilever *c = NULL;
    TlStepper *st = NULL;
    TL_TEST_STATUS(tl_cantilever_create(&p, &c), TL_OK);
    c->load_scale = 0.0;
    TlMechSystem *sys = tl_solid_system(c->solid);
    TlStepperOptions o;
    tl_stepper_options_default(&o);
    o.allow_unstable = 1;
    TL_TEST_STATUS(tl_stepper_create("central_difference", sys, &o, &st), TL_OK);
    double u0[4096];
    TL_TEST_ASSERT(st->n <= 4096, "beam dofs %lld", (long long)st->n);
    for (TlSparseIndex i = 0; i < st->n; ++i) u0[i] = 1e-6 * sin(1.3 * (double)i) * cos(0.7 * (double)(i * i));
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, u0, NULL), TL_OK);
    double dtc = st->dt_crit;
    TlStatus s = TL_OK;
    double umax = 0;
    for (int k = 0; k < sz.explicit_steps && s == TL_OK; ++k) {
      s = tl_stepper_step(st, 0.98 * dtc);
      for (TlSparseIndex i = 0; i < st->n; ++i) umax = fmax(umax, fabs(st->u[i]));
    }
    TL_TEST_ASSERT(s == TL_OK && umax < 1e-4, "0.98 dt_crit: status %d max |u| %g", (int)s, umax);
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, u0, NULL), TL_OK);
    s = TL_OK;
    int k = 0;
    for (; k < sz.explicit_steps && s == TL_OK; ++k) s = tl_stepper_step(st, 1.02 * dtc);
    TL_TEST_ASSERT(s == TL_ERR_UNSTABLE, "1.02 dt_crit: status %d after %d steps", (int)s, k);
    printf("central difference on the beam: dt_crit %.6e s (dX/c = %.6e s); stable over %d steps at 0.98 "
           "dt_crit, blow-up after %d steps at 1.02 dt_crit (%.2f s)\n", dtc, 0.4 / sqrt(p.E / p.rho),
           sz.explicit_steps, k, omp_get_wtime() - t_mark);
    tl_stepper_destroy(&st);
    o.allow_unstable = 0;
    TL_TEST_STATUS(tl_stepper_create("central_difference", sys, &o, &st), TL_OK);
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, u0, NULL), TL_OK);
    TL_TEST_STATUS(tl_stepper_step(st, 1.02 * dtc), TL_ERR_UNSTABLE);
    TL_TEST_ASSERT(strstr(tl_error_message(), "exceeds the critical step") != NULL, "%s",
                   tl_error_message());
    tl_stepper_destroy(&st);
    tl_cantilever_destroy(&c);
  }
  printf("%s run: %.2f s\n", full ? "long" : "unit", omp_get_wtime() - t_start);
  return tl_test_report();
}
