/* The single periodic cell of FEM×DEM (seeds/004: 400 disks, linear contacts
 * with Coulomb friction) in Talus and in Yade (Debian `yade`), in the same
 * invocation: time per particle-step, ratio = talus / yade (goal < 0.5).
 *
 * The packing is made once by Talus: a random gas of -n disks in a planar
 * periodic cell (tl_dem_insert_gas), compressed to -pressure
 * (tl_dem_compress) with the contact law below, written to
 * <output_dir>/packing.txt.  Both codes then run the same biaxial loading
 * of that packing at a constant velocity gradient (shortening along y at
 * -rate, lengthening along x at -rate/2; z inert) with the same time step,
 * -steps steps timed -repeat times in a row (after -warmup steps), the
 * fastest kept:
 *   Talus  the 2-D world (tl_dem_set_dimension 2): disks, mass per unit
 *          thickness ρ π r², inertia ½ m r²; linear normal spring k_n,
 *          restitution -contact_restitution (viscous), Coulomb friction μ with
 *          k_t = 2/7 k_n (the objective tangential law of seeds/004, Eq. 11);
 *   Yade   spheres blocked in the plane (blockedDOFs 'zXY') given the disks'
 *          masses and inertias, in a periodic cell of height 5 times the
 *          largest diameter (its collider wants a body under half the cell); Ip2_FrictMat_FrictMat_FrictPhys with
 *          E = k_n / r_mean (k_n = E R for equal radii, E 2 R1 R2 / (R1 + R2)
 *          otherwise) and ks/kn = 2/7, friction angle atan μ;
 *          Law2_ScGeom_FrictPhys_CundallStrack (the same linear law with
 *          Coulomb friction); NewtonIntegrator(damping = -yade_damping), its
 *          non-viscous damping standing in for the viscous one; the
 *          InsertionSortCollider with its default Verlet distance; one
 *          thread (-j1).
 * The Yade script is written next to the packing (yade_cell.py) and run as
 * `yade -j1 -n -x yade_cell.py ...`; without yade the benchmark says so and
 * exits non-zero (a benchmark that cannot measure reports no ratio).
 *
 * Last line: summary: n=... steps=... talus_ns=... yade_ns=... (per
 * particle-step) ratio=... talus_contacts=... yade_contacts=... */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "peers/tl_peer.h"
#include "talus.h"
#include "tl_bench.h"
#include "tl_options_renamed.h"
#include "tl_bench.h"
#include "tl_dem.h"

typedef struct {
  long n, steps, repeat, warmup, seed;
  double k_n, mu, restitution, density, pressure, rate, dt_fraction, yade_damping, packing_tolerance;
  double inertial, inertial_fast;
  const char *out;
} Settings;

static const double R_MIN = 0.004, R_MAX = 0.006;

static const char *yade_script =
    "import sys, time, math\n"
    "from yade import *\n"
    "from yade import utils\n"
    "args = dict(a.split('=', 1) for a in sys.argv[1:])\n"
    "steps, repeat, warmup = int(args['steps']), int(args['repeat']), int(args['warmup'])\n"
    "kn, mu, rho, dt, damping, rate = (float(args[k]) for k in ('kn', 'mu', 'rho', 'dt', 'damping', 'rate'))\n"
    "lines = open(args['packing']).read().split('\\n')\n"
    "h = [float(v) for v in lines[0].split()]\n"
    "disks = [[float(v) for v in l.split()] for l in lines[1:] if l.strip()]\n"
    "rmax = max(d[2] for d in disks)\n"
    "rmean = sum(d[2] for d in disks) / len(disks)\n"
    "O.periodic = True\n"
    "O.cell.hSize = Matrix3(h[0], h[1], 0, h[2], h[3], 0, 0, 0, 10.0 * rmax)\n"
    "mat = O.materials.append(FrictMat(young=kn / rmean, poisson=2.0 / 7.0, frictionAngle=math.atan(mu), "
    "density=rho))\n"
    "for x, y, r in disks:\n"
    "    b = utils.sphere((x, y, 5.0 * rmax), r, material=mat)\n"
    "    m = rho * math.pi * r * r\n"
    "    b.state.mass = m\n"
    "    b.state.inertia = Vector3(0.5 * m * r * r, 0.5 * m * r * r, 0.5 * m * r * r)\n"
    "    b.state.blockedDOFs = 'zXY'\n"
    "    O.bodies.append(b)\n"
    "O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),\n"
    "    InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],\n"
    "                    [Law2_ScGeom_FrictPhys_CundallStrack()]),\n"
    "    NewtonIntegrator(damping=damping)]\n"
    "O.dt = dt\n"
    "O.cell.velGrad = Matrix3(0.5 * rate, 0, 0, 0, -rate, 0, 0, 0, 0)\n"
    "O.run(warmup, True)\n"
    "best = 1e300\n"
    "for k in range(repeat):\n"
    "    t0 = time.time()\n"
    "    O.run(steps, True)\n"
    "    best = min(best, time.time() - t0)\n"
    "real = sum(1 for i in O.interactions if i.isReal)\n"
    "zmax = max(abs(b.state.pos[2] - 5.0 * rmax) for b in O.bodies)\n"
    "print('yade: n=%d steps=%d seconds=%.9g contacts=%d zmax=%.3g' % (len(O.bodies), steps, best, real, zmax))\n"
    "sys.stdout.flush()\n";

