/* CG kernels: normalisation in 1, 2 and 3 dimensions by quadrature,
 * non-negativity, compact support of radius c, gradients against finite
 * differences, and the refusals (Dirac point values, bad widths). */
#include <math.h>
#include <stdint.h>
#include "talus.h"
#include "tl_cg_kernel.h"
#include "tl_test.h"

static const double gl5x_[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                 0.9061798459386640};
static const double gl5w_[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                 0.4786286704993665, 0.2369268850561891};

/* ∫_{R^dim} W by composite Gauss-Legendre in the radius (panels of
 * 5 points), times the area of the unit sphere; independent of the closed
 * form moments the kernel uses for its prefactor. */
static double integrate_radial(const TlCGKernel *k, int panels)
{
  static const double x5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
  static const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};
  const double sphere[4] = {0.0, 2.0, 2.0 * TL_PI, 4.0 * TL_PI};
  double h = k->c / panels, sum = 0.0;
  for (int p = 0; p < panels; ++p)
    for (int g = 0; g < 5; ++g) {
      double r = (p + 0.5 * (1.0 + x5[g])) * h;
      sum += 0.5 * h * w5[g] * tl_cg_kernel_value(k, r) * pow(r, k->dim - 1);
    }
  return sphere[k->dim] * sum;
}

/* ∫ over a cube by a tensor Gauss rule: a check of the 3D prefactor in
 * Cartesian coordinates (the Lucy kernel is smooth at r = c). */
