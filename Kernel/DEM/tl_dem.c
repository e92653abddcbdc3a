#include "tl_dem.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "tl_contact_kernels.h"
#include "tl_contact_list.h"
#include "tl_log.h"
#include "tl_memory.h"
#include "tl_parallel.h"
#include "tl_wall_trisurface.h"

enum { TL_DEM_MAX_LAWS = 16, CHUNK = 64 };

typedef struct {
  size_t start, end;
  int law;
} Chunk;

typedef struct {
  TlPrescribedEval eval;
  void *ctx;
  size_t n;
  int64_t *ids;
  size_t *idx;
  TlVec3 *x0, *xs, *vs;
} Prescribed;

typedef struct {
  int a, b, law;
} PairLaw;

struct TlDem {
  TlParticles *P;
  TlDomain domain;
  TlVec3 gravity;
  double skin_factor, skin, max_cut;
  int threads, sort_every, skip_fixed, track_energy;
  TlContactLaw *laws[TL_DEM_MAX_LAWS];
  int n_laws;
  PairLaw *pair_laws;
  size_t n_pair_laws, pair_laws_cap;
  int *law_table;
  size_t law_table_n;
  TlWall **walls;
  size_t n_walls, walls_cap;
  size_t hd; /* history stride */
  TlContactList list, old, bonds;
  int64_t *bond_ids;
  size_t n_bond_ids, bond_ids_cap;
  Chunk *chunks, *bond_chunks;
  size_t n_chunks, chunks_cap, n_bond_chunks, bond_chunks_cap;
  TlPair *pairs;
  size_t pairs_cap, n_pairs;
  TlHGrid *grid;
  TlVec3 *x_build;
  size_t x_build_cap;
  TlMat3 h_build_inv;
  uint8_t *skip;
  size_t skip_cap;
  size_t *perm, *old_to_new;
  size_t perm_cap;
  TlVec3 *tf, *tt;
  double (*xr)[4]; /* position and radius packed: one cache line per neighbour in the pair scan */
  size_t xr_cap;
  size_t t_cap;
  int nt, nt_now;
  Prescribed *presc;
  size_t n_presc, presc_cap;
  double dt, t, disp2max, r_min;
  int allow_above, setup_done, need_rebuild, rotation, orientation;
  long steps, rebuilds;
  size_t n_touching;
  /* energy bookkeeping */
  double elastic_pp, contact_work_pp, work_ext;
  double *scratch;
  size_t scratch_cap;
  /* weights of the equations (volume coupling), all unused without a field */
  TlDemWeightFn weight_fn;
  void *weight_ctx;
  double *cw_list, *cw_bonds; /* per-contact weights of the last evaluation */
  size_t cw_list_cap, cw_bonds_cap;
  TlVec3 *cpoint;             /* contact points, scratch */
  size_t cpoint_cap;
  double *im_w, *ii_w;        /* 1 / (w m), 1 / (w I): the kicks of a weighted world */
  size_t im_w_cap, ii_w_cap;
  TlDemStepHook hook;
  void *hook_ctx;
};

TlStatus tl_dem_create(TlDem **out)
{
  TlDem *d;
  TL_CHECK(TL_NEW(d));
  TlStatus s;
  TL_CHECK_GOTO(s, tl_particles_create(&d->P), fail);
  TL_CHECK_GOTO(s, tl_hgrid_create(&d->grid), fail);
  TL_CHECK_GOTO(s, tl_domain_init_open(&d->domain, tl_v3(0, 0, 0), tl_v3(1, 1, 1)), fail);
  d->skin_factor = 0.1;
  d->sort_every = 10;
  d->skip_fixed = 1;
  d->track_energy = 1;
  d->orientation = 1;
  d->need_rebuild = 1;
  *out = d;
  return TL_OK;
fail:
  tl_dem_destroy(&d);
  return s;
}

void tl_dem_destroy(TlDem **dp)
{
  TlDem *d = *dp;
  if (!d) return;
  tl_particles_destroy(&d->P);
  tl_hgrid_destroy(&d->grid);
  for (int k = 0; k < d->n_laws; ++k) tl_contact_law_destroy(&d->laws[k]);
  for (size_t k = 0; k < d->n_walls; ++k) tl_wall_destroy(&d->walls[k]);
  tl_free(&d->walls);
  tl_free(&d->pair_laws);
  tl_free(&d->law_table);
  tl_contact_list_free(&d->list);
  tl_contact_list_free(&d->old);
  tl_contact_list_free(&d->bonds);
  tl_free(&d->bond_ids);
  tl_free(&d->chunks);
  tl_free(&d->bond_chunks);
  tl_free(&d->pairs);
  tl_free(&d->x_build);
  tl_free(&d->skip);
  tl_free(&d->perm);
  tl_free(&d->old_to_new);
  tl_free(&d->tf);
  tl_free(&d->xr);
  tl_free(&d->tt);
  for (size_t k = 0; k < d->n_presc; ++k) {
    Prescribed *p = &d->presc[k];
    tl_free(&p->ids); tl_free(&p->idx); tl_free(&p->x0); tl_free(&p->xs); tl_free(&p->vs);
  }
  tl_free(&d->presc);
  tl_free(&d->scratch);
  tl_free(&d->cw_list);
  tl_free(&d->cw_bonds);
  tl_free(&d->cpoint);
  tl_free(&d->im_w);
  tl_free(&d->ii_w);
  tl_free(dp);
}

TlParticles *tl_dem_particles(TlDem *d) { return d->P; }
TlDomain *tl_dem_domain(TlDem *d) { return &d->domain; }
const TlHGrid *tl_dem_grid(const TlDem *d) { return d->grid; }
size_t tl_dem_n_walls(const TlDem *d) { return d->n_walls; }
TlWall *tl_dem_wall(TlDem *d, size_t k) { return k < d->n_walls ? d->walls[k] : NULL; }
double tl_dem_timestep(const TlDem *d) { return d->dt; }
double tl_dem_time(const TlDem *d) { return d->t; }
void tl_dem_set_gravity(TlDem *d, TlVec3 g) { d->gravity = g; }
void tl_dem_set_threads(TlDem *d, int threads)
{
  d->threads = threads;
  if (threads > 0) omp_set_num_threads(threads); /* walls follow the OpenMP default */
  if (d->setup_done) d->nt = threads > 0 ? threads : omp_get_max_threads();
}
void tl_dem_set_weight_field(TlDem *d, TlDemWeightFn fn, void *ctx)
{
  d->weight_fn = fn;
  d->weight_ctx = ctx;
}

void tl_dem_set_step_hook(TlDem *d, TlDemStepHook hook, void *ctx)
{
  d->hook = hook;
  d->hook_ctx = ctx;
}

void tl_dem_skip_fixed_pairs(TlDem *d, int skip) { d->skip_fixed = skip; d->need_rebuild = 1; }
void tl_dem_track_energy(TlDem *d, int on) { d->track_energy = on; }
void tl_dem_track_orientation(TlDem *d, int on) { d->orientation = on; }
void tl_dem_set_sort_interval(TlDem *d, int rebuilds) { d->sort_every = rebuilds < 0 ? 0 : rebuilds; }

TlStatus tl_dem_set_domain(TlDem *d, const TlDomain *domain)
{
  d->domain = *domain;
  d->need_rebuild = 1;
  return TL_OK;
}

TlStatus tl_dem_set_skin(TlDem *d, double f)
{
  if (!(f >= 0.0) || !(f <= 10.0)) TL_ERROR(TL_ERR_ARG, "skin %g (fraction of the mean diameter) must be in [0, 10]", f);
  d->skin_factor = f;
  d->need_rebuild = 1;
  return TL_OK;
}

TlStatus tl_dem_add_law(TlDem *d, TlContactLaw *law, int *index)
{
  if (!law) TL_ERROR(TL_ERR_ARG, "contact law is NULL");
  if (d->n_laws >= TL_DEM_MAX_LAWS) TL_ERROR(TL_ERR_ARG, "too many contact laws (limit %d)", TL_DEM_MAX_LAWS);
  if (d->setup_done && law->history_doubles > d->hd)
    TL_ERROR(TL_ERR_STATE, "a law needing %zu history doubles cannot be added after setup (stride %zu)",
             law->history_doubles, d->hd);
  d->laws[d->n_laws] = law;
  if (index) *index = d->n_laws;
  d->n_laws++;
  return TL_OK;
}

TlStatus tl_dem_set_pair_law(TlDem *d, int a, int b, int law)
{
  if (law < 0 || law >= d->n_laws) TL_ERROR(TL_ERR_ARG, "law index %d out of range (%d laws)", law, d->n_laws);
  if (a < 0 || b < 0) TL_ERROR(TL_ERR_ARG, "species %d, %d must be >= 0", a, b);
  TL_CHECK(tl_array_reserve(&d->pair_laws, &d->pair_laws_cap, d->n_pair_laws + 1, sizeof *d->pair_laws));
  d->pair_laws[d->n_pair_laws++] = (PairLaw){a, b, law};
  d->need_rebuild = 1;
  return TL_OK;
}

TlStatus tl_dem_add_wall(TlDem *d, TlWall *w, int law)
{
  if (!w) TL_ERROR(TL_ERR_ARG, "wall is NULL");
  if (law < 0 || law >= d->n_laws) TL_ERROR(TL_ERR_ARG, "wall law index %d out of range (%d laws); add the law first", law, d->n_laws);
  TL_CHECK(tl_array_reserve(&d->walls, &d->walls_cap, d->n_walls + 1, sizeof *d->walls));
  w->law = law;
  d->walls[d->n_walls++] = w;
  return TL_OK;
}

TlStatus tl_dem_add_bond(TlDem *d, int64_t a, int64_t b)
{
  if (a == b) TL_ERROR(TL_ERR_ARG, "bond of particle %lld with itself", (long long)a);
  TL_CHECK(tl_array_reserve(&d->bond_ids, &d->bond_ids_cap, d->n_bond_ids + 2, sizeof *d->bond_ids));
  d->bond_ids[d->n_bond_ids++] = a;
  d->bond_ids[d->n_bond_ids++] = b;
  d->need_rebuild = 1;
  d->bonds.n = (size_t)-1; /* bond list to be rebuilt from ids */
  return TL_OK;
}

TlStatus tl_dem_prescribe(TlDem *d, size_t n, const int64_t *ids, TlPrescribedEval eval, void *ctx)
{
  if (!eval || !n) TL_ERROR(TL_ERR_ARG, "prescribed motion needs a function and at least one particle (n = %zu)", n);
  TL_CHECK(tl_array_reserve(&d->presc, &d->presc_cap, d->n_presc + 1, sizeof *d->presc));
  Prescribed *p = &d->presc[d->n_presc];
  memset(p, 0, sizeof *p);
  p->eval = eval;
  p->ctx = ctx;
  p->n = n;
  TL_CHECK(tl_calloc(&p->ids, n, sizeof *p->ids));
  TL_CHECK(tl_calloc(&p->idx, n, sizeof *p->idx));
  TL_CHECK(tl_calloc(&p->x0, n, sizeof *p->x0));
  TL_CHECK(tl_calloc(&p->xs, n, sizeof *p->xs));
  TL_CHECK(tl_calloc(&p->vs, n, sizeof *p->vs));
  d->n_presc++;
  for (size_t k = 0; k < n; ++k) {
    p->ids[k] = ids[k];
    TL_CHECK(tl_particles_find(d->P, ids[k], &p->idx[k]));
    p->x0[k] = d->P->x[p->idx[k]];
    TL_CHECK(tl_particles_set_motion(d->P, p->idx[k], TL_MOTION_PRESCRIBED));
  }
  return TL_OK;
}

