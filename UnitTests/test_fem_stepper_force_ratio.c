/* The quasi-static stepper's force-ratio test (seeds/004 §2.5.3):
 *  - |F| and |R| it reports equal, at the accepted state, the 2-norms of the
 *    free-dof residual and of the solid's reactions (tl_solid_reactions) on
 *    a displacement-controlled block, and their ratio is below ratio_tol;
 *  - a tighter tolerance takes more iterations, the loose tolerance after
 *    tl_stepper_set_post_peak fewer;
 *  - the TAYLOR predictor starts from the last increment continued and
 *    reaches the same state within the tolerance;
 *  - the default test is still the residual one, and bad tolerances are
 *    refused by name. */
#include <math.h>
#include <string.h>

#include "talus.h"
#include "tl_material.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_test.h"

static void prescribe_zero(double t, const double X[3], int c, void *ctx, double out[3])
{
  (void)t, (void)X, (void)c, (void)ctx;
  out[0] = out[1] = out[2] = 0.0;
}

/* The top pulled up and sheared: u = (0.02 t, 0.05 t). */
static void prescribe_top(double t, const double X[3], int c, void *ctx, double out[3])
{
  (void)X, (void)ctx;
  const double v = c == 0 ? 0.02 : 0.05;
  out[0] = v * t, out[1] = v, out[2] = 0.0;
}

typedef struct {
  TlMesh *mesh;
  TlMaterial *mat;
  TlSolid *solid;
} Block;

