/* Discharge of a flat-bottomed cylindrical hopper through a circular orifice,
 * against the Beverloo law.
 *
 * The hopper is an STL surface (written by this driver into -output_dir for
 * each orifice, or given with -stl) read back, repaired and placed as a
 * triangulated wall.  Polydisperse spheres (diameters uniform in
 * [d_min, d_max]) are inserted on a lattice inside the closed fill region
 * (the bin's interior shrunk by a margin; the exact inside test of
 * tl_surface_mesh_contains picks the sites), fall and settle on a lid (a
 * plane at z = 0) closing the orifice.  Since the orifice lies in the plane of
 * the lid, the settled packing is the same for every orifice: it is settled
 * once and copied into one run per orifice diameter D, where the lid drops
 * away at 5 m/s and the grains flow out; grains a few diameters below the
 * orifice are removed.
 *
 * The discharged mass m(t) (grains whose centre is below the orifice plane)
 * grows linearly in steady discharge; its slope between 15% and 60% of the
 * mass is the flow rate W.  Beverloo: W = C rho_b sqrt(g) (D - k d)^(5/2)
 * with rho_b the bulk density of the settled packing and d the mean
 * diameter; W^(2/5) is linear in D, whose least-squares line gives C and k
 * (for two or more orifices); C is also given for k = 1.5 fixed.
 *
 * Output in -output_dir: hopper_<i>.stl (the walls), fill_region.stl,
 * discharge_<i>.csv (t, discharged mass), rates.csv (D, W, the fit),
 * particles_<i>_*.h5 + .xmf (ParaView, -snapshots per orifice).  Plot:
 * SelfTests/hopper_discharge/plot_hopper.py <output_dir>.  Last line:
 * summary: n=... rho_b=... W_1=... C=... k=... C_k_fixed=... (C for k = 1.5)
 * mass_balance_error=...
 *
 * Restart: -checkpoint_every n writes <output_dir>/checkpoint.h5 every n
 * steps (counted over the whole run: the settling, then each discharge in
 * turn; in the settling at the first 1000-step block at or after each
 * multiple): the options, the world with its walls and contacts, the run's
 * stage and step, the settled packing every discharge starts from, the
 * results of the discharges done, and in a discharge its table, its snapshot
 * series and its samples of m(t).  -restart <file> rebuilds the scene from
 * the same options, loads the file and continues bit for bit; -stop_step n
 * ends the run with a checkpoint at step n (in the settling: the first block
 * end at or after it). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_options_checkpoint.h"
#include "tl_dem.h"
#include "tl_particle_snapshot.h"
#include "tl_stl.h"
#include "tl_timeseries.h"
#include "tl_wall_trisurface.h"

enum { MAX_ORIFICES = 16 };

typedef struct {
  long n, segments, snapshots;
  double d_min, d_max, density, E, mu, restitution, radius, t_settle, t_discharge, dt_fraction, lid_speed;
  double orifice[MAX_ORIFICES]; /* in mean diameters */
  int n_orifices, threads;
  long checkpoint_every, stop_step;
  const char *out, *stl, *restart;
} Settings;

