/* Closed surfaces meshed into tetrahedra (tl_mesh_from_surface): the mesh's
 * volume against the volume the surface encloses (and, for the sphere,
 * against 4/3 pi r^3), every Jacobian positive, the surface triangles as
 * the coupled boundary, the same mesh twice from the same seed; on the
 * generated Tet4 and Tet10 meshes the finite-strain solid reproduces a
 * linear displacement field (the patch test: boundary nodes prescribed,
 * interior nodes solved for) and feels no stress under a rigid rotation;
 * open, inside-out, non-manifold and self-intersecting surfaces are refused
 * with a message naming the edge or triangles. */
#include <math.h>
#include <string.h>
#include "talus.h"
#include "tl_config.h"
#include "tl_mesh_from_surface.h"
#include "tl_solid.h"
#include "tl_stl.h"
#include "tl_stepper.h"
#include "tl_test.h"

static const double E_mod = 1e8;

/* Smallest Jacobian determinant over the corners and the stiffness Gauss
 * points of every element, relative to the element's mean. */
static double min_jacobian(const TlMesh *m)
{
  double worst = INFINITY;
  const TlElementBlock *b = &m->blocks[0];
  TlQuadrature q;
  if (tl_element_quadrature(b->type, b->type->order_stiffness, &q)) return -1.0;
  double x[3 * TL_ELEMENT_MAX_NODES];
  for (size_t e = 0; e < b->n_elements; ++e) {
    tl_mesh_element_coords(m, 0, e, x);
    for (int p = 0; p < q.n + b->type->n_corners; ++p) {
      const double *xi = p < q.n ? q.xi[p] : b->type->ref_coords + 3 * (p - q.n);
      double J[3][3], det;
      if (tl_element_jacobian(b->type, 3, x, xi, J, &det)) return -1.0;
      if (det < worst) worst = det;
    }
  }
  return worst;
}

static TlMesh *mesh_of(const TlSurfaceArrays *s, const TlElementType *type, double h,
                       TlMeshFromSurfaceInfo *info)
{
  TlMeshFromSurfaceOptions o;
  tl_mesh_from_surface_options_default(&o);
  o.type = type;
  o.cell_size = h;
  o.facet_size = h;
  o.facet_distance = 0.02 * h;
  TlMesh *m = NULL;
  TL_TEST_STATUS(tl_mesh_from_surface(s, &o, &m, info), TL_OK);
  return m;
}

