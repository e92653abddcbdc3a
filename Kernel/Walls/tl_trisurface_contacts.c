#include "tl_trisurface_contacts.h"

#include <stdlib.h>
#include <string.h>
#include "tl_memory.h"
#include "tl_parallel.h"

TlStatus tl_tricontacts_create(TlTriContactSet **set)
{
  if (!set) TL_ERROR(TL_ERR_ARG, "tl_tricontacts_create: NULL pointer");
  TL_CHECK(TL_NEW(*set));
  return TL_OK;
}

void tl_tricontacts_destroy(TlTriContactSet **set)
{
  if (!set || !*set) return;
  tl_free(&(*set)->c);
  tl_free(&(*set)->group);
  tl_free(&(*set)->history);
  tl_free(&(*set)->link);
  tl_free(&(*set)->region);
  tl_free(&(*set)->used);
  tl_free(&(*set)->bucket);
  tl_free(&(*set)->sorted);
  tl_free(set);
}

void tl_tricontacts_clear(TlTriContactSet *set)
{
  set->count = 0;
  set->n_groups = 0;
  set->regions_valid = 0;
}

void tl_tricontacts_swap(TlTriContactSet *a, TlTriContactSet *b)
{
  TlTriContactSet t = *a;
  *a = *b;
  *b = t;
}

TlStatus tl_tricontacts_append(TlTriContactSet *set, const TlTriContactRecord *r)
{
  TL_CHECK(tl_array_reserve(&set->c, &set->capacity, set->count + 1, sizeof *set->c));
  set->c[set->count++] = *r;
  set->regions_valid = 0;
  return TL_OK;
}

TlStatus tl_tricontacts_test(TlTriContactSet *set, const TlTriSurface *s, const TlDomain *domain,
                             int32_t t, int32_t p, TlVec3 x, double r)
{
  TlVec3 anchor = s->x[s->tri[3 * (size_t)t]];
  TlVec3 lo = s->box_lo[t], hi = s->box_hi[t];
  /* cheap rejections first: the box along directions without images, then
   * the nearest image, the box and the triangle's plane */
  if (domain && domain->any_periodic) {
    if (domain->kind == TL_DOMAIN_PERIODIC_BOX) {
      if ((!domain->periodic[0] && (x.x + r < lo.x || x.x - r > hi.x)) ||
          (!domain->periodic[1] && (x.y + r < lo.y || x.y - r > hi.y)) ||
          (!domain->periodic[2] && (x.z + r < lo.z || x.z - r > hi.z)))
        return TL_OK;
    }
    x = tl_v3_add(anchor, tl_domain_branch(domain, anchor, x));
  }
  if (x.x + r < lo.x || x.x - r > hi.x || x.y + r < lo.y || x.y - r > hi.y || x.z + r < lo.z || x.z - r > hi.z)
    return TL_OK;
  if (fabs(tl_v3_dot(s->normal[t], tl_v3_sub(x, anchor))) >= r) return TL_OK;
  TlTriContact con;
  if (!tl_trisurface_sphere_contact(s, t, x, r, &con)) return TL_OK;
  TlTriContactRecord rec = {.particle = p, .triangle = t, .feature = con.feature, .active = 1,
                            .point = con.point, .normal = con.normal, .overlap = con.overlap,
                            .bary = {con.bary[0], con.bary[1], con.bary[2]}, .center = x,
                            .radius = r, .weight = 1.0};
  TL_CHECK(tl_tricontacts_append(set, &rec));
  return TL_OK;
}

