/* The total-Lagrangian solid: patch tests (constant finite strain, exact to
 * round-off) for every element type, zero stress and residual under rigid
 * rotations (90 degrees and an arbitrary one), element tangents against
 * finite differences for every element type and law, the assembled tangent
 * with a follower pressure, mass matrices summing to the total mass,
 * energies, reactions, the rigid-body-mode check, and a uniaxial finite-
 * strain solve through the quasi-static stepper against the closed form. */
#include <math.h>
#include <stddef.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_test.h"

static const TlElementType *const types[] = {&tl_element_hex8,  &tl_element_hex27, &tl_element_tet4,
                                             &tl_element_tet10, &tl_element_quad4, &tl_element_quad8,
                                             &tl_element_tri3,  &tl_element_tri6};
static const double E_mod = 1e8;

static double urand(void) { return 2.0 * rand() / RAND_MAX - 1.0; }

/* A 2 x 2 (x 2) mesh of [0, 1.2] x [0, 1] (x [0, 0.8]) whose interior nodes
 * are moved at random, so that elements are distorted (and curved for the
 * quadratic types). */
/* Plane triangles: each cell of a quad4 / quad9 rectangle split along its
 * 0-2 diagonal; face sets named by the side they lie on. */
static TlMesh *triangle_mesh(const TlElementType *t)
{
  size_t n[2] = {2, 2};
  double lo[2] = {0, 0}, hi[2] = {1.2, 1.0};
  TlMesh *q = NULL, *m = NULL;
  int six = t == &tl_element_tri6;
  TL_TEST_STATUS(tl_mesh_create_rectangle(six ? &tl_element_quad9 : &tl_element_quad4, n, lo, hi, &q), TL_OK);
  if (!q) return NULL;
  const TlElementBlock *qb = &q->blocks[0];
  int qn = qb->type->n_nodes, tn = t->n_nodes;
  size_t ne = 2 * qb->n_elements;
  size_t *conn = calloc(ne * tn, sizeof *conn);
  static const int split3[2][3] = {{0, 1, 2}, {0, 2, 3}};
  static const int split6[2][6] = {{0, 1, 2, 4, 5, 8}, {0, 2, 3, 8, 6, 7}};
  for (size_t e = 0; e < qb->n_elements; ++e)
    for (int k = 0; k < 2; ++k)
      for (int a = 0; a < tn; ++a)
        conn[(2 * e + k) * tn + a] = qb->conn[e * qn + (six ? split6[k][a] : split3[k][a])];
  TL_TEST_STATUS(tl_mesh_create(2, &m), TL_OK);
  TL_TEST_STATUS(tl_mesh_set_nodes(m, q->n_nodes, q->x), TL_OK);
  TL_TEST_STATUS(tl_mesh_add_block(m, "body", t, ne, conn, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_mesh_finalize(m), TL_OK);
  const char *names[4] = {"xmin", "xmax", "ymin", "ymax"};
  TlFaceRef *faces = calloc(m->n_boundary, sizeof *faces);
  for (int side = 0; side < 4; ++side) {
    size_t nf = 0;
    for (size_t b = 0; b < m->n_boundary; ++b) {
      size_t fn[TL_ELEMENT_MAX_FACE_NODES];
      tl_mesh_face_nodes(m, m->boundary[b], fn, NULL);
      int all = 1;
      for (int k = 0; k < t->face_n_nodes; ++k)
        all &= fabs(m->x[3 * fn[k] + side / 2] - (side % 2 ? hi[side / 2] : lo[side / 2])) < 1e-12;
      if (all) faces[nf++] = m->boundary[b];
    }
    TL_TEST_STATUS(tl_mesh_add_face_set(m, names[side], nf, faces), TL_OK);
    TL_TEST_STATUS(tl_mesh_add_node_set_from_faces(m, names[side], names[side]), TL_OK);
  }
  free(faces);
  free(conn);
  tl_mesh_destroy(&q);
  return m;
}

static TlMesh *distorted_mesh(const TlElementType *t)
{
  TlMesh *m = NULL;
  TlStatus s;
  if (t->shape == TL_SHAPE_TRI) {
    m = triangle_mesh(t);
    s = m ? TL_OK : TL_ERR_ARG;
  } else if (t->dim == 3) {
    size_t n[3] = {2, 2, 2};
    double lo[3] = {0, 0, 0}, hi[3] = {1.2, 1.0, 0.8};
    s = tl_mesh_create_box(t, n, lo, hi, &m);
  } else {
    size_t n[2] = {2, 2};
    double lo[2] = {0, 0}, hi[2] = {1.2, 1.0};
    s = tl_mesh_create_rectangle(t, n, lo, hi, &m);
  }
  TL_TEST_STATUS(s, TL_OK);
  if (!m) return NULL;
  double hi[3] = {1.2, 1.0, 0.8};
  for (size_t i = 0; i < m->n_nodes; ++i) {
    double *x = m->x + 3 * i;
    int interior = 1;
    for (int d = 0; d < t->dim; ++d) interior &= x[d] > 1e-12 && x[d] < hi[d] - 1e-12;
    if (interior)
      for (int d = 0; d < t->dim; ++d) x[d] += (t->n_nodes == t->n_corners ? 0.06 : 0.015) * urand();
  }
  TL_TEST_STATUS(tl_mesh_finalize(m), TL_OK);
  return m;
}

static TlMaterial *make_law(const char *name, double nu)
{
  TlMaterial *m = NULL;
  TL_TEST_STATUS(tl_material_create(name, &m), TL_OK);
  tl_material_set(m, "E", E_mod);
  tl_material_set(m, "nu", nu);
  tl_material_set(m, "density", 1309.0);
  TL_TEST_STATUS(tl_material_setup(m), TL_OK);
  return m;
}

static double max_abs(const double *v, size_t n)
{
  double m = 0.0;
  for (size_t i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
  return m;
}

/* Constant-strain patch: u = A X; tractions P N on every boundary face set
 * must balance the internal forces at every node, to round-off. */
static void patch_test(const TlElementType *t, const char *law)
{
  TlMesh *mesh = distorted_mesh(t);
  TlMaterial *mat = make_law(law, 0.3);
  if (!mesh || !mat) return;
  int dim = t->dim;
  double A[3][3] = {{0.02, 0.01, -0.005}, {0.003, -0.01, 0.008}, {0.004, 0.002, 0.015}};
  TlMat3 F = tl_m3_identity(), S;
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) F.m[i][j] += A[i][j];
  double st[64] = {0}, st2[64] = {0};
  if (mat->state_size) mat->ops->init_state(mat, 1, st);
  TL_TEST_STATUS(tl_material_evaluate(mat, 1, &F, mat->state_size ? st : NULL, mat->state_size ? st2 : NULL, &S, NULL, NULL), TL_OK);
  TlMat3 P = tl_m3_mul(F, S);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  TL_TEST_STATUS(tl_solid_set_material(solid, NULL, mat), TL_OK);
  const char *names[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
  for (int f = 0; f < 2 * dim; ++f) {
    TlVec3 N = tl_v3(0, 0, 0);
    double sign = f % 2 ? 1.0 : -1.0;
    if (f / 2 == 0) N.x = sign;
    if (f / 2 == 1) N.y = sign;
    if (f / 2 == 2) N.z = sign;
    TL_TEST_STATUS(tl_solid_add_traction(solid, names[f], tl_m3_mulv(P, N), NULL, NULL), TL_OK);
  }
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *fi = calloc(n, sizeof *fi), *fe = calloc(n, sizeof *fe);
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int i = 0; i < dim; ++i) {
      double v = 0.0;
      for (int j = 0; j < dim; ++j) v += A[i][j] * mesh->x[3 * a + j];
      u[tl_solid_dof(solid, a, i)] = v;
    }
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, fi), TL_OK);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, fe), TL_OK);
  double scale = max_abs(fe, n), err = 0.0;
  for (size_t i = 0; i < n; ++i) err = fmax(err, fabs(fi[i] - fe[i]));
  TL_TEST_ASSERT(scale > 0 && err <= 1e-12 * scale, "patch %s/%s: |f_int - f_ext| = %g of %g", t->header.name,
                 law, err, scale);
  /* F is the imposed one at every Gauss point. */
  double *un = calloc(mesh->n_nodes * dim, sizeof *un);
  tl_solid_dofs_to_nodes(solid, u, un);
  double ferr = 0.0;
  for (size_t e = 0; e < mesh->blocks[0].n_elements; ++e) {
    TlMat3 Fq, Sq;
    TL_TEST_STATUS(tl_solid_gauss_stress(solid, 0, e, 0, un, &Fq, &Sq), TL_OK);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) ferr = fmax(ferr, fabs(Fq.m[i][j] - F.m[i][j]));
  }
  TL_TEST_ASSERT(ferr < 1e-14, "patch %s/%s: F off by %g", t->header.name, law, ferr);
  /* Strain energy of the patch: W(F) V (potential laws). */
  if (!strcmp(law, "neo_hookean")) {
    double W = 0.0, Wd;
    TL_TEST_STATUS(tl_solid_strain_energy(solid, u, &W), TL_OK);
    tl_material_evaluate(mat, 1, &F, NULL, NULL, &S, NULL, &Wd);
    TL_TEST_CLOSE(W / (Wd * tl_mesh_volume(mesh)), 1.0, 1e-12);
  }
  free(u), free(fi), free(fe), free(un);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* Rigid motion u = (R - 1) X + c: zero stress and zero residual. */
