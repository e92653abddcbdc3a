/* The two-dimensional (disk) world (tl_dem_set_dimension, the planar cell).
 *
 *  1. Impact: two free disks meet head-on along an oblique in-plane line
 *     (linear spring, no damping): the contact lasts π sqrt(m* / k_n) with the
 *     disks' mass per unit thickness m = ρ π r² (m* = m/2), and the
 *     velocities are exchanged.
 *  2. Spin-down: a spinning disk squeezed between two fixed disks slides on
 *     both; its spin falls at the constant rate 2 μ f_N l / I with the
 *     cylinder inertia I = ½ m r² (l = r - δ/2) while its centre stays put.
 *  3. A periodic planar cell of disks compressed and sheared (ḣ in the
 *     plane) against the same packing run as spheres in a 3-D cell periodic
 *     along z of height L_z, with the disks' masses and inertias, whose
 *     motion stays in the plane by symmetry ("locked"): the 2-D stress per
 *     unit thickness equals L_z times the 3-D stress; its antisymmetric part
 *     is the particles' total torque over the area, small once relaxed; the
 *     z row and column are zero.
 *  4. z stays exactly 0 and v_z, ω_x, ω_y exactly 0 throughout.
 *  5. A 2-D gas compressed to a pressure (tl_dem_compress): the packing
 *     reaches the target pressure per unit thickness -tr(σ)/2 within the
 *     tolerance and every disk its static balance (Eq. 19).
 *  6. Checkpoints carry the dimension (a 2-D checkpoint restarts bit for bit
 *     in a 2-D world and is refused by a 3-D one); bad input is refused
 *     (dimension 4, a planar h with a z entry, a z rate, a particle off the
 *     plane, a 3-D cell in a 2-D world, a gas too dense to insert). */
#include <math.h>
#include <string.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

static double max_off_plane(TlDem *dem)
{
  const TlParticles *P = tl_dem_particles(dem);
  double m = 0.0;
  for (size_t i = 0; i < P->n; ++i) {
    m = fmax(m, fabs(P->x[i].z));
    m = fmax(m, fabs(P->v[i].z));
    if (P->w) m = fmax(m, fmax(fabs(P->w[i].x), fabs(P->w[i].y)));
  }
  return m;
}

static TlContactLaw *linear_law(double kn, double restitution, double mu)
{
  TlContactLaw *law = NULL;
  if (tl_test_law(&law, "linear", "k_n", kn, "restitution", restitution, "mu", mu, NULL) != TL_OK) return NULL;
  return law;
}

/* An empty 2-D world with one species of disks (density rho, radius r). */
static TlDem *disk_world(double rho, double r, int *sp)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TL_TEST_STATUS(tl_dem_set_dimension(dem, 2), TL_OK);
  TL_TEST_STATUS(tl_particles_add_species(tl_dem_particles(dem), "g", rho, r, r, sp), TL_OK);
  return dem;
}

