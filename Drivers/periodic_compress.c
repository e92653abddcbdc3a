/* A periodic packing compressed isotropically to a target pressure and
 * relaxed, the way Voisin-Leprince et al. 2023 §3.1 prepares its gouge, by one of two
 * protocols (-protocol):
 *
 * servo (default): polydisperse Hertz spheres with friction (Voisin-Leprince et al. 2023
 * supplementary Eqs. 18-20, Table 1) start as a loose random gas without
 * overlaps in a cubic periodic cell; the cell shrinks at a strain rate set
 * by an inertial number (Desrues et al. 2019 Eq. 18, ε̇ = I sqrt(p/ρ)/<d>) until the
 * pressure reaches the target, then a servo holds the pressure (ḣ = ε̇ h with
 * ε̇ proportional to the pressure error) while the packing relaxes, until the
 * static balance of every particle (Desrues et al. 2019 Eq. 19, Δ_n < tolerance) and
 * the pressure error are both met, or -t_end.
 *
 * scripts: the authors' LAMMPS preparation (create_random.py, relax.in, and
 * the relaxation of in.elastic in ManonVL/fem-dem-bridging-coupling):
 * bidisperse grains (d_min or d_max with probability 1/2 each) at random
 * centres, overlaps allowed, until the solid volume is -fill_fraction of a
 * cube of side -box d0; the frictionless gouge law (gran/hertz/history Kn 0
 * gamma_n 0 0 0) with a global viscous force -c v (fix viscous c); -push_steps
 * to push overlaps apart; then -cycles times {-relax_steps steps; compress
 * at engineering rate -erate on x, y and z (fix deform erate) until the mean
 * pressure reaches -pressure (fix halt) or -compress_steps}; then damped
 * chunks of -chunk_steps until the kinetic energy is below -ke_rest, the
 * damping off, undamped chunks until the kinetic energy stops decreasing.
 * The frictionless packing is written; friction is switched on (the law of
 * -contact/-friction, by default the gouge law lammps_hertz + lammps_history
 * of Table 1, = gran/hertz/history Kn Kt 0.2 NULL 0.5 1), the damping again
 * for -friction_damped_steps, chunks until at rest, undamped chunks until at
 * rest, and the frictional packing is written.  One difference from the
 * scripts: a random centre whose grain would overlap another by more than
 * -max_initial_overlap of the smaller radius is drawn again (a world refuses
 * initial overlaps beyond its limit, 0.5 of a radius by default, raised here
 * to -max_initial_overlap; the scripts allow any overlap).
 *
 * Defaults are Voisin-Leprince et al. 2023 Table 1: E = 50 GPa, ν = 0.3, ρ = 2500 kg/m³,
 * d ∈ [2.5, 3.5] mm, μ = 0.5, γ_n = 0.2, γ_t = 0.1 (1/(m s), the Hertz
 * form's damping), dt = 1e-8 s, 5 MPa; the cell side is 12 d0 (the size at
 * which the paper's moduli plateau).
 *
 * Output in -output_dir: compress.csv/.h5 (time, pressure, packing
 * fraction, kinetic energy, coordination, largest Δ_n, strain rate, stage)
 * and the final packing (packing_*.h5 + packing.xmf, with the cell: see
 * tl_dem_packing.h; scripts: also packing_frictionless_*.h5 and packing.data
 * for LAMMPS).  Last line:
 * summary: n=... pressure=... packing_fraction=... coordination=... wall=...
 *
 * Restart: -checkpoint_every n writes <output_dir>/checkpoint.h5 every n
 * steps (the world, the cell and its contacts, the table, the options, and
 * the protocol's state: the servo's loop step, or the scripts' phase, cycle,
 * and place in their loops with the figures the summary reports); -restart
 * <file> rebuilds the world from the same options (from the frictionless
 * packing file when the checkpoint is in the friction stage), loads the file
 * and continues bit for bit; -stop_step n ends the run after step n with a
 * checkpoint (to make one to restart from).  Servo: both multiples of
 * -control_every; scripts: at the first check (every -control_every or
 * -halt_every steps) at or after the step. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_options_checkpoint.h"
#include "tl_atomic_file.h"
#include "tl_dem.h"
#include "tl_dem_packing.h"
#include "tl_particle_snapshot.h"
#include "tl_timeseries.h"

enum { PROTOCOL_SERVO, PROTOCOL_SCRIPTS };
enum { DIST_UNIFORM, DIST_BIDISPERSE };
/* the stage column of compress.csv */
enum { STAGE_COMPRESS, STAGE_SERVO, STAGE_PUSH, STAGE_RELAX, STAGE_DEFORM, STAGE_SETTLE, STAGE_UNDAMPED,
       STAGE_FRICTION_DAMPED, STAGE_FRICTION_UNDAMPED };

typedef struct {
  int protocol, distribution, friction_stage;
  double d_min, d_max, density, pressure, dt, box_d0, phi0, inertial, inertial_gas;
  double t_end, tolerance, pressure_tolerance;
  double fill, max_overlap, viscous, mu_compaction, erate, ke_rest;
  long seed, control_every, checkpoint_every, stop_step;
  const char *restart;
  long push_steps, cycles, relax_steps, compress_steps, halt_every, chunk_steps, max_chunks, friction_damped_steps;
  int threads;
  const char *out;
  TlContactLaw *law;
} Settings;

