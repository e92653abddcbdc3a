/* Element types: Kronecker property, partition of unity, gradients against
 * finite differences, quadrature exactness, outward faces, face-to-element
 * maps, and the inverse map on interior, face, edge and corner points of
 * distorted elements. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_element.h"
#include "tl_test.h"

static const TlElementType *const all_types[] = {
    &tl_element_line2, &tl_element_line3, &tl_element_tri3,  &tl_element_tri6,
    &tl_element_quad4, &tl_element_quad8, &tl_element_quad9, &tl_element_tet4,
    &tl_element_tet10, &tl_element_hex8,  &tl_element_hex27};
static const TlElementType *const solid_types[] = {&tl_element_quad4, &tl_element_quad8,
                                                   &tl_element_tet4,  &tl_element_tet10,
                                                   &tl_element_hex8,  &tl_element_hex27};

static double urand(void) { return (double)rand() / RAND_MAX; }

/* A random point inside the reference element. */
static void random_point(const TlElementType *t, double *xi)
{
  xi[0] = xi[1] = xi[2] = 0.0;
  if (t->shape == TL_SHAPE_TRI || t->shape == TL_SHAPE_TET) {
    double s = 0.0;
    for (int d = 0; d < t->dim; ++d) s += (xi[d] = urand());
    if (s > 1.0)
      for (int d = 0; d < t->dim; ++d) xi[d] *= 0.95 / s;
  } else {
    for (int d = 0; d < t->dim; ++d) xi[d] = 2.0 * urand() - 1.0;
  }
}

/* Nodal coordinates: the reference element mapped by an affine map plus a
 * smooth distortion (keeps the Jacobian positive). */
static void distorted_nodes(const TlElementType *t, double amp, double *x)
{
  for (int a = 0; a < t->n_nodes; ++a) {
    double r[3] = {0, 0, 0};
    for (int d = 0; d < t->dim; ++d) r[d] = t->ref_coords[a * t->dim + d];
    x[3 * a + 0] = 1.3 * r[0] + 0.2 * r[1] + 0.1 * r[2] + amp * sin(r[1] + 0.5 * r[2]) + 0.7;
    x[3 * a + 1] = 0.1 * r[0] + 0.9 * r[1] + 0.2 * r[2] + amp * r[0] * r[0] - 0.3;
    x[3 * a + 2] = t->dim == 3 ? 0.05 * r[0] + 0.1 * r[1] + 1.1 * r[2] + amp * r[0] * r[1] : 0.0;
  }
}

static void test_shape(const TlElementType *t)
{
  int nn = t->n_nodes, dim = t->dim;
  double N[TL_ELEMENT_MAX_NODES], dN[TL_ELEMENT_MAX_NODES * 3];
  for (int a = 0; a < nn; ++a) {
    double xi[3] = {0, 0, 0};
    for (int d = 0; d < dim; ++d) xi[d] = t->ref_coords[a * dim + d];
    t->eval(1, xi, N, NULL);
    double err = 0.0;
    for (int b = 0; b < nn; ++b) err = fmax(err, fabs(N[b] - (a == b)));
    TL_TEST_ASSERT(err < 1e-14, "%s: N_b(node %d) != delta, error %g", t->header.name, a, err);
  }
  for (int k = 0; k < 5; ++k) {
    double xi[3];
    random_point(t, xi);
    t->eval(1, xi, N, dN);
    double sum = 0.0, gsum[3] = {0, 0, 0}, lin[3] = {0, 0, 0};
    for (int a = 0; a < nn; ++a) {
      sum += N[a];
      for (int d = 0; d < dim; ++d) {
        gsum[d] += dN[a * dim + d];
        lin[d] += N[a] * t->ref_coords[a * dim + d];
      }
    }
    TL_TEST_CLOSE(sum, 1.0, 1e-14);
    for (int d = 0; d < dim; ++d) {
      TL_TEST_CLOSE(gsum[d], 0.0, 1e-13);
      TL_TEST_CLOSE(lin[d], xi[d], 1e-14);
    }
    /* Gradients against central differences. */
    double h = 1e-6, err = 0.0;
    for (int d = 0; d < dim; ++d) {
      double xp[3], xm[3], Np[TL_ELEMENT_MAX_NODES], Nm[TL_ELEMENT_MAX_NODES];
      memcpy(xp, xi, sizeof xp);
      memcpy(xm, xi, sizeof xm);
      xp[d] += h;
      xm[d] -= h;
      t->eval(1, xp, Np, NULL);
      t->eval(1, xm, Nm, NULL);
      for (int a = 0; a < nn; ++a) err = fmax(err, fabs((Np[a] - Nm[a]) / (2 * h) - dN[a * dim + d]));
    }
    TL_TEST_ASSERT(err < 1e-8, "%s: gradient differs from finite difference by %g",
                   t->header.name, err);
  }
}

