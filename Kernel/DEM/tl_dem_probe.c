/* Elastic tensor by strain probing (tl_dem_probe.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_checkpoint.h"
#include "tl_memory.h"
#include "tl_dem_private.h"
#include "tl_dem_probe.h"

/* Voigt pairs: xx yy zz yz xz xy */
static const int voigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};

void tl_probe_settings_default(TlProbeSettings *s)
{
  s->kind = TL_PROBE_AFFINE;
  s->strain = 1e-6;
  s->jiggle = 0.0;
  s->jiggle_seed = 87287;
  s->viscous = 0.5;
  s->tolerance = 1e-4;
  s->max_steps = 1000000;
  s->check_every = 200;
  s->relax_reference = 1;
  s->scratch = "elastic_probe_reference.h5";
}

void tl_elastic_moduli(const double (*C)[6], TlElasticModuli *m)
{
  m->C11 = (C[0][0] + C[1][1] + C[2][2]) / 3.0;
  m->C12 = (C[0][1] + C[1][0] + C[0][2] + C[2][0] + C[1][2] + C[2][1]) / 6.0;
  m->C44 = (C[3][3] + C[4][4] + C[5][5]) / 3.0;
  m->K = (m->C11 + 2.0 * m->C12) / 3.0;
  m->G1 = m->C44;
  m->G2 = 0.5 * (m->C11 - m->C12);
  m->nu = 1.0 / (1.0 + m->C11 / m->C12);
  m->G = 0.5 * (m->G1 + m->G2);
  m->E = 2.0 * m->G * (1.0 + m->nu);
  m->zener = 2.0 * m->C44 / (m->C11 - m->C12);
}

TlMat3 tl_probe_strain_map(int J, double e)
{
  TlMat3 F = tl_m3_identity();
  if (J >= 0 && J < 6) F.m[voigt[J][0]][voigt[J][1]] += e;
  return F;
}

TlStatus tl_dem_map_affine(TlDem *d, TlMat3 F)
{
  TlDomain *D = &d->domain;
  if (D->kind != TL_DOMAIN_DEFORMABLE_CELL)
    TL_ERROR(TL_ERR_ARG, "an affine map needs a deformable periodic cell (domain kind %d)", (int)D->kind);
  TL_CHECK(tl_domain_set_h(D, tl_m3_mul(F, D->h)));
  TlParticles *P = d->P;
  const TlVec3 o = D->origin;
  for (size_t i = 0; i < P->n; ++i) P->x[i] = tl_v3_add(o, tl_m3_mulv(F, tl_v3_sub(P->x[i], o)));
  /* the skin check of a cell at rest only watches the drift: the jump of
   * the cell and of the centres must be seen by the next evaluation */
  d->need_rebuild = 1;
  return TL_OK;
}

/* Symmetric part of the whole (contact + kinetic) stress, Voigt order, and
 * its largest skew component. */
static TlStatus voigt_stress(TlDem *d, double s[6], double *skew)
{
  TlMat3 sc, sk;
  TL_CHECK(tl_dem_stress(d, &sc, &sk));
  TlMat3 t = tl_m3_add(sc, sk);
  for (int i = 0; i < 6; ++i) {
    int a = voigt[i][0], b = voigt[i][1];
    s[i] = 0.5 * (t.m[a][b] + t.m[b][a]);
    if (!isfinite(s[i])) TL_ERROR(TL_ERR_NUMERIC, "probe: stress component %d is %g", i, s[i]);
    if (skew) *skew = fmax(*skew, 0.5 * fabs(t.m[a][b] - t.m[b][a]));
  }
  return TL_OK;
}

typedef struct {
  double c;
} Viscous;

/* LAMMPS fix viscous: f = -c v on every free particle, with the half-step
 * velocity the forces at t + dt are evaluated with.  The spins decay at the
 * same rate c/m (LAMMPS's fix leaves them free, damped only by the
 * tangential dashpots, which leaves the torques out of balance far longer
 * than the forces). */
static TlStatus viscous_hook(void *ctx, TlDem *d)
{
  const Viscous *v = ctx;
  TlParticles *P = d->P;
  for (size_t i = 0; i < P->n; ++i) {
    const int free = P->motion[i] == TL_MOTION_FREE;
    P->f_coupling[i] = free ? tl_v3_scale(P->v[i], -v->c) : tl_v3(0, 0, 0);
    if (P->w && free) P->w[i] = tl_v3_scale(P->w[i], fmax(0.0, 1.0 - v->c * d->dt * P->inv_mass[i]));
  }
  return TL_OK;
}