int tl_trisurface_within(const TlTriSurface *s, const TlDomain *domain, int32_t t, TlVec3 x, double reach)
{
  const int *v = s->tri + 3 * (size_t)t;
  TlVec3 a = s->x[v[0]];
  if (domain && domain->any_periodic) x = tl_v3_add(a, tl_domain_branch(domain, a, x));
  TlVec3 lo = s->box_lo[t], hi = s->box_hi[t];
  if (x.x + reach < lo.x || x.x - reach > hi.x || x.y + reach < lo.y || x.y - reach > hi.y || x.z + reach < lo.z ||
      x.z - reach > hi.z)
    return 0;
  if (fabs(tl_v3_dot(s->normal[t], tl_v3_sub(x, a))) >= reach) return 0;
  TlVec3 q;
  double bary[3];
  tl_triangle_closest_point(a, s->x[v[1]], s->x[v[2]], x, &q, bary);
  return tl_v3_norm2(tl_v3_sub(x, q)) < reach * reach;
}

TlStatus tl_tricontacts_detect_brute(TlTriContactSet *set, const TlTriSurface *s,
                                     const TlDomain *domain, size_t n, const TlVec3 *x,
                                     const double *radius)
{
  for (size_t t = 0; t < s->n_triangles; ++t)
    for (size_t p = 0; p < n; ++p)
      TL_CHECK(tl_tricontacts_test(set, s, domain, (int32_t)t, (int32_t)p, x[p], radius[p]));
  return TL_OK;
}

static int tl_record_compare(const void *pa, const void *pb)
{
  const TlTriContactRecord *a = pa, *b = pb;
  if (a->particle != b->particle) return a->particle < b->particle ? -1 : 1;
  return (a->triangle > b->triangle) - (a->triangle < b->triangle);
}

static TlStatus tl_tricontacts_build_groups(TlTriContactSet *set)
{
  size_t ng = 0;
  for (size_t i = 0; i < set->count; ++i)
    if (i == 0 || set->c[i].particle != set->c[i - 1].particle) ++ng;
  TL_CHECK(tl_array_reserve(&set->group, &set->group_capacity, ng + 1, sizeof *set->group));
  ng = 0;
  for (size_t i = 0; i < set->count; ++i)
    if (i == 0 || set->c[i].particle != set->c[i - 1].particle) set->group[ng++] = i;
  set->group[ng] = set->count;
  set->n_groups = ng;
  return TL_OK;
}

TlStatus tl_tricontacts_sort(TlTriContactSet *set)
{
  /* Detection order depends on the grid and the threads; sorting makes every
   * later decision (ties included) independent of both.  Counting sort by
   * particle (O(count + particles)), then insertion sort by triangle within
   * each particle's few contacts. */
  size_t n = set->count;
  set->regions_valid = 0;
  if (n > 1) {
    int32_t pmax = 0;
    for (size_t i = 0; i < n; ++i) pmax = set->c[i].particle > pmax ? set->c[i].particle : pmax;
    size_t np = (size_t)pmax + 2;
    TL_CHECK(tl_array_reserve(&set->bucket, &set->bucket_capacity, np, sizeof *set->bucket));
    TL_CHECK(tl_array_reserve(&set->sorted, &set->sorted_capacity, n, sizeof *set->sorted));
    memset(set->bucket, 0, np * sizeof *set->bucket);
    for (size_t i = 0; i < n; ++i) ++set->bucket[set->c[i].particle + 1];
    for (size_t p = 1; p < np; ++p) set->bucket[p] += set->bucket[p - 1];
    for (size_t i = 0; i < n; ++i) set->sorted[set->bucket[set->c[i].particle]++] = set->c[i];
    TlTriContactRecord *tmp = set->c;
    size_t cap = set->capacity;
    set->c = set->sorted, set->capacity = set->sorted_capacity;
    set->sorted = tmp, set->sorted_capacity = cap;
  }
  TL_CHECK(tl_tricontacts_build_groups(set));
  for (size_t g = 0; g < set->n_groups; ++g)
    for (size_t i = set->group[g] + 1; i < set->group[g + 1]; ++i) {
      TlTriContactRecord r = set->c[i];
      size_t j = i;
      while (j > set->group[g] && set->c[j - 1].triangle > r.triangle) {
        set->c[j] = set->c[j - 1];
        --j;
      }
      set->c[j] = r;
    }
  return TL_OK;
}