static TlStatus options(int argc, char **argv, TlOptions **o, Settings *s)
{
  TL_CHECK(tl_options_create(argc, argv,
                             "Polydisperse spheres settled in a flat-bottomed STL hopper and discharged through "
                             "orifices of several diameters; flow rate against the Beverloo law.",
                             o));
  TL_CHECK(tl_options_get_int(*o, "-n", 2500, 10, 10000000, "number of grains", &s->n));
  TL_CHECK(tl_options_get_real(*o, "-d_min", 1.6e-3, 1e-6, 1.0, "m", "smallest diameter", &s->d_min));
  TL_CHECK(tl_options_get_real(*o, "-d_max", 2.4e-3, 1e-6, 1.0, "m", "largest diameter", &s->d_max));
  TL_CHECK(tl_options_get_real(*o, "-density", 2500, 1.0, 1e5, "kg/m^3", "grain density", &s->density));
  TL_CHECK(tl_options_get_real(*o, "-E", 1e5, 1.0, 1e12, "Pa",
                               "modulus of the linear contacts, k_n = E d_mean (soft: overlaps stay below 1% of d "
                               "at the bottom of the bed, and the step is large)", &s->E));
  TL_CHECK(tl_options_get_real(*o, "-mu", 0.5, 0.0, 10.0, "", "Coulomb friction coefficient (grains and walls)", &s->mu));
  TL_CHECK(tl_options_get_real(*o, "-restitution", 0.5, 0.01, 1.0, "", "normal restitution coefficient", &s->restitution));
  TL_CHECK(tl_options_get_real(*o, "-radius", 0.02, 1e-5, 100.0, "m", "hopper radius", &s->radius));
  TL_CHECK(tl_options_get_real_list_range(*o, "-orifices", "5,6,7", 1.0, 1000.0, "mean diameters",
                                          "orifice diameters D / d_mean, one discharge each", s->orifice,
                                          MAX_ORIFICES, &s->n_orifices));
  TL_CHECK(tl_options_get_int(*o, "-segments", 48, 8, 100000, "hopper facets around its axis", &s->segments));
  TL_CHECK(tl_options_get_real(*o, "-t_settle", 0.5, 0.0, 1e4, "s", "settling time on the closed lid", &s->t_settle));
  TL_CHECK(tl_options_get_real(*o, "-t_discharge", 1.0, 0.01, 1e4, "s", "longest discharge per orifice", &s->t_discharge));
  TL_CHECK(tl_options_get_real(*o, "-dt_fraction", 0.2, 1e-4, 1.0, "", "time step over the critical one", &s->dt_fraction));
  TL_CHECK(tl_options_get_real(*o, "-lid_speed", 5.0, 0.1, 1e3, "m/s", "speed at which the lid drops away", &s->lid_speed));
  TL_CHECK(tl_options_get_string(*o, "-stl", "",
                                 "hopper surface file (STL or Gmsh; metres, orifice centred on the z axis in the "
                                 "plane z = 0) instead of the generated one; one orifice, -orifices its D/d_mean",
                                 &s->stl));
  TL_CHECK(tl_options_get_int(*o, "-snapshots", 5, 0, 100000, "particle snapshots per discharge (ParaView)", &s->snapshots));
  long th;
  TL_CHECK(tl_options_get_int(*o, "-threads", 0, 0, 1024, "OpenMP threads (0: default)", &th));
  s->threads = (int)th;
  TL_CHECK(tl_options_get_string(*o, "-output_dir", "results/hopper_discharge", "output folder", &s->out));
  TL_CHECK(tl_output_dir_check(s->out));
  TL_CHECK(tl_options_get_int(*o, "-checkpoint_every", 0, 0, 1000000000,
                              "write <output_dir>/checkpoint.h5 every n steps of the run (settling, then the "
                              "discharges; 0: never)", &s->checkpoint_every));
  TL_CHECK(tl_options_get_string(*o, "-restart", "", "continue from this checkpoint file (same options)", &s->restart));
  TL_CHECK(tl_options_get_int(*o, "-stop_step", 0, 0, 1000000000,
                              "stop with a checkpoint at this step of the run (0: run to the end)", &s->stop_step));
  TL_CHECK(tl_options_finish(*o, stdout));
  if (!(s->d_max >= s->d_min)) TL_ERROR(TL_ERR_ARG, "-d_max %g is smaller than -d_min %g", s->d_max, s->d_min);
  double dm = 0.5 * (s->d_min + s->d_max);
  for (int k = 0; k < s->n_orifices; ++k)
    if (!(s->orifice[k] * dm < 2.0 * s->radius - 2.0 * s->d_max))
      TL_ERROR(TL_ERR_ARG, "-orifices %g (D = %g m) leaves no bottom in a hopper of radius %g m: D must be below %g m",
               s->orifice[k], s->orifice[k] * dm, s->radius, 2.0 * s->radius - 2.0 * s->d_max);
  if (s->stl[0] && s->n_orifices != 1)
    TL_ERROR(TL_ERR_ARG, "-stl gives one hopper: -orifices must name its one diameter (got %d values)", s->n_orifices);
  if (!(s->radius >= 3.0 * s->d_max))
    TL_ERROR(TL_ERR_ARG, "-radius %g m is below 3 d_max = %g m: no room for grains", s->radius, 3.0 * s->d_max);
  return TL_OK;
}

/* A surface of revolution about z from a profile (r_k, z_k): segment k to
 * k + 1 is a band of quads; a profile point at r = 0 is an apex (a fan).
 * Triangles traverse shared edges in opposite directions by construction. */
static TlStatus revolve(const double *r, const double *z, int np, int nseg, TlSurfaceMesh **m)
{
  size_t nv = 0, nt = 0;
  for (int k = 0; k < np; ++k) nv += r[k] > 0.0 ? (size_t)nseg : 1;
  for (int k = 0; k + 1 < np; ++k) nt += (r[k] > 0.0 && r[k + 1] > 0.0) ? 2 * (size_t)nseg : (size_t)nseg;
  double *x = NULL;
  int *tri = NULL, *first = NULL;
  TlStatus st = TL_OK;
  TL_CHECK_GOTO(st, tl_calloc(&x, 3 * nv, sizeof *x), done);
  TL_CHECK_GOTO(st, tl_calloc(&tri, 3 * nt, sizeof *tri), done);
  TL_CHECK_GOTO(st, tl_calloc(&first, (size_t)np, sizeof *first), done);
  size_t v = 0;
  for (int k = 0; k < np; ++k) {
    first[k] = (int)v;
    int n = r[k] > 0.0 ? nseg : 1;
    for (int s = 0; s < n; ++s, ++v) {
      double a = 2.0 * TL_PI * s / nseg;
      x[3 * v] = r[k] * cos(a), x[3 * v + 1] = r[k] * sin(a), x[3 * v + 2] = z[k];
    }
  }
  size_t t = 0;
  for (int k = 0; k + 1 < np; ++k)
    for (int s = 0; s < nseg; ++s) {
      int s1 = (s + 1) % nseg;
      int a = first[k] + s, b = first[k] + s1, c = first[k + 1] + s1, d = first[k + 1] + s;
      if (r[k] > 0.0 && r[k + 1] > 0.0) {
        int q[6] = {a, b, c, a, c, d};
        memcpy(tri + 3 * t, q, sizeof q);
        t += 2;
      } else if (r[k] == 0.0) { /* apex below: fan to ring k + 1 */
        int q[3] = {first[k], c, d};
        memcpy(tri + 3 * t, q, sizeof q);
        ++t;
      } else { /* apex above */
        int q[3] = {first[k + 1], a, b};
        memcpy(tri + 3 * t, q, sizeof q);
        ++t;
      }
    }
  TL_CHECK_GOTO(st, tl_surface_mesh_create(nv, x, nt, tri, m), done);
done:
  tl_free(&x);
  tl_free(&tri);
  tl_free(&first);
  return st;
}

