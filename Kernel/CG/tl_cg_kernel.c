#include "tl_cg_kernel.h"

#include <math.h>
#include <stddef.h>
#include "tl_math.h"
#include "tl_memory.h"
#include "tl_registry.h"

/* ---------------------------------------------------------------- profiles */

static void dirac_profile(size_t n, const double *q, double *f, double *dfdq)
{
  (void)q;
  for (size_t k = 0; k < n; ++k) {
    f[k] = 0.0;
    if (dfdq) dfdq[k] = 0.0;
  }
}
static double dirac_moment(int dim)
{
  (void)dim;
  return 0.0;
}

static void heaviside_profile(size_t n, const double *q, double *f, double *dfdq)
{
  (void)q;
  for (size_t k = 0; k < n; ++k) {
    f[k] = 1.0;
    if (dfdq) dfdq[k] = 0.0;
  }
}
static double heaviside_moment(int dim) { return 1.0 / dim; }

/* Eq. 9: standard deviation c/3, so f = exp(-q^2 / (2/9)) = exp(-4.5 q^2). */
static const double tl_gauss_a = 4.5;
static void gaussian_profile(size_t n, const double *q, double *f, double *dfdq)
{
  for (size_t k = 0; k < n; ++k) {
    double s = q[k], e = exp(-tl_gauss_a * s * s); /* q and f may alias */
    f[k] = e;
    if (dfdq) dfdq[k] = -2.0 * tl_gauss_a * s * e;
  }
}
static double gaussian_moment(int dim)
{
  const double a = tl_gauss_a, sa = sqrt(a);
  switch (dim) {
  case 1: return 0.5 * sqrt(TL_PI / a) * erf(sa);
  case 2: return (1.0 - exp(-a)) / (2.0 * a);
  default: return sqrt(TL_PI) * erf(sa) / (4.0 * a * sa) - exp(-a) / (2.0 * a);
  }
}

/* Eq. 10: f = -3q^4 + 8q^3 - 6q^2 + 1 = (1 - q)^3 (1 + 3q). */
static void lucy_profile(size_t n, const double *q, double *f, double *dfdq)
{
  for (size_t k = 0; k < n; ++k) {
    double s = q[k], m = 1.0 - s;
    f[k] = m * m * m * (1.0 + 3.0 * s);
    if (dfdq) dfdq[k] = -12.0 * s * m * m;
  }
}
static double lucy_moment(int dim)
{
  /* ∫_0^1 (1 - 6q^2 + 8q^3 - 3q^4) q^(dim-1) dq */
  return 1.0 / dim - 6.0 / (dim + 2) + 8.0 / (dim + 3) - 3.0 / (dim + 4);
}

/* ------------------------------------------- line integrals in closed form
 *
 * Along a line, q(s)^2 = alpha s^2 + beta s + gamma = alpha t^2 + delta with
 * t = s + beta / (2 alpha) and delta = gamma - beta^2 / (4 alpha) >= 0 (the
 * squared closest distance). */

static void heaviside_line(size_t n, const double *alpha, const double *beta, const double *gamma,
                           const double *s0, const double *s1, double *out)
{
  (void)alpha, (void)beta, (void)gamma;
  for (size_t k = 0; k < n; ++k) out[k] = s1[k] - s0[k];
}

static void gaussian_line(size_t n, const double *alpha, const double *beta, const double *gamma,
                          const double *s0, const double *s1, double *out)
{
  const double A = tl_gauss_a;
  for (size_t k = 0; k < n; ++k) {
    double al = alpha[k], sh = beta[k] / (2.0 * al), delta = fmax(0.0, gamma[k] - beta[k] * sh * 0.5);
    double r = sqrt(A * al), x0 = r * (s0[k] + sh), x1 = r * (s1[k] + sh), diff;
    /* erfc differences on one side of the closest point keep their digits */
    if (x0 > 0.0) diff = erfc(x0) - erfc(x1);
    else if (x1 < 0.0) diff = erfc(-x1) - erfc(-x0);
    else diff = erf(x1) - erf(x0);
    out[k] = exp(-A * delta) * 0.5 * sqrt(TL_PI) / r * diff;
  }
}

