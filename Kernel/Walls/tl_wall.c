/* The wall base type: construction by name, the calls every wall type
 * answers, and the registration of this folder's types. */
#include "tl_wall.h"

#include <string.h>
#include "tl_memory.h"
#include "tl_wall_trisurface.h"

TlStatus tl_walls_register_all(void)
{
  TL_CHECK(tl_wall_register_plane());
  TL_CHECK(tl_wall_register_trisurface());
  return TL_OK;
}

TlStatus tl_wall_register(const char *name, const char *description, TlWallConstructor create, const TlWallOps *ops,
                          const TlParam *params, int n_params)
{
  if (!name || !create || !ops)
    TL_ERROR(TL_ERR_ARG, "wall type '%s': a registered wall type needs a name, a constructor and ops",
             name ? name : "(null)");
  if (!ops->bounding_box || !ops->interact || !ops->destroy)
    TL_ERROR(TL_ERR_ARG, "wall type '%s': its ops need bounding_box, interact and destroy", name);
  if (!ops->prepare != !ops->interact_range)
    TL_ERROR(TL_ERR_ARG, "wall type '%s': its ops give %s without %s (a wall by particle ranges needs both)", name,
             ops->prepare ? "prepare" : "interact_range", ops->prepare ? "interact_range" : "prepare");
  for (int k = 0; k < n_params; ++k)
    if (params[k].offset % sizeof(double))
      TL_ERROR(TL_ERR_ARG, "wall type '%s': parameter '%s' at offset %zu is not a double of the parameter block", name,
               params[k].name, params[k].offset);
  TlTypeEntry e = {"wall", name, description, (TlConstructor)create, ops, params, n_params};
  return tl_registry_register(&e);
}

/* The names of a type's parameters, for error messages. */
static void param_names(const TlTypeEntry *e, char *buf, size_t size)
{
  buf[0] = '\0';
  for (int k = 0; k < e->n_params; ++k) {
    if (k) strncat(buf, ", ", size - strlen(buf) - 1);
    strncat(buf, e->params[k].name, size - strlen(buf) - 1);
  }
  if (!e->n_params) strncat(buf, "none", size - strlen(buf) - 1);
}

TlStatus tl_wall_create(const char *type, size_t n, const TlWallSetting *settings, TlWall **w)
{
  if (!type || !w || (n && !settings)) TL_ERROR(TL_ERR_ARG, "tl_wall_create: NULL argument");
  *w = NULL;
  const TlTypeEntry *e;
  TL_CHECK(tl_registry_lookup("wall", type, &e));
  if (!e->create)
    TL_ERROR(TL_ERR_UNSUPPORTED, "wall type '%s' is registered without a constructor (register it with tl_wall_register)",
             type);
  /* the parameter block: defaults, then the settings */
  size_t n_doubles = 1;
  for (int k = 0; k < e->n_params; ++k)
    if (e->params[k].offset / sizeof(double) + 1 > n_doubles) n_doubles = e->params[k].offset / sizeof(double) + 1;
  double *block = NULL;
  TL_CHECK(tl_calloc(&block, n_doubles, sizeof *block));
  for (int k = 0; k < e->n_params; ++k) block[e->params[k].offset / sizeof(double)] = e->params[k].def;
  char names[512];
  for (size_t s = 0; s < n; ++s) {
    const TlParam *p = tl_param_find(e->params, e->n_params, settings[s].name ? settings[s].name : "");
    double v = settings[s].value;
    if (!p) {
      tl_free(&block);
      param_names(e, names, sizeof names);
      TL_ERROR(TL_ERR_NOT_FOUND, "wall type '%s' has no parameter '%s' (its parameters: %s)", type,
               settings[s].name ? settings[s].name : "(null)", names);
    }
    if (!(v >= p->lo && v <= p->hi)) {
      tl_free(&block);
      TL_ERROR(TL_ERR_ARG, "wall type '%s': %s = %g %s outside [%g, %g]", type, p->name, v, p->unit ? p->unit : "",
               p->lo, p->hi);
    }
    block[p->offset / sizeof(double)] = v;
  }
  TlStatus s = ((TlWallConstructor)e->create)(block, w);
  tl_free(&block);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  if (!*w || !(*w)->ops) TL_ERROR(TL_ERR_STATE, "wall type '%s': its constructor returned no wall", type);
  return TL_OK;
}

TlStatus tl_wall_visit_contacts(const TlWall *w, const TlParticles *particles, TlWallVisitor visit, void *ctx)
{
  if (!w || !particles || !visit) TL_ERROR(TL_ERR_ARG, "tl_wall_visit_contacts: NULL argument");
  if (!w->ops->visit_contacts)
    TL_ERROR(TL_ERR_UNSUPPORTED, "wall '%s' is of type '%s', whose ops have no visit_contacts: its contacts cannot be "
             "visited", w->name, w->ops->header.name);
  return w->ops->visit_contacts(w, particles, visit, ctx);
}

void tl_wall_destroy(TlWall **w)
{
  if (!*w) return;
  (*w)->ops->destroy(*w);
  *w = NULL;
}

int tl_wall_is_bounded(const TlWall *w)
{
  TlVec3 lo, hi;
  w->ops->bounding_box(w, &lo, &hi);
  return tl_v3_isfinite(lo) && tl_v3_isfinite(hi);
}

int tl_wall_by_ranges(const TlWall *w) { return w->ops->prepare && w->ops->interact_range; }

TlStatus tl_wall_book_blocks(TlWall *w, const TlWallStep *step, const TlWallSums *sums, size_t nb, size_t stride)
{
  TlWallSums t;
  memset(&t, 0, sizeof t);
  for (size_t b = 0; b < nb; ++b) {
    const TlWallSums *s = sums + b * stride;
    if (s->status != TL_OK) return tl_error_trace(s->status, __FILE__, __LINE__);
    t.elastic += s->elastic;
    t.power += s->power;
    t.work += s->work;
    t.force = tl_v3_add(t.force, s->force);
    t.torque = tl_v3_add(t.torque, s->torque);
    t.n_contacts += s->n_contacts;
  }
  w->force = t.force;
  w->torque = t.torque;
  w->n_contacts = t.n_contacts;
  if (step->want_energy) {
    w->elastic_energy = t.elastic;
    w->contact_work += step->dt * t.power;
    w->work += step->dt * t.work;
  }
  return TL_OK;
}

TlStatus tl_wall_interact_blocks(TlWall *w, const TlWallStep *step)
{
  if (!tl_wall_by_ranges(w))
    TL_ERROR(TL_ERR_UNSUPPORTED, "wall '%s' of type '%s' is not evaluated by particle ranges (no prepare or "
             "interact_range)", w->name, w->ops->header.name);
  TL_CHECK(w->ops->prepare(w, step));
  /* the blocks' sums one after another, each added as the world adds it */
  const size_t n = step->particles->n;
  TlWallSums t, s;
  memset(&t, 0, sizeof t);
  for (size_t lo = 0; lo < n; lo += TL_WALL_BLOCK) {
    memset(&s, 0, sizeof s);
    w->ops->interact_range(w, step, lo, lo + TL_WALL_BLOCK < n ? lo + TL_WALL_BLOCK : n, &s);
    if (s.status != TL_OK) return tl_error_trace(s.status, __FILE__, __LINE__);
    t.elastic += s.elastic;
    t.power += s.power;
    t.work += s.work;
    t.force = tl_v3_add(t.force, s.force);
    t.torque = tl_v3_add(t.torque, s.torque);
    t.n_contacts += s.n_contacts;
  }
  return tl_wall_book_blocks(w, step, &t, 1, 1);
}
