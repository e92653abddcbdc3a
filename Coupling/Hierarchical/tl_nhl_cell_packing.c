/* The cells the library builds: an FCC lattice pre-compressed to σ0 and a
 * random packing compressed isotropically to σ0 and relaxed (seeds/004
 * §2.4; F1: k_t/k_n = 1, κ = 500, μ = 0.5).  Linear normal springs with
 * restitution damping and Coulomb friction (the paper's law, Eqs. 4, 22-26). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_nhl_cell.h"

void tl_nhl_packing_default(TlNhlPacking *p)
{
  memset(p, 0, sizeof *p);
  p->kind = "fcc";
  p->dim = 3;
  p->n_side = 3;
  p->n = 200;
  p->radius_min = 0.8e-3;
  p->radius_max = 1.2e-3;
  p->density = 2600.0;
  p->pressure = 1e5;
  p->kappa = 500.0;
  p->kt_over_kn = 1.0;
  p->mu = 0.5;
  p->restitution = 0.1;
  p->dt_fraction = 0.2;
  p->skin = 0.1;
  p->seed = 1;
}

typedef struct {
  TlNhlPacking p;
  char kind[16];
} PackingCtx;

static TlStatus check_packing(const TlNhlPacking *p)
{
  if (!p->kind || (strcmp(p->kind, "fcc") && strcmp(p->kind, "random")))
    TL_ERROR(TL_ERR_ARG, "NHL packing kind '%s' is neither \"fcc\" nor \"random\"", p->kind ? p->kind : "(null)");
  if (p->dim != 2 && p->dim != 3) TL_ERROR(TL_ERR_ARG, "NHL packing: dimension %d (2 or 3)", p->dim);
  if (!strcmp(p->kind, "fcc") && p->dim != 3) TL_ERROR(TL_ERR_ARG, "NHL packing: an fcc lattice is 3-D (dim %d given)", p->dim);
  if (!strcmp(p->kind, "fcc") && (p->n_side < 1 || p->n_side > 40))
    TL_ERROR(TL_ERR_ARG, "NHL packing: fcc n_side = %ld outside [1, 40]", p->n_side);
  if (!strcmp(p->kind, "random") && (p->n < 2 || p->n > 1000000))
    TL_ERROR(TL_ERR_ARG, "NHL packing: random n = %ld particles outside [2, 1e6]", p->n);
  if (!(p->radius_max > 0.0 && p->radius_min > 0.0 && p->radius_min <= p->radius_max))
    TL_ERROR(TL_ERR_ARG, "NHL packing: radii [%g, %g] m must be positive and ordered", p->radius_min, p->radius_max);
  if (!(p->density > 0.0)) TL_ERROR(TL_ERR_ARG, "NHL packing: density %g kg/m^3 must be > 0", p->density);
  if (!(p->pressure > 0.0 && isfinite(p->pressure))) TL_ERROR(TL_ERR_ARG, "NHL packing: pressure %g Pa must be > 0", p->pressure);
  if (!(p->kappa > 1.0 && isfinite(p->kappa))) TL_ERROR(TL_ERR_ARG, "NHL packing: kappa %g must be > 1", p->kappa);
  if (!(p->kt_over_kn >= 0.0)) TL_ERROR(TL_ERR_ARG, "NHL packing: k_t/k_n = %g must be >= 0", p->kt_over_kn);
  if (!(p->mu >= 0.0)) TL_ERROR(TL_ERR_ARG, "NHL packing: mu = %g must be >= 0", p->mu);
  if (!(p->restitution > 0.0 && p->restitution <= 1.0))
    TL_ERROR(TL_ERR_ARG, "NHL packing: restitution %g outside (0, 1]", p->restitution);
  if (!(p->dt_fraction > 0.0 && p->dt_fraction <= 1.0))
    TL_ERROR(TL_ERR_ARG, "NHL packing: dt_fraction %g outside (0, 1]", p->dt_fraction);
  if (!(p->skin >= 0.0 && p->skin <= 1.0)) TL_ERROR(TL_ERR_ARG, "NHL packing: skin %g outside [0, 1] diameters", p->skin);
  return TL_OK;
}

/* k_n from κ: 2-D κ = k_n/σ0 (per unit thickness), 3-D κ = k_n/(σ0 <d>). */
static double normal_stiffness(const TlNhlPacking *p, double d_mean)
{
  return p->dim == 2 ? p->kappa * p->pressure : p->kappa * p->pressure * d_mean;
}