/* Static balance: the largest Δ_n of seeds/004 Eq. 19 (a grain's net
 * contact force over its largest contact force) over the free grains whose
 * largest contact carries at least 1e-3 of the mean contact force.  The
 * grains left out are rattlers: a strained packing often leaves one touched
 * by a single vanishing contact (Δ_n = 1 whatever its force), drifting off
 * for a long time while the stress has long settled.  `sum` holds 4 n
 * doubles of scratch. */
static double imbalance_of(const TlDem *d, double *sum)
{
  const TlParticles *P = d->P;
  double *mx = sum + 3 * P->n;
  memset(sum, 0, 4 * P->n * sizeof *sum);
  double fsum = 0.0;
  size_t nc = 0;
  const TlContactList *lists[2] = {&d->list, &d->bonds};
  for (int q = 0; q < 2; ++q) {
    const TlContactList *L = lists[q];
    if (L->n == (size_t)-1) continue;
    for (size_t c = 0; c < L->n; ++c) {
      if (!L->touching[c]) continue;
      const TlVec3 f = L->force[c];
      const size_t i = L->i[c], j = L->j[c];
      sum[3 * i] += f.x, sum[3 * i + 1] += f.y, sum[3 * i + 2] += f.z;
      sum[3 * j] -= f.x, sum[3 * j + 1] -= f.y, sum[3 * j + 2] -= f.z;
      const double m = tl_v3_norm(f);
      mx[i] = fmax(mx[i], m);
      mx[j] = fmax(mx[j], m);
      fsum += m;
      ++nc;
    }
  }
  if (nc == 0 || !(fsum > 0.0)) return 0.0;
  const double floor = 1e-3 * fsum / (double)nc;
  double worst = 0.0;
  for (size_t i = 0; i < P->n; ++i)
    if (P->motion[i] == TL_MOTION_FREE && mx[i] >= floor)
      worst = fmax(worst, sqrt(sum[3 * i] * sum[3 * i] + sum[3 * i + 1] * sum[3 * i + 1] + sum[3 * i + 2] * sum[3 * i + 2]) / mx[i]);
  return worst;
}

/* Relaxes at fixed cell until the packing's imbalance is below the tolerance. */
static TlStatus relax(TlDem *d, const TlProbeSettings *s, TlProbeResult *r, long *steps, double *imbalance)
{
  Viscous visc = {s->viscous};
  double *sum = NULL;
  TL_CHECK(tl_calloc(&sum, 4 * d->P->n + 4, sizeof *sum));
  tl_dem_set_step_hook(d, viscous_hook, &visc);
  TlStatus st = tl_dem_compute_forces(d);
  long k = 0;
  double imb = INFINITY;
  for (; st == TL_OK;) {
    imb = imbalance_of(d, sum);
    if (imb < s->tolerance || k >= s->max_steps) break;
    long n = s->check_every < s->max_steps - k ? s->check_every : s->max_steps - k;
    st = tl_dem_step(d, n);
    k += n;
  }
  tl_free(&sum);
  tl_dem_set_step_hook(d, NULL, NULL);
  if (st != TL_OK) return tl_error_trace(st, __FILE__, __LINE__);
  TlParticles *P = d->P;
  memset(P->f_coupling, 0, P->n * sizeof *P->f_coupling);
  /* the stress is read from forces without the viscous part */
  TL_CHECK(tl_dem_compute_forces(d));
  *steps = k;
  *imbalance = imb;
  if (k > r->relax_steps) r->relax_steps = k;
  if (!(imb <= r->relax_imbalance)) r->relax_imbalance = imb;
  if (!(imb < s->tolerance)) r->relax_converged = 0;
  return TL_OK;
}

static TlStatus check(const TlDem *d, const TlProbeSettings *s)
{
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "probe: tl_dem_setup must precede the probe");
  if (d->domain.kind != TL_DOMAIN_DEFORMABLE_CELL)
    TL_ERROR(TL_ERR_ARG, "probe: the packing must be in a deformable periodic cell (tl_domain_init_cell)");
  if (d->n_walls) TL_ERROR(TL_ERR_ARG, "probe: %zu walls; a probed packing has none", d->n_walls);
  if (d->n_presc) TL_ERROR(TL_ERR_ARG, "probe: %zu prescribed-motion groups; a probed packing has none", d->n_presc);
  if (d->P->n < 2) TL_ERROR(TL_ERR_ARG, "probe: %zu particles; at least 2", d->P->n);
  if (!(s->strain > 0.0 && s->strain <= 0.1)) TL_ERROR(TL_ERR_ARG, "probe: strain %g outside (0, 0.1]", s->strain);
  if (!(s->jiggle >= 0.0 && s->jiggle <= d->r_min))
    TL_ERROR(TL_ERR_ARG, "probe: jiggle %g m outside [0, %g] (the smallest radius)", s->jiggle, d->r_min);
  if (s->kind == TL_PROBE_RELAXED) {
    if (!(s->viscous > 0.0 && isfinite(s->viscous)))
      TL_ERROR(TL_ERR_ARG, "probe: viscous damping %g N s/m must be positive", s->viscous);
    if (!(s->tolerance > 0.0)) TL_ERROR(TL_ERR_ARG, "probe: tolerance %g must be positive", s->tolerance);
    if (s->max_steps < 1) TL_ERROR(TL_ERR_ARG, "probe: max_steps %ld must be >= 1", s->max_steps);
    if (s->check_every < 1) TL_ERROR(TL_ERR_ARG, "probe: check_every %ld must be >= 1", s->check_every);
  } else if (s->kind != TL_PROBE_AFFINE)
    TL_ERROR(TL_ERR_ARG, "probe: unknown protocol %d", (int)s->kind);
  if (!s->scratch || !s->scratch[0]) TL_ERROR(TL_ERR_ARG, "probe: no scratch path");
  return TL_OK;
}