/* Record index of triangle t within c[lo, hi) (sorted by triangle), or -1. */
static long tl_find_triangle(const TlTriContactRecord *c, size_t lo, size_t end, int32_t t)
{
  size_t hi = end;
  while (lo < hi) {
    size_t mid = lo + (hi - lo) / 2;
    if (c[mid].triangle < t) lo = mid + 1;
    else hi = mid;
  }
  return (lo < end && c[lo].triangle == t) ? (long)lo : -1;
}

static int32_t tl_root(int32_t *link, int32_t i)
{
  while (link[i] != i) {
    link[i] = link[link[i]];
    i = link[i];
  }
  return i;
}

/* Whether record a should be kept over record b. */
static int tl_record_better(const TlTriContactRecord *a, const TlTriContactRecord *b)
{
  if (a->overlap != b->overlap) return a->overlap > b->overlap;
  return a->triangle < b->triangle;
}

TlStatus tl_tricontacts_merge_shared_edges(TlTriContactSet *set, const TlTriSurface *s)
{
  size_t n = set->count;
  set->regions_valid = 0;
  if (n == 0) return TL_OK;
  if (n > (size_t)INT32_MAX) TL_ERROR(TL_ERR_ARG, "%zu wall contacts exceed the limit %d", n, INT32_MAX);
  TL_CHECK(tl_array_reserve(&set->link, &set->link_capacity, n, sizeof *set->link));
  TL_CHECK(tl_array_reserve(&set->region, &set->region_capacity, n, sizeof *set->region));
  TlTriContactRecord *c = set->c;
  int32_t *link = set->link, *region = set->region;
  long ng = (long)set->n_groups;
  TL_PARALLEL_IF(ng > 2048, "omp parallel for schedule(dynamic, 64)",
    for (long g = 0; g < ng; ++g) {
      size_t g0 = set->group[g], g1 = set->group[g + 1];
      for (size_t i = g0; i < g1; ++i) link[i] = region[i] = (int32_t)i;
      if (g1 - g0 < 2) continue;
      for (size_t i = g0; i < g1; ++i) {
        int32_t t = c[i].triangle;
        for (int k = 0; k < 3; ++k) {
          int32_t nb = s->tri_nbr[3 * (size_t)t + k];
          if (nb <= t) continue; /* each pair once, from its lower triangle */
          long j = tl_find_triangle(c, g0, g1, nb);
          if (j < 0) continue;
          int e = s->tri_edge[3 * (size_t)t + k];
          TlEdgeShape shape = tl_trisurface_edge_shape_seen_from(s, e, c[i].center, c[i].triangle);
          /* one smooth piece of surface unless the edge is a sharp valley
           * seen from the particle (touched triangles of one piece are
           * joined edge to edge, so the pre-merge records link them all) */
          if (!(shape == TL_EDGE_CONCAVE && s->edge_sharp[e])) {
            int32_t qi = tl_root(region, (int32_t)i), qj = tl_root(region, (int32_t)j);
            if (qi != qj) region[qi > qj ? qi : qj] = qi < qj ? qi : qj;
          }
          int kb = 0;
          while (kb < 2 && s->tri_edge[3 * (size_t)nb + kb] != e) ++kb;
          if (!tl_tri_feature_on_edge(c[i].feature, k) && !tl_tri_feature_on_edge(c[j].feature, kb))
            continue;
          if (shape == TL_EDGE_CONCAVE) continue;
          int32_t ri = tl_root(link, (int32_t)i), rj = tl_root(link, (int32_t)j);
          if (ri == rj) continue;
          /* the root of a cluster is always its best contact */
          if (tl_record_better(&c[ri], &c[rj])) link[rj] = ri;
          else link[ri] = rj;
        }
      }
      for (size_t i = g0; i < g1; ++i) {
        c[i].active = tl_root(link, (int32_t)i) == (int32_t)i;
        region[i] = tl_root(region, (int32_t)i); /* a label from now on */
      }
    });
  /* compact */
  size_t m = 0;
  for (size_t i = 0; i < n; ++i)
    if (c[i].active) region[m] = region[i], c[m++] = c[i];
  set->count = m;
  TL_CHECK(tl_tricontacts_build_groups(set));
  set->regions_valid = 1;
  return TL_OK;
}

