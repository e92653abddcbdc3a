/* The SCoupling element type (seeds/001 §5.3.1, Fig. 7): the coupling puts
 * a wrapper over the blocks holding coupled faces, which adds the
 * coupling's load to the external force, R_a = f_int - f_ext - int N_a t dA.
 * On short hex8 and tet10 beams with particles pressing on faces, edges and
 * a corner, for c = 0 (Eq. 16) and c > 0 (Eq. 15):
 *   - the external force with the accumulated forces minus the one without
 *     is exactly the assembled nodal forces (to round-off), it is the same
 *     bit for bit before accumulating and after clearing, and the internal
 *     force does not move;
 *   - no tangent and no stored energy is added (a dead load within the step);
 *   - the active SCoupling elements are the owners of the contacted faces
 *     (c = 0) or of every face with a quadrature point within c of a
 *     contact (c > 0: the contacted faces' owners and their neighbours);
 *   - accumulating twice with scale 1/2 equals once with scale 1;
 *   - destroying the coupling removes its wrapper;
 *   - two couplings on one block stack their wrappers, which come off in
 *     either order, also from under a wrapper of another kind. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "talus.h"
#include "tl_scoupling.h"
#include "tl_test.h"

static double max_abs(const double *v, size_t n)
{
  double m = 0.0;
  for (size_t i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
  return m;
}

static int has_element(const TlFaceRef *list, size_t n, TlFaceRef e)
{
  for (size_t k = 0; k < n; ++k)
    if (list[k].block == e.block && list[k].element == e.element) return 1;
  return 0;
}

/* A world with one species of radius r (rho 2e4) and the S1 linear law
 * (k_n = 2e7 N/m); *sp and *law receive their indices. */
static TlDem *make_world(double r, int *sp, int *law)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TL_TEST_STATUS(tl_particles_add_species(tl_dem_particles(dem), "g", 2e4, r, r, sp), TL_OK);
  TlContactLaw *l = NULL;
  TL_TEST_STATUS(tl_test_law(&l, "linear", "k_n", 2e7, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, l, law), TL_OK);
  return dem;
}

/* The short S1 beam (2 x 6 x 2 cells, clamped at y = 0) of an element type. */
static TlSolid *beam(const TlElementType *type, TlMesh **mesh, TlMaterial **mat)
{
  const size_t nc[3] = {2, 6, 2};
  const double lo[3] = {-0.4, 0.0, -0.4}, hi[3] = {0.4, 2.4, 0.4};
  TL_TEST_STATUS(tl_mesh_create_box(type, nc, lo, hi, mesh), TL_OK);
  TL_TEST_STATUS(tl_material_create_hooke(1e8, 0.2, 1309.0, mat), TL_OK);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(*mesh, &solid), TL_OK);
  TL_TEST_STATUS(tl_solid_set_material(solid, NULL, *mat), TL_OK);
  TL_TEST_STATUS(tl_solid_fix(solid, "ymin", 7), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  return solid;
}