/* ------------------------------------------------------------ time step */

static double min_radius(const TlParticles *P, double *rmax, double *m_min)
{
  double r = INFINITY, R = 0.0, m = INFINITY;
  for (size_t i = 0; i < P->n; ++i) {
    r = fmin(r, P->radius[i]);
    R = fmax(R, P->radius[i]);
    if (P->motion[i] == TL_MOTION_FREE) m = fmin(m, P->mass[i]);
  }
  *rmax = R;
  *m_min = m;
  return r;
}

TlStatus tl_dem_critical_timestep(TlDem *d, double *dt_c, double *k_max_out, double *m_min_out)
{
  double rmax, m_min, rmin = min_radius(d->P, &rmax, &m_min);
  if (!d->P->n || !isfinite(m_min)) {
    *dt_c = INFINITY;
    if (k_max_out) *k_max_out = 0.0;
    if (m_min_out) *m_min_out = m_min;
    return TL_OK;
  }
  double overlap = 0.1 * rmin, k_max = 0.0, zeta = 0.0;
  for (int l = 0; l < d->n_laws; ++l) {
    const TlContactLaw *law = d->laws[l];
    double k = law->ops->max_stiffness(law, rmax, overlap);
    k_max = fmax(k_max, k);
    double c = law->ops->max_damping ? law->ops->max_damping(law, 0.5 * m_min, rmax, overlap) : 0.0;
    if (k > 0.0) zeta = fmax(zeta, c / (2.0 * sqrt(k * 0.5 * m_min)));
  }
  *dt_c = k_max > 0.0 ? 0.5 * sqrt(m_min / k_max) * (sqrt(1.0 + zeta * zeta) - zeta) : INFINITY;
  if (k_max_out) *k_max_out = k_max;
  if (m_min_out) *m_min_out = m_min;
  return TL_OK;
}

TlStatus tl_dem_set_timestep(TlDem *d, double dt, int allow)
{
  if (!(dt > 0.0) || !isfinite(dt)) TL_ERROR(TL_ERR_ARG, "time step %g must be positive and finite", dt);
  d->dt = dt;
  d->allow_above = allow;
  if (d->setup_done) {
    double dtc, k, m;
    TL_CHECK(tl_dem_critical_timestep(d, &dtc, &k, &m));
    if (dt > dtc && !allow)
      TL_ERROR(TL_ERR_UNSTABLE, "time step %g s exceeds the critical time step %g s (k_max = %g N/m, m_min = %g kg); "
               "reduce dt or set the override", dt, dtc, k, m);
  }
  return TL_OK;
}

/* ---------------------------------------------------------- neighbours */

static int law_of(const TlDem *d, int a, int b)
{
  size_t ns = d->law_table_n;
  if ((size_t)a < ns && (size_t)b < ns) return d->law_table[(size_t)a * ns + (size_t)b];
  return 0;
}

static TlStatus build_law_table(TlDem *d)
{
  size_t ns = d->P->n_species ? d->P->n_species : 1;
  if (ns != d->law_table_n) {
    tl_free(&d->law_table);
    TL_CHECK(tl_calloc(&d->law_table, ns * ns, sizeof *d->law_table));
    d->law_table_n = ns;
  }
  memset(d->law_table, 0, ns * ns * sizeof *d->law_table);
  for (size_t k = 0; k < d->n_pair_laws; ++k) {
    PairLaw p = d->pair_laws[k];
    if ((size_t)p.a >= ns || (size_t)p.b >= ns)
      TL_ERROR(TL_ERR_ARG, "pair law for species %d-%d: only %zu species exist", p.a, p.b, ns);
    d->law_table[(size_t)p.a * ns + (size_t)p.b] = p.law;
    d->law_table[(size_t)p.b * ns + (size_t)p.a] = p.law;
  }
  return TL_OK;
}

static TlStatus make_chunks(const TlContactList *L, Chunk **chunks, size_t *cap, size_t *n)
{
  *n = 0;
  size_t k = 0;
  while (k < L->n) {
    int law = L->law[k];
    size_t e = k;
    while (e < L->n && L->law[e] == law && e - k < CHUNK) ++e;
    TL_CHECK(tl_array_reserve(chunks, cap, *n + 1, sizeof **chunks));
    (*chunks)[(*n)++] = (Chunk){k, e, law};
    k = e;
  }
  return TL_OK;
}

static TlStatus remap_everything(TlDem *d, const size_t *old_to_new, size_t n_old)
{
  TlContactList *lists[2] = {&d->list, &d->bonds};
  for (int q = 0; q < 2; ++q) {
    TlContactList *L = lists[q];
    if (L->n == (size_t)-1) continue;
    size_t m = 0;
    for (size_t k = 0; k < L->n; ++k) {
      size_t i = old_to_new[L->i[k]], j = old_to_new[L->j[k]];
      if (i == SIZE_MAX || j == SIZE_MAX) continue; /* a removed particle: contact gone */
      L->i[m] = (uint32_t)i;
      L->j[m] = (uint32_t)j;
      L->law[m] = L->law[k];
      L->touching[m] = L->touching[k];
      L->force[m] = L->force[k];
      if (L->history_doubles && m != k)
        memmove(L->history + m * L->history_doubles, L->history + k * L->history_doubles,
                L->history_doubles * sizeof *L->history);
      ++m;
    }
    L->n = m;
  }
  /* the bond hash (which keeps bonded pairs out of the neighbour list) is
   * keyed by index: rebuild it */
  if (d->bonds.n != (size_t)-1 && d->bonds.n) TL_CHECK(tl_contact_list_index(&d->bonds, 0));
  for (size_t w = 0; w < d->n_walls; ++w)
    if (d->walls[w]->ops->remap) TL_CHECK(d->walls[w]->ops->remap(d->walls[w], old_to_new, n_old));
  for (size_t g = 0; g < d->n_presc; ++g) {
    Prescribed *p = &d->presc[g];
    for (size_t k = 0; k < p->n; ++k) {
      size_t q = old_to_new[p->idx[k]];
      if (q == SIZE_MAX)
        TL_ERROR(TL_ERR_STATE, "prescribed particle id %lld was removed; remove its motion first", (long long)p->ids[k]);
      p->idx[k] = q;
    }
  }
  return TL_OK;
}

static TlStatus build_bonds(TlDem *d)
{
  TlContactList *B = &d->bonds;
  B->n = 0;
  for (size_t k = 0; k < d->n_bond_ids; k += 2) {
    size_t a, b;
    TL_CHECK(tl_particles_find(d->P, d->bond_ids[k], &a));
    TL_CHECK(tl_particles_find(d->P, d->bond_ids[k + 1], &b));
    int law = law_of(d, d->P->species[a], d->P->species[b]);
    TL_CHECK(tl_contact_list_push(B, (uint32_t)a, (uint32_t)b, law, NULL));
    B->touching[B->n - 1] = 1;
  }
  /* group by law for batching (stable: few laws) */
  if (d->n_laws > 1 && B->n > 1) {
    /* insertion by law: bonds are set up once */
    for (size_t k = 1; k < B->n; ++k)
      for (size_t m = k; m > 0 && B->law[m - 1] > B->law[m]; --m) {
        uint32_t ti = B->i[m]; B->i[m] = B->i[m - 1]; B->i[m - 1] = ti;
        uint32_t tj = B->j[m]; B->j[m] = B->j[m - 1]; B->j[m - 1] = tj;
        uint8_t tl = B->law[m]; B->law[m] = B->law[m - 1]; B->law[m - 1] = tl;
      }
  }
  TL_CHECK(tl_contact_list_index(B, 0));
  return make_chunks(B, &d->bond_chunks, &d->bond_chunks_cap, &d->n_bond_chunks);
}