TlStatus tl_tricontacts_carry_history(TlTriContactSet *set, const TlTriContactSet *prev,
                                      size_t history_doubles)
{
  size_t n = set->count, hd = history_doubles;
  set->history_doubles = hd;
  for (size_t i = 0; i < n; ++i) set->c[i].force_prev = tl_v3(0, 0, 0);
  if (hd && n) {
    TL_CHECK(tl_array_reserve(&set->history, &set->history_capacity, n * hd, sizeof *set->history));
    memset(set->history, 0, n * hd * sizeof *set->history);
  }
  if (!prev || prev->count == 0 || prev->history_doubles != hd) return TL_OK;
  TL_CHECK(tl_array_reserve(&set->used, &set->used_capacity, prev->count, 1));
  TL_CHECK(tl_array_reserve(&set->link, &set->link_capacity, n, sizeof *set->link));
  memset(set->used, 0, prev->count);
  TlTriContactRecord *c = set->c;
  const TlTriContactRecord *pc = prev->c;
  unsigned char *used = set->used;
  int32_t *done = set->link;
  long ng = (long)set->n_groups;
  /* the previous group of each particle, by one merge of the two sorted
   * group lists (kept in the scratch `bucket`) */
  TL_CHECK(tl_array_reserve(&set->bucket, &set->bucket_capacity, set->n_groups + 1, sizeof *set->bucket));
  size_t *match = set->bucket;
  for (size_t g = 0, h = 0; g < set->n_groups; ++g) {
    int32_t p = c[set->group[g]].particle;
    while (h < prev->n_groups && pc[prev->group[h]].particle < p) ++h;
    match[g] = (h < prev->n_groups && pc[prev->group[h]].particle == p) ? h : SIZE_MAX;
  }
  TL_PARALLEL_IF(ng > 2048, "omp parallel for schedule(dynamic, 64)",
    for (long g = 0; g < ng; ++g) {
      size_t g0 = set->group[g], g1 = set->group[g + 1];
      if (match[g] == SIZE_MAX) continue;
      size_t h = match[g];
      size_t h0 = prev->group[h], h1 = prev->group[h + 1];
      /* the same triangle first */
      for (size_t i = g0; i < g1; ++i) {
        long j = tl_find_triangle(pc, h0, h1, c[i].triangle);
        done[i] = j >= 0;
        if (j < 0) continue;
        used[j] = 1;
        c[i].force_prev = pc[j].force;
        if (hd) memcpy(set->history + i * hd, prev->history + (size_t)j * hd, hd * sizeof(double));
      }
      /* then contacts that moved to another triangle take over the nearest
       * contact that ended */
      for (size_t i = g0; i < g1; ++i) {
        if (done[i]) continue;
        long best = -1;
        double best_d2 = INFINITY;
        for (size_t j = h0; j < h1; ++j) {
          if (used[j]) continue;
          double d2 = tl_v3_norm2(tl_v3_sub(c[i].point, pc[j].point));
          if (d2 < best_d2) best_d2 = d2, best = (long)j;
        }
        if (best < 0) continue;
        used[best] = 1;
        c[i].force_prev = pc[best].force;
        if (hd) memcpy(set->history + i * hd, prev->history + (size_t)best * hd, hd * sizeof(double));
      }
    });
  return TL_OK;
}

