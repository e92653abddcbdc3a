#include "tl_trisurface_bins.h"

#include <math.h>
#include <string.h>
#include "tl_memory.h"

void tl_tribins_free(TlTriBins *b)
{
  tl_free(&b->start);
  tl_free(&b->tri);
  tl_free(&b->bin_stamp);
  tl_free(&b->tri_stamp);
  tl_free(&b->selected);
  memset(b, 0, sizeof *b);
}

static inline int tl_bin_coord(const TlTriBins *b, double v, int k)
{
  double f = floor((v - tl_v3_get(b->lo, k)) / b->size);
  if (f < 0) return 0;
  if (f > b->n[k] - 1) return b->n[k] - 1;
  return (int)f;
}

TlStatus tl_tribins_build(TlTriBins *b, const TlTriSurface *s)
{
  if (b->built && b->built_version == s->version) return TL_OK;
  size_t nt = s->n_triangles;
  /* bin edge: the mean largest extent of a triangle box, enlarged until the
   * bins number at most about 4 per triangle (a flat surface fills one
   * layer of its box only) */
  double mean = 0.0;
  for (size_t t = 0; t < nt; ++t) {
    TlVec3 d = tl_v3_sub(s->box_hi[t], s->box_lo[t]);
    mean += fmax(d.x, fmax(d.y, d.z));
  }
  mean /= (double)nt;
  TlVec3 ext = tl_v3_sub(s->surface_hi, s->surface_lo);
  double size = mean > 0.0 ? mean : 1.0;
  for (;;) {
    double cells = 1.0;
    for (int k = 0; k < 3; ++k) cells *= fmax(1.0, ceil(tl_v3_get(ext, k) / size));
    if (cells <= 4.0 * (double)nt + 64.0) break;
    size *= 1.5;
  }
  b->size = size;
  b->lo = s->surface_lo;
  for (int k = 0; k < 3; ++k) b->n[k] = (int)fmax(1.0, ceil(tl_v3_get(ext, k) / size));
  size_t nb = (size_t)b->n[0] * (size_t)b->n[1] * (size_t)b->n[2];
  size_t old_cap = b->bin_capacity;
  TL_CHECK(tl_array_reserve(&b->start, &b->bin_capacity, nb + 1, sizeof *b->start));
  if (b->bin_capacity != old_cap || !b->bin_stamp) {
    TL_CHECK(tl_realloc(&b->bin_stamp, b->bin_capacity, sizeof *b->bin_stamp));
    memset(b->bin_stamp, 0, b->bin_capacity * sizeof *b->bin_stamp);
  }
  size_t old_tcap = b->tri_stamp_capacity;
  TL_CHECK(tl_array_reserve(&b->tri_stamp, &b->tri_stamp_capacity, nt, sizeof *b->tri_stamp));
  if (b->tri_stamp_capacity != old_tcap) memset(b->tri_stamp, 0, b->tri_stamp_capacity * sizeof *b->tri_stamp);
  b->n_bins = nb;
  memset(b->start, 0, (nb + 1) * sizeof *b->start);
  /* counting sort of (bin, triangle) entries */
  size_t entries = 0;
  for (size_t t = 0; t < nt; ++t) {
    int c0[3], c1[3];
    for (int k = 0; k < 3; ++k) {
      c0[k] = tl_bin_coord(b, tl_v3_get(s->box_lo[t], k), k);
      c1[k] = tl_bin_coord(b, tl_v3_get(s->box_hi[t], k), k);
    }
    for (int z = c0[2]; z <= c1[2]; ++z)
      for (int y = c0[1]; y <= c1[1]; ++y)
        for (int x = c0[0]; x <= c1[0]; ++x) {
          ++b->start[((size_t)z * (size_t)b->n[1] + (size_t)y) * (size_t)b->n[0] + (size_t)x + 1];
          ++entries;
        }
  }
  for (size_t i = 0; i < nb; ++i) b->start[i + 1] += b->start[i];
  TL_CHECK(tl_array_reserve(&b->tri, &b->tri_capacity, entries, sizeof *b->tri));
  for (size_t t = 0; t < nt; ++t) {
    int c0[3], c1[3];
    for (int k = 0; k < 3; ++k) {
      c0[k] = tl_bin_coord(b, tl_v3_get(s->box_lo[t], k), k);
      c1[k] = tl_bin_coord(b, tl_v3_get(s->box_hi[t], k), k);
    }
    for (int z = c0[2]; z <= c1[2]; ++z)
      for (int y = c0[1]; y <= c1[1]; ++y)
        for (int x = c0[0]; x <= c1[0]; ++x) {
          size_t id = ((size_t)z * (size_t)b->n[1] + (size_t)y) * (size_t)b->n[0] + (size_t)x;
          b->tri[b->start[id]++] = (int32_t)t;
        }
  }
  for (size_t i = nb; i > 0; --i) b->start[i] = b->start[i - 1];
  b->start[0] = 0;
  b->built = 1;
  b->built_version = s->version;
  return TL_OK;
}

