/* Contact laws composed from parts (tl_contact_part.h): creation by the
 * parts' names, parameters by name, set-up, and the two evaluations of the
 * base interface, the batch (walls, couplings) and the chunk (the world's
 * particle loop), both running the parts' chunk loops in order. */
#include "tl_contact_law.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "tl_contact_part.h"
#include "tl_memory.h"
#include "tl_options.h"
#include "tl_registry.h"

const char *const tl_contact_part_kinds[TL_CONTACT_N_KINDS] = {"contact_normal", "contact_adhesion",
                                                               "contact_friction", "contact_rolling"};
static const char *const kind_words[TL_CONTACT_N_KINDS] = {"normal", "adhesion", "friction", "rolling"};

typedef struct {
  TlContactLaw base;
  TlContactPart *part[TL_CONTACT_N_KINDS]; /* NULL: absent */
  const TlContactPart *run[TL_CONTACT_N_KINDS]; /* the active parts, in order */
  int run_kind[TL_CONTACT_N_KINDS];
  int n_run;
  int friction, rolling; /* active */
  int ready;
} Composed;

TlStatus tl_contact_part_register(const TlContactPartOps *ops)
{
  if (!ops || !ops->header.kind || !ops->header.name) TL_ERROR(TL_ERR_ARG, "contact part: NULL ops or name");
  int kind = -1;
  for (int k = 0; k < TL_CONTACT_N_KINDS; ++k)
    if (!strcmp(ops->header.kind, tl_contact_part_kinds[k])) kind = k;
  if (kind < 0)
    TL_ERROR(TL_ERR_ARG, "contact part '%s': kind '%s' is none of contact_normal, contact_friction, "
             "contact_rolling, contact_adhesion", ops->header.name, ops->header.kind);
  if (!strcmp(ops->header.name, "none"))
    TL_ERROR(TL_ERR_ARG, "contact part: 'none' is reserved (it means no part)");
  if (ops->size < sizeof(TlContactPart) || !ops->setup || !ops->evaluate)
    TL_ERROR(TL_ERR_ARG, "contact part '%s': needs size >= sizeof(TlContactPart), setup and evaluate",
             ops->header.name);
  if (kind == TL_CONTACT_NORMAL && (!ops->max_stiffness || !ops->max_damping || !ops->tangential_scale))
    TL_ERROR(TL_ERR_ARG, "normal contact part '%s': needs max_stiffness, max_damping and tangential_scale",
             ops->header.name);
  TlTypeEntry e = {ops->header.kind, ops->header.name, ops->header.description, NULL, ops, ops->params,
                   ops->n_params};
  return tl_registry_register(&e);
}

/* ------------------------------------------------------------ evaluation */

static inline TlStatus run_part(const TlContactPart *p, TlContactChunk *c, const int HOT)
{
  return HOT && p->ops->evaluate_hot ? p->ops->evaluate_hot(p, c) : p->ops->evaluate(p, c);
}

/* The normal and adhesion parts, the normal force -fn n, then the friction
 * part adding the tangential force and the rolling part setting the couple.
 * The normal force is a pass of its own so that its product is rounded
 * before the tangential force is added, as in a single loop where friction
 * is optional: the sum then rounds the same way in every build. */
static inline TlStatus run_parts(const Composed *law, TlContactChunk *c, const int HOT)
{
  int k = 0;
  for (; k < law->n_run && law->run_kind[k] <= TL_CONTACT_ADHESION; ++k) TL_CHECK(run_part(law->run[k], c, HOT));
  const size_t n = c->n;
  for (size_t q = 0; q < n; ++q)
    if (c->on[q]) c->force[q] = tl_v3_scale(c->normal[q], -c->fn[q]);
  if (!law->rolling)
    for (size_t q = 0; q < n; ++q) c->couple[q] = (TlVec3){0, 0, 0};
  for (; k < law->n_run; ++k) TL_CHECK(run_part(law->run[k], c, HOT));
  return TL_OK;
}

TL_CONTACT_HOT_CLONES static TlStatus composed_evaluate_chunk(const TlContactLaw *base, TlContactChunk *c)
{
  const Composed *law = (const Composed *)base;
  if (!law->ready) TL_ERROR(TL_ERR_STATE, "contact law: evaluated before tl_contact_law_setup");
  return run_parts(law, c, 1);
}

