/* Coarse-graining kernels W(x) (seeds/001 §4, Eqs. 8-10).
 *
 * A kernel is radial with compact support of radius c (the CG width):
 *   W(x) = C_dim(c) f(|x|/c)  for |x| < c,  0 otherwise,
 * with a profile f on q in [0, 1) and the prefactor C_dim(c) that makes
 * ∫ W = 1 over R^dim, computed in closed form from the profile's radial
 * moment ∫_0^1 f(q) q^(dim-1) dq.  Registered types (kind "cg_kernel"):
 *
 *   dirac      the c -> 0 limit.  It has no point values: every user of a
 *              kernel branches on tl_cg_kernel_is_dirac() and takes the
 *              closed form (cell averages on a grid, shape functions at the
 *              contact point for Eqs. 16 and 19), never a narrow kernel.
 *   heaviside  f = 1 (uniform over the ball of radius c).
 *   gaussian   cut-off Gaussian, f = exp(-q^2 / (2 (1/3)^2)), Eq. 9.
 *   lucy       Lucy polynomial, f = 1 - 6q^2 + 8q^3 - 3q^4, Eq. 10.
 *
 * Evaluation is by batch (one indirect call for many distances), so hot
 * loops gather squared distances into a buffer and evaluate them at once. */
#ifndef TL_CG_KERNEL_H
#define TL_CG_KERNEL_H

#include <stddef.h>
#include "tl_error.h"
#include "tl_object.h"

#define TL_CG_KERNEL_KIND "cg_kernel"

typedef struct {
  TlOpsHeader header;
  int is_dirac;
  /* Profile f(q) and f'(q) for n values q in [0, 1) (dfdq may be NULL). */
  void (*profile)(size_t n, const double *q, double *f, double *dfdq);
  /* ∫_0^1 f(q) q^(dim-1) dq, dim = 1, 2, 3. */
  double (*radial_moment)(int dim);
  /* Optional (NULL: Gauss-Legendre on the profile): for k < n,
   * out[k] = ∫_{s0}^{s1} f(q(s)) ds along a straight line, where
   * q(s)^2 = alpha s^2 + beta s + gamma (alpha > 0) and q < 1 on (s0, s1). */
  void (*line_integral)(size_t n, const double *alpha, const double *beta, const double *gamma, const double *s0,
                        const double *s1, double *out);
} TlCGKernelOps;

typedef struct {
  const TlCGKernelOps *ops;
  double c;      /* width (support radius), 0 for the Dirac kernel */
  int dim;       /* 1, 2 or 3 */
  double norm;   /* C_dim(c): W(0) / f(0) */
} TlCGKernel;

/* Creates the kernel registered as `name` with width c in dim dimensions.
 * c must be > 0 and finite for every kernel but dirac (which takes c = 0). */
TlStatus tl_cg_kernel_create(const char *name, double c, int dim, TlCGKernel **kernel);
/* The same from an ops table (for types not registered). */
TlStatus tl_cg_kernel_create_from_ops(const TlCGKernelOps *ops, double c, int dim, TlCGKernel **kernel);
void tl_cg_kernel_destroy(TlCGKernel **kernel);
/* Changes the width of an existing kernel (same validity rules). */
TlStatus tl_cg_kernel_set_width(TlCGKernel *kernel, double c);

static inline int tl_cg_kernel_is_dirac(const TlCGKernel *k) { return k->ops->is_dirac; }

/* W at n squared distances r2[k]; zero outside the support.  grad_over_r
 * (may be NULL) receives (dW/dr)/r, so that ∇W(x) = grad_over_r * x.
 * The Dirac kernel refuses (TL_ERR_UNSUPPORTED): it has no point values. */
TlStatus tl_cg_kernel_eval(const TlCGKernel *k, size_t n, const double *r2, double *w,
                           double *grad_over_r);
/* Integrals of W along n line pieces: out[k] = ∫_{s0}^{s1} W(|d_k - s b_k|) ds
 * given as the squared distance |d - s b|^2 = A s^2 + B s + C (A > 0,
 * real units) and an interval inside the support (|d - s b| < c there).
 * Closed form where the kernel has one (heaviside, gaussian, lucy),
 * Gauss-Legendre with `gauss_points` (1..10) on the profile otherwise. */
TlStatus tl_cg_kernel_line_integral(const TlCGKernel *k, size_t n, const double *A, const double *B, const double *C,
                                    const double *s0, const double *s1, int gauss_points, double *out);
/* Convenience for one point (tests, set-up code; not for loops). */
double tl_cg_kernel_value(const TlCGKernel *k, double r);

/* Built-in ops tables. */
extern const TlCGKernelOps tl_cg_kernel_dirac_ops;
extern const TlCGKernelOps tl_cg_kernel_heaviside_ops;
extern const TlCGKernelOps tl_cg_kernel_gaussian_ops;
extern const TlCGKernelOps tl_cg_kernel_lucy_ops;

/* Registers the built-in kernels (called by tl_initialize). */
TlStatus tl_cg_register_all(void);

#endif