static double integrate_cartesian_3d(const TlCGKernel *k, int panels)
{
  static const double x5[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
  static const double w5[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                               0.4786286704993665, 0.2369268850561891};
  double h = 2.0 * k->c / panels, sum = 0.0;
  for (int a = 0; a < panels * 5; ++a)
    for (int b = 0; b < panels * 5; ++b)
      for (int c = 0; c < panels * 5; ++c) {
        double x = -k->c + (a / 5 + 0.5 * (1 + x5[a % 5])) * h;
        double y = -k->c + (b / 5 + 0.5 * (1 + x5[b % 5])) * h;
        double z = -k->c + (c / 5 + 0.5 * (1 + x5[c % 5])) * h;
        double wq = w5[a % 5] * w5[b % 5] * w5[c % 5] * 0.125 * h * h * h;
        sum += wq * tl_cg_kernel_value(k, sqrt(x * x + y * y + z * z));
      }
  return sum;
}

/* The closed-form line integrals against composite Gauss-Legendre on the
 * kernel's values, for lines through, near and far from the point, and the
 * Gauss-Legendre fallback (via an ops table without line_integral). */
static void test_line_integrals(void)
{
  const char *names[] = {"heaviside", "gaussian", "lucy"};
  uint64_t state = 12345;
  for (int n = 0; n < 3; ++n) {
    TlCGKernel *k;
    TL_TEST_STATUS(tl_cg_kernel_create(names[n], 1.3, 3, &k), TL_OK);
    TlCGKernelOps no_line = *k->ops;
    no_line.line_integral = NULL;
    TlCGKernel *kg;
    TL_TEST_STATUS(tl_cg_kernel_create_from_ops(&no_line, 1.3, 3, &kg), TL_OK);
    double worst = 0.0, worst_gl = 0.0;
    int tested = 0;
    for (int trial = 0; trial < 200; ++trial) {
      /* d = x - a, b the branch; q(s) = |d - s b| */
      double v[6];
      for (int i = 0; i < 6; ++i) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        v[i] = 2.0 * ((double)(state >> 11) / 9007199254740992.0) - 1.0;
      }
      TlVec3 d = tl_v3(1.2 * v[0], 1.2 * v[1], 1.2 * v[2]), b = tl_v3(1.5 * v[3], 1.5 * v[4], 1.5 * v[5]);
      if (trial % 10 == 0) d = tl_v3_scale(b, 0.3); /* the line passes through the point */
      double A = tl_v3_norm2(b), B = -2.0 * tl_v3_dot(d, b), C = tl_v3_norm2(d), c2 = k->c * k->c;
      double disc = B * B - 4.0 * A * (C - c2);
      if (!(A > 0.0) || disc <= 0.0) continue;
      double s0 = fmax(0.0, (-B - sqrt(disc)) / (2 * A)), s1 = fmin(1.0, (-B + sqrt(disc)) / (2 * A));
      if (!(s1 > s0)) continue;
      double closed, fallback;
      TL_TEST_STATUS(tl_cg_kernel_line_integral(k, 1, &A, &B, &C, &s0, &s1, 6, &closed), TL_OK);
      TL_TEST_STATUS(tl_cg_kernel_line_integral(kg, 1, &A, &B, &C, &s0, &s1, 10, &fallback), TL_OK);
      /* reference: 2000 panels of 5-point Gauss on the kernel's values */
      double ref = 0.0, h = (s1 - s0) / 2000.0;
      for (int pnl = 0; pnl < 2000; ++pnl)
        for (int g = 0; g < 5; ++g) {
          double s = s0 + (pnl + 0.5 * (1.0 + gl5x_[g])) * h;
          ref += 0.5 * h * gl5w_[g] * tl_cg_kernel_value(k, tl_v3_norm(tl_v3_axpy(d, -s, b)));
        }
      double scale = k->norm * (s1 - s0);
      worst = fmax(worst, fabs(closed - ref) / scale);
      worst_gl = fmax(worst_gl, fabs(fallback - ref) / scale);
      ++tested;
    }
    TL_TEST_ASSERT(tested > 50, "%s: %d line configurations tested", names[n], tested);
    TL_TEST_ASSERT(worst < 1e-11, "%s: closed-form line integral off by %g (relative to W(0) length)", names[n], worst);
    TL_TEST_ASSERT(worst_gl < 1e-3, "%s: Gauss-Legendre fallback off by %g", names[n], worst_gl);
    printf("line integral %s: closed form %.2e, 10-point Gauss %.2e (max relative error)\n", names[n], worst, worst_gl);
    tl_cg_kernel_destroy(&k);
    tl_cg_kernel_destroy(&kg);
  }
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_line_integrals();
  const char *names[] = {"heaviside", "gaussian", "lucy"};
  const double widths[] = {0.37, 1.0, 4.5};
  for (int n = 0; n < 3; ++n)
    for (int dim = 1; dim <= 3; ++dim)
      for (int wi = 0; wi < 3; ++wi) {
        TlCGKernel *k = NULL;
        TL_TEST_STATUS(tl_cg_kernel_create(names[n], widths[wi], dim, &k), TL_OK);
        if (!k) continue;
        double integral = integrate_radial(k, 400);
        TL_TEST_ASSERT(fabs(integral - 1.0) < 1e-10, "%s dim %d c %g integrates to %.15g", names[n], dim,
                       widths[wi], integral);
        /* non-negative everywhere, positive inside, zero from c on */
        int negative = 0, zero_inside = 0, outside = 0;
        for (int s = 0; s <= 2000; ++s) {
          double r = 1.5 * widths[wi] * s / 2000.0;
          double w = tl_cg_kernel_value(k, r);
          negative += w < 0.0;
          if (r < widths[wi] * (1.0 - 1e-9)) zero_inside += !(w > 0.0);
          else outside += w != 0.0;
        }
        TL_TEST_ASSERT(negative == 0, "%s: %d negative values", names[n], negative);
        TL_TEST_ASSERT(zero_inside == 0, "%s: %d non-positive values inside the support", names[n], zero_inside);
        TL_TEST_ASSERT(outside == 0, "%s: %d non-zero values at or beyond c", names[n], outside);
        TL_TEST_ASSERT(tl_cg_kernel_value(k, widths[wi]) == 0.0, "%s: W(c) = %g", names[n],
                       tl_cg_kernel_value(k, widths[wi]));
        /* gradient: (dW/dr)/r against central differences */
        if (n > 0) {
          double worst = 0.0;
          for (int s = 1; s < 40; ++s) {
            double r = widths[wi] * s / 40.0, e = 1e-6 * widths[wi];
            double r2 = r * r, w, g;
            TL_TEST_STATUS(tl_cg_kernel_eval(k, 1, &r2, &w, &g), TL_OK);
            double fd = (tl_cg_kernel_value(k, r + e) - tl_cg_kernel_value(k, r - e)) / (2 * e);
            worst = fmax(worst, fabs(g * r - fd) / (k->norm / widths[wi]));
          }
          TL_TEST_ASSERT(worst < 1e-6, "%s dim %d: gradient off by %g (relative)", names[n], dim, worst);
        }
        tl_cg_kernel_destroy(&k);
        TL_TEST_ASSERT(k == NULL, "destroy nulls the pointer");
      }
  /* closed-form prefactors of the Lucy kernel (1D 5/(4c), 2D 5/(pi c^2), 3D 105/(16 pi c^3)) */
  {
    TlCGKernel *k;
    TL_TEST_STATUS(tl_cg_kernel_create("lucy", 2.0, 1, &k), TL_OK);
    TL_TEST_CLOSE(k->norm, 5.0 / 8.0, 1e-14);
    tl_cg_kernel_destroy(&k);
    TL_TEST_STATUS(tl_cg_kernel_create("lucy", 2.0, 2, &k), TL_OK);
    TL_TEST_CLOSE(k->norm, 5.0 / (TL_PI * 4.0), 1e-14);
    tl_cg_kernel_destroy(&k);
    TL_TEST_STATUS(tl_cg_kernel_create("lucy", 2.0, 3, &k), TL_OK);
    TL_TEST_CLOSE(k->norm, 105.0 / (16.0 * TL_PI * 8.0), 1e-14);
    double cart = integrate_cartesian_3d(k, 12);
    TL_TEST_ASSERT(fabs(cart - 1.0) < 1e-5, "lucy 3D Cartesian integral %.12g", cart);
    /* width change keeps the normalisation */
    TL_TEST_STATUS(tl_cg_kernel_set_width(k, 0.5), TL_OK);
    TL_TEST_ASSERT(fabs(integrate_radial(k, 400) - 1.0) < 1e-10, "after set_width: %.15g", integrate_radial(k, 400));
    TL_TEST_STATUS(tl_cg_kernel_set_width(k, -1.0), TL_ERR_ARG);
    TL_TEST_CLOSE(k->c, 0.5, 0.0);
    tl_cg_kernel_destroy(&k);
  }
  /* Dirac: width 0 only, no point values */
  {
    TlCGKernel *k = NULL;
    TL_TEST_STATUS(tl_cg_kernel_create("dirac", 0.0, 3, &k), TL_OK);
    TL_TEST_ASSERT(k && tl_cg_kernel_is_dirac(k), "dirac is dirac");
    double r2 = 0.0, w;
    TL_TEST_STATUS(tl_cg_kernel_eval(k, 1, &r2, &w, NULL), TL_ERR_UNSUPPORTED);
    tl_cg_kernel_destroy(&k);
    TL_TEST_STATUS(tl_cg_kernel_create("dirac", 0.1, 3, &k), TL_ERR_ARG);
    TL_TEST_ASSERT(k == NULL, "failed create leaves NULL");
  }
  /* refusals */
  {
    TlCGKernel *k = NULL;
    TL_TEST_STATUS(tl_cg_kernel_create("lucy", 0.0, 3, &k), TL_ERR_ARG);
    TL_TEST_STATUS(tl_cg_kernel_create("lucy", NAN, 3, &k), TL_ERR_ARG);
    TL_TEST_STATUS(tl_cg_kernel_create("lucy", INFINITY, 3, &k), TL_ERR_ARG);
    TL_TEST_STATUS(tl_cg_kernel_create("lucy", 1.0, 4, &k), TL_ERR_ARG);
    TL_TEST_STATUS(tl_cg_kernel_create("wendland", 1.0, 3, &k), TL_ERR_NOT_FOUND);
    TL_TEST_ASSERT(k == NULL, "no kernel after refusals");
  }
  return tl_test_report();
}
