/* B-U3: ghost forces of a pre-stressed overlap and their removal
 * (seeds/000 §4.2).  A bonded FCC lattice (central linear springs, every
 * nearest-neighbour bond compressed by the strain eps, so the lattice
 * holds the pressure p = 4 k eps / a) fills y in [0, 8a], periodic in x
 * and z (4a x 4a), its first plane held; a hex8 bar of the lattice's
 * moduli (K = 4k/3a and the P-wave modulus C11 = 2k/a: E = 4k/3a,
 * nu = 1/3) with the matching eigenstrain (S = -3K eps = -p) overlaps it
 * on the bridging zone y in [6a, 8a] (one element, h = 2a), its far end
 * and lateral faces on rollers.  At rest:
 *  - without the ghost-force correction the section displacement of the
 *    bar two elements past the zone drifts above 1e-8 a (strong and weak),
 *    the weak constraint more than the strong one;
 *  - with it (FE nodes and particles) the coupled system stays at rest to
 *    round-off (below 1e-12 a), strong and weak;
 *  - the recorded ghost forces are balanced: the FE's sum equals minus the
 *    particles' (the overlap as a whole is in equilibrium);
 *  - a coupled run saved half-way and restarted continues bit for bit. */
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

#define A_CELL 0.01   /* FCC cell (m) */
#define NX 4          /* cells across x and z */
#define NY 8          /* cells along y (DEM) */
#define K_BOND 1e5    /* N/m */
#define EPS 1e-3      /* bond compression strain */
#define RHO_G 2500.0  /* grain density */
#define N_FE 10       /* elements along y */

typedef struct {
  TlDem *dem;
  TlMesh *mesh;
  TlMaterial *mat;
  TlSolid *solid;
  TlStepper *st;
  TlBdm *bdm;
  double dt;
  size_t n_mon;
  size_t mon[64];
} Scene;

static void scene_free(Scene *S)
{
  test_bdm_destroy(&S->bdm, &S->st, &S->solid, &S->mat, &S->mesh, &S->dem);
}

/* FCC positions with y in [0, NY a]: basis (0,0,0), (1/2,1/2,0),
 * (1/2,0,1/2), (0,1/2,1/2); periodic in x and z. */
static TlStatus build_dem(Scene *S)
{
  const double a = A_CELL, l = a / sqrt(2.0), r = 0.5 * l * (1.0 + EPS);
  TL_CHECK(tl_dem_create(&S->dem));
  TlDomain dom;
  int per[3] = {1, 0, 1};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(0, -a, 0), tl_v3(NX * a, (NY + 1) * a, NX * a), per));
  TL_CHECK(tl_dem_set_domain(S->dem, &dom));
  TlParticles *P = tl_dem_particles(S->dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "grains", RHO_G, r, r, &sp));
  static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  for (int j = 0; j <= NY; ++j)
    for (int k = 0; k < NX; ++k)
      for (int i = 0; i < NX; ++i)
        for (int b = 0; b < 4; ++b) {
          double y = (j + basis[b][1]) * a;
          if (y > NY * a + 1e-12) continue;
          size_t idx;
          TL_CHECK(tl_dem_add_particle(S->dem, tl_v3((i + basis[b][0]) * a, y, (k + basis[b][2]) * a), tl_v3(0, 0, 0),
                                       r, sp, &idx));
          if (j == 0 && basis[b][1] == 0.0) TL_CHECK(tl_particles_set_motion(P, idx, TL_MOTION_FIXED));
        }
  /* nearest-neighbour bonds (periodic images in x and z) */
  const TlDomain *D = tl_dem_domain(S->dem);
  for (size_t p = 0; p < P->n; ++p)
    for (size_t q = p + 1; q < P->n; ++q) {
      TlVec3 bv = tl_domain_branch(D, P->x[p], P->x[q]);
      if (fabs(tl_v3_norm(bv) - l) < 1e-6 * l) TL_CHECK(tl_dem_add_bond(S->dem, P->id[p], P->id[q]));
    }
  const TlContactValue kv[] = {{"k_n", K_BOND}};
  const TlContactSpec spec = {"bonded_linear", NULL, NULL, NULL, kv, 1};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TL_CHECK(tl_dem_add_law(S->dem, law, NULL));
  const double m = RHO_G * 4.0 / 3.0 * TL_PI * r * r * r;
  S->dt = 0.02 * sqrt(m / K_BOND);
  TL_CHECK(tl_dem_set_timestep(S->dem, S->dt, 0));
  return TL_OK;
}

