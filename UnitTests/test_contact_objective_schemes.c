/* The three time integrations of the objective tangential force (seeds/004
 * §2.3.3, §2.4.1; the coulomb part's `transport`): project (Eq. 11), rotate
 * (Eq. 24) and implicit (Eq. 12).
 *
 *  1. One step of each kernel against its closed form: a contact plane
 *     tilted by θ (no spin about the normal) shortens a sticking force by
 *     cos θ under projection and lengthens it by sqrt(1 + sin²θ -
 *     sin²θ (1 - cos θ)²) = 1 + θ²/2 + O(θ⁴) under the rotation of Eq. 24,
 *     both staying tangent; the error of the rotation is second order (it
 *     quarters when θ halves).  A spin ω about the normal turns the force by
 *     atan(c), c = ω dt, with the norm times sqrt(1 + c²) (explicit spin
 *     term) or 1 / sqrt(1 + c²) (implicit), the implicit result satisfying
 *     Eq. 12 to round-off.
 *  2. The Coulomb cut: every scheme puts a sliding force on the cone μ f_N;
 *     the implicit closed form equals a Newton solve of Eq. 12 with the
 *     consistency condition ‖f_T‖ = μ f_N.
 *  3. The part: transport 0 / 1 / 2 keep 3 / 6 / 3 history doubles; 0.5 and
 *     3 are refused.
 *  4. A sticking pair of spheres rigidly rotated in a DEM world: the ratio
 *     ‖f_T‖ / ‖f_T⁰‖ after N steps is cos(θ)^N (project), r(θ)^N (rotate)
 *     for a tilt, and (1 + c²)^(±N/2) for a spin about the normal, the force
 *     turning with the pair; about an oblique axis every scheme converges to
 *     the rigidly rotated force at first order in dt. */
#include <math.h>
#include <string.h>
#include "talus.h"
#include "tl_contact_kernels.h"
#include "tl_contact_part.h"
#include "tl_dem.h"
#include "tl_test.h"

typedef TlVec3 (*Kernel)(double *, TlVec3, TlVec3, TlVec3, double, double, double, double, double, double *);
static const Kernel kernels[3] = {tl_friction_force, tl_friction_force_rotate, tl_friction_force_implicit};
static const char *names[3] = {"project", "rotate", "implicit"};

/* One step of scheme s from f (tangent to ni) to the normal nf. */
static TlVec3 step(int s, TlVec3 f, TlVec3 ni, TlVec3 nf, TlVec3 vrel, TlVec3 spin, double kt, double mu, double fn,
                   double dt)
{
  double h[6] = {f.x, f.y, f.z, ni.x, ni.y, ni.z};
  return kernels[s](h, nf, vrel, spin, kt, 0.0, mu, fn, dt, NULL);
}

static double rotate_ratio(double th)
{
  double s = sin(th), c = cos(th);
  return sqrt(1.0 + s * s - s * s * (1.0 - c) * (1.0 - c));
}

