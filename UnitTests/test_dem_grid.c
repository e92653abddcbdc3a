/* The hierarchical grid against brute force: identical pair sets on random
 * polydisperse packings (size ratio 10) in an open box, a periodic box and a
 * sheared periodic cell; the wall box query returns a superset of the
 * particles that can reach the box; and during a run with a Verlet skin the
 * world's touching contacts equal the brute-force overlaps at every step. */
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_hgrid.h"
#include "tl_test.h"

static int cmp_pair(const void *a, const void *b)
{
  const TlPair *p = a, *q = b;
  if (p->i != q->i) return p->i < q->i ? -1 : 1;
  if (p->j != q->j) return p->j < q->j ? -1 : 1;
  return 0;
}

static void random_packing(const TlDomain *dom, size_t n, double rmin, double ratio, uint64_t seed, TlVec3 *x,
                           double *r)
{
  uint64_t s = seed;
  for (size_t i = 0; i < n; ++i) {
    TlVec3 u = {tl_random_uniform(&s), tl_random_uniform(&s), tl_random_uniform(&s)};
    x[i] = tl_domain_from_reduced(dom, u);
    double q = tl_random_uniform(&s);
    r[i] = rmin * (q < 0.9 ? 1.0 + q : ratio * (0.8 + 0.2 * q)); /* mostly small, some large */
  }
}

static void compare(const char *name, const TlDomain *dom, size_t n, const TlVec3 *x, const double *r, double skin)
{
  TlHGrid *g;
  TL_TEST_STATUS(tl_hgrid_create(&g), TL_OK);
  TL_TEST_STATUS(tl_hgrid_build(g, dom, n, x, r, skin), TL_OK);
  TlPair *a = NULL, *b = NULL;
  size_t ca = 0, cb = 0, na = 0, nb = 0;
  TL_TEST_STATUS(tl_hgrid_pairs(g, x, r, NULL, &a, &ca, &na), TL_OK);
  TL_TEST_STATUS(tl_hgrid_pairs_brute_force(dom, n, x, r, skin, NULL, &b, &cb, &nb), TL_OK);
  qsort(a, na, sizeof *a, cmp_pair);
  qsort(b, nb, sizeof *b, cmp_pair);
  int same = na == nb && (na == 0 || memcmp(a, b, na * sizeof *a) == 0);
  printf("%s: %d levels, grid %zu pairs, brute force %zu pairs%s\n", name, g->n_levels, na, nb,
         same ? ", identical" : ", DIFFERENT");
  TL_TEST_ASSERT(same, "%s: grid and brute force pair sets differ (%zu vs %zu)", name, na, nb);
  TL_TEST_ASSERT(nb > n / 4, "%s: too few pairs (%zu) for a meaningful comparison", name, nb);
  /* box queries: every particle that can reach the box must be returned */
  uint64_t s = 7;
  size_t *out = NULL, co = 0, no = 0;
  int missing = 0;
  for (int q = 0; q < 50; ++q) {
    TlVec3 c = tl_domain_from_reduced(dom, tl_v3(tl_random_uniform(&s), tl_random_uniform(&s), tl_random_uniform(&s)));
    TlVec3 h = tl_v3(0.02 + 0.1 * tl_random_uniform(&s), 0.02 + 0.1 * tl_random_uniform(&s), 0.01);
    TlVec3 lo = tl_v3_sub(c, h), hi = tl_v3_add(c, h);
    TL_TEST_STATUS(tl_hgrid_query_box(g, lo, hi, &out, &co, &no), TL_OK);
    char *in = calloc(n, 1);
    for (size_t k = 0; k < no; ++k) in[out[k]] = 1;
    for (size_t i = 0; i < n; ++i) {
      /* distance from the box to the nearest image of the particle */
      TlVec3 b2 = tl_domain_branch(dom, c, x[i]);
      TlVec3 p = tl_v3_add(c, b2);
      double dx = fmax(0.0, fmax(lo.x - p.x, p.x - hi.x)), dy = fmax(0.0, fmax(lo.y - p.y, p.y - hi.y)),
             dz = fmax(0.0, fmax(lo.z - p.z, p.z - hi.z));
      double dist = sqrt(dx * dx + dy * dy + dz * dz);
      if (dist <= r[i] + 0.5 * skin && !in[i]) ++missing;
    }
    free(in);
  }
  TL_TEST_ASSERT(missing == 0, "%s: %d particles near a query box were not returned", name, missing);
  free(out);
  free(a);
  free(b);
  tl_hgrid_destroy(&g);
}