static TlStatus rebuild(TlDem *d)
{
  TlParticles *P = d->P;
  size_t n = P->n;
  /* wrap into the periodic cell and remember the build positions */
  if (d->domain.any_periodic)
    for (size_t i = 0; i < n; ++i) P->x[i] = tl_domain_wrap(&d->domain, P->x[i]);
  TL_CHECK(tl_hgrid_build(d->grid, &d->domain, n, P->x, P->radius, d->skin));
  /* renumber particles in grid order now and then, for memory locality */
  int sort = d->sort_every > 0 && (d->rebuilds % d->sort_every) == 0 && n > 1;
  if (sort) {
    if (n > d->perm_cap) {
      TL_CHECK(tl_realloc(&d->perm, n, sizeof *d->perm));
      TL_CHECK(tl_realloc(&d->old_to_new, n, sizeof *d->old_to_new));
      d->perm_cap = n;
    }
    for (size_t k = 0; k < n; ++k) {
      d->perm[k] = d->grid->index[k];
      d->old_to_new[d->perm[k]] = k;
    }
    TL_CHECK(tl_particles_permute(P, d->perm));
    TL_CHECK(remap_everything(d, d->old_to_new, n));
    /* the grid follows: particle k of the new order is grid entry k */
    TlHGrid *g = d->grid;
    int32_t *c = (int32_t *)d->tf; /* not used as forces here; reuse safely below */
    (void)c;
    TL_CHECK(tl_array_reserve(&d->scratch, &d->scratch_cap, 4 * n + 4, sizeof *d->scratch));
    TlVec3 *red = (TlVec3 *)d->scratch;
    for (size_t k = 0; k < n; ++k) red[k] = g->reduced[d->perm[k]];
    memcpy(g->reduced, red, n * sizeof *red);
    int32_t *cells = (int32_t *)d->scratch;
    for (size_t k = 0; k < n; ++k) cells[k] = g->cell_of[d->perm[k]];
    memcpy(g->cell_of, cells, n * sizeof *cells);
    uint8_t *lv = (uint8_t *)d->scratch;
    for (size_t k = 0; k < n; ++k) lv[k] = g->level_of[d->perm[k]];
    memcpy(g->level_of, lv, n);
    for (size_t k = 0; k < n; ++k) g->index[k] = k;
  }
  if (d->bonds.n == (size_t)-1) TL_CHECK(build_bonds(d));
  /* skip pairs of two non-free particles */
  const uint8_t *skip = NULL;
  if (d->skip_fixed) {
    TL_CHECK(tl_array_reserve(&d->skip, &d->skip_cap, n + 1, 1));
    for (size_t i = 0; i < n; ++i) d->skip[i] = P->motion[i] != TL_MOTION_FREE;
    skip = d->skip;
  }
  TL_CHECK(tl_hgrid_pairs(d->grid, P->x, P->radius, skip, &d->pairs, &d->pairs_cap, &d->n_pairs));
  /* new list, grouped by law, history carried over from the old one */
  TlContactList tmp = d->old;
  d->old = d->list;
  d->list = tmp;
  TlContactList *L = &d->list;
  L->history_doubles = d->hd;
  TL_CHECK(tl_contact_list_reserve(L, d->n_pairs));
  L->n = 0;
  int have_bonds = d->bonds.n > 0;
  size_t counts[TL_DEM_MAX_LAWS + 1] = {0};
  int multi = d->n_laws > 1;
  if (multi)
    for (size_t k = 0; k < d->n_pairs; ++k)
      counts[law_of(d, P->species[d->pairs[k].i], P->species[d->pairs[k].j]) + 1]++;
  for (int l = 0; l < TL_DEM_MAX_LAWS; ++l) counts[l + 1] += counts[l];
  size_t kept = 0;
  for (size_t k = 0; k < d->n_pairs; ++k) {
    TlPair pr = d->pairs[k];
    if (have_bonds && tl_contact_list_find(&d->bonds, pr.i, pr.j) != SIZE_MAX) continue;
    int law = multi ? law_of(d, P->species[pr.i], P->species[pr.j]) : 0;
    size_t m = multi ? counts[law]++ : kept;
    L->i[m] = pr.i;
    L->j[m] = pr.j;
    L->law[m] = (uint8_t)law;
    L->touching[m] = 0;
    L->force[m] = tl_v3(0, 0, 0);
    if (d->hd) memset(L->history + m * d->hd, 0, d->hd * sizeof *L->history);
    ++kept;
  }
  if (multi && have_bonds) {
    /* bonds removed some pairs: compact the law groups */
    size_t m = 0;
    size_t start[TL_DEM_MAX_LAWS + 1] = {0};
    for (size_t k = 0; k < d->n_pairs; ++k)
      start[law_of(d, P->species[d->pairs[k].i], P->species[d->pairs[k].j]) + 1]++;
    for (int l = 0; l < TL_DEM_MAX_LAWS; ++l) start[l + 1] += start[l];
    for (int l = 0; l < d->n_laws; ++l)
      for (size_t k = start[l]; k < counts[l]; ++k, ++m)
        if (m != k) {
          L->i[m] = L->i[k]; L->j[m] = L->j[k]; L->law[m] = L->law[k];
          L->touching[m] = 0; L->force[m] = tl_v3(0, 0, 0);
          if (d->hd) memset(L->history + m * d->hd, 0, d->hd * sizeof *L->history);
        }
    kept = m;
  }
  L->n = kept;
  if (d->old.n && d->old.n != (size_t)-1) {
    TL_CHECK(tl_contact_list_index(&d->old, 1));
    tl_contact_list_transfer(L, &d->old);
  }
  TL_CHECK(make_chunks(L, &d->chunks, &d->chunks_cap, &d->n_chunks));
  /* build positions for the displacement criterion */
  if (n > d->x_build_cap) {
    TL_CHECK(tl_realloc(&d->x_build, n + n / 2 + 16, sizeof *d->x_build));
    d->x_build_cap = n + n / 2 + 16;
  }
  memcpy(d->x_build, P->x, n * sizeof *P->x);
  d->h_build_inv = d->domain.h_inv;
  d->rebuilds++;
  d->need_rebuild = 0;
  return TL_OK;
}

/* Largest centre displacement since the last build, the affine part of a
 * deforming cell removed, and the strain measure ||h h_build⁻¹ - I||. */
static int needs_rebuild(TlDem *d)
{
  if (d->need_rebuild || d->skin <= 0.0) return 1;
  const TlParticles *P = d->P;
  double max2 = 0.0;
  double strain = 0.0;
  if (d->domain.deforming) {
    TlMat3 A = tl_m3_mul(d->domain.h, d->h_build_inv);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double e = A.m[i][j] - (i == j);
        strain += e * e;
      }
    strain = sqrt(strain);
    TlVec3 o = d->domain.origin;
    for (size_t i = 0; i < P->n; ++i) {
      TlVec3 xa = tl_v3_add(o, tl_m3_mulv(A, tl_v3_sub(d->x_build[i], o)));
      double m = tl_v3_norm2(tl_v3_sub(P->x[i], xa));
      if (m > max2) max2 = m;
    }
  } else {
    /* free particles: measured during the drift; prescribed ones here */
    max2 = d->disp2max;
    for (size_t g = 0; g < d->n_presc; ++g)
      for (size_t k = 0; k < d->presc[g].n; ++k) {
        size_t i = d->presc[g].idx[k];
        double m = tl_v3_norm2(tl_v3_sub(P->x[i], d->x_build[i]));
        if (m > max2) max2 = m;
      }
  }
  return 2.0 * sqrt(max2) + strain * d->max_cut > d->skin;
}

/* ------------------------------------------------------------- forces */

typedef struct {
  double elastic, power;
  size_t touching;
} Accum;

/* What one chunk of contacts needs; filled once per list evaluation. */
typedef struct {
  TlDem *d;
  TlContactList *L;
  const TlVec3 *x, *v, *w;
  const double *radius, *inv_mass, *mass;
  const double (*xr)[4];
  const double *cw; /* per-contact weights, NULL: unweighted */
  TlVec3 *F, *T;
  double len[3], half[3];
  int bonded, want_energy;
  size_t hd;
  double el, pw;
  size_t touching;
  TlStatus status;
} ChunkCtx;

/* The nearest periodic image of a branch vector in an orthogonal box. */
static inline void minimum_image_ortho(const ChunkCtx *c, TlVec3 *b)
{
  double *bc = &b->x;
  for (int q = 0; q < 3; ++q) {
    if (c->len[q] <= 0.0) continue;
    if (bc[q] > c->half[q]) bc[q] -= c->len[q];
    else if (bc[q] < -c->half[q]) bc[q] += c->len[q];
  }
}

/* A pair that has separated: its force and history start again from zero. */
static inline void release_contact(TlContactList *L, size_t k, size_t hd)
{
  if (!L->touching[k]) return;
  L->touching[k] = 0;
  L->force[k] = tl_v3(0, 0, 0);
  if (hd) memset(L->history + k * hd, 0, hd * sizeof(double));
}

/* The contact loop of one chunk, specialised at compile time on the domain
 * kind (ORTHO: orthogonal periodic box; GENERAL: sheared or deforming cell)
 * and on rotation, so the common cases carry no dead branches. */
static inline __attribute__((always_inline)) void process_chunk(ChunkCtx *c, Chunk ch, const int ORTHO,
                                                                const int GENERAL, const int ROT, const int WEIGHTED)
{
  TlDem *d = c->d;
  TlContactList *L = c->L;
  const TlVec3 *x = c->x, *v = c->v, *w = c->w;
  const double *radius = c->radius;
  const TlDomain *dom = &d->domain;
  const size_t hd = c->hd;
  const int bonded = c->bonded;
  TlContactGeometry g[CHUNK];
  TlContactResult r[CHUNK];
  uint32_t idx[CHUNK];
  size_t m = 0;
  for (size_t k = ch.start; k < ch.end; ++k) {
    const uint32_t i = L->i[k], j = L->j[k];
    TlVec3 b;
    if (GENERAL) {
      b = tl_domain_branch(dom, x[i], x[j]);
    } else {
      b.x = x[j].x - x[i].x;
      b.y = x[j].y - x[i].y;
      b.z = x[j].z - x[i].z;
      if (ORTHO) minimum_image_ortho(c, &b);
    }
    const double ri = radius[i], rj = radius[j], cut = ri + rj;
    const double r2 = b.x * b.x + b.y * b.y + b.z * b.z;
    if (r2 >= cut * cut && !bonded) {
      release_contact(L, k, hd);
      continue;
    }
    const double dist = sqrt(r2);
    TlContactGeometry *G = &g[m];
    const double inv = dist > 0.0 ? 1.0 / dist : 0.0;
    G->normal = dist > 0.0 ? tl_v3_scale(b, inv) : tl_v3(1, 0, 0);
    G->overlap = cut - dist;
    G->branch_i = tl_v3_scale(G->normal, ri - 0.5 * G->overlap);
    G->branch_j = tl_v3_scale(G->normal, -(rj - 0.5 * G->overlap));
    TlVec3 vr = tl_v3_sub(v[j], v[i]);
    if (GENERAL && dom->deforming) vr = tl_v3_add(vr, tl_m3_mulv(dom->L, b));
    if (ROT) {
      const TlVec3 wi = w[i], wj = w[j];
      vr = tl_v3_add(vr, tl_v3_sub(tl_v3_cross(wj, G->branch_j), tl_v3_cross(wi, G->branch_i)));
      G->spin_mean = tl_v3_scale(tl_v3_add(wi, wj), 0.5);
      G->spin_rel = tl_v3_sub(wj, wi);
    } else {
      G->spin_mean = G->spin_rel = tl_v3(0, 0, 0);
    }
    G->vrel = vr;
    const double isum = c->inv_mass[i] + c->inv_mass[j];
    G->meff = isum > 0.0 ? 1.0 / isum : 0.5 * (c->mass[i] + c->mass[j]);
    G->reff = ri * rj / cut;
    G->history = hd ? L->history + k * hd : NULL;
    G->bonded = bonded;
    idx[m++] = (uint32_t)k;
  }
  if (!m) return;
  const TlContactLaw *law = d->laws[ch.law];
  TlContactBatch batch = {m, g, r, d->dt, c->want_energy};
  TlStatus s = law->ops->evaluate(law, &batch);
  if (s != TL_OK) c->status = s;
  TlVec3 *F = c->F, *T = c->T;
  for (size_t q = 0; q < m; ++q) {
    const size_t k = idx[q];
    const uint32_t i = L->i[k], j = L->j[k];
    const TlVec3 f = r[q].force;
    /* a weighted contact (seeds/001 Eq. 24) acts with w_ab f on both
     * particles and stores w_ab of its energy; its history is the law's */
    const double wk = WEIGHTED ? c->cw[k] : 1.0;
    if (c->want_energy) {
      /* work of the contact over the step by the trapezoidal rule on the
       * relative displacement dt vrel (vrel is the half-step velocity), so
       * the dissipation booked is second-order accurate */
      const TlVec3 fo = L->touching[k] ? L->force[k] : tl_v3(0, 0, 0);
      double e = r[q].elastic_energy, p = 0.5 * (tl_v3_dot(tl_v3_add(fo, f), g[q].vrel)) + tl_v3_dot(r[q].couple, g[q].spin_rel);
      c->el += WEIGHTED ? wk * e : e;
      c->pw += WEIGHTED ? wk * p : p;
    }
    L->force[k] = f;
    L->touching[k] = 1;
    const TlVec3 fs = WEIGHTED ? tl_v3_scale(f, wk) : f;
    const TlVec3 cs = WEIGHTED ? tl_v3_scale(r[q].couple, wk) : r[q].couple;
    F[i] = tl_v3_add(F[i], fs);
    F[j] = tl_v3_sub(F[j], fs);
    if (ROT) {
      T[i] = tl_v3_add(T[i], tl_v3_add(tl_v3_cross(g[q].branch_i, fs), cs));
      T[j] = tl_v3_sub(T[j], tl_v3_add(tl_v3_cross(g[q].branch_j, fs), cs));
    }
  }
  c->touching += m;
}

