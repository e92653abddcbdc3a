/* Contact laws composed from parts: every part's parameter table (defaults,
 * ranges refused by name), the composition rules, the -help listing of
 * tl_contact_law_from_options, and a normal part defined here, outside the
 * library (a spring with a quadratic dashpot), registered from the test,
 * created by name and run by the world through the same chunk path as the
 * built-in parts: its restitution against a reference integration of the
 * same law, and the energy balance. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "talus.h"
#include "tl_contact_part.h"
#include "tl_dem.h"
#include "tl_options.h"
#include "tl_test.h"

static int mentions(const char *what) { return strstr(tl_error_message(), what) != NULL; }

/* ---- a normal part from outside the library: f_n = k δ + c |dδ/dt| dδ/dt */

typedef struct {
  TlContactPart base;
  double k, c;
} Quadratic;

static const TlParam quadratic_params[] = {
    {"k_q", 1e5, 0.0, 1e300, "N/m", "spring stiffness", offsetof(Quadratic, k)},
    {"c_q", 0.0, 0.0, 1e300, "N s^2/m^2", "quadratic dashpot: c |d(delta)/dt| d(delta)/dt", offsetof(Quadratic, c)},
};

static long chunk_calls, batch_calls; /* which op ran (single-threaded test) */

static TlStatus quadratic_setup(TlContactPart *part, const TlContactPart *normal)
{
  (void)normal;
  const Quadratic *q = (const Quadratic *)part;
  if (!(q->k > 0.0)) TL_ERROR(TL_ERR_ARG, "quadratic part: k_q = %g N/m must be > 0", q->k);
  part->active = 1;
  return TL_OK;
}

static inline void quadratic_loop(const TlContactPart *part, TlContactChunk *c)
{
  const Quadratic *qd = (const Quadratic *)part;
  for (size_t q = 0; q < c->n; ++q) {
    const double delta = c->overlap[q];
    c->on[q] = delta > 0.0;
    if (!c->on[q]) continue;
    const double rate = -tl_v3_dot(c->vrel[q], c->normal[q]); /* dδ/dt */
    c->fn[q] = qd->k * delta + qd->c * fabs(rate) * rate;
    c->scale[q] = 1.0;
    if (c->want_energy) c->energy[q] = 0.5 * qd->k * delta * delta;
  }
}

static TlStatus quadratic_evaluate(const TlContactPart *part, TlContactChunk *chunk)
{
  batch_calls++;
  quadratic_loop(part, chunk);
  return TL_OK;
}

static TlStatus quadratic_evaluate_hot(const TlContactPart *part, TlContactChunk *chunk)
{
  chunk_calls++;
  quadratic_loop(part, chunk);
  return TL_OK;
}

static double quadratic_stiffness(const TlContactPart *part, double reff, double overlap)
{
  (void)reff, (void)overlap;
  return ((const Quadratic *)part)->k;
}
static double quadratic_damping(const TlContactPart *part, double meff, double reff, double overlap)
{
  (void)part, (void)meff, (void)reff, (void)overlap;
  return 0.0;
}
static double quadratic_scale(const TlContactPart *part, double reff, double overlap)
{
  (void)part, (void)reff, (void)overlap;
  return 1.0;
}
static double quadratic_tangential(const TlContactPart *part) { return 2.0 / 7.0 * ((const Quadratic *)part)->k; }

static const TlContactPartOps quadratic_ops = {
    {"contact_normal", "quadratic_dashpot", "linear spring with a quadratic dashpot (defined in a test)"},
    sizeof(Quadratic), 2, quadratic_params, quadratic_setup, quadratic_evaluate, quadratic_evaluate_hot,
    quadratic_stiffness, quadratic_damping, quadratic_scale, quadratic_tangential, NULL, NULL};

/* An adhesion part whose parameter clashes with Coulomb's mu. */
static const TlParam clash_params[] = {{"mu", 0.1, 0.0, 1.0, "", "a clashing name", sizeof(TlContactPart)}};
static TlStatus clash_setup(TlContactPart *part, const TlContactPart *normal)
{
  (void)normal;
  part->active = 0;
  return TL_OK;
}
static TlStatus clash_evaluate(const TlContactPart *part, TlContactChunk *chunk)
{
  (void)part, (void)chunk;
  return TL_OK;
}
static const TlContactPartOps clash_ops = {
    {"contact_adhesion", "clash", "adhesion with a parameter named mu"},
    sizeof(TlContactPart) + sizeof(double), 1, clash_params, clash_setup, clash_evaluate, NULL,
    NULL, NULL, NULL, NULL, NULL, NULL};

