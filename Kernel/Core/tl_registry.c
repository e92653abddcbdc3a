#include "tl_registry.h"

#include <string.h>

#include "tl_init.h"
#include "tl_memory.h"

static TlTypeEntry *tl_entries;
static size_t tl_n_entries, tl_cap_entries;

TlStatus tl_registry_register(const TlTypeEntry *e)
{
  if (!e || !e->kind || !e->name || !e->kind[0] || !e->name[0])
    TL_ERROR(TL_ERR_ARG, "a registered type needs a kind and a name");
  if (e->n_params < 0 || (e->n_params > 0 && !e->params))
    TL_ERROR(TL_ERR_ARG, "%s type '%s': %d parameters without a table", e->kind, e->name, e->n_params);
  for (size_t i = 0; i < tl_n_entries; ++i) {
    const TlTypeEntry *r = &tl_entries[i];
    if (strcmp(r->kind, e->kind) == 0 && strcmp(r->name, e->name) == 0) {
      if (r->create == e->create && r->ops == e->ops) return TL_OK;
      TL_ERROR(TL_ERR_ARG, "a %s type named '%s' is already registered", e->kind, e->name);
    }
  }
  TL_CHECK(tl_array_reserve(&tl_entries, &tl_cap_entries, tl_n_entries + 1, sizeof *tl_entries));
  tl_entries[tl_n_entries++] = *e;
  return TL_OK;
}

TlStatus tl_registry_lookup(const char *kind, const char *name, const TlTypeEntry **entry)
{
  *entry = NULL;
  /* the built-ins are there whether or not the caller initialised */
  TL_CHECK(tl_initialize());
  char known[512] = "";
  for (size_t i = 0; i < tl_n_entries; ++i) {
    const TlTypeEntry *r = &tl_entries[i];
    if (strcmp(r->kind, kind) != 0) continue;
    if (name && strcmp(r->name, name) == 0) return (*entry = r), TL_OK;
    if (known[0]) strncat(known, ", ", sizeof known - strlen(known) - 1);
    strncat(known, r->name, sizeof known - strlen(known) - 1);
  }
  TL_ERROR(TL_ERR_NOT_FOUND, "no %s type named '%s' (known: %s)", kind, name ? name : "(null)",
           known[0] ? known : "none");
}

const TlTypeEntry *tl_registry_entry(const char *kind, size_t i)
{
  if (tl_initialize() != TL_OK) return NULL;
  for (size_t k = 0; k < tl_n_entries; ++k)
    if (strcmp(tl_entries[k].kind, kind) == 0 && i-- == 0) return &tl_entries[k];
  return NULL;
}

const TlTypeEntry *tl_registry_at(size_t i)
{
  if (tl_initialize() != TL_OK) return NULL;
  return i < tl_n_entries ? &tl_entries[i] : NULL;
}

TlStatus tl_registry_add(const TlOpsHeader *ops)
{
  if (!ops || !ops->kind || !ops->name) TL_ERROR(TL_ERR_ARG, "ops table without kind or name");
  TlTypeEntry e = {ops->kind, ops->name, ops->description, NULL, ops, NULL, 0};
  return tl_registry_register(&e);
}

TlStatus tl_registry_find(const char *kind, const char *name, const TlOpsHeader **ops)
{
  const TlTypeEntry *e;
  *ops = NULL;
  TL_CHECK(tl_registry_lookup(kind, name, &e));
  if (!e->ops) TL_ERROR(TL_ERR_UNSUPPORTED, "%s type '%s' has no ops table", kind, name);
  *ops = e->ops;
  return TL_OK;
}

size_t tl_registry_list(const char *kind, const char **names, size_t max)
{
  size_t n = 0;
  for (const TlTypeEntry *e; (e = tl_registry_entry(kind, n)); ++n)
    if (n < max) names[n] = e->name;
  return n;
}

const TlParam *tl_param_find(const TlParam *params, int n_params, const char *name)
{
  for (int i = 0; i < n_params; ++i)
    if (strcmp(params[i].name, name) == 0) return &params[i];
  return NULL;
}

void tl_registry_clear(void)
{
  tl_free(&tl_entries);
  tl_n_entries = tl_cap_entries = 0;
  tl_initialize_forget();
}
