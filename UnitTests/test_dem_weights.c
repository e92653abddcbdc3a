/* Weighted particle equations (seeds/001 Eqs. 24-25; tl_dem_set_weight_field):
 * weights 1 change nothing, bit for bit; two bonded particles under gravity
 * with a weight field get w_ab f_ab + w_a m g and accelerate by it over
 * w_a m; the coupling force f^C enters as it is, and through the VCoupling
 * element the particle and the solid sides balance (Eq. 41). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_dem.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_test.h"
#include "tl_vcoupling.h"
#include "tl_vcoupling_element.h"

static TlStatus weight_one(void *ctx, size_t n, const TlVec3 *x, double *w)
{
  (void)ctx, (void)x;
  for (size_t k = 0; k < n; ++k) w[k] = 1.0;
  return TL_OK;
}

/* w = 0.3 + 25 x (0.3 at x = 0, 0.8 at x = 0.02) */
static TlStatus weight_ramp(void *ctx, size_t n, const TlVec3 *x, double *w)
{
  (void)ctx;
  for (size_t k = 0; k < n; ++k) w[k] = 0.3 + 25.0 * x[k].x;
  return TL_OK;
}

static double rnd(unsigned *s)
{
  *s = *s * 1103515245u + 12345u;
  return ((*s >> 8) & 0xffff) / 65535.0 - 0.5;
}

/* A linear law of stiffness k_n whose bonds act in tension. */
static void add_bonded_law(TlDem *dem, double k_n)
{
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_test_law(&law, "bonded_linear", "k_n", k_n, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
}

/* n[0] x n[1] x n[2] particles of radius r, h apart from x0 (particle
 * (j n[2] + k) n[0] + i at x0 + h (i, j, k)), bonded to their neighbours
 * along each axis, velocities v0 + amp (random in [-1/2, 1/2]^3). */
static void bonded_lattice(TlDem *dem, int sp, const int n[3], TlVec3 x0, double h, double r, TlVec3 v0, double amp,
                           unsigned *seed)
{
  for (int j = 0; j < n[1]; ++j)
    for (int k = 0; k < n[2]; ++k)
      for (int i = 0; i < n[0]; ++i)
        tl_dem_add_particle(dem, tl_v3(x0.x + h * i, x0.y + h * j, x0.z + h * k),
                            tl_v3(v0.x + amp * rnd(seed), v0.y + amp * rnd(seed), v0.z + amp * rnd(seed)), r, sp, NULL);
  for (int j = 0; j < n[1]; ++j)
    for (int k = 0; k < n[2]; ++k)
      for (int i = 0; i < n[0]; ++i) {
        int64_t a = (j * n[2] + k) * n[0] + i;
        if (i < n[0] - 1) tl_dem_add_bond(dem, a, a + 1);
        if (k < n[2] - 1) tl_dem_add_bond(dem, a, a + n[0]);
        if (j < n[1] - 1) tl_dem_add_bond(dem, a, a + n[0] * n[2]);
      }
}

/* A bonded 3 x 5 x 3 lattice (spacing 0.02) with random velocities, gravity
 * and an external force on one particle. */
static TlDem *lattice(int weighted)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  if (!dem) return NULL;
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", 2500, 0.01, 0.01, &sp), TL_OK);
  unsigned seed = 7u;
  bonded_lattice(dem, sp, (const int[3]){3, 5, 3}, tl_v3(0, 0, 0), 0.02, 0.01, tl_v3(0, 0, 0), 0.05, &seed);
  add_bonded_law(dem, 1e5);
  tl_dem_set_gravity(dem, tl_v3(0, -9.81, 0));
  TL_TEST_STATUS(tl_particles_enable_external_force(P), TL_OK);
  P->f_ext[4] = tl_v3(0.3, 0.1, -0.2);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 2e-5, 0), TL_OK);
  if (weighted) tl_dem_set_weight_field(dem, weight_one, NULL);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  return dem;
}

