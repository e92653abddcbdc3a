/* Coarse-grains a packing onto a regular grid (Cheng et al. 2022 §4, Eqs. 8-12):
 * density, velocity, kinetic and contact stress, boundary force density of
 * the floor, and fabric.
 *
 *   -packing random   (default) inserts -n spheres at random in a box
 *                     periodic in x and y above a floor at z = 0 and lets
 *                     them settle under gravity (linear law, damped), so
 *                     the driver runs on its own;
 *   -packing FILE.h5  reads a particle snapshot (a settle run's output,
 *                     Kernel/IO format) and uses it as it is.
 *
 * With -average_snapshots N the fields are averaged over N states
 * -average_interval DEM steps apart (the velocity as <j>/<rho>).
 *
 * Contacts and their forces come from the DEM world at each state, the
 * floor's contacts included (tl_dem_visit_wall_contacts: the forces the DEM
 * computed, with damping and any friction, at their contact points).
 *
 * Output under -output_dir: fields.xmf + fields_*.h5 (the grid as hexahedra
 * with node fields; open fields.xmf in ParaView), profile.csv (averages over
 * x-y layers against z, with the weight of the material above each layer
 * as a check of sigma_zz), and packing.xmf (the particles).  The last line
 * is `summary: ...` with the volume-averaged CG stress against the
 * Cauchy-Poisson stress of the same contacts (Desrues et al. 2019 Eq. 27). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_options_renamed.h"
#include "tl_plot_hint.h"
#include "tl_cg_fields.h"
#include "tl_cg_kernel.h"
#include "tl_dem.h"
#include "tl_io.h"
#include "tl_options_checkpoint.h"

typedef struct {
  const char *packing, *kernel, *output_dir;
  long n, settle_steps, seed, average_snapshots, average_interval;
  double d, d_spread, density, lx, ly, height, gravity, c, h, settle_tol, floor_z;
  int box_from_extent, write_hdf5;
  long checkpoint_every, stop_step; /* settling steps, multiples of the 500-step chunk */
  const char *restart;
  TlContactLaw *law;
  TlOptions *options; /* kept for the checkpoint; destroyed at the end of the run */
} Config;

enum { SETTLE_CHUNK = 500 }; /* settling steps between kinetic-energy checks (and checkpoints) */

static TlStatus check_grid_size(const Config *c, double zmax);

