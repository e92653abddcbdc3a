/* One material point of the numerically homogenised law (Desrues et al. 2019 §2.2-2.5):
 * a periodic DEM cell (the dem_cell material, Coupling/Hierarchical) taken
 * along a prescribed path, the element test of the FEM x DEM method.
 *
 *   biaxial    plane strain (F_33 = 1): axial shortening ε_11 in -steps
 *              equal increments, the lateral stress σ_22 held at -lateral
 *              (2-D disk cells, the paper's 20 x 20 = 400, or 3-D cells);
 *   triaxial   3-D cells: axial shortening with σ_22 = σ_33 = -lateral.
 * The lateral stretch is found at every step by Newton's method on the
 * lateral stress with the tangent of the chosen operator (-operator), each
 * evaluation integrating the cell's whole path from the committed state
 * (Eq. 18 with I = -inertial, relaxation to Eq. 19 with ε_R = -tolerance),
 * then the step is committed.  The operator's moduli (current
 * configuration, dσ = C : d, Voigt 11 22 33 12 23 13 with engineering
 * shear) are printed beside the stress, with those of the operators listed
 * in -compare evaluated on the same state.
 *
 * Cells: -cells 2d (disks, plane strain, stresses per unit thickness) or
 * 3d (spheres), a random packing compressed isotropically to -pressure
 * (σ0) and relaxed, or -packing fcc (3-D lattice); linear contacts with
 * Coulomb friction, k_n from κ = -kappa (2-D: k_n = κ σ0; 3-D: k_n = κ σ0
 * <d>, a reading), k_t = -kt_over_kn k_n, μ = -contact_mu (F1 of Desrues et al. 2019: 400
 * disks, k_n/k_t = 1, κ = 500, μ = 0.5).
 *
 * Output in -output_dir: path.csv / path.h5 (one row per step: strains,
 * stresses, lateral iterations, DEM steps, seconds, imbalance, the
 * operator's moduli and the compared ones), the cell's particles
 * (cell_*.h5 + cell.xmf) every -snapshot_every steps and at the end.
 * Last line: summary: key=value ... */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_options_renamed.h"
#include "tl_nhl_material.h"
#include "tl_nhl_operator.h"
#include "tl_particle_snapshot.h"
#include "tl_timeseries.h"

enum { MAX_COMPARE = 8 };

typedef struct {
  int dim, triaxial, packing_fcc;
  long n, n_side, steps, max_lateral, snapshot_every, seed;
  double strain, lateral, lateral_tolerance;
  TlNhlPacking p;
  double inertial, tolerance, max_relax, permissive, eps, directions;
  const char *op, *compare, *out;
  char compare_names[MAX_COMPARE][32];
  int n_compare;
} Settings;

