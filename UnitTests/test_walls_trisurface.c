/* Triangle walls and triangulated surfaces in motion: face, edge and vertex
 * forces through a contact law; a sphere bouncing inside a box of triangles
 * exactly as inside a box of planes; a particle sliding with friction across
 * a flat surface triangulated in different ways feeling the plane's force
 * history (so the tangential history survives every edge crossing); grid =
 * brute force for wall contacts in open and periodic domains with a size
 * ratio of 10, and on 1 or 2 threads; the wall velocity interpolated from the
 * vertices; degenerate triangles refused. */
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "talus.h"
#include "tl_contact_law.h"
#include "tl_hgrid.h"
#include "tl_particles.h"
#include "tl_test.h"
#include "tl_wall.h"
#include "tl_wall_trisurface.h"

static double urand(uint64_t *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

/* A minimal world: particles, walls, one law, Velocity-Verlet. */
typedef struct {
  TlParticles *p;
  TlHGrid *grid;
  TlDomain domain;
  TlContactLaw *law;
  TlWall *wall[8];
  int n_walls;
  double dt, t;
  TlVec3 g;
  double skin;
  TlVec3 x_build[4]; /* positions at the last grid build (small scenes) */
  int built;
} Mini;

/* the linear law's parameters of a scene */
typedef struct {
  double k_n, restitution, mu;
} TestLaw;

static TlStatus mini_create(Mini *m, const TestLaw *cp, int rotation)
{
  memset(m, 0, sizeof *m);
  TL_CHECK(tl_particles_create(&m->p));
  if (rotation) TL_CHECK(tl_particles_enable_rotation(m->p));
  TL_CHECK(tl_hgrid_create(&m->grid));
  TL_CHECK(tl_domain_init_open(&m->domain, tl_v3(-1, -1, -1), tl_v3(2, 2, 2)));
  TL_CHECK(tl_test_law(&m->law, "linear", "k_n", cp->k_n, "restitution", cp->restitution, "mu", cp->mu, NULL));
  return TL_OK;
}

static void mini_destroy(Mini *m)
{
  for (int k = 0; k < m->n_walls; ++k) tl_wall_destroy(&m->wall[k]);
  tl_contact_law_destroy(&m->law);
  tl_hgrid_destroy(&m->grid);
  tl_particles_destroy(&m->p);
}

static TlStatus mini_forces(Mini *m)
{
  TlParticles *p = m->p;
  for (size_t i = 0; i < p->n; ++i) {
    p->f[i] = tl_v3(0, 0, 0);
    if (p->torque) p->torque[i] = tl_v3(0, 0, 0);
  }
  /* rebuild the grid only when a particle has moved more than skin/2, as
   * the world does (small scenes track their positions) */
  int rebuild = !m->built || p->n > 4;
  for (size_t i = 0; !rebuild && i < p->n; ++i)
    rebuild = tl_v3_norm(tl_v3_sub(p->x[i], m->x_build[i])) > 0.5 * m->skin;
  if (rebuild) {
    TL_CHECK(tl_hgrid_build(m->grid, &m->domain, p->n, p->x, p->radius, m->skin));
    for (size_t i = 0; i < p->n && i < 4; ++i) m->x_build[i] = p->x[i];
    m->built = 1;
  }
  TlWallStep st = {.particles = p, .grid = m->grid, .domain = &m->domain, .law = m->law, .t = m->t, .dt = m->dt};
  for (int k = 0; k < m->n_walls; ++k) TL_CHECK(m->wall[k]->ops->interact(m->wall[k], &st));
  return TL_OK;
}

static void mini_kick(Mini *m)
{
  TlParticles *p = m->p;
  for (size_t i = 0; i < p->n; ++i) {
    p->v[i] = tl_v3_axpy(p->v[i], 0.5 * m->dt, tl_v3_axpy(m->g, p->inv_mass[i], p->f[i]));
    if (p->w) p->w[i] = tl_v3_axpy(p->w[i], 0.5 * m->dt * p->inv_inertia[i], p->torque[i]);
  }
}

static TlStatus mini_step(Mini *m)
{
  mini_kick(m);
  for (size_t i = 0; i < m->p->n; ++i) m->p->x[i] = tl_v3_axpy(m->p->x[i], m->dt, m->p->v[i]);
  m->t += m->dt;
  TL_CHECK(mini_forces(m));
  mini_kick(m);
  return TL_OK;
}

static void test_features(void)
{
  TestLaw cp = {0.0, 1.0, 0.0};
  cp.k_n = 1000.0;
  Mini m;
  TL_TEST_STATUS(mini_create(&m, &cp, 0), TL_OK);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(m.p, "glass", 2500, 0.1, 0.1, &sp), TL_OK);
  TL_TEST_STATUS(tl_particles_add(m.p, tl_v3(0.3, 0.3, 0.08), tl_v3(0, 0, 0), 0.1, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_wall_triangle_create(tl_v3(0, 0, 0), tl_v3(1, 0, 0), tl_v3(0, 1, 0), &m.wall[0]), TL_OK);
  m.n_walls = 1;
  m.dt = 1e-4;
  TL_TEST_ASSERT(tl_wall_is_bounded(m.wall[0]), "a triangle is bounded");
  struct {
    TlVec3 x;
    TlVec3 f;
    int feature;
  } cases[] = {
      {{0.3, 0.3, 0.08}, {0, 0, 20.0}, TL_TRI_FACE},
      {{0.3, 0.3, -0.06}, {0, 0, -40.0}, TL_TRI_FACE},
      {{0.55, 0.55, 0}, {sqrt(0.5) * (100 - 1000 * 0.05 * sqrt(2)), sqrt(0.5) * (100 - 1000 * 0.05 * sqrt(2)), 0},
       TL_TRI_EDGE1},
      {{-0.03, -0.04, 0}, {-0.6 * 50, -0.8 * 50, 0}, TL_TRI_VERTEX0},
      {{0.5, -0.05, 0.05}, {0, -sqrt(0.5) * (100 - 1000 * 0.05 * sqrt(2)), sqrt(0.5) * (100 - 1000 * 0.05 * sqrt(2))},
       TL_TRI_EDGE0},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    m.p->x[0] = cases[k].x;
    TL_TEST_STATUS(mini_forces(&m), TL_OK);
    TL_TEST_CLOSE(tl_v3_norm(tl_v3_sub(m.p->f[0], cases[k].f)), 0.0, 1e-10);
    TL_TEST_CLOSE(tl_v3_norm(tl_v3_add(m.wall[0]->force, cases[k].f)), 0.0, 1e-10);
    const TlTriContactSet *c = tl_wall_trisurface_contacts(m.wall[0]);
    TL_TEST_ASSERT(c && c->count == 1 && c->c[0].feature == cases[k].feature, "case %zu: feature %d, expected %d",
                   k, c && c->count ? c->c[0].feature : -1, cases[k].feature);
  }
  m.p->x[0] = tl_v3(0.3, 0.3, 0.1);
  TL_TEST_STATUS(mini_forces(&m), TL_OK);
  TL_TEST_ASSERT(m.wall[0]->n_contacts == 0 && tl_v3_norm(m.p->f[0]) == 0, "just touching: no force");

  /* degenerate triangles are refused and no wall is returned */
  TlWall *bad = (TlWall *)&m;
  TL_TEST_STATUS(tl_wall_triangle_create(tl_v3(0, 0, 0), tl_v3(1, 0, 0), tl_v3(2, 0, 0), &bad), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(bad == NULL, "no wall from a degenerate triangle");
  TL_TEST_STATUS(tl_wall_triangle_create(tl_v3(0, 0, 0), tl_v3(1, 0, 0), tl_v3(1, 1e-10, 0), &bad), TL_ERR_NUMERIC);
  mini_destroy(&m);
}

/* Runs a sphere inside [0,1]^3 for `steps` steps, walls either 6 planes or
 * 12 triangles; records the trajectory. */
static TlStatus box_run(int triangles, int steps, TlVec3 *traj, TlVec3 *spin, int *max_contacts)
{
  TestLaw cp = {0.0, 1.0, 0.0};
  cp.k_n = 1e5;
  cp.restitution = 0.8;
  cp.mu = 0.4;
  Mini m;
  TL_CHECK(mini_create(&m, &cp, 1));
  int sp;
  TL_CHECK(tl_particles_add_species(m.p, "steel", 2500, 0.1, 0.1, &sp));
  TL_CHECK(tl_particles_add(m.p, tl_v3(0.5, 0.42, 0.37), tl_v3(1.3, 0.71, -0.45), 0.1, sp, NULL));
  m.p->w[0] = tl_v3(3, -2, 5);
  m.g = tl_v3(0, 0, 0);
  m.dt = 2e-4;
  m.skin = 0.02;
  if (triangles) {
    TlTriSurface *s = NULL;
    TL_CHECK(tl_trisurface_create_box(tl_v3(0, 0, 0), tl_v3(1, 1, 1), &s));
    TL_CHECK(tl_wall_trisurface_create(s, &m.wall[0]));
    m.n_walls = 1;
  } else {
    for (int k = 0; k < 3; ++k) {
      TlVec3 n = tl_v3(k == 0, k == 1, k == 2);
      TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), n, &m.wall[m.n_walls++]));
      TL_CHECK(tl_wall_plane_create(tl_v3(1, 1, 1), tl_v3_neg(n), &m.wall[m.n_walls++]));
    }
  }
  TL_CHECK(mini_forces(&m));
  *max_contacts = 0;
  for (int s = 0; s < steps; ++s) {
    TL_CHECK(mini_step(&m));
    int nc = 0;
    for (int k = 0; k < m.n_walls; ++k) nc += (int)m.wall[k]->n_contacts;
    if (nc > *max_contacts) *max_contacts = nc;
    traj[s] = m.p->x[0];
    spin[s] = m.p->w[0];
  }
  mini_destroy(&m);
  return TL_OK;
}

