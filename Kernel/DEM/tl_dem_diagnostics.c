/* DEM diagnostics: energy balance, stress, coordination, force imbalance,
 * statistics and the contact visitors. */
#include "tl_dem_private.h"

#include <math.h>
#include <string.h>
#include "tl_memory.h"

TlStatus tl_dem_energy(TlDem *d, TlDemEnergy *e)
{
  const TlParticles *P = d->P;
  memset(e, 0, sizeof *e);
  for (size_t i = 0; i < P->n; ++i) {
    if (P->motion[i] != TL_MOTION_FREE) continue;
    /* a weighted world: its energies are the weighted ones (Eq. 25) */
    double m = P->mass[i] * (d->weight_fn ? P->weight[i] : 1.0);
    TlVec3 v = P->v[i];
    e->kinetic_translational += 0.5 * m * tl_v3_norm2(v);
    e->gravitational -= m * tl_v3_dot(d->gravity, P->x[i]);
    e->momentum = tl_v3_axpy(e->momentum, m, v);
    TlVec3 L = tl_v3_scale(tl_v3_cross(P->x[i], v), m);
    if (P->w) {
      double I = (d->weight_fn ? P->weight[i] : 1.0) / P->inv_inertia[i];
      e->kinetic_rotational += 0.5 * I * tl_v3_norm2(P->w[i]);
      L = tl_v3_axpy(L, I, P->w[i]);
    }
    e->angular_momentum = tl_v3_add(e->angular_momentum, L);
  }
  double cw = d->contact_work_pp, el = d->elastic_pp, ww = 0.0;
  for (size_t w = 0; w < d->n_walls; ++w) {
    cw += d->walls[w]->contact_work;
    el += d->walls[w]->elastic_energy;
    ww += d->walls[w]->work;
  }
  e->elastic = el;
  e->work_external = d->work_ext + ww;
  e->dissipated = cw - el;
  e->total = e->kinetic_translational + e->kinetic_rotational + e->elastic + e->gravitational - e->work_external +
             e->dissipated;
  return TL_OK;
}

TlStatus tl_dem_stress(TlDem *d, TlMat3 *sc, TlMat3 *sk)
{
  const TlParticles *P = d->P;
  /* a 2-D world: per unit thickness, over the in-plane area */
  double V = d->dim == 2 ? tl_domain_area(&d->domain) : tl_domain_volume(&d->domain);
  TlMat3 s = tl_m3_zero(), k = tl_m3_zero();
  const TlContactList *lists[2] = {&d->list, &d->bonds};
  for (int q = 0; q < 2; ++q) {
    const TlContactList *L = lists[q];
    if (L->n == (size_t)-1) continue;
    for (size_t c = 0; c < L->n; ++c) {
      if (!L->touching[c]) continue;
      TlVec3 b = tl_domain_branch(&d->domain, P->x[L->i[c]], P->x[L->j[c]]);
      s = tl_m3_add(s, tl_m3_outer(L->force[c], b));
    }
  }
  for (size_t i = 0; i < P->n; ++i)
    if (P->motion[i] == TL_MOTION_FREE) k = tl_m3_add(k, tl_m3_scale(tl_m3_outer(P->v[i], P->v[i]), -P->mass[i]));
  *sc = tl_m3_scale(s, 1.0 / V);
  if (sk) *sk = tl_m3_scale(k, 1.0 / V);
  return TL_OK;
}

TlStatus tl_dem_coordination(TlDem *d, double *z, double *z_nr)
{
  const TlParticles *P = d->P;
  TL_CHECK(tl_array_reserve(&d->scratch, &d->scratch_cap, P->n + 1, sizeof *d->scratch));
  double *cnt = d->scratch;
  memset(cnt, 0, P->n * sizeof *cnt);
  const TlContactList *lists[2] = {&d->list, &d->bonds};
  for (int q = 0; q < 2; ++q) {
    const TlContactList *L = lists[q];
    if (L->n == (size_t)-1) continue;
    for (size_t c = 0; c < L->n; ++c)
      if (L->touching[c]) {
        cnt[L->i[c]] += 1.0;
        cnt[L->j[c]] += 1.0;
      }
  }
  double sum = 0.0, sum_nr = 0.0;
  size_t nf = 0, nnr = 0;
  for (size_t i = 0; i < P->n; ++i) {
    if (P->motion[i] != TL_MOTION_FREE) continue;
    sum += cnt[i];
    ++nf;
    if (cnt[i] >= 2.0) {
      sum_nr += cnt[i];
      ++nnr;
    }
  }
  *z = nf ? sum / (double)nf : 0.0;
  if (z_nr) *z_nr = nnr ? sum_nr / (double)nnr : 0.0;
  return TL_OK;
}

