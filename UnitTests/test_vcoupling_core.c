/* Volume coupling: weights (Eqs. 22-26), the homogenisation operator Pi in
 * both forms (Eq. 19 through the inverse map, Eq. 18 by quadrature), the
 * penalty forces (Eqs. 29-32) and their balance (Eq. 41). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_test.h"
#include "tl_vcoupling.h"

/* A 2 x 10 x 2 hex8 bar on y in [8, 12] (element size 0.4) and a simple
 * cubic lattice of n^3 particles per element on y in [6, 12], x and z in
 * [0, 0.8]: the geometry of the coupling zone of the wave case. */
enum { MAXP = 6000 };
static double xp[3 * MAXP], mp[MAXP], dup[3 * MAXP], fp[3 * MAXP];

static size_t make_lattice(int n, int jitter)
{
  double d = 0.4 / n;
  size_t np = 0;
  int nx = (int)lround(0.8 / d), ny = (int)lround(6.0 / d);
  unsigned seed = 12345u;
  for (int j = 0; j < ny; ++j)
    for (int k = 0; k < nx; ++k)
      for (int i = 0; i < nx; ++i) {
        xp[3 * np] = (i + 0.5) * d;
        xp[3 * np + 1] = 6.0 + (j + 0.5) * d;
        xp[3 * np + 2] = (k + 0.5) * d;
        mp[np] = 1.0;
        if (jitter) {
          for (int c = 0; c < 3; ++c) {
            seed = seed * 1103515245u + 12345u;
            xp[3 * np + c] += 0.2 * d * (((seed >> 8) & 0xffff) / 65535.0 - 0.5);
          }
          seed = seed * 1103515245u + 12345u;
          mp[np] = 0.5 + ((seed >> 8) & 0xffff) / 65535.0;
        }
        ++np;
      }
  return np;
}

static double rnd(unsigned *s)
{
  *s = *s * 1103515245u + 12345u;
  return ((*s >> 8) & 0xffff) / 65535.0 - 0.5;
}