/* Marks the bins that the extent [x - r, x + r] meets, collecting their
 * triangles once each. */
static TlStatus tl_tribins_mark(TlTriBins *b, const TlTriSurface *s, TlVec3 x, double r)
{
  TlVec3 lo = s->surface_lo, hi = s->surface_hi;
  if (x.x + r < lo.x || x.y + r < lo.y || x.z + r < lo.z || x.x - r > hi.x || x.y - r > hi.y || x.z - r > hi.z)
    return TL_OK;
  int c0[3], c1[3];
  for (int k = 0; k < 3; ++k) {
    c0[k] = tl_bin_coord(b, tl_v3_get(x, k) - r, k);
    c1[k] = tl_bin_coord(b, tl_v3_get(x, k) + r, k);
  }
  for (int z = c0[2]; z <= c1[2]; ++z)
    for (int y = c0[1]; y <= c1[1]; ++y)
      for (int xx = c0[0]; xx <= c1[0]; ++xx) {
        size_t id = ((size_t)z * (size_t)b->n[1] + (size_t)y) * (size_t)b->n[0] + (size_t)xx;
        if (b->bin_stamp[id] == b->now) continue;
        b->bin_stamp[id] = b->now;
        for (size_t e = b->start[id]; e < b->start[id + 1]; ++e) {
          int32_t t = b->tri[e];
          if (b->tri_stamp[t] == b->now) continue;
          b->tri_stamp[t] = b->now;
          TL_CHECK(tl_array_reserve(&b->selected, &b->selected_capacity, b->n_selected + 1, sizeof *b->selected));
          b->selected[b->n_selected++] = t;
        }
      }
  return TL_OK;
}

TlStatus tl_tribins_select(TlTriBins *b, const TlTriSurface *s, const TlDomain *domain, size_t n,
                           const TlVec3 *x, const double *radius, const uint8_t *motion, double margin)
{
  TL_CHECK(tl_tribins_build(b, s));
  b->n_selected = 0;
  if (++b->now == 0) {
    /* stamp wrapped around: clear once every 2^32 steps */
    memset(b->bin_stamp, 0, b->bin_capacity * sizeof *b->bin_stamp);
    memset(b->tri_stamp, 0, b->tri_stamp_capacity * sizeof *b->tri_stamp);
    b->now = 1;
  }
  /* periodic shifts: every combination of -1, 0, +1 cell vectors along the
   * periodic directions */
  TlVec3 shift[27];
  int n_shift = 0;
  int per[3] = {0, 0, 0};
  if (domain && domain->any_periodic)
    for (int k = 0; k < 3; ++k) per[k] = domain->periodic[k];
  for (int a = -per[0]; a <= per[0]; ++a)
    for (int c = -per[1]; c <= per[1]; ++c)
      for (int d = -per[2]; d <= per[2]; ++d) {
        TlVec3 v = tl_v3(0, 0, 0);
        if (a || c || d) {
          TlVec3 col0 = tl_v3(domain->h.m[0][0], domain->h.m[1][0], domain->h.m[2][0]);
          TlVec3 col1 = tl_v3(domain->h.m[0][1], domain->h.m[1][1], domain->h.m[2][1]);
          TlVec3 col2 = tl_v3(domain->h.m[0][2], domain->h.m[1][2], domain->h.m[2][2]);
          v = tl_v3_add(tl_v3_scale(col0, a), tl_v3_add(tl_v3_scale(col1, c), tl_v3_scale(col2, d)));
        }
        shift[n_shift++] = v;
      }
  for (size_t i = 0; i < n; ++i) {
    if (motion && motion[i] != 0) continue;
    for (int k = 0; k < n_shift; ++k) TL_CHECK(tl_tribins_mark(b, s, tl_v3_add(x[i], shift[k]), radius[i] + margin));
  }
  return TL_OK;
}