static void test_box_bounce(void)
{
  const int steps = 20000;
  TlVec3 *a = NULL, *b = NULL, *wa = NULL, *wb = NULL;
  TL_TEST_STATUS(tl_calloc(&a, steps, sizeof *a), TL_OK);
  TL_TEST_STATUS(tl_calloc(&b, steps, sizeof *b), TL_OK);
  TL_TEST_STATUS(tl_calloc(&wa, steps, sizeof *wa), TL_OK);
  TL_TEST_STATUS(tl_calloc(&wb, steps, sizeof *wb), TL_OK);
  int ca = 0, cb = 0;
  TL_TEST_STATUS(box_run(0, steps, a, wa, &ca), TL_OK);
  TL_TEST_STATUS(box_run(1, steps, b, wb, &cb), TL_OK);
  double dx = 0, dw = 0;
  int bounces = 0;
  for (int s = 0; s < steps; ++s) {
    dx = fmax(dx, tl_v3_norm(tl_v3_sub(a[s], b[s])));
    dw = fmax(dw, tl_v3_norm(tl_v3_sub(wa[s], wb[s])));
    if (s > 0 && (a[s].x - a[s - 1].x) * (s > 1 ? a[s - 1].x - a[s - 2].x : 1) < 0) ++bounces;
  }
  printf("box: %d x-bounces, max position difference %.3e, spin difference %.3e\n", bounces, dx, dw);
  TL_TEST_ASSERT(ca == 1, "the plane run touched %d walls at once; choose another start", ca);
  TL_TEST_ASSERT(bounces >= 3, "only %d bounces", bounces);
  TL_TEST_ASSERT(dx < 1e-10 && dw < 1e-8, "triangles and planes differ: position %g, spin %g", dx, dw);
  tl_free(&a);
  tl_free(&b);
  tl_free(&wa);
  tl_free(&wb);
}

