/* Checkpoint and restart of DEM runs: N steps in one go against N/2 steps,
 * a checkpoint, a fresh world built the same way, a load and N/2 more steps.
 * Positions, velocities, forces, spins, orientations, torques, ids, energy
 * bookkeeping, wall forces and counters must agree bit for bit (memcmp) for
 * (a) a frictional Hertz packing with rolling resistance on a plane floor,
 *     with a prescribed particle ploughing through it,
 * (b) frictional spheres on a triangulated floor (edge corrections on),
 * (c) a frictional packing in a periodic cell under compression and shear.
 * The neighbour list is rebuilt, and particles renumbered, several times in
 * each half, so a restart between rebuilds is exercised.
 *
 * The same scenes also check tl_dem_visit_wall_contacts (what the coarse-
 * graining reads): the visited forces sum to minus the wall's force, their
 * count is the wall's, and contact points lie on the floor. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_checkpoint.h"
#include "tl_dem.h"
#include "tl_test.h"
#include "tl_test_dem.h"
#include "tl_wall_trisurface.h"

enum { SCENE_HERTZ_PLANE, SCENE_TRISURFACE, SCENE_CELL, N_SCENES };
static const char *scene_name[N_SCENES] = {"hertz_plane", "trisurface", "cell"};

static double urand(uint64_t *s) { return tl_random_uniform(s); }

/* The plough: moves along x at constant speed from where it was attached. */
static TlStatus plough(void *ctx, double t, size_t n, const int64_t *id, const TlVec3 *x0, TlVec3 *x, TlVec3 *v)
{
  (void)ctx;
  (void)id;
  for (size_t k = 0; k < n; ++k) {
    v[k] = tl_v3(0.05, 0, 0);
    x[k] = tl_v3_axpy(x0[k], t, v[k]);
  }
  return TL_OK;
}

static TlStatus build_column(TlDem *dem, double L, int hertz)
{
  const TlTestColumn column = {.L = L, .n = 125, .r_min = 0.0014, .r_max = 0.0016, .z0 = 0.0017, .dz = 0.0033,
                               .v_jitter = 0.2, .v_z = -0.1, .seed = 77};
  TL_CHECK(tl_test_dem_column(dem, &column, NULL));
  TlContactLaw *law = NULL;
  if (hertz) {
    TL_CHECK(tl_test_law(&law, "hertz", "E", 5e6, "nu", 0.3, "gamma_n", 5e3, "mu", 0.5, "mu_roll", 0.05, NULL));
  } else {
    TL_CHECK(tl_test_law(&law, "linear", "k_n", 200.0, "restitution", 0.3, "mu", 0.4, NULL));
  }
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  return TL_OK;
}

static TlStatus build(int scene, TlDem **out)
{
  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  const double L = 0.02;
  if (scene == SCENE_HERTZ_PLANE) {
    TL_CHECK(build_column(dem, L, 1));
    TlWall *floor_ = NULL;
    TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &floor_));
    TL_CHECK(tl_dem_add_wall(dem, floor_, 0));
    int64_t id = 37; /* a particle of the second layer */
    TL_CHECK(tl_dem_prescribe(dem, 1, &id, plough, NULL));
    TL_CHECK(tl_dem_set_timestep(dem, 2e-5, 0));
  } else if (scene == SCENE_TRISURFACE) {
    TL_CHECK(build_column(dem, L, 0));
    TlTriSurface *s = NULL;
    TL_CHECK(tl_trisurface_create_rectangle(0, 0, L, L, 0, 7, 7, 2, &s));
    size_t linked = 0;
    TL_CHECK(tl_trisurface_link_periodic(s, &tl_dem_domain(dem)[0], 1e-9, &linked));
    TlWall *floor_ = NULL;
    TL_CHECK(tl_wall_trisurface_create(s, &floor_));
    TL_CHECK(tl_wall_trisurface_set_corrections(floor_, 1));
    TL_CHECK(tl_dem_add_wall(dem, floor_, 0));
    TL_CHECK(tl_dem_set_timestep(dem, 4e-5, 0));
  } else {
    /* fcc crystal, slightly compressed, in a cell sheared and compressed */
    const int m = 3;
    const double a = 0.01, d = a / sqrt(2.0);
    static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    TlDomain dom;
    TlMat3 h0 = tl_m3_scale(tl_m3_identity(), m * a);
    TL_CHECK(tl_domain_init_cell(&dom, tl_v3(0, 0, 0), h0));
    TL_CHECK(tl_dem_set_domain(dem, &dom));
    TlParticles *P = tl_dem_particles(dem);
    int sp;
    TL_CHECK(tl_particles_add_species(P, "g", 2500, 0.45 * d, 0.52 * d, &sp));
    uint64_t seed = 5;
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j)
        for (int k = 0; k < m; ++k)
          for (int q = 0; q < 4; ++q) {
            TlVec3 x = tl_v3((i + 0.25 + basis[q][0]) * a, (j + 0.25 + basis[q][1]) * a, (k + 0.25 + basis[q][2]) * a);
            TlVec3 v = tl_v3(0.3 * (urand(&seed) - 0.5), 0.3 * (urand(&seed) - 0.5), 0.3 * (urand(&seed) - 0.5));
            TL_CHECK(tl_dem_add_particle(dem, x, v, (0.45 + 0.07 * urand(&seed)) * d, sp, NULL));
          }
    TlContactLaw *law = NULL;
    TL_CHECK(tl_test_law(&law, "hertz", "E", 1e7, "nu", 0.3, "gamma_n", 2e3, "mu", 0.3, NULL));
    TL_CHECK(tl_dem_add_law(dem, law, NULL));
    TlMat3 hdot = {{{-0.5, 0.8, 0.0}, {0.0, -0.3, 0.0}, {0.2, 0.0, -0.4}}};
    TL_CHECK(tl_domain_set_h_rate(tl_dem_domain(dem), tl_m3_scale(tl_m3_mul(hdot, h0), 1.0)));
    double dtc, k, mm;
    TL_CHECK(tl_dem_critical_timestep(dem, &dtc, &k, &mm));
    TL_CHECK(tl_dem_set_timestep(dem, 0.3 * dtc, 0));
  }
  tl_dem_set_skin(dem, 0.05);
  tl_dem_set_sort_interval(dem, 2);
  tl_dem_track_energy(dem, 1);
  TL_CHECK(tl_dem_setup(dem));
  *out = dem;
  return TL_OK;
}

