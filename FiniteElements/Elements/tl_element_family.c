#include "tl_element_family.h"

#include "tl_element.h"

/* 1-D Lagrange basis of degree 1 (nodes -1, 1) or 2 (nodes -1, 0, 1): value
 * and derivative of the polynomial belonging to node coordinate c. */
static void lagrange_1d(int degree, double c, double x, double *phi, double *dphi)
{
  if (degree == 1) {
    *phi = 0.5 * (1.0 + c * x);
    *dphi = 0.5 * c;
  } else if (c < -0.5) {
    *phi = 0.5 * x * (x - 1.0);
    *dphi = x - 0.5;
  } else if (c > 0.5) {
    *phi = 0.5 * x * (x + 1.0);
    *dphi = x + 0.5;
  } else {
    *phi = 1.0 - x * x;
    *dphi = -2.0 * x;
  }
}

void tl_family_tensor_eval(int dim, int degree, int n_nodes, const double *ref, int npts,
                           const double *xi, double *N, double *dN)
{
  for (int p = 0; p < npts; ++p) {
    const double *x = xi + 3 * p;
    for (int a = 0; a < n_nodes; ++a) {
      double phi[3], dphi[3];
      for (int d = 0; d < dim; ++d) lagrange_1d(degree, ref[a * dim + d], x[d], &phi[d], &dphi[d]);
      double value = 1.0;
      for (int d = 0; d < dim; ++d) value *= phi[d];
      if (N) N[p * n_nodes + a] = value;
      if (dN) {
        for (int d = 0; d < dim; ++d) {
          double g = dphi[d];
          for (int e = 0; e < dim; ++e)
            if (e != d) g *= phi[e];
          dN[(p * n_nodes + a) * dim + d] = g;
        }
      }
    }
  }
}

void tl_family_simplex_eval(int dim, int degree, int n_edges, const int *edges, int npts,
                            const double *xi, double *N, double *dN)
{
  int nv = dim + 1;
  int nn = degree == 1 ? nv : nv + n_edges;
  for (int p = 0; p < npts; ++p) {
    const double *x = xi + 3 * p;
    /* Barycentric coordinates L_0 = 1 - sum xi, L_i = xi_{i-1}, and their
     * gradients with respect to xi. */
    double L[4], dL[4][3] = {{0}};
    L[0] = 1.0;
    for (int d = 0; d < dim; ++d) {
      L[0] -= x[d];
      L[d + 1] = x[d];
      dL[0][d] = -1.0;
      dL[d + 1][d] = 1.0;
    }
    for (int v = 0; v < nv; ++v) {
      double value = degree == 1 ? L[v] : L[v] * (2.0 * L[v] - 1.0);
      double factor = degree == 1 ? 1.0 : 4.0 * L[v] - 1.0;
      if (N) N[p * nn + v] = value;
      if (dN)
        for (int d = 0; d < dim; ++d) dN[(p * nn + v) * dim + d] = factor * dL[v][d];
    }
    if (degree == 2) {
      for (int e = 0; e < n_edges; ++e) {
        int i = edges[2 * e], j = edges[2 * e + 1], a = nv + e;
        if (N) N[p * nn + a] = 4.0 * L[i] * L[j];
        if (dN)
          for (int d = 0; d < dim; ++d)
            dN[(p * nn + a) * dim + d] = 4.0 * (dL[i][d] * L[j] + L[i] * dL[j][d]);
      }
    }
  }
}

void tl_family_serendipity8_eval(int npts, const double *xi, double *N, double *dN)
{
  static const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int p = 0; p < npts; ++p) {
    double r = xi[3 * p], s = xi[3 * p + 1];
    double *n = N ? N + 8 * p : NULL;
    double *g = dN ? dN + 16 * p : NULL;
    for (int a = 0; a < 4; ++a) {
      double ra = corner[a][0], sa = corner[a][1];
      double u = 1.0 + ra * r, v = 1.0 + sa * s, w = ra * r + sa * s - 1.0;
      if (n) n[a] = 0.25 * u * v * w;
      if (g) {
        g[2 * a] = 0.25 * ra * v * (w + u);
        g[2 * a + 1] = 0.25 * sa * u * (w + v);
      }
    }
    /* Mid-edge nodes 4 (s = -1), 5 (r = 1), 6 (s = 1), 7 (r = -1). */
    static const double mid_s[2] = {-1.0, 1.0};
    for (int k = 0; k < 2; ++k) { /* nodes 4 and 6: r varies */
      int a = k == 0 ? 4 : 6;
      double sa = mid_s[k];
      if (n) n[a] = 0.5 * (1.0 - r * r) * (1.0 + sa * s);
      if (g) {
        g[2 * a] = -r * (1.0 + sa * s);
        g[2 * a + 1] = 0.5 * (1.0 - r * r) * sa;
      }
    }
    for (int k = 0; k < 2; ++k) { /* nodes 5 (r = 1) and 7 (r = -1): s varies */
      int a = k == 0 ? 5 : 7;
      double ra = k == 0 ? 1.0 : -1.0;
      if (n) n[a] = 0.5 * (1.0 + ra * r) * (1.0 - s * s);
      if (g) {
        g[2 * a] = 0.5 * ra * (1.0 - s * s);
        g[2 * a + 1] = -(1.0 + ra * r) * s;
      }
    }
  }
}
