/* Talus against CalculiX on the same beam, mesh and load steps, in one
 * invocation:
 *
 *  static:  the S1 cantilever (Hex8 / C3D8, 2 x 2 x 30) under a dead tip
 *           load P = k E I / L^2 in n equal load increments, geometrically
 *           nonlinear (Talus quasi-static Newton; CalculiX *STATIC with
 *           NLGEOM and fixed increments);
 *  dynamic: the same beam, the tip load applied suddenly at t = 0, Newmark
 *           beta = 1/4, gamma = 1/2 with the same step (CalculiX *DYNAMIC,
 *           ALPHA = 0, i.e. HHT reduced to that Newmark rule), consistent
 *           mass in both.
 *
 * Both codes get identical nodal loads (consistent weights of a uniform
 * shear traction on the tip face) and report the weighted mean tip
 * displacement.  Materials: Talus "hooke" (seeds/001 Eq. 34), CalculiX
 * linear elastic under NLGEOM (St. Venant-Kirchhoff); with nu = 0 they
 * agree to first order in the strain.  ccx runs single-threaded, as Talus.
 * When ccx is missing and the program runs as root it installs the Debian
 * package calculix-ccx. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "talus.h"
#include "tl_atomic_file.h"
#include "tl_cantilever.h"
#include "tl_stepper.h"

typedef struct {
  const TlCantilever *beam;
  int dynamic;
  long increments;
  double dt, t_end;
} Deck;

static TlStatus write_deck(FILE *f, void *ctx)
{
  const Deck *d = ctx;
  const TlMesh *m = d->beam->mesh;
  const TlCantileverParams *p = &d->beam->p;
  fprintf(f, "** Talus fem_vs_calculix: S1 cantilever, %s\n*NODE, NSET=NALL\n",
          d->dynamic ? "sudden tip load, Newmark" : "static tip load, NLGEOM");
  for (size_t i = 0; i < m->n_nodes; ++i)
    fprintf(f, "%zu, %.17g, %.17g, %.17g\n", i + 1, m->x[3 * i], m->x[3 * i + 1], m->x[3 * i + 2]);
  const TlElementBlock *b = &m->blocks[0];
  fprintf(f, "*ELEMENT, TYPE=C3D8, ELSET=EALL\n");
  for (size_t e = 0; e < b->n_elements; ++e) {
    fprintf(f, "%zu", e + 1);
    for (int a = 0; a < 8; ++a) fprintf(f, ", %zu", b->conn[8 * e + a] + 1);
    fprintf(f, "\n");
  }
  const TlNodeSet *fix = NULL;
  TL_CHECK(tl_mesh_find_node_set(m, "ymin", &fix));
  fprintf(f, "*NSET, NSET=FIX\n");
  for (size_t k = 0; k < fix->n; ++k) fprintf(f, "%zu,\n", fix->nodes[k] + 1);
  fprintf(f, "*NSET, NSET=TIP\n");
  for (size_t k = 0; k < d->beam->n_tip; ++k) fprintf(f, "%zu,\n", d->beam->tip_nodes[k] + 1);
  fprintf(f, "*BOUNDARY\nFIX, 1, 3\n*MATERIAL, NAME=BEAM\n*ELASTIC\n%.17g, %.17g\n*DENSITY\n%.17g\n",
          p->E, p->nu, p->rho);
  fprintf(f, "*SOLID SECTION, ELSET=EALL, MATERIAL=BEAM\n");
  if (d->dynamic) {
    fprintf(f, "*AMPLITUDE, NAME=ON\n0., 1., 1e6, 1.\n");
    fprintf(f, "*STEP, NLGEOM, INC=1000000\n*DYNAMIC, ALPHA=0.0, DIRECT\n%.17g, %.17g\n", d->dt,
            d->t_end);
    fprintf(f, "*CLOAD, AMPLITUDE=ON\n");
  } else {
    fprintf(f, "*STEP, NLGEOM, INC=1000000\n*STATIC, DIRECT\n%.17g, 1.0\n",
            1.0 / (double)d->increments);
    fprintf(f, "*CLOAD\n");
  }
  for (size_t k = 0; k < d->beam->n_tip; ++k)
    fprintf(f, "%zu, 3, %.17g\n", d->beam->tip_nodes[k] + 1, -p->load * d->beam->tip_weight[k]);
  fprintf(f, "*NODE PRINT, NSET=TIP\nU\n*END STEP\n");
  return TL_OK;
}

/* The last "displacements ... for set TIP" block of a .dat file, weighted
 * like tl_cantilever_tip(). */
