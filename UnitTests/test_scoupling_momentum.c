/* Surface coupling: walls from the faces of a hex8 beam, SCoupling elements,
 * and the momentum balance of the coupling forces: at every step the forces
 * put on the FE nodes sum to minus the particle–wall forces, for the Dirac
 * limit (Eq. 16) and for the Lucy kernel (Eq. 15), with particles on faces,
 * on an edge and at a corner of the deforming beam. */
#include <math.h>
#include <string.h>
#include "talus.h"
#include "tl_cantilever.h"
#include "tl_coupled_loop.h"
#include "tl_scoupling.h"
#include "tl_test.h"

static TlCantilever *small_beam(const TlElementType *type)
{
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.type = type;
  p.ny = 6;
  p.L = 2.4;
  p.load = 0.0;
  TlCantilever *c = NULL;
  TL_TEST_STATUS(tl_cantilever_create(&p, &c), TL_OK);
  return c;
}

static TlDem *world(double r, double kn)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(tl_dem_particles(dem), "g", 2e4, r, r, &sp), TL_OK);
  TlContactParameters cp;
  tl_contact_parameters_default(&cp);
  cp.k_n = kn;
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_contact_law_create_linear(&cp, &law), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  return dem;
}

static double sum_abs(const double *f, size_t n)
{
  double s = 0.0;
  for (size_t i = 0; i < n; i++) s += fabs(f[i]);
  return s;
}