static void test_unit_weights(void)
{
  TlDem *a = lattice(0), *b = lattice(1);
  if (!a || !b) return;
  TL_TEST_STATUS(tl_dem_step(a, 500), TL_OK);
  TL_TEST_STATUS(tl_dem_step(b, 500), TL_OK);
  const TlParticles *Pa = tl_dem_particles(a), *Pb = tl_dem_particles(b);
  TL_TEST_ASSERT(Pb->weight != NULL && Pa->weight == NULL, "only the weighted world holds weights");
  int same = Pa->n == Pb->n && memcmp(Pa->id, Pb->id, Pa->n * sizeof *Pa->id) == 0 &&
             memcmp(Pa->x, Pb->x, Pa->n * sizeof *Pa->x) == 0 && memcmp(Pa->v, Pb->v, Pa->n * sizeof *Pa->v) == 0 &&
             memcmp(Pa->f, Pb->f, Pa->n * sizeof *Pa->f) == 0;
  TL_TEST_ASSERT(same, "weights 1: positions, velocities and forces bit for bit after 500 steps");
  TlDemEnergy ea, eb;
  tl_dem_energy(a, &ea);
  tl_dem_energy(b, &eb);
  TL_TEST_ASSERT(memcmp(&ea, &eb, sizeof ea) == 0, "weights 1: the same energies (total %g and %g)", ea.total,
                 eb.total);
  tl_dem_destroy(&a);
  tl_dem_destroy(&b);
}

typedef struct {
  TlVec3 f;
} Bond;

static void grab(void *ctx, size_t i, size_t j, TlVec3 force_on_i, TlVec3 branch, TlVec3 cp)
{
  (void)j, (void)branch, (void)cp;
  Bond *b = ctx;
  b->f = i == 0 ? force_on_i : tl_v3_scale(force_on_i, -1.0);
}

/* Two bonded particles (radius 0.01) at x = 0 and 0.0203, at rest, under
 * gravity, with w = 0.3 + 25 x: w_0 = 0.3, w_1 = 0.8075, the bond's
 * contact point at x = 0.01015 (the middle of the overlap) w_01 = 0.55375. */