static void rotation_test(const TlElementType *t, TlMat3 R, const char *what)
{
  TlMesh *mesh = distorted_mesh(t);
  TlMaterial *mat = make_law("hooke", 0.3);
  if (!mesh || !mat) return;
  int dim = t->dim;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *f = calloc(n, sizeof *f);
  double c[3] = {0.3, -0.7, 1.1};
  for (size_t a = 0; a < mesh->n_nodes; ++a) {
    TlVec3 X = tl_v3(mesh->x[3 * a], mesh->x[3 * a + 1], mesh->x[3 * a + 2]);
    TlVec3 x = tl_m3_mulv(R, X);
    double d[3] = {x.x - X.x + c[0], x.y - X.y + c[1], x.z - X.z + c[2]};
    for (int i = 0; i < dim; ++i) u[tl_solid_dof(solid, a, i)] = d[i];
  }
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f), TL_OK);
  double fscale = E_mod * 0.25; /* stress scale x element face area */
  TL_TEST_ASSERT(max_abs(f, n) < 1e-12 * fscale, "%s rotation %s: residual %g", t->header.name, what, max_abs(f, n));
  double *un = calloc(mesh->n_nodes * dim, sizeof *un);
  tl_solid_dofs_to_nodes(solid, u, un);
  double smax = 0.0;
  for (size_t e = 0; e < mesh->blocks[0].n_elements; ++e) {
    TlMat3 Fq, Sq;
    tl_solid_gauss_stress(solid, 0, e, 0, un, &Fq, &Sq);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) smax = fmax(smax, fabs(Sq.m[i][j]));
  }
  TL_TEST_ASSERT(smax < 1e-12 * E_mod, "%s rotation %s: stress %g", t->header.name, what, smax);
  free(u), free(f), free(un);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* Element tangent against central differences of the element residual. */