void tl_tricontacts_apply_weights(TlTriContactSet *set)
{
  TlTriContactRecord *c = set->c;
  /* without the regions of Modification 1, every contact of a particle is
   * in one piece (seeds/001) */
  const int32_t *region = set->regions_valid ? set->region : NULL;
  long ng = (long)set->n_groups;
  TL_PARALLEL_IF(ng > 2048, "omp parallel for schedule(dynamic, 64)",
    for (long g = 0; g < ng; ++g) {
      size_t g0 = set->group[g], g1 = set->group[g + 1];
      if (g1 - g0 == 1) {
        c[g0].weight = 1.0;
        continue;
      }
      /* the weights within each piece first, from the unscaled forces */
      for (size_t i = g0; i < g1; ++i) {
        double sum = 0.0;
        size_t count = 0;
        for (size_t j = g0; j < g1; ++j)
          if (!region || region[j] == region[i]) sum += tl_v3_norm(c[j].force), ++count;
        c[i].weight = sum > 0.0 ? tl_v3_norm(c[i].force) / sum : 1.0 / (double)count;
      }
      for (size_t i = g0; i < g1; ++i) {
        c[i].force = tl_v3_scale(c[i].force, c[i].weight);
        c[i].torque = tl_v3_scale(c[i].torque, c[i].weight);
      }
    });
}

TlStatus tl_tricontacts_append_all(TlTriContactSet *dst, const TlTriContactSet *src)
{
  if (src->count == 0) return TL_OK;
  TL_CHECK(tl_array_reserve(&dst->c, &dst->capacity, dst->count + src->count, sizeof *dst->c));
  memcpy(dst->c + dst->count, src->c, src->count * sizeof *src->c);
  dst->count += src->count;
  return TL_OK;
}

TlStatus tl_tricontacts_remap(TlTriContactSet *set, const size_t *old_to_new, size_t n_old)
{
  size_t hd = set->history_doubles, m = 0;
  for (size_t i = 0; i < set->count; ++i) {
    size_t p = (size_t)set->c[i].particle;
    if (p >= n_old)
      TL_ERROR(TL_ERR_ARG, "wall contact %zu refers to particle %zu, beyond the %zu remapped", i, p, n_old);
    size_t q = old_to_new[p];
    if (q == SIZE_MAX) continue;
    if (q > (size_t)INT32_MAX) TL_ERROR(TL_ERR_ARG, "particle index %zu exceeds %d", q, INT32_MAX);
    set->c[m] = set->c[i];
    set->c[m].particle = (int32_t)q;
    if (hd) memmove(set->history + m * hd, set->history + i * hd, hd * sizeof(double));
    ++m;
  }
  set->count = m;
  set->regions_valid = 0;
  /* re-sort records and history together: insertion order by key through
   * a permutation kept in the scratch link array */
  TL_CHECK(tl_array_reserve(&set->link, &set->link_capacity, m, sizeof *set->link));
  int sorted = 1;
  for (size_t i = 1; i < m; ++i)
    if (tl_record_compare(&set->c[i - 1], &set->c[i]) > 0) sorted = 0;
  if (!sorted) {
    TlTriContactRecord *c = NULL;
    double *h = NULL;
    TlStatus status = TL_OK;
    TL_CHECK_GOTO(status, tl_calloc(&c, m, sizeof *c), fail);
    if (hd) TL_CHECK_GOTO(status, tl_calloc(&h, m * hd, sizeof *h), fail);
    /* tag each record with its position through `active`, sort, gather */
    for (size_t i = 0; i < m; ++i) {
      c[i] = set->c[i];
      c[i].active = (int32_t)i;
    }
    qsort(c, m, sizeof *c, tl_record_compare);
    for (size_t i = 0; i < m; ++i) {
      if (hd) memcpy(h + i * hd, set->history + (size_t)c[i].active * hd, hd * sizeof(double));
      c[i].active = 1;
    }
    memcpy(set->c, c, m * sizeof *c);
    if (hd) memcpy(set->history, h, m * hd * sizeof *h);
  fail:
    tl_free(&c);
    tl_free(&h);
    if (status != TL_OK) return status;
  }
  TL_CHECK(tl_tricontacts_build_groups(set));
  return TL_OK;
}
