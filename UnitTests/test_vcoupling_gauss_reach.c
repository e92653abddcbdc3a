/* Volume coupling with the published runs' quadrature and reach: Eq. 18 on
 * the hex8 element's own 2-point rule, the particles within c of the
 * element.  One particle per element (1P): below the width at which the
 * kernel of a Gauss point reaches the next particle (0.82 element sizes for
 * the 2-point rule), Pi is the one of Eq. 19 (the published plateau at
 * c = 0.5 dX); at c = dX the neighbours enter (reach c) or are cut off by a
 * box shrunk by a diameter (reach c - d); and the whole-cell search of the
 * published runs (box c - d beyond the element, widened by half a search
 * cell of size d and rounded out to whole cells) holds every particle the
 * 2-point kernel reaches, for 1 to 4 particles per element edge and every
 * published width: so reach c gathers what they gathered. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_test.h"
#include "tl_vcoupling.h"

enum { MAXP = 8000, MAXN = 400 };
static double xp[3 * MAXP], mp[MAXP], q[3 * MAXP];

/* A simple cubic lattice, n^3 particles per element, on y in [6, 12]. */
static size_t make_lattice(int n)
{
  double d = 0.4 / n;
  size_t np = 0;
  int nx = (int)lround(0.8 / d), ny = (int)lround(6.0 / d);
  for (int j = 0; j < ny; ++j)
    for (int k = 0; k < nx; ++k)
      for (int i = 0; i < nx; ++i) {
        xp[3 * np] = (i + 0.5) * d;
        xp[3 * np + 1] = 6.0 + (j + 0.5) * d;
        xp[3 * np + 2] = (k + 0.5) * d;
        mp[np] = 1.0;
        ++np;
      }
  return np;
}

/* Homogenised field of q (a displacement that differs from particle to
 * particle) at the nodes some row reaches. */
static int homogenise(const TlMesh *mesh, double c, int quad, double shrink, size_t np, double *out, char *reached)
{
  TlVCouplingParams p = {{1, 8.0, 12.0}, c, "lucy", 1e10, quad, 1};
  TlVCoupling *vc = NULL;
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &p, &vc), TL_OK);
  if (!vc) return 0;
  TL_TEST_STATUS(tl_vcoupling_set_reach_shrink(vc, shrink), TL_OK);
  TL_TEST_STATUS(tl_vcoupling_update(vc, NULL, np, xp, mp), TL_OK);
  memset(out, 0, 3 * mesh->n_nodes * sizeof *out);
  TL_TEST_STATUS(tl_vcoupling_homogenise(vc, q, out, reached), TL_OK);
  tl_vcoupling_destroy(&vc);
  return 1;
}

static double largest_difference(const TlMesh *mesh, const double *a, const char *ra, const double *b, const char *rb,
                                 size_t *n_both)
{
  double worst = 0.0;
  *n_both = 0;
  for (size_t i = 0; i < mesh->n_nodes; ++i) {
    if (!ra[i] || !rb[i]) continue;
    ++*n_both;
    for (int d = 0; d < 3; ++d) worst = fmax(worst, fabs(a[3 * i + d] - b[3 * i + d]));
  }
  return worst;
}

static void test_plateau_1p(const TlMesh *mesh)
{
  size_t np = make_lattice(1);
  for (size_t a = 0; a < np; ++a)
    for (int d = 0; d < 3; ++d) q[3 * a + d] = sin(1.7 * (double)a + 0.9 * d) * 1e-3;
  static double u0[3 * MAXN], u1[3 * MAXN];
  static char r0[MAXN], r1[MAXN];
  TL_TEST_ASSERT(mesh->n_nodes <= MAXN, "mesh has %zu nodes", mesh->n_nodes);
  if (!homogenise(mesh, 0.0, 2, 0.0, np, u0, r0)) return;
  /* c = 0.5 dX (the published CG1R) and just below the reach of a Gauss
   * point (0.82 dX): the own particle alone, Pi as Eq. 19 */
  const double widths[] = {0.5 * 0.4 * 1.001, 0.8 * 0.4};
  for (int k = 0; k < 2; ++k) {
    if (!homogenise(mesh, widths[k], 2, 0.0, np, u1, r1)) return;
    size_t nb = 0;
    double dmax = largest_difference(mesh, u0, r0, u1, r1, &nb);
    TL_TEST_ASSERT(nb > 0 && dmax <= 1e-15, "c = %g m, 2-point rule: Pi off Eq. 19 by %g m (%zu nodes)", widths[k], dmax,
                   nb);
  }
  /* c = dX: the face neighbours enter with the reach c, not with c - d */
  if (!homogenise(mesh, 0.4, 2, 0.0, np, u1, r1)) return;
  size_t nb = 0;
  double dmax = largest_difference(mesh, u0, r0, u1, r1, &nb);
  TL_TEST_ASSERT(nb > 0 && dmax > 1e-6, "c = dX, reach c: the neighbours must enter Pi (difference %g m)", dmax);
  if (!homogenise(mesh, 0.4, 2, 0.4, np, u1, r1)) return;
  dmax = largest_difference(mesh, u0, r0, u1, r1, &nb);
  TL_TEST_ASSERT(nb > 0 && dmax <= 1e-15, "c = dX, reach c - d: own particle only, off Eq. 19 by %g m", dmax);
}

/* The published search: cells of size d (their restart files: cellSizes
 * 400 mm at 1P), cell index floor(x / d); an element's box [lo, hi]
 * extended by c - d gathers the cells floor((lo - (c - d)) / d - 1/2) to
 * floor((hi + c - d) / d + 1/2) along each axis.  A particle the Lucy
 * kernel of support c reaches from a Gauss point lies within c of it along
 * each axis, and the 2-point rule's points sit (1/2 -+ 1/(2 sqrt 3)) dX
 * into the element: every such particle centre must lie in the gathered
 * cells (the same along x, y and z: the lattice and the mesh share their
 * origin), and within c of the element (what reach c gathers). */
static void test_whole_cells(void)
{
  const double dx = 0.4, g = 0.5 / sqrt(3.0), lo = 8.0, hi = 8.4;
  int missing = 0, beyond = 0, reached = 0;
  for (int n = 1; n <= 4; ++n) {
    double d = dx / n;
    for (int nr = 1; nr <= 5; ++nr) { /* CGnR with n = nr (1 .. 5) x the particles per edge: c = 0.5 .. 2.5 dX */
      double c = nr * 0.5 * dx, e = c - d;
      long cs = (long)floor((lo - e) / d - 0.5), ce = (long)floor((hi + e) / d + 0.5);
      for (long j = (long)floor((lo - 2 * c) / d); j <= (long)ceil((hi + 2 * c) / d); ++j) {
        double y = (j + 0.5) * d;
        double axial = fmin(fabs(y - (lo + (0.5 - g) * dx)), fabs(y - (lo + (0.5 + g) * dx)));
        if (!(axial < c)) continue;
        ++reached;
        long cell = (long)floor(y / d);
        if (cell < cs || cell > ce) ++missing;
        if (y < lo - c || y > hi + c) ++beyond;
      }
    }
  }
  TL_TEST_ASSERT(reached > 0 && missing == 0, "%d of %d particle centres the kernel reaches lie outside the published "
                 "search cells", missing, reached);
  TL_TEST_ASSERT(beyond == 0, "%d particle centres reached beyond c of the element", beyond);
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
  test_plateau_1p(mesh);
  test_whole_cells();
  tl_mesh_destroy(&mesh);
  return tl_test_report();
}