static void tangent_test(const TlElementType *t, const char *law, double nu)
{
  TlMesh *mesh = distorted_mesh(t);
  TlMaterial *mat = make_law(law, nu);
  if (!mesh || !mat) return;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  int nd = t->n_nodes * t->dim;
  double *ue = calloc(nd, sizeof *ue), *f0 = calloc(nd, sizeof *f0), *fp = calloc(nd, sizeof *fp),
         *fm = calloc(nd, sizeof *fm), *K = calloc((size_t)nd * nd, sizeof *K);
  double worst = 0.0;
  for (size_t e = 0; e < mesh->blocks[0].n_elements && e < 3; ++e) {
    for (int i = 0; i < nd; ++i) ue[i] = 0.04 * urand();
    TL_TEST_STATUS(tl_solid_element_matrices(solid, 0, e, ue, f0, K, NULL), TL_OK);
    double kmax = max_abs(K, (size_t)nd * nd), err = 0.0;
    /* Central differences with Richardson extrapolation (steps h and h/2):
     * truncation O(h^4), so strongly deformed elements are checked as
     * sharply as mildly deformed ones. */
    for (int c = 0; c < nd; ++c) {
      double keep = ue[c], h = 1e-5;
      for (int r = 0; r < nd; ++r) f0[r] = 0.0;
      for (int level = 0; level < 2; ++level) {
        double hl = level ? 0.5 * h : h, wgt = level ? 4.0 / 3.0 : -1.0 / 3.0;
        ue[c] = keep + hl;
        tl_solid_element_matrices(solid, 0, e, ue, fp, NULL, NULL);
        ue[c] = keep - hl;
        tl_solid_element_matrices(solid, 0, e, ue, fm, NULL, NULL);
        for (int r = 0; r < nd; ++r) f0[r] += wgt * (fp[r] - fm[r]) / (2 * hl);
      }
      ue[c] = keep;
      for (int r = 0; r < nd; ++r) err = fmax(err, fabs(f0[r] - K[r * nd + c]));
    }
    worst = fmax(worst, err / kmax);
  }
  printf("tangent %s/%s nu=%g: max relative error %.2e\n", t->header.name, law, nu, worst);
  TL_TEST_ASSERT(worst < 1e-6, "%s/%s nu=%g: tangent off finite differences by %g (relative)", t->header.name,
                 law, nu, worst);
  free(ue), free(f0), free(fp), free(fm), free(K);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* The residual-only kernel (component-major points, vector lanes) against
 * the general element path, which the stored energy's request selects: the
 * same nodal forces to round-off, with an eigenstrain and an initial stress
 * in the law. */
static void residual_path_test(const TlElementType *t, const char *law)
{
  TlMesh *mesh = distorted_mesh(t);
  TlMaterial *mat = make_law(law, 0.0);
  if (!mesh || !mat) return;
  TL_TEST_STATUS(tl_material_set_eigenstrain(mat, (TlMat3){{{0.002, 0.001, 0}, {0.001, -0.003, 0}, {0, 0, 0.001}}}),
                 TL_OK);
  TL_TEST_STATUS(tl_material_set_initial_stress(mat, (TlMat3){{{2e5, 0, 1e4}, {0, -1e5, 0}, {1e4, 0, 3e4}}}), TL_OK);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  const size_t nc = mesh->n_nodes * 3;
  double *u = calloc(nc, sizeof *u), *f_fast = calloc(nc, sizeof *f_fast), *f_gen = calloc(nc, sizeof *f_gen);
  for (size_t i = 0; i < nc; ++i) u[i] = 0.03 * urand();
  double W = 0.0;
  TL_TEST_STATUS(tl_solid_block_forces(solid, 0, u, f_fast, 0.0, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_block_forces(solid, 0, u, f_gen, 0.0, NULL, &W), TL_OK);
  const double f_max = max_abs(f_gen, nc);
  double err = 0.0;
  for (size_t i = 0; i < nc; ++i) err = fmax(err, fabs(f_fast[i] - f_gen[i]));
  printf("residual path %s/%s: %.2e of the largest force %.3g N\n", t->header.name, law, err / f_max, f_max);
  TL_TEST_ASSERT(f_max > 0.0 && err <= 1e-13 * f_max, "%s/%s: residual-only forces differ by %g of %g",
                 t->header.name, law, err, f_max);
  free(u), free(f_fast), free(f_gen);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* Assembled tangent (internal minus follower-load tangent) against
 * differences of the assembled residual; masses; energies; reactions. */
static void system_test(const TlElementType *t)
{
  TlMesh *mesh = distorted_mesh(t);
  TlMaterial *mat = make_law("neo_hookean", 0.3);
  if (!mesh || !mat) return;
  int dim = t->dim;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_add_pressure(solid, "xmax", 3e6, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_add_gravity(solid, tl_v3(0, -9.81, 0)), TL_OK);
  TL_TEST_STATUS(tl_solid_fix(solid, "xmin", (1 << dim) - 1), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TL_TEST_STATUS(tl_solid_check_constraints(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  TL_TEST_ASSERT(!sys->symmetric, "follower pressure must make the system non-symmetric");
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *d = calloc(n, sizeof *d), *up = calloc(n, sizeof *up),
         *rp = calloc(n, sizeof *rp), *rm = calloc(n, sizeof *rm), *fx = calloc(n, sizeof *fx),
         *Kd = calloc(n, sizeof *Kd), *ones = calloc(n, sizeof *ones), *Mo = calloc(n, sizeof *Mo);
  for (size_t i = 0; i < n; ++i) {
    u[i] = 0.03 * urand();
    d[i] = urand();
  }
  TlSparse *K = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 0, &K), TL_OK);
  if (!K) return;
  TL_TEST_STATUS(sys->ops->internal_tangent(sys, 0.0, u, NULL, 1.0, 0.0, K), TL_OK);
  TL_TEST_STATUS(sys->ops->external_tangent(sys, 0.0, u, -1.0, K), TL_OK);
  tl_sparse_matvec(K, d, Kd);
  double h = 1e-7;
  for (int sgn = 0; sgn < 2; ++sgn) {
    double *r = sgn ? rm : rp;
    for (size_t i = 0; i < n; ++i) up[i] = u[i] + (sgn ? -h : h) * d[i];
    sys->ops->internal_force(sys, 0.0, up, NULL, r);
    sys->ops->external_force(sys, 0.0, up, fx);
    for (size_t i = 0; i < n; ++i) r[i] -= fx[i];
  }
  double err = 0.0;
  for (size_t i = 0; i < n; ++i) err = fmax(err, fabs((rp[i] - rm[i]) / (2 * h) - Kd[i]));
  TL_TEST_ASSERT(err < 1e-6 * max_abs(Kd, n), "%s: assembled tangent off by %g of %g", t->header.name, err,
                 max_abs(Kd, n));
  /* Masses: consistent and lumped both sum to rho V per direction. */
  double mass = 1309.0 * tl_mesh_volume(mesh);
  TL_TEST_CLOSE(tl_solid_total_mass(solid) / mass, 1.0, 1e-13);
  tl_sparse_zero(K);
  TL_TEST_STATUS(sys->ops->consistent_mass(sys, 1.0, K), TL_OK);
  /* Free-body check on the unconstrained nodes is incomplete here (xmin is
   * clamped), so compare M 1 summed over free dofs with the lumped sum. */
  for (size_t a = 0; a < mesh->n_nodes; ++a) {
    TlSparseIndex k = tl_solid_dof(solid, a, 0);
    if (k >= 0) ones[k] = 1.0;
  }
  double *ml = calloc(n, sizeof *ml);
  sys->ops->lumped_mass(sys, ml);
  tl_sparse_matvec(K, ones, Mo);
  double sum_c = 0.0, sum_l = 0.0;
  for (size_t i = 0; i < n; ++i) sum_c += ones[i] * Mo[i], sum_l += ones[i] * ml[i];
  TL_TEST_ASSERT(sum_c > 0 && sum_l > 0 && sum_c < mass && sum_l < mass, "free-dof masses %g %g of %g", sum_c,
                 sum_l, mass);
  /* Kinetic energy of a uniform velocity on the free dofs equals 1/2 1.M.1. */
  double Ek = 0.0;
  TL_TEST_STATUS(tl_solid_kinetic_energy(solid, ones, &Ek), TL_OK);
  TL_TEST_CLOSE(Ek, 0.5 * sum_c, 1e-12);
  tl_sparse_destroy(&K);
  free(u), free(d), free(up), free(rp), free(rm), free(fx), free(Kd), free(ones), free(Mo), free(ml);
  tl_solid_destroy(&solid);
  tl_mesh_destroy(&mesh);

  /* An unconstrained copy: the full consistent mass sums to rho V in each
   * direction, and so does the lumped one. */
  mesh = distorted_mesh(t);
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  sys = tl_solid_system(solid);
  n = (size_t)sys->ndof;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, sys->symmetric, &K), TL_OK);
  TL_TEST_STATUS(sys->ops->consistent_mass(sys, 1.0, K), TL_OK);
  ones = calloc(n, sizeof *ones), Mo = calloc(n, sizeof *Mo);
  mass = 1309.0 * tl_mesh_volume(mesh);
  for (int c = 0; c < dim; ++c) {
    memset(ones, 0, n * sizeof *ones);
    for (size_t a = 0; a < mesh->n_nodes; ++a) ones[tl_solid_dof(solid, a, c)] = 1.0;
    tl_sparse_matvec(K, ones, Mo);
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) sum += ones[i] * Mo[i];
    TL_TEST_CLOSE(sum / mass, 1.0, 1e-13);
  }
  TL_TEST_STATUS(tl_solid_check_constraints(solid), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "body") && strstr(tl_error_message(), "translation along x"),
                 "free-body message: %s", tl_error_message());
  tl_sparse_destroy(&K);
  free(ones), free(Mo);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* Prescribed displacement u = A X on xmin: the reactions there balance the
 * tractions on the other faces. */
static void prescribed_affine(double t, const double X[3], int component, void *ctx, double out[3])
{
  const double *A = ctx;
  out[0] = t * (A[3 * component] * X[0] + A[3 * component + 1] * X[1] + A[3 * component + 2] * X[2]);
  out[1] = out[0] / (t == 0.0 ? 1.0 : t);
  out[2] = 0.0;
}

static void reaction_test(void)
{
  TlMesh *mesh = distorted_mesh(&tl_element_hex8);
  TlMaterial *mat = make_law("neo_hookean", 0.25);
  if (!mesh || !mat) return;
  double A[9] = {0.02, 0.0, 0.0, 0.0, -0.005, 0.0, 0.0, 0.0, -0.005};
  TlMat3 F = {{{1.02, 0, 0}, {0, 0.995, 0}, {0, 0, 0.995}}}, S;
  tl_material_evaluate(mat, 1, &F, NULL, NULL, &S, NULL, NULL);
  TlMat3 P = tl_m3_mul(F, S);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  for (int c = 0; c < 3; ++c) TL_TEST_STATUS(tl_solid_prescribe(solid, "xmin", c, prescribed_affine, A), TL_OK);
  const char *names[5] = {"xmax", "ymin", "ymax", "zmin", "zmax"};
  TlVec3 normals[5] = {{1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  for (int f = 0; f < 5; ++f) tl_solid_add_traction(solid, names[f], tl_m3_mulv(P, normals[f]), NULL, NULL);
  TL_TEST_STATUS(tl_solid_fix(solid, "xmin", 1), TL_ERR_ARG); /* already prescribed */
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TL_TEST_STATUS(tl_solid_check_constraints(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof, nc = mesh->n_nodes * 3;
  TL_TEST_ASSERT(sys->n_dirichlet == 27, "%ld Dirichlet dofs", (long)sys->n_dirichlet);
  double *u = calloc(n, sizeof *u), *R = calloc(nc, sizeof *R);
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int c = 0; c < 3; ++c) {
      double out[3];
      prescribed_affine(1.0, mesh->x + 3 * a, c, A, out);
      u[tl_solid_dof(solid, a, c)] = out[0];
    }
  double *check = calloc(n, sizeof *check);
  memcpy(check, u, n * sizeof *u);
  TL_TEST_STATUS(sys->ops->dirichlet(sys, 1.0, check, NULL, NULL), TL_OK);
  double derr = 0.0;
  for (size_t i = 0; i < n; ++i) derr = fmax(derr, fabs(check[i] - u[i]));
  TL_TEST_ASSERT(derr == 0.0, "dirichlet values differ by %g", derr);
  TL_TEST_STATUS(tl_solid_reactions(solid, 1.0, u, NULL, R), TL_OK);
  double sum[3] = {0, 0, 0};
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int c = 0; c < 3; ++c) sum[c] += R[3 * a + c];
  /* Expected: the traction P (-e_x) over the xmin face (area 1 x 0.8). */
  TlVec3 expect = tl_v3_scale(tl_m3_mulv(P, tl_v3(-1, 0, 0)), 0.8);
  TL_TEST_CLOSE(sum[0] / expect.x, 1.0, 1e-11);
  TL_TEST_ASSERT(fabs(sum[1]) < 1e-9 * fabs(expect.x) && fabs(sum[2]) < 1e-9 * fabs(expect.x), "shear reactions %g %g",
                 sum[1], sum[2]);
  free(u), free(R), free(check);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* Uniaxial stretch of a bar with symmetry conditions under a dead traction
 * P on xmax, solved by the quasi-static stepper.  For Eq. 34 with nu = 0,
 * F = diag(lambda, 1, 1) and P = E (lambda^2 - 1) / (2 lambda^3)
 * (contravariant reading) or E lambda^5 (lambda^2 - 1) / 2 (covariant). */
static void uniaxial_test(const char *law, double lambda)
{
  size_t n[3] = {4, 1, 1};
  double lo[3] = {0, 0, 0}, hi[3] = {2.0, 0.5, 0.5};
  TlMesh *mesh = NULL;
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &mesh), TL_OK);
  TlMaterial *mat = make_law(law, 0.0);
  if (!mesh || !mat) return;
  double P = !strcmp(law, "hooke") ? E_mod * (lambda * lambda - 1) / (2 * pow(lambda, 3))
                                   : E_mod * pow(lambda, 5) * (lambda * lambda - 1) / 2;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  tl_solid_fix(solid, "xmin", 1);
  tl_solid_fix(solid, "ymin", 2);
  tl_solid_fix(solid, "zmin", 4);
  tl_solid_add_traction(solid, "xmax", tl_v3(P, 0, 0), NULL, NULL);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TL_TEST_STATUS(tl_solid_check_constraints(solid), TL_OK);
  TlStepperOptions opt;
  tl_stepper_options_default(&opt);
  opt.ramp_time = 1.0;
  TlStepper *st = NULL;
  TL_TEST_STATUS(tl_stepper_create("quasi_static", tl_solid_system(solid), &opt, &st), TL_OK);
  if (!st) return;
  TL_TEST_STATUS(tl_stepper_set_state(st, 0.0, NULL, NULL), TL_OK);
  for (int k = 0; k < 4; ++k) TL_TEST_STATUS(tl_stepper_step(st, 0.25), TL_OK);
  double err = 0.0;
  for (size_t a = 0; a < mesh->n_nodes; ++a) {
    const double *X = mesh->x + 3 * a;
    double expect[3] = {(lambda - 1) * X[0], 0, 0};
    for (int c = 0; c < 3; ++c) {
      TlSparseIndex d = tl_solid_dof(solid, a, c);
      double v = d >= 0 ? st->u[d] : 0.0;
      err = fmax(err, fabs(v - expect[c]));
    }
  }
  TL_TEST_ASSERT(err < 1e-9 * (lambda - 1) * 2.0, "%s uniaxial lambda=%g: displacement off by %g", law, lambda, err);
  tl_stepper_destroy(&st);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* A spring of stiffness k between two nodes (a, b) of one element, with
 * its tangent (inside the element's pattern). */
typedef struct {
  size_t a, b;
  double k;
} Spring;

static TlStatus spring_term(const Spring *sp, TlSolid *solid, const double *u, double *f, double c_u, TlSparse *K)
{
  int dim = tl_solid_mesh(solid)->dim;
  if (f)
    for (int c = 0; c < dim; ++c) {
      double d = u[sp->a * dim + c] - u[sp->b * dim + c];
      f[sp->a * dim + c] += sp->k * d;
      f[sp->b * dim + c] -= sp->k * d;
    }
  if (K) {
    double Ke[36] = {0};
    size_t nodes[2] = {sp->a, sp->b};
    for (int c = 0; c < dim; ++c) {
      int n2 = 2 * dim;
      Ke[c * n2 + c] = sp->k, Ke[(dim + c) * n2 + dim + c] = sp->k;
      Ke[c * n2 + dim + c] = -sp->k, Ke[(dim + c) * n2 + c] = -sp->k;
    }
    TL_CHECK(tl_solid_matrix_add_nodes(solid, K, 2, nodes, c_u, Ke));
  }
  return TL_OK;
}

/* A block wrapper (what coupling element types do): the solid evaluates
 * the block's elements, then the wrapper adds a spring between two nodes of
 * element 0 (an internal term) and counts its calls; a second wrapper puts
 * a dead point load on a node (an external load). */
typedef struct {
  Spring spring;
  int calls;
  double t_seen;
} Wrapper;

static TlStatus wrapper_spring(void *ctx, TlSolid *solid, int b, double t, const double *u, double *f, double c_u,
                               TlSparse *K, double *W)
{
  (void)b, (void)W;
  Wrapper *w = ctx;
  w->calls++;
  w->t_seen = t;
  return spring_term(&w->spring, solid, u, f, c_u, K);
}

typedef struct {
  size_t node;
  double f;
} PointLoad;

static TlStatus wrapper_load(void *ctx, TlSolid *solid, int b, double t, const double *u, double *f, double c,
                             TlSparse *K)
{
  (void)b, (void)t, (void)u, (void)c, (void)K;
  const PointLoad *p = ctx;
  if (f) f[p->node * tl_solid_mesh(solid)->dim + 1] += p->f;
  return TL_OK;
}

static const TlSolidWrapperOps spring_ops = {.header = {"solid_wrapper", "test_spring", "spring"},
                                             .internal = wrapper_spring};
static const TlSolidWrapperOps load_ops = {.header = {"solid_wrapper", "test_load", "point load"},
                                           .external = wrapper_load};

static void wrap_test(void)
{
  TlMesh *mesh = distorted_mesh(&tl_element_hex8);
  TlMaterial *mat = make_law("neo_hookean", 0.3);
  if (!mesh || !mat) return;
  const size_t *conn = mesh->blocks[0].conn;
  Wrapper w = {{conn[0], conn[6], 3e7}, 0, 0.0};
  PointLoad pl = {conn[6], 250.0};
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *d = calloc(n, sizeof *d), *up = calloc(n, sizeof *up), *rp = calloc(n, sizeof *rp),
         *rm = calloc(n, sizeof *rm), *Kd = calloc(n, sizeof *Kd), *f0 = calloc(n, sizeof *f0), *g0 = calloc(n, sizeof *g0);
  for (size_t i = 0; i < n; ++i) u[i] = 0.02 * urand(), d[i] = urand();
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f0), TL_OK);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, g0), TL_OK);
  TlSolidWrapper *hs = NULL, *hl = NULL, *bad = NULL;
  TL_TEST_STATUS(tl_solid_add_wrapper(solid, 1, &spring_ops, &w, &bad), TL_ERR_ARG);
  TL_TEST_ASSERT(bad == NULL, "refused wrapper: no handle");
  TL_TEST_STATUS(tl_solid_add_wrapper(solid, 0, &spring_ops, &w, &hs), TL_OK);
  TL_TEST_STATUS(tl_solid_add_wrapper(solid, 0, &load_ops, &pl, &hl), TL_OK);
  TL_TEST_ASSERT(hs && hl && tl_solid_n_wrappers(solid, 0) == 2, "two wrappers installed (%d)", tl_solid_n_wrappers(solid, 0));
  TL_TEST_STATUS(sys->ops->internal_force(sys, 2.5, u, NULL, rp), TL_OK);
  TL_TEST_ASSERT(w.calls == 1 && w.t_seen == 2.5, "wrapper called once with t = 2.5 (got %d, %g)", w.calls, w.t_seen);
  /* The force added is the spring's, exactly where it acts. */
  double worst = 0.0;
  for (size_t node = 0; node < mesh->n_nodes; ++node)
    for (int c = 0; c < 3; ++c) {
      TlSparseIndex i = tl_solid_dof(solid, node, c);
      if (i < 0) continue;
      double dd = u[tl_solid_dof(solid, w.spring.a, c)] - u[tl_solid_dof(solid, w.spring.b, c)];
      double expect = node == w.spring.a ? w.spring.k * dd : node == w.spring.b ? -w.spring.k * dd : 0.0;
      worst = fmax(worst, fabs(rp[i] - f0[i] - expect));
    }
  TL_TEST_ASSERT(worst < 1e-12 * max_abs(f0, n), "wrapped block adds the spring force (off by %g)", worst);
  /* The external load enters f_ext, exactly, and nothing else moves. */
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, rm), TL_OK);
  worst = 0.0;
  for (size_t i = 0; i < n; ++i) worst = fmax(worst, fabs(rm[i] - g0[i] - (i == (size_t)tl_solid_dof(solid, pl.node, 1) ? pl.f : 0.0)));
  TL_TEST_ASSERT(worst == 0.0, "the wrapper's external load is in f_ext (off by %g)", worst);
  /* Its tangent enters the system's through the element pattern. */
  TlSparse *K = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 1, &K), TL_OK);
  if (!K) return;
  TL_TEST_STATUS(sys->ops->internal_tangent(sys, 0.0, u, NULL, 1.0, 0.0, K), TL_OK);
  tl_sparse_matvec(K, d, Kd);
  double h = 1e-7, err = 0.0;
  for (size_t i = 0; i < n; ++i) up[i] = u[i] + h * d[i];
  sys->ops->internal_force(sys, 0.0, up, NULL, rp);
  for (size_t i = 0; i < n; ++i) up[i] = u[i] - h * d[i];
  sys->ops->internal_force(sys, 0.0, up, NULL, rm);
  for (size_t i = 0; i < n; ++i) err = fmax(err, fabs((rp[i] - rm[i]) / (2 * h) - Kd[i]));
  TL_TEST_ASSERT(err < 1e-6 * max_abs(Kd, n), "tangent of a wrapped block off by %g of %g", err, max_abs(Kd, n));
  /* Removed in the order of installation (the first under the second): the
   * solid's own force and load again, bit for bit. */
  tl_solid_remove_wrapper(solid, &hs);
  TL_TEST_ASSERT(hs == NULL && tl_solid_n_wrappers(solid, 0) == 1, "first wrapper removed from under the second");
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, rp), TL_OK);
  TL_TEST_ASSERT(memcmp(rp, f0, n * sizeof *rp) == 0, "without the spring: the own kernel's force");
  tl_solid_remove_wrapper(solid, &hl);
  tl_solid_remove_wrapper(solid, &hl); /* a removed handle is NULL: nothing */
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, u, rm), TL_OK);
  TL_TEST_ASSERT(memcmp(rm, g0, n * sizeof *rm) == 0 && tl_solid_n_wrappers(solid, 0) == 0,
                 "unwrapped block gives the own external force");
  /* A wrapper left on is freed with the solid. */
  TL_TEST_STATUS(tl_solid_add_wrapper(solid, 0, &spring_ops, &w, &hs), TL_OK);
  tl_sparse_destroy(&K);
  free(u), free(d), free(up), free(rp), free(rm), free(Kd), free(f0), free(g0);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* An isotropic eigenstrain e0 on a free body: the stress-free state
 * F = sqrt(1 + 2 e0) 1 has zero residual at every node. */