/* Everything compared, copied out of the world. */
typedef struct {
  size_t n;
  TlVec3 x[200], v[200], f[200], w[200], torque[200];
  TlQuat q[200];
  int64_t id[200];
  TlDemEnergy energy;
  TlVec3 wall_force;
  double t;
  long steps, rebuilds;
  size_t contacts;
} State;

static void record(TlDem *dem, State *s)
{
  memset(s, 0, sizeof *s);
  TlParticles *P = tl_dem_particles(dem);
  s->n = P->n < 200 ? P->n : 200;
  memcpy(s->x, P->x, s->n * sizeof *P->x);
  memcpy(s->v, P->v, s->n * sizeof *P->v);
  memcpy(s->f, P->f, s->n * sizeof *P->f);
  memcpy(s->id, P->id, s->n * sizeof *P->id);
  if (P->w) {
    memcpy(s->w, P->w, s->n * sizeof *P->w);
    memcpy(s->q, P->q, s->n * sizeof *P->q);
    memcpy(s->torque, P->torque, s->n * sizeof *P->torque);
  }
  tl_dem_energy(dem, &s->energy);
  if (tl_dem_n_walls(dem)) s->wall_force = tl_dem_wall(dem, 0)->force;
  s->t = tl_dem_time(dem);
  TlDemStats st;
  tl_dem_stats(dem, &st);
  s->steps = st.steps;
  s->rebuilds = st.rebuilds;
  s->contacts = st.n_contacts;
}

static State full, split;

static void test_scene(int scene, long N)
{
  char path[64];
  snprintf(path, sizeof path, "restart_%s.h5", scene_name[scene]);
  TlDem *dem = NULL;
  TL_TEST_STATUS(build(scene, &dem), TL_OK);
  if (!dem) return;
  TL_TEST_STATUS(tl_dem_step(dem, N), TL_OK);
  record(dem, &full);
  tl_dem_destroy(&dem);

  TL_TEST_STATUS(build(scene, &dem), TL_OK);
  TL_TEST_STATUS(tl_dem_step(dem, N / 2), TL_OK);
  TlDemStats half;
  tl_dem_stats(dem, &half);
  TlCheckpoint *cp = NULL;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, path, tl_dem_time(dem), half.steps), TL_OK);
  tl_checkpoint_destroy(&cp);
  tl_dem_destroy(&dem);

  TL_TEST_STATUS(build(scene, &dem), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), TL_OK);
  double t = 0.0;
  int64_t step = 0;
  TL_TEST_STATUS(tl_checkpoint_load(cp, path, &t, &step), TL_OK);
  TL_TEST_ASSERT(step == half.steps && t == tl_dem_time(dem), "%s: checkpoint at step %lld, t %g", scene_name[scene],
                 (long long)step, t);
  tl_checkpoint_destroy(&cp);
  TL_TEST_STATUS(tl_dem_step(dem, N - N / 2), TL_OK);
  record(dem, &split);
  tl_dem_destroy(&dem);

  printf("%s: %zu particles, %ld steps, %ld rebuilds (%ld before the checkpoint), %zu contacts at the end, wall force z %.6g N\n",
         scene_name[scene], full.n, full.steps, full.rebuilds, half.rebuilds, full.contacts, full.wall_force.z);
  TL_TEST_ASSERT(full.contacts > full.n / 2, "%s: %zu contacts only: the scene does not test histories", scene_name[scene],
                 full.contacts);
  TL_TEST_ASSERT(half.rebuilds > 2 && full.rebuilds > half.rebuilds + 2, "%s: rebuilds %ld then %ld: too few",
                 scene_name[scene], half.rebuilds, full.rebuilds);
  TL_TEST_ASSERT(memcmp(full.x, split.x, sizeof full.x) == 0, "%s: positions differ after restart", scene_name[scene]);
  TL_TEST_ASSERT(memcmp(full.v, split.v, sizeof full.v) == 0, "%s: velocities differ after restart", scene_name[scene]);
  TL_TEST_ASSERT(memcmp(full.f, split.f, sizeof full.f) == 0, "%s: forces differ after restart", scene_name[scene]);
  TL_TEST_ASSERT(memcmp(full.w, split.w, sizeof full.w) == 0, "%s: spins differ after restart", scene_name[scene]);
  TL_TEST_ASSERT(memcmp(full.q, split.q, sizeof full.q) == 0, "%s: orientations differ after restart", scene_name[scene]);
  TL_TEST_ASSERT(memcmp(full.torque, split.torque, sizeof full.torque) == 0, "%s: torques differ after restart",
                 scene_name[scene]);
  TL_TEST_ASSERT(memcmp(full.id, split.id, sizeof full.id) == 0, "%s: particle order differs after restart",
                 scene_name[scene]);
  TL_TEST_ASSERT(memcmp(&full.energy, &split.energy, sizeof full.energy) == 0,
                 "%s: energy bookkeeping differs after restart (dissipated %.17g vs %.17g)", scene_name[scene],
                 full.energy.dissipated, split.energy.dissipated);
  TL_TEST_ASSERT(memcmp(&full.wall_force, &split.wall_force, sizeof full.wall_force) == 0,
                 "%s: wall force differs after restart", scene_name[scene]);
  TL_TEST_ASSERT(full.t == split.t && full.steps == split.steps && full.rebuilds == split.rebuilds &&
                     full.contacts == split.contacts,
                 "%s: clocks or counters differ (t %.17g/%.17g, steps %ld/%ld, rebuilds %ld/%ld, contacts %zu/%zu)",
                 scene_name[scene], full.t, split.t, full.steps, split.steps, full.rebuilds, split.rebuilds,
                 full.contacts, split.contacts);
}