/* The bar on y in [6a, 6a + N_FE 2a], 2 x 2 elements across. */
static TlStatus build_fe(Scene *S)
{
  const double a = A_CELL, h = 2.0 * a;
  size_t n[3] = {NX / 2, N_FE, NX / 2};
  double lo[3] = {0, (NY - 2) * a, 0}, hi[3] = {NX * a, (NY - 2) * a + N_FE * h, NX * a};
  TL_CHECK(tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &S->mesh));
  const double r = 0.5 * a / sqrt(2.0) * (1.0 + EPS), m = RHO_G * 4.0 / 3.0 * TL_PI * r * r * r;
  TL_CHECK(tl_material_create("hooke", &S->mat));
  TL_CHECK(tl_material_set(S->mat, "E", 4.0 * K_BOND / (3.0 * a)));
  TL_CHECK(tl_material_set(S->mat, "nu", 1.0 / 3.0));
  TL_CHECK(tl_material_set(S->mat, "density", 4.0 * m / (a * a * a)));
  TL_CHECK(tl_material_set_eigenstrain(S->mat, tl_m3_scale(tl_m3_identity(), EPS)));
  TL_CHECK(tl_material_setup(S->mat));
  TL_CHECK(tl_solid_create(S->mesh, &S->solid));
  TL_CHECK(tl_solid_set_material(S->solid, NULL, S->mat));
  TL_CHECK(tl_solid_fix(S->solid, "ymax", 2));
  TL_CHECK(tl_solid_fix(S->solid, "xmin", 1));
  TL_CHECK(tl_solid_fix(S->solid, "xmax", 1));
  TL_CHECK(tl_solid_fix(S->solid, "zmin", 4));
  TL_CHECK(tl_solid_fix(S->solid, "zmax", 4));
  const double ymon = NY * a + 2.0 * h;
  S->n_mon = 0;
  for (size_t I = 0; I < S->mesh->n_nodes; ++I)
    if (fabs(S->mesh->x[3 * I + 1] - ymon) < 1e-9 && S->n_mon < 64) S->mon[S->n_mon++] = I;
  return TL_OK;
}

static TlStatus scene_build(Scene *S, TlBdmConstraint c, TlBdmGhost g)
{
  memset(S, 0, sizeof *S);
  TL_CHECK(build_dem(S));
  TL_CHECK(build_fe(S));
  TlBdmOptions o;
  tl_bdm_options_default(&o);
  o.constraint = c;
  o.ghost = g;
  const TlBdmZone zone = {1, (NY - 2) * A_CELL, NY * A_CELL};
  TL_CHECK(test_bdm_couple(S->solid, S->dem, &zone, &o, &S->bdm, &S->st));
  TL_CHECK(tl_dem_setup(S->dem));
  TL_CHECK(tl_bdm_setup(S->bdm, S->st));
  return TL_OK;
}

static TlStatus scene_step(Scene *S, TlBdmReport *rep)
{
  TL_CHECK(tl_dem_step(S->dem, 1));
  TL_CHECK(tl_stepper_step(S->st, S->dt));
  TL_CHECK(tl_bdm_correct(S->bdm, rep));
  return TL_OK;
}

/* |mean u| over the monitored node plane, in cell sizes. */
static double section_displacement(const Scene *S)
{
  double u[3] = {0, 0, 0};
  for (size_t k = 0; k < S->n_mon; ++k)
    for (int c = 0; c < 3; ++c) {
      TlSparseIndex J = tl_solid_dof(S->solid, S->mon[k], c);
      if (J >= 0) u[c] += S->st->u[J] / (double)S->n_mon;
    }
  return sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) / A_CELL;
}

/* max over the run of the section displacement and of the particles'
 * largest displacement, both in cell sizes. */