/* Weights of a block's equations (seeds/001 Eq. 26): weights 1 change
 * nothing, bit for bit; weights 0.3 scale force, tangent, energy and both
 * masses by 0.3, and the tangent still matches finite differences. */
typedef struct {
  TlSolid *solid;
  TlMechSystem *sys;
  size_t n;
  double *f, *Kd, *ml, *Mo, W;
} WeightedRun;

static void weighted_run(TlMesh *mesh, TlMaterial *mat, int mode, double value, const double *u, const double *d,
                         WeightedRun *r)
{
  memset(r, 0, sizeof *r);
  TL_TEST_STATUS(tl_solid_create(mesh, &r->solid), TL_OK);
  tl_solid_set_material(r->solid, NULL, mat);
  int nq = 0, nqm = 0;
  TL_TEST_STATUS(tl_solid_weight_points(r->solid, 0, &nq, &nqm), TL_OK);
  size_t ne = mesh->blocks[0].n_elements;
  double *w = calloc(ne * nq, sizeof *w), *wm = calloc(ne * nqm, sizeof *wm);
  for (size_t k = 0; k < ne * nq; ++k) w[k] = value;
  for (size_t k = 0; k < ne * nqm; ++k) wm[k] = value;
  if (mode == 1) TL_TEST_STATUS(tl_solid_set_point_weights(r->solid, 0, w, wm), TL_OK);
  free(w), free(wm);
  TL_TEST_STATUS(tl_solid_setup(r->solid), TL_OK);
  r->sys = tl_solid_system(r->solid);
  r->n = (size_t)r->sys->ndof;
  size_t n = r->n;
  r->f = calloc(n, sizeof(double)), r->Kd = calloc(n, sizeof(double)), r->ml = calloc(n, sizeof(double)),
  r->Mo = calloc(n, sizeof(double));
  TL_TEST_STATUS(r->sys->ops->internal_force(r->sys, 0.0, u, NULL, r->f), TL_OK);
  TlSparse *K = NULL;
  TL_TEST_STATUS(r->sys->ops->create_matrix(r->sys, 0, &K), TL_OK);
  if (!K) return;
  TL_TEST_STATUS(r->sys->ops->internal_tangent(r->sys, 0.0, u, NULL, 1.0, 0.0, K), TL_OK);
  tl_sparse_matvec(K, d, r->Kd);
  tl_sparse_zero(K);
  TL_TEST_STATUS(r->sys->ops->consistent_mass(r->sys, 1.0, K), TL_OK);
  tl_sparse_matvec(K, d, r->Mo);
  r->sys->ops->lumped_mass(r->sys, r->ml);
  TL_TEST_STATUS(tl_solid_strain_energy(r->solid, u, &r->W), TL_OK);
  tl_sparse_destroy(&K);
}

