/* Polydisperse spheres poured into a box and settled under gravity: the
 * floor is a triangulated surface (squares split into four triangles around
 * their centres, as Cheng et al. 2022 represents quadrilateral faces) and the four
 * sides are infinite planes.  Particles are inserted on a jittered lattice in
 * the upper part of the box with small random velocities and fall.
 *
 * Material (Voisin-Leprince et al. 2023 Table 1 where it applies): density 2500 kg/m^3,
 * diameters uniform in [2.5, 3.5] mm, friction 0.5; the linear normal
 * stiffness follows the coupling paper's k_n = E d with a soft E = 10 MPa
 * (stated in -help) so that settling takes a fraction of a second;
 * restitution 0.5.  Time step 0.2 of the critical one.
 *
 * Output in -output_dir: energies.csv/.h5 (every energy term, momentum,
 * coordination), particles_*.h5 + particles.xmf and walls_*.h5 + walls.xmf
 * (the floor and the four sides, drawn over the box; ParaView).  At the end the
 * vertical force on the walls is compared with the weight of the packing
 * (a settled packing carries its weight on the walls).  Last line:
 * summary: n=... kinetic_final=... weight_balance=... wall=...
 *
 * Restart: -checkpoint_every n writes <output_dir>/checkpoint.h5 every n
 * steps (the whole DEM world, the energy table, the snapshot series and the
 * driver's counters); -restart <file> rebuilds the scene from the same
 * options, loads the file and continues bit for bit (restart in the same
 * -output_dir to keep one table and one snapshot series); -stop_step n ends
 * the run early after step n (to make a checkpoint to restart from). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_options_checkpoint.h"
#include "tl_options_renamed.h"
#include "tl_series_sweep.h"
#include "tl_plot_hint.h"
#include "tl_atomic_file.h"
#include "tl_dem.h"
#include "tl_particle_snapshot.h"
#include "tl_timeseries.h"
#include "tl_wall_trisurface.h"

typedef struct {
  long n;
  double d_min, d_max, density, E, box, height, t_end, dt_fraction, energy_tolerance, snapshot_dt, walls_stl_scale;
  long samples, floor_cells, checkpoint_every, stop_step;
  int threads, plane_floor;
  const char *out, *restart, *particles, *walls_stl;
  TlContactLaw *law;
} Settings;

static TlStatus options(int argc, char **argv, TlOptions **o, Settings *s)
{
  s->law = NULL;
  TL_CHECK(tl_options_create(argc, argv,
                             "Polydisperse spheres poured into a box and settled on a triangulated floor and plane "
                             "side walls; energies, coordination and the weight carried by the walls.  Material after " TL_PAPER_VOISIN_LEPRINCE_2023 ".",
                             o));
  static const TlRenamedOption renamed[] = {
      {"-snapshots", "-snapshot_dt", "snapshots are now every -snapshot_dt seconds, as in every time-stepping driver"},
      {"-samples", "-table_rows", "table cadence: -table_dt seconds, -table_every steps, -table_rows a count"}};
  TL_CHECK(tl_options_refuse_renamed(*o, renamed, (int)(sizeof renamed / sizeof renamed[0])));
  TL_CHECK(tl_options_get_int(*o, "-n", 1500, 1, 100000000, "number of particles", &s->n));
  TL_CHECK(tl_options_get_real(*o, "-d_min", 2.5e-3, 1e-9, 1e3, "m", "smallest diameter (Voisin-Leprince et al. 2023 Table 1)", &s->d_min));
  TL_CHECK(tl_options_get_real(*o, "-d_max", 3.5e-3, 1e-9, 1e3, "m", "largest diameter (Voisin-Leprince et al. 2023 Table 1)", &s->d_max));
  TL_CHECK(tl_options_get_real(*o, "-density", 2500, 1e-6, 1e6, "kg/m^3", "grain density (Voisin-Leprince et al. 2023 Table 1)", &s->density));
  TL_CHECK(tl_options_get_real(*o, "-E", 1e7, 1.0, 1e12, "Pa",
                               "modulus giving the linear stiffness k_n = E d_mean (soft, so that settling is quick)", &s->E));
  /* linear spring-dashpot k_n = E d_mean, restitution 0.5, Coulomb mu = 0.5
   * (Voisin-Leprince et al. 2023 Table 1); -contact_* override */
  const TlContactValue law_values[] = {
      {"k_n", s->E * 0.5 * (s->d_min + s->d_max)}, {"restitution", 0.5}, {"mu", 0.5}};
  const TlContactSpec law_spec = {"linear", "coulomb", NULL, NULL, law_values, 3};
  TL_CHECK(tl_contact_law_from_options(*o, &law_spec, &s->law));
  TL_CHECK(tl_options_get_real(*o, "-box", 0.04, 1e-6, 1e3, "m", "box width (x and y)", &s->box));
  TL_CHECK(tl_options_get_real(*o, "-height", 0.12, 1e-6, 1e3, "m", "box height", &s->height));
  TL_CHECK(tl_options_get_real(*o, "-t_end", 0.4, 0.0, 1e6, "s", "simulated time", &s->t_end));
  TL_CHECK(tl_options_get_real(*o, "-dt_fraction", 0.2, 1e-6, 10.0, "", "time step over the critical time step (> 1 is refused)", &s->dt_fraction));
  TL_CHECK(tl_options_get_real(*o, "-energy_tolerance", 0.05, 1e-12, 1.0, "",
                               "stop with a diagnosis when |E_total - E_0| exceeds this fraction of |E_0| (E_total "
                               "counts the dissipated energy: it is conserved by an accurate run)",
                               &s->energy_tolerance));
  TL_CHECK(tl_options_get_real(*o, "-snapshot_dt", 0.04, 0.0, 1e6, "s",
                               "particle snapshots at t = 0, dt, 2 dt, ... and at -t_end (0: none)", &s->snapshot_dt));
  if (s->snapshot_dt > 0.0 && !(s->t_end / s->snapshot_dt <= 100000.0))
    TL_ERROR(TL_ERR_ARG, "-snapshot_dt %g s makes %.3g snapshots of -t_end %g s, beyond the limit 100000: at least "
             "-snapshot_dt %g s", s->snapshot_dt, s->t_end / s->snapshot_dt, s->t_end, s->t_end / 100000.0);
  TL_CHECK(tl_options_get_int(*o, "-table_rows", 400, 1, 10000000, "rows of the energy table", &s->samples));
  TL_CHECK(tl_options_get_int(*o, "-floor_cells", 8, 1, 10000, "floor squares per side (4 triangles each)", &s->floor_cells));
  TL_CHECK(tl_options_get_bool(*o, "-plane_floor", 0, "use an infinite plane as floor instead of triangles", &s->plane_floor));
  long th;
  TL_CHECK(tl_options_get_int(*o, "-threads", 0, 0, 1024, "OpenMP threads (0: default)", &th));
  s->threads = (int)th;
  TL_CHECK(tl_options_get_string(*o, "-output_dir", "results/settle", "output folder", &s->out));
  TL_CHECK(tl_output_dir_check(s->out));
  TL_CHECK(tl_options_get_int(*o, "-checkpoint_every", 0, 0, 1000000000,
                              "write <output_dir>/checkpoint.h5 every n steps (0: never)", &s->checkpoint_every));
  TL_CHECK(tl_options_get_string(*o, "-restart", "", "continue from this checkpoint file (same options)", &s->restart));
  TL_CHECK(tl_options_get_string(*o, "-particles", "",
                                 "start from the particles of this file instead of the pour: a LAMMPS data file "
                                 "(atom_style sphere) or a Talus particle snapshot (.h5), each particle of species "
                                 "grains (-n is then the file's count)",
                                 &s->particles));
  TL_CHECK(tl_options_get_string(*o, "-walls_stl", "",
                                 "add the triangulated wall of this STL or Gmsh surface file (repaired: duplicate "
                                 "points merged, degenerate facets removed, orientation made consistent) beside the "
                                 "floor and the side planes",
                                 &s->walls_stl));
  TL_CHECK(tl_options_get_real(*o, "-walls_stl_scale", 1.0, 1e-12, 1e12, "",
                               "scale of the -walls_stl file's coordinates to metres (1e-3: a file in mm)",
                               &s->walls_stl_scale));
  TL_CHECK(tl_options_get_int(*o, "-stop_step", 0, 0, 1000000000, "stop after this step (0: run to -t_end)",
                              &s->stop_step));
  return tl_options_finish(*o, stdout);
}

