/* Walls in the hierarchical grid (seeds/001 §5.1.1, Algorithm 2).
 *
 * 1. Scaling: 10 000 spheres (r = 1 mm) resting in a square patch on a flat
 *    triangulated floor of 10^3 ... 10^6 triangles of fixed size (the floor
 *    grows around the patch).  Time per particle-step of the whole DEM step
 *    and of the wall alone must stay flat as the triangle count grows; the
 *    wall's cost is compared with brute force (every particle against every
 *    triangle), measured where it fits in -brute_max tests per step.
 * 2. The peer scene mesh_wall of the peers' README: 5 000 settled spheres on
 *    LIGGGHTS's 3 200-triangle floor, periodic in x and y, Hertz contacts
 *    (E = 5 MPa, nu = 0.45, e = 0.3, mu = 0.5), dt = 1e-5 s; Talus and
 *    LIGGGHTS run in the same invocation (Benchmarks/peers/run_peer.sh) and
 *    the ratio of their times per particle-step is printed.  -peer_sweep also
 *    runs both over the README's floors of 200 ... 12 800 triangles.
 *
 * 3. STL floors of 10^3 ... 10^6 triangles (-stl_triangles): the peers'
 *    STL file of each size is the wall of both codes: LIGGGHTS reads it with
 *    fix mesh/surface, Talus with tl_wall_trisurface_from_file (read, check,
 *    periodic edges joined); the same 5 000 settled spheres, the same Hertz
 *    law, the ratio of times per particle-step in the same invocation.
 * 4. The same answer (-stl_answer): 16 spheres resting on the smallest STL
 *    floor at scattered places (on faces, near edges), run by LIGGGHTS (a deck
 *    written here: fix mesh/surface/stress gives the force on the mesh) and
 *    by Talus: the vertical force on the mesh and the resting heights of both
 *    against each other and against the weight and Hertz's overlap.
 *
 * 5. STL hoppers of 10^3 ... 10^6 triangles (-hopper_triangles): a conical
 *    funnel on a plate (walls_hgrid_hopper.h) written as one STL file that
 *    both codes read; the same lattice of grains (-hopper_particles) falls
 *    into it and flows down the funnel; after -hopper_warmup untimed steps,
 *    -hopper_steps timed ones, both codes, the ratio printed.  The same
 *    answer on the smallest hopper (-hopper_answer): eight spheres rolling
 *    down facet columns of the funnel for -hopper_answer_steps steps, their
 *    positions and the force on the mesh from both codes.
 *
 * Output: <output_dir>/scaling.csv, peer.csv, stl.csv, hopper.csv; last line
 *   summary: ... ratio=<talus/liggghts> ... stl_ratio_<n>=... hopper_ratio_<n>=... wall=<s> */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "peers/tl_peer.h"
#include "talus.h"
#include "tl_atomic_file.h"
#include "tl_contact_law.h"
#include "tl_dem.h"
#include "tl_lammps_data.h"
#include "tl_wall_trisurface.h"
#include "walls_hgrid_hopper.h"

typedef struct {
  double radius, density, youngs, poisson, restitution, mu, dt;
  long n_particles, steps, warmup, brute_steps;
  double brute_max;
  double triangles[8];
  int n_sizes;
  int peer, peer_sweep, peer_repeat;
  long peer_steps, peer_warmup;
  double stl_triangles[8];
  int n_stl, stl_repeat, stl_answer;
  long stl_steps;
  int stl_floors;
  double hopper_triangles[8];
  int n_hopper, hopper_answer;
  long hopper_particles, hopper_warmup, hopper_steps, hopper_answer_steps;
  const char *output_dir;
} Setup;

/* The Hertz law of the peers' scene: Talus's k_n, k_t are LIGGGHTS's
 * (4/3 Y*, 8 G*); LIGGGHTS's damping sqrt(s m)-form is matched at the
 * resting overlap of a sphere under its weight. */
static TlStatus make_law(const Setup *s, TlContactLaw **law)
{
  double kn = 2.0 / 3.0 * s->youngs / (1 - s->poisson * s->poisson);
  double m = s->density * 4.0 / 3.0 * TL_PI * pow(s->radius, 3);
  double delta = pow(m * 9.81 / (kn * sqrt(s->radius)), 2.0 / 3.0);
  double sq = sqrt(delta * s->radius), le = log(s->restitution);
  double beta = le / sqrt(le * le + TL_PI * TL_PI);
  double ystar = s->youngs / (2 * (1 - s->poisson * s->poisson));
  double gstar = s->youngs / (4 * (2 - s->poisson) * (1 + s->poisson));
  double cn = -2 * sqrt(5.0 / 6.0) * beta * sqrt(2 * ystar * sq * m);
  double ct = -2 * sqrt(5.0 / 6.0) * beta * sqrt(8 * gstar * sq * m);
  const TlContactValue hv[] = {{"E", s->youngs}, {"nu", s->poisson}, {"mu", s->mu}, {"gamma_n", cn / (sq * m)},
                               {"gamma_t", ct / (sq * m)}};
  const TlContactSpec spec = {"hertz", "coulomb", NULL, NULL, hv, 5};
  TL_CHECK(tl_contact_law_build(&spec, law));
  return TL_OK;
}

static double resting_overlap(const Setup *s)
{
  double kn = 2.0 / 3.0 * s->youngs / (1 - s->poisson * s->poisson);
  double m = s->density * 4.0 / 3.0 * TL_PI * pow(s->radius, 3);
  return pow(m * 9.81 / (kn * sqrt(s->radius)), 2.0 / 3.0);
}

/* CPU seconds of this process (all threads): on a shared machine the wall
 * clock also counts the time other programs held the cores. */
