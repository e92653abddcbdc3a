/* Talus against LAMMPS on the same granular scenes, answers to 1e-6 relative.
 *
 * Each scene is written once as doubles (%.17g, so both codes read the same
 * numbers): a LAMMPS data file and deck, run by lmp, and the same spheres in
 * a Talus world with the parts that reproduce LAMMPS's styles:
 *   gran/hooke          = lammps_hooke + lammps_viscous
 *   gran/hooke/history  = lammps_hooke + lammps_history
 *   gran/hertz/history  = lammps_hertz + lammps_history
 * (fix wall/gran with the same style for plane walls).  Both integrate with
 * velocity Verlet, forces evaluated at the half-step velocities and spins
 * (LAMMPS fix nve/sphere; Talus tl_dem_step), moment of inertia 2/5 m R^2.
 * The first force evaluation (LAMMPS's setup, Talus's tl_dem_setup) does
 * not advance the shear history in either code.
 *
 * Scenes: oblique impacts of two spinning spheres of different radii with
 * each of the three styles; a sphere landing spinning on a plane wall under
 * gravity, sliding then rolling (hooke/history and hertz/history); 200 steps
 * of a dense packing of 216 polydisperse spheres, periodic in x and y,
 * sheared between two plane walls moving at -V and +V along x
 * (hertz/history, fix wall/gran ... shear x V), once from no contact and
 * once compressed, overlapping from the start; and (given a packing file as
 * the argument) the gouge of seeds/000: a Talus-made 5 MPa packing of
 * bidisperse grains, periodic in x, y and z, with the gouge law of Table 1
 * (explicit Kt), stirred by random velocities and spins, 2000 steps.
 *
 * Norm: for each of velocity, spin, force and torque, the largest over the
 * particles of |Talus - LAMMPS| (Euclidean), over the largest |LAMMPS| of
 * that quantity in the scene.  Skips (77) when lmp cannot be run or
 * installed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "talus.h"
#include "tl_dem.h"
#include "tl_dem_packing.h"
#include "tl_test.h"
#include "tl_wall.h"

static const double tolerance = 1e-6;

typedef enum { HOOKE, HOOKE_HISTORY, HERTZ_HISTORY } Style;
static const char *const lammps_style[] = {"hooke", "hooke/history", "hertz/history"};

typedef struct {
  double z, vx; /* plane z = z, moving along x at vx; particles above if up */
  int up;
} Wall;

typedef struct {
  const char *name;
  Style style;
  double kn, gamma_n, mu;
  double kt;   /* LAMMPS Kt; 0: NULL (2/7 Kn) */
  double skin; /* LAMMPS neighbor skin, m (0: 0.1) */
  double lo[3], hi[3];
  int periodic[3]; /* x, y, z */
  double gravity;  /* along -z, m/s^2 */
  double dt;
  long steps;
  size_t n;
  double *r, *x, *v, *w; /* radius, position, velocity, spin (3 per particle) */
  double density;
  int n_walls;
  Wall walls[2];
} Scene;

