/* A deformable cone pushed at constant speed into a settled granular bed
 * through the surface coupling (seeds/001 §5.1), at one or more CG widths.
 *
 * Bed: polydisperse spheres poured on a jittered lattice into a box of side
 * -box (planes: floor and four sides), settled under gravity for -t_settle
 * with the contact law's damping and friction.  Cone: a closed triangulated
 * surface (apex down, axis z, base radius -radius, apex half-angle
 * -half_angle, -rim_segments flank triangles) meshed into Tet4 or Tet10
 * elements through CGAL Mesh_3 (tl_mesh_from_surface.h; -mesh_h), a
 * finite-strain solid (-material).  Its base face is driven down at -speed (all three
 * components prescribed: u = (0, 0, -V t)); every other face is the coupled
 * boundary, a triangulated wall the grains touch, whose contact forces come
 * back to the solid as CG tractions of width c (c = 0: the point-source
 * limit).  The apex starts -gap above the bed surface (the highest grain
 * top within the cone's radius of its axis) and goes down to -depth.
 *
 * Each width of -cg_widths (in mean grain diameters) runs from the same
 * settled bed (positions kept, velocities zeroed) and the same mesh.
 * Energy balance: E = FE kinetic + strain + DEM kinetic + contact elastic +
 * gravitational + dissipated - W_drive, with W_drive the work the drive
 * does on the base (the reactions there times the prescribed velocity,
 * trapezoidal rule per FE step); a coupling that creates no energy keeps E
 * constant, and the balance error is max |E - E_0| / W_drive.
 *
 * Output in -output_dir: settle.csv (bed energies), force_depth_c<k>.csv
 * (per width k: time, depth, resistance F_z of the grains on the cone,
 * base reaction, contacts, energies, balance), cone_c<k>.xmf (the solid with
 * its displacement and per-element stress: Cauchy, von Mises) and
 * particles_c<k>.xmf for ParaView.  Plot: tools/plot_penetrometer.py.
 * Last line: summary: ... */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_coupled_loop.h"
#include "tl_dem.h"
#include "tl_mesh_from_surface.h"
#include "tl_particle_snapshot.h"
#include "tl_scoupling.h"
#include "tl_solid_output.h"
#include "tl_timeseries.h"

#define MAX_WIDTHS 4

typedef struct {
  long n, rim, substeps, snapshots, samples, reuse;
  double d_min, d_max, rho_g, E_g, restitution, mu, box, pour_height, t_settle, dt_fraction, fe_dt_fraction, contacts_per_node;
  double radius, tip_radius, half_angle, mesh_h, E_c, nu_c, rho_c, speed, gap, depth;
  double widths[MAX_WIDTHS];
  int n_widths, tet10, threads, explicit_fe;
  const char *out, *material, *surface;
  double surface_scale, body_h; /* body_h: the body's height (m), set once it is built */
} Settings;