static void weighted_free(WeightedRun *r)
{
  free(r->f), free(r->Kd), free(r->ml), free(r->Mo);
  tl_solid_destroy(&r->solid);
}

static double max_diff_scaled(const double *a, const double *b, double s, size_t n)
{
  double m = 0.0;
  for (size_t i = 0; i < n; ++i) m = fmax(m, fabs(a[i] - s * b[i]));
  return m;
}

static void weights_test(const TlElementType *t)
{
  TlMesh *mesh = distorted_mesh(t);
  TlMaterial *mat = make_law("neo_hookean", 0.3);
  if (!mesh || !mat) return;
  WeightedRun plain, one, part;
  size_t n = mesh->n_nodes * t->dim;
  double *u = calloc(n, sizeof *u), *d = calloc(n, sizeof *d);
  for (size_t i = 0; i < n; ++i) u[i] = 0.03 * urand(), d[i] = urand();
  weighted_run(mesh, mat, 0, 1.0, u, d, &plain);
  weighted_run(mesh, mat, 1, 1.0, u, d, &one);
  weighted_run(mesh, mat, 1, 0.3, u, d, &part);
  n = plain.n;
  TL_TEST_ASSERT(memcmp(plain.f, one.f, n * sizeof(double)) == 0 && memcmp(plain.Kd, one.Kd, n * sizeof(double)) == 0 &&
                     memcmp(plain.ml, one.ml, n * sizeof(double)) == 0 &&
                     memcmp(plain.Mo, one.Mo, n * sizeof(double)) == 0 && plain.W == one.W,
                 "%s: weights 1 give the unweighted force, tangent, masses and energy bit for bit", t->header.name);
  double ef = max_diff_scaled(part.f, plain.f, 0.3, n) / max_abs(plain.f, n);
  double ek = max_diff_scaled(part.Kd, plain.Kd, 0.3, n) / max_abs(plain.Kd, n);
  double el = max_diff_scaled(part.ml, plain.ml, 0.3, n) / max_abs(plain.ml, n);
  double em = max_diff_scaled(part.Mo, plain.Mo, 0.3, n) / max_abs(plain.Mo, n);
  TL_TEST_ASSERT(ef < 1e-14 && ek < 1e-14 && el < 1e-14 && em < 1e-14,
                 "%s: weights 0.3 scale force (%g), tangent (%g), lumped (%g) and consistent mass (%g) by 0.3",
                 t->header.name, ef, ek, el, em);
  TL_TEST_CLOSE(part.W / plain.W, 0.3, 1e-14);
  TL_TEST_CLOSE(tl_solid_total_mass(part.solid) / tl_solid_total_mass(plain.solid), 0.3, 1e-14);
  /* the weighted tangent against central differences of the weighted force */
  double h = 1e-7, err = 0.0, *up = calloc(n, sizeof *up), *rp = calloc(n, sizeof *rp), *rm = calloc(n, sizeof *rm);
  for (size_t i = 0; i < n; ++i) up[i] = u[i] + h * d[i];
  part.sys->ops->internal_force(part.sys, 0.0, up, NULL, rp);
  for (size_t i = 0; i < n; ++i) up[i] = u[i] - h * d[i];
  part.sys->ops->internal_force(part.sys, 0.0, up, NULL, rm);
  for (size_t i = 0; i < n; ++i) err = fmax(err, fabs((rp[i] - rm[i]) / (2 * h) - part.Kd[i]));
  TL_TEST_ASSERT(err < 1e-6 * max_abs(part.Kd, n), "%s: weighted tangent off finite differences by %g of %g",
                 t->header.name, err, max_abs(part.Kd, n));
  /* bad weights are refused with the value */
  TlSolid *bad = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &bad), TL_OK);
  double *wn = calloc(mesh->n_nodes, sizeof *wn);
  wn[1] = -0.5;
  TL_TEST_STATUS(tl_solid_set_node_weights(bad, 0, wn), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "-0.5") != NULL, "message names the weight: %s", tl_error_message());
  tl_solid_destroy(&bad);
  free(wn), free(up), free(rp), free(rm), free(u), free(d);
  weighted_free(&plain), weighted_free(&one), weighted_free(&part);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* A nodal weight w = 0.2 + 0.5 x / Lx on a box of hex8: the consistent
 * mass rows are int rho w N_a dV and the HRZ masses the diagonal
 * int rho w N_a^2 dV scaled to the element's int rho w dV, both in closed
 * form per element (w is linear in x, the shape functions tensor
 * products). */
