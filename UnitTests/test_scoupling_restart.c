/* Surface coupling restart: two particles sliding on a short beam (the S1
 * set-up on 2 x 6 x 2 cells, c = 0.4 m), run N steps in one go, and N/2
 * steps + checkpoint + a freshly built scene loaded from it + N/2 steps:
 * particle positions and velocities, the beam's displacements and the
 * coupling forces (node-wise and per face) agree bit for bit.  Explicit FEM
 * in lock-step and Newmark with 3 DEM steps per FEM step (predictor
 * scheme); Newmark with 2 and explicit with 1 in the interpolating scheme;
 * Newmark lock-step in the parallel one; two of them again with friction
 * (the walls' tangential history across the restart). */
#include <math.h>
#include <string.h>
#include "talus.h"
#include "tl_cantilever.h"
#include "tl_coupled_loop.h"
#include "tl_scoupling.h"
#include "tl_test.h"

typedef struct {
  TlCantilever *beam;
  TlSCoupling *sc;
  TlDem *dem;
  TlStepper *st;
  TlCoupledLoop *loop;
  TlCheckpoint *cp;
} Scene;

/* The CG support of the scenes built next (surface unless a case says), and
 * their friction coefficient (frictionless unless a case says: with
 * friction the walls' tangential history crosses the restart). */
static int cg_support = TL_SCOUPLING_SUPPORT_SURFACE;
static double friction_mu = 0.0;