static void one_step_closed_forms(void)
{
  const double F = 2.0, kt = 1e5, mu = 0.5, fn = 1e3, dt = 1e-4; /* deep inside the cone */
  const TlVec3 ni = {0, 0, 1}, f = {F, 0, 0}, zero = {0, 0, 0};
  double err_rot[2];
  for (int q = 0; q < 2; ++q) {
    const double th = q ? 0.01 : 0.02;
    const TlVec3 nf = {sin(th), 0.0, cos(th)};
    for (int s = 0; s < 3; ++s) {
      TlVec3 g = step(s, f, ni, nf, zero, zero, kt, mu, fn, dt);
      double ratio = tl_v3_norm(g) / F;
      double want = s == TL_FRICTION_ROTATE ? rotate_ratio(th) : cos(th);
      TL_TEST_ASSERT(fabs(ratio - want) <= 1e-14, "%s, tilt %g: |f_T| ratio %.17g, closed form %.17g", names[s], th,
                     ratio, want);
      TL_TEST_ASSERT(fabs(tl_v3_dot(g, nf)) <= 1e-14 * F, "%s: f_T . n^f = %g (tangent)", names[s],
                     tl_v3_dot(g, nf));
      /* the direction turns with the plane: along (cos θ, 0, -sin θ) */
      TlVec3 dir = tl_v3_scale(g, 1.0 / tl_v3_norm(g));
      TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(dir, tl_v3(cos(th), 0.0, -sin(th)))) <= 1e-13, "%s: direction (%g %g %g)",
                     names[s], dir.x, dir.y, dir.z);
      if (s == TL_FRICTION_ROTATE) err_rot[q] = ratio - 1.0;
    }
  }
  printf("tilt 0.02 / 0.01 rad: rotate |f_T| error %.4e / %.4e (project %.4e / %.4e)\n", err_rot[0], err_rot[1],
         cos(0.02) - 1.0, cos(0.01) - 1.0);
  TL_TEST_ASSERT(err_rot[0] > 0.0 && err_rot[0] <= 0.51 * 0.02 * 0.02, "rotate error %g not +θ²/2", err_rot[0]);
  TL_TEST_CLOSE(err_rot[0] / err_rot[1], 4.0, 0.01);
  /* spin about the normal: c = dt C_N */
  const double w = 150.0, c = dt * w;
  const TlVec3 spin = {0, 0, w};
  for (int s = 0; s < 3; ++s) {
    TlVec3 g = step(s, f, ni, ni, zero, spin, kt, mu, fn, dt);
    double ratio = tl_v3_norm(g) / F, angle = atan2(g.y, g.x);
    double want = s == TL_FRICTION_IMPLICIT ? 1.0 / sqrt(1.0 + c * c) : sqrt(1.0 + c * c);
    TL_TEST_ASSERT(fabs(ratio - want) <= 1e-14, "%s, spin: ratio %.17g, closed form %.17g", names[s], ratio, want);
    TL_TEST_ASSERT(fabs(angle - atan(c)) <= 1e-14, "%s, spin: angle %.17g, closed form %.17g", names[s], angle, atan(c));
    if (s == TL_FRICTION_IMPLICIT) {
      /* Eq. 12 with x = 0: f^f - c n ∧ f^f = P f^i */
      TlVec3 res = tl_v3_sub(tl_v3_axpy(g, -c, tl_v3_cross(ni, g)), f);
      TL_TEST_ASSERT(tl_v3_norm(res) <= 1e-14 * F, "implicit: Eq. 12 residual %g", tl_v3_norm(res));
    }
  }
}

/* Newton on Eq. 12 with the cone: unknowns a, b (f = a e1 + b e2 in the
 * plane) and x; residuals (1 + x) f - c n∧f - φ (two components) and
 * (a² + b² - cap²) / cap. */
static TlVec3 newton_eq12(TlVec3 n, TlVec3 phi, double c, double cap, int *iters, double *res_out)
{
  TlVec3 e1 = tl_v3_normalize(phi), e2 = tl_v3_cross(n, e1);
  double p1 = tl_v3_dot(phi, e1), p2 = tl_v3_dot(phi, e2);
  double a = cap, b = 0.0, x = p1 / cap - 1.0, res = 0.0;
  int k;
  for (k = 0; k < 50; ++k) {
    /* n ∧ (a e1 + b e2) = a e2 - b e1 */
    double r1 = (1 + x) * a + c * b - p1, r2 = (1 + x) * b - c * a - p2, r3 = (a * a + b * b - cap * cap) / cap;
    res = sqrt(r1 * r1 + r2 * r2 + r3 * r3);
    if (res <= 1e-15 * cap) break;
    double J[3][3] = {{1 + x, c, a}, {-c, 1 + x, b}, {2 * a / cap, 2 * b / cap, 0}}, r[3] = {-r1, -r2, -r3};
    /* Cramer */
    double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                 J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    double d[3];
    for (int col = 0; col < 3; ++col) {
      double M[3][3];
      memcpy(M, J, sizeof M);
      for (int row = 0; row < 3; ++row) M[row][col] = r[row];
      d[col] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) / det;
    }
    a += d[0];
    b += d[1];
    x += d[2];
  }
  *iters = k;
  *res_out = res;
  return tl_v3_add(tl_v3_scale(e1, a), tl_v3_scale(e2, b));
}