/* ∫ (alpha t^2 + delta)^(3/2) dt = alpha^(3/2) [ t/8 (2t^2 + 5a^2) sqrt(t^2 + a^2)
 *                                   + 3a^4/8 asinh(t/a) ],  a^2 = delta / alpha,
 * between t0 and t1, with the asinh difference as one logarithm taken on
 * the side of the closest point that keeps its digits. */
static inline double u32_integral(double al, double a2, double t0, double t1)
{
  double r0 = sqrt(t0 * t0 + a2), r1 = sqrt(t1 * t1 + a2);
  double v = 0.125 * (t1 * (2.0 * t1 * t1 + 5.0 * a2) * r1 - t0 * (2.0 * t0 * t0 + 5.0 * a2) * r0);
  if (a2 > 0.0) {
    double D;
    if (t0 >= 0.0) D = log((t1 + r1) / (t0 + r0));
    else if (t1 <= 0.0) D = log((r0 - t0) / (r1 - t1));
    else D = log((t1 + r1) * (r0 - t0) / a2);
    v += 0.375 * a2 * a2 * D;
  }
  return al * sqrt(al) * v;
}

static void lucy_line(size_t n, const double *alpha, const double *beta, const double *gamma, const double *s0,
                      const double *s1, double *out)
{
  for (size_t k = 0; k < n; ++k) {
    double al = alpha[k], be = beta[k], ga = gamma[k];
    double sh = be / (2.0 * al), delta = fmax(0.0, ga - be * sh * 0.5), a2 = delta / al;
    /* polynomial parts in t, where u = alpha t^2 + delta has no linear term */
    double t0 = s0[k] + sh, t1 = s1[k] + sh, q0 = t0 * t0, q1 = t1 * t1;
    double p1 = t1 - t0, p3 = (q1 * t1 - q0 * t0) / 3.0, p5 = (q1 * q1 * t1 - q0 * q0 * t0) / 5.0;
    double int_u = al * p3 + delta * p1;
    double int_u2 = al * al * p5 + 2.0 * al * delta * p3 + delta * delta * p1;
    out[k] = p1 - 6.0 * int_u + 8.0 * u32_integral(al, a2, t0, t1) - 3.0 * int_u2;
  }
}

const TlCGKernelOps tl_cg_kernel_dirac_ops = {
    {TL_CG_KERNEL_KIND, "dirac", "c -> 0 limit: point values in closed form (Eqs. 16, 19)"},
    1, dirac_profile, dirac_moment, NULL};
const TlCGKernelOps tl_cg_kernel_heaviside_ops = {
    {TL_CG_KERNEL_KIND, "heaviside", "uniform over the ball of radius c"}, 0, heaviside_profile,
    heaviside_moment, heaviside_line};
const TlCGKernelOps tl_cg_kernel_gaussian_ops = {
    {TL_CG_KERNEL_KIND, "gaussian", "Gaussian of standard deviation c/3 cut off at c (Eq. 9)"}, 0,
    gaussian_profile, gaussian_moment, gaussian_line};
const TlCGKernelOps tl_cg_kernel_lucy_ops = {
    {TL_CG_KERNEL_KIND, "lucy", "Lucy polynomial of support c (Eq. 10)"}, 0, lucy_profile,
    lucy_moment, lucy_line};

/* The width c, the argument of tl_cg_kernel_create (no default: the
 * caller chooses it; NAN marks that in the table). */
static const TlParam dirac_params[] = {
    {"width", 0, 0, 0, "m", "the CG width c: 0 by definition (the point-source limit)", offsetof(TlCGKernel, c)}};
static const TlParam heaviside_params[] = {
    {"width", NAN, 0, 1e300, "m", "the CG width c (> 0, no default): radius of the ball", offsetof(TlCGKernel, c)}};
static const TlParam gaussian_params[] = {
    {"width", NAN, 0, 1e300, "m", "the CG width c (> 0, no default): cut-off radius; standard deviation c/3", offsetof(TlCGKernel, c)}};