/* The bin: annular bottom from the orifice radius r0 to R at z = 0, then
 * the cylinder up to H; rings about one facet width apart. */
static TlStatus hopper_mesh(double r0, double R, double H, int nseg, TlSurfaceMesh **m)
{
  double h = 2.0 * TL_PI * R / nseg;
  int nr = (int)ceil((R - r0) / h), nz = (int)ceil(H / h);
  if (nr < 1) nr = 1;
  if (nz < 1) nz = 1;
  double r[4096], z[4096];
  if (nr + nz + 1 > 4096) TL_ERROR(TL_ERR_ARG, "hopper profile of %d rings exceeds 4096: fewer -segments", nr + nz + 1);
  int np = 0;
  for (int k = 0; k <= nr; ++k) r[np] = r0 + (R - r0) * k / nr, z[np++] = 0.0;
  for (int k = 1; k <= nz; ++k) r[np] = R, z[np++] = H * k / nz;
  TL_CHECK(revolve(r, z, np, nseg, m));
  return TL_OK;
}

/* The closed fill region: a cylinder of radius R from z0 to z1 with its
 * caps. */
static TlStatus fill_mesh(double R, double z0, double z1, int nseg, TlSurfaceMesh **m)
{
  double h = 2.0 * TL_PI * R / nseg;
  int nz = (int)ceil((z1 - z0) / h);
  if (nz < 1) nz = 1;
  if (nz > 4000) nz = 4000;
  double r[4096], z[4096];
  int np = 0;
  r[np] = 0.0, z[np++] = z0;
  for (int k = 0; k <= nz; ++k) r[np] = R, z[np++] = z0 + (z1 - z0) * k / nz;
  r[np] = 0.0, z[np++] = z1;
  TL_CHECK(revolve(r, z, np, nseg, m));
  return TL_OK;
}

static TlStatus make_law(const Settings *s, TlContactLaw **law)
{
  const TlContactValue values[] = {{"k_n", s->E * 0.5 * (s->d_min + s->d_max)}, {"restitution", s->restitution}, {"mu", s->mu}};
  const TlContactSpec spec = {"linear", "coulomb", NULL, NULL, values, 3};
  TL_CHECK(tl_contact_law_build(&spec, law));
  return TL_OK;
}

/* A world with the hopper wall from file and the lid; particles added by
 * the caller. */
static TlStatus make_world(const Settings *s, const char *stl, double top, TlDem **dem, TlWall **lid, TlSurfaceReport *rep)
{
  TL_CHECK(tl_dem_create(dem));
  TlDomain dom;
  double R = s->radius + 2 * s->d_max;
  TL_CHECK(tl_domain_init_open(&dom, tl_v3(-R, -R, -6 * s->d_max), tl_v3(R, R, top)));
  TL_CHECK(tl_dem_set_domain(*dem, &dom));
  TlContactLaw *law = NULL;
  TL_CHECK(make_law(s, &law));
  TL_CHECK(tl_dem_add_law(*dem, law, NULL));
  TlWall *w = NULL;
  TL_CHECK(tl_wall_trisurface_from_file(stl, NULL, &w, rep));
  TL_CHECK(tl_dem_add_wall(*dem, w, 0));
  TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), lid));
  TL_CHECK(tl_dem_add_wall(*dem, *lid, 0));
  tl_dem_set_gravity(*dem, tl_v3(0, 0, -9.81));
  tl_dem_set_threads(*dem, s->threads);
  return TL_OK;
}

static TlStatus timestep(const Settings *s, TlDem *dem, double *dt)
{
  double dtc, kmax, mmin;
  TL_CHECK(tl_dem_critical_timestep(dem, &dtc, &kmax, &mmin));
  *dt = s->dt_fraction * dtc;
  TL_CHECK(tl_dem_set_timestep(dem, *dt, 0));
  return TL_OK;
}

/* Least-squares slope of y against x. */
static double slope(const double *x, const double *y, size_t n, double *intercept)
{
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < n; ++i) sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
  double den = (double)n * sxx - sx * sx;
  double b = den != 0.0 ? ((double)n * sxy - sx * sy) / den : NAN;
  if (intercept) *intercept = (sy - b * sx) / (double)n;
  return b;
}

typedef struct {
  double W, t_flow, mass_out, mass_left, balance_error;
  int clogged;
} Discharge;

/* Where the run is, checkpointed with it: the stage (0 the settling, 1 + i
 * discharge i), the step to continue with in it, the steps of the stages
 * done; the settled packing and its figures; the results of the discharges
 * done; in a discharge, its samples of m(t) and its accumulators. */
typedef struct {
  const Settings *s;
  int64_t stage, k, done_steps, ns;
  size_t n_settled, cap;
  double rho_b, kinetic, total, removed, last_change, last_out;
  TlVec3 *x, *v;
  double *radius, *tt, *mm;
  Discharge res[MAX_ORIFICES];
  int stopped;
} Hopper;

enum { H_INTS = 5, H_REALS = 6, H_RESULT = 6 };

