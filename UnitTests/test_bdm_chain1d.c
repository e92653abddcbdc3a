/* B-U2: the classical one-dimensional check of the bridging domain method
 * (Xiao & Belytschko): a bonded particle chain (linear springs k, spacing
 * d, mass m) coupled over one element to a 1-D-like hex8 bar of the
 * chain's long-wave properties (rho = m / d^3, E = k / d, nu = 0, lateral
 * components held), element size h = 4 d.  A right-going Gaussian pulse
 * u = A exp(-1/2 (2 pi (y - y0) / lambda)^2) (seeds/000 Eq. 15) starts in
 * the chain; when its reflection has left the overlap, the energy back in
 * the pure chain over the incident energy is the reflection coefficient R.
 * Checks, for lambda / h = 4, 8, 12, 20 with the consistent strong
 * constraint:
 *  - R falls as lambda / h grows (the bar resolves the pulse better);
 *  - the energy balance closes: chain + bar + energy the correction
 *    removed = initial energy, to the integrators' O(dt^2) error;
 *  - the correction never adds energy (consistent A), and the lumped A
 *    (row sum) removes more of the short pulse's energy than the
 *    consistent one (its dissipative treatment of what the bar cannot
 *    carry);
 *  - weighted momentum is unchanged by every correction;
 *  - the FE masses weighted at the mass points (-bdm_mass_weight
 *    quadrature) reflect and remove far less than the paper's nodal
 *    alpha(X_I) M_I, whose end node inside the chain weighs alpha_min M. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_bdm.h"
#include "tl_dem.h"
#include "tl_element.h"
#include "tl_material.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_test.h"
#include "tl_test_bdm.h"

#define D 0.01       /* particle spacing (m) */
#define K 1e5        /* bond stiffness (N/m) */
#define MASS 1e-3    /* particle mass (kg) */
#define H (4 * D)    /* element size */
#define AMP (1e-3 * D)

typedef struct {
  TlDem *dem;
  TlMesh *mesh;
  TlMaterial *mat;
  TlSolid *solid;
  TlStepper *st;
  TlBdm *bdm;
  double dt, s_dem, y0, lambda, c;
  long steps;
  int np;
} Chain;

static void chain_free(Chain *C)
{
  test_bdm_destroy(&C->bdm, &C->st, &C->solid, &C->mat, &C->mesh, &C->dem);
}

