/* The gouge contact law (seeds/000 supplementary Eq. 18, Table 1), LAMMPS
 * gran/hertz/history = the parts lammps_hertz + lammps_history, on a scripted
 * two-sphere path against values computed from Eq. 18 with the displacement
 * history:
 *
 *   F_i = sqrt(δ R*) [ -(k_n δ + γ_n m* dδ/dt) n + (k_t ξ + γ_t m* u) ],
 *
 * ξ the tangential displacement of j relative to i accumulated along the
 * path (ξ += u dt, projected on the current tangent plane, reset at the
 * Coulomb cap |F_t| <= μ |F_n| so that the spring plus dashpot give the cap).
 *
 * Path (dt = 1e-8 s, Table 1 grains of d = 2.5 and 3.5 mm):
 *   1 oblique approach in stick: δ grows at 1 m/s, tangential 1e-3 m/s;
 *     closed form ξ = k u dt;
 *   2 sliding at constant δ, tangential 1 m/s: |F_t| = μ F_n once capped;
 *   3 tangential reversal, back inside the cone;
 *   4 normal unloading at constant tangential displacement (u = 0): closed
 *     form |F_t| ∝ sqrt(δ) (the spring k_t sqrt(δR*) acts on the stored ξ);
 *   5 rotation of the normal at constant δ, u = 0: ξ projected each step,
 *     its length not restored: |F_t|_k = |F_t|_0 cos^k θ.
 * Every step is compared with the recursion of Eq. 18 written here.
 *
 * The force-history law of seeds/004 (hertz + coulomb, the same k_n, k_t and
 * dampings) agrees at constant overlap and differs when δ varies at constant
 * tangential displacement: in stage 4 its F_t stays constant, the
 * displacement law's falls with sqrt(δ); in stage 1 its F_t is the sum of
 * increments k_t sqrt(δ_k R*) u dt, below k_t sqrt(δ R*) ξ. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_contact_law.h"
#include "tl_dem_packing.h"
#include "tl_test.h"

static const double kn = 36630036630.03663, kt = 45248868778.28054, gn = 0.2, gt = 0.1, mu = 0.5, dt = 1e-8;

typedef struct {
  long steps;
  double ddelta; /* dδ/dt, m/s */
  double ut;     /* tangential relative velocity along t = (-sin φ, cos φ, 0), m/s */
  double omega;  /* rate of the normal's angle φ about z, rad/s */
} Stage;

static const Stage path[] = {{300, 1.0, 1e-3, 0.0}, {600, 0.0, 1.0, 0.0}, {50, 0.0, -1.0, 0.0},
                             {120, -0.5, 0.0, 0.0}, {200, 0.0, 0.0, 1e5}};
enum { N_STAGES = sizeof path / sizeof path[0] };

typedef struct {
  TlVec3 n, t, u, vrel;
  double delta;
} State;

typedef struct {
  long n;
  TlVec3 *f;      /* Talus, per step */
  TlVec3 *ref;    /* Eq. 18, per step */
  double *fn_ref; /* Eq. 18 normal force magnitude */
  double *delta;
  TlVec3 *normal;
  int *stage;
} Trace;

static double meff, reff;

/* Eq. 18 with the displacement history; xi persists between calls. */
static TlVec3 eq18(const State *s, TlVec3 *xi, double *fn_out)
{
  const double a = sqrt(s->delta * reff);
  const double vn = tl_v3_dot(s->vrel, s->n);
  const double fn = a * (kn * s->delta - meff * gn * vn);
  *xi = tl_v3_add(*xi, tl_v3_scale(s->u, dt));
  *xi = tl_v3_axpy(*xi, -tl_v3_dot(*xi, s->n), s->n);
  TlVec3 ft = tl_v3_scale(tl_v3_add(tl_v3_scale(*xi, kt), tl_v3_scale(s->u, meff * gt)), a);
  const double cap = mu * fabs(fn), fs = tl_v3_norm(ft);
  if (fs > cap) {
    ft = tl_v3_scale(ft, cap / fs);
    /* the displacement that gives the capped force with the dashpot */
    *xi = tl_v3_scale(tl_v3_sub(tl_v3_scale(ft, 1.0 / a), tl_v3_scale(s->u, meff * gt)), 1.0 / kt);
  }
  *fn_out = fn;
  return tl_v3_add(tl_v3_scale(s->n, -fn), ft);
}

static long total_steps(const Stage *st, int ns)
{
  long n = 0;
  for (int k = 0; k < ns; ++k) n += st[k].steps;
  return n;
}

