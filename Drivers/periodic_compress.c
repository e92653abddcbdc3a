/* A periodic packing compressed isotropically to a target pressure and
 * relaxed, the way seeds/000 §3.1 prepares its gouge: polydisperse Hertz
 * spheres with friction (seeds/000 supplementary Eqs. 18-20, Table 1) start
 * as a loose random gas in a cubic periodic cell; the cell shrinks at a
 * strain rate set by an inertial number (seeds/004 Eq. 18,
 * ε̇ = I sqrt(p/ρ)/<d>) until the pressure reaches the target, then a
 * servo holds the pressure (ḣ = ε̇ h with ε̇ proportional to the pressure
 * error) while the packing relaxes, until the static balance of every
 * particle (seeds/004 Eq. 19, Δ_n < tolerance) and the pressure error are
 * both met, or -t_end.
 *
 * Defaults are seeds/000 Table 1: E = 50 GPa, ν = 0.3, ρ = 2500 kg/m³,
 * d ∈ [2.5, 3.5] mm, μ = 0.5, γ_n = 0.2, γ_t = 0.1 (1/(m s), the Hertz
 * form's damping), dt = 1e-8 s, 5 MPa; the cell side is 12 d0 (the size at
 * which the paper's moduli plateau).  With the paper's tiny damping the
 * relaxation is long (the paper quotes about 3e6 steps for a 12 d0 box).
 *
 * Output in -output_dir: compress.csv/.h5 (time, pressure, packing
 * fraction, kinetic energy, coordination, largest Δ_n, strain rate) and the
 * final packing (packing_*.h5 + packing.xmf).  Last line:
 * summary: n=... pressure=... packing_fraction=... coordination=... wall=... */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "talus.h"
#include "tl_atomic_file.h"
#include "tl_dem.h"
#include "tl_particle_snapshot.h"
#include "tl_timeseries.h"

typedef struct {
  double d_min, d_max, density, pressure, dt, box_d0, phi0, inertial, inertial_gas;
  double t_end, tolerance, pressure_tolerance;
  long seed, control_every;
  int threads;
  const char *out;
  TlContactLaw *law;
} Settings;

static TlStatus options(int argc, char **argv, TlOptions **o, Settings *s)
{
  s->law = NULL;
  TL_CHECK(tl_options_create(argc, argv,
                             "Isotropic compression of a periodic Hertz packing to a target pressure, then "
                             "relaxation under a pressure servo (seeds/000 §3.1 preparation).",
                             o));
  TL_CHECK(tl_options_get_real(*o, "-d_min", 2.5e-3, 1e-9, 1e3, "m", "smallest diameter (seeds/000 Table 1)", &s->d_min));
  TL_CHECK(tl_options_get_real(*o, "-d_max", 3.5e-3, 1e-9, 1e3, "m", "largest diameter (seeds/000 Table 1)", &s->d_max));
  TL_CHECK(tl_options_get_real(*o, "-density", 2500, 1e-6, 1e6, "kg/m^3", "grain density (Table 1)", &s->density));
  /* Hertz with viscous damping and Coulomb friction, seeds/000 Table 1:
   * E = 50 GPa, nu = 0.3, mu_g = 0.5, gamma_n = 0.2, gamma_t = 0.1 1/(m s) */
  const TlContactValue law_values[] = {{"E", 50e9}, {"nu", 0.3}, {"mu", 0.5}, {"gamma_n", 0.2}, {"gamma_t", 0.1}};
  const TlContactSpec law_spec = {"hertz", "coulomb", NULL, NULL, law_values, 5};
  TL_CHECK(tl_contact_law_from_options(*o, &law_spec, &s->law));
  TL_CHECK(tl_options_get_real(*o, "-pressure", 5e6, 1.0, 1e12, "Pa", "target confining pressure (seeds/000: 5 MPa)", &s->pressure));
  TL_CHECK(tl_options_get_real(*o, "-dt", 1e-8, 1e-15, 1.0, "s", "time step (Table 1)", &s->dt));
  TL_CHECK(tl_options_get_real(*o, "-box", 12.0, 2.5, 1000.0, "d0", "cell side in mean diameters d0", &s->box_d0));
  TL_CHECK(tl_options_get_real(*o, "-phi0", 0.3, 0.01, 0.5, "", "initial packing fraction of the gas", &s->phi0));
  TL_CHECK(tl_options_get_real(*o, "-inertial", 1e-3, 1e-7, 1.0, "",
                               "inertial number setting the strain rate near the target (seeds/004 Eq. 18)", &s->inertial));
  TL_CHECK(tl_options_get_real(*o, "-inertial_gas", 3e-2, 1e-7, 10.0, "",
                               "inertial number of the initial compression, while the pressure is low", &s->inertial_gas));
  TL_CHECK(tl_options_get_real(*o, "-t_end", 0.05, 0.0, 1e6, "s", "longest simulated time", &s->t_end));
  TL_CHECK(tl_options_get_real(*o, "-tolerance", 1e-3, 1e-12, 1.0, "", "static balance Δ_n of every particle (seeds/004 Eq. 19)", &s->tolerance));
  TL_CHECK(tl_options_get_real(*o, "-pressure_tolerance", 1e-2, 1e-9, 1.0, "", "relative pressure error at the end", &s->pressure_tolerance));
  TL_CHECK(tl_options_get_int(*o, "-control_every", 100, 1, 1000000, "steps between servo updates and table rows", &s->control_every));
  TL_CHECK(tl_options_get_int(*o, "-seed", 1, 0, 1000000000, "random seed of the initial gas", &s->seed));
  long th;
  TL_CHECK(tl_options_get_int(*o, "-threads", 0, 0, 1024, "OpenMP threads (0: default)", &th));
  s->threads = (int)th;
  TL_CHECK(tl_options_get_string(*o, "-output_dir", "results/periodic_compress", "output folder", &s->out));
  return tl_options_finish(*o, stdout);
}