static TlStatus chain_build(Chain *C, double lambda_over_h, TlBdmLumping lump, TlBdmMassWeight mass)
{
  memset(C, 0, sizeof *C);
  C->lambda = lambda_over_h * H;
  const double s = C->lambda / (2.0 * TL_PI), margin = ceil((5.0 * s + 4.0 * D) / D) * D;
  C->c = D * sqrt(K / MASS);
  C->y0 = margin;
  C->s_dem = 2.0 * margin;
  C->np = (int)lround((C->s_dem + H) / D);
  /* particles at (j + 1/2) d on y in [0, s_dem + h] */
  TL_CHECK(tl_dem_create(&C->dem));
  TlDomain dom;
  TL_CHECK(tl_domain_init_open(&dom, tl_v3(-D, -D, -D), tl_v3(D, C->s_dem + 2 * H, D)));
  TL_CHECK(tl_dem_set_domain(C->dem, &dom));
  TlParticles *P = tl_dem_particles(C->dem);
  int sp;
  const double r = 0.5 * D, rho_g = MASS / (4.0 / 3.0 * TL_PI * r * r * r);
  TL_CHECK(tl_particles_add_species(P, "chain", rho_g, r, r, &sp));
  for (int j = 0; j < C->np; ++j) TL_CHECK(tl_dem_add_particle(C->dem, tl_v3(0.5 * D, (j + 0.5) * D, 0.5 * D), tl_v3(0, 0, 0), r, sp, NULL));
  for (int j = 0; j + 1 < C->np; ++j) TL_CHECK(tl_dem_add_bond(C->dem, j, j + 1));
  const TlContactValue kv[] = {{"k_n", K}};
  const TlContactSpec spec = {"bonded_linear", NULL, NULL, NULL, kv, 1};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TL_CHECK(tl_dem_add_law(C->dem, law, NULL));
  tl_dem_set_sort_interval(C->dem, 0);
  tl_dem_track_energy(C->dem, 1);
  C->dt = 0.05 * sqrt(MASS / K);
  TL_CHECK(tl_dem_set_timestep(C->dem, C->dt, 0));
  /* the bar from s_dem, long enough that the transmitted pulse never
   * comes back */
  size_t ne = (size_t)ceil((2.0 * margin + 6.0 * H) / H);
  size_t n[3] = {1, ne, 1};
  double lo[3] = {0, C->s_dem, 0}, hi[3] = {D, C->s_dem + (double)ne * H, D};
  TL_CHECK(tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &C->mesh));
  TL_CHECK(tl_material_create("hooke", &C->mat));
  TL_CHECK(tl_material_set(C->mat, "E", K / D));
  TL_CHECK(tl_material_set(C->mat, "nu", 0.0));
  TL_CHECK(tl_material_set(C->mat, "density", MASS / (D * D * D)));
  TL_CHECK(tl_material_setup(C->mat));
  TL_CHECK(tl_solid_create(C->mesh, &C->solid));
  TL_CHECK(tl_solid_set_material(C->solid, NULL, C->mat));
  TL_CHECK(tl_solid_fix(C->solid, "xmin", 1 | 4));
  TL_CHECK(tl_solid_fix(C->solid, "xmax", 1 | 4));
  TL_CHECK(tl_solid_fix(C->solid, "ymax", 2));
  TlBdmOptions o;
  tl_bdm_options_default(&o);
  o.lumping = lump;
  o.ghost = TL_BDM_GHOST_NONE;
  o.mass_weight = mass;
  const TlBdmZone zone = {1, C->s_dem, C->s_dem + H};
  TL_CHECK(test_bdm_couple(C->solid, C->dem, &zone, &o, &C->bdm, &C->st));
  /* the right-going pulse: u(y0 + ...) and v = -c du/dy */
  for (size_t i = 0; i < P->n; ++i) {
    double y = P->x[i].y, xi = 2.0 * TL_PI * (y - C->y0) / C->lambda;
    double u = AMP * exp(-0.5 * xi * xi), du = -u * xi * 2.0 * TL_PI / C->lambda;
    P->x[i].y += u;
    P->v[i].y = -C->c * du;
  }
  TL_CHECK(tl_dem_setup(C->dem));
  TL_CHECK(tl_bdm_setup(C->bdm, C->st));
  /* the reflection back at y0 when it has left the overlap */
  C->steps = (long)ceil(2.0 * (C->s_dem + 0.5 * H - C->y0) / C->c / C->dt);
  return TL_OK;
}

/* Energy of the pure chain left of the overlap (weights 1 there). */
static double chain_energy_left(const Chain *C, double y_max)
{
  const TlParticles *P = tl_dem_particles(C->dem);
  double E = 0.0;
  for (size_t i = 0; i < P->n; ++i) {
    if (P->x[i].y > y_max) continue;
    E += 0.5 * P->mass[i] * tl_v3_norm2(P->v[i]);
  }
  /* bonds j, j + 1 (indices are the lattice order: no sorting) */
  for (size_t i = 0; i + 1 < P->n; ++i) {
    if (P->x[i + 1].y > y_max) continue;
    double delta = 2.0 * P->radius[i] - tl_v3_norm(tl_v3_sub(P->x[i + 1], P->x[i]));
    E += 0.5 * K * delta * delta;
  }
  return E;
}

static TlStatus total_energy(Chain *C, double *E)
{
  TlDemEnergy de;
  TL_CHECK(tl_dem_energy(C->dem, &de));
  TlEnergies fe;
  TL_CHECK(tl_stepper_energies(C->st, &fe));
  *E = de.kinetic_translational + de.elastic + fe.kinetic + fe.strain - fe.external_work;
  return TL_OK;
}

typedef struct {
  double R, balance, removed, min_step_removed, momentum;
} Result;

