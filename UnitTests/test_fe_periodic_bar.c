/* The FE bar of the bridging-domain gouge (seeds/000 §4.1): a hex8 bar
 * along y, pre-stressed by an eigenstrain, periodic in x and z through the
 * solid's periodic ties (tl_solid_tie.h: slave nodes numbered as their masters), u_y held at the far ends,
 * and its linear fast path (tl_mech_linear.h).
 *  - At rest the pre-stress leaves forces on the lateral faces of the plain
 *    solid; the periodic tie cancels them to round-off (the lateral faces
 *    are inside the periodic body).
 *  - The tied tangent matches finite differences of the tied force (the
 *    pattern of elements sharing a dof across the period).
 *  - A cycle of ties and a tie between differently held nodes are refused.
 *  - The tied lumped mass is the bar's mass.
 *  - The linear system agrees with the solid to second order in u.
 *  - A P pulse (Eq. 15) launched at y = 0 stays uniform over each section
 *    (periodicity) and arrives at a section at t0 + y / c_P with amplitude I;
 *    an S pulse moves u_x only, at c_S; the linear and finite-strain paths
 *    give the same history. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_mech_linear.h"
#include "tl_pulse.h"
#include "tl_solid_tie.h"
#include "tl_stepper.h"
#include "tl_test.h"
#include "tl_timer.h"

static const double E = 0.977e9, NU = 0.255, RHO = 1643.0, EPS0 = 0.0025;
static const double A = 0.035; /* section side (m) */

typedef struct {
  TlMesh *mesh;
  TlMaterial *mat;
  TlSolid *solid;
  TlPulse pulse;
} Bar;

/* ny elements of 0.5 A along y, 2 x 2 in the section; held in y at
 * ymax, the pulse (component pulse_c, or held when < 0) at ymin. */
/* Elements across the section (1: an element tied to itself across the
 * period, its two x faces sharing their dofs). */
static size_t n_section = 2;

static int bar_build(Bar *b, size_t ny, int pulse_c, int tie)
{
  memset(b, 0, sizeof *b);
  size_t n[3] = {n_section, ny, n_section};
  double lo[3] = {0, 0, 0}, hi[3] = {A, 0.5 * A * (double)ny, A};
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &b->mesh), TL_OK);
  TL_TEST_STATUS(tl_material_create("saint_venant_kirchhoff", &b->mat), TL_OK);
  if (!b->mesh || !b->mat) return 0;
  tl_material_set(b->mat, "E", E);
  tl_material_set(b->mat, "nu", NU);
  tl_material_set(b->mat, "density", RHO);
  TL_TEST_STATUS(tl_material_set_eigenstrain(b->mat, (TlMat3){{{EPS0, 0, 0}, {0, EPS0, 0}, {0, 0, EPS0}}}), TL_OK);
  TL_TEST_STATUS(tl_solid_create(b->mesh, &b->solid), TL_OK);
  tl_solid_set_material(b->solid, NULL, b->mat);
  TL_TEST_STATUS(tl_solid_fix(b->solid, "ymax", 2), TL_OK);
  if (pulse_c < 0) TL_TEST_STATUS(tl_solid_fix(b->solid, "ymin", 2), TL_OK);
  else {
    double c = pulse_c == 1 ? sqrt(E * (1 - NU) / ((1 + NU) * (1 - 2 * NU)) / RHO) : sqrt(E / (2 * (1 + NU)) / RHO);
    TL_TEST_STATUS(tl_pulse_init(&b->pulse, TL_PULSE_GAUSSIAN, 1e-5, 10.0 * A, c), TL_OK);
    /* The S pulse moves u_x at ymin; u_y is held there too. */
    if (pulse_c == 0) TL_TEST_STATUS(tl_solid_fix(b->solid, "ymin", 2), TL_OK);
    TL_TEST_STATUS(tl_solid_prescribe(b->solid, "ymin", pulse_c, tl_pulse_prescribed, &b->pulse), TL_OK);
  }
  if (tie) {
    TL_TEST_STATUS(tl_solid_tie(b->solid, "xmin", "xmax", (double[3]){A, 0, 0}, 1e-9), TL_OK);
    TL_TEST_STATUS(tl_solid_tie(b->solid, "zmin", "zmax", (double[3]){0, 0, A}, 1e-9), TL_OK);
  }
  TlStatus s = tl_solid_setup(b->solid);
  TL_TEST_STATUS(s, TL_OK);
  return s == TL_OK;
}

