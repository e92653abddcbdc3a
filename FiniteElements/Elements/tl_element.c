#include "tl_element.h"

#include <math.h>
#include <string.h>


/* Gauss-Legendre points and weights on [-1, 1], 1 to 5 points. */
static const double gauss_x[5][5] = {
    {0.0},
    {-0.57735026918962576451, 0.57735026918962576451},
    {-0.77459666924148337704, 0.0, 0.77459666924148337704},
    {-0.86113631159405257522, -0.33998104358485626480, 0.33998104358485626480,
     0.86113631159405257522},
    {-0.90617984593866399280, -0.53846931010568309104, 0.0, 0.53846931010568309104,
     0.90617984593866399280}};
static const double gauss_w[5][5] = {
    {2.0},
    {1.0, 1.0},
    {0.55555555555555555556, 0.88888888888888888889, 0.55555555555555555556},
    {0.34785484513745385737, 0.65214515486254614263, 0.65214515486254614263,
     0.34785484513745385737},
    {0.23692688505618908751, 0.47862867049936646804, 0.56888888888888888889,
     0.47862867049936646804, 0.23692688505618908751}};

TlStatus tl_element_quadrature(const TlElementType *type, int order, TlQuadrature *rule)
{
  if (!type || !rule) TL_ERROR(TL_ERR_ARG, "tl_element_quadrature: NULL argument");
  if (order < 1 || order > 5)
    TL_ERROR(TL_ERR_ARG, "quadrature order %d for element %s outside [1, 5]", order,
             type->header.name);
  const double *gx = gauss_x[order - 1], *gw = gauss_w[order - 1];
  int n = 0, dim = type->dim;
  memset(rule, 0, sizeof *rule);
  rule->dim = dim;
  if (type->shape == TL_SHAPE_LINE || type->shape == TL_SHAPE_QUAD || type->shape == TL_SHAPE_HEX) {
    int nk = dim >= 3 ? order : 1, nj = dim >= 2 ? order : 1;
    for (int k = 0; k < nk; ++k)
      for (int j = 0; j < nj; ++j)
        for (int i = 0; i < order; ++i) {
          rule->xi[n][0] = gx[i];
          rule->w[n] = gw[i];
          if (dim >= 2) rule->xi[n][1] = gx[j], rule->w[n] *= gw[j];
          if (dim >= 3) rule->xi[n][2] = gx[k], rule->w[n] *= gw[k];
          ++n;
        }
  } else {
    /* Collapsed product rule: Gauss points on [0, 1] mapped to the simplex. */
    for (int k = 0; k < (dim == 3 ? order : 1); ++k)
      for (int j = 0; j < order; ++j)
        for (int i = 0; i < order; ++i) {
          double a = 0.5 * (1.0 + gx[i]), b = 0.5 * (1.0 + gx[j]);
          double w = 0.25 * gw[i] * gw[j];
          if (dim == 2) {
            rule->xi[n][0] = a * (1.0 - b);
            rule->xi[n][1] = b;
            rule->w[n] = w * (1.0 - b);
          } else {
            double c = 0.5 * (1.0 + gx[k]);
            w *= 0.5 * gw[k];
            rule->xi[n][0] = a * (1.0 - b) * (1.0 - c);
            rule->xi[n][1] = b * (1.0 - c);
            rule->xi[n][2] = c;
            rule->w[n] = w * (1.0 - b) * (1.0 - c) * (1.0 - c);
          }
          ++n;
        }
  }
  rule->n = n;
  return TL_OK;
}

double tl_element_reference_measure(const TlElementType *type)
{
  switch (type->shape) {
  case TL_SHAPE_LINE: return 2.0;
  case TL_SHAPE_QUAD: return 4.0;
  case TL_SHAPE_HEX: return 8.0;
  case TL_SHAPE_TRI: return 0.5;
  case TL_SHAPE_TET: return 1.0 / 6.0;
  }
  return 0.0;
}

