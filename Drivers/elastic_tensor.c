/* Elastic tensor of a periodic granular packing by strain probing
 * (Voisin-Leprince et al. 2023 §3.2; the protocols of tl_dem_probe.h).
 *
 * Reads a packing, either a Talus particle snapshot (.h5, as written by
 * periodic_compress, a packing file of tl_dem_packing.h with its cell in
 * /cell/origin and /cell/h; a plain snapshot with -cell_side, a cubic cell
 * at the origin) or a LAMMPS data file (atom_style sphere; the box and tilt
 * factors from its header, the density of each atom from its Atoms line),
 * builds the periodic cell with the gouge contact law (LAMMPS's
 * gran/hertz/history with Voisin-Leprince et al. 2023 Table 1: lammps_hertz + lammps_history,
 * k_n = 3.663e10 Pa, k_t = 4.5249e10 Pa, gamma_n = 0.2 1/(m s), gamma_t =
 * gamma_n/2, mu = 0.5, the values of the authors' contact_law.mod), applies
 * ±ε on each of the six strain components and prints the 36 C_iJ (and the
 * symmetrised tensor), the cubic averages C11, C12, C44, the bulk modulus K,
 * the shear moduli G1 = C44 and G2 = (C11 - C12)/2, Young's modulus E,
 * Poisson's ratio ν and the Zener index Z = 2 C44/(C11 - C12), all by the
 * formulas of the authors' in.elastic.
 *
 * Protocols (-probe, -probe_jiggle): affine with a jiggle of 1e-5 m (the
 * default: what the authors' scripts do, reproducing Table 2
 * statistically), affine with -probe_jiggle 0 (the clean affine stiffness of
 * the packing as read), relaxed (each strained state relaxed to static
 * balance under global viscous damping, what the paper's text describes).
 *
 * -compare FILE reads a 6 x 6 tensor (36 numbers after '#' comment lines,
 * row by row, Pa: the authors' stiffness_matrix_sym.txt) and prints the
 * differences entry by entry.  -write_data FILE writes the probed reference
 * state (after the jiggle or the relaxation) as a LAMMPS data file, so that
 * LAMMPS can probe exactly the same state.
 * Last line: summary: n=... protocol=... E=... nu=... K=... G1=... G2=...
 * zener=... pressure=... wall=... */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_papers.h"
#include "tl_dem.h"
#include "tl_dem_packing.h"
#include "tl_dem_probe.h"
#include "tl_lammps_data.h"
#include "tl_particle_snapshot.h"

typedef struct {
  const char *input, *compare, *write_data, *output;
  int probe;
  double density, cell_side, dt;
  int threads, velocities;
  TlProbeSettings ps;
  TlContactLaw *law;
} Settings;

static const char *const probes[] = {"affine", "relaxed", NULL};