static TlStatus options(int argc, char **argv, TlOptions **o, Settings *s)
{
  TL_CHECK(tl_options_create(argc, argv,
                             "A deformable cone, meshed into tetrahedra from a closed surface, pushed at constant "
                             "speed into a settled granular bed through the surface coupling; resistance against "
                             "depth at CG widths c = 0 and c > 0, energy balance, the cone's stress field.",
                             o));
  TL_CHECK(tl_options_get_int(*o, "-n", 2500, 10, 10000000, "number of grains", &s->n));
  TL_CHECK(tl_options_get_real(*o, "-d_min", 2.0e-3, 1e-9, 1e3, "m", "smallest grain diameter", &s->d_min));
  TL_CHECK(tl_options_get_real(*o, "-d_max", 3.0e-3, 1e-9, 1e3, "m", "largest grain diameter", &s->d_max));
  TL_CHECK(tl_options_get_real(*o, "-rho_g", 2500, 1e-6, 1e6, "kg/m^3", "grain density", &s->rho_g));
  TL_CHECK(tl_options_get_real(*o, "-E_g", 1e7, 1.0, 1e12, "Pa",
                               "grain modulus: linear contact stiffness k_n = E_g d_mean (soft, for quick runs)", &s->E_g));
  TL_CHECK(tl_options_get_real(*o, "-restitution", 0.5, 1e-3, 1.0, "", "normal restitution of a contact", &s->restitution));
  TL_CHECK(tl_options_get_real(*o, "-mu", 0.5, 0.0, 10.0, "", "Coulomb friction coefficient (grains and cone)", &s->mu));
  TL_CHECK(tl_options_get_real(*o, "-box", 0.04, 1e-6, 1e3, "m", "box side (x and y)", &s->box));
  TL_CHECK(tl_options_get_real(*o, "-pour_height", 0.0, 0.0, 1e3, "m",
                               "height of the pour lattice's top layer (0: just high enough for -n grains)", &s->pour_height));
  TL_CHECK(tl_options_get_real(*o, "-t_settle", 0.25, 0.0, 1e6, "s", "settling time of the bed", &s->t_settle));
  TL_CHECK(tl_options_get_real(*o, "-dt_fraction", 0.2, 1e-6, 1.0, "", "DEM time step over the critical one", &s->dt_fraction));
  TL_CHECK(tl_options_get_string(*o, "-surface", "",
                                 "closed surface file of the body (STL or Gmsh; repaired, then meshed) instead of the "
                                 "generated cone: its top must be a flat face normal to +z, where the drive holds it; "
                                 "it is centred on the box's axis with its lowest point -gap above the bed; -radius is "
                                 "then its half-width", &s->surface));
  TL_CHECK(tl_options_get_real(*o, "-surface_scale", 1.0, 1e-12, 1e12, "", "scale of the -surface file's coordinates to "
                               "metres (1e-3 for a file in mm)", &s->surface_scale));
  TL_CHECK(tl_options_get_real(*o, "-radius", 6e-3, 1e-9, 1e3, "m", "cone base radius R", &s->radius));
  TL_CHECK(tl_options_get_real(*o, "-tip_radius", 1.5e-3, 0.0, 1e3, "m",
                               "radius of the cone's flat tip (0: sharp; a sharp tip's nodes are so light that the "
                               "explicit contact springs need a tiny FE step)", &s->tip_radius));
  TL_CHECK(tl_options_get_real(*o, "-half_angle", 30.0, 5.0, 85.0, "degrees", "cone apex half-angle (CPT: 30)", &s->half_angle));
  TL_CHECK(tl_options_get_int(*o, "-rim_segments", 32, 3, 100000, "segments of the cone surface's rim", &s->rim));
  TL_CHECK(tl_options_get_real(*o, "-mesh_h", 0.0, 0.0, 1e3, "m", "tetrahedron and surface triangle size (0: R / 3)", &s->mesh_h));
  int element;
  static const char *const elements[] = {"tet4", "tet10", NULL};
  TL_CHECK(tl_options_get_choice(*o, "-element", "tet4", elements, "element type of the cone", &element));
  s->tet10 = element == 1;
  TL_CHECK(tl_options_get_real(*o, "-E_c", 2e7, 1.0, 1e13, "Pa", "cone Young's modulus (20 MPa: a rubber-like cone the explicit step resolves)", &s->E_c));
  TL_CHECK(tl_options_get_string(*o, "-material", "hooke", "cone material: a registered finite-strain law with E, nu and "
                                 "density (hooke: St Venant-Kirchhoff; neo_hookean)", &s->material));
  TL_CHECK(tl_options_get_real(*o, "-nu_c", 0.3, 0.0, 0.49, "", "cone Poisson's ratio", &s->nu_c));
  TL_CHECK(tl_options_get_real(*o, "-rho_c", 2000, 1e-6, 1e6, "kg/m^3", "cone density", &s->rho_c));
  TL_CHECK(tl_options_get_real(*o, "-speed", 0.2, 1e-9, 1e3, "m/s", "push speed V of the cone's base", &s->speed));
  TL_CHECK(tl_options_get_real(*o, "-gap", 0.5e-3, 0.0, 1e3, "m", "apex height above the bed surface at the start", &s->gap));
  TL_CHECK(tl_options_get_real(*o, "-depth", 0.012, 1e-9, 1e3, "m", "apex depth below the bed surface at the end", &s->depth));
  TL_CHECK(tl_options_get_real_list_range(*o, "-cg_widths", "0,1", 0.0, 100.0, "mean grain diameters",
                                          "CG widths c of the runs (0: Dirac, Eq. 16)", s->widths, MAX_WIDTHS, &s->n_widths));
  int fem;
  static const char *const fems[] = {"central_difference", "newmark", NULL};
  TL_CHECK(tl_options_get_choice(*o, "-fem", "central_difference", fems,
                                 "cone time stepper: explicit with lumped mass, one FE step per DEM step (the wall "
                                 "kinetics then are the solid's own, no lag), or implicit Newmark", &fem));
  s->explicit_fe = fem == 0;
  TL_CHECK(tl_options_get_int(*o, "-substeps", 1, 1, 1000, "DEM steps per FE step", &s->substeps));
  TL_CHECK(tl_options_get_real(*o, "-fe_dt_fraction", 0.9, 1e-6, 1.0, "",
                               "explicit cone: largest FE step over its critical one; a shorter step than the bed's "
                               "then becomes the push's DEM step too (Tet10 at the defaults)", &s->fe_dt_fraction));
  TL_CHECK(tl_options_get_real(*o, "-contacts_per_node", 4, 0.0, 1000.0, "",
                               "explicit cone: grains whose contact springs one surface node may carry at once, in "
                               "its stable step", &s->contacts_per_node));
  TL_CHECK(tl_options_get_int(*o, "-reuse", 20, 1, 100000, "Newton: refactorise the FE tangent every n iterations",
                              &s->reuse));
  TL_CHECK(tl_options_get_int(*o, "-samples", 200, 2, 10000000, "rows of each force-depth table", &s->samples));
  TL_CHECK(tl_options_get_int(*o, "-snapshots", 10, 0, 100000, "ParaView snapshots per run (0: none)", &s->snapshots));
  long th;
  TL_CHECK(tl_options_get_int(*o, "-threads", 0, 0, 1024, "OpenMP threads (0: default)", &th));
  s->threads = (int)th;
  TL_CHECK(tl_options_get_string(*o, "-output_dir", "results/penetrometer", "output folder", &s->out));
  TL_CHECK(tl_output_dir_check(s->out));
  return tl_options_finish(*o, stdout);
}

static TlStatus check_settings(const Settings *s)
{
  if (s->d_max < s->d_min) TL_ERROR(TL_ERR_ARG, "-d_max %g m is smaller than -d_min %g m", s->d_max, s->d_min);
  /* The side walls hold the bed: a box under four cone radii lets them
   * carry the cone's load. */
  if (!(s->box >= 4.0 * s->radius))
    TL_ERROR(TL_ERR_ARG, "-box %g m is below four cone radii (4 x -radius %g m = %g m): the side walls would carry "
             "the cone", s->box, s->radius, 4.0 * s->radius);
  if (!(s->tip_radius < s->radius))
    TL_ERROR(TL_ERR_ARG, "-tip_radius %g m must be below -radius %g m", s->tip_radius, s->radius);
  if (!(s->radius >= s->d_max))
    TL_ERROR(TL_ERR_ARG, "-radius %g m is below the largest grain diameter %g m: the cone would meet single grains",
             s->radius, s->d_max);
  double pitch = 1.05 * s->d_max, per_side = floor((s->box - pitch) / pitch);
  if (!(per_side >= 2.0)) TL_ERROR(TL_ERR_ARG, "-box %g m holds fewer than two grains of %g m across", s->box, s->d_max);
  return TL_OK;
}