static double urand(unsigned long long *s)
{
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static void scene_alloc(Scene *s, size_t n)
{
  s->n = n;
  s->r = calloc(n, sizeof(double));
  s->x = calloc(3 * n, sizeof(double));
  s->v = calloc(3 * n, sizeof(double));
  s->w = calloc(3 * n, sizeof(double));
}

static void scene_free(Scene *s)
{
  free(s->r), free(s->x), free(s->v), free(s->w);
}

/* ---------------------------------------------------------------- LAMMPS */

static int have_lammps(void)
{
  if (system("command -v lmp > /dev/null 2>&1") == 0) return 1;
  if (geteuid() != 0) {
    printf("SKIP: lmp (Debian package lammps) is not installed and this is not root; as root run: "
           "apt-get install -y lammps\n");
    return 0;
  }
  printf("installing lammps (apt-get install -y lammps)\n");
  fflush(stdout);
  if (system("DEBIAN_FRONTEND=noninteractive apt-get install -y lammps > apt.log 2>&1") != 0 &&
      system("apt-get update > apt.log 2>&1 && DEBIAN_FRONTEND=noninteractive apt-get install -y lammps >> apt.log "
             "2>&1") != 0) {
    printf("SKIP: apt-get install -y lammps failed (see apt.log)\n");
    return 0;
  }
  if (system("command -v lmp > /dev/null 2>&1") != 0) {
    printf("SKIP: lmp still missing after installing lammps\n");
    return 0;
  }
  return 1;
}

static void style_args(const Scene *s, char *out, size_t cap)
{
  /* Kn Kt gamma_n gamma_t xmu dampflag: gamma_t NULL (gamma_n/2), Kt NULL (2/7 Kn) unless given */
  char kt[32] = "NULL";
  if (s->kt > 0.0) snprintf(kt, sizeof kt, "%.17g", s->kt);
  snprintf(out, cap, "%s %.17g %s %.17g NULL %.17g 1", lammps_style[s->style], s->kn, kt, s->gamma_n, s->mu);
}

static TlStatus run_lammps(const Scene *s, double *out /* 12 per particle: v w f t */)
{
  char data[256], deck[256], dump[256], cmd[1024], args[256];
  snprintf(data, sizeof data, "%s.data", s->name);
  snprintf(deck, sizeof deck, "in.%s", s->name);
  snprintf(dump, sizeof dump, "%s.dump", s->name);
  FILE *f = fopen(data, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write %s", data);
  fprintf(f, "LAMMPS data file of the parity scene %s\n\n%zu atoms\n1 atom types\n\n", s->name, s->n);
  const char *ax[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) fprintf(f, "%.17g %.17g %slo %shi\n", s->lo[k], s->hi[k], ax[k], ax[k]);
  fprintf(f, "\nAtoms # sphere\n\n");
  for (size_t i = 0; i < s->n; ++i)
    fprintf(f, "%zu 1 %.17g %.17g %.17g %.17g %.17g\n", i + 1, 2.0 * s->r[i], s->density, s->x[3 * i],
            s->x[3 * i + 1], s->x[3 * i + 2]);
  fprintf(f, "\nVelocities\n\n");
  for (size_t i = 0; i < s->n; ++i)
    fprintf(f, "%zu %.17g %.17g %.17g %.17g %.17g %.17g\n", i + 1, s->v[3 * i], s->v[3 * i + 1], s->v[3 * i + 2],
            s->w[3 * i], s->w[3 * i + 1], s->w[3 * i + 2]);
  fclose(f);
  style_args(s, args, sizeof args);
  f = fopen(deck, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write %s", deck);
  fprintf(f, "units si\natom_style sphere\nboundary %s %s %s\ncomm_modify vel yes\nread_data %s\n",
          s->periodic[0] ? "p" : "f", s->periodic[1] ? "p" : "f", s->periodic[2] ? "p" : "f", data);
  fprintf(f, "pair_style gran/%s\npair_coeff * *\nneighbor %.17g bin\nneigh_modify delay 0 every 1 check yes\n", args,
          s->skin > 0.0 ? s->skin : 0.1);
  fprintf(f, "fix integrate all nve/sphere\n");
  if (s->gravity > 0.0) fprintf(f, "fix gravity all gravity %.17g vector 0 0 -1\n", s->gravity);
  for (int k = 0; k < s->n_walls; ++k) {
    const Wall *w = &s->walls[k];
    fprintf(f, "fix wall%d all wall/gran %s zplane ", k, args);
    if (w->up) fprintf(f, "%.17g NULL", w->z);
    else fprintf(f, "NULL %.17g", w->z);
    if (w->vx != 0.0) fprintf(f, " shear x %.17g", w->vx);
    fprintf(f, "\n");
  }
  fprintf(f, "timestep %.17g\nthermo_style custom step atoms\nthermo %ld\nrun %ld\n", s->dt, s->steps, s->steps);
  fprintf(f, "write_dump all custom %s id vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz modify sort id "
             "format float %%.17g\n", dump);
  fclose(f);
  snprintf(cmd, sizeof cmd, "lmp -in %s -log %s.log -screen none -echo none -nocite", deck, s->name);
  if (system(cmd) != 0) TL_ERROR(TL_ERR_IO, "LAMMPS failed on %s (its log: %s.log)", deck, s->name);
  f = fopen(dump, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "LAMMPS wrote no %s", dump);
  char line[4096];
  int atoms = 0;
  size_t got = 0;
  while (fgets(line, sizeof line, f)) {
    if (!strncmp(line, "ITEM: ATOMS", 11)) {
      atoms = 1;
      continue;
    }
    if (!atoms) continue;
    double q[13];
    char *p = line, *e;
    int k = 0;
    for (; k < 13; ++k, p = e) {
      q[k] = strtod(p, &e);
      if (e == p) break;
    }
    if (k != 13 || q[0] < 1 || q[0] > (double)s->n) {
      fclose(f);
      TL_ERROR(TL_ERR_FORMAT, "%s: unreadable atom line '%s'", dump, line);
    }
    memcpy(out + 12 * ((size_t)q[0] - 1), q + 1, 12 * sizeof(double));
    ++got;
  }
  fclose(f);
  if (got != s->n) TL_ERROR(TL_ERR_FORMAT, "%s: %zu atoms, expected %zu (atoms lost?)", dump, got, s->n);
  return TL_OK;
}

/* ----------------------------------------------------------------- Talus */

static TlStatus run_talus(const Scene *s, double *out, size_t *touching)
{
  static const char *const normal[] = {"lammps_hooke", "lammps_hooke", "lammps_hertz"};
  static const char *const friction[] = {"lammps_viscous", "lammps_history", "lammps_history"};
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  const TlVec3 lo = tl_v3(s->lo[0], s->lo[1], s->lo[2]), hi = tl_v3(s->hi[0], s->hi[1], s->hi[2]);
  if (s->periodic[0] || s->periodic[1] || s->periodic[2]) {
    int per[3] = {s->periodic[0], s->periodic[1], s->periodic[2]};
    TL_CHECK(tl_domain_init_periodic_box(&dom, lo, hi, per));
  } else {
    TL_CHECK(tl_domain_init_open(&dom, lo, hi));
  }
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  double rmin = INFINITY, rmax = 0.0;
  for (size_t i = 0; i < s->n; ++i) rmin = fmin(rmin, s->r[i]), rmax = fmax(rmax, s->r[i]);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "grains", s->density, rmin, rmax, &sp));
  for (size_t i = 0; i < s->n; ++i)
    TL_CHECK(tl_dem_add_particle(dem, tl_v3(s->x[3 * i], s->x[3 * i + 1], s->x[3 * i + 2]),
                                 tl_v3(s->v[3 * i], s->v[3 * i + 1], s->v[3 * i + 2]), s->r[i], sp, NULL));
  TL_CHECK(tl_particles_enable_rotation(P));
  for (size_t i = 0; i < s->n; ++i) P->w[i] = tl_v3(s->w[3 * i], s->w[3 * i + 1], s->w[3 * i + 2]);
  const TlContactValue values[] = {{"k_n", s->kn}, {"gamma_n", s->gamma_n}, {"mu", s->mu}, {"k_t", s->kt}};
  const TlContactSpec spec = {normal[s->style], friction[s->style], NULL, NULL, values, s->kt > 0.0 ? 4 : 3};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  for (int k = 0; k < s->n_walls; ++k) {
    const Wall *w = &s->walls[k];
    TlWall *wall;
    TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, w->z), tl_v3(0, 0, w->up ? 1.0 : -1.0), &wall));
    TL_CHECK(tl_wall_plane_set_velocity(wall, tl_v3(w->vx, 0, 0)));
    TL_CHECK(tl_dem_add_wall(dem, wall, 0));
  }
  tl_dem_set_gravity(dem, tl_v3(0, 0, -s->gravity));
  tl_dem_set_threads(dem, 1);
  tl_dem_set_sort_interval(dem, 0);
  tl_dem_track_orientation(dem, 0);
  TL_CHECK(tl_dem_set_timestep(dem, s->dt, 0));
  TL_CHECK(tl_dem_setup(dem));
  TL_CHECK(tl_dem_step(dem, s->steps));
  for (size_t k = 0; k < P->n; ++k) {
    double *o = out + 12 * (size_t)P->id[k];
    const TlVec3 q[4] = {P->v[k], P->w[k], P->f[k], P->torque[k]};
    for (int a = 0; a < 4; ++a) o[3 * a] = q[a].x, o[3 * a + 1] = q[a].y, o[3 * a + 2] = q[a].z;
  }
  TlDemStats st;
  tl_dem_stats(dem, &st);
  *touching = st.n_contacts;
  tl_dem_destroy(&dem);
  return TL_OK;
}

