/* The cost of physics: a frictionless scene must be measurably cheaper than
 * a frictional one (DESIGN.md: simulate only what the scene calls for).
 *
 * One state for every measurement: polydisperse spheres settled under a
 * gravity -gravity on a plane floor in a box periodic in x and y (linear law
 * with friction and strong damping), then frozen (velocities and spins zero).
 * Each case builds a fresh world from that state with another contact law
 * and another set of walls and times single steps of it; after each timed
 * step the frozen positions are put back and velocities and spins zeroed
 * (outside the timing), so every law sees exactly the same contacts (a
 * frictionless law would otherwise let the frictional packing slump, and
 * without walls the packing would spring apart):
 *   laws   (i)   linear, frictionless: no rotation, no history
 *          (ii)  linear with Coulomb friction: rotation, 3 history doubles
 *          (iii) Hertz-Mindlin with friction and rolling resistance
 *   walls  none (gravity off),
 *          plane floor, triangulated floor (edge corrections on)
 * with the energy bookkeeping off (it costs a little per contact) and no
 * coarse-graining in the loop; one more row times (ii) with the energy
 * bookkeeping on.  Each case is timed -repeat times, the fastest kept.  The
 * benchmark also reports what each world allocated: rotational arrays and
 * per-contact history must be absent for the frictionless law.
 *
 * Output: <output_dir>/physics_cost.csv (one row per case; law 0
 * frictionless, 1 friction, 2 Hertz-Mindlin with rolling; walls 0 none,
 * 1 plane, 2 triangles); last line
 * summary: ... friction_over_frictionless=... hertz_over_frictionless=... */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_bench.h"
#include "tl_dem.h"
#include "tl_output_dir.h"
#include "tl_timeseries.h"
#include "tl_wall_trisurface.h"

typedef struct {
  long n, steps, repeat, settle_steps;
  int threads;
  double d, E, settle_gravity;
  const char *out;
} Settings;

typedef struct {
  size_t n;
  TlVec3 *x;
  double *radius;
  double box, top;
} Packing;

enum { LAW_FRICTIONLESS, LAW_FRICTION, LAW_HERTZ_ROLLING, N_LAWS };
enum { WALLS_NONE, WALLS_PLANE, WALLS_TRIANGLES, N_WALLS };
static const char *law_name[N_LAWS] = {"linear_frictionless", "linear_friction", "hertz_mindlin_rolling"};
static const char *walls_name[N_WALLS] = {"none", "plane", "triangles"};

static TlStatus make_law(const Settings *s, int kind, TlContactLaw **law)
{
  const TlContactValue lin[] = {{"k_n", s->E * s->d}, {"restitution", 0.3}, {"mu", 0.5}};
  const TlContactSpec frictionless = {"linear", NULL, NULL, NULL, lin, 2};
  const TlContactSpec friction = {"linear", "coulomb", NULL, NULL, lin, 3};
  if (kind == LAW_FRICTIONLESS) return tl_contact_law_build(&frictionless, law);
  if (kind == LAW_FRICTION) return tl_contact_law_build(&friction, law);
  /* Hertz with the same stiffness at 1 % overlap of the mean radius */
  const TlContactValue hz[] = {{"E", s->E}, {"nu", 0.3}, {"gamma_n", 0.0}, {"mu", 0.5}, {"mu_roll", 0.05}};
  const TlContactSpec hertz = {"hertz", "coulomb", "constant", NULL, hz, 5};
  return tl_contact_law_build(&hertz, law);
}

static TlStatus make_world(const Settings *s, const Packing *pk, int law_kind, int walls, int gravity, TlDem **out)
{
  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  TlDomain dom;
  int per[3] = {1, 1, 0};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), tl_v3(pk->box, pk->box, pk->top), per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "grains", 2500, 0.45 * s->d, 0.55 * s->d, &sp));
  TL_CHECK(tl_particles_reserve(P, pk->n));
  for (size_t i = 0; i < pk->n; ++i) TL_CHECK(tl_dem_add_particle(dem, pk->x[i], tl_v3(0, 0, 0), pk->radius[i], sp, NULL));
  TlContactLaw *law = NULL;
  TL_CHECK(make_law(s, law_kind, &law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TlWall *w = NULL;
  if (walls == WALLS_PLANE) {
    TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &w));
    TL_CHECK(tl_dem_add_wall(dem, w, 0));
  } else if (walls == WALLS_TRIANGLES) {
    TlTriSurface *surf = NULL;
    int cells = (int)fmax(1.0, round(pk->box / (2.0 * s->d)));
    TL_CHECK(tl_trisurface_create_rectangle(0, 0, pk->box, pk->box, 0.0, cells, cells, 2, &surf));
    size_t linked = 0;
    TL_CHECK(tl_trisurface_link_periodic(surf, &dom, 1e-9 * pk->box, &linked));
    TL_CHECK(tl_wall_trisurface_create(surf, &w));
    TL_CHECK(tl_dem_add_wall(dem, w, 0));
  }
  if (gravity) tl_dem_set_gravity(dem, tl_v3(0, 0, -s->settle_gravity));
  tl_dem_set_threads(dem, s->threads);
  tl_dem_set_sort_interval(dem, 0); /* indices stay those of the frozen state */
  double dtc, k, m;
  TL_CHECK(tl_dem_critical_timestep(dem, &dtc, &k, &m));
  TL_CHECK(tl_dem_set_timestep(dem, 0.2 * dtc, 0));
  tl_dem_track_energy(dem, 0);
  TL_CHECK(tl_dem_setup(dem));
  *out = dem;
  return TL_OK;
}