static void test_balance(double width)
{
  TlCantilever *beam = small_beam(&tl_element_hex8);
  const TlMesh *mesh = beam->mesh;
  TlSCouplingOptions so;
  tl_scoupling_options_default(&so);
  so.width = width;
  const char *clamped[] = {"ymin"};
  TlSCoupling *sc = NULL;
  TL_TEST_STATUS(tl_scoupling_create_boundary(beam->solid, 1, clamped, &so, &sc), TL_OK);
  /* 2 x 6 x 2 cells: every element touches the free boundary. */
  TL_TEST_ASSERT(tl_scoupling_n_elements(sc) == 24, "SCoupling elements %zu, expected 24", tl_scoupling_n_elements(sc));
  const double r = 0.1, kn = 2e7;
  TlDem *dem = world(r, kn);
  /* On the top face, on the top-side edge x = 0.4, at the free-end corner,
   * under the bottom face, and moving fast towards the free end face. */
  const TlVec3 x[] = {{0.2, 0.6, 0.4 + r - 1e-3}, {-0.1, 1.3, 0.4 + r - 2e-3},
                      {0.4 + 0.05, 1.7, 0.4 + 0.05}, {0.4 + r / sqrt(3) - 1e-3, 2.4 + r / sqrt(3) - 1e-3, 0.4 + r / sqrt(3) - 1e-3},
                      {0.0, 1.9, -0.4 - r + 1e-3}, {0.1, 2.4 + r + 0.01, 0.0}};
  const TlVec3 v[] = {{0, 0.5, 0}, {0.3, 0, 0}, {0, 0, 0}, {0.1, 0, 0}, {0, 0, 0.2}, {0, -3.0, 0}};
  for (int k = 0; k < 6; k++) TL_TEST_STATUS(tl_dem_add_particle(dem, x[k], v[k], r, 0, NULL), TL_OK);
  TL_TEST_STATUS(tl_scoupling_add_to_dem(sc, dem, 0), TL_OK);
  const double m = 2e4 * 4.0 / 3.0 * M_PI * r * r * r;
  const double dt = 0.01 * M_PI * sqrt(m / kn);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, dt, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TlStepperOptions sto;
  tl_stepper_options_default(&sto);
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("central_difference", tl_solid_system(beam->solid), &sto, &st), TL_OK);
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
  TlCoupledLoop *loop = NULL;
  TlSCoupling *list[] = {sc};
  TL_TEST_STATUS(tl_coupled_loop_create(dem, beam->solid, st, 1, list, NULL, &loop), TL_OK);
  const size_t nn = mesh->n_nodes;
  double worst = 0.0, f_peak = 0.0;
  size_t max_contacts = 0, max_active = 0;
  for (int step = 0; step < 400; step++) {
    TL_TEST_STATUS(tl_coupled_loop_step(loop), TL_OK);
    const double *F = tl_coupled_loop_forces(loop);
    TlVec3 sum = tl_v3(0, 0, 0);
    for (size_t i = 0; i < nn; i++) sum = tl_v3_add(sum, tl_v3(F[3 * i], F[3 * i + 1], F[3 * i + 2]));
    TlVec3 w = tl_coupled_loop_wall_force(loop);
    /* The wall total is also what the particles felt: no gravity, no pairs in contact. */
    TlParticles *P = tl_dem_particles(dem);
    TlVec3 pf = tl_v3(0, 0, 0);
    for (size_t i = 0; i < P->n; i++) pf = tl_v3_add(pf, P->f[i]);
    TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(pf, w)) <= 1e-12 * (tl_v3_norm(w) + 1.0),
                   "step %d: particles felt %g N, the wall contacts total %g N", step, tl_v3_norm(pf), tl_v3_norm(w));
    double scale = sum_abs(F, 3 * nn) + tl_v3_norm(w);
    double defect = tl_v3_norm(tl_v3_add(sum, w));
    if (scale > 0) worst = fmax(worst, defect / scale);
    f_peak = fmax(f_peak, tl_v3_norm(w));
    max_contacts = tl_scoupling_n_contacts(sc) > max_contacts ? tl_scoupling_n_contacts(sc) : max_contacts;
    max_active = tl_scoupling_n_active_elements(sc) > max_active ? tl_scoupling_n_active_elements(sc) : max_active;
  }
  printf("c = %g: worst |sum F_nodes + sum f_wall| / scale = %.3e over 400 steps, max |f_wall| = %.3e N, "
         "up to %zu contacts on %zu SCoupling elements\n", width, worst, f_peak, max_contacts, max_active);
  TL_TEST_ASSERT(f_peak > 1e3, "the particles must press on the beam (max wall force %g N)", f_peak);
  TL_TEST_ASSERT(max_contacts >= 4, "at least four particles in contact at once (got %zu)", max_contacts);
  TL_TEST_ASSERT(worst < 1e-14, "momentum balance defect %g (relative) beyond round-off", worst);
  TlCoupledEnergy e;
  TL_TEST_STATUS(tl_coupled_loop_energy(loop, &e), TL_OK);
  TL_TEST_ASSERT(e.fem_strain > 0.0 && isfinite(e.total), "the beam deforms (strain %g J)", e.fem_strain);
  tl_coupled_loop_destroy(&loop);
  tl_stepper_destroy(&st);
  tl_dem_destroy(&dem);
  tl_scoupling_destroy(&sc);
  tl_cantilever_destroy(&beam);
}

/* Quadratic faces are refused with a message; a coupling on a 2-D mesh too. */
static void test_refusals(void)
{
  TlCantilever *beam = small_beam(&tl_element_hex27);
  TlSCoupling *sc = NULL;
  TL_TEST_STATUS(tl_scoupling_create_boundary(beam->solid, 0, NULL, NULL, &sc), TL_ERR_UNSUPPORTED);
  TL_TEST_ASSERT(sc == NULL, "no coupling after a refusal");
  tl_cantilever_destroy(&beam);
  beam = small_beam(&tl_element_hex8);
  TlSCouplingOptions so;
  tl_scoupling_options_default(&so);
  so.width = -1.0;
  TL_TEST_STATUS(tl_scoupling_create_boundary(beam->solid, 0, NULL, &so, &sc), TL_ERR_ARG);
  const char *bad[] = {"nowhere"};
  TL_TEST_STATUS(tl_scoupling_create_boundary(beam->solid, 1, bad, NULL, &sc), TL_ERR_NOT_FOUND);
  tl_cantilever_destroy(&beam);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_balance(0.0);
  test_balance(0.4);
  test_balance(2.0);
  test_refusals();
  return tl_test_report();
}
