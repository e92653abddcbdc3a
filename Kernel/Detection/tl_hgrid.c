#include "tl_hgrid.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <string.h>
#include "tl_memory.h"

TlStatus tl_hgrid_create(TlHGrid **grid)
{
  TL_CHECK(TL_NEW(*grid));
  return TL_OK;
}

void tl_hgrid_destroy(TlHGrid **gp)
{
  TlHGrid *g = *gp;
  if (!g) return;
  for (int l = 0; l < TL_HGRID_MAX_LEVELS; ++l) tl_free(&g->level[l].cell_start);
  tl_free(&g->index);
  tl_free(&g->cell_of);
  tl_free(&g->level_of);
  tl_free(&g->reduced);
  for (int t = 0; t < TL_HGRID_MAX_THREADS; ++t) tl_free(&g->thread_pairs[t]);
  tl_free(gp);
}

/* Cell coordinate along direction k of reduced coordinate s on level l. */
static inline int cell_coord(const TlHGrid *g, int l, int k, double s)
{
  const TlHGridLevel *L = &g->level[l];
  double lo = g->domain->periodic[k] ? 0.0 : tl_v3_get(g->frame_lo, k);
  int c = (int)floor((s - lo) / tl_v3_get(g->cell_width[l], k));
  if (g->domain->periodic[k]) {
    c %= L->n[k];
    if (c < 0) c += L->n[k];
  } else {
    if (c < 0) c = 0;
    if (c >= L->n[k]) c = L->n[k] - 1;
  }
  return c;
}

static inline size_t cell_id(const TlHGridLevel *L, int cx, int cy, int cz)
{
  return ((size_t)cz * (size_t)L->n[1] + (size_t)cy) * (size_t)L->n[0] + (size_t)cx;
}