/* Volume, Jacobians, coupled boundary for one surface. */
static void check_mesh(const char *what, const TlSurfaceArrays *s, const TlElementType *type, double h,
                       double exact, double exact_tol)
{
  TlMeshFromSurfaceInfo info;
  TlMesh *m = mesh_of(s, type, h, &info);
  if (!m) return;
  double vol = tl_mesh_volume(m);
  double rel_surface = fabs(vol - info.surface_volume) / info.surface_volume;
  printf("%s %s: %zu triangles in, %zu tetrahedra, %zu nodes, %zu boundary faces; volume %.8g m^3, "
         "enclosed by the surface %.8g (rel. %.2e)", what, type->header.name, s->n_triangles,
         info.n_tetrahedra, info.n_nodes, info.n_boundary_faces, vol, info.surface_volume, rel_surface);
  if (exact > 0) printf(", exact %.8g (rel. %.2e)", exact, fabs(vol - exact) / exact);
  printf("; dihedral angles %.1f to %.1f degrees\n", info.min_dihedral, info.max_dihedral);
  TL_TEST_ASSERT(info.n_tetrahedra > 20, "%s: only %zu tetrahedra", what, info.n_tetrahedra);
  TL_TEST_CLOSE(vol / info.mesh_volume, 1.0, 1e-12); /* the mesh's own measure of its elements */
  /* The mesh's surface vertices lie on the input surface and its triangles
   * deviate from it by at most the facet distance (0.02 h): the volumes
   * differ by about that times the area. */
  double bound = 0.02 * h * info.surface_area / info.surface_volume;
  TL_TEST_ASSERT(rel_surface <= bound, "%s: mesh volume off the enclosed one by %.3e, bound %.3e", what,
                 rel_surface, bound);
  if (exact > 0)
    TL_TEST_ASSERT(fabs(vol - exact) / exact <= exact_tol, "%s: mesh volume off the exact %g by %.3e, "
                   "more than %.3e", what, exact, fabs(vol - exact) / exact, exact_tol);
  double jmin = min_jacobian(m);
  TL_TEST_ASSERT(jmin > 0.0, "%s: an element with Jacobian %g (inverted or degenerate)", what, jmin);
  TL_TEST_ASSERT(info.min_dihedral > 1.0, "%s: a sliver with dihedral angle %g degrees", what, info.min_dihedral);
  /* The face set "surface" is the whole boundary, and its area is the mesh
   * surface's: each boundary face's area from its face type. */
  const TlFaceSet *fs = NULL;
  TL_TEST_STATUS(tl_mesh_find_face_set(m, "surface", &fs), TL_OK);
  if (fs) {
    TL_TEST_ASSERT(fs->n == m->n_boundary && fs->n == info.n_boundary_faces, "%s: %zu surface faces, %zu boundary", what, fs->n, m->n_boundary);
    double area = 0.0;
    for (size_t i = 0; i < fs->n; ++i) {
      size_t nodes[TL_ELEMENT_MAX_FACE_NODES];
      double fx[3 * TL_ELEMENT_MAX_FACE_NODES], n[3];
      tl_mesh_face_nodes(m, fs->faces[i], nodes, fx);
      double sc[3] = {1.0 / 3.0, 1.0 / 3.0, 0.0};
      tl_element_face_normal(type->face_type, 3, fx, sc, n);
      area += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    TL_TEST_ASSERT(fabs(area - info.surface_area) / info.surface_area <= 2.0 * bound,
                   "%s: mesh surface %g m^2 against the input's %g", what, area, info.surface_area);
  }
  tl_mesh_destroy(&m);
}

static void affine(double t, const double X[3], int c, void *ctx, double out[3])
{
  const double *A = ctx;
  (void)t;
  out[0] = A[3 * c] * X[0] + A[3 * c + 1] * X[1] + A[3 * c + 2] * X[2];
  out[1] = out[2] = 0.0;
}

/* Patch test: u = A X prescribed on the surface nodes; the interior nodes,
 * solved for by Newton with the neo-Hookean law, must land on A X. */
static void patch_test(const TlSurfaceArrays *s, const TlElementType *type, double h)
{
  TlMesh *m = mesh_of(s, type, h, NULL);
  if (!m) return;
  TlMaterial *mat = NULL;
  TL_TEST_STATUS(tl_material_create("neo_hookean", &mat), TL_OK);
  tl_material_set(mat, "E", E_mod);
  tl_material_set(mat, "nu", 0.3);
  tl_material_set(mat, "density", 1000.0);
  TL_TEST_STATUS(tl_material_setup(mat), TL_OK);
  double A[9] = {0.02, 0.01, -0.005, 0.003, -0.01, 0.008, 0.004, 0.002, 0.015};
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(m, &solid), TL_OK);
  TL_TEST_STATUS(tl_solid_set_material(solid, NULL, mat), TL_OK);
  for (int c = 0; c < 3; ++c) TL_TEST_STATUS(tl_solid_prescribe(solid, "surface", c, affine, A), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlStepperOptions opt;
  tl_stepper_options_default(&opt);
  opt.rtol = 1e-13;
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("quasi_static", tl_solid_system(solid), &opt, &st), TL_OK);
  if (st) {
    TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
    TL_TEST_STATUS(tl_stepper_step(st, 1.0), TL_OK);
    const TlNodeSet *surf = NULL;
    TL_TEST_STATUS(tl_mesh_find_node_set(m, "surface", &surf), TL_OK);
    double err = 0.0, umax = 0.0;
    size_t interior = 0;
    for (size_t a = 0; a < m->n_nodes; ++a) {
      const double *X = m->x + 3 * a;
      int on = 0;
      for (size_t k = 0; surf && k < surf->n && !on; ++k) on = surf->nodes[k] == a;
      if (!on) ++interior;
      for (int c = 0; c < 3; ++c) {
        double expect = A[3 * c] * X[0] + A[3 * c + 1] * X[1] + A[3 * c + 2] * X[2];
        err = fmax(err, fabs(st->u[tl_solid_dof(solid, a, c)] - expect));
        umax = fmax(umax, fabs(expect));
      }
    }
    printf("patch test %s: %zu elements, %zu interior nodes solved for: largest |u - A X| = %.3e of |u| %.3e\n",
           type->header.name, m->blocks[0].n_elements, interior, err, umax);
    TL_TEST_ASSERT(interior > 10, "patch test %s: only %zu interior nodes", type->header.name, interior);
    TL_TEST_ASSERT(err <= 1e-10 * umax, "patch test %s: u off A X by %g (|u| %g)", type->header.name, err, umax);
  }
  tl_stepper_destroy(&st);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&m);
}