static void run_rest(TlBdmConstraint c, TlBdmGhost g, long steps, double *sec, double *part, double *rate)
{
  Scene S;
  *sec = *part = *rate = NAN;
  TlStatus s = scene_build(&S, c, g);
  TL_TEST_STATUS(s, TL_OK);
  if (s != TL_OK) {
    scene_free(&S);
    return;
  }
  const TlParticles *P = tl_dem_particles(S.dem);
  TlVec3 *x0 = calloc(P->n, sizeof *x0);
  int64_t *id0 = calloc(P->n, sizeof *id0);
  size_t n = P->n;
  for (size_t i = 0; i < n; ++i) {
    x0[i] = P->x[i];
    id0[i] = P->id[i];
  }
  double smax = 0.0, pmax = 0.0, rmax = 0.0;
  for (long k = 0; k < steps && s == TL_OK; ++k) {
    TlBdmReport rep;
    s = scene_step(&S, &rep);
    double d = section_displacement(&S);
    smax = d > smax || d != d ? d : smax;
    rmax = fmax(rmax, rep.rate_after);
  }
  TL_TEST_STATUS(s, TL_OK);
  for (size_t i = 0; i < n; ++i) {
    size_t j;
    if (tl_particles_find(P, id0[i], &j) != TL_OK) continue;
    double d = tl_v3_norm(tl_domain_branch(tl_dem_domain(S.dem), x0[i], P->x[j])) / A_CELL;
    pmax = d > pmax || d != d ? d : pmax;
  }
  free(x0);
  free(id0);
  *sec = smax;
  *part = pmax;
  *rate = rmax;
  scene_free(&S);
}

static void check_rest(void)
{
  const long steps = 3000;
  const char *cn[2] = {"strong", "weak"};
  double sec[2][2], part[2][2], rate[2][2];
  for (int c = 0; c < 2; ++c)
    for (int g = 0; g < 2; ++g) {
      run_rest((TlBdmConstraint)c, g ? TL_BDM_GHOST_BOTH : TL_BDM_GHOST_NONE, steps, &sec[c][g], &part[c][g],
               &rate[c][g]);
      printf("%s, ghost-force correction %s: %ld steps, max section displacement %.3e a, max particle displacement "
             "%.3e a, max constraint rate after correction %.3e m/s\n",
             cn[c], g ? "on (fe + particles)" : "off", steps, sec[c][g], part[c][g], rate[c][g]);
    }
  for (int c = 0; c < 2; ++c) {
    TL_TEST_ASSERT(sec[c][0] > 1e-8, "%s without correction: the section drifts only %.3e a (ghost forces expected)",
                   cn[c], sec[c][0]);
    TL_TEST_ASSERT(sec[c][1] < 1e-12, "%s with correction: section displacement %.3e a, not round-off", cn[c],
                   sec[c][1]);
    TL_TEST_ASSERT(part[c][1] < 1e-12, "%s with correction: particles moved %.3e a", cn[c], part[c][1]);
  }
  TL_TEST_ASSERT(sec[0][0] < sec[1][0], "without correction strong (%.3e a) should drift less than weak (%.3e a)",
                 sec[0][0], sec[1][0]);
  /* one model's initial forces alone: the other's unbalance is then
   * nobody's (the overlap as a whole was balanced, see the ghost balance) */
  double one[2], pp, rr;
  const TlBdmGhost scope[2] = {TL_BDM_GHOST_FE, TL_BDM_GHOST_DEM};
  for (int k = 0; k < 2; ++k) {
    run_rest(TL_BDM_STRONG, scope[k], steps / 3, &one[k], &pp, &rr);
    printf("strong, ghost-force correction %s only, %ld steps: max section displacement %.3e a, max particle displacement %.3e "
           "a\n", tl_bdm_ghost_name(scope[k]), steps / 3, one[k], pp);
    TL_TEST_ASSERT(one[k] > 1e6 * sec[0][1], "%s alone: %.3e a, not far above both's %.3e a",
                   tl_bdm_ghost_name(scope[k]), one[k], sec[0][1]);
  }
}

/* The recorded ghost forces: the FE's and the particles' balance (the
 * overlap as a whole carries no net force at the onset). */
