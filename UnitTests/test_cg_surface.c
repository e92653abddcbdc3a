/* Surface-restricted CG kernels (seeds/001 Eqs. 14-16) on a structured
 * quadrilateral surface and on a triangulated one: normalisation to 1 for
 * contact points at face centres, on edges and at corners, also after the
 * surface deforms; momentum balance of the nodal forces; convergence of
 * Eq. 15 to the point-source formula Eq. 16 as c -> 0; and the element
 * projection of Eq. 18. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include "talus.h"
#include "tl_cg_surface.h"
#include "tl_test.h"

/* Closed unit cube [0,1]^3: 8 corners, one quadrilateral per side. */
static const int cube_quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                     {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
static void cube_nodes(TlVec3 *x)
{
  for (int i = 0; i < 8; ++i) {
    int b = i & 3;
    x[i] = tl_v3((b == 1 || b == 2) ? 1 : 0, (b >= 2) ? 1 : 0, i >= 4 ? 1 : 0);
  }
}
/* The same cube with every side split into four triangles around its
 * centre (nodes 8..13), the paper's representation of a quadrilateral. */
static void cube_triangles(TlVec3 *x, int *tri)
{
  cube_nodes(x);
  for (int f = 0; f < 6; ++f) {
    TlVec3 c = tl_v3(0, 0, 0);
    for (int a = 0; a < 4; ++a) c = tl_v3_axpy(c, 0.25, x[cube_quads[f][a]]);
    x[8 + f] = c;
    for (int a = 0; a < 4; ++a) {
      int *t = tri + 3 * (4 * f + a);
      t[0] = cube_quads[f][a];
      t[1] = cube_quads[f][(a + 1) % 4];
      t[2] = 8 + f;
    }
  }
}

static double uniform(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static void check_normalisation(TlCGSurface *s, const char *what)
{
  const char *names[3] = {"lucy", "gaussian", "heaviside"};
  TlVec3 pts[5] = {{0.5, 0.5, 0.0}, {0.5, 0.0, 0.0}, {0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, {0.02, 0.97, 1.0}};
  const char *where[5] = {"face centre", "edge", "corner", "corner", "near a corner"};
  TlVec3 f = tl_v3(0.3, -0.2, 1.0);
  size_t cap = s->n_faces * (size_t)s->qp_per_face;
  size_t *slot = malloc(cap * sizeof *slot);
  double *w = malloc(cap * sizeof *w);
  TlVec3 *nodal = malloc(s->n_nodes * sizeof *nodal), *ref = malloc(s->n_nodes * sizeof *ref);
  TlVec3 *trac = malloc(cap * sizeof *trac);
  for (int kn = 0; kn < 3; ++kn) {
    TlCGKernel *k;
    TL_TEST_STATUS(tl_cg_kernel_create(names[kn], 0.35, 3, &k), TL_OK);
    for (int p = 0; p < 5; ++p) {
      size_t n = 0;
      TL_TEST_STATUS(tl_cg_surface_weights(s, k, pts[p], cap, &n, slot, w), TL_OK);
      double sum = 0.0, neg = 0.0;
      size_t faces_seen = 0, last_face = (size_t)-1;
      for (size_t i = 0; i < n; ++i) {
        sum += w[i];
        neg += w[i] < 0.0;
        size_t face = slot[i] / (size_t)s->qp_per_face;
        if (face != last_face) ++faces_seen, last_face = face;
      }
      TL_TEST_ASSERT(fabs(sum - 1.0) < 1e-14, "%s %s at %s: surface kernel integrates to %.17g", what, names[kn],
                     where[p], sum);
      TL_TEST_ASSERT(neg == 0 && n > 0, "%s: %g negative weights of %zu", what, neg, n);
      if (p == 2) TL_TEST_ASSERT(faces_seen >= 3, "%s: a corner kernel spans %zu faces", what, faces_seen);
      /* momentum balance: nodal forces sum to -f */
      for (size_t i = 0; i < s->n_nodes; ++i) nodal[i] = tl_v3(0, 0, 0);
      TL_TEST_STATUS(tl_cg_surface_nodal_forces(s, k, 1, NULL, &pts[p], &f, nodal), TL_OK);
      TlVec3 tot = tl_v3(0, 0, 0);
      for (size_t i = 0; i < s->n_nodes; ++i) tot = tl_v3_add(tot, nodal[i]);
      TL_TEST_ASSERT(tl_v3_norm(tl_v3_add(tot, f)) < 4e-16 * tl_v3_norm(f) * (double)s->n_nodes,
                     "%s %s at %s: nodal forces sum off by %g", what, names[kn], where[p], tl_v3_norm(tl_v3_add(tot, f)));
      /* against a direct sum over every quadrature point of the surface (no search) */
      double S = 0.0, worst = 0.0;
      for (size_t q = 0; q < cap; ++q) S += s->wq[q] * tl_cg_kernel_value(k, tl_v3_norm(tl_v3_sub(s->xq[q], pts[p])));
      for (size_t i = 0; i < s->n_nodes; ++i) ref[i] = tl_v3(0, 0, 0);
      for (size_t q = 0; q < cap; ++q) {
        double wk = s->wq[q] * tl_cg_kernel_value(k, tl_v3_norm(tl_v3_sub(s->xq[q], pts[p]))) / S;
        size_t face = q / (size_t)s->qp_per_face;
        for (int a = 0; a < s->nodes_per_face; ++a) {
          int node = s->face_node[face * (size_t)s->nodes_per_face + (size_t)a];
          ref[node] = tl_v3_axpy(ref[node], -wk * s->Nq[q * (size_t)s->nodes_per_face + (size_t)a], f);
        }
      }
      for (size_t i = 0; i < s->n_nodes; ++i) worst = fmax(worst, tl_v3_norm(tl_v3_sub(ref[i], nodal[i])));
      TL_TEST_ASSERT(worst < 1e-14, "%s %s at %s: nodal forces differ from the direct sum by %g", what, names[kn],
                     where[p], worst);
      /* traction of Eq. 14 integrates to -f as well */
      for (size_t i = 0; i < cap; ++i) trac[i] = tl_v3(0, 0, 0);
      TL_TEST_STATUS(tl_cg_surface_traction(s, k, 1, &pts[p], &f, trac), TL_OK);
      tot = tl_v3(0, 0, 0);
      for (size_t i = 0; i < cap; ++i) tot = tl_v3_axpy(tot, s->wq[i], trac[i]);
      TL_TEST_ASSERT(tl_v3_norm(tl_v3_add(tot, f)) < 1e-13, "%s: traction integral off by %g", what,
                     tl_v3_norm(tl_v3_add(tot, f)));
    }
    tl_cg_kernel_destroy(&k);
  }
  free(slot);
  free(w);
  free(nodal);
  free(ref);
  free(trac);
}

static void test_cube_normalisation(void)
{
  TlVec3 xq[8], xt[14];
  int tri[72];
  cube_nodes(xq);
  cube_triangles(xt, tri);
  TlCGSurface *sq, *st;
  TL_TEST_STATUS(tl_cg_surface_create_quads(8, xq, 6, &cube_quads[0][0], 6, &sq), TL_OK);
  TL_TEST_STATUS(tl_cg_surface_create_triangles(14, xt, 24, tri, 5, &st), TL_OK);
  double area = 0.0;
  for (size_t i = 0; i < 6 * (size_t)sq->qp_per_face; ++i) area += sq->wq[i];
  TL_TEST_CLOSE(area, 6.0, 1e-13);
  area = 0.0;
  for (size_t i = 0; i < 24 * (size_t)st->qp_per_face; ++i) area += st->wq[i];
  TL_TEST_CLOSE(area, 6.0, 1e-13);
  check_normalisation(sq, "quad cube");
  check_normalisation(st, "triangulated cube");
  /* deform: stretch, shear and jiggle the nodes; the quadrature follows */
  uint64_t seed = 5;
  for (int i = 0; i < 8; ++i) {
    TlVec3 p = xq[i];
    xq[i] = tl_v3(1.2 * p.x + 0.1 * p.z + 0.03 * uniform(&seed), 0.9 * p.y + 0.02 * uniform(&seed), p.z + 0.05 * p.x * p.y);
  }
  for (int i = 0; i < 14; ++i) {
    TlVec3 p = xt[i];
    xt[i] = tl_v3(1.2 * p.x + 0.1 * p.z + 0.03 * uniform(&seed), 0.9 * p.y + 0.02 * uniform(&seed), p.z + 0.05 * p.x * p.y);
  }
  TL_TEST_STATUS(tl_cg_surface_update(sq, NULL), TL_OK);
  TL_TEST_STATUS(tl_cg_surface_update(st, NULL), TL_OK);
  check_normalisation(sq, "deformed quad cube");
  check_normalisation(st, "deformed triangulated cube");
  /* a collapsed triangle is refused at update */
  TlVec3 keep = xt[8];
  xt[8] = xt[0];
  xt[1] = xt[0];
  TL_TEST_STATUS(tl_cg_surface_update(st, NULL), TL_ERR_NUMERIC);
  (void)keep;
  tl_cg_surface_destroy(&sq);
  tl_cg_surface_destroy(&st);
  TL_TEST_ASSERT(sq == NULL && st == NULL, "destroy nulls");
}

/* Flat n x n plate of unit squares in z = 0: as quadrilaterals, or each
 * square as four triangles around its centre. */
static void plate(int n, int triangles, TlVec3 **x, size_t *nn, int **faces, size_t *nf)
{
  size_t ng = (size_t)(n + 1) * (n + 1);
  *nn = ng + (triangles ? (size_t)n * n : 0);
  *x = malloc(*nn * sizeof(TlVec3));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) (*x)[j * (n + 1) + i] = tl_v3(i, j, 0);
  *nf = (size_t)n * n * (triangles ? 4 : 1);
  *faces = malloc(*nf * (triangles ? 3 : 4) * sizeof(int));
  int *f = *faces;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      int q[4] = {j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i};
      if (!triangles) {
        for (int a = 0; a < 4; ++a) *f++ = q[a];
      } else {
        int c = (int)ng + j * n + i;
        (*x)[c] = tl_v3(i + 0.5, j + 0.5, 0);
        for (int a = 0; a < 4; ++a) {
          *f++ = q[a];
          *f++ = q[(a + 1) % 4];
          *f++ = c;
        }
      }
    }
}

/* Eq. 15 -> Eq. 16 as c -> 0, for a contact at a node (where the shape
 * functions have their kink, so the error is first order in c) and for a
 * contact inside a face near an edge (exact once the kernel fits in the
 * face). */
static void test_dirac_limit(int triangles)
{
  const char *what = triangles ? "triangulated plate" : "quad plate";
  TlVec3 *x;
  int *faces;
  size_t nn, nf;
  plate(4, triangles, &x, &nn, &faces, &nf);
  TlVec3 point[2] = {{2.0, 2.0, 0.0}, {1.3, 2.15, 0.0}};
  size_t face_of[2];
  TlVec3 f = tl_v3(0.2, 0.1, -1.0);
  TlVec3 *F0 = calloc(nn, sizeof *F0), *F = calloc(nn, sizeof *F);
  TlCGKernel *dirac;
  TL_TEST_STATUS(tl_cg_kernel_create("dirac", 0.0, 3, &dirac), TL_OK);
  double widths[4] = {0.8, 0.4, 0.2, 0.1};
  for (int p = 0; p < 2; ++p) {
    /* the face holding the contact point, for Eq. 16 */
    size_t square = (size_t)(2 * 4 + (p ? 1 : 2)); /* both points lie in the lower triangle of their square */
    face_of[p] = triangles ? 4 * square : square;
    TlCGSurface *s;
    TL_TEST_STATUS(triangles ? tl_cg_surface_create_triangles(nn, x, nf, faces, 1, &s)
                             : tl_cg_surface_create_quads(nn, x, nf, faces, 1, &s),
                   TL_OK);
    for (size_t i = 0; i < nn; ++i) F0[i] = tl_v3(0, 0, 0);
    TL_TEST_STATUS(tl_cg_surface_nodal_forces(s, dirac, 1, &face_of[p], &point[p], &f, F0), TL_OK);
    TlVec3 tot = tl_v3(0, 0, 0), centroid = tl_v3(0, 0, 0);
    for (size_t i = 0; i < nn; ++i) {
      tot = tl_v3_add(tot, F0[i]);
      centroid = tl_v3_axpy(centroid, -F0[i].z / f.z, x[i]);
    }
    TL_TEST_ASSERT(tl_v3_norm(tl_v3_add(tot, f)) < 1e-15, "%s: Eq. 16 forces sum off by %g", what,
                   tl_v3_norm(tl_v3_add(tot, f)));
    TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(centroid, point[p])) < 1e-14,
                   "%s: Eq. 16 weights reproduce the contact point to %g", what,
                   tl_v3_norm(tl_v3_sub(centroid, point[p])));
    tl_cg_surface_destroy(&s);
    double err[4];
    for (int ci = 0; ci < 4; ++ci) {
      int sub = (int)ceil(2.0 / widths[ci]); /* about 6 quadrature points across the kernel */
      TL_TEST_STATUS(triangles ? tl_cg_surface_create_triangles(nn, x, nf, faces, sub, &s)
                               : tl_cg_surface_create_quads(nn, x, nf, faces, sub, &s),
                     TL_OK);
      TlCGKernel *k;
      TL_TEST_STATUS(tl_cg_kernel_create("lucy", widths[ci], 3, &k), TL_OK);
      for (size_t i = 0; i < nn; ++i) F[i] = tl_v3(0, 0, 0);
      TL_TEST_STATUS(tl_cg_surface_nodal_forces(s, k, 1, NULL, &point[p], &f, F), TL_OK);
      err[ci] = 0.0;
      for (size_t i = 0; i < nn; ++i) err[ci] = fmax(err[ci], tl_v3_norm(tl_v3_sub(F[i], F0[i])) / tl_v3_norm(f));
      printf("%s, contact %s: c = %.2f  max |F_i(c) - F_i(Dirac)| / |f| = %.3e\n", what, p ? "near an edge" : "at a node",
             widths[ci], err[ci]);
      tl_cg_kernel_destroy(&k);
      tl_cg_surface_destroy(&s);
    }
    if (p == 0) {
      for (int ci = 1; ci < 4; ++ci) {
        double ratio = err[ci - 1] / err[ci];
        TL_TEST_ASSERT(ratio > 1.8 && ratio < 2.2, "%s: error ratio %g at c = %g, expected first order (2)", what, ratio,
                       widths[ci]);
      }
      TL_TEST_ASSERT(err[3] < 0.05, "%s: error %g at c = 0.1", what, err[3]);
    } else {
      TL_TEST_ASSERT(err[0] > err[1] && err[1] > err[2], "%s: errors %g %g %g do not decrease", what, err[0], err[1],
                     err[2]);
      /* at c = 0.1 the kernel lies inside one face: only quadrature error is left */
      TL_TEST_ASSERT(err[3] < 1e-3 * err[1], "%s: kernel inside one face still differs from Eq. 16 by %g", what, err[3]);
    }
  }
  /* a kernel narrower than the quadrature spacing is refused */
  TlCGSurface *s;
  TL_TEST_STATUS(triangles ? tl_cg_surface_create_triangles(nn, x, nf, faces, 1, &s)
                           : tl_cg_surface_create_quads(nn, x, nf, faces, 1, &s),
                 TL_OK);
  TlCGKernel *tiny;
  TL_TEST_STATUS(tl_cg_kernel_create("lucy", 0.01, 3, &tiny), TL_OK);
  TL_TEST_STATUS(tl_cg_surface_nodal_forces(s, tiny, 1, NULL, &point[0], &f, F), TL_ERR_ARG);
  size_t cnt, sl[4];
  double wt[4];
  TL_TEST_STATUS(tl_cg_surface_weights(s, dirac, point[0], 4, &cnt, sl, wt), TL_ERR_UNSUPPORTED);
  tl_cg_kernel_destroy(&tiny);
  tl_cg_surface_destroy(&s);
  tl_cg_kernel_destroy(&dirac);
  free(F0);
  free(F);
  free(x);
  free(faces);
}

