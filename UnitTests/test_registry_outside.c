/* Types defined outside the library, registered from here, are created by
 * name exactly like the built-in ones, and work:
 *
 *   - a wall type "sphere_container" (particles inside a sphere), created by
 *     tl_wall_create with its parameters, holds a bouncing ball in a DEM
 *     world: the ball comes back to the height it fell from (no damping:
 *     energy conserved), the wall's contacts are visited through its op;
 *     beside it the built-in plane created by name runs bit for bit as the
 *     plane made by its typed constructor;
 *   - a CG kernel "raised_cosine" (kind "cg_kernel", tl_cg_kernel_create):
 *     W integrates to 1 in 1, 2 and 3 dimensions;
 *   - a linear solver "dense_cholesky" (kind "linear_solver",
 *     tl_linear_solver_create): the solution of a small SPD system against
 *     the known one, and a matrix that is not positive definite refused. */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "talus.h"
#include "tl_cg_kernel.h"
#include "tl_dem.h"
#include "tl_linear_solver.h"
#include "tl_memory.h"
#include "tl_registry.h"
#include "tl_sparse.h"
#include "tl_test.h"
#include "tl_wall.h"
#include "tl_wall_trisurface.h"

/* ================================================ a wall type: a sphere
 * container.  A particle at distance d from the centre touches the sphere
 * of radius R when d + r > R (overlap d + r - R); the normal points from
 * the particle's centre outwards.  The wall never moves. */

typedef struct {
  TlWall base;
  TlVec3 center;
  double radius;
  size_t n, hd; /* per-particle state, indexed by particle */
  uint8_t *touching;
  TlVec3 *force;  /* on the particle, at the last interact */
  double *history;
} SphereWall;

typedef struct {
  double center_x, center_y, center_z, radius;
} SphereParams;

static const TlParam sphere_params[] = {
    {"center_x", 0.0, -DBL_MAX, DBL_MAX, "m", "centre of the sphere, x", offsetof(SphereParams, center_x)},
    {"center_y", 0.0, -DBL_MAX, DBL_MAX, "m", "centre of the sphere, y", offsetof(SphereParams, center_y)},
    {"center_z", 0.0, -DBL_MAX, DBL_MAX, "m", "centre of the sphere, z", offsetof(SphereParams, center_z)},
    {"radius", 1.0, 1e-300, DBL_MAX, "m", "inner radius of the sphere", offsetof(SphereParams, radius)},
};

static void sphere_bbox(const TlWall *w, TlVec3 *lo, TlVec3 *hi)
{
  (void)w; /* the wall is the outside of a ball: unbounded */
  *lo = tl_v3(-INFINITY, -INFINITY, -INFINITY);
  *hi = tl_v3(INFINITY, INFINITY, INFINITY);
}

static TlStatus sphere_fit(SphereWall *s, size_t n, size_t hd)
{
  if (n <= s->n && hd == s->hd) return TL_OK;
  TL_CHECK(tl_realloc(&s->touching, n ? n : 1, sizeof *s->touching));
  TL_CHECK(tl_realloc(&s->force, n ? n : 1, sizeof *s->force));
  TL_CHECK(tl_realloc(&s->history, (n * hd) > 0 ? n * hd : 1, sizeof *s->history));
  size_t from = hd == s->hd ? s->n : 0;
  for (size_t i = from; i < n; ++i) {
    s->touching[i] = 0;
    s->force[i] = tl_v3(0, 0, 0);
    for (size_t q = 0; q < hd; ++q) s->history[i * hd + q] = 0.0;
  }
  s->n = n;
  s->hd = hd;
  return TL_OK;
}

