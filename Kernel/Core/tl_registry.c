#include "tl_registry.h"

#include <string.h>

#include "tl_memory.h"

static const TlOpsHeader **tl_registered;
static size_t tl_n_registered, tl_cap_registered;

TlStatus tl_registry_add(const TlOpsHeader *ops)
{
  if (!ops || !ops->kind || !ops->name) TL_ERROR(TL_ERR_ARG, "ops table without kind or name");
  for (size_t i = 0; i < tl_n_registered; ++i) {
    const TlOpsHeader *r = tl_registered[i];
    if (strcmp(r->kind, ops->kind) == 0 && strcmp(r->name, ops->name) == 0) {
      if (r == ops) return TL_OK;
      TL_ERROR(TL_ERR_ARG, "a %s type named '%s' is already registered", ops->kind, ops->name);
    }
  }
  TL_CHECK(tl_array_reserve(&tl_registered, &tl_cap_registered, tl_n_registered + 1, sizeof *tl_registered));
  tl_registered[tl_n_registered++] = ops;
  return TL_OK;
}

TlStatus tl_registry_find(const char *kind, const char *name, const TlOpsHeader **ops)
{
  *ops = NULL;
  char known[512] = "";
  for (size_t i = 0; i < tl_n_registered; ++i) {
    const TlOpsHeader *r = tl_registered[i];
    if (strcmp(r->kind, kind) != 0) continue;
    if (strcmp(r->name, name) == 0) return (*ops = r), TL_OK;
    if (known[0]) strncat(known, ", ", sizeof known - strlen(known) - 1);
    strncat(known, r->name, sizeof known - strlen(known) - 1);
  }
  TL_ERROR(TL_ERR_NOT_FOUND, "no %s type named '%s' (known: %s)", kind, name, known[0] ? known : "none");
}

size_t tl_registry_list(const char *kind, const char **names, size_t max)
{
  size_t n = 0;
  for (size_t i = 0; i < tl_n_registered; ++i)
    if (strcmp(tl_registered[i]->kind, kind) == 0) {
      if (n < max) names[n] = tl_registered[i]->name;
      ++n;
    }
  return n;
}

void tl_registry_clear(void)
{
  tl_free(&tl_registered);
  tl_n_registered = tl_cap_registered = 0;
}