static TlStatus options(int argc, char **argv, TlOptions **o, Settings *s)
{
  TL_CHECK(tl_options_create(argc, argv,
                             "Elastic tensor of a periodic packing by +-eps strain probes on the six components "
                             "(Voisin-Leprince et al. 2023, Sec. 3.2): all C_ij, cubic averages, K, G1, G2, E, nu, Zener index.  "
                             "Paper: " TL_PAPER_VOISIN_LEPRINCE_2023 ".",
                             o));
  TL_CHECK(tl_options_get_string(*o, "-input", "", "packing: Talus particle snapshot (.h5) or LAMMPS data file", &s->input));
  TL_CHECK(tl_options_get_real(*o, "-cell_side", 0.0, 0.0, 1e6, "m",
                               "cubic cell side of a plain snapshot without /cell (0: the packing file's cell)", &s->cell_side));
  TL_CHECK(tl_options_get_real(*o, "-density", 2500, 1e-6, 1e6, "kg/m^3",
                               "grain density of a Talus snapshot (LAMMPS data carry theirs; Table 1: 2500)", &s->density));
  TL_CHECK(tl_options_get_bool(*o, "-velocities", 1, "keep the velocities and spins stored in the packing", &s->velocities));
  /* the gouge law, the authors' contact_law.mod: gran/hertz/history
   * 3.663e10 4.5249e10 0.2 NULL 0.5 1 (tl_dem_packing.h) */
  TL_CHECK(tl_contact_law_from_options(*o, &tl_gouge_law_spec, &s->law));
  TL_CHECK(tl_options_get_real(*o, "-dt", 1e-8, 1e-15, 1.0, "s", "time step of the relaxed probe (Table 1)", &s->dt));
  tl_probe_settings_default(&s->ps);
  TL_CHECK(tl_options_get_choice(*o, "-probe", "affine", probes,
                                 "affine: stress read at once after the affine map (LAMMPS run 0); relaxed: relaxed to "
                                 "static balance first",
                                 &s->probe));
  s->ps.kind = s->probe == 1 ? TL_PROBE_RELAXED : TL_PROBE_AFFINE;
  TL_CHECK(tl_options_get_real(*o, "-strain", 1e-6, 1e-12, 0.1, "", "probe strain eps (the scripts' up = 1e-6)", &s->ps.strain));
  TL_CHECK(tl_options_get_real(*o, "-probe_jiggle", 1e-5, 0.0, 1.0, "m",
                               "random displacement in [-a, a] per component before the probes (the scripts' "
                               "atomjiggle 1e-5 m; 0: none)",
                               &s->ps.jiggle));
  long seed;
  TL_CHECK(tl_options_get_int(*o, "-jiggle_seed", 87287, 0, 2000000000, "seed of the jiggle (the scripts' 87287)", &seed));
  s->ps.jiggle_seed = (uint64_t)seed;
  TL_CHECK(tl_options_get_real(*o, "-viscous", 0.5, 1e-12, 1e12, "N s/m",
                               "relaxed probe: global viscous force -c v (LAMMPS fix viscous 0.5 in the scripts)", &s->ps.viscous));
  TL_CHECK(tl_options_get_real(*o, "-tolerance", 1e-4, 1e-15, 1.0, "",
                               "relaxed probe: static balance, largest Delta_n (Desrues et al. 2019 Eq. 19) of the grains whose largest contact carries >= 1e-3 of the mean contact force", &s->ps.tolerance));
  TL_CHECK(tl_options_get_int(*o, "-max_steps", 2000000, 1, 2000000000, "relaxed probe: longest relaxation, steps", &s->ps.max_steps));
  TL_CHECK(tl_options_get_int(*o, "-check_every", 200, 1, 100000000, "relaxed probe: steps between balance checks", &s->ps.check_every));
  TL_CHECK(tl_options_get_bool(*o, "-relax_reference", 1, "relaxed probe: relax the reference state first", &s->ps.relax_reference));
  TL_CHECK(tl_options_get_string(*o, "-scratch", "elastic_tensor_reference.h5", "scratch checkpoint of the reference state (removed at the end)", &s->ps.scratch));
  TL_CHECK(tl_options_get_string(*o, "-compare", "", "a 6x6 tensor to compare with (36 numbers, Pa; the authors' stiffness_matrix_sym.txt)", &s->compare));
  TL_CHECK(tl_options_get_string(*o, "-write_data", "", "write the probed reference state as a LAMMPS data file", &s->write_data));
  TL_CHECK(tl_options_get_string(*o, "-output", "",
                                 "write C_iJ, then the symmetrised tensor, 36 numbers each row by row (Pa, %.17g)",
                                 &s->output));
  long th;
  TL_CHECK(tl_options_get_int(*o, "-threads", 1, 0, 1024, "OpenMP threads (0: default)", &th));
  s->threads = (int)th;
  TlStatus f = tl_options_finish(*o, stdout);
  if (f != TL_OK) return f;
  if (!s->input[0]) TL_ERROR(TL_ERR_ARG, "-input is required (a .h5 particle snapshot or a LAMMPS data file)");
  return TL_OK;
}

