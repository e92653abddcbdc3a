/* Per-face coupling forces of the CG surface (seeds/001 Eqs. 15-16): the
 * share of every face, integral over the face of N_a t dA, for Dirac and
 * Lucy kernels on deformed quadrilateral and triangulated plates.
 *   - assembled node-wise they equal tl_cg_surface_nodal_forces and an
 *     independent evaluation (the normalised weights of every quadrature
 *     point times the shape values; for c = 0 the shape functions at the
 *     contact point) to round-off;
 *   - the faces flagged are exactly those the kernel reaches (c > 0: a
 *     quadrature point within c of a contact) or the contacts' faces (c = 0),
 *     listed once each, and no other face holds a force;
 *   - the shares sum to minus the contact forces (momentum balance). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "talus.h"
#include "tl_cg_surface.h"
#include "tl_test.h"

/* n x n plate of unit squares, bumped out of plane: quadrilaterals, or each
 * square as four triangles around its centre. */
static void bumped_plate(int n, int triangles, TlVec3 **x, size_t *nn, int **faces, size_t *nf)
{
  size_t ng = (size_t)(n + 1) * (n + 1);
  *nn = ng + (triangles ? (size_t)n * n : 0);
  *x = malloc(*nn * sizeof(TlVec3));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) (*x)[j * (n + 1) + i] = tl_v3(i + 0.1 * sin(1.3 * j), j + 0.07 * i, 0);
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
        (*x)[c] = tl_v3(0, 0, 0);
        for (int a = 0; a < 4; ++a) (*x)[c] = tl_v3_axpy((*x)[c], 0.25, (*x)[q[a]]);
        for (int a = 0; a < 4; ++a) {
          *f++ = q[a];
          *f++ = q[(a + 1) % 4];
          *f++ = c;
        }
      }
    }
  for (size_t i = 0; i < *nn; ++i) (*x)[i].z = 0.3 * sin(0.7 * (*x)[i].x) * cos(0.5 * (*x)[i].y);
}

static double norm_max(const TlVec3 *v, size_t n)
{
  double m = 0.0;
  for (size_t i = 0; i < n; ++i) m = fmax(m, tl_v3_norm(v[i]));
  return m;
}