/* u = (R - 1) X + c: no internal force, no stress. */
static void rotation_test(const TlSurfaceArrays *s, const TlElementType *type, double h)
{
  TlMesh *m = mesh_of(s, type, h, NULL);
  if (!m) return;
  TlMaterial *mat = NULL;
  TL_TEST_STATUS(tl_material_create_hooke(E_mod, 0.3, 1000.0, &mat), TL_OK);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(m, &solid), TL_OK);
  TL_TEST_STATUS(tl_solid_set_material(solid, NULL, mat), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *f = calloc(n, sizeof *f), *un = calloc(3 * m->n_nodes, sizeof *un);
  TlMat3 R = tl_m3_rotation(tl_v3(1.0, -2.0, 0.5), 1.1);
  for (size_t a = 0; a < m->n_nodes; ++a) {
    TlVec3 X = tl_v3(m->x[3 * a], m->x[3 * a + 1], m->x[3 * a + 2]);
    TlVec3 x = tl_m3_mulv(R, X);
    double d[3] = {x.x - X.x + 0.3, x.y - X.y - 0.7, x.z - X.z + 1.1};
    for (int c = 0; c < 3; ++c) u[tl_solid_dof(solid, a, c)] = d[c];
  }
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f), TL_OK);
  double fmaxv = 0.0, smax = 0.0;
  for (size_t i = 0; i < n; ++i) fmaxv = fmax(fmaxv, fabs(f[i]));
  tl_solid_dofs_to_nodes(solid, u, un);
  for (size_t e = 0; e < m->blocks[0].n_elements; ++e) {
    TlMat3 F, S;
    TL_TEST_STATUS(tl_solid_gauss_stress(solid, 0, e, 0, un, &F, &S), TL_OK);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) smax = fmax(smax, fabs(S.m[i][j]));
  }
  double fscale = E_mod * h * h; /* stress scale times an element face */
  printf("rigid rotation %s (1.1 rad): largest internal force %.3e N (scale %.3e), stress %.3e Pa (E %.1e)\n",
         type->header.name, fmaxv, fscale, smax, E_mod);
  TL_TEST_ASSERT(fmaxv <= 1e-11 * fscale, "rotation %s: internal force %g N", type->header.name, fmaxv);
  TL_TEST_ASSERT(smax <= 1e-11 * E_mod, "rotation %s: stress %g Pa", type->header.name, smax);
  free(u), free(f), free(un);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&m);
}

/* A surface through a file: the sphere written as binary STL, read back
 * (corners joined), meshed; the same mesh as from the arrays, up to the
 * single-precision coordinates (volume within 1e-6). */
static void through_stl(const TlSurfaceArrays *s)
{
  int *tri = malloc(3 * s->n_triangles * sizeof *tri);
  for (size_t i = 0; i < 3 * s->n_triangles; ++i) tri[i] = (int)s->tri[i];
  TlSurfaceMesh *sm = NULL, *back = NULL;
  TL_TEST_STATUS(tl_surface_mesh_create(s->n_vertices, s->x, s->n_triangles, tri, &sm), TL_OK);
  const char *path = "test_mesh_from_surface_sphere.stl";
  TL_TEST_STATUS(tl_stl_write(path, sm, 1), TL_OK);
  TL_TEST_STATUS(tl_surface_mesh_read(path, &back), TL_OK);
  if (back) {
    TL_TEST_ASSERT(back->n_vertices == s->n_vertices && back->n_triangles == s->n_triangles,
                   "STL read back: %zu vertices, %zu triangles", back->n_vertices, back->n_triangles);
    TlMeshFromSurfaceOptions o;
    tl_mesh_from_surface_options_default(&o);
    o.cell_size = o.facet_size = 0.3;
    o.facet_distance = 0.006;
    TlMesh *a = NULL, *b = NULL;
    TlMeshFromSurfaceInfo ia, ib;
    TL_TEST_STATUS(tl_mesh_from_surface(s, &o, &a, &ia), TL_OK);
    TL_TEST_STATUS(tl_mesh_from_surface_mesh(back, &o, &b, &ib), TL_OK);
    if (a && b) {
      printf("through STL: %zu tetrahedra (arrays: %zu), volume %.9g (arrays: %.9g)\n", ib.n_tetrahedra,
             ia.n_tetrahedra, ib.mesh_volume, ia.mesh_volume);
      TL_TEST_REL(ib.mesh_volume, ia.mesh_volume, 1e-5);
    }
    tl_mesh_destroy(&a);
    tl_mesh_destroy(&b);
  }
  remove(path);
  tl_surface_mesh_destroy(&sm);
  tl_surface_mesh_destroy(&back);
  free(tri);
}