static void test_two_particles(void)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  if (!dem) return;
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", 2500, 0.01, 0.01, &sp), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0, 0, 0), tl_v3(0, 0, 0), 0.01, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0.0203, 0, 0), tl_v3(0, 0, 0), 0.01, sp, NULL), TL_OK);
  add_bonded_law(dem, 1e5);
  TL_TEST_STATUS(tl_dem_add_bond(dem, P->id[0], P->id[1]), TL_OK);
  tl_dem_set_gravity(dem, tl_v3(0, -9.81, 0));
  tl_dem_set_weight_field(dem, weight_ramp, NULL);
  tl_dem_set_sort_interval(dem, 0);
  double dt = 1e-5;
  TL_TEST_STATUS(tl_dem_set_timestep(dem, dt, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  double m = P->mass[0], w[2] = {0.3, 0.3 + 25.0 * 0.0203}, wab = 0.3 + 25.0 * 0.01015;
  TL_TEST_CLOSE(P->weight[0], w[0], 1e-15);
  TL_TEST_CLOSE(P->weight[1], w[1], 1e-15);
  Bond b;
  TL_TEST_STATUS(tl_dem_visit_contacts(dem, grab, &b), TL_OK);
  TL_TEST_ASSERT(b.f.x > 0.0, "the stretched bond pulls particle 0 towards 1 (%g)", b.f.x);
  double err = 0.0;
  for (int i = 0; i < 2; ++i) {
    double sgn = i == 0 ? 1.0 : -1.0;
    TlVec3 expect = {sgn * wab * b.f.x, w[i] * m * -9.81 + sgn * wab * b.f.y, sgn * wab * b.f.z};
    err = fmax(err, tl_v3_norm(tl_v3_sub(P->f[i], expect)));
  }
  TL_TEST_ASSERT(err < 1e-14 * (fabs(b.f.x) + m * 9.81), "forces w_ab f_ab + w_a m g (off by %g)", err);
  /* one step: v = h f_0 / (w_0 m) + h f_1 / (w_1 m) with the weights of
   * each evaluation */
  TlVec3 f0[2] = {P->f[0], P->f[1]};
  double w0[2] = {P->weight[0], P->weight[1]};
  TL_TEST_STATUS(tl_dem_step(dem, 1), TL_OK);
  err = 0.0;
  double scale = 0.0;
  for (int i = 0; i < 2; ++i) {
    TlVec3 v = tl_v3_add(tl_v3_scale(f0[i], 0.5 * dt / (w0[i] * m)), tl_v3_scale(P->f[i], 0.5 * dt / (P->weight[i] * m)));
    err = fmax(err, tl_v3_norm(tl_v3_sub(P->v[i], v)));
    scale = fmax(scale, tl_v3_norm(v));
  }
  printf("two particles: forces and velocities as weighted, velocity error %.3g of %.3g\n", err, scale);
  TL_TEST_ASSERT(err < 1e-14 * scale, "weighted accelerations: velocities off by %g of %g", err, scale);
  /* the lighter-weighted particle accelerates more under the same bond */
  TL_TEST_ASSERT(P->v[0].x > 0 && P->v[1].x < 0 && P->v[0].x / -P->v[1].x > 2.0,
                 "w_0 < w_1: particle 0 moves %g times faster", P->v[0].x / -P->v[1].x);
  /* a weight field that reaches zero at a particle is refused */
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(-0.012, 0.5, 0), tl_v3(0, 0, 0), 0.01, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_step(dem, 1), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(strstr(tl_error_message(), "weight") != NULL, "message: %s", tl_error_message());
  tl_dem_destroy(&dem);
}

/* ---- the coupling force through the step hook, against the solid ---- */
typedef struct {
  TlVCoupling *vc;
  TlVCouplingElement *el;
  double *xp, *mp, *dup, *fp, *u0, *u1, *Fn;
  size_t nn;
  int calls;
} Coupled;

static TlStatus coupled_weights(void *ctx, size_t n, const TlVec3 *x, double *w)
{
  Coupled *c = ctx;
  return tl_vcoupling_point_weights(c->vc, n, (const double *)x, w);
}

/* After the drift: Pi at the new positions, the step's displacements
 * (dt v, and u1 - u0 for the solid, held still here), f^C into the
 * particles, F into Fn. */
static TlStatus coupled_hook(void *ctx, TlDem *dem)
{
  Coupled *c = ctx;
  TlParticles *P = tl_dem_particles(dem);
  double dt = tl_dem_timestep(dem);
  for (size_t a = 0; a < P->n; ++a) {
    c->xp[3 * a] = P->x[a].x, c->xp[3 * a + 1] = P->x[a].y, c->xp[3 * a + 2] = P->x[a].z;
    c->mp[a] = P->mass[a];
    c->dup[3 * a] = dt * P->v[a].x, c->dup[3 * a + 1] = dt * P->v[a].y, c->dup[3 * a + 2] = dt * P->v[a].z;
  }
  TL_CHECK(tl_vcoupling_update(c->vc, c->u1, P->n, c->xp, c->mp));
  TL_CHECK(tl_vcoupling_element_set_step(c->el, c->dup, c->u0));
  memset(P->f_coupling, 0, P->n * sizeof *P->f_coupling);
  TL_CHECK(tl_vcoupling_element_particle_forces(c->el, c->u1, (double *)P->f_coupling, NULL));
  memset(c->Fn, 0, 3 * c->nn * sizeof *c->Fn);
  TL_CHECK(tl_vcoupling_element_nodal_forces(c->el, c->u1, c->Fn));
  c->calls++;
  return TL_OK;
}

static void test_coupling_balance(void)
{
  size_t nc[3] = {2, 15, 2};
  double lo[3] = {0, 8, 0}, hi[3] = {0.8, 14, 0.8};
  TlMesh *mesh = NULL;
  TL_TEST_STATUS(tl_mesh_create_box(&tl_element_hex8, nc, lo, hi, &mesh), TL_OK);
  TlMaterial *mat = NULL;
  TL_TEST_STATUS(tl_material_create("hooke", &mat), TL_OK);
  tl_material_set(mat, "E", 1e8);
  tl_material_set(mat, "nu", 0.0);
  tl_material_set(mat, "density", 1309.0);
  TL_TEST_STATUS(tl_material_setup(mat), TL_OK);
  Coupled c = {0};
  TlVCouplingParams vp = {{1, 8.0, 12.0}, 0.0, "lucy", 1e8, 4, 0}; /* explicit-stable for w_a down to 1e-3 */
  TL_TEST_STATUS(tl_vcoupling_create(mesh, 0, &vp, &c.vc), TL_OK);
  TlSolid *solid = NULL;
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_vcoupling_element_create(c.vc, solid, &c.el), TL_OK);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  if (!c.vc || !c.el) return;
  /* particles: a bonded simple-cubic lattice, 8 per element, on y in [6, 12] */
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "g", 6 * 1309.0 / TL_PI, 0.1, 0.1, &sp), TL_OK);
  unsigned seed = 3u;
  bonded_lattice(dem, sp, (const int[3]){4, 30, 4}, tl_v3(0.1, 6.1, 0.1), 0.2, 0.1, tl_v3(0, 0.1, 0), 1e-3, &seed);
  add_bonded_law(dem, 1e8 * 0.2);
  TL_TEST_STATUS(tl_particles_enable_coupling_force(P), TL_OK);
  size_t np = P->n;
  c.nn = mesh->n_nodes;
  c.xp = calloc(3 * np, sizeof(double)), c.mp = calloc(np, sizeof(double)), c.dup = calloc(3 * np, sizeof(double));
  c.u0 = calloc(3 * c.nn, sizeof(double)), c.u1 = calloc(3 * c.nn, sizeof(double));
  c.Fn = calloc(3 * c.nn, sizeof(double));
  for (size_t k = 0; k < 3 * c.nn; ++k) c.u0[k] = 1e-5 * rnd(&seed), c.u1[k] = c.u0[k] + 1e-6 * rnd(&seed);
  for (size_t a = 0; a < np; ++a) {
    c.xp[3 * a] = P->x[a].x, c.xp[3 * a + 1] = P->x[a].y, c.xp[3 * a + 2] = P->x[a].z;
    c.mp[a] = P->mass[a];
  }
  TL_TEST_STATUS(tl_vcoupling_update(c.vc, c.u1, np, c.xp, c.mp), TL_OK);
  tl_dem_set_weight_field(dem, coupled_weights, &c);
  tl_dem_set_step_hook(dem, coupled_hook, &c);
  double dtc, k, m;
  TL_TEST_STATUS(tl_dem_critical_timestep(dem, &dtc, &k, &m), TL_OK);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 0.1 * dtc, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TL_TEST_STATUS(tl_dem_step(dem, 20), TL_OK);
  TL_TEST_ASSERT(c.calls == 20, "the step hook ran once per step (%d)", c.calls);
  /* Eq. 41: sum f^C = -sum F, and the particles' total force is f^C alone
   * (no gravity; bond forces cancel pairwise, weighted by w_ab on both) */
  double sc[3] = {0, 0, 0}, sf[3] = {0, 0, 0}, sn[3] = {0, 0, 0}, abs_n = 0.0, abs_f = 0.0;
  for (size_t a = 0; a < np; ++a) {
    const double *fc = &P->f_coupling[a].x, *f = &P->f[a].x;
    for (int d = 0; d < 3; ++d) sc[d] += fc[d], sf[d] += f[d], abs_f += fabs(f[d]);
  }
  for (size_t i = 0; i < 3 * c.nn; ++i) sn[i % 3] += c.Fn[i], abs_n += fabs(c.Fn[i]);
  double e41 = 0.0, etot = 0.0;
  for (int d = 0; d < 3; ++d) {
    e41 = fmax(e41, fabs(sc[d] + sn[d]));
    etot = fmax(etot, fabs(sf[d] - sc[d]));
  }
  printf("coupled: |sum f^C + sum F| = %.3g of sum |F| = %.3g; |sum f - sum f^C| = %.3g of %.3g\n", e41, abs_n, etot,
         abs_f);
  TL_TEST_ASSERT(abs_n > 0 && e41 < 1e-14 * abs_n, "Eq. 41 through the DEM: |sum f^C + sum F| = %g of %g", e41, abs_n);
  TL_TEST_ASSERT(etot < 1e-13 * abs_f, "the particles' total force is the coupling's (off by %g of %g)", etot, abs_f);
  /* weights: 1 on the particle side, falling across the zone */
  double wmin = 1.0, wmax = 0.0;
  for (size_t a = 0; a < np; ++a) wmin = fmin(wmin, P->weight[a]), wmax = fmax(wmax, P->weight[a]);
  TL_TEST_ASSERT(wmax == 1.0 && wmin > 0.0 && wmin < 0.01, "particle weights in [%g, %g]", wmin, wmax);
  tl_dem_destroy(&dem);
  tl_vcoupling_element_destroy(&c.el);
  tl_solid_destroy(&solid);
  tl_vcoupling_destroy(&c.vc);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
  free(c.xp), free(c.mp), free(c.dup), free(c.u0), free(c.u1), free(c.Fn);
}

int main(void)
{
  if (tl_initialize() != TL_OK) {
    fprintf(stderr, "%s\n", tl_error_message());
    return 1;
  }
  test_unit_weights();
  test_two_particles();
  test_coupling_balance();
  return tl_test_report();
}
