/* The plane wall evaluated by particle ranges keeps candidates while the
 * world promises (TlWallStep version and reach) that no particle moves
 * further than `reach`: it must give, to the last bit, what a plane that
 * scans every particle gives (version 0), while particles drift within that
 * reach, contacts begin and end, the plane moves further than its slack and
 * the version changes.  It must also give what its own `interact` gives
 * block by block (tl_wall_interact_blocks). */
#include <math.h>
#include <string.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"
#include "tl_wall.h"

enum { N = 4000, STEPS = 120, VERSION_STEPS = 15 };

static TlVec3 f_scan[N], f_cand[N];

/* One evaluation of a plane: forces from zero, the wall's accounting. */
static TlStatus evaluate(TlWall *w, TlParticles *P, const TlContactLaw *law, unsigned long version, double reach,
                         TlVec3 *f_out, TlVec3 *wall_force, size_t *contacts, double *elastic)
{
  for (size_t i = 0; i < P->n; ++i) {
    P->f[i] = tl_v3(0, 0, 0);
    P->torque[i] = tl_v3(0, 0, 0);
  }
  TlWallStep st = {P, NULL, NULL, law, 0.0, 1e-4, 1, version, reach};
  TL_CHECK(w->ops->interact(w, &st));
  memcpy(f_out, P->f, P->n * sizeof *f_out);
  *wall_force = w->force;
  *contacts = w->n_contacts;
  *elastic = w->elastic_energy;
  return TL_OK;
}

/* In the world: after steps (candidates kept), a sphere moved by hand
 * onto the floor and the forces evaluated on their own
 * (tl_dem_compute_forces) meets the floor: no candidate list is trusted
 * outside tl_dem_step. */
static void test_world_moved_by_hand(void)
{
  TlDem *dem = NULL;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "g", 1000.0, 0.5, 0.5, &sp), TL_OK);
  for (int k = 0; k < 20; ++k)
    TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(3.0 * k, 0, 5.0), tl_v3(0, 0, 0), 0.5, sp, NULL), TL_OK);
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e4, "restitution", 0.5, "mu", 0.5, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  TlWall *floor_ = NULL;
  TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &floor_), TL_OK);
  TL_TEST_STATUS(tl_dem_add_wall(dem, floor_, 0), TL_OK);
  tl_dem_set_gravity(dem, tl_v3(0, 0, 0));
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 1e-4, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TL_TEST_STATUS(tl_dem_step(dem, 5), TL_OK);
  P->x[3].z = 0.5 - 1e-3; /* 1e-3 into the floor */
  TL_TEST_STATUS(tl_dem_compute_forces(dem), TL_OK);
  TL_TEST_REL(P->f[3].z, 1e4 * 1e-3, 1e-12);
  TL_TEST_ASSERT(tl_dem_wall(dem, 0)->n_contacts == 1, "%zu floor contacts after the move, expected 1",
                 tl_dem_wall(dem, 0)->n_contacts);
  tl_dem_destroy(&dem);
}

