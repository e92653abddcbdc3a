#include "tl_contact_list.h"

#include <string.h>
#include "tl_memory.h"

TlStatus tl_contact_list_init(TlContactList *c, size_t history_doubles)
{
  memset(c, 0, sizeof *c);
  c->history_doubles = history_doubles;
  return TL_OK;
}

void tl_contact_list_free(TlContactList *c)
{
  tl_free(&c->i); tl_free(&c->j); tl_free(&c->law); tl_free(&c->touching);
  tl_free(&c->force); tl_free(&c->history); tl_free(&c->keys); tl_free(&c->slots);
  memset(c, 0, sizeof *c);
}

TlStatus tl_contact_list_reserve(TlContactList *c, size_t n)
{
  if (n <= c->capacity) return TL_OK;
  size_t cap = c->capacity ? c->capacity : 256;
  while (cap < n) cap *= 2;
  TL_CHECK(tl_realloc(&c->i, cap, sizeof *c->i));
  TL_CHECK(tl_realloc(&c->j, cap, sizeof *c->j));
  TL_CHECK(tl_realloc(&c->law, cap, sizeof *c->law));
  TL_CHECK(tl_realloc(&c->touching, cap, sizeof *c->touching));
  TL_CHECK(tl_realloc(&c->force, cap, sizeof *c->force));
  if (c->history_doubles) TL_CHECK(tl_realloc(&c->history, cap * c->history_doubles, sizeof *c->history));
  c->capacity = cap;
  return TL_OK;
}

TlStatus tl_contact_list_push(TlContactList *c, uint32_t i, uint32_t j, int law, size_t *k)
{
  if (c->n >= c->capacity) TL_CHECK(tl_contact_list_reserve(c, c->n + 1));
  size_t m = c->n++;
  c->i[m] = i < j ? i : j;
  c->j[m] = i < j ? j : i;
  c->law[m] = (uint8_t)law;
  c->touching[m] = 0;
  c->force[m] = (TlVec3){0, 0, 0};
  if (c->history_doubles) memset(c->history + m * c->history_doubles, 0, c->history_doubles * sizeof *c->history);
  if (k) *k = m;
  return TL_OK;
}

static inline uint64_t pair_key(uint32_t i, uint32_t j)
{
  return i < j ? ((uint64_t)i << 32) | j : ((uint64_t)j << 32) | i;
}

static inline size_t hash64(uint64_t k)
{
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdULL;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53ULL;
  k ^= k >> 33;
  return (size_t)k;
}

TlStatus tl_contact_list_index(TlContactList *c, int touching_only)
{
  size_t m = 0;
  for (size_t k = 0; k < c->n; ++k) m += !touching_only || c->touching[k];
  size_t use = 16;
  while (use < 2 * m + 16) use *= 2;
  if (use > c->hash_allocated) {
    TL_CHECK(tl_realloc(&c->keys, use, sizeof *c->keys));
    TL_CHECK(tl_realloc(&c->slots, use, sizeof *c->slots));
    c->hash_allocated = use;
  }
  c->hash_capacity = use;
  memset(c->slots, 0, use * sizeof *c->slots);
  for (size_t k = 0; k < c->n; ++k) {
    if (touching_only && !c->touching[k]) continue;
    uint64_t key = pair_key(c->i[k], c->j[k]);
    size_t s = hash64(key) & (use - 1);
    while (c->slots[s]) s = (s + 1) & (use - 1);
    c->keys[s] = key;
    c->slots[s] = (uint32_t)(k + 1);
  }
  return TL_OK;
}

size_t tl_contact_list_find(const TlContactList *c, uint32_t i, uint32_t j)
{
  if (!c->hash_capacity) return SIZE_MAX;
  uint64_t key = pair_key(i, j);
  size_t mask = c->hash_capacity - 1, s = hash64(key) & mask;
  while (c->slots[s]) {
    if (c->keys[s] == key) return c->slots[s] - 1;
    s = (s + 1) & mask;
  }
  return SIZE_MAX;
}

void tl_contact_list_transfer(TlContactList *to, const TlContactList *from)
{
  size_t hd = to->history_doubles;
  for (size_t k = 0; k < to->n; ++k) {
    size_t o = tl_contact_list_find(from, to->i[k], to->j[k]);
    if (o == SIZE_MAX) continue;
    int swapped = from->i[o] != to->i[k];
    to->touching[k] = from->touching[o];
    to->force[k] = swapped ? tl_v3_neg(from->force[o]) : from->force[o];
    if (hd && from->history_doubles == hd) {
      const double *src = from->history + o * hd;
      double *dst = to->history + k * hd;
      for (size_t q = 0; q < hd; ++q) dst[q] = swapped ? -src[q] : src[q];
    }
  }
}