static TlStatus configure(int argc, char **argv, Config *c)
{
  TlOptions *o = NULL;
  TlStatus s = TL_OK;
  TL_CHECK(tl_options_create(argc, argv,
                             "Coarse-grains a settled packing onto a grid (Cheng et al. 2022, Eqs. 8-12): density, velocity, "
                             "stress, boundary force density, fabric; HDF5+XDMF and a CSV profile against z.  Paper: " TL_PAPER_CHENG_2022 ".",
                             &o));
  static const TlRenamedOption renamed[] = {{"-kernel", "-cg_kernel", NULL}};
  TL_CHECK_GOTO(s, tl_options_refuse_renamed(o, renamed, 1), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-packing", "random", "'random' or a particle snapshot .h5 file",
                                         &c->packing), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-d", 0.01, 1e-9, 1e3, "m", "mean particle diameter (unit 'd' of lengths)",
                                       &c->d), done);
  TlScale d_scale[1] = {{"d", c->d, "mean particle diameter"}};
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-n", 1500, 1, 100000000, "particles of the random packing", &c->n), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-d_spread", 0.2, 0.0, 1.0, "", "random packing: diameters uniform in d (1 +- spread/2)",
                                       &c->d_spread), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-seed", 1, 0, 1L << 62, "random packing: seed", &c->seed), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-density", 2500.0, 1e-6, 1e6, "kg/m^3", "particle density", &c->density), done);
  TL_CHECK_GOTO(s, tl_options_get_scaled(o, "-lx", "10d", 1e-9, 1e9, "m", d_scale, 1, "box length along x", &c->lx), done);
  TL_CHECK_GOTO(s, tl_options_get_scaled(o, "-ly", "10d", 1e-9, 1e9, "m", d_scale, 1, "box length along y", &c->ly), done);
  /* a file's packing: the box defaults to the extent of its centres plus d */
  c->box_from_extent = strcmp(c->packing, "random") != 0 && !(tl_options_has(o, "-lx") && tl_options_has(o, "-ly"));
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-floor_z", 0.0, -1e9, 1e9, "m", "height of the floor plane", &c->floor_z), done);
  {
    /* linear spring-dashpot k_n = 1e4 N/m, restitution 0.3 while settling */
    const TlContactValue law_values[] = {{"k_n", 1e4}, {"restitution", 0.3}};
    const TlContactSpec law_spec = {"linear", NULL, NULL, NULL, law_values, 2};
    TL_CHECK_GOTO(s, tl_contact_law_from_options(o, &law_spec, &c->law), done);
  }
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-gravity", 9.81, 0.0, 1e6, "m/s^2", "gravity along -z", &c->gravity), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-settle_steps", 60000, 0, 100000000, "random packing: most settling steps",
                                      &c->settle_steps), done);
  TL_CHECK_GOTO(s, tl_options_get_real(o, "-settle_tolerance", 1e-6, 0.0, 1.0, "",
                                       "settled when the kinetic energy per particle is below this times m g d",
                                       &c->settle_tol), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-cg_kernel", "lucy", "CG kernel: lucy, gaussian, heaviside (dirac when c = 0)",
                                         &c->kernel), done);
  TL_CHECK_GOTO(s, tl_options_get_scaled(o, "-cg_width", "2d", 0.0, 1e9, "m", d_scale, 1, "CG width c (0: Dirac, cell averages)",
                                         &c->c), done);
  TL_CHECK_GOTO(s, tl_options_get_scaled(o, "-grid_spacing", "0.5d", 1e-12, 1e9, "m", d_scale, 1, "grid spacing (about)",
                                         &c->h), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-average_snapshots", 1, 1, 1000000,
                                      "states the fields are averaged over (1: the final state only)", &c->average_snapshots),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-average_interval", 200, 1, 100000000, "DEM steps between averaged states",
                                      &c->average_interval), done);
  TL_CHECK_GOTO(s, tl_options_get_bool(o, "-write_hdf5", 1, "write the grid fields and particles as HDF5+XDMF",
                                       &c->write_hdf5),
                done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-checkpoint_every", 0, 0, 1000000000,
                                      "random packing: checkpoint.h5 in the output folder every n settling steps (a "
                                      "multiple of 500; 0: none)", &c->checkpoint_every), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-restart", "", "continue the settling from this checkpoint file (same options)",
                                         &c->restart), done);
  TL_CHECK_GOTO(s, tl_options_get_int(o, "-stop_step", 0, 0, 1000000000,
                                      "random packing: stop after this settling step (a multiple of 500; 0: run to the end)",
                                      &c->stop_step), done);
  TL_CHECK_GOTO(s, tl_options_get_string(o, "-output_dir", "results/cg_fields", "output folder", &c->output_dir), done);
  TL_CHECK_GOTO(s, tl_output_dir_check(c->output_dir), done);
  /* strings point into the options database: copy before destroying it */
  static char packing[4096], kernel[64], outdir[4096];
  snprintf(packing, sizeof packing, "%s", c->packing);
  snprintf(kernel, sizeof kernel, "%s", c->kernel);
  snprintf(outdir, sizeof outdir, "%s", c->output_dir);
  c->packing = packing;
  c->kernel = kernel;
  c->output_dir = outdir;
  s = tl_options_finish(o, stdout);
  if (s == TL_OK) { /* refuse an unknown kernel before any settling */
    const TlOpsHeader *known;
    s = tl_registry_find(TL_CG_KERNEL_KIND, c->kernel, &known);
  }
  if (s == TL_OK && !c->box_from_extent) s = check_grid_size(c, c->floor_z);
  if (s == TL_OK && (c->checkpoint_every % SETTLE_CHUNK != 0 || c->stop_step % SETTLE_CHUNK != 0))
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                     "-checkpoint_every %ld and -stop_step %ld must be multiples of the %d settling steps between "
                     "kinetic-energy checks", c->checkpoint_every, c->stop_step, SETTLE_CHUNK);
  if (s == TL_OK && (c->checkpoint_every > 0 || c->stop_step > 0 || c->restart[0]) && strcmp(c->packing, "random") != 0)
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                     "-checkpoint_every, -stop_step and -restart checkpoint the settling of a random packing; "
                     "-packing %s is not settled", c->packing);
done:
  if (s != TL_OK) {
    tl_contact_law_destroy(&c->law);
    tl_options_destroy(&o);
  }
  c->options = o;
  return s;
}

/* The CG grid's node count, computed in floating point before anything is
 * allocated: a width or spacing far from the particle scale would ask for
 * more nodes than memory holds (or overflow the count).  zmax is the top of
 * the bed (the floor before settling gives a lower bound). */