static TlStatus options(int argc, char **argv, TlOptions **o, Settings *s)
{
  s->law = NULL;
  TL_CHECK(tl_options_create(argc, argv,
                             "Isotropic compression of a periodic Hertz packing to a target pressure, then "
                             "relaxation (the preparation of Voisin-Leprince et al. 2023, §3.1): under a pressure servo (-protocol servo) or "
                             "by the authors' LAMMPS scripts (-protocol scripts: frictionless compaction under "
                             "viscous damping until the pressure is reached, then friction on and relaxation).  Paper: " TL_PAPER_VOISIN_LEPRINCE_2023 ".",
                             o));
  static const char *const protocols[] = {"servo", "scripts", NULL};
  TL_CHECK(tl_options_get_choice(*o, "-protocol", "servo", protocols,
                                 "servo: inertial-number compression and pressure servo; scripts: the LAMMPS "
                                 "preparation of Voisin-Leprince et al.'s scripts (see the options marked [scripts])",
                                 &s->protocol));
  const int scripts = s->protocol == PROTOCOL_SCRIPTS;
  static const char *const dists[] = {"uniform", "bidisperse", NULL};
  TL_CHECK(tl_options_get_choice(*o, "-distribution", scripts ? "bidisperse" : "uniform", dists,
                                 "grain diameters: uniform in [d_min, d_max], or d_min or d_max with probability 1/2 "
                                 "each (the scripts' bi_size); default bidisperse with -protocol scripts",
                                 &s->distribution));
  TL_CHECK(tl_options_get_real(*o, "-d_min", 2.5e-3, 1e-9, 1e3, "m", "smallest diameter (Voisin-Leprince et al. 2023 Table 1)", &s->d_min));
  TL_CHECK(tl_options_get_real(*o, "-d_max", 3.5e-3, 1e-9, 1e3, "m", "largest diameter (Voisin-Leprince et al. 2023 Table 1)", &s->d_max));
  TL_CHECK(tl_options_get_real(*o, "-density", 2500, 1e-6, 1e6, "kg/m^3", "grain density (Table 1)", &s->density));
  if (scripts) {
    /* the gouge law of Table 1 = gran/hertz/history 3.663e10 4.5249e10 0.2 NULL 0.5 1 */
    TL_CHECK(tl_contact_law_from_options(*o, &tl_gouge_law_spec, &s->law));
  } else {
    /* Hertz with viscous damping and Coulomb friction, Voisin-Leprince et al. 2023 Table 1:
     * E = 50 GPa, nu = 0.3, mu_g = 0.5, gamma_n = 0.2, gamma_t = 0.1 1/(m s) */
    const TlContactValue law_values[] = {{"E", 50e9}, {"nu", 0.3}, {"mu", 0.5}, {"gamma_n", 0.2}, {"gamma_t", 0.1}};
    const TlContactSpec law_spec = {"hertz", "coulomb", NULL, NULL, law_values, 5};
    TL_CHECK(tl_contact_law_from_options(*o, &law_spec, &s->law));
  }
  TL_CHECK(tl_options_get_real(*o, "-pressure", 5e6, 1.0, 1e12, "Pa", "target confining pressure (Voisin-Leprince et al. 2023: 5 MPa)", &s->pressure));
  TL_CHECK(tl_options_get_real(*o, "-dt", 1e-8, 1e-15, 1.0, "s", "time step (Table 1)", &s->dt));
  TL_CHECK(tl_options_get_real(*o, "-box", scripts ? 6.0 : 12.0, 2.0, 1000.0, "d0",
                               "cell side in mean diameters d0 (servo: of the final packing, default 12; scripts: of "
                               "the initial box at -fill_fraction, default 6, as the scripts' box_0.018)", &s->box_d0));
  TL_CHECK(tl_options_get_real(*o, "-phi0", 0.3, 0.01, 0.5, "", "[servo] initial packing fraction of the gas", &s->phi0));
  TL_CHECK(tl_options_get_real(*o, "-inertial", 1e-3, 1e-7, 1.0, "",
                               "[servo] inertial number setting the strain rate near the target (Desrues et al. 2019 Eq. 18)", &s->inertial));
  TL_CHECK(tl_options_get_real(*o, "-inertial_gas", 3e-2, 1e-7, 10.0, "",
                               "[servo] inertial number of the initial compression, while the pressure is low", &s->inertial_gas));
  TL_CHECK(tl_options_get_real(*o, "-t_end", 0.05, 0.0, 1e6, "s", "[servo] longest simulated time", &s->t_end));
  TL_CHECK(tl_options_get_real(*o, "-tolerance", 1e-3, 1e-12, 1.0, "", "[servo] static balance Δ_n of every particle (Desrues et al. 2019 Eq. 19)", &s->tolerance));
  TL_CHECK(tl_options_get_real(*o, "-pressure_tolerance", 1e-2, 1e-9, 1.0, "", "[servo] relative pressure error at the end", &s->pressure_tolerance));
  TL_CHECK(tl_options_get_real(*o, "-fill_fraction", 0.6, 0.01, 0.9, "",
                               "[scripts] solid volume / box volume at which the random insertion stops (scripts: 0.60)", &s->fill));
  TL_CHECK(tl_options_get_real(*o, "-max_initial_overlap", 0.5, 0.0, 0.95, "",
                               "[scripts] largest initial overlap of two grains, in units of the smaller radius "
                               "(at most 0.95; the world's set-up refuses more)", &s->max_overlap));
  TL_CHECK(tl_options_get_real(*o, "-viscous", 0.5, 0.0, 1e9, "N s/m",
                               "[scripts] global viscous damping c: force -c v on every grain (LAMMPS fix viscous 0.5)", &s->viscous));
  TL_CHECK(tl_options_get_real(*o, "-mu_compaction", 0.0, 0.0, 1e4, "",
                               "[scripts] friction coefficient during the compaction (scripts: 0, no tangential force; > 0: "
                               "the friction part of -friction with this mu)", &s->mu_compaction));
  TL_CHECK(tl_options_get_real(*o, "-erate", 10.0, 1e-6, 1e6, "1/s",
                               "[scripts] engineering compression rate of each box side (LAMMPS fix deform erate -10)", &s->erate));
  TL_CHECK(tl_options_get_real(*o, "-ke_rest", 1e-15, 0.0, 1e3, "J",
                               "[scripts] translational kinetic energy below which the packing is at rest (scripts: 1e-15)", &s->ke_rest));
  TL_CHECK(tl_options_get_int(*o, "-push_steps", 100000, 0, 1000000000, "[scripts] steps pushing the initial overlaps apart", &s->push_steps));
  TL_CHECK(tl_options_get_int(*o, "-cycles", 100, 1, 1000000, "[scripts] relax + compress cycles (scripts: loop a, 100)", &s->cycles));
  TL_CHECK(tl_options_get_int(*o, "-relax_steps", 100000, 0, 1000000000, "[scripts] relaxation steps of each cycle", &s->relax_steps));
  TL_CHECK(tl_options_get_int(*o, "-compress_steps", 500000, 0, 1000000000,
                              "[scripts] longest compression of each cycle, in steps (it halts at -pressure)", &s->compress_steps));
  TL_CHECK(tl_options_get_int(*o, "-halt_every", 1, 1, 1000000,
                              "[scripts] steps between pressure checks while compressing (LAMMPS fix halt 1)", &s->halt_every));
  TL_CHECK(tl_options_get_int(*o, "-chunk_steps", 100000, 1, 1000000000,
                              "[scripts] steps between kinetic-energy checks of the relaxations", &s->chunk_steps));
  TL_CHECK(tl_options_get_int(*o, "-max_chunks", 50, 0, 1000000, "[scripts] most chunks of each relaxation loop (scripts: 50)", &s->max_chunks));
  TL_CHECK(tl_options_get_int(*o, "-friction_damped_steps", 1000000, 0, 1000000000,
                              "[scripts] damped steps after friction is switched on (in.elastic's in.relax: 1e6)", &s->friction_damped_steps));
  TL_CHECK(tl_options_get_bool(*o, "-friction_stage", 1, "[scripts] switch friction on and relax again after the compaction",
                               &s->friction_stage));
  TL_CHECK(tl_options_get_int(*o, "-control_every", 100, 1, 1000000, "steps between servo updates and table rows", &s->control_every));
  TL_CHECK(tl_options_get_int(*o, "-seed", 1, 0, 1000000000, "random seed of the initial gas", &s->seed));
  long th;
  TL_CHECK(tl_options_get_int(*o, "-threads", 0, 0, 1024, "OpenMP threads (0: default)", &th));
  s->threads = (int)th;
  TL_CHECK(tl_options_get_string(*o, "-output_dir", "results/periodic_compress", "output folder", &s->out));
  TL_CHECK(tl_output_dir_check(s->out));
  TL_CHECK(tl_options_get_int(*o, "-checkpoint_every", 0, 0, 1000000000,
                              "write <output_dir>/checkpoint.h5 every n steps (servo: a multiple of -control_every; "
                              "scripts: at the first check at or after each multiple of n; 0: never)",
                              &s->checkpoint_every));
  TL_CHECK(tl_options_get_string(*o, "-restart", "", "continue from this checkpoint file (same options)", &s->restart));
  TL_CHECK(tl_options_get_int(*o, "-stop_step", 0, 0, 1000000000,
                              "stop with a checkpoint after this step (servo: a multiple of -control_every; scripts: "
                              "at the first check at or after it; 0: run to the end)", &s->stop_step));
  if (!scripts && s->checkpoint_every % s->control_every != 0)
    TL_ERROR(TL_ERR_ARG, "-checkpoint_every %ld is not a multiple of -control_every %ld (the servo's cadence)",
             s->checkpoint_every, s->control_every);
  if (!scripts && s->stop_step % s->control_every != 0)
    TL_ERROR(TL_ERR_ARG, "-stop_step %ld is not a multiple of -control_every %ld (the servo's cadence)", s->stop_step,
             s->control_every);
  return tl_options_finish(*o, stdout);
}