static double pressure_of(TlDem *dem)
{
  TlMat3 sc, sk;
  if (tl_dem_stress(dem, &sc, &sk) != TL_OK) return NAN;
  return -(tl_m3_trace(sc) + tl_m3_trace(sk)) / 3.0;
}

static TlStatus run(int argc, char **argv)
{
  double wall0 = tl_wtime();
  TlOptions *o = NULL;
  Settings s;
  TlStatus st = options(argc, argv, &o, &s);
  if (st != TL_OK) {
    tl_contact_law_destroy(&s.law);
    tl_options_destroy(&o);
    return st;
  }
  if (s.d_max < s.d_min) TL_ERROR(TL_ERR_ARG, "-d_max %g is smaller than -d_min %g", s.d_max, s.d_min);
  const double d0 = 0.5 * (s.d_min + s.d_max);
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "gouge", s.density, 0.5 * s.d_min, 0.5 * s.d_max, &sp));
  /* number of grains: a dense packing (φ ≈ 0.64) of the final cell */
  double L_final = s.box_d0 * d0;
  double mean_vol = TL_PI / 6.0 * (pow(s.d_max, 4) - pow(s.d_min, 4)) / (4.0 * (s.d_max - s.d_min + 1e-300));
  if (s.d_max - s.d_min < 1e-12 * d0) mean_vol = TL_PI / 6.0 * d0 * d0 * d0;
  long n = (long)(0.64 * L_final * L_final * L_final / mean_vol);
  if (n < 2) n = 2;
  double L0 = cbrt((double)n * mean_vol / s.phi0);
  TlDomain dom;
  TL_CHECK(tl_domain_init_cell(&dom, tl_v3(0, 0, 0), tl_m3_scale(tl_m3_identity(), L0)));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  /* random sequential insertion without overlap (periodic images) */
  uint64_t rng = (uint64_t)s.seed * 0x9e3779b97f4a7c15ULL + 1;
  TL_CHECK(tl_particles_reserve(P, (size_t)n));
  for (long k = 0; k < n; ++k) {
    double r = tl_species_sample_radius(&P->species_table[sp], &rng);
    int placed = 0;
    for (int attempt = 0; attempt < 100000 && !placed; ++attempt) {
      TlVec3 x = {L0 * tl_random_uniform(&rng), L0 * tl_random_uniform(&rng), L0 * tl_random_uniform(&rng)};
      placed = 1;
      for (size_t i = 0; i < P->n && placed; ++i)
        placed = tl_v3_norm(tl_domain_branch(&dom, P->x[i], x)) > P->radius[i] + r;
      if (placed) TL_CHECK(tl_dem_add_particle(dem, x, tl_v3(0, 0, 0), r, sp, NULL));
    }
    if (!placed) TL_ERROR(TL_ERR_ARG, "could not place particle %ld in the gas: -phi0 %g too dense", k, s.phi0);
  }
  TL_CHECK(tl_dem_add_law(dem, s.law, NULL));
  tl_dem_set_threads(dem, s.threads);
  tl_dem_track_energy(dem, 0);
  TL_CHECK(tl_dem_set_timestep(dem, s.dt, 0));
  TL_CHECK(tl_dem_setup(dem));
  printf("periodic_compress: %ld grains, d in [%g, %g] m, cell %.4g m -> about %.4g m, target %g Pa, dt %g s\n", n,
         s.d_min, s.d_max, L0, L_final, s.pressure, s.dt);
  TL_CHECK(tl_mkdir_p(s.out));
  char base[4096];
  snprintf(base, sizeof base, "%s/compress", s.out);
  static const TlColumn cols[] = {{"time", "s"}, {"pressure", "Pa"}, {"packing_fraction", ""}, {"kinetic", "J"},
                                  {"coordination", ""}, {"max_imbalance", ""}, {"strain_rate", "1/s"}};
  TlTimeSeries *ts;
  TL_CHECK(tl_timeseries_create(base, TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, sizeof cols / sizeof cols[0], cols, &ts));
  double vol_grains = 0.0;
  for (size_t i = 0; i < P->n; ++i) vol_grains += 4.0 / 3.0 * TL_PI * pow(P->radius[i], 3);
  long steps_max = (long)ceil(s.t_end / s.dt);
  TlProgress prog;
  tl_progress_init(&prog, "compress", (double)steps_max);
  const double rate_target = s.inertial * sqrt(s.pressure / s.density) / d0;
  const double rate_gas = s.inertial_gas * sqrt(s.pressure / s.density) / d0;
  int reached = 0, converged = 0;
  double pr = 0.0, imbalance = 1.0, z = 0.0, rate = 0.0;
  long k = 0;
  for (k = 0; k < steps_max; k += s.control_every) {
    pr = pressure_of(dem);
    TL_CHECK(tl_dem_max_force_imbalance(dem, &imbalance));
    TL_CHECK(tl_dem_coordination(dem, &z, NULL));
    double err = (pr - s.pressure) / s.pressure;
    if (!reached && pr >= s.pressure) reached = 1;
    if (!reached) {
      /* compress: fast while the pressure is far below, slower near it */
      double frac = fmax(pr, 0.0) / s.pressure;
      rate = -(rate_gas * (1.0 - frac) + rate_target * frac);
    } else {
      /* servo: expand when above the target, compress when below */
      rate = fmax(-rate_target, fmin(rate_target, rate_target * 2.0 * err));
    }
    if (reached && fabs(err) < s.pressure_tolerance && imbalance < s.tolerance) {
      converged = 1;
      break;
    }
    TlDomain *D = tl_dem_domain(dem);
    TL_CHECK(tl_domain_set_h_rate(D, tl_m3_scale(D->h, rate)));
    double ke = 0.0;
    for (size_t i = 0; i < P->n; ++i) ke += 0.5 * P->mass[i] * tl_v3_norm2(P->v[i]);
    double row[] = {tl_dem_time(dem), pr, vol_grains / tl_domain_volume(D), ke, z, imbalance, rate};
    TL_CHECK(tl_timeseries_append(ts, row));
    TL_CHECK(tl_dem_step(dem, s.control_every));
    tl_progress_update(&prog, (double)k);
  }
  tl_progress_finish(&prog);
  TlDomain *D = tl_dem_domain(dem);
  TL_CHECK(tl_domain_set_h_rate(D, tl_m3_zero()));
  TL_CHECK(tl_timeseries_close(&ts));
  TlParticleWriter *writer;
  TL_CHECK(tl_particle_writer_create(s.out, "packing", &writer));
  TlParticleView view = {P->n, P->x, P->radius, P->v, P->w, P->f, P->torque, NULL, 0, NULL};
  TL_CHECK(tl_particle_writer_write(writer, k, tl_dem_time(dem), &view));
  tl_particle_writer_destroy(&writer);
  double phi = vol_grains / tl_domain_volume(D);
  double side = cbrt(tl_domain_volume(D));
  printf("%s after %ld steps: pressure %.6g Pa (target %g), packing fraction %.4f, coordination %.3f, largest Δ_n %.3g, cell %.4g m = %.2f d0\n",
         converged ? "converged" : "stopped at t_end", k, pr, s.pressure, phi, z, imbalance, side, side / d0);
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "n", n);
  tl_summary_int(&sum, "steps", k);
  tl_summary_int(&sum, "converged", converged);
  tl_summary_real(&sum, "pressure", pr);
  tl_summary_real(&sum, "packing_fraction", phi);
  tl_summary_real(&sum, "coordination", z);
  tl_summary_real(&sum, "max_imbalance", imbalance);
  tl_summary_real(&sum, "cell_d0", side / d0);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  tl_summary_print(&sum, stdout);
  tl_dem_destroy(&dem);
  tl_options_destroy(&o);
  return TL_OK;
}

int main(int argc, char **argv)
{
  TlStatus s = tl_initialize();
  if (s == TL_OK) s = run(argc, argv);
  return tl_driver_exit(s);
}
