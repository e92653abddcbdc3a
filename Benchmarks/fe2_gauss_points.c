/* The cost of the point-by-point material evaluation (OpenMP over Gauss
 * points, longest first; tl_solid_set_evaluation) against the chunked one,
 * in the same invocation, on a plane-strain Q8 rectangle (-nx x 2 nx
 * elements, 2 x 2 Gauss points): the time of one Newton iteration's
 * assembly (the residual at u, then the tangent at the same u), u changed
 * between iterations.
 *
 *   cheap law (hooke): ratio = points / chunked on 1 and 2 threads: what
 *     the point path costs a law that takes nanoseconds (it should not be
 *     slower; the solid picks chunked for such laws by default anyway);
 *   costly law (a Saint Venant-Kirchhoff law that burns -work x (1 + 9 w)
 *     floating-point operations per evaluation, w in [0, 1] from the
 *     point's strain, so costs vary by 10 across the mesh as a DEM cell's
 *     do): time per iteration on 1 and 2 threads, the speed-up, and the
 *     results' bits compared across the thread counts.
 * Prints the machine load (1-minute average) beside the figures. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_bench.h"
#include "tl_material.h"
#include "tl_solid.h"

/* ------------------------------------------------------- costly law */
typedef struct {
  TlMaterial base;
  double lambda, mu, work;
} Costly;

static const TlMaterialParam costly_params[] = {
    {"lambda", 5e7, 0, 1e12, "Pa", "first Lame constant", offsetof(Costly, lambda)},
    {"mu", 4e7, 1, 1e12, "Pa", "shear modulus", offsetof(Costly, mu)},
    {"work", 2e4, 0, 1e12, "", "busy-loop iterations per evaluation (times 1 to 10)", offsetof(Costly, work)},
};

static TlStatus costly_setup(TlMaterial *m)
{
  m->state_size = 0;
  return TL_OK;
}

static TlStatus costly_evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma,
                                const double *so, double *sn, TlMat3 *S, double *D, double *W)
{
  (void)F, (void)so, (void)sn, (void)W;
  const Costly *c = (const Costly *)m;
  for (size_t p = 0; p < npts; ++p) {
    const double tr = tl_m3_trace(gamma[p]);
    /* The cost: 1 to 10 times `work`, from the shear strain. */
    const double w = fmin(1.0, fabs(gamma[p].m[0][1]) * 1e3);
    const long n = (long)(c->work * (1.0 + 9.0 * w));
    volatile double x = 1.0;
    for (long k = 0; k < n; ++k) x = x * 0.999999 + 1e-9;
    S[p] = tl_m3_add(tl_m3_scale(tl_m3_identity(), c->lambda * tr), tl_m3_scale(gamma[p], 2.0 * c->mu));
    S[p].m[0][0] += 0.0 * x;
    if (D) {
      double *d = D + 36 * p;
      memset(d, 0, 36 * sizeof *d);
      for (int I = 0; I < 3; ++I) {
        for (int J = 0; J < 3; ++J) d[6 * I + J] = c->lambda;
        d[6 * I + I] += 2.0 * c->mu;
        d[6 * (I + 3) + I + 3] = c->mu;
      }
    }
  }
  return TL_OK;
}

static int costly_symmetric(const TlMaterial *m)
{
  (void)m;
  return 1;
}

static const TlMaterialOps costly_ops = {
    .header = {"material", "bench_costly", "SVK with a busy loop per point (benchmark)"},
    .size = sizeof(Costly), .n_params = 3, .params = costly_params, .setup = costly_setup,
    .evaluate = costly_evaluate, .symmetric_tangent = costly_symmetric};

/* --------------------------------------------------------- the runs */
typedef struct {
  double per_iteration;
  unsigned long hash;
  TlSolidEvalStats stats;
} Run;

static unsigned long hash_doubles(const double *x, size_t n, unsigned long h)
{
  const unsigned char *b = (const unsigned char *)x;
  for (size_t i = 0; i < n * sizeof *x; ++i) h = (h ^ b[i]) * 1099511628211UL;
  return h;
}