static void impact(void)
{
  const double r = 0.01, rho = 2500, kn = 1e5, v0 = 0.1, a = 0.3;
  const double m = rho * TL_PI * r * r, tc = TL_PI * sqrt(0.5 * m / kn), dt = tc / 400;
  int sp;
  TlDem *dem = disk_world(rho, r, &sp);
  TlParticles *P = tl_dem_particles(dem);
  const TlVec3 e = {cos(a), sin(a), 0.0};
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.3, 0.4, 0), tl_v3_scale(e, v0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3_axpy(tl_v3(0.3, 0.4, 0), 2.02 * r, e), tl_v3(0, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_CLOSE(P->mass[0], m, 1e-15);
  TL_TEST_STATUS(tl_dem_add_law(dem, linear_law(kn, 1.0, 0.0), NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, dt, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  long touching = 0;
  for (int s = 0; s < 2000; ++s) {
    TL_TEST_STATUS(tl_dem_step(dem, 1), TL_OK);
    TlDemStats st;
    tl_dem_stats(dem, &st);
    touching += st.n_contacts > 0;
  }
  const double t_meas = touching * dt;
  printf("impact: contact %.6e s (π sqrt(m*/k) = %.6e s), v after (%.3e, %.6e) m/s of %g\n", t_meas, tc,
         tl_v3_norm(P->v[0]), tl_v3_dot(P->v[1], e), v0);
  TL_TEST_ASSERT(fabs(t_meas - tc) <= 2.0 * dt, "contact duration %g s, closed form %g s (dt %g)", t_meas, tc, dt);
  TL_TEST_ASSERT(tl_v3_norm(P->v[0]) <= 1e-4 * v0, "striker keeps %g m/s", tl_v3_norm(P->v[0]));
  TL_TEST_REL(tl_v3_dot(P->v[1], e), v0, 1e-4);
  TL_TEST_ASSERT(max_off_plane(dem) == 0.0, "off-plane motion %g", max_off_plane(dem));
  tl_dem_destroy(&dem);
}

static void spin_down(void)
{
  const double r = 0.01, rho = 2500, kn = 1e5, mu = 0.3, delta = 1e-4, w0 = 20.0, dt = 1e-5;
  int sp;
  TlDem *dem = disk_world(rho, r, &sp);
  TlParticles *P = tl_dem_particles(dem);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0, 0, 0), tl_v3(0, 0, 0), r, sp, NULL), TL_OK);
  for (int k = 0; k < 2; ++k) {
    size_t idx;
    TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3((k ? 1 : -1) * (2 * r - delta), 0, 0), tl_v3(0, 0, 0), r, sp, &idx),
                   TL_OK);
    TL_TEST_STATUS(tl_particles_set_motion(P, idx, TL_MOTION_FIXED), TL_OK);
  }
  TL_TEST_STATUS(tl_dem_add_law(dem, linear_law(kn, 0.5, mu), NULL), TL_OK);
  tl_dem_set_sort_interval(dem, 0);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, dt, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  P->w[0] = tl_v3(0, 0, w0);
  const double m = rho * TL_PI * r * r, I = 0.5 * m * r * r, l = r - 0.5 * delta;
  TL_TEST_CLOSE(1.0 / P->inv_inertia[0], I, 1e-15);
  const double rate = 2.0 * mu * kn * delta * l / I;
  TL_TEST_STATUS(tl_dem_step(dem, 200), TL_OK);
  const double w1 = P->w[0].z;
  TL_TEST_STATUS(tl_dem_step(dem, 600), TL_OK);
  const double w2 = P->w[0].z, meas = (w1 - w2) / (600 * dt);
  printf("spin-down: spin falls at %.12g rad/s² (2 μ f_N l / I with I = m r²/2: %.12g; sphere inertia would give "
         "%.6g)\n", meas, rate, rate * 0.5 / 0.4);
  TL_TEST_ASSERT(w2 > 0.0 && w2 < w1, "spins %g then %g: the disk must still slide", w1, w2);
  TL_TEST_REL(meas, rate, 1e-9);
  TL_TEST_ASSERT(tl_v3_norm(P->x[0]) <= 1e-15 && tl_v3_norm(P->v[0]) <= 1e-12, "centre moved to (%g %g), v %g",
                 P->x[0].x, P->x[0].y, tl_v3_norm(P->v[0]));
  TL_TEST_ASSERT(max_off_plane(dem) == 0.0, "off-plane motion %g", max_off_plane(dem));
  tl_dem_destroy(&dem);
}

/* ---- a periodic cell of disks against the same packing in 3-D ---- */

enum { NGAS = 70 };
static const double CELL = 0.2, LZ = 0.1, DT = 2e-4;

static TlStatus make_world(int dim, const TlVec3 *x, const double *radius, size_t n, TlDem **out)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TL_CHECK(tl_dem_set_dimension(dem, dim));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "g", 2500, 0.008, 0.012, &sp));
  TlMat3 h = tl_m3_identity();
  h.m[0][0] = CELL;
  h.m[1][1] = CELL;
  h.m[0][1] = 0.1 * CELL; /* sheared from the start: the general rounding */
  TlDomain D;
  if (dim == 2) {
    TL_CHECK(tl_domain_init_cell_2d(&D, tl_v3(0, 0, 0), h));
  } else {
    h.m[2][2] = LZ;
    TL_CHECK(tl_domain_init_cell(&D, tl_v3(0, 0, 0), h));
  }
  TL_CHECK(tl_dem_set_domain(dem, &D));
  if (x) {
    for (size_t i = 0; i < n; ++i) TL_CHECK(tl_dem_add_particle(dem, x[i], tl_v3(0, 0, 0), radius[i], sp, NULL));
  } else {
    size_t placed = 0;
    TL_CHECK(tl_dem_insert_gas(dem, sp, NGAS, 7, 100000, &placed));
  }
  /* the 3-D twin carries the disks' masses */
  if (dim == 3)
    for (size_t i = 0; i < P->n; ++i) {
      P->mass[i] = 2500 * TL_PI * P->radius[i] * P->radius[i];
      P->inv_mass[i] = 1.0 / P->mass[i];
    }
  TlContactLaw *law = linear_law(1e5, 0.3, 0.4);
  if (!law) TL_ERROR(TL_ERR_ARG, "law");
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  tl_dem_track_energy(dem, 0);
  TL_CHECK(tl_dem_set_timestep(dem, DT, 1));
  TL_CHECK(tl_dem_setup(dem));
  if (dim == 3)
    for (size_t i = 0; i < P->n; ++i) P->inv_inertia[i] = 1.0 / (0.5 * P->mass[i] * P->radius[i] * P->radius[i]);
  *out = dem;
  return TL_OK;
}