/* -------------------------------------------------------------- compare */

static void compare(const Scene *s)
{
  double *lmp = calloc(12 * s->n, sizeof(double)), *tal = calloc(12 * s->n, sizeof(double));
  size_t touching = 0;
  TL_TEST_STATUS(run_lammps(s, lmp), TL_OK);
  TL_TEST_STATUS(run_talus(s, tal, &touching), TL_OK);
  static const char *const what[4] = {"velocity", "spin", "force", "torque"};
  printf("%s (%s, %zu spheres, %ld steps, %zu contacts at the end in Talus):\n", s->name, lammps_style[s->style], s->n,
         s->steps, touching);
  for (int a = 0; a < 4; ++a) {
    double dmax = 0.0, ref = 0.0;
    for (size_t i = 0; i < s->n; ++i) {
      const double *p = lmp + 12 * i + 3 * a, *q = tal + 12 * i + 3 * a;
      const double d = sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) + (q[2] - p[2]) * (q[2] - p[2]));
      const double m = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      dmax = d > dmax || isnan(d) ? d : dmax;
      ref = fmax(ref, m);
    }
    if (ref == 0.0) {
      /* apart (no force) or rolling without slip (no torque): zero in both */
      printf("  %-8s  zero in LAMMPS, max |Talus| %.3e\n", what[a], dmax);
      TL_TEST_ASSERT(dmax == 0.0, "%s %s: zero in LAMMPS, %g in Talus", s->name, what[a], dmax);
      continue;
    }
    const double rel = dmax / ref;
    printf("  %-8s  max |LAMMPS| %.6e  max |Talus - LAMMPS| %.3e  relative %.3e\n", what[a], ref, dmax, rel);
    TL_TEST_ASSERT(rel <= tolerance, "%s %s: relative difference %.3g > %g (reference %g)", s->name, what[a], rel,
                   tolerance, ref);
  }
  if (getenv("PARITY_DEBUG"))
    for (size_t i = 0; i < s->n && i < 4; ++i)
      for (int a = 0; a < 12; ++a) printf("    %zu %d %.17g %.17g\n", i, a, lmp[12 * i + a], tal[12 * i + a]);
  if (s->n == 2)
    printf("  final spins: LAMMPS (%.9g, %.9g, %.9g), Talus (%.9g, %.9g, %.9g)\n", lmp[3], lmp[4], lmp[5], tal[3],
           tal[4], tal[5]);
  free(lmp);
  free(tal);
}