static void test_element(const TlElementType *type, double width, int support)
{
  const char *name = type->header.name;
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = beam(type, &mesh, &mat);
  TL_TEST_ASSERT(tl_solid_n_wrappers(solid, 0) == 0, "%s: a bare block", name);
  TlSCouplingOptions so;
  tl_scoupling_options_default(&so);
  so.width = width;
  so.support = support;
  const char *clamped[] = {"ymin"};
  TlSCoupling *sc = NULL;
  TL_TEST_STATUS(tl_scoupling_create_boundary(solid, 1, clamped, &so, &sc), TL_OK);
  if (!sc) return;
  const int on_elements = support == TL_SCOUPLING_SUPPORT_ELEMENTS && width > 0.0;
  TL_TEST_ASSERT(tl_solid_n_wrappers(solid, 0) == 1, "%s: the coupling wraps the block", name);
  /* Particles pressing on the top face, an edge, the free-end corner and the bottom face. */
  const double r = 0.1;
  int sp, law;
  TlDem *dem = make_world(r, &sp, &law);
  const TlVec3 x[] = {{0.17, 0.63, 0.4 + r - 2e-3}, {0.4 + 0.05, 1.3, 0.4 + 0.05},
                      {0.4 + r / sqrt(3) - 1e-3, 2.4 + r / sqrt(3) - 1e-3, 0.4 + r / sqrt(3) - 1e-3 - 0.004 /* the tip deflects 4 mm */},
                      {-0.05, 1.9, -0.4 - r + 1e-3}};
  for (int k = 0; k < 4; ++k) TL_TEST_STATUS(tl_dem_add_particle(dem, x[k], tl_v3(0, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_scoupling_add_to_dem(sc, dem, law), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 1e-5, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  /* The solid in a deformed state, the walls on it, the DEM forces there. */
  TlMechSystem *sys = tl_solid_system(solid);
  const size_t nd = (size_t)sys->ndof, nn = 3 * mesh->n_nodes;
  double *u = calloc(nd, sizeof *u), *u_nodes = calloc(nn, sizeof *u_nodes);
  for (size_t n = 0; n < mesh->n_nodes; ++n) {
    const double *X = mesh->x + 3 * n;
    const double s = X[1] / 2.4;
    for (int c = 0; c < 3; ++c) {
      TlSparseIndex i = tl_solid_dof(solid, n, c);
      if (i >= 0) u[i] = (c == 2 ? -0.004 * s * s : 0.0005 * sin(3.0 * X[0] + c)) * (X[1] > 0.0);
    }
  }
  tl_solid_dofs_to_nodes(solid, u, u_nodes);
  TL_TEST_STATUS(tl_scoupling_set_kinematics(sc, u_nodes, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_compute_forces(dem), TL_OK);
  double *f0 = calloc(nd, sizeof *f0), *f1 = calloc(nd, sizeof *f1), *f2 = calloc(nd, sizeof *f2), *f_own = calloc(nd, sizeof *f_own);
  double *g0 = calloc(nd, sizeof *g0), *g1 = calloc(nd, sizeof *g1);
  double *F_nodes = calloc(nn, sizeof *F_nodes), *F = calloc(nd, sizeof *F);
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f0), TL_OK);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, g0), TL_OK);
  /* Accumulate the forces of the current contacts. */
  TlVec3 wall;
  TL_TEST_STATUS(tl_scoupling_accumulate_forces(sc, 1.0, &wall), TL_OK);
  const size_t n_contacts = tl_scoupling_n_contacts(sc);
  tl_scoupling_assemble_forces(sc, F_nodes);
  tl_solid_nodes_to_dofs(solid, F_nodes, F);
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f1), TL_OK);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, g1), TL_OK);
  TL_TEST_ASSERT(memcmp(f1, f0, nd * sizeof *f0) == 0, "%s: the coupling load leaves the internal force bit for bit", name);
  /* Momentum: the assembled forces (clamped nodes included) balance the wall's. */
  TlVec3 sum = tl_v3(0, 0, 0);
  for (size_t n = 0; n < mesh->n_nodes; ++n) sum = tl_v3_add(sum, tl_v3(F_nodes[3 * n], F_nodes[3 * n + 1], F_nodes[3 * n + 2]));
  const double balance = tl_v3_norm(tl_v3_add(sum, wall)) / tl_v3_norm(wall);
  double diff = 0.0;
  for (size_t i = 0; i < nd; ++i) diff = fmax(diff, fabs((g1[i] - g0[i]) - F[i]));
  const double Fmax = max_abs(F, nd), fmax0 = max_abs(f0, nd);
  /* Active elements against the contacted faces and the kernel's reach. */
  const TlTriSurface *ws = tl_wall_trisurface_surface(tl_scoupling_wall(sc));
  const TlTriContactSet *set = tl_wall_trisurface_contacts(tl_scoupling_wall(sc));
  const size_t n_faces = tl_scoupling_n_faces(sc), pieces = ws->n_triangles / n_faces;
  const TlFaceRef *faces = tl_scoupling_faces(sc);
  const TlCGSurface *cs = tl_scoupling_cg_surface(sc);
  const TlFaceRef *active = tl_scoupling_active_elements(sc);
  const size_t n_active = tl_scoupling_n_active_elements(sc);
  size_t missing = 0, n_expected = 0, n_contacted = 0, dup = 0;
  unsigned char *reached = calloc(n_faces, 1), *contacted = calloc(n_faces, 1);
  for (size_t k = 0; k < set->count; ++k) {
    if (!set->c[k].active) continue;
    const size_t f = (size_t)set->c[k].triangle / pieces;
    contacted[f] = 1;
    if (width == 0.0) reached[f] = 1;
    else if (!on_elements)
      for (size_t g = 0; g < n_faces; ++g)
        for (int q = 0; q < cs->qp_per_face; ++q)
          if (tl_v3_norm(tl_v3_sub(cs->xq[g * (size_t)cs->qp_per_face + (size_t)q], set->c[k].point)) < width) reached[g] = 1;
  }
  TlFaceRef *expected = calloc(n_faces, sizeof *expected), *owners = calloc(n_faces, sizeof *owners);
  for (size_t f = 0; f < n_faces; ++f) {
    if (contacted[f] && !has_element(owners, n_contacted, faces[f])) owners[n_contacted++] = faces[f];
    if (!on_elements && reached[f] && !has_element(expected, n_expected, faces[f])) expected[n_expected++] = faces[f];
  }
  /* With the element support the kernel reaches elements through their own
   * integration points (the support's "faces" are the SCoupling elements). */
  if (on_elements) {
    const TlFaceRef *elems = tl_scoupling_elements(sc);
    TL_TEST_ASSERT(cs->n_faces == tl_scoupling_n_elements(sc), "%s: element support over the %zu SCoupling elements (%zu)",
                   name, tl_scoupling_n_elements(sc), cs->n_faces);
    for (size_t g = 0; g < cs->n_faces; ++g) {
      int hit = 0;
      for (size_t k = 0; k < set->count && !hit; ++k)
        for (int q = 0; q < cs->qp_per_face && set->c[k].active && !hit; ++q)
          hit = tl_v3_norm(tl_v3_sub(cs->xq[g * (size_t)cs->qp_per_face + (size_t)q], set->c[k].point)) < width;
      if (hit) expected[n_expected++] = elems[g];
    }
  }
  for (size_t k = 0; k < n_expected; ++k) missing += !has_element(active, n_active, expected[k]);
  for (size_t k = 0; k < n_active; ++k) dup += has_element(active, k, active[k]);
  size_t owners_active = 0;
  for (size_t k = 0; k < n_contacted; ++k) owners_active += has_element(active, n_active, owners[k]);
  printf("%s, c = %g, %s support: %zu contacts; external force change vs F: %.3g (|F| %.3g N, |f_int| %.3g N); momentum %.2g; %zu active "
         "SCoupling elements of %zu (%zu own a contacted face, %zu expected)\n",
         name, width, on_elements ? "element" : "surface", n_contacts, diff, Fmax, fmax0, balance, n_active, tl_scoupling_n_elements(sc), n_contacted, n_expected);
  TL_TEST_ASSERT(n_contacts >= 4 && Fmax > 100.0, "%s: the particles press on the beam (%zu contacts, %g N)", name,
                 n_contacts, Fmax);
  TL_TEST_ASSERT(diff <= 1e-13 * (Fmax + fmax0), "%s, c = %g: external force with the load - without = F off by %g", name, width, diff);
  TL_TEST_ASSERT(balance < 1e-14, "%s, c = %g: momentum defect %g", name, width, balance);
  TL_TEST_ASSERT(missing == 0 && dup == 0 && n_active == n_expected, "%s, c = %g: active %zu, expected %zu, %zu missing, %zu twice",
                 name, width, n_active, n_expected, missing, dup);
  TL_TEST_ASSERT(owners_active == n_contacted, "%s: the contacted faces' owners are active (%zu of %zu)", name,
                 owners_active, n_contacted);
  if (width > 0.0)
    TL_TEST_ASSERT(n_active > n_contacted, "%s, c = %g: neighbours within reach are active too (%zu vs %zu)", name, width,
                   n_active, n_contacted);
  else
    TL_TEST_ASSERT(n_active == n_contacted, "%s, c = 0: the contacted faces' owners only (%zu vs %zu)", name, n_active,
                   n_contacted);
  /* No tangent and no stored energy from the coupling. */
  TlSparse *K0 = NULL, *K1 = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 0, &K0), TL_OK);
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 0, &K1), TL_OK);
  double W1 = 0.0, W0 = 0.0;
  TL_TEST_STATUS(sys->ops->internal_tangent(sys, 0.0, u, NULL, 1.0, 0.0, K1), TL_OK);
  TL_TEST_STATUS(sys->ops->external_tangent(sys, 0.0, u, -1.0, K1), TL_OK);
  TL_TEST_STATUS(sys->ops->strain_energy(sys, u, &W1), TL_OK);
  /* Twice with scale 1/2 equals once with scale 1. */
  tl_scoupling_clear_forces(sc);
  TL_TEST_ASSERT(tl_scoupling_n_active_elements(sc) == 0 && tl_scoupling_n_touched_faces(sc) == 0, "%s: cleared", name);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, f2), TL_OK);
  TL_TEST_ASSERT(memcmp(f2, g0, nd * sizeof *g0) == 0, "%s: cleared coupling leaves the external force bit for bit", name);
  TL_TEST_STATUS(sys->ops->internal_tangent(sys, 0.0, u, NULL, 1.0, 0.0, K0), TL_OK);
  TL_TEST_STATUS(sys->ops->external_tangent(sys, 0.0, u, -1.0, K0), TL_OK);
  TL_TEST_STATUS(sys->ops->strain_energy(sys, u, &W0), TL_OK);
  if (K0 && K1)
    TL_TEST_ASSERT(memcmp(K0->values, K1->values, (size_t)K0->nnz * sizeof(double)) == 0 && W0 == W1,
                   "%s: the coupling adds no tangent and no stored energy", name);
  TL_TEST_STATUS(tl_scoupling_accumulate_forces(sc, 0.5, NULL), TL_OK);
  TL_TEST_STATUS(tl_scoupling_accumulate_forces(sc, 0.5, NULL), TL_OK);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, f2), TL_OK);
  double half = 0.0;
  for (size_t i = 0; i < nd; ++i) half = fmax(half, fabs(f2[i] - g1[i]));
  TL_TEST_ASSERT(half <= 1e-13 * (Fmax + fmax0) && tl_scoupling_n_active_elements(sc) == n_active,
                 "%s: two half-scaled accumulations differ from one by %g", name, half);
  /* Unwrapped on destroy: the solid's own forces, without the coupling. */
  tl_dem_destroy(&dem);
  tl_scoupling_destroy(&sc);
  TL_TEST_ASSERT(tl_solid_n_wrappers(solid, 0) == 0, "%s: destroy removes the wrapper", name);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, f_own), TL_OK);
  TL_TEST_ASSERT(memcmp(f_own, g0, nd * sizeof *g0) == 0, "%s: own external force after the coupling is gone", name);
  tl_sparse_destroy(&K0);
  tl_sparse_destroy(&K1);
  free(reached), free(contacted), free(expected), free(owners);
  free(u), free(u_nodes), free(f0), free(f1), free(f2), free(f_own), free(g0), free(g1), free(F_nodes), free(F);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* A wrapper of another kind (as a volume coupling's would be): an internal
 * term that adds nothing and counts its calls. */
static TlStatus foreign_terms(void *ctx, TlSolid *solid, int b, double t, const double *u, double *f, double c_u,
                              TlSparse *K, double *W)
{
  (void)solid, (void)b, (void)t, (void)u, (void)f, (void)c_u, (void)K, (void)W;
  (*(int *)ctx)++;
  return TL_OK;
}

static const TlSolidWrapperOps foreign_ops = {.header = {"solid_wrapper", "test_foreign", "counts its calls"},
                                              .internal = foreign_terms};

/* Two couplings on the same block (top and bottom faces): the wrappers
 * stack, the external force carries both loads, and destroying them in
 * either order leaves the solid's own forces. */
static void test_two_couplings(void)
{
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = beam(&tl_element_hex8, &mesh, &mat);
  const char *sets[2] = {"zmax", "zmin"};
  TlSCoupling *sc[2] = {NULL, NULL};
  const double r = 0.1;
  int sp, law;
  TlDem *dem = make_world(r, &sp, &law);
  for (int k = 0; k < 2; ++k) {
    const TlFaceSet *set = NULL;
    TL_TEST_STATUS(tl_mesh_find_face_set(mesh, sets[k], &set), TL_OK);
    if (!set) return;
    TlSCouplingOptions so;
    tl_scoupling_options_default(&so);
    so.width = 0.3 * k;
    TL_TEST_STATUS(tl_scoupling_create(solid, set->n, set->faces, &so, &sc[k]), TL_OK);
    if (!sc[k]) return;
    TL_TEST_STATUS(tl_scoupling_add_to_dem(sc[k], dem, law), TL_OK);
  }
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.1, 1.1, 0.4 + r - 1e-3), tl_v3(0, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(-0.2, 1.7, -0.4 - r + 2e-3), tl_v3(0, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 1e-5, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TL_TEST_STATUS(tl_dem_compute_forces(dem), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  const size_t nd = (size_t)sys->ndof, nn = 3 * mesh->n_nodes;
  double *u = calloc(nd, sizeof *u), *f0 = calloc(nd, sizeof *f0), *f1 = calloc(nd, sizeof *f1);
  double *g0 = calloc(nd, sizeof *g0), *g1 = calloc(nd, sizeof *g1);
  double *F_nodes = calloc(nn, sizeof *F_nodes), *F = calloc(nd, sizeof *F);
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f0), TL_OK);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, g0), TL_OK);
  size_t contacts = 0;
  for (int k = 0; k < 2; ++k) {
    TL_TEST_STATUS(tl_scoupling_accumulate_forces(sc[k], 1.0, NULL), TL_OK);
    tl_scoupling_assemble_forces(sc[k], F_nodes);
    contacts += tl_scoupling_n_contacts(sc[k]) > 0;
  }
  tl_solid_nodes_to_dofs(solid, F_nodes, F);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, g1), TL_OK);
  double diff = 0.0;
  for (size_t i = 0; i < nd; ++i) diff = fmax(diff, fabs(g1[i] - g0[i] - F[i]));
  printf("two couplings on one block: external force change vs F_top + F_bottom %.3g (|F| %.3g N)\n", diff, max_abs(F, nd));
  TL_TEST_ASSERT(contacts == 2 && max_abs(F, nd) > 100.0, "both couplings are loaded (%zu)", contacts);
  TL_TEST_ASSERT(diff <= 1e-14 * max_abs(F, nd) && tl_solid_n_wrappers(solid, 0) == 2, "two wrappers: external force off by %g", diff);
  tl_dem_destroy(&dem);
  tl_scoupling_destroy(&sc[1]);
  tl_scoupling_destroy(&sc[0]);
  TL_TEST_ASSERT(tl_solid_n_wrappers(solid, 0) == 0, "the solid's own block after both couplings");
  /* Destroyed in the creation order: the first comes off from under the
   * second, then the second. */
  for (int k = 0; k < 2; ++k) {
    const TlFaceSet *set = NULL;
    TL_TEST_STATUS(tl_mesh_find_face_set(mesh, sets[k], &set), TL_OK);
    if (set) TL_TEST_STATUS(tl_scoupling_create(solid, set->n, set->faces, NULL, &sc[k]), TL_OK);
  }
  tl_scoupling_destroy(&sc[0]);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, g1), TL_OK);
  TL_TEST_ASSERT(memcmp(g1, g0, nd * sizeof *g0) == 0 && tl_solid_n_wrappers(solid, 0) == 1,
                 "first coupling destroyed: the second still wraps, the external force bit for bit");
  tl_scoupling_destroy(&sc[1]);
  TL_TEST_ASSERT(tl_solid_n_wrappers(solid, 0) == 0, "destroyed in creation order: the bare block again");
  /* From under a wrapper of another kind: it stays and keeps working. */
  TL_TEST_STATUS(tl_scoupling_create_boundary(solid, 1, sets, NULL, &sc[0]), TL_OK);
  int calls = 0;
  TlSolidWrapper *fw = NULL;
  TL_TEST_STATUS(tl_solid_add_wrapper(solid, 0, &foreign_ops, &calls, &fw), TL_OK);
  tl_scoupling_destroy(&sc[0]);
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f1), TL_OK);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, g1), TL_OK);
  TL_TEST_ASSERT(calls == 1 && tl_solid_n_wrappers(solid, 0) == 1 && memcmp(f1, f0, nd * sizeof *f0) == 0 &&
                     memcmp(g1, g0, nd * sizeof *g0) == 0,
                 "the wrapper above a destroyed coupling keeps working");
  tl_solid_remove_wrapper(solid, &fw);
  free(u), free(f0), free(f1), free(g0), free(g1), free(F_nodes), free(F);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const TlElementType *types[] = {&tl_element_hex8, &tl_element_tet10};
  for (int k = 0; k < 2; ++k) {
    test_element(types[k], 0.0, TL_SCOUPLING_SUPPORT_SURFACE);
    test_element(types[k], 0.4, TL_SCOUPLING_SUPPORT_SURFACE);
    test_element(types[k], 0.4, TL_SCOUPLING_SUPPORT_ELEMENTS);
  }
  test_two_couplings();
  return tl_test_report();
}