static void test_faces(int triangles, double width)
{
  const char *what = triangles ? "triangulated plate" : "quad plate";
  TlVec3 *x;
  int *faces;
  size_t nn, nf;
  bumped_plate(6, triangles, &x, &nn, &faces, &nf);
  TlCGSurface *s = NULL;
  TL_TEST_STATUS(triangles ? tl_cg_surface_create_triangles(nn, x, nf, faces, 3, &s)
                           : tl_cg_surface_create_quads(nn, x, nf, faces, 3, &s),
                 TL_OK);
  if (!s) return;
  TlCGKernel *k = NULL;
  TL_TEST_STATUS(tl_cg_kernel_create(width > 0.0 ? "lucy" : "dirac", width, 3, &k), TL_OK);
  const int npf = s->nodes_per_face;
  /* Contacts on faces (points on the face from its own shape functions):
   * inside, near an edge, at a node, near the plate's border. */
  enum { NC = 5 };
  const size_t cface[NC] = {nf / 2 + 1, 7, nf - 3, 2, nf / 3};
  const double cxi[NC][2] = {{0.3, 0.4}, {0.05, 0.6}, {0.0, 0.0}, {0.5, 0.1}, {0.25, 0.25}};
  TlVec3 point[NC], fw[NC];
  for (int c = 0; c < NC; ++c) {
    const int *v = s->face_node + cface[c] * (size_t)npf;
    double N[4];
    if (triangles) {
      N[0] = 1.0 - cxi[c][0] - cxi[c][1], N[1] = cxi[c][0], N[2] = cxi[c][1];
    } else {
      const double u = 2.0 * cxi[c][0] - 1.0, w = 2.0 * cxi[c][1] - 1.0;
      N[0] = 0.25 * (1 - u) * (1 - w), N[1] = 0.25 * (1 + u) * (1 - w), N[2] = 0.25 * (1 + u) * (1 + w), N[3] = 0.25 * (1 - u) * (1 + w);
    }
    point[c] = tl_v3(0, 0, 0);
    for (int a = 0; a < npf; ++a) point[c] = tl_v3_axpy(point[c], N[a], x[v[a]]);
    fw[c] = tl_v3(0.3 - 0.1 * c, 0.2 * c - 0.4, -1.0 - 0.5 * c);
  }
  TlVec3 *face_nodal = calloc(nf * (size_t)npf, sizeof *face_nodal);
  unsigned char *flag = calloc(nf, 1);
  size_t *list = calloc(nf, sizeof *list), n_list = 0;
  TL_TEST_STATUS(tl_cg_surface_face_forces(s, k, NC, cface, point, fw, face_nodal, flag, list, &n_list), TL_OK);
  /* Assembled per-face forces, the nodal function, and the reference. */
  TlVec3 *assembled = calloc(nn, sizeof *assembled), *nodal = calloc(nn, sizeof *nodal), *ref = calloc(nn, sizeof *ref);
  tl_cg_surface_assemble_faces(s, n_list, list, face_nodal, assembled);
  TL_TEST_STATUS(tl_cg_surface_nodal_forces(s, k, NC, cface, point, fw, nodal), TL_OK);
  unsigned char *expect = calloc(nf, 1);
  if (width > 0.0) {
    enum { MAXW = 20000 };
    size_t *slot = malloc(MAXW * sizeof *slot), count = 0;
    double *weight = malloc(MAXW * sizeof *weight);
    for (int c = 0; c < NC; ++c) {
      TL_TEST_STATUS(tl_cg_surface_weights(s, k, point[c], MAXW, &count, slot, weight), TL_OK);
      for (size_t j = 0; j < count; ++j) {
        const size_t f = slot[j] / (size_t)s->qp_per_face;
        for (int a = 0; a < npf; ++a)
          ref[s->face_node[f * (size_t)npf + (size_t)a]] =
              tl_v3_axpy(ref[s->face_node[f * (size_t)npf + (size_t)a]], -weight[j] * s->Nq[slot[j] * (size_t)npf + (size_t)a], fw[c]);
      }
      /* reached: a quadrature point strictly within c (Lucy vanishes at c) */
      for (size_t f = 0; f < nf; ++f)
        for (int q = 0; q < s->qp_per_face; ++q)
          if (tl_v3_norm(tl_v3_sub(s->xq[f * (size_t)s->qp_per_face + (size_t)q], point[c])) < width) expect[f] = 1;
    }
    free(slot);
    free(weight);
  } else {
    double N[4 * NC];
    TL_TEST_STATUS(s->ops->shape_at(s, NC, cface, point, N), TL_OK);
    for (int c = 0; c < NC; ++c) {
      for (int a = 0; a < npf; ++a)
        ref[s->face_node[cface[c] * (size_t)npf + (size_t)a]] =
            tl_v3_axpy(ref[s->face_node[cface[c] * (size_t)npf + (size_t)a]], -N[c * npf + a], fw[c]);
      expect[cface[c]] = 1;
    }
  }
  const double scale = norm_max(ref, nn);
  double d_nodal = 0.0, d_ref = 0.0;
  for (size_t i = 0; i < nn; ++i) {
    d_nodal = fmax(d_nodal, tl_v3_norm(tl_v3_sub(assembled[i], nodal[i])));
    d_ref = fmax(d_ref, tl_v3_norm(tl_v3_sub(assembled[i], ref[i])));
  }
  /* flags, list and the faces holding forces */
  size_t n_flag = 0, n_expect = 0, mismatched = 0, dup = 0, stray = 0;
  unsigned char *seen = calloc(nf, 1);
  for (size_t t = 0; t < n_list; ++t) {
    dup += seen[list[t]];
    seen[list[t]] = 1;
  }
  TlVec3 sum = tl_v3(0, 0, 0), fsum = tl_v3(0, 0, 0);
  for (size_t f = 0; f < nf; ++f) {
    n_flag += flag[f];
    n_expect += expect[f];
    mismatched += flag[f] != expect[f] || seen[f] != flag[f];
    for (int a = 0; a < npf; ++a) {
      sum = tl_v3_add(sum, face_nodal[f * (size_t)npf + (size_t)a]);
      if (!flag[f] && tl_v3_norm(face_nodal[f * (size_t)npf + (size_t)a]) != 0.0) stray++;
    }
  }
  for (int c = 0; c < NC; ++c) fsum = tl_v3_add(fsum, fw[c]);
  const double balance = tl_v3_norm(tl_v3_add(sum, fsum)) / tl_v3_norm(fsum);
  printf("%s, c = %g: assembled per-face vs nodal forces %.3g, vs reference %.3g (largest %.3g N); %zu faces reached "
         "(%zu expected, %zu listed), momentum defect %.3g\n",
         what, width, d_nodal, d_ref, scale, n_flag, n_expect, n_list, balance);
  TL_TEST_ASSERT(scale > 0.1, "%s: the contacts load the nodes (%g)", what, scale);
  TL_TEST_ASSERT(d_nodal <= 1e-14 * scale, "%s, c = %g: assembled per-face forces differ from the nodal ones by %g", what,
                 width, d_nodal);
  TL_TEST_ASSERT(d_ref <= 1e-14 * scale, "%s, c = %g: assembled per-face forces differ from the reference by %g", what,
                 width, d_ref);
  TL_TEST_ASSERT(mismatched == 0 && dup == 0 && n_list == n_flag, "%s, c = %g: %zu faces flagged wrongly, %zu listed twice",
                 what, width, mismatched, dup);
  TL_TEST_ASSERT(stray == 0, "%s: %zu forces on faces not flagged", what, stray);
  TL_TEST_ASSERT(width == 0.0 ? n_flag <= NC : n_flag > NC, "%s, c = %g: %zu faces reached", what, width, n_flag);
  TL_TEST_ASSERT(balance < 1e-14, "%s, c = %g: per-face forces do not balance the contacts (%g)", what, width, balance);
  /* A second call adds to the shares and lists no face twice. */
  size_t n_before = n_list;
  TL_TEST_STATUS(tl_cg_surface_face_forces(s, k, NC, cface, point, fw, face_nodal, flag, list, &n_list), TL_OK);
  double twice = 0.0;
  memset(assembled, 0, nn * sizeof *assembled);
  tl_cg_surface_assemble_faces(s, nf, NULL, face_nodal, assembled); /* NULL: faces 0 .. nf - 1 */
  for (size_t i = 0; i < nn; ++i) twice = fmax(twice, tl_v3_norm(tl_v3_sub(assembled[i], tl_v3_scale(ref[i], 2.0))));
  TL_TEST_ASSERT(n_list == n_before && twice <= 1e-14 * scale, "%s: accumulation (%zu -> %zu faces, off by %g)", what,
                 n_before, n_list, twice);
  /* The list needs the flags. */
  TL_TEST_STATUS(tl_cg_surface_face_forces(s, k, NC, cface, point, fw, face_nodal, NULL, list, &n_list), TL_ERR_ARG);
  free(seen);
  free(expect);
  free(assembled);
  free(nodal);
  free(ref);
  free(face_nodal);
  free(flag);
  free(list);
  tl_cg_kernel_destroy(&k);
  tl_cg_surface_destroy(&s);
  free(x);
  free(faces);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  for (int tri = 0; tri < 2; ++tri) {
    test_faces(tri, 0.0);
    test_faces(tri, 0.8);
    test_faces(tri, 2.5);
  }
  return tl_test_report();
}