static TlStatus composed_evaluate(const TlContactLaw *base, const TlContactBatch *b)
{
  const Composed *law = (const Composed *)base;
  if (!law->ready) TL_ERROR(TL_ERR_STATE, "contact law: evaluated before tl_contact_law_setup");
  TlContactChunk c;
  TlVec3 spin_mean[TL_CONTACT_CHUNK], spin_rel[TL_CONTACT_CHUNK];
  c.dt = b->dt;
  c.want_energy = b->want_energy;
  c.spin_mean = spin_mean;
  c.spin_rel = spin_rel;
  for (size_t start = 0; start < b->n; start += TL_CONTACT_CHUNK) {
    const size_t m = b->n - start < TL_CONTACT_CHUNK ? b->n - start : TL_CONTACT_CHUNK;
    const TlContactGeometry *g = b->geometry + start;
    c.n = m;
    for (size_t q = 0; q < m; ++q) {
      c.normal[q] = g[q].normal;
      c.overlap[q] = g[q].overlap;
      c.vrel[q] = g[q].vrel;
      spin_mean[q] = g[q].spin_mean;
      spin_rel[q] = g[q].spin_rel;
      c.meff[q] = g[q].meff;
      c.reff[q] = g[q].reff;
      c.history[q] = g[q].history;
      c.bonded[q] = g[q].bonded != 0;
    }
    TL_CHECK(run_parts(law, &c, 0));
    TlContactResult *r = b->result + start;
    for (size_t q = 0; q < m; ++q) {
      if (!c.on[q]) {
        r[q].force = r[q].couple = (TlVec3){0, 0, 0};
        r[q].elastic_energy = r[q].power = 0.0;
        continue;
      }
      r[q].force = c.force[q];
      r[q].couple = c.couple[q];
      if (b->want_energy) {
        r[q].elastic_energy = c.energy[q];
        r[q].power = tl_v3_dot(r[q].force, g[q].vrel) + tl_v3_dot(r[q].couple, g[q].spin_rel);
      }
    }
  }
  return TL_OK;
}

static double composed_max_stiffness(const TlContactLaw *base, double reff, double overlap)
{
  const Composed *law = (const Composed *)base;
  const TlContactPart *n = law->part[TL_CONTACT_NORMAL], *f = law->part[TL_CONTACT_FRICTION];
  double k = n->ops->max_stiffness(n, reff, overlap);
  double t = law->friction && f->ops->max_tangential_stiffness ? f->ops->max_tangential_stiffness(f, reff, overlap)
                                                                : 0.0;
  return k > t ? k : t;
}

static double composed_max_damping(const TlContactLaw *base, double meff, double reff, double overlap)
{
  const TlContactPart *n = ((const Composed *)base)->part[TL_CONTACT_NORMAL];
  return n->ops->max_damping(n, meff, reff, overlap);
}

static void composed_describe(const TlContactLaw *base, char *text, size_t size)
{
  const Composed *law = (const Composed *)base;
  size_t used = 0;
  text[0] = '\0';
  for (int k = 0; k < TL_CONTACT_N_KINDS; ++k) {
    const TlContactPart *p = law->part[k];
    if (!p || (k != TL_CONTACT_NORMAL && !p->active)) continue;
    int w = snprintf(text + used, size - used, "%s%s %s:", used ? "; " : "", kind_words[k], p->ops->header.name);
    if (w < 0 || (size_t)w >= size - used) return;
    used += (size_t)w;
    for (int i = 0; i < p->ops->n_params; ++i) {
      const TlParam *q = &p->ops->params[i];
      w = snprintf(text + used, size - used, " %s=%g%s%s", q->name, *(const double *)((const char *)p + q->offset),
                   q->unit[0] && strcmp(q->unit, "1") ? " " : "", strcmp(q->unit, "1") ? q->unit : "");
      if (w < 0 || (size_t)w >= size - used) return;
      used += (size_t)w;
    }
  }
}

static void composed_destroy(TlContactLaw *base)
{
  Composed *law = (Composed *)base;
  for (int k = 0; k < TL_CONTACT_N_KINDS; ++k)
    if (law->part[k]) {
      if (law->part[k]->ops->destroy) law->part[k]->ops->destroy(law->part[k]);
      tl_free(&law->part[k]);
    }
  tl_free(&law);
}