/* The same surface and seed give the same mesh (exudation included: it
 * runs to completion, not to a wall-clock limit). */
static void reproducible(const TlSurfaceArrays *s)
{
  TlMesh *a = mesh_of(s, &tl_element_tet4, 0.3, NULL), *b = mesh_of(s, &tl_element_tet4, 0.3, NULL);
  if (a && b) {
    int same = a->n_nodes == b->n_nodes && a->blocks[0].n_elements == b->blocks[0].n_elements &&
               !memcmp(a->x, b->x, 3 * a->n_nodes * sizeof(double)) &&
               !memcmp(a->blocks[0].conn, b->blocks[0].conn, 4 * a->blocks[0].n_elements * sizeof(size_t));
    TL_TEST_ASSERT(same, "two meshes of one surface and seed differ (%zu / %zu nodes)", a->n_nodes, b->n_nodes);
  }
  tl_mesh_destroy(&a);
  tl_mesh_destroy(&b);
}

static void expect_refusal(const char *what, const TlSurfaceArrays *s, const char *needle)
{
  TlMeshFromSurfaceOptions o;
  tl_mesh_from_surface_options_default(&o);
  o.cell_size = 0.3;
  TlMesh *m = NULL;
  TlStatus st = tl_mesh_from_surface(s, &o, &m, NULL);
  const char *msg = tl_error_message();
  printf("%s: %s\n", what, msg);
  TL_TEST_ASSERT(st == TL_ERR_ARG && !m, "%s: accepted (status %d)", what, (int)st);
  TL_TEST_ASSERT(strstr(msg, needle) != NULL, "%s: message '%s' does not say '%s'", what, msg, needle);
  tl_mesh_destroy(&m);
}