/* Jittered lattice just above the floor, settled with friction and damping. */
static TlStatus make_packing(const Settings *s, Packing *pk)
{
  int per_side = (int)ceil(cbrt((double)s->n / 2.0));
  double pitch = 1.12 * s->d;
  pk->box = per_side * pitch;
  int layers = (int)((s->n + (long)per_side * per_side - 1) / ((long)per_side * per_side));
  pk->top = (layers + 2) * pitch;
  TlDem *dem = NULL;
  TL_CHECK(tl_dem_create(&dem));
  TlDomain dom;
  int per[3] = {1, 1, 0};
  TL_CHECK(tl_domain_init_periodic_box(&dom, tl_v3(0, 0, 0), tl_v3(pk->box, pk->box, pk->top), per));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "grains", 2500, 0.45 * s->d, 0.55 * s->d, &sp));
  uint64_t rng = 4242;
  for (long k = 0; k < s->n; ++k) {
    long layer = k / ((long)per_side * per_side), in = k % ((long)per_side * per_side);
    TlVec3 x = {pitch * (0.5 + (double)(in % per_side)) + 0.05 * pitch * (tl_random_uniform(&rng) - 0.5),
                pitch * (0.5 + (double)(in / per_side)) + 0.05 * pitch * (tl_random_uniform(&rng) - 0.5),
                pitch * (0.6 + (double)layer)};
    double r = tl_species_sample_radius(&P->species_table[sp], &rng);
    TL_CHECK(tl_dem_add_particle(dem, x, tl_v3(0, 0, 0), r, sp, NULL));
  }
  const TlContactValue lv[] = {{"k_n", s->E * s->d}, {"restitution", 0.1}, {"mu", 0.5}};
  const TlContactSpec spec = {"linear", "coulomb", NULL, NULL, lv, 3};
  TlContactLaw *law = NULL;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TlWall *w = NULL;
  TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &w));
  TL_CHECK(tl_dem_add_wall(dem, w, 0));
  tl_dem_set_gravity(dem, tl_v3(0, 0, -s->settle_gravity));
  tl_dem_set_threads(dem, s->threads);
  double dtc, k, m;
  TL_CHECK(tl_dem_critical_timestep(dem, &dtc, &k, &m));
  TL_CHECK(tl_dem_set_timestep(dem, 0.2 * dtc, 0));
  tl_dem_track_energy(dem, 1);
  TL_CHECK(tl_dem_setup(dem));
  TlProgress bar;
  long total = s->settle_steps;
  tl_progress_init(&bar, "settling the packing", (double)total);
  for (long q = 0; q < total; q += 200) {
    TL_CHECK(tl_dem_step(dem, 200));
    tl_progress_update(&bar, (double)q);
  }
  tl_progress_finish(&bar);
  TlDemEnergy e;
  TL_CHECK(tl_dem_energy(dem, &e));
  double z;
  TL_CHECK(tl_dem_coordination(dem, &z, NULL));
  pk->n = P->n;
  TL_CHECK(tl_calloc(&pk->x, pk->n, sizeof *pk->x));
  TL_CHECK(tl_calloc(&pk->radius, pk->n, sizeof *pk->radius));
  /* wrapped into the cell, as a world's setup would put them */
  for (size_t i = 0; i < pk->n; ++i) pk->x[i] = tl_domain_wrap(tl_dem_domain(dem), P->x[i]);
  memcpy(pk->radius, P->radius, pk->n * sizeof *pk->radius);
  double top = 0.0;
  for (size_t i = 0; i < pk->n; ++i) top = fmax(top, pk->x[i].z + pk->radius[i]);
  pk->top = top + 2.0 * s->d;
  printf("packing: %zu spheres settled in %ld steps, kinetic %.3g J (potential scale %.3g J), coordination %.2f, bed %.4g m\n",
         pk->n, total, e.kinetic_translational + e.kinetic_rotational, fabs(e.gravitational), z, top);
  tl_dem_destroy(&dem);
  return TL_OK;
}