static void weights_linear_test(void)
{
  size_t nc[3] = {3, 2, 2};
  double lo[3] = {0, 0, 0}, hi[3] = {1.2, 1.0, 0.8}, rho = 1309.0;
  TlMesh *mesh = NULL;
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, nc, lo, hi, &mesh), TL_OK);
  TlMaterial *mat = make_law("hooke", 0.25);
  if (!mesh || !mat) return;
  size_t nn = mesh->n_nodes;
  double *wn = calloc(nn, sizeof *wn), *row = calloc(nn, sizeof *row), *hrz = calloc(nn, sizeof *hrz);
  for (size_t i = 0; i < nn; ++i) wn[i] = 0.2 + 0.5 * mesh->x[3 * i] / hi[0];
  const TlElementBlock *B = &mesh->blocks[0];
  for (size_t e = 0; e < B->n_elements; ++e) {
    double x0 = INFINITY, x1 = -INFINITY, h[3];
    double lo3[3] = {INFINITY, INFINITY, INFINITY}, hi3[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int a = 0; a < 8; ++a)
      for (int c = 0; c < 3; ++c) {
        lo3[c] = fmin(lo3[c], mesh->x[3 * B->conn[8 * e + a] + c]);
        hi3[c] = fmax(hi3[c], mesh->x[3 * B->conn[8 * e + a] + c]);
      }
    for (int c = 0; c < 3; ++c) h[c] = hi3[c] - lo3[c];
    x0 = lo3[0], x1 = hi3[0];
    double w0 = 0.2 + 0.5 * x0 / hi[0], w1 = 0.2 + 0.5 * x1 / hi[0];
    double diag[8], dsum = 0.0, total = rho * h[0] * h[1] * h[2] * 0.5 * (w0 + w1);
    for (int a = 0; a < 8; ++a) {
      int left = fabs(mesh->x[3 * B->conn[8 * e + a]] - x0) < 1e-12;
      double wa = left ? w0 : w1, wb = left ? w1 : w0;
      row[B->conn[8 * e + a]] += rho * h[0] * (2 * wa + wb) / 6.0 * h[1] * h[2] / 4.0;
      diag[a] = rho * h[0] * (3 * wa + wb) / 12.0 * h[1] / 3.0 * h[2] / 3.0;
      dsum += diag[a];
    }
    for (int a = 0; a < 8; ++a) hrz[B->conn[8 * e + a]] += diag[a] * total / dsum;
  }
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_set_node_weights(solid, 0, wn), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *ml = calloc(n, sizeof *ml), *ones = calloc(n, sizeof *ones), *Mo = calloc(n, sizeof *Mo);
  sys->ops->lumped_mass(sys, ml);
  TlSparse *M = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 0, &M), TL_OK);
  if (!M) return;
  TL_TEST_STATUS(sys->ops->consistent_mass(sys, 1.0, M), TL_OK);
  for (size_t i = 0; i < nn; ++i) ones[tl_solid_dof(solid, i, 1)] = 1.0;
  tl_sparse_matvec(M, ones, Mo);
  double er = 0.0, eh = 0.0, scale = 0.0;
  for (size_t i = 0; i < nn; ++i) {
    er = fmax(er, fabs(Mo[tl_solid_dof(solid, i, 1)] - row[i]));
    eh = fmax(eh, fabs(ml[tl_solid_dof(solid, i, 1)] - hrz[i]));
    scale = fmax(scale, row[i]);
  }
  TL_TEST_ASSERT(er < 1e-13 * scale && eh < 1e-13 * scale,
                 "linear weight: consistent rows off by %g, HRZ masses by %g (of %g)", er, eh, scale);
  double V = hi[0] * hi[1] * hi[2];
  TL_TEST_CLOSE(tl_solid_total_mass(solid) / (rho * V * (0.2 + 0.25)), 1.0, 1e-13);
  tl_sparse_destroy(&M);
  free(ml), free(ones), free(Mo), free(wn), free(row), free(hrz);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

