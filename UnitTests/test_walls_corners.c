/* Triangulated walls at genuine corners: a box of 12 triangles gives the
 * force of the same box made of 6 planes when a sphere is pressed into any
 * of its 12 edges and 8 corners (the faces meet at 90 degrees, sharper than
 * the feature angle, so their contacts add), and a sphere bouncing through
 * edge and corner impacts follows the planes' trajectory; with the feature
 * angle at 180 degrees (the corrections of seeds/001 alone) the same presses
 * give 1/2 and 1/3 of the planes' force.  A nearly flat concave fold (below
 * the feature angle) keeps the weighted mean of seeds/001, a sharper one
 * adds, and a fold that crosses the feature angle as the surface deforms is
 * reclassified by the full and the partial geometry updates.  The feature
 * angle by name: set, and refused outside [0, 180]. */
#include <stdint.h>
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

/* The larger of an accumulated error and a new one; a NaN sticks (fmax
 * would drop it), so that the assertions on it fail. */
static double worse(double acc, double e)
{
  if (acc != acc) return acc;
  return (e > acc || e != e) ? e : acc;
}

static const TlVec3 LO = {0.0, 0.0, 0.0}, HI = {1.0, 1.5, 2.0}; /* a box that is not a cube */

/* One sphere, the walls of a box, one law, Velocity-Verlet. */
typedef struct {
  TlParticles *p;
  TlHGrid *grid;
  TlDomain domain;
  TlContactLaw *law;
  TlWall *wall[6];
  int n_walls;
  double dt, skin;
  TlVec3 g, x_build;
  int built;
} Scene;

/* kind 0: six planes; 1: twelve triangles with the default feature angle;
 * 2: twelve triangles with the feature angle 180 (no sharp edge). */
static TlStatus scene_create(Scene *m, int kind, double mu)
{
  memset(m, 0, sizeof *m);
  TL_CHECK(tl_particles_create(&m->p));
  TL_CHECK(tl_particles_enable_rotation(m->p));
  TL_CHECK(tl_hgrid_create(&m->grid));
  TL_CHECK(tl_domain_init_open(&m->domain, tl_v3(-1, -1, -1), tl_v3(3, 3, 3)));
  /* steel sphere of 0.1 m at 4 m/s: overlaps of a few mm */
  TL_CHECK(tl_test_law(&m->law, "linear", "k_n", 1e7, "restitution", 0.7, "mu", mu, (const char *)NULL));
  int sp;
  TL_CHECK(tl_particles_add_species(m->p, "steel", 7800, 0.1, 0.1, &sp));
  TL_CHECK(tl_particles_add(m->p, tl_v3(0.5, 0.5, 0.5), tl_v3(0, 0, 0), 0.1, sp, NULL));
  m->dt = 2e-5;
  m->skin = 0.02;
  if (kind == 0) {
    for (int k = 0; k < 3; ++k) {
      TlVec3 n = tl_v3(k == 0, k == 1, k == 2);
      TL_CHECK(tl_wall_plane_create(LO, n, &m->wall[m->n_walls++]));
      TL_CHECK(tl_wall_plane_create(HI, tl_v3_neg(n), &m->wall[m->n_walls++]));
    }
  } else {
    TlTriSurface *s = NULL;
    TL_CHECK(tl_trisurface_create_box(LO, HI, &s));
    TlWallSetting angle = {"feature_angle", kind == 2 ? 180.0 : TL_TRISURFACE_FEATURE_ANGLE};
    TL_CHECK(tl_wall_create("trisurface", 1, &angle, &m->wall[0]));
    m->n_walls = 1;
    TL_CHECK(tl_wall_trisurface_set_surface(m->wall[0], s));
  }
  return TL_OK;
}

static void scene_destroy(Scene *m)
{
  for (int k = 0; k < m->n_walls; ++k) tl_wall_destroy(&m->wall[k]);
  tl_contact_law_destroy(&m->law);
  tl_hgrid_destroy(&m->grid);
  tl_particles_destroy(&m->p);
}