static double cpu_seconds(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Runs `steps` DEM steps with a progress bar; returns the wall time and the
 * CPU time. */
static TlStatus timed_steps(TlDem *dem, long steps, const char *label, double *seconds, double *cpu)
{
  TlProgress bar;
  tl_progress_init(&bar, label, (double)steps);
  double c0 = cpu_seconds();
  double t0 = tl_wtime();
  long chunk = steps < 100 ? steps : 100;
  for (long done = 0; done < steps; done += chunk) {
    long n = steps - done < chunk ? steps - done : chunk;
    TL_CHECK(tl_dem_step(dem, n));
    tl_progress_update(&bar, (double)(done + n));
  }
  *seconds = tl_wtime() - t0;
  *cpu = cpu_seconds() - c0;
  tl_progress_finish(&bar);
  return TL_OK;
}

/* Seconds per call of the wall's interact on the current state. */
static TlStatus time_wall(TlDem *dem, TlWall *w, const TlContactLaw *law, long calls, double *seconds, double *cpu)
{
  TlWallStep st = {.particles = tl_dem_particles(dem), .grid = tl_dem_grid(dem), .domain = tl_dem_domain(dem),
                   .law = law, .t = tl_dem_time(dem), .dt = tl_dem_timestep(dem)};
  TlParticles *P = st.particles;
  double c0 = cpu_seconds();
  double t0 = tl_wtime();
  for (long k = 0; k < calls; ++k) {
    for (size_t i = 0; i < P->n; ++i) P->f[i] = tl_v3(0, 0, 0);
    TL_CHECK(w->ops->interact(w, &st));
  }
  *seconds = (tl_wtime() - t0) / (double)calls;
  *cpu = (cpu_seconds() - c0) / (double)calls;
  return TL_OK;
}

typedef struct {
  double triangles, floor_side, us_step, us_wall, us_brute, brute_ratio;
  double cpu_step, cpu_wall, cpu_brute; /* the same in CPU time */
  size_t wall_contacts;
  int brute_measured;
} ScalingRow;

static TlStatus scaling_case(const Setup *s, double n_triangles, ScalingRow *row)
{
  /* 100 x 100 lattice of spheres at pitch 2.2 r, resting at the Hertz
   * overlap of their weight; the floor's squares are sized so that the
   * smallest floor (-triangles' first value) just carries the patch */
  long side = (long)ceil(sqrt((double)s->n_particles));
  double pitch = 2.2 * s->radius, patch = side * pitch;
  int n_min = (int)floor(sqrt(s->triangles[0] / 2.0));
  if (n_min < 1) n_min = 1;
  double a = patch / n_min;
  int n = (int)floor(sqrt(n_triangles / 2.0));
  if (n < n_min) n = n_min;
  double L = n * a;
  TlDem *dem = NULL;
  TlContactLaw *law = NULL;
  TlTriSurface *surface = NULL;
  TlWall *wall = NULL;
  TlStatus status = TL_OK;
  TL_CHECK_GOTO(status, tl_dem_create(&dem), done);
  TlDomain dom;
  TL_CHECK_GOTO(status, tl_domain_init_open(&dom, tl_v3(-0.5 * patch, -0.5 * patch, -s->radius),
                                            tl_v3(0.5 * patch, 0.5 * patch, 3 * s->radius)), done);
  TL_CHECK_GOTO(status, tl_dem_set_domain(dem, &dom), done);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK_GOTO(status, tl_particles_add_species(P, "glass", s->density, s->radius, s->radius, &sp), done);
  TL_CHECK_GOTO(status, tl_particles_reserve(P, (size_t)s->n_particles), done);
  double z = s->radius - resting_overlap(s);
  for (long k = 0; k < s->n_particles; ++k) {
    double x = -0.5 * patch + (k % side + 0.5) * pitch, y = -0.5 * patch + (k / side + 0.5) * pitch;
    TL_CHECK_GOTO(status, tl_dem_add_particle(dem, tl_v3(x, y, z), tl_v3(0, 0, 0), s->radius, sp, NULL), done);
  }
  TL_CHECK_GOTO(status, make_law(s, &law), done);
  const TlContactLaw *law_ref = law;
  TL_CHECK_GOTO(status, tl_dem_add_law(dem, law, NULL), done);
  law = NULL;
  TL_CHECK_GOTO(status, tl_trisurface_create_rectangle(-0.5 * L, -0.5 * L, L, L, 0.0, n, n, 0, &surface), done);
  row->triangles = (double)surface->n_triangles;
  row->floor_side = L;
  TL_CHECK_GOTO(status, tl_wall_trisurface_create(surface, &wall), done);
  surface = NULL;
  TlWall *w = wall;
  TL_CHECK_GOTO(status, tl_dem_add_wall(dem, wall, 0), done);
  wall = NULL;
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  TL_CHECK_GOTO(status, tl_dem_set_timestep(dem, s->dt, 0), done);
  TL_CHECK_GOTO(status, tl_dem_setup(dem), done);
  TL_CHECK_GOTO(status, tl_dem_step(dem, s->warmup), done);
  double sec = 0.0, cpu = 0.0;
  char label[64];
  snprintf(label, sizeof label, "%.0f triangles", row->triangles);
  TL_CHECK_GOTO(status, timed_steps(dem, s->steps, label, &sec, &cpu), done);
  row->us_step = 1e6 * sec / ((double)s->steps * (double)P->n);
  row->cpu_step = 1e6 * cpu / ((double)s->steps * (double)P->n);
  row->wall_contacts = w->n_contacts;
  TL_CHECK_GOTO(status, time_wall(dem, w, law_ref, s->steps / 4 + 1, &sec, &cpu), done);
  row->us_wall = 1e6 * sec / (double)P->n;
  row->cpu_wall = 1e6 * cpu / (double)P->n;
  row->brute_measured = (double)P->n * row->triangles <= s->brute_max;
  if (row->brute_measured) {
    TL_CHECK_GOTO(status, tl_wall_trisurface_set_brute_force(w, 1), done);
    TL_CHECK_GOTO(status, time_wall(dem, w, law_ref, s->brute_steps, &sec, &cpu), done);
    TL_CHECK_GOTO(status, tl_wall_trisurface_set_brute_force(w, 0), done);
    row->us_brute = 1e6 * sec / (double)P->n;
    row->cpu_brute = 1e6 * cpu / (double)P->n;
    row->brute_ratio = row->cpu_brute / row->cpu_wall;
  }
done:
  tl_contact_law_destroy(&law);
  tl_trisurface_destroy(&surface);
  tl_wall_destroy(&wall);
  tl_dem_destroy(&dem);
  return status;
}

/* The peer scene's world without its floor: the settled spheres of the
 * LAMMPS data file in the periodic box, with the benchmark's law. */
static TlStatus peer_world_create(const Setup *s, const char *data_path, TlLammpsData **data, TlDem **dem,
                                  TlDomain *dom)
{
  TlContactLaw *law = NULL;
  TlStatus status = TL_OK;
  TL_CHECK_GOTO(status, tl_lammps_data_read(data_path, data), done);
  TL_CHECK_GOTO(status, tl_dem_create(dem), done);
  const TlLammpsData *d = *data;
  int per[3] = {1, 1, 0};
  TL_CHECK_GOTO(status, tl_domain_init_periodic_box(dom, tl_v3(d->lo[0], d->lo[1], d->lo[2]),
                                                    tl_v3(d->hi[0], d->hi[1], d->hi[2]), per), done);
  TL_CHECK_GOTO(status, tl_dem_set_domain(*dem, dom), done);
  TlParticles *P = tl_dem_particles(*dem);
  int sp;
  TL_CHECK_GOTO(status, tl_particles_add_species(P, "glass", s->density, s->radius, s->radius, &sp), done);
  TL_CHECK_GOTO(status, tl_particles_reserve(P, d->n), done);
  for (size_t i = 0; i < d->n; ++i)
    TL_CHECK_GOTO(status, tl_dem_add_particle(*dem, d->x[i], d->v[i], 0.5 * d->diameter[i], sp, NULL), done);
  TL_CHECK_GOTO(status, make_law(s, &law), done);
  TL_CHECK_GOTO(status, tl_dem_add_law(*dem, law, NULL), done);
  law = NULL;
done:
  tl_contact_law_destroy(&law);
  return status;
}

/* Sets the peer scene's world up (its floor added), warms it up and times
 * `steps` steps: µs per particle-step and the CPU share. */
static TlStatus peer_world_time(const Setup *s, const TlLammpsData *data, TlDem *dem, long steps, const char *label,
                                double *us, double *cpu_share, size_t *particles)
{
  TlParticles *P = tl_dem_particles(dem);
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  TL_CHECK(tl_dem_set_skin(dem, 0.0002 / (2 * s->radius)));
  TL_CHECK(tl_dem_set_timestep(dem, s->dt, 0));
  TL_CHECK(tl_dem_setup(dem));
  if (P->w)
    for (size_t i = 0; i < data->n; ++i) P->w[i] = data->omega[i];
  TL_CHECK(tl_dem_step(dem, s->peer_warmup));
  double sec = 0.0, cpu = 0.0;
  TL_CHECK(timed_steps(dem, steps, label, &sec, &cpu));
  *particles = P->n;
  *us = 1e6 * sec / ((double)steps * (double)P->n);
  *cpu_share = sec > 0.0 ? cpu / sec : 0.0;
  return TL_OK;
}

/* Talus on the peer scene: the settled spheres of `data` on an n x n floor. */
static TlStatus peer_scene_talus(const Setup *s, const char *data_path, int n, double *us, double *cpu_share,
                                 size_t *particles)
{
  TlLammpsData *data = NULL;
  TlDem *dem = NULL;
  TlWall *wall = NULL;
  TlTriSurface *surface = NULL;
  TlDomain dom;
  TlStatus status = TL_OK;
  TL_CHECK_GOTO(status, peer_world_create(s, data_path, &data, &dem, &dom), done);
  double lx = data->hi[0] - data->lo[0], ly = data->hi[1] - data->lo[1];
  TL_CHECK_GOTO(status, tl_trisurface_create_rectangle(data->lo[0], data->lo[1], lx, ly, 0.0, n, n, 0, &surface), done);
  /* the floor crosses the periodic faces: join its edges there */
  TL_CHECK_GOTO(status, tl_trisurface_link_periodic(surface, &dom, 1e-9, NULL), done);
  TL_CHECK_GOTO(status, tl_wall_trisurface_create(surface, &wall), done);
  surface = NULL;
  TL_CHECK_GOTO(status, tl_dem_add_wall(dem, wall, 0), done);
  wall = NULL;
  char label[64];
  snprintf(label, sizeof label, "talus %d triangles", 2 * n * n);
  TL_CHECK_GOTO(status, peer_world_time(s, data, dem, s->peer_steps, label, us, cpu_share, particles), done);
done:
  tl_trisurface_destroy(&surface);
  tl_wall_destroy(&wall);
  tl_dem_destroy(&dem);
  tl_lammps_data_destroy(&data);
  return status;
}

/* Talus on the peer scene with the floor read from the peer's STL file. */
static TlStatus stl_scene_talus(const Setup *s, const char *data_path, const char *stl_path, double *us, double *cpu_share,
                                size_t *particles, size_t *triangles, double *load_seconds)
{
  TlLammpsData *data = NULL;
  TlDem *dem = NULL;
  TlWall *wall = NULL;
  TlDomain dom;
  TlStatus status = TL_OK;
  TL_CHECK_GOTO(status, peer_world_create(s, data_path, &data, &dem, &dom), done);
  /* the wall from the file: read, checked (a clean floor: no repair), and
   * joined across the periodic faces */
  double t0 = tl_wtime();
  TlWallPlacement place;
  tl_wall_placement_default(&place);
  place.repair = 0;
  TL_CHECK_GOTO(status, tl_wall_trisurface_from_file(stl_path, &place, &wall, NULL), done);
  TL_CHECK_GOTO(status, tl_trisurface_link_periodic(tl_wall_trisurface_surface(wall), &dom, 1e-9, NULL), done);
  *load_seconds = tl_wtime() - t0;
  *triangles = tl_wall_trisurface_surface(wall)->n_triangles;
  TL_CHECK_GOTO(status, tl_dem_add_wall(dem, wall, 0), done);
  wall = NULL;
  char label[64];
  snprintf(label, sizeof label, "talus STL %zu triangles", *triangles);
  TL_CHECK_GOTO(status, peer_world_time(s, data, dem, s->stl_steps, label, us, cpu_share, particles), done);
done:
  tl_wall_destroy(&wall);
  tl_dem_destroy(&dem);
  tl_lammps_data_destroy(&data);
  return status;
}

/* The 16 resting spheres of the same-answer check: scattered over the
 * floor [0, 0.1]^2, at the Hertz overlap of their weight. */
enum { ANSWER_SPHERES = 16, ANSWER_STEPS = 3000 };
static TlVec3 answer_position(const Setup *s, int i)
{
  return tl_v3(0.0123 + 0.0217 * (i % 4) + 0.0011 * (i / 4), 0.0234 + 0.0209 * (i / 4) + 0.0007 * (i % 4),
               s->radius - resting_overlap(s));
}

typedef struct {
  double force_z, z_min, z_max;
} AnswerResult;

static TlStatus answer_liggghts(const Setup *s, const char *stl_path, AnswerResult *r)
{
  char dir[4200], deck[4300], log[4300], command[13000];
  snprintf(dir, sizeof dir, "%s/answer", s->output_dir);
  TL_CHECK(tl_mkdir_p(dir));
  snprintf(deck, sizeof deck, "%s/in.rest", dir);
  snprintf(log, sizeof log, "%s/log.rest", dir);
  FILE *f = fopen(deck, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write the LIGGGHTS deck %s", deck);
  double ystar = s->youngs, e = s->restitution;
  fprintf(f, "atom_style granular\natom_modify map array\nboundary f f f\nnewton off\ncommunicate single vel yes\n"
             "units si\nregion box block -0.01 0.11 -0.01 0.11 -0.01 0.02 units box\ncreate_box 1 box\n"
             "neighbor 0.0002 bin\nneigh_modify delay 0\n"
             "fix m1 all property/global youngsModulus peratomtype %.17g\n"
             "fix m2 all property/global poissonsRatio peratomtype %.17g\n"
             "fix m3 all property/global coefficientRestitution peratomtypepair 1 %.17g\n"
             "fix m4 all property/global coefficientFriction peratomtypepair 1 %.17g\n"
             "pair_style gran model hertz tangential history\npair_coeff * *\ntimestep %.17g\n"
             "fix plane all mesh/surface/stress file %s type 1\n"
             "fix wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes plane\n",
          ystar, s->poisson, e, s->mu, s->dt, stl_path);
  for (int i = 0; i < ANSWER_SPHERES; ++i) {
    TlVec3 x = answer_position(s, i);
    fprintf(f, "create_atoms 1 single %.17g %.17g %.17g units box\n", x.x, x.y, x.z);
  }
  fprintf(f, "set group all diameter %.17g density %.17g\nfix integr all nve/sphere\n"
             "fix grav all gravity 9.81 vector 0.0 0.0 -1.0\ncompute zmin all reduce min z\n"
             "compute zmax all reduce max z\nthermo_style custom step atoms ke f_plane[3] c_zmin c_zmax\n"
             "thermo_modify format float %%.15g\nthermo %d\nrun %d\n",
          2 * s->radius, s->density, ANSWER_STEPS, ANSWER_STEPS);
  fclose(f);
  snprintf(command, sizeof command, "cd '%s' && liggghts -in in.rest -log log.rest -echo none > out.rest 2>&1", dir);
  fflush(stdout);
  int rc = system(command);
  if (rc != 0) TL_ERROR(TL_ERR_IO, "LIGGGHTS failed on %s (exit %d; see %s/out.rest)", deck, rc, dir);
  f = fopen(log, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "no LIGGGHTS log %s", log);
  char line[1024];
  int found = 0;
  while (fgets(line, sizeof line, f)) {
    long step, atoms;
    double ke, fz, z0, z1;
    if (sscanf(line, "%ld %ld %lf %lf %lf %lf", &step, &atoms, &ke, &fz, &z0, &z1) == 6 && step == ANSWER_STEPS)
      r->force_z = fz, r->z_min = z0, r->z_max = z1, found = 1;
  }
  fclose(f);
  if (!found) TL_ERROR(TL_ERR_FORMAT, "LIGGGHTS log %s has no thermo line at step %d", log, ANSWER_STEPS);
  return TL_OK;
}

static TlStatus answer_talus(const Setup *s, const char *stl_path, AnswerResult *r)
{
  TlDem *dem = NULL;
  TlContactLaw *law = NULL;
  TlWall *wall = NULL;
  TlStatus status = TL_OK;
  TL_CHECK_GOTO(status, tl_dem_create(&dem), done);
  TlDomain dom;
  TL_CHECK_GOTO(status, tl_domain_init_open(&dom, tl_v3(-0.01, -0.01, -0.01), tl_v3(0.11, 0.11, 0.02)), done);
  TL_CHECK_GOTO(status, tl_dem_set_domain(dem, &dom), done);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK_GOTO(status, tl_particles_add_species(P, "glass", s->density, s->radius, s->radius, &sp), done);
  for (int i = 0; i < ANSWER_SPHERES; ++i)
    TL_CHECK_GOTO(status, tl_dem_add_particle(dem, answer_position(s, i), tl_v3(0, 0, 0), s->radius, sp, NULL), done);
  TL_CHECK_GOTO(status, make_law(s, &law), done);
  TL_CHECK_GOTO(status, tl_dem_add_law(dem, law, NULL), done);
  law = NULL;
  TL_CHECK_GOTO(status, tl_wall_trisurface_from_file(stl_path, NULL, &wall, NULL), done);
  TlWall *w = wall;
  TL_CHECK_GOTO(status, tl_dem_add_wall(dem, wall, 0), done);
  wall = NULL;
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  TL_CHECK_GOTO(status, tl_dem_set_timestep(dem, s->dt, 0), done);
  TL_CHECK_GOTO(status, tl_dem_setup(dem), done);
  TL_CHECK_GOTO(status, tl_dem_step(dem, ANSWER_STEPS), done);
  r->force_z = w->force.z;
  r->z_min = INFINITY, r->z_max = -INFINITY;
  for (size_t i = 0; i < P->n; ++i) r->z_min = fmin(r->z_min, P->x[i].z), r->z_max = fmax(r->z_max, P->x[i].z);
done:
  tl_contact_law_destroy(&law);
  tl_wall_destroy(&wall);
  tl_dem_destroy(&dem);
  return status;
}

/* Talus in the hopper: spheres from x, the wall read from the STL file
 * (checked, not repaired: the file is clean), `warmup` untimed and `steps`
 * timed steps; the final positions (x_end, may be NULL) and the force on the
 * mesh. */
static TlStatus hopper_talus(const Setup *s, const char *stl, const TlVec3 *x, size_t n, long warmup, long steps,
                             double *us, double *cpu_share, double *load_seconds, size_t *triangles, TlVec3 *x_end,
                             TlVec3 *force)
{
  TlDem *dem = NULL;
  TlContactLaw *law = NULL;
  TlWall *wall = NULL;
  TlStatus status = TL_OK;
  TL_CHECK_GOTO(status, tl_dem_create(&dem), done);
  TlDomain dom;
  TL_CHECK_GOTO(status, tl_domain_init_open(&dom, tl_v3(-0.045, -0.045, -0.005), tl_v3(0.045, 0.045, 0.05)), done);
  TL_CHECK_GOTO(status, tl_dem_set_domain(dem, &dom), done);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK_GOTO(status, tl_particles_add_species(P, "glass", s->density, s->radius, s->radius, &sp), done);
  TL_CHECK_GOTO(status, tl_particles_reserve(P, n), done);
  int64_t id0 = 0;
  for (size_t i = 0; i < n; ++i) {
    size_t at;
    TL_CHECK_GOTO(status, tl_dem_add_particle(dem, x[i], tl_v3(0, 0, 0), s->radius, sp, &at), done);
    if (i == 0) id0 = P->id[at];
  }
  TL_CHECK_GOTO(status, make_law(s, &law), done);
  TL_CHECK_GOTO(status, tl_dem_add_law(dem, law, NULL), done);
  law = NULL;
  double t0 = tl_wtime();
  TlWallPlacement place;
  tl_wall_placement_default(&place);
  place.repair = 0;
  TL_CHECK_GOTO(status, tl_wall_trisurface_from_file(stl, &place, &wall, NULL), done);
  *load_seconds = tl_wtime() - t0;
  *triangles = tl_wall_trisurface_surface(wall)->n_triangles;
  TlWall *w = wall;
  TL_CHECK_GOTO(status, tl_dem_add_wall(dem, wall, 0), done);
  wall = NULL;
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  TL_CHECK_GOTO(status, tl_dem_set_skin(dem, 0.0002 / (2 * s->radius)), done);
  TL_CHECK_GOTO(status, tl_dem_set_timestep(dem, s->dt, 0), done);
  TL_CHECK_GOTO(status, tl_dem_setup(dem), done);
  if (warmup > 0) TL_CHECK_GOTO(status, tl_dem_step(dem, warmup), done);
  double sec = 0.0, cpu = 0.0;
  char label[64];
  snprintf(label, sizeof label, "talus hopper %zu triangles", *triangles);
  TL_CHECK_GOTO(status, timed_steps(dem, steps, label, &sec, &cpu), done);
  *us = 1e6 * sec / ((double)steps * (double)P->n);
  *cpu_share = sec > 0.0 ? cpu / sec : 0.0;
  /* by insertion order (ids are given in it; the storage is sorted) */
  if (x_end)
    for (size_t i = 0; i < P->n; ++i) {
      int64_t k = P->id[i] - id0;
      if (k >= 0 && (size_t)k < n) x_end[k] = P->x[i];
    }
  *force = w->force;
done:
  tl_contact_law_destroy(&law);
  tl_wall_destroy(&wall);
  tl_dem_destroy(&dem);
  return status;
}

/* Part 5: hoppers of growing triangle count, then the same answer. */
static TlStatus hoppers(const Setup *s, TlSummary *summary)
{
  char dir[4200], stl[4400], smallest[4400] = "", *path = NULL;
  TlSurfaceMesh *mesh = NULL;
  TlVec3 *sites = NULL;
  TlAtomicFile *f = NULL;
  size_t n_sites = 0;
  HopperGeometry g0;
  memset(&g0, 0, sizeof g0);
  TlStatus status = TL_OK;
  snprintf(dir, sizeof dir, "%s/hopper", s->output_dir);
  TL_CHECK(tl_mkdir_p(dir));
  TL_CHECK_GOTO(status, tl_path_join(s->output_dir, "hopper.csv", &path), done);
  TL_CHECK_GOTO(status, tl_atomic_file_open(path, &f), done);
  FILE *out = tl_atomic_file_stream(f);
  fprintf(out, "triangles,spheres,talus_load_s,talus_us_per_particle_step,talus_cpu_share,liggghts_us_per_particle_step,"
               "talus_over_liggghts\n");
  for (int c = 0; c < s->n_hopper; ++c) {
    HopperGeometry g;
    hopper_geometry(s->hopper_triangles[c], &g);
    if (c == 0) g0 = g;
    TL_CHECK_GOTO(status, hopper_mesh(&g, &mesh), done);
    snprintf(stl, sizeof stl, "%s/hopper_%zu.stl", dir, mesh->n_triangles);
    TL_CHECK_GOTO(status, tl_stl_write(stl, mesh, 0), done); /* ASCII: what LIGGGHTS reads */
    tl_surface_mesh_destroy(&mesh);
    if (c == 0) snprintf(smallest, sizeof smallest, "%s", stl);
    tl_free(&sites);
    TL_CHECK_GOTO(status, hopper_sites(&g, s->radius, (size_t)s->hopper_particles, &sites, &n_sites), done);
    double us = 0.0, share = 0.0, load = 0.0, lig = 0.0;
    size_t nt = 0;
    TlVec3 force;
    TL_CHECK_GOTO(status, hopper_talus(s, stl, sites, n_sites, s->hopper_warmup, s->hopper_steps, &us, &share, &load, &nt,
                                       NULL, &force), done);
    char deck[64], deck_path[4600];
    snprintf(deck, sizeof deck, "in.hopper_%zu", nt);
    snprintf(deck_path, sizeof deck_path, "%s/%s", dir, deck);
    TL_CHECK_GOTO(status, hopper_deck(deck_path, stl, sites, n_sites, s->radius, s->density, s->youngs, s->poisson,
                                      s->restitution, s->mu, s->dt, s->hopper_warmup, s->hopper_steps, 0), done);
    char key[48];
    snprintf(key, sizeof key, "hopper_ratio_%zu", nt);
    if (hopper_liggghts(dir, deck, &lig) != TL_OK) {
      /* The peer's failure at one size leaves Talus's figure standing and the
       * other sizes to run; the ratio is undefined and says why. */
      printf("STL hopper %s: %zu triangles, %zu spheres: talus %.4f us/particle-step (load %.3g s, cpu_share %.2f); "
             "no ratio: %s\n", stl, nt, n_sites, us, load, share, tl_error_message());
      fprintf(out, "%zu,%zu,%.6g,%.6g,%.3g,,\n", nt, n_sites, load, us, share);
      tl_summary_undefined(summary, key, "liggghts_failed");
      tl_error_clear();
      fflush(stdout);
      continue;
    }
    double lig_us = 1e6 * lig / ((double)s->hopper_steps * (double)n_sites), ratio = us / lig_us;
    printf("STL hopper %s: %zu triangles (%d x %d funnel, %d^2 x 2 plate), %zu spheres, steps %ld..%ld: talus %.4f "
           "us/particle-step (load %.3g s, cpu_share %.2f), liggghts %.4f, talus/liggghts = %.3f\n",
           stl, nt, g.n_theta, g.n_z, g.n_plate, n_sites, s->hopper_warmup, s->hopper_warmup + s->hopper_steps, us, load,
           share, lig_us, ratio);
    fprintf(out, "%zu,%zu,%.6g,%.6g,%.3g,%.6g,%.6g\n", nt, n_sites, load, us, share, lig_us, ratio);
    tl_summary_real(summary, key, ratio);
    fflush(stdout);
  }
  TL_CHECK_GOTO(status, tl_atomic_file_commit(&f), done);
  if (s->hopper_answer && smallest[0]) {
    TlVec3 x[HOPPER_ANSWER_SPHERES], xt[HOPPER_ANSWER_SPHERES], xl[HOPPER_ANSWER_SPHERES], ft;
    for (int i = 0; i < HOPPER_ANSWER_SPHERES; ++i) x[i] = hopper_answer_position(&g0, s->radius, i);
    double us, share, load;
    size_t nt;
    TL_CHECK_GOTO(status, hopper_talus(s, smallest, x, HOPPER_ANSWER_SPHERES, 0, s->hopper_answer_steps, &us, &share,
                                       &load, &nt, xt, &ft), done);
    char deck_path[4600], dump[4600];
    snprintf(deck_path, sizeof deck_path, "%s/in.answer", dir);
    TL_CHECK_GOTO(status, hopper_deck(deck_path, smallest, x, HOPPER_ANSWER_SPHERES, s->radius, s->density, s->youngs,
                                      s->poisson, s->restitution, s->mu, s->dt, 0, s->hopper_answer_steps, 1), done);
    double lig;
    TL_CHECK_GOTO(status, hopper_liggghts(dir, "in.answer", &lig), done);
    snprintf(dump, sizeof dump, "%s/answer.dump", dir);
    TL_CHECK_GOTO(status, hopper_read_dump(dump, xl, HOPPER_ANSWER_SPHERES), done);
    double dx = 0.0, travel = INFINITY;
    for (int i = 0; i < HOPPER_ANSWER_SPHERES; ++i) {
      dx = fmax(dx, tl_v3_norm(tl_v3_sub(xt[i], xl[i])));
      travel = fmin(travel, tl_v3_norm(tl_v3_sub(xt[i], x[i])));
    }
    printf("same answer, %d spheres rolling down the funnel of %s for %ld steps: each travelled at least %.4g m; "
           "positions differ by at most %.3e m (%.2e of the radius); force on the mesh talus (%.9g, %.9g, %.9g) N\n",
           HOPPER_ANSWER_SPHERES, smallest, s->hopper_answer_steps, travel, dx, dx / s->radius, ft.x, ft.y, ft.z);
    tl_summary_real(summary, "hopper_answer_position_diff", dx / s->radius);
    tl_summary_real(summary, "hopper_answer_travel", travel);
  }
done:
  tl_atomic_file_abort(&f);
  tl_free(&path);
  tl_free(&sites);
  tl_surface_mesh_destroy(&mesh);
  return status;
}

static TlStatus run(int argc, char **argv, TlSummary *summary)
{
  double wall0 = tl_wtime();
  TlOptions *o = NULL;
  TL_CHECK(tl_options_create(argc, argv,
                             "Triangulated walls through the hierarchical grid: time per step against the "
                             "triangle count, against brute force, and against LIGGGHTS's mesh walls.",
                             &o));
  Setup s;
  memset(&s, 0, sizeof s);
  long threads;
  TlStatus status = TL_OK;
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-n_particles", 10000, 1, 10000000, "spheres in the scaling scene", &s.n_particles), done);
  TL_CHECK_GOTO(status, tl_options_get_real_list(o, "-triangles", "1e3,1e4,1e5,1e6", "", "triangle counts of the scaling floors (ascending; the first carries the particle patch)", s.triangles, 8, &s.n_sizes), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-steps", 200, 1, 100000000, "timed steps per scaling case", &s.steps), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-warmup", 20, 0, 100000000, "untimed steps before timing", &s.warmup), done);
  TL_CHECK_GOTO(status, tl_options_get_real(o, "-brute_max", 2e8, 0, 1e12, "", "largest particle x triangle count for which brute force is measured", &s.brute_max), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-brute_steps", 3, 1, 1000, "brute-force wall evaluations timed", &s.brute_steps), done);
  TL_CHECK_GOTO(status, tl_options_get_real(o, "-radius", 1e-3, 1e-9, 1e3, "m", "sphere radius", &s.radius), done);
  TL_CHECK_GOTO(status, tl_options_get_real(o, "-density", 2500, 1e-6, 1e6, "kg/m^3", "sphere density", &s.density), done);
  TL_CHECK_GOTO(status, tl_options_get_real(o, "-youngs_modulus", 5e6, 1, 1e13, "Pa", "Young's modulus (Hertz)", &s.youngs), done);
  TL_CHECK_GOTO(status, tl_options_get_real(o, "-poisson_ratio", 0.45, -0.99, 0.499, "", "Poisson ratio", &s.poisson), done);
  TL_CHECK_GOTO(status, tl_options_get_real(o, "-restitution", 0.3, 1e-3, 1, "", "coefficient of restitution", &s.restitution), done);
  TL_CHECK_GOTO(status, tl_options_get_real(o, "-mu", 0.5, 0, 10, "", "friction coefficient", &s.mu), done);
  TL_CHECK_GOTO(status, tl_options_get_real(o, "-dt", 1e-5, 1e-12, 1, "s", "time step", &s.dt), done);
  TL_CHECK_GOTO(status, tl_options_get_bool(o, "-peer", 1, "run the LIGGGHTS mesh-wall scene and its Talus twin", &s.peer), done);
  TL_CHECK_GOTO(status, tl_options_get_bool(o, "-peer_sweep", 0, "also run both over floors of 200, 800, 3200, 12800 triangles", &s.peer_sweep), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-peer_repeat", 3, 1, 100, "LIGGGHTS runs (the median is used)", &threads), done);
  s.peer_repeat = (int)threads;
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-peer_steps", 5000, 1, 100000000, "timed steps of the peer scene (both codes)", &s.peer_steps), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-peer_warmup", 500, 0, 100000000, "warm-up steps of the peer scene (as the LIGGGHTS deck)", &s.peer_warmup), done);
  TL_CHECK_GOTO(status, tl_options_get_real_list(o, "-stl_triangles", "1e3,1e4,1e5,1e6", "", "approximate triangle counts of the STL floors run by both codes (2 n^2 each; empty: skip)", s.stl_triangles, 8, &s.n_stl), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-stl_steps", 1000, 1, 100000000, "timed steps of each STL floor (both codes)", &s.stl_steps), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-stl_repeat", 1, 1, 100, "LIGGGHTS runs per STL floor (the median is used)", &threads), done);
  s.stl_repeat = (int)threads;
  TL_CHECK_GOTO(status, tl_options_get_bool(o, "-stl_answer", 1, "compare forces and heights of spheres resting on the STL floor with LIGGGHTS", &s.stl_answer), done);
  TL_CHECK_GOTO(status, tl_options_get_bool(o, "-stl_floors", 1, "run the STL floors (parts 3 and 4)", &s.stl_floors), done);
  TL_CHECK_GOTO(status, tl_options_get_real_list(o, "-hopper_triangles", "1e3,1e4,1e5,1e6", "", "approximate triangle counts of the STL hoppers run by both codes (part 5)", s.hopper_triangles, 8, &s.n_hopper), done);
  int hopper_on = 1;
  TL_CHECK_GOTO(status, tl_options_get_bool(o, "-hopper", 1, "run the STL hoppers (part 5)", &hopper_on), done);
  if (!hopper_on) s.n_hopper = 0;
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-hopper_particles", 3000, 1, 100000, "spheres poured into the hopper (lattice sites, from the bottom up)", &s.hopper_particles), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-hopper_warmup", 1000, 0, 100000000, "untimed steps of each hopper (both codes)", &s.hopper_warmup), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-hopper_steps", 1000, 1, 100000000, "timed steps of each hopper (both codes)", &s.hopper_steps), done);
  TL_CHECK_GOTO(status, tl_options_get_bool(o, "-hopper_answer", 1, "compare spheres rolling down the smallest hopper with LIGGGHTS", &s.hopper_answer), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-hopper_answer_steps", 5000, 1, 100000000, "steps of the same-answer run", &s.hopper_answer_steps), done);
  TL_CHECK_GOTO(status, tl_options_get_int(o, "-threads", 1, 1, 1024, "OpenMP threads for Talus (LIGGGHTS runs on 1 rank)", &threads), done);
  TL_CHECK_GOTO(status, tl_options_get_string(o, "-output_dir", "results/walls_hgrid", "output folder", &s.output_dir), done);
  status = tl_options_finish(o, stdout);
  if (status != TL_OK) goto done;
  for (int k = 1; k < s.n_sizes; ++k)
    if (!(s.triangles[k] >= s.triangles[k - 1])) {
      status = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "-triangles must ascend: %g after %g", s.triangles[k], s.triangles[k - 1]);
      goto done;
    }
  omp_set_num_threads((int)threads);
  TL_CHECK_GOTO(status, tl_initialize(), done);
  TL_CHECK_GOTO(status, tl_mkdir_p(s.output_dir), done);

  /* ---- 1. scaling ---- */
  ScalingRow rows[8];
  memset(rows, 0, sizeof rows);
  printf("scaling: %ld spheres (r = %g m) on floors of growing triangle count, %ld thread(s), %ld steps each\n",
         s.n_particles, s.radius, threads, s.steps);
  printf("times in us per particle-step, wall clock (CPU time in brackets; the ratios use CPU time, which a shared\n"
         "machine does not inflate)\n");
  printf("%10s %8s %20s %20s %20s %11s %9s\n", "triangles", "floor_m", "whole step", "wall alone", "brute-force wall",
         "brute/talus", "contacts");
  for (int k = 0; k < s.n_sizes; ++k) {
    TL_CHECK_GOTO(status, scaling_case(&s, s.triangles[k], &rows[k]), done);
    ScalingRow *r = &rows[k];
    char step[48], wall[48], brute[48], ratio[32];
    snprintf(step, sizeof step, "%.4f (%.4f)", r->us_step, r->cpu_step);
    snprintf(wall, sizeof wall, "%.4f (%.4f)", r->us_wall, r->cpu_wall);
    if (r->brute_measured) snprintf(brute, sizeof brute, "%.4g (%.4g)", r->us_brute, r->cpu_brute), snprintf(ratio, sizeof ratio, "%.1f", r->brute_ratio);
    else snprintf(brute, sizeof brute, "(skipped)"), snprintf(ratio, sizeof ratio, "-");
    printf("%10.0f %8.3f %20s %20s %20s %11s %9zu\n", r->triangles, r->floor_side, step, wall, brute, ratio,
           r->wall_contacts);
    fflush(stdout);
  }
  double flat = rows[s.n_sizes - 1].cpu_step / rows[0].cpu_step;
  double flat_wall = rows[s.n_sizes - 1].cpu_wall / rows[0].cpu_wall;
  printf("CPU time per step, largest / smallest floor: %.2f (whole step), %.2f (wall alone)\n", flat, flat_wall);
  {
    char *path = NULL;
    TlAtomicFile *f = NULL;
    TL_CHECK_GOTO(status, tl_path_join(s.output_dir, "scaling.csv", &path), done);
    status = tl_atomic_file_open(path, &f);
    tl_free(&path);
    if (status != TL_OK) goto done;
    FILE *out = tl_atomic_file_stream(f);
    fprintf(out, "triangles,floor_m,us_per_particle_step,cpu_us_per_particle_step,wall_us_per_particle,"
                 "wall_cpu_us_per_particle,brute_us_per_particle,brute_cpu_us_per_particle,brute_over_talus_cpu,"
                 "wall_contacts\n");
    for (int k = 0; k < s.n_sizes; ++k)
      fprintf(out, "%.0f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%zu\n", rows[k].triangles, rows[k].floor_side,
              rows[k].us_step, rows[k].cpu_step, rows[k].us_wall, rows[k].cpu_wall,
              rows[k].brute_measured ? rows[k].us_brute : NAN, rows[k].brute_measured ? rows[k].cpu_brute : NAN,
              rows[k].brute_measured ? rows[k].brute_ratio : NAN, rows[k].wall_contacts);
    TL_CHECK_GOTO(status, tl_atomic_file_commit(&f), done);
  }
  tl_summary_real(summary, "flat_step", flat);
  tl_summary_real(summary, "flat_wall", flat_wall);
  double best_brute = 0;
  for (int k = 0; k < s.n_sizes; ++k)
    if (rows[k].brute_measured) best_brute = fmax(best_brute, rows[k].brute_ratio);
  tl_summary_real(summary, "brute_over_talus", best_brute);

  /* ---- 2. the LIGGGHTS scene ---- */
  if (s.peer) {
    char data[4096], stl[4096];
    TL_CHECK_GOTO(status, tl_peer_prepare("mesh_liggghts_rest", data, sizeof data, stl, sizeof stl), done);
    int sides[4] = {40, 10, 20, 80};
    int n_cases = s.peer_sweep ? 4 : 1;
    double ratio40 = NAN, talus40 = NAN, lig40 = NAN, cpu40 = NAN;
    char *path = NULL;
    TlAtomicFile *f = NULL;
    TL_CHECK_GOTO(status, tl_path_join(s.output_dir, "peer.csv", &path), done);
    status = tl_atomic_file_open(path, &f);
    tl_free(&path);
    if (status != TL_OK) goto done;
    FILE *out = tl_atomic_file_stream(f);
    fprintf(out, "triangles,talus_us_per_particle_step,liggghts_us_min,liggghts_us_median,talus_over_liggghts\n");
    for (int c = 0; c < n_cases; ++c) {
      int n = sides[c];
      double us = 0.0, share = 0.0;
      size_t np = 0;
      status = peer_scene_talus(&s, data, n, &us, &share, &np);
      if (status != TL_OK) {
        tl_atomic_file_abort(&f);
        goto done;
      }
      char scene[64];
      if (n == 40) snprintf(scene, sizeof scene, "mesh_liggghts_rest");
      else snprintf(scene, sizeof scene, "mesh_liggghts_ntri=%d", 2 * n * n);
      TlPeerResult peer;
      status = tl_peer_run(scene, 1, s.peer_steps, s.peer_repeat, &peer);
      if (status != TL_OK) {
        tl_atomic_file_abort(&f);
        goto done;
      }
      double ratio = us / peer.us_median;
      printf("peer scene, %d triangles, %zu spheres: talus %.4f us/particle-step (%ld thread(s), cpu_share %.2f), "
             "liggghts %.4f (median; min %.4f), talus/liggghts = %.3f\n",
             2 * n * n, np, us, threads, share, peer.us_median, peer.us_min, ratio);
      fprintf(out, "%d,%.6g,%.6g,%.6g,%.6g\n", 2 * n * n, us, peer.us_min, peer.us_median, ratio);
      if (n == 40) ratio40 = ratio, talus40 = us, lig40 = peer.us_median, cpu40 = us * share;
      fflush(stdout);
    }
    TL_CHECK_GOTO(status, tl_atomic_file_commit(&f), done);
    tl_summary_real(summary, "talus_us", talus40);
    tl_summary_real(summary, "talus_cpu_us", cpu40);
    tl_summary_real(summary, "liggghts_us", lig40);
    tl_summary_real(summary, "ratio", ratio40);
  }
  /* ---- 3. STL floors of growing size, both codes on the same file ---- */
  if (s.stl_floors && s.n_stl > 0) {
    char *path = NULL;
    TlAtomicFile *f = NULL;
    TL_CHECK_GOTO(status, tl_path_join(s.output_dir, "stl.csv", &path), done);
    status = tl_atomic_file_open(path, &f);
    tl_free(&path);
    if (status != TL_OK) goto done;
    FILE *out = tl_atomic_file_stream(f);
    fprintf(out, "triangles,talus_load_s,talus_us_per_particle_step,liggghts_us_min,liggghts_us_median,talus_over_liggghts\n");
    char smallest[4096] = "";
    for (int c = 0; c < s.n_stl; ++c) {
      int n = (int)floor(sqrt(s.stl_triangles[c] / 2.0) + 0.5);
      if (n < 1) n = 1;
      char scene[64], data[4096], stl[4096];
      snprintf(scene, sizeof scene, "mesh_liggghts_ntri=%d", 2 * n * n);
      status = tl_peer_prepare(scene, data, sizeof data, stl, sizeof stl);
      if (status == TL_OK && !stl[0]) status = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "scene %s has no STL file", scene);
      double us = 0.0, share = 0.0, load = 0.0;
      size_t np = 0, nt = 0;
      if (status == TL_OK) status = stl_scene_talus(&s, data, stl, &us, &share, &np, &nt, &load);
      TlPeerResult peer;
      if (status == TL_OK) status = tl_peer_run(scene, 1, s.stl_steps, s.stl_repeat, &peer);
      if (status != TL_OK) {
        tl_atomic_file_abort(&f);
        goto done;
      }
      if (c == 0) snprintf(smallest, sizeof smallest, "%s", stl);
      double ratio = us / peer.us_median;
      printf("STL floor %s: %zu triangles, %zu spheres: talus %.4f us/particle-step (load %.3g s, cpu_share %.2f), "
             "liggghts %.4f (median; min %.4f), talus/liggghts = %.3f\n",
             stl, nt, np, us, load, share, peer.us_median, peer.us_min, ratio);
      fprintf(out, "%zu,%.6g,%.6g,%.6g,%.6g,%.6g\n", nt, load, us, peer.us_min, peer.us_median, ratio);
      char key[48];
      snprintf(key, sizeof key, "stl_ratio_%zu", nt);
      tl_summary_real(summary, key, ratio);
      fflush(stdout);
    }
    TL_CHECK_GOTO(status, tl_atomic_file_commit(&f), done);
    /* ---- 4. the same answer on the smallest floor ---- */
    if (s.stl_answer && smallest[0]) {
      AnswerResult lig = {NAN, NAN, NAN}, tal = {NAN, NAN, NAN};
      TL_CHECK_GOTO(status, answer_liggghts(&s, smallest, &lig), done);
      TL_CHECK_GOTO(status, answer_talus(&s, smallest, &tal), done);
      double m = s.density * 4.0 / 3.0 * TL_PI * pow(s.radius, 3), weight = ANSWER_SPHERES * m * 9.81;
      double delta = resting_overlap(&s);
      double df = fabs(tal.force_z - lig.force_z) / weight;
      double dz = fmax(fabs(tal.z_min - lig.z_min), fabs(tal.z_max - lig.z_max)) / delta;
      printf("same answer, %d spheres resting on %s after %d steps: force on the mesh talus %.9g N, liggghts %.9g N, "
             "weight %.9g N (difference %.2e of the weight); heights talus [%.9g, %.9g] m, liggghts [%.9g, %.9g] m, "
             "Hertz %.9g m (difference %.2e of the overlap %.3g m)\n",
             ANSWER_SPHERES, smallest, ANSWER_STEPS, tal.force_z, lig.force_z, -weight, df, tal.z_min, tal.z_max,
             lig.z_min, lig.z_max, s.radius - delta, dz, delta);
      tl_summary_real(summary, "answer_force_diff", df);
      tl_summary_real(summary, "answer_height_diff", dz);
    }
  }
  /* ---- 5. STL hoppers, both codes on the same file ---- */
  if (s.n_hopper > 0) TL_CHECK_GOTO(status, hoppers(&s, summary), done);
  tl_summary_int(summary, "threads", threads);
  tl_summary_real(summary, "wall", tl_wtime() - wall0);
done:
  tl_options_destroy(&o);
  return status;
}

int main(int argc, char **argv)
{
  TlSummary summary;
  tl_summary_init(&summary);
  TlStatus status = run(argc, argv, &summary);
  if (status == TL_OK) status = tl_summary_print(&summary, stdout);
  return tl_driver_exit(status);
}