/* Eq. 18 on one trilinear hexahedron [0,1]^3 with a composite Gauss rule:
 * for a particle whose kernel lies inside the element, sum_a of the
 * projection is 1 and the normalised weights equal N_a(x) (a symmetric
 * kernel reproduces linear and bilinear terms). */
static void test_element_projection(void)
{
  const int m = 10, nq = 27 * m * m * m;
  static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
  static const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  TlVec3 *xq = malloc(nq * sizeof *xq);
  double *wq = malloc(nq * sizeof *wq), *Nq = malloc(nq * 8 * sizeof *Nq);
  int q = 0;
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b)
      for (int c = 0; c < m; ++c)
        for (int i = 0; i < 27; ++i, ++q) {
          double u = (a + 0.5 * (1 + gx[i % 3])) / m, v = (b + 0.5 * (1 + gx[(i / 3) % 3])) / m,
                 w = (c + 0.5 * (1 + gx[i / 9])) / m;
          xq[q] = tl_v3(u, v, w);
          wq[q] = gw[i % 3] * gw[(i / 3) % 3] * gw[i / 9] / (8.0 * m * m * m);
          for (int n = 0; n < 8; ++n)
            Nq[q * 8 + n] = ((n & 1) ? u : 1 - u) * ((n & 2) ? v : 1 - v) * ((n & 4) ? w : 1 - w);
        }
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create("lucy", 0.2, 3, &k), TL_OK);
  TlVec3 p = tl_v3(0.3, 0.45, 0.62);
  double out[8] = {0}, sum = 0.0, worst = 0.0;
  TL_TEST_STATUS(tl_cg_project_to_element(k, (size_t)nq, xq, wq, 8, Nq, p, 1.0, out), TL_OK);
  for (int n = 0; n < 8; ++n) sum += out[n];
  for (int n = 0; n < 8; ++n) {
    double Na = ((n & 1) ? p.x : 1 - p.x) * ((n & 2) ? p.y : 1 - p.y) * ((n & 4) ? p.z : 1 - p.z);
    worst = fmax(worst, fabs(out[n] / sum - Na));
  }
  TL_TEST_ASSERT(fabs(sum - 1.0) < 1e-4, "Eq. 18 weights of an interior particle sum to %.10g", sum);
  TL_TEST_ASSERT(worst < 1e-4, "Eq. 18 normalised weights differ from N_a(x) by %g", worst);
  printf("Eq. 18 interior particle: |sum - 1| = %.2e, max |w_a - N_a| = %.2e\n", fabs(sum - 1.0), worst);
  /* a particle at a corner sees an eighth of its kernel */
  double corner[8] = {0};
  TL_TEST_STATUS(tl_cg_project_to_element(k, (size_t)nq, xq, wq, 8, Nq, tl_v3(0, 0, 0), 1.0, corner), TL_OK);
  double cs = 0.0;
  for (int n = 0; n < 8; ++n) cs += corner[n];
  TL_TEST_ASSERT(fabs(cs - 0.125) < 1e-3, "corner particle: weight %g, expected 1/8", cs);
  tl_cg_kernel_destroy(&k);
  free(xq);
  free(wq);
  free(Nq);
}