static TlStatus add_law(const Settings *s, TlDem *dem)
{
  const TlContactValue v[] = {{"k_n", s->k_n}, {"restitution", s->restitution}, {"mu", s->mu}};
  const TlContactSpec spec = {"linear", "coulomb", NULL, NULL, v, 3};
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_build(&spec, &law));
  return tl_dem_add_law(dem, law, NULL);
}

static TlStatus make_world(const Settings *s, TlMat3 h, size_t n, const TlVec3 *x, const double *radius, TlDem **out)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TL_CHECK(tl_dem_set_dimension(dem, 2));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "disks", s->density, R_MIN, R_MAX, &sp));
  TlDomain D;
  TL_CHECK(tl_domain_init_cell_2d(&D, tl_v3(0, 0, 0), h));
  TL_CHECK(tl_dem_set_domain(dem, &D));
  if (x)
    for (size_t i = 0; i < n; ++i) TL_CHECK(tl_dem_add_particle(dem, x[i], tl_v3(0, 0, 0), radius[i], sp, NULL));
  else
    TL_CHECK(tl_dem_insert_gas(dem, sp, n, (uint64_t)s->seed, 100000, NULL));
  TL_CHECK(add_law(s, dem));
  tl_dem_set_threads(dem, 1);
  tl_dem_track_energy(dem, 0);
  tl_dem_track_orientation(dem, 0);
  double dtc, k, m;
  TL_CHECK(tl_dem_set_timestep(dem, 1.0, 1));
  TL_CHECK(tl_dem_critical_timestep(dem, &dtc, &k, &m));
  TL_CHECK(tl_dem_set_timestep(dem, s->dt_fraction * dtc, 0));
  TL_CHECK(tl_dem_setup(dem));
  *out = dem;
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  double wall0 = tl_wtime();
  TlOptions *o;
  Settings s;
  TL_CHECK(tl_options_create(argc, argv,
                             "The FEM x DEM single periodic cell (2-D disks, linear contacts with Coulomb friction, "
                             "biaxial at a constant velocity gradient) in Talus and in Yade: time per particle-step "
                             "and ratio talus/yade.",
                             &o));
  static const TlRenamedOption renamed[] = {
      {"-k_n", "-contact_k_n", NULL}, {"-mu", "-contact_mu", NULL}, {"-restitution", "-contact_restitution", NULL}};
  TL_CHECK(tl_options_refuse_renamed(o, renamed, 3));
  TL_CHECK(tl_options_get_int(o, "-n", 400, 10, 1000000, "disks (seeds/004: 400)", &s.n));
  TL_CHECK(tl_options_get_int(o, "-steps", 20000, 1, 100000000, "timed steps per run", &s.steps));
  TL_CHECK(tl_options_get_int(o, "-repeat", 3, 1, 1000, "timed runs in a row, the fastest kept", &s.repeat));
  TL_CHECK(tl_options_get_int(o, "-warmup", 1000, 0, 100000000, "untimed steps before the timed runs", &s.warmup));
  TL_CHECK(tl_options_get_int(o, "-seed", 1, 0, 1000000000, "random seed of the gas", &s.seed));
  TL_CHECK(tl_options_get_real(o, "-contact_k_n", 1e6, 1e-3, 1e15, "N/m", "normal stiffness (per unit thickness)", &s.k_n));
  TL_CHECK(tl_options_get_real(o, "-contact_mu", 0.5, 0.0, 10.0, "", "Coulomb friction coefficient", &s.mu));
  TL_CHECK(tl_options_get_real(o, "-contact_restitution", 0.3, 0.01, 1.0, "", "Talus: restitution of the viscous normal damping",
                               &s.restitution));
  TL_CHECK(tl_options_get_real(o, "-yade_damping", 0.2, 0.0, 0.99, "", "Yade: NewtonIntegrator non-viscous damping",
                               &s.yade_damping));
  TL_CHECK(tl_options_get_real(o, "-density", 2500, 1e-6, 1e6, "kg/m^3", "grain density", &s.density));
  TL_CHECK(tl_options_get_real(o, "-pressure", 1e3, 1e-6, 1e12, "N/m", "confining pressure of the packing (2-D: per unit "
                               "thickness)", &s.pressure));
  TL_CHECK(tl_options_get_real(o, "-packing_tolerance", 1e-3, 1e-9, 1.0, "",
                               "static balance of every disk of the prepared packing (seeds/004 Eq. 19)",
                               &s.packing_tolerance));
  TL_CHECK(tl_options_get_real(o, "-inertial", 1e-5, 1e-9, 1.0, "",
                               "inertial number of the compression near the target pressure (seeds/004 Eq. 18)",
                               &s.inertial));
  TL_CHECK(tl_options_get_real(o, "-inertial_fast", 3e-3, 1e-9, 1.0, "",
                               "inertial number of the compression of the gas", &s.inertial_fast));
  TL_CHECK(tl_options_get_real(o, "-rate", 0.01, 0.0, 1e3, "1/s", "axial strain rate of the biaxial loading", &s.rate));
  TL_CHECK(tl_options_get_real(o, "-dt_fraction", 0.2, 1e-3, 1.0, "", "time step over Talus's critical time step",
                               &s.dt_fraction));
  TL_CHECK(tl_options_get_string(o, "-output_dir", "results/cell_vs_yade", "folder of the packing and the Yade script",
                                 &s.out));
  TL_CHECK(tl_options_finish(o, stdout));
  TL_CHECK(tl_mkdir_p(s.out));

  /* the packing: a gas compressed to the pressure */
  const double mean_area = TL_PI * (R_MIN * R_MIN + R_MIN * R_MAX + R_MAX * R_MAX) / 3.0;
  const double L = sqrt((double)s.n * mean_area / 0.42);
  TlMat3 h = tl_m3_identity();
  h.m[0][0] = h.m[1][1] = L;
  TlDem *dem;
  TL_CHECK(make_world(&s, h, (size_t)s.n, NULL, NULL, &dem));
  const double dt = tl_dem_timestep(dem);
  const double d_mean = R_MIN + R_MAX;
  /* strain rates from inertial numbers (seeds/004 Eq. 18, P / ρ with the 2-D pressure over the diameter) */
  const double sqrt_p_rho = sqrt(s.pressure / d_mean / s.density);
  const TlDemCompress c = {s.pressure, s.inertial * sqrt_p_rho / d_mean, s.inertial_fast * sqrt_p_rho / d_mean,
                           s.packing_tolerance, 1e-2, 10, 2000000};
  TlDemCompressResult cr;
  double t0 = tl_wtime();
  TL_CHECK(tl_dem_compress(dem, &c, &cr));
  TlParticles *P = tl_dem_particles(dem);
  printf("packing: %zu disks, %s after %ld steps (%.1f s): pressure %.5g N/m, area fraction %.4f, coordination %.2f, "
         "largest imbalance %.2e, dt %.3g s\n", P->n, cr.converged ? "converged" : "NOT converged", cr.steps,
         tl_wtime() - t0, cr.pressure, cr.solid_fraction, cr.coordination, cr.max_imbalance, dt);
  char path[4096];
  snprintf(path, sizeof path, "%s/packing.txt", s.out);
  FILE *f = fopen(path, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write %s", path);
  const TlMat3 hp = tl_dem_domain(dem)->h;
  fprintf(f, "%.17g %.17g %.17g %.17g\n", hp.m[0][0], hp.m[0][1], hp.m[1][0], hp.m[1][1]);
  for (size_t i = 0; i < P->n; ++i) fprintf(f, "%.17g %.17g %.17g\n", P->x[i].x, P->x[i].y, P->radius[i]);
  fclose(f);

  /* Talus: the biaxial loading, from the packing as it stands */
  TlMat3 Lg = tl_m3_zero();
  Lg.m[0][0] = 0.5 * s.rate;
  Lg.m[1][1] = -s.rate;
  TlDomain *D = tl_dem_domain(dem);
  TL_CHECK(tl_domain_set_h_rate(D, tl_m3_mul(Lg, D->h)));
  TL_CHECK(tl_dem_step(dem, s.warmup));
  double best = INFINITY;
  for (long r = 0; r < s.repeat; ++r) {
    TL_CHECK(tl_domain_set_h_rate(D, tl_m3_mul(Lg, D->h))); /* a constant velocity gradient, as Yade's velGrad */
    double t1 = tl_wtime();
    TL_CHECK(tl_dem_step(dem, s.steps));
    best = fmin(best, tl_wtime() - t1);
  }
  TlDemStats st;
  tl_dem_stats(dem, &st);
  const double talus_ns = 1e9 * best / ((double)P->n * (double)s.steps);
  printf("talus: %zu disks, %ld steps in %.4f s (fastest of %ld), %.1f ns per particle-step, %zu contacts\n", P->n,
         s.steps, best, s.repeat, talus_ns, st.n_contacts);

  /* Yade on the same packing */
  snprintf(path, sizeof path, "%s/yade_cell.py", s.out);
  f = fopen(path, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write %s", path);
  fputs(yade_script, f);
  fclose(f);
  if (system("command -v yade > /dev/null 2>&1") != 0)
    TL_ERROR(TL_ERR_UNSUPPORTED, "yade is not installed (Debian package yade): no peer to compare with");
  char cmd[8192], line[4096];
  snprintf(cmd, sizeof cmd,
           "cd '%s' && yade -j1 -n -x yade_cell.py packing=packing.txt steps=%ld repeat=%ld warmup=%ld kn=%.17g "
           "mu=%.17g rho=%.17g dt=%.17g damping=%.17g rate=%.17g 2>&1",
           s.out, s.steps, s.repeat, s.warmup, s.k_n, s.mu, s.density, dt, s.yade_damping, s.rate);
  TL_CHECK(tl_peer_command(cmd, "yade:", line, sizeof line));
  long yn = 0, ysteps = 0, ycontacts = 0;
  double ysec = 0.0, zmax = 0.0;
  if (sscanf(line, "yade: n=%ld steps=%ld seconds=%lf contacts=%ld zmax=%lf", &yn, &ysteps, &ysec, &ycontacts, &zmax) != 5 ||
      yn != (long)P->n || !(ysec > 0.0))
    TL_ERROR(TL_ERR_FORMAT, "yade gave no timing line (got '%s'); command: %s", line, cmd);
  const double yade_ns = 1e9 * ysec / ((double)yn * (double)ysteps);
  printf("yade: %ld spheres in the plane, %ld steps in %.4f s (fastest of %ld), %.1f ns per particle-step, %ld "
         "contacts, largest z drift %.2g m\n", yn, ysteps, ysec, s.repeat, yade_ns, ycontacts, zmax);
  printf("ratio talus / yade = %.3f (goal < 0.5)\n", talus_ns / yade_ns);
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "n", (long)P->n);
  tl_summary_int(&sum, "steps", s.steps);
  tl_summary_real(&sum, "talus_ns", talus_ns);
  tl_summary_real(&sum, "yade_ns", yade_ns);
  tl_summary_real(&sum, "ratio", talus_ns / yade_ns);
  tl_summary_int(&sum, "talus_contacts", (long)st.n_contacts);
  tl_summary_int(&sum, "yade_contacts", ycontacts);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  TlStatus s_sum = tl_summary_print(&sum, stdout);
  tl_dem_destroy(&dem);
  tl_options_destroy(&o);
  return s_sum;
}

int main(int argc, char **argv) { return tl_bench_main(argc, argv, run); }