static void test_weights(const TlMesh *mesh)
{
  TlVCouplingZone z = {1, 8.0, 12.0};
  double x[3] = {0.3, 8.0, 0.1};
  TL_TEST_CLOSE(tl_vcoupling_zone_weight(&z, x), 1.0, 1e-15);
  x[1] = 12.0;
  TL_TEST_CLOSE(tl_vcoupling_zone_weight(&z, x), 0.0, 1e-15);
  x[1] = 10.0;
  TL_TEST_CLOSE(tl_vcoupling_zone_weight(&z, x), 0.5, 1e-15);
  x[1] = 3.0;
  TL_TEST_CLOSE(tl_vcoupling_zone_weight(&z, x), 1.0, 0);
  x[1] = 15.0;
  TL_TEST_CLOSE(tl_vcoupling_zone_weight(&z, x), 0.0, 0);
  double prev = 2.0;
  int monotone = 1;
  for (int k = 0; k <= 100; ++k) {
    x[1] = 7.0 + 0.06 * k;
    double w = tl_vcoupling_zone_weight(&z, x);
    if (w > prev || w < 0.0 || w > 1.0) monotone = 0;
    prev = w;
  }
  TL_TEST_ASSERT(monotone, "zone weight must fall monotonically from 1 to 0 within [0, 1]");

  TlVCouplingParams p = {z, 0.0, "lucy", 1e10, 4, 0};
  TlVCoupling *vc = NULL;
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
  if (!vc) return;
  size_t np = make_lattice(2, 1);
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
  static double w[MAXP];
  TL_TEST_STATUS(tl_vcoupling_point_weights(vc, np, xp, w), TL_OK);
  int ok = 1, interp = 1;
  double maxdiff = 0.0;
  for (size_t a = 0; a < np; ++a) {
    if (!(w[a] >= 0.0 && w[a] <= 1.0)) ok = 0;
    if (xp[3 * a + 1] < 8.0 && w[a] != 1.0) ok = 0; /* Eq. 22 */
    /* interpolated by the trilinear shape functions: w depends on y alone
     * and is linear between the node layers */
    if (xp[3 * a + 1] > 8.0) {
      double y = xp[3 * a + 1];
      double y0 = 8.0 + 0.4 * floor((y - 8.0) / 0.4), y1 = y0 + 0.4, q0[3] = {0, y0, 0}, q1[3] = {0, y1, 0};
      double lin = tl_vcoupling_zone_weight(&z, q0) + (y - y0) / 0.4 * (tl_vcoupling_zone_weight(&z, q1) -
                                                                         tl_vcoupling_zone_weight(&z, q0));
      if (fabs(lin - w[a]) > 1e-12) interp = 0;
      maxdiff = fmax(maxdiff, fabs(w[a] - tl_vcoupling_zone_weight(&z, xp + 3 * a)));
    }
  }
  TL_TEST_ASSERT(ok, "particle weights must lie in [0, 1] and be 1 outside the zone");
  TL_TEST_ASSERT(interp, "inside the mesh the weight is interpolated from the nodal values");
  TL_TEST_ASSERT(maxdiff > 1e-4 && maxdiff < 0.05, "interpolated and profile weights differ by %g", maxdiff);
  /* the solid's weight 1 - w and the particles' w sum to one at any point */
  double xi[3] = {0.3, -0.7, 0.1}, xe[8 * 3], pt[3], wp;
  size_t ne;
  const size_t *el;
  tl_vcoupling_elements(vc, &ne, &el);
  TL_TEST_ASSERT(ne == 40, "coupling elements %zu, expected 40", ne);
  tl_mesh_element_coords(mesh, 0, el[7], xe);
  tl_element_interpolate(&tl_element_hex8, xe, xi, pt);
  TL_TEST_STATUS(tl_vcoupling_point_weights(vc, 1, pt, &wp), TL_OK);
  TL_TEST_CLOSE(wp + tl_vcoupling_solid_weight(vc, el[7], xi), 1.0, 1e-14);
  tl_vcoupling_destroy(&vc);
}

/* Pi: rows sum to one, entries non-negative, reach limited by c, constant
 * fields reproduced everywhere and affine fields at nodes whose
 * neighbourhood is symmetric. */