#define CG_MAX_NODES 5e7
static TlStatus check_grid_size(const Config *c, double zmax)
{
  const double nx = fmax(1.0, nearbyint(c->lx / c->h)), ny = fmax(1.0, nearbyint(c->ly / c->h));
  const double nz = c->c == 0.0 ? ceil((zmax + c->d - c->floor_z) / c->h) : ceil((zmax + 2.0 * c->c + c->d - c->floor_z) / c->h) + 1.0;
  const double nodes = nx * ny * nz;
  if (!(nodes <= CG_MAX_NODES))
    TL_ERROR(TL_ERR_ARG,
             "-cg_width %g m with -grid_spacing %g m asks for a CG grid of %.3g x %.3g x %.3g = %.3g nodes, "
             "beyond the limit of %.0e nodes: raise -grid_spacing or lower -cg_width",
             c->c, c->h, nx, ny, nz, nodes, CG_MAX_NODES);
  return TL_OK;
}

/* Random sequential insertion in [0, lx) x [0, ly) x [floor + r, floor + H - r],
 * periodic in x and y: O(n^2) overlap checks, fine for the packings of a
 * driver run (a few thousand particles). */
static TlStatus insert_random(TlDem *dem, const Config *c, int species, double height)
{
  TlParticles *P = tl_dem_particles(dem);
  uint64_t state = (uint64_t)c->seed * 0x9E3779B97F4A7C15ULL + 1;
  TlVec3 *x = NULL;
  double *r = NULL;
  TL_CHECK(tl_calloc(&x, (size_t)c->n, sizeof *x));
  TlStatus s = tl_calloc(&r, (size_t)c->n, sizeof *r);
  if (s != TL_OK) {
    tl_free(&x);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  long placed = 0;
  for (long k = 0; k < c->n && s == TL_OK; ++k) {
    double rk = tl_species_sample_radius(&P->species_table[species], &state);
    int ok = 0;
    for (int attempt = 0; attempt < 2000 && !ok; ++attempt) {
      TlVec3 p = tl_v3(c->lx * tl_random_uniform(&state), c->ly * tl_random_uniform(&state),
                       c->floor_z + rk + (height - 2 * rk) * tl_random_uniform(&state));
      ok = 1;
      for (long j = 0; j < placed && ok; ++j) {
        TlVec3 b = tl_v3_sub(p, x[j]);
        b.x -= c->lx * nearbyint(b.x / c->lx);
        b.y -= c->ly * nearbyint(b.y / c->ly);
        ok = tl_v3_norm2(b) >= (rk + r[j]) * (rk + r[j]);
      }
      if (ok) {
        x[placed] = p;
        r[placed++] = rk;
      }
    }
    if (!ok)
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "random packing: no room for particle %ld of %ld in a %g x %g x %g m insertion box", k, c->n,
                       c->lx, c->ly, height);
  }
  for (long k = 0; k < placed && s == TL_OK; ++k) s = tl_dem_add_particle(dem, x[k], tl_v3(0, 0, 0), r[k], species, NULL);
  tl_free(&x);
  tl_free(&r);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}

typedef struct {
  TlVec3 *x, *b, *f;
  size_t n, cap;
  TlStatus status;
} ContactSink;

/* Wall contacts: contact point, force on the particle, particle centre. */
typedef struct {
  TlVec3 *p, *f, *c;
  size_t n, cap;
  TlStatus status;
} WallSink;

static void collect_wall_contact(void *ctx, size_t wall, size_t i, TlVec3 force, TlVec3 point, TlVec3 center)
{
  WallSink *k = ctx;
  (void)wall;
  (void)i;
  if (k->status != TL_OK) return;
  if (k->n == k->cap) {
    size_t c1 = k->cap, c2 = k->cap, c3 = k->cap;
    k->status = tl_array_reserve(&k->p, &c1, k->n + 1, sizeof(TlVec3));
    if (k->status == TL_OK) k->status = tl_array_reserve(&k->f, &c2, k->n + 1, sizeof(TlVec3));
    if (k->status == TL_OK) k->status = tl_array_reserve(&k->c, &c3, k->n + 1, sizeof(TlVec3));
    if (k->status != TL_OK) return;
    k->cap = c1;
  }
  k->p[k->n] = point;
  k->f[k->n] = force;
  k->c[k->n] = center;
  k->n++;
}

static void collect_contact(void *ctx, size_t i, size_t j, TlVec3 force_on_i, TlVec3 branch, TlVec3 point)
{
  ContactSink *k = ctx;
  (void)j;
  (void)point;
  if (k->status != TL_OK) return;
  if (k->n == k->cap) {
    size_t c1 = k->cap, c2 = k->cap, c3 = k->cap;
    k->status = tl_array_reserve(&k->x, &c1, k->n + 1, sizeof(TlVec3));
    if (k->status == TL_OK) k->status = tl_array_reserve(&k->b, &c2, k->n + 1, sizeof(TlVec3));
    if (k->status == TL_OK) k->status = tl_array_reserve(&k->f, &c3, k->n + 1, sizeof(TlVec3));
    if (k->status != TL_OK) return;
    k->cap = c1;
  }
  /* the centre of i is kept as its index for now and resolved by the caller */
  k->x[k->n] = tl_v3((double)i, 0, 0);
  k->b[k->n] = branch;
  k->f[k->n] = force_on_i;
  k->n++;
}