/* A sphere sliding and starting to roll on z = 0 with friction: total wall
 * force history for a plane and for three triangulations of the floor. */
static TlStatus slide_run(int kind, int corrections, int steps, TlVec3 *force, int *n_triangles_visited)
{
  TestLaw cp = {0.0, 1.0, 0.0};
  cp.k_n = 1e4;
  cp.restitution = 0.5;
  cp.mu = 0.3;
  Mini m;
  TL_CHECK(mini_create(&m, &cp, 1));
  int sp;
  TL_CHECK(tl_particles_add_species(m.p, "glass", 2500, 0.05, 0.05, &sp));
  double r = 0.05, mass = 2500 * 4.0 / 3.0 * TL_PI * r * r * r;
  m.g = tl_v3(0, 0, -9.81);
  TL_CHECK(tl_particles_add(m.p, tl_v3(0.13, 0.21, r - mass * 9.81 / cp.k_n), tl_v3(1.7, 0.9, 0), r, sp, NULL));
  m.dt = 1e-4;
  m.skin = 0.01;
  if (kind < 0) {
    TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &m.wall[0]));
  } else {
    TlTriSurface *s = NULL;
    TL_CHECK(tl_trisurface_create_rectangle(0, 0, 2, 2, 0, 16, 16, kind, &s));
    TL_CHECK(tl_wall_trisurface_create(s, &m.wall[0]));
    TL_CHECK(tl_wall_trisurface_set_corrections(m.wall[0], corrections));
  }
  m.n_walls = 1;
  int last = -1;
  *n_triangles_visited = 0;
  TL_CHECK(mini_forces(&m));
  for (int s = 0; s < steps; ++s) {
    TL_CHECK(mini_step(&m));
    force[s] = m.p->f[0];
    if (kind >= 0) {
      const TlTriContactSet *c = tl_wall_trisurface_contacts(m.wall[0]);
      if (c->count && c->c[0].triangle != last) ++*n_triangles_visited, last = c->c[0].triangle;
    }
  }
  mini_destroy(&m);
  return TL_OK;
}