TlStatus tl_hgrid_build(TlHGrid *g, const TlDomain *domain, size_t n, const TlVec3 *x,
                        const double *radius, double skin)
{
  if (!(skin >= 0.0) || !isfinite(skin)) TL_ERROR(TL_ERR_ARG, "grid skin %g must be >= 0", skin);
  if (n > UINT32_MAX) TL_ERROR(TL_ERR_ARG, "grid: %zu particles exceed the limit %u", n, UINT32_MAX);
  g->domain = domain;
  g->skin = skin;
  g->n_particles = n;
  if (n > g->capacity_particles) {
    size_t cap = n + n / 2 + 16;
    TL_CHECK(tl_realloc(&g->index, cap, sizeof *g->index));
    TL_CHECK(tl_realloc(&g->cell_of, cap, sizeof *g->cell_of));
    TL_CHECK(tl_realloc(&g->level_of, cap, sizeof *g->level_of));
    TL_CHECK(tl_realloc(&g->reduced, cap, sizeof *g->reduced));
    g->capacity_particles = cap;
  }
  /* reduced coordinates, size range */
  double dmin = INFINITY, dmax = 0.0;
  TlVec3 lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY};
  g->max_radius = 0.0;
  for (size_t i = 0; i < n; ++i) {
    if (!(radius[i] > 0.0) || !tl_v3_isfinite(x[i]))
      TL_ERROR(TL_ERR_NUMERIC, "grid: particle %zu has radius %g and position (%g, %g, %g); need r > 0 and finite x",
               i, radius[i], x[i].x, x[i].y, x[i].z);
    TlVec3 s = tl_domain_to_reduced(domain, x[i]);
    double *c = &s.x;
    for (int k = 0; k < 3; ++k)
      if (domain->periodic[k]) c[k] -= floor(c[k]);
    /* a finite position can still overflow in cell lengths (x = -1e308 in a
     * 1 cm cell): an infinite extent would enlarge the cells forever */
    if (!tl_v3_isfinite(s))
      TL_ERROR(TL_ERR_NUMERIC, "grid: particle %zu at (%g, %g, %g) m is (%g, %g, %g) cell lengths from the origin, "
               "beyond the range of a double", i, x[i].x, x[i].y, x[i].z, s.x, s.y, s.z);
    g->reduced[i] = s;
    lo.x = fmin(lo.x, s.x); lo.y = fmin(lo.y, s.y); lo.z = fmin(lo.z, s.z);
    hi.x = fmax(hi.x, s.x); hi.y = fmax(hi.y, s.y); hi.z = fmax(hi.z, s.z);
    double d = 2.0 * radius[i] + skin;
    dmin = fmin(dmin, d);
    dmax = fmax(dmax, d);
    g->max_radius = fmax(g->max_radius, radius[i]);
  }
  if (n == 0) {
    dmin = dmax = 1.0;
    lo = hi = tl_v3(0, 0, 0);
  }
  g->frame_lo = lo;
  g->frame_hi = hi;
  /* levels: cell sizes double from the largest diameter down */
  int L = 1;
  while (L < TL_HGRID_MAX_LEVELS && dmax / ldexp(1.0, L) >= dmin) ++L;
  double size[TL_HGRID_MAX_LEVELS];
  for (int l = 0; l < L; ++l) size[l] = dmax / ldexp(1.0, L - 1 - l);
  size_t count[TL_HGRID_MAX_LEVELS] = {0};
  for (size_t i = 0; i < n; ++i) {
    double d = 2.0 * radius[i] + skin;
    int l = 0;
    while (l < L - 1 && size[l] < d) ++l;
    g->level_of[i] = (uint8_t)l;
    count[l]++;
  }
  /* drop empty levels */
  int map[TL_HGRID_MAX_LEVELS], nl = 0;
  for (int l = 0; l < L; ++l) {
    map[l] = count[l] ? nl : -1;
    if (count[l]) {
      g->level[nl].cell_size = size[l];
      g->level[nl].count = count[l];
      ++nl;
    }
  }
  if (nl == 0) {
    nl = 1;
    g->level[0].cell_size = dmax;
    g->level[0].count = 0;
    map[0] = 0;
  }
  for (size_t i = 0; i < n; ++i) g->level_of[i] = (uint8_t)map[g->level_of[i]];
  g->n_levels = nl;
  /* cells per direction: real extent over cell size, total capped */
  size_t first = 0;
  for (int l = 0; l < nl; ++l) {
    TlHGridLevel *Lv = &g->level[l];
    Lv->first = first;
    first += Lv->count;
    double ext[3];
    for (int k = 0; k < 3; ++k) {
      double face = tl_domain_face_distance(domain, k);
      double span = domain->periodic[k] ? 1.0 : fmax(tl_v3_get(hi, k) - tl_v3_get(lo, k), 0.0);
      ext[k] = span * face;
      if (!isfinite(ext[k]))
        TL_ERROR(TL_ERR_NUMERIC, "grid: the particles span %g cell lengths of %g m along direction %d, beyond the range "
                 "of a double", span, face, k);
      if (domain->periodic[k] && face < 2.0 * Lv->cell_size && face < 2.0 * (2.0 * g->max_radius + skin))
        TL_ERROR(TL_ERR_ARG, "periodic direction %d: cell width %g is less than twice the interaction range %g",
                 k, face, 2.0 * g->max_radius + skin);
    }
    double cs = Lv->cell_size;
    size_t cap_cells = 4 * (Lv->count + n / 8) + 64;
    for (;;) {
      size_t total = 1;
      for (int k = 0; k < 3; ++k) {
        double m = floor(ext[k] / cs);
        if (m < 1.0) m = 1.0;
        if (m > 1e6) m = 1e6;
        Lv->n[k] = (int)m;
        total *= (size_t)Lv->n[k];
      }
      if (total <= cap_cells) {
        Lv->n_cells = total;
        break;
      }
      cs *= 1.26;
    }
    TlVec3 w;
    double *wc = &w.x;
    for (int k = 0; k < 3; ++k) {
      double span = domain->periodic[k] ? 1.0 : tl_v3_get(hi, k) - tl_v3_get(lo, k);
      if (!(span > 0.0)) span = 1.0;
      wc[k] = span / Lv->n[k] * (1.0 + 1e-12);
    }
    g->cell_width[l] = w;
    if (Lv->n_cells + 1 > g->cell_capacity[l]) {
      size_t cap = Lv->n_cells + 1 + (Lv->n_cells + 1) / 2;
      TL_CHECK(tl_realloc(&Lv->cell_start, cap, sizeof *Lv->cell_start));
      g->cell_capacity[l] = cap;
    }
    memset(Lv->cell_start, 0, (Lv->n_cells + 1) * sizeof *Lv->cell_start);
  }
  /* counting sort into cells */
  for (size_t i = 0; i < n; ++i) {
    int l = g->level_of[i];
    TlVec3 s = g->reduced[i];
    size_t c = cell_id(&g->level[l], cell_coord(g, l, 0, s.x), cell_coord(g, l, 1, s.y), cell_coord(g, l, 2, s.z));
    g->cell_of[i] = (int32_t)c;
    g->level[l].cell_start[c + 1]++;
  }
  for (int l = 0; l < nl; ++l) {
    TlHGridLevel *Lv = &g->level[l];
    for (size_t c = 0; c < Lv->n_cells; ++c) Lv->cell_start[c + 1] += Lv->cell_start[c];
    for (size_t c = 0; c <= Lv->n_cells; ++c) Lv->cell_start[c] += Lv->first;
  }
  /* fill: use cell_start as running cursor, then shift back */
  for (size_t i = 0; i < n; ++i) {
    TlHGridLevel *Lv = &g->level[g->level_of[i]];
    g->index[Lv->cell_start[g->cell_of[i]]++] = i;
  }
  for (int l = 0; l < nl; ++l) {
    TlHGridLevel *Lv = &g->level[l];
    for (size_t c = Lv->n_cells; c > 0; --c) Lv->cell_start[c] = Lv->cell_start[c - 1];
    Lv->cell_start[0] = Lv->first;
  }
  return TL_OK;
}

