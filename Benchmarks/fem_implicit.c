/* Time per implicit Newmark step from 10^3 to 10^5 (optionally 10^6)
 * degrees of freedom, CHOLMOD, with and without reuse of the numeric
 * factorisation (modified Newton).
 *
 * The body: the S1 cantilever refined k times across (k x 15k x k Hex8
 * cells, 3 (k+1)^2 (15k+1) dofs), a sudden tip load of ten times S1's at
 * t = 0, Newmark (1/4, 1/2) with dt = T1/100.  Full Newton refactorises at
 * every iteration; "reuse" keeps the factors across iterations and steps
 * (KINSOL's max_setup_calls = -reuse) and refactorises only when KINSOL
 * asks for it. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_cantilever.h"
#include "tl_options_renamed.h"
#include "tl_stepper.h"

typedef struct {
  long long dofs;
  double step, factor_each, assembly;
  long iterations, factorisations, steps;
} Run;

static TlStatus one(long k, long steps, long reuse, double rtol, Run *r)
{
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.nx = p.nz = (size_t)k;
  p.ny = (size_t)(15 * k);
  p.load *= 10.0;
  TlCantilever *beam = NULL;
  TlStepper *st = NULL;
  TlStatus s = TL_OK;
  TL_CHECK(tl_cantilever_create(&p, &beam));
  TlStepperOptions so;
  tl_stepper_options_default(&so);
  so.solver = "cholmod";
  so.rtol = rtol;
  so.reuse = reuse;
  so.keep_factors = reuse > 1;
  so.max_iterations = reuse > 1 ? 200 : 30;
  TL_CHECK_GOTO(s, tl_stepper_create("newmark", tl_solid_system(beam->solid), &so, &st), done);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), done);
  double dt = 2.0 * M_PI / tl_cantilever_omega1(&p) / 100.0;
  double t0 = tl_wtime();
  for (long i = 0; i < steps; ++i) TL_CHECK_GOTO(s, tl_stepper_step(st, dt), done);
  double t = tl_wtime() - t0;
  TlStepperStats ss;
  tl_stepper_get_stats(st, &ss);
  r->dofs = (long long)st->n;
  r->steps = steps;
  r->step = t / (double)steps;
  r->iterations = ss.newton_iterations;
  r->factorisations = ss.factorisations;
  r->factor_each = ss.factorisations ? ss.t_factor / (double)ss.factorisations : 0.0;
  r->assembly = (ss.t_residual + ss.t_jacobian) / (double)steps;
done:
  tl_stepper_destroy(&st);
  tl_cantilever_destroy(&beam);
  return s;
}

/* The refinement whose dof count is nearest the target (in ratio). */
static long k_for(double dofs)
{
  long best = 1;
  for (long k = 1; k < 200; ++k) {
    double n = 3.0 * (k + 1) * (k + 1) * (15.0 * k + 1), nb = 3.0 * (best + 1) * (best + 1) * (15.0 * best + 1);
    if (fabs(log(n / dofs)) < fabs(log(nb / dofs))) best = k;
  }
  return best;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv,
                             "Time per Newmark step (CHOLMOD) from 1e3 to 1e5 dofs (1e6 with "
                             "-with_1e6), full Newton against factorisation reuse.",
                             &o));
  double sizes[8];
  int n_sizes = 0, with_1e6 = 0;
  long steps, reuse, threads;
  double rtol;
  TlStatus s = TL_OK;
  static const TlRenamedOption renamed[] = {{"-rtol", "-newton_rtol", NULL}};
  TL_CHECK_GOTO(s, tl_options_refuse_renamed(o, renamed, 1), done);
  TL_CHECK_GOTO(s, tl_options_get_real_list(o, "-dofs", "1e3,1e4,1e5", "", "target sizes (dofs)",
                                            sizes, 7, &n_sizes), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-with_1e6", 0, "add the 1e6-dof case (memory, time)", &with_1e6), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-steps", 3, 1, 100000, "Newmark steps per case", &steps), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-reuse", 20, 2, 100000, "modified Newton: iterations per factorisation", &reuse), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-newton_rtol", 1e-8, 1e-14, 1e-2, "", "Newton tolerance relative to the force scale", &rtol), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-threads", 1, 1, 256, "OpenMP threads", &threads), done);
  TL_CHECK_GOTO(s, tl_options_finish(o, stdout), done);
  omp_set_num_threads((int)threads);
  if (with_1e6) sizes[n_sizes++] = 1e6;
  TlSummary sum;
  tl_summary_init(&sum);
  double wall0 = tl_wtime();
  printf("%10s %6s | %-44s | %-44s | %s\n", "dofs", "cells", "full Newton: s/step  its  fact  s/fact",
         "reuse: s/step  its  fact  s/fact", "speed-up");
  for (int i = 0; i < n_sizes; ++i) {
    long k = k_for(sizes[i]);
    Run full, mod;
    TL_CHECK_GOTO(s, one(k, steps, 1, rtol, &full), done);
    TL_CHECK_GOTO(s, one(k, steps, reuse, rtol, &mod), done);
    printf("%10lld %2ldx%ld | %10.4f %5ld %5ld %9.4f %11s | %10.4f %5ld %5ld %9.4f %11s | %.2f\n",
           full.dofs, k, 15 * k, full.step, full.iterations, full.factorisations, full.factor_each, "",
           mod.step, mod.iterations, mod.factorisations, mod.factor_each, "", full.step / mod.step);
    fflush(stdout);
    char key[64];
    snprintf(key, sizeof key, "full_%lld", full.dofs);
    tl_summary_real(&sum, key, full.step);
    snprintf(key, sizeof key, "reuse_%lld", mod.dofs);
    tl_summary_real(&sum, key, mod.step);
  }
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  s = tl_summary_print(&sum, stdout);
done:
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