/* The same loop for the built-in laws (LAW 1 linear, 2 Hertz), with the law
 * evaluated in place: no staging of the geometry, forces scattered at once.
 * Same arithmetic as the batch ops (tl_contact_kernels.h). */
static inline __attribute__((always_inline)) void process_chunk_fused(ChunkCtx *c, Chunk ch, const int ORTHO,
                                                                      const int GENERAL, const int ROT, const int LAW,
                                                                      const int WEIGHTED)
{
  TlDem *d = c->d;
  TlContactList *L = c->L;
  const TlVec3 *x = c->x, *v = c->v, *w = c->w;
  const double *radius = c->radius, *inv_mass = c->inv_mass;
  const TlDomain *dom = &d->domain;
  const size_t hd = c->hd;
  const int bonded = c->bonded, want = c->want_energy;
  const TlStdLaw *law = (const TlStdLaw *)d->laws[ch.law];
  const double dt = d->dt;
  TlVec3 *F = c->F, *T = c->T;
  const double(*xr)[4] = c->xr;
  for (size_t k = ch.start; k < ch.end; ++k) {
    const uint32_t i = L->i[k], j = L->j[k];
    TlVec3 b;
    double ri, rj;
    if (GENERAL) {
      b = tl_domain_branch(dom, x[i], x[j]);
      ri = radius[i];
      rj = radius[j];
    } else {
      b.x = xr[j][0] - xr[i][0];
      b.y = xr[j][1] - xr[i][1];
      b.z = xr[j][2] - xr[i][2];
      ri = xr[i][3];
      rj = xr[j][3];
      if (ORTHO) minimum_image_ortho(c, &b);
    }
    const double cut = ri + rj;
    const double r2 = b.x * b.x + b.y * b.y + b.z * b.z;
    if (r2 >= cut * cut && !bonded) {
      release_contact(L, k, hd);
      continue;
    }
    const double dist = sqrt(r2);
    const double inv = dist > 0.0 ? 1.0 / dist : 0.0;
    const TlVec3 n = dist > 0.0 ? tl_v3_scale(b, inv) : tl_v3(1, 0, 0);
    const double delta = cut - dist;
    const double li = ri - 0.5 * delta, lj = rj - 0.5 * delta; /* lever arms along ±n */
    TlVec3 vr = {v[j].x - v[i].x, v[j].y - v[i].y, v[j].z - v[i].z};
    if (GENERAL && dom->deforming) vr = tl_v3_add(vr, tl_m3_mulv(dom->L, b));
    TlVec3 spin_mean = {0, 0, 0}, spin_rel = {0, 0, 0};
    if (ROT) {
      const TlVec3 wi = w[i], wj = w[j];
      /* ω_j × (-lj n) - ω_i × (li n) = -(lj ω_j + li ω_i) × n */
      TlVec3 s = {lj * wj.x + li * wi.x, lj * wj.y + li * wi.y, lj * wj.z + li * wi.z};
      vr = tl_v3_sub(vr, tl_v3_cross(s, n));
      spin_mean = tl_v3_scale(tl_v3_add(wi, wj), 0.5);
      spin_rel = tl_v3_sub(wj, wi);
    }
    const double isum = inv_mass[i] + inv_mass[j];
    const double meff = isum > 0.0 ? 1.0 / isum : 0.5 * (c->mass[i] + c->mass[j]);
    const double reff = ri * rj / cut;
    double *hist = hd ? L->history + k * hd : NULL;
    TlVec3 f, cpl;
    double e = 0.0;
    int on = LAW == 1 ? tl_linear_contact(law, n, delta, vr, spin_mean, spin_rel, meff, reff, hist, bonded, dt, want,
                                          &f, &cpl, &e)
                      : tl_hertz_contact(law, n, delta, vr, spin_mean, spin_rel, meff, reff, hist, dt, want, &f,
                                         &cpl, &e);
    if (!on) {
      if (L->touching[k]) {
        L->touching[k] = 0;
        L->force[k] = tl_v3(0, 0, 0);
      }
      continue;
    }
    const double wk = WEIGHTED ? c->cw[k] : 1.0;
    if (want) {
      const TlVec3 fo = L->touching[k] ? L->force[k] : tl_v3(0, 0, 0);
      const double p = 0.5 * tl_v3_dot(tl_v3_add(fo, f), vr) + tl_v3_dot(cpl, spin_rel);
      c->el += WEIGHTED ? wk * e : e;
      c->pw += WEIGHTED ? wk * p : p;
    }
    L->force[k] = f;
    L->touching[k] = 1;
    if (WEIGHTED) {
      f = tl_v3_scale(f, wk);
      cpl = tl_v3_scale(cpl, wk);
    }
    F[i].x += f.x; F[i].y += f.y; F[i].z += f.z;
    F[j].x -= f.x; F[j].y -= f.y; F[j].z -= f.z;
    if (ROT) {
      /* branch_i = li n, branch_j = -lj n */
      const TlVec3 nf = tl_v3_cross(n, f);
      T[i].x += li * nf.x + cpl.x; T[i].y += li * nf.y + cpl.y; T[i].z += li * nf.z + cpl.z;
      T[j].x += lj * nf.x - cpl.x; T[j].y += lj * nf.y - cpl.y; T[j].z += lj * nf.z - cpl.z;
    }
    c->touching++;
  }
}

#define TL_DISPATCH_CHUNKS(FN, ...)                                                  \
  do {                                                                               \
    if (general) {                                                                   \
      if (rot) for (size_t k = lo; k < hi; ++k) FN(c, chunks[k], 0, 1, 1 __VA_ARGS__); \
      else for (size_t k = lo; k < hi; ++k) FN(c, chunks[k], 0, 1, 0 __VA_ARGS__);    \
    } else if (ortho) {                                                              \
      if (rot) for (size_t k = lo; k < hi; ++k) FN(c, chunks[k], 1, 0, 1 __VA_ARGS__); \
      else for (size_t k = lo; k < hi; ++k) FN(c, chunks[k], 1, 0, 0 __VA_ARGS__);    \
    } else {                                                                         \
      if (rot) for (size_t k = lo; k < hi; ++k) FN(c, chunks[k], 0, 0, 1 __VA_ARGS__); \
      else for (size_t k = lo; k < hi; ++k) FN(c, chunks[k], 0, 0, 0 __VA_ARGS__);    \
    }                                                                                \
  } while (0)

/* Compiled twice: for x86-64 with AVX2 and FMA (three-operand forms and
 * fused multiply-adds shorten this register-hungry loop by a third) and for
 * the baseline; the loader picks the one the processor runs. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define TL_HOT_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define TL_HOT_CLONES
#endif

/* The contact loop of a range of chunks.  One law for the whole range (the
 * common case) runs the fused loop of the built-in laws; anything else goes
 * through the batch ops.  It is compiled twice: unweighted (the plain
 * world's loop, its code untouched by the weights) and with per-contact
 * weights (a volume coupling's overlap), both for the same processors so
 * that weights of 1 give the same arithmetic. */
#define TL_DEFINE_PROCESS_RANGE(name, weighted)                                                              \
  TL_HOT_CLONES static void name(ChunkCtx *c, const Chunk *chunks, size_t lo, size_t hi)                     \
  {                                                                                                          \
    const TlDomain *dom = &c->d->domain;                                                                     \
    const int general = dom->any_periodic && (dom->kind != TL_DOMAIN_PERIODIC_BOX || dom->deforming);       \
    const int ortho = dom->any_periodic && !general;                                                         \
    const int rot = c->w != NULL;                                                                            \
    int uniform = 1;                                                                                         \
    for (size_t k = lo + 1; k < hi && uniform; ++k) uniform = chunks[k].law == chunks[lo].law;               \
    const TlContactLawOps *ops = lo < hi ? c->d->laws[chunks[lo].law]->ops : NULL;                          \
    if (uniform && ops == &tl_contact_linear_ops) {                                                          \
      TL_DISPATCH_CHUNKS(process_chunk_fused, , 1, weighted);                                                \
    } else if (uniform && ops == &tl_contact_hertz_ops) {                                                    \
      TL_DISPATCH_CHUNKS(process_chunk_fused, , 2, weighted);                                                \
    } else {                                                                                                 \
      TL_DISPATCH_CHUNKS(process_chunk, , weighted);                                                         \
    }                                                                                                        \
  }
TL_DEFINE_PROCESS_RANGE(process_range, 0)
TL_DEFINE_PROCESS_RANGE(process_range_weighted, 1)

static TlStatus evaluate_list(TlDem *d, TlContactList *L, const Chunk *chunks, size_t n_chunks, int bonded,
                              int want_energy, const double *cw, Accum *acc)
{
  TlParticles *P = d->P;
  const size_t n = P->n;
  const int rot = P->w != NULL;
  const int nt = d->nt_now;
  const TlDomain *dom = &d->domain;
  double el = 0.0, pw = 0.0;
  size_t touching = 0;
  TlStatus status = TL_OK;
  TL_PARALLEL_IF(nt > 1, "omp parallel num_threads(nt) reduction(+ : el, pw, touching)", {
    int tid = nt > 1 ? omp_get_thread_num() : 0;
    ChunkCtx c;
    memset(&c, 0, sizeof c);
    c.d = d;
    c.L = L;
    c.x = P->x;
    c.v = P->v;
    c.w = rot ? P->w : NULL;
    c.radius = P->radius;
    c.xr = (const double(*)[4])d->xr;
    c.cw = cw;
    c.inv_mass = P->inv_mass;
    c.mass = P->mass;
    c.F = nt > 1 ? d->tf + (size_t)tid * n : P->f;
    c.T = nt > 1 ? (rot ? d->tt + (size_t)tid * n : NULL) : P->torque;
    for (int q = 0; q < 3; ++q) {
      c.len[q] = dom->periodic[q] ? dom->h.m[q][q] : 0.0;
      c.half[q] = 0.5 * c.len[q];
    }
    c.bonded = bonded;
    c.want_energy = want_energy;
    c.hd = L->history_doubles;
    /* static contiguous ranges: each thread walks its own part of the list */
    size_t lo = n_chunks * (size_t)tid / (size_t)nt, hi = n_chunks * (size_t)(tid + 1) / (size_t)nt;
    if (cw) process_range_weighted(&c, chunks, lo, hi);
    else process_range(&c, chunks, lo, hi);
    el += c.el;
    pw += c.pw;
    touching += c.touching;
    if (c.status != TL_OK) {
      _Pragma("omp critical")
      status = c.status;
    }
  });
  if (status != TL_OK) return tl_error_trace(status, __FILE__, __LINE__);
  acc->elastic += el;
  acc->power += pw;
  acc->touching += touching;
  return TL_OK;
}