static void test_operator(const TlMesh *mesh, double c, int n)
{
  TlVCouplingParams p = {{1, 8.0, 12.0}, c, "lucy", 1e10, 4, 0};
  TlVCoupling *vc = NULL;
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
  if (!vc) return;
  size_t np = make_lattice(n, 0);
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
  size_t ne;
  const size_t *node, *part;
  const double *val;
  tl_vcoupling_operator(vc, &ne, &node, &part, &val);
  TL_TEST_ASSERT(ne > 0, "Pi is empty");
  static double rows[3 * 400];
  memset(rows, 0, sizeof rows);
  int nonneg = 1, local = 1;
  for (size_t j = 0; j < ne; ++j) {
    rows[node[j]] += val[j];
    if (val[j] < 0.0) nonneg = 0;
    /* the particle lies within c (plus half an element diagonal) of the node's elements */
    double dy = fabs(xp[3 * part[j] + 1] - mesh->x[3 * node[j] + 1]);
    if (dy > 0.4 + c + 1e-12) local = 0;
  }
  int pou = 1;
  for (size_t i = 0; i < mesh->n_nodes; ++i) {
    double y = mesh->x[3 * i + 1];
    if (y < 12.0 + 1e-12 && fabs(rows[i] - 1.0) > 1e-14) pou = 0;
    if (y > 12.0 + 1e-12 && rows[i] != 0.0) pou = 0;
  }
  TL_TEST_ASSERT(pou, "c = %g, n = %d: every coupled row of Pi must sum to one", c, n);
  TL_TEST_ASSERT(nonneg, "c = %g: hex8 Pi entries are non-negative", c);
  TL_TEST_ASSERT(local, "c = %g: Pi reaches particles beyond the element and c", c);

  /* affine field q = a + B x */
  const double A[3] = {0.1, -0.2, 0.3}, Bm[3][3] = {{1, 2, 3}, {-1, 0.5, 2}, {0.25, -3, 1}};
  for (size_t a = 0; a < np; ++a)
    for (int d = 0; d < 3; ++d)
      dup[3 * a + d] = A[d] + Bm[d][0] * xp[3 * a] + Bm[d][1] * xp[3 * a + 1] + Bm[d][2] * xp[3 * a + 2];
  static double out[3 * 400];
  static char reached[400];
  TL_TEST_STATUS(tl_vcoupling_homogenise(vc, dup, out, reached), TL_OK);
  double err_mid = 0.0;
  int n_mid = 0;
  for (size_t i = 0; i < mesh->n_nodes; ++i) {
    const double *X = mesh->x + 3 * i;
    /* x = z = 0.4 and far enough from the lattice ends for the support + c */
    if (fabs(X[0] - 0.4) > 1e-9 || fabs(X[2] - 0.4) > 1e-9 || X[1] < 8.4 - 1e-9 || X[1] > 12.0 - 0.4 - c - 1e-9)
      continue;
    TL_TEST_ASSERT(reached[i], "interior node %zu not reached", i);
    for (int d = 0; d < 3; ++d) {
      double ex = A[d] + Bm[d][0] * X[0] + Bm[d][1] * X[1] + Bm[d][2] * X[2];
      err_mid = fmax(err_mid, fabs(out[3 * i + d] - ex));
    }
    ++n_mid;
  }
  TL_TEST_ASSERT(n_mid >= 3, "c = %g: only %d interior nodes", c, n_mid);
  TL_TEST_ASSERT(err_mid < 1e-12, "c = %g, n = %d: affine field at interior nodes off by %g", c, n, err_mid);
  /* constant field: exact at every coupled node, so a rigid translation of
   * both models leaves no residual and no force */
  for (size_t a = 0; a < np; ++a)
    for (int d = 0; d < 3; ++d) dup[3 * a + d] = A[d];
  static double dun[3 * 400], fn[3 * 400];
  for (size_t i = 0; i < mesh->n_nodes; ++i)
    for (int d = 0; d < 3; ++d) dun[3 * i + d] = A[d];
  memset(fn, 0, sizeof fn);
  memset(fp, 0, sizeof fp);
  TlVCouplingDiag dg;
  TL_TEST_STATUS(tl_vcoupling_forces(vc, dup, dun, fn, fp, &dg), TL_OK);
  TL_TEST_ASSERT(dg.residual_max < 1e-14 * 0.3, "c = %g: rigid translation leaves residual %g", c, dg.residual_max);
  double fmax_ = 0.0;
  for (size_t k = 0; k < 3 * mesh->n_nodes; ++k) fmax_ = fmax(fmax_, fabs(fn[k]));
  TL_TEST_ASSERT(fmax_ < 1e-4, "c = %g: rigid translation gives nodal force %g (eps 1e10)", c, fmax_);
  tl_vcoupling_destroy(&vc);
}

/* Eq. 41: random motions, unequal masses, jittered particles; the forces
 * on the solid and the particles balance to round-off, and the penalty's
 * work in the step is -eps r.M r <= 0. */