static void bar_free(Bar *b)
{
  tl_solid_destroy(&b->solid);
  tl_material_destroy(&b->mat);
  tl_mesh_destroy(&b->mesh);
}

static double max_abs(const double *x, size_t n)
{
  double m = 0.0;
  for (size_t i = 0; i < n; ++i) m = fmax(m, fabs(x[i]));
  return m;
}

static void rest_test(void)
{
  Bar b, pb;
  if (!bar_build(&b, 8, -1, 1) || !bar_build(&pb, 8, -1, 0)) return;
  TlMechSystem *plain = tl_solid_system(pb.solid), *tied = tl_solid_system(b.solid);
  size_t np = (size_t)plain->ndof, nt = (size_t)tied->ndof;
  size_t nodes = b.mesh->n_nodes;
  /* 3 x 9 x 3 nodes, y held at the ends: the tie leaves 2 x 9 x 2 nodes. */
  TL_TEST_ASSERT(nt == 3 * 2 * 9 * 2 - 2 * 2 * 2, "tied dofs %zu, expected %d", nt, 3 * 2 * 9 * 2 - 8);
  TL_TEST_ASSERT(tl_solid_n_tied(b.solid) == 3 * 3 * 9 - 2 * 2 * 9, "tied nodes %zu", tl_solid_n_tied(b.solid));
  double *u = calloc(np, sizeof *u), *f = calloc(np, sizeof *f), *ft = calloc(nt, sizeof *ft);
  double *m = calloc(nt, sizeof *m);
  plain->ops->internal_force(plain, 0.0, u, NULL, f);
  TL_TEST_STATUS(tied->ops->internal_force(tied, 0.0, u, NULL, ft), TL_OK);
  double sigma0 = 3.0 * E / (3.0 * (1 - 2 * NU)) * EPS0, scale = sigma0 * A * A / 4.0;
  /* The plain solid: the pre-stress pulls on the lateral faces' nodes (x
   * and z components); the tied one: nothing at a free dof. */
  double lateral = 0.0;
  for (size_t k = 0; k < nodes; ++k) {
    TlSparseIndex d = tl_solid_dof(pb.solid, k, 0);
    if (d >= 0) lateral = fmax(lateral, fabs(f[d]));
  }
  printf("rest: plain lateral force %.3e N, tied %.3e N (sigma0 A^2/4 = %.3e N)\n", lateral, max_abs(ft, nt), scale);
  TL_TEST_ASSERT(lateral > 0.2 * scale, "the plain bar shows its lateral pre-stress forces: %g of %g", lateral, scale);
  TL_TEST_ASSERT(max_abs(ft, nt) <= 1e-10 * scale, "tied bar at rest: force %g N against a scale %g N", max_abs(ft, nt),
                 scale);
  TL_TEST_ASSERT(tl_solid_dof(b.solid, 2, 0) == tl_solid_dof(b.solid, 0, 0) && tl_solid_dof(b.solid, 0, 0) >= 0,
                 "node 2 (x = A) shares the dofs of node 0 (x = 0): %lld, %lld", (long long)tl_solid_dof(b.solid, 2, 0),
                 (long long)tl_solid_dof(b.solid, 0, 0));
  /* Mass. */
  tied->ops->lumped_mass(tied, m);
  /* Each tied x dof once: the bar's mass. */
  double mass = 0.0;
  double *seen = calloc(nt, sizeof *seen);
  for (size_t k = 0; k < nodes; ++k) {
    TlSparseIndex r = tl_solid_dof(b.solid, k, 0);
    if (!seen[r]) mass += m[r], seen[r] = 1;
  }
  TL_TEST_REL(mass, RHO * A * A * 4.0 * A, 1e-12);
  /* Tangent against central differences of the tied force. */
  TlSparse *K = NULL;
  TL_TEST_STATUS(tied->ops->create_matrix(tied, 1, &K), TL_OK);
  double *ut = calloc(nt, sizeof *ut), *d = calloc(nt, sizeof *d), *Kd = calloc(nt, sizeof *Kd);
  double *fp = calloc(nt, sizeof *fp), *fm = calloc(nt, sizeof *fm);
  srand(5);
  for (size_t i = 0; i < nt; ++i) {
    ut[i] = 1e-4 * A * (rand() / (double)RAND_MAX - 0.5);
    d[i] = rand() / (double)RAND_MAX - 0.5;
  }
  if (K) {
    TL_TEST_STATUS(tied->ops->internal_tangent(tied, 0.0, ut, NULL, 1.0, 0.0, K), TL_OK);
    tl_sparse_matvec(K, d, Kd);
    double h = 1e-7 * A, err = 0.0;
    for (size_t i = 0; i < nt; ++i) fp[i] = ut[i] + h * d[i];
    tied->ops->internal_force(tied, 0.0, fp, NULL, fm);
    memcpy(fp, fm, nt * sizeof *fp);
    for (size_t i = 0; i < nt; ++i) fm[i] = ut[i] - h * d[i];
    double *g = calloc(nt, sizeof *g);
    tied->ops->internal_force(tied, 0.0, fm, NULL, g);
    for (size_t i = 0; i < nt; ++i) err = fmax(err, fabs((fp[i] - g[i]) / (2 * h) - Kd[i]));
    printf("tied tangent: max error %.3e of %.3e\n", err, max_abs(Kd, nt));
    TL_TEST_ASSERT(err <= 1e-6 * max_abs(Kd, nt), "tied tangent off finite differences by %g of %g", err,
                   max_abs(Kd, nt));
    free(g);
  }
  tl_sparse_destroy(&K);
  /* Linear path: same force to second order in u. */
  TlMechSystem *lin = NULL;
  TL_TEST_STATUS(tl_mech_linear_create(tied, 0.0, NULL, 0, &lin), TL_OK);
  if (lin) {
    double err[2], werr[2];
    for (int level = 0; level < 2; ++level) {
      double s = level ? 0.5 : 1.0, Ws = 0.0, Wl = 0.0;
      for (size_t i = 0; i < nt; ++i) fp[i] = s * ut[i];
      tied->ops->internal_force(tied, 0.0, fp, NULL, fm);
      lin->ops->internal_force(lin, 0.0, fp, NULL, Kd);
      double e = 0.0;
      for (size_t i = 0; i < nt; ++i) e = fmax(e, fabs(fm[i] - Kd[i]));
      err[level] = e;
      TL_TEST_STATUS(tied->ops->strain_energy(tied, fp, &Ws), TL_OK);
      TL_TEST_STATUS(lin->ops->strain_energy(lin, fp, &Wl), TL_OK);
      werr[level] = fabs(Ws - Wl);
    }
    /* Stored energy: the quadratic expansion, off by third order. */
    printf("linear path energy: error %.3e at u, %.3e at u/2 (ratio %.2f, third order: 8)\n", werr[0], werr[1],
           werr[0] / werr[1]);
    TL_TEST_ASSERT(werr[0] / werr[1] > 7.0 && werr[0] / werr[1] < 9.0, "linear path energy error ratio %g (8)",
                   werr[0] / werr[1]);
    printf("linear path: error %.3e at u, %.3e at u/2 (ratio %.2f, second order: 4)\n", err[0], err[1],
           err[0] / err[1]);
    TL_TEST_ASSERT(err[0] / err[1] > 3.5 && err[0] / err[1] < 4.5, "linear path error ratio %g (second order: 4)",
                   err[0] / err[1]);
    TL_TEST_ASSERT(err[0] <= 1e-3 * scale * 1e-4 * 100, "linear path error %g N", err[0]);
    tl_mech_system_destroy(&lin);
  }
  /* A cycle and a mismatched boundary condition are refused at setup. */
  TlSolid *bad = NULL;
  TL_TEST_STATUS(tl_solid_create(b.mesh, &bad), TL_OK);
  tl_solid_set_material(bad, NULL, b.mat);
  TL_TEST_STATUS(tl_solid_tie(bad, "xmin", "xmax", (double[3]){A, 0, 0}, 1e-9), TL_OK);
  TL_TEST_STATUS(tl_solid_tie(bad, "xmax", "xmin", (double[3]){-A, 0, 0}, 1e-9), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(bad), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "cycle") != NULL, "cycle named: %s", tl_error_message());
  tl_solid_destroy(&bad);
  TL_TEST_STATUS(tl_solid_create(b.mesh, &bad), TL_OK);
  tl_solid_set_material(bad, NULL, b.mat);
  TL_TEST_STATUS(tl_solid_fix(bad, "xmin", 7), TL_OK);
  TL_TEST_STATUS(tl_solid_tie(bad, "xmin", "xmax", (double[3]){A, 0, 0}, 1e-9), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(bad), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "share their boundary") != NULL, "mismatch named: %s", tl_error_message());
  tl_solid_destroy(&bad);
  TL_TEST_STATUS(tl_solid_create(b.mesh, &bad), TL_OK);
  TL_TEST_STATUS(tl_solid_tie(bad, "xmin", "xmax", (double[3]){0.9 * A, 0, 0}, 1e-9), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "has no node") != NULL, "unpaired node named: %s", tl_error_message());
  tl_solid_destroy(&bad);
  free(u), free(f), free(ft), free(m), free(seen), free(ut), free(d), free(Kd), free(fp), free(fm);
  bar_free(&b);
  bar_free(&pb);
}