static TlStatus sphere_interact(TlWall *w, const TlWallStep *st)
{
  SphereWall *s = (SphereWall *)w;
  TlParticles *P = st->particles;
  const size_t hd = st->law->history_doubles;
  TL_CHECK(sphere_fit(s, P->n, hd));
  double elastic = 0.0, power = 0.0;
  TlVec3 F = tl_v3(0, 0, 0), T = tl_v3(0, 0, 0);
  size_t n_contacts = 0;
  for (size_t i = 0; i < P->n; ++i) {
    TlVec3 rel = tl_v3_sub(P->x[i], s->center);
    double d = tl_v3_norm(rel), ri = P->radius[i], delta = d + ri - s->radius;
    if (!(delta > 0.0) || !(d > 0.0) || P->motion[i] != TL_MOTION_FREE) {
      s->touching[i] = 0;
      s->force[i] = tl_v3(0, 0, 0);
      for (size_t q = 0; q < hd; ++q) s->history[i * hd + q] = 0.0;
      continue;
    }
    TlContactGeometry g;
    memset(&g, 0, sizeof g);
    g.normal = tl_v3_scale(rel, 1.0 / d);
    g.overlap = delta;
    g.branch_i = tl_v3_scale(g.normal, ri - 0.5 * delta);
    TlVec3 vi = P->v[i];
    if (P->w) {
      vi = tl_v3_add(vi, tl_v3_cross(P->w[i], g.branch_i));
      g.spin_mean = tl_v3_scale(P->w[i], 0.5);
      g.spin_rel = tl_v3_neg(P->w[i]);
    }
    g.vrel = tl_v3_neg(vi); /* the wall is at rest */
    g.meff = P->mass[i];
    g.reff = ri;
    g.history = hd ? s->history + i * hd : NULL;
    TlContactResult r;
    TL_CHECK(tl_contact_law_evaluate_one(st->law, &g, st->dt, &r));
    TlVec3 f_old = s->touching[i] ? s->force[i] : tl_v3(0, 0, 0);
    P->f[i] = tl_v3_add(P->f[i], r.force);
    if (P->torque) P->torque[i] = tl_v3_add(P->torque[i], tl_v3_add(tl_v3_cross(g.branch_i, r.force), r.couple));
    F = tl_v3_sub(F, r.force);
    T = tl_v3_sub(T, tl_v3_cross(tl_v3_add(P->x[i], g.branch_i), r.force));
    elastic += r.elastic_energy;
    /* trapezoidal rule over the step, as the world books its contacts */
    power += 0.5 * tl_v3_dot(tl_v3_add(f_old, r.force), g.vrel) + tl_v3_dot(r.couple, g.spin_rel);
    s->touching[i] = 1;
    s->force[i] = r.force;
    ++n_contacts;
  }
  w->force = F;
  w->torque = T;
  w->n_contacts = n_contacts;
  if (st->want_energy) {
    w->elastic_energy = elastic;
    w->contact_work += st->dt * power;
  }
  return TL_OK;
}

static TlStatus sphere_remap(TlWall *w, const size_t *old_to_new, size_t n_old)
{
  SphereWall *s = (SphereWall *)w;
  size_t n = s->n < n_old ? s->n : n_old;
  /* the map may be any permutation: go through a copy */
  SphereWall old = *s;
  s->touching = NULL, s->force = NULL, s->history = NULL, s->n = 0;
  TlStatus st = sphere_fit(s, n, old.hd);
  for (size_t k = 0; st == TL_OK && k < n; ++k) {
    size_t q = old_to_new[k];
    if (q == SIZE_MAX || q >= n) continue;
    s->touching[q] = old.touching[k];
    s->force[q] = old.force[k];
    for (size_t h = 0; h < old.hd; ++h) s->history[q * old.hd + h] = old.history[k * old.hd + h];
  }
  tl_free(&old.touching);
  tl_free(&old.force);
  tl_free(&old.history);
  return st;
}

static TlStatus sphere_visit(const TlWall *w, const TlParticles *P, TlWallVisitor visit, void *ctx)
{
  const SphereWall *s = (const SphereWall *)w;
  for (size_t i = 0; i < P->n && i < s->n; ++i) {
    if (!s->touching[i]) continue;
    TlVec3 rel = tl_v3_sub(P->x[i], s->center);
    TlVec3 point = tl_v3_axpy(s->center, s->radius / tl_v3_norm(rel), rel);
    visit(ctx, i, s->force[i], point, P->x[i]);
  }
  return TL_OK;
}

static void sphere_destroy(TlWall *w)
{
  SphereWall *s = (SphereWall *)w;
  tl_free(&s->touching);
  tl_free(&s->force);
  tl_free(&s->history);
  tl_free(&s);
}

