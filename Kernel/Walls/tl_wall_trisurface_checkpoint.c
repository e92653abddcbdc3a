/* Checkpoint of a triangulated surface wall: the vertex state and the kept
 * contacts with their history, for a bit-exact restart. */
#include <stdint.h>
#include <string.h>
#include "tl_memory.h"
#include "tl_wall_trisurface_private.h"

/* Checkpoint: vertex positions and velocities, then the kept contacts and
 * their history, as raw bytes (bit-exact restart). */
typedef struct {
  uint64_t n_vertices, n_contacts, history_doubles;
} TlTriCheckpointHeader;

size_t tl_wall_trisurface_checkpoint_size(const TlWall *w)
{
  const TlWallTriSurface *t = (const TlWallTriSurface *)w;
  const TlTriContactSet *c = t->current;
  if (!t->surface) return 0; /* refused by save */
  return sizeof(TlTriCheckpointHeader) + 2 * t->surface->n_vertices * sizeof(TlVec3) +
         c->count * sizeof(TlTriContactRecord) + c->count * c->history_doubles * sizeof(double);
}

TlStatus tl_wall_trisurface_checkpoint_save(const TlWall *w, void *buffer, size_t size)
{
  const TlWallTriSurface *t = (const TlWallTriSurface *)w;
  const TlTriContactSet *c = t->current;
  TL_REQUIRE_SURFACE(t);
  size_t need = tl_wall_trisurface_checkpoint_size(w);
  if (size < need) TL_ERROR(TL_ERR_ARG, "wall '%s' checkpoint buffer of %zu bytes, need %zu", w->name, size, need);
  char *b = buffer;
  TlTriCheckpointHeader h = {t->surface->n_vertices, c->count, c->history_doubles};
  memcpy(b, &h, sizeof h), b += sizeof h;
  memcpy(b, t->surface->x, t->surface->n_vertices * sizeof(TlVec3)), b += t->surface->n_vertices * sizeof(TlVec3);
  memcpy(b, t->surface->v, t->surface->n_vertices * sizeof(TlVec3)), b += t->surface->n_vertices * sizeof(TlVec3);
  if (c->count) memcpy(b, c->c, c->count * sizeof *c->c), b += c->count * sizeof *c->c;
  if (c->count && c->history_doubles) memcpy(b, c->history, c->count * c->history_doubles * sizeof(double));
  return TL_OK;
}

TlStatus tl_wall_trisurface_checkpoint_load(TlWall *w, const void *buffer, size_t size)
{
  TlWallTriSurface *t = (TlWallTriSurface *)w;
  TlTriContactSet *c = t->current;
  const char *b = buffer;
  TlTriCheckpointHeader h;
  TL_REQUIRE_SURFACE(t);
  if (size < sizeof h) TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint of %zu bytes is truncated", w->name, size);
  memcpy(&h, b, sizeof h), b += sizeof h;
  if (h.n_vertices != t->surface->n_vertices)
    TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint has %llu vertices, the surface %zu", w->name,
             (unsigned long long)h.n_vertices, t->surface->n_vertices);
  size_t need = sizeof h + 2 * h.n_vertices * sizeof(TlVec3) + h.n_contacts * sizeof(TlTriContactRecord) +
                h.n_contacts * h.history_doubles * sizeof(double);
  if (size != need) TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint has %zu bytes, expected %zu", w->name, size, need);
  memcpy(t->surface->x, b, h.n_vertices * sizeof(TlVec3)), b += h.n_vertices * sizeof(TlVec3);
  memcpy(t->surface->v, b, h.n_vertices * sizeof(TlVec3)), b += h.n_vertices * sizeof(TlVec3);
  TL_CHECK(tl_trisurface_update(t->surface));
  tl_tricontacts_clear(c);
  TL_CHECK(tl_array_reserve(&c->c, &c->capacity, h.n_contacts, sizeof *c->c));
  if (h.n_contacts) memcpy(c->c, b, h.n_contacts * sizeof *c->c), b += h.n_contacts * sizeof *c->c;
  c->count = h.n_contacts;
  c->history_doubles = h.history_doubles;
  if (h.n_contacts && h.history_doubles) {
    TL_CHECK(tl_array_reserve(&c->history, &c->history_capacity, h.n_contacts * h.history_doubles, sizeof(double)));
    memcpy(c->history, b, h.n_contacts * h.history_doubles * sizeof(double));
  }
  TL_CHECK(tl_tricontacts_sort(c));
  t->list_valid = 0;
  return TL_OK;
}