static void coulomb_cut(void)
{
  const double kt = 2e5, mu = 0.4, fn = 10.0, dt = 1e-3, cap = mu * fn;
  const TlVec3 ni = tl_v3_normalize(tl_v3(0.1, -0.2, 1.0));
  const TlVec3 nf = tl_v3_normalize(tl_v3(0.16, -0.23, 1.0));
  TlVec3 f = tl_v3(1.5, 0.9, 0.0);
  f = tl_v3_scale(tl_v3_axpy(f, -tl_v3_dot(f, ni), ni), 3.0 / tl_v3_norm(tl_v3_axpy(f, -tl_v3_dot(f, ni), ni)));
  const TlVec3 vrel = {0.02, 0.05, -0.01}, spin = tl_v3_scale(nf, 400.0); /* c = 0.4 */
  for (int s = 0; s < 3; ++s) {
    TlVec3 g = step(s, f, ni, nf, vrel, spin, kt, mu, fn, dt);
    TL_TEST_ASSERT(fabs(tl_v3_norm(g) - cap) <= 1e-14 * cap, "%s: sliding |f_T| = %.17g, cone %.17g", names[s],
                   tl_v3_norm(g), cap);
    TL_TEST_ASSERT(fabs(tl_v3_dot(g, nf)) <= 1e-6 * cap, "%s: f_T . n = %g", names[s], tl_v3_dot(g, nf));
  }
  /* the trial forces really are outside the cone (else the check is void) */
  double h[6] = {f.x, f.y, f.z, ni.x, ni.y, ni.z};
  TlVec3 phi = tl_v3_axpy(tl_v3_axpy(f, -tl_v3_dot(f, nf), nf), kt * dt,
                          tl_v3_axpy(vrel, -tl_v3_dot(vrel, nf), nf));
  const double c = dt * tl_v3_dot(spin, nf);
  TL_TEST_ASSERT(tl_v3_norm(phi) / sqrt(1 + c * c) > 1.5 * cap, "elastic implicit force %g not beyond the cone %g",
                 tl_v3_norm(phi) / sqrt(1 + c * c), cap);
  TlVec3 g = tl_friction_force_implicit(h, nf, vrel, spin, kt, 0.0, mu, fn, dt, NULL);
  int it;
  double res;
  TlVec3 ref = newton_eq12(nf, phi, c, cap, &it, &res);
  printf("implicit cut: closed form (%.15g %.15g %.15g), Newton (%d iterations, residual %.2e) (%.15g %.15g %.15g)\n",
         g.x, g.y, g.z, it, res, ref.x, ref.y, ref.z);
  TL_TEST_ASSERT(res <= 1e-13 * cap, "Newton on Eq. 12 did not converge (residual %g after %d iterations)", res, it);
  TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(g, ref)) <= 1e-12 * cap, "implicit closed form differs from Newton by %g",
                 tl_v3_norm(tl_v3_sub(g, ref)));
  /* the stored history is the returned spring force (no damping here) */
  TL_TEST_ASSERT(h[0] == g.x && h[1] == g.y && h[2] == g.z, "implicit history not updated to f_T^f");
  /* a fresh contact (zero history, zero normal for rotate) starts from k_T Δu_T */
  for (int s = 0; s < 3; ++s) {
    double z[6] = {0, 0, 0, 0, 0, 0};
    TlVec3 v = {1e-3, 0, 0};
    TlVec3 q = kernels[s](z, ni, v, tl_v3(0, 0, 0), kt, 0.0, mu, 1e6, dt, NULL);
    TlVec3 vt = tl_v3_axpy(v, -tl_v3_dot(v, ni), ni);
    TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(q, tl_v3_scale(vt, kt * dt))) <= 1e-15 * kt * dt, "%s: first touch", names[s]);
  }
}

static void part_parameter(void)
{
  const double want[3] = {3, 6, 3};
  for (int s = 0; s < 3; ++s) {
    TlContactLaw *law;
    TL_TEST_STATUS(tl_contact_law_create("linear", "coulomb", NULL, NULL, &law), TL_OK);
    TL_TEST_STATUS(tl_contact_law_set(law, "k_n", 1e5), TL_OK);
    TL_TEST_STATUS(tl_contact_law_set(law, "transport", s), TL_OK);
    TL_TEST_STATUS(tl_contact_law_setup(law), TL_OK);
    TL_TEST_ASSERT((double)law->history_doubles == want[s], "transport %d: %zu history doubles, expected %g", s,
                   law->history_doubles, want[s]);
    tl_contact_law_destroy(&law);
  }
  TlContactLaw *law;
  TL_TEST_STATUS(tl_contact_law_create("linear", "coulomb", NULL, NULL, &law), TL_OK);
  TL_TEST_STATUS(tl_contact_law_set(law, "k_n", 1e5), TL_OK);
  double def = -1.0;
  TL_TEST_STATUS(tl_contact_law_get(law, "transport", &def), TL_OK);
  TL_TEST_ASSERT(def == 0.0, "default transport %g (project expected)", def);
  TL_TEST_STATUS(tl_contact_law_set(law, "transport", 3.0), TL_ERR_ARG);
  TL_TEST_STATUS(tl_contact_law_set(law, "transport", 0.5), TL_OK);
  TL_TEST_STATUS(tl_contact_law_setup(law), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "0.5") != NULL, "message does not name the value: %s", tl_error_message());
  tl_contact_law_destroy(&law);
}