static double pressure_of(TlDem *dem)
{
  TlMat3 sc, sk;
  if (tl_dem_stress(dem, &sc, &sk) != TL_OK) return NAN;
  return -(tl_m3_trace(sc) + tl_m3_trace(sk)) / 3.0;
}

static double kinetic_of(const TlParticles *P)
{
  double ke = 0.0;
  for (size_t i = 0; i < P->n; ++i) ke += 0.5 * P->mass[i] * tl_v3_norm2(P->v[i]);
  return ke;
}

/* A radius of the size distribution: uniform in diameter, or one of the two
 * sizes with probability 1/2 (the scripts' np.random.choice([dmin, dmax])). */
static double sample_radius(const Settings *s, const TlSpecies *sp, uint64_t *rng)
{
  if (s->distribution == DIST_BIDISPERSE) return tl_random_uniform(rng) < 0.5 ? 0.5 * s->d_min : 0.5 * s->d_max;
  return tl_species_sample_radius(sp, rng);
}

/* Mean grain volume of the size distribution. */
static double mean_volume(const Settings *s, double d0)
{
  if (s->distribution == DIST_BIDISPERSE) return TL_PI / 12.0 * (pow(s->d_min, 3) + pow(s->d_max, 3));
  if (s->d_max - s->d_min < 1e-12 * d0) return TL_PI / 6.0 * d0 * d0 * d0;
  return TL_PI / 6.0 * (pow(s->d_max, 4) - pow(s->d_min, 4)) / (4.0 * (s->d_max - s->d_min + 1e-300));
}

/* ------------------------------------------------------------ the run state */

/* The phases of -protocol scripts, in order. */
enum { PH_PUSH, PH_CYCLES, PH_SETTLE, PH_UNDAMPED, PH_SETTLE_UNDAMPED, PH_FRICTIONLESS, PH_FRICTION_DAMPED,
       PH_FRICTION_SETTLE, PH_FRICTION_UNDAMPED, PH_FRICTION_SETTLE_UNDAMPED, PH_DONE };

/* A -protocol scripts run.  Everything below `dem` up to `frictionless` is
 * the run's position (the phase and where its loops are) and what its
 * summary reports, checkpointed with the world and the table: a restart
 * continues at the same point of the same loops. */
typedef struct {
  const Settings *s;
  TlDem *dem;
  TlTimeSeries *ts;
  TlCheckpoint *cp;
  char cp_path[4200];
  int stopped; /* -stop_step reached: a checkpoint was written, the run ends */
  int64_t phase, cycle, in_compress; /* in_compress: the cycle's relaxation is done */
  int64_t k;                         /* steps done by the current advance or compression */
  int64_t since_row;                 /* compression: steps since its last table row */
  int64_t compress_started, compress_done;
  int64_t settle_started, chunk, at_rest; /* settle: its chunks so far, at rest after the last */
  int64_t steps;                          /* steps done by every world of the run */
  int64_t cycles_reaching, rest_damped, rest;
  double ke;                        /* settle: the kinetic energy after the previous chunk */
  double pr;                        /* compression: the pressure at its last check */
  double vol_grains, rate, c_visc;  /* c_visc: the viscous coefficient in force, N s/m */
  /* the first halt of a compression: the pressure there and at the check before */
  double halt_pressure, halt_pressure_before;
  double p_frictionless, phi_frictionless;
  char frictionless[4096]; /* the frictionless packing file the friction stage starts from */
} Run;

enum { RUN_INTS = 16, RUN_REALS = 10 };

static void run_ints(const Run *r, int64_t v[RUN_INTS])
{
  const int64_t a[RUN_INTS] = {r->phase,      r->cycle,       r->in_compress,     r->k,           r->since_row,
                               r->compress_started, r->compress_done, r->settle_started, r->chunk, r->at_rest,
                               r->steps,      r->cycles_reaching, r->rest_damped, r->rest,        0, 0};
  memcpy(v, a, sizeof a);
}

static void run_reals(const Run *r, double v[RUN_REALS])
{
  const double a[RUN_REALS] = {r->ke,          r->pr,        r->vol_grains,           r->rate,
                               r->c_visc,      r->halt_pressure, r->halt_pressure_before, r->p_frictionless,
                               r->phi_frictionless, 0.0};
  memcpy(v, a, sizeof a);
}

static TlStatus scripts_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const Run *r = object;
  int64_t iv[RUN_INTS];
  double rv[RUN_REALS];
  run_ints(r, iv);
  run_reals(r, rv);
  TL_CHECK(tl_checkpoint_write_int64s(w, group, "position", RUN_INTS, iv));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "figures", RUN_REALS, rv));
  TL_CHECK(tl_checkpoint_write_string(w, group, "frictionless", r->frictionless));
  return TL_OK;
}

/* Every value checked against what the run's loops can reach before any is
 * used (a checkpoint is input like any other). */
static TlStatus scripts_load(void *object, TlCheckpointReader *rd, const char *group)
{
  Run *r = object;
  const Settings *s = r->s;
  int64_t iv[RUN_INTS];
  double rv[RUN_REALS];
  char *path = NULL;
  TL_CHECK(tl_checkpoint_read_int64s(rd, group, "position", RUN_INTS, iv));
  TL_CHECK(tl_checkpoint_read_doubles(rd, group, "figures", RUN_REALS, rv));
  static const char *const inames[] = {"phase",  "cycle", "in_compress", "k", "since_row", "compress_started",
                                       "compress_done", "settle_started", "chunk", "at_rest", "steps",
                                       "cycles_reaching", "rest_damped", "rest", "spare", "spare"};
  const int64_t big = INT64_MAX / 4;
  int64_t longest = s->push_steps;
  const long lengths[] = {s->relax_steps, s->compress_steps, s->chunk_steps, s->friction_damped_steps};
  for (int i = 0; i < 4; ++i) longest = lengths[i] > longest ? lengths[i] : longest;
  const int64_t hi[RUN_INTS] = {PH_DONE - 1, s->cycles, 1, longest, big, 1, 1, 1, s->max_chunks, 1,
                                big, s->cycles, 1, 1, 0, 0};
  char name[64];
  for (int i = 0; i < RUN_INTS; ++i) {
    snprintf(name, sizeof name, "position[%d] (%s)", i, inames[i]);
    TL_CHECK(tl_checkpoint_check_count(rd, group, name, iv[i], 0, hi[i]));
  }
  static const char *const rnames[] = {"ke", "pressure", "grain volume", "strain rate", "viscous coefficient",
                                       "halt_pressure", "halt_pressure_before", "pressure_frictionless",
                                       "packing_fraction_frictionless", "spare"};
  for (int i = 0; i < RUN_REALS; ++i) {
    if ((i == 5 || i == 6) && isnan(rv[i])) continue; /* no compression has halted yet */
    snprintf(name, sizeof name, "figures[%d] (%s)", i, rnames[i]);
    TL_CHECK(tl_checkpoint_check_finite(rd, group, name, 1, &rv[i]));
  }
  if (!(rv[2] > 0.0)) TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': %s/figures[2] (grain volume) = %g must be > 0",
                               tl_checkpoint_reader_path(rd), group, rv[2]);
  if (rv[4] != 0.0 && rv[4] != s->viscous)
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': %s/figures[4] (viscous coefficient) = %g is neither 0 nor -viscous %g",
             tl_checkpoint_reader_path(rd), group, rv[4], s->viscous);
  TL_CHECK(tl_checkpoint_read_string(rd, group, "frictionless", &path));
  const size_t len = strlen(path);
  if (len >= sizeof r->frictionless || (iv[0] >= PH_FRICTION_DAMPED && len == 0)) {
    tl_free(&path);
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': %s/frictionless holds %zu characters (a path of 1 to %zu needed from "
             "the friction stage on)", tl_checkpoint_reader_path(rd), group, len, sizeof r->frictionless - 1);
  }
  memcpy(r->frictionless, path, len + 1);
  tl_free(&path);
  r->phase = iv[0], r->cycle = iv[1], r->in_compress = iv[2], r->k = iv[3], r->since_row = iv[4];
  r->compress_started = iv[5], r->compress_done = iv[6], r->settle_started = iv[7], r->chunk = iv[8];
  r->at_rest = iv[9], r->steps = iv[10], r->cycles_reaching = iv[11], r->rest_damped = iv[12], r->rest = iv[13];
  r->ke = rv[0], r->pr = rv[1], r->vol_grains = rv[2], r->rate = rv[3], r->c_visc = rv[4];
  r->halt_pressure = rv[5], r->halt_pressure_before = rv[6], r->p_frictionless = rv[7], r->phi_frictionless = rv[8];
  return TL_OK;
}

