/* Benchmark of the PSTLO tangent operator's condensation solve: a cell
 * prepared by the library (tl_nhl_cell_create_packing), one load step along
 * the NHL path (so that the contacts carry tangential forces and the network
 * stiffness is not symmetric), then pstlo with its default solve (CHOLMOD,
 * refined on the symmetric part) against the direct LU of the full matrix
 * (UMFPACK and KLU), in the same invocation, on the same cell: the ratios
 * printed are LU time / default time, and the largest relative difference of
 * the operators (they solve the same system).  uko's time for scale.  Last
 * line: `summary: ...`. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_bench.h"
#include "tl_nhl_cell.h"
#include "tl_nhl_operator.h"

static TlStatus time_operator(const char *name, double solver, const TlNhlOperatorInput *in, long repeats,
                              double c[81], double *best, TlNhlOperatorStats *st)
{
  TlNhlOperator *op;
  TL_CHECK(tl_nhl_operator_create(name, &op));
  TlStatus s = solver >= 0.0 ? tl_nhl_operator_set(op, "solver", solver) : TL_OK;
  if (s == TL_OK) s = tl_nhl_operator_setup(op);
  *best = INFINITY;
  for (long r = 0; r < repeats && s == TL_OK; ++r) {
    s = tl_nhl_operator_compute(op, in, NULL, NULL, c, st);
    if (s == TL_OK) *best = fmin(*best, st->seconds);
  }
  tl_nhl_operator_destroy(&op);
  return s;
}

static double rel_diff(const double *a, const double *b)
{
  double d = 0.0, m = 0.0;
  for (int q = 0; q < 81; ++q) d = fmax(d, fabs(a[q] - b[q])), m = fmax(m, fabs(b[q]));
  return m > 0.0 ? d / m : 0.0;
}

static TlStatus run(int argc, char **argv, TlSummary *sum)
{
  TlOptions *o = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv,
                             "PSTLO's condensation: the default solve (CHOLMOD, refined) against the LU of the full "
                             "matrix (UMFPACK, KLU) on one loaded cell.", &o));
  const char *kind = "fcc";
  long dim = 3, size = 6, repeats = 2, klu = 1;
  double step = 1e-4;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-kind", "fcc", "packing: fcc (3-D lattice) or random", &kind), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-dim", 3, 2, 3, "3 spheres, 2 disks (random only)", &dim), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-size", 6, 1, 100000, "fcc: cubic cells per side (4 n^3 spheres); random: particles", &size), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-step", 1e-4, 1e-8, 1e-2, "", "axial shortening of the load step", &step), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-repeats", 2, 1, 100, "timed repeats (the fastest counts)", &repeats), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-klu", 1, 0, 1, "1: time KLU too (slow on 3-D cells)", &klu), done);
  char kname[16];
  snprintf(kname, sizeof kname, "%s", kind);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
done:
  tl_options_destroy(&o);
  if (s != TL_OK) return s;

  TlNhlPacking pk;
  tl_nhl_packing_default(&pk);
  pk.kind = kname;
  pk.dim = (int)dim;
  pk.n_side = size;
  pk.n = size;
  TlNhlCellSettings set;
  tl_nhl_cell_settings_default(&set);
  TlNhlCell *cell = NULL;
  double t0 = tl_wtime();
  TL_CHECK(tl_nhl_cell_create_packing(&pk, &set, &cell));
  double t_prep = tl_wtime() - t0;
  TlMat3 F = tl_m3_identity(), sigma;
  F.m[1][1] -= step, F.m[0][1] += 0.3 * step;
  TlNhlCellStats cs;
  s = tl_nhl_cell_evaluate(cell, F, &sigma, &cs);
  TlNhlOperatorInput in = {tl_nhl_cell_dem(cell), (int)dim, F, sigma, NULL, NULL, 0, 1};
  double c0[81], c1[81], c2[81], cu[81], t_def = 0, t_umf = 0, t_klu = 0, t_uko = 0;
  TlNhlOperatorStats s0, s1, s2, su;
  memset(&s2, 0, sizeof s2);
  if (s == TL_OK) s = time_operator("pstlo", 0, &in, repeats, c0, &t_def, &s0);
  if (s == TL_OK) s = time_operator("pstlo", 1, &in, repeats, c1, &t_umf, &s1);
  if (s == TL_OK && klu) s = time_operator("pstlo", 2, &in, 1, c2, &t_klu, &s2);
  if (s == TL_OK) s = time_operator("uko", -1, &in, repeats, cu, &t_uko, &su);
  if (s == TL_OK) {
    printf("cell: %s, %zu particles, prepared in %.1f s; load step %g: %ld DEM steps, %zu contacts\n", kname,
           tl_nhl_cell_n_particles(cell), t_prep, step, cs.dem_steps, cs.contacts);
    printf("%-22s %10s %12s %14s %12s\n", "pstlo solve", "seconds", "residual", "vs default", "operator diff");
    printf("%-22s %10.4f %12.1e %14s %12s   (%d refinement sweeps, %zu rattlers)\n", s0.solver, t_def, s0.residual,
           "1", "-", s0.refinements, s0.rattlers);
    printf("%-22s %10.4f %12.1e %13.2fx %12.1e\n", s1.solver, t_umf, s1.residual, t_umf / t_def, rel_diff(c1, c0));
    if (klu)
      printf("%-22s %10.4f %12.1e %13.2fx %12.1e\n", s2.solver, t_klu, s2.residual, t_klu / t_def, rel_diff(c2, c0));
    printf("%-22s %10.4f\n", "uko (one pass)", t_uko);
    tl_summary_string(sum, "kind", kname);
    tl_summary_int(sum, "particles", (long)tl_nhl_cell_n_particles(cell));
    tl_summary_int(sum, "contacts", (long)cs.contacts);
    tl_summary_real(sum, "t_default", t_def);
    tl_summary_real(sum, "t_umfpack", t_umf);
    if (klu) tl_summary_real(sum, "t_klu", t_klu);
    tl_summary_real(sum, "ratio_umfpack_over_default", t_umf / t_def);
    if (klu) tl_summary_real(sum, "ratio_klu_over_default", t_klu / t_def);
    tl_summary_int(sum, "refinements", s0.refinements);
    tl_summary_real(sum, "operator_diff", rel_diff(c1, c0));
  }
  tl_nhl_cell_destroy(&cell);
  return s;
}

int main(int argc, char **argv) { return tl_bench_main_summary(argc, argv, run); }
