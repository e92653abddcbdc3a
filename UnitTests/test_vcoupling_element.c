/* The VCoupling element type (tl_vcoupling_element.h): the solid weighted by
 * 1 - w (Eq. 26) through the block wrapper, the coupling body force of
 * Eq. 31 inside the block's evaluation with its tangent, Eq. 41 against the
 * particle side, and unwrapping. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_test.h"
#include "tl_vcoupling.h"
#include "tl_vcoupling_element.h"

/* A 2 x 15 x 2 hex8 bar on y in [8, 14] (element size 0.4), the zone
 * (8, 12), a simple cubic lattice of 8 particles per element on y in
 * [6, 12]: the geometry of the wave case's overlap. */
enum { MAXP = 4000 };
static double xp[3 * MAXP], mp[MAXP], dup[3 * MAXP], fp[3 * MAXP];

static double rnd(unsigned *s)
{
  *s = *s * 1103515245u + 12345u;
  return ((*s >> 8) & 0xffff) / 65535.0 - 0.5;
}

static size_t make_lattice(void)
{
  double d = 0.2;
  size_t np = 0;
  for (int j = 0; j < 30; ++j)
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 4; ++i) {
        xp[3 * np] = (i + 0.5) * d;
        xp[3 * np + 1] = 6.0 + (j + 0.5) * d;
        xp[3 * np + 2] = (k + 0.5) * d;
        mp[np++] = 3.4;
      }
  return np;
}