static void refusals(void)
{
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  TlSurfaceArrays box;
  TL_TEST_STATUS(tl_surface_box(lo, hi, 2, &box), TL_OK);
  size_t nt = box.n_triangles;
  size_t *tri = malloc(3 * nt * sizeof *tri);
  memcpy(tri, box.tri, 3 * nt * sizeof *tri);
  TlSurfaceArrays s = box;
  s.tri = tri;
  /* Open: the last triangle dropped. */
  s.n_triangles = nt - 1;
  expect_refusal("open box", &s, "is open: edge");
  s.n_triangles = nt;
  /* One triangle flipped. */
  size_t t0 = tri[0];
  tri[0] = tri[1];
  tri[1] = t0;
  expect_refusal("one triangle flipped", &s, "not consistently oriented");
  memcpy(tri, box.tri, 3 * nt * sizeof *tri);
  /* All flipped: inside out. */
  for (size_t t = 0; t < nt; ++t) {
    size_t x = tri[3 * t];
    tri[3 * t] = tri[3 * t + 1];
    tri[3 * t + 1] = x;
  }
  expect_refusal("inside out", &s, "inside out");
  memcpy(tri, box.tri, 3 * nt * sizeof *tri);
  /* A triangle repeated: non-manifold edges. */
  size_t *tri2 = malloc(3 * (nt + 2) * sizeof *tri2);
  memcpy(tri2, box.tri, 3 * nt * sizeof *tri2);
  memcpy(tri2 + 3 * nt, box.tri, 3 * sizeof *tri2);
  size_t flipped[3] = {box.tri[1], box.tri[0], box.tri[2]};
  memcpy(tri2 + 3 * nt + 3, flipped, sizeof flipped);
  TlSurfaceArrays s2 = {box.n_vertices, box.x, nt + 2, tri2};
  expect_refusal("a triangle twice", &s2, "not manifold");
  free(tri2);
  /* A vertex pushed through the opposite face: the surface intersects itself. */
  double *x = malloc(3 * box.n_vertices * sizeof *x);
  memcpy(x, box.x, 3 * box.n_vertices * sizeof *x);
  size_t centre = SIZE_MAX;
  for (size_t i = 0; i < box.n_vertices; ++i)
    if (fabs(x[3 * i] - 0.5) < 1e-12 && fabs(x[3 * i + 1] - 0.5) < 1e-12 && fabs(x[3 * i + 2] - 1.0) < 1e-12) centre = i;
  TL_TEST_ASSERT(centre != SIZE_MAX, "the box has a vertex at the centre of its top");
  if (centre != SIZE_MAX) {
    x[3 * centre + 2] = -0.5; /* the top's centre dragged below the bottom */
    TlSurfaceArrays s3 = {box.n_vertices, x, nt, box.tri};
#if TALUS_WITH_CGAL
    expect_refusal("self-intersecting", &s3, "intersects itself: triangles");
#else
    (void)s3;
#endif
  }
  free(x);
  free(tri);
  tl_surface_arrays_free(&box);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  refusals();
#if !TALUS_WITH_CGAL
  tl_test_report();
  return tl_test_skip("meshing needs CGAL (built without it); only the surface checks ran");
#else
  const double c[3] = {0.1, -0.2, 0.3}, r = 1.0;
  TlSurfaceArrays sphere, cone, box;
  TL_TEST_STATUS(tl_surface_sphere(c, r, 4, &sphere), TL_OK);
  const double apex[3] = {0, 0, -1}, lo[3] = {-0.5, -0.4, -0.3}, hi[3] = {0.5, 0.4, 0.3};
  TL_TEST_STATUS(tl_surface_cone(apex, 0.6, 1.2, 0.0, 48, &cone), TL_OK);
  TL_TEST_STATUS(tl_surface_box(lo, hi, 3, &box), TL_OK);
  /* The sphere against 4/3 pi r^3.  Two discretisations, each bounded: the
   * input polyhedron (5120 flat triangles, vertices on the sphere) encloses
   * less than the ball, by 1 - V_poly / V_ball = 2.2e-3 at level 4 (computed
   * from the polyhedron, not assumed); the mesh's surface triangles stand
   * off the polyhedron by about the facet distance delta = 0.02 h, which
   * changes the volume by at most delta A / V = 3 delta / r = 1.5e-2 at
   * h = 0.25 r.  The test allows their sum. */
  {
    double v_poly = 0.0;
    TL_TEST_STATUS(tl_surface_check(&sphere, &v_poly, NULL), TL_OK);
    const double v_ball = 4.0 / 3.0 * M_PI * r * r * r, h = 0.25 * r;
    const double tol = (1.0 - v_poly / v_ball) + 3.0 * 0.02 * h / r;
    printf("sphere: the input polyhedron encloses %.3e less than the ball; allowed mesh error %.3e\n",
           1.0 - v_poly / v_ball, tol);
    check_mesh("sphere", &sphere, &tl_element_tet4, h, v_ball, tol);
    check_mesh("sphere", &sphere, &tl_element_tet10, h, v_ball, tol);
  }
  /* The cone and the box are polyhedral with sharp edges (protected): their
   * volumes are the exact ones of the polyhedra. */
  check_mesh("cone", &cone, &tl_element_tet4, 0.15, 0.0, 0.0);
  {
    TlSurfaceArrays blunt;
    TL_TEST_STATUS(tl_surface_cone(apex, 0.6, 1.2, 0.15, 48, &blunt), TL_OK);
    check_mesh("truncated cone", &blunt, &tl_element_tet10, 0.15, 0.0, 0.0);
    tl_surface_arrays_free(&blunt);
  }
  check_mesh("box", &box, &tl_element_tet10, 0.2, 0.8 * 0.6, 1e-12);
  patch_test(&sphere, &tl_element_tet4, 0.35);
  patch_test(&sphere, &tl_element_tet10, 0.5);
  rotation_test(&cone, &tl_element_tet4, 0.15);
  rotation_test(&sphere, &tl_element_tet10, 0.4);
  reproducible(&sphere);
  through_stl(&sphere);
  tl_surface_arrays_free(&sphere);
  tl_surface_arrays_free(&cone);
  tl_surface_arrays_free(&box);
  return tl_test_report();
#endif
}
