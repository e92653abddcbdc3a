/* The Gaussian CG kernel's shape (seeds Eq. 9: standard deviation c/3, cut
 * at c): its second moment <r^2> = ∫ W r^2 dV over the ball against the
 * same moment of exp(-r^2 / (2 (c/3)^2)) integrated here (on
 * [0, c] by the midpoint rule), in 3, 2 and 1 dimensions.  The normalisation alone (∫ W dV = 1)
 * does not see the width of the profile. */
#include <math.h>
#include <stdio.h>
#include "talus.h"
#include "tl_cg_kernel.h"
#include "tl_test.h"

/* ∫_0^c f(r) r^(dim-1) r^p dr by the midpoint rule with n intervals (no
 * point on the cut r = c, where the kernel is 0 and the profile is not) */
static double radial(double (*f)(void *, double), void *ctx, double c, int dim, int p, int n)
{
  double h = c / n, s = 0.0;
  for (int k = 0; k < n; ++k) {
    double r = (k + 0.5) * h;
    s += f(ctx, r) * pow(r, dim - 1 + p);
  }
  return s * h;
}
static double library(void *k, double r) { return tl_cg_kernel_value(k, r); }
static double gaussian(void *c, double r)
{
  double s = *(double *)c / 3.0;
  return exp(-r * r / (2.0 * s * s));
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  const double c = 0.7;
  for (int dim = 1; dim <= 3; ++dim) {
    TlCGKernel *k = NULL;
    TL_TEST_STATUS(tl_cg_kernel_create("gaussian", c, dim, &k), TL_OK);
    if (!k) continue;
    const int n = 20000;
    /* the surface of the unit sphere cancels in the ratio */
    double m_lib = radial(library, k, c, dim, 2, n) / radial(library, k, c, dim, 0, n);
    double c_ = c, m_ref = radial(gaussian, &c_, c, dim, 2, n) / radial(gaussian, &c_, c, dim, 0, n);
    printf("gaussian, %d D: <r^2> = %.12g m^2 (sigma = c/3 cut at c: %.12g)\n", dim, m_lib, m_ref);
    TL_TEST_REL(m_lib, m_ref, 1e-9);
    tl_cg_kernel_destroy(&k);
  }
  return tl_test_report();
}