static const TlCheckpointOps scripts_checkpoint_ops = {
    .header = {"checkpoint", "periodic_compress_scripts_v1", "phase and loop position of periodic_compress -protocol scripts"},
    .save = scripts_save,
    .load = scripts_load,
};

static TlStatus viscous_hook(void *ctx, TlDem *dem)
{
  const Run *r = ctx;
  TlParticles *P = tl_dem_particles(dem);
  /* LAMMPS fix viscous: -c v with the half-step velocity, added after the
   * forces of the step (here before them: the same sum) */
  for (size_t i = 0; i < P->n; ++i)
    P->f_coupling[i] = P->motion[i] == TL_MOTION_FREE ? tl_v3_scale(P->v[i], -r->c_visc) : tl_v3(0, 0, 0);
  return TL_OK;
}

static void set_viscous(Run *r, double c)
{
  TlParticles *P = tl_dem_particles(r->dem);
  r->c_visc = c;
  if (!(c > 0.0))
    for (size_t i = 0; i < P->n; ++i) P->f_coupling[i] = tl_v3(0, 0, 0);
  tl_dem_set_step_hook(r->dem, c > 0.0 ? viscous_hook : NULL, r);
}

static TlStatus log_row(Run *r, int stage, double pr)
{
  double imbalance, z;
  TL_CHECK(tl_dem_max_force_imbalance(r->dem, &imbalance));
  TL_CHECK(tl_dem_coordination(r->dem, &z, NULL));
  const TlDomain *D = tl_dem_domain(r->dem);
  double row[] = {tl_dem_time(r->dem), pr,      r->vol_grains / tl_domain_volume(D), kinetic_of(tl_dem_particles(r->dem)),
                  z,                   imbalance, r->rate,                           (double)stage};
  return tl_timeseries_append(r->ts, row);
}

/* After every block of steps: a checkpoint when the step count crossed a
 * multiple of -checkpoint_every, or reached -stop_step (then the run ends).
 * It is written at the end of an iteration of the loop doing the steps, so a
 * restart continues with the next iteration. */
static TlStatus after_block(Run *r, int64_t before)
{
  const Settings *s = r->s;
  const long ce = s->checkpoint_every;
  r->stopped = s->stop_step > 0 && r->steps >= s->stop_step;
  if ((ce > 0 && r->steps / ce > before / ce) || r->stopped)
    TL_CHECK(tl_checkpoint_save(r->cp, r->cp_path, tl_dem_time(r->dem), r->steps));
  return TL_OK;
}

/* n steps in blocks of control_every, a table row before each block; from
 * step r->k of them (a restart). */
static TlStatus advance(Run *r, long n, int stage)
{
  while (r->k < n) {
    long b = n - r->k < r->s->control_every ? n - r->k : r->s->control_every;
    TL_CHECK(log_row(r, stage, pressure_of(r->dem)));
    const int64_t before = r->steps;
    TL_CHECK(tl_dem_step(r->dem, b));
    r->k += b;
    r->steps += b;
    TL_CHECK(after_block(r, before));
    if (r->stopped) return TL_OK;
  }
  r->k = 0;
  return TL_OK;
}

/* Compression at engineering rate -erate of every side (ḣ = -erate h0 for
 * the whole stage, as fix deform erate) until the mean pressure reaches the
 * target, checked every -halt_every steps (fix halt), or -compress_steps. */
static TlStatus compress(Run *r, int *reached)
{
  const Settings *s = r->s;
  TlDomain *D = tl_dem_domain(r->dem);
  *reached = 0;
  if (!r->compress_started) {
    r->pr = pressure_of(r->dem);
    if (r->pr >= s->pressure) {
      *reached = 1;
      return TL_OK;
    }
    TL_CHECK(tl_domain_set_h_rate(D, tl_m3_scale(D->h, -s->erate)));
    r->rate = -s->erate;
    r->k = 0, r->since_row = s->control_every, r->compress_done = 0, r->compress_started = 1;
  }
  while (!r->compress_done && r->k < s->compress_steps) {
    if (r->since_row >= s->control_every) {
      TL_CHECK(log_row(r, STAGE_DEFORM, r->pr));
      r->since_row = 0;
    }
    long b = s->halt_every;
    if (b > s->compress_steps - r->k) b = s->compress_steps - r->k;
    const int64_t steps_before = r->steps;
    TL_CHECK(tl_dem_step(r->dem, b));
    r->k += b, r->steps += b, r->since_row += b;
    const double before = r->pr;
    r->pr = pressure_of(r->dem);
    if (r->pr >= s->pressure) {
      r->compress_done = 1;
      if (isnan(r->halt_pressure)) r->halt_pressure = r->pr, r->halt_pressure_before = before;
    }
    TL_CHECK(after_block(r, steps_before));
    if (r->stopped) return TL_OK;
  }
  *reached = (int)r->compress_done;
  r->k = 0, r->compress_started = r->compress_done = 0;
  r->rate = 0.0;
  TL_CHECK(tl_domain_set_h_rate(D, tl_m3_zero()));
  return TL_OK;
}

/* Chunks of -chunk_steps (at most -max_chunks) until the kinetic energy is
 * below -ke_rest, or (stop_on_rise) no longer decreases. */
static TlStatus settle(Run *r, int stage, int stop_on_rise, int64_t *at_rest)
{
  const Settings *s = r->s;
  const TlParticles *P = tl_dem_particles(r->dem);
  if (!r->settle_started) {
    r->ke = kinetic_of(P);
    r->at_rest = r->ke < s->ke_rest;
    r->chunk = 0, r->settle_started = 1;
  }
  while (r->chunk < s->max_chunks && !r->at_rest) {
    TL_CHECK(advance(r, s->chunk_steps, stage));
    if (r->stopped) return TL_OK;
    double ke1 = kinetic_of(P);
    r->at_rest = ke1 < s->ke_rest;
    ++r->chunk;
    if (stop_on_rise && !(ke1 < r->ke)) break;
    r->ke = ke1;
  }
  *at_rest = r->at_rest;
  r->settle_started = 0;
  return TL_OK;
}

/* Random centres in the cube [0, L)^3, overlaps allowed up to max_overlap
 * of the smaller radius, until the grains' volume reaches fill L^3. */