static const TlParam lucy_params[] = {
    {"width", NAN, 0, 1e300, "m", "the CG width c (> 0, no default): radius of the support", offsetof(TlCGKernel, c)}};

static TlStatus register_kernel(const TlCGKernelOps *ops, const TlParam *params)
{
  const TlTypeEntry e = {TL_CG_KERNEL_KIND, ops->header.name, ops->header.description, NULL, ops, params, 1};
  TL_CHECK(tl_registry_register(&e));
  return TL_OK;
}

TlStatus tl_cg_register_all(void)
{
  TL_CHECK(register_kernel(&tl_cg_kernel_dirac_ops, dirac_params));
  TL_CHECK(register_kernel(&tl_cg_kernel_heaviside_ops, heaviside_params));
  TL_CHECK(register_kernel(&tl_cg_kernel_gaussian_ops, gaussian_params));
  TL_CHECK(register_kernel(&tl_cg_kernel_lucy_ops, lucy_params));
  return TL_OK;
}

/* ------------------------------------------------------------- life cycle */

static TlStatus kernel_configure(TlCGKernel *k, double c)
{
  if (k->ops->is_dirac) {
    if (c != 0.0)
      TL_ERROR(TL_ERR_ARG, "the dirac kernel has width 0 by definition, got c = %g", c);
    k->c = 0.0;
    k->norm = 0.0;
    return TL_OK;
  }
  if (!(c > 0.0) || !isfinite(c))
    TL_ERROR(TL_ERR_ARG, "CG width c = %g of kernel '%s' must be positive and finite (use the dirac kernel for c = 0)",
             c, k->ops->header.name);
  const double sphere[4] = {0.0, 2.0, 2.0 * TL_PI, 4.0 * TL_PI}; /* |S^(dim-1)| */
  double moment = k->ops->radial_moment(k->dim);
  double volume = sphere[k->dim] * pow(c, k->dim) * moment;
  if (!(volume > 0.0) || !isfinite(volume))
    TL_ERROR(TL_ERR_NUMERIC, "kernel '%s' with c = %g in %d dimensions has normalisation volume %g",
             k->ops->header.name, c, k->dim, volume);
  k->c = c;
  k->norm = 1.0 / volume;
  return TL_OK;
}

TlStatus tl_cg_kernel_create_from_ops(const TlCGKernelOps *ops, double c, int dim, TlCGKernel **kernel)
{
  *kernel = NULL;
  if (!ops || !ops->profile || !ops->radial_moment)
    TL_ERROR(TL_ERR_ARG, "kernel ops table is incomplete");
  if (dim < 1 || dim > 3)
    TL_ERROR(TL_ERR_ARG, "kernel dimension %d is outside [1, 3]", dim);
  TlCGKernel *k;
  TL_CHECK(TL_NEW(k));
  k->ops = ops;
  k->dim = dim;
  TlStatus s = kernel_configure(k, c);
  if (s != TL_OK) {
    tl_free(&k);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  *kernel = k;
  return TL_OK;
}

TlStatus tl_cg_kernel_create(const char *name, double c, int dim, TlCGKernel **kernel)
{
  const TlOpsHeader *h;
  *kernel = NULL;
  TL_CHECK(tl_registry_find(TL_CG_KERNEL_KIND, name, &h));
  TL_CHECK(tl_cg_kernel_create_from_ops((const TlCGKernelOps *)h, c, dim, kernel));
  return TL_OK;
}

void tl_cg_kernel_destroy(TlCGKernel **kernel)
{
  if (kernel) tl_free(kernel);
}

TlStatus tl_cg_kernel_set_width(TlCGKernel *kernel, double c)
{
  TlCGKernel trial = *kernel;
  TL_CHECK(kernel_configure(&trial, c));
  *kernel = trial;
  return TL_OK;
}

/* ------------------------------------------------------------- evaluation */

TlStatus tl_cg_kernel_eval(const TlCGKernel *k, size_t n, const double *r2, double *w,
                           double *grad_over_r)
{
  if (k->ops->is_dirac)
    TL_ERROR(TL_ERR_UNSUPPORTED,
             "the dirac kernel has no point values; use its closed form (cell averages, shape functions at the point)");
  const double inv_c = 1.0 / k->c, inv_c2 = inv_c * inv_c;
  /* q in place in w, then the profile overwrites it: one pass, no buffer */
  for (size_t i = 0; i < n; ++i) w[i] = r2[i] < k->c * k->c ? sqrt(r2[i] * inv_c2) : 1.0;
  k->ops->profile(n, w, w, grad_over_r);
  for (size_t i = 0; i < n; ++i) {
    int inside = r2[i] < k->c * k->c;
    if (grad_over_r) {
      /* dW/dr / r = C f'(q) / (c r) = C f'(q) / (c^2 q); f'(0) = 0 for every
       * profile here, and f'(q)/q stays finite as q -> 0 */
      double q = sqrt(r2[i] * inv_c2);
      grad_over_r[i] = inside && q > 0.0 ? k->norm * grad_over_r[i] * inv_c2 / q : 0.0;
    }
    w[i] = inside ? k->norm * w[i] : 0.0;
  }
  return TL_OK;
}

double tl_cg_kernel_value(const TlCGKernel *k, double r)
{
  if (k->ops->is_dirac) return r == 0.0 ? INFINITY : 0.0;
  double r2 = r * r, w = 0.0;
  (void)tl_cg_kernel_eval(k, 1, &r2, &w, NULL);
  return w;
}

/* Gauss-Legendre nodes and weights on [0, 1]. */
static void gauss_legendre01(int n, double *x, double *w)
{
  for (int i = 0; i < n; ++i) {
    double z = cos(TL_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = 0.0;
      for (int k = 1; k <= n; ++k) {
        double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p2) / k;
      }
      dp = n * (z * p0 - p1) / (z * z - 1.0);
      double dz = p0 / dp;
      z -= dz;
      if (fabs(dz) < 1e-16) break;
    }
    x[i] = 0.5 * (1.0 - z);
    w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
  }
}