/* 1 / (w m) and 1 / (w I) from the particle weights (also after particles
 * came or went between evaluations; capacity kept, so the arrays stay put
 * within a step). */
static TlStatus weighted_inverses(TlDem *d)
{
  TlParticles *P = d->P;
  const size_t n = P->n;
  TL_CHECK(tl_particles_enable_weights(P));
  TL_CHECK(tl_array_reserve(&d->im_w, &d->im_w_cap, P->capacity ? P->capacity : 1, sizeof *d->im_w));
  for (size_t i = 0; i < n; ++i) d->im_w[i] = P->inv_mass[i] / P->weight[i];
  if (P->inv_inertia) {
    TL_CHECK(tl_array_reserve(&d->ii_w, &d->ii_w_cap, P->capacity ? P->capacity : 1, sizeof *d->ii_w));
    for (size_t i = 0; i < n; ++i) d->ii_w[i] = P->inv_inertia[i] / P->weight[i];
  }
  return TL_OK;
}

/* Weights at the particle centres (seeds/001 Eq. 25) and 1 / (w m) for
 * the kicks. */
static TlStatus particle_weights(TlDem *d)
{
  TlParticles *P = d->P;
  const size_t n = P->n;
  TL_CHECK(tl_particles_enable_weights(P));
  TL_CHECK(d->weight_fn(d->weight_ctx, n, P->x, P->weight));
  for (size_t i = 0; i < n; ++i) {
    double w = P->weight[i];
    if (!(w > 0.0) || !isfinite(w))
      TL_ERROR(TL_ERR_NUMERIC, "step %ld: particle id %lld at (%g, %g, %g) has weight %g; a weighted particle "
               "needs 0 < w (it has left the particle side of the overlap)", d->steps, (long long)P->id[i],
               P->x[i].x, P->x[i].y, P->x[i].z, w);
  }
  return weighted_inverses(d);
}

/* Weights of the contacts of a list at their contact points (seeds/001
 * Eq. 24): x_i + n (r_i - delta/2), on the line of centres. */
static TlStatus contact_weights(TlDem *d, const TlContactList *L, double **cw, size_t *cap)
{
  const TlParticles *P = d->P;
  const size_t n = L->n;
  TL_CHECK(tl_array_reserve(cw, cap, n ? n : 1, sizeof **cw));
  TL_CHECK(tl_array_reserve(&d->cpoint, &d->cpoint_cap, n ? n : 1, sizeof *d->cpoint));
  for (size_t k = 0; k < n; ++k) {
    const uint32_t i = L->i[k], j = L->j[k];
    TlVec3 b = d->domain.any_periodic ? tl_domain_branch(&d->domain, P->x[i], P->x[j]) : tl_v3_sub(P->x[j], P->x[i]);
    double dist = tl_v3_norm(b), ri = P->radius[i];
    double li = ri - 0.5 * (ri + P->radius[j] - dist);
    d->cpoint[k] = dist > 0.0 ? tl_v3_axpy(P->x[i], li / dist, b) : P->x[i];
  }
  TL_CHECK(d->weight_fn(d->weight_ctx, n, d->cpoint, *cw));
  for (size_t k = 0; k < n; ++k)
    if (!((*cw)[k] >= 0.0) || !isfinite((*cw)[k]))
      TL_ERROR(TL_ERR_NUMERIC, "step %ld: contact of particles id %lld and id %lld at (%g, %g, %g) has weight %g; "
               "weights must be finite and >= 0", d->steps, (long long)P->id[L->i[k]], (long long)P->id[L->j[k]],
               d->cpoint[k].x, d->cpoint[k].y, d->cpoint[k].z, (*cw)[k]);
  return TL_OK;
}

static TlStatus compute_forces(TlDem *d)
{
  TlParticles *P = d->P;
  const size_t n = P->n;
  const int rot = P->w != NULL;
  const int want = d->track_energy;
  /* body forces, and the packed positions of this evaluation */
  const TlVec3 g = d->gravity;
  const int ntb = n >= 8192 ? d->nt : 1;
  if (n > d->xr_cap) {
    TL_CHECK(tl_realloc(&d->xr, n + n / 2 + 16, sizeof *d->xr));
    d->xr_cap = n + n / 2 + 16;
  }
  double(*xr)[4] = d->xr;
  TL_PARALLEL_IF(ntb > 1, "omp parallel for num_threads(ntb) schedule(static)",
    for (size_t i = 0; i < n; ++i) {
      P->f[i] = tl_v3_scale(g, P->mass[i]);
      xr[i][0] = P->x[i].x;
      xr[i][1] = P->x[i].y;
      xr[i][2] = P->x[i].z;
      xr[i][3] = P->radius[i];
    });
  if (P->f_ext)
    for (size_t i = 0; i < n; ++i) P->f[i] = tl_v3_add(P->f[i], P->f_ext[i]);
  /* weighted equations (seeds/001 Eq. 25): w_a (m_a g + f_ext) */
  const int weighted = d->weight_fn != NULL;
  if (weighted) {
    if (d->n_walls)
      TL_ERROR(TL_ERR_UNSUPPORTED, "a weighted world (tl_dem_set_weight_field) with %zu walls: wall contacts are not "
               "weighted; remove the walls or the weight field", d->n_walls);
    TL_CHECK(particle_weights(d));
    for (size_t i = 0; i < n; ++i) P->f[i] = tl_v3_scale(P->f[i], P->weight[i]);
  }
  if (P->f_coupling)
    for (size_t i = 0; i < n; ++i) P->f[i] = tl_v3_add(P->f[i], P->f_coupling[i]);
  if (rot) memset(P->torque, 0, n * sizeof *P->torque);
  /* threads only pay for themselves on large contact lists */
  d->nt_now = d->list.n + (d->bonds.n == (size_t)-1 ? 0 : d->bonds.n) >= 8192 ? d->nt : 1;
  if (d->nt_now > 1) {
    const int nt = d->nt_now;
    size_t need = (size_t)nt * n;
    if (need > d->t_cap) {
      TL_CHECK(tl_realloc(&d->tf, need, sizeof *d->tf));
      /* per-thread torques only when something rotates (the rotation
       * state is fixed at setup) */
      if (rot) TL_CHECK(tl_realloc(&d->tt, need, sizeof *d->tt));
      d->t_cap = need;
    }
    TlVec3 *tf = d->tf, *tt = d->tt;
#pragma omp parallel for num_threads(nt) schedule(static)
    for (size_t i = 0; i < n; ++i)
      for (int t = 0; t < nt; ++t) {
        tf[(size_t)t * n + i] = tl_v3(0, 0, 0);
        if (rot) tt[(size_t)t * n + i] = tl_v3(0, 0, 0);
      }
  }
  Accum acc = {0, 0, 0};
  const int has_bonds = d->bonds.n && d->bonds.n != (size_t)-1;
  if (weighted) {
    TL_CHECK(contact_weights(d, &d->list, &d->cw_list, &d->cw_list_cap));
    if (has_bonds) TL_CHECK(contact_weights(d, &d->bonds, &d->cw_bonds, &d->cw_bonds_cap));
  }
  TL_CHECK(evaluate_list(d, &d->list, d->chunks, d->n_chunks, 0, want, weighted ? d->cw_list : NULL, &acc));
  if (has_bonds)
    TL_CHECK(evaluate_list(d, &d->bonds, d->bond_chunks, d->n_bond_chunks, 1, want, weighted ? d->cw_bonds : NULL,
                           &acc));
  if (d->nt_now > 1) {
    const int nt = d->nt_now;
#pragma omp parallel for num_threads(nt) schedule(static)
    for (size_t i = 0; i < n; ++i) {
      TlVec3 s = P->f[i];
      for (int t = 0; t < nt; ++t) s = tl_v3_add(s, d->tf[(size_t)t * n + i]);
      P->f[i] = s;
      if (rot) {
        TlVec3 q = P->torque[i];
        for (int t = 0; t < nt; ++t) q = tl_v3_add(q, d->tt[(size_t)t * n + i]);
        P->torque[i] = q;
      }
    }
  }
  d->n_touching = acc.touching;
  if (want) {
    d->elastic_pp = acc.elastic;
    d->contact_work_pp += d->dt * acc.power;
  }
  /* walls */
  for (size_t w = 0; w < d->n_walls; ++w) {
    TlWall *W = d->walls[w];
    TlWallStep st = {P, d->grid, &d->domain, d->laws[W->law], d->t, d->dt, want};
    TL_CHECK(W->ops->interact(W, &st));
  }
  return TL_OK;
}

TlStatus tl_dem_compute_forces(TlDem *d)
{
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "tl_dem_setup must precede force computation");
  if (needs_rebuild(d)) TL_CHECK(rebuild(d));
  double dt = d->dt;
  int track = d->track_energy;
  /* a pure evaluation must not book work */
  double cw = d->contact_work_pp;
  TL_CHECK(compute_forces(d));
  d->contact_work_pp = cw;
  (void)dt;
  (void)track;
  return TL_OK;
}

/* --------------------------------------------------------------- setup */

TlStatus tl_dem_setup(TlDem *d)
{
  TlParticles *P = d->P;
  if (d->n_laws == 0) TL_ERROR(TL_ERR_STATE, "the scene has no contact law; add one with tl_dem_add_law");
  if (!(d->dt > 0.0)) TL_ERROR(TL_ERR_STATE, "no time step set; call tl_dem_set_timestep");
  for (size_t s = 0; s < P->n_species; ++s)
    if (!(P->species_table[s].density > 0.0))
      TL_ERROR(TL_ERR_ARG, "species %zu has density %g; it must be positive", s, P->species_table[s].density);
  size_t hd = 0;
  int rot = 0;
  for (int l = 0; l < d->n_laws; ++l) {
    if (d->laws[l]->history_doubles > hd) hd = d->laws[l]->history_doubles;
    rot |= d->laws[l]->needs_rotation;
  }
  d->hd = hd;
  TL_CHECK(tl_contact_list_init(&d->list, hd));
  TL_CHECK(tl_contact_list_init(&d->old, hd));
  TL_CHECK(tl_contact_list_init(&d->bonds, hd));
  if (d->n_bond_ids) d->bonds.n = (size_t)-1;
  if (rot) TL_CHECK(tl_particles_enable_rotation(P));
  d->rotation = rot;
  d->nt = d->threads > 0 ? d->threads : omp_get_max_threads();
  if (d->nt < 1) d->nt = 1;
  TL_CHECK(build_law_table(d));
  /* skin from the mean diameter */
  double mean = 0.0;
  for (size_t i = 0; i < P->n; ++i) {
    if (!(P->radius[i] > 0.0)) TL_ERROR(TL_ERR_ARG, "particle %zu has radius %g; it must be positive", i, P->radius[i]);
    if (!tl_v3_isfinite(P->x[i]) || !tl_v3_isfinite(P->v[i]))
      TL_ERROR(TL_ERR_ARG, "particle %zu (id %lld) has a non-finite position or velocity", i, (long long)P->id[i]);
    mean += 2.0 * P->radius[i];
  }
  mean = P->n ? mean / (double)P->n : 1.0;
  d->skin = d->skin_factor * mean;
  double rmax;
  double m_min;
  d->r_min = min_radius(P, &rmax, &m_min);
  d->max_cut = 2.0 * rmax + d->skin;
  /* time step */
  double dtc, k, m;
  TL_CHECK(tl_dem_critical_timestep(d, &dtc, &k, &m));
  if (d->dt > dtc) {
    if (!d->allow_above)
      TL_ERROR(TL_ERR_UNSTABLE, "time step %g s exceeds the critical time step %g s (k_max = %g N/m, m_min = %g kg); "
               "reduce dt or set the override", d->dt, dtc, k, m);
    tl_warn("time step %g s is above the critical time step %g s (k_max = %g N/m, m_min = %g kg): override in force",
            d->dt, dtc, k, m);
  }
  d->setup_done = 1;
  d->need_rebuild = 1;
  TL_CHECK(rebuild(d));
  /* overlaps larger than a radius are a broken scene, not a stiff one */
  for (size_t q = 0; q < d->list.n; ++q) {
    uint32_t i = d->list.i[q], j = d->list.j[q];
    TlVec3 b = tl_domain_branch(&d->domain, P->x[i], P->x[j]);
    double ov = P->radius[i] + P->radius[j] - tl_v3_norm(b);
    double rs = fmin(P->radius[i], P->radius[j]);
    if (ov > rs)
      TL_ERROR(TL_ERR_ARG, "particles id %lld and id %lld overlap by %g, more than the smaller radius %g",
               (long long)P->id[i], (long long)P->id[j], ov, rs);
  }
  TL_CHECK(compute_forces(d));
  d->contact_work_pp = d->elastic_pp; /* stored energy at start counts as work done on contacts */
  for (size_t w = 0; w < d->n_walls; ++w) d->walls[w]->contact_work = d->walls[w]->elastic_energy;
  return TL_OK;
}

