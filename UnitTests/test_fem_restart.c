/* Checkpoint and restart of FEM runs: N steps in one go against N/2 steps,
 * a checkpoint, fresh objects built the same way, a load and N/2 more
 * steps.  The states must agree bit for bit (memcmp) for Newmark with full
 * Newton, with kept factors (modified Newton), with the lumped mass, with a
 * path-dependent law (its committed state travels with the solid), with a
 * prescribed end motion, and for central difference.  The scene: a clamped
 * hex8 beam with an initial velocity and a time-dependent tip traction (or
 * its free end driven sideways). */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_checkpoint.h"
#include "tl_mesh.h"
#include "tl_registry.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_test.h"

/* A Saint Venant-Kirchhoff law that stiffens with the largest |tr E| of its
 * committed path: S = (1 + k h) (lambda tr E 1 + 2 mu E), h_new = max(h, |tr E|).
 * The stress reads the committed h, so a restart that lost it would differ. */
typedef struct {
  TlMaterial base;
  double lambda, mu, k;
} HardeningLaw;

static TlStatus law_setup(TlMaterial *m)
{
  m->state_size = 1;
  return TL_OK;
}

static TlStatus law_evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma,
                             const double *so, double *sn, TlMat3 *S, double *D, double *W)
{
  (void)F;
  const HardeningLaw *l = (const HardeningLaw *)m;
  for (size_t p = 0; p < npts; ++p) {
    double tr = tl_m3_trace(gamma[p]), c = 1.0 + l->k * so[p];
    S[p] = tl_m3_scale(tl_m3_add(tl_m3_scale(tl_m3_identity(), l->lambda * tr), tl_m3_scale(gamma[p], 2 * l->mu)), c);
    sn[p] = fmax(so[p], fabs(tr));
    if (W) W[p] = c * (0.5 * l->lambda * tr * tr + l->mu * tl_m3_ddot(gamma[p], gamma[p]));
    if (D) {
      memset(D + 36 * p, 0, 36 * sizeof(double));
      for (int I = 0; I < 3; ++I) {
        for (int J = 0; J < 3; ++J) D[36 * p + 6 * I + J] = c * l->lambda;
        D[36 * p + 7 * I] += c * 2 * l->mu;
        D[36 * p + 7 * (I + 3)] = c * l->mu;
      }
    }
  }
  return TL_OK;
}

static int law_symmetric(const TlMaterial *m)
{
  (void)m;
  return 1;
}

static const TlMaterialParam law_params[] = {
    {"lambda", 0.0, 0, 1e12, "Pa", "first Lame constant", offsetof(HardeningLaw, lambda)},
    {"mu", 5e7, 1, 1e12, "Pa", "shear modulus", offsetof(HardeningLaw, mu)},
    {"k", 2e3, 0, 1e9, "-", "stiffening per unit of the largest |tr E|", offsetof(HardeningLaw, k)},
};

static const TlMaterialOps law_ops = {
    .header = {"material", "test_restart_hardening", "SVK stiffening with its path (restart test)"},
    .size = sizeof(HardeningLaw), .n_params = 3, .params = law_params, .setup = law_setup,
    .evaluate = law_evaluate, .symmetric_tangent = law_symmetric};

typedef struct {
  TlMesh *mesh;
  TlMaterial *mat;
  TlSolid *solid;
  TlStepper *st;
} Scene;

typedef struct {
  const char *stepper;
  int lumped, keep_factors, hardening;
  int prescribed; /* the free end driven sideways instead of loaded */
  int newton;     /* TL_NEWTON_KINSOL or TL_NEWTON_SUNNONLINSOL */
} Case;

static double amplitude(double t, void *ctx)
{
  (void)ctx;
  return sin(2.0 * t) + 0.5 * t;
}

static void drive(double t, const double X[3], int component, void *ctx, double out[3])
{
  (void)X, (void)component, (void)ctx;
  out[0] = 0.05 * sin(3.0 * t);
  out[1] = 0.15 * cos(3.0 * t);
  out[2] = -0.45 * sin(3.0 * t);
}

static TlStatus scene_create(const Case *c, Scene *sc)
{
  memset(sc, 0, sizeof *sc);
  size_t n[3] = {2, 6, 2};
  double lo[3] = {-0.4, 0.0, -0.4}, hi[3] = {0.4, 6.0, 0.4};
  TL_CHECK(tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &sc->mesh));
  if (c->hardening) {
    TL_CHECK(tl_material_create("test_restart_hardening", &sc->mat));
    TL_CHECK(tl_material_set(sc->mat, "density", 1309.0));
    if (c->hardening == 2) TL_CHECK(tl_material_set(sc->mat, "k", 0.0));
  } else {
    TL_CHECK(tl_material_create_hooke(1e8, 0.25, 1309.0, &sc->mat));
  }
  TL_CHECK(tl_solid_create(sc->mesh, &sc->solid));
  TL_CHECK(tl_solid_set_material(sc->solid, NULL, sc->mat));
  TL_CHECK(tl_solid_fix(sc->solid, "ymin", 7));
  if (c->prescribed) TL_CHECK(tl_solid_prescribe(sc->solid, "ymax", 0, drive, NULL));
  else TL_CHECK(tl_solid_add_traction(sc->solid, "ymax", tl_v3(2e4, 0.0, -5e4), amplitude, NULL));
  TL_CHECK(tl_solid_setup(sc->solid));
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  o.lumped = c->lumped;
  o.keep_factors = c->keep_factors;
  o.reuse = c->keep_factors ? 4 : 1;
  o.nonlinear_solver = c->newton;
  /* Factors kept over the whole run: the rate estimate then carries over
   * the restart. */
  if (c->newton == TL_NEWTON_SUNNONLINSOL) o.reuse = 100000;
  TL_CHECK(tl_stepper_create(c->stepper, tl_solid_system(sc->solid), &o, &sc->st));
  return TL_OK;
}

