/* The DEM neighbour list: law table, rebuild from the grid (with renumbering
 * in grid order now and then), remap after renumbering or removal, bonds. */
#include "tl_dem_private.h"

#include <math.h>
#include <string.h>
#include "tl_memory.h"

static int law_of(const TlDem *d, int a, int b)
{
  size_t ns = d->law_table_n;
  if ((size_t)a < ns && (size_t)b < ns) return d->law_table[(size_t)a * ns + (size_t)b];
  return 0;
}

TlStatus tl_dem_build_law_table(TlDem *d)
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

TlStatus tl_dem_make_chunks(const TlContactList *L, Chunk **chunks, size_t *cap, size_t *n)
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

TlStatus tl_dem_remap(TlDem *d, const size_t *old_to_new, size_t n_old)
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
  d->list_version++;
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
  d->list_version++;
  return tl_dem_make_chunks(B, &d->bond_chunks, &d->bond_chunks_cap, &d->n_bond_chunks);
}

TlStatus tl_dem_rebuild(TlDem *d)
{
  TlParticles *P = d->P;
  size_t n = P->n;
  double t0 = tl_dem_clock(d);
  /* a 2-D world: a particle inserted off the plane would meet the others
   * only through the grid's z, which the contacts ignore */
  if (d->dim == 2)
    for (size_t i = 0; i < n; ++i)
      if (P->x[i].z != 0.0)
        TL_ERROR(TL_ERR_ARG, "2-D world: particle id %lld has z = %g; disks lie in the plane z = 0", (long long)P->id[i],
                 P->x[i].z);
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
    TL_CHECK(tl_dem_remap(d, d->old_to_new, n));
    /* the grid follows: particle k of the new order is grid entry k */
    TlHGrid *g = d->grid;
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
  tl_dem_tick(d, TL_DEM_PHASE_GRID, &t0);
  TL_CHECK(tl_hgrid_pairs(d->grid, P->x, P->radius, skip, &d->pairs, &d->pairs_cap, &d->n_pairs));
  tl_dem_tick(d, TL_DEM_PHASE_PAIRS, &t0);
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
  TL_CHECK(tl_dem_make_chunks(L, &d->chunks, &d->chunks_cap, &d->n_chunks));
  /* build positions for the displacement criterion */
  if (n > d->x_build_cap) {
    TL_CHECK(tl_realloc(&d->x_build, n + n / 2 + 16, sizeof *d->x_build));
    d->x_build_cap = n + n / 2 + 16;
  }
  memcpy(d->x_build, P->x, n * sizeof *P->x);
  d->h_build_inv = d->domain.h_inv;
  d->rebuilds++;
  d->list_version++;
  d->need_rebuild = 0;
  tl_dem_tick(d, TL_DEM_PHASE_LIST, &t0);
  return TL_OK;
}

/* Largest centre displacement since the last build, the affine part of a
 * deforming cell removed, and the strain measure ||h h_build⁻¹ - I||. */
int tl_dem_needs_rebuild(TlDem *d)
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
    if (d->dim == 2) {
      /* the plane only: z is inert */
      const double a00 = A.m[0][0], a01 = A.m[0][1], a10 = A.m[1][0], a11 = A.m[1][1];
      for (size_t i = 0; i < P->n; ++i) {
        const double px = d->x_build[i].x - o.x, py = d->x_build[i].y - o.y;
        const double dx = P->x[i].x - (o.x + a00 * px + a01 * py), dy = P->x[i].y - (o.y + a10 * px + a11 * py);
        const double m = dx * dx + dy * dy;
        if (m > max2) max2 = m;
      }
    } else
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