static double max_abs(const double *v, size_t n)
{
  double m = 0.0;
  for (size_t i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
  return m;
}

static TlMaterial *hooke(void)
{
  TlMaterial *m = NULL;
  TL_TEST_STATUS(tl_material_create("hooke", &m), TL_OK);
  tl_material_set(m, "E", 1e8);
  tl_material_set(m, "nu", 0.2);
  tl_material_set(m, "density", 1309.0);
  TL_TEST_STATUS(tl_material_setup(m), TL_OK);
  return m;
}

static void test_element(double c)
{
  size_t nc[3] = {2, 15, 2};
  double lo[3] = {0, 8, 0}, hi[3] = {0.8, 14, 0.8}, rho = 1309.0, eps = 4e10;
  TlMesh *mesh = NULL;
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, nc, lo, hi, &mesh), TL_OK);
  TlMaterial *mat = hooke();
  if (!mesh || !mat) return;
  TlVCouplingParams p = {{1, 8.0, 12.0}, c, "lucy", eps, 4, 0};
  TlVCoupling *vc = NULL;
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
  TlSolid *solid = NULL, *plain = NULL;
  TlVCouplingElement *el = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  TL_TEST_STATUS(tl_solid_create(mesh, &plain), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  tl_solid_set_material(plain, NULL, mat);
  TL_TEST_STATUS(tl_vcoupling_element_create(vc, solid, &el), TL_OK);
  if (!vc || !el) return;
  /* the same weights without the wrapper: the reference for the force */
  TL_TEST_STATUS(tl_solid_set_node_weights(plain, 0, tl_vcoupling_element_weights(el)), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(plain), TL_OK);
  /* after setup the weights are frozen: a second element is refused */
  TlVCouplingElement *late = NULL;
  TL_TEST_STATUS(tl_vcoupling_element_create(vc, solid, &late), TL_ERR_STATE);

  /* Eq. 26 on the mass: hex8 boxes average a trilinear field by their
   * nodal mean, so the weighted mass is rho sum_e V_e (1 - mean w_i). */
  const TlElementBlock *B = &mesh->blocks[0];
  const double *w = tl_vcoupling_node_weights(vc);
  double expect = 0.0, Ve = 0.4 * 0.4 * 0.4;
  for (size_t e = 0; e < B->n_elements; ++e) {
    double m = 0.0;
    for (int a = 0; a < 8; ++a) m += w[B->conn[8 * e + a]] / 8.0;
    expect += rho * Ve * (1.0 - m);
  }
  TL_TEST_CLOSE(tl_solid_total_mass(solid) / expect, 1.0, 1e-13);
  TL_TEST_ASSERT(expect < 0.8 * rho * 0.8 * 6 * 0.8, "the zone takes mass off the solid (%g of %g)", expect,
                 rho * 0.8 * 6 * 0.8);

  /* a step: particle and nodal displacements */
  size_t np = make_lattice(), nn = mesh->n_nodes;
  unsigned seed = 99u;
  double *u0 = calloc(3 * nn, sizeof *u0), *u = calloc(3 * nn, sizeof *u), *dun = calloc(3 * nn, sizeof *dun),
         *Fn = calloc(3 * nn, sizeof *Fn);
  for (size_t k = 0; k < 3 * nn; ++k) u0[k] = 1e-4 * rnd(&seed), u[k] = u0[k] + 1e-5 * rnd(&seed);
  for (size_t k = 0; k < 3 * np; ++k) dup[k] = 1e-5 * rnd(&seed);
  TL_TEST_STATUS(tl_vcoupling_update(vc, u0, np, xp, mp), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid), *sysp = tl_solid_system(plain);
  size_t n = (size_t)sys->ndof;
  double *ud = calloc(n, sizeof *ud), *f = calloc(n, sizeof *f), *fpl = calloc(n, sizeof *fpl),
         *d = calloc(n, sizeof *d), *Kd = calloc(n, sizeof *Kd), *up = calloc(n, sizeof *up),
         *rp = calloc(n, sizeof *rp), *rm = calloc(n, sizeof *rm);
  tl_solid_nodes_to_dofs(solid, u, ud);
  /* before the first step's data the wrapper adds nothing */
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, ud, NULL, f), TL_OK);
  TL_TEST_STATUS(sysp->ops->internal_force(sysp, 0.0, ud, NULL, fpl), TL_OK);
  TL_TEST_ASSERT(memcmp(f, fpl, n * sizeof *f) == 0, "c = %g: no step data, the weighted solid alone", c);
  TL_TEST_STATUS(tl_vcoupling_element_set_step(el, dup, u0), TL_OK);
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, ud, NULL, f), TL_OK);
  /* expected: the weighted solid minus F_i = eps sum_j M_ij r_j (Eq. 31) */
  tl_solid_dofs_to_nodes(solid, ud, u);
  for (size_t k = 0; k < 3 * nn; ++k) dun[k] = u[k] - u0[k];
  TL_TEST_STATUS(tl_vcoupling_forces(vc, dup, dun, Fn, NULL, NULL), TL_OK);
  double err = 0.0, scale = max_abs(Fn, 3 * nn);
  for (size_t i = 0; i < nn; ++i)
    for (int cc = 0; cc < 3; ++cc) {
      TlSparseIndex k = tl_solid_dof(solid, i, cc);
      if (k >= 0) err = fmax(err, fabs(f[k] - (fpl[k] - Fn[3 * i + cc])));
    }
  TL_TEST_ASSERT(scale > 0 && err < 1e-12 * (scale + max_abs(fpl, n)),
                 "c = %g: wrapped block = weighted solid - coupling force (off by %g, force scale %g)", c, err, scale);
  /* Eq. 41: the particles feel minus what the nodes feel */
  memset(fp, 0, 3 * np * sizeof *fp);
  TlVCouplingDiag dg;
  TL_TEST_STATUS(tl_vcoupling_element_particle_forces(el, u, fp, &dg), TL_OK);
  double sp[3] = {0, 0, 0}, sn[3] = {0, 0, 0}, sa = 0.0;
  for (size_t a = 0; a < np; ++a)
    for (int cc = 0; cc < 3; ++cc) sp[cc] += fp[3 * a + cc];
  for (size_t i = 0; i < nn; ++i)
    for (int cc = 0; cc < 3; ++cc) sn[cc] += Fn[3 * i + cc], sa += fabs(Fn[3 * i + cc]);
  double bal = 0.0;
  for (int cc = 0; cc < 3; ++cc) bal = fmax(bal, fabs(sp[cc] + sn[cc]));
  TL_TEST_ASSERT(bal < 1e-14 * sa && dg.eq41 < 1e-14, "c = %g: Eq. 41 off by %g of %g (diag %g)", c, bal, sa, dg.eq41);
  /* the tangent with the coupling's -dF/du = eps M against central
   * differences of the wrapped force */
  TlSparse *K = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 0, &K), TL_OK);
  if (!K) return;
  for (size_t k = 0; k < n; ++k) d[k] = rnd(&seed);
  TL_TEST_STATUS(sys->ops->internal_tangent(sys, 0.0, ud, NULL, 1.0, 0.0, K), TL_OK);
  tl_sparse_matvec(K, d, Kd);
  double h = 1e-7;
  for (size_t k = 0; k < n; ++k) up[k] = ud[k] + h * d[k];
  sys->ops->internal_force(sys, 0.0, up, NULL, rp);
  for (size_t k = 0; k < n; ++k) up[k] = ud[k] - h * d[k];
  sys->ops->internal_force(sys, 0.0, up, NULL, rm);
  err = 0.0;
  for (size_t k = 0; k < n; ++k) err = fmax(err, fabs((rp[k] - rm[k]) / (2 * h) - Kd[k]));
  TL_TEST_ASSERT(err < 1e-6 * max_abs(Kd, n), "c = %g: wrapped tangent off by %g of %g", c, err, max_abs(Kd, n));
  /* the penalty part alone: K - K_plain = eps M on the coupled nodes */
  TlSparse *Kp = NULL;
  TL_TEST_STATUS(sysp->ops->create_matrix(sysp, 0, &Kp), TL_OK);
  TL_TEST_STATUS(sysp->ops->internal_tangent(sysp, 0.0, ud, NULL, 1.0, 0.0, Kp), TL_OK);
  tl_sparse_matvec(Kp, d, rp);
  double pen = 0.0;
  for (size_t k = 0; k < n; ++k) pen = fmax(pen, fabs(Kd[k] - rp[k]));
  TL_TEST_ASSERT(pen > 1e-3 * eps * Ve / 27, "c = %g: the penalty enters the tangent (%g)", c, pen);
  /* cleared: the weighted solid alone again; destroyed: unwrapped */
  tl_vcoupling_element_clear(el);
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, ud, NULL, f), TL_OK);
  TL_TEST_ASSERT(memcmp(f, fpl, n * sizeof *f) == 0, "c = %g: cleared element adds nothing", c);
  TL_TEST_ASSERT(tl_solid_n_wrappers(solid, 0) == 1, "the element wraps the block");
  tl_vcoupling_element_destroy(&el);
  TL_TEST_ASSERT(el == NULL && tl_solid_n_wrappers(solid, 0) == 0, "destroy unwraps the block");
  TL_TEST_STATUS(sys->ops->internal_force(sys, 0.0, ud, NULL, f), TL_OK);
  TL_TEST_ASSERT(memcmp(f, fpl, n * sizeof *f) == 0, "c = %g: unwrapped block = weighted solid", c);
  tl_sparse_destroy(&K);
  tl_sparse_destroy(&Kp);
  free(u0), free(u), free(dun), free(Fn), free(ud), free(f), free(fpl), free(d), free(Kd), free(up), free(rp),
      free(rm);
  tl_solid_destroy(&solid);
  tl_solid_destroy(&plain);
  tl_vcoupling_destroy(&vc);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