/* Refreshing the quadrature near the contacts only gives the nodal forces
 * of a full refresh (to round-off: the faces are summed in another order),
 * on a plate deformed after creation, for quadrilaterals and triangles. */
static void test_update_near(int triangles)
{
  const char *what = triangles ? "triangulated plate" : "quad plate";
  TlVec3 *x;
  int *faces;
  size_t nn, nf;
  plate(8, triangles, &x, &nn, &faces, &nf);
  TlCGSurface *s;
  TL_TEST_STATUS(triangles ? tl_cg_surface_create_triangles(nn, x, nf, faces, 2, &s)
                           : tl_cg_surface_create_quads(nn, x, nf, faces, 2, &s),
                 TL_OK);
  TlCGKernel *k;
  TL_TEST_STATUS(tl_cg_kernel_create("lucy", 0.9, 3, &k), TL_OK);
  /* a bump moves the nodes; contacts near one corner */
  for (size_t i = 0; i < nn; ++i) x[i].z = 0.3 * sin(0.7 * x[i].x) * cos(0.5 * x[i].y) + 0.05 * x[i].x;
  TlVec3 pts[3] = {{1.1, 1.3, 0.0}, {1.6, 0.9, 0.0}, {2.4, 1.8, 0.0}}, fw[3] = {{0.1, 0, -1}, {0, 0.2, -2}, {-0.3, 0.1, -1.5}};
  for (int c = 0; c < 3; ++c) pts[c].z = 0.3 * sin(0.7 * pts[c].x) * cos(0.5 * pts[c].y) + 0.05 * pts[c].x;
  TlVec3 *Ffull = calloc(nn, sizeof *Ffull), *Fnear = calloc(nn, sizeof *Fnear);
  TL_TEST_STATUS(tl_cg_surface_update(s, NULL), TL_OK);
  TL_TEST_STATUS(tl_cg_surface_nodal_forces(s, k, 3, NULL, pts, fw, Ffull), TL_OK);
  /* move again, back to the same shape, refreshing near the contacts only */
  for (size_t i = 0; i < nn; ++i) x[i].z += 0.2;
  TL_TEST_STATUS(tl_cg_surface_update(s, NULL), TL_OK);
  for (size_t i = 0; i < nn; ++i) x[i].z -= 0.2;
  TL_TEST_STATUS(tl_cg_surface_update_near(s, 3, pts, 0.9 + 1.0), TL_OK);
  TL_TEST_STATUS(tl_cg_surface_nodal_forces(s, k, 3, NULL, pts, fw, Fnear), TL_OK);
  double diff = 0.0, scale = 0.0;
  size_t loaded = 0;
  for (size_t i = 0; i < nn; ++i) {
    diff = fmax(diff, tl_v3_norm(tl_v3_sub(Ffull[i], Fnear[i])));
    scale = fmax(scale, tl_v3_norm(Ffull[i]));
    loaded += tl_v3_norm(Ffull[i]) > 0.0;
  }
  printf("%s: update near the contacts vs full update: largest nodal difference %.3g (largest force %.3g, %zu of %zu "
         "nodes loaded)\n", what, diff, scale, loaded, nn);
  TL_TEST_ASSERT(loaded > 4 && loaded < nn, "%s: the kernel loads some nodes, not all (%zu of %zu)", what, loaded, nn);
  TL_TEST_ASSERT(diff <= 1e-14 * scale, "%s: partial update changes the forces by %g", what, diff);
  free(Ffull);
  free(Fnear);
  tl_cg_kernel_destroy(&k);
  tl_cg_surface_destroy(&s);
  free(x);
  free(faces);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_update_near(0);
  test_update_near(1);
  test_cube_normalisation();
  test_dirac_limit(0);
  test_dirac_limit(1);
  test_element_projection();
  return tl_test_report();
}