static TlStatus one(const char *law, long nx, int mode, int threads, long iterations, double work, Run *r)
{
  TlMesh *mesh = NULL;
  TlSolid *solid = NULL;
  TlMaterial *m = NULL;
  TlSparse *K = NULL;
  double *u = NULL, *f = NULL;
  TlStatus s = TL_OK;
  size_t n[2] = {(size_t)nx, (size_t)(2 * nx)};
  double lo[2] = {0, 0}, hi[2] = {0.05, 0.1};
  TL_CHECK(tl_mesh_create_rectangle(&tl_element_quad8, n, lo, hi, &mesh));
  TL_CHECK_GOTO(s, tl_material_create(law, &m), done);
  if (!strcmp(law, "hooke")) {
    TL_CHECK_GOTO(s, tl_material_set(m, "E", 1e8), done);
    TL_CHECK_GOTO(s, tl_material_set(m, "nu", 0.3), done);
  } else {
    TL_CHECK_GOTO(s, tl_material_set(m, "work", work), done);
  }
  TL_CHECK_GOTO(s, tl_material_setup(m), done);
  TL_CHECK_GOTO(s, tl_solid_create(mesh, &solid), done);
  TL_CHECK_GOTO(s, tl_solid_set_material(solid, NULL, m), done);
  TL_CHECK_GOTO(s, tl_solid_fix(solid, "ymin", 3), done);
  TL_CHECK_GOTO(s, tl_solid_set_evaluation(solid, mode, threads), done);
  omp_set_num_threads(threads); /* the element loops' threads too (set at set-up) */
  TL_CHECK_GOTO(s, tl_solid_setup(solid), done);
  TlMechSystem *sys = tl_solid_system(solid);
  TL_CHECK_GOTO(s, sys->ops->create_matrix(sys, sys->symmetric, &K), done);
  TL_CHECK_GOTO(s, tl_calloc(&u, (size_t)sys->ndof, sizeof *u), done);
  TL_CHECK_GOTO(s, tl_calloc(&f, (size_t)sys->ndof, sizeof *f), done);
  r->hash = 1469598103934665603UL;
  double t = 0.0;
  for (long it = 0; it <= iterations; ++it) {
    /* A smooth displacement with shear that varies over the mesh. */
    for (size_t a = 0; a < mesh->n_nodes; ++a) {
      const double x = mesh->x[3 * a], y = mesh->x[3 * a + 1];
      const TlSparseIndex dx = tl_solid_dof(solid, a, 0), dy = tl_solid_dof(solid, a, 1);
      const double amp = 1e-3 * (1.0 + 0.01 * (double)it);
      if (dx >= 0) u[dx] = amp * y * y * 40.0 * sin(60.0 * x);
      if (dy >= 0) u[dy] = -amp * y;
    }
    tl_sparse_zero(K);
    const double t0 = tl_wtime();
    TL_CHECK_GOTO(s, sys->ops->internal_force(sys, 0.0, u, NULL, f), done);
    TL_CHECK_GOTO(s, sys->ops->internal_tangent(sys, 0.0, u, NULL, 1.0, 0.0, K), done);
    if (it > 0) t += tl_wtime() - t0; /* the first one warms up (allocations, first LPT order) */
    r->hash = hash_doubles(f, (size_t)sys->ndof, r->hash);
    r->hash = hash_doubles(K->values, (size_t)K->nnz, r->hash);
  }
  r->per_iteration = t / (double)iterations;
  tl_solid_get_evaluation_stats(solid, &r->stats);
done:
  tl_free(&u);
  tl_free(&f);
  tl_sparse_destroy(&K);
  tl_solid_destroy(&solid);
  tl_material_destroy(&m);
  tl_mesh_destroy(&mesh);
  return s;
}