/* Forces and torques on the sphere; *n_contacts the contacts kept. */
static TlStatus scene_forces(Scene *m, int *n_contacts)
{
  TlParticles *p = m->p;
  p->f[0] = tl_v3(0, 0, 0);
  p->torque[0] = tl_v3(0, 0, 0);
  if (!m->built || tl_v3_norm(tl_v3_sub(p->x[0], m->x_build)) > 0.5 * m->skin) {
    TL_CHECK(tl_hgrid_build(m->grid, &m->domain, p->n, p->x, p->radius, m->skin));
    m->x_build = p->x[0];
    m->built = 1;
  }
  TlWallStep st = {.particles = p, .grid = m->grid, .domain = &m->domain, .law = m->law, .dt = m->dt};
  int nc = 0;
  for (int k = 0; k < m->n_walls; ++k) {
    TL_CHECK(m->wall[k]->ops->interact(m->wall[k], &st));
    nc += (int)m->wall[k]->n_contacts;
  }
  if (n_contacts) *n_contacts = nc;
  return TL_OK;
}

static TlStatus scene_step(Scene *m, int *n_contacts)
{
  TlParticles *p = m->p;
  p->v[0] = tl_v3_axpy(p->v[0], 0.5 * m->dt, tl_v3_axpy(m->g, p->inv_mass[0], p->f[0]));
  p->w[0] = tl_v3_axpy(p->w[0], 0.5 * m->dt * p->inv_inertia[0], p->torque[0]);
  p->x[0] = tl_v3_axpy(p->x[0], m->dt, p->v[0]);
  TL_CHECK(scene_forces(m, n_contacts));
  p->v[0] = tl_v3_axpy(p->v[0], 0.5 * m->dt, tl_v3_axpy(m->g, p->inv_mass[0], p->f[0]));
  p->w[0] = tl_v3_axpy(p->w[0], 0.5 * m->dt * p->inv_inertia[0], p->torque[0]);
  return TL_OK;
}

/* Force and torque on the sphere at x with velocity v and spin w, from a
 * fresh scene of the given kind (no history from earlier presses); for the
 * planes also the weighted mean of their contact forces (what Modification 2
 * makes of them when the faces are one piece). */
static TlStatus press(int kind, double mu, TlVec3 x, TlVec3 v, TlVec3 w, TlVec3 *f, TlVec3 *tq,
                      int *nc, TlVec3 *mean)
{
  Scene m;
  TL_CHECK(scene_create(&m, kind, mu));
  m.p->x[0] = x, m.p->v[0] = v, m.p->w[0] = w;
  TlStatus status = scene_forces(&m, nc);
  *f = m.p->f[0], *tq = m.p->torque[0];
  if (mean) {
    TlVec3 num = tl_v3(0, 0, 0);
    double den = 0;
    for (int k = 0; k < m.n_walls; ++k) {
      TlVec3 fk;
      if (!tl_wall_plane_contact_force(m.wall[k], 0, &fk)) continue;
      num = tl_v3_add(num, tl_v3_scale(fk, tl_v3_norm(fk)));
      den += tl_v3_norm(fk);
    }
    *mean = tl_v3_scale(num, 1.0 / den);
  }
  scene_destroy(&m);
  return status;
}

/* The sphere (radius 0.1) pressed into every edge and corner: its centre at
 * depth delta_k into each face it touches (different depths, so that sum and
 * mean differ in direction as well), at several places along each edge,
 * moving and spinning (so damping and friction act as well), and once
 * symmetric and at rest. */