static void check_ghost_balance(void)
{
  Scene S;
  TlStatus s = scene_build(&S, TL_BDM_STRONG, TL_BDM_GHOST_BOTH);
  TL_TEST_STATUS(s, TL_OK);
  if (s == TL_OK) {
    const double *gf = tl_bdm_ghost_fe(S.bdm), *gd = tl_bdm_ghost_dem(S.bdm);
    TlBdmInfo info;
    tl_bdm_info(S.bdm, &info);
    TL_TEST_ASSERT(gf && gd, "ghost forces not recorded");
    double fe = 0.0, dem = 0.0, fe_abs = 0.0;
    for (size_t I = 0; gf && I < S.mesh->n_nodes; ++I) {
      fe += gf[3 * I + 1];
      fe_abs += fabs(gf[3 * I + 1]);
    }
    for (size_t k = 0; gd && k < info.n_ghost_particles; ++k) dem += gd[3 * k + 1];
    /* ghost_fe is the internal force subtracted: the initial net force on
     * the FE is -ghost_fe; on the particles +ghost_dem */
    double p = 4.0 * K_BOND * EPS / A_CELL, area = NX * A_CELL * NX * A_CELL;
    printf("coupled particles %zu, ghost-force particles %zu, constraints %zu, FE dofs %zu; initial y forces: FE %.6e N, particles %.6e N "
           "(p A = %.6e N)\n", info.n_particles, info.n_ghost_particles, info.n_constraints, info.n_dofs, -fe, dem, p * area);
    TL_TEST_ASSERT(fe_abs > 1e-3 * p * area, "the FE's ghost forces %.3e N are negligible", fe_abs);
    TL_TEST_ASSERT(fabs(-fe + dem) < 0.05 * p * area, "initial forces FE %.6e and particles %.6e N do not balance",
                   -fe, dem);
  }
  scene_free(&S);
}

/* Save at step 100, restart from it, compare step 200 bit for bit: the
 * world, the bar's stepper and the coupling in one checkpoint, saved
 * (saving = 1) or loaded. */
static TlStatus checkpoint(Scene *S, const char *path, int saving)
{
  TlCheckpoint *cp = NULL;
  TL_CHECK(tl_checkpoint_create(&cp));
  TlStatus s = tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, S->dem);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "fe", &tl_stepper_checkpoint_ops, S->st);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "bdm", &tl_bdm_checkpoint_ops, S->bdm);
  if (s == TL_OK)
    s = saving ? tl_checkpoint_save(cp, path, tl_dem_time(S->dem), 100) : tl_checkpoint_load(cp, path, NULL, NULL);
  tl_checkpoint_destroy(&cp);
  return s;
}

static void kick(Scene *S)
{
  /* a velocity field so that the restart has something to reproduce */
  TlParticles *P = tl_dem_particles(S->dem);
  for (size_t i = 0; i < P->n; ++i)
    if (P->motion[i] == TL_MOTION_FREE) P->v[i].y = 1e-3 * sin(37.0 * P->x[i].y / A_CELL + P->x[i].x / A_CELL);
}