/* A constructor for the refused type below (never called). */
static TlStatus half_create(const void *params, TlWall **w)
{
  (void)params;
  (void)w;
  return TL_ERR_STATE;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TlParticles *P = NULL;
  TL_TEST_STATUS(tl_particles_create(&P), TL_OK);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "grains", 1000.0, 0.4, 0.6, &sp), TL_OK);
  uint64_t seed = 7;
  /* a slab of particles above the plane z = 0, the lowest within a few
   * reaches of it */
  for (int k = 0; k < N; ++k) {
    TlVec3 x = tl_v3(40.0 * tl_random_uniform(&seed), 40.0 * tl_random_uniform(&seed), 3.0 * tl_random_uniform(&seed));
    TL_TEST_STATUS(tl_particles_add(P, x, tl_v3(0, 0, 0), 0.4 + 0.2 * tl_random_uniform(&seed), sp, NULL), TL_OK);
  }
  TL_TEST_STATUS(tl_particles_enable_rotation(P), TL_OK);
  for (size_t i = 0; i < P->n; ++i) P->w[i] = tl_v3(tl_random_uniform(&seed), 0.0, tl_random_uniform(&seed));
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e4, "restitution", 0.5, "mu", 0.5, NULL), TL_OK);
  /* the same plane twice: one scans every particle, one keeps candidates;
   * it rises 0.004 a step, 0.06 a version, more than its slack (the reach),
   * then comes down faster */
  TlWall *scan = NULL, *cand = NULL;
  TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &scan), TL_OK);
  TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &cand), TL_OK);
  TL_TEST_STATUS(tl_wall_plane_set_velocity(scan, tl_v3(0, 0, 40.0)), TL_OK);
  TL_TEST_STATUS(tl_wall_plane_set_velocity(cand, tl_v3(0, 0, 40.0)), TL_OK);
  TL_TEST_ASSERT(tl_wall_by_ranges(cand), "the plane is evaluated by particle ranges");
  const double reach = 0.05;
  static TlVec3 x0[N], dir[N];
  unsigned long version = 0;
  size_t bad = 0, begun = 0, ended = 0, max_contacts = 0;
  int same_walls = 1;
  uint8_t before[N] = {0};
  for (int s = 0; s < STEPS; ++s) {
    if (s % VERSION_STEPS == 0) {
      /* a new version: the particles start from here and drift up to the
       * reach, each along its own direction, down more often than up */
      ++version;
      if (s == STEPS / 2) { /* the plane comes back down: contacts end */
        TL_TEST_STATUS(tl_wall_plane_set_velocity(scan, tl_v3(0, 0, -60.0)), TL_OK);
        TL_TEST_STATUS(tl_wall_plane_set_velocity(cand, tl_v3(0, 0, -60.0)), TL_OK);
      }
      for (size_t i = 0; i < P->n; ++i) {
        x0[i] = P->x[i];
        dir[i] = tl_v3(tl_random_uniform(&seed) - 0.5, tl_random_uniform(&seed) - 0.5, 0.3 - tl_random_uniform(&seed));
        dir[i] = tl_v3_scale(dir[i], 1.0 / tl_v3_norm(dir[i]));
      }
    }
    const double a = reach * (double)(s % VERSION_STEPS + 1) / VERSION_STEPS;
    for (size_t i = 0; i < P->n; ++i) P->x[i] = tl_v3_axpy(x0[i], a, dir[i]);
    TlVec3 fw_scan, fw_cand;
    size_t n_scan = 0, n_cand = 0;
    double e_scan = 0.0, e_cand = 0.0;
    TL_TEST_STATUS(evaluate(scan, P, law, 0, INFINITY, f_scan, &fw_scan, &n_scan, &e_scan), TL_OK);
    TL_TEST_STATUS(evaluate(cand, P, law, version, reach, f_cand, &fw_cand, &n_cand, &e_cand), TL_OK);
    for (size_t i = 0; i < P->n; ++i) {
      bad += memcmp(&f_scan[i], &f_cand[i], sizeof f_scan[i]) != 0;
      TlVec3 fi;
      const uint8_t now = (uint8_t)tl_wall_plane_contact_force(scan, i, &fi);
      begun += now && !before[i];
      ended += !now && before[i];
      before[i] = now;
    }
    same_walls &= !memcmp(&fw_scan, &fw_cand, sizeof fw_scan) && n_scan == n_cand && !memcmp(&e_scan, &e_cand, sizeof e_scan);
    max_contacts = n_scan > max_contacts ? n_scan : max_contacts;
    TL_TEST_STATUS(scan->ops->advance(scan, 0.0, 1e-4), TL_OK);
    TL_TEST_STATUS(cand->ops->advance(cand, 0.0, 1e-4), TL_OK);
  }
  printf("%d steps, %lu versions: up to %zu contacts, %zu begun, %zu ended; %zu particle forces differ between the "
         "full scan and the candidates, wall sums %s\n",
         STEPS, version, max_contacts, begun, ended, bad, same_walls ? "identical" : "differ");
  TL_TEST_ASSERT(begun > 200 && ended > 50, "the scene must start and end contacts (%zu begun, %zu ended)", begun,
                 ended);
  TL_TEST_ASSERT(bad == 0 && same_walls, "candidates change the answers: %zu forces differ, wall sums %s", bad,
                 same_walls ? "same" : "differ");
  /* the blocks done by hand on the second plane (in the same state), in
   * reverse order, booked in block order: the same as the first's interact */
  TlWallStep st = {P, NULL, NULL, law, 0.0, 1e-4, 1, 0, INFINITY};
  TlVec3 fw;
  size_t nc;
  double el;
  TL_TEST_STATUS(evaluate(scan, P, law, 0, INFINITY, f_scan, &fw, &nc, &el), TL_OK);
  TL_TEST_STATUS(cand->ops->prepare(cand, &st), TL_OK);
  const size_t nb = (P->n + TL_WALL_BLOCK - 1) / TL_WALL_BLOCK;
  TlWallSums sums[16];
  TL_TEST_ASSERT(nb <= 16, "%zu blocks", nb);
  for (size_t i = 0; i < P->n; ++i) P->f[i] = P->torque[i] = tl_v3(0, 0, 0);
  for (size_t b = nb; b-- > 0;) {
    memset(&sums[b], 0, sizeof sums[b]);
    const size_t lo = b * TL_WALL_BLOCK, hi = lo + TL_WALL_BLOCK < P->n ? lo + TL_WALL_BLOCK : P->n;
    cand->ops->interact_range(cand, &st, lo, hi, &sums[b]);
  }
  TL_TEST_STATUS(tl_wall_book_blocks(cand, &st, sums, nb, 1), TL_OK);
  bad = 0;
  for (size_t i = 0; i < P->n; ++i) bad += memcmp(&f_scan[i], &P->f[i], sizeof f_scan[i]) != 0;
  TL_TEST_ASSERT(bad == 0 && !memcmp(&fw, &cand->force, sizeof fw) && nc == cand->n_contacts && nc > 0 &&
                     !memcmp(&scan->contact_work, &cand->contact_work, sizeof el),
                 "blocks in reverse order: %zu forces differ, wall force (%g, %g, %g) against (%g, %g, %g)", bad,
                 cand->force.x, cand->force.y, cand->force.z, fw.x, fw.y, fw.z);
  /* a failure in one block is the booking's failure */
  sums[1].status = TL_ERR_NUMERIC;
  TL_TEST_STATUS(tl_wall_book_blocks(scan, &st, sums, nb, 1), TL_ERR_NUMERIC);
  /* a type with one of the two range ops and not the other is refused */
  TlWallOps half = *scan->ops;
  half.interact_range = NULL;
  TL_TEST_STATUS(tl_wall_register("plane_half_ranges", "prepare without interact_range", NULL, &half, NULL, 0),
                 TL_ERR_ARG);
  TL_TEST_STATUS(tl_wall_register("plane_half_ranges", "prepare without interact_range", half_create, &half, NULL, 0),
                 TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "interact_range") != NULL, "the refusal names the missing op: %s",
                 tl_error_message());
  test_world_moved_by_hand();
  tl_wall_destroy(&scan);
  tl_wall_destroy(&cand);
  tl_contact_law_destroy(&law);
  tl_particles_destroy(&P);
  return tl_test_report();
}