static TlStatus hopper_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const Hopper *h = object;
  const int64_t iv[H_INTS] = {h->stage, h->k, h->done_steps, h->ns, (int64_t)h->n_settled};
  const double rv[H_REALS] = {h->rho_b, h->kinetic, h->total, h->removed, h->last_change, h->last_out};
  double res[H_RESULT * MAX_ORIFICES];
  for (int i = 0; i < MAX_ORIFICES; ++i) {
    const Discharge *d = &h->res[i];
    const double a[H_RESULT] = {d->W, d->t_flow, d->mass_out, d->mass_left, d->balance_error, (double)d->clogged};
    memcpy(res + H_RESULT * i, a, sizeof a);
  }
  TL_CHECK(tl_checkpoint_write_int64s(w, group, "position", H_INTS, iv));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "figures", H_REALS, rv));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "results", H_RESULT * MAX_ORIFICES, res));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "sample_t", (size_t)h->ns, h->tt));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "sample_m", (size_t)h->ns, h->mm));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "settled_x", 3 * h->n_settled, (const double *)h->x));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "settled_v", 3 * h->n_settled, (const double *)h->v));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "settled_radius", h->n_settled, h->radius));
  return TL_OK;
}

/* Every value checked before the run uses it (a checkpoint is input). */
static TlStatus hopper_load(void *object, TlCheckpointReader *r, const char *group)
{
  Hopper *h = object;
  const Settings *s = h->s;
  int64_t iv[H_INTS];
  double rv[H_REALS], res[H_RESULT * MAX_ORIFICES];
  TL_CHECK(tl_checkpoint_read_int64s(r, group, "position", H_INTS, iv));
  TL_CHECK(tl_checkpoint_check_count(r, group, "position[0] (stage)", iv[0], 0, s->n_orifices));
  TL_CHECK(tl_checkpoint_check_count(r, group, "position[1] (step)", iv[1], 0, INT64_MAX / 4));
  TL_CHECK(tl_checkpoint_check_count(r, group, "position[2] (steps done)", iv[2], 0, INT64_MAX / 4));
  TL_CHECK(tl_checkpoint_check_count(r, group, "position[3] (samples)", iv[3], 0, 100000000));
  TL_CHECK(tl_checkpoint_check_count(r, group, "position[4] (settled grains)", iv[4], iv[0] > 0 ? s->n : 0, s->n));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "figures", H_REALS, rv));
  /* the bulk density is undefined (NaN) for a bed too low for its core */
  TL_CHECK(tl_checkpoint_check_finite(r, group, "figures", H_REALS - 1, rv + 1));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "results", H_RESULT * MAX_ORIFICES, res));
  for (int i = 0; i < H_RESULT * MAX_ORIFICES; ++i)
    if (!(i % H_RESULT == 0 && isnan(res[i]))) /* W is undefined without a steady flow */
      TL_CHECK(tl_checkpoint_check_finite(r, group, "results", 1, &res[i]));
  const size_t ns = (size_t)iv[3], n = (size_t)iv[4];
  if (ns > h->cap) {
    TL_CHECK(tl_realloc(&h->tt, ns, sizeof *h->tt));
    TL_CHECK(tl_realloc(&h->mm, ns, sizeof *h->mm));
    h->cap = ns;
  }
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "sample_t", ns, h->tt));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "sample_m", ns, h->mm));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "sample_t", ns, h->tt));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "sample_m", ns, h->mm));
  if (n != h->n_settled) {
    TL_CHECK(tl_realloc(&h->x, n ? n : 1, sizeof *h->x));
    TL_CHECK(tl_realloc(&h->v, n ? n : 1, sizeof *h->v));
    TL_CHECK(tl_realloc(&h->radius, n ? n : 1, sizeof *h->radius));
    h->n_settled = n;
  }
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "settled_x", 3 * n, (double *)h->x));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "settled_v", 3 * n, (double *)h->v));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "settled_radius", n, h->radius));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "settled_x", 3 * n, (const double *)h->x));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "settled_v", 3 * n, (const double *)h->v));
  TL_CHECK(tl_checkpoint_check_positive(r, group, "settled_radius", n, h->radius, 0));
  h->stage = iv[0], h->k = iv[1], h->done_steps = iv[2], h->ns = iv[3];
  h->rho_b = rv[0], h->kinetic = rv[1], h->total = rv[2], h->removed = rv[3], h->last_change = rv[4];
  h->last_out = rv[5];
  for (int i = 0; i < MAX_ORIFICES; ++i) {
    const double *a = res + H_RESULT * i;
    h->res[i] = (Discharge){a[0], a[1], a[2], a[3], a[4], a[5] != 0.0};
  }
  return TL_OK;
}

static const TlCheckpointOps hopper_checkpoint_ops = {
    .header = {"checkpoint", "hopper_discharge_v1", "stage, step, settled packing and results of hopper_discharge"},
    .save = hopper_save,
    .load = hopper_load,
};

/* At a step where the run may checkpoint (cum: the step of the whole run):
 * a checkpoint at each multiple of -checkpoint_every crossed since the last
 * chance (prev), and at -stop_step, which ends the run. */
static TlStatus maybe_checkpoint(Hopper *h, const TlCheckpoint *cp, double t, int64_t prev, int64_t cum)
{
  const Settings *s = h->s;
  const long ce = s->checkpoint_every;
  h->stopped = s->stop_step > 0 && cum >= s->stop_step;
  if ((ce > 0 && cum / ce > prev / ce) || h->stopped) {
    char path[4200];
    snprintf(path, sizeof path, "%s/checkpoint.h5", s->out);
    TL_CHECK(tl_checkpoint_save(cp, path, t, cum));
  }
  return TL_OK;
}