static TlStatus make_law(const Settings *s, TlContactLaw **law)
{
  TL_CHECK(tl_contact_law_create("linear", "coulomb", NULL, NULL, law));
  TL_CHECK(tl_contact_law_set(*law, "k_n", s->E_g * 0.5 * (s->d_min + s->d_max)));
  TL_CHECK(tl_contact_law_set(*law, "restitution", s->restitution));
  TL_CHECK(tl_contact_law_set(*law, "mu", s->mu));
  return tl_contact_law_setup(*law);
}

/* The box: floor and four sides. */
static TlStatus add_box(TlDem *dem, double box)
{
  const TlVec3 pts[5] = {{0, 0, 0}, {0, 0, 0}, {box, 0, 0}, {0, 0, 0}, {0, box, 0}};
  const TlVec3 nrm[5] = {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  for (int k = 0; k < 5; ++k) {
    TlWall *w = NULL;
    TL_CHECK(tl_wall_plane_create(pts[k], nrm[k], &w));
    TL_CHECK(tl_dem_add_wall(dem, w, 0));
  }
  return TL_OK;
}

/* The settled bed, kept to start every run from. */
typedef struct {
  size_t n;
  TlVec3 *x;
  double *r;
  double dt, surface, kinetic, packing;
} Bed;

static TlStatus settle(const Settings *s, Bed *bed)
{
  TlStatus st = TL_OK;
  TlDem *dem = NULL;
  TlContactLaw *law = NULL;
  TlTimeSeries *ts = NULL;
  const double pitch = 1.05 * s->d_max;
  const int per_side = (int)floor((s->box - pitch) / pitch);
  const long layers = (s->n + (long)per_side * per_side - 1) / ((long)per_side * per_side);
  const double top = s->pour_height > 0.0 ? s->pour_height : pitch * (layers + 1.0);
  if (layers * pitch > top - 0.5 * pitch)
    TL_ERROR(TL_ERR_ARG, "-n %ld grains need %ld lattice layers of %g m: -pour_height %g m is too low", s->n, layers,
             pitch, s->pour_height);
  TL_CHECK_GOTO(st, tl_dem_create(&dem), done);
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  TL_CHECK_GOTO(st, tl_domain_init_open(&dom, tl_v3(0, 0, 0), tl_v3(s->box, s->box, top + pitch)), done);
  TL_CHECK_GOTO(st, tl_dem_set_domain(dem, &dom), done);
  int sp;
  TL_CHECK_GOTO(st, tl_particles_add_species(P, "grains", s->rho_g, 0.5 * s->d_min, 0.5 * s->d_max, &sp), done);
  uint64_t rng = 2026;
  TL_CHECK_GOTO(st, tl_particles_reserve(P, (size_t)s->n), done);
  for (long k = 0; k < s->n; ++k) {
    long layer = k / ((long)per_side * per_side), in = k % ((long)per_side * per_side);
    double jx = 0.02 * pitch * (tl_random_uniform(&rng) - 0.5), jy = 0.02 * pitch * (tl_random_uniform(&rng) - 0.5);
    TlVec3 x = {pitch * (1.0 + (double)(in % per_side)) + jx, pitch * (1.0 + (double)(in / per_side)) + jy,
                top - pitch * (double)layer};
    TlVec3 v = {0.05 * (tl_random_uniform(&rng) - 0.5), 0.05 * (tl_random_uniform(&rng) - 0.5), 0.0};
    TL_CHECK_GOTO(st, tl_dem_add_particle(dem, x, v, tl_species_sample_radius(&P->species_table[sp], &rng), sp, NULL), done);
  }
  TL_CHECK_GOTO(st, make_law(s, &law), done);
  TL_CHECK_GOTO(st, tl_dem_add_law(dem, law, NULL), done);
  law = NULL;
  TL_CHECK_GOTO(st, add_box(dem, s->box), done);
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  tl_dem_set_threads(dem, s->threads);
  double dtc, kmax, mmin;
  TL_CHECK_GOTO(st, tl_dem_critical_timestep(dem, &dtc, &kmax, &mmin), done);
  bed->dt = s->dt_fraction * dtc;
  TL_CHECK_GOTO(st, tl_dem_set_timestep(dem, bed->dt, 0), done);
  TL_CHECK_GOTO(st, tl_dem_setup(dem), done);
  char *base = NULL;
  TL_CHECK_GOTO(st, tl_path_join(s->out, "settle", &base), done);
  static const TlColumn cols[] = {{"time", "s"}, {"kinetic", "J"}, {"elastic", "J"}, {"gravitational", "J"},
                                  {"dissipated", "J"}, {"total", "J"}};
  st = tl_timeseries_create(base, TL_TIMESERIES_CSV, 6, cols, &ts);
  tl_free(&base);
  if (st) goto done;
  long steps = (long)ceil(s->t_settle / bed->dt), every = steps / 50 > 0 ? steps / 50 : 1;
  tl_printf("settling %ld grains, d in [%g, %g] m, dt = %.3g s, %ld steps\n", s->n, s->d_min, s->d_max, bed->dt, steps);
  TlProgress prog;
  tl_progress_init(&prog, "settle", (double)steps);
  TlDemEnergy en;
  for (long k = 0; k <= steps; ++k) {
    if (k % every == 0 || k == steps) {
      TL_CHECK_GOTO(st, tl_dem_energy(dem, &en), done);
      double row[6] = {tl_dem_time(dem), en.kinetic_translational + en.kinetic_rotational, en.elastic,
                       en.gravitational, en.dissipated, en.total};
      TL_CHECK_GOTO(st, tl_timeseries_append(ts, row), done);
      tl_progress_update(&prog, (double)k);
    }
    if (k == steps) break;
    TL_CHECK_GOTO(st, tl_dem_step(dem, 1), done);
  }
  tl_progress_finish(&prog);
  TL_CHECK_GOTO(st, tl_timeseries_close(&ts), done);
  bed->n = P->n;
  TL_CHECK_GOTO(st, tl_calloc(&bed->x, bed->n, sizeof *bed->x), done);
  TL_CHECK_GOTO(st, tl_calloc(&bed->r, bed->n, sizeof *bed->r), done);
  double zmax = 0.0, vol = 0.0, surface = -INFINITY;
  const double cx = 0.5 * s->box, cy = 0.5 * s->box;
  for (size_t i = 0; i < P->n; ++i) {
    bed->x[i] = P->x[i];
    bed->r[i] = P->radius[i];
    zmax = fmax(zmax, P->x[i].z + P->radius[i]);
    vol += 4.0 / 3.0 * M_PI * pow(P->radius[i], 3);
    double dx = P->x[i].x - cx, dy = P->x[i].y - cy;
    if (dx * dx + dy * dy <= s->radius * s->radius) surface = fmax(surface, P->x[i].z + P->radius[i]);
  }
  bed->surface = surface;
  bed->kinetic = en.kinetic_translational + en.kinetic_rotational;
  bed->packing = vol / (s->box * s->box * zmax);
  if (!isfinite(surface))
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "no grain lies under the cone (radius %g m) after settling", s->radius);
  else if (surface - s->depth < 2.0 * s->d_max)
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                      "the bed is %g m deep under the cone: -depth %g m brings the apex within two grain diameters of "
                      "the floor; at most -depth %g m for this bed (or raise -n)",
                      surface, s->depth, surface - 2.0 * s->d_max);
  else
    tl_printf("settled: kinetic energy %.3e J, bed surface under the cone z = %.4g m, packing fraction %.3f\n",
              bed->kinetic, surface, bed->packing);