static TlStatus insert_overlapping(const Settings *s, TlDem *dem, int sp, double L, uint64_t *rng)
{
  TlParticles *P = tl_dem_particles(dem);
  const TlDomain *dom = tl_dem_domain(dem);
  double vol = 0.0;
  while (vol < s->fill * L * L * L) {
    double r = sample_radius(s, &P->species_table[sp], rng);
    int placed = 0;
    for (int attempt = 0; attempt < 100000 && !placed; ++attempt) {
      TlVec3 x = {L * tl_random_uniform(rng), L * tl_random_uniform(rng), L * tl_random_uniform(rng)};
      placed = 1;
      for (size_t i = 0; i < P->n && placed; ++i)
        placed = tl_v3_norm(tl_domain_branch(dom, P->x[i], x)) > P->radius[i] + r - s->max_overlap * fmin(P->radius[i], r);
      if (placed) TL_CHECK(tl_dem_add_particle(dem, x, tl_v3(0, 0, 0), r, sp, NULL));
    }
    if (!placed)
      TL_ERROR(TL_ERR_ARG, "could not place grain %zu: -fill_fraction %g too dense for -max_initial_overlap %g", P->n,
               s->fill, s->max_overlap);
    vol += 4.0 / 3.0 * TL_PI * r * r * r;
  }
  return TL_OK;
}

static void count_sizes(const Settings *s, const TlParticles *P, long *n_small, long *n_large)
{
  *n_small = *n_large = 0;
  for (size_t i = 0; i < P->n; ++i) {
    if (P->radius[i] == 0.5 * s->d_min) ++*n_small;
    if (P->radius[i] == 0.5 * s->d_max) ++*n_large;
  }
}

static TlStatus open_table(const Settings *s, TlTimeSeries **ts)
{
  TL_CHECK(tl_mkdir_p(s->out));
  char base[4096];
  snprintf(base, sizeof base, "%s/compress", s->out);
  static const TlColumn cols[] = {{"time", "s"},         {"pressure", "Pa"},      {"packing_fraction", ""},
                                  {"kinetic", "J"},      {"coordination", ""},    {"max_imbalance", ""},
                                  {"strain_rate", "1/s"}, {"stage", ""}};
  return tl_timeseries_create(base, TL_TIMESERIES_CSV | TL_TIMESERIES_HDF5, sizeof cols / sizeof cols[0], cols, ts);
}

static double grain_volume(const TlParticles *P)
{
  double v = 0.0;
  for (size_t i = 0; i < P->n; ++i) v += 4.0 / 3.0 * TL_PI * pow(P->radius[i], 3);
  return v;
}

static void configure(TlDem *dem, const Settings *s)
{
  tl_dem_set_threads(dem, s->threads);
  tl_dem_track_energy(dem, 0);
}

/* ------------------------------------------------------- -protocol scripts */

/* The world of the friction stage: the frictionless packing file read back
 * (its contacts carry no tangential history: the scripts' read of the data
 * file) with the law of -contact/-friction. */
static TlStatus friction_world(Settings *s, const char *path, TlDem **out)
{
  TL_CHECK(tl_dem_create(out));
  TlDem *dem = *out;
  TL_CHECK(tl_dem_packing_load(dem, path, s->density, NULL));
  TL_CHECK(tl_dem_add_law(dem, s->law, NULL));
  s->law = NULL;
  TL_CHECK(tl_particles_enable_coupling_force(tl_dem_particles(dem)));
  configure(dem, s);
  TL_CHECK(tl_dem_set_timestep(dem, s->dt, 0));
  TL_CHECK(tl_dem_setup(dem));
  return TL_OK;
}

/* The world of the compaction: the random insertion, the frictionless law. */
static TlStatus compaction_world(const Settings *s, TlDem **out)
{
  const double d0 = 0.5 * (s->d_min + s->d_max), L = s->box_d0 * d0;
  TL_CHECK(tl_dem_create(out));
  TlDem *dem = *out;
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "gouge", s->density, 0.5 * s->d_min, 0.5 * s->d_max, &sp));
  TlDomain dom;
  TL_CHECK(tl_domain_init_cell(&dom, tl_v3(0, 0, 0), tl_m3_scale(tl_m3_identity(), L)));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  uint64_t rng = (uint64_t)s->seed * 0x9e3779b97f4a7c15ULL + 1;
  TL_CHECK(insert_overlapping(s, dem, sp, L, &rng));
  /* compaction law: the normal part of the gouge law, friction off (or
   * -mu_compaction) */
  double kn, gn;
  TlStatus st = tl_contact_law_get(s->law, "k_n", &kn);
  if (st == TL_OK) st = tl_contact_law_get(s->law, "gamma_n", &gn);
  if (st != TL_OK || !(kn > 0.0))
    TL_ERROR(TL_ERR_ARG, "-protocol scripts compacts with the normal part lammps_hertz and takes its k_n (here %g Pa) "
             "and gamma_n from the chosen law: use -contact lammps_hertz with -contact_k_n > 0", st == TL_OK ? kn : 0.0);
  TlContactLaw *law_c;
  {
    double kt = 0.0, gt = -1.0;
    tl_contact_law_get(s->law, "k_t", &kt);
    tl_contact_law_get(s->law, "gamma_t", &gt);
    const TlContactValue v[] = {{"k_n", kn}, {"gamma_n", gn}, {"k_t", kt}, {"gamma_t", gt}, {"mu", s->mu_compaction}};
    const TlContactSpec spec = {"lammps_hertz", s->mu_compaction > 0.0 ? "lammps_history" : NULL, NULL, NULL, v,
                                s->mu_compaction > 0.0 ? 5 : 2};
    TL_CHECK(tl_contact_law_build(&spec, &law_c));
  }
  st = tl_dem_add_law(dem, law_c, NULL);
  if (st != TL_OK) {
    tl_contact_law_destroy(&law_c);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  TL_CHECK(tl_particles_enable_coupling_force(P));
  configure(dem, s);
  /* the random insertion overlaps grains up to -max_initial_overlap on purpose */
  TL_CHECK(tl_dem_set_max_initial_overlap(dem, fmax(TL_DEM_MAX_INITIAL_OVERLAP, fmin(1.0, s->max_overlap))));
  TL_CHECK(tl_dem_set_timestep(dem, s->dt, 0));
  TL_CHECK(tl_dem_setup(dem));
  return TL_OK;
}

/* The checkpoint's sections, on the world of the current stage. */
static TlStatus make_checkpoint(Run *r, TlOptions *o)
{
  tl_checkpoint_destroy(&r->cp);
  TL_CHECK(tl_checkpoint_create(&r->cp));
  TL_CHECK(tl_checkpoint_add(r->cp, "options", &tl_options_checkpoint_ops, o));
  TL_CHECK(tl_checkpoint_add(r->cp, "dem", &tl_dem_checkpoint_ops, r->dem));
  TL_CHECK(tl_checkpoint_add(r->cp, "table", &tl_timeseries_checkpoint_ops, r->ts));
  TL_CHECK(tl_checkpoint_add(r->cp, "scripts", &scripts_checkpoint_ops, r));
  return TL_OK;
}

/* The relax + compress cycles, from cycle r->cycle. */
static TlStatus cycles(Run *r)
{
  const Settings *s = r->s;
  while (r->cycle < s->cycles) {
    if (!r->in_compress) {
      TL_CHECK(advance(r, s->relax_steps, STAGE_RELAX));
      if (r->stopped) return TL_OK;
      r->in_compress = 1;
    }
    int reached;
    TL_CHECK(compress(r, &reached));
    if (r->stopped) return TL_OK;
    r->cycles_reaching += reached;
    r->in_compress = 0;
    const long c = (long)r->cycle++;
    tl_printf("cycle %ld: pressure %.6g Pa%s, packing fraction %.4f, step %ld\n", c + 1, pressure_of(r->dem),
              reached ? " (target reached)" : "", r->vol_grains / tl_domain_volume(tl_dem_domain(r->dem)), (long)r->steps);
    fflush(stdout);
  }
  return TL_OK;
}

