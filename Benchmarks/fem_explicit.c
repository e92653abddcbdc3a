/* Cost of an explicit step on the finite-strain solid, per element, for
 * Hex8 and Hex27, against a flop-count bound.
 *
 * Flop count of the total-Lagrangian internal force per Gauss point of an
 * element with n nodes (reference gradients dN/dX precomputed):
 *   H = sum_a u_a (x) dN_a                  18 n   (9 multiply-adds per node)
 *   F = 1 + H, C = F^T F (6 entries)         33
 *   gamma = (C - 1)/2                        12
 *   Hooke, Eq. 34 with M = C^-1:
 *     C^-1 (cofactors, determinant)          40
 *     M gamma M (two 3x3 products)           90
 *     trace term c2 (M : gamma) M            30
 *   P = F S                                  45
 *   weight P by w det J                       9
 *   f_a += P dN_a                            18 n
 * = 36 n + 259 per Gauss point:
 *   Hex8  (n = 8,  8 points):  8 x 547  =  4 376 flops per element,
 *   Hex27 (n = 27, 27 points): 27 x 1231 = 33 237 flops per element.
 * The vector updates of the central-difference step add ~10 flops per dof.
 * The bound is that count divided by the rate this compiler reaches on an
 * in-cache dense kernel of the same shape (3x3 and 3xn products, measured
 * here, single core): the best the element loop could do without
 * hand-vectorisation.  The ratio measured / bound is printed (target < 3).
 * Timings are the best of repeated rounds, since the machine may be shared.
 *
 * The body: a free cube of n^3 cells (E = 100 MPa, nu = 0, rho = 1309),
 * random small initial velocities, central difference at half the
 * critical step (the solid's element bound). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_element.h"
#include "tl_material.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_stepper.h"

/* Attainable flop rate: many independent 3x3 by 3xN products in cache;
 * the best of five timings (the machine may be shared). */
static double measure_flop_rate(void)
{
  enum { N = 27, REPS = 1000000 };
  static double A[9], B[3 * N], Cm[3 * N];
  for (int i = 0; i < 9; ++i) A[i] = 1.0 + 1e-3 * i;
  for (int i = 0; i < 3 * N; ++i) B[i] = 1e-3 * i;
  double best = HUGE_VAL;
  for (int trial = 0; trial < 5; ++trial) {
    double t0 = tl_wtime();
    for (int r = 0; r < REPS; ++r) {
      for (int j = 0; j < N; ++j)
        for (int i = 0; i < 3; ++i)
          Cm[3 * j + i] = A[3 * i] * B[3 * j] + A[3 * i + 1] * B[3 * j + 1] + A[3 * i + 2] * B[3 * j + 2];
      B[r % (3 * N)] += 1e-12 * Cm[(r * 7) % (3 * N)]; /* keep the loop alive */
    }
    best = fmin(best, tl_wtime() - t0);
  }
  volatile double sink = Cm[0];
  (void)sink;
  return (double)REPS * N * 3 * 5 / best;
}

typedef struct {
  const char *name;
  double flops_per_element;
  double ns_force, ns_step, ratio;
  size_t elements;
  long long dofs;
} Result;