/* Runs a pulse through a tied bar of 80 elements (40 A) with the central
 * difference; records u_c at the section y = 10 A (every node of it) and
 * returns the peak time and amplitude; *spread = the largest difference
 * across the section, *other = the largest other component there. */
static void pulse_run(int component, int linear, double *t_peak, double *u_peak, double *spread, double *other,
                      double *us_per_step, double *c_out, double *t0_out)
{
  Bar b;
  *t_peak = *u_peak = *spread = *other = NAN;
  if (!bar_build(&b, 80, component, 1)) return;
  TlMechSystem *sys = tl_solid_system(b.solid), *lin = NULL;
  if (linear) {
    TL_TEST_STATUS(tl_mech_linear_create(sys, 0.0, NULL, 0, &lin), TL_OK);
    if (!lin) return;
    sys = lin;
  }
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("central_difference", sys, &o, &st), TL_OK);
  if (!st) return;
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
  double dt = 2e-6, c = b.pulse.speed, y_mon = 10.0 * A; /* below every mesh's critical step */
  TL_TEST_ASSERT(dt < 0.5 * st->dt_crit, "dt %g against the critical step %g", dt, st->dt_crit);
  *c_out = c, *t0_out = b.pulse.t0;
  double t_end = b.pulse.t0 + y_mon / c + 2.0 * b.pulse.t0;
  size_t nodes = b.mesh->n_nodes;
  size_t *sec = calloc(nodes, sizeof *sec), ns = 0;
  for (size_t k = 0; k < nodes; ++k)
    if (fabs(b.mesh->x[3 * k + 1] - y_mon) < 1e-9) sec[ns++] = k;
  double best = 0.0, tb = 0.0, spr = 0.0, oth = 0.0;
  double t_start = tl_wtime();
  long steps = 0;
  while (st->t < t_end) {
    TL_TEST_STATUS(tl_stepper_step(st, dt), TL_OK);
    ++steps;
    double lo = INFINITY, hi = -INFINITY;
    for (size_t k = 0; k < ns; ++k) {
      for (int cc = 0; cc < 3; ++cc) {
        TlSparseIndex d = tl_solid_dof(b.solid, sec[k], cc);
        double v = d >= 0 ? st->u[d] : 0.0;
        if (cc == component) lo = fmin(lo, v), hi = fmax(hi, v);
        else oth = fmax(oth, fabs(v));
      }
    }
    spr = fmax(spr, hi - lo);
    if (hi > best) best = hi, tb = st->t;
  }
  *us_per_step = 1e6 * (tl_wtime() - t_start) / (double)steps;
  *t_peak = tb, *u_peak = best, *spread = spr, *other = oth;
  free(sec);
  tl_stepper_destroy(&st);
  tl_mech_system_destroy(&lin);
  bar_free(&b);
}