/* ---------------------------------------------------------------- scenes */

/* Two spheres of radii 0.5 and 0.4 m, spinning, meeting obliquely. */
static void impact(Style style, const char *name)
{
  Scene s;
  memset(&s, 0, sizeof s);
  s.name = name;
  s.style = style;
  s.density = 2500.0;
  s.kn = style == HERTZ_HISTORY ? 2e8 : 1e7;
  s.gamma_n = style == HERTZ_HISTORY ? 200.0 : 20.0;
  s.mu = 0.5;
  for (int k = 0; k < 3; ++k) s.lo[k] = -4.0, s.hi[k] = 4.0;
  s.dt = 1e-4;
  scene_alloc(&s, 2);
  const double x[6] = {0, 0, 0, 1.1, 0.35, 0.15}, v[6] = {1.5, 0.2, -0.1, -1.5, -0.3, 0.05},
               w[6] = {5, -3, 8, -4, 6, 2};
  s.r[0] = 0.5, s.r[1] = 0.4;
  memcpy(s.x, x, sizeof x), memcpy(s.v, v, sizeof v), memcpy(s.w, w, sizeof w);
  /* contact from step 898 to about 1100: in the middle of it, then apart */
  s.steps = 1000;
  compare(&s);
  s.steps = 2500;
  compare(&s);
  scene_free(&s);
}