static const TlWallOps sphere_ops = {
    .header = {"wall", "sphere_container", "the inside of a sphere (defined by a test)"},
    .bounding_box = sphere_bbox,
    .interact = sphere_interact,
    .remap = sphere_remap,
    .destroy = sphere_destroy,
    .visit_contacts = sphere_visit,
};

static TlStatus sphere_create(const void *params, TlWall **w)
{
  const SphereParams *q = params;
  SphereWall *s;
  TL_CHECK(TL_NEW(s));
  s->base.ops = &sphere_ops;
  snprintf(s->base.name, sizeof s->base.name, "container");
  s->center = tl_v3(q->center_x, q->center_y, q->center_z);
  s->radius = q->radius;
  *w = &s->base;
  return TL_OK;
}

/* A law without damping (restitution 1) or friction.  (The one place this
 * test names the contact-law interface.) */
static TlStatus elastic_law(double k_n, TlContactLaw **law)
{
  return tl_test_law(law, "linear", "k_n", k_n, "restitution", 1.0, (const char *)NULL);
}

typedef struct {
  size_t count, wall, particle;
  TlVec3 force, point;
} WallSeen;

static void see_wall_contact(void *ctx, size_t wall, size_t i, TlVec3 f, TlVec3 point, TlVec3 center)
{
  WallSeen *s = ctx;
  (void)center;
  s->count++;
  s->wall = wall;
  s->particle = i;
  s->force = f;
  s->point = point;
}

static double mechanical(TlDem *dem)
{
  TlDemEnergy e;
  tl_dem_energy(dem, &e);
  return e.kinetic_translational + e.kinetic_rotational + e.gravitational + e.elastic;
}

/* A ball dropped from the centre of the container bounces on its bottom and
 * rises back to where it started. */
