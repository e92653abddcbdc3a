/* The surface coupling on the 20-node serendipity hexahedron
 * (element_hex20.c), registered from outside the library: particles
 * dropped onto, pressed against and rolling on a short clamped hex20 beam,
 * surface-coupled (Coupling/Surface/tl_scoupling.h) with the Dirac limit (c = 0)
 * and with a Lucy kernel of width 0.4 m.  At every step the coupling
 * forces put on the beam's nodes must sum to minus the particle-wall
 * contact forces (momentum balance, to round-off), the particles must press
 * on the beam and the beam must deform.
 * Prints `summary:` and exits non-zero when a check fails. */
#include <math.h>
#include <stdio.h>

#include "examples.h"
#include "tl_coupled_loop.h"
#include "tl_dem.h"
#include "tl_element.h"
#include "tl_mesh.h"
#include "tl_scoupling.h"
#include "tl_solid.h"
#include "tl_stepper.h"

/* The particles' contact law: linear spring of stiffness kn, no friction. */
static TlStatus contact_law(double kn, TlContactLaw **law)
{
  TL_CHECK(tl_contact_law_create("linear", NULL, NULL, NULL, law));
  TlStatus s = tl_contact_law_set(*law, "k_n", kn);
  if (s == TL_OK) s = tl_contact_law_setup(*law);
  if (s != TL_OK) tl_contact_law_destroy(law);
  return s;
}

typedef struct {
  double worst, f_peak, strain;
  size_t contacts, active, elements;
} Result;

static TlStatus run_case(const TlElementType *type, double width, long steps, Result *res)
{
  const size_t n[3] = {2, 6, 2};
  const double lo[3] = {-0.4, 0.0, -0.4}, hi[3] = {0.4, 2.4, 0.4};
  const double r = 0.1, kn = 2e7, rho_p = 2e4;
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TlSCoupling *sc = NULL;
  TlDem *dem = NULL;
  TlContactLaw *law = NULL;
  TlStepper *st = NULL;
  TlCoupledLoop *loop = NULL;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_mesh_create_box(type, n, lo, hi, &mesh), done);
  TL_CHECK_GOTO(s, tl_material_create_hooke(1e8, 0.0, 1309.0, &mat), done);
  TL_CHECK_GOTO(s, tl_solid_create(mesh, &solid), done);
  TL_CHECK_GOTO(s, tl_solid_set_material(solid, NULL, mat), done);
  TL_CHECK_GOTO(s, tl_solid_fix(solid, "ymin", 7), done);
  TL_CHECK_GOTO(s, tl_solid_setup(solid), done);
  TlSCouplingOptions so;
  tl_scoupling_options_default(&so);
  so.width = width;
  const char *clamped[] = {"ymin"};
  TL_CHECK_GOTO(s, tl_scoupling_create_boundary(solid, 1, clamped, &so, &sc), done);
  TL_CHECK_GOTO(s, tl_dem_create(&dem), done);
  int sp;
  TL_CHECK_GOTO(s, tl_particles_add_species(tl_dem_particles(dem), "grain", rho_p, r, r, &sp), done);
  TL_CHECK_GOTO(s, contact_law(kn, &law), done);
  TL_CHECK_GOTO(s, tl_dem_add_law(dem, law, NULL), done);
  law = NULL; /* the world owns it */
  /* Pressed on the top face, on the top-side edge, at a free-end corner,
   * under the bottom face, and falling fast onto the free end face. */
  const TlVec3 x[] = {{0.2, 0.6, 0.4 + r - 1e-3},
                      {-0.1, 1.3, 0.4 + r - 2e-3},
                      {0.4 + 0.05, 1.7, 0.4 + 0.05},
                      {0.4 + r / sqrt(3) - 1e-3, 2.4 + r / sqrt(3) - 1e-3, 0.4 + r / sqrt(3) - 1e-3},
                      {0.0, 1.9, -0.4 - r + 1e-3},
                      {0.1, 2.4 + r + 0.01, 0.0}};
  const TlVec3 v[] = {{0, 0.5, 0}, {0.3, 0, 0}, {0, 0, 0}, {0.1, 0, 0}, {0, 0, 0.2}, {0, -3.0, 0}};
  for (int k = 0; k < 6; ++k) TL_CHECK_GOTO(s, tl_dem_add_particle(dem, x[k], v[k], r, 0, NULL), done);
  TL_CHECK_GOTO(s, tl_scoupling_add_to_dem(sc, dem, 0), done);
  const double m = rho_p * 4.0 / 3.0 * M_PI * r * r * r, dt = 0.01 * M_PI * sqrt(m / kn);
  TL_CHECK_GOTO(s, tl_dem_set_timestep(dem, dt, 0), done);
  TL_CHECK_GOTO(s, tl_dem_setup(dem), done);
  TL_CHECK_GOTO(s, tl_stepper_create("central_difference", tl_solid_system(solid), NULL, &st), done);
  TL_CHECK_GOTO(s, tl_stepper_set_state(st, 0.0, NULL, NULL), done);
  TlSCoupling *list[] = {sc};
  TL_CHECK_GOTO(s, tl_coupled_loop_create(dem, solid, st, 1, list, NULL, &loop), done);
  *res = (Result){0};
  res->elements = tl_scoupling_n_elements(sc);
  for (long k = 0; k < steps; ++k) {
    TL_CHECK_GOTO(s, tl_coupled_loop_step(loop), done);
    const double *F = tl_coupled_loop_forces(loop);
    TlVec3 sum = tl_v3(0, 0, 0), w = tl_coupled_loop_wall_force(loop);
    double scale = tl_v3_norm(w);
    for (size_t i = 0; i < mesh->n_nodes; ++i) {
      sum = tl_v3_add(sum, tl_v3(F[3 * i], F[3 * i + 1], F[3 * i + 2]));
      scale += fabs(F[3 * i]) + fabs(F[3 * i + 1]) + fabs(F[3 * i + 2]);
    }
    if (scale > 0.0) res->worst = fmax(res->worst, tl_v3_norm(tl_v3_add(sum, w)) / scale);
    res->f_peak = fmax(res->f_peak, tl_v3_norm(w));
    if (tl_scoupling_n_contacts(sc) > res->contacts) res->contacts = tl_scoupling_n_contacts(sc);
    if (tl_scoupling_n_active_elements(sc) > res->active) res->active = tl_scoupling_n_active_elements(sc);
  }
  TlCoupledEnergy e;
  TL_CHECK_GOTO(s, tl_coupled_loop_energy(loop, &e), done);
  res->strain = e.fem_strain;