done:
  if (ts) tl_timeseries_close(&ts);
  tl_contact_law_destroy(&law);
  tl_dem_destroy(&dem);
  return st;
}

/* u = (0, 0, -V t) on the base. */
static void push(double t, const double X[3], int c, void *ctx, double out[3])
{
  const double V = *(const double *)ctx;
  (void)X;
  out[0] = c == 2 ? -V * t : 0.0;
  out[1] = c == 2 ? -V : 0.0;
  out[2] = 0.0;
}

typedef struct {
  double force_end, force_growth, energy_error, wall, depth_reached, sigma_vm_max;
  size_t max_contacts;
} RunResult;

/* Mean resistance over depth windows: [lo, hi] fractions of the final depth. */
static double mean_force(const double *depth, const double *force, size_t n, double lo, double hi)
{
  double s = 0.0;
  size_t k = 0;
  for (size_t i = 0; i < n; ++i)
    if (depth[i] >= lo && depth[i] <= hi) {
      s += force[i];
      ++k;
    }
  return k ? s / (double)k : NAN;
}

static TlStatus penetrate(const Settings *s, const Bed *bed, TlMesh *mesh, double apex_z, int k, RunResult *res)
{
  const double wall0 = tl_wtime();
  const double c_w = s->widths[k] * 0.5 * (s->d_min + s->d_max);
  TlStatus st = TL_OK;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TlSCoupling *sc = NULL;
  TlDem *dem = NULL;
  TlContactLaw *law = NULL;
  TlStepper *stp = NULL;
  TlCoupledLoop *loop = NULL;
  TlTimeSeries *ts = NULL;
  TlSolidOutput *cone_out = NULL;
  TlParticleWriter *pw = NULL;
  double *v0 = NULL, *R = NULL, *depth = NULL, *force = NULL;
  size_t n_rows = 0;
  double V = s->speed;
  TL_CHECK_GOTO(st, tl_material_create(s->material, &mat), done);
  TL_CHECK_GOTO(st, tl_material_set(mat, "E", s->E_c), done);
  TL_CHECK_GOTO(st, tl_material_set(mat, "nu", s->nu_c), done);
  TL_CHECK_GOTO(st, tl_material_set(mat, "density", s->rho_c), done);
  TL_CHECK_GOTO(st, tl_material_setup(mat), done);
  TL_CHECK_GOTO(st, tl_solid_create(mesh, &solid), done);
  TL_CHECK_GOTO(st, tl_solid_set_material(solid, NULL, mat), done);
  for (int c = 0; c < 3; ++c) TL_CHECK_GOTO(st, tl_solid_prescribe(solid, "base", c, push, &V), done);
  TL_CHECK_GOTO(st, tl_solid_setup(solid), done);
  TlSCouplingOptions so;
  tl_scoupling_options_default(&so);
  so.width = c_w;
  const char *excluded[] = {"base"};
  TL_CHECK_GOTO(st, tl_scoupling_create_boundary(solid, 1, excluded, &so, &sc), done);
  /* The world: the settled grains at rest, the box, the cone's wall. */
  TL_CHECK_GOTO(st, tl_dem_create(&dem), done);
  TlParticles *P = tl_dem_particles(dem);
  TlDomain dom;
  TL_CHECK_GOTO(st, tl_domain_init_open(&dom, tl_v3(0, 0, 0), tl_v3(s->box, s->box, apex_z + s->body_h + s->depth + s->d_max)), done);
  TL_CHECK_GOTO(st, tl_dem_set_domain(dem, &dom), done);
  int sp;
  TL_CHECK_GOTO(st, tl_particles_add_species(P, "grains", s->rho_g, 0.5 * s->d_min, 0.5 * s->d_max, &sp), done);
  TL_CHECK_GOTO(st, tl_particles_reserve(P, bed->n), done);
  for (size_t i = 0; i < bed->n; ++i) TL_CHECK_GOTO(st, tl_dem_add_particle(dem, bed->x[i], tl_v3(0, 0, 0), bed->r[i], sp, NULL), done);
  TL_CHECK_GOTO(st, make_law(s, &law), done);
  TL_CHECK_GOTO(st, tl_dem_add_law(dem, law, NULL), done);
  law = NULL;
  TL_CHECK_GOTO(st, add_box(dem, s->box), done);
  const size_t nn = mesh->n_nodes;
  TL_CHECK_GOTO(st, tl_scoupling_add_to_dem(sc, dem, 0), done);
  tl_dem_set_gravity(dem, tl_v3(0, 0, -9.81));
  tl_dem_set_threads(dem, s->threads);
  /* The solid starts moving with its base: v = (0, 0, -V) everywhere. */
  TlStepperOptions sto;
  tl_stepper_options_default(&sto);
  sto.reuse = s->reuse;
  sto.keep_factors = s->reuse > 1;
  sto.max_iterations = s->reuse > 1 ? 200 : 30;

  TL_CHECK_GOTO(st, tl_stepper_create(s->explicit_fe ? "central_difference" : "newmark", tl_solid_system(solid), &sto, &stp), done);
  const size_t ndof = (size_t)tl_solid_system(solid)->ndof;
  /* The contact springs act on the cone's surface nodes explicitly (the
   * wall is placed, the forces come back after the DEM steps): a node of
   * lumped mass m under a spring k_n is stable for a FE step below
   * dt_c = 2 sqrt(m / k_n).  The smallest node mass is at the sharp apex, where
   * the mesh is finest. */
  const TlNodeSet *surf = NULL;
  TL_CHECK_GOTO(st, tl_mesh_find_node_set(mesh, "surface", &surf), done);
  double m_min = INFINITY;
  for (size_t i = 0; i < surf->n; ++i) {
    TlSparseIndex d = tl_solid_dof(solid, surf->nodes[i], 2);
    if (d >= 0) m_min = fmin(m_min, stp->m[d]);
  }
  const double k_n = s->E_g * 0.5 * (s->d_min + s->d_max), limit = 2.0 * sqrt(m_min / k_n);
  /* The push's step: the bed's, unless the explicit cone needs a shorter
   * one.  A node carries its elements' stiffness and the springs of the
   * grains on its faces at once: stable below 1 / sqrt(1 / dt_e^2 + K / dt_c^2)
   * with dt_e the elements' critical step and K = -contacts_per_node.
   * Tet10 needs the shorter step at the defaults: HRZ lumping leaves a corner
   * node 6/216 of its element's mass (dt_e 3.6e-7 s against Tet4's 3.7e-6 s
   * on the same mesh, dt_c 9.8e-7 s against 8.4e-6 s); the grains and the
   * cone then share it (lock-step), at its cost. */
  double dt = bed->dt;
  if (s->explicit_fe) {
    double dt_crit;
    TL_CHECK_GOTO(st, tl_stepper_critical_dt(stp, &dt_crit), done);
    const double dt_both = 1.0 / sqrt(1.0 / (dt_crit * dt_crit) + s->contacts_per_node / (limit * limit));
    if (!((double)s->substeps * dt <= s->fe_dt_fraction * dt_both)) {
      dt = s->fe_dt_fraction * dt_both / (double)s->substeps;
      if (k == 0)
        tl_printf("cone: the bed's step %.3g s x %ld substeps exceeds -fe_dt_fraction %g of the cone's stable step %.3g s "
                  "(elements %.3g s, %g contact springs per node %.3g s each): the push runs at a DEM step of %.3g s\n",
                  bed->dt, s->substeps, s->fe_dt_fraction, dt_both, dt_crit, s->contacts_per_node, limit, dt);
    }
    if (k == 0) tl_printf("cone: explicit critical step %.3g s, FE step %.3g s\n", dt_crit, (double)s->substeps * dt);
    if (!(dt > 0.0))
      TL_CHECK_GOTO(st, tl_error_set(TL_ERR_UNSTABLE, __FILE__, __LINE__,
                                     "the cone's explicit critical step %g s leaves no positive step", dt_crit), done);
  }
  TL_CHECK_GOTO(st, tl_dem_set_timestep(dem, dt, 0), done);
  TL_CHECK_GOTO(st, tl_dem_setup(dem), done);
  {
    const double Dt_fe = (double)s->substeps * dt;
    if (k == 0)
      tl_printf("cone: smallest surface node mass %.3g kg; contact-spring step limit 2 sqrt(m / k_n) = %.3g s, FE step %.3g s\n",
                m_min, limit, Dt_fe);
    /* refuse a step beyond half that limit (an implicit cone too) */
    if (!(Dt_fe <= 0.5 * limit))
      TL_CHECK_GOTO(st, tl_error_set(TL_ERR_UNSTABLE, __FILE__, __LINE__,
                                     "the FE step %ld x %g s = %g s is beyond half the limit 2 sqrt(m / k_n) = %g s of "
                                     "the lightest surface node (m = %g kg, k_n = %g N/m): the coupling would feed "
                                     "energy into the cone; at most -substeps %ld, or a denser (-rho_c) or coarser "
                                     "(-mesh_h) cone", s->substeps, dt, Dt_fe, limit, m_min, k_n,
                                     (long)floor(0.5 * limit / dt)), done);
  }
  TL_CHECK_GOTO(st, tl_calloc(&v0, ndof, sizeof *v0), done);
  for (size_t a = 0; a < nn; ++a) v0[tl_solid_dof(solid, a, 2)] = -V;
  TL_CHECK_GOTO(st, tl_stepper_set_state(stp, 0.0, NULL, v0), done);
  TlCoupledLoopOptions lo;
  tl_coupled_loop_options_default(&lo);
  lo.substeps = (int)s->substeps;

  TL_CHECK_GOTO(st, tl_coupled_loop_create(dem, solid, stp, 1, &sc, &lo, &loop), done);
  /* Tables and snapshots. */
  char name[64], *base = NULL;
  snprintf(name, sizeof name, "force_depth_c%d", k);
  TL_CHECK_GOTO(st, tl_path_join(s->out, name, &base), done);
  static const TlColumn cols[] = {{"time", "s"}, {"depth", "m"}, {"force", "N"}, {"base_reaction", "N"},
                                  {"contacts", ""}, {"dem_kinetic", "J"}, {"dem_elastic", "J"},
                                  {"gravitational", "J"}, {"dissipated", "J"}, {"fem_kinetic", "J"},
                                  {"fem_strain", "J"}, {"work_drive", "J"}, {"balance", "J"}};
  st = tl_timeseries_create(base, TL_TIMESERIES_CSV, sizeof cols / sizeof cols[0], cols, &ts);
  tl_free(&base);
  if (st) goto done;
  if (s->snapshots > 0) {
    snprintf(name, sizeof name, "cone_c%d", k);
    TL_CHECK_GOTO(st, tl_solid_output_create(solid, s->out, name, &cone_out), done);
    snprintf(name, sizeof name, "particles_c%d", k);
    TL_CHECK_GOTO(st, tl_particle_writer_create(s->out, name, &pw), done);
  }
  const double Dt = (double)s->substeps * dt;
  const double t_end = (s->gap + s->depth) / V;
  const long n_macro = (long)ceil(t_end / Dt - 1e-9);
  const long every = n_macro / s->samples > 0 ? n_macro / s->samples : 1;
  const long snap_every = s->snapshots > 0 ? (n_macro / s->snapshots > 0 ? n_macro / s->snapshots : 1) : 0;
  TL_CHECK_GOTO(st, tl_calloc(&R, 3 * nn, sizeof *R), done);
  TL_CHECK_GOTO(st, tl_calloc(&depth, (size_t)(n_macro / every + 2), sizeof *depth), done);
  TL_CHECK_GOTO(st, tl_calloc(&force, (size_t)(n_macro / every + 2), sizeof *force), done);
  const TlNodeSet *base_nodes = NULL;
  TL_CHECK_GOTO(st, tl_mesh_find_node_set(mesh, "base", &base_nodes), done);
  tl_printf("run %d: c = %g m (%g d), %ld FE steps of %.3g s (%ld DEM steps each), %zu SCoupling elements, t_end %.4g s\n",
            k, c_w, s->widths[k], n_macro, Dt, s->substeps, tl_scoupling_n_elements(sc), t_end);
  char label[64];
  snprintf(label, sizeof label, "penetration c%d", k);
  TlProgress prog;
  tl_progress_init(&prog, label, (double)n_macro);
  double W_drive = 0.0, P_prev = 0.0, E0 = 0.0, worst = 0.0, Rz = 0.0;
  res->max_contacts = 0;
  for (long step = 0;; ++step) {
    const double t = tl_coupled_loop_time(loop);
    /* The drive's force on the base: the reactions there, with the mass the
     * stepper integrates. */
    Rz = 0.0;
    if (s->explicit_fe) {
      /* The explicit stepper keeps f_int and f_ext of the state it reached:
       * R = f_int - f_ext + m a at the base's dofs, for free. */
      for (size_t i = 0; i < base_nodes->n; ++i) {
        TlSparseIndex d = tl_solid_dof(solid, base_nodes->nodes[i], 2);
        Rz += stp->f_int[d] - stp->f_ext[d] + stp->m[d] * stp->a[d];
      }
    } else {
      TL_CHECK_GOTO(st, tl_solid_reactions(solid, t, stp->u, stp->a, R), done);
      for (size_t i = 0; i < base_nodes->n; ++i) Rz += R[3 * base_nodes->nodes[i] + 2];
    }
    const double power = Rz * (-V);
    if (step > 0) W_drive += 0.5 * (power + P_prev) * Dt;
    P_prev = power;
    const double d_apex = bed->surface - (apex_z - V * t);
    const double F = -tl_coupled_loop_wall_force(loop).z; /* on the cone, up */
    size_t nc = tl_scoupling_n_contacts(sc);
    if (nc > res->max_contacts) res->max_contacts = nc;
    if (step % every == 0 || step == n_macro) {
      TlCoupledEnergy ce;
      TlDemEnergy de;
      TL_CHECK_GOTO(st, tl_coupled_loop_energy(loop, &ce), done);
      TL_CHECK_GOTO(st, tl_dem_energy(dem, &de), done);
      const double E = ce.fem_kinetic + ce.fem_strain + de.kinetic_translational + de.kinetic_rotational +
                       de.elastic + de.gravitational + de.dissipated - W_drive;
      if (step == 0) E0 = E;
      if (W_drive > 0.0 && step * Dt > 0.5 * t_end) worst = fmax(worst, fabs(E - E0) / W_drive);
      double row[13] = {t, d_apex, F, Rz, (double)nc, de.kinetic_translational + de.kinetic_rotational, de.elastic,
                        de.gravitational, de.dissipated, ce.fem_kinetic, ce.fem_strain, W_drive, E - E0};
      TL_CHECK_GOTO(st, tl_timeseries_append(ts, row), done);
      depth[n_rows] = d_apex;
      force[n_rows] = F;
      ++n_rows;
      tl_progress_update(&prog, (double)step);
    }
    if (snap_every && (step % snap_every == 0 || step == n_macro)) {
      TL_CHECK_GOTO(st, tl_solid_output_write(cone_out, step, t, stp->u, stp->v), done);
      TlParticleView view;
      tl_particle_view_of(P, &view); /* with ids and species */
      TL_CHECK_GOTO(st, tl_particle_writer_write(pw, step, t, &view), done);
    }
    if (step == n_macro) break;
    TL_CHECK_GOTO(st, tl_coupled_loop_step(loop), done);
  }
  tl_progress_finish(&prog);
  TL_CHECK_GOTO(st, tl_timeseries_close(&ts), done);
  /* The stress field at the end: the largest von Mises stress in the cone. */
  double *un = NULL, vm = 0.0;
  TL_CHECK_GOTO(st, tl_calloc(&un, 3 * nn, sizeof *un), done);
  tl_solid_dofs_to_nodes(solid, stp->u, un);
  for (size_t e = 0; e < mesh->blocks[0].n_elements && !st; ++e) {
    TlMat3 sig;
    st = tl_solid_element_stress(solid, 0, e, un, NULL, &sig);
    double p = (sig.m[0][0] + sig.m[1][1] + sig.m[2][2]) / 3.0, j2 = 0.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double dij = sig.m[i][j] - (i == j ? p : 0.0);
        j2 += 0.5 * dij * dij;
      }
    vm = fmax(vm, sqrt(3.0 * j2));
  }
  tl_free(&un);
  if (st) goto done;
  res->depth_reached = bed->surface - (apex_z - V * tl_coupled_loop_time(loop));
  res->force_end = mean_force(depth, force, n_rows, 0.8 * s->depth, s->depth + 1e-12);
  double f_start = mean_force(depth, force, n_rows, 0.2 * s->depth, 0.4 * s->depth);
  res->force_growth = f_start > 0.0 ? res->force_end / f_start : NAN;
  res->energy_error = W_drive > 0.0 ? worst : NAN; /* no drive work: nothing to measure the balance against */
  res->sigma_vm_max = vm;
  res->wall = tl_wtime() - wall0;
  tl_printf("run %d (c = %g d): resistance %.4g N at depth 0.8-1.0 x %g m, %.4g N at 0.2-0.4 x; energy balance error %.3e of "
            "the drive's work %.4g J; largest von Mises stress %.4g Pa; up to %zu contacts; wall %.2f s\n",
            k, s->widths[k], res->force_end, s->depth, f_start, worst, W_drive, vm, res->max_contacts, res->wall);