/* A sphere landing on the floor z = 0 with spin against its motion: it
 * slides, then rolls. */
static void on_wall(Style style, const char *name)
{
  Scene s;
  memset(&s, 0, sizeof s);
  s.name = name;
  s.style = style;
  s.density = 2500.0;
  s.kn = style == HERTZ_HISTORY ? 2e8 : 1e7;
  s.gamma_n = style == HERTZ_HISTORY ? 200.0 : 20.0;
  s.mu = 0.3;
  s.lo[0] = s.lo[1] = -10.0, s.hi[0] = s.hi[1] = 10.0;
  s.lo[2] = -1.0, s.hi[2] = 4.0;
  s.gravity = 9.81;
  s.dt = 1e-4;
  scene_alloc(&s, 1);
  const double x[3] = {0, 0, 0.52}, v[3] = {2.0, 0.5, -0.4}, w[3] = {3, 10, 1};
  s.r[0] = 0.5;
  memcpy(s.x, x, sizeof x), memcpy(s.v, v, sizeof v), memcpy(s.w, w, sizeof w);
  s.n_walls = 1;
  s.walls[0] = (Wall){0.0, 0.0, 1};
  /* in the first contact (from about step 500), sliding with the spin
   * against the motion; then after bounces, rolling */
  s.steps = 650;
  compare(&s);
  s.steps = 4000;
  compare(&s);
  scene_free(&s);
}

/* 6 x 6 x 6 spheres of radii in [r0, r0 + 0.03] m on a lattice of spacing
 * a, periodic in x and y, between the floor and the lid moving at -V and +V
 * along x, with a shear profile and random velocities and spins: 200 steps
 * of a dense sheared packing.  a = 1.015, r0 = 0.47: gaps of 0.009 m and
 * more, no contact at the start; a = 1.0, r0 = 0.485: overlaps up to 0.03 m
 * from the start (the first force evaluation, LAMMPS's setup, then carries
 * contacts: neither code advances the shear history over it). */
static void packing(const char *name, double a, double r0)
{
  Scene s;
  memset(&s, 0, sizeof s);
  s.name = name;
  s.style = HERTZ_HISTORY;
  s.density = 2500.0;
  s.kn = 2e8;
  s.gamma_n = 200.0;
  s.mu = 0.5;
  const int m = 6;
  const double V = 2.0, H = m * a + 0.02;
  s.lo[0] = s.lo[1] = s.lo[2] = 0.0;
  s.hi[0] = s.hi[1] = m * a, s.hi[2] = H;
  s.periodic[0] = s.periodic[1] = 1;
  s.dt = 1e-4;
  s.steps = 200;
  scene_alloc(&s, (size_t)(m * m * m));
  unsigned long long seed = 20261201ULL;
  size_t k = 0;
  for (int iz = 0; iz < m; ++iz)
    for (int iy = 0; iy < m; ++iy)
      for (int ix = 0; ix < m; ++ix, ++k) {
        s.r[k] = r0 + 0.03 * urand(&seed);
        const double c[3] = {(ix + 0.5) * a, (iy + 0.5) * a, (iz + 0.5) * a + 0.01};
        for (int q = 0; q < 3; ++q) {
          s.x[3 * k + q] = c[q] + 0.003 * (2.0 * urand(&seed) - 1.0);
          s.v[3 * k + q] = 2.0 * (2.0 * urand(&seed) - 1.0);
          s.w[3 * k + q] = 4.0 * (2.0 * urand(&seed) - 1.0);
        }
        s.v[3 * k] += V * (2.0 * s.x[3 * k + 2] / H - 1.0);
      }
  s.n_walls = 2;
  s.walls[0] = (Wall){0.0, -V, 1};
  s.walls[1] = (Wall){H, V, 0};
  compare(&s);
  scene_free(&s);
}