static int ends_with(const char *s, const char *tail)
{
  size_t n = strlen(s), m = strlen(tail);
  return n >= m && strcmp(s + n - m, tail) == 0;
}

/* The packing as arrays, from either format. */
typedef struct {
  size_t n;
  TlVec3 *x, *v, *w;
  double *radius, density;
  TlVec3 origin;
  TlMat3 h;
} Packing;

static void packing_free(Packing *p)
{
  tl_free(&p->x);
  tl_free(&p->v);
  tl_free(&p->w);
  tl_free(&p->radius);
}

static TlStatus read_lammps(const char *path, Packing *p)
{
  TlLammpsData *L = NULL;
  TL_CHECK(tl_lammps_data_read(path, &L));
  TlStatus st = TL_OK;
  p->n = L->n;
  p->density = L->n ? L->density[0] : 0.0;
  for (size_t i = 0; i < L->n && st == TL_OK; ++i)
    if (L->density[i] != p->density)
      st = tl_error_set(TL_ERR_UNSUPPORTED, __FILE__, __LINE__,
                        "%s: atom %lld has density %g, atom 1 %g: one density per packing", path,
                        (long long)L->id[i], L->density[i], p->density);
  if (st == TL_OK) st = tl_calloc(&p->x, p->n ? p->n : 1, sizeof *p->x);
  if (st == TL_OK) st = tl_calloc(&p->v, p->n ? p->n : 1, sizeof *p->v);
  if (st == TL_OK) st = tl_calloc(&p->w, p->n ? p->n : 1, sizeof *p->w);
  if (st == TL_OK) st = tl_calloc(&p->radius, p->n ? p->n : 1, sizeof *p->radius);
  if (st == TL_OK) {
    for (size_t i = 0; i < L->n; ++i) {
      p->x[i] = L->x[i];
      p->v[i] = L->v[i];
      p->w[i] = L->omega[i];
      p->radius[i] = 0.5 * L->diameter[i];
    }
    p->origin = tl_v3(L->lo[0], L->lo[1], L->lo[2]);
    p->h = tl_m3_zero();
    p->h.m[0][0] = L->hi[0] - L->lo[0];
    p->h.m[1][1] = L->hi[1] - L->lo[1];
    p->h.m[2][2] = L->hi[2] - L->lo[2];
    p->h.m[0][1] = L->tilt[0]; /* xy: b = (xy, ly, 0) */
    p->h.m[0][2] = L->tilt[1]; /* xz: c = (xz, yz, lz) */
    p->h.m[1][2] = L->tilt[2]; /* yz */
  }
  tl_lammps_data_destroy(&L);
  return st == TL_OK ? TL_OK : tl_error_trace(st, __FILE__, __LINE__);
}

/* A packing file (snapshot + /cell, tl_dem_packing.h), or with -cell_side a
 * plain particle snapshot in a cubic cell at the origin. */
static TlStatus read_snapshot(const char *path, double side, double density, Packing *p)
{
  TlParticleSnapshot snap;
  memset(&snap, 0, sizeof snap);
  p->n = 0;
  p->density = density;
  p->origin = tl_v3(0, 0, 0);
  if (side > 0.0) {
    TL_CHECK(tl_particle_snapshot_read(path, &snap));
    p->h = tl_m3_scale(tl_m3_identity(), side);
  } else
    TL_CHECK(tl_dem_packing_read(path, &snap, &p->origin, &p->h));
  TlStatus st = TL_OK;
  p->n = snap.n;
  if (st == TL_OK) st = tl_calloc(&p->x, p->n ? p->n : 1, sizeof *p->x);
  if (st == TL_OK) st = tl_calloc(&p->v, p->n ? p->n : 1, sizeof *p->v);
  if (st == TL_OK) st = tl_calloc(&p->w, p->n ? p->n : 1, sizeof *p->w);
  if (st == TL_OK) st = tl_calloc(&p->radius, p->n ? p->n : 1, sizeof *p->radius);
  if (st == TL_OK)
    for (size_t i = 0; i < snap.n; ++i) {
      p->x[i] = snap.position[i];
      p->radius[i] = snap.radius[i];
      if (snap.velocity) p->v[i] = snap.velocity[i];
      if (snap.angular_velocity) p->w[i] = snap.angular_velocity[i];
    }
  tl_particle_snapshot_free(&snap);
  return st == TL_OK ? TL_OK : tl_error_trace(st, __FILE__, __LINE__);
}