/* ---- a sticking pair rigidly rotated in a DEM world ---- */

typedef struct {
  TlVec3 c, axis, u; /* rotation centre and unit axis; tangential load of particle 1 */
  double omega, t1;  /* spin; end of the loading phase */
  TlVec3 x0[2];
} Motion;

static TlStatus motion_eval(void *ctx, double t, size_t n, const int64_t *id, const TlVec3 *x0, TlVec3 *x, TlVec3 *v)
{
  const Motion *m = ctx;
  (void)x0;
  const double load = t < m->t1 ? t / m->t1 : 1.0, ang = t > m->t1 ? m->omega * (t - m->t1) : 0.0;
  const TlMat3 R = tl_m3_rotation(m->axis, ang);
  const TlVec3 W = tl_v3_scale(m->axis, t > m->t1 ? m->omega : 0.0);
  for (size_t k = 0; k < n; ++k) {
    TlVec3 rel = tl_v3_sub(m->x0[id[k]], m->c);
    if (id[k] == 1) rel = tl_v3_axpy(rel, load, m->u);
    TlVec3 r = tl_m3_mulv(R, rel);
    x[k] = tl_v3_add(m->c, r);
    v[k] = tl_v3_cross(W, r);
    if (id[k] == 1 && t < m->t1) v[k] = tl_v3_add(v[k], tl_v3_scale(m->u, 1.0 / m->t1));
  }
  return TL_OK;
}

typedef struct {
  TlVec3 f, b;
  int n;
} Grab;

static void grab(void *ctx, size_t i, size_t j, TlVec3 f, TlVec3 b, TlVec3 cp)
{
  Grab *g = ctx;
  (void)cp;
  /* the force on particle 0, the branch from 0 to 1, whatever the order */
  g->f = i < j ? f : tl_v3_neg(f);
  g->b = i < j ? b : tl_v3_neg(b);
  g->n++;
}

/* Loads the pair tangentially, then rotates it by `turn` rad in `steps`
 * steps about `axis` (zero: the normal); *ratio = |f_T| / |f_T^0|, *dir_err = |f_T - R f_T^0| /
 * |f_T^0|. */