static void test_press(void)
{
  const double mu = 0.3;
  const double r = 0.1;
  const double lo[3] = {LO.x, LO.y, LO.z}, hi[3] = {HI.x, HI.y, HI.z};
  double worst[2] = {0, 0}, worst_mean[2] = {0, 0}, sym[2][2] = {{INFINITY, 0}, {INFINITY, 0}}, sym_dev[2] = {0, 0};
  int count[2] = {0, 0}, bad_count = 0;
  uint64_t seed = 3;
  for (int kind = 0; kind < 2; ++kind) /* 0: edges, 1: corners */
    for (int which = 0; which < (kind ? 8 : 12); ++which)
      for (int place = 0; place < 5; ++place) {
        double x[3];
        int symmetric = place == 4, touching = kind ? 3 : 2;
        if (kind == 0) {
          /* axis a free, the other two at a low or high face */
          int a = which / 4, b = (a + 1) % 3, c = (a + 2) % 3;
          double d1 = symmetric ? 0.02 : 0.005 + 0.02 * urand(&seed);
          double d2 = symmetric ? 0.02 : 0.005 + 0.02 * urand(&seed);
          x[a] = lo[a] + (hi[a] - lo[a]) * (0.15 + 0.175 * place);
          x[b] = which & 1 ? hi[b] - (r - d1) : lo[b] + (r - d1);
          x[c] = which & 2 ? hi[c] - (r - d2) : lo[c] + (r - d2);
        } else {
          /* symmetric: the projections on the faces fall on the diagonals
           * of the triangulation at some corners, where two triangles tie */
          for (int k = 0; k < 3; ++k) {
            double d = symmetric ? 0.02 : 0.005 + 0.02 * urand(&seed);
            x[k] = (which >> k) & 1 ? hi[k] - (r - d) : lo[k] + (r - d);
          }
        }
        TlVec3 X = tl_v3(x[0], x[1], x[2]);
        TlVec3 v = symmetric ? tl_v3(0, 0, 0) : tl_v3(0.3 * urand(&seed), -0.2, 0.1);
        TlVec3 w = symmetric ? tl_v3(0, 0, 0) : tl_v3(2, 1, -3 * urand(&seed));
        TlVec3 f[3], tq[3], mean;
        int nc[3];
        for (int k = 0; k < 3; ++k)
          TL_TEST_STATUS(press(k, mu, X, v, w, &f[k], &tq[k], &nc[k], k == 0 ? &mean : NULL), TL_OK);
        double fp = tl_v3_norm(f[0]);
        double e = worse(tl_v3_norm(tl_v3_sub(f[1], f[0])), tl_v3_norm(tl_v3_sub(tq[1], tq[0])) / r) / fp;
        double em = tl_v3_norm(tl_v3_sub(f[2], mean)) / fp;
        bad_count += !(nc[0] == touching && nc[1] == touching && nc[2] == touching);
        worst[kind] = worse(worst[kind], e);
        worst_mean[kind] = worse(worst_mean[kind], em);
        if (symmetric) {
          double ratio = tl_v3_norm(f[2]) / fp;
          sym[kind][0] = fmin(sym[kind][0], ratio);
          sym[kind][1] = fmax(sym[kind][1], ratio);
          sym_dev[kind] = worse(sym_dev[kind], fabs(ratio - (kind ? 1.0 / 3.0 : 0.5)));
        }
        ++count[kind];
      }
  printf("press: %d edge and %d corner positions; max |F_tri - F_planes| / |F_planes| (torque / r likewise): edges "
         "%.2e, corners %.2e\n", count[0], count[1], worst[0], worst[1]);
  printf("feature angle 180 (mean only): off the planes' weighted mean by %.2e (edges), %.2e (corners); symmetric "
         "presses |F| / |F_planes| = %.6f..%.6f (edges), %.6f..%.6f (corners)\n", worst_mean[0], worst_mean[1],
         sym[0][0], sym[0][1], sym[1][0], sym[1][1]);
  TL_TEST_ASSERT(bad_count == 0, "%d positions without 2 (edge) or 3 (corner) contacts", bad_count);
  TL_TEST_ASSERT(worst[0] < 1e-13, "edges: triangles differ from planes by %g (relative)", worst[0]);
  TL_TEST_ASSERT(worst[1] < 1e-13, "corners: triangles differ from planes by %g (relative)", worst[1]);
  /* what the mean alone gives: the weighted mean, 1/2 at an edge, 1/3 in a corner */
  TL_TEST_ASSERT(worst_mean[0] < 1e-13 && worst_mean[1] < 1e-13, "the mean alone: off by %g, %g", worst_mean[0],
                 worst_mean[1]);
  TL_TEST_ASSERT(sym_dev[0] < 1e-12, "edges: %g..%g, not 1/2", sym[0][0], sym[0][1]);
  TL_TEST_ASSERT(sym_dev[1] < 1e-12, "corners: %g..%g, not 1/3", sym[1][0], sym[1][1]);
}