/* ---- parameter tables */

static void test_tables(void)
{
  static const char *const kinds[] = {"contact_normal", "contact_adhesion", "contact_friction", "contact_rolling"};
  static const char *const builtin[] = {"linear", "bonded_linear", "hertz", "coulomb", "constant"};
  int seen[5] = {0};
  for (int k = 0; k < 4; ++k)
    for (size_t i = 0;; ++i) {
      const TlTypeEntry *e = tl_registry_entry(kinds[k], i);
      if (!e) break;
      for (int b = 0; b < 5; ++b) seen[b] += !strcmp(e->name, builtin[b]);
      const TlContactPartOps *ops = e->ops;
      TL_TEST_ASSERT(ops && ops->n_params == e->n_params && ops->params == e->params, "%s: entry and ops agree",
                     e->name);
      /* a law with this part alone (or on a linear normal part) */
      TlContactLaw *law = NULL;
      const char *nm = k == 0 ? e->name : "linear";
      TL_TEST_STATUS(tl_contact_law_create(nm, k == 2 ? e->name : NULL, k == 3 ? e->name : NULL,
                                           k == 1 ? e->name : NULL, &law), TL_OK);
      if (!law) continue;
      for (int p = 0; p < e->n_params; ++p) {
        const TlParam *q = &e->params[p];
        double v = -1.0;
        TL_TEST_STATUS(tl_contact_law_get(law, q->name, &v), TL_OK);
        TL_TEST_ASSERT(v == q->def, "%s.%s: default %g, table %g", e->name, q->name, v, q->def);
        TL_TEST_ASSERT(q->lo <= q->def && q->def <= q->hi, "%s.%s: default inside its range", e->name, q->name);
        TL_TEST_ASSERT(q->unit && q->help && q->help[0], "%s.%s: unit and help", e->name, q->name);
        /* below the range: refused, naming the parameter, the value and the limit */
        if (q->lo > -1e300) {
          double bad = q->lo - 1.0 - fabs(q->lo);
          TL_TEST_STATUS(tl_contact_law_set(law, q->name, bad), TL_ERR_ARG);
          char want[64];
          snprintf(want, sizeof want, "%s = %g", q->name, bad);
          TL_TEST_ASSERT(mentions(want) && mentions(e->name), "%s refused by name: %s", want, tl_error_message());
        }
        TL_TEST_STATUS(tl_contact_law_set(law, q->name, NAN), TL_ERR_ARG);
      }
      TL_TEST_STATUS(tl_contact_law_set(law, "no_such_parameter", 1.0), TL_ERR_NOT_FOUND);
      tl_contact_law_destroy(&law);
    }
  for (int b = 0; b < 5; ++b) TL_TEST_ASSERT(seen[b] >= 1, "built-in part %s registered", builtin[b]);
  /* the linear part's defaults, one by one */
  TlContactLaw *law = NULL;
  TL_TEST_STATUS(tl_contact_law_create("linear", "coulomb", "constant", "constant", &law), TL_OK);
  double v;
  tl_contact_law_get(law, "restitution", &v);
  TL_TEST_ASSERT(v == 1.0, "restitution default 1");
  tl_contact_law_get(law, "k_n", &v);
  TL_TEST_ASSERT(v == 0.0, "k_n has no default");
  TL_TEST_STATUS(tl_contact_law_setup(law), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("k_n = 0"), "missing stiffness named: %s", tl_error_message());
  TL_TEST_STATUS(tl_contact_law_set(law, "restitution", 1.5), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("restitution = 1.5") && mentions("1]"), "restitution limit named: %s", tl_error_message());
  tl_contact_law_destroy(&law);
}

/* ---- composition rules */