static void scene_destroy(Scene *sc)
{
  tl_stepper_destroy(&sc->st);
  tl_solid_destroy(&sc->solid);
  tl_material_destroy(&sc->mat);
  tl_mesh_destroy(&sc->mesh);
}

static TlStatus initial_state(Scene *sc)
{
  size_t n = (size_t)sc->st->n;
  double *v = NULL;
  TL_CHECK(tl_calloc(&v, n, sizeof *v));
  for (size_t a = 0; a < sc->mesh->n_nodes; ++a) {
    double y = sc->mesh->x[3 * a + 1] / 6.0;
    TlSparseIndex d = tl_solid_dof(sc->solid, a, 0);
    if (d >= 0) v[d] = 0.3 * y * y;
  }
  TlStatus s = tl_stepper_set_state(sc->st, 0.0, NULL, v);
  tl_free(&v);
  return s;
}

static TlStatus steps(Scene *sc, int count, double dt)
{
  for (int k = 0; k < count; ++k) TL_CHECK(tl_stepper_step(sc->st, dt));
  return TL_OK;
}

/* Final state of a run: u, v, a, f_ext and the external work. */
typedef struct {
  double *u, *v, *a, *f;
  double W, t;
  long steps;
} Final;

static void final_take(const TlStepper *st, Final *f)
{
  size_t bytes = (size_t)st->n * sizeof(double);
  f->u = malloc(bytes), f->v = malloc(bytes), f->a = malloc(bytes), f->f = malloc(bytes);
  memcpy(f->u, st->u, bytes), memcpy(f->v, st->v, bytes), memcpy(f->a, st->a, bytes);
  memcpy(f->f, st->f_ext, bytes);
  f->W = st->W_ext;
  f->t = st->t;
  f->steps = st->stats.steps;
}

static void final_free(Final *f) { free(f->u), free(f->v), free(f->a), free(f->f); }

static double max_diff(const double *x, const double *y, size_t n)
{
  double d = 0.0;
  for (size_t i = 0; i < n; ++i) d = fmax(d, fabs(x[i] - y[i]));
  return d;
}

static void restart_case(const Case *c, int N, const char *label, Final *out_ref)
{
  const char *path = "restart.h5";
  Scene sc;
  double dt = 0.02;
  /* Reference: N steps in one go. */
  TL_TEST_STATUS(scene_create(c, &sc), TL_OK);
  if (!sc.st) return;
  TL_TEST_STATUS(initial_state(&sc), TL_OK);
  if (!strcmp(c->stepper, "central_difference")) dt = 0.5 * sc.st->dt_crit;
  TL_TEST_STATUS(steps(&sc, N, dt), TL_OK);
  Final ref;
  final_take(sc.st, &ref);
  size_t n = (size_t)sc.st->n;
  scene_destroy(&sc);
  /* First half, checkpoint, destroy everything. */
  TL_TEST_STATUS(scene_create(c, &sc), TL_OK);
  TL_TEST_STATUS(initial_state(&sc), TL_OK);
  TL_TEST_STATUS(steps(&sc, N / 2, dt), TL_OK);
  TlCheckpoint *cp = NULL;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "fem", &tl_stepper_checkpoint_ops, sc.st), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, path, sc.st->t, sc.st->stats.steps), TL_OK);
  tl_checkpoint_destroy(&cp);
  scene_destroy(&sc);
  /* Fresh objects, load, second half. */
  TL_TEST_STATUS(scene_create(c, &sc), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "fem", &tl_stepper_checkpoint_ops, sc.st), TL_OK);
  double t = -1.0;
  int64_t step = -1;
  TL_TEST_STATUS(tl_checkpoint_load(cp, path, &t, &step), TL_OK);
  tl_checkpoint_destroy(&cp);
  TL_TEST_ASSERT(step == N / 2 && t == sc.st->t, "%s: checkpoint at step %lld, t = %g", label, (long long)step, t);
  TL_TEST_STATUS(steps(&sc, N - N / 2, dt), TL_OK);
  size_t bytes = n * sizeof(double);
  int same = !memcmp(ref.u, sc.st->u, bytes) && !memcmp(ref.v, sc.st->v, bytes) &&
             !memcmp(ref.a, sc.st->a, bytes) && !memcmp(ref.f, sc.st->f_ext, bytes) &&
             !memcmp(&ref.W, &sc.st->W_ext, sizeof ref.W) && !memcmp(&ref.t, &sc.st->t, sizeof ref.t);
  double umax = 0.0;
  for (size_t i = 0; i < n; ++i) umax = fmax(umax, fabs(ref.u[i]));
  printf("%-38s %d steps (restart at %d): bit-for-bit %s (max |du| %.1e, |dv| %.1e, |da| %.1e; |u| %.3e m)\n",
         label, N, N / 2, same ? "yes" : "NO", max_diff(ref.u, sc.st->u, n), max_diff(ref.v, sc.st->v, n),
         max_diff(ref.a, sc.st->a, n), umax);
  TL_TEST_ASSERT(same, "%s: restarted run differs from the continuous one", label);
  TL_TEST_ASSERT(umax > 1e-3, "%s: the beam barely moved (%g m)", label, umax);
  TL_TEST_ASSERT(sc.st->stats.steps == ref.steps, "%s: %ld steps counted, %ld expected", label,
                 sc.st->stats.steps, ref.steps);
  scene_destroy(&sc);
  if (out_ref) *out_ref = ref;
  else final_free(&ref);
}