static TlStatus rigid_pair(int transport, TlVec3 axis, TlVec3 u, double turn, int steps, double *ratio,
                           double *dir_err, double *theta)
{
  const double r = 0.01, dt = 1e-5;
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "g", 2500, r, r, &sp));
  Motion m = {.u = u, .t1 = 20 * dt};
  m.x0[0] = tl_v3(0, 0, 0);
  m.x0[1] = tl_v3(1.98 * r, 0, 0);
  /* about the loaded pair's midpoint; a zero axis: the loaded normal */
  const TlVec3 x1 = tl_v3_add(m.x0[1], u);
  m.c = tl_v3_scale(tl_v3_add(m.x0[0], x1), 0.5);
  m.axis = tl_v3_normalize(tl_v3_norm(axis) > 0.0 ? axis : tl_v3_sub(x1, m.x0[0]));
  m.omega = turn / (steps * dt);
  for (int k = 0; k < 2; ++k) TL_CHECK(tl_dem_add_particle(dem, m.x0[k], tl_v3(0, 0, 0), r, sp, NULL));
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_create("linear", "coulomb", NULL, NULL, &law));
  TL_CHECK(tl_contact_law_set(law, "k_n", 1e5));
  TL_CHECK(tl_contact_law_set(law, "mu", 0.5));
  TL_CHECK(tl_contact_law_set(law, "transport", transport));
  TL_CHECK(tl_contact_law_setup(law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  tl_dem_skip_fixed_pairs(dem, 0);
  tl_dem_set_sort_interval(dem, 0);
  tl_dem_track_energy(dem, 0);
  TL_CHECK(tl_dem_prescribe(dem, 2, (int64_t[]){0, 1}, motion_eval, &m));
  TL_CHECK(tl_dem_set_timestep(dem, dt, 0));
  TL_CHECK(tl_dem_setup(dem));
  TL_CHECK(tl_dem_step(dem, 20));
  Grab g0 = {0};
  TL_CHECK(tl_dem_visit_contacts(dem, grab, &g0));
  TlVec3 n0 = tl_v3_normalize(g0.b);
  TlVec3 ft0 = tl_v3_axpy(g0.f, -tl_v3_dot(g0.f, n0), n0);
  /* the pair spins rigidly from now on */
  for (int k = 0; k < 2; ++k) P->w[k] = tl_v3_scale(m.axis, m.omega);
  TL_CHECK(tl_dem_step(dem, steps));
  Grab g = {0};
  TL_CHECK(tl_dem_visit_contacts(dem, grab, &g));
  TlVec3 n = tl_v3_normalize(g.b);
  TlVec3 ft = tl_v3_axpy(g.f, -tl_v3_dot(g.f, n), n);
  TlVec3 want = tl_m3_mulv(tl_m3_rotation(m.axis, turn), ft0);
  *ratio = tl_v3_norm(ft) / tl_v3_norm(ft0);
  *dir_err = tl_v3_norm(tl_v3_sub(ft, want)) / tl_v3_norm(ft0);
  *theta = m.omega * dt;
  TlStatus s = g0.n == 1 && g.n == 1 && tl_v3_norm(ft0) > 0.5 ? TL_OK : TL_ERR_STATE;
  if (s != TL_OK) printf("pair: %d / %d contacts, |f_T0| = %g\n", g0.n, g.n, tl_v3_norm(ft0));
  tl_dem_destroy(&dem);
  return s;
}

static void dem_pair(void)
{
  /* tilt: rotation about z (normal along x at the start), load along y */
  const int N = 400;
  const double turn = 0.8;
  for (int s = 0; s < 3; ++s) {
    double ratio, err, th;
    TL_TEST_STATUS(rigid_pair(s, tl_v3(0, 0, 1), tl_v3(0, 1e-4, 0), turn, N, &ratio, &err, &th), TL_OK);
    double want = s == TL_FRICTION_ROTATE ? pow(rotate_ratio(th), N) : pow(cos(th), N);
    printf("rigid tilt, %s: |f_T| ratio %.12f (closed form %.12f), direction error %.2e\n", names[s], ratio, want, err);
    TL_TEST_ASSERT(fabs(ratio - want) <= 1e-9, "%s tilt: ratio %.15g, closed form %.15g", names[s], ratio, want);
    TL_TEST_ASSERT(fabs(err - fabs(ratio - 1.0)) <= 1e-9, "%s tilt: the force left the rotating plane (error %g)",
                   names[s], err);
  }
  /* spin about the normal: rotation about the pair's axis */
  for (int s = 0; s < 3; ++s) {
    double ratio, err, th;
    TL_TEST_STATUS(rigid_pair(s, tl_v3(0, 0, 0), tl_v3(0, 1e-4, 0), turn, N, &ratio, &err, &th), TL_OK);
    double g = 0.5 * N * log1p(th * th);
    double want = exp(s == TL_FRICTION_IMPLICIT ? -g : g);
    printf("rigid spin, %s: |f_T| ratio %.12f (closed form %.12f), direction error %.2e\n", names[s], ratio, want, err);
    TL_TEST_ASSERT(fabs(ratio - want) <= 1e-9, "%s spin: ratio %.15g, closed form %.15g", names[s], ratio, want);
  }
  /* oblique axis: first order in dt towards the rigidly rotated force */
  for (int s = 0; s < 3; ++s) {
    double e[2], ratio, th;
    for (int h = 0; h < 2; ++h)
      TL_TEST_STATUS(rigid_pair(s, tl_v3(0.6, -0.3, 0.74), tl_v3(0, 0.7e-4, 0.7e-4), turn, N << h, &ratio, &e[h], &th),
                     TL_OK);
    printf("rigid oblique turn, %s: error %.3e (N = %d), %.3e (N = %d)\n", names[s], e[0], N, e[1], 2 * N);
    TL_TEST_ASSERT(e[0] <= 2.0 * turn * turn / N, "%s oblique: error %g above 2 turn^2 / N = %g", names[s], e[0],
                   2.0 * turn * turn / N);
    TL_TEST_CLOSE(e[0] / e[1], 2.0, 0.1);
  }
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  one_step_closed_forms();
  coulomb_cut();
  part_parameter();
  dem_pair();
  return tl_test_report();
}