static TlStatus read_tip(const char *dat, const TlCantilever *beam, double out[3], double *time)
{
  FILE *f = fopen(dat, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "CalculiX wrote no %s", dat);
  char line[512];
  int in_block = 0, blocks = 0;
  double acc[3] = {0, 0, 0};
  while (fgets(line, sizeof line, f)) {
    if (strstr(line, "displacements") && strstr(line, "TIP")) {
      const char *t = strstr(line, "time");
      *time = t ? atof(t + 4) : NAN;
      in_block = 1;
      acc[0] = acc[1] = acc[2] = 0.0;
      ++blocks;
      continue;
    }
    if (!in_block) continue;
    long node;
    double u[3];
    if (sscanf(line, "%ld %lf %lf %lf", &node, &u[0], &u[1], &u[2]) == 4) {
      for (size_t k = 0; k < beam->n_tip; ++k)
        if (beam->tip_nodes[k] + 1 == (size_t)node)
          for (int d = 0; d < 3; ++d) acc[d] += beam->tip_weight[k] * u[d];
    } else if (line[0] != '\n' && line[0] != '\r') {
      in_block = 0;
    }
    memcpy(out, acc, sizeof acc);
  }
  fclose(f);
  if (!blocks) TL_ERROR(TL_ERR_FORMAT, "no tip displacements in %s", dat);
  return TL_OK;
}

static TlStatus ensure_ccx(void)
{
  if (system("command -v ccx > /dev/null 2>&1") == 0) return TL_OK;
  if (geteuid() != 0)
    TL_ERROR(TL_ERR_UNSUPPORTED, "CalculiX (ccx) is not installed; as root: apt-get install -y calculix-ccx");
  printf("installing calculix-ccx ...\n");
  fflush(stdout);
  if (system("apt-get install -y calculix-ccx > /dev/null 2>&1") != 0 ||
      system("command -v ccx > /dev/null 2>&1") != 0)
    TL_ERROR(TL_ERR_UNSUPPORTED, "apt-get install calculix-ccx failed");
  return TL_OK;
}