/* Unique neighbour coordinates of c along direction k (wrapping in periodic
 * directions, clipping otherwise). */
static int neighbours_1d(const TlHGrid *g, int l, int k, int c, int out[3])
{
  int n = g->level[l].n[k], m = 0;
  for (int d = -1; d <= 1; ++d) {
    int v = c + d;
    if (g->domain->periodic[k]) {
      v %= n;
      if (v < 0) v += n;
    } else if (v < 0 || v >= n) {
      continue;
    }
    int dup = 0;
    for (int q = 0; q < m; ++q) dup |= out[q] == v;
    if (!dup) out[m++] = v;
  }
  return m;
}

static inline TlStatus push_pair(TlPair **pairs, size_t *capacity, size_t *count, size_t i, size_t j)
{
  if (*count >= *capacity) TL_CHECK(tl_array_reserve(pairs, capacity, *count + 1, sizeof **pairs));
  (*pairs)[(*count)++] = i < j ? (TlPair){(uint32_t)i, (uint32_t)j} : (TlPair){(uint32_t)j, (uint32_t)i};
  return TL_OK;
}

/* Pair test specialised on the frame: orthogonal frames (open or periodic
 * box) use one conditional image shift per periodic direction (positions
 * are wrapped at every build), other frames the rounding of Eq. 20. */
typedef struct {
  const TlDomain *dom;
  const TlVec3 *x;
  const double *radius;
  const uint8_t *skip;
  double skin, len[3], half[3];
  int ortho;
  TlPair **pairs;
  size_t *capacity, *count;
} PairScan;

static inline __attribute__((always_inline)) TlStatus check_pair(const PairScan *ps, size_t i, size_t j)
{
  if (ps->skip && ps->skip[i] && ps->skip[j]) return TL_OK;
  TlVec3 b;
  if (ps->ortho) {
    b = tl_v3_sub(ps->x[j], ps->x[i]);
    double *bc = &b.x;
    for (int q = 0; q < 3; ++q) {
      if (ps->len[q] <= 0.0) continue;
      if (bc[q] > ps->half[q]) bc[q] -= ps->len[q];
      else if (bc[q] < -ps->half[q]) bc[q] += ps->len[q];
    }
  } else {
    b = tl_domain_branch(ps->dom, ps->x[i], ps->x[j]);
  }
  double cut = ps->radius[i] + ps->radius[j] + ps->skin;
  if (b.x * b.x + b.y * b.y + b.z * b.z > cut * cut) return TL_OK;
  if (*ps->count >= *ps->capacity)
    TL_CHECK(tl_array_reserve(ps->pairs, ps->capacity, *ps->count + 1, sizeof **ps->pairs));
  (*ps->pairs)[(*ps->count)++] = i < j ? (TlPair){(uint32_t)i, (uint32_t)j} : (TlPair){(uint32_t)j, (uint32_t)i};
  return TL_OK;
}

/* The pairs found from the cells with cz in [z0, z1) of level l (same level
 * and coarser levels), appended through ps. */