static void check_restart(void)
{
  Scene A, B;
  TlStatus s = scene_build(&A, TL_BDM_STRONG, TL_BDM_GHOST_BOTH);
  TL_TEST_STATUS(s, TL_OK);
  if (s == TL_OK) {
    kick(&A);
    TlBdmReport ra, rb;
    for (int k = 0; k < 100 && s == TL_OK; ++k) s = scene_step(&A, &ra);
    if (s == TL_OK) s = checkpoint(&A, "bdm_restart.h5", 1);
    TL_TEST_STATUS(s, TL_OK);
    for (int k = 0; k < 100 && s == TL_OK; ++k) s = scene_step(&A, &ra);
    TlStatus sb = scene_build(&B, TL_BDM_STRONG, TL_BDM_GHOST_BOTH);
    if (sb == TL_OK) sb = checkpoint(&B, "bdm_restart.h5", 0);
    TL_TEST_STATUS(sb, TL_OK);
    /* the restarted run asks for no report: the last one is computed on
     * demand from the state and must equal the continuous run's */
    for (int k = 0; k < 100 && sb == TL_OK; ++k) {
      sb = tl_dem_step(B.dem, 1);
      if (sb == TL_OK) sb = tl_stepper_step(B.st, B.dt);
      if (sb == TL_OK) sb = tl_bdm_correct(B.bdm, NULL);
    }
    TL_TEST_STATUS(sb, TL_OK);
    if (sb == TL_OK) {
      tl_bdm_last_report(B.bdm, &rb);
      TL_TEST_ASSERT(rb.rate_after == ra.rate_after && rb.residual_max == ra.residual_max &&
                         rb.residual_rms == ra.residual_rms && rb.momentum[1] == ra.momentum[1] &&
                         rb.energy_removed == ra.energy_removed && rb.rate_before == ra.rate_before,
                     "report on demand differs: rate %.17g / %.17g, residual %.17g / %.17g", rb.rate_after,
                     ra.rate_after, rb.residual_max, ra.residual_max);
    }
    if (s == TL_OK && sb == TL_OK) {
      const TlParticles *PA = tl_dem_particles(A.dem), *PB = tl_dem_particles(B.dem);
      int same = PA->n == PB->n && !memcmp(PA->x, PB->x, PA->n * sizeof *PA->x) &&
                 !memcmp(PA->v, PB->v, PA->n * sizeof *PA->v);
      same = same && !memcmp(A.st->u, B.st->u, (size_t)A.st->n * sizeof(double)) &&
             !memcmp(A.st->v, B.st->v, (size_t)A.st->n * sizeof(double));
      printf("restart at step 100: step 200 %s; removed energy %.17g / %.17g J, steps %ld / %ld\n",
             same ? "identical bit for bit" : "DIFFERS", ra.energy_removed_total, rb.energy_removed_total, ra.step,
             rb.step);
      TL_TEST_ASSERT(same, "the restarted coupled run differs from the continuous one");
      TL_TEST_ASSERT(ra.energy_removed_total == rb.energy_removed_total && ra.step == rb.step,
                     "coupling counters differ after the restart");
      TL_TEST_ASSERT(ra.energy_removed_total > 0.0, "the kicked run removed no energy (%.3e J)",
                     ra.energy_removed_total);
    }
    /* a coupling of another kind refuses the checkpoint */
    Scene C;
    TlStatus sc = scene_build(&C, TL_BDM_WEAK, TL_BDM_GHOST_BOTH);
    if (sc == TL_OK) {
      TlStatus sl = checkpoint(&C, "bdm_restart.h5", 0);
      TL_TEST_ASSERT(sl == TL_ERR_ARG && strstr(tl_error_message(), "constraint"),
                     "weak coupling loading a strong checkpoint: status %d, %s", (int)sl, tl_error_message());
    }
    scene_free(&C);
    scene_free(&B);
  }
  scene_free(&A);
}

static void check_refusals(void)
{
  Scene S;
  memset(&S, 0, sizeof S);
  TlStatus s = build_dem(&S);
  if (s == TL_OK) s = build_fe(&S);
  TL_TEST_STATUS(s, TL_OK);
  if (s == TL_OK) {
    TlBdmOptions o;
    tl_bdm_options_default(&o);
    const TlBdmZone zone = {1, (NY - 2) * A_CELL, NY * A_CELL};
    o.alpha_min = 0.0;
    TL_TEST_STATUS(tl_bdm_create(S.solid, 0, S.dem, &zone, 1, &o, &S.bdm), TL_ERR_ARG);
    TL_TEST_ASSERT(strstr(tl_error_message(), "alpha_min = 0") != NULL, "message: %s", tl_error_message());
    tl_bdm_options_default(&o);
    const TlBdmZone bad = {3, 0.0, 1.0};
    TL_TEST_STATUS(tl_bdm_create(S.solid, 0, S.dem, &bad, 1, &o, &S.bdm), TL_ERR_ARG);
    const TlBdmZone two[2] = {zone, {1, 7.5 * A_CELL, 9 * A_CELL}};
    TL_TEST_STATUS(tl_bdm_create(S.solid, 0, S.dem, two, 2, &o, &S.bdm), TL_ERR_ARG);
    TL_TEST_ASSERT(strstr(tl_error_message(), "overlap") != NULL, "message: %s", tl_error_message());
    /* a zone that leaves FE nodes on its DEM side: their mass would vanish */
    const TlBdmZone inside = {1, (NY - 1) * A_CELL, NY * A_CELL};
    TL_TEST_STATUS(tl_bdm_create(S.solid, 0, S.dem, &inside, 1, &o, &S.bdm), TL_ERR_ARG);
    TL_TEST_ASSERT(strstr(tl_error_message(), "DEM side") != NULL, "message: %s", tl_error_message());
    /* a zone whose FE side ends inside the lattice: particles beyond it
     * would weigh nothing */
    const TlBdmZone short_zone = {1, (NY - 2) * A_CELL, (NY - 1) * A_CELL};
    TL_TEST_STATUS(tl_bdm_create(S.solid, 0, S.dem, &short_zone, 1, &o, &S.bdm), TL_ERR_ARG);
    TL_TEST_ASSERT(strstr(tl_error_message(), "FE side") != NULL, "message: %s", tl_error_message());
    o.jacobi = 3;
    o.lumping = TL_BDM_LUMP_NONE;
    TL_TEST_STATUS(tl_bdm_create(S.solid, 0, S.dem, &zone, 1, &o, &S.bdm), TL_ERR_ARG);
    TL_TEST_ASSERT(S.bdm == NULL, "a refused coupling was returned");
  }
  scene_free(&S);
}