/* A spinning sphere under gravity thrown, with friction, at a corner, at
 * the opposite corner and at two edges of the box, then left to bounce for
 * 1.2 s: corner, edge and face impacts, the same with planes and with
 * triangles. */
static void test_bounce(void)
{
  const double mu = 0.4;
  const int steps = 60000; /* 1.2 s */
  const double T = 0.2;    /* time to the aimed point */
  enum { N_THROWS = 4 };
  const TlVec3 start[N_THROWS] = {{0.55, 0.8, 1.0}, {0.45, 0.6, 0.9}, {0.6, 0.9, 1.2}, {0.3, 0.7, 0.8}};
  const TlVec3 aim[N_THROWS] = {{0.095, 0.096, 0.094}, {0.904, 1.405, 1.906}, {0.5, 0.094, 0.095}, {0.905, 0.8, 1.906}};
  const TlVec3 g = {0, 0, -9.81};
  TlVec3 *x[2] = {NULL, NULL}, *w[2] = {NULL, NULL};
  int *nc[2] = {NULL, NULL};
  for (int k = 0; k < 2; ++k) {
    TL_TEST_STATUS(tl_calloc(&x[k], steps, sizeof *x[k]), TL_OK);
    TL_TEST_STATUS(tl_calloc(&w[k], steps, sizeof *w[k]), TL_OK);
    TL_TEST_STATUS(tl_calloc(&nc[k], steps, sizeof *nc[k]), TL_OK);
    if (!x[k] || !w[k] || !nc[k]) return;
  }
  double dx = 0, dw = 0;
  int impacts[4] = {0, 0, 0, 0}, corner_first = 0, edge_first = 0, same_contacts = 1;
  for (int throw = 0; throw < N_THROWS; ++throw) {
    for (int k = 0; k < 2; ++k) {
      Scene sc;
      TL_TEST_STATUS(scene_create(&sc, k, mu), TL_OK);
      if (!sc.p) return;
      sc.g = g;
      TlParticles *p = sc.p;
      p->x[0] = start[throw];
      /* x(T) = x0 + v0 T + g T^2 / 2 = aim */
      p->v[0] = tl_v3_scale(tl_v3_sub(tl_v3_sub(aim[throw], start[throw]), tl_v3_scale(g, 0.5 * T * T)), 1.0 / T);
      p->w[0] = tl_v3(5, -3, 8);
      TL_TEST_STATUS(scene_forces(&sc, NULL), TL_OK);
      TlStatus status = TL_OK;
      for (int s = 0; s < steps && status == TL_OK; ++s) {
        status = scene_step(&sc, &nc[k][s]);
        x[k][s] = p->x[0];
        w[k][s] = p->w[0];
      }
      TL_TEST_STATUS(status, TL_OK);
      scene_destroy(&sc);
    }
    int first = 0;
    for (int s = 0; s < steps; ++s) {
      dx = worse(dx, tl_v3_norm(tl_v3_sub(x[0][s], x[1][s])));
      dw = worse(dw, tl_v3_norm(tl_v3_sub(w[0][s], w[1][s])));
      same_contacts &= nc[0][s] == nc[1][s];
      /* an impact: the most walls touched during one contact period */
      if (nc[0][s] > 0 && (s == 0 || nc[0][s - 1] == 0)) {
        int most = 0;
        for (int q = s; q < steps && nc[0][q] > 0; ++q) most = nc[0][q] > most ? nc[0][q] : most;
        ++impacts[most];
        if (!first) first = most;
      }
    }
    corner_first += throw < 2 && first == 3;
    edge_first += throw >= 2 && first == 2;
  }
  printf("bounce: impacts on %d faces, %d edges, %d corners (%d throws began in a corner, %d on an edge); max "
         "position difference %.3e m, spin %.3e 1/s\n", impacts[1], impacts[2], impacts[3], corner_first, edge_first,
         dx, dw);
  TL_TEST_ASSERT(corner_first == 2 && edge_first == 2, "the throws should begin with 2 corner (%d) and 2 edge (%d) "
                 "impacts", corner_first, edge_first);
  TL_TEST_ASSERT(impacts[1] >= 10, "only %d face impacts", impacts[1]);
  TL_TEST_ASSERT(same_contacts, "planes and triangles touched a different number of faces at some step");
  /* round-off, amplified by 18 impacts with friction over 1.2 s: the
   * difference grows smoothly (a factor of 4 every few thousand steps) from
   * 1e-15, with no jump at any impact */
  TL_TEST_ASSERT(dx < 1e-10 && dw < 1e-8, "triangles and planes differ: position %g m, spin %g 1/s", dx, dw);
  for (int k = 0; k < 2; ++k) {
    tl_free(&x[k]);
    tl_free(&w[k]);
    tl_free(&nc[k]);
  }
}