static void test_sliding_triangulations(void)
{
  const int steps = 4000;
  double r = 0.05, mg = 2500 * 4.0 / 3.0 * TL_PI * r * r * r * 9.81;
  TlVec3 *ref = NULL, *f = NULL;
  TL_TEST_STATUS(tl_calloc(&ref, steps, sizeof *ref), TL_OK);
  TL_TEST_STATUS(tl_calloc(&f, steps, sizeof *f), TL_OK);
  int visited = 0;
  TL_TEST_STATUS(slide_run(-1, 1, steps, ref, &visited), TL_OK);
  double tangential = 0;
  for (int s = 0; s < steps; ++s) tangential = fmax(tangential, hypot(ref[s].x, ref[s].y));
  TL_TEST_ASSERT(tangential > 0.2 * mg, "friction acts on the plane (max tangential %g, mg %g)", tangential, mg);
  for (int pattern = 0; pattern < 3; ++pattern) {
    TL_TEST_STATUS(slide_run(pattern, 1, steps, f, &visited), TL_OK);
    double dev = 0;
    for (int s = 0; s < steps; ++s) dev = fmax(dev, tl_v3_norm(tl_v3_sub(f[s], ref[s])));
    printf("sliding, pattern %d: %d triangles crossed, max |F - F_plane| / mg = %.3e\n", pattern, visited, dev / mg);
    TL_TEST_ASSERT(visited >= 8, "pattern %d: the particle crossed only %d triangles", pattern, visited);
    TL_TEST_ASSERT(dev < 1e-8 * mg, "pattern %d: force history differs from the plane's by %g (mg %g)", pattern, dev, mg);
  }
  /* without the corrections the edges are felt */
  TL_TEST_STATUS(slide_run(2, 0, steps, f, &visited), TL_OK);
  double dev = 0;
  for (int s = 0; s < steps; ++s) dev = fmax(dev, tl_v3_norm(tl_v3_sub(f[s], ref[s])));
  printf("sliding, pattern 2 without corrections: max |F - F_plane| / mg = %.3f\n", dev / mg);
  TL_TEST_ASSERT(dev > 0.1 * mg, "without corrections the force should jump at edges (%g)", dev);
  tl_free(&ref);
  tl_free(&f);
}

/* A floor spanning a periodic box: without joining its edges across the
 * periodic faces a sliding particle feels the seam; joined, the force
 * history is the plane's, seam crossings included. */
static TlStatus seam_run(int kind, int link, int steps, TlVec3 *force, size_t *n_linked)
{
  TestLaw cp = {0.0, 1.0, 0.0};
  cp.k_n = 1e4;
  cp.restitution = 0.5;
  cp.mu = 0.3;
  Mini m;
  TL_CHECK(mini_create(&m, &cp, 1));
  int per[3] = {1, 1, 0};
  const double L = 0.5;
  TL_CHECK(tl_domain_init_periodic_box(&m.domain, tl_v3(0, 0, -0.5), tl_v3(L, L, 0.5), per));
  int sp;
  TL_CHECK(tl_particles_add_species(m.p, "glass", 2500, 0.05, 0.05, &sp));
  double r = 0.05, mass = 2500 * 4.0 / 3.0 * TL_PI * r * r * r;
  m.g = tl_v3(0, 0, -9.81);
  TL_CHECK(tl_particles_add(m.p, tl_v3(0.36, 0.3, r - mass * 9.81 / cp.k_n), tl_v3(1.7, 0.9, 0), r, sp, NULL));
  m.dt = 1e-4;
  m.skin = 0.01;
  *n_linked = 0;
  if (kind < 0) {
    TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &m.wall[0]));
  } else {
    TlTriSurface *s = NULL;
    TL_CHECK(tl_trisurface_create_rectangle(0, 0, L, L, 0, 4, 4, kind, &s));
    if (link) {
      TlStatus st = tl_trisurface_link_periodic(s, &m.domain, 1e-9, n_linked);
      if (st != TL_OK) {
        tl_trisurface_destroy(&s);
        return st;
      }
    }
    TL_CHECK(tl_wall_trisurface_create(s, &m.wall[0]));
  }
  m.n_walls = 1;
  TL_CHECK(mini_forces(&m));
  for (int k = 0; k < steps; ++k) {
    TL_CHECK(mini_step(&m));
    force[k] = m.p->f[0];
  }
  mini_destroy(&m);
  return TL_OK;
}