static void test_balance(const TlMesh *mesh, double c, const char *kernel, int per_element)
{
  TlVCouplingParams p = {{1, 8.0, 12.0}, c, kernel, 4e8 / 0.04, 4, per_element};
  TlVCoupling *vc = NULL;
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
  if (!vc) return;
  size_t np = make_lattice(2, 1);
  static double un[3 * 400], dun[3 * 400], fn[3 * 400];
  unsigned s = 777u;
  for (size_t k = 0; k < 3 * mesh->n_nodes; ++k) un[k] = 0.01 * rnd(&s);
  TL_TEST_STATUS(tl_vcoupling_update(vc, un, np, xp, mp), TL_OK);
  for (size_t k = 0; k < 3 * np; ++k) dup[k] = 1e-4 * rnd(&s);
  for (size_t k = 0; k < 3 * mesh->n_nodes; ++k) dun[k] = 1e-4 * rnd(&s);
  memset(fn, 0, sizeof fn);
  memset(fp, 0, sizeof fp);
  TlVCouplingDiag dg;
  TL_TEST_STATUS(tl_vcoupling_forces(vc, dup, dun, fn, fp, &dg), TL_OK);
  double sf[3] = {0, 0, 0}, sp[3] = {0, 0, 0}, mag = 0.0;
  for (size_t i = 0; i < mesh->n_nodes; ++i)
    for (int d = 0; d < 3; ++d) {
      sf[d] += fn[3 * i + d];
      mag += fabs(fn[3 * i + d]);
    }
  for (size_t a = 0; a < np; ++a)
    for (int d = 0; d < 3; ++d) sp[d] += fp[3 * a + d];
  double viol = 0.0;
  for (int d = 0; d < 3; ++d) viol = fmax(viol, fabs(sf[d] + sp[d]));
  TL_TEST_ASSERT(mag > 1.0, "c = %g: forces too small to test (%g)", c, mag);
  TL_TEST_ASSERT(viol <= 1e-13 * mag, "c = %g: Eq. 41 violated by %g (force scale %g)", c, viol, mag);
  TL_TEST_ASSERT(dg.eq41 <= 1e-13, "c = %g: reported Eq. 41 violation %g", c, dg.eq41);
  TL_TEST_CLOSE(dg.force_fem[1], sf[1], 1e-12);
  TL_TEST_CLOSE(dg.force_dem[1], sp[1], 1e-12);
  TL_TEST_ASSERT(dg.residual_max > 0.0 && dg.residual_rms <= dg.residual_max, "residual %g rms %g",
                 dg.residual_max, dg.residual_rms);
  TL_TEST_ASSERT(dg.work_fem + dg.work_dem < 0.0, "c = %g: penalty work %g must be negative",
                 c, dg.work_fem + dg.work_dem);
  /* scaling the mismatch scales the forces linearly (the penalty is linear) */
  for (size_t k = 0; k < 3 * np; ++k) dup[k] *= 2.0;
  for (size_t k = 0; k < 3 * mesh->n_nodes; ++k) dun[k] *= 2.0;
  TlVCouplingDiag d2;
  TL_TEST_STATUS(tl_vcoupling_forces(vc, dup, dun, NULL, NULL, &d2), TL_OK);
  TL_TEST_CLOSE(d2.force_fem[1], 2.0 * dg.force_fem[1], 1e-12);
  TL_TEST_CLOSE(d2.work_fem + d2.work_dem, 4.0 * (dg.work_fem + dg.work_dem), 1e-10);
  tl_vcoupling_destroy(&vc);
}

/* Element-local rows (Eq. 18 over Omega_e alone): every element's rows sum
 * to one, so each node's entries sum to the number of its coupling elements
 * that particles reach; a rigid translation still gives no force. */