static TlStatus composed_set(TlContactLaw *base, const char *name, double value);
static TlStatus composed_get(const TlContactLaw *base, const char *name, double *value);
static TlStatus composed_setup(TlContactLaw *base);

static const TlContactLawOps composed_ops = {
    {"contact_law", "composed", "a normal part with optional friction, rolling and adhesion parts"},
    composed_evaluate, composed_evaluate_chunk, composed_max_stiffness, composed_max_damping, composed_describe,
    composed_destroy, composed_set, composed_get, composed_setup};

/* ------------------------------------------------------------ life cycle */

static int absent(const char *name) { return !name || !name[0] || !strcmp(name, "none"); }

static TlStatus create_part(int kind, const char *name, TlContactPart **out)
{
  const TlTypeEntry *e;
  TL_CHECK(tl_registry_lookup(tl_contact_part_kinds[kind], name, &e));
  const TlContactPartOps *ops = e->ops;
  char *mem;
  TL_CHECK(tl_calloc(&mem, 1, ops->size));
  TlContactPart *p = (TlContactPart *)mem;
  p->ops = ops;
  for (int i = 0; i < ops->n_params; ++i) *(double *)(mem + ops->params[i].offset) = ops->params[i].def;
  *out = p;
  return TL_OK;
}

TlStatus tl_contact_law_create(const char *normal, const char *friction, const char *rolling, const char *adhesion,
                               TlContactLaw **out)
{
  if (!out) TL_ERROR(TL_ERR_ARG, "tl_contact_law_create: NULL output");
  *out = NULL;
  if (absent(normal)) TL_ERROR(TL_ERR_ARG, "contact law: a normal part is required (linear, hertz, ...)");
  const char *names[TL_CONTACT_N_KINDS];
  names[TL_CONTACT_NORMAL] = normal;
  names[TL_CONTACT_FRICTION] = friction;
  names[TL_CONTACT_ROLLING] = rolling;
  names[TL_CONTACT_ADHESION] = adhesion;
  Composed *law;
  TL_CHECK(TL_NEW(law));
  law->base.ops = &composed_ops;
  TlStatus s = TL_OK;
  for (int k = 0; k < TL_CONTACT_N_KINDS && s == TL_OK; ++k)
    if (!absent(names[k])) s = create_part(k, names[k], &law->part[k]);
  /* composition rule: a parameter name belongs to one part of the law */
  for (int a = 0; a < TL_CONTACT_N_KINDS && s == TL_OK; ++a)
    for (int b = a + 1; b < TL_CONTACT_N_KINDS && s == TL_OK && law->part[a]; ++b) {
      if (!law->part[b]) continue;
      const TlContactPartOps *pa = law->part[a]->ops, *pb = law->part[b]->ops;
      for (int i = 0; i < pa->n_params && s == TL_OK; ++i)
        if (tl_param_find(pb->params, pb->n_params, pa->params[i].name)) {
          tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "contact law: parts '%s' and '%s' both have a parameter '%s'; they cannot be composed",
                       pa->header.name, pb->header.name, pa->params[i].name);
          s = TL_ERR_ARG;
        }
    }
  if (s != TL_OK) {
    composed_destroy(&law->base);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  *out = &law->base;
  return TL_OK;
}

static const TlParam *find_param(const Composed *law, const char *name, int *kind)
{
  for (int k = 0; k < TL_CONTACT_N_KINDS; ++k) {
    const TlContactPart *p = law->part[k];
    if (!p) continue;
    const TlParam *q = tl_param_find(p->ops->params, p->ops->n_params, name);
    if (q) {
      *kind = k;
      return q;
    }
  }
  return NULL;
}

static TlStatus composed_set(TlContactLaw *base, const char *name, double value)
{
  Composed *law = (Composed *)base;
  int k;
  const TlParam *q = find_param(law, name, &k);
  if (!q) TL_ERROR(TL_ERR_NOT_FOUND, "contact law: none of its parts has a parameter '%s'", name);
  TlContactPart *p = law->part[k];
  if (!(value >= q->lo && value <= q->hi))
    TL_ERROR(TL_ERR_ARG, "contact law: %s part '%s': %s = %g %s outside [%g, %g]", kind_words[k],
             p->ops->header.name, name, value, q->unit, q->lo, q->hi);
  *(double *)((char *)p + q->offset) = value;
  law->ready = 0;
  return TL_OK;
}