static void test_periodic_seam(void)
{
  const int steps = 4000;
  double r = 0.05, mg = 2500 * 4.0 / 3.0 * TL_PI * r * r * r * 9.81;
  TlVec3 *ref = NULL, *f = NULL;
  TL_TEST_STATUS(tl_calloc(&ref, steps, sizeof *ref), TL_OK);
  TL_TEST_STATUS(tl_calloc(&f, steps, sizeof *f), TL_OK);
  size_t linked = 0;
  TL_TEST_STATUS(seam_run(-1, 0, steps, ref, &linked), TL_OK);
  for (int pattern = 0; pattern < 3; pattern += 2) {
    TL_TEST_STATUS(seam_run(pattern, 1, steps, f, &linked), TL_OK);
    double dev = 0;
    for (int k = 0; k < steps; ++k) dev = fmax(dev, tl_v3_norm(tl_v3_sub(f[k], ref[k])));
    printf("periodic seam, pattern %d: %zu edges joined, max |F - F_plane| / mg = %.3e\n", pattern, linked, dev / mg);
    TL_TEST_ASSERT(linked == 8, "pattern %d: %zu edges joined across the periodic faces, expected 8", pattern, linked);
    TL_TEST_ASSERT(dev < 1e-8 * mg, "pattern %d: force history across the seam differs by %g (mg %g)", pattern, dev, mg);
  }
  TL_TEST_STATUS(seam_run(0, 0, steps, f, &linked), TL_OK);
  double dev = 0;
  for (int k = 0; k < steps; ++k) dev = fmax(dev, tl_v3_norm(tl_v3_sub(f[k], ref[k])));
  printf("periodic seam not joined: max |F - F_plane| / mg = %.3f\n", dev / mg);
  TL_TEST_ASSERT(dev > 0.05 * mg, "an unjoined seam should be felt (%g)", dev);
  /* two triangles at the faces x = 0 and x = 2 of a cell periodic in x:
   * their edges on the faces are images; joined when traversed in opposite
   * directions, refused when traversed the same way */
  TlDomain dom;
  int per[3] = {1, 0, 0};
  TL_TEST_STATUS(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, -1), tl_v3(2, 1, 1), per), TL_OK);
  double x[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 2, 1, 0, 1.5, 0.5, 0};
  int good[6] = {0, 1, 2, 3, 4, 5}, flipped[6] = {0, 1, 2, 3, 5, 4};
  TlTriSurface *s = NULL;
  size_t nl = 0;
  TL_TEST_STATUS(tl_trisurface_create(6, x, 2, good, &s), TL_OK);
  TL_TEST_STATUS(tl_trisurface_link_periodic(s, &dom, 1e-9, &nl), TL_OK);
  TL_TEST_ASSERT(nl == 1, "one pair of image edges joined (%zu)", nl);
  tl_trisurface_destroy(&s);
  TL_TEST_STATUS(tl_trisurface_create(6, x, 2, flipped, &s), TL_OK);
  TL_TEST_STATUS(tl_trisurface_link_periodic(s, &dom, 1e-9, &nl), TL_ERR_ARG);
  tl_trisurface_destroy(&s);
  tl_free(&ref);
  tl_free(&f);
}

/* Grid = brute force for the contacts of a bumpy triangulated surface with a
 * polydisperse packing (radius ratio 10), open and periodic (x, y). */