static void test_quadrature(const TlElementType *t)
{
  /* Volume of the reference element, and exactness of the mass rule on
   * the product of two shape functions: sum over a, b of int N_a N_b = V. */
  TlQuadrature q;
  TL_TEST_STATUS(tl_element_quadrature(t, t->order_mass, &q), TL_OK);
  double V = 0.0, sum = 0.0;
  for (int p = 0; p < q.n; ++p) {
    double N[TL_ELEMENT_MAX_NODES];
    t->eval(1, q.xi[p], N, NULL);
    V += q.w[p];
    double s = 0.0;
    for (int a = 0; a < t->n_nodes; ++a) s += N[a];
    sum += q.w[p] * s * s;
  }
  TL_TEST_CLOSE(V, tl_element_reference_measure(t), 1e-14);
  TL_TEST_CLOSE(sum, tl_element_reference_measure(t), 1e-14);
  /* Exactness of the mass rule on N_0 N_last against a finer rule. */
  TlQuadrature fine;
  TL_TEST_STATUS(tl_element_quadrature(t, 5, &fine), TL_OK);
  double m1 = 0.0, m2 = 0.0;
  int last = t->n_nodes - 1;
  for (int p = 0; p < q.n; ++p) {
    double N[TL_ELEMENT_MAX_NODES];
    t->eval(1, q.xi[p], N, NULL);
    m1 += q.w[p] * N[0] * N[last];
  }
  for (int p = 0; p < fine.n; ++p) {
    double N[TL_ELEMENT_MAX_NODES];
    t->eval(1, fine.xi[p], N, NULL);
    m2 += fine.w[p] * N[0] * N[last];
  }
  TL_TEST_CLOSE(m1, m2, 1e-13);
}

static void test_faces(const TlElementType *t)
{
  double x[TL_ELEMENT_MAX_NODES * 3], centroid[3], xc[3] = {0, 0, 0};
  distorted_nodes(t, 0.05, x);
  if (t->shape == TL_SHAPE_TET) xc[0] = xc[1] = xc[2] = 0.25;
  if (t->shape == TL_SHAPE_TRI) xc[0] = xc[1] = 1.0 / 3.0;
  tl_element_interpolate(t, x, xc, centroid);
  const TlElementType *ft = t->face_type;
  int sdim = t->dim;
  double total[3] = {0, 0, 0};
  for (int f = 0; f < t->n_faces; ++f) {
    double fx[TL_ELEMENT_MAX_FACE_NODES * 3];
    for (int k = 0; k < t->face_n_nodes; ++k)
      memcpy(fx + 3 * k, x + 3 * t->face_nodes[f * t->face_n_nodes + k], 3 * sizeof(double));
    TlQuadrature q;
    tl_element_quadrature(ft, ft->order_mass, &q);
    for (int p = 0; p < q.n; ++p) {
      double n[3], xf[3], xe[3], ref[3];
      tl_element_face_normal(ft, sdim, fx, q.xi[p], n);
      tl_element_interpolate(ft, fx, q.xi[p], xf);
      double out = 0.0;
      for (int i = 0; i < 3; ++i) {
        out += n[i] * (xf[i] - centroid[i]);
        total[i] += q.w[p] * n[i];
      }
      TL_TEST_ASSERT(out > 0.0, "%s face %d: normal points inward", t->header.name, f);
      /* The face point mapped to the element's reference coordinates gives
       * the same physical point, and lies on the reference boundary. */
      tl_element_face_to_element(t, f, q.xi[p], ref);
      tl_element_interpolate(t, x, ref, xe);
      double err = 0.0;
      for (int i = 0; i < 3; ++i) err = fmax(err, fabs(xe[i] - xf[i]));
      TL_TEST_ASSERT(err < 1e-13, "%s face %d: face and element maps differ by %g",
                     t->header.name, f, err);
    }
  }
  /* Closed surface: the integral of n dA vanishes. */
  for (int i = 0; i < 3; ++i) TL_TEST_CLOSE(total[i], 0.0, 1e-12);
}