static TlStatus options(int argc, char **argv, TlOptions **o, Settings *s)
{
  TL_CHECK(tl_options_create(argc, argv,
                             "One material point of the FEM x DEM numerically homogenised law (Desrues et al. 2019): a "
                             "periodic DEM cell along a biaxial (plane strain) or triaxial path with constant "
                             "lateral stress, the tangent operators printed beside the stress.  Paper: " TL_PAPER_DESRUES_2019 ".",
                             o));
  static const char *const cells[] = {"2d", "3d", NULL}, *const paths[] = {"biaxial", "triaxial", NULL},
                           *const packings[] = {"random", "fcc", NULL};
  static const TlRenamedOption renamed[] = {{"-mu", "-contact_mu", NULL}, {"-restitution", "-contact_restitution", NULL}};
  TL_CHECK(tl_options_refuse_renamed(*o, renamed, 2));
  int ci = 0, pi = 0, ki = 0;
  TL_CHECK(tl_options_get_choice(*o, "-cells", "2d", cells, "cell of disks (2d, plane strain) or spheres (3d)", &ci));
  TL_CHECK(tl_options_get_choice(*o, "-path", "biaxial", paths,
                                 "biaxial: plane strain, sigma_22 held; triaxial (3d): sigma_22 = sigma_33 held", &pi));
  TL_CHECK(tl_options_get_choice(*o, "-packing", "random", packings,
                                 "random packing compressed to -pressure, or an fcc lattice (3d)", &ki));
  s->dim = ci == 0 ? 2 : 3;
  s->triaxial = pi == 1;
  s->packing_fcc = ki == 1;
  tl_nhl_packing_default(&s->p);
  TL_CHECK(tl_options_get_int(*o, "-n", s->dim == 2 ? 400 : 1000, 2, 1000000,
                              "particles of a random cell (Desrues et al. 2019: 400 disks, 1000 spheres)", &s->n));
  TL_CHECK(tl_options_get_int(*o, "-n_side", 3, 1, 40, "fcc: cubic cells per side (4 particles each)", &s->n_side));
  TL_CHECK(tl_options_get_real(*o, "-radius_min", 0.5e-3, 1e-9, 1e3, "m", "smallest radius", &s->p.radius_min));
  TL_CHECK(tl_options_get_real(*o, "-radius_max", 1.0e-3, 1e-9, 1e3, "m",
                               "largest radius (r_max / r_min = 2: the recommended 2-D cell)", &s->p.radius_max));
  TL_CHECK(tl_options_get_real(*o, "-density", 2600, 1e-6, 1e6, "kg/m^3", "grain density", &s->p.density));
  TL_CHECK(tl_options_get_real(*o, "-pressure", 1e5, 1e-6, 1e12, "Pa",
                               "confining stress sigma_0 of the packing (2-D: per unit thickness)", &s->p.pressure));
  TL_CHECK(tl_options_get_real(*o, "-kappa", 500, 1.0001, 1e9, "",
                               "stiffness level: 2-D k_n / sigma_0, 3-D k_n / (sigma_0 <d>) (F1: 500)", &s->p.kappa));
  TL_CHECK(tl_options_get_real(*o, "-kt_over_kn", 1.0, 0.0, 100.0, "", "tangential / normal stiffness (F1: 1)",
                               &s->p.kt_over_kn));
  TL_CHECK(tl_options_get_real(*o, "-contact_mu", 0.5, 0.0, 100.0, "", "contact friction coefficient (F1: 0.5)", &s->p.mu));
  TL_CHECK(tl_options_get_real(*o, "-contact_restitution", 0.1, 1e-6, 1.0, "",
                               "normal restitution of a contact (sets the damping ratio)", &s->p.restitution));
  TL_CHECK(tl_options_get_real(*o, "-dt_fraction", 0.2, 1e-3, 1.0, "", "DEM time step / critical time step",
                               &s->p.dt_fraction));
  TL_CHECK(tl_options_get_int(*o, "-seed", 1, 0, 1000000000, "seed of the random packing", &s->seed));
  TL_CHECK(tl_options_get_real(*o, "-strain", 0.02, 1e-9, 0.5, "", "total axial shortening -epsilon_11", &s->strain));
  TL_CHECK(tl_options_get_int(*o, "-steps", 20, 1, 100000, "load steps (equal axial increments)", &s->steps));
  TL_CHECK(tl_options_get_real(*o, "-lateral", 0.0, 0.0, 1e12, "Pa",
                               "lateral stress held (compressive; 0: -pressure)", &s->lateral));
  TL_CHECK(tl_options_get_real(*o, "-lateral_tolerance", 1e-3, 1e-9, 0.5, "",
                               "relative error of the lateral stress accepted", &s->lateral_tolerance));
  TL_CHECK(tl_options_get_int(*o, "-max_lateral", 12, 1, 1000, "Newton iterations on the lateral stress per step",
                              &s->max_lateral));
  TL_CHECK(tl_options_get_real(*o, "-inertial", 1e-4, 1e-9, 1.0, "", "inertial number I of the drive (Eq. 18)",
                               &s->inertial));
  TL_CHECK(tl_options_get_real(*o, "-tolerance", 1e-3, 1e-12, 1.0, "",
                               "equilibrium tolerance eps_R on every particle's imbalance (Eq. 19)", &s->tolerance));
  TL_CHECK(tl_options_get_real(*o, "-max_relax_steps", 1e6, 0, 1e12, "DEM steps", "cap on relaxation per evaluation",
                               &s->max_relax));
  TL_CHECK(tl_options_get_real(*o, "-permissive", 0, 0, 1, "",
                               "1: cell pressure steady over a window instead of Eq. 19", &s->permissive));
  TL_CHECK(tl_options_get_string(*o, "-operator", "demqo",
                                 "tangent operator used for the lateral control (cto, aeo, demqo, pstlo, uko, ucko, "
                                 "ucko_2dof, kao)", &s->op));
  TL_CHECK(tl_options_get_string(*o, "-compare", "",
                                 "operators printed beside, comma-separated (\"all\": every registered one)",
                                 &s->compare));
  TL_CHECK(tl_options_get_real(*o, "-eps", 1e-5, 1e-12, 0.1, "", "perturbation size of cto / demqo (a reading)", &s->eps));
  TL_CHECK(tl_options_get_real(*o, "-directions", 9, 6, 9, "",
                               "cto / demqo directions: 9 (Eq. 30; 4 in 2-D) or 6 (symmetric; 3 in 2-D)", &s->directions));
  TL_CHECK(tl_options_get_int(*o, "-snapshot_every", 0, 0, 100000, "steps between particle snapshots (0: the end only)",
                              &s->snapshot_every));
  TL_CHECK(tl_options_get_string(*o, "-output_dir", "results/nhl_element_test", "output folder", &s->out));
  TL_CHECK(tl_options_finish(*o, stdout));
  if (s->triaxial && s->dim != 3) TL_ERROR(TL_ERR_ARG, "-path triaxial needs -cells 3d (given 2d)");
  if (s->packing_fcc && s->dim != 3) TL_ERROR(TL_ERR_ARG, "-packing fcc is a 3-D lattice: use -cells 3d");
  if (s->p.radius_min > s->p.radius_max)
    TL_ERROR(TL_ERR_ARG, "-radius_min %g m exceeds -radius_max %g m", s->p.radius_min, s->p.radius_max);
  if (s->lateral == 0.0) s->lateral = s->p.pressure;
  s->p.kind = s->packing_fcc ? "fcc" : "random";
  s->p.dim = s->dim;
  s->p.n = s->n;
  s->p.n_side = s->n_side;
  s->p.seed = s->seed;
  /* the operators to compare */
  s->n_compare = 0;
  if (!strcmp(s->compare, "all")) {
    for (size_t k = 0;; ++k) {
      const TlTypeEntry *e = tl_registry_entry("nhl_operator", k);
      if (!e) break;
      if (s->n_compare < MAX_COMPARE) snprintf(s->compare_names[s->n_compare++], 32, "%s", e->name);
    }
  } else {
    const char *c = s->compare;
    while (*c) {
      size_t len = strcspn(c, ",");
      if (len == 0 || len >= 32) TL_ERROR(TL_ERR_ARG, "-compare '%s': empty or over-long name", s->compare);
      if (s->n_compare == MAX_COMPARE) TL_ERROR(TL_ERR_ARG, "-compare: at most %d operators", MAX_COMPARE);
      memcpy(s->compare_names[s->n_compare], c, len);
      s->compare_names[s->n_compare++][len] = 0;
      c += len;
      if (*c == ',') ++c;
    }
  }
  return TL_OK;
}