static TlStatus composed_get(const TlContactLaw *base, const char *name, double *value)
{
  const Composed *law = (const Composed *)base;
  int k;
  const TlParam *q = find_param(law, name, &k);
  if (!q) TL_ERROR(TL_ERR_NOT_FOUND, "contact law: none of its parts has a parameter '%s'", name);
  *value = *(const double *)((const char *)law->part[k] + q->offset);
  return TL_OK;
}

static TlStatus composed_setup(TlContactLaw *base)
{
  Composed *law = (Composed *)base;
  TlContactPart *n = law->part[TL_CONTACT_NORMAL];
  law->ready = 0;
  law->n_run = 0;
  law->base.history_doubles = 0;
  law->base.needs_rotation = 0;
  law->base.lever_radius = 0;
  law->base.ignores_spins = 1;
  for (int k = 0; k < TL_CONTACT_N_KINDS; ++k) {
    TlContactPart *p = law->part[k];
    if (!p) continue;
    p->normal = n;
    p->history_doubles = 0;
    p->needs_rotation = p->bonded = p->active = p->lever_radius = p->ignores_spins = 0;
    TL_CHECK(p->ops->setup(p, k == TL_CONTACT_NORMAL ? NULL : n));
    if (k == TL_CONTACT_NORMAL) p->active = 1;
    if (!p->active) continue;
    p->history_offset = law->base.history_doubles;
    law->base.history_doubles += p->history_doubles;
    law->base.needs_rotation |= p->needs_rotation;
    law->base.lever_radius |= p->lever_radius;
    law->base.ignores_spins &= p->ignores_spins;
    law->run_kind[law->n_run] = k;
    law->run[law->n_run++] = p;
  }
  law->base.bonded = n->bonded;
  law->friction = law->part[TL_CONTACT_FRICTION] && law->part[TL_CONTACT_FRICTION]->active;
  law->rolling = law->part[TL_CONTACT_ROLLING] && law->part[TL_CONTACT_ROLLING]->active;
  law->ready = 1;
  return TL_OK;
}

TlStatus tl_contact_law_set(TlContactLaw *law, const char *name, double value)
{
  if (!law || !name) TL_ERROR(TL_ERR_ARG, "tl_contact_law_set: NULL argument");
  if (!law->ops->set) TL_ERROR(TL_ERR_UNSUPPORTED, "contact law '%s' has no parameters by name", law->ops->header.name);
  if (!isfinite(value)) TL_ERROR(TL_ERR_ARG, "contact law: parameter %s = %g is not finite", name, value);
  return law->ops->set(law, name, value);
}

TlStatus tl_contact_law_get(const TlContactLaw *law, const char *name, double *value)
{
  if (!law || !name || !value) TL_ERROR(TL_ERR_ARG, "tl_contact_law_get: NULL argument");
  if (!law->ops->get) TL_ERROR(TL_ERR_UNSUPPORTED, "contact law '%s' has no parameters by name", law->ops->header.name);
  return law->ops->get(law, name, value);
}

TlStatus tl_contact_law_setup(TlContactLaw *law)
{
  if (!law) TL_ERROR(TL_ERR_ARG, "tl_contact_law_setup: NULL law");
  return law->ops->setup ? law->ops->setup(law) : TL_OK;
}

void tl_contact_law_destroy(TlContactLaw **law)
{
  if (!law || !*law) return;
  (*law)->ops->destroy(*law);
  *law = NULL;
}

TlStatus tl_contact_law_evaluate_one(const TlContactLaw *law, const TlContactGeometry *g, double dt,
                                     TlContactResult *r)
{
  TlContactBatch b = {1, g, r, dt, 1};
  return law->ops->evaluate(law, &b);
}

TlStatus tl_contact_law_build(const TlContactSpec *spec, TlContactLaw **out)
{
  if (!spec || !out) TL_ERROR(TL_ERR_ARG, "tl_contact_law_build: NULL argument");
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_create(absent(spec->normal) ? "linear" : spec->normal, spec->friction, spec->rolling,
                                 spec->adhesion, &law));
  TlStatus s = TL_OK;
  for (int i = 0; i < spec->n_values && s == TL_OK; ++i) s = tl_contact_law_set(law, spec->values[i].name, spec->values[i].value);
  if (s == TL_OK) s = tl_contact_law_setup(law);
  if (s != TL_OK) {
    tl_contact_law_destroy(&law);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  *out = law;
  return TL_OK;
}