/* Two unit squares folded about the y axis by theta (concave seen from +z),
 * each split along a diagonal. */
static void hinge_vertices(double theta, double x[18])
{
  double c = cos(theta), s = sin(theta);
  const double v[18] = {-1, -1, 0, 0, -1, 0, c, -1, s, -1, 1, 0, 0, 1, 0, c, 1, s};
  memcpy(x, v, sizeof v);
}

static TlStatus hinge(double theta, TlTriSurface **s)
{
  double x[18];
  hinge_vertices(theta, x);
  int tri[12] = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
  TL_CHECK(tl_trisurface_create(6, x, 4, tri, s));
  return TL_OK;
}

/* The sphere in the valley of the hinge through the wall: the total force
 * against the single-face forces a (triangle on face A) and b (face B). */
static void test_fold(void)
{
  const double r = 0.2;
  struct {
    double theta_deg, feature_deg;
    int adds;
  } cases[] = {{20, TL_TRISURFACE_FEATURE_ANGLE, 0}, {34, TL_TRISURFACE_FEATURE_ANGLE, 0},
               {36, TL_TRISURFACE_FEATURE_ANGLE, 1}, {60, TL_TRISURFACE_FEATURE_ANGLE, 1},
               {60, 75, 0},                          {20, 10, 1}};
  for (size_t q = 0; q < sizeof cases / sizeof cases[0]; ++q) {
    double th = cases[q].theta_deg * TL_PI / 180.0;
    Scene m;
    memset(&m, 0, sizeof m);
    TL_TEST_STATUS(tl_particles_create(&m.p), TL_OK);
    TL_TEST_STATUS(tl_particles_enable_rotation(m.p), TL_OK);
    TL_TEST_STATUS(tl_hgrid_create(&m.grid), TL_OK);
    TL_TEST_STATUS(tl_domain_init_open(&m.domain, tl_v3(-2, -2, -2), tl_v3(2, 2, 2)), TL_OK);
    TL_TEST_STATUS(tl_test_law(&m.law, "linear", "k_n", 1e7, "restitution", 0.7, (const char *)NULL), TL_OK);
    int sp;
    TL_TEST_STATUS(tl_particles_add_species(m.p, "glass", 2500, 0.1, 0.1, &sp), TL_OK);
    /* off-centre in the valley: depths into A and B differ */
    TlVec3 nb = tl_v3(-sin(th), 0, cos(th)), eb = tl_v3(cos(th), 0, sin(th));
    TlVec3 x = tl_v3_add(tl_v3_add(tl_v3(0, 0.13, 0), tl_v3_scale(eb, 0.03)), tl_v3_scale(nb, r - 0.03));
    x.z -= 0.01;
    TL_TEST_STATUS(tl_particles_add(m.p, x, tl_v3(0, 0, 0), r, sp, NULL), TL_OK);
    TlTriSurface *s = NULL;
    TL_TEST_STATUS(hinge(th, &s), TL_OK);
    TlWallSetting set[2] = {{"feature_angle", cases[q].feature_deg}, {"brute_force", 1}};
    TL_TEST_STATUS(tl_wall_create("trisurface", 2, set, &m.wall[0]), TL_OK);
    if (!m.wall[0] || !s || !m.p) return;
    TL_TEST_STATUS(tl_wall_trisurface_set_surface(m.wall[0], s), TL_OK);
    m.n_walls = 1;
    m.dt = 1e-5;
    TL_TEST_STATUS(scene_forces(&m, NULL), TL_OK);
    const TlTriContactSet *c = tl_wall_trisurface_contacts(m.wall[0]);
    /* the raw forces of the kept contacts (undo the weights) */
    TlVec3 sum = tl_v3(0, 0, 0), wmean = tl_v3(0, 0, 0);
    double norms = 0;
    for (size_t k = 0; c && k < c->count; ++k) {
      TlVec3 raw = tl_v3_scale(c->c[k].force, 1.0 / c->c[k].weight);
      sum = tl_v3_add(sum, raw);
      norms += tl_v3_norm(raw);
      wmean = tl_v3_add(wmean, tl_v3_scale(raw, tl_v3_norm(raw)));
    }
    wmean = tl_v3_scale(wmean, 1.0 / norms);
    TlVec3 expect = cases[q].adds ? sum : wmean;
    TlVec3 f = m.p->f[0];
    double err = tl_v3_norm(tl_v3_sub(f, expect)) / tl_v3_norm(expect);
    double apart = tl_v3_norm(tl_v3_sub(sum, wmean)) / tl_v3_norm(sum);
    printf("fold %4.0f deg, feature angle %3.0f: %zu contacts, |F| = %.4f (sum %.4f, weighted mean %.4f), %s\n",
           cases[q].theta_deg, cases[q].feature_deg, c ? c->count : 0, tl_v3_norm(f), tl_v3_norm(sum),
           tl_v3_norm(wmean), cases[q].adds ? "adds" : "mean");
    TL_TEST_ASSERT(c && c->count == 2, "fold %g: %zu contacts, expected one on each face", cases[q].theta_deg,
                   c ? c->count : 0);
    TL_TEST_ASSERT(apart > 0.3, "fold %g: sum and mean should differ (%g)", cases[q].theta_deg, apart);
    TL_TEST_ASSERT(err < 1e-14, "fold %g, feature %g: force off the %s by %g", cases[q].theta_deg,
                   cases[q].feature_deg, cases[q].adds ? "sum" : "mean", err);
    scene_destroy(&m);
  }
}