/* --------------------------------------------------------------- steps */

static TlStatus prescribe(TlDem *d, double t)
{
  TlParticles *P = d->P;
  for (size_t g = 0; g < d->n_presc; ++g) {
    Prescribed *p = &d->presc[g];
    TL_CHECK(p->eval(p->ctx, t, p->n, p->ids, p->x0, p->xs, p->vs));
    for (size_t k = 0; k < p->n; ++k) {
      if (!tl_v3_isfinite(p->xs[k]) || !tl_v3_isfinite(p->vs[k]))
        TL_ERROR(TL_ERR_NUMERIC, "prescribed motion of particle id %lld at t = %g gave x = (%g, %g, %g), v = (%g, %g, %g)",
                 (long long)p->ids[k], t, p->xs[k].x, p->xs[k].y, p->xs[k].z, p->vs[k].x, p->vs[k].y, p->vs[k].z);
      size_t i = p->idx[k];
      if (d->track_energy) {
        TlVec3 dx = tl_v3_sub(p->xs[k], P->x[i]);
        double mg = P->mass[i] * (d->weight_fn && P->weight ? P->weight[i] : 1.0);
        d->work_ext -= tl_v3_dot(P->f[i], dx) - tl_v3_dot(tl_v3_scale(d->gravity, mg), dx);
      }
      P->x[i] = p->xs[k];
      P->v[i] = p->vs[k];
    }
  }
  return TL_OK;
}

static TlStatus report_blowup(TlDem *d, double dt)
{
  TlParticles *P = d->P;
  for (size_t i = 0; i < P->n; ++i) {
    TlVec3 v = P->v[i];
    if (!tl_v3_isfinite(v) || !tl_v3_isfinite(P->x[i]))
      TL_ERROR(TL_ERR_UNSTABLE, "step %ld, t = %g: particle id %lld has a non-finite state (v = (%g, %g, %g), force (%g, %g, %g))",
               d->steps, d->t, (long long)P->id[i], v.x, v.y, v.z, P->f[i].x, P->f[i].y, P->f[i].z);
    if (P->motion[i] == TL_MOTION_FREE && !(tl_v3_norm(v) * dt < P->radius[i]))
      TL_ERROR(TL_ERR_UNSTABLE,
               "step %ld, t = %g: particle id %lld moved %g in one step, more than its radius %g (v = (%g, %g, %g)); "
               "the time step %g is too large for this scene or a force blew up",
               d->steps, d->t, (long long)P->id[i], tl_v3_norm(v) * dt, P->radius[i], v.x, v.y, v.z, dt);
  }
  return TL_OK;
}

static TlStatus one_step(TlDem *d)
{
  TlParticles *P = d->P;
  const size_t n = P->n;
  const double dt = d->dt, h = 0.5 * dt;
  const int rot = P->w != NULL;
  TlVec3 *restrict x = P->x, *restrict v = P->v;
  const TlVec3 *restrict f = P->f;
  /* a weighted world kicks with 1 / (w m) and 1 / (w I), refreshed by
   * every force evaluation in place (the same arrays all step long) */
  if (d->weight_fn) TL_CHECK(weighted_inverses(d));
  const double *restrict im = d->weight_fn ? d->im_w : P->inv_mass;
  const uint8_t *restrict motion = P->motion;
  /* first half kick and drift; the largest step and the largest distance
   * from the build positions are tracked in the same pass */
  TlMat3 A;
  TL_CHECK(tl_domain_advance(&d->domain, dt, &A));
  const int deforming = d->domain.deforming;
  const TlVec3 o = d->domain.origin;
  double v2max = 0.0, disp2max = 0.0;
  const TlVec3 *restrict xb = d->x_build;
  if (d->track_energy && (P->f_ext || P->f_coupling))
    for (size_t i = 0; i < n; ++i)
      if (motion[i] == TL_MOTION_FREE) {
        TlVec3 vv = tl_v3_axpy(v[i], h * im[i], f[i]);
        TlVec3 fe = tl_v3(0, 0, 0);
        if (P->f_ext) fe = d->weight_fn ? tl_v3_scale(P->f_ext[i], P->weight[i]) : P->f_ext[i];
        if (P->f_coupling) fe = tl_v3_add(fe, P->f_coupling[i]);
        d->work_ext += dt * tl_v3_dot(fe, vv);
      }
  const int nt = n >= 8192 ? d->nt : 1;
  TL_PARALLEL_IF(nt > 1, "omp parallel for num_threads(nt) schedule(static) reduction(max : v2max, disp2max)",
    for (size_t i = 0; i < n; ++i) {
      if (motion[i] != TL_MOTION_FREE) continue;
      const double hi = h * im[i];
      TlVec3 vv = {v[i].x + hi * f[i].x, v[i].y + hi * f[i].y, v[i].z + hi * f[i].z};
      v[i] = vv;
      double v2 = vv.x * vv.x + vv.y * vv.y + vv.z * vv.z;
      v2max = v2 > v2max ? v2 : v2max;
      if (deforming) {
        x[i] = tl_v3_axpy(tl_v3_add(o, tl_m3_mulv(A, tl_v3_sub(x[i], o))), dt, vv);
      } else {
        TlVec3 xn = {x[i].x + dt * vv.x, x[i].y + dt * vv.y, x[i].z + dt * vv.z};
        x[i] = xn;
        double dx = xn.x - xb[i].x, dy = xn.y - xb[i].y, dz = xn.z - xb[i].z;
        double d2 = dx * dx + dy * dy + dz * dz;
        disp2max = d2 > disp2max ? d2 : disp2max;
      }
    });
  d->disp2max = disp2max;
  if (!(v2max * dt * dt < d->r_min * d->r_min)) TL_CHECK(report_blowup(d, dt));
  if (rot) {
    TlVec3 *restrict w = P->w;
    const TlVec3 *restrict tq = P->torque;
    const double *restrict ii = d->weight_fn ? d->ii_w : P->inv_inertia;
    const int orient = d->orientation;
    TL_PARALLEL_IF(nt > 1, "omp parallel for num_threads(nt) schedule(static)",
      for (size_t i = 0; i < n; ++i) {
        if (motion[i] != TL_MOTION_FREE) continue;
        const double hi = h * ii[i];
        TlVec3 ww = {w[i].x + hi * tq[i].x, w[i].y + hi * tq[i].y, w[i].z + hi * tq[i].z};
        w[i] = ww;
        if (!orient) continue;
        /* seeds/001 Eq. 2: dq/dt = ½ (0, ω) ⊗ q, with the half-step spin,
         * then renormalised */
        TlQuat q = P->q[i];
        TlQuat dq = tl_q_mul((TlQuat){0.0, ww.x, ww.y, ww.z}, q);
        q.w += h * dq.w; q.x += h * dq.x; q.y += h * dq.y; q.z += h * dq.z;
        double nq = 1.0 / sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
        P->q[i] = (TlQuat){q.w * nq, q.x * nq, q.y * nq, q.z * nq};
      });
  }
  for (size_t w = 0; w < d->n_walls; ++w)
    if (d->walls[w]->ops->advance) TL_CHECK(d->walls[w]->ops->advance(d->walls[w], d->t, dt));
  d->t += dt;
  TL_CHECK(prescribe(d, d->t));
  if (needs_rebuild(d)) TL_CHECK(rebuild(d));
  if (d->hook) TL_CHECK(d->hook(d->hook_ctx, d));
  TL_CHECK(compute_forces(d));
  /* second half kick; a NaN anywhere poisons the sum and is then located */
  double sum = 0.0;
  TL_PARALLEL_IF(nt > 1, "omp parallel for num_threads(nt) schedule(static) reduction(+ : sum)",
    for (size_t i = 0; i < n; ++i) {
      const double hi = h * im[i]; /* 0 for fixed and prescribed particles */
      TlVec3 vv = {v[i].x + hi * f[i].x, v[i].y + hi * f[i].y, v[i].z + hi * f[i].z};
      v[i] = vv;
      sum += vv.x + vv.y + vv.z;
    });
  if (rot) {
    TlVec3 *restrict w = P->w;
    const TlVec3 *restrict tq = P->torque;
    const double *restrict ii = d->weight_fn ? d->ii_w : P->inv_inertia;
    TL_PARALLEL_IF(nt > 1, "omp parallel for num_threads(nt) schedule(static)",
      for (size_t i = 0; i < n; ++i) {
        const double hi = h * ii[i];
        w[i] = (TlVec3){w[i].x + hi * tq[i].x, w[i].y + hi * tq[i].y, w[i].z + hi * tq[i].z};
      });
  }
  if (!isfinite(sum)) TL_CHECK(report_blowup(d, dt));
  d->steps++;
  return TL_OK;
}

TlStatus tl_dem_step(TlDem *d, long n)
{
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "tl_dem_setup must precede tl_dem_step");
  for (long s = 0; s < n; ++s) TL_CHECK(one_step(d));
  return TL_OK;
}

/* ----------------------------------------------------- insert / remove */