/* The options database and the registry entry. */
static void check_options(void)
{
  const TlTypeEntry *e = NULL;
  TL_TEST_STATUS(tl_registry_lookup("coupling", "bdm", &e), TL_OK);
  TlBdmOptions o;
  tl_bdm_options_default(&o);
  if (e) {
    const TlParam *p = tl_param_find(e->params, e->n_params, "alpha_min");
    TL_TEST_ASSERT(p && p->def == o.alpha_min, "registry alpha_min default differs from the options' %g", o.alpha_min);
  }
  char *good[] = {"prog", "-bdm", "weak", "-bdm_alpha", "cosine", "-ghost_force", "both", "-bdm_alpha_min", "0.01", NULL};
  TlOptions *db = NULL;
  TL_TEST_STATUS(tl_options_create(9, good, "test", &db), TL_OK);
  if (db) {
    TL_TEST_STATUS(tl_bdm_options_from_db(db, &o), TL_OK);
    TL_TEST_ASSERT(o.constraint == TL_BDM_WEAK && o.profile == TL_BDM_ALPHA_COSINE && o.ghost == TL_BDM_GHOST_BOTH &&
                       o.alpha_min == 0.01 && o.lumping == TL_BDM_LUMP_ROWSUM,
                   "options read: %d %d %d %g %d", (int)o.constraint, (int)o.profile, (int)o.ghost, o.alpha_min,
                   (int)o.lumping);
    TL_TEST_STATUS(tl_options_finish(db, stdout), TL_OK);
  }
  tl_options_destroy(&db);
  char *bad[] = {"prog", "-bdm", "medium", NULL};
  TL_TEST_STATUS(tl_options_create(3, bad, "test", &db), TL_OK);
  if (db) {
    tl_bdm_options_default(&o);
    TL_TEST_STATUS(tl_bdm_options_from_db(db, &o), TL_ERR_ARG);
    TL_TEST_ASSERT(strstr(tl_error_message(), "medium") != NULL, "message: %s", tl_error_message());
  }
  tl_options_destroy(&db);
  char *sweeps[] = {"prog", "-bdm_lumped", "none", "-bdm_jacobi", "4", NULL};
  TL_TEST_STATUS(tl_options_create(5, sweeps, "test", &db), TL_OK);
  if (db) {
    tl_bdm_options_default(&o);
    TL_TEST_STATUS(tl_bdm_options_from_db(db, &o), TL_ERR_ARG);
    TL_TEST_ASSERT(strstr(tl_error_message(), "Jacobi") != NULL, "message: %s", tl_error_message());
  }
  tl_options_destroy(&db);
}

int main(void)
{
  if (tl_initialize() != TL_OK) {
    fprintf(stderr, "%s\n", tl_error_message());
    return 1;
  }
  check_options();
  check_refusals();
  check_ghost_balance();
  check_rest();
  check_restart();
  return tl_test_report();
}
