/* STL walls that move: a floor written as STL (in millimetres) read back,
 * scaled and placed, then given a prescribed rigid motion.  Checks: the
 * vertices follow x(t) = c + V tau + R(omega tau)(X - c) exactly; the wall
 * velocity at a contact point (interpolated from the vertices) is the rigid
 * field V + omega x (p - c(t)) there; a sphere resting on a turntable turns
 * with it without slip at its contact; a sphere on a descending piston
 * descends at the piston's speed with the floor carrying its weight, and
 * stops when the piston stops. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_stl.h"
#include "tl_test.h"
#include "tl_wall_trisurface.h"

/* A square floor of side 200 mm centred on the origin, as STL in mm. */
static TlStatus write_floor(const char *path)
{
  TlTriSurface *s = NULL;
  TL_CHECK(tl_trisurface_create_rectangle(-100, -100, 200, 200, 0, 8, 8, 1, &s));
  TlSurfaceMesh *m = NULL;
  TlStatus st = tl_surface_mesh_create(s->n_vertices, &s->x[0].x, s->n_triangles, s->tri, &m);
  if (st == TL_OK) st = tl_stl_write(path, m, 1);
  tl_surface_mesh_destroy(&m);
  tl_trisurface_destroy(&s);
  return st;
}

static TlStatus make_floor(TlWall **w, TlVec3 shift)
{
  TlWallPlacement place;
  tl_wall_placement_default(&place);
  place.scale = 1e-3;
  place.shift = shift;
  TlSurfaceReport r;
  TL_CHECK(tl_wall_trisurface_from_file("floor.stl", &place, w, &r));
  return TL_OK;
}

static void test_kinematics(void)
{
  TlWall *w = NULL;
  TL_TEST_STATUS(make_floor(&w, tl_v3(0.5, 0, 0)), TL_OK);
  if (!w) return;
  TlTriSurface *s = tl_wall_trisurface_surface(w);
  TL_TEST_ASSERT(s->n_triangles == 128, "%zu triangles", s->n_triangles);
  TlVec3 lo = s->surface_lo, hi = s->surface_hi;
  TL_TEST_CLOSE(lo.x, 0.4, 1e-12);
  TL_TEST_CLOSE(hi.y, 0.1, 1e-12);
  TlVec3 X[81];
  for (size_t i = 0; i < s->n_vertices && i < 81; ++i) X[i] = s->x[i];
  TlRigidMotion m = {tl_v3(0.01, 0, -0.02), tl_v3(0, 0.3, 2.0), tl_v3(0.5, 0, 0), 0.1, 5.0};
  TL_TEST_STATUS(tl_wall_trisurface_set_motion(w, &m, 0.1), TL_OK);
  /* advance from t = 0.1 to 1.3 in steps: positions from time, no drift */
  for (int k = 0; k < 120; ++k) TL_TEST_STATUS(w->ops->advance(w, 0.1 + 0.01 * k, 0.01), TL_OK);
  double t = 1.3, tau = t - m.start, om = tl_v3_norm(m.omega);
  TlMat3 R = tl_m3_rotation(tl_v3_scale(m.omega, 1 / om), om * tau);
  TlVec3 c = tl_v3_axpy(m.center, tau, m.velocity);
  double ex = 0, ev = 0;
  for (size_t i = 0; i < s->n_vertices; ++i) {
    TlVec3 r = tl_m3_mulv(R, tl_v3_sub(X[i], m.center));
    ex = fmax(ex, tl_v3_norm(tl_v3_sub(s->x[i], tl_v3_add(c, r))));
    ev = fmax(ev, tl_v3_norm(tl_v3_sub(s->v[i], tl_v3_add(m.velocity, tl_v3_cross(m.omega, r)))));
  }
  TL_TEST_ASSERT(ex <= 1e-15 && ev <= 1e-14, "vertices off the rigid motion by %g m, %g m/s", ex, ev);
  /* after stop: at rest where the motion left it */
  TL_TEST_STATUS(w->ops->advance(w, 6.0, 0.01), TL_OK);
  double vmax = 0;
  for (size_t i = 0; i < s->n_vertices; ++i) vmax = fmax(vmax, tl_v3_norm(s->v[i]));
  TL_TEST_ASSERT(vmax == 0.0, "at rest after stop: %g", vmax);
  /* refusals */
  TlRigidMotion bad = m;
  bad.stop = 0.0;
  TL_TEST_STATUS(tl_wall_trisurface_set_motion(w, &bad, 0), TL_ERR_ARG);
  bad = m;
  bad.omega.x = NAN;
  TL_TEST_STATUS(tl_wall_trisurface_set_motion(w, &bad, 0), TL_ERR_ARG);
  tl_error_clear();
  tl_wall_destroy(&w);
}

typedef struct {
  double slip, wall_speed, field_error, vz, force_z, weight, vz_after;
} Run;

/* One sphere on the floor: turntable (omega about z through the floor's
 * centre) or piston (descending at u until stop). */