static TlStatus run(int argc, char **argv)
{
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_material_register(&costly_ops));
  TlOptions *o = NULL;
  TL_CHECK(tl_options_create(argc, argv,
                             "Point-by-point (OpenMP over Gauss points, LPT) against chunked material evaluation: "
                             "time per Newton assembly for a cheap and a costly law, 1 and 2 threads.",
                             &o));
  long nx = 16, nx_costly = 4, iterations = 20, repeats = 3;
  double work = 2e4;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nx", 16, 1, 1000, "cheap law: elements across (mesh nx x 2 nx)", &nx), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nx_costly", 4, 1, 1000, "costly law: elements across", &nx_costly), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-iterations", 20, 1, 100000, "assemblies timed per run", &iterations), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-repeats", 3, 1, 100, "runs per configuration (the fastest kept)", &repeats),
                done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-work", 2e4, 0, 1e12, "", "costly law: busy-loop iterations (x 1..10)", &work),
                done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  printf("load average at the start: %.2f on %d hardware threads\n", tl_bench_load_average(), omp_get_num_procs());
  Run best[2][2]; /* [mode: chunked, points][threads 1, 2] */
  for (int mode = 0; mode < 2; ++mode)
    for (int th = 0; th < 2; ++th) {
      best[mode][th].per_iteration = HUGE_VAL;
      for (long k = 0; k < repeats; ++k) {
        Run r;
        TL_CHECK_GOTO(s, one("hooke", nx, mode ? TL_SOLID_EVAL_POINTS : TL_SOLID_EVAL_CHUNKED, th + 1, iterations, 0.0, &r),
                      done);
        if (r.per_iteration < best[mode][th].per_iteration) best[mode][th] = r;
      }
    }
  const double ratio1 = best[1][0].per_iteration / best[0][0].per_iteration;
  const double ratio2 = best[1][1].per_iteration / best[0][1].per_iteration;
  printf("hooke, %ld Q8 (%ld Gauss points): assembly per Newton iteration chunked %.3e s (1 thread) %.3e s (2), "
         "points %.3e s (1) %.3e s (2); ratio points/chunked %.3f (1 thread) %.3f (2 threads)\n",
         2 * nx * nx, 8 * nx * nx, best[0][0].per_iteration, best[0][1].per_iteration, best[1][0].per_iteration,
         best[1][1].per_iteration, ratio1, ratio2);
  Run c1 = {HUGE_VAL, 0, {0}}, c2 = {HUGE_VAL, 0, {0}};
  for (long k = 0; k < repeats; ++k) {
    Run r;
    TL_CHECK_GOTO(s, one("bench_costly", nx_costly, TL_SOLID_EVAL_POINTS, 1, iterations, work, &r), done);
    if (r.per_iteration < c1.per_iteration) c1 = r;
    TL_CHECK_GOTO(s, one("bench_costly", nx_costly, TL_SOLID_EVAL_POINTS, 2, iterations, work, &r), done);
    if (r.per_iteration < c2.per_iteration) c2 = r;
  }
  const double per_point1 = c1.stats.t_points / (double)c1.stats.points;
  const double per_point2 = c2.stats.t_points / (double)c2.stats.points;
  printf("costly law, %ld Q8 (%ld Gauss points, costs 1 to 10 x): per Newton iteration %.3e s (1 thread) %.3e s "
         "(2 threads), speed-up %.2f; per point evaluation %.3e s / %.3e s; tangents reused %ld of %ld; "
         "results %s across thread counts\n",
         2 * nx_costly * nx_costly, 8 * nx_costly * nx_costly, c1.per_iteration, c2.per_iteration,
         c1.per_iteration / c2.per_iteration, per_point1, per_point2, c2.stats.reuses, c2.stats.reuses + c2.stats.evaluations,
         c1.hash == c2.hash ? "identical" : "DIFFERENT");
  printf("load average at the end: %.2f\n", tl_bench_load_average());
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_real(&sum, "hooke_ratio_1thread", ratio1);
  tl_summary_real(&sum, "hooke_ratio_2threads", ratio2);
  tl_summary_real(&sum, "hooke_chunked_1", best[0][0].per_iteration);
  tl_summary_real(&sum, "hooke_points_1", best[1][0].per_iteration);
  tl_summary_real(&sum, "costly_iteration_1", c1.per_iteration);
  tl_summary_real(&sum, "costly_iteration_2", c2.per_iteration);
  tl_summary_real(&sum, "costly_speedup", c1.per_iteration / c2.per_iteration);
  tl_summary_real(&sum, "costly_per_point", per_point1);
  tl_summary_int(&sum, "identical", c1.hash == c2.hash);
  tl_summary_real(&sum, "load", tl_bench_load_average());
  s = tl_summary_print(&sum, stdout);
  if (c1.hash != c2.hash) s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "results differ between 1 and 2 threads");
done:
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