/* The driver's own counters, checkpointed with the run. */
typedef struct {
  int64_t next_step; /* the loop step the run continues with */
  double e0;         /* total energy at the start */
} Progress;

static TlStatus progress_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const Progress *p = object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "next_step", p->next_step));
  TL_CHECK(tl_checkpoint_write_double(w, group, "initial_energy", p->e0));
  return TL_OK;
}

static TlStatus progress_load(void *object, TlCheckpointReader *r, const char *group)
{
  Progress *p = object;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "next_step", &p->next_step));
  TL_CHECK(tl_checkpoint_read_double(r, group, "initial_energy", &p->e0));
  return TL_OK;
}

static const TlCheckpointOps progress_checkpoint_ops = {
    .header = {"checkpoint", "settle_progress_v1", "loop step and initial energy of the settle driver"},
    .save = progress_save,
    .load = progress_load,
};

/* The sizes a run needs, checked before anything is allocated. */
static TlStatus check_sizes(const Settings *s)
{
  if (s->d_max < s->d_min) TL_ERROR(TL_ERR_ARG, "-d_max %g is smaller than -d_min %g", s->d_max, s->d_min);
  if (s->particles[0]) return TL_OK; /* no pour: the file's particles are checked once read */
  const double pitch = 1.05 * s->d_max; /* the pour lattice's */
  const double sites = floor((s->box - pitch) / pitch);
  if (!(sites >= 1.0)) TL_ERROR(TL_ERR_ARG, "-box %g is too narrow for particles of diameter %g", s->box, s->d_max);
  const int per_side = (int)sites;
  /* A box wider than the particles can fill makes no bed: its packing
   * fraction and coordination would describe scattered grains. */
  if ((double)s->n < (double)per_side * per_side)
    TL_ERROR(TL_ERR_ARG,
             "-box %g m: %ld particles fill %.2g of one layer of the pour lattice (%d x %d sites of pitch %g m), "
             "so they make no bed: -box must be below %.4g m for -n %ld", s->box, s->n,
             (double)s->n / ((double)per_side * per_side), per_side, per_side, pitch, pitch * (floor(sqrt((double)s->n)) + 2.0), s->n);
  /* 4 triangles per floor cell, each binned and tested: refuse a floor
   * that cannot be built in memory before allocating it. */
  const double max_floor_triangles = 1e6;
  if (!s->plane_floor && !(4.0 * (double)s->floor_cells * (double)s->floor_cells <= max_floor_triangles))
    TL_ERROR(TL_ERR_ARG, "-floor_cells %ld makes 4 x %ld^2 = %.3g floor triangles, beyond the limit %.0e: at most -floor_cells %d",
             s->floor_cells, s->floor_cells, 4.0 * (double)s->floor_cells * (double)s->floor_cells, max_floor_triangles,
             (int)floor(sqrt(max_floor_triangles / 4.0)));
  long layers = (s->n + (long)per_side * per_side - 1) / ((long)per_side * per_side);
  if (layers * pitch > s->height - pitch)
    TL_ERROR(TL_ERR_ARG, "%ld particles need %ld layers of %g m: more than the box height %g allows", s->n, layers, pitch,
             s->height);
  return TL_OK;
}

