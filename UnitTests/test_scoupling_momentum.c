/* Surface coupling: walls from the faces of a beam of hex8, hex27, tet4 or
 * tet10 elements (quadratic faces subdivided), SCoupling elements,
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
#include "tl_scoupling_faces.h"
#include "tl_test.h"

/* The short S1 beam (2 x 6 x 2 cells, 0.8 x 2.4 x 0.8 m, clamped at y = 0)
 * of any 3-D element type (tetrahedra: six per cell). */
typedef struct {
  TlMesh *mesh;
  TlMaterial *material;
  TlSolid *solid;
} Beam;

static Beam *small_beam(const TlElementType *type)
{
  Beam *b = NULL;
  TL_TEST_STATUS(TL_NEW(b), TL_OK);
  const size_t n[3] = {2, 6, 2};
  const double lo[3] = {-0.4, 0.0, -0.4}, hi[3] = {0.4, 2.4, 0.4};
  TL_TEST_STATUS(tl_mesh_create_box(type, n, lo, hi, &b->mesh), TL_OK);
  TL_TEST_STATUS(tl_material_create_hooke(1e8, 0.0, 1309.0, &b->material), TL_OK);
  TL_TEST_STATUS(tl_solid_create(b->mesh, &b->solid), TL_OK);
  TL_TEST_STATUS(tl_solid_set_material(b->solid, NULL, b->material), TL_OK);
  TL_TEST_STATUS(tl_solid_fix(b->solid, "ymin", 7), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(b->solid), TL_OK);
  return b;
}

static void beam_destroy(Beam **b)
{
  tl_solid_destroy(&(*b)->solid);
  tl_material_destroy(&(*b)->material);
  tl_mesh_destroy(&(*b)->mesh);
  tl_free(b);
}

static TlDem *world(double r, double kn)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(tl_dem_particles(dem), "g", 2e4, r, r, &sp), TL_OK);
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", kn, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  return dem;
}

static double sum_abs(const double *f, size_t n)
{
  double s = 0.0;
  for (size_t i = 0; i < n; i++) s += fabs(f[i]);
  return s;
}

static void test_balance(const TlElementType *type, double width, int support)
{
  Beam *beam = small_beam(type);
  const TlMesh *mesh = beam->mesh;
  TlSCouplingOptions so;
  tl_scoupling_options_default(&so);
  so.width = width;
  so.support = support;
  const char *clamped[] = {"ymin"};
  TlSCoupling *sc = NULL;
  TL_TEST_STATUS(tl_scoupling_create_boundary(beam->solid, 1, clamped, &so, &sc), TL_OK);
  /* 2 x 6 x 2 cells: every hexahedron touches the free boundary (and most
   * of the six tetrahedra of each cell). */
  if (type->shape == TL_SHAPE_HEX)
    TL_TEST_ASSERT(tl_scoupling_n_elements(sc) == 24, "SCoupling elements %zu, expected 24", tl_scoupling_n_elements(sc));
  else
    TL_TEST_ASSERT(tl_scoupling_n_elements(sc) >= 48, "SCoupling elements %zu, expected 48 or more", tl_scoupling_n_elements(sc));
  /* The wall and the CG quadrature cover the coupled surface exactly: all
   * faces but the clamped end, 2 (0.8 x 2.4) 2 + 0.8 x 0.8 = 8.32 m^2. */
  const TlTriSurface *ws = tl_wall_trisurface_surface(tl_scoupling_wall(sc));
  const TlCGSurface *cs = tl_scoupling_cg_surface(sc);
  double wall_area = 0.0, cg_area = 0.0;
  for (size_t t = 0; t < ws->n_triangles; t++) wall_area += ws->area[t];
  for (size_t q = 0; q < cs->n_faces * (size_t)cs->qp_per_face; q++) cg_area += cs->wq[q];
  TL_TEST_CLOSE(wall_area, 8.32, 1e-12);
  /* The element support integrates over the SCoupling elements instead: the
   * whole beam here, 0.8 x 2.4 x 0.8 = 1.536 m^3 (hexahedra; tetrahedra
   * only partly, all that touch the boundary). */
  if (support == TL_SCOUPLING_SUPPORT_ELEMENTS && width > 0.0) {
    if (type->shape == TL_SHAPE_HEX) TL_TEST_CLOSE(cg_area, 1.536, 1e-12);
    else TL_TEST_ASSERT(cg_area > 0.5 && cg_area <= 1.536 + 1e-12, "element support volume %g m^3", cg_area);
  } else {
    TL_TEST_CLOSE(cg_area, 8.32, 1e-12);
  }
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
  printf("%s, c = %g, %s support: worst |sum F_nodes + sum f_wall| / scale = %.3e over 400 steps, max |f_wall| = %.3e N, "
         "up to %zu contacts on %zu SCoupling elements\n", type->header.name, width,
         support == TL_SCOUPLING_SUPPORT_ELEMENTS ? "element" : "surface", worst, f_peak, max_contacts, max_active);
  TL_TEST_ASSERT(f_peak > 1e3, "the particles must press on the beam (max wall force %g N)", f_peak);
  TL_TEST_ASSERT(max_contacts >= 4, "at least four particles in contact at once (got %zu)", max_contacts);
  TL_TEST_ASSERT(worst < 1e-14, "momentum balance defect %g (relative) beyond round-off", worst);
  TlCoupledEnergy e;
  TL_TEST_STATUS(tl_coupled_loop_energy(loop, &e), TL_OK);
  TL_TEST_ASSERT(e.fem_strain > 0.0 && isfinite(e.total), "the beam deforms (strain %g J)", e.fem_strain);
  /* The stepper counts the coupling load's work as that of any external
   * load (the SCoupling elements put it in f_ext), so its explicit blow-up
   * test is armed although the beam starts at rest without other loads. */
  TlEnergies se;
  TL_TEST_STATUS(tl_stepper_energies(st, &se), TL_OK);
  printf("%s, c = %g: work of the coupling on the beam %.6g J (loop, trapezoidal), %.6g J (stepper); blow-up budget %.3g J\n",
         type->header.name, width, e.work_on_solid, se.external_work, st->energy_budget);
  TL_TEST_ASSERT(se.external_work != 0.0 && st->energy_budget >= fabs(se.external_work) && st->energy_budget > e.fem_kinetic / 1e6,
                 "stepper's external work %g J, blow-up budget %g J", se.external_work, st->energy_budget);
  tl_coupled_loop_destroy(&loop);
  tl_stepper_destroy(&st);
  tl_dem_destroy(&dem);
  tl_scoupling_destroy(&sc);
  beam_destroy(&beam);
}