static void test_rows_per_element(const TlMesh *mesh)
{
  for (int k = 0; k < 2; ++k) {
    double c = k ? 0.6 : 0.0;
    TlVCouplingParams p = {{1, 8.0, 12.0}, c, "lucy", 1e10, 4, 1};
    TlVCoupling *vc = NULL;
    TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
    if (!vc) return;
    size_t np = make_lattice(2, 1);
    TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
    size_t ne, nel;
    const size_t *node, *part, *el;
    const double *val;
    tl_vcoupling_operator(vc, &ne, &node, &part, &val);
    tl_vcoupling_elements(vc, &nel, &el);
    static double rows[400], count[400];
    memset(rows, 0, sizeof rows);
    memset(count, 0, sizeof count);
    for (size_t j = 0; j < ne; ++j) rows[node[j]] += val[j];
    for (size_t e = 0; e < nel; ++e)
      for (int a = 0; a < 8; ++a) count[mesh->blocks[0].conn[8 * el[e] + a]] += 1.0;
    int ok = 1;
    for (size_t i = 0; i < mesh->n_nodes; ++i)
      if (fabs(rows[i] - count[i]) > 1e-13) ok = 0;
    TL_TEST_ASSERT(ok, "c = %g: element rows must each sum to one", c);
    for (size_t a = 0; a < np; ++a)
      for (int d = 0; d < 3; ++d) dup[3 * a + d] = 0.01 * (d + 1);
    static double dun[3 * 400];
    for (size_t i = 0; i < mesh->n_nodes; ++i)
      for (int d = 0; d < 3; ++d) dun[3 * i + d] = 0.01 * (d + 1);
    TlVCouplingDiag dg;
    TL_TEST_STATUS(tl_vcoupling_forces(vc, dup, dun, NULL, NULL, &dg), TL_OK);
    TL_TEST_ASSERT(dg.residual_max < 1e-16, "c = %g: rigid translation leaves residual %g", c, dg.residual_max);
    tl_vcoupling_destroy(&vc);
  }
}

static void test_bad_input(const TlMesh *mesh)
{
  TlVCoupling *vc = NULL;
  TlVCouplingParams p = {{1, 8.0, 12.0}, -0.1, "lucy", 1e10, 4, 0};
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_ERR_ARG);
  p.c = 0.0;
  p.zone.axis = 3;
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_ERR_ARG);
  p.zone = (TlVCouplingZone){1, 12.0, 8.0};
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_ERR_ARG);
  p.zone = (TlVCouplingZone){1, 20.0, 30.0};
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_ERR_ARG);
  p.zone = (TlVCouplingZone){1, 8.0, 12.0};
  p.epsilon = NAN;
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_ERR_ARG);
  p.epsilon = 1.0;
  p.c = 0.4;
  p.kernel = "no_such_kernel";
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(vc == NULL, "failed create leaves the pointer NULL");
  p.kernel = "lucy";
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
  double dummy[3] = {0, 0, 0}, f[3];
  TL_TEST_STATUS(tl_vcoupling_forces(vc, dummy, dummy, f, f, NULL), TL_ERR_STATE);
  double x1[3] = {0.2, 9.0, 0.2}, m1 = -1.0;
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, 1, x1, &m1), TL_ERR_ARG);
  x1[1] = NAN;
  m1 = 1.0;
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, 1, x1, &m1), TL_ERR_NUMERIC);
  TL_TEST_STATUS(tl_vcoupling_set_width(vc, INFINITY), TL_ERR_ARG);
  tl_vcoupling_destroy(&vc);
  TL_TEST_ASSERT(vc == NULL, "destroy nulls the pointer");
}

/* Resolution of Pi: with the kernel cut off where the particles end, the
 * homogenised position of a node's particles drifts from its shape
 * function's centroid as c grows; with the same c and particles all around
 * (no cut-off) it stays within a small fraction of the element size. */