static int make(Block *b)
{
  memset(b, 0, sizeof *b);
  size_t n[2] = {2, 4};
  double lo[2] = {0, 0}, hi[2] = {0.5, 1.0};
  TL_TEST_STATUS(tl_mesh_create_rectangle(&tl_element_quad8, n, lo, hi, &b->mesh), TL_OK);
  TL_TEST_STATUS(tl_material_create_hooke(1e7, 0.3, 1000.0, &b->mat), TL_OK);
  if (!b->mesh || !b->mat) return 0;
  TL_TEST_STATUS(tl_solid_create(b->mesh, &b->solid), TL_OK);
  if (!b->solid) return 0;
  TL_TEST_STATUS(tl_solid_set_material(b->solid, NULL, b->mat), TL_OK);
  TL_TEST_STATUS(tl_solid_prescribe(b->solid, "ymin", 0, prescribe_zero, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_prescribe(b->solid, "ymin", 1, prescribe_zero, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_prescribe(b->solid, "ymax", 0, prescribe_top, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_prescribe(b->solid, "ymax", 1, prescribe_top, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(b->solid), TL_OK);
  return 1;
}

static void destroy(Block *b)
{
  tl_solid_destroy(&b->solid);
  tl_material_destroy(&b->mat);
  tl_mesh_destroy(&b->mesh);
}

static void options(TlStepperOptions *o, double tol)
{
  tl_stepper_options_default(o);
  o->convergence = TL_CONVERGENCE_FORCE_RATIO;
  o->ratio_tol = tol;
  o->ratio_tol_post = fmax(tol, 1e-2);
}

/* Runs `steps` steps to t = 1; returns the Newton iterations. */
static long run(Block *b, const TlStepperOptions *o, long steps, int post_peak, double *u_out)
{
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("quasi_static", tl_solid_system(b->solid), o, &st), TL_OK);
  if (!st) return -1;
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
  if (post_peak) tl_stepper_set_post_peak(st, 1);
  long it = 0;
  for (long k = 0; k < steps; ++k) {
    TL_TEST_STATUS(tl_stepper_step(st, 1.0 / (double)steps), TL_OK);
    it += st->last_step.iterations;
    const double tol = post_peak ? o->ratio_tol_post : o->ratio_tol;
    TL_TEST_ASSERT(st->last_step.ratio <= tol, "step %ld: |F|/|R| = %g above %g", k, st->last_step.ratio, tol);
    TL_TEST_ASSERT(st->last_step.increments == 1 && st->last_step.cuts == 0, "step %ld: %ld increments %ld cuts", k,
                   st->last_step.increments, st->last_step.cuts);
  }
  /* |F| and |R| against the solid's own reactions and residual. */
  TlSolid *s = b->solid;
  TlMechSystem *sys = tl_solid_system(s);
  const size_t nn = b->mesh->n_nodes;
  double *R = calloc(2 * nn, sizeof *R), *fi = calloc((size_t)sys->ndof, sizeof *fi),
         *fe = calloc((size_t)sys->ndof, sizeof *fe);
  TL_TEST_STATUS(tl_solid_reactions(s, st->t, st->u, NULL, R), TL_OK);
  TL_TEST_STATUS(sys->ops->internal_force(sys, st->t, st->u, NULL, fi), TL_OK);
  TL_TEST_STATUS(sys->ops->external_force(sys, st->t, st->u, fe), TL_OK);
  double R2 = 0.0, F2 = 0.0;
  for (size_t i = 0; i < 2 * nn; ++i) R2 += R[i] * R[i];
  unsigned char *dir = calloc((size_t)sys->ndof, 1);
  for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) dir[sys->dirichlet_dofs[k]] = 1;
  for (TlSparseIndex i = 0; i < sys->ndof; ++i)
    if (!dir[i]) F2 += (fi[i] - fe[i]) * (fi[i] - fe[i]);
  TL_TEST_ASSERT(R2 > 0.0, "no reactions: the test is vacuous");
  TL_TEST_REL(st->last_step.reaction, sqrt(R2), 1e-12);
  TL_TEST_CLOSE(st->last_step.force / sqrt(R2), sqrt(F2) / sqrt(R2), 1e-12);
  if (u_out) memcpy(u_out, st->u, (size_t)sys->ndof * sizeof *u_out);
  free(R), free(fi), free(fe), free(dir);
  tl_stepper_destroy(&st);
  return it;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  Block b;
  if (!make(&b)) {
    destroy(&b);
    return tl_test_report();
  }
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  TL_TEST_ASSERT(o.convergence == TL_CONVERGENCE_RESIDUAL, "default convergence test %d", o.convergence);
  const size_t n = (size_t)tl_solid_system(b.solid)->ndof;
  double *u1 = calloc(n, sizeof *u1), *u2 = calloc(n, sizeof *u2);
  options(&o, 1e-3);
  const long loose = run(&b, &o, 4, 0, u1);
  options(&o, 1e-10);
  const long tight = run(&b, &o, 4, 0, u2);
  TL_TEST_ASSERT(tight > loose, "tolerance 1e-10: %ld iterations, 1e-3: %ld", tight, loose);
  options(&o, 1e-10);
  o.ratio_tol_post = 1e-2;
  const long post = run(&b, &o, 4, 1, NULL);
  TL_TEST_ASSERT(post < tight, "after the peak (1e-2) %ld iterations, before (1e-10) %ld", post, tight);
  /* The predictor: the same state to the tolerance, in fewer iterations. */
  options(&o, 1e-10);
  o.predictor = TL_PREDICTOR_TAYLOR;
  double *u3 = calloc(n, sizeof *u3);
  const long taylor = run(&b, &o, 4, 0, u3);
  double d = 0.0, m = 0.0;
  for (size_t i = 0; i < n; ++i) d = fmax(d, fabs(u3[i] - u2[i])), m = fmax(m, fabs(u2[i]));
  TL_TEST_ASSERT(d <= 1e-8 * m, "TAYLOR predictor ends %g off (scale %g)", d, m);
  TL_TEST_ASSERT(taylor < tight, "TAYLOR predictor %ld iterations, the last equilibrium %ld", taylor, tight);
  /* Bad tolerances by name. */
  TlStepper *st = NULL;
  options(&o, 0.0);
  TL_TEST_STATUS(tl_stepper_create("quasi_static", tl_solid_system(b.solid), &o, &st), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "force-ratio tolerances 0") != NULL, "message: %s", tl_error_message());
  options(&o, 1e-3);
  o.ratio_diverge = 0.5;
  TL_TEST_STATUS(tl_stepper_create("quasi_static", tl_solid_system(b.solid), &o, &st), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "ratio_diverge = 0.5") != NULL, "message: %s", tl_error_message());
  tl_stepper_destroy(&st);
  free(u1), free(u2), free(u3);
  destroy(&b);
  return tl_test_report();
}