static TlStatus drive(TlDem *dem, TlMat3 rate, long steps)
{
  TlDomain *D = tl_dem_domain(dem);
  TlMat3 hd = tl_m3_mul(rate, D->h);
  hd.m[2][0] = hd.m[2][1] = hd.m[0][2] = hd.m[1][2] = hd.m[2][2] = 0.0;
  TL_CHECK(tl_domain_set_h_rate(D, hd));
  TL_CHECK(tl_dem_step(dem, steps));
  return tl_domain_set_h_rate(D, tl_m3_zero());
}

static double diff_2d(TlMat3 a, TlMat3 b, double scale_b, double *norm)
{
  double d = 0.0, n = 0.0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      d = fmax(d, fabs(a.m[i][j] - scale_b * b.m[i][j]));
      n = fmax(n, fabs(a.m[i][j]));
    }
  *norm = n;
  return d;
}

static double total_torque_z(TlDem *dem)
{
  const TlParticles *P = tl_dem_particles(dem);
  double t = 0.0;
  for (size_t i = 0; i < P->n; ++i) t += P->torque[i].z;
  return t;
}

static void cell_against_3d(void)
{
  TlDem *d2 = NULL, *d3 = NULL;
  TL_TEST_STATUS(make_world(2, NULL, NULL, 0, &d2), TL_OK);
  if (!d2) return;
  TlParticles *P2 = tl_dem_particles(d2);
  TL_TEST_ASSERT(P2->n == NGAS, "gas: %zu disks placed of %d", P2->n, NGAS);
  double phi0 = 0.0, worst_gap = INFINITY;
  for (size_t i = 0; i < P2->n; ++i) {
    phi0 += TL_PI * P2->radius[i] * P2->radius[i];
    for (size_t j = i + 1; j < P2->n; ++j) {
      TlVec3 b = tl_domain_branch(tl_dem_domain(d2), P2->x[i], P2->x[j]);
      worst_gap = fmin(worst_gap, tl_v3_norm(b) - P2->radius[i] - P2->radius[j]);
    }
  }
  phi0 /= tl_domain_area(tl_dem_domain(d2));
  printf("gas: %zu disks, area fraction %.4f, smallest gap %.3e m\n", P2->n, phi0, worst_gap);
  TL_TEST_ASSERT(worst_gap > 0.0, "gas disks overlap by %g", -worst_gap);
  TL_TEST_STATUS(make_world(3, P2->x, P2->radius, P2->n, &d3), TL_OK);
  if (!d3) return;
  /* compress to an area fraction of about 0.84, shear, relax */
  const double eps = (1.0 - sqrt(phi0 / 0.84)) / (3000 * DT); /* constant ḣ: h shrinks linearly */
  TlMat3 compress = tl_m3_zero(), shear = tl_m3_zero();
  compress.m[0][0] = compress.m[1][1] = -eps;
  shear.m[0][1] = 0.5;
  const struct {
    TlMat3 rate;
    long steps;
    const char *what;
  } phases[3] = {{compress, 3000, "compressed"}, {shear, 600, "sheared"}, {tl_m3_zero(), 2000, "relaxed"}};
  for (int q = 0; q < 3; ++q) {
    TL_TEST_STATUS(drive(d2, phases[q].rate, phases[q].steps), TL_OK);
    TL_TEST_STATUS(drive(d3, phases[q].rate, phases[q].steps), TL_OK);
    TlMat3 s2, s3, k2;
    TL_TEST_STATUS(tl_dem_stress(d2, &s2, &k2), TL_OK);
    TL_TEST_STATUS(tl_dem_stress(d3, &s3, NULL), TL_OK);
    double norm, d = diff_2d(s2, s3, LZ, &norm);
    double z = 0.0;
    for (int i = 0; i < 3; ++i) z = fmax(z, fmax(fabs(s2.m[i][2]), fabs(s2.m[2][i])));
    /* antisymmetric part = total torque / area (Σ b × f = Σ torques) */
    double asym = s2.m[0][1] - s2.m[1][0], tq = total_torque_z(d2) / tl_domain_area(tl_dem_domain(d2));
    double zc;
    tl_dem_coordination(d2, &zc, NULL);
    printf("%s: 2-D stress per unit thickness xx %.6e yy %.6e xy %.6e yx %.6e N/m, coordination %.2f; "
           "|2-D - L_z 3-D| %.2e of it; antisymmetric %.3e, torque / area %.3e\n",
           phases[q].what, s2.m[0][0], s2.m[1][1], s2.m[0][1], s2.m[1][0], zc, d / norm, asym, tq);
    TL_TEST_ASSERT(norm > 1.0, "%s: no stress (%g N/m): the packing has no contacts", phases[q].what, norm);
    TL_TEST_ASSERT(d <= 1e-8 * norm, "%s: 2-D and 3-D stresses differ by %g of %g", phases[q].what, d, norm);
    TL_TEST_ASSERT(z == 0.0, "%s: z row or column %g", phases[q].what, z);
    TL_TEST_ASSERT(fabs(asym + tq) <= 1e-9 * norm, "%s: antisymmetric part %g, minus torque / area %g",
                   phases[q].what, asym, -tq);
    TL_TEST_ASSERT(max_off_plane(d2) == 0.0 && max_off_plane(d3) == 0.0, "%s: off-plane motion %g (2-D), %g (3-D)",
                   phases[q].what, max_off_plane(d2), max_off_plane(d3));
    if (q == 2) TL_TEST_ASSERT(fabs(asym) <= 1e-3 * norm, "relaxed: antisymmetric part %g of %g", asym, norm);
  }
  tl_dem_destroy(&d3);
  tl_dem_destroy(&d2);
}