static void build(Scene *S, const char *stepper, int substeps, int scheme)
{
  memset(S, 0, sizeof *S);
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.ny = 6;
  p.L = 2.4;
  p.load = 0.0;
  TL_TEST_STATUS(tl_cantilever_create(&p, &S->beam), TL_OK);
  TlSCouplingOptions so;
  tl_scoupling_options_default(&so);
  so.width = 0.4;
  so.support = cg_support;
  const char *clamped[] = {"ymin"};
  TL_TEST_STATUS(tl_scoupling_create_boundary(S->beam->solid, 1, clamped, &so, &S->sc), TL_OK);
  TL_TEST_STATUS(tl_dem_create(&S->dem), TL_OK);
  const double r = 0.1, kn = 2e7, m = 2e4 * 4.0 / 3.0 * M_PI * r * r * r;
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(tl_dem_particles(S->dem), "g", 2e4, r, r, &sp), TL_OK);
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", kn, "mu", friction_mu, "k_t", 2.0 / 7.0 * kn, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(S->dem, law, NULL), TL_OK);
  const double z = 0.4 + r - m * 9.81 / kn;
  TL_TEST_STATUS(tl_dem_add_particle(S->dem, tl_v3(0.2, 0.2, z), tl_v3(0, 2.0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(S->dem, tl_v3(-0.2, 0.2, z), tl_v3(0.1, 2.0, 0), r, sp, NULL), TL_OK);
  tl_dem_set_gravity(S->dem, tl_v3(0, 0, -9.81));
  TL_TEST_STATUS(tl_scoupling_add_to_dem(S->sc, S->dem, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(S->dem, 0.01 * M_PI * sqrt(2.0 * m / kn), 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(S->dem), TL_OK);
  TlStepperOptions sto;
  tl_stepper_options_default(&sto);
  TL_TEST_STATUS(tl_stepper_create(stepper, tl_solid_system(S->beam->solid), &sto, &S->st), TL_OK);
  TL_TEST_STATUS(tl_stepper_set_state(S->st, 0.0, NULL, NULL), TL_OK);
  TlCoupledLoopOptions lo;
  tl_coupled_loop_options_default(&lo);
  lo.substeps = substeps;
  lo.scheme = scheme;
  TlSCoupling *list[] = {S->sc};
  TL_TEST_STATUS(tl_coupled_loop_create(S->dem, S->beam->solid, S->st, 1, list, &lo, &S->loop), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_create(&S->cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(S->cp, "fem", &tl_stepper_checkpoint_ops, S->st), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(S->cp, "dem", &tl_dem_checkpoint_ops, S->dem), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(S->cp, "coupling", &tl_coupled_loop_checkpoint_ops, S->loop), TL_OK);
}

static void destroy(Scene *S)
{
  tl_checkpoint_destroy(&S->cp);
  tl_coupled_loop_destroy(&S->loop);
  tl_stepper_destroy(&S->st);
  tl_dem_destroy(&S->dem);
  tl_scoupling_destroy(&S->sc);
  tl_cantilever_destroy(&S->beam);
}

static void run(Scene *S, long n)
{
  for (long k = 0; k < n; k++) TL_TEST_STATUS(tl_coupled_loop_step(S->loop), TL_OK);
}

static void test_restart(const char *stepper, int substeps, int scheme, long n)
{
  Scene A, B;
  build(&A, stepper, substeps, scheme);
  run(&A, n);
  build(&B, stepper, substeps, scheme);
  run(&B, n / 2);
  TL_TEST_STATUS(tl_checkpoint_save(B.cp, "scoupling.h5", tl_coupled_loop_time(B.loop), n / 2), TL_OK);
  destroy(&B);
  build(&B, stepper, substeps, scheme);
  TL_TEST_STATUS(tl_checkpoint_load(B.cp, "scoupling.h5", NULL, NULL), TL_OK);
  run(&B, n - n / 2);
  TlParticles *PA = tl_dem_particles(A.dem), *PB = tl_dem_particles(B.dem);
  TL_TEST_ASSERT(PA->n == PB->n, "particle counts");
  TL_TEST_ASSERT(memcmp(PA->x, PB->x, PA->n * sizeof *PA->x) == 0, "%s: positions differ after the restart (x0 %.17g vs %.17g)",
                 stepper, PA->x[0].z, PB->x[0].z);
  TL_TEST_ASSERT(memcmp(PA->v, PB->v, PA->n * sizeof *PA->v) == 0, "%s: velocities differ after the restart", stepper);
  const size_t nd = (size_t)tl_solid_system(A.beam->solid)->ndof, nn = 3 * A.beam->mesh->n_nodes;
  TL_TEST_ASSERT(memcmp(A.st->u, B.st->u, nd * sizeof(double)) == 0, "%s: beam displacements differ", stepper);
  TL_TEST_ASSERT(memcmp(tl_coupled_loop_forces(A.loop), tl_coupled_loop_forces(B.loop), nn * sizeof(double)) == 0,
                 "%s: coupling forces differ", stepper);
  TL_TEST_ASSERT(tl_coupled_loop_time(A.loop) == tl_coupled_loop_time(B.loop), "%s: times differ", stepper);
  TlCoupledEnergy ea, eb;
  TL_TEST_STATUS(tl_coupled_loop_energy(A.loop, &ea), TL_OK);
  TL_TEST_STATUS(tl_coupled_loop_energy(B.loop, &eb), TL_OK);
  TL_TEST_ASSERT(ea.total == eb.total && ea.work_on_solid == eb.work_on_solid, "%s: energies differ (%.17g vs %.17g)",
                 stepper, ea.total, eb.total);
  double moved = fabs(PA->x[0].y - 0.2);
  TL_TEST_ASSERT(moved > 0.05, "the particles slid (%g m)", moved);
  if (friction_mu > 0.0) {
    /* friction acted: it spun the particles up (same spins after the restart) */
    TL_TEST_ASSERT(PA->w && PB->w && memcmp(PA->w, PB->w, PA->n * sizeof *PA->w) == 0,
                   "%s: spins differ after the frictional restart", stepper);
    TL_TEST_ASSERT(PA->w && fabs(PA->w[0].x) > 1.0, "%s: friction did not spin the particle (w_x %g rad/s)", stepper,
                   PA->w ? PA->w[0].x : 0.0);
    if (PA->w) printf("friction mu = %g: particle 1 spins at %.6g rad/s\n", friction_mu, PA->w[0].x);
  }
  /* The per-face forces the SCoupling elements carry, and their elements. */
  const size_t nfv = tl_scoupling_n_faces(A.sc) * (size_t)tl_scoupling_nodes_per_face(A.sc);
  TL_TEST_ASSERT(memcmp(tl_scoupling_face_forces(A.sc), tl_scoupling_face_forces(B.sc), nfv * sizeof(TlVec3)) == 0 &&
                     tl_scoupling_n_active_elements(A.sc) == tl_scoupling_n_active_elements(B.sc),
                 "%s: per-face coupling forces or active elements differ", stepper);
  printf("%s, %d DEM steps per FEM step, %s scheme: %ld steps, restart at %ld equals the run in one go (particle 1 at "
         "y = %.6f, total energy %.9g J, %zu active SCoupling elements)\n", stepper, substeps,
         scheme == TL_COUPLING_PREDICT ? "predictor" : scheme == TL_COUPLING_INTERPOLATE ? "interpolating" : scheme == TL_COUPLING_PARALLEL ? "parallel" : "lagged-walls", n, n / 2, PA->x[0].y, ea.total,
         tl_scoupling_n_active_elements(A.sc));
  destroy(&A);
  destroy(&B);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_restart("central_difference", 1, TL_COUPLING_PREDICT, 600);
  test_restart("newmark", 3, TL_COUPLING_PREDICT, 200);
  /* The interpolating scheme steps the solid first, under the per-face
   * forces of the previous macro step: they come from the checkpoint. */
  test_restart("newmark", 2, TL_COUPLING_INTERPOLATE, 200);
  test_restart("central_difference", 1, TL_COUPLING_INTERPOLATE, 600);
  test_restart("newmark", 1, TL_COUPLING_PARALLEL, 600);
  test_restart("newmark", 2, TL_COUPLING_LAGGED_WALLS, 200);
  test_restart("central_difference", 1, TL_COUPLING_LAGGED_WALLS, 600);
  /* The per-element forces of the element CG support come from the
   * checkpoint too (the lagged-walls scheme loads the solid with them). */
  cg_support = TL_SCOUPLING_SUPPORT_ELEMENTS;
  test_restart("newmark", 1, TL_COUPLING_LAGGED_WALLS, 600);
  test_restart("newmark", 2, TL_COUPLING_INTERPOLATE, 200);
  /* Friction: the tangential history of the wall contacts is saved and
   * loaded with the coupled loop. */
  cg_support = TL_SCOUPLING_SUPPORT_SURFACE;
  friction_mu = 0.5;
  test_restart("central_difference", 1, TL_COUPLING_PREDICT, 600);
  test_restart("newmark", 2, TL_COUPLING_LAGGED_WALLS, 200);
  return tl_test_report();
}