static TlStatus test_sphere_container(void)
{
  const double R = 0.05, r = 0.005, cz = 0.1;
  TlWall *w = NULL;
  TlWallSetting set[] = {{"center_x", 0.1}, {"center_y", 0.1}, {"center_z", cz}, {"radius", R}};
  TL_TEST_STATUS(tl_wall_create("sphere_container", 4, set, &w), TL_OK);
  TL_TEST_ASSERT(w && w->ops == &sphere_ops, "the registered type is created by name");
  if (!w) return TL_OK;
  const SphereWall *sw = (const SphereWall *)w;
  TL_TEST_CLOSE(sw->radius, R, 0.0);
  TL_TEST_CLOSE(sw->center.z, cz, 0.0);

  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  TlDomain dom;
  TL_CHECK(tl_domain_init_open(&dom, tl_v3(0, 0, 0), tl_v3(0.2, 0.2, 0.2)));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "glass", 2500, r, r, &sp));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0.1, 0.1, cz), tl_v3(0, 0, 0), r, sp, NULL));
  TlContactLaw *law = NULL;
  TL_CHECK(elastic_law(1e4, &law));
  int li;
  TL_CHECK(tl_dem_add_law(dem, law, &li));
  TL_CHECK(tl_dem_add_wall(dem, w, li));
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  TL_CHECK(tl_dem_set_timestep(dem, 2e-5, 0));
  TL_CHECK(tl_dem_setup(dem));
  const double e0 = mechanical(dem);
  const double drop = R - r; /* to first touch */
  const double ke_impact = P->mass[0] * 9.81 * drop;
  double z_min = cz, z_max_after = -INFINITY, vz_max = 0.0, f_max = 0.0;
  int touched = 0, left = 0;
  WallSeen seen = {0};
  for (long s = 0; s < 20000; ++s) {
    TL_CHECK(tl_dem_step(dem, 1));
    double z = P->x[0].z;
    z_min = fmin(z_min, z);
    if (w->n_contacts) {
      touched = 1;
      if (fabs(w->force.z) > f_max) {
        f_max = fabs(w->force.z);
        WallSeen now = {0};
        TL_CHECK(tl_dem_visit_wall_contacts(dem, see_wall_contact, &now));
        seen = now;
      }
    } else if (touched) {
      left = 1;
    }
    if (left) {
      z_max_after = fmax(z_max_after, z);
      vz_max = fmax(vz_max, P->v[0].z);
      if (P->v[0].z < 0.0) break; /* past the apex */
    }
  }
  const double e1 = mechanical(dem);
  TlDemEnergy e;
  TL_CHECK(tl_dem_energy(dem, &e));
  TL_TEST_ASSERT(touched && left, "the ball touched the container and left it (touched %d, left %d)", touched, left);
  TL_TEST_ASSERT(z_min > cz - R && z_min < cz - drop, "lowest centre %g between the wall %g and first touch %g", z_min,
                 cz - R, cz - drop);
  TL_TEST_CLOSE(vz_max, sqrt(2.0 * 9.81 * drop), 1e-3);
  TL_TEST_CLOSE(z_max_after, cz, 1e-3);
  /* Velocity Verlet through a contact: an error of O((dt / contact
   * time)^2) = 3e-4 of the impact energy (measured 1e-4) */
  TL_TEST_ASSERT(fabs(e1 - e0) < 1e-3 * ke_impact, "mechanical energy %.12g after the bounce, %.12g before (impact %g)",
                 e1, e0, ke_impact);
  /* the booked contact work (trapezoidal rule) matches the stored energy
   * to O((dt / contact time)^2) = 3e-4 */
  TL_TEST_ASSERT(fabs(e.dissipated) < 2e-3 * ke_impact, "dissipated %g of %g without damping", e.dissipated, ke_impact);
  printf("bounce: mechanical energy %.9g -> %.9g (impact %.6g), booked dissipation %.3g, apex %.9g of %.9g\n", e0, e1,
         ke_impact, e.dissipated, z_max_after, cz);
  /* the contact as the world visits it: one, of wall 0 and particle 0, on
   * the sphere, pushing the ball up with the force the wall took */
  TL_TEST_ASSERT(seen.count == 1 && seen.wall == 0 && seen.particle == 0, "visited %zu contacts (wall %zu, particle %zu)",
                 seen.count, seen.wall, seen.particle);
  TL_TEST_CLOSE(tl_v3_norm(tl_v3_sub(seen.point, tl_v3(0.1, 0.1, cz))), R, 1e-12);
  TL_TEST_CLOSE(seen.force.z, f_max, 1e-12);
  TL_TEST_ASSERT(f_max > P->mass[0] * 9.81, "peak wall force %g above the weight %g", f_max, P->mass[0] * 9.81);
  tl_dem_destroy(&dem);
  return TL_OK;
}

/* The same ball on the built-in plane made two ways: by name with its
 * parameters, and by its typed constructor.  Bit for bit the same. */
static TlStatus bounce_on_plane(int by_name, TlVec3 *x, TlVec3 *v)
{
  TlWall *w = NULL;
  if (by_name) {
    TlWallSetting set[] = {{"normal_z", 2.0}, {"point_z", 0.01}, {"velocity_z", 0.01}};
    TL_CHECK(tl_wall_create("plane", 3, set, &w));
  } else {
    TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0.01), tl_v3(0, 0, 2.0), &w));
    TL_CHECK(tl_wall_plane_set_velocity(w, tl_v3(0, 0, 0.01)));
  }
  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  TlDomain dom;
  TL_CHECK(tl_domain_init_open(&dom, tl_v3(0, 0, 0), tl_v3(0.2, 0.2, 0.2)));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "glass", 2500, 0.005, 0.005, &sp));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0.1, 0.1, 0.03), tl_v3(0.1, 0, -0.5), 0.005, sp, NULL));
  TlContactLaw *law = NULL;
  TL_CHECK(elastic_law(1e4, &law));
  int li;
  TL_CHECK(tl_dem_add_law(dem, law, &li));
  TL_CHECK(tl_dem_add_wall(dem, w, li));
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  TL_CHECK(tl_dem_set_timestep(dem, 2e-5, 0));
  TL_CHECK(tl_dem_setup(dem));
  TL_CHECK(tl_dem_step(dem, 5000));
  *x = P->x[0];
  *v = P->v[0];
  tl_dem_destroy(&dem);
  return TL_OK;
}