static void compress_2d(void)
{
  TlDem *d = NULL;
  TL_TEST_STATUS(make_world(2, NULL, NULL, 0, &d), TL_OK);
  if (!d) return;
  const TlDemCompress c = {100.0, 0.05, 1.0, 1e-3, 1e-2, 50, 200000};
  TlDemCompressResult r;
  double t0 = tl_wtime();
  TL_TEST_STATUS(tl_dem_compress(d, &c, &r), TL_OK);
  TlMat3 sc, sk;
  TL_TEST_STATUS(tl_dem_stress(d, &sc, &sk), TL_OK);
  const double p = -0.5 * (sc.m[0][0] + sc.m[1][1] + sk.m[0][0] + sk.m[1][1]);
  double delta;
  TL_TEST_STATUS(tl_dem_max_force_imbalance(d, &delta), TL_OK);
  printf("compress: %s after %ld steps (%.2f s): pressure %.6g N/m (target %g), area fraction %.4f, coordination "
         "%.2f, largest imbalance %.2e\n", r.converged ? "converged" : "not converged", r.steps, tl_wtime() - t0,
         r.pressure, c.pressure, r.solid_fraction, r.coordination, r.max_imbalance);
  TL_TEST_ASSERT(r.converged, "not converged after %ld steps", r.steps);
  TL_TEST_REL(p, c.pressure, c.pressure_tolerance);
  TL_TEST_ASSERT(delta < c.tolerance, "largest imbalance %g", delta);
  TL_TEST_ASSERT(r.solid_fraction > 0.75 && r.solid_fraction < 0.9, "area fraction %g of a jammed disk packing",
                 r.solid_fraction);
  TL_TEST_ASSERT(max_off_plane(d) == 0.0, "off-plane motion %g", max_off_plane(d));
  tl_dem_destroy(&d);
}

/* ---- checkpoints and refusals ---- */