static void test_composition(void)
{
  TlContactLaw *law = NULL;
  /* a part of the wrong kind, or none, is refused by name */
  TL_TEST_STATUS(tl_contact_law_create("coulomb", NULL, NULL, NULL, &law), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(mentions("coulomb") && mentions("linear"), "wrong kind named with the known ones: %s",
                 tl_error_message());
  TL_TEST_STATUS(tl_contact_law_create(NULL, "coulomb", NULL, NULL, &law), TL_ERR_ARG);
  TL_TEST_STATUS(tl_contact_law_create("linear", "hertz", NULL, NULL, &law), TL_ERR_NOT_FOUND);
  /* parameter names belong to one part */
  TL_TEST_STATUS(tl_contact_part_register(&clash_ops), TL_OK);
  TL_TEST_STATUS(tl_contact_law_create("linear", "coulomb", NULL, "clash", &law), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("'mu'") && mentions("clash"), "clash named: %s", tl_error_message());
  TL_TEST_ASSERT(law == NULL, "no law on failure");

  /* what each part adds: history, rotation, bonds */
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e4, NULL), TL_OK);
  TL_TEST_ASSERT(law->history_doubles == 0 && !law->needs_rotation && !law->bonded, "inactive parts cost nothing");
  tl_contact_law_destroy(&law);
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "E", 1e7, "mu", 0.5, "mu_roll", 0.1, NULL), TL_OK);
  TL_TEST_ASSERT(law->history_doubles == 3 && law->needs_rotation, "friction keeps 3 doubles, rolling rotates");
  double k_t;
  tl_contact_law_get(law, "k_t", &k_t);
  TL_TEST_ASSERT(k_t == 0.0, "k_t 0: the normal part's default is used");
  /* Hertz's default tangential stiffness 2E/((1+nu)(2-nu)) scaled by sqrt(delta reff) */
  const double E = 1e7, nu = 0.3, a = sqrt(1e-3 * 1e-6);
  TL_TEST_CLOSE(law->ops->max_stiffness(law, 1e-3, 1e-6),
                fmax(1.5 * (2.0 / 3.0) * E / (1 - nu * nu) * a, 2.0 * E / ((1 + nu) * (2 - nu)) * a), 1e-14);
  tl_contact_law_destroy(&law);
  /* Hertz given k_n alone cannot default k_t: friction then names it */
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "k_n", 1e7, "mu", 0.5, NULL), TL_ERR_ARG);
  TL_TEST_ASSERT(mentions("k_t") && mentions("hertz"), "missing k_t named: %s", tl_error_message());
  TL_TEST_STATUS(tl_test_law(&law, "hertz", "k_n", 1e7, "mu", 0.5, "k_t", 3e6, NULL), TL_OK);
  tl_contact_law_destroy(&law);

  /* a bonded normal part with friction: the bond pulls in tension, where
   * the Coulomb cone (mu <f_n>_+ = 0) leaves no tangential force; in
   * compression friction acts */
  TL_TEST_STATUS(tl_test_law(&law, "bonded_linear", "k_n", 1e4, "mu", 0.5, NULL), TL_OK);
  TL_TEST_ASSERT(law->bonded && law->history_doubles == 3, "bonded with friction history");
  double h[3] = {0, 0, 0};
  TlContactGeometry g;
  memset(&g, 0, sizeof g);
  g.normal = tl_v3(1, 0, 0);
  g.overlap = -1e-4;
  g.vrel = tl_v3(0, 0.1, 0);
  g.meff = 0.01;
  g.reff = 0.005;
  g.history = h;
  g.bonded = 1;
  TlContactResult r;
  TL_TEST_STATUS(tl_contact_law_evaluate_one(law, &g, 1e-4, &r), TL_OK);
  TL_TEST_CLOSE(r.force.x, 1e4 * 1e-4, 1e-12); /* pulled towards j: +x on i */
  TL_TEST_ASSERT(r.force.y == 0.0 && h[1] == 0.0, "no friction in tension (%g)", r.force.y);
  g.overlap = 1e-4;
  TL_TEST_STATUS(tl_contact_law_evaluate_one(law, &g, 1e-4, &r), TL_OK);
  TL_TEST_CLOSE(r.force.x, -1.0, 1e-12);
  TL_TEST_ASSERT(r.force.y > 0.0, "friction in compression (%g)", r.force.y);
  g.bonded = 0;
  g.overlap = -1e-4;
  TL_TEST_STATUS(tl_contact_law_evaluate_one(law, &g, 1e-4, &r), TL_OK);
  TL_TEST_ASSERT(r.force.x == 0.0, "an unbonded contact apart carries nothing");
  tl_contact_law_destroy(&law);
  /* the plain linear part does not act on bonds in tension */
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e4, NULL), TL_OK);
  g.bonded = 1;
  TL_TEST_STATUS(tl_contact_law_evaluate_one(law, &g, 1e-4, &r), TL_OK);
  TL_TEST_ASSERT(!law->bonded && r.force.x == 0.0, "linear ignores bonds");
  tl_contact_law_destroy(&law);
}