static void test_grid_equals_brute(void)
{
  for (int periodic = 0; periodic < 2; ++periodic) {
    TestLaw cp = {0.0, 1.0, 0.0};
    cp.k_n = 1e3;
    Mini m;
    TL_TEST_STATUS(mini_create(&m, &cp, 0), TL_OK);
    int per[3] = {1, 1, 0};
    if (periodic) TL_TEST_STATUS(tl_domain_init_periodic_box(&m.domain, tl_v3(0, 0, 0), tl_v3(1, 1, 1), per), TL_OK);
    else TL_TEST_STATUS(tl_domain_init_open(&m.domain, tl_v3(0, 0, 0), tl_v3(1, 1, 1)), TL_OK);
    int sp;
    TL_TEST_STATUS(tl_particles_add_species(m.p, "poly", 1000, 0.004, 0.04, &sp), TL_OK);
    uint64_t seed = 1234 + (uint64_t)periodic;
    for (int i = 0; i < 3000; ++i) {
      double r = 0.004 * pow(10.0, urand(&seed)); /* ratio 10, more small ones */
      TlVec3 x = tl_v3(urand(&seed), urand(&seed), 0.5 + 0.1 * (urand(&seed) - 0.5));
      TL_TEST_STATUS(tl_particles_add(m.p, x, tl_v3(0, 0, 0), r, sp, NULL), TL_OK);
    }
    TlTriSurface *s = NULL;
    TL_TEST_STATUS(tl_trisurface_create_rectangle(0, 0, 1, 1, 0.5, 25, 25, 1, &s), TL_OK);
    for (size_t i = 0; i < s->n_vertices; ++i) s->x[i].z += 0.02 * (urand(&seed) - 0.5);
    TL_TEST_STATUS(tl_trisurface_update(s), TL_OK);
    TL_TEST_STATUS(tl_wall_trisurface_create(s, &m.wall[0]), TL_OK);
    m.n_walls = 1;
    m.dt = 1e-4;
    m.skin = 0.002;
    TL_TEST_STATUS(tl_wall_trisurface_set_corrections(m.wall[0], 0), TL_OK);
    /* the same contacts from the grid and from brute force, the grid built
     * before a small move (within skin/2) as between rebuilds */
    TL_TEST_STATUS(mini_forces(&m), TL_OK);
    for (size_t i = 0; i < m.p->n; ++i)
      m.p->x[i] = tl_v3_add(m.p->x[i], tl_v3(0.0009 * (urand(&seed) - 0.5), 0, 0.0009 * (urand(&seed) - 0.5)));
    TlWallStep st = {.particles = m.p, .grid = m.grid, .domain = &m.domain, .law = m.law, .dt = m.dt};
    TL_TEST_STATUS(m.wall[0]->ops->interact(m.wall[0], &st), TL_OK);
    TlTriContactSet *grid_set = NULL;
    TL_TEST_STATUS(tl_tricontacts_create(&grid_set), TL_OK);
    TL_TEST_STATUS(tl_tricontacts_append_all(grid_set, tl_wall_trisurface_contacts(m.wall[0])), TL_OK);
    TL_TEST_STATUS(tl_wall_trisurface_set_brute_force(m.wall[0], 1), TL_OK);
    TL_TEST_STATUS(m.wall[0]->ops->interact(m.wall[0], &st), TL_OK);
    const TlTriContactSet *brute = tl_wall_trisurface_contacts(m.wall[0]);
    int same = grid_set->count == brute->count;
    size_t wrapped = 0;
    for (size_t k = 0; same && k < brute->count; ++k) {
      same &= grid_set->c[k].particle == brute->c[k].particle && grid_set->c[k].triangle == brute->c[k].triangle &&
              grid_set->c[k].overlap == brute->c[k].overlap;
      wrapped += fabs(brute->c[k].center.x - m.p->x[brute->c[k].particle].x) > 0.5 ||
                 fabs(brute->c[k].center.y - m.p->x[brute->c[k].particle].y) > 0.5;
    }
    printf("%s: %zu wall contacts (grid) vs %zu (brute force), %zu through a periodic boundary\n",
           periodic ? "periodic" : "open", grid_set->count, brute->count, wrapped);
    TL_TEST_ASSERT(same && brute->count > 1000, "%s: grid and brute force differ (%zu vs %zu)",
                   periodic ? "periodic" : "open", grid_set->count, brute->count);
    if (periodic) TL_TEST_ASSERT(wrapped > 5, "periodic images: only %zu contacts wrap", wrapped);

    /* with corrections, a frictional law and 1 or 2 threads: identical forces */
    TL_TEST_STATUS(tl_wall_trisurface_set_brute_force(m.wall[0], 0), TL_OK);
    TL_TEST_STATUS(tl_wall_trisurface_set_corrections(m.wall[0], 1), TL_OK);
    TlVec3 *f1 = NULL;
    TL_TEST_STATUS(tl_calloc(&f1, m.p->n, sizeof *f1), TL_OK);
    for (int th = 1; th <= 2; ++th) {
      omp_set_num_threads(th);
      TL_TEST_STATUS(mini_forces(&m), TL_OK);
      if (th == 1) memcpy(f1, m.p->f, m.p->n * sizeof *f1);
    }
    TL_TEST_ASSERT(memcmp(f1, m.p->f, m.p->n * sizeof *f1) == 0, "forces differ between 1 and 2 threads");
    tl_free(&f1);

    /* a moving surface and moving particles, small steps: the candidate
     * list is kept while the displacements allow it and rebuilt after; the
     * contacts stay those of brute force at every step */
    TL_TEST_STATUS(tl_wall_trisurface_set_corrections(m.wall[0], 0), TL_OK);
    TlTriSurface *ms = tl_wall_trisurface_surface(m.wall[0]);
    int all_same = 1;
    for (int it = 0; it < 6; ++it) {
      for (size_t i = 0; i < ms->n_vertices; ++i) ms->x[i].z += 0.0002 * (urand(&seed) - 0.5) + 0.0004;
      TL_TEST_STATUS(tl_trisurface_update(ms), TL_OK);
      for (size_t i = 0; i < m.p->n; ++i) m.p->x[i].z -= 0.0001 * urand(&seed);
      TL_TEST_STATUS(tl_wall_trisurface_set_brute_force(m.wall[0], 0), TL_OK);
      TL_TEST_STATUS(m.wall[0]->ops->interact(m.wall[0], &st), TL_OK);
      tl_tricontacts_clear(grid_set);
      TL_TEST_STATUS(tl_tricontacts_append_all(grid_set, tl_wall_trisurface_contacts(m.wall[0])), TL_OK);
      TL_TEST_STATUS(tl_wall_trisurface_set_brute_force(m.wall[0], 1), TL_OK);
      TL_TEST_STATUS(m.wall[0]->ops->interact(m.wall[0], &st), TL_OK);
      brute = tl_wall_trisurface_contacts(m.wall[0]);
      int same_it = grid_set->count == brute->count && brute->count > 1000;
      for (size_t k = 0; same_it && k < brute->count; ++k)
        same_it &= grid_set->c[k].particle == brute->c[k].particle && grid_set->c[k].triangle == brute->c[k].triangle;
      all_same &= same_it;
    }
    TL_TEST_ASSERT(all_same, "%s: moving surface: grid and brute force differ", periodic ? "periodic" : "open");
    tl_tricontacts_destroy(&grid_set);
    mini_destroy(&m);
  }
}