int tl_element_contains(const TlElementType *type, const double *xi, double tol)
{
  if (type->shape == TL_SHAPE_TRI || type->shape == TL_SHAPE_TET) {
    double sum = 0.0;
    for (int d = 0; d < type->dim; ++d) {
      if (xi[d] < -tol) return 0;
      sum += xi[d];
    }
    return sum <= 1.0 + tol;
  }
  for (int d = 0; d < type->dim; ++d)
    if (fabs(xi[d]) > 1.0 + tol) return 0;
  return 1;
}

void tl_element_interpolate(const TlElementType *type, const double *x, const double *xi,
                            double *out)
{
  double N[TL_ELEMENT_MAX_NODES];
  double p[3] = {xi[0], type->dim > 1 ? xi[1] : 0.0, type->dim > 2 ? xi[2] : 0.0};
  type->eval(1, p, N, NULL);
  out[0] = out[1] = out[2] = 0.0;
  for (int a = 0; a < type->n_nodes; ++a)
    for (int i = 0; i < 3; ++i) out[i] += N[a] * x[3 * a + i];
}

/* J[i][j] = dx_i / dxi_j over the first sdim coordinates; unused rows and
 * columns are the identity so a 2-D map is a 3x3 matrix with J[2][2] = 1. */
static double jacobian_from_dN(const TlElementType *type, int sdim, const double *x,
                               const double *dN, double J[3][3])
{
  int dim = type->dim;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) J[i][j] = (i == j && i >= sdim) ? 1.0 : 0.0;
  for (int a = 0; a < type->n_nodes; ++a)
    for (int i = 0; i < sdim; ++i)
      for (int j = 0; j < dim; ++j) J[i][j] += x[3 * a + i] * dN[a * dim + j];
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
         J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

TlStatus tl_element_jacobian(const TlElementType *type, int sdim, const double *x,
                             const double *xi, double J[3][3], double *detJ)
{
  if (type->dim != sdim)
    TL_ERROR(TL_ERR_ARG, "element %s has dimension %d, space dimension is %d", type->header.name,
             type->dim, sdim);
  double dN[TL_ELEMENT_MAX_NODES * 3];
  double p[3] = {xi[0], sdim > 1 ? xi[1] : 0.0, sdim > 2 ? xi[2] : 0.0};
  type->eval(1, p, NULL, dN);
  *detJ = jacobian_from_dN(type, sdim, x, dN, J);
  return TL_OK;
}

/* Solves the 3x3 system J d = r (Cramer); returns 0 when singular. */
static int solve3(double J[3][3], const double *r, double *d)
{
  double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
               J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
               J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
  if (!(fabs(det) > 0.0) || !isfinite(det)) return 0;
  for (int c = 0; c < 3; ++c) {
    double M[3][3];
    memcpy(M, J, sizeof M);
    for (int i = 0; i < 3; ++i) M[i][c] = r[i];
    d[c] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
            M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
            M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) / det;
  }
  return 1;
}

/* Newton from xi (in/out); returns 1 on convergence. */
static int newton_inverse(const TlElementType *type, int sdim, const double *x, const double *point,
                          double size, double *xi)
{
  double N[TL_ELEMENT_MAX_NODES], dN[TL_ELEMENT_MAX_NODES * 3], J[3][3];
  double tol = 1e-13 * size;
  for (int it = 0; it < 60; ++it) {
    type->eval(1, xi, N, dN);
    double r[3] = {0, 0, 0};
    for (int a = 0; a < type->n_nodes; ++a)
      for (int i = 0; i < sdim; ++i) r[i] += N[a] * x[3 * a + i];
    double rn = 0.0;
    for (int i = 0; i < sdim; ++i) {
      r[i] = point[i] - r[i];
      rn += r[i] * r[i];
    }
    rn = sqrt(rn);
    if (rn <= tol) return 1;
    jacobian_from_dN(type, sdim, x, dN, J);
    double d[3];
    if (!solve3(J, r, d)) return 0;
    /* Limit the step: a Newton step longer than the reference element means
     * a poor start; shorten it so the iterate stays near the element. */
    double dn = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double scale = dn > 1.0 ? 1.0 / dn : 1.0;
    for (int d_ = 0; d_ < type->dim; ++d_) xi[d_] += scale * d[d_];
    if (dn < 1e-15 && scale == 1.0) return 1;
  }
  return 0;
}