/* The frictionless packing written; the world of the friction stage. */
static TlStatus frictionless_end(Run *r, Settings *s, TlOptions *o)
{
  TlDem *dem = r->dem;
  const TlParticles *P = tl_dem_particles(dem);
  r->p_frictionless = pressure_of(dem);
  r->phi_frictionless = r->vol_grains / tl_domain_volume(tl_dem_domain(dem));
  tl_printf("frictionless packing after %ld steps: pressure %.6g Pa, packing fraction %.4f, kinetic energy %.3g J\n",
            (long)r->steps, r->p_frictionless, r->phi_frictionless, kinetic_of(P));
  TlParticleWriter *writer;
  TL_CHECK(tl_particle_writer_create(s->out, "packing_frictionless", &writer));
  const char *file;
  TlStatus st = tl_dem_packing_write(dem, writer, r->steps, &file);
  if (st == TL_OK && strlen(file) >= sizeof r->frictionless)
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "packing path '%s' longer than %zu characters", file,
                      sizeof r->frictionless - 1);
  if (st == TL_OK) snprintf(r->frictionless, sizeof r->frictionless, "%s", file);
  tl_particle_writer_destroy(&writer);
  TL_CHECK(st);
  if (!s->friction_stage) return TL_OK;
  tl_dem_destroy(&r->dem);
  TL_CHECK(friction_world(s, r->frictionless, &r->dem));
  TL_CHECK(make_checkpoint(r, o));
  return TL_OK;
}

static TlStatus copy_stream(FILE *out, void *ctx)
{
  FILE *in = fopen((const char *)ctx, "rb");
  if (!in) TL_ERROR(TL_ERR_IO, "cannot read '%s'", (const char *)ctx);
  char buf[65536];
  size_t n;
  int ok = 1;
  while (ok && (n = fread(buf, 1, sizeof buf, in)) > 0) ok = fwrite(buf, 1, n, out) == n;
  ok = ok && !ferror(in);
  fclose(in);
  if (!ok) TL_ERROR(TL_ERR_IO, "cannot copy '%s'", (const char *)ctx);
  return TL_OK;
}

/* A restart of the friction stage into another -output_dir: the frictionless
 * packing (its .h5 and the .xmf naming it) is copied there, so the folder
 * holds every output of the run; the friction stage then reads the copy. */
static TlStatus copy_frictionless(Run *r, const Settings *s)
{
  const char *slash = strrchr(r->frictionless, '/');
  const char *base = slash ? slash + 1 : r->frictionless;
  char to[8300], from_xmf[4200], to_xmf[4200];
  snprintf(to, sizeof to, "%s/%s", s->out, base);
  if (strlen(to) >= sizeof r->frictionless) TL_ERROR(TL_ERR_ARG, "path '%s' too long", to);
  if (access(to, R_OK) != 0) { /* not restarted in the folder that holds it */
    snprintf(from_xmf, sizeof from_xmf, "%.*spacking_frictionless.xmf", (int)(base - r->frictionless), r->frictionless);
    snprintf(to_xmf, sizeof to_xmf, "%s/packing_frictionless.xmf", s->out);
    TL_CHECK(tl_atomic_write(to, copy_stream, r->frictionless));
    if (access(from_xmf, R_OK) == 0) TL_CHECK(tl_atomic_write(to_xmf, copy_stream, from_xmf));
  }
  snprintf(r->frictionless, sizeof r->frictionless, "%s", to);
  return TL_OK;
}

static TlStatus scripts_body(Run *r, Settings *s, TlOptions *o, double wall0)
{
  const double d0 = 0.5 * (s->d_min + s->d_max), L = s->box_d0 * d0;
  snprintf(r->cp_path, sizeof r->cp_path, "%s/checkpoint.h5", s->out);
  if (s->restart[0]) {
    /* where the run is first: it says which world to build */
    TlCheckpoint *head = NULL;
    TlStatus st = tl_checkpoint_create(&head);
    if (st == TL_OK) st = tl_checkpoint_add(head, "options", &tl_options_checkpoint_ops, o);
    if (st == TL_OK) st = tl_checkpoint_add(head, "scripts", &scripts_checkpoint_ops, r);
    if (st == TL_OK) st = tl_checkpoint_load(head, s->restart, NULL, NULL);
    tl_checkpoint_destroy(&head);
    TL_CHECK(st);
  }
  const int friction = r->phase >= PH_FRICTION_DAMPED;
  if (friction) TL_CHECK(copy_frictionless(r, s));
  if (friction) TL_CHECK(friction_world(s, r->frictionless, &r->dem));
  else TL_CHECK(compaction_world(s, &r->dem));
  TlDem *dem = r->dem;
  TlParticles *P = tl_dem_particles(dem);
  const size_t n = P->n;
  long n_small, n_large;
  count_sizes(s, P, &n_small, &n_large);
  if (!s->restart[0]) {
    r->vol_grains = grain_volume(P);
    tl_printf("periodic_compress -protocol scripts: %zu grains (%ld of d = %g m, %ld of d = %g m) in a %.4g m box "
              "(%.3g d0) at solid fraction %.4f, target %g Pa, dt %g s\n",
              n, n_small, s->d_min, n_large, s->d_max, L, s->box_d0, grain_volume(P) / (L * L * L), s->pressure, s->dt);
  }
  TL_CHECK(open_table(s, &r->ts));
  TL_CHECK(make_checkpoint(r, o));
  if (s->restart[0]) {
    TL_CHECK(tl_checkpoint_load(r->cp, s->restart, NULL, NULL));
    if (friction) TL_CHECK(copy_frictionless(r, s)); /* the load restored the path the checkpoint names */
    tl_printf("restarted from %s at step %lld (phase %lld), t = %.9g s\n", s->restart, (long long)r->steps,
              (long long)r->phase, tl_dem_time(dem));
  }
  set_viscous(r, r->c_visc);
  while (r->phase < PH_DONE && !r->stopped) {
    switch (r->phase) {
    case PH_PUSH: TL_CHECK(advance(r, s->push_steps, STAGE_PUSH)); break;
    case PH_CYCLES: TL_CHECK(cycles(r)); break;
    case PH_SETTLE: TL_CHECK(settle(r, STAGE_SETTLE, 0, &r->rest_damped)); break;
    case PH_UNDAMPED: TL_CHECK(advance(r, s->chunk_steps, STAGE_UNDAMPED)); break;
    case PH_SETTLE_UNDAMPED: TL_CHECK(settle(r, STAGE_UNDAMPED, 1, &r->rest)); break;
    case PH_FRICTIONLESS: TL_CHECK(frictionless_end(r, s, o)); break;
    case PH_FRICTION_DAMPED: TL_CHECK(advance(r, s->friction_damped_steps, STAGE_FRICTION_DAMPED)); break;
    case PH_FRICTION_SETTLE: TL_CHECK(settle(r, STAGE_FRICTION_DAMPED, 0, &r->rest_damped)); break;
    case PH_FRICTION_UNDAMPED: TL_CHECK(advance(r, s->chunk_steps, STAGE_FRICTION_UNDAMPED)); break;
    case PH_FRICTION_SETTLE_UNDAMPED: TL_CHECK(settle(r, STAGE_FRICTION_UNDAMPED, 1, &r->rest)); break;
    }
    if (r->stopped) break;
    /* the next phase, and what changes on entering it */
    ++r->phase;
    if (r->phase == PH_UNDAMPED || r->phase == PH_FRICTION_UNDAMPED) set_viscous(r, 0.0);
    if (r->phase == PH_FRICTION_DAMPED) {
      if (!s->friction_stage) r->phase = PH_DONE;
      else set_viscous(r, s->viscous);
    }
  }
  dem = r->dem;
  P = tl_dem_particles(dem);
  if (r->stopped) {
    TL_CHECK(tl_timeseries_close(&r->ts));
    tl_printf("stopped after step %lld (-stop_step): %s continues the run with -restart\n", (long long)r->steps,
              r->cp_path);
    TlSummary sum;
    tl_summary_init(&sum);
    tl_summary_int(&sum, "n", (long)n);
    tl_summary_int(&sum, "steps", (long)r->steps);
    tl_summary_string(&sum, "stopped", "true");
    tl_summary_real(&sum, "wall", tl_wtime() - wall0);
    return tl_summary_print(&sum, stdout);
  }
  const int rest = (int)r->rest;
  const double pr = pressure_of(dem);
  TL_CHECK(log_row(r, s->friction_stage ? STAGE_FRICTION_UNDAMPED : STAGE_UNDAMPED, pr));
  TL_CHECK(tl_timeseries_close(&r->ts));
  TlParticleWriter *writer;
  TL_CHECK(tl_particle_writer_create(s->out, "packing", &writer));
  TlStatus st = tl_dem_packing_write(dem, writer, r->steps, NULL);
  tl_particle_writer_destroy(&writer);
  TL_CHECK(st);
  char path[4096];
  snprintf(path, sizeof path, "%s/packing.data", s->out);
  TL_CHECK(tl_dem_packing_write_lammps(dem, s->density, path));
  double z, imbalance;
  TL_CHECK(tl_dem_coordination(dem, &z, NULL));
  TL_CHECK(tl_dem_max_force_imbalance(dem, &imbalance));
  const TlDomain *D = tl_dem_domain(dem);
  const double phi = r->vol_grains / tl_domain_volume(D), side = cbrt(tl_domain_volume(D)), ke = kinetic_of(P);
  tl_printf("%s after %ld steps: pressure %.6g Pa (target %g), packing fraction %.4f, coordination %.3f, largest Δ_n "
            "%.3g, kinetic energy %.3g J, cell %.6g m = %.4f d0\n",
            rest ? "at rest" : "not at rest", (long)r->steps, pr, s->pressure, phi, z, imbalance, ke, side, side / d0);
  TlSummary sum;
  tl_summary_init(&sum);
  tl_summary_int(&sum, "n", (long)n);
  tl_summary_int(&sum, "n_small", n_small);
  tl_summary_int(&sum, "n_large", n_large);
  tl_summary_int(&sum, "steps", (long)r->steps);
  tl_summary_int(&sum, "cycles_reaching", (long)r->cycles_reaching);
  if (!isnan(r->halt_pressure)) {
    tl_summary_real(&sum, "halt_pressure", r->halt_pressure);
    tl_summary_real(&sum, "halt_pressure_before", r->halt_pressure_before);
  }
  tl_summary_int(&sum, "at_rest", rest);
  tl_summary_real(&sum, "pressure_frictionless", r->p_frictionless);
  tl_summary_real(&sum, "packing_fraction_frictionless", r->phi_frictionless);
  tl_summary_real(&sum, "pressure", pr);
  tl_summary_real(&sum, "packing_fraction", phi);
  tl_summary_real(&sum, "coordination", z);
  tl_summary_real(&sum, "max_imbalance", imbalance);
  tl_summary_real(&sum, "kinetic", ke);
  tl_summary_real(&sum, "cell_d0", side / d0);
  tl_summary_real(&sum, "wall", tl_wtime() - wall0);
  return tl_summary_print(&sum, stdout);
}