static void test_bad_input(void)
{
  size_t nc[3] = {2, 15, 2};
  double lo[3] = {0, 8, 0}, hi[3] = {0.8, 14, 0.8};
  TlMesh *mesh = NULL, *other = NULL;
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, nc, lo, hi, &mesh), TL_OK);
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, nc, lo, hi, &other), TL_OK);
  TlVCouplingParams p = {{1, 8.0, 12.0}, 0.0, "lucy", 1e10, 4, 0};
  TlVCoupling *vc = NULL;
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(other, &solid), TL_OK);
  TlVCouplingElement *el = NULL;
  TL_TEST_STATUS(tl_vcoupling_element_create(vc, solid, &el), TL_ERR_ARG);
  TL_TEST_ASSERT(el == NULL && strstr(tl_error_message(), "another mesh"), "other mesh refused: %s", tl_error_message());
  tl_solid_destroy(&solid);
  tl_vcoupling_destroy(&vc);
  tl_mesh_destroy(&mesh);
  tl_mesh_destroy(&other);
}

int main(void)
{
  if (tl_initialize() != TL_OK) {
    fprintf(stderr, "%s\n", tl_error_message());
    return 1;
  }
  test_element(0.0);
  test_element(0.6);
  test_bad_input();
  return tl_test_report();
}