static void test_resolution(const TlMesh *mesh)
{
  size_t np = make_lattice(2, 0);
  double prev = -1.0, h = 0.4;
  int monotone = 1;
  double bias[5];
  const double cs[5] = {0.0, 0.4, 0.8, 1.2, 2.0};
  for (int k = 0; k < 5; ++k) {
    TlVCouplingParams p = {{1, 8.0, 12.0}, cs[k], "lucy", 1e10, 4, 1};
    TlVCoupling *vc = NULL;
    TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
    if (!vc) return;
    TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
    TlVCouplingResolution r;
    TL_TEST_STATUS(tl_vcoupling_resolution(vc, xp, &r), TL_OK);
    TL_TEST_CLOSE(r.h, h, 1e-12);
    bias[k] = r.bias_max / h;
    if (!(bias[k] > prev)) monotone = 0;
    prev = bias[k];
    /* the stop: names the width, the limit and the step */
    TlStatus st = tl_vcoupling_check_resolution(vc, xp, TL_VCOUPLING_BIAS_LIMIT, 42, NULL);
    TL_TEST_STATUS(st, bias[k] > TL_VCOUPLING_BIAS_LIMIT ? TL_ERR_UNSTABLE : TL_OK);
    if (st != TL_OK) {
      char want[64];
      snprintf(want, sizeof want, "c = %g m", cs[k]);
      TL_TEST_ASSERT(strstr(tl_error_message(), want) && strstr(tl_error_message(), "at step 42") &&
                         strstr(tl_error_message(), "limit of 0.5 element sizes"),
                     "diagnosis names c, the step and the limit: %s", tl_error_message());
    }
    tl_vcoupling_destroy(&vc);
  }
  /* 2 particles per element edge: c = 0 within a quarter of the spacing */
  TL_TEST_ASSERT(bias[0] < 0.125 * 0.5, "c = 0: bias %g element sizes", bias[0]);
  TL_TEST_ASSERT(monotone, "bias grows with c: %g %g %g %g %g", bias[0], bias[1], bias[2], bias[3], bias[4]);
  TL_TEST_ASSERT(bias[4] > 0.5, "c = 5 h outruns the mesh: bias %g", bias[4]);

  /* one element inside a lattice reaching 5 element sizes beyond it on every
   * side: no cut-off, and the same c = 3 h keeps the bias small */
  TlMesh *one = NULL;
  size_t n1[3] = {1, 1, 1};
  double lo[3] = {0, 0, 0}, hi[3] = {0.4, 0.4, 0.4};
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, n1, lo, hi, &one), TL_OK);
  if (!one) return;
  size_t n = 0;
  for (int k = 0; k < 11; ++k)
    for (int j = 0; j < 11; ++j)
      for (int i = 0; i < 11; ++i) {
        xp[3 * n] = -2.0 + (i + 0.5) * 0.4;
        xp[3 * n + 1] = -2.0 + (j + 0.5) * 0.4;
        xp[3 * n + 2] = -2.0 + (k + 0.5) * 0.4;
        mp[n++] = 1.0;
      }
  TlVCouplingParams p = {{1, 0.0, 0.4}, 1.2, "lucy", 1e10, 4, 1};
  TlVCoupling *vc = NULL;
  TL_TEST_STATUS(tl_vcoupling_create(one, 0, &p, &vc), TL_OK);
  if (vc) {
    TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, n, xp, mp), TL_OK);
    TlVCouplingResolution r;
    TL_TEST_STATUS(tl_vcoupling_resolution(vc, xp, &r), TL_OK);
    TL_TEST_ASSERT(r.bias_max < 0.1 * h && r.bias_max < 0.25 * bias[3] * h,
                   "no cut-off at c = 3 h: bias %g element sizes (cut off: %g)", r.bias_max / h, bias[3]);
  }
  tl_vcoupling_destroy(&vc);
  tl_mesh_destroy(&one);
}

int main(void)
{
  if (tl_initialize() != TL_OK) {
    fprintf(stderr, "%s\n", tl_error_message());
    return 1;
  }
  TlMesh *mesh = NULL;
  size_t n[3] = {2, 10, 2};
  double lo[3] = {0, 8, 0}, hi[3] = {0.8, 12, 0.8};
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &mesh), TL_OK);
  if (!mesh) return tl_test_report();
  test_weights(mesh);
  for (int k = 1; k <= 2; ++k) {
    test_operator(mesh, 0.0, k);
    test_operator(mesh, 0.2, k);
    test_operator(mesh, 0.6, k);
  }
  for (int pe = 0; pe <= 1; ++pe) {
    test_balance(mesh, 0.0, "lucy", pe);
    test_balance(mesh, 0.4, "lucy", pe);
    test_balance(mesh, 0.6, "gaussian", pe);
  }
  test_rows_per_element(mesh);
  test_bad_input(mesh);
  test_resolution(mesh);
  tl_mesh_destroy(&mesh);
  return tl_test_report();
}