typedef struct {
  double seconds_per_step;
  size_t contacts;
  int rotation, history;
} Result;

static TlStatus measure(const Settings *s, const Packing *pk, int law, int walls, int energy, Result *res)
{
  double best = INFINITY;
  for (long r = 0; r < s->repeat; ++r) {
    TlDem *dem = NULL;
    TL_CHECK(make_world(s, pk, law, walls, walls != WALLS_NONE, &dem));
    tl_dem_track_energy(dem, energy);
    TlParticles *P = tl_dem_particles(dem);
    double t = 0.0;
    for (long k = -20; k < s->steps; ++k) { /* 20 warm-up steps: buffers at their working size */
      double t0 = tl_wtime();
      TL_CHECK(tl_dem_step(dem, 1));
      if (k >= 0) t += tl_wtime() - t0;
      /* back to the frozen state (particles are never renumbered: no rebuild) */
      memcpy(P->x, pk->x, pk->n * sizeof *P->x);
      memset(P->v, 0, pk->n * sizeof *P->v);
      if (P->w) memset(P->w, 0, pk->n * sizeof *P->w);
    }
    t /= (double)s->steps;
    best = fmin(best, t);
    TlDemStats st;
    tl_dem_stats(dem, &st);
    if (st.rebuilds != 1)
      TL_ERROR(TL_ERR_STATE, "the frozen state was rebuilt %ld times while timed; the cases would not compare", st.rebuilds - 1);
    res->contacts = st.n_contacts;
    for (size_t k = 0; k < tl_dem_n_walls(dem); ++k) res->contacts += tl_dem_wall(dem, k)->n_contacts;
    res->rotation = P->w != NULL || P->q != NULL || P->torque != NULL || P->inv_inertia != NULL;
    TlContactLaw *l = NULL;
    TL_CHECK(make_law(s, law, &l));
    res->history = (int)l->history_doubles;
    tl_contact_law_destroy(&l);
    tl_dem_destroy(&dem);
  }
  res->seconds_per_step = best;
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  double wall0 = tl_wtime();
  TlOptions *o = NULL;
  Settings s;
  TL_CHECK(tl_options_create(argc, argv,
                             "Time per step of one settled packing with a frictionless, a frictional and a "
                             "Hertz-Mindlin law with rolling resistance, without walls, on a plane and on a "
                             "triangulated floor.",
                             &o));
  TL_CHECK(tl_options_get_int(o, "-n", 2000, 8, 10000000, "number of particles", &s.n));
  TL_CHECK(tl_options_get_int(o, "-steps", 400, 1, 100000000, "timed steps per case", &s.steps));
  TL_CHECK(tl_options_get_int(o, "-repeat", 3, 1, 1000, "timings per case (the fastest is kept)", &s.repeat));
  TL_CHECK(tl_options_get_int(o, "-settle_steps", 60000, 0, 100000000, "steps settling the packing", &s.settle_steps));
  long th;
  TL_CHECK(tl_options_get_int(o, "-threads", 1, 1, 1024, "OpenMP threads", &th));
  s.threads = (int)th;
  TL_CHECK(tl_options_get_real(o, "-d", 1e-3, 1e-9, 1e3, "m", "mean diameter (uniform in [0.9, 1.1] d)", &s.d));
  TL_CHECK(tl_options_get_real(o, "-E", 1e7, 1.0, 1e12, "Pa", "modulus: k_n = E d, Hertz Young's modulus E", &s.E));
  TL_CHECK(tl_options_get_real(o, "-gravity", 100.0, 0.0, 1e6, "m/s^2",
                               "gravity of the packing and of the cases with walls (strong: overlaps well above round-off)",
                               &s.settle_gravity));
  TL_CHECK(tl_options_get_string(o, "-output_dir", "results/dem_physics_cost", "output folder", &s.out));
  TlStatus st = tl_options_finish(o, stdout);
  if (st != TL_OK) {
    tl_options_destroy(&o);
    return st;
  }
  Packing pk;
  memset(&pk, 0, sizeof pk);
  TL_CHECK(make_packing(&s, &pk));
  TL_CHECK(tl_mkdir_p(s.out));
  char base[4200];
  snprintf(base, sizeof base, "%s/physics_cost", s.out);
  static const TlColumn cols[] = {{"law", ""},
                                  {"walls", ""},
                                  {"energy_tracking", ""},
                                  {"seconds_per_step", "s"},
                                  {"ns_per_particle_step", "ns"},
                                  {"contacts", ""},
                                  {"rotation_allocated", ""},
                                  {"history_doubles", ""}};
  TlTimeSeries *ts = NULL;
  TL_CHECK(tl_timeseries_create(base, TL_TIMESERIES_CSV, sizeof cols / sizeof cols[0], cols, &ts));
  Result res[N_LAWS][N_WALLS];
  printf("%-22s %-10s %14s %12s %9s %9s %8s\n", "law", "walls", "s/step", "ns/(p step)", "contacts", "rotation",
         "history");
  for (int l = 0; l < N_LAWS; ++l)
    for (int w = 0; w < N_WALLS; ++w) {
      Result *r = &res[l][w];
      TL_CHECK(measure(&s, &pk, l, w, 0, r));
      double ns = 1e9 * r->seconds_per_step / (double)pk.n;
      printf("%-22s %-10s %14.4e %12.1f %9zu %9s %8d\n", law_name[l], walls_name[w], r->seconds_per_step, ns,
             r->contacts, r->rotation ? "yes" : "no", r->history);
      double row[] = {l, w, 0, r->seconds_per_step, ns, (double)r->contacts, r->rotation, r->history};
      TL_CHECK(tl_timeseries_append(ts, row));
    }
  Result en;
  TL_CHECK(measure(&s, &pk, LAW_FRICTION, WALLS_PLANE, 1, &en));
  double ns_en = 1e9 * en.seconds_per_step / (double)pk.n;
  printf("%-22s %-10s %14.4e %12.1f %9zu %9s %8d  (energy bookkeeping on)\n", law_name[LAW_FRICTION], "plane",
         en.seconds_per_step, ns_en, en.contacts, en.rotation ? "yes" : "no", en.history);
  double row[] = {LAW_FRICTION, WALLS_PLANE, 1, en.seconds_per_step, ns_en, (double)en.contacts, en.rotation, en.history};
  TL_CHECK(tl_timeseries_append(ts, row));
  TL_CHECK(tl_timeseries_close(&ts));
  double f0 = res[LAW_FRICTIONLESS][WALLS_NONE].seconds_per_step;
  double friction = res[LAW_FRICTION][WALLS_NONE].seconds_per_step / f0;
  double hertz = res[LAW_HERTZ_ROLLING][WALLS_NONE].seconds_per_step / f0;
  double plane = res[LAW_FRICTION][WALLS_PLANE].seconds_per_step / res[LAW_FRICTION][WALLS_NONE].seconds_per_step;
  double tri = res[LAW_FRICTION][WALLS_TRIANGLES].seconds_per_step / res[LAW_FRICTION][WALLS_NONE].seconds_per_step;
  double energy = en.seconds_per_step / res[LAW_FRICTION][WALLS_PLANE].seconds_per_step;
  int lean = !res[LAW_FRICTIONLESS][WALLS_NONE].rotation && res[LAW_FRICTIONLESS][WALLS_NONE].history == 0;
  printf("friction/frictionless %.3f, hertz+rolling/frictionless %.3f, plane floor/no walls %.3f, "
         "triangulated floor/no walls %.3f, energy bookkeeping on/off %.3f; frictionless world allocates %s\n",
         friction, hertz, plane, tri, energy, lean ? "no rotational state and no history" : "rotation or history (unexpected)");
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "n", (long)pk.n);
  tl_summary_int(&sum, "threads", s.threads);
  tl_summary_real(&sum, "frictionless_ns", 1e9 * f0 / (double)pk.n);
  tl_summary_real(&sum, "friction_over_frictionless", friction);
  tl_summary_real(&sum, "hertz_over_frictionless", hertz);
  tl_summary_real(&sum, "plane_over_none", plane);
  tl_summary_real(&sum, "triangles_over_none", tri);
  tl_summary_real(&sum, "energy_on_over_off", energy);
  tl_summary_int(&sum, "frictionless_lean", lean);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  TlStatus s_sum = tl_summary_print(&sum, stdout);
  tl_free(&pk.x);
  tl_free(&pk.radius);
  tl_options_destroy(&o);
  return s_sum;
}

int main(int argc, char **argv) { return tl_bench_main(argc, argv, run); }