/* Bad widths and unknown face sets are refused with a message. */
static void test_refusals(void)
{
  TlSCoupling *sc = NULL;
  Beam *beam = small_beam(&tl_element_hex8);
  TlSCouplingOptions so;
  tl_scoupling_options_default(&so);
  so.width = -1.0;
  TL_TEST_STATUS(tl_scoupling_create_boundary(beam->solid, 0, NULL, &so, &sc), TL_ERR_ARG);
  const char *bad[] = {"nowhere"};
  TL_TEST_STATUS(tl_scoupling_create_boundary(beam->solid, 1, bad, NULL, &sc), TL_ERR_NOT_FOUND);
  beam_destroy(&beam);
}

/* The face plug-in on one curved quad9 and one curved tri6: the Dirac limit
 * (Eq. 16) puts -f N_a(s) on the nodes for a contact at x(s), the
 * projection recovering s on the curved face. */
static void test_face_projection(void)
{
  const TlElementType *types[] = {&tl_element_quad9, &tl_element_tri6};
  const double s0[2][2] = {{0.3, -0.55}, {0.2, 0.35}};
  for (int k = 0; k < 2; k++) {
    const TlElementType *t = types[k];
    TlSCouplingFaceType *ft = NULL;
    TL_TEST_STATUS(tl_scoupling_face_type_create(t, 1, &ft), TL_OK);
    TlVec3 x[9];
    int fn[9];
    for (int a = 0; a < t->n_nodes; a++) {
      const double u = t->ref_coords[2 * a], v = t->ref_coords[2 * a + 1];
      x[a] = tl_v3(1.3 * u + 0.2 * v, 0.9 * v, 0.15 * u * u - 0.1 * v * v + 0.05 * u * v); /* curved */
      fn[a] = a;
    }
    TlCGSurface *cs = NULL;
    TL_TEST_STATUS(tl_cg_surface_create_element_faces(ft, (size_t)t->n_nodes, x, 1, fn, &cs), TL_OK);
    TlCGKernel *dirac = NULL;
    TL_TEST_STATUS(tl_cg_kernel_create("dirac", 0.0, 3, &dirac), TL_OK);
    double xi[3] = {s0[k][0], s0[k][1], 0.0}, N[9];
    t->eval(1, xi, N, NULL);
    TlVec3 p = tl_v3(0, 0, 0), nodal[9] = {{0}};
    for (int a = 0; a < t->n_nodes; a++) p = tl_v3_axpy(p, N[a], x[a]);
    const TlVec3 f = tl_v3(0.3, -0.2, 1.0);
    size_t face = 0;
    TL_TEST_STATUS(tl_cg_surface_nodal_forces(cs, dirac, 1, &face, &p, &f, nodal), TL_OK);
    double err = 0.0;
    for (int a = 0; a < t->n_nodes; a++) err = fmax(err, tl_v3_norm(tl_v3_add(nodal[a], tl_v3_scale(f, N[a]))));
    printf("%s: Dirac nodal forces against -f N(s): largest difference %.3g N\n", t->header.name, err);
    TL_TEST_ASSERT(err < 1e-12, "%s: Eq. 16 on the curved face off by %g N", t->header.name, err);
    tl_cg_kernel_destroy(&dirac);
    tl_cg_surface_destroy(&cs);
    tl_scoupling_face_type_destroy(&ft);
  }
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  /* Linear faces (the CG module's own types) and quadratic faces through
   * their element type's ops, subdivided for the wall. */
  const TlElementType *types[] = {&tl_element_hex8, &tl_element_hex27, &tl_element_tet4, &tl_element_tet10};
  for (int k = 0; k < 4; k++) {
    test_balance(types[k], 0.0, TL_SCOUPLING_SUPPORT_SURFACE);
    test_balance(types[k], 0.4, TL_SCOUPLING_SUPPORT_SURFACE);
    test_balance(types[k], 0.4, TL_SCOUPLING_SUPPORT_ELEMENTS);
    if (k == 0) test_balance(types[k], 2.0, TL_SCOUPLING_SUPPORT_SURFACE);
    if (k == 0) test_balance(types[k], 2.0, TL_SCOUPLING_SUPPORT_ELEMENTS);
  }
  test_face_projection();
  test_refusals();
  return tl_test_report();
}