static TlStatus pairs_slab(const TlHGrid *g, const PairScan *ps, int l, int z0, int z1)
{
  const TlHGridLevel *Lv = &g->level[l];
  for (int cz = z0; cz < z1; ++cz)
    for (int cy = 0; cy < Lv->n[1]; ++cy)
      for (int cx = 0; cx < Lv->n[0]; ++cx) {
        size_t c = cell_id(Lv, cx, cy, cz);
        size_t a0 = Lv->cell_start[c], a1 = Lv->cell_start[c + 1];
        if (a0 == a1) continue;
        /* same level: pairs inside the cell, then with each neighbouring
         * cell of larger number (each cell pair once) */
        for (size_t a = a0; a < a1; ++a)
          for (size_t b = a + 1; b < a1; ++b) TL_CHECK(check_pair(ps, g->index[a], g->index[b]));
        int nx[3], ny[3], nz[3];
        int mx = neighbours_1d(g, l, 0, cx, nx), my = neighbours_1d(g, l, 1, cy, ny),
            mz = neighbours_1d(g, l, 2, cz, nz);
        for (int iz = 0; iz < mz; ++iz)
          for (int iy = 0; iy < my; ++iy)
            for (int ix = 0; ix < mx; ++ix) {
              size_t c2 = cell_id(Lv, nx[ix], ny[iy], nz[iz]);
              if (c2 <= c) continue;
              size_t b0 = Lv->cell_start[c2], b1 = Lv->cell_start[c2 + 1];
              for (size_t a = a0; a < a1; ++a)
                for (size_t b = b0; b < b1; ++b) TL_CHECK(check_pair(ps, g->index[a], g->index[b]));
            }
        /* coarser levels: the 27 cells around each particle there */
        for (size_t a = a0; a < a1; ++a) {
          size_t i = g->index[a];
          TlVec3 s = g->reduced[i];
          for (int m = l + 1; m < g->n_levels; ++m) {
            const TlHGridLevel *M = &g->level[m];
            if (!M->count) continue;
            int px[3], py[3], pz[3];
            int qx = neighbours_1d(g, m, 0, cell_coord(g, m, 0, s.x), px);
            int qy = neighbours_1d(g, m, 1, cell_coord(g, m, 1, s.y), py);
            int qz = neighbours_1d(g, m, 2, cell_coord(g, m, 2, s.z), pz);
            for (int iz = 0; iz < qz; ++iz)
              for (int iy = 0; iy < qy; ++iy)
                for (int ix = 0; ix < qx; ++ix) {
                  size_t c2 = cell_id(M, px[ix], py[iy], pz[iz]);
                  for (size_t q = M->cell_start[c2]; q < M->cell_start[c2 + 1]; ++q)
                    TL_CHECK(check_pair(ps, i, g->index[q]));
                }
          }
        }
      }
  return TL_OK;
}

TlStatus tl_hgrid_pairs(const TlHGrid *gc, const TlVec3 *x, const double *radius, const uint8_t *skip,
                        TlPair **pairs, size_t *capacity, size_t *count)
{
  TlHGrid *g = (TlHGrid *)gc; /* only the scratch buffers change */
  const TlDomain *dom = g->domain;
  PairScan base = {dom, x, radius, skip, g->skin, {0, 0, 0}, {0, 0, 0}, 0, pairs, capacity, count};
  base.ortho = dom->kind != TL_DOMAIN_DEFORMABLE_CELL;
  for (int q = 0; q < 3; ++q) {
    base.len[q] = dom->periodic[q] ? dom->h.m[q][q] : 0.0;
    base.half[q] = 0.5 * base.len[q];
  }
  *count = 0;
  int nt = g->n_particles >= 20000 ? omp_get_max_threads() : 1;
  if (nt > TL_HGRID_MAX_THREADS) nt = TL_HGRID_MAX_THREADS;
  for (int l = 0; l < g->n_levels; ++l) {
    const TlHGridLevel *Lv = &g->level[l];
    if (!Lv->count) continue;
    int nz = Lv->n[2];
    int use = nt < nz ? nt : 1;
    if (use <= 1) {
      TL_CHECK(pairs_slab(g, &base, l, 0, nz));
      continue;
    }
    TlStatus status = TL_OK;
#pragma omp parallel num_threads(use)
    {
      int t = omp_get_thread_num();
      PairScan ps = base;
      g->thread_count[t] = 0;
      ps.pairs = &g->thread_pairs[t];
      ps.capacity = &g->thread_capacity[t];
      ps.count = &g->thread_count[t];
      TlStatus s = pairs_slab(g, &ps, l, nz * t / use, nz * (t + 1) / use);
      if (s != TL_OK) {
#pragma omp critical(tl_hgrid_pairs_status)
        status = s;
      }
    }
    if (status != TL_OK) return tl_error_trace(status, __FILE__, __LINE__);
    size_t total = *count;
    for (int t = 0; t < use; ++t) total += g->thread_count[t];
    TL_CHECK(tl_array_reserve(pairs, capacity, total, sizeof **pairs));
    for (int t = 0; t < use; ++t) {
      memcpy(*pairs + *count, g->thread_pairs[t], g->thread_count[t] * sizeof **pairs);
      *count += g->thread_count[t];
    }
  }
  return TL_OK;
}