static TlStatus test_plane_by_name(void)
{
  TlVec3 xa, va, xb, vb;
  TL_TEST_STATUS(bounce_on_plane(1, &xa, &va), TL_OK);
  TL_TEST_STATUS(bounce_on_plane(0, &xb, &vb), TL_OK);
  TL_TEST_ASSERT(memcmp(&xa, &xb, sizeof xa) == 0 && memcmp(&va, &vb, sizeof va) == 0,
                 "plane by name: x = (%.17g, %.17g, %.17g), typed: (%.17g, %.17g, %.17g)", xa.x, xa.y, xa.z, xb.x,
                 xb.y, xb.z);
  TL_TEST_ASSERT(va.z > 0.0 && xa.z > 0.015, "the ball bounced off the plane (z %g, vz %g)", xa.z, va.z);
  /* what creation by name refuses */
  TlWall *w = NULL;
  TL_TEST_STATUS(tl_wall_create("plane", 1, (TlWallSetting[]){{"normal_q", 1.0}}, &w), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(strstr(tl_error_message(), "normal_z") != NULL, "the error lists the parameters: %s",
                 tl_error_message());
  TL_TEST_STATUS(tl_wall_create("plane", 1, (TlWallSetting[]){{"velocity_x", INFINITY}}, &w), TL_ERR_ARG);
  TL_TEST_STATUS(tl_wall_create("plane", 1, (TlWallSetting[]){{"normal_z", 0.0}}, &w), TL_ERR_ARG);
  TL_TEST_STATUS(tl_wall_create("sphere_container", 1, (TlWallSetting[]){{"radius", -1.0}}, &w), TL_ERR_ARG);
  TL_TEST_STATUS(tl_wall_create("cylinder", 0, NULL, &w), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(strstr(tl_error_message(), "sphere_container") && strstr(tl_error_message(), "trisurface"),
                 "the error lists the known wall types: %s", tl_error_message());
  TL_TEST_ASSERT(w == NULL, "no wall after a refusal");
  /* the triangulated surface by name, given its surface afterwards */
  TL_TEST_STATUS(tl_wall_create("trisurface", 1, (TlWallSetting[]){{"corrections", 0.0}}, &w), TL_OK);
  TlTriSurface *s = NULL;
  TL_CHECK(tl_trisurface_create_rectangle(0, 0, 1, 1, 0, 2, 2, 2, &s));
  TL_TEST_STATUS(tl_wall_trisurface_set_surface(w, s), TL_OK);
  TL_TEST_ASSERT(tl_wall_trisurface_surface(w) == s, "the wall holds its surface");
  tl_wall_destroy(&w);
  return TL_OK;
}

/* ========================================== a CG kernel: raised cosine,
 * f(q) = (1 + cos(pi q)) / 2, with its radial moments in closed form. */

static void cosine_profile(size_t n, const double *q, double *f, double *dfdq)
{
  for (size_t k = 0; k < n; ++k) {
    double s = q[k];
    f[k] = 0.5 * (1.0 + cos(TL_PI * s));
    if (dfdq) dfdq[k] = -0.5 * TL_PI * sin(TL_PI * s);
  }
}

static double cosine_moment(int dim)
{
  /* ∫_0^1 f q^(dim-1) dq */
  const double p2 = TL_PI * TL_PI;
  return dim == 1 ? 0.5 : dim == 2 ? 0.25 - 1.0 / p2 : 1.0 / 6.0 - 1.0 / p2;
}

static const TlCGKernelOps cosine_ops = {
    {TL_CG_KERNEL_KIND, "raised_cosine", "(1 + cos(pi |x|/c)) / 2 (defined by a test)"}, 0, cosine_profile,
    cosine_moment, NULL};

static TlStatus test_cg_kernel(void)
{
  const double c = 0.3;
  const double sphere[4] = {0.0, 2.0, 2.0 * TL_PI, 4.0 * TL_PI};
  for (int dim = 1; dim <= 3; ++dim) {
    TlCGKernel *k = NULL;
    TL_TEST_STATUS(tl_cg_kernel_create("raised_cosine", c, dim, &k), TL_OK);
    if (!k) continue;
    TL_TEST_ASSERT(k->ops == &cosine_ops, "the registered kernel is created by name");
    /* ∫ W over R^dim = |S^(dim-1)| ∫_0^c W(r) r^(dim-1) dr, Simpson on 2000 panels */
    enum { N = 2000 };
    static double r2[N + 1], wv[N + 1];
    for (int i = 0; i <= N; ++i) r2[i] = pow(c * i / N, 2);
    TL_CHECK(tl_cg_kernel_eval(k, N + 1, r2, wv, NULL));
    double sum = 0.0, h = c / N;
    for (int i = 0; i <= N; ++i) {
      double ri = c * i / N, wt = (i == 0 || i == N) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      sum += wt * wv[i] * pow(ri, dim - 1);
    }
    double integral = sphere[dim] * sum * h / 3.0;
    TL_TEST_CLOSE(integral, 1.0, 1e-10);
    TL_TEST_CLOSE(tl_cg_kernel_value(k, 0.0), k->norm, 1e-15);
    TL_TEST_CLOSE(tl_cg_kernel_value(k, c), 0.0, 0.0);
    /* the line integral through the centre by the generic quadrature */
    double A = 1.0, B = 0.0, C = 0.0, s0 = -0.999 * c, s1 = 0.999 * c, out = 0.0;
    TL_TEST_STATUS(tl_cg_kernel_line_integral(k, 1, &A, &B, &C, &s0, &s1, 10, &out), TL_OK);
    /* ∫_{-c}^{c} C (1 + cos(pi s/c))/2 ds = C c, less the two tails (O(0.001^3)) */
    TL_TEST_CLOSE(out, k->norm * c, 1e-6);
    tl_cg_kernel_destroy(&k);
  }
  return TL_OK;
}

/* ====================================== a linear solver: dense Cholesky
 * of the upper-triangle storage, for tiny SPD systems. */

typedef struct {
  double *L; /* n x n, row-major, lower factor */
} DenseData;

static TlStatus dense_setup(TlLinearSolver *ls, const TlSparse *A)
{
  DenseData *d;
  TL_CHECK(TL_NEW(d));
  ls->data = d;
  TL_CHECK(tl_calloc(&d->L, (size_t)(A->n * A->n), sizeof *d->L));
  return TL_OK;
}

static TlStatus dense_factor(TlLinearSolver *ls, const TlSparse *A)
{
  DenseData *d = ls->data;
  const size_t n = (size_t)A->n;
  double *L = d->L;
  memset(L, 0, n * n * sizeof *L);
  for (size_t j = 0; j < n; ++j)
    for (TlSparseIndex p = A->colptr[j]; p < A->colptr[j + 1]; ++p) {
      size_t i = (size_t)A->rowind[p]; /* i <= j: upper triangle */
      L[j * n + i] = A->values[p];   /* the lower triangle, row j */
    }
  for (size_t j = 0; j < n; ++j) {
    double s = L[j * n + j];
    for (size_t k = 0; k < j; ++k) s -= L[j * n + k] * L[j * n + k];
    if (!(s > 0.0)) TL_ERROR(TL_ERR_NUMERIC, "dense Cholesky: pivot %zu is %g, the matrix is not positive definite", j, s);
    double djj = sqrt(s);
    L[j * n + j] = djj;
    for (size_t i = j + 1; i < n; ++i) {
      double t = L[i * n + j];
      for (size_t k = 0; k < j; ++k) t -= L[i * n + k] * L[j * n + k];
      L[i * n + j] = t / djj;
    }
  }
  return TL_OK;
}

static TlStatus dense_solve(TlLinearSolver *ls, const double *b, double *x)
{
  const DenseData *d = ls->data;
  const size_t n = (size_t)ls->n;
  const double *L = d->L;
  if (x != b) memcpy(x, b, n * sizeof *x);
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < i; ++k) x[i] -= L[i * n + k] * x[k];
    x[i] /= L[i * n + i];
  }
  for (size_t i = n; i-- > 0;) {
    for (size_t k = i + 1; k < n; ++k) x[i] -= L[k * n + i] * x[k];
    x[i] /= L[i * n + i];
  }
  return TL_OK;
}