done:
  if (ts) tl_timeseries_close(&ts);
  tl_solid_output_destroy(&cone_out);
  tl_particle_writer_destroy(&pw);
  tl_coupled_loop_destroy(&loop);
  tl_stepper_destroy(&stp);
  tl_dem_destroy(&dem);
  tl_scoupling_destroy(&sc);
  tl_contact_law_destroy(&law);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_free(&v0);
  tl_free(&R);
  tl_free(&depth);
  tl_free(&force);
  return st;
}

static TlStatus run(int argc, char **argv)
{
  const double wall0 = tl_wtime();
  TlOptions *o = NULL;
  Settings s;
  memset(&s, 0, sizeof s);
  TlStatus st = options(argc, argv, &o, &s);
  TlSurfaceArrays surf;
  memset(&surf, 0, sizeof surf);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  if (st == TL_OK && s.surface[0]) {
    /* A body from a file: read, repaired, refused unless closed; its
     * half-width plays the cone radius's part in the checks. */
    TlSurfaceMesh *sm = NULL;
    TlSurfaceReport rep;
    st = tl_surface_mesh_read(s.surface, &sm);
    if (!st) st = tl_surface_mesh_repair(sm, NULL, &rep);
    if (!st) st = tl_surface_mesh_check(sm, TL_SURFACE_CLOSED);
    if (!st) st = tl_surface_mesh_transform(sm, s.surface_scale, tl_m3_identity(), tl_v3(0, 0, 0));
    if (!st) {
      tl_printf("surface %s: %zu vertices, %zu triangles (repair: %zu vertices merged, %zu triangles removed, %zu flipped)\n",
                s.surface, sm->n_vertices, sm->n_triangles, rep.vertices_merged, rep.triangles_removed, rep.triangles_flipped);
      double *x = NULL;
      size_t *tri = NULL;
      st = tl_calloc(&x, 3 * sm->n_vertices, sizeof *x);
      if (!st) st = tl_calloc(&tri, 3 * sm->n_triangles, sizeof *tri);
      for (size_t i = 0; !st && i < sm->n_vertices; ++i) {
        const double v[3] = {sm->x[i].x, sm->x[i].y, sm->x[i].z};
        for (int d = 0; d < 3; ++d) {
          x[3 * i + d] = v[d];
          lo[d] = fmin(lo[d], v[d]);
          hi[d] = fmax(hi[d], v[d]);
        }
      }
      for (size_t t = 0; !st && t < 3 * sm->n_triangles; ++t) tri[t] = (size_t)sm->tri[t / 3][t % 3];
      surf = (TlSurfaceArrays){sm->n_vertices, x, sm->n_triangles, tri};
      s.radius = 0.5 * fmax(hi[0] - lo[0], hi[1] - lo[1]);
      s.tip_radius = 0.0;
      s.body_h = hi[2] - lo[2];
    }
    tl_surface_mesh_destroy(&sm);
  }
  if (st == TL_OK) st = check_settings(&s);
  if (st != TL_OK) {
    tl_surface_arrays_free(&surf);
    tl_options_destroy(&o);
    return st;
  }
  Bed bed;
  memset(&bed, 0, sizeof bed);
  TlMesh *mesh = NULL;
  RunResult res[MAX_WIDTHS];
  memset(res, 0, sizeof res);
  TL_CHECK_GOTO(st, tl_output_dir_prepare(s.out), done);
  TL_CHECK_GOTO(st, settle(&s, &bed), done);
  /* The body: its lowest point -gap above the bed surface on the box's axis. */
  const double apex[3] = {0.5 * s.box, 0.5 * s.box, bed.surface + s.gap};
  if (s.surface[0]) {
    double *x = (double *)surf.x;
    const double shift[3] = {apex[0] - 0.5 * (lo[0] + hi[0]), apex[1] - 0.5 * (lo[1] + hi[1]), apex[2] - lo[2]};
    for (size_t i = 0; i < surf.n_vertices; ++i)
      for (int d = 0; d < 3; ++d) x[3 * i + d] += shift[d];
  } else {
    s.body_h = (s.radius - s.tip_radius) / tan(s.half_angle * M_PI / 180.0);
    TL_CHECK_GOTO(st, tl_surface_cone(apex, s.radius, s.body_h, s.tip_radius, (int)s.rim, &surf), done);
  }
  const double h = s.body_h;
  TlMeshFromSurfaceOptions mo;
  tl_mesh_from_surface_options_default(&mo);
  mo.type = s.tet10 ? &tl_element_tet10 : &tl_element_tet4;
  mo.cell_size = s.mesh_h > 0.0 ? s.mesh_h : s.radius / 3.0;
  mo.facet_size = mo.cell_size;
  mo.facet_distance = 0.05 * mo.cell_size;
  TlMeshFromSurfaceInfo info;
  const double tm0 = tl_wtime();
  TL_CHECK_GOTO(st, tl_mesh_from_surface(&surf, &mo, &mesh, &info), done);
  const double t_mesh = tl_wtime() - tm0;
  const double base_pt[3] = {apex[0], apex[1], apex[2] + h}, up[3] = {0, 0, 1};
  TL_CHECK_GOTO(st, tl_mesh_add_face_set_on_plane(mesh, "base", base_pt, up, 1e-9 * h), done);
  tl_printf("body: half-width %g m, height %g m, %zu surface triangles -> %zu %s elements, %zu nodes in %.3f s; volume %.6g m^3 "
            "(surface encloses %.6g); dihedral angles %.1f to %.1f degrees\n",
            s.radius, h, surf.n_triangles, info.n_tetrahedra, mo.type->header.name, mesh->n_nodes, t_mesh,
            info.mesh_volume, info.surface_volume, info.min_dihedral, info.max_dihedral);
  for (int k = 0; k < s.n_widths; ++k) TL_CHECK_GOTO(st, penetrate(&s, &bed, mesh, apex[2], k, &res[k]), done);
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "n", (long)bed.n);
  tl_summary_int(&sum, "tetrahedra", (long)info.n_tetrahedra);
  tl_summary_real(&sum, "packing_fraction", bed.packing);
  tl_summary_real(&sum, "depth", res[0].depth_reached);
  double worst_energy = 0.0, worst_growth = INFINITY;
  for (int k = 0; k < s.n_widths; ++k) {
    char key[64];
    snprintf(key, sizeof key, "force_c%d", k);
    tl_summary_real(&sum, key, res[k].force_end);
    snprintf(key, sizeof key, "energy_error_c%d", k);
    if (isfinite(res[k].energy_error)) tl_summary_real(&sum, key, res[k].energy_error);
    else tl_summary_undefined(&sum, key, "the drive did no work (the body met no grain)");
    snprintf(key, sizeof key, "wall_c%d", k);
    tl_summary_real(&sum, key, res[k].wall);
    worst_energy = isfinite(res[k].energy_error) ? fmax(worst_energy, res[k].energy_error) : NAN;
    worst_growth = isnan(worst_growth) || isnan(res[k].force_growth) ? NAN : fmin(worst_growth, res[k].force_growth);
  }
  if (isfinite(worst_energy)) tl_summary_real(&sum, "energy_error", worst_energy);
  else tl_summary_undefined(&sum, "energy_error", "a run whose drive did no work");
  if (isfinite(worst_growth)) tl_summary_real(&sum, "force_growth", worst_growth);
  else tl_summary_undefined(&sum, "force_growth", "no resistance at 0.2-0.4 of the depth to compare with (the body met no grain there)");
  if (s.n_widths > 1) {
    if (res[0].force_end > 0.0) tl_summary_real(&sum, "force_ratio", res[s.n_widths - 1].force_end / res[0].force_end);
    else tl_summary_undefined(&sum, "force_ratio", "no resistance at c = %g d to compare with", s.widths[0]);
  }
  tl_summary_real(&sum, "sigma_vm_max", res[0].sigma_vm_max);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  st = tl_summary_print(&sum, stdout);
done:
  tl_mesh_destroy(&mesh);
  tl_surface_arrays_free(&surf);
  tl_free(&bed.x);
  tl_free(&bed.r);
  tl_options_destroy(&o);
  return st;
}

int main(int argc, char **argv)
{
  TlStatus s = tl_initialize();
  if (s == TL_OK) s = run(argc, argv);
  return tl_driver_exit(s);
}