/* A checkpoint of one stepper type refuses to load into another, and a
 * system of another size is named. */
static void refusals(void)
{
  Case cd = {"central_difference", 0, 0, 0, 0, 0}, nm = {"newmark", 0, 0, 0, 0, 0};
  Scene a, b;
  TL_TEST_STATUS(scene_create(&cd, &a), TL_OK);
  TL_TEST_STATUS(scene_create(&nm, &b), TL_OK);
  if (!a.st || !b.st) return;
  TL_TEST_STATUS(initial_state(&a), TL_OK);
  TlCheckpoint *cp = NULL;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "fem", &tl_stepper_checkpoint_ops, a.st), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, "cd.h5", 0.0, 0), TL_OK);
  tl_checkpoint_destroy(&cp);
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "fem", &tl_stepper_checkpoint_ops, b.st), TL_OK);
  TL_TEST_ASSERT(tl_checkpoint_load(cp, "cd.h5", NULL, NULL) != TL_OK, "newmark loaded a central-difference state");
  TL_TEST_ASSERT(strstr(tl_error_message(), "central_difference") != NULL, "%s", tl_error_message());
  tl_checkpoint_destroy(&cp);
  scene_destroy(&a);
  scene_destroy(&b);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TL_TEST_STATUS(tl_registry_add(&law_ops.header), TL_OK);
  const Case cases[] = {
      {"newmark", 0, 0, 0, 0, 0}, {"newmark", 0, 1, 0, 0, 0},           {"newmark", 1, 0, 0, 0, 0},
      {"newmark", 0, 0, 1, 0, 0}, {"newmark", 0, 0, 0, 1, 0},           {"central_difference", 0, 0, 0, 0, 0},
      {"central_difference", 0, 0, 0, 1, 0},
      /* The correction test's rate estimate is restored with the factors. */
      {"newmark", 0, 1, 0, 0, TL_NEWTON_SUNNONLINSOL},
  };
  const char *labels[] = {"newmark, consistent mass", "newmark, kept factors (reuse 4)", "newmark, lumped mass",
                          "newmark, path-dependent law", "newmark, prescribed end motion", "central difference",
                          "central difference, prescribed motion", "newmark, kept factors, SUNNonlinSol"};
  const int n_cases = (int)(sizeof cases / sizeof cases[0]);
  Final hard;
  memset(&hard, 0, sizeof hard);
  for (int k = 0; k < n_cases; ++k)
    restart_case(&cases[k], strcmp(cases[k].stepper, "newmark") ? 200 : 20, labels[k], k == 3 ? &hard : NULL);
  /* The law's state matters: the same run with k = 0 ends elsewhere. */
  if (hard.u) {
    Case plain = {"newmark", 0, 0, 2, 0, 0};
    Scene sc;
    TL_TEST_STATUS(scene_create(&plain, &sc), TL_OK);
    if (sc.st) {
      TL_TEST_STATUS(initial_state(&sc), TL_OK);
      TL_TEST_STATUS(steps(&sc, 20, 0.02), TL_OK);
      double d = max_diff(sc.st->u, hard.u, (size_t)sc.st->n), size = 0.0;
      for (TlSparseIndex i = 0; i < sc.st->n; ++i) size = fmax(size, fabs(hard.u[i]));
      printf("path-dependent law: the stiffening moves the end state by %.2e of %.2e m\n", d, size);
      TL_TEST_ASSERT(d > 1e-3 * size, "the law's state changed u by only %g of %g", d, size);
    }
    scene_destroy(&sc);
  }
  final_free(&hard);
  refusals();
  return tl_test_report();
}