/* Grid field arrays as mesh node fields (row-major n x components). */
static TlStatus write_fields(const Config *c, const TlCGGrid *g, const TlCGFields *f, const TlMat3 *stress)
{
  size_t nodes = f->n;
  int nx = g->n[0], ny = g->n[1], nz = g->n[2];
  size_t cells = (size_t)(nx - 1 > 0 ? nx - 1 : 0) * (size_t)(ny - 1 > 0 ? ny - 1 : 0) * (size_t)(nz - 1 > 0 ? nz - 1 : 0);
  if (cells == 0) {
    tl_warn("grid has a single layer along some direction: no HDF5 grid written");
    return TL_OK;
  }
  TlVec3 *ref = NULL;
  int *conn = NULL;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_calloc(&ref, nodes, sizeof *ref), done);
  TL_CHECK_GOTO(s, tl_calloc(&conn, cells * 8, sizeof *conn), done);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) ref[i + (size_t)nx * (j + (size_t)ny * k)] = tl_cg_grid_node(g, i, j, k);
  size_t e = 0;
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i, ++e) {
        int n0 = i + nx * (j + ny * k);
        int q[8] = {n0, n0 + 1, n0 + 1 + nx, n0 + nx, n0 + nx * ny, n0 + 1 + nx * ny, n0 + 1 + nx + nx * ny,
                    n0 + nx + nx * ny};
        memcpy(conn + 8 * e, q, sizeof q);
      }
  TlField fields[7] = {
      {"density", 1, f->density},
      {"velocity", 3, &f->velocity[0].x},
      {"stress", 9, &stress[0].m[0][0]},
      {"stress_contact", 9, &f->stress_contact[0].m[0][0]},
      {"stress_kinetic", 9, &f->stress_kinetic[0].m[0][0]},
      {"boundary_force_density", 3, &f->boundary_force[0].x},
      {"fabric", 9, &f->fabric[0].m[0][0]},
  };
  TlMeshBlock block = {"grid", TL_CELL_HEX8, cells, conn, 0, NULL};
  TlMeshView view = {nodes, ref, NULL, 7, fields, 1, &block};
  TlMeshWriter *w = NULL;
  TL_CHECK_GOTO(s, tl_mesh_writer_create(c->output_dir, "fields", &w), done);
  s = tl_mesh_writer_write(w, 0, 0.0, &view);
  tl_mesh_writer_destroy(&w);
  if (s != TL_OK) tl_error_trace(s, __FILE__, __LINE__);
done:
  tl_free(&ref);
  tl_free(&conn);
  return s;
}