/* ---- options: every chosen part's parameter in -help, values by option */

static void test_options(void)
{
  const TlContactValue values[] = {{"k_n", 123.0}, {"mu", 0.25}, {"E", 5e6}};
  const TlContactSpec scene = {"linear", "coulomb", NULL, NULL, values, 3};
  {
    const char *argv[] = {"prog", "-help", "-contact", "hertz", "-rolling", "constant"};
    TlOptions *o = NULL;
    TL_TEST_STATUS(tl_options_create(6, (char **)argv, "test", &o), TL_OK);
    TlContactLaw *law = NULL;
    TL_TEST_STATUS(tl_contact_law_from_options(o, &scene, &law), TL_OK);
    FILE *f = tmpfile();
    TL_TEST_STATUS(tl_options_finish(o, f), TL_HELP);
    rewind(f);
    char text[16384];
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    static const char *const listed[] = {"-contact ",    "-friction ",      "-rolling ",       "-adhesion ",
                                         "-contact_k_n", "-contact_E",      "-contact_nu",     "-contact_gamma_n",
                                         "-contact_mu ", "-contact_k_t",    "-contact_gamma_t", "-contact_c_t",
                                         "-contact_mu_roll", "quadratic_dashpot", "[Pa]"};
    for (size_t i = 0; i < sizeof listed / sizeof listed[0]; ++i)
      TL_TEST_ASSERT(strstr(text, listed[i]) != NULL, "-help lists %s", listed[i]);
    TL_TEST_ASSERT(strstr(text, "-contact_restitution") == NULL, "the linear part's options only with -contact linear");
    TL_TEST_ASSERT(strstr(text, "-contact_adhesion_force") == NULL, "no adhesion part chosen");
    double v;
    tl_contact_law_get(law, "E", &v);
    TL_TEST_ASSERT(v == 5e6, "scene default E");
    tl_contact_law_get(law, "mu", &v);
    TL_TEST_ASSERT(v == 0.25, "scene default mu");
    tl_contact_law_destroy(&law);
    tl_options_destroy(&o);
  }
  {
    const char *argv[] = {"prog", "-contact_mu", "0.6", "-contact_restitution", "0.5"};
    TlOptions *o = NULL;
    TL_TEST_STATUS(tl_options_create(5, (char **)argv, "test", &o), TL_OK);
    TlContactLaw *law = NULL;
    TL_TEST_STATUS(tl_contact_law_from_options(o, &scene, &law), TL_OK);
    TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
    double v;
    tl_contact_law_get(law, "mu", &v);
    TL_TEST_ASSERT(v == 0.6, "-contact_mu read");
    tl_contact_law_get(law, "k_n", &v);
    TL_TEST_ASSERT(v == 123.0, "scene k_n");
    TL_TEST_ASSERT(law->history_doubles == 3, "set up");
    tl_contact_law_destroy(&law);
    tl_options_destroy(&o);
  }
  {
    const char *argv[] = {"prog", "-contact_mu", "-1"};
    TlOptions *o = NULL;
    TL_TEST_STATUS(tl_options_create(3, (char **)argv, "test", &o), TL_OK);
    TlContactLaw *law = NULL;
    TL_TEST_ASSERT(tl_contact_law_from_options(o, &scene, &law) != TL_OK, "a value out of range is refused");
    TL_TEST_ASSERT(mentions("contact_mu"), "by its option: %s", tl_error_message());
    TL_TEST_ASSERT(law == NULL, "no law");
    tl_options_destroy(&o);
  }
}

/* ---- the outside part in a world */

/* Reference: m_eff x'' = -(k x + c |x'| x'), x the overlap, from x = 0,
 * x' = v until x returns to 0 (RK4, fine steps). */