/* Runs the scripted path through `law` (and Eq. 18 if ref != NULL). */
static void run_path(const TlContactLaw *law, const Stage *st, int ns, double delta0, Trace *tr)
{
  double hist[16] = {0};
  TL_TEST_ASSERT(law->history_doubles <= 16, "history of %zu doubles", law->history_doubles);
  TlVec3 xi = tl_v3(0, 0, 0);
  double phi = 0.0, delta = delta0;
  long q = 0;
  const TlVec3 zero = tl_v3(0, 0, 0);
  for (int k = 0; k < ns; ++k)
    for (long j = 0; j < st[k].steps; ++j, ++q) {
      delta += st[k].ddelta * dt;
      phi += st[k].omega * dt;
      State s;
      s.delta = delta;
      s.n = tl_v3(cos(phi), sin(phi), 0.0);
      s.t = tl_v3(-sin(phi), cos(phi), 0.0);
      s.u = tl_v3_scale(s.t, st[k].ut);
      /* approach (δ growing): j moves towards i, v_n = (v_j - v_i)·n < 0 */
      s.vrel = tl_v3_axpy(s.u, -st[k].ddelta, s.n);
      const double ri = 1.25e-3;
      TlContactGeometry g;
      memset(&g, 0, sizeof g);
      g.normal = s.n;
      g.overlap = delta;
      g.branch_i = tl_v3_scale(s.n, ri);
      g.branch_j = tl_v3_scale(s.n, -1.75e-3);
      g.vrel = s.vrel;
      g.spin_mean = zero;
      g.spin_rel = zero;
      g.meff = meff;
      g.reff = reff;
      g.history = hist;
      TlContactResult r;
      TL_TEST_STATUS(tl_contact_law_evaluate_one(law, &g, dt, &r), TL_OK);
      tr->f[q] = r.force;
      tr->delta[q] = delta;
      tr->normal[q] = s.n;
      tr->stage[q] = k;
      tr->ref[q] = eq18(&s, &xi, &tr->fn_ref[q]);
    }
  tr->n = q;
}

static void trace_alloc(Trace *t, long n)
{
  t->f = calloc((size_t)n, sizeof *t->f);
  t->ref = calloc((size_t)n, sizeof *t->ref);
  t->fn_ref = calloc((size_t)n, sizeof *t->fn_ref);
  t->delta = calloc((size_t)n, sizeof *t->delta);
  t->normal = calloc((size_t)n, sizeof *t->normal);
  t->stage = calloc((size_t)n, sizeof *t->stage);
}

static void trace_free(Trace *t)
{
  free(t->f), free(t->ref), free(t->fn_ref), free(t->delta), free(t->normal), free(t->stage);
}

static TlVec3 tangential(TlVec3 f, TlVec3 n) { return tl_v3_axpy(f, -tl_v3_dot(f, n), n); }