/* A deforming hinge whose fold crosses the feature angle: the sharpness of
 * its edge follows, through the full and through the partial update. */
static void test_reclassify(void)
{
  TlTriSurface *s = NULL;
  TL_TEST_STATUS(hinge(0.1, &s), TL_OK);
  if (!s) return;
  int shared = -1;
  for (size_t e = 0; e < s->n_edges; ++e)
    if (s->edge_tri[2 * e] >= 0 && s->edge_tri[2 * e + 1] >= 0 && s->edge_vertex[2 * e] == 1 &&
        s->edge_vertex[2 * e + 1] == 4)
      shared = (int)e;
  TL_TEST_ASSERT(shared >= 0, "the hinge edge");
  if (shared < 0) return;
  TL_TEST_ASSERT(s->edge_shape[shared] == TL_EDGE_CONCAVE && !s->edge_sharp[shared], "10 degrees: smooth valley");
  double x[18];
  hinge_vertices(50 * TL_PI / 180, x);
  TL_TEST_STATUS(tl_trisurface_set_vertices(s, x, NULL), TL_OK);
  TL_TEST_ASSERT(s->edge_shape[shared] == TL_EDGE_CONCAVE && s->edge_sharp[shared], "50 degrees: sharp valley");
  hinge_vertices(-50 * TL_PI / 180, x);
  TL_TEST_STATUS(tl_trisurface_set_vertices(s, x, NULL), TL_OK);
  TL_TEST_ASSERT(s->edge_shape[shared] == TL_EDGE_CONVEX && s->edge_sharp[shared], "-50 degrees: sharp ridge");
  /* partial update of the triangles on one side */
  hinge_vertices(20 * TL_PI / 180, x);
  TL_TEST_STATUS(tl_trisurface_move_vertices(s, x, NULL), TL_OK);
  int32_t touched[1] = {3};
  TL_TEST_STATUS(tl_trisurface_update_triangles(s, 1, touched), TL_OK);
  TL_TEST_ASSERT(s->edge_shape[shared] == TL_EDGE_CONCAVE && !s->edge_sharp[shared],
                 "20 degrees after a partial update: smooth valley");
  /* exactly flat: the predicate says coplanar */
  hinge_vertices(0, x);
  TL_TEST_STATUS(tl_trisurface_set_vertices(s, x, NULL), TL_OK);
  TL_TEST_ASSERT(s->edge_shape[shared] == TL_EDGE_FLAT && s->edge_fold[shared] == 0.0 && !s->edge_sharp[shared],
                 "flat: shape %d, fold %g", s->edge_shape[shared], s->edge_fold[shared]);
  /* exactly coplanar but tilted: the plane z = x + y through points whose
   * coordinates are multiples of 2^-30 (so z is exact), where the computed
   * normals and folds carry round-off.  With a flat tolerance below
   * round-off (1e-300), only the exact predicate can tell: coplanar faces
   * are flat with a zero fold, and a far vertex nudged by one ulp never
   * gives the wrong sense (it may read flat when the computed fold is 0:
   * the magnitude is a double) */
  {
    TL_TEST_STATUS(tl_trisurface_set_tolerances(s, 1e-300, s->quality_tolerance), TL_OK);
    uint64_t seed = 11;
    int flat_ok = 0, wrong_sense = 0, folded = 0, trials = 500;
    for (int trial = 0; trial < trials; ++trial) {
      double xt[18], sx = 0.2 + urand(&seed), sy = 0.2 + urand(&seed), ox = urand(&seed) - 0.5, oy = urand(&seed);
      hinge_vertices(0, xt);
      for (int v = 0; v < 6; ++v) {
        xt[3 * v] = ldexp(nearbyint(ldexp(sx * xt[3 * v] + ox + 0.01 * urand(&seed), 30)), -30);
        xt[3 * v + 1] = ldexp(nearbyint(ldexp(sy * xt[3 * v + 1] + oy + 0.01 * urand(&seed), 30)), -30);
        xt[3 * v + 2] = xt[3 * v] + xt[3 * v + 1];
      }
      TL_TEST_STATUS(tl_trisurface_set_vertices(s, xt, NULL), TL_OK);
      flat_ok += s->edge_shape[shared] == TL_EDGE_FLAT && s->edge_fold[shared] == 0.0;
      int ta = s->edge_tri[2 * shared], tb = s->edge_tri[2 * shared + 1], far = -1;
      for (int k = 0; k < 3; ++k) {
        int v = s->tri[3 * tb + k];
        if (v != s->edge_vertex[2 * shared] && v != s->edge_vertex[2 * shared + 1]) far = v;
      }
      /* raising the far vertex moves it to the side A's normal points to
       * when that normal has a positive z */
      int up_shape = s->normal[ta].z > 0 ? TL_EDGE_CONCAVE : TL_EDGE_CONVEX;
      int down_shape = up_shape == TL_EDGE_CONCAVE ? TL_EDGE_CONVEX : TL_EDGE_CONCAVE;
      for (int dir = 1; dir >= -1; dir -= 2) {
        double y[18];
        memcpy(y, xt, sizeof y);
        y[3 * far + 2] = nextafter(y[3 * far + 2], dir * INFINITY);
        TL_TEST_STATUS(tl_trisurface_set_vertices(s, y, NULL), TL_OK);
        int shape = s->edge_shape[shared];
        folded += shape != TL_EDGE_FLAT;
        wrong_sense += shape == (dir > 0 ? down_shape : up_shape);
      }
    }
    printf("tilted coplanar hinges, flat tolerance 1e-300: %d of %d flat; one ulp off: %d of %d folded, %d of the "
           "wrong sense\n", flat_ok, trials, folded, 2 * trials, wrong_sense);
    TL_TEST_ASSERT(flat_ok == trials, "tilted coplanar hinges: %d of %d flat", flat_ok, trials);
    TL_TEST_ASSERT(wrong_sense == 0 && folded > trials, "one ulp off: %d of the wrong sense, %d folded", wrong_sense,
                   folded);
    TL_TEST_STATUS(tl_trisurface_set_tolerances(s, 1e-9, s->quality_tolerance), TL_OK);
  }
  /* the feature angle of the surface itself */
  hinge_vertices(50 * TL_PI / 180, x);
  TL_TEST_STATUS(tl_trisurface_set_vertices(s, x, NULL), TL_OK);
  TL_TEST_STATUS(tl_trisurface_set_feature_angle(s, 60), TL_OK);
  TL_TEST_ASSERT(!s->edge_sharp[shared], "50 degrees under a feature angle of 60: smooth");
  TL_TEST_STATUS(tl_trisurface_set_feature_angle(s, -1), TL_ERR_ARG);
  TL_TEST_STATUS(tl_trisurface_set_feature_angle(s, 181), TL_ERR_ARG);
  tl_trisurface_destroy(&s);
}