static void run(double loh, TlBdmLumping lump, TlBdmMassWeight mass, Result *res)
{
  Chain C;
  res->R = res->balance = res->removed = NAN;
  TlStatus s = chain_build(&C, loh, lump, mass);
  TL_TEST_STATUS(s, TL_OK);
  double E0 = NAN, E1 = NAN, Ei = NAN, minr = INFINITY, pmax = 0.0;
  if (s == TL_OK) {
    s = total_energy(&C, &E0);
    Ei = chain_energy_left(&C, C.s_dem);
  }
  TlBdmReport rep;
  memset(&rep, 0, sizeof rep);
  for (long k = 0; k < C.steps && s == TL_OK; ++k) {
    s = tl_dem_step(C.dem, 1);
    if (s == TL_OK) s = tl_stepper_step(C.st, C.dt);
    if (s == TL_OK) s = tl_bdm_correct(C.bdm, &rep);
    minr = fmin(minr, rep.energy_removed);
    double ps = fabs(rep.momentum_change[1]) / (MASS * C.c * AMP / D);
    pmax = ps > pmax || ps != ps ? ps : pmax;
  }
  TL_TEST_STATUS(s, TL_OK);
  if (s == TL_OK) s = total_energy(&C, &E1);
  if (s == TL_OK) {
    double Er = chain_energy_left(&C, C.s_dem - 2.0 * D);
    res->R = Er / Ei;
    res->removed = rep.energy_removed_total / E0;
    res->balance = (E1 + rep.energy_removed_total - E0) / E0;
    res->min_step_removed = minr / E0;
    res->momentum = pmax;
    printf("lambda/h = %4.1f, A %-6s, FE masses %-10s: %ld steps, R = E_reflected / E_incident = %.4e, removed by the correction "
           "%.4e E0, energy balance (chain + bar + removed - E0) / E0 = %+.3e, smallest step removal %.2e E0, "
           "momentum change per step %.2e of the pulse's\n",
           loh, tl_bdm_lumping_name(lump), mass == TL_BDM_MASS_NODAL ? "nodal" : "quadrature", C.steps, res->R, res->removed, res->balance, res->min_step_removed, pmax);
  }
  chain_free(&C);
}

int main(void)
{
  if (tl_initialize() != TL_OK) {
    fprintf(stderr, "%s\n", tl_error_message());
    return 1;
  }
  const double loh[4] = {4, 8, 12, 20};
  Result r[4], lumped, quad[2];
  for (int k = 0; k < 4; ++k) {
    run(loh[k], TL_BDM_LUMP_NONE, TL_BDM_MASS_NODAL, &r[k]);
    TL_TEST_ASSERT(fabs(r[k].balance) <= 2e-4, "lambda/h = %g: energy balance off by %.3e of E0", loh[k], r[k].balance);
    TL_TEST_ASSERT(r[k].min_step_removed >= -1e-15, "lambda/h = %g: a consistent correction added %.3e E0", loh[k],
                   -r[k].min_step_removed);
    TL_TEST_ASSERT(r[k].momentum <= 1e-12, "lambda/h = %g: momentum changed by %.3e", loh[k], r[k].momentum);
  }
  for (int k = 1; k < 4; ++k)
    TL_TEST_ASSERT(r[k].R < r[k - 1].R, "reflection does not fall: R(%g) = %.4e, R(%g) = %.4e", loh[k - 1],
                   r[k - 1].R, loh[k], r[k].R);
  TL_TEST_ASSERT(r[0].R > 0.1 && r[3].R < 0.05, "reflection range R(4) = %.3e, R(20) = %.3e", r[0].R, r[3].R);
  /* the lumped A dissipates what the bar cannot carry: more energy removed,
   * less reflected */
  run(4, TL_BDM_LUMP_ROWSUM, TL_BDM_MASS_NODAL, &lumped);
  TL_TEST_ASSERT(fabs(lumped.balance) <= 2e-4, "lumped: energy balance off by %.3e of E0", lumped.balance);
  TL_TEST_ASSERT(lumped.removed > r[0].removed && lumped.R < r[0].R,
                 "lumped A removed %.3e E0 and reflected %.3e; consistent %.3e E0 and %.3e", lumped.removed, lumped.R,
                 r[0].removed, r[0].R);
  TL_TEST_ASSERT(lumped.momentum <= 1e-12, "lumped: momentum changed by %.3e", lumped.momentum);
  /* the FE masses weighted at the mass points, like its stiffness, leave
   * no light node (alpha_min M) at the bar's end inside the chain: a
   * weighted node that light rings against its own stiffness every step
   * and the correction takes that energy out */
  run(4, TL_BDM_LUMP_NONE, TL_BDM_MASS_QUADRATURE, &quad[0]);
  run(20, TL_BDM_LUMP_NONE, TL_BDM_MASS_QUADRATURE, &quad[1]);
  TL_TEST_ASSERT(fabs(quad[1].balance) <= 2e-4, "quadrature masses: energy balance off by %.3e", quad[1].balance);
  TL_TEST_ASSERT(quad[1].R < quad[0].R && quad[1].R < 0.1 * r[3].R && quad[1].removed < r[3].removed,
                 "quadrature masses at lambda/h = 20: R = %.3e (nodal %.3e), removed %.3e E0 (nodal %.3e)", quad[1].R,
                 r[3].R, quad[1].removed, r[3].removed);
  return tl_test_report();
}