done:
  tl_coupled_loop_destroy(&loop);
  tl_stepper_destroy(&st);
  tl_dem_destroy(&dem);
  tl_contact_law_destroy(&law);
  tl_scoupling_destroy(&sc);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
  return s;
}

static TlStatus run(int argc, char **argv)
{
  TlOptions *o = NULL;
  const char *elements;
  long steps;
  TL_CHECK(tl_initialize());
  TL_CHECK(example_hex20_register());
  TL_CHECK(tl_options_create(argc, argv,
                             "The surface coupling on a 20-node serendipity hexahedron defined outside the "
                             "library: momentum balance of the coupling forces against the contact forces.",
                             &o));
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-elements", "hex20", "element type of the beam (by name)", &elements), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-steps", 400, 1, 1000000, "coupled steps per case", &steps), done);
  if ((s = tl_options_finish(o, stdout)) != TL_OK) goto done;
  double t0 = tl_wtime();
  const TlElementType *type = NULL;
  TL_CHECK_GOTO(s, tl_element_type_find(elements, &type), done);
  const double widths[2] = {0.0, 0.4};
  double worst = 0.0;
  int ok = 1;
  for (int c = 0; c < 2; ++c) {
    Result r = {0};
    TL_CHECK_GOTO(s, run_case(type, widths[c], steps, &r), done);
    printf("%s beam 2x6x2, c = %g m: %zu SCoupling elements, up to %zu contacts on %zu active elements, "
           "max |f_wall| %.3e N, strain energy %.3e J, momentum defect %.2e\n",
           elements, widths[c], r.elements, r.contacts, r.active, r.f_peak, r.strain, r.worst);
    ok &= r.worst < 1e-14 && r.f_peak > 1e3 && r.contacts >= 4 && r.strain > 0.0 && r.elements == 24;
    worst = fmax(worst, r.worst);
  }
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_string(&sum, "elements", elements);
  tl_summary_real(&sum, "momentum_defect", worst);
  tl_summary_string(&sum, "check", ok ? "pass" : "fail");
  tl_summary_real(&sum, "wall", tl_wtime() - t0);
  s = tl_summary_print(&sum, stdout);
  if (!ok) s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "hex20 coupling example: a check failed (see above)");
done:
  tl_options_destroy(&o);
  return s;
}

int main(int argc, char **argv) { return tl_driver_exit(run(argc, argv)); }