static double reference_rebound(double meff, double k, double c, double v)
{
  double x = 0.0, u = v, h = 1e-3 * sqrt(meff / k);
  for (long s = 0; s < 100000000; ++s) {
    double k1x = u, k1u = -(k * x + c * fabs(u) * u) / meff;
    double k2x = u + 0.5 * h * k1u, k2u = -(k * (x + 0.5 * h * k1x) + c * fabs(k2x) * k2x) / meff;
    double k3x = u + 0.5 * h * k2u, k3u = -(k * (x + 0.5 * h * k2x) + c * fabs(k3x) * k3x) / meff;
    double k4x = u + h * k3u, k4u = -(k * (x + h * k3x) + c * fabs(k4x) * k4x) / meff;
    double xn = x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x), un = u + h / 6 * (k1u + 2 * k2u + 2 * k3u + k4u);
    if (xn <= 0.0 && s > 0) return -(u + (un - u) * x / (x - xn)); /* interpolated exit speed */
    x = xn;
    u = un;
  }
  return NAN;
}

static void test_outside_part(void)
{
  TL_TEST_STATUS(tl_contact_part_register(&quadratic_ops), TL_OK);
  const double r = 0.01, rho = 2500, v0 = 0.5, k = 1e5, c = 20.0;
  const double m = rho * 4.0 / 3.0 * TL_PI * r * r * r, meff = 0.5 * m;
  TlContactLaw *law = NULL;
  const TlContactValue values[] = {{"k_q", k}, {"c_q", c}};
  const TlContactSpec spec = {"quadratic_dashpot", NULL, NULL, NULL, values, 2};
  TL_TEST_STATUS(tl_contact_law_build(&spec, &law), TL_OK);
  if (!law) return;
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", rho, r, r, &sp), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(-r - 1e-4, 0, 0), tl_v3(v0, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(r + 1e-4, 0, 0), tl_v3(-v0, 0, 0), r, sp, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  tl_dem_set_threads(dem, 1);
  tl_dem_track_energy(dem, 1);
  const double tc = TL_PI * sqrt(meff / k);
  TL_TEST_STATUS(tl_dem_set_timestep(dem, tc / 4000, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  TlDemEnergy e0, e1;
  TL_TEST_STATUS(tl_dem_energy(dem, &e0), TL_OK);
  double worst = 0.0;
  chunk_calls = batch_calls = 0;
  int touched = 0;
  for (long s = 0; s < 100000; ++s) {
    TL_TEST_STATUS(tl_dem_step(dem, 1), TL_OK);
    double ov = 2 * r - (P->x[1].x - P->x[0].x);
    TL_TEST_STATUS(tl_dem_energy(dem, &e1), TL_OK);
    worst = fmax(worst, fabs(e1.total - e0.total) / e0.total);
    if (ov > 0) touched = 1;
    if (touched && ov < 0) break;
  }
  const double vr = P->v[1].x - P->v[0].x, ref = reference_rebound(meff, k, c, 2 * v0);
  printf("quadratic dashpot: rebound %.6f m/s (reference %.6f), restitution %.5f, energy drift %.2e, "
         "dissipated %.4e J, chunk calls %ld, batch calls %ld\n",
         vr, ref, vr / (2 * v0), worst, e1.dissipated, chunk_calls, batch_calls);
  TL_TEST_ASSERT(touched, "the spheres met");
  /* the world evaluates the dashpot at the half-step velocity: first order
   * in dt, 3e-4 at tc / 4000 */
  TL_TEST_CLOSE(vr / ref, 1.0, 1e-3);
  TL_TEST_ASSERT(vr / (2 * v0) < 0.99 && vr > 0.0, "the dashpot dissipates (e = %g)", vr / (2 * v0));
  TL_TEST_ASSERT(worst < 2e-4, "energy balance kinetic + elastic + dissipated (drift %g)", worst);
  TL_TEST_CLOSE(e1.dissipated / (0.5 * meff * (4 * v0 * v0 - vr * vr)), 1.0, 2e-4);
  /* the world's loop called the part's chunk op, as for every built-in */
  TL_TEST_ASSERT(chunk_calls > 0 && batch_calls == 0, "the world's chunk path (%ld chunk, %ld batch calls)",
                 chunk_calls, batch_calls);
  tl_dem_destroy(&dem);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TL_TEST_STATUS(tl_contact_part_register(&quadratic_ops), TL_OK); /* listed in -help below */
  test_tables();
  test_composition();
  test_options();
  test_outside_part();
  return tl_test_report();
}