static TlStatus run(int piston, Run *out)
{
  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  TlDomain dom;
  int per[3] = {0, 0, 0};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(-0.15, -0.15, -0.2), tl_v3(0.15, 0.15, 0.1), per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  const double r = 0.005, rho = 2500;
  TL_CHECK(tl_particles_add_species(P, "glass", rho, r, r, &sp));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0.05, 0.02, r * 0.999), tl_v3(0, 0, 0), r, sp, NULL));
  TlContactLaw *law = NULL;
  TL_CHECK(tl_test_law(&law, "linear", "k_n", 2e4, "restitution", 0.2, "mu", 0.8, "gamma_t", 2000.0, NULL));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TlWall *w = NULL;
  TL_CHECK(make_floor(&w, tl_v3(0, 0, 0)));
  const double u = 0.05, omega = 3.0, stop = piston ? 0.4 : 1e12;
  TlRigidMotion m = {piston ? tl_v3(0, 0, -u) : tl_v3(0, 0, 0), piston ? tl_v3(0, 0, 0) : tl_v3(0, 0, omega),
                     tl_v3(0, 0, 0), 0.0, stop};
  TL_CHECK(tl_wall_trisurface_set_motion(w, &m, 0.0));
  TL_CHECK(tl_dem_add_wall(dem, w, 0));
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  const double dt = 2e-5;
  TL_CHECK(tl_dem_set_timestep(dem, dt, 0));
  TL_CHECK(tl_dem_setup(dem));
  /* settle and spin up, then measure over the last steps */
  int steps = piston ? 15000 : 50000; /* 0.3 s; 1 s */
  TL_CHECK(tl_dem_step(dem, steps));
  const TlTriContactSet *cs = tl_wall_trisurface_contacts(w);
  TlTriSurface *s = tl_wall_trisurface_surface(w);
  out->field_error = INFINITY;
  out->slip = INFINITY;
  if (cs && cs->count >= 1) {
    double t = steps * dt;
    TlVec3 c = tl_v3_axpy(m.center, t, m.velocity);
    double fe = 0.0;
    for (size_t k = 0; k < cs->count; ++k) {
      const TlTriContactRecord *rec = &cs->c[k];
      TlVec3 vw = tl_trisurface_velocity_at(s, rec->triangle, rec->bary);
      TlVec3 field = tl_v3_add(m.velocity, tl_v3_cross(m.omega, tl_v3_sub(rec->point, c)));
      fe = fmax(fe, tl_v3_norm(tl_v3_sub(vw, field)) / fmax(tl_v3_norm(field), 1e-300));
    }
    out->field_error = fe;
    /* the particle's velocity at its contact point against the wall's */
    const TlTriContactRecord *rec = &cs->c[0];
    TlVec3 vw = tl_trisurface_velocity_at(s, rec->triangle, rec->bary);
    TlVec3 arm = tl_v3_sub(rec->point, P->x[0]);
    TlVec3 vp = P->w ? tl_v3_add(P->v[0], tl_v3_cross(P->w[0], arm)) : P->v[0];
    TlVec3 d = tl_v3_sub(vp, vw);
    out->slip = sqrt(d.x * d.x + d.y * d.y);
    out->wall_speed = tl_v3_norm(vw);
  }
  out->vz = P->v[0].z;
  out->force_z = w->force.z;
  out->weight = P->mass[0] * 9.81;
  if (piston) {
    TL_CHECK(tl_dem_step(dem, 15000)); /* past the stop at 0.4 s, then at rest */
    out->vz_after = P->v[0].z;
  }
  tl_dem_destroy(&dem);
  return TL_OK;
}

int main(void)
{
  if (tl_initialize() != TL_OK) return 1;
  tl_log_set_level(TL_LOG_ERROR);
  TL_TEST_STATUS(write_floor("floor.stl"), TL_OK);
  test_kinematics();
  Run turn, pist;
  TL_TEST_STATUS(run(0, &turn), TL_OK);
  printf("turntable: wall speed at the contact %.5g m/s, slip %.3g m/s, field error %.3g\n", turn.wall_speed, turn.slip,
         turn.field_error);
  TL_TEST_ASSERT(turn.field_error <= 1e-12, "wall velocity at the contact off the rigid field by %g", turn.field_error);
  TL_TEST_ASSERT(turn.wall_speed > 0.05 && turn.slip <= 0.01 * turn.wall_speed,
                 "the sphere turns with the table: slip %g of %g m/s", turn.slip, turn.wall_speed);
  TL_TEST_STATUS(run(1, &pist), TL_OK);
  printf("piston: vz %.6g m/s (piston -0.05), floor force %.6g N, weight %.6g N, vz after stop %.3g m/s, field error %.3g\n",
         pist.vz, pist.force_z, pist.weight, pist.vz_after, pist.field_error);
  TL_TEST_ASSERT(pist.field_error <= 1e-12, "piston field error %g", pist.field_error);
  TL_TEST_ASSERT(fabs(pist.vz + 0.05) <= 1e-3 * 0.05, "descends with the piston: vz %g", pist.vz);
  TL_TEST_ASSERT(fabs(-pist.force_z - pist.weight) <= 0.01 * pist.weight, "floor carries the weight: %g vs %g",
                 -pist.force_z, pist.weight);
  TL_TEST_ASSERT(fabs(pist.vz_after) <= 1e-3, "at rest after the stroke: vz %g", pist.vz_after);
  return tl_test_report();
}