static TlStatus run_scripts(Settings *s, TlOptions *o, double wall0)
{
  Run r;
  memset(&r, 0, sizeof r);
  r.s = s;
  r.c_visc = s->viscous;
  r.halt_pressure = r.halt_pressure_before = NAN;
  TlStatus st = scripts_body(&r, s, o, wall0);
  tl_checkpoint_destroy(&r.cp);
  if (r.ts) (void)tl_timeseries_close(&r.ts);
  tl_dem_destroy(&r.dem);
  return st;
}

/* --------------------------------------------------------- -protocol servo */

/* The servo's own state, checkpointed with the run: the loop step it
 * continues with and whether the target pressure was reached (compression
 * gave way to the servo). */
typedef struct {
  int64_t next_step, reached;
} ServoState;

static TlStatus servo_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const ServoState *p = object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "next_step", p->next_step));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "reached", p->reached));
  return TL_OK;
}

static TlStatus servo_load(void *object, TlCheckpointReader *r, const char *group)
{
  ServoState *p = object;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "next_step", &p->next_step));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "reached", &p->reached));
  TL_CHECK(tl_checkpoint_check_count(r, group, "next_step", p->next_step, 0, INT64_MAX));
  TL_CHECK(tl_checkpoint_check_count(r, group, "reached", p->reached, 0, 1));
  return TL_OK;
}

static const TlCheckpointOps servo_checkpoint_ops = {
    .header = {"checkpoint", "periodic_compress_servo_v1", "loop step and stage of the periodic_compress servo"},
    .save = servo_save,
    .load = servo_load,
};