static void checkpoint_and_refusals(void)
{
  TlDem *a = NULL, *b = NULL, *c = NULL;
  TL_TEST_STATUS(make_world(2, NULL, NULL, 0, &a), TL_OK);
  if (!a) return;
  TlMat3 compress = tl_m3_zero();
  compress.m[0][0] = compress.m[1][1] = -1.0;
  TL_TEST_STATUS(drive(a, compress, 800), TL_OK);
  TlCheckpoint *cp = NULL;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, a), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, "disks.h5", tl_dem_time(a), 800), TL_OK);
  tl_checkpoint_destroy(&cp);
  /* a 2-D world built the same way */
  TL_TEST_STATUS(make_world(2, NULL, NULL, 0, &b), TL_OK);
  double t;
  int64_t step;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, b), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp, "disks.h5", &t, &step), TL_OK);
  tl_checkpoint_destroy(&cp);
  TL_TEST_STATUS(drive(a, compress, 300), TL_OK);
  TL_TEST_STATUS(drive(b, compress, 300), TL_OK);
  const TlParticles *A = tl_dem_particles(a), *B = tl_dem_particles(b);
  int same = A->n == B->n;
  for (size_t i = 0; same && i < A->n; ++i)
    same = memcmp(&A->x[i], &B->x[i], sizeof A->x[i]) == 0 && memcmp(&A->w[i], &B->w[i], sizeof A->w[i]) == 0;
  TL_TEST_ASSERT(same, "the restarted 2-D world departs from the uninterrupted one");
  /* a 3-D world refuses it */
  TL_TEST_STATUS(make_world(3, A->x, A->radius, A->n, &c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp, "disks.h5", &t, &step), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "2-dimensional") != NULL, "message: %s", tl_error_message());
  tl_checkpoint_destroy(&cp);
  tl_dem_destroy(&c);
  tl_dem_destroy(&b);
  tl_dem_destroy(&a);

  /* refusals */
  TlDem *d;
  TL_TEST_STATUS(tl_dem_create(&d), TL_OK);
  TL_TEST_STATUS(tl_dem_set_dimension(d, 4), TL_ERR_ARG);
  TlDomain D;
  TlMat3 h = tl_m3_scale(tl_m3_identity(), 0.1);
  TL_TEST_STATUS(tl_domain_init_cell_2d(&D, tl_v3(0, 0, 0), h), TL_ERR_ARG); /* h_zz = 0.1 */
  TL_TEST_ASSERT(strstr(tl_error_message(), "h[2][2]") != NULL, "message: %s", tl_error_message());
  h.m[2][2] = 1.0;
  TL_TEST_STATUS(tl_domain_init_cell_2d(&D, tl_v3(0, 0, 0), h), TL_OK);
  TL_TEST_ASSERT(D.periodic[0] && D.periodic[1] && !D.periodic[2] && D.planar, "planar cell flags");
  TL_TEST_CLOSE(tl_domain_area(&D), 0.01, 1e-15);
  TlMat3 rate = tl_m3_zero();
  rate.m[0][2] = 1.0;
  TL_TEST_STATUS(tl_domain_set_h_rate(&D, rate), TL_ERR_ARG);
  TL_TEST_STATUS(tl_dem_set_dimension(d, 2), TL_OK);
  TlParticles *P = tl_dem_particles(d);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "g", 2500, 0.01, 0.01, &sp), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(d, tl_v3(0.05, 0.05, 0.001), tl_v3(0, 0, 0), 0.01, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_set_domain(d, &D), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(d, linear_law(1e5, 0.5, 0.3), NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(d, 1e-5, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(d), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "z = 0.001") != NULL, "message: %s", tl_error_message());
  P->x[0].z = 0.0;
  TlDomain D3;
  TL_TEST_STATUS(tl_domain_init_cell(&D3, tl_v3(0, 0, 0), tl_m3_scale(tl_m3_identity(), 0.1)), TL_OK);
  TL_TEST_STATUS(tl_dem_set_domain(d, &D3), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(d), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "planar cell") != NULL, "message: %s", tl_error_message());
  TL_TEST_STATUS(tl_dem_set_domain(d, &D), TL_OK);
  TL_TEST_STATUS(tl_dem_insert_gas(d, sp, 200, 1, 1000, NULL), TL_ERR_ARG); /* 200 disks of area 3.1e-4 in 0.01 */
  TL_TEST_ASSERT(strstr(tl_error_message(), "packing fraction") != NULL, "message: %s", tl_error_message());
  tl_dem_destroy(&d);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  impact();
  spin_down();
  cell_against_3d();
  compress_2d();
  checkpoint_and_refusals();
  return tl_test_report();
}