/* One discharge from the settled state (h->x, v, radius); from the
 * checkpoint `restart` when given (its stage is this discharge). */
static TlStatus discharge(Hopper *h, TlOptions *o, int index, double D, const char *stl, double top,
                          const char *restart, Discharge *out)
{
  const Settings *s = h->s;
  const size_t n = h->n_settled;
  TlDem *dem = NULL;
  TlWall *lid = NULL;
  TlParticleWriter *writer = NULL;
  TlTimeSeries *ts = NULL;
  TlCheckpoint *cp = NULL;
  TlStatus st = TL_OK;
  TlSurfaceReport rep;
  TL_CHECK_GOTO(st, make_world(s, stl, top, &dem, &lid, &rep), done);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK_GOTO(st, tl_particles_add_species(P, "grains", s->density, 0.5 * s->d_min, 0.5 * s->d_max, &sp), done);
  TL_CHECK_GOTO(st, tl_particles_reserve(P, n), done);
  double total = 0.0;
  for (size_t i = 0; i < n; ++i) TL_CHECK_GOTO(st, tl_dem_add_particle(dem, h->x[i], h->v[i], h->radius[i], sp, NULL), done);
  for (size_t i = 0; i < P->n; ++i) total += P->mass[i];
  TL_CHECK_GOTO(st, tl_wall_plane_set_velocity(lid, tl_v3(0, 0, -s->lid_speed)), done);
  double dt = 0.0;
  TL_CHECK_GOTO(st, timestep(s, dem, &dt), done);
  TL_CHECK_GOTO(st, tl_dem_setup(dem), done);
  char name[64], path[4200];
  snprintf(name, sizeof name, "particles_%d", index);
  if (s->snapshots > 0) TL_CHECK_GOTO(st, tl_particle_writer_create(s->out, name, &writer), done);
  snprintf(path, sizeof path, "%s/discharge_%d", s->out, index);
  static const TlColumn cols[] = {{"time", "s"}, {"mass_out", "kg"}, {"grains_left", ""}};
  TL_CHECK_GOTO(st, tl_timeseries_create(path, TL_TIMESERIES_CSV, 3, cols, &ts), done);
  const long every = (long)fmax(1.0, floor(2e-3 / dt)); /* a sample every 2 ms */
  const long steps = (long)ceil(s->t_discharge / dt);
  const long snap_every = s->snapshots > 0 ? (long)fmax(1.0, (double)steps / (double)s->snapshots) : 0;
  const double z_remove = -4.0 * s->d_max;
  size_t cap = (size_t)(steps / every) + 4;
  if (cap > h->cap) {
    TL_CHECK_GOTO(st, tl_realloc(&h->tt, cap, sizeof *h->tt), done);
    TL_CHECK_GOTO(st, tl_realloc(&h->mm, cap, sizeof *h->mm), done);
    h->cap = cap;
  }
  h->k = 0, h->ns = 0, h->total = total, h->removed = 0.0, h->last_change = 0.0, h->last_out = -1.0;
  TL_CHECK_GOTO(st, tl_checkpoint_create(&cp), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, o), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "hopper", &hopper_checkpoint_ops, h), done);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "table", &tl_timeseries_checkpoint_ops, ts), done);
  if (writer) TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "snapshots", &tl_particle_writer_checkpoint_ops, writer), done);
  if (restart) {
    TL_CHECK_GOTO(st, tl_checkpoint_load(cp, restart, NULL, NULL), done);
    if ((size_t)h->ns > cap || h->total != total) {
      st = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "checkpoint %s: %lld samples (at most %zu) and a mass of "
                        "%.17g kg (this scene %.17g kg) do not fit this discharge", restart, (long long)h->ns, cap,
                        h->total, total);
      goto done;
    }
    tl_printf("restarted from %s at step %lld of discharge %d\n", restart, (long long)h->k, index);
  }
  TlProgress prog;
  char label[64];
  snprintf(label, sizeof label, "discharge D = %.3g mm", 1e3 * D);
  tl_progress_init(&prog, label, (double)steps);
  out->clogged = 0;
  const long k0 = (long)h->k;
  long k = k0;
  for (;; ++k) {
    if (k > k0) {
      h->k = k;
      TL_CHECK_GOTO(st, maybe_checkpoint(h, cp, tl_dem_time(dem), h->done_steps + k - 1, h->done_steps + k), done);
      if (h->stopped) goto done;
    }
    if (k % every == 0) {
      /* discharged: removed, or centre below the orifice plane */
      double inside = 0.0;
      for (size_t i = 0; i < P->n; ++i)
        if (P->x[i].z >= 0.0) inside += P->mass[i];
      double t = tl_dem_time(dem), mout = total - inside;
      double row[3] = {t, mout, (double)P->n};
      TL_CHECK_GOTO(st, tl_timeseries_append(ts, row), done);
      if ((size_t)h->ns < cap) h->tt[h->ns] = t, h->mm[h->ns] = mout, ++h->ns;
      if (mout > h->last_out) h->last_out = mout, h->last_change = t;
      if (mout >= 0.9 * total) break;
      if (t - h->last_change > 0.2) { /* no grain out for 0.2 s: an arch blocks the orifice */
        out->clogged = 1;
        break;
      }
    }
    if (snap_every && k % snap_every == 0) {
      TlParticleView view;
      tl_particle_view_of(P, &view); /* with ids and species */
      TL_CHECK_GOTO(st, tl_particle_writer_write(writer, k, tl_dem_time(dem), &view), done);
    }
    if (k >= steps) break;
    TL_CHECK_GOTO(st, tl_dem_step(dem, 1), done);
    for (size_t i = P->n; i-- > 0;)
      if (P->x[i].z < z_remove) {
        h->removed += P->mass[i];
        TL_CHECK_GOTO(st, tl_dem_remove_particle(dem, i), done);
      }
    if (k % 500 == 0) tl_progress_update(&prog, (double)k);
  }
  tl_progress_finish(&prog);
  h->k = k;
  /* steady part: between 15% and 60% of the mass out */
  const size_t ns = (size_t)h->ns;
  const double *tt = h->tt, *mm = h->mm;
  size_t i0 = 0, i1 = 0;
  while (i0 < ns && mm[i0] < 0.15 * total) ++i0;
  i1 = i0;
  while (i1 < ns && mm[i1] <= 0.6 * total) ++i1;
  out->W = i1 - i0 >= 5 ? slope(tt + i0, mm + i0, i1 - i0, NULL) : NAN;
  out->t_flow = i1 > i0 ? tt[i1 - 1] - tt[i0] : 0.0;
  double left = 0.0;
  for (size_t i = 0; i < P->n; ++i) left += P->mass[i];
  out->mass_out = total - left;
  out->mass_left = left;
  /* every grain is in the world or was removed */
  out->balance_error = fabs(left + h->removed - total) / total;