static TlStatus bench(const TlElementType *type, long n, long steps, double rate, Result *r)
{
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TlStepper *st = NULL;
  double *v0 = NULL, *f = NULL;
  TlStatus s = TL_OK;
  const size_t cells[3] = {(size_t)n, (size_t)n, (size_t)n};
  const double lo[3] = {0, 0, 0}, hi[3] = {0.4 * n, 0.4 * n, 0.4 * n};
  TL_CHECK_GOTO(s, tl_mesh_create_box(type, cells, lo, hi, &mesh), done);
  TL_CHECK_GOTO(s, tl_material_create_hooke(1e8, 0.0, 1309.0, &mat), done);
  TL_CHECK_GOTO(s, tl_solid_create(mesh, &solid), done);
  TL_CHECK_GOTO(s, tl_solid_set_material(solid, NULL, mat), done);
  TL_CHECK_GOTO(s, tl_solid_setup(solid), done);
  TlMechSystem *sys = tl_solid_system(solid);
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  so.critical_bound = 1;
  TL_CHECK_GOTO(s, tl_stepper_create("central_difference", sys, &so, &st), done);
  TL_CHECK_GOTO(s, tl_calloc(&v0, (size_t)sys->ndof, sizeof *v0), done);
  TL_CHECK_GOTO(s, tl_calloc(&f, (size_t)sys->ndof, sizeof *f), done);
  unsigned seed = 12345;
  for (TlSparseIndex i = 0; i < sys->ndof; ++i) {
    seed = seed * 1664525u + 1013904223u;
    v0[i] = 1e-3 * ((double)(seed >> 8) / (double)(1u << 24) - 0.5);
  }
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, v0), done);
  double dt = 0.5 * st->dt_crit;
  r->elements = mesh->blocks[0].n_elements;
  r->dofs = (long long)sys->ndof;
  /* Internal force alone, then whole explicit steps; best of three rounds
   * of `steps` (the machine may be shared). */
  double best_f = HUGE_VAL, best_s = HUGE_VAL;
  for (int round = 0; round < 3; ++round) {
    double t0 = tl_wtime();
    for (long k = 0; k < steps; ++k)
      TL_CHECK_GOTO(s, sys->ops->internal_force(sys, 0.0, st->u, st->v, f), done);
    best_f = fmin(best_f, tl_wtime() - t0);
    t0 = tl_wtime();
    for (long k = 0; k < steps; ++k) TL_CHECK_GOTO(s, tl_stepper_step(st, dt), done);
    best_s = fmin(best_s, tl_wtime() - t0);
  }
  r->ns_force = 1e9 * best_f / ((double)steps * (double)r->elements);
  r->ns_step = 1e9 * best_s / ((double)steps * (double)r->elements);
  r->name = type->header.name;
  int nn = type->n_nodes;
  r->flops_per_element = (double)nn * (36.0 * nn + 259.0);
  r->ratio = r->ns_step / (1e9 * r->flops_per_element / rate);
done:
  tl_free(&v0);
  tl_free(&f);
  tl_stepper_destroy(&st);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
  return s;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv,
                             "ns per Hex8 and Hex27 element per explicit step, against a flop-count "
                             "bound.",
                             &o));
  long n8, n27, steps, threads;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-n8", 20, 1, 500, "Hex8 cube: cells per side", &n8), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-n27", 10, 1, 250, "Hex27 cube: cells per side", &n27), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-steps", 50, 1, 1000000, "timed steps", &steps), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-threads", 1, 1, 256, "OpenMP threads", &threads), done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  omp_set_num_threads((int)threads);
  double wall0 = tl_wtime(), rate = measure_flop_rate();
  printf("attainable rate of compiled 3x3 x 3xN products: %.2f Gflop/s\n", rate * 1e-9);
  Result r[2];
  TL_CHECK_GOTO(s, bench(&tl_element_hex8, n8, steps, rate, &r[0]), done);
  TL_CHECK_GOTO(s, bench(&tl_element_hex27, n27, steps, rate, &r[1]), done);
  TlSummary sum;
  tl_summary_init(&sum);
  for (int i = 0; i < 2; ++i) {
    double bound = 1e9 * r[i].flops_per_element / rate;
    printf("%-6s %zu elements, %lld dofs: internal force %.0f ns/element, explicit step %.0f "
           "ns/element; bound %.0f ns (%.0f flops); ratio %.2f (%d thread%s)\n",
           r[i].name, r[i].elements, r[i].dofs, r[i].ns_force, r[i].ns_step, bound,
           r[i].flops_per_element, r[i].ratio, (int)threads, threads > 1 ? "s" : "");
    char key[64];
    snprintf(key, sizeof key, "%s_ns", r[i].name);
    tl_summary_real(&sum, key, r[i].ns_step);
    snprintf(key, sizeof key, "%s_ratio", r[i].name);
    tl_summary_real(&sum, key, r[i].ratio);
  }
  tl_summary_real(&sum, "gflops", rate * 1e-9);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  s = tl_summary_print(&sum, stdout);
done:
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