TlStatus tl_hgrid_pairs_brute_force(const TlDomain *domain, size_t n, const TlVec3 *x, const double *radius,
                                    double skin, const uint8_t *skip, TlPair **pairs, size_t *capacity,
                                    size_t *count)
{
  *count = 0;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      if (skip && skip[i] && skip[j]) continue;
      TlVec3 b = tl_domain_branch(domain, x[i], x[j]);
      double cut = radius[i] + radius[j] + skin;
      if (tl_v3_norm2(b) <= cut * cut) TL_CHECK(push_pair(pairs, capacity, count, i, j));
    }
  return TL_OK;
}

TlStatus tl_hgrid_query_box(const TlHGrid *g, TlVec3 lo, TlVec3 hi, size_t **out, size_t *capacity, size_t *count)
{
  const TlDomain *dom = g->domain;
  *count = 0;
  for (int l = 0; l < g->n_levels; ++l) {
    const TlHGridLevel *Lv = &g->level[l];
    if (Lv->count == 0) continue;
    double grow = Lv->cell_size + 0.5 * g->skin;
    TlVec3 a = tl_v3(lo.x - grow, lo.y - grow, lo.z - grow), b = tl_v3(hi.x + grow, hi.y + grow, hi.z + grow);
    /* reduced bounding box of the enlarged box's corners */
    double rlo[3] = {INFINITY, INFINITY, INFINITY}, rhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    int unbounded[3] = {0, 0, 0};
    if (!tl_v3_isfinite(a) || !tl_v3_isfinite(b)) {
      /* an infinite component: every cell along directions it reaches */
      for (int k = 0; k < 3; ++k) unbounded[k] = 1;
      /* for an orthogonal frame only the infinite directions are unbounded */
      if (dom->kind != TL_DOMAIN_DEFORMABLE_CELL)
        for (int k = 0; k < 3; ++k) {
          unbounded[k] = !(isfinite(tl_v3_get(a, k)) && isfinite(tl_v3_get(b, k)));
          if (!unbounded[k]) {
            double o = tl_v3_get(dom->origin, k), len = dom->h.m[k][k];
            rlo[k] = (tl_v3_get(a, k) - o) / len;
            rhi[k] = (tl_v3_get(b, k) - o) / len;
          }
        }
    } else {
      for (int corner = 0; corner < 8; ++corner) {
        TlVec3 p = {(corner & 1) ? b.x : a.x, (corner & 2) ? b.y : a.y, (corner & 4) ? b.z : a.z};
        TlVec3 s = tl_domain_to_reduced(dom, p);
        for (int k = 0; k < 3; ++k) {
          rlo[k] = fmin(rlo[k], tl_v3_get(s, k));
          rhi[k] = fmax(rhi[k], tl_v3_get(s, k));
        }
      }
    }
    int c0[3], c1[3];
    for (int k = 0; k < 3; ++k) {
      int n = Lv->n[k];
      if (unbounded[k]) {
        c0[k] = 0;
        c1[k] = n - 1;
        continue;
      }
      double flo = dom->periodic[k] ? 0.0 : tl_v3_get(g->frame_lo, k);
      double w = tl_v3_get(g->cell_width[l], k);
      double f0 = floor((rlo[k] - flo) / w), f1 = floor((rhi[k] - flo) / w);
      if (dom->periodic[k]) {
        if (f1 - f0 + 1 >= n) {
          c0[k] = 0;
          c1[k] = n - 1;
        } else {
          c0[k] = (int)f0;
          c1[k] = (int)f1; /* wrapped below */
        }
      } else {
        if (f1 < 0 || f0 > n - 1) {
          /* outside the particles' frame: only the clamped boundary cell can
           * hold particles that were clamped there, and they are farther
           * than the enlargement; nothing to find */
          c0[k] = 1;
          c1[k] = 0;
        } else {
          c0[k] = f0 < 0 ? 0 : (int)f0;
          c1[k] = f1 > n - 1 ? n - 1 : (int)f1;
        }
      }
    }
    for (int cz = c0[2]; cz <= c1[2]; ++cz)
      for (int cy = c0[1]; cy <= c1[1]; ++cy)
        for (int cx = c0[0]; cx <= c1[0]; ++cx) {
          int w3[3] = {cx, cy, cz};
          for (int k = 0; k < 3; ++k)
            if (dom->periodic[k]) {
              w3[k] %= Lv->n[k];
              if (w3[k] < 0) w3[k] += Lv->n[k];
            }
          size_t c = cell_id(Lv, w3[0], w3[1], w3[2]);
          size_t m = Lv->cell_start[c + 1] - Lv->cell_start[c];
          if (!m) continue;
          TL_CHECK(tl_array_reserve(out, capacity, *count + m, sizeof **out));
          memcpy(*out + *count, g->index + Lv->cell_start[c], m * sizeof **out);
          *count += m;
        }
  }
  return TL_OK;
}