static TlStatus make_law(const TlNhlPacking *p, double kn, TlContactLaw **law)
{
  TL_CHECK(tl_contact_law_create("linear", p->mu > 0.0 ? "coulomb" : NULL, NULL, NULL, law));
  TlStatus s = tl_contact_law_set(*law, "k_n", kn);
  if (s == TL_OK) s = tl_contact_law_set(*law, "restitution", p->restitution);
  if (s == TL_OK && p->mu > 0.0) s = tl_contact_law_set(*law, "mu", p->mu);
  if (s == TL_OK && p->mu > 0.0 && p->kt_over_kn > 0.0) s = tl_contact_law_set(*law, "k_t", p->kt_over_kn * kn);
  if (s == TL_OK) s = tl_contact_law_setup(*law);
  if (s != TL_OK) tl_contact_law_destroy(law);
  return s;
}

/* Law, time step and setup of a world whose particles are placed. */
static TlStatus finish_world(const TlNhlPacking *p, double kn, TlNhlWorld *w)
{
  TlContactLaw *law = NULL;
  TL_CHECK(make_law(p, kn, &law));
  int index = 0;
  TlStatus s = tl_dem_add_law(w->dem, law, &index);
  if (s != TL_OK) {
    tl_contact_law_destroy(&law);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  w->law = law;
  TL_CHECK(tl_dem_set_skin(w->dem, p->skin));
  tl_dem_track_orientation(w->dem, 0);
  double dtc, k, m;
  TL_CHECK(tl_dem_critical_timestep(w->dem, &dtc, &k, &m));
  TL_CHECK(tl_dem_set_timestep(w->dem, p->dt_fraction * dtc, 0));
  TL_CHECK(tl_dem_setup(w->dem));
  return TL_OK;
}

/* FCC at σ0: the bond length l with 2√2 k_n (d - l) / l² = σ0 (six bonds
 * per particle of volume a³/4, a = √2 l). */
static TlStatus build_fcc(const TlNhlPacking *p, TlNhlWorld *w)
{
  const double r = p->radius_max, d = 2.0 * r, kn = normal_stiffness(p, d);
  const double c = p->pressure / (2.0 * sqrt(2.0) * kn);
  const double l = (-1.0 + sqrt(1.0 + 4.0 * c * d)) / (2.0 * c), a = sqrt(2.0) * l;
  const long m = p->n_side;
  static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  TL_CHECK(tl_dem_create(&w->dem));
  TlParticles *P = tl_dem_particles(w->dem);
  TlDomain dom;
  TL_CHECK(tl_domain_init_cell(&dom, tl_v3(0, 0, 0), tl_m3_scale(tl_m3_identity(), (double)m * a)));
  TL_CHECK(tl_dem_set_domain(w->dem, &dom));
  int sp;
  TL_CHECK(tl_particles_add_species(P, "grain", p->density, r, r, &sp));
  TL_CHECK(tl_particles_reserve(P, (size_t)(4 * m * m * m)));
  for (long i = 0; i < m; ++i)
    for (long j = 0; j < m; ++j)
      for (long k = 0; k < m; ++k)
        for (int q = 0; q < 4; ++q)
          TL_CHECK(tl_dem_add_particle(w->dem,
                                       tl_v3((i + 0.25 + basis[q][0]) * a, (j + 0.25 + basis[q][1]) * a,
                                             (k + 0.25 + basis[q][2]) * a),
                                       tl_v3(0, 0, 0), r, sp, NULL));
  w->dim = 3;
  return finish_world(p, kn, w);
}

/* A gas at packing fraction φ0 in a cube (a square of unit thickness for
 * disks), radii uniform in diameter (tl_dem_insert_gas). */
static TlStatus build_random(const TlNhlPacking *p, TlNhlWorld *w)
{
  const double a = p->radius_min, b = p->radius_max, d_mean = a + b, kn = normal_stiffness(p, d_mean);
  const double phi0 = p->dim == 2 ? 0.4 : 0.3;
  /* mean particle volume (area) with r uniform in [a, b] */
  const double mean = p->dim == 2 ? TL_PI * (a * a + a * b + b * b) / 3.0 : TL_PI / 3.0 * (a + b) * (a * a + b * b);
  const double L = p->dim == 2 ? sqrt((double)p->n * mean / phi0) : cbrt((double)p->n * mean / phi0);
  TL_CHECK(tl_dem_create(&w->dem));
  TlParticles *P = tl_dem_particles(w->dem);
  TlDomain dom;
  TlMat3 h = tl_m3_scale(tl_m3_identity(), L);
  if (p->dim == 2) {
    h.m[2][2] = 1.0;
    TL_CHECK(tl_dem_set_dimension(w->dem, 2));
    TL_CHECK(tl_domain_init_cell_2d(&dom, tl_v3(0, 0, 0), h));
  } else {
    TL_CHECK(tl_domain_init_cell(&dom, tl_v3(0, 0, 0), h));
  }
  TL_CHECK(tl_dem_set_domain(w->dem, &dom));
  int sp = 0;
  TL_CHECK(tl_particles_add_species(P, "grain", p->density, a, b, &sp));
  TL_CHECK(tl_particles_reserve(P, (size_t)p->n));
  TL_CHECK(tl_dem_insert_gas(w->dem, sp, (size_t)p->n, (uint64_t)p->seed, 100000, NULL));
  w->dim = p->dim;
  return finish_world(p, kn, w);
}

static TlStatus build(void *ctx, TlNhlWorld *w)
{
  const PackingCtx *c = ctx;
  if (!strcmp(c->kind, "fcc")) return build_fcc(&c->p, w);
  return build_random(&c->p, w);
}

static void free_ctx(void *ctx)
{
  PackingCtx *c = ctx;
  tl_free(&c);
}

/* Isotropic compression to σ0 under a pressure servo, then relaxation to
 * Eq. 19 (the preparation of periodic_compress, seeds/004 Eq. 18 for the
 * rates). */
static TlStatus prepare_random(TlNhlCell *cell, const TlNhlPacking *p)
{
  TlDem *dem = tl_nhl_cell_dem(cell);
  const int dim = tl_nhl_cell_dim(cell);
  const double d = tl_nhl_cell_mean_diameter(cell), rho = tl_nhl_cell_grain_density(cell);
  const double rate_target = 1e-3 * sqrt(p->pressure / rho) / d, rate_gas = 3e-2 * sqrt(p->pressure / rho) / d;
  const double tol = tl_nhl_cell_settings(cell)->tolerance;
  const long every = 50, max_steps = 20000000;
  int reached = 0;
  double pr = 0.0, imb = 1.0;
  long k;
  for (k = 0; k < max_steps; k += every) {
    TlMat3 sc;
    TL_CHECK(tl_nhl_cell_stress(cell, &sc, NULL));
    pr = dim == 2 ? -0.5 * (sc.m[0][0] + sc.m[1][1]) : -tl_m3_trace(sc) / 3.0;
    TL_CHECK(tl_dem_max_force_imbalance(dem, &imb));
    const double err = (pr - p->pressure) / p->pressure;
    if (!reached && pr >= p->pressure) reached = 1;
    if (reached && fabs(err) < 1e-2 && imb < tol) break;
    double rate;
    if (!reached) {
      const double frac = fmax(pr, 0.0) / p->pressure;
      rate = -(rate_gas * (1.0 - frac) + rate_target * frac);
    } else {
      rate = fmax(-rate_target, fmin(rate_target, rate_target * 2.0 * err));
    }
    TlDomain *D = tl_dem_domain(dem);
    TlMat3 hdot = tl_m3_scale(D->h, rate);
    if (dim == 2) hdot.m[2][0] = hdot.m[2][1] = hdot.m[2][2] = hdot.m[0][2] = hdot.m[1][2] = 0.0;
    TL_CHECK(tl_domain_set_h_rate(D, hdot));
    TL_CHECK(tl_dem_step(dem, every));
  }
  TL_CHECK(tl_domain_set_h_rate(tl_dem_domain(dem), tl_m3_zero()));
  if (k >= max_steps)
    TL_ERROR(TL_ERR_CONVERGENCE, "NHL packing: the random packing did not settle in %ld steps (pressure %g Pa, target %g; "
             "largest imbalance %g, tolerance %g)", max_steps, pr, p->pressure, imb, tol);
  return TL_OK;
}

TlStatus tl_nhl_cell_create_packing(const TlNhlPacking *p, const TlNhlCellSettings *s, TlNhlCell **cell)
{
  if (!p || !s || !cell) TL_ERROR(TL_ERR_ARG, "tl_nhl_cell_create_packing: NULL argument");
  TL_CHECK(check_packing(p));
  PackingCtx *c;
  TL_CHECK(TL_NEW(c));
  c->p = *p;
  snprintf(c->kind, sizeof c->kind, "%s", p->kind);
  c->p.kind = c->kind;
  TlStatus st = tl_nhl_cell_create(build, c, s, cell);
  if (st != TL_OK) {
    tl_free(&c);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  tl_nhl_cell_set_free_ctx(*cell, free_ctx);
  if (!strcmp(c->kind, "random")) {
    st = prepare_random(*cell, &c->p);
    if (st == TL_OK) st = tl_nhl_cell_rebase(*cell);
    if (st != TL_OK) {
      tl_nhl_cell_destroy(cell);
      return tl_error_trace(st, __FILE__, __LINE__);
    }
  }
  return TL_OK;
}