/* The wall velocity at the contact point comes from the vertex velocities:
 * a damped contact with a surface whose vertices move feels the same force
 * as a plane moving with the interpolated velocity. */
static void test_moving_surface(void)
{
  TestLaw cp = {0.0, 1.0, 0.0};
  cp.k_n = 1e3;
  cp.restitution = 0.3;
  TlVec3 fplane = tl_v3(0, 0, 0), fsurf = tl_v3(0, 0, 0);
  for (int kind = 0; kind < 2; ++kind) {
    Mini m;
    TL_TEST_STATUS(mini_create(&m, &cp, 0), TL_OK);
    int sp;
    TL_TEST_STATUS(tl_particles_add_species(m.p, "a", 1000, 0.1, 0.1, &sp), TL_OK);
    TL_TEST_STATUS(tl_particles_add(m.p, tl_v3(0.3, 0.4, 0.09), tl_v3(0.1, 0, -0.2), 0.1, sp, NULL), TL_OK);
    m.dt = 1e-4;
    /* vertex velocities v_z = 0.5 + 2 x - y: at (0.3, 0.4) that is 0.7 */
    if (kind == 0) {
      TL_TEST_STATUS(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &m.wall[0]), TL_OK);
      TL_TEST_STATUS(tl_wall_plane_set_velocity(m.wall[0], tl_v3(0, 0, 0.7)), TL_OK);
    } else {
      TlTriSurface *s = NULL;
      TL_TEST_STATUS(tl_trisurface_create_rectangle(0, 0, 1, 1, 0, 3, 3, 2, &s), TL_OK);
      for (size_t i = 0; i < s->n_vertices; ++i) s->v[i] = tl_v3(0, 0, 0.5 + 2 * s->x[i].x - s->x[i].y);
      TL_TEST_STATUS(tl_wall_trisurface_create(s, &m.wall[0]), TL_OK);
    }
    m.n_walls = 1;
    TL_TEST_STATUS(mini_forces(&m), TL_OK);
    if (kind == 0) fplane = m.p->f[0];
    else fsurf = m.p->f[0];
    mini_destroy(&m);
  }
  printf("moving: plane force %.12g, surface force %.12g\n", fplane.z, fsurf.z);
  TL_TEST_ASSERT(fplane.z > 20.0, "damping adds to the spring force (%g)", fplane.z);
  TL_TEST_CLOSE(tl_v3_norm(tl_v3_sub(fsurf, fplane)), 0.0, 1e-10);
}