TlStatus tl_cg_kernel_line_integral(const TlCGKernel *k, size_t n, const double *A, const double *B, const double *C,
                                    const double *s0, const double *s1, int gauss_points, double *out)
{
  if (k->ops->is_dirac)
    TL_ERROR(TL_ERR_UNSUPPORTED, "the dirac kernel has no line integral at a point; use its cell averages");
  enum { CHUNK = 64 };
  const double ic2 = 1.0 / (k->c * k->c);
  if (k->ops->line_integral) {
    /* to units of c: q^2 = (A s^2 + B s + C) / c^2 */
    double al[CHUNK], be[CHUNK], ga[CHUNK];
    for (size_t k0 = 0; k0 < n; k0 += CHUNK) {
      size_t m = n - k0 < CHUNK ? n - k0 : CHUNK;
      for (size_t j = 0; j < m; ++j) {
        al[j] = A[k0 + j] * ic2;
        be[j] = B[k0 + j] * ic2;
        ga[j] = C[k0 + j] * ic2;
      }
      k->ops->line_integral(m, al, be, ga, s0 + k0, s1 + k0, out + k0);
      for (size_t j = 0; j < m; ++j) out[k0 + j] *= k->norm;
    }
    return TL_OK;
  }
  if (gauss_points < 1 || gauss_points > 10)
    TL_ERROR(TL_ERR_ARG, "line-integral Gauss points %d outside [1, 10]", gauss_points);
  double gx[10], gw[10], q[10], f[10];
  gauss_legendre01(gauss_points, gx, gw);
  for (size_t j = 0; j < n; ++j) {
    double len = s1[j] - s0[j];
    for (int g = 0; g < gauss_points; ++g) {
      double s = s0[j] + len * gx[g];
      q[g] = sqrt(fmax(0.0, (A[j] * s * s + B[j] * s + C[j]) * ic2));
      if (q[g] > 1.0) q[g] = 1.0;
    }
    k->ops->profile((size_t)gauss_points, q, f, NULL);
    double sum = 0.0;
    for (int g = 0; g < gauss_points; ++g) sum += gw[g] * (q[g] < 1.0 ? f[g] : 0.0);
    out[j] = k->norm * len * sum;
  }
  return TL_OK;
}