TlStatus tl_dem_add_particle(TlDem *d, TlVec3 x, TlVec3 v, double radius, int species, size_t *index)
{
  TL_CHECK(tl_particles_add(d->P, x, v, radius, species, index));
  if (d->setup_done) {
    double r = radius;
    if (2.0 * r + d->skin > d->max_cut) d->max_cut = 2.0 * r + d->skin;
    if (r < d->r_min) d->r_min = r;
    size_t n = d->P->n;
    if (n > d->x_build_cap) {
      TL_CHECK(tl_realloc(&d->x_build, n + n / 2 + 16, sizeof *d->x_build));
      d->x_build_cap = n + n / 2 + 16;
    }
    d->x_build[n - 1] = x;
    TL_CHECK(build_law_table(d));
    d->need_rebuild = 1;
  }
  return TL_OK;
}

TlStatus tl_dem_remove_particle(TlDem *d, size_t index)
{
  TlParticles *P = d->P;
  if (index >= P->n) TL_ERROR(TL_ERR_ARG, "particle index %zu out of range (n = %zu)", index, P->n);
  size_t n = P->n, last = n - 1;
  for (size_t g = 0; g < d->n_presc; ++g)
    for (size_t k = 0; k < d->presc[g].n; ++k)
      if (d->presc[g].idx[k] == index)
        TL_ERROR(TL_ERR_STATE, "particle id %lld has a prescribed motion and cannot be removed", (long long)P->id[index]);
  for (size_t k = 0; k < d->n_bond_ids; ++k)
    if (d->bond_ids[k] == P->id[index])
      TL_ERROR(TL_ERR_STATE, "particle id %lld is bonded and cannot be removed", (long long)P->id[index]);
  if (n > d->perm_cap) {
    TL_CHECK(tl_realloc(&d->perm, n, sizeof *d->perm));
    TL_CHECK(tl_realloc(&d->old_to_new, n, sizeof *d->old_to_new));
    d->perm_cap = n;
  }
  for (size_t k = 0; k < n; ++k) d->old_to_new[k] = k;
  d->old_to_new[index] = SIZE_MAX;
  if (index != last) d->old_to_new[last] = index;
  TL_CHECK(tl_particles_remove(P, index));
  if (d->setup_done) {
    TL_CHECK(remap_everything(d, d->old_to_new, n));
    if (index != last && d->x_build) d->x_build[index] = d->x_build[last];
    d->need_rebuild = 1;
  }
  return TL_OK;
}

/* --------------------------------------------------------- diagnostics */

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
  double V = tl_domain_volume(&d->domain);
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

TlStatus tl_dem_visit_wall_contacts(TlDem *d, TlWallContactVisitor visit, void *ctx)
{
  const TlParticles *P = d->P;
  for (size_t k = 0; k < d->n_walls; ++k) {
    const TlWall *W = d->walls[k];
    if (tl_wall_is_trisurface(W)) {
      const TlTriContactSet *c = tl_wall_trisurface_contacts(W);
      for (size_t q = 0; c && q < c->count; ++q) {
        const TlTriContactRecord *r = &c->c[q];
        if (!r->active) continue;
        visit(ctx, k, (size_t)r->particle, r->force, r->point, r->center);
      }
    } else if (strcmp(W->ops->header.name, "plane") == 0) {
      TlVec3 point, normal;
      tl_wall_plane_get(W, &point, &normal);
      for (size_t i = 0; i < P->n; ++i) {
        TlVec3 f;
        if (!tl_wall_plane_contact_force(W, i, &f)) continue;
        double s = tl_v3_dot(tl_v3_sub(P->x[i], point), normal);
        visit(ctx, k, i, f, tl_v3_axpy(P->x[i], -s, normal), P->x[i]);
      }
    } else {
      TL_ERROR(TL_ERR_ARG, "wall %zu '%s' is of type '%s', whose contacts cannot be visited (plane and trisurface can)", k,
               W->name, W->ops->header.name);
    }
  }
  return TL_OK;
}

TlStatus tl_dem_register_all(void)
{
  TL_CHECK(tl_contact_register_all());
  TL_CHECK(tl_wall_register_plane());
  return TL_OK;
}

/* ---------------------------------------------------------- checkpoint */

static TlStatus save_list(const TlContactList *L, TlCheckpointWriter *w, const char *group)
{
  size_t n = L->n == (size_t)-1 ? 0 : L->n;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n", L->n == (size_t)-1 ? -1 : (int64_t)L->n));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "history_doubles", (int64_t)L->history_doubles));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "i", n * sizeof *L->i, L->i));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "j", n * sizeof *L->j, L->j));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "law", n, L->law));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "touching", n, L->touching));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "force", 3 * n, (const double *)L->force));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "history", n * L->history_doubles, L->history));
  return TL_OK;
}

static TlStatus load_list(TlContactList *L, TlCheckpointReader *r, const char *group, int n_laws)
{
  const char *path = tl_checkpoint_reader_path(r);
  int64_t n64 = 0, hd = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n", &n64));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "history_doubles", &hd));
  if (hd != (int64_t)L->history_doubles)
    TL_ERROR(TL_ERR_ARG, "%s: '%s' has %lld history doubles per contact; the laws of this scene keep %zu", path, group,
             (long long)hd, L->history_doubles);
  if (n64 < 0) {
    L->n = (size_t)-1; /* bonds still to be built from ids */
    return TL_OK;
  }
  if (n64 > (int64_t)UINT32_MAX) TL_ERROR(TL_ERR_ARG, "%s: '%s' holds %lld contacts (limit %u)", path, group, (long long)n64, UINT32_MAX);
  size_t n = (size_t)n64;
  TL_CHECK(tl_contact_list_reserve(L, n));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "i", n * sizeof *L->i, L->i));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "j", n * sizeof *L->j, L->j));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "law", n, L->law));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "touching", n, L->touching));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "force", 3 * n, (double *)L->force));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "history", n * L->history_doubles, L->history));
  for (size_t k = 0; k < n; ++k)
    if (L->law[k] >= n_laws)
      TL_ERROR(TL_ERR_ARG, "%s: '%s' contact %zu uses law %d; this scene has %d laws", path, group, k, L->law[k], n_laws);
  L->n = n;
  return TL_OK;
}

static TlStatus dem_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlDem *d = object;
  const TlParticles *P = d->P;
  const size_t n = P->n;
  char sub[512];
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "a DEM world is checkpointed after tl_dem_setup");
  /* run state */
  TL_CHECK(tl_checkpoint_write_double(w, group, "t", d->t));
  TL_CHECK(tl_checkpoint_write_double(w, group, "dt", d->dt));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "steps", d->steps));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "rebuilds", d->rebuilds));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "need_rebuild", d->need_rebuild));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_touching", (int64_t)d->n_touching));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_laws", d->n_laws));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "rotation", d->rotation));
  double scalars[8] = {d->skin, d->max_cut, d->r_min, d->disp2max, d->elastic_pp, d->contact_work_pp, d->work_ext, 0.0};
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "skin_cut_rmin_disp2_energy", 8, scalars));
  /* domain */
  const TlDomain *D = &d->domain;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "domain_kind", (int64_t)D->kind));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_origin", 3, &D->origin.x));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_h", 9, &D->h.m[0][0]));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_h_inv", 9, &D->h_inv.m[0][0]));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_h_dot", 9, &D->h_dot.m[0][0]));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "domain_L", 9, &D->L.m[0][0]));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "domain_deforming", D->deforming));
  /* particles */
  snprintf(sub, sizeof sub, "%s/particles", group ? group : "");
  TL_CHECK(tl_checkpoint_write_int64(w, sub, "n", (int64_t)n));
  TL_CHECK(tl_checkpoint_write_int64(w, sub, "next_id", P->next_id));
  TL_CHECK(tl_checkpoint_write_int64(w, sub, "n_species", (int64_t)P->n_species));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "x", 3 * n, (const double *)P->x));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "v", 3 * n, (const double *)P->v));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "f", 3 * n, (const double *)P->f));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "radius", n, P->radius));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "mass", n, P->mass));
  TL_CHECK(tl_checkpoint_write_doubles(w, sub, "inv_mass", n, P->inv_mass));
  TL_CHECK(tl_checkpoint_write_bytes(w, sub, "species", n * sizeof *P->species, P->species));
  TL_CHECK(tl_checkpoint_write_bytes(w, sub, "motion", n, P->motion));
  TL_CHECK(tl_checkpoint_write_int64s(w, sub, "id", n, P->id));
  if (P->q) {
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "q", 4 * n, (const double *)P->q));
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "w", 3 * n, (const double *)P->w));
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "torque", 3 * n, (const double *)P->torque));
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "inv_inertia", n, P->inv_inertia));
  }
  if (P->f_ext) TL_CHECK(tl_checkpoint_write_doubles(w, sub, "f_ext", 3 * n, (const double *)P->f_ext));
  if (P->f_coupling)
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "f_coupling", 3 * n, (const double *)P->f_coupling));
  if (P->weight) TL_CHECK(tl_checkpoint_write_doubles(w, sub, "weight", n, P->weight));
  /* neighbour list as it stands, and its build state */
  snprintf(sub, sizeof sub, "%s/contacts", group ? group : "");
  TL_CHECK(save_list(&d->list, w, sub));
  snprintf(sub, sizeof sub, "%s/bonds", group ? group : "");
  TL_CHECK(save_list(&d->bonds, w, sub));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "x_build", 3 * n, (const double *)d->x_build));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "h_build_inv", 9, &d->h_build_inv.m[0][0]));
  /* prescribed motions: current indices and attach positions */
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_prescribed", (int64_t)d->n_presc));
  for (size_t g = 0; g < d->n_presc; ++g) {
    const Prescribed *p = &d->presc[g];
    snprintf(sub, sizeof sub, "%s/prescribed_%zu", group ? group : "", g);
    TL_CHECK(tl_checkpoint_write_int64s(w, sub, "id", p->n, p->ids));
    TL_CHECK(tl_checkpoint_write_bytes(w, sub, "index", p->n * sizeof *p->idx, p->idx));
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "x0", 3 * p->n, (const double *)p->x0));
  }
  /* walls: their own state through the hooks, and the accounting */
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_walls", (int64_t)d->n_walls));
  for (size_t k = 0; k < d->n_walls; ++k) {
    const TlWall *W = d->walls[k];
    snprintf(sub, sizeof sub, "%s/wall_%zu", group ? group : "", k);
    TL_CHECK(tl_checkpoint_write_string(w, sub, "type", W->ops->header.name));
    double acc[9] = {W->elastic_energy, W->contact_work, W->work, W->force.x, W->force.y, W->force.z,
                     W->torque.x, W->torque.y, W->torque.z};
    TL_CHECK(tl_checkpoint_write_doubles(w, sub, "accounting", 9, acc));
    TL_CHECK(tl_checkpoint_write_int64(w, sub, "n_contacts", (int64_t)W->n_contacts));
    if (!W->ops->checkpoint_size || !W->ops->checkpoint_save)
      TL_ERROR(TL_ERR_STATE, "wall '%s' (%s) has no checkpoint hooks", W->name, W->ops->header.name);
    size_t bytes = W->ops->checkpoint_size(W);
    void *buffer = NULL;
    TL_CHECK(tl_calloc(&buffer, bytes ? bytes : 1, 1));
    TlStatus s = W->ops->checkpoint_save(W, buffer, bytes);
    if (s == TL_OK) s = tl_checkpoint_write_bytes(w, sub, "state", bytes, buffer);
    tl_free(&buffer);
    TL_CHECK(s);
  }
  return TL_OK;
}