/* The loop step of snapshot j, or -1 past the last: snapshots at t = 0,
 * dt_s, 2 dt_s, ... up to -t_end on the step grid, and one at -t_end when it
 * is not on the dt_s grid, so -t_end 0.1 -snapshot_dt 0.01 writes 11. */
static long snapshot_step(const Settings *s, double dt, long steps, long j)
{
  if (!(s->snapshot_dt > 0.0) || j < 0) return -1;
  const long on_grid = (long)floor(s->t_end / s->snapshot_dt * (1.0 + 1e-12)); /* last j with j dt_s <= t_end */
  if (j <= on_grid) {
    if (s->t_end - (double)j * s->snapshot_dt < dt) return steps; /* -t_end on the grid: its last step */
    long k = lround((double)j * s->snapshot_dt / dt);
    return k < steps ? k : steps;
  }
  if (j == on_grid + 1 && snapshot_step(s, dt, steps, on_grid) < steps) return steps;
  return -1;
}

static TlStatus run(int argc, char **argv)
{
  double wall0 = tl_wtime();
  TlOptions *o = NULL;
  Settings s;
  TlStatus st = options(argc, argv, &o, &s);
  if (st == TL_OK) st = check_sizes(&s);
  if (st != TL_OK) {
    tl_contact_law_destroy(&s.law);
    tl_options_destroy(&o);
    return st;
  }
  /* every exit after this point goes through done: nothing leaks on a refusal */
  TlDem *dem = NULL;
  TlParticleWriter *writer = NULL;
  TlWallWriter *walls = NULL;
  TlTimeSeries *ts = NULL;
  TlCheckpoint *cp = NULL;
  TL_CHECK_GOTO(st, tl_dem_create(&dem), done);
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  TL_CHECK_GOTO(st, tl_domain_init_open(&dom, tl_v3(0, 0, 0), tl_v3(s.box, s.box, s.height)), done);
  TL_CHECK_GOTO(st, tl_dem_set_domain(dem, &dom), done);
  int sp;
  TL_CHECK_GOTO(st, tl_particles_add_species(P, "grains", s.density, 0.5 * s.d_min, 0.5 * s.d_max, &sp), done);
  if (s.particles[0]) {
    size_t added = 0;
    TL_CHECK_GOTO(st, tl_dem_add_particles_from_file(dem, s.particles, sp, &added), done);
    for (size_t i = 0; i < P->n; ++i) {
      TlVec3 x = P->x[i];
      double r = P->radius[i];
      if (!(x.x - r >= 0 && x.x + r <= s.box && x.y - r >= 0 && x.y + r <= s.box && x.z - r >= 0 && x.z + r <= s.height)) {
        st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                          "-particles %s: particle %zu at (%g, %g, %g) m, radius %g m, is not inside the box "
                          "[0, %g] x [0, %g] x [0, %g] m (-box, -height)",
                          s.particles, i + 1, x.x, x.y, x.z, r, s.box, s.box, s.height);
        goto done;
      }
    }
    s.n = (long)P->n;
    tl_printf("%zu particles from %s\n", added, s.particles);
  }
  /* pour: jittered lattice of pitch d_max * 1.05 from the top down */
  const double pitch = 1.05 * s.d_max;
  const int per_side = (int)floor((s.box - pitch) / pitch);
  uint64_t rng = 12345;
  TL_CHECK_GOTO(st, tl_particles_reserve(P, (size_t)s.n), done);
  for (long k = 0; k < s.n && !s.particles[0]; ++k) {
    long layer = k / ((long)per_side * per_side), in = k % ((long)per_side * per_side);
    double jx = 0.02 * pitch * (tl_random_uniform(&rng) - 0.5), jy = 0.02 * pitch * (tl_random_uniform(&rng) - 0.5);
    TlVec3 x = {pitch * (1.0 + (double)(in % per_side)) + jx, pitch * (1.0 + (double)(in / per_side)) + jy,
                s.height - pitch * (1.0 + (double)layer)};
    TlVec3 v = {0.05 * (tl_random_uniform(&rng) - 0.5), 0.05 * (tl_random_uniform(&rng) - 0.5), 0.0};
    double r = tl_species_sample_radius(&P->species_table[sp], &rng);
    TL_CHECK_GOTO(st, tl_dem_add_particle(dem, x, v, r, sp, NULL), done);
  }
  double k_n;
  TL_CHECK_GOTO(st, tl_contact_law_get(s.law, "k_n", &k_n), done);
  TL_CHECK_GOTO(st, tl_dem_add_law(dem, s.law, NULL), done);
  s.law = NULL; /* the world owns it */
  /* walls: triangulated floor, four planes */
  TlWall *w;
  if (s.plane_floor) {
    TL_CHECK_GOTO(st, tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &w), done);
  } else {
    TlTriSurface *floor_;
    TL_CHECK_GOTO(st, tl_trisurface_create_rectangle(0, 0, s.box, s.box, 0.0, (int)s.floor_cells, (int)s.floor_cells, 2, &floor_), done);
    TL_CHECK_GOTO(st, tl_wall_trisurface_create(floor_, &w), done);
  }
  TL_CHECK_GOTO(st, tl_dem_add_wall(dem, w, 0), done);
  const TlVec3 pts[4] = {{0, 0, 0}, {s.box, 0, 0}, {0, 0, 0}, {0, s.box, 0}};
  const TlVec3 nrm[4] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  for (int k = 0; k < 4; ++k) {
    TL_CHECK_GOTO(st, tl_wall_plane_create(pts[k], nrm[k], &w), done);
    TL_CHECK_GOTO(st, tl_dem_add_wall(dem, w, 0), done);
  }
  if (s.walls_stl[0]) {
    TlWallPlacement place;
    tl_wall_placement_default(&place);
    place.scale = s.walls_stl_scale;
    TlSurfaceReport report;
    TL_CHECK_GOTO(st, tl_wall_trisurface_from_file(s.walls_stl, &place, &w, &report), done);
    TL_CHECK_GOTO(st, tl_dem_add_wall(dem, w, 0), done);
    tl_printf("wall from %s: %zu triangles (repair: %zu points merged, %zu triangles removed, %zu flipped)\n",
              s.walls_stl, tl_wall_trisurface_surface(w)->n_triangles, report.vertices_merged, report.triangles_removed,
              report.triangles_flipped);
  }
  const double g = 9.81;
  tl_dem_set_gravity(dem, tl_v3(0, 0, -g));
  tl_dem_set_threads(dem, s.threads);
  double dtc, kmax, mmin;
  TL_CHECK_GOTO(st, tl_dem_critical_timestep(dem, &dtc, &kmax, &mmin), done);
  double dt = s.dt_fraction * dtc;
  TL_CHECK_GOTO(st, tl_dem_set_timestep(dem, dt, 0), done);
  TL_CHECK_GOTO(st, tl_dem_setup(dem), done);
  long steps = (long)ceil(s.t_end / dt);
  tl_printf("settle: %ld particles, d in [%g, %g] m, k_n = %g N/m, dt = %g s (%.2g dt_c), %ld steps, floor %s\n", s.n,
            s.d_min, s.d_max, k_n, dt, s.dt_fraction, steps, s.plane_floor ? "plane" : "triangulated");
  /* output */
  TL_CHECK_GOTO(st, tl_output_dir_prepare(s.out), done);
  if (!(s.snapshot_dt > 0.0) && !s.restart[0]) { /* a rerun with snapshots off: the earlier run's series would pass for this one's */
    size_t removed;
    TL_CHECK_GOTO(st, tl_series_sweep_whole(s.out, "particles", &removed), done);
    TL_CHECK_GOTO(st, tl_series_sweep_whole(s.out, "walls", &removed), done);
  }
  char base[4096];
  snprintf(base, sizeof base, "%s/energies", s.out);
  TL_CHECK_GOTO(st, tl_particle_writer_create(s.out, "particles", &writer), done);
  TL_CHECK_GOTO(st, tl_wall_writer_create(s.out, "walls", &walls), done);
  static const TlColumn cols[] = {{"time", "s"},          {"kinetic", "J"},        {"rotational", "J"},
                                  {"elastic", "J"},       {"gravitational", "J"},  {"dissipated", "J"},
                                  {"work_external", "J"}, {"total", "J"},          {"momentum_z", "kg m/s"},
                                  {"coordination", ""},   {"wall_force_z", "N"}};
  TL_CHECK_GOTO(st, tl_timeseries_create(base, TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, sizeof cols / sizeof cols[0], cols, &ts), done);
  TL_CHECK_GOTO(st, tl_timeseries_reserve(ts, (size_t)s.samples + 2), done);
  long every = steps / s.samples > 0 ? steps / s.samples : 1;
  TlProgress prog;
  tl_progress_init(&prog, "settle", (double)steps);
  double weight = 0.0;
  for (size_t i = 0; i < P->n; ++i) weight += P->mass[i] * g;
  TlDemEnergy en;
  double wall_fz = 0.0;
  Progress pr = {0, 0.0};
  char cp_path[4200];
  snprintf(cp_path, sizeof cp_path, "%s/checkpoint.h5", s.out);
  TL_CHECK_GOTO(st, tl_checkpoint_create(&cp), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, o), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "energies", &tl_timeseries_checkpoint_ops, ts), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "snapshots", &tl_particle_writer_checkpoint_ops, writer), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "wall_snapshots", &tl_wall_writer_checkpoint_ops, walls), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "driver", &progress_checkpoint_ops, &pr), done);
  if (s.restart && s.restart[0]) {
    TL_CHECK_GOTO(st, tl_checkpoint_load(cp, s.restart, NULL, NULL), done);
    tl_printf("restarted from %s at step %lld, t = %.9g s\n", s.restart, (long long)pr.next_step, tl_dem_time(dem));
    weight = 0.0;
    for (size_t i = 0; i < P->n; ++i) weight += P->mass[i] * g;
  }
  long last = s.stop_step > 0 && s.stop_step < steps ? s.stop_step : steps;
  long next_snap = 0, snap_k; /* the next snapshot's index and its step */
  while ((snap_k = snapshot_step(&s, dt, steps, next_snap)) >= 0 && snap_k < (long)pr.next_step) next_snap++;
  for (long k = (long)pr.next_step; k <= steps; ++k) {
    if (k % every == 0 || k == steps) {
      TL_CHECK_GOTO(st, tl_dem_energy(dem, &en), done);
      if (k == 0) pr.e0 = en.total;
      double z;
      TL_CHECK_GOTO(st, tl_dem_coordination(dem, &z, NULL), done);
      wall_fz = 0.0;
      for (size_t q = 0; q < tl_dem_n_walls(dem); ++q) wall_fz += tl_dem_wall(dem, q)->force.z;
      double row[] = {tl_dem_time(dem), en.kinetic_translational, en.kinetic_rotational, en.elastic, en.gravitational,
                      en.dissipated, en.work_external, en.total, en.momentum.z, z, wall_fz};
      TL_CHECK_GOTO(st, tl_timeseries_append(ts, row), done);
      double balance_error = fabs(en.total - pr.e0) / fmax(fabs(pr.e0), 1e-300);
      if (!(balance_error <= s.energy_tolerance)) {
        TlStatus lost = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__,
                                   "energy balance lost at t = %.6g s (step %ld): |E_total - E_0| = %.3g of |E_0|, "
                                   "beyond -energy_tolerance %g; the time step (-dt_fraction %g of the critical "
                                   "step) is too large for the contacts, or the run is unstable",
                                   tl_dem_time(dem), k, balance_error, s.energy_tolerance, s.dt_fraction);
        st = lost;
        goto done;
      }
    }
    if (snapshot_step(&s, dt, steps, next_snap) == k) {
      TlParticleView view;
      tl_particle_view_of(P, &view); /* with ids and species */
      TL_CHECK_GOTO(st, tl_particle_writer_write(writer, k, tl_dem_time(dem), &view), done);
      TL_CHECK_GOTO(st, tl_wall_writer_write_dem(walls, k, dem), done);
      while (snapshot_step(&s, dt, steps, next_snap) == k) next_snap++; /* -snapshot_dt below dt: one per step */
    }
    if (k == steps || k == last) break;
    TL_CHECK_GOTO(st, tl_dem_step(dem, 1), done);
    pr.next_step = k + 1;
    if (s.checkpoint_every > 0 && pr.next_step % s.checkpoint_every == 0)
      TL_CHECK_GOTO(st, tl_checkpoint_save(cp, cp_path, tl_dem_time(dem), pr.next_step), done);
    if (k % 200 == 0) tl_progress_update(&prog, (double)k);
  }
  tl_progress_finish(&prog);
  tl_checkpoint_destroy(&cp);
  TL_CHECK_GOTO(st, tl_timeseries_close(&ts), done);
  tl_particle_writer_destroy(&writer);
  /* results */
  TL_CHECK_GOTO(st, tl_dem_energy(dem, &en), done);
  double z, znr, imbalance;
  TL_CHECK_GOTO(st, tl_dem_coordination(dem, &z, &znr), done);
  TL_CHECK_GOTO(st, tl_dem_max_force_imbalance(dem, &imbalance), done);
  double top = 0.0, vol = 0.0;
  for (size_t i = 0; i < P->n; ++i) {
    top = fmax(top, P->x[i].z + P->radius[i]);
    vol += 4.0 / 3.0 * TL_PI * pow(P->radius[i], 3);
  }
  /* the walls push up on the particles: their reactions are -force (+ 0.0:
   * no "-0.0000" when nothing touches them) */
  double balance = -wall_fz / weight + 0.0;
  double energy_error = (en.total - pr.e0) / fmax(fabs(pr.e0), 1e-300);
  /* Settled: the walls carry the weight (within 5 %) and the grains are at
   * rest (kinetic energy below 1e-3 of lifting the packing by one mean
   * diameter).  Otherwise coordination, wall load and packing fraction
   * describe grains still falling, and the run says so. */
  const double ke = en.kinetic_translational + en.kinetic_rotational;
  const double ke_scale = weight * 0.5 * (s.d_min + s.d_max);
  const int settled = fabs(balance - 1.0) <= 0.05 && ke <= 1e-3 * ke_scale;
  const double t_now = tl_dem_time(dem);
  if (settled) {
    tl_printf("settled: kinetic %.3e J, elastic %.3e J, dissipated %.3e J, coordination %.2f (%.2f without rattlers)\n",
              ke, en.elastic, en.dissipated, z, znr);
    tl_printf("walls carry %.4f of the weight; bed height %.4g m, packing fraction %.3f; energy balance error %.2e\n",
              balance, top, vol / (s.box * s.box * top), energy_error);
  } else {
    tl_printf("not settled at t = %.4g s: the walls carry %.4f of the weight (settled: 1 within 0.05), kinetic energy "
              "%.3e J is %.3g of the weight times the mean diameter (settled: below 1e-3); the coordination %.2f and "
              "packing fraction %.3f are of grains still moving: run longer (-t_end)\n",
              t_now, balance, ke, ke / ke_scale, z, vol / (s.box * s.box * top));
    tl_printf("energy balance error %.2e\n", energy_error);
  }
  {
    char plot_cmd[4200], plot_dir[4200];
    tl_printf("plots: %s %s\n", tl_plot_command(TALUS_TOOLS_DIR, "plot_timeseries.py", plot_cmd, sizeof plot_cmd),
              (tl_plot_abs_dir(s.out, plot_dir, sizeof plot_dir - 16), strcat(plot_dir, "/energies.csv")));
  }
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "n", (long)P->n);
  tl_summary_int(&sum, "steps", last);
  tl_summary_string(&sum, "settled", settled ? "true" : "false");
  tl_summary_real(&sum, "kinetic_final", en.kinetic_translational + en.kinetic_rotational);
  tl_summary_real(&sum, "coordination", z);
  tl_summary_real(&sum, "weight_balance", balance);
  tl_summary_real(&sum, "packing_fraction", vol / (s.box * s.box * top));
  tl_summary_real(&sum, "energy_balance_error", energy_error);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  st = tl_summary_print(&sum, stdout);
done:
  tl_checkpoint_destroy(&cp);
  if (ts) {
    TlStatus sc = tl_timeseries_close(&ts);
    if (st == TL_OK) st = sc;
  }
  tl_particle_writer_destroy(&writer);
  tl_wall_writer_destroy(&walls);
  tl_dem_destroy(&dem);
  tl_contact_law_destroy(&s.law);
  tl_options_destroy(&o);
  return st;
}

int main(int argc, char **argv)
{
  TlStatus s = tl_initialize();
  if (s == TL_OK) s = run(argc, argv);
  return tl_driver_exit(s);
}