TlStatus tl_element_inverse_map(const TlElementType *type, int sdim, const double *x,
                                const double *point, double *xi, int *inside)
{
  if (type->dim != sdim || sdim < 2)
    TL_ERROR(TL_ERR_ARG, "inverse map of element %s (dimension %d) in %d-D space is not defined",
             type->header.name, type->dim, sdim);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int a = 0; a < type->n_corners; ++a)
    for (int i = 0; i < sdim; ++i) {
      lo[i] = fmin(lo[i], x[3 * a + i]);
      hi[i] = fmax(hi[i], x[3 * a + i]);
    }
  double size = 0.0;
  for (int i = 0; i < sdim; ++i) size += (hi[i] - lo[i]) * (hi[i] - lo[i]);
  size = sqrt(size);
  if (!(size > 0.0)) TL_ERROR(TL_ERR_NUMERIC, "element %s has zero size", type->header.name);
  /* Starts: the centroid of the reference element, then each vertex. */
  for (int start = -1; start < type->n_corners; ++start) {
    double p[3] = {0, 0, 0};
    if (start < 0) {
      if (type->shape == TL_SHAPE_TRI || type->shape == TL_SHAPE_TET)
        for (int d = 0; d < type->dim; ++d) p[d] = 1.0 / (type->dim + 1);
    } else {
      for (int d = 0; d < type->dim; ++d) p[d] = 0.9 * type->ref_coords[start * type->dim + d];
    }
    if (newton_inverse(type, sdim, x, point, size, p)) {
      for (int d = 0; d < type->dim; ++d) xi[d] = p[d];
      for (int d = type->dim; d < 3; ++d) xi[d] = 0.0;
      if (inside) *inside = tl_element_contains(type, p, 1e-10);
      return TL_OK;
    }
  }
  TL_ERROR(TL_ERR_CONVERGENCE,
           "inverse map of point (%g, %g, %g) in element %s did not converge from any start "
           "(degenerate element?)",
           point[0], point[1], sdim > 2 ? point[2] : 0.0, type->header.name);
}

void tl_element_face_normal(const TlElementType *face_type, int sdim, const double *x,
                            const double *s, double n_dA[3])
{
  double dN[TL_ELEMENT_MAX_FACE_NODES * 2];
  double p[3] = {s[0], face_type->dim > 1 ? s[1] : 0.0, 0.0};
  face_type->eval(1, p, NULL, dN);
  int dim = face_type->dim;
  double t[2][3] = {{0, 0, 0}, {0, 0, 0}};
  for (int a = 0; a < face_type->n_nodes; ++a)
    for (int j = 0; j < dim; ++j)
      for (int i = 0; i < 3; ++i) t[j][i] += x[3 * a + i] * dN[a * dim + j];
  if (sdim == 3 && dim == 2) {
    n_dA[0] = t[0][1] * t[1][2] - t[0][2] * t[1][1];
    n_dA[1] = t[0][2] * t[1][0] - t[0][0] * t[1][2];
    n_dA[2] = t[0][0] * t[1][1] - t[0][1] * t[1][0];
  } else {
    n_dA[0] = t[0][1];
    n_dA[1] = -t[0][0];
    n_dA[2] = 0.0;
  }
}

void tl_element_face_to_element(const TlElementType *type, int f, const double *s, double *xi)
{
  const TlElementType *ft = type->face_type;
  double N[TL_ELEMENT_MAX_FACE_NODES];
  double p[3] = {s[0], ft->dim > 1 ? s[1] : 0.0, 0.0};
  ft->eval(1, p, N, NULL);
  xi[0] = xi[1] = xi[2] = 0.0;
  for (int k = 0; k < ft->n_nodes; ++k) {
    int a = type->face_nodes[f * type->face_n_nodes + k];
    for (int d = 0; d < type->dim; ++d) xi[d] += N[k] * type->ref_coords[a * type->dim + d];
  }
}