/* A surface moved every step by tl_trisurface_move_vertices, whose wall
 * refreshes only the triangles near particles, gives the same trajectories
 * bit for bit as one fully updated every step; frictional grains with
 * rotation on a rippling, folding sheet (convex and concave edges). */
static TlStatus ripple_run(int partial, int steps, TlVec3 *x_end, long *builds)
{
  TestLaw cp = {0.0, 1.0, 0.0};
  cp.k_n = 2e4;
  cp.restitution = 0.5;
  cp.mu = 0.4;
  Mini m;
  TL_CHECK(mini_create(&m, &cp, 1));
  TlTriSurface *s = NULL;
  TL_CHECK(tl_trisurface_create_rectangle(0, 0, 1, 1, 0, 12, 12, 2, &s));
  TL_CHECK(tl_wall_trisurface_create(s, &m.wall[0]));
  m.n_walls = 1;
  int sp;
  TL_CHECK(tl_particles_add_species(m.p, "g", 2000, 0.03, 0.03, &sp));
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      TL_CHECK(tl_particles_add(m.p, tl_v3(0.1 + 0.2 * i, 0.1 + 0.2 * j, 0.031), tl_v3(0.3 * (i - 2), 0.2 * (j - 2), 0), 0.03, sp, NULL));
  m.dt = 2e-5;
  m.skin = 0.01;
  m.g = tl_v3(0, 0, -9.81);
  size_t nv = s->n_vertices;
  double *x0 = NULL, *x = NULL, *v = NULL;
  TL_CHECK(tl_calloc(&x0, 3 * nv, sizeof *x0));
  TL_CHECK(tl_calloc(&x, 3 * nv, sizeof *x));
  TL_CHECK(tl_calloc(&v, 3 * nv, sizeof *v));
  for (size_t i = 0; i < nv; ++i) x0[3 * i] = s->x[i].x, x0[3 * i + 1] = s->x[i].y, x0[3 * i + 2] = s->x[i].z;
  TlStatus st = TL_OK;
  for (int it = 0; it < steps && st == TL_OK; ++it) {
    const double t = m.t + m.dt, om = 40.0;
    for (size_t i = 0; i < nv; ++i) {
      const double *X = x0 + 3 * i;
      double ph = 9.0 * X[0] + 7.0 * X[1] - om * t;
      x[3 * i] = X[0], x[3 * i + 1] = X[1], x[3 * i + 2] = 0.01 * sin(ph);
      v[3 * i] = v[3 * i + 1] = 0.0, v[3 * i + 2] = -0.01 * om * cos(ph);
    }
    st = partial ? tl_trisurface_move_vertices(s, x, v) : tl_trisurface_set_vertices(s, x, v);
    if (st == TL_OK) st = mini_step(&m);
  }
  for (size_t i = 0; i < m.p->n; ++i) x_end[i] = m.p->x[i];
  *builds = (long)s->version;
  tl_free(&x0);
  tl_free(&x);
  tl_free(&v);
  mini_destroy(&m);
  return st;
}

static void test_partial_update(void)
{
  TlVec3 xa[25], xb[25];
  long va = 0, vb = 0;
  TL_TEST_STATUS(ripple_run(0, 400, xa, &va), TL_OK);
  TL_TEST_STATUS(ripple_run(1, 400, xb, &vb), TL_OK);
  double moved = 0.0;
  for (int i = 0; i < 25; ++i) moved = fmax(moved, fabs(xa[i].z - 0.031));
  printf("partial update: largest vertical excursion %.3g m; trajectories %s\n", moved,
         memcmp(xa, xb, sizeof xa) == 0 ? "bit-identical" : "differ");
  TL_TEST_ASSERT(moved > 1e-3, "the ripple moved the grains (%g m)", moved);
  TL_TEST_ASSERT(memcmp(xa, xb, sizeof xa) == 0, "partial and full geometry updates give different trajectories");
}

int main(void)
{
  test_features();
  test_box_bounce();
  test_sliding_triangulations();
  test_periodic_seam();
  test_grid_equals_brute();
  test_moving_surface();
  test_partial_update();
  return tl_test_report();
}
