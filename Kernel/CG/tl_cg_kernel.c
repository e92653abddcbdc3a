#include "tl_cg_kernel.h"

#include <math.h>
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

const TlCGKernelOps tl_cg_kernel_dirac_ops = {
    {TL_CG_KERNEL_KIND, "dirac", "c -> 0 limit: point values in closed form (Eqs. 16, 19)"},
    1, dirac_profile, dirac_moment};
const TlCGKernelOps tl_cg_kernel_heaviside_ops = {
    {TL_CG_KERNEL_KIND, "heaviside", "uniform over the ball of radius c"}, 0, heaviside_profile,
    heaviside_moment};
const TlCGKernelOps tl_cg_kernel_gaussian_ops = {
    {TL_CG_KERNEL_KIND, "gaussian", "Gaussian of standard deviation c/3 cut off at c (Eq. 9)"}, 0,
    gaussian_profile, gaussian_moment};
const TlCGKernelOps tl_cg_kernel_lucy_ops = {
    {TL_CG_KERNEL_KIND, "lucy", "Lucy polynomial of support c (Eq. 10)"}, 0, lucy_profile,
    lucy_moment};

TlStatus tl_cg_register_all(void)
{
  TL_CHECK(tl_registry_add(&tl_cg_kernel_dirac_ops.header));
  TL_CHECK(tl_registry_add(&tl_cg_kernel_heaviside_ops.header));
  TL_CHECK(tl_registry_add(&tl_cg_kernel_gaussian_ops.header));
  TL_CHECK(tl_registry_add(&tl_cg_kernel_lucy_ops.header));
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