static TlStatus dem_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlDem *d = object;
  TlParticles *P = d->P;
  const char *path = tl_checkpoint_reader_path(r);
  char sub[512];
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "%s: load into a DEM world after tl_dem_setup (built as the saved one)", path);
  int64_t v = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_laws", &v));
  if (v != d->n_laws) TL_ERROR(TL_ERR_ARG, "%s: the saved scene has %lld contact laws; this one %d", path, (long long)v, d->n_laws);
  TL_CHECK(tl_checkpoint_read_int64(r, group, "rotation", &v));
  if (v != d->rotation)
    TL_ERROR(TL_ERR_ARG, "%s: the saved scene %s rotation; this one %s", path, v ? "has" : "has no", d->rotation ? "has" : "has none");
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_walls", &v));
  if (v != (int64_t)d->n_walls) TL_ERROR(TL_ERR_ARG, "%s: the saved scene has %lld walls; this one %zu", path, (long long)v, d->n_walls);
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_prescribed", &v));
  if (v != (int64_t)d->n_presc)
    TL_ERROR(TL_ERR_ARG, "%s: the saved scene has %lld prescribed-motion groups; this one %zu", path, (long long)v, d->n_presc);
  /* particles */
  snprintf(sub, sizeof sub, "%s/particles", group ? group : "");
  int64_t n64 = 0, ns = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, sub, "n", &n64));
  TL_CHECK(tl_checkpoint_read_int64(r, sub, "n_species", &ns));
  if (ns != (int64_t)P->n_species)
    TL_ERROR(TL_ERR_ARG, "%s: the saved scene has %lld species; this one %zu", path, (long long)ns, P->n_species);
  if (n64 < 0 || n64 > (int64_t)UINT32_MAX) TL_ERROR(TL_ERR_ARG, "%s: particle count %lld out of range [0, %u]", path, (long long)n64, UINT32_MAX);
  const size_t n = (size_t)n64;
  if (P->q && !tl_checkpoint_has(r, sub, "q")) TL_ERROR(TL_ERR_ARG, "%s: no rotational state saved; this scene rotates", path);
  if (P->f_ext && !tl_checkpoint_has(r, sub, "f_ext")) TL_ERROR(TL_ERR_ARG, "%s: no external forces saved; this scene has them", path);
  if (!P->f_ext && tl_checkpoint_has(r, sub, "f_ext")) TL_CHECK(tl_particles_enable_external_force(P));
  if (tl_checkpoint_has(r, sub, "f_coupling")) TL_CHECK(tl_particles_enable_coupling_force(P));
  if (tl_checkpoint_has(r, sub, "weight")) TL_CHECK(tl_particles_enable_weights(P));
  TL_CHECK(tl_particles_reserve(P, n));
  TL_CHECK(tl_checkpoint_read_int64(r, sub, "next_id", &P->next_id));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "x", 3 * n, (double *)P->x));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "v", 3 * n, (double *)P->v));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "f", 3 * n, (double *)P->f));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "radius", n, P->radius));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "mass", n, P->mass));
  TL_CHECK(tl_checkpoint_read_doubles(r, sub, "inv_mass", n, P->inv_mass));
  TL_CHECK(tl_checkpoint_read_bytes(r, sub, "species", n * sizeof *P->species, P->species));
  TL_CHECK(tl_checkpoint_read_bytes(r, sub, "motion", n, P->motion));
  TL_CHECK(tl_checkpoint_read_int64s(r, sub, "id", n, P->id));
  if (P->q) {
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "q", 4 * n, (double *)P->q));
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "w", 3 * n, (double *)P->w));
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "torque", 3 * n, (double *)P->torque));
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "inv_inertia", n, P->inv_inertia));
  }
  if (P->f_ext) TL_CHECK(tl_checkpoint_read_doubles(r, sub, "f_ext", 3 * n, (double *)P->f_ext));
  if (P->f_coupling && tl_checkpoint_has(r, sub, "f_coupling"))
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "f_coupling", 3 * n, (double *)P->f_coupling));
  if (P->weight && tl_checkpoint_has(r, sub, "weight"))
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "weight", n, P->weight));
  for (size_t i = 0; i < n; ++i)
    if (P->species[i] < 0 || (size_t)P->species[i] >= P->n_species)
      TL_ERROR(TL_ERR_ARG, "%s: particle %zu has species %d; this scene has %zu", path, i, P->species[i], P->n_species);
  P->n = n;
  /* run state */
  TL_CHECK(tl_checkpoint_read_double(r, group, "t", &d->t));
  TL_CHECK(tl_checkpoint_read_double(r, group, "dt", &d->dt));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "steps", &v));
  d->steps = (long)v;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "rebuilds", &v));
  d->rebuilds = (long)v;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "need_rebuild", &v));
  d->need_rebuild = (int)v;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_touching", &v));
  d->n_touching = (size_t)v;
  double scalars[8];
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "skin_cut_rmin_disp2_energy", 8, scalars));
  d->skin = scalars[0];
  d->max_cut = scalars[1];
  d->r_min = scalars[2];
  d->disp2max = scalars[3];
  d->elastic_pp = scalars[4];
  d->contact_work_pp = scalars[5];
  d->work_ext = scalars[6];
  /* domain */
  TlDomain *D = &d->domain;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "domain_kind", &v));
  if (v != (int64_t)D->kind) TL_ERROR(TL_ERR_ARG, "%s: the saved domain is of kind %lld; this one %d", path, (long long)v, (int)D->kind);
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_origin", 3, &D->origin.x));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_h", 9, &D->h.m[0][0]));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_h_inv", 9, &D->h_inv.m[0][0]));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_h_dot", 9, &D->h_dot.m[0][0]));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "domain_L", 9, &D->L.m[0][0]));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "domain_deforming", &v));
  D->deforming = (int)v;
  /* neighbour list */
  snprintf(sub, sizeof sub, "%s/contacts", group ? group : "");
  TL_CHECK(load_list(&d->list, r, sub, d->n_laws));
  snprintf(sub, sizeof sub, "%s/bonds", group ? group : "");
  TL_CHECK(load_list(&d->bonds, r, sub, d->n_laws));
  TlContactList *lists[2] = {&d->list, &d->bonds};
  for (int q = 0; q < 2; ++q)
    if (lists[q]->n != (size_t)-1)
      for (size_t k = 0; k < lists[q]->n; ++k)
        if (lists[q]->i[k] >= n || lists[q]->j[k] >= n)
          TL_ERROR(TL_ERR_ARG, "%s: contact %zu joins particles %u and %u; there are %zu", path, k, lists[q]->i[k],
                   lists[q]->j[k], n);
  TL_CHECK(make_chunks(&d->list, &d->chunks, &d->chunks_cap, &d->n_chunks));
  if (d->bonds.n != (size_t)-1) {
    if (d->bonds.n) TL_CHECK(tl_contact_list_index(&d->bonds, 0));
    TL_CHECK(make_chunks(&d->bonds, &d->bond_chunks, &d->bond_chunks_cap, &d->n_bond_chunks));
  }
  if (n > d->x_build_cap) {
    TL_CHECK(tl_realloc(&d->x_build, n + n / 2 + 16, sizeof *d->x_build));
    d->x_build_cap = n + n / 2 + 16;
  }
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "x_build", 3 * n, (double *)d->x_build));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "h_build_inv", 9, &d->h_build_inv.m[0][0]));
  /* the grid walls query between rebuilds: from the build positions */
  TL_CHECK(tl_hgrid_build(d->grid, &d->domain, n, d->x_build, P->radius, d->skin));
  /* prescribed motions */
  for (size_t g = 0; g < d->n_presc; ++g) {
    Prescribed *p = &d->presc[g];
    snprintf(sub, sizeof sub, "%s/prescribed_%zu", group ? group : "", g);
    size_t m = 0;
    TL_CHECK(tl_checkpoint_length(r, sub, "id", &m));
    if (m != p->n)
      TL_ERROR(TL_ERR_ARG, "%s: prescribed group %zu has %zu particles saved; this one %zu", path, g, m, p->n);
    TL_CHECK(tl_checkpoint_read_int64s(r, sub, "id", p->n, p->ids));
    TL_CHECK(tl_checkpoint_read_bytes(r, sub, "index", p->n * sizeof *p->idx, p->idx));
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "x0", 3 * p->n, (double *)p->x0));
    for (size_t k = 0; k < p->n; ++k)
      if (p->idx[k] >= n || P->id[p->idx[k]] != p->ids[k])
        TL_ERROR(TL_ERR_ARG, "%s: prescribed particle id %lld is not at its saved index %zu", path, (long long)p->ids[k], p->idx[k]);
  }
  /* walls */
  for (size_t k = 0; k < d->n_walls; ++k) {
    TlWall *W = d->walls[k];
    snprintf(sub, sizeof sub, "%s/wall_%zu", group ? group : "", k);
    char *type = NULL;
    TL_CHECK(tl_checkpoint_read_string(r, sub, "type", &type));
    int same = strcmp(type, W->ops->header.name) == 0;
    tl_free(&type);
    if (!same) TL_ERROR(TL_ERR_ARG, "%s: wall %zu was saved as another type than '%s'", path, k, W->ops->header.name);
    if (!W->ops->checkpoint_load) TL_ERROR(TL_ERR_STATE, "wall '%s' (%s) has no checkpoint hooks", W->name, W->ops->header.name);
    double acc[9];
    TL_CHECK(tl_checkpoint_read_doubles(r, sub, "accounting", 9, acc));
    W->elastic_energy = acc[0];
    W->contact_work = acc[1];
    W->work = acc[2];
    W->force = tl_v3(acc[3], acc[4], acc[5]);
    W->torque = tl_v3(acc[6], acc[7], acc[8]);
    TL_CHECK(tl_checkpoint_read_int64(r, sub, "n_contacts", &v));
    W->n_contacts = (size_t)v;
    size_t bytes = 0;
    TL_CHECK(tl_checkpoint_length(r, sub, "state", &bytes));
    void *buffer = NULL;
    TL_CHECK(tl_calloc(&buffer, bytes ? bytes : 1, 1));
    TlStatus s = tl_checkpoint_read_bytes(r, sub, "state", bytes, buffer);
    if (s == TL_OK) s = W->ops->checkpoint_load(W, buffer, bytes);
    tl_free(&buffer);
    TL_CHECK(s);
  }
  return TL_OK;
}

const TlCheckpointOps tl_dem_checkpoint_ops = {
    .header = {"checkpoint", "dem_v1",
               "DEM world: particles, contact list with histories, neighbour-list build state, domain, clocks, "
               "energy accumulators, prescribed motions and walls"},
    .save = dem_save,
    .load = dem_load,
};