/* 36 numbers after '#' comment lines */
static TlStatus read_tensor(const char *path, double C[6][6])
{
  FILE *f = fopen(path, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot open %s", path);
  char line[8192];
  int k = 0;
  while (k < 36 && fgets(line, sizeof line, f)) {
    if (line[0] == '#') continue;
    char *p = line, *end;
    for (double v; k < 36 && (v = strtod(p, &end), end != p); p = end) C[k / 6][k % 6] = v, ++k;
  }
  fclose(f);
  if (k != 36) TL_ERROR(TL_ERR_FORMAT, "%s: %d numbers, expected 36 (a 6 x 6 tensor)", path, k);
  return TL_OK;
}

static TlStatus write_tensors(const char *path, const TlProbeResult *r)
{
  FILE *f = fopen(path, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write %s", path);
  const double(*T[2])[6] = {r->C, r->C_sym};
  static const char *title[2] = {"C_iJ = (sigma_i(+eps_J) - sigma_i(-eps_J)) / (2 eps), Pa, row by row",
                                 "(C + C^T) / 2, Pa, row by row"};
  for (int t = 0; t < 2; ++t) {
    fprintf(f, "# %s\n", title[t]);
    for (int k = 0; k < 36; ++k) fprintf(f, "%.17g%c", T[t][k / 6][k % 6], k == 35 ? '\n' : ' ');
  }
  if (fclose(f) != 0) TL_ERROR(TL_ERR_IO, "writing %s failed", path);
  return TL_OK;
}

static void print_tensor(const char *title, const double C[6][6])
{
  static const char *lab[6] = {"xx", "yy", "zz", "yz", "xz", "xy"};
  tl_printf("%s (GPa; rows: stress, columns: strain, Voigt xx yy zz yz xz xy)\n      ", title);
  for (int J = 0; J < 6; ++J) tl_printf(" %12s", lab[J]);
  tl_printf("\n");
  for (int i = 0; i < 6; ++i) {
    tl_printf("  %s  ", lab[i]);
    for (int J = 0; J < 6; ++J) tl_printf(" %12.6f", C[i][J] * 1e-9);
    tl_printf("\n");
  }
}

static TlStatus run(int argc, char **argv)
{
  double wall0 = tl_wtime();
  TlOptions *o = NULL;
  Settings s;
  memset(&s, 0, sizeof s);
  TlStatus st = options(argc, argv, &o, &s);
  if (st != TL_OK) {
    tl_contact_law_destroy(&s.law);
    tl_options_destroy(&o);
    return st;
  }
  Packing pk;
  memset(&pk, 0, sizeof pk);
  int is_h5 = ends_with(s.input, ".h5");
  st = is_h5 ? read_snapshot(s.input, s.cell_side, s.density, &pk) : read_lammps(s.input, &pk);
  TlDem *dem = NULL;
  if (st == TL_OK && pk.n < 2)
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "%s: %zu particles; the probe needs at least 2", s.input, pk.n);
  if (st == TL_OK && !(pk.density > 0.0))
    st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "%s: density %g must be positive", s.input, pk.density);
  if (st == TL_OK) st = tl_dem_create(&dem);
  double rmin = INFINITY, rmax = 0.0, vol = 0.0;
  for (size_t i = 0; i < pk.n; ++i) {
    rmin = fmin(rmin, pk.radius[i]);
    rmax = fmax(rmax, pk.radius[i]);
    vol += 4.0 / 3.0 * TL_PI * pow(pk.radius[i], 3);
  }
  if (st == TL_OK) {
    TlDomain dom;
    TlParticles *P = tl_dem_particles(dem);
    int sp;
    st = tl_domain_init_cell(&dom, pk.origin, pk.h);
    if (st == TL_OK) st = tl_dem_set_domain(dem, &dom);
    if (st == TL_OK) st = tl_particles_add_species(P, "gouge", pk.density, rmin, rmax, &sp);
    for (size_t i = 0; i < pk.n && st == TL_OK; ++i)
      st = tl_dem_add_particle(dem, pk.x[i], s.velocities ? pk.v[i] : tl_v3(0, 0, 0), pk.radius[i], sp, NULL);
    if (st == TL_OK) {
      st = tl_dem_add_law(dem, s.law, NULL);
      if (st == TL_OK) s.law = NULL;
    }
    if (st == TL_OK) {
      tl_dem_set_threads(dem, s.threads);
      tl_dem_track_energy(dem, 0);
      tl_dem_track_orientation(dem, 0);
      st = tl_dem_set_timestep(dem, s.dt, 0);
    }
    if (st == TL_OK) st = tl_dem_setup(dem);
    /* spins by id (the ids follow the order of insertion) */
    if (st == TL_OK && P->w && s.velocities)
      for (size_t i = 0; i < P->n; ++i)
        if (P->id[i] >= 0 && (size_t)P->id[i] < pk.n) P->w[i] = pk.w[P->id[i]];
  }
  double V = st == TL_OK ? tl_domain_volume(tl_dem_domain(dem)) : 0.0;
  TlProbeResult r;
  memset(&r, 0, sizeof r);
  if (st == TL_OK) {
    tl_printf("elastic_tensor: %s, %zu grains, d in [%g, %g] m, cell volume %.6g m^3 (side %.6g m), packing fraction "
              "%.5f, density of the packing %.2f kg/m^3\n",
              s.input, pk.n, 2 * rmin, 2 * rmax, V, cbrt(V), vol / V, pk.density * vol / V);
    tl_printf("probe %s, strain %g, jiggle %g m (seed %lld)%s\n", probes[s.probe], s.ps.strain, s.ps.jiggle,
              (long long)s.ps.jiggle_seed, s.ps.kind == TL_PROBE_RELAXED ? ", relaxed to static balance" : "");
    st = tl_dem_probe_elastic(dem, &s.ps, &r);
  }
  if (st == TL_OK && s.write_data[0]) st = tl_dem_packing_write_lammps(dem, pk.density, s.write_data);
  if (st == TL_OK && s.output[0]) st = write_tensors(s.output, &r);
  double coord = 0.0;
  if (st == TL_OK) st = tl_dem_coordination(dem, &coord, NULL);
  double Cref[6][6];
  double cmp = NAN;
  if (st == TL_OK && s.compare[0]) st = read_tensor(s.compare, Cref);
  if (st == TL_OK) {
    print_tensor("C_iJ = (sigma_i(+eps_J) - sigma_i(-eps_J)) / (2 eps)", r.C);
    print_tensor("symmetrised (C + C^T)/2", r.C_sym);
    const TlElasticModuli *m = &r.moduli;
    tl_printf("reference stress (Pa): xx %.6g yy %.6g zz %.6g yz %.6g xz %.6g xy %.6g; pressure %.6g Pa; coordination %.3f\n",
              r.stress0[0], r.stress0[1], r.stress0[2], r.stress0[3], r.stress0[4], r.stress0[5], r.pressure0, coord);
    tl_printf("cubic averages: C11 %.6g  C12 %.6g  C44 %.6g Pa\n", m->C11, m->C12, m->C44);
    tl_printf("moduli: K %.6g  G1 = C44 %.6g  G2 = (C11-C12)/2 %.6g  G %.6g  E %.6g Pa  nu %.6f  Zener %.6f\n", m->K, m->G1,
              m->G2, m->G, m->E, m->nu, m->zener);
    tl_printf("Table 2 (Voisin-Leprince et al. 2023): E 0.977e9 Pa, nu 0.255; this packing: E/E_T2 = %.4f\n", m->E / 0.977e9);
    if (s.ps.kind == TL_PROBE_RELAXED) {
      static const char *lab[6] = {"xx", "yy", "zz", "yz", "xz", "xy"};
      tl_printf("relaxations (steps, final imbalance): reference %ld, %.2g", r.reference_steps, r.reference_imbalance);
      for (int J = 0; J < 6; ++J)
        tl_printf("; %s -eps %ld, %.2g, +eps %ld, %.2g", lab[J], r.probe_steps[J][0], r.probe_imbalance[J][0],
                  r.probe_steps[J][1], r.probe_imbalance[J][1]);
      tl_printf("\nrelaxations: up to %ld steps, largest final imbalance %.3g, all converged: %s\n", r.relax_steps,
                r.relax_imbalance, r.relax_converged ? "yes" : "no");
    }
    if (s.compare[0]) {
      double big = 0.0, err = 0.0;
      tl_printf("against %s: entry, this, that, difference relative to the largest entry\n", s.compare);
      for (int i = 0; i < 6; ++i)
        for (int J = 0; J < 6; ++J) big = fmax(big, fabs(Cref[i][J]));
      for (int i = 0; i < 6; ++i)
        for (int J = 0; J < 6; ++J) {
          double e = fabs(r.C_sym[i][J] - Cref[i][J]) / big;
          err = fmax(err, e);
          tl_printf("  C%d%d %.15g %.15g %.3e\n", i + 1, J + 1, r.C_sym[i][J], Cref[i][J], e);
        }
      TlElasticModuli mr;
      tl_elastic_moduli(Cref, &mr);
      tl_printf("that tensor's moduli: E %.6g Pa nu %.6f K %.6g G1 %.6g G2 %.6g Zener %.6f\n", mr.E, mr.nu, mr.K, mr.G1,
                mr.G2, mr.zener);
      cmp = err;
    }
    TlSummary sum;
    tl_summary_init(&sum);
    tl_summary_int(&sum, "n", (long)pk.n);
    tl_summary_string(&sum, "protocol", probes[s.probe]);
    tl_summary_real(&sum, "jiggle", s.ps.jiggle);
    tl_summary_real(&sum, "strain", s.ps.strain);
    tl_summary_real(&sum, "C11", m->C11);
    tl_summary_real(&sum, "C12", m->C12);
    tl_summary_real(&sum, "C44", m->C44);
    tl_summary_real(&sum, "K", m->K);
    tl_summary_real(&sum, "G1", m->G1);
    tl_summary_real(&sum, "G2", m->G2);
    tl_summary_real(&sum, "E", m->E);
    tl_summary_real(&sum, "nu", m->nu);
    tl_summary_real(&sum, "zener", m->zener);
    tl_summary_real(&sum, "pressure", r.pressure0);
    tl_summary_real(&sum, "packing_fraction", vol / V);
    tl_summary_real(&sum, "density_packing", pk.density * vol / V);
    tl_summary_real(&sum, "box_d0", cbrt(V) / 3e-3);
    if (s.ps.kind == TL_PROBE_RELAXED) {
      tl_summary_int(&sum, "relax_steps", r.relax_steps);
      tl_summary_int(&sum, "relax_converged", r.relax_converged);
    }
    if (s.compare[0]) tl_summary_real(&sum, "compare_max_rel", cmp);
    tl_summary_real(&sum, "wall", tl_wtime() - wall0);
    st = tl_summary_print(&sum, stdout);
  }
  tl_dem_destroy(&dem);
  tl_contact_law_destroy(&s.law);
  packing_free(&pk);
  tl_options_destroy(&o);
  return st == TL_OK ? TL_OK : tl_error_trace(st, __FILE__, __LINE__);
}

int main(int argc, char **argv)
{
  TlStatus s = tl_initialize();
  if (s == TL_OK) s = run(argc, argv);
  return tl_driver_exit(s);
}