static void eigenstrain_test(const TlElementType *t)
{
  TlMesh *mesh = distorted_mesh(t);
  TlMaterial *mat = make_law("hooke", 0.3);
  if (!mesh || !mat) return;
  double e0 = 0.01;
  TlMat3 E0 = tl_m3_scale(tl_m3_identity(), e0);
  if (t->dim == 2) E0.m[2][2] = 0.0; /* plane strain: no growth out of plane */
  TL_TEST_STATUS(tl_material_set_eigenstrain(mat, E0), TL_OK);
  TL_TEST_STATUS(tl_material_setup(mat), TL_OK);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *f = calloc(n, sizeof *f);
  double stretch = sqrt(1.0 + 2.0 * e0) - 1.0;
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int i = 0; i < t->dim; ++i) u[tl_solid_dof(solid, a, i)] = stretch * mesh->x[3 * a + i];
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f), TL_OK);
  /* Against the residual of the same body without the eigenstrain moved. */
  memset(u, 0, n * sizeof *u);
  double *f0 = calloc(n, sizeof *f0);
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f0), TL_OK);
  TL_TEST_ASSERT(max_abs(f, n) < 1e-12 * max_abs(f0, n), "%s eigenstrain: residual %g at the stress-free state (%g at rest)",
                 t->header.name, max_abs(f, n), max_abs(f0, n));
  free(u), free(f), free(f0);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* A mesh large enough for threaded assembly: the internal force with 1 and
 * 2 threads is bitwise the same (colours make the sums order-independent),
 * and an inverted element inside a threaded batch is reported by name. */
static void threads_test(void)
{
  size_t nc[3] = {12, 12, 8};
  double lo[3] = {0, 0, 0}, hi[3] = {1.2, 1.2, 0.8};
  TlMesh *mesh = NULL;
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, nc, lo, hi, &mesh), TL_OK);
  TlMaterial *mat = make_law("neo_hookean", 0.3);
  if (!mesh || !mat) return;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *f1 = calloc(n, sizeof *f1), *f2 = calloc(n, sizeof *f2);
  for (size_t i = 0; i < n; ++i) u[i] = 0.002 * urand();
  int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f1), TL_OK);
  omp_set_num_threads(2);
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f2), TL_OK);
  TL_TEST_ASSERT(memcmp(f1, f2, n * sizeof *f1) == 0, "internal force depends on the thread count");
  /* Push one interior node through its neighbours. */
  size_t node = (6 + 13 * (6 + 13 * 4));
  u[tl_solid_dof(solid, node, 2)] = -0.5;
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, u, NULL, f2), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(strstr(tl_error_message(), "block body element") && strstr(tl_error_message(), "inverted"),
                 "message names the block and the problem: %s", tl_error_message());
  omp_set_num_threads(saved);
  free(u), free(f1), free(f2);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* Assembled internal tangent against central differences along a random
 * direction. */
static void tangent_check_system(TlMechSystem *sys, const double *u, const char *what)
{
  size_t n = (size_t)sys->ndof;
  double *d = calloc(n, sizeof *d), *up = calloc(n, sizeof *up), *rp = calloc(n, sizeof *rp), *rm = calloc(n, sizeof *rm),
         *Kd = calloc(n, sizeof *Kd);
  for (size_t i = 0; i < n; ++i) d[i] = urand();
  TlSparse *K = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, sys->symmetric, &K), TL_OK);
  if (!K) return;
  TL_TEST_STATUS(sys->ops->internal_tangent(sys, 0.0, u, NULL, 1.0, 0.0, K), TL_OK);
  tl_sparse_matvec(K, d, Kd);
  double h = 1e-7;
  for (size_t i = 0; i < n; ++i) up[i] = u[i] + h * d[i];
  sys->ops->internal_force(sys, 0.0, up, NULL, rp);
  for (size_t i = 0; i < n; ++i) up[i] = u[i] - h * d[i];
  sys->ops->internal_force(sys, 0.0, up, NULL, rm);
  double err = 0.0;
  for (size_t i = 0; i < n; ++i) err = fmax(err, fabs((rp[i] - rm[i]) / (2 * h) - Kd[i]));
  TL_TEST_ASSERT(err < 1e-6 * max_abs(Kd, n), "%s: assembled tangent off by %g of %g", what, err, max_abs(Kd, n));
  tl_sparse_destroy(&K);
  free(d), free(up), free(rp), free(rm), free(Kd);
}

/* A law defined outside the kernel (Saint Venant-Kirchhoff, S = lambda tr(E)
 * 1 + 2 mu E) with one state value per point (the largest tr E seen on the
 * committed path) and commit/rollback callbacks, as a DEM-cell law would
 * use them. */
typedef struct {
  TlMaterial base;
  double lambda, mu;
  size_t commits, rollbacks, last_npts;
} TestLaw;

static TlStatus test_law_setup(TlMaterial *m)
{
  m->state_size = 1;
  return TL_OK;
}

static TlStatus test_law_evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma,
                                  const double *so, double *sn, TlMat3 *S, double *D, double *W)
{
  (void)F;
  const TestLaw *l = (const TestLaw *)m;
  for (size_t p = 0; p < npts; ++p) {
    double tr = tl_m3_trace(gamma[p]);
    S[p] = tl_m3_add(tl_m3_scale(tl_m3_identity(), l->lambda * tr), tl_m3_scale(gamma[p], 2 * l->mu));
    sn[p] = fmax(so[p], tr);
    if (W) W[p] = 0.5 * l->lambda * tr * tr + l->mu * tl_m3_ddot(gamma[p], gamma[p]);
    if (D) {
      memset(D + 36 * p, 0, 36 * sizeof(double));
      for (int I = 0; I < 3; ++I) {
        for (int J = 0; J < 3; ++J) D[36 * p + 6 * I + J] = l->lambda;
        D[36 * p + 7 * I] += 2 * l->mu;
        D[36 * p + 7 * (I + 3)] = l->mu;
      }
    }
  }
  return TL_OK;
}

static TlStatus test_law_commit(TlMaterial *m, size_t npts, const double *state)
{
  (void)state;
  ((TestLaw *)m)->commits++;
  ((TestLaw *)m)->last_npts = npts;
  return TL_OK;
}

static TlStatus test_law_rollback(TlMaterial *m, size_t npts, const double *state)
{
  (void)npts, (void)state;
  ((TestLaw *)m)->rollbacks++;
  return TL_OK;
}

static int test_law_symmetric(const TlMaterial *m)
{
  (void)m;
  return 1;
}

static const TlMaterialParam test_law_params[] = {
    {"lambda", 5e7, 0, 1e12, "Pa", "first Lame constant", offsetof(TestLaw, lambda)},
    {"mu", 4e7, 1, 1e12, "Pa", "shear modulus", offsetof(TestLaw, mu)},
};

static const TlMaterialOps test_law_ops = {
    .header = {"material", "test_svk_history", "Saint Venant-Kirchhoff with a history value (test)"},
    .size = sizeof(TestLaw), .n_params = 2, .params = test_law_params, .setup = test_law_setup,
    .evaluate = test_law_evaluate, .symmetric_tangent = test_law_symmetric, .commit = test_law_commit,
    .rollback = test_law_rollback};

static void state_test(void)
{
  TL_TEST_STATUS(tl_registry_add(&test_law_ops.header), TL_OK);
  TlMaterial *mat = NULL;
  TL_TEST_STATUS(tl_material_create("test_svk_history", &mat), TL_OK);
  TlMesh *mesh = distorted_mesh(&tl_element_hex8);
  if (!mat || !mesh) return;
  TL_TEST_STATUS(tl_material_set(mat, "mu", 3e7), TL_OK);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u);
  for (size_t a = 0; a < mesh->n_nodes; ++a) u[tl_solid_dof(solid, a, 0)] = 0.01 * mesh->x[3 * a];
  /* Tangent of the outside law against differences, through the solid. */
  tangent_check_system(sys, u, "test law");
  double W = 0.0;
  TL_TEST_STATUS(tl_solid_strain_energy(solid, u, &W), TL_OK);
  TL_TEST_STATUS(sys->ops->commit(sys), TL_OK);
  TL_TEST_STATUS(sys->ops->rollback(sys), TL_OK);
  const TestLaw *l = (const TestLaw *)mat;
  TL_TEST_ASSERT(l->commits == 1 && l->rollbacks == 1 && l->last_npts == 8 * 8, "commits %zu rollbacks %zu points %zu",
                 l->commits, l->rollbacks, l->last_npts);
  TlMat3 E = tl_m3_zero();
  E.m[0][0] = 0.01 + 0.5 * 0.01 * 0.01;
  double Wexp = (0.5 * 5e7 * E.m[0][0] * E.m[0][0] + 3e7 * E.m[0][0] * E.m[0][0]) * tl_mesh_volume(mesh);
  TL_TEST_CLOSE(W / Wexp, 1.0, 1e-12);
  free(u);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