/* ---------------------------------------------------------------- options */

enum { MAX_CHOICES = 32 };

static TlStatus choose(TlOptions *o, int kind, const char *option, const char *def, const char **name)
{
  const char *choices[MAX_CHOICES + 2];
  int n = 0;
  if (kind != TL_CONTACT_NORMAL) choices[n++] = "none";
  for (size_t i = 0; n < MAX_CHOICES; ++i) {
    const TlTypeEntry *e = tl_registry_entry(tl_contact_part_kinds[kind], i);
    if (!e) break;
    choices[n++] = e->name;
  }
  choices[n] = NULL;
  char help[128];
  snprintf(help, sizeof help, "%s part of the contact law", kind_words[kind]);
  int index;
  TL_CHECK(tl_options_get_choice(o, option, absent(def) ? (kind == TL_CONTACT_NORMAL ? "linear" : "none") : def,
                                 choices, help, &index));
  *name = choices[index];
  return TL_OK;
}

static TlStatus from_options(TlOptions *o, const TlContactSpec *d, TlContactLaw **out)
{
  static const TlContactSpec none = {NULL, NULL, NULL, NULL, NULL, 0};
  if (!d) d = &none;
  const char *names[TL_CONTACT_N_KINDS] = {NULL, NULL, NULL, NULL};
  TL_CHECK(choose(o, TL_CONTACT_NORMAL, "-contact", d->normal, &names[TL_CONTACT_NORMAL]));
  TL_CHECK(choose(o, TL_CONTACT_FRICTION, "-friction", d->friction, &names[TL_CONTACT_FRICTION]));
  TL_CHECK(choose(o, TL_CONTACT_ROLLING, "-rolling", d->rolling, &names[TL_CONTACT_ROLLING]));
  TL_CHECK(choose(o, TL_CONTACT_ADHESION, "-adhesion", d->adhesion, &names[TL_CONTACT_ADHESION]));
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_create(names[TL_CONTACT_NORMAL], names[TL_CONTACT_FRICTION], names[TL_CONTACT_ROLLING],
                                 names[TL_CONTACT_ADHESION], &law));
  const Composed *c = (const Composed *)law;
  TlStatus s = TL_OK;
  for (int k = 0; k < TL_CONTACT_N_KINDS && s == TL_OK; ++k) {
    const TlContactPart *p = c->part[k];
    if (!p) continue;
    for (int i = 0; i < p->ops->n_params && s == TL_OK; ++i) {
      const TlParam *q = &p->ops->params[i];
      double def = q->def, v;
      for (int j = 0; j < d->n_values; ++j)
        if (!strcmp(d->values[j].name, q->name)) def = d->values[j].value;
      char option[96], help[512];
      snprintf(option, sizeof option, "-contact_%s", q->name);
      snprintf(help, sizeof help, "%s %s: %s", kind_words[k], p->ops->header.name, q->help);
      s = tl_options_get_real(o, option, def, q->lo, q->hi, q->unit, help, &v);
      if (s == TL_OK) s = tl_contact_law_set(law, q->name, v);
    }
  }
  if (s == TL_OK) s = tl_contact_law_setup(law);
  if (s != TL_OK) {
    tl_contact_law_destroy(&law);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  *out = law;
  return TL_OK;
}

/* The law's options under their own heading in -help. */
TlStatus tl_contact_law_from_options(TlOptions *o, const TlContactSpec *d, TlContactLaw **out)
{
  TL_CHECK(tl_options_begin_group(o, "Contact law"));
  TlStatus s = from_options(o, d, out);
  tl_options_end_group(o);
  return s == TL_OK ? TL_OK : tl_error_trace(s, __FILE__, __LINE__);
}

TlStatus tl_contact_register_linear(void);
TlStatus tl_contact_register_hertz(void);
TlStatus tl_contact_register_coulomb(void);
TlStatus tl_contact_register_rolling(void);
TlStatus tl_contact_register_adhesion(void);

TlStatus tl_contact_register_all(void)
{
  TL_CHECK(tl_contact_register_linear());
  TL_CHECK(tl_contact_register_hertz());
  TL_CHECK(tl_contact_register_coulomb());
  TL_CHECK(tl_contact_register_rolling());
  TL_CHECK(tl_contact_register_adhesion());
  return TL_OK;
}