static TlStatus run_servo(Settings *s, TlOptions *o, double wall0)
{
  const double d0 = 0.5 * (s->d_min + s->d_max);
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_CHECK(tl_particles_add_species(P, "gouge", s->density, 0.5 * s->d_min, 0.5 * s->d_max, &sp));
  /* number of grains: a dense packing (φ ≈ 0.64) of the final cell */
  double L_final = s->box_d0 * d0;
  double mean_vol = mean_volume(s, d0);
  long n = (long)(0.64 * L_final * L_final * L_final / mean_vol);
  if (n < 2) n = 2;
  double L0 = cbrt((double)n * mean_vol / s->phi0);
  TlDomain dom;
  TL_CHECK(tl_domain_init_cell(&dom, tl_v3(0, 0, 0), tl_m3_scale(tl_m3_identity(), L0)));
  TL_CHECK(tl_dem_set_domain(dem, &dom));
  /* random sequential insertion without overlap (periodic images) */
  uint64_t rng = (uint64_t)s->seed * 0x9e3779b97f4a7c15ULL + 1;
  TL_CHECK(tl_particles_reserve(P, (size_t)n));
  for (long k = 0; k < n; ++k) {
    double r = sample_radius(s, &P->species_table[sp], &rng);
    int placed = 0;
    for (int attempt = 0; attempt < 100000 && !placed; ++attempt) {
      TlVec3 x = {L0 * tl_random_uniform(&rng), L0 * tl_random_uniform(&rng), L0 * tl_random_uniform(&rng)};
      placed = 1;
      for (size_t i = 0; i < P->n && placed; ++i)
        placed = tl_v3_norm(tl_domain_branch(&dom, P->x[i], x)) > P->radius[i] + r;
      if (placed) TL_CHECK(tl_dem_add_particle(dem, x, tl_v3(0, 0, 0), r, sp, NULL));
    }
    if (!placed) TL_ERROR(TL_ERR_ARG, "could not place particle %ld in the gas: -phi0 %g too dense", k, s->phi0);
  }
  TL_CHECK(tl_dem_add_law(dem, s->law, NULL));
  s->law = NULL;
  configure(dem, s);
  TL_CHECK(tl_dem_set_timestep(dem, s->dt, 0));
  TL_CHECK(tl_dem_setup(dem));
  tl_printf("periodic_compress: %ld grains, d in [%g, %g] m, cell %.4g m -> about %.4g m, target %g Pa, dt %g s\n", n,
            s->d_min, s->d_max, L0, L_final, s->pressure, s->dt);
  TlTimeSeries *ts;
  TL_CHECK(open_table(s, &ts));
  double vol_grains = grain_volume(P);
  long steps_max = (long)ceil(s->t_end / s->dt);
  TlProgress prog;
  tl_progress_init(&prog, "compress", (double)steps_max);
  const double rate_target = s->inertial * sqrt(s->pressure / s->density) / d0;
  const double rate_gas = s->inertial_gas * sqrt(s->pressure / s->density) / d0;
  int reached = 0, converged = 0, stopped = 0;
  double pr = 0.0, imbalance = 1.0, z = 0.0, rate = 0.0;
  long k = 0;
  ServoState sv = {0, 0};
  TlCheckpoint *cp = NULL;
  char cp_path[4200];
  snprintf(cp_path, sizeof cp_path, "%s/checkpoint.h5", s->out);
  TlStatus st = TL_OK;
  TL_CHECK_GOTO(st, tl_checkpoint_create(&cp), fail);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "options", &tl_options_checkpoint_ops, o), fail);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, dem), fail);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "table", &tl_timeseries_checkpoint_ops, ts), fail);
  TL_CHECK_GOTO(st, tl_checkpoint_add(cp, "servo", &servo_checkpoint_ops, &sv), fail);
  if (s->restart[0]) {
    TL_CHECK_GOTO(st, tl_checkpoint_load(cp, s->restart, NULL, NULL), fail);
    if (sv.next_step % s->control_every != 0) {
      st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "checkpoint %s is at step %lld, not a multiple of "
                        "-control_every %ld", s->restart, (long long)sv.next_step, s->control_every);
      goto fail;
    }
    reached = (int)sv.reached;
    tl_printf("restarted from %s at step %lld, t = %.9g s\n", s->restart, (long long)sv.next_step, tl_dem_time(dem));
  }
  for (k = (long)sv.next_step; k < steps_max; k += s->control_every) {
    pr = pressure_of(dem);
    TL_CHECK(tl_dem_max_force_imbalance(dem, &imbalance));
    TL_CHECK(tl_dem_coordination(dem, &z, NULL));
    double err = (pr - s->pressure) / s->pressure;
    if (!reached && pr >= s->pressure) reached = 1;
    if (!reached) {
      /* compress: fast while the pressure is far below, slower near it */
      double frac = fmax(pr, 0.0) / s->pressure;
      rate = -(rate_gas * (1.0 - frac) + rate_target * frac);
    } else {
      /* servo: expand when above the target, compress when below */
      rate = fmax(-rate_target, fmin(rate_target, rate_target * 2.0 * err));
    }
    if (reached && fabs(err) < s->pressure_tolerance && imbalance < s->tolerance) {
      converged = 1;
      break;
    }
    TlDomain *D = tl_dem_domain(dem);
    TL_CHECK(tl_domain_set_h_rate(D, tl_m3_scale(D->h, rate)));
    double row[] = {tl_dem_time(dem), pr, vol_grains / tl_domain_volume(D), kinetic_of(P), z, imbalance, rate,
                    (double)(reached ? STAGE_SERVO : STAGE_COMPRESS)};
    TL_CHECK_GOTO(st, tl_timeseries_append(ts, row), fail);
    TL_CHECK_GOTO(st, tl_dem_step(dem, s->control_every), fail);
    tl_progress_update(&prog, (double)k);
    sv.next_step = k + s->control_every;
    sv.reached = reached;
    stopped = s->stop_step > 0 && sv.next_step >= s->stop_step && sv.next_step < steps_max;
    if ((s->checkpoint_every > 0 && sv.next_step % s->checkpoint_every == 0) || stopped)
      TL_CHECK_GOTO(st, tl_checkpoint_save(cp, cp_path, tl_dem_time(dem), sv.next_step), fail);
    if (stopped) {
      k = (long)sv.next_step;
      break;
    }
  }
  tl_progress_finish(&prog);
  tl_checkpoint_destroy(&cp);
  if (stopped) {
    TL_CHECK(tl_timeseries_close(&ts));
    tl_printf("stopped after step %ld (-stop_step): %s continues the run with -restart\n", k, cp_path);
    TlSummary sum;
    tl_summary_init(&sum);
    tl_summary_int(&sum, "n", n);
    tl_summary_int(&sum, "steps", k);
    tl_summary_string(&sum, "stopped", "true");
    tl_summary_real(&sum, "wall", tl_wtime() - wall0);
    TlStatus s_sum = tl_summary_print(&sum, stdout);
    tl_dem_destroy(&dem);
    return s_sum;
  }
  TlDomain *D = tl_dem_domain(dem);
  TL_CHECK(tl_domain_set_h_rate(D, tl_m3_zero()));
  TL_CHECK(tl_timeseries_close(&ts));
  TlParticleWriter *writer;
  TL_CHECK(tl_particle_writer_create(s->out, "packing", &writer));
  TL_CHECK(tl_dem_packing_write(dem, writer, k, NULL));
  tl_particle_writer_destroy(&writer);
  double phi = vol_grains / tl_domain_volume(D);
  double side = cbrt(tl_domain_volume(D));
  tl_printf("%s after %ld steps: pressure %.6g Pa (target %g), packing fraction %.4f, coordination %.3f, largest Δ_n %.3g, cell %.4g m = %.2f d0\n",
            converged ? "converged" : "stopped at t_end", k, pr, s->pressure, phi, z, imbalance, side, side / d0);
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
  TlStatus s_sum = tl_summary_print(&sum, stdout);
  tl_dem_destroy(&dem);
  return s_sum;
fail:
  tl_checkpoint_destroy(&cp);
  if (ts) (void)tl_timeseries_close(&ts);
  tl_dem_destroy(&dem);
  return st;
}

/* A target pressure the contacts cannot carry at a small overlap makes no
 * packing (the grains interpenetrate and the compression runs on): the mean
 * contact force of a packing at pressure p is <F> = pi d^2 p / (z phi)
 * (the Cauchy stress of the contacts with z = 6, phi = 0.64), and the law
 * must give it at an overlap delta/d within the limit. */
#define MAX_OVERLAP_D 0.05
static TlStatus check_pressure(const Settings *s)
{
  const double d = 0.5 * (s->d_min + s->d_max), z = 6.0, phi = 0.64;
  const double f_target = TL_PI * d * d * s->pressure / (z * phi);
  double *h = NULL;
  TL_CHECK(tl_calloc(&h, s->law->history_doubles + 1, sizeof *h));
  TlContactGeometry g;
  memset(&g, 0, sizeof g);
  g.normal = tl_v3(1, 0, 0);
  g.reff = 0.25 * d;
  g.meff = 0.5 * s->density * TL_PI / 6.0 * d * d * d;
  g.history = h;
  TlContactResult r;
  g.overlap = MAX_OVERLAP_D * d;
  TlStatus st = tl_contact_law_evaluate_one(s->law, &g, s->dt, &r);
  tl_free(&h);
  TL_CHECK(st);
  const double f_limit = -r.force.x, p_limit = f_limit * z * phi / (TL_PI * d * d);
  if (!(f_target <= f_limit))
    TL_ERROR(TL_ERR_ARG,
             "-pressure %g Pa needs a mean contact force pi d^2 p / (z phi) = %.3g N (d = %g m, z = 6, phi = 0.64), "
             "beyond the %.3g N the contact law gives at the overlap limit delta/d = %g: at most -pressure %.3g Pa",
             s->pressure, f_target, d, f_limit, MAX_OVERLAP_D, p_limit);
  return TL_OK;
}

static TlStatus run(int argc, char **argv)
{
  double wall0 = tl_wtime();
  TlOptions *o = NULL;
  Settings s;
  TlStatus st = options(argc, argv, &o, &s);
  if (st == TL_OK && s.d_max < s.d_min)
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "-d_max %g is smaller than -d_min %g", s.d_max, s.d_min);
  if (st == TL_OK) st = tl_output_dir_prepare(s.out);
  if (st == TL_OK) st = check_pressure(&s);
  if (st == TL_OK) st = s.protocol == PROTOCOL_SCRIPTS ? run_scripts(&s, o, wall0) : run_servo(&s, o, wall0);
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