static double ramp(double t, void *ctx)
{
  (void)ctx;
  return 2.0 * t;
}

/* Load totals on the undeformed body: gravity rho V g, a follower pressure
 * -p A n on a face, a point force times its amplitude. */
static void load_test(const TlElementType *t)
{
  TlMesh *mesh = distorted_mesh(t);
  TlMaterial *mat = make_law("neo_hookean", 0.3);
  if (!mesh || !mat) return;
  int dim = t->dim;
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_add_gravity(solid, tl_v3(0.5, -9.81, dim == 3 ? 1.5 : 0.0)), TL_OK);
  TL_TEST_STATUS(tl_solid_add_pressure(solid, "xmax", 2e5, ramp, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_add_point_force(solid, 3, tl_v3(0, 0, dim == 3 ? 7.0 : 0.0), ramp, NULL), TL_OK);
  TL_TEST_STATUS(tl_solid_add_point_force(solid, mesh->n_nodes, tl_v3(1, 0, 0), NULL, NULL), TL_ERR_ARG);
  TL_TEST_STATUS(tl_solid_add_pressure(solid, "no_such_face_set", 1.0, NULL, NULL), TL_ERR_NOT_FOUND);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TL_TEST_STATUS(tl_solid_add_gravity(solid, tl_v3(0, 0, 1)), TL_ERR_STATE);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *f = calloc(n, sizeof *f);
  TL_TEST_STATUS(sys->ops->external_force(sys, 0.75, u, f), TL_OK);
  double sum[3] = {0, 0, 0};
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int c = 0; c < dim; ++c) sum[c] += f[tl_solid_dof(solid, a, c)];
  double m = 1309.0 * tl_mesh_volume(mesh), area = dim == 3 ? 1.0 * 0.8 : 1.0, a = 2.0 * 0.75;
  TL_TEST_CLOSE(sum[0] / (m * 0.5 - a * 2e5 * area), 1.0, 1e-12);
  TL_TEST_CLOSE(sum[1] / (m * -9.81), 1.0, 1e-12);
  if (dim == 3) TL_TEST_CLOSE(sum[2] / (m * 1.5 + a * 7.0), 1.0, 1e-12);
  free(u), free(f);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

/* A wrapper's displacement-dependent external load (a spring to the ground
 * at one node, f = -k u) and its tangent: the system's external tangent
 * (K += c d f_ext/du, with c = 1) against central differences of f_ext. */
typedef struct {
  size_t node;
  double k;
} GroundSpring;

static TlStatus wrapper_ground(void *ctx, TlSolid *solid, int b, double t, const double *u, double *f, double c,
                               TlSparse *K)
{
  (void)b, (void)t;
  const GroundSpring *g = ctx;
  const int dim = tl_solid_mesh(solid)->dim;
  for (int q = 0; q < dim; ++q) {
    if (f) f[g->node * dim + q] -= g->k * u[g->node * dim + q];
    TlSparseIndex i = tl_solid_dof(solid, g->node, q);
    if (K && i >= 0) TL_CHECK(tl_sparse_add(K, i, i, -c * g->k));
  }
  return TL_OK;
}
static const TlSolidWrapperOps ground_ops = {.header = {"solid_wrapper", "test_ground", "spring to the ground"},
                                             .external = wrapper_ground};

static void wrap_tangent_test(void)
{
  TlMesh *mesh = distorted_mesh(&tl_element_hex8);
  TlMaterial *mat = make_law("neo_hookean", 0.3);
  if (!mesh || !mat) return;
  GroundSpring g = {mesh->blocks[0].conn[6], 2e7};
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlSolidWrapper *hg = NULL;
  TL_TEST_STATUS(tl_solid_add_wrapper(solid, 0, &ground_ops, &g, &hg), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  const size_t n = (size_t)sys->ndof;
  double *u = calloc(n, sizeof *u), *d = calloc(n, sizeof *d), *up = calloc(n, sizeof *up), *fp = calloc(n, sizeof *fp),
         *fm = calloc(n, sizeof *fm), *Kd = calloc(n, sizeof *Kd);
  TlSparse *K = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 1, &K), TL_OK);
  if (!K || !u || !d || !up || !fp || !fm || !Kd || !sys->ops->external_tangent) {
    TL_TEST_ASSERT(sys->ops->external_tangent != NULL, "the solid has an external tangent");
  } else {
    for (size_t i = 0; i < n; ++i) u[i] = 0.02 * urand(), d[i] = urand();
    tl_sparse_zero(K);
    TL_TEST_STATUS(sys->ops->external_tangent(sys, 0.0, u, 1.0, K), TL_OK);
    tl_sparse_matvec(K, d, Kd);
    const double h = 1e-6;
    for (size_t i = 0; i < n; ++i) up[i] = u[i] + h * d[i];
    TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, up, fp), TL_OK);
    for (size_t i = 0; i < n; ++i) up[i] = u[i] - h * d[i];
    TL_TEST_STATUS(sys->ops->external_force(sys, 0.0, up, fm), TL_OK);
    double err = 0.0, scale = 0.0;
    for (size_t i = 0; i < n; ++i) {
      err = fmax(err, fabs((fp[i] - fm[i]) / (2 * h) - Kd[i]));
      scale = fmax(scale, fabs(Kd[i]));
    }
    printf("wrapper load's tangent: |K_ext d - d f_ext| = %.3g of %.3g\n", err, scale);
    TL_TEST_ASSERT(scale > 0.0 && err <= 1e-6 * scale, "the wrapper load's tangent is off by %g of %g", err, scale);
  }
  tl_sparse_destroy(&K);
  free(u), free(d), free(up), free(fp), free(fm), free(Kd);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  srand(11);
  TlMat3 R90 = tl_m3_rotation(tl_v3(0, 0, 1), M_PI / 2);
  TlMat3 Rany = tl_m3_rotation(tl_v3(0.4, -1.1, 0.7), 1.234);
  TlMat3 Rplane = tl_m3_rotation(tl_v3(0, 0, 1), 2.345);
  for (size_t k = 0; k < sizeof types / sizeof types[0]; ++k) {
    const TlElementType *t = types[k];
    patch_test(t, "hooke");
    patch_test(t, "hooke_covariant");
    patch_test(t, "neo_hookean");
    rotation_test(t, R90, "90 degrees about z");
    rotation_test(t, t->dim == 3 ? Rany : Rplane, "arbitrary");
    tangent_test(t, "hooke", 0.0);
    tangent_test(t, "hooke", 0.3);
    tangent_test(t, "hooke_covariant", 0.3);
    tangent_test(t, "neo_hookean", 0.3);
    if (t->dim == 3) {
      residual_path_test(t, "hooke");
      residual_path_test(t, "neo_hookean");
    }
  }
  system_test(&tl_element_hex8);
  system_test(&tl_element_tet10);
  system_test(&tl_element_quad8);
  reaction_test();
  wrap_test();
  wrap_tangent_test();
  weights_test(&tl_element_hex8);
  weights_test(&tl_element_tet10);
  weights_test(&tl_element_quad8);
  weights_linear_test();
  threads_test();
  state_test();
  load_test(&tl_element_hex27);
  load_test(&tl_element_tet10);
  load_test(&tl_element_quad8);
  eigenstrain_test(&tl_element_hex27);
  eigenstrain_test(&tl_element_quad8);
  uniaxial_test("hooke", 1.05);
  uniaxial_test("hooke_covariant", 1.02);
  return tl_test_report();
}