static void test_static(void)
{
  size_t n = 3000;
  TlVec3 *x = malloc(n * sizeof *x);
  double *r = malloc(n * sizeof *r);
  TlDomain dom;
  TL_TEST_STATUS(tl_domain_init_open(&dom, tl_v3(0, 0, 0), tl_v3(1, 1, 0.5)), TL_OK);
  random_packing(&dom, n, 0.006, 10.0, 1, x, r);
  compare("open box", &dom, n, x, r, 0.002);
  int per[3] = {1, 1, 0};
  TL_TEST_STATUS(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), tl_v3(1, 1, 0.5), per), TL_OK);
  random_packing(&dom, n, 0.006, 10.0, 2, x, r);
  compare("periodic box (x, y)", &dom, n, x, r, 0.002);
  TlMat3 h = {{{1.0, 0.35, 0.1}, {0.0, 0.9, -0.2}, {0.05, 0.0, 0.6}}};
  TL_TEST_STATUS(tl_domain_init_cell(&dom, tl_v3(0.1, -0.2, 0.3), h), TL_OK);
  random_packing(&dom, n, 0.006, 10.0, 3, x, r);
  compare("sheared periodic cell", &dom, n, x, r, 0.002);
  free(x);
  free(r);
}

/* The world during a run: touching contacts equal brute-force overlaps. */
typedef struct {
  size_t n;
  TlPair *p;
} Collect;

static void collect(void *ctx, size_t i, size_t j, TlVec3 f, TlVec3 b, TlVec3 cp)
{
  Collect *c = ctx;
  c->p[c->n++] = i < j ? (TlPair){(uint32_t)i, (uint32_t)j} : (TlPair){(uint32_t)j, (uint32_t)i};
}