/* first and last step of stage k */
static void stage_range(int k, long *first, long *last)
{
  long a = 0;
  for (int j = 0; j < k; ++j) a += path[j].steps;
  *first = a;
  *last = a + path[k].steps - 1;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const double rho = 2500.0, r1 = 1.25e-3, r2 = 1.75e-3;
  const double m1 = rho * 4.0 / 3.0 * TL_PI * r1 * r1 * r1, m2 = rho * 4.0 / 3.0 * TL_PI * r2 * r2 * r2;
  meff = m1 * m2 / (m1 + m2);
  reff = r1 * r2 / (r1 + r2);
  const double delta0 = 1e-6;

  /* the gouge law as the packings and the driver use it (Table 1) */
  TlContactLaw *law;
  TL_TEST_STATUS(tl_contact_law_build(&tl_gouge_law_spec, &law), TL_OK);
  double v;
  TL_TEST_STATUS(tl_contact_law_get(law, "k_n", &v), TL_OK);
  TL_TEST_REL(v, 2.0 / 3.0 * 50e9 / (1.0 - 0.09), 1e-15); /* k_n = (2/3) E/(1 - ν²) */
  TL_TEST_STATUS(tl_contact_law_get(law, "k_t", &v), TL_OK);
  TL_TEST_REL(v, 2.0 * 50e9 / (1.3 * 1.7), 1e-15); /* k_t = 2E/((1 + ν)(2 - ν)) */

  const long n = total_steps(path, N_STAGES);
  Trace tr;
  trace_alloc(&tr, n);
  run_path(law, path, N_STAGES, delta0, &tr);

  /* every step against the recursion of Eq. 18 */
  double fmax_ref = 0.0, dmax = 0.0;
  for (long q = 0; q < n; ++q) {
    fmax_ref = fmax(fmax_ref, tl_v3_norm(tr.ref[q]));
    const double d = tl_v3_norm(tl_v3_sub(tr.f[q], tr.ref[q]));
    dmax = d > dmax || isnan(d) ? d : dmax;
  }
  printf("path of %ld steps: max |F| %.6g N, max |F_Talus - F_Eq18| %.3g N\n", n, fmax_ref, dmax);
  TL_TEST_ASSERT(dmax <= 1e-12 * fmax_ref, "Talus against Eq. 18: %g N of %g N", dmax, fmax_ref);

  /* stage 1, approach in stick: closed form ξ = k u dt, F_n = sqrt(δR*)(k_n δ + γ_n m* dδ/dt) */
  long a, b;
  stage_range(0, &a, &b);
  double worst = 0.0;
  for (long q = a; q <= b; ++q) {
    const double s = sqrt(tr.delta[q] * reff), k = (double)(q - a + 1);
    const double ft = s * (kt * k * path[0].ut * dt + meff * gt * path[0].ut);
    const double fn = s * (kn * tr.delta[q] + meff * gn * path[0].ddelta);
    const TlVec3 want = tl_v3(-fn, ft, 0.0);
    worst = fmax(worst, tl_v3_norm(tl_v3_sub(tr.f[q], want)) / tl_v3_norm(want));
  }
  printf("stage 1 (approach, stick): closed form within %.3g relative\n", worst);
  TL_TEST_ASSERT(worst <= 1e-10, "stage 1 closed form: %g", worst);
  TL_TEST_ASSERT(tl_v3_norm(tangential(tr.f[b], tr.normal[b])) < 0.5 * mu * tr.fn_ref[b], "stage 1 is not in stick");

  /* stage 2, sliding: capped at mu F_n, along the motion */
  stage_range(1, &a, &b);
  long slid = 0;
  for (long q = a; q <= b; ++q) {
    const TlVec3 ft = tangential(tr.f[q], tr.normal[q]);
    if (fabs(tl_v3_norm(ft) - mu * tr.fn_ref[q]) <= 1e-12 * mu * tr.fn_ref[q] && ft.y > 0.0) ++slid;
  }
  printf("stage 2 (sliding): %ld of %ld steps on the cone |F_t| = mu F_n\n", slid, path[1].steps);
  TL_TEST_ASSERT(slid > path[1].steps / 2 && slid < path[1].steps, "stage 2: %ld steps capped", slid);
  {
    const TlVec3 ft = tangential(tr.f[b], tr.normal[b]);
    TL_TEST_REL(tl_v3_norm(ft), mu * tr.fn_ref[b], 1e-12);
  }

  /* stage 4, normal unloading at constant ξ: |F_t| ∝ sqrt(δ), inside the cone */
  stage_range(3, &a, &b);
  /* from its first step: the last of stage 3 still carries the dashpot of u */
  const double ft0 = tl_v3_norm(tangential(tr.f[a], tr.normal[a])), d0 = tr.delta[a];
  worst = 0.0;
  for (long q = a; q <= b; ++q) {
    const double ft = tl_v3_norm(tangential(tr.f[q], tr.normal[q]));
    worst = fmax(worst, fabs(ft / ft0 - sqrt(tr.delta[q] / d0)));
    TL_TEST_ASSERT(ft < mu * tr.fn_ref[q], "stage 4 step %ld slides", q - a);
  }
  printf("stage 4 (unloading at constant tangential displacement): |F_t| = |F_t0| sqrt(delta/delta0) within %.3g; "
         "delta falls by %.3g, |F_t| by %.3g\n",
         worst, 1.0 - tr.delta[b] / d0, 1.0 - tl_v3_norm(tangential(tr.f[b], tr.normal[b])) / ft0);
  TL_TEST_ASSERT(worst <= 1e-12, "stage 4 closed form: %g", worst);
  const double ft_disp_end4 = tl_v3_norm(tangential(tr.f[b], tr.normal[b]));

  /* stage 5, the normal turns: ξ projected, |F_t|_k = |F_t|_0 cos^k θ, F_t ⊥ n */
  stage_range(4, &a, &b);
  const double theta = path[4].omega * dt, f50 = ft_disp_end4;
  worst = 0.0;
  double ortho = 0.0;
  for (long q = a; q <= b; ++q) {
    const TlVec3 ft = tangential(tr.f[q], tr.normal[q]);
    const double k = (double)(q - a + 1);
    worst = fmax(worst, fabs(tl_v3_norm(ft) / f50 - pow(cos(theta), k)));
    /* the tangential force is the stored ξ times k_t sqrt(δR*): ⊥ n */
    const double fn = -tl_v3_dot(tr.f[q], tr.normal[q]);
    ortho = fmax(ortho, fabs(tl_v3_dot(tl_v3_add(tr.f[q], tl_v3_scale(tr.normal[q], fn)), tr.normal[q])) / tl_v3_norm(ft));
  }
  const double shrink = 1.0 - tl_v3_norm(tangential(tr.f[b], tr.normal[b])) / f50;
  printf("stage 5 (normal turning %g rad a step): |F_t| = |F_t0| cos^k(theta) within %.3g (shrank by %.3g)\n", theta,
         worst, shrink);
  TL_TEST_ASSERT(worst <= 1e-12, "stage 5 closed form: %g", worst);
  TL_TEST_ASSERT(shrink > 1e-5, "stage 5: the projection did not shorten the history (%g)", shrink);

  /* the force-history law of seeds/004 with the same stiffnesses and dampings */
  TlContactLaw *force_law;
  const TlContactValue fv[] = {{"k_n", kn}, {"gamma_n", gn}, {"k_t", kt}, {"gamma_t", gt}, {"mu", mu}};
  const TlContactSpec fs = {"hertz", "coulomb", NULL, NULL, fv, 5};
  TL_TEST_STATUS(tl_contact_law_build(&fs, &force_law), TL_OK);
  Trace tf;
  trace_alloc(&tf, n);
  run_path(force_law, path, N_STAGES, delta0, &tf);
  stage_range(0, &a, &b);
  const double t1_disp = tl_v3_norm(tangential(tr.f[b], tr.normal[b]));
  const double t1_force = tl_v3_norm(tangential(tf.f[b], tf.normal[b]));
  const double n1 = fabs(tl_v3_dot(tl_v3_sub(tr.f[b], tf.f[b]), tr.normal[b]));
  printf("force history (hertz + coulomb): end of stage 1 |F_t| %.6g N against %.6g N (displacement history), normal "
         "forces equal within %.3g N\n", t1_force, t1_disp, n1);
  TL_TEST_ASSERT(t1_force < 0.9 * t1_disp, "stage 1: force history %g, displacement history %g", t1_force, t1_disp);
  stage_range(3, &a, &b);
  const double f4a = tl_v3_norm(tangential(tf.f[a], tf.normal[a]));
  const double f4b = tl_v3_norm(tangential(tf.f[b], tf.normal[b]));
  printf("force history, stage 4: |F_t| from %.6g to %.6g N (constant), displacement history falls by %.3g\n", f4a, f4b,
         1.0 - ft_disp_end4 / ft0);
  TL_TEST_REL(f4b, f4a, 1e-12);
  for (long q = a; q <= b; ++q)
    TL_TEST_ASSERT(tl_v3_norm(tangential(tf.f[q], tf.normal[q])) < mu * tf.fn_ref[q], "force law slides in stage 4");
  TL_TEST_ASSERT(fabs(f4b / f4a - ft_disp_end4 / ft0) > 0.05, "stage 4: both laws give %g", f4b / f4a);

  /* ... and at constant overlap, in stick, both laws agree */
  const Stage flat[] = {{400, 0.0, 0.05, 0.0}};
  Trace c1, c2;
  trace_alloc(&c1, 400);
  trace_alloc(&c2, 400);
  run_path(law, flat, 1, 4e-6, &c1);
  run_path(force_law, flat, 1, 4e-6, &c2);
  double agree = 0.0;
  for (long q = 0; q < 400; ++q)
    agree = fmax(agree, tl_v3_norm(tl_v3_sub(c1.f[q], c2.f[q])) / tl_v3_norm(c1.f[q]));
  printf("constant overlap, stick: the two laws agree within %.3g relative\n", agree);
  TL_TEST_ASSERT(agree <= 1e-10, "constant overlap: %g", agree);
  TL_TEST_ASSERT(tl_v3_norm(tangential(c1.f[399], c1.normal[399])) < mu * c1.fn_ref[399], "constant overlap slides");

  trace_free(&tr), trace_free(&tf), trace_free(&c1), trace_free(&c2);
  tl_contact_law_destroy(&law);
  tl_contact_law_destroy(&force_law);
  return tl_test_report();
}