static TlStatus probe(TlDem *d, const TlProbeSettings *s, TlProbeResult *r, TlCheckpoint *cp)
{
  TlParticles *P = d->P;
  const int relaxed = s->kind == TL_PROBE_RELAXED;
  if (relaxed) TL_CHECK(tl_particles_enable_coupling_force(P));
  if (s->jiggle > 0.0) {
    uint64_t rng = s->jiggle_seed * 0x9e3779b97f4a7c15ULL + 0x632be59bd9b4e019ULL;
    for (size_t i = 0; i < P->n; ++i) {
      if (P->motion[i] != TL_MOTION_FREE) continue;
      double *x = &P->x[i].x;
      for (int k = 0; k < 3; ++k) x[k] += s->jiggle * (2.0 * tl_random_uniform(&rng) - 1.0);
    }
    d->need_rebuild = 1;
  }
  if (relaxed && s->relax_reference) TL_CHECK(relax(d, s, r, &r->reference_steps, &r->reference_imbalance));
  else TL_CHECK(tl_dem_compute_forces(d));
  TL_CHECK(voigt_stress(d, r->stress0, &r->max_skew));
  r->pressure0 = -(r->stress0[0] + r->stress0[1] + r->stress0[2]) / 3.0;
  TL_CHECK(tl_checkpoint_save(cp, s->scratch, tl_dem_time(d), 0));
  const double e = s->strain;
  for (int J = 0; J < 6; ++J) {
    double sp[6], sm[6];
    for (int sign = -1; sign <= 1; sign += 2) {
      TL_CHECK(tl_checkpoint_load(cp, s->scratch, NULL, NULL));
      TL_CHECK(tl_dem_map_affine(d, tl_probe_strain_map(J, sign * e)));
      if (relaxed) TL_CHECK(relax(d, s, r, &r->probe_steps[J][sign > 0], &r->probe_imbalance[J][sign > 0]));
      else TL_CHECK(tl_dem_compute_forces(d));
      TL_CHECK(voigt_stress(d, sign > 0 ? sp : sm, &r->max_skew));
    }
    for (int i = 0; i < 6; ++i) {
      r->C[i][J] = (sp[i] - sm[i]) / (2.0 * e);
      r->C_pos[i][J] = (sp[i] - r->stress0[i]) / e;
      r->C_neg[i][J] = (sm[i] - r->stress0[i]) / -e;
    }
  }
  for (int i = 0; i < 6; ++i)
    for (int J = 0; J < 6; ++J) r->C_sym[i][J] = 0.5 * (r->C[i][J] + r->C[J][i]);
  tl_elastic_moduli(r->C_sym, &r->moduli);
  /* back to the reference state */
  TL_CHECK(tl_checkpoint_load(cp, s->scratch, NULL, NULL));
  d->need_rebuild = 1;
  TL_CHECK(tl_dem_compute_forces(d));
  return TL_OK;
}

TlStatus tl_dem_probe_elastic(TlDem *d, const TlProbeSettings *s, TlProbeResult *r)
{
  TL_CHECK(check(d, s));
  memset(r, 0, sizeof *r);
  r->relax_converged = 1;
  TlDemStepHook hook = d->hook;
  void *hook_ctx = d->hook_ctx;
  TlCheckpoint *cp = NULL;
  TlStatus st = tl_checkpoint_create(&cp);
  if (st == TL_OK) st = tl_checkpoint_add(cp, "dem", &tl_dem_checkpoint_ops, d);
  if (st == TL_OK) st = probe(d, s, r, cp);
  tl_checkpoint_destroy(&cp);
  remove(s->scratch);
  tl_dem_set_step_hook(d, hook, hook_ctx);
  if (st != TL_OK) return tl_error_trace(st, __FILE__, __LINE__);
  return TL_OK;
}
