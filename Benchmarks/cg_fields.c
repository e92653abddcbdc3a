/* Benchmark of the CG fields (issue 5): the stress field (contact and
 * kinetic parts) on a 64^3 grid from about 10^5 particles, for growing CG
 * widths c, with the Dirac cell averages as the c = 0 reference.
 *
 * The packing: a periodic simple cubic lattice of 47^3 spheres of
 * diameter d, jittered and slightly compressed, with a linear spring on each
 * lattice bond that overlaps (about 3 contacts per particle) and random
 * velocities, so that every source type is present.  Ratios printed:
 * binned point evaluation against the brute-force oracle on a sample of
 * points (the neighbour search's gain), and each grid evaluation's time per
 * node.  Last line: `summary: ...`. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_bench.h"
#include "tl_cg_fields.h"
#include "tl_cg_kernel.h"
#include "tl_options_renamed.h"

static double uniform(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static TlStatus run(int argc, char **argv, TlSummary *sum)
{
  TlOptions *o = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv, "CG stress field on a grid from a periodic packing: time per evaluation against c.", &o));
  long side = 47, grid = 64, repeats = 3, sample = 400;
  double c_list[16];
  int n_c = 0;
  const char *kernel_name = "lucy";
  TlStatus s = TL_OK;
  static const TlRenamedOption renamed[] = {{"-kernel", "-cg_kernel", NULL}};
  TL_CHECK_GOTO(s, tl_options_refuse_renamed(o, renamed, 1), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-side", 47, 2, 1000, "particles per lattice side (n = side^3)", &side), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-grid", 64, 2, 1024, "grid nodes per direction", &grid), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-repeats", 3, 1, 100, "timed repeats per width (the fastest counts)", &repeats), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-sample", 400, 1, 100000, "points of the brute-force comparison", &sample), done);
  TL_CHECK_GOTO(s, tl_options_get_real_list(o, "-c_list", "0,0.5,1,2,3,4", "d", "CG widths c/d (0: Dirac cell averages)",
                                            c_list, 16, &n_c), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-cg_kernel", "lucy", "CG kernel for c > 0", &kernel_name), done);
  char kname[64];
  snprintf(kname, sizeof kname, "%s", kernel_name);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
done:
  tl_options_destroy(&o);
  if (s != TL_OK) return s;

  const double d = 1.0, a = 0.998 * d, L = side * a, kn = 1e3;
  size_t n = (size_t)(side * side * side);
  TlVec3 *x = malloc(n * sizeof *x), *v = malloc(n * sizeof *v);
  double *m = malloc(n * sizeof *m);
  TlVec3 *cx = malloc(3 * n * sizeof *cx), *cb = malloc(3 * n * sizeof *cb), *cf = malloc(3 * n * sizeof *cf);
  if (!x || !v || !m || !cx || !cb || !cf) return tl_error_set(TL_ERR_MEM, __FILE__, __LINE__, "benchmark arrays for %zu particles", n);
  uint64_t st = 7;
  for (size_t i = 0; i < n; ++i) {
    size_t ix = i % (size_t)side, iy = (i / (size_t)side) % (size_t)side, iz = i / (size_t)(side * side);
    x[i] = tl_v3((ix + 0.5) * a + 0.001 * (uniform(&st) - 0.5), (iy + 0.5) * a + 0.001 * (uniform(&st) - 0.5),
                 (iz + 0.5) * a + 0.001 * (uniform(&st) - 0.5));
    v[i] = tl_v3(0.01 * (uniform(&st) - 0.5), 0.01 * (uniform(&st) - 0.5), 0.01 * (uniform(&st) - 0.5));
    m[i] = TL_PI / 6.0;
  }
  size_t nc = 0;
  for (size_t i = 0; i < n; ++i) {
    size_t ix = i % (size_t)side, iy = (i / (size_t)side) % (size_t)side, iz = i / (size_t)(side * side);
    size_t nb[3] = {(ix + 1) % (size_t)side + (size_t)side * (iy + (size_t)side * iz),
                    ix + (size_t)side * ((iy + 1) % (size_t)side + (size_t)side * iz),
                    ix + (size_t)side * (iy + (size_t)side * ((iz + 1) % (size_t)side))};
    for (int k = 0; k < 3; ++k) {
      TlVec3 b = tl_v3_sub(x[nb[k]], x[i]);
      b.x -= L * nearbyint(b.x / L);
      b.y -= L * nearbyint(b.y / L);
      b.z -= L * nearbyint(b.z / L);
      double r = tl_v3_norm(b);
      if (r >= d) continue;
      cx[nc] = x[i];
      cb[nc] = b;
      cf[nc++] = tl_v3_scale(b, -kn * (d - r) / r);
    }
  }
  TlCGParticleArrays pa = {n, x, m, v};
  TlCGContactArrays ca = {nc, cx, cb, cf};
  double h = L / grid;
  TlCGGrid g = {tl_v3(0.5 * h, 0.5 * h, 0.5 * h), tl_v3(h, h, h), {(int)grid, (int)grid, (int)grid}};
  size_t nodes = (size_t)grid * grid * grid;
  TlCGBox box = {tl_v3(0, 0, 0), tl_v3(L, L, L), {1, 1, 1}};
  printf("packing: %zu particles, %zu contacts, periodic box %.1f d, grid %ld^3 (h = %.3f d)\n", n, nc, L, grid, h);
  printf("%-10s %8s %12s %14s %16s %14s\n", "kernel", "c/d", "grid [s]", "per node [us]", "vs Dirac", "brute/binned");
  TlCGFields *f = NULL;
  TL_CHECK(tl_cg_fields_create(nodes, TL_CG_STRESS_CONTACT | TL_CG_STRESS_KINETIC, &f));
  double t_dirac = 0.0, first_c = -1, t_first = 0, t_last = 0, last_c = 0, speedup_at_2 = 0;
  char key[64];
  for (int q = 0; q < n_c; ++q) {
    double c = c_list[q] * d;
    TlCGKernel *k = NULL;
    TL_CHECK(tl_cg_kernel_create(c > 0 ? kname : "dirac", c, 3, &k));
    TlCG *cg = NULL;
    TL_CHECK(tl_cg_create(k, &box, 0, &cg));
    TL_CHECK(tl_cg_set_data(cg, &pa, &ca, NULL));
    double best = INFINITY;
    for (long r = 0; r < repeats; ++r) {
      double t0 = tl_wtime();
      TL_CHECK(tl_cg_evaluate_grid(cg, &g, f));
      best = fmin(best, tl_wtime() - t0);
    }
    double ratio_brute = 0.0;
    if (c > 0) {
      /* the neighbour search against the oracle, on a sample of points */
      TlVec3 *pts = malloc((size_t)sample * sizeof *pts);
      TlCGFields *fs = NULL;
      TL_CHECK(tl_cg_fields_create((size_t)sample, TL_CG_STRESS_CONTACT | TL_CG_STRESS_KINETIC, &fs));
      for (long i = 0; i < sample; ++i) pts[i] = tl_v3(L * uniform(&st), L * uniform(&st), L * uniform(&st));
      double t0 = tl_wtime();
      TL_CHECK(tl_cg_evaluate_points(cg, (size_t)sample, pts, fs));
      double t_bin = tl_wtime() - t0;
      t0 = tl_wtime();
      TL_CHECK(tl_cg_evaluate_points_brute_force(cg, (size_t)sample, pts, fs));
      double t_brute = tl_wtime() - t0;
      ratio_brute = t_brute / t_bin;
      tl_cg_fields_destroy(&fs);
      free(pts);
      if (first_c < 0) first_c = c, t_first = best;
      last_c = c, t_last = best;
      if (fabs(c - 2.0 * d) < 1e-12) speedup_at_2 = ratio_brute;
    } else {
      t_dirac = best;
    }
    printf("%-10s %8.2f %12.4f %14.3f %16.2f %14.1f\n", k->ops->header.name, c / d, best, 1e6 * best / nodes,
           t_dirac > 0 ? best / t_dirac : 0.0, ratio_brute);
    snprintf(key, sizeof key, "t_c%g", c / d);
    tl_summary_real(sum, key, best);
    tl_cg_destroy(&cg);
    tl_cg_kernel_destroy(&k);
  }
  tl_cg_fields_destroy(&f);
  tl_summary_int(sum, "particles", (long)n);
  tl_summary_int(sum, "contacts", (long)nc);
  tl_summary_int(sum, "grid", grid);
  if (first_c > 0 && last_c > first_c)
    tl_summary_real(sum, "growth_exponent", log(t_last / t_first) / log(last_c / first_c));
  tl_summary_real(sum, "brute_over_binned_c2", speedup_at_2);
  free(x); free(v); free(m); free(cx); free(cb); free(cf);
  return TL_OK;
}

int main(int argc, char **argv) { return tl_bench_main_summary(argc, argv, run); }