TlStatus tl_dem_max_force_imbalance(TlDem *d, double *delta)
{
  const TlParticles *P = d->P;
  TL_CHECK(tl_array_reserve(&d->scratch, &d->scratch_cap, 4 * P->n + 4, sizeof *d->scratch));
  double *sx = d->scratch, *mx = d->scratch + 3 * P->n;
  memset(d->scratch, 0, 4 * P->n * sizeof *d->scratch);
  const TlContactList *lists[2] = {&d->list, &d->bonds};
  for (int q = 0; q < 2; ++q) {
    const TlContactList *L = lists[q];
    if (L->n == (size_t)-1) continue;
    for (size_t c = 0; c < L->n; ++c) {
      if (!L->touching[c]) continue;
      TlVec3 f = L->force[c];
      size_t i = L->i[c], j = L->j[c];
      sx[3 * i] += f.x; sx[3 * i + 1] += f.y; sx[3 * i + 2] += f.z;
      sx[3 * j] -= f.x; sx[3 * j + 1] -= f.y; sx[3 * j + 2] -= f.z;
      double m = tl_v3_norm(f);
      mx[i] = fmax(mx[i], m);
      mx[j] = fmax(mx[j], m);
    }
  }
  double worst = 0.0;
  for (size_t i = 0; i < P->n; ++i) {
    if (P->motion[i] != TL_MOTION_FREE || !(mx[i] > 0.0)) continue;
    double s = sqrt(sx[3 * i] * sx[3 * i] + sx[3 * i + 1] * sx[3 * i + 1] + sx[3 * i + 2] * sx[3 * i + 2]) / mx[i];
    worst = fmax(worst, s);
  }
  *delta = worst;
  return TL_OK;
}

void tl_dem_stats(const TlDem *d, TlDemStats *s)
{
  s->steps = d->steps;
  s->rebuilds = d->rebuilds;
  s->n_contacts = d->n_touching;
  s->n_pairs = d->list.n;
}

void tl_dem_phase_times(const TlDem *d, TlDemPhaseTimes *t)
{
  *t = d->prof;
  t->steps = d->steps - d->prof.steps;
}

void tl_dem_reset_phase_times(TlDem *d)
{
  memset(&d->prof, 0, sizeof d->prof);
  d->prof.steps = d->steps;
  d->profile = 1;
}

const char *tl_dem_phase_name(int phase)
{
  static const char *names[TL_DEM_N_PHASES] = {"integrate", "grid", "pairs",   "list", "body",
                                               "contacts",  "reduce", "walls", "other"};
  return phase >= 0 && phase < TL_DEM_N_PHASES ? names[phase] : "?";
}

TlStatus tl_dem_visit_contacts(TlDem *d, TlContactVisitor visit, void *ctx)
{
  const TlParticles *P = d->P;
  const TlContactList *lists[2] = {&d->list, &d->bonds};
  for (int q = 0; q < 2; ++q) {
    const TlContactList *L = lists[q];
    if (L->n == (size_t)-1) continue;
    for (size_t c = 0; c < L->n; ++c) {
      if (!L->touching[c]) continue;
      size_t i = L->i[c], j = L->j[c];
      TlVec3 b = tl_domain_branch(&d->domain, P->x[i], P->x[j]);
      double dist = tl_v3_norm(b);
      double ov = P->radius[i] + P->radius[j] - dist;
      TlVec3 nrm = dist > 0.0 ? tl_v3_scale(b, 1.0 / dist) : tl_v3(1, 0, 0);
      TlVec3 cp = tl_v3_add(P->x[i], tl_v3_scale(nrm, P->radius[i] - 0.5 * ov));
      visit(ctx, i, j, L->force[c], b, cp);
    }
  }
  return TL_OK;
}

/* Adds the wall's index to what the wall's own visitor reports. */
typedef struct {
  TlWallContactVisitor visit;
  void *ctx;
  size_t wall;
} WallVisit;

static void visit_wall_contact(void *ctx, size_t i, TlVec3 force, TlVec3 point, TlVec3 center)
{
  const WallVisit *v = ctx;
  v->visit(v->ctx, v->wall, i, force, point, center);
}

TlStatus tl_dem_visit_wall_contacts(TlDem *d, TlWallContactVisitor visit, void *ctx)
{
  for (size_t k = 0; k < d->n_walls; ++k) {
    WallVisit v = {visit, ctx, k};
    TL_CHECK(tl_wall_visit_contacts(d->walls[k], d->P, visit_wall_contact, &v));
  }
  return TL_OK;
}
