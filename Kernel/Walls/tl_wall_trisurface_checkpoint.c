/* Checkpoint of a triangulated surface wall: the vertex state and the kept
 * contacts with their history, for a bit-exact restart. */
#include <math.h>
#include <stddef.h>
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

/* Vertex state finite; each kept contact names a particle (>= 0), a
 * triangle of the surface, a feature of a triangle, with finite values. */
static TlStatus check_state(const TlWall *w, const char *b, const TlTriCheckpointHeader *h, size_t n_triangles)
{
  size_t nx = 6 * h->n_vertices;
  for (size_t k = 0; k < nx; ++k) {
    double v;
    memcpy(&v, b + k * sizeof v, sizeof v);
    if (!isfinite(v))
      TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint: vertex %s %zu component %zu is %g, not a finite number", w->name,
               k < nx / 2 ? "position" : "velocity", (k % (nx / 2)) / 3, k % 3, v);
  }
  b += nx * sizeof(double);
  for (size_t k = 0; k < h->n_contacts; ++k) {
    TlTriContactRecord rec;
    memcpy(&rec, b + k * sizeof rec, sizeof rec);
    if (rec.particle < 0 || rec.triangle < 0 || (size_t)rec.triangle >= n_triangles || rec.feature < 0 ||
        rec.feature > 6)
      TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint: contact %zu joins particle %d and triangle %d (feature %d); "
               "the surface has %zu triangles", w->name, k, (int)rec.particle, (int)rec.triangle, (int)rec.feature,
               n_triangles);
    const double *d = &rec.point.x;
    for (size_t q = 0; q < (sizeof rec - offsetof(TlTriContactRecord, point)) / sizeof(double); ++q)
      if (!isfinite(d[q]))
        TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint: contact %zu value %zu is %g, not a finite number", w->name, k, q,
                 d[q]);
  }
  b += h->n_contacts * sizeof(TlTriContactRecord);
  for (size_t k = 0; k < h->n_contacts * h->history_doubles; ++k) {
    double v;
    memcpy(&v, b + k * sizeof v, sizeof v);
    if (!isfinite(v)) TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint: history value %zu is %g, not a finite number", w->name, k, v);
  }
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
  if (h.history_doubles != c->history_doubles)
    TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint keeps %llu history doubles per contact; its law keeps %zu", w->name,
             (unsigned long long)h.history_doubles, c->history_doubles);
  /* The count bounded by the buffer before it is multiplied (no overflow). */
  if (h.n_contacts > size / sizeof(TlTriContactRecord))
    TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint of %zu bytes cannot hold %llu contacts", w->name, size,
             (unsigned long long)h.n_contacts);
  size_t need = sizeof h + 2 * h.n_vertices * sizeof(TlVec3) + h.n_contacts * sizeof(TlTriContactRecord) +
                h.n_contacts * h.history_doubles * sizeof(double);
  if (size != need) TL_ERROR(TL_ERR_FORMAT, "wall '%s' checkpoint has %zu bytes, expected %zu", w->name, size, need);
  TL_CHECK(check_state(w, b, &h, t->surface->n_triangles));
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