static void test_inverse_map(const TlElementType *t)
{
  double x[TL_ELEMENT_MAX_NODES * 3];
  distorted_nodes(t, 0.08, x);
  int sdim = t->dim;
  /* Interior points, every node (corners and mid-side/face nodes lie on the
   * boundary), face and edge points, and an outside point. */
  for (int k = 0; k < 10 + t->n_nodes; ++k) {
    double xi[3] = {0, 0, 0}, p[3], back[3];
    int boundary = k >= 10;
    if (!boundary) {
      random_point(t, xi);
    } else {
      for (int d = 0; d < t->dim; ++d) xi[d] = t->ref_coords[(k - 10) * t->dim + d];
    }
    tl_element_interpolate(t, x, xi, p);
    int inside = 0;
    TL_TEST_STATUS(tl_element_inverse_map(t, sdim, x, p, back, &inside), TL_OK);
    double err = 0.0;
    for (int d = 0; d < t->dim; ++d) err = fmax(err, fabs(back[d] - xi[d]));
    TL_TEST_ASSERT(err < 1e-10, "%s: inverse map of xi = (%g, %g, %g) off by %g", t->header.name,
                   xi[0], xi[1], xi[2], err);
    TL_TEST_ASSERT(inside, "%s: point (%g, %g, %g) on the element reported outside",
                   t->header.name, xi[0], xi[1], xi[2]);
  }
  /* Face points of every face (through the face maps). */
  for (int f = 0; f < t->n_faces; ++f) {
    double s[3] = {0.3, 0.2, 0}, xi[3], p[3], back[3];
    if (t->face_type->shape == TL_SHAPE_LINE || t->face_type->shape == TL_SHAPE_QUAD) s[0] = -0.4;
    tl_element_face_to_element(t, f, s, xi);
    tl_element_interpolate(t, x, xi, p);
    int inside = 0;
    TL_TEST_STATUS(tl_element_inverse_map(t, sdim, x, p, back, &inside), TL_OK);
    double err = 0.0;
    for (int d = 0; d < t->dim; ++d) err = fmax(err, fabs(back[d] - xi[d]));
    TL_TEST_ASSERT(err < 1e-10 && inside, "%s face %d: inverse map off by %g (inside %d)",
                   t->header.name, f, err, inside);
  }
  /* Outside. */
  {
    double xi[3] = {0, 0, 0}, p[3], back[3];
    xi[0] = t->shape == TL_SHAPE_TET ? -0.2 : 1.2;
    tl_element_interpolate(t, x, xi, p);
    int inside = 1;
    TL_TEST_STATUS(tl_element_inverse_map(t, sdim, x, p, back, &inside), TL_OK);
    TL_TEST_ASSERT(!inside, "%s: outside point reported inside", t->header.name);
  }
}

/* A type whose table breaks what the others rely on is refused by name. */
static void test_check_refuses(void)
{
  const TlElementType *hex8 = &tl_element_hex8;
  TlElementType bad = *hex8;
  static const int inward[6 * 4] = {0, 1, 2, 3, 4, 5, 6, 7, 0, 1, 5, 4, 2, 3, 7, 6, 0, 4, 7, 3, 1, 2, 6, 5};
  bad.header.name = "hex8_inward";
  bad.face_nodes = inward;
  TL_TEST_STATUS(tl_element_type_check(&bad), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "face 0 is oriented inward") != NULL, "message: %s", tl_error_message());
  bad = *hex8;
  static const TlElementOutput wrong = {TL_CELL_HEX27, NULL};
  bad.output = &wrong;
  TL_TEST_STATUS(tl_element_type_check(&bad), TL_ERR_ARG);
  bad = tl_element_hex27;
  bad.linear = 1;
  TL_TEST_STATUS(tl_element_type_register(&bad), TL_ERR_ARG);
  const TlElementType *none = NULL;
  TL_TEST_STATUS(tl_element_type_find_gmsh(17, &none), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(strstr(tl_error_message(), "12 (hex27)") != NULL, "message lists the codes: %s", tl_error_message());
  TL_TEST_STATUS(tl_element_type_find("hex20", &none), TL_ERR_NOT_FOUND);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  srand(7);
  for (size_t i = 0; i < sizeof all_types / sizeof all_types[0]; ++i) {
    test_shape(all_types[i]);
    test_quadrature(all_types[i]);
    const TlOpsHeader *found = NULL;
    TL_TEST_STATUS(tl_registry_find("element", all_types[i]->header.name, &found), TL_OK);
    TL_TEST_ASSERT(found == &all_types[i]->header, "%s not registered", all_types[i]->header.name);
    const TlElementType *by_name = NULL, *by_gmsh = NULL;
    TL_TEST_STATUS(tl_element_type_find(all_types[i]->header.name, &by_name), TL_OK);
    TL_TEST_STATUS(tl_element_type_find_gmsh(all_types[i]->gmsh_type, &by_gmsh), TL_OK);
    TL_TEST_ASSERT(by_name == all_types[i] && by_gmsh == all_types[i], "%s found by name and Gmsh code",
                   all_types[i]->header.name);
    TL_TEST_STATUS(tl_element_type_check(all_types[i]), TL_OK);
    TL_TEST_ASSERT(all_types[i]->linear == (all_types[i]->n_nodes == all_types[i]->n_corners), "%s linear flag",
                   all_types[i]->header.name);
    TL_TEST_ASSERT(all_types[i]->dim == 1 || all_types[i]->output, "%s has an output cell", all_types[i]->header.name);
  }
  test_check_refuses();
  for (size_t i = 0; i < sizeof solid_types / sizeof solid_types[0]; ++i) {
    test_faces(solid_types[i]);
    test_inverse_map(solid_types[i]);
  }
  return tl_test_report();
}