static void pulse_test(void)
{
  for (int component = 1; component >= 0; --component) {
    double tp[2], up[2], spread[2], other[2], us[2], c = 0, t0 = 0;
    for (int linear = 0; linear < 2; ++linear)
      pulse_run(component, linear, &tp[linear], &up[linear], &spread[linear], &other[linear], &us[linear], &c, &t0);
    const char *w = component == 1 ? "P" : "S";
    double expect = t0 + 10.0 * A / c;
    printf("%s pulse: peak %.4e m at %.4e s (expected %.4e s), spread %.1e m, other components %.1e m; "
           "linear path: peak %.4e m at %.4e s; %.1f us/step finite strain, %.1f us/step linear\n",
           w, up[0], tp[0], expect, spread[0], other[0], up[1], tp[1], us[0], us[1]);
    for (int l = 0; l < 2; ++l) {
      TL_TEST_REL(tp[l], expect, 0.02);
      TL_TEST_REL(up[l], 1e-5, 0.03);
      TL_TEST_ASSERT(spread[l] <= 1e-12 * 1e-5, "%s pulse: section not uniform, spread %g m", w, spread[l]);
      TL_TEST_ASSERT(other[l] <= 1e-3 * 1e-5, "%s pulse: other components %g m", w, other[l]);
    }
    TL_TEST_REL(up[1], up[0], 1e-3);
  }
}