/* A checkpoint of one scene refused by a world of another, with a message. */
static void test_mismatch(void)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(build(SCENE_CELL, &dem), TL_OK);
  TlCheckpoint *cp = NULL;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), TL_OK);
  TlStatus s = tl_checkpoint_load(cp, "restart_hertz_plane.h5", NULL, NULL);
  TL_TEST_ASSERT(s != TL_OK, "a plane-floor checkpoint loaded into a wall-less cell");
  tl_checkpoint_destroy(&cp);
  tl_dem_destroy(&dem);
}

typedef struct {
  TlVec3 sum;
  size_t n;
  double worst_z, worst_lever;
  const TlParticles *P;
} WallVisit;

static void visit_wall(void *ctx, size_t wall, size_t i, TlVec3 f, TlVec3 point, TlVec3 center)
{
  WallVisit *v = ctx;
  (void)wall;
  v->sum = tl_v3_add(v->sum, f);
  v->n++;
  v->worst_z = fmax(v->worst_z, fabs(point.z));
  /* the contact point is within a radius of the centre used */
  v->worst_lever = fmax(v->worst_lever, tl_v3_norm(tl_v3_sub(point, center)) / v->P->radius[i]);
}

static void test_wall_visitor(int scene)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(build(scene, &dem), TL_OK);
  if (!dem) return;
  TL_TEST_STATUS(tl_dem_step(dem, 3000), TL_OK);
  WallVisit v = {tl_v3(0, 0, 0), 0, 0.0, 0.0, tl_dem_particles(dem)};
  TL_TEST_STATUS(tl_dem_visit_wall_contacts(dem, visit_wall, &v), TL_OK);
  const TlWall *W = tl_dem_wall(dem, 0);
  double scale = tl_v3_norm(W->force);
  printf("%s wall visitor: %zu contacts (wall %zu), force sum (%.6g, %.6g, %.6g) N vs wall (%.6g, %.6g, %.6g) N\n",
         scene_name[scene], v.n, W->n_contacts, v.sum.x, v.sum.y, v.sum.z, W->force.x, W->force.y, W->force.z);
  TL_TEST_ASSERT(v.n >= 5 && v.n == W->n_contacts, "%s: %zu wall contacts visited, the wall counts %zu", scene_name[scene],
                 v.n, W->n_contacts);
  TL_TEST_ASSERT(tl_v3_norm(tl_v3_add(v.sum, W->force)) <= 1e-12 * scale && scale > 0.0,
                 "%s: visited wall forces do not sum to minus the wall force", scene_name[scene]);
  TL_TEST_ASSERT(v.worst_z <= 1e-15, "%s: a contact point lies %g off the floor", scene_name[scene], v.worst_z);
  TL_TEST_ASSERT(v.worst_lever <= 1.0, "%s: a contact point is %g radii from its centre", scene_name[scene], v.worst_lever);
  tl_dem_destroy(&dem);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_scene(SCENE_HERTZ_PLANE, 6000);
  test_scene(SCENE_TRISURFACE, 1200);
  test_scene(SCENE_CELL, 1200);
  test_mismatch();
  test_wall_visitor(SCENE_HERTZ_PLANE);
  test_wall_visitor(SCENE_TRISURFACE);
  return tl_test_report();
}