static void dense_destroy(TlLinearSolver *ls)
{
  DenseData *d = ls->data;
  if (!d) return;
  tl_free(&d->L);
  tl_free(&d);
  ls->data = NULL;
}

static const TlLinearSolverOps dense_ops = {
    {"linear_solver", "dense_cholesky", "dense Cholesky for tiny SPD systems (defined by a test)"}, 1, dense_setup,
    dense_factor, dense_solve, dense_destroy};

/* The 1-D Laplacian plus a shift, tridiagonal (2 + shift, -1), of size n. */
static TlStatus laplacian(TlSparseIndex n, double shift, TlSparse **A)
{
  TlSparseIndex ptr[64], dofs[128];
  TlSparseIndex ne = n - 1;
  for (TlSparseIndex e = 0; e < ne; ++e) {
    ptr[e] = 2 * e;
    dofs[2 * e] = e;
    dofs[2 * e + 1] = e + 1;
  }
  ptr[ne] = 2 * ne;
  TL_CHECK(tl_sparse_create_from_elements(n, 1, ne, ptr, dofs, 0, A));
  for (TlSparseIndex i = 0; i < n; ++i) {
    TL_CHECK(tl_sparse_add(*A, i, i, 2.0 + shift));
    if (i + 1 < n) TL_CHECK(tl_sparse_add(*A, i, i + 1, -1.0));
  }
  return TL_OK;
}