/* One element across the period (each element's x and z faces share their
 * dofs): the same one-dimensional motion as with 2 x 2, to round-off, and
 * zero force at rest. */
static void single_element_section_test(void)
{
  double tp[2], up[2], spread, other, us, c, t0;
  pulse_run(1, 0, &tp[0], &up[0], &spread, &other, &us, &c, &t0);
  n_section = 1;
  pulse_run(1, 0, &tp[1], &up[1], &spread, &other, &us, &c, &t0);
  printf("one element across: P peak %.15e m at %.6e s; 2 x 2: %.15e m at %.6e s\n", up[1], tp[1], up[0], tp[0]);
  TL_TEST_REL(up[1], up[0], 1e-10);
  TL_TEST_ASSERT(tp[1] == tp[0], "peak times %.17g and %.17g", tp[1], tp[0]);
  Bar b;
  if (bar_build(&b, 8, -1, 1)) {
    TlMechSystem *sys = tl_solid_system(b.solid);
    size_t n = (size_t)sys->ndof;
    double *u = calloc(n, sizeof *u), *f = calloc(n, sizeof *f);
    TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f), TL_OK);
    double scale = 3.0 * E / (3.0 * (1 - 2 * NU)) * EPS0 * A * A;
    TL_TEST_ASSERT(max_abs(f, n) <= 1e-10 * scale, "one element across, at rest: force %g N", max_abs(f, n));
    TL_TEST_ASSERT(n == 3 * 9 - 2, "one element across: %zu dofs (one node per plane, y held at the ends: 25)", n);
    free(u), free(f);
    bar_free(&b);
  }
  n_section = 2;
}

static void pulse_shape_test(void)
{
  TlPulse g, r;
  TL_TEST_STATUS(tl_pulse_init(&g, TL_PULSE_GAUSSIAN, 5e-4, 0.6, 848.8), TL_OK);
  TL_TEST_STATUS(tl_pulse_init(&r, TL_PULSE_RICKER, 5e-4, 0.6, 848.8), TL_OK);
  double o[3], h = 1e-9;
  TL_TEST_REL(g.t0, 0.6 / (2 * 848.8), 1e-15);
  tl_pulse_eval(&g, 0.0, o);
  TL_TEST_REL(o[0], 5e-4 * exp(-TL_PI * TL_PI / 2), 1e-12);
  tl_pulse_eval(&g, g.t0, o);
  TL_TEST_REL(o[0], 5e-4, 1e-15);
  TL_TEST_REL(tl_pulse_peak_strain(&g), 2 * TL_PI / 0.6 * 5e-4 * exp(-0.5), 1e-12);
  /* Derivatives against central differences, both shapes. */
  const TlPulse *ps[2] = {&g, &r};
  for (int k = 0; k < 2; ++k) {
    double t = ps[k]->t0 * 0.7, p[3], m[3];
    tl_pulse_eval(ps[k], t, o);
    tl_pulse_eval(ps[k], t + h, p);
    tl_pulse_eval(ps[k], t - h, m);
    TL_TEST_REL((p[0] - m[0]) / (2 * h), o[1], 1e-6);
    TL_TEST_REL((p[1] - m[1]) / (2 * h), o[2], 1e-6);
  }
  /* The Ricker has zero mean (its integral over time vanishes). */
  double sum = 0.0, tot = 0.0;
  for (int k = 0; k <= 40000; ++k) {
    tl_pulse_eval(&r, 4.0 * r.t0 * k / 40000.0, o);
    sum += o[0], tot += fabs(o[0]);
  }
  TL_TEST_ASSERT(fabs(sum) < 1e-3 * tot, "Ricker mean %g of %g", sum, tot);
  g.subtract_initial = 1;
  tl_pulse_eval(&g, 0.0, o);
  TL_TEST_ASSERT(o[0] == 0.0, "subtracted initial value: %g", o[0]);
  TL_TEST_STATUS(tl_pulse_init(&g, TL_PULSE_GAUSSIAN, 5e-4, -1.0, 848.8), TL_ERR_ARG);
  TL_TEST_STATUS(tl_pulse_init(&g, TL_PULSE_GAUSSIAN, 5e-4, 0.6, 0.0), TL_ERR_ARG);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  pulse_shape_test();
  rest_test();
  pulse_test();
  single_element_section_test();
  return tl_test_report();
}