static TlStatus run_ccx(const char *dir, const char *job, const Deck *deck, double tip[3],
                        double *wall)
{
  char *inp = NULL, *dat = NULL, name[64], cmd[1024];
  snprintf(name, sizeof name, "%s.inp", job);
  TL_CHECK(tl_path_join(dir, name, &inp));
  TlStatus s = tl_atomic_write(inp, write_deck, (void *)deck);
  tl_free(&inp);
  TL_CHECK(s);
  snprintf(cmd, sizeof cmd, "cd '%s' && OMP_NUM_THREADS=1 CCX_NPROC_EQUATION_SOLVER=1 ccx -i %s > %s.log 2>&1",
           dir, job, job);
  double t0 = tl_wtime();
  int rc = system(cmd);
  *wall = tl_wtime() - t0;
  if (rc != 0) TL_ERROR(TL_ERR_IO, "ccx failed (exit %d); see %s/%s.log", rc, dir, job);
  snprintf(name, sizeof name, "%s.dat", job);
  TL_CHECK(tl_path_join(dir, name, &dat));
  double t = 0;
  s = read_tip(dat, deck->beam, tip, &t);
  tl_free(&dat);
  return s;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv,
                             "The S1 cantilever in Talus and in CalculiX: static nonlinear and "
                             "Newmark dynamics on the same mesh and steps; times, answers, ratios.",
                             &o));
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  long nx, ny, increments, steps, threads;
  double k, periods;
  const char *dir;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-nx", 2, 1, 100, "cells across x and z", &nx), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-ny", 30, 1, 10000, "cells along the beam", &ny), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-load_parameter", 1.0, 0.0, 20.0, "",
                                       "static: P L^2 / (E I)", &k), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-increments", 10, 1, 10000, "static load increments", &increments), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-steps", 100, 1, 1000000, "dynamic: Newmark steps", &steps), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-periods", 0.5, 0.01, 100.0, "",
                                       "dynamic: duration in first-mode periods", &periods), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-threads", 1, 1, 256, "OpenMP threads for Talus", &threads), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-output_dir", "results/fem_vs_calculix", "output folder", &dir), done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  omp_set_num_threads((int)threads);
  TL_CHECK_GOTO(s, ensure_ccx(), done);
  TL_CHECK_GOTO(s, tl_mkdir_p(dir), done);
  p.nx = p.nz = (size_t)nx;
  p.ny = (size_t)ny;
  double I = p.b * p.h * p.h * p.h / 12.0;
  double small_load = p.load;
  p.load = k * p.E * I / (p.L * p.L);
  TlSummary sum;
  tl_summary_init(&sum);
  double wall0 = tl_wtime();

  /* ------------------------------------------------ static, NLGEOM */
  TlCantilever *beam = NULL;
  TlStepper *st = NULL;
  TL_CHECK_GOTO(s, tl_cantilever_create(&p, &beam), done);
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  so.ramp_time = 1.0;
  so.rtol = 1e-10;
  TL_CHECK_GOTO(s, tl_stepper_create("quasi_static", tl_solid_system(beam->solid), &so, &st), out);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), out);
  double t0 = tl_wtime();
  for (long i = 0; i < increments; ++i)
    TL_CHECK_GOTO(s, tl_stepper_step(st, 1.0 / (double)increments), out);
  double talus_static = tl_wtime() - t0, tip_t[3], tip_c[3], ccx_static = 0;
  tl_cantilever_tip(beam, st->u, tip_t);
  TlStepperStats ss;
  tl_stepper_get_stats(st, &ss);
  Deck deck = {beam, 0, increments, 0, 0};
  TL_CHECK_GOTO(s, run_ccx(dir, "static", &deck, tip_c, &ccx_static), out);
  double we, ve;
  TL_CHECK_GOTO(s, tl_cantilever_elastica(k, &we, &ve), out);
  printf("static, P L^2/(E I) = %g in %ld increments, %lld dofs:\n", k, increments, (long long)st->n);
  printf("  Talus    tip w = %.6f m, v = %.6f m, %.3f s (%ld Newton iterations)\n", -tip_t[2],
         -tip_t[1], talus_static, ss.newton_iterations);
  printf("  CalculiX tip w = %.6f m, v = %.6f m, %.3f s\n", -tip_c[2], -tip_c[1], ccx_static);
  printf("  difference w %+.3f %%, v %+.3f %%; elastica w = %.6f m; time ratio Talus/CalculiX %.3f\n",
         100.0 * (tip_t[2] - tip_c[2]) / tip_c[2], 100.0 * (tip_t[1] - tip_c[1]) / tip_c[1],
         we * p.L, talus_static / ccx_static);
  tl_summary_real(&sum, "static_talus_w", -tip_t[2]);
  tl_summary_real(&sum, "static_ccx_w", -tip_c[2]);
  tl_summary_real(&sum, "static_diff", (tip_t[2] - tip_c[2]) / tip_c[2]);
  tl_summary_real(&sum, "static_time_ratio", talus_static / ccx_static);
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&beam);

  /* ---------------------------------------------- dynamic, Newmark */
  p.load = small_load * 10.0;
  TL_CHECK_GOTO(s, tl_cantilever_create(&p, &beam), done);
  double T1 = 2.0 * M_PI / tl_cantilever_omega1(&p), t_end = periods * T1, dt = t_end / (double)steps;
  tl_stepper_options_default(&so);
  so.rtol = 1e-10;
  TL_CHECK_GOTO(s, tl_stepper_create("newmark", tl_solid_system(beam->solid), &so, &st), out);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), out);
  t0 = tl_wtime();
  for (long i = 0; i < steps; ++i) TL_CHECK_GOTO(s, tl_stepper_step(st, dt), out);
  double talus_dyn = tl_wtime() - t0, ccx_dyn = 0;
  tl_cantilever_tip(beam, st->u, tip_t);
  tl_stepper_get_stats(st, &ss);
  Deck deck2 = {beam, 1, 0, dt, t_end};
  TL_CHECK_GOTO(s, run_ccx(dir, "dynamic", &deck2, tip_c, &ccx_dyn), out);
  printf("dynamic, sudden tip load %g N, %ld Newmark steps of %.4g s (t = %.4g s):\n", p.load, steps,
         dt, t_end);
  printf("  Talus    tip w = %.6e m, %.3f s (%ld Newton iterations)\n", -tip_t[2], talus_dyn,
         ss.newton_iterations);
  printf("  CalculiX tip w = %.6e m, %.3f s\n", -tip_c[2], ccx_dyn);
  printf("  difference %+.3f %%; time ratio Talus/CalculiX %.3f\n",
         100.0 * (tip_t[2] - tip_c[2]) / tip_c[2], talus_dyn / ccx_dyn);
  tl_summary_real(&sum, "dynamic_talus_w", -tip_t[2]);
  tl_summary_real(&sum, "dynamic_ccx_w", -tip_c[2]);
  tl_summary_real(&sum, "dynamic_diff", (tip_t[2] - tip_c[2]) / tip_c[2]);
  tl_summary_real(&sum, "dynamic_time_ratio", talus_dyn / ccx_dyn);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  tl_summary_print(&sum, stdout);
out:
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&beam);
done:
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