static void test_dynamic(int periodic)
{
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  int per[3] = {periodic, periodic, 0};
  TL_TEST_STATUS(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), tl_v3(0.3, 0.3, 0.3), per), TL_OK);
  TL_TEST_STATUS(tl_dem_set_domain(dem, &dom), TL_OK);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "g", 2500, 0.004, 0.02, &sp), TL_OK);
  uint64_t s = 11;
  for (int k = 0; k < 1500; ++k) {
    double r = tl_random_uniform(&s) < 0.9 ? 0.004 + 0.002 * tl_random_uniform(&s) : 0.02;
    TlVec3 x = {r + (0.3 - 2 * r) * tl_random_uniform(&s), r + (0.3 - 2 * r) * tl_random_uniform(&s),
                r + (0.3 - 2 * r) * tl_random_uniform(&s)};
    TlVec3 v = {tl_random_uniform(&s) - 0.5, tl_random_uniform(&s) - 0.5, tl_random_uniform(&s) - 0.5};
    /* keep only non-overlapping insertions */
    int ok = 1;
    for (size_t i = 0; i < P->n && ok; ++i)
      ok = tl_v3_norm(tl_domain_branch(&dom, P->x[i], x)) > P->radius[i] + r;
    if (ok) TL_TEST_STATUS(tl_dem_add_particle(dem, x, v, r, sp, NULL), TL_OK);
  }
  TlContactLaw *law;
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e4, "restitution", 0.9, "mu", 0.3, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  TlWall *floor_, *roof;
  TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &floor_), TL_OK);
  TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0.3), tl_v3(0, 0, -1), &roof), TL_OK);
  TL_TEST_STATUS(tl_dem_add_wall(dem, floor_, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_add_wall(dem, roof, 0), TL_OK);
  if (!periodic) {
    TlWall *w[4];
    TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(1, 0, 0), &w[0]), TL_OK);
    TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0.3, 0, 0), tl_v3(-1, 0, 0), &w[1]), TL_OK);
    TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 1, 0), &w[2]), TL_OK);
    TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0.3, 0), tl_v3(0, -1, 0), &w[3]), TL_OK);
    for (int k = 0; k < 4; ++k) TL_TEST_STATUS(tl_dem_add_wall(dem, w[k], 0), TL_OK);
  }
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  TL_TEST_STATUS(tl_dem_set_timestep(dem, 6e-5, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  Collect c = {0, malloc(20 * P->n * sizeof(TlPair))};
  TlPair *b = NULL;
  size_t cb = 0, nb = 0;
  int mismatches = 0, checks = 0;
  size_t max_contacts = 0;
  for (int k = 0; k < 25; ++k) {
    TL_TEST_STATUS(tl_dem_step(dem, 100), TL_OK);
    c.n = 0;
    TL_TEST_STATUS(tl_dem_visit_contacts(dem, collect, &c), TL_OK);
    TL_TEST_STATUS(tl_hgrid_pairs_brute_force(tl_dem_domain(dem), P->n, P->x, P->radius, 0.0, NULL, &b, &cb, &nb), TL_OK);
    qsort(c.p, c.n, sizeof *c.p, cmp_pair);
    qsort(b, nb, sizeof *b, cmp_pair);
    ++checks;
    if (!(c.n == nb && (nb == 0 || memcmp(c.p, b, nb * sizeof *b) == 0))) ++mismatches;
    if (nb > max_contacts) max_contacts = nb;
  }
  TlDemStats st;
  tl_dem_stats(dem, &st);
  printf("%s run: %d checks, %d mismatches, up to %zu contacts, %ld rebuilds in %ld steps\n",
         periodic ? "periodic" : "walled", checks, mismatches, max_contacts, st.rebuilds, st.steps);
  TL_TEST_ASSERT(mismatches == 0, "touching contacts differ from brute force at %d of %d checks", mismatches, checks);
  TL_TEST_ASSERT(max_contacts > 10, "too few contacts (%zu)", max_contacts);
  TL_TEST_ASSERT(st.rebuilds > 1 && st.rebuilds < st.steps, "rebuild count %ld over %ld steps", st.rebuilds, st.steps);
  free(c.p);
  free(b);
  tl_dem_destroy(&dem);
}

/* A grid large enough to be scanned by several threads gives the same
 * pairs as one thread (whose equality with brute force the other cases
 * check). */
static void test_threaded(void)
{
  size_t n = 24000;
  TlVec3 *x = malloc(n * sizeof *x);
  double *r = malloc(n * sizeof *r);
  TlDomain dom;
  int per[3] = {1, 1, 1};
  TL_TEST_STATUS(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), tl_v3(1, 1, 1), per), TL_OK);
  random_packing(&dom, n, 0.01, 3.0, 9, x, r);
  TlHGrid *g;
  TL_TEST_STATUS(tl_hgrid_create(&g), TL_OK);
  TL_TEST_STATUS(tl_hgrid_build(g, &dom, n, x, r, 0.002), TL_OK);
  TlPair *a = NULL, *b = NULL;
  size_t ca = 0, cb = 0, na = 0, nb = 0;
  omp_set_num_threads(1);
  TL_TEST_STATUS(tl_hgrid_pairs(g, x, r, NULL, &a, &ca, &na), TL_OK);
  omp_set_num_threads(2);
  TL_TEST_STATUS(tl_hgrid_pairs(g, x, r, NULL, &b, &cb, &nb), TL_OK);
  qsort(a, na, sizeof *a, cmp_pair);
  qsort(b, nb, sizeof *b, cmp_pair);
  int same = na == nb && memcmp(a, b, na * sizeof *a) == 0;
  printf("threaded scan: %zu particles, 1 thread %zu pairs, 2 threads %zu%s\n", n, na, nb,
         same ? ", identical" : ", DIFFERENT");
  TL_TEST_ASSERT(same && na > n, "threaded pair scan differs (%zu, %zu)", na, nb);
  free(a);
  free(b);
  free(x);
  free(r);
  tl_hgrid_destroy(&g);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_static();
  test_threaded();
  test_dynamic(0);
  test_dynamic(1);
  return tl_test_report();
}
