/* What the FE bars of the bridging-domain gouge (seeds/000 §5, S-B2) cost
 * per step of the paper's single time step (dt = 1e-8 s, the DEM's), on
 * the finite-strain solid (the paper's path) and on its linearisation
 * about the pre-stressed rest state (tl_mech_linear.h: K assembled once),
 * in the same invocation: ratio = linear / solid.
 *
 * The bars: the scripts' two FE meshes, section 2 a (a = 0.0349 m, the
 * replicated 11.64 d0 cell), length 36 elements of 12 d0 (1.296 m) each,
 * h = a (2 x 2 in the section) or a / 4 (8 x 8, the paper's 3 d0), Table 2
 * continuum with the 0.0025 eigenstrain, periodic in x and z (solid ties),
 * ends held in y; random small initial velocities.  One bar is timed; the
 * scene has two.  Also printed: the FE critical step against the paper's
 * 1e-8 s (the factor a sub-cycled FE could gain). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "talus.h"
#include "tl_element.h"
#include "tl_material.h"
#include "tl_mech_linear.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_solid_tie.h"
#include "tl_stepper.h"
#include "tl_memory.h"
#include "tl_timer.h"

static TlStatus bar_time(int per_cell, int linear, int steps, double *us, double *dt_crit, size_t *ndof)
{
  const double a = 0.0349, L = 2 * a, len = 36 * a;
  size_t n[3] = {(size_t)(2 * per_cell), (size_t)(36 * per_cell), (size_t)(2 * per_cell)};
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TlMechSystem *lin = NULL;
  TlStepper *st = NULL;
  double *v = NULL;
  TL_CHECK(tl_mesh_create_box(&tl_element_hex8, n, (double[3]){0, 0, 0}, (double[3]){L, len, L}, &mesh));
  TlStatus s = tl_material_create("saint_venant_kirchhoff", &mat);
  if (s == TL_OK) s = tl_material_set(mat, "E", 0.977e9);
  if (s == TL_OK) s = tl_material_set(mat, "nu", 0.255);
  if (s == TL_OK) s = tl_material_set(mat, "density", 1643.0);
  if (s == TL_OK) s = tl_material_set_eigenstrain(mat, (TlMat3){{{0.0025, 0, 0}, {0, 0.0025, 0}, {0, 0, 0.0025}}});
  if (s == TL_OK) s = tl_solid_create(mesh, &solid);
  if (s == TL_OK) s = tl_solid_set_material(solid, NULL, mat);
  if (s == TL_OK) s = tl_solid_tie(solid, "xmin", "xmax", (double[3]){L, 0, 0}, 1e-9);
  if (s == TL_OK) s = tl_solid_tie(solid, "zmin", "zmax", (double[3]){0, 0, L}, 1e-9);
  if (s == TL_OK) s = tl_solid_fix(solid, "ymin", 2);
  if (s == TL_OK) s = tl_solid_fix(solid, "ymax", 2);
  if (s == TL_OK) s = tl_solid_setup(solid);
  TlMechSystem *sys = s == TL_OK ? tl_solid_system(solid) : NULL;
  if (s == TL_OK && linear) {
    s = tl_mech_linear_create(sys, 0.0, NULL, 0, &lin);
    sys = lin;
  }
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  if (s == TL_OK) s = tl_stepper_create("central_difference", sys, &o, &st);
  if (s == TL_OK) s = tl_calloc(&v, (size_t)sys->ndof, sizeof *v);
  if (s == TL_OK) {
    srand(3);
    for (TlSparseIndex i = 0; i < sys->ndof; ++i) v[i] = 1e-6 * (rand() / (double)RAND_MAX - 0.5);
    s = tl_stepper_set_state(st, 0.0, NULL, v);
  }
  if (s == TL_OK) {
    *dt_crit = st->dt_crit;
    *ndof = (size_t)sys->ndof;
    double best = INFINITY;
    for (int round = 0; round < 3 && s == TL_OK; ++round) {
      double t0 = tl_wtime();
      for (int k = 0; k < steps && s == TL_OK; ++k) s = tl_stepper_step(st, 1e-8);
      best = fmin(best, (tl_wtime() - t0) / steps);
    }
    *us = 1e6 * best;
  }
  tl_free(&v);
  tl_stepper_destroy(&st);
  tl_mech_system_destroy(&lin);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
  return s;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  long steps = 200;
  TL_CHECK(tl_initialize());
  TL_CHECK(tl_options_create(argc, argv,
                             "Cost of one step of the gouge's FE bar (seeds/000 S-B2) at the paper's dt = 1e-8 s: "
                             "finite-strain solid against its linearisation (K once).",
                             &o));
  TlStatus s = tl_options_get_int(o, "-steps", 200, 1, 100000000L, "timed steps per round (best of 3 rounds)", &steps);
  if (s == TL_OK) s = tl_options_finish(o, stdout);
  tl_options_destroy(&o);
  if (s) return s;
  const char *mesh_name[2] = {"h12d0", "h3d0"};
  int per_cell[2] = {1, 4};
  for (int m = 0; m < 2; ++m) {
    double us[2] = {0, 0}, dtc = 0;
    size_t nd = 0;
    for (int lin = 0; lin < 2; ++lin) TL_CHECK(bar_time(per_cell[m], lin, (int)steps, &us[lin], &dtc, &nd));
    printf("bench: mesh=%s elements=%d dofs=%zu us_solid=%.1f us_linear=%.1f ratio=%.3f dt_crit=%.3g "
           "dt_crit_over_paper_dt=%.0f\n",
           mesh_name[m], 2 * per_cell[m] * 36 * per_cell[m] * 2 * per_cell[m], nd, us[0], us[1], us[1] / us[0], dtc,
           dtc / 1e-8);
  }
  return TL_OK;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