done:
  tl_checkpoint_destroy(&cp);
  if (ts) {
    TlStatus sc = tl_timeseries_close(&ts);
    if (st == TL_OK) st = sc;
  }
  tl_particle_writer_destroy(&writer);
  tl_dem_destroy(&dem);
  return st;
}

static TlStatus run(int argc, char **argv)
{
  double wall0 = tl_wtime();
  TlOptions *o = NULL;
  Settings s;
  TlStatus st = options(argc, argv, &o, &s);
  if (st != TL_OK) {
    tl_options_destroy(&o);
    return st;
  }
  TlDem *dem = NULL;
  TlSurfaceMesh *fill = NULL, *hop = NULL;
  double *sites = NULL;
  TlCheckpoint *cp = NULL;
  FILE *rates = NULL;
  const double dm = 0.5 * (s.d_min + s.d_max), g = 9.81;
  TL_CHECK_GOTO(st, tl_output_dir_prepare(s.out), done);
  /* fill region: the bin's interior shrunk by 0.6 d_max, as high as the
   * grains need at a lattice pitch of 1.05 d_max */
  const double pitch = 1.05 * s.d_max, rf = s.radius - 0.6 * s.d_max, z0 = 0.6 * s.d_max;
  double per_layer = TL_PI * rf * rf / (pitch * pitch);
  double z1 = z0 + pitch * (ceil((double)s.n / (0.9 * per_layer)) + 1.0);
  TL_CHECK_GOTO(st, fill_mesh(rf, z0, z1, (int)s.segments, &fill), done);
  char path[4200];
  snprintf(path, sizeof path, "%s/fill_region.stl", s.out);
  TL_CHECK_GOTO(st, tl_stl_write(path, fill, 1), done);
  size_t n_sites = 0;
  TL_CHECK_GOTO(st, tl_surface_mesh_lattice_inside(fill, pitch, (size_t)s.n, &sites, &n_sites), done);
  if (n_sites < (size_t)s.n) {
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "the fill region holds %zu lattice sites, fewer than -n %ld", n_sites, s.n);
    goto done;
  }
  const double top = z1 + 2.0 * s.d_max;
  /* hopper files: one per orifice (or the given one) */
  char stl[MAX_ORIFICES][4200];
  for (int k = 0; k < s.n_orifices; ++k) {
    if (s.stl[0]) {
      snprintf(stl[k], sizeof stl[k], "%s", s.stl);
      continue;
    }
    snprintf(stl[k], sizeof stl[k], "%s/hopper_%d.stl", s.out, k);
    TL_CHECK_GOTO(st, hopper_mesh(0.5 * s.orifice[k] * dm, s.radius, top, (int)s.segments, &hop), done);
    TL_CHECK_GOTO(st, tl_stl_write(stl[k], hop, 1), done);
    if (k == 0) tl_printf("hopper: radius %g m, height %g m, %zu triangles per STL, orifices", s.radius, top, hop->n_triangles);
    tl_printf(" %g mm%s", 1e3 * s.orifice[k] * dm, k + 1 == s.n_orifices ? "\n" : ",");
    tl_surface_mesh_destroy(&hop);
  }
  Hopper h;
  memset(&h, 0, sizeof h);
  h.s = &s;
  if (s.restart[0]) {
    /* the stage first: it says what to rebuild */
    TlCheckpoint *head = NULL;
    st = tl_checkpoint_create(&head);
    if (st == TL_OK) st = tl_checkpoint_add(head, "options", &tl_options_checkpoint_ops, o);
    if (st == TL_OK) st = tl_checkpoint_add(head, "hopper", &hopper_checkpoint_ops, &h);
    if (st == TL_OK) st = tl_checkpoint_load(head, s.restart, NULL, NULL);
    tl_checkpoint_destroy(&head);
    if (st != TL_OK) goto done;
  }
  const int64_t first_stage = h.stage;
  double rho_b = h.rho_b, kinetic = h.kinetic;
  size_t n = h.n_settled;
  if (h.stage == 0) {
    /* settle on the lid */
    TlWall *lid = NULL;
    TlSurfaceReport rep;
    TL_CHECK_GOTO(st, make_world(&s, stl[0], top, &dem, &lid, &rep), done);
    tl_printf("hopper surface: %s, closed %d, repaired (%zu vertices merged, %zu triangles removed, %zu flipped, %zu holes)\n",
              stl[0], rep.closed, rep.vertices_merged, rep.triangles_removed, rep.triangles_flipped, rep.holes);
    TlParticles *P = tl_dem_particles(dem);
    int sp;
    TL_CHECK_GOTO(st, tl_particles_add_species(P, "grains", s.density, 0.5 * s.d_min, 0.5 * s.d_max, &sp), done);
    TL_CHECK_GOTO(st, tl_particles_reserve(P, (size_t)s.n), done);
    uint64_t rng = 2026;
    for (long i = 0; i < s.n; ++i) {
      double r = tl_species_sample_radius(&P->species_table[sp], &rng);
      TlVec3 xi = tl_v3(sites[3 * i], sites[3 * i + 1], sites[3 * i + 2]);
      TlVec3 vi = tl_v3(0.05 * (tl_random_uniform(&rng) - 0.5), 0.05 * (tl_random_uniform(&rng) - 0.5), 0.0);
      TL_CHECK_GOTO(st, tl_dem_add_particle(dem, xi, vi, r, sp, NULL), done);
    }
    double dt = 0.0;
    TL_CHECK_GOTO(st, timestep(&s, dem, &dt), done);
    TL_CHECK_GOTO(st, tl_dem_setup(dem), done);
    long settle_steps = (long)ceil(s.t_settle / dt);
    tl_printf("hopper_discharge: %ld grains, d in [%g, %g] m, k_n = %g N/m, dt = %g s, settling %ld steps\n", s.n, s.d_min,
              s.d_max, s.E * dm, dt, settle_steps);
    TL_CHECK_GOTO(st, tl_checkpoint_create(&cp), done);
    TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, o), done);
    TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), done);
    TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "hopper", &hopper_checkpoint_ops, &h), done);
    if (s.restart[0]) {
      TL_CHECK_GOTO(st, tl_checkpoint_load(cp, s.restart, NULL, NULL), done);
      tl_printf("restarted from %s at step %lld of the settling\n", s.restart, (long long)h.k);
    }
    TlProgress prog;
    tl_progress_init(&prog, "settle", (double)settle_steps);
    for (long k = (long)h.k; k < settle_steps; k += 1000) {
      const long b = settle_steps - k < 1000 ? settle_steps - k : 1000;
      TL_CHECK_GOTO(st, tl_dem_step(dem, b), done);
      tl_progress_update(&prog, (double)k);
      h.k = k + b;
      TL_CHECK_GOTO(st, maybe_checkpoint(&h, cp, tl_dem_time(dem), k, h.k), done);
      if (h.stopped) break;
    }
    tl_progress_finish(&prog);
    tl_checkpoint_destroy(&cp);
    if (h.stopped) goto stopped;
    TlDemEnergy en;
    TL_CHECK_GOTO(st, tl_dem_energy(dem, &en), done);
    /* bulk density: grains whose centre lies in the core of the bed (2 d_max
     * from the walls and from the bed's bottom and top) */
    double bed_top = 0.0, mass_core = 0.0;
    for (size_t i = 0; i < P->n; ++i) bed_top = fmax(bed_top, P->x[i].z + P->radius[i]);
    double rc = s.radius - 2 * s.d_max, zc0 = 2 * s.d_max, zc1 = bed_top - 2 * s.d_max;
    for (size_t i = 0; i < P->n; ++i) {
      TlVec3 p = P->x[i];
      if (p.x * p.x + p.y * p.y < rc * rc && p.z > zc0 && p.z < zc1) mass_core += P->mass[i];
    }
    rho_b = zc1 > zc0 ? mass_core / (TL_PI * rc * rc * (zc1 - zc0)) : NAN;
    kinetic = en.kinetic_translational + en.kinetic_rotational;
    tl_printf("settled: bed height %.4g m, bulk density %.4g kg/m^3 (packing fraction %.3f), kinetic energy %.3g J\n", bed_top,
              rho_b, rho_b / s.density, kinetic);
    n = P->n;
    TL_CHECK_GOTO(st, tl_calloc(&h.x, n, sizeof *h.x), done);
    TL_CHECK_GOTO(st, tl_calloc(&h.v, n, sizeof *h.v), done);
    TL_CHECK_GOTO(st, tl_calloc(&h.radius, n, sizeof *h.radius), done);
    memcpy(h.x, P->x, n * sizeof *h.x);
    memcpy(h.v, P->v, n * sizeof *h.v);
    memcpy(h.radius, P->radius, n * sizeof *h.radius);
    h.n_settled = n;
    h.rho_b = rho_b, h.kinetic = kinetic;
    h.done_steps = settle_steps, h.stage = 1, h.k = 0;
    tl_dem_destroy(&dem);
  }

  /* discharges */
  Discharge *res = h.res;
  double worst_balance = 0.0, Dv[MAX_ORIFICES], W25[MAX_ORIFICES];
  int n_fit = 0;
  snprintf(path, sizeof path, "%s/rates.csv", s.out);
  rates = fopen(path, "w");
  if (!rates) {
    st = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "cannot write %s", path);
    goto done;
  }
  fprintf(rates, "# D [m], D/d_mean, W [kg/s], clogged, steady window [s]; d_mean %.9g m, rho_b %.9g kg/m^3, g %.9g m/s^2\n", dm,
          rho_b, g);
  for (int k = 0; k < s.n_orifices; ++k) {
    double D = s.orifice[k] * dm;
    if (k + 1 >= h.stage) {
      const int resume = s.restart[0] && first_stage == k + 1;
      TL_CHECK_GOTO(st, discharge(&h, o, k, D, stl[k], top, resume ? s.restart : NULL, &res[k]), done);
      if (h.stopped) goto stopped;
      h.done_steps += h.k, h.stage = k + 2, h.k = 0, h.ns = 0;
      tl_printf("orifice D = %.4g mm (%.3g d): W = %.5g kg/s over %.3g s of steady flow, %.4g kg out, %.4g kg left%s\n", 1e3 * D,
                s.orifice[k], res[k].W, res[k].t_flow, res[k].mass_out, res[k].mass_left, res[k].clogged ? ", CLOGGED" : "");
    }
    worst_balance = fmax(worst_balance, res[k].balance_error);
    fprintf(rates, "%.9g,%.9g,%.9g,%d,%.6g\n", D, s.orifice[k], res[k].W, res[k].clogged, res[k].t_flow);
    if (isfinite(res[k].W) && res[k].W > 0.0) Dv[n_fit] = D, W25[n_fit] = pow(res[k].W, 0.4), ++n_fit;
  }
  /* Beverloo: W^(2/5) = (C rho_b sqrt g)^(2/5) (D - k d) */
  double C = NAN, kk = NAN, C15 = NAN;
  if (n_fit >= 2) {
    double b, a = slope(Dv, W25, (size_t)n_fit, &b);
    C = pow(a, 2.5) / (rho_b * sqrt(g));
    kk = -b / (a * dm);
  }
  if (n_fit >= 1) {
    double sum = 0.0;
    int m = 0;
    for (int k = 0; k < n_fit; ++k)
      if (Dv[k] > 1.5 * dm) sum += pow(W25[k], 2.5) / (rho_b * sqrt(g) * pow(Dv[k] - 1.5 * dm, 2.5)), ++m;
    C15 = m ? sum / m : NAN;
  }
  fprintf(rates, "# fit: C %.6g k %.6g; C with k = 1.5: %.6g\n", C, kk, C15);
  fclose(rates);
  rates = NULL;
  tl_printf("Beverloo fit over %d orifices: C = %.4g, k = %.4g (with k = 1.5 fixed: C = %.4g)\n", n_fit, C, kk, C15);
  int monotone = 1;
  for (int k = 1; k < s.n_orifices; ++k)
    if (!(res[k].W > res[k - 1].W) || !(s.orifice[k] > s.orifice[k - 1])) monotone = 0;
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "n", (long)n);
  tl_summary_real(&sum, "rho_b", rho_b);
  tl_summary_real(&sum, "packing_fraction", rho_b / s.density);
  tl_summary_real(&sum, "settled_kinetic", kinetic);
  for (int k = 0; k < s.n_orifices; ++k) {
    char key[32];
    snprintf(key, sizeof key, "W_%d", k + 1);
    if (isfinite(res[k].W)) tl_summary_real(&sum, key, res[k].W);
    else tl_summary_string(&sum, key, "none");
  }
  int clogged = 0;
  for (int k = 0; k < s.n_orifices; ++k) clogged += res[k].clogged;
  tl_summary_int(&sum, "clogged", clogged);
  tl_summary_int(&sum, "rate_grows_with_D", monotone);
  if (isfinite(C)) tl_summary_real(&sum, "C", C), tl_summary_real(&sum, "k", kk);
  else tl_summary_string(&sum, "C", "none"), tl_summary_string(&sum, "k", "none");
  if (isfinite(C15)) tl_summary_real(&sum, "C_k_fixed", C15); /* C with k = 1.5 */
  tl_summary_real(&sum, "mass_balance_error", worst_balance);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  st = tl_summary_print(&sum, stdout);
  goto done;
stopped:
  tl_printf("stopped after step %lld (-stop_step): %s/checkpoint.h5 continues the run with -restart\n",
            (long long)(h.done_steps + h.k), s.out);
  {
    TlSummary part;
    tl_summary_init(&part);
    tl_summary_int(&part, "n", s.n);
    tl_summary_int(&part, "steps", (long)(h.done_steps + h.k));
    tl_summary_string(&part, "stopped", "true");
    tl_summary_real(&part, "wall", tl_wtime() - wall0);
    st = tl_summary_print(&part, stdout);
  }
done:
  tl_checkpoint_destroy(&cp);
  tl_free(&h.x);
  tl_free(&h.v);
  tl_free(&h.radius);
  tl_free(&h.tt);
  tl_free(&h.mm);
  if (rates) fclose(rates);
  tl_dem_destroy(&dem);
  tl_surface_mesh_destroy(&fill);
  tl_surface_mesh_destroy(&hop);
  tl_free(&sites);
  tl_options_destroy(&o);
  return st;
}

int main(int argc, char **argv)
{
  TlStatus s = tl_initialize();
  if (s == TL_OK) s = run(argc, argv);
  return tl_driver_exit(s);
}