/* The gouge of seeds/000: a packing made by periodic_compress -protocol
 * scripts (bidisperse Table 1 grains at 5 MPa, periodic in x, y and z) with
 * the gouge law of Table 1 (gran/hertz/history 3.663e10 4.5249e10 0.2 NULL
 * 0.5 1 = lammps_hertz + lammps_history, dt = 1e-8 s), stirred by random
 * velocities (±0.2 m/s) and spins (±100 rad/s) so that contacts load, slide
 * and open: 2000 steps from the packing's overlaps. */
static void gouge(const char *path)
{
  TlParticleSnapshot snap;
  TlVec3 o;
  TlMat3 h;
  TL_TEST_STATUS(tl_dem_packing_read(path, &snap, &o, &h), TL_OK);
  if (snap.n == 0) return;
  Scene s;
  memset(&s, 0, sizeof s);
  s.name = "gouge_packing";
  s.style = HERTZ_HISTORY;
  s.density = 2500.0;
  s.kn = tl_gouge_law_spec.values[0].value;
  s.gamma_n = tl_gouge_law_spec.values[1].value;
  s.kt = tl_gouge_law_spec.values[2].value;
  s.mu = tl_gouge_law_spec.values[3].value;
  s.skin = 3e-4;
  s.lo[0] = o.x, s.lo[1] = o.y, s.lo[2] = o.z;
  for (int k = 0; k < 3; ++k) s.hi[k] = s.lo[k] + h.m[k][k], s.periodic[k] = 1;
  s.dt = 1e-8;
  s.steps = 2000;
  scene_alloc(&s, snap.n);
  unsigned long long seed = 20261202ULL;
  for (size_t i = 0; i < snap.n; ++i) {
    s.r[i] = snap.radius[i];
    const double x[3] = {snap.position[i].x, snap.position[i].y, snap.position[i].z};
    for (int k = 0; k < 3; ++k) {
      /* inside [lo, hi): LAMMPS's read_data and Talus's box see the same doubles */
      double L = s.hi[k] - s.lo[k], u = (x[k] - s.lo[k]) / L;
      u -= floor(u);
      s.x[3 * i + k] = s.lo[k] + L * u;
      if (!(s.x[3 * i + k] < s.hi[k])) s.x[3 * i + k] = s.lo[k];
      s.v[3 * i + k] = 0.2 * (2.0 * urand(&seed) - 1.0);
      s.w[3 * i + k] = 100.0 * (2.0 * urand(&seed) - 1.0);
    }
  }
  tl_particle_snapshot_free(&snap);
  compare(&s);
  scene_free(&s);
}

int main(int argc, char **argv)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  if (!have_lammps()) return 77;
  if (argc > 1) {
    /* the gouge packing alone (its own ctest) */
    gouge(argv[1]);
    return tl_test_report();
  }
  impact(HOOKE, "impact_hooke");
  impact(HOOKE_HISTORY, "impact_hooke_history");
  impact(HERTZ_HISTORY, "impact_hertz_history");
  on_wall(HOOKE_HISTORY, "wall_hooke_history");
  on_wall(HERTZ_HISTORY, "wall_hertz_history");
  packing("sheared_packing", 1.015, 0.47);
  packing("compressed_sheared_packing", 1.0, 0.485);
  return tl_test_report();
}