/* The feature angle by name: refused outside its range; the C wrapper keeps
 * the surface's own. */
static void test_parameter(void)
{
  TlWall *w = NULL;
  TlWallSetting bad = {"feature_angle", 200};
  TL_TEST_STATUS(tl_wall_create("trisurface", 1, &bad, &w), TL_ERR_ARG);
  TL_TEST_ASSERT(w == NULL, "no wall from a bad feature angle");
  TlTriSurface *s = NULL;
  TL_TEST_STATUS(tl_trisurface_create_box(LO, HI, &s), TL_OK);
  if (!s) return;
  size_t sharp = 0;
  for (size_t e = 0; e < s->n_edges; ++e) sharp += s->edge_sharp[e];
  TL_TEST_ASSERT(sharp == 12, "a box has 12 sharp edges (the 6 diagonals are flat): %zu", sharp);
  TL_TEST_STATUS(tl_trisurface_set_feature_angle(s, 120), TL_OK);
  TL_TEST_STATUS(tl_wall_trisurface_create(s, &w), TL_OK);
  TlTriSurface *kept = tl_wall_trisurface_surface(w);
  TL_TEST_ASSERT(kept && kept->feature_angle == 120 && kept->edge_sharp[0] == 0, "the wrapper keeps the angle 120");
  TL_TEST_STATUS(tl_wall_trisurface_set_feature_angle(w, 45), TL_OK);
  sharp = 0;
  for (size_t e = 0; kept && e < kept->n_edges; ++e) sharp += kept->edge_sharp[e];
  TL_TEST_ASSERT(sharp == 12, "feature angle 45 through the wall: %zu sharp edges", sharp);
  TL_TEST_STATUS(tl_wall_trisurface_set_feature_angle(w, 190), TL_ERR_ARG);
  tl_wall_destroy(&w);
}

int main(void)
{
  test_press();
  test_bounce();
  test_fold();
  test_reclassify();
  test_parameter();
  return tl_test_report();
}