static TlStatus test_linear_solver(void)
{
  enum { N = 7 };
  TlSparse *A = NULL;
  TL_CHECK(laplacian(N, 0.0, &A));
  double x_true[N], b[N], x[N];
  for (int i = 0; i < N; ++i) x_true[i] = 1.0 + i * i - 0.5 * i;
  tl_sparse_matvec(A, x_true, b);
  TlLinearSolver *ls = NULL;
  TL_TEST_STATUS(tl_linear_solver_create("dense_cholesky", A, &ls), TL_OK);
  if (ls) {
    TL_TEST_ASSERT(ls->ops == &dense_ops, "the registered solver is created by name");
    TL_TEST_STATUS(tl_linear_solver_factor(ls, A), TL_OK);
    TL_TEST_STATUS(tl_linear_solver_solve(ls, b, x), TL_OK);
    for (int i = 0; i < N; ++i) TL_TEST_CLOSE(x[i], x_true[i], 1e-12);
    int upper = 0;
    TL_TEST_STATUS(tl_linear_solver_needs_upper("dense_cholesky", &upper), TL_OK);
    TL_TEST_ASSERT(upper == 1, "upper-triangle storage: %d", upper);
    /* shifted below the smallest eigenvalue (2 - 2 cos(pi/(N+1)) > 0): not
     * positive definite, refused by the factorisation */
    TlSparse *B = NULL;
    TL_CHECK(laplacian(N, -0.5, &B));
    TL_TEST_STATUS(tl_linear_solver_factor(ls, B), TL_ERR_NUMERIC);
    tl_sparse_destroy(&B);
    tl_linear_solver_destroy(&ls);
  }
  tl_sparse_destroy(&A);
  return TL_OK;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  /* registered from outside the library, as a driver or a plug-in would */
  TL_TEST_STATUS(tl_wall_register("sphere_container", sphere_ops.header.description, sphere_create, &sphere_ops,
                                  sphere_params, 4),
                 TL_OK);
  TL_TEST_STATUS(tl_registry_add(&cosine_ops.header), TL_OK);
  TL_TEST_STATUS(tl_registry_add(&dense_ops.header), TL_OK);
  /* again: harmless; another type under a taken name: refused */
  TL_TEST_STATUS(tl_wall_register("sphere_container", "", sphere_create, &sphere_ops, sphere_params, 4), TL_OK);
  TL_TEST_STATUS(tl_registry_add(&cosine_ops.header), TL_OK);
  TL_TEST_STATUS(tl_wall_register("plane", "", sphere_create, &sphere_ops, sphere_params, 4), TL_ERR_ARG);

  TL_TEST_STATUS(test_sphere_container(), TL_OK);
  TL_TEST_STATUS(test_plane_by_name(), TL_OK);
  TL_TEST_STATUS(test_cg_kernel(), TL_OK);
  TL_TEST_STATUS(test_linear_solver(), TL_OK);
  return tl_test_report();
}