/* Voigt moduli of the current configuration from D (dσ = C : d). */
static void moduli(const double D[36], TlMat3 F, TlMat3 sigma, double C[36])
{
  double c[81];
  tl_nhl_operator_from_D(D, F, sigma, c);
  tl_nhl_operator_voigt(c, C);
}

static TlStatus write_cell(TlParticleWriter *w, TlNhlCell *cell, long step)
{
  TlDem *dem = tl_nhl_cell_dem(cell);
  TlParticles *P = tl_dem_particles(dem);
  TlParticleView view;
  tl_particle_view_of(P, &view); /* with ids and species */
  return tl_particle_writer_write(w, step, tl_dem_time(dem), &view);
}

static TlStatus run(int argc, char **argv)
{
  const double wall0 = tl_wtime();
  TlOptions *o = NULL;
  Settings s;
  TlStatus st = options(argc, argv, &o, &s);
  if (st != TL_OK) {
    tl_options_destroy(&o);
    return st;
  }
  TlMaterial *m = NULL;
  TlNhlOperator *cmp[MAX_COMPARE] = {NULL};
  double *so = NULL, *sn = NULL;
  TlTimeSeries *ts = NULL;
  TlParticleWriter *pw = NULL;
  TL_CHECK_GOTO(st, tl_material_create("dem_cell", &m), done);
  TL_CHECK_GOTO(st, tl_material_set(m, "inertial", s.inertial), done);
  TL_CHECK_GOTO(st, tl_material_set(m, "tolerance", s.tolerance), done);
  TL_CHECK_GOTO(st, tl_material_set(m, "max_relax_steps", s.max_relax), done);
  TL_CHECK_GOTO(st, tl_material_set(m, "permissive", s.permissive), done);
  double t0 = tl_wtime();
  TL_CHECK_GOTO(st, tl_nhl_material_set_packing(m, &s.p), done);
  const double t_prepare = tl_wtime() - t0;
  TL_CHECK_GOTO(st, tl_nhl_material_set_operator(m, s.op), done);
  TL_CHECK_GOTO(st, tl_nhl_operator_set(tl_nhl_material_operator(m), "eps", s.eps), done);
  TL_CHECK_GOTO(st, tl_nhl_operator_set(tl_nhl_material_operator(m), "directions", s.directions), done);
  for (int k = 0; k < s.n_compare; ++k) {
    TL_CHECK_GOTO(st, tl_nhl_operator_create(s.compare_names[k], &cmp[k]), done);
    TL_CHECK_GOTO(st, tl_nhl_operator_set(cmp[k], "eps", s.eps), done);
    TL_CHECK_GOTO(st, tl_nhl_operator_set(cmp[k], "directions", s.directions), done);
    TL_CHECK_GOTO(st, tl_nhl_operator_setup(cmp[k]), done);
  }
  TL_CHECK_GOTO(st, tl_material_setup(m), done);
  const size_t ss = m->state_size;
  TL_CHECK_GOTO(st, tl_calloc(&so, ss, sizeof *so), done);
  TL_CHECK_GOTO(st, tl_calloc(&sn, ss, sizeof *sn), done);
  TL_CHECK_GOTO(st, m->ops->init_state(m, 1, so), done);
  TlNhlCell *cell = tl_nhl_material_cell(m, 0);
  const TlMat3 sigma0 = tl_nhl_cell_committed_stress(cell);
  tl_printf("nhl_element_test: %s cell of %zu %s prepared in %.2f s: sigma_0 = [%.5g %.5g %.5g] Pa, <d> %.4g m, dt %.3g s; "
            "%s path to %g axial strain in %ld steps, lateral %g Pa; operator %s\n",
            s.dim == 2 ? "2-D" : "3-D", tl_nhl_cell_n_particles(cell), s.dim == 2 ? "disks" : "spheres", t_prepare,
            sigma0.m[0][0], sigma0.m[1][1], sigma0.m[2][2], tl_nhl_cell_mean_diameter(cell),
            tl_dem_timestep(tl_nhl_cell_dem(cell)), s.triaxial ? "triaxial" : "biaxial", s.strain, s.steps, s.lateral, s.op);
  TL_CHECK_GOTO(st, tl_mkdir_p(s.out), done);
  /* the table */
  enum { BASE_COLS = 16, MOD = 4 };
  TlColumn cols[BASE_COLS + MOD * (MAX_COMPARE + 1)];
  static const TlColumn base[BASE_COLS] = {
      {"step", ""},         {"eps_axial", ""},  {"eps_lateral", ""}, {"eps_volume", ""},
      {"sigma_11", "Pa"},   {"sigma_22", "Pa"}, {"sigma_33", "Pa"},  {"sigma_12", "Pa"},
      {"q", "Pa"},          {"p", "Pa"},        {"lateral_its", ""}, {"dem_steps", ""},
      {"seconds", "s"},     {"imbalance", ""},  {"tau", "s"},        {"kinetic_ratio", ""}};
  memcpy(cols, base, sizeof base);
  char names[MOD * (MAX_COMPARE + 1)][48];
  static const char *const mod_names[MOD] = {"C1111", "C2222", "C1122", "C1212"};
  int ncol = BASE_COLS;
  for (int k = 0; k <= s.n_compare; ++k)
    for (int q = 0; q < MOD; ++q) {
      snprintf(names[ncol - BASE_COLS], sizeof names[0], "%s_%s", k == 0 ? s.op : s.compare_names[k - 1], mod_names[q]);
      cols[ncol].name = names[ncol - BASE_COLS];
      cols[ncol].unit = "Pa";
      ncol++;
    }
  char base_path[4096];
  snprintf(base_path, sizeof base_path, "%s/path", s.out);
  TL_CHECK_GOTO(st, tl_timeseries_create(base_path, TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, (size_t)ncol, cols, &ts), done);
  TL_CHECK_GOTO(st, tl_particle_writer_create(s.out, "cell", &pw), done);
  TL_CHECK_GOTO(st, write_cell(pw, cell, 0), done);
  tl_printf("%5s %10s %10s %12s %12s %12s %3s %8s %7s | %s: %10s %10s %10s %10s\n", "step", "eps_11", "eps_22", "sigma_11",
            "sigma_22", "q", "its", "DEM", "s", s.op, "C1111", "C2222", "C1122", "C1212");
  double lam_l = 1.0, q_peak = 0.0, eps_peak = 0.0, eval_seconds = 0.0, last_q = 0.0, last_p = 0.0;
  long evaluations = 0, dem_steps = 0, unconverged_lateral = 0, unconverged_cells = 0;
  TlMat3 sigma = sigma0, F = tl_m3_identity();
  for (long k = 1; k <= s.steps; ++k) {
    const double lam_a = 1.0 - s.strain * (double)k / (double)s.steps;
    TlMat3 S;
    double D[36], r = 0.0;
    long its = 0, step_dem = 0;
    double step_seconds = 0.0;
    int ok = 0;
    for (its = 1; its <= s.max_lateral; ++its) {
      F = tl_m3_identity();
      F.m[0][0] = lam_a, F.m[1][1] = lam_l;
      if (s.triaxial) F.m[2][2] = lam_l;
      TL_CHECK_GOTO(st, tl_material_evaluate(m, 1, &F, so, sn, &S, D, NULL), done);
      evaluations++;
      step_dem += (long)sn[TL_NHL_STATE_DEM_STEPS];
      step_seconds += sn[TL_NHL_STATE_SECONDS];
      sigma = tl_nhl_pk2_to_cauchy(F, S);
      /* lateral stress error and its derivative in lam_l from D (dE_22 = lam_l dlam_l) */
      double dsig;
      if (s.triaxial) {
        r = 0.5 * (sigma.m[1][1] + sigma.m[2][2]) + s.lateral;
        dsig = lam_l * (D[1 * 6 + 1] + D[1 * 6 + 2] + D[2 * 6 + 1] + D[2 * 6 + 2]) / (2.0 * lam_a);
      } else {
        r = sigma.m[1][1] + s.lateral;
        dsig = S.m[1][1] / lam_a + lam_l * lam_l * D[1 * 6 + 1] / lam_a;
      }
      if (fabs(r) <= s.lateral_tolerance * s.lateral) {
        ok = 1;
        break;
      }
      if (its == s.max_lateral) break;
      if (!(fabs(dsig) > 0.0) || !isfinite(dsig)) {
        st = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__,
                          "step %ld: the operator %s gives no lateral stiffness (d sigma_22 / d lambda = %g Pa)", k, s.op,
                          dsig);
        goto done;
      }
      double dl = -r / dsig;
      dl = fmax(-0.01, fmin(0.01, dl));
      lam_l += dl;
    }
    unconverged_lateral += !ok;
    unconverged_cells += sn[TL_NHL_STATE_IMBALANCE] >= s.tolerance && s.permissive < 0.5;
    dem_steps += step_dem;
    eval_seconds += step_seconds;
    double C[36];
    moduli(D, F, sigma, C);
    double row[BASE_COLS + MOD * (MAX_COMPARE + 1)];
    /* deviator: lateral minus axial (positive in axial compression) */
    const double q = sigma.m[1][1] - sigma.m[0][0];
    const double p = s.dim == 2 ? -0.5 * (sigma.m[0][0] + sigma.m[1][1]) : -tl_m3_trace(sigma) / 3.0;
    TlNhlPointStats ps;
    TL_CHECK_GOTO(st, tl_nhl_material_point_stats(m, 0, &ps), done);
    row[0] = (double)k, row[1] = lam_a - 1.0, row[2] = lam_l - 1.0;
    row[3] = lam_a * lam_l * (s.triaxial ? lam_l : 1.0) - 1.0;
    row[4] = sigma.m[0][0], row[5] = sigma.m[1][1], row[6] = sigma.m[2][2], row[7] = sigma.m[0][1];
    row[8] = q, row[9] = p, row[10] = (double)its, row[11] = (double)step_dem, row[12] = step_seconds;
    row[13] = sn[TL_NHL_STATE_IMBALANCE], row[14] = ps.path.tau, row[15] = ps.path.kinetic_ratio;
    int col = BASE_COLS;
    row[col++] = C[0], row[col++] = C[7], row[col++] = C[1], row[col++] = C[21];
    tl_printf("%5ld %10.3e %10.3e %12.5e %12.5e %12.5e %3ld %8ld %7.2f | %10.4e %10.4e %10.4e %10.4e\n", k, lam_a - 1.0,
              lam_l - 1.0, sigma.m[0][0], sigma.m[1][1], q, its, step_dem, step_seconds, C[0], C[7], C[1], C[21]);
    for (int c = 0; c < s.n_compare; ++c) {
      double cc[81], Cc[36];
      TlNhlOperatorStats ost;
      TL_CHECK_GOTO(st, tl_nhl_material_compare(m, 0, cmp[c], cc, &ost), done);
      tl_nhl_operator_voigt(cc, Cc);
      row[col++] = Cc[0], row[col++] = Cc[7], row[col++] = Cc[1], row[col++] = Cc[21];
      tl_printf("%*s %-10s: %10.4e %10.4e %10.4e %10.4e  (%d evaluations, %.2f s)\n", 78, "", cmp[c]->ops->header.name,
                Cc[0], Cc[7], Cc[1], Cc[21], ost.evaluations, ost.seconds);
    }
    TL_CHECK_GOTO(st, tl_timeseries_append(ts, row), done);
    /* accept the step */
    TL_CHECK_GOTO(st, m->ops->commit(m, 1, sn), done);
    memcpy(so, sn, ss * sizeof *so);
    if (q > q_peak) q_peak = q, eps_peak = 1.0 - lam_a;
    last_q = q, last_p = p;
    if (s.snapshot_every > 0 && k % s.snapshot_every == 0) TL_CHECK_GOTO(st, write_cell(pw, cell, k), done);
  }
  if (s.snapshot_every == 0 || s.steps % s.snapshot_every) TL_CHECK_GOTO(st, write_cell(pw, cell, s.steps), done);
  TL_CHECK_GOTO(st, tl_timeseries_close(&ts), done);
  tl_printf("peak deviator %.6g Pa at axial strain %.4g; %ld evaluations, %ld DEM steps, %.3f s per evaluation, "
            "%.3g s per particle-step\n", q_peak, eps_peak, evaluations, dem_steps, eval_seconds / (double)evaluations,
            eval_seconds / ((double)dem_steps * (double)tl_nhl_cell_n_particles(cell)));
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "particles", (long)tl_nhl_cell_n_particles(cell));
  tl_summary_int(&sum, "steps", s.steps);
  tl_summary_real(&sum, "q_final", last_q);
  tl_summary_real(&sum, "p_final", last_p);
  tl_summary_real(&sum, "q_peak", q_peak);
  tl_summary_real(&sum, "eps_peak", eps_peak);
  tl_summary_int(&sum, "evaluations", evaluations);
  tl_summary_int(&sum, "dem_steps", dem_steps);
  tl_summary_real(&sum, "seconds_per_evaluation", eval_seconds / (double)evaluations);
  tl_summary_int(&sum, "lateral_unconverged", unconverged_lateral);
  tl_summary_int(&sum, "cells_unconverged", unconverged_cells);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  st = tl_summary_print(&sum, stdout);
done:
  tl_timeseries_close(&ts);
  tl_particle_writer_destroy(&pw);
  for (int k = 0; k < MAX_COMPARE; ++k) tl_nhl_operator_destroy(&cmp[k]);
  tl_free(&so);
  tl_free(&sn);
  tl_material_destroy(&m);
  tl_options_destroy(&o);
  return st;
}

int main(int argc, char **argv)
{
  TlStatus s = tl_initialize();
  if (s == TL_OK) s = run(argc, argv);
  return tl_driver_exit(s);
}