static TlStatus run(int argc, char **argv, TlSummary *sum)
{
  Config c;
  memset(&c, 0, sizeof c);
  TL_CHECK(tl_initialize());
  TL_CHECK(configure(argc, argv, &c));
  TlTimers timers;
  tl_timers_init(&timers);
  int ph_setup = tl_timers_phase(&timers, "packing"), ph_cg = tl_timers_phase(&timers, "coarse-graining"),
      ph_out = tl_timers_phase(&timers, "output");
  tl_timers_start(&timers, ph_setup);

  TlStatus s = TL_OK;
  TlDem *dem = NULL;
  TlParticleSnapshot snap;
  memset(&snap, 0, sizeof snap);
  TlCGKernel *kernel = NULL;
  TlCG *cg = NULL;
  TlCGFields *f = NULL, *snapshot = NULL;
  TlMat3 *stress = NULL;
  ContactSink sink = {NULL, NULL, NULL, 0, 0, TL_OK};
  WallSink wsink = {NULL, NULL, NULL, 0, 0, TL_OK};
  double *prof = NULL;
  TlTimeSeries *ts = NULL;
  TlCheckpoint *cp = NULL;
  char *cp_path = NULL;

  int random = strcmp(c.packing, "random") == 0;
  double r_mean = 0.5 * c.d, height;
  TL_CHECK_GOTO(s, tl_dem_create(&dem), done);
  TlParticles *P = tl_dem_particles(dem);
  int species = 0;
  if (random) {
    TL_CHECK_GOTO(s, tl_particles_add_species(P, "grains", c.density, r_mean * (1 - 0.5 * c.d_spread),
                                              r_mean * (1 + 0.5 * c.d_spread), &species), done);
    /* a loose insertion region (solid fraction 0.2) the packing settles from */
    height = c.n * (TL_PI / 6.0) * c.d * c.d * c.d * (1 + 0.25 * c.d_spread * c.d_spread) / (0.2 * c.lx * c.ly) + 2 * c.d;
  } else {
    TL_CHECK_GOTO(s, tl_particle_snapshot_read(c.packing, &snap), done);
    if (snap.n == 0) {
      s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "packing file %s holds no particles", c.packing);
      goto done;
    }
    double rmin = INFINITY, rmax = 0, zmax = -INFINITY;
    TlVec3 lo = snap.position[0], hi = snap.position[0];
    for (size_t i = 0; i < snap.n; ++i) {
      rmin = fmin(rmin, snap.radius[i]);
      rmax = fmax(rmax, snap.radius[i]);
      zmax = fmax(zmax, snap.position[i].z + snap.radius[i]);
      lo = tl_v3(fmin(lo.x, snap.position[i].x), fmin(lo.y, snap.position[i].y), 0);
      hi = tl_v3(fmax(hi.x, snap.position[i].x), fmax(hi.y, snap.position[i].y), 0);
    }
    if (c.box_from_extent) {
      c.lx = hi.x - lo.x + 2 * rmax;
      c.ly = hi.y - lo.y + 2 * rmax;
      tl_info("box from the packing's extent: %g x %g m (give -lx and -ly for the true periodic box)", c.lx, c.ly);
    }
    height = zmax - c.floor_z + c.d;
    TL_CHECK_GOTO(s, tl_particles_add_species(P, "grains", c.density, rmin, rmax, &species), done);
  }
  TlDomain dom;
  int per[3] = {1, 1, 0};
  TL_CHECK_GOTO(s, tl_domain_init_periodic_box(&dom, tl_v3(0, 0, c.floor_z), tl_v3(c.lx, c.ly, c.floor_z + height), per),
                done);
  TL_CHECK_GOTO(s, tl_dem_set_domain(dem, &dom), done);
  if (random) {
    TL_CHECK_GOTO(s, insert_random(dem, &c, species, height), done);
  } else {
    for (size_t i = 0; i < snap.n && s == TL_OK; ++i) {
      TlVec3 x = snap.position[i];
      x.x -= c.lx * floor(x.x / c.lx);
      x.y -= c.ly * floor(x.y / c.ly);
      s = tl_dem_add_particle(dem, x, snap.velocity ? snap.velocity[i] : tl_v3(0, 0, 0), snap.radius[i], species, NULL);
    }
    if (s != TL_OK) goto done;
  }
  TL_CHECK_GOTO(s, tl_dem_add_law(dem, c.law, NULL), done);
  c.law = NULL; /* the world owns it */
  TlWall *floor_wall = NULL;
  TL_CHECK_GOTO(s, tl_wall_plane_create(tl_v3(0, 0, c.floor_z), tl_v3(0, 0, 1), &floor_wall), done);
  TL_CHECK_GOTO(s, tl_dem_add_wall(dem, floor_wall, 0), done);
  tl_dem_set_gravity(dem, tl_v3(0, 0, -c.gravity));
  double dtc, kmax, mmin;
  TL_CHECK_GOTO(s, tl_dem_critical_timestep(dem, &dtc, &kmax, &mmin), done);
  TL_CHECK_GOTO(s, tl_dem_set_timestep(dem, 0.2 * dtc, 0), done);
  TL_CHECK_GOTO(s, tl_dem_setup(dem), done);
  P = tl_dem_particles(dem);
  double m_mean = c.density * TL_PI / 6.0 * c.d * c.d * c.d;
  long steps = 0;
  double ekin_per = 0.0;
  if (random && c.settle_steps > 0) {
    /* The settling is checkpointed (the options, the world, the step count)
     * between chunks; a restart continues it bit for bit and then
     * coarse-grains as the uninterrupted run does. */
    int64_t settled = 0;
    TL_CHECK_GOTO(s, tl_checkpoint_create(&cp), done);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, c.options), done);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), done);
    TL_CHECK_GOTO(s, tl_path_join(c.output_dir, "checkpoint.h5", &cp_path), done);
    if (c.restart[0]) {
      TL_CHECK_GOTO(s, tl_checkpoint_load(cp, c.restart, NULL, &settled), done);
      if (!(settled >= 0 && settled % SETTLE_CHUNK == 0 && settled <= c.settle_steps))
        TL_CHECK_GOTO(s, tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                                      "checkpoint '%s' is at settling step %lld: not a multiple of %d in [0, -settle_steps %ld]",
                                      c.restart, (long long)settled, SETTLE_CHUNK, c.settle_steps), done);
      steps = (long)settled;
      tl_printf("restarted from %s at settling step %ld\n", c.restart, steps);
    }
    if (c.checkpoint_every > 0) TL_CHECK_GOTO(s, tl_output_dir_prepare(c.output_dir), done);
    TlProgress prog;
    tl_progress_init(&prog, "settling", (double)c.settle_steps);
    const long chunk = SETTLE_CHUNK;
    while (steps < c.settle_steps) {
      long m = c.settle_steps - steps < chunk ? c.settle_steps - steps : chunk;
      TL_CHECK_GOTO(s, tl_dem_step(dem, m), done);
      steps += m;
      TlDemEnergy e;
      TL_CHECK_GOTO(s, tl_dem_energy(dem, &e), done);
      ekin_per = (e.kinetic_translational + e.kinetic_rotational) / (double)P->n;
      tl_progress_update(&prog, (double)steps);
      if (steps > 5 * chunk && ekin_per < c.settle_tol * m_mean * c.gravity * c.d) break;
      if (c.checkpoint_every > 0 && steps % c.checkpoint_every == 0)
        TL_CHECK_GOTO(s, tl_checkpoint_save(cp, cp_path, tl_dem_time(dem), steps), done);
      if (c.stop_step > 0 && steps >= c.stop_step) {
        tl_progress_finish(&prog);
        tl_printf("stopped after settling step %ld\n", steps);
        tl_summary_int(sum, "stopped_at_step", steps);
        tl_summary_int(sum, "particles", (long)P->n);
        goto done;
      }
    }
    tl_progress_finish(&prog);
    tl_info("settled for %ld steps: kinetic energy per particle %.3g m g d", steps, ekin_per / (m_mean * c.gravity * c.d));
  }
  TL_CHECK_GOTO(s, tl_dem_compute_forces(dem), done);
  double zmax = c.floor_z, total_mass = 0;
  for (size_t i = 0; i < P->n; ++i) {
    zmax = fmax(zmax, P->x[i].z + P->radius[i]);
    total_mass += P->mass[i];
  }
  tl_timers_stop(&timers, ph_setup);

  /* ---- coarse-graining, averaged over -average_snapshots states ---- */
  TL_CHECK_GOTO(s, tl_cg_kernel_create(c.c > 0 ? c.kernel : "dirac", c.c, 3, &kernel), done);
  TlCGBox box = {tl_v3(0, 0, c.floor_z), tl_v3(c.lx, c.ly, zmax), {1, 1, 0}};
  TL_CHECK_GOTO(s, tl_cg_create(kernel, &box, 0, &cg), done);
  TL_CHECK_GOTO(s, check_grid_size(&c, zmax), done);
  TlCGGrid g;
  g.n[0] = (int)fmax(1.0, nearbyint(c.lx / c.h));
  g.n[1] = (int)fmax(1.0, nearbyint(c.ly / c.h));
  double z0 = c.floor_z - c.c, z1 = zmax + c.c + c.d; /* a diameter of room for the grains' motion */
  g.n[2] = (int)ceil((z1 - z0) / c.h) + 1;
  g.h = tl_v3(c.lx / g.n[0], c.ly / g.n[1], (z1 - z0) / (g.n[2] - 1));
  g.lo = tl_v3(0.5 * g.h.x, 0.5 * g.h.y, z0);
  if (c.c == 0.0) { /* cell averages: the cells must tile the whole height */
    g.h.z = c.h;
    g.n[2] = (int)ceil((zmax + c.d - c.floor_z) / c.h);
    g.lo.z = c.floor_z + 0.5 * c.h;
  }
  size_t nodes = (size_t)g.n[0] * g.n[1] * g.n[2];
  TL_CHECK_GOTO(s, tl_cg_fields_create(nodes, TL_CG_ALL, &snapshot), done);
  TL_CHECK_GOTO(s, tl_cg_fields_create(nodes, TL_CG_ALL, &f), done);
  tl_cg_fields_zero(f);
  double dv = g.h.x * g.h.y * g.h.z, mass_cg = 0, t_cg = 0;
  TlMat3 sc_int = tl_m3_zero(), cp_sum = tl_m3_zero();
  size_t nw = 0;
  for (long snap_k = 0; snap_k < c.average_snapshots; ++snap_k) {
    if (snap_k > 0) {
      tl_timers_start(&timers, ph_setup);
      TL_CHECK_GOTO(s, tl_dem_step(dem, c.average_interval), done);
      steps += c.average_interval;
      tl_timers_stop(&timers, ph_setup);
    }
    tl_timers_start(&timers, ph_cg);
    sink.n = 0;
    TL_CHECK_GOTO(s, tl_dem_visit_contacts(dem, collect_contact, &sink), done);
    TL_CHECK_GOTO(s, sink.status, done);
    for (size_t k = 0; k < sink.n; ++k) sink.x[k] = P->x[(size_t)sink.x[k].x];
    /* floor contacts with the forces the DEM computed */
    wsink.n = 0;
    TL_CHECK_GOTO(s, tl_dem_visit_wall_contacts(dem, collect_wall_contact, &wsink), done);
    TL_CHECK_GOTO(s, wsink.status, done);
    nw = wsink.n;
    TlVec3 *wp = wsink.p, *wf = wsink.f, *wc = wsink.c;
    TlCGParticleArrays pa = {P->n, P->x, P->mass, P->v};
    TlCGContactArrays ca = {sink.n, sink.x, sink.b, sink.f};
    TlCGWallContactArrays wa = {nw, wp, wf, wc};
    TL_CHECK_GOTO(s, tl_cg_set_data(cg, &pa, &ca, &wa), done);
    double t0 = tl_wtime();
    TL_CHECK_GOTO(s, tl_cg_evaluate_grid(cg, &g, snapshot), done);
    t_cg += tl_wtime() - t0;
    TL_CHECK_GOTO(s, tl_cg_fields_accumulate(f, snapshot, 1.0), done);
    for (size_t k = 0; k < sink.n; ++k) cp_sum = tl_m3_add(cp_sum, tl_m3_outer(sink.f[k], sink.b[k]));
    for (size_t k = 0; k < nw; ++k) cp_sum = tl_m3_add(cp_sum, tl_m3_outer(wf[k], tl_v3_sub(wp[k], wc[k])));
    tl_timers_stop(&timers, ph_cg);
  }
  TL_CHECK_GOTO(s, tl_cg_fields_average_finish(f), done);
  t_cg /= (double)c.average_snapshots;
  cp_sum = tl_m3_scale(cp_sum, 1.0 / (double)c.average_snapshots);
  TL_CHECK_GOTO(s, tl_calloc(&stress, nodes, sizeof *stress), done);
  for (size_t i = 0; i < nodes; ++i) {
    stress[i] = tl_m3_add(f->stress_contact[i], f->stress_kinetic[i]);
    sc_int = tl_m3_add(sc_int, tl_m3_scale(f->stress_contact[i], dv));
    mass_cg += f->density[i] * dv;
  }
  double stress_diff = 0, stress_scale = fabs(tl_m3_trace(cp_sum)) / 3.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) stress_diff = tl_track_max(stress_diff, fabs(sc_int.m[a][b] - cp_sum.m[a][b]));
  stress_diff = stress_scale > 0 ? stress_diff / stress_scale : 0.0;

  /* ---- profile against z: layer averages, and the weight of what lies above ---- */
  tl_timers_start(&timers, ph_out);
  TL_CHECK_GOTO(s, tl_output_dir_prepare(c.output_dir), done);
  enum { NCOL = 16 };
  TL_CHECK_GOTO(s, tl_calloc(&prof, (size_t)g.n[2] * NCOL, sizeof *prof), done);
  size_t layer = (size_t)g.n[0] * g.n[1];
  for (int k = 0; k < g.n[2]; ++k) {
    double *row = prof + (size_t)k * NCOL;
    row[0] = g.lo.z + k * g.h.z;
    for (size_t q = 0; q < layer; ++q) {
      size_t i = (size_t)k * layer + q;
      row[1] += f->density[i];
      row[3] += f->velocity[i].x;
      row[4] += f->velocity[i].y;
      row[5] += f->velocity[i].z;
      row[6] += stress[i].m[0][0];
      row[7] += stress[i].m[1][1];
      row[8] += stress[i].m[2][2];
      row[9] += stress[i].m[0][2];
      row[10] += stress[i].m[1][2];
      row[11] += f->stress_kinetic[i].m[2][2];
      row[13] += f->boundary_force[i].z;
      row[14] += tl_m3_trace(f->fabric[i]);
    }
    for (int col = 1; col < 15; ++col) row[col] /= (double)layer;
    row[2] = row[1] / c.density;                                   /* solid fraction */
    row[12] = -(row[6] + row[7] + row[8]) / 3.0;                   /* pressure */
  }
  /* weight per area of the material above z: g * int_z^top rho dz' (trapezoid) */
  for (int k = g.n[2] - 2; k >= 0; --k) {
    double *row = prof + (size_t)k * NCOL, *up = row + NCOL;
    row[15] = up[15] + c.gravity * 0.5 * (row[1] + up[1]) * g.h.z;
  }
  /* at mid-depth of the packing the vertical stress carries that weight */
  int kmid = (int)nearbyint((0.5 * (zmax + c.floor_z) - g.lo.z) / g.h.z);
  if (kmid < 0) kmid = 0;
  if (kmid >= g.n[2]) kmid = g.n[2] - 1;
  double w_mid = prof[(size_t)kmid * NCOL + 15], szz_mid = prof[(size_t)kmid * NCOL + 8];
  double szz_vs_weight = w_mid > 0 ? (-szz_mid - w_mid) / w_mid : 0.0;
  static const TlColumn cols[NCOL] = {{"z", "m"},           {"density", "kg/m^3"}, {"solid_fraction", ""},
                                      {"vx", "m/s"},        {"vy", "m/s"},         {"vz", "m/s"},
                                      {"sxx", "Pa"},        {"syy", "Pa"},         {"szz", "Pa"},
                                      {"sxz", "Pa"},        {"syz", "Pa"},         {"szz_kinetic", "Pa"},
                                      {"pressure", "Pa"},   {"bz", "N/m^3"},       {"fabric_trace", "1/m^3"},
                                      {"weight_above", "Pa"}};
  char base[4200];
  snprintf(base, sizeof base, "%s/profile", c.output_dir);
  TL_CHECK_GOTO(s, tl_timeseries_create(base, TL_TIMESERIES_CSV, NCOL, cols, &ts), done);
  for (int k = 0; k < g.n[2]; ++k) TL_CHECK_GOTO(s, tl_timeseries_append(ts, prof + (size_t)k * NCOL), done);
  TL_CHECK_GOTO(s, tl_timeseries_close(&ts), done);
  if (c.write_hdf5) {
    TL_CHECK_GOTO(s, write_fields(&c, &g, f, stress), done);
    TlParticleWriter *pw = NULL;
    TL_CHECK_GOTO(s, tl_particle_writer_create(c.output_dir, "packing", &pw), done);
    TlParticleView pv = {.n = P->n, .position = P->x, .radius = P->radius, .velocity = P->v, .force = P->f,
                         .species = (const int *)P->species, .id = P->id};
    s = tl_particle_writer_write(pw, steps, tl_dem_time(dem), &pv);
    tl_particle_writer_destroy(&pw);
    if (s != TL_OK) goto done;
  }
  tl_timers_stop(&timers, ph_out);
  if (tl_log_enabled(TL_LOG_INFO)) tl_timers_print(&timers, stderr);
  {
    char plot_cmd[4200], plot_dir[4200];
    tl_printf("plots: %s %s\n", tl_plot_command(TALUS_TOOLS_DIR, "plot_cg_profile.py", plot_cmd, sizeof plot_cmd),
              (tl_plot_abs_dir(c.output_dir, plot_dir, sizeof plot_dir - 16), strcat(plot_dir, "/profile.csv")));
  }

  tl_summary_int(sum, "particles", (long)P->n);
  tl_summary_int(sum, "contacts", (long)sink.n);
  tl_summary_int(sum, "wall_contacts", (long)nw);
  tl_summary_int(sum, "settle_steps", steps);
  tl_summary_string(sum, "kernel", kernel->ops->header.name);
  tl_summary_real(sum, "c_over_d", c.c / c.d);
  tl_summary_int(sum, "grid_nodes", (long)nodes);
  tl_summary_int(sum, "averaged_states", c.average_snapshots);
  tl_summary_real(sum, "cg_seconds", t_cg);
  tl_summary_real(sum, "mass_rel_error", (mass_cg - total_mass) / total_mass);
  tl_summary_real(sum, "stress_vs_cauchy_poisson", stress_diff);
  tl_summary_real(sum, "szz_vs_weight_mid", szz_vs_weight);
  tl_summary_real(sum, "solid_fraction_mid", prof[(size_t)kmid * NCOL + 2]);
done:
  tl_timeseries_destroy(&ts);
  tl_free(&prof);
  tl_free(&stress);
  tl_cg_fields_destroy(&f);
  tl_cg_fields_destroy(&snapshot);
  tl_cg_destroy(&cg);
  tl_cg_kernel_destroy(&kernel);
  tl_free(&sink.x);
  tl_free(&sink.b);
  tl_free(&sink.f);
  tl_free(&wsink.p);
  tl_free(&wsink.f);
  tl_free(&wsink.c);
  tl_particle_snapshot_free(&snap);
  tl_checkpoint_destroy(&cp);
  tl_free(&cp_path);
  tl_dem_destroy(&dem);
  tl_contact_law_destroy(&c.law);
  tl_options_destroy(&c.options);
  return s;
}

int main(int argc, char **argv)
{
  double t0 = tl_wtime();
  TlSummary sum;
  tl_summary_init(&sum);
  TlStatus s = run(argc, argv, &sum);
  if (s == TL_OK) {
    tl_summary_real(&sum, "wall", tl_wtime() - t0);
    s = tl_summary_print(&sum, stdout);
  }
  return tl_driver_exit(s);
}
