/* Struct sizes and named settings for bindings (tl_api.h). */
#include "tl_api.h"

#include <math.h>

#include "tl_registry.h"
#include <limits.h>
#include <stdio.h>
#include <string.h>

size_t tl_api_sizeof(const char *type_name)
{
  static const struct {
    const char *name;
    size_t size;
  } sizes[] = {
      {"TlVec3", sizeof(TlVec3)},
      {"TlDemEnergy", sizeof(TlDemEnergy)},
      {"TlDemStats", sizeof(TlDemStats)},
      {"TlCoupledEnergy", sizeof(TlCoupledEnergy)},
      {"TlEnergies", sizeof(TlEnergies)},
      {"TlWallSetting", sizeof(TlWallSetting)},
      {"TlVCouplingDiag", sizeof(TlVCouplingDiag)},
      {"TlVCouplingParams", sizeof(TlVCouplingParams)},
  };
  if (!type_name) return 0;
  for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; ++k)
    if (!strcmp(sizes[k].name, type_name)) return sizes[k].size;
  return 0;
}

TlStatus tl_api_set_fields(const char *what, const TlApiField *table, int n_table, void *object, size_t n,
                           const char *const *names, const double *values)
{
  for (size_t k = 0; k < n; ++k) {
    const TlApiField *f = NULL;
    for (int j = 0; j < n_table && !f; ++j)
      if (names[k] && !strcmp(table[j].name, names[k])) f = &table[j];
    if (!f) {
      char list[1024];
      size_t len = 0;
      list[0] = '\0';
      for (int j = 0; j < n_table && len < sizeof list; ++j)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s%s", j ? ", " : "", table[j].name);
      TL_ERROR(TL_ERR_NOT_FOUND, "%s has no setting '%s' (settings: %s)", what, names[k] ? names[k] : "(null)", list);
    }
    char *at = (char *)object + f->offset;
    const double x = values[k];
    if (f->kind == 0) {
      if (!isfinite(x)) TL_ERROR(TL_ERR_ARG, "%s setting %s = %g is not finite", what, f->name, x);
      memcpy(at, &x, sizeof x);
      continue;
    }
    const double lim = f->kind == 1 ? (double)INT_MAX : (double)LONG_MAX;
    if (!(x == floor(x)) || !(fabs(x) <= lim))
      TL_ERROR(TL_ERR_ARG, "%s setting %s = %g is not an integer within +-%.0f", what, f->name, x, lim);
    if (f->kind == 1) {
      int i = (int)x;
      memcpy(at, &i, sizeof i);
    } else {
      long l = (long)x;
      memcpy(at, &l, sizeof l);
    }
  }
  return TL_OK;
}

TlStatus tl_api_type_param(const char *kind, const char *name, int k, int *n, const char **pname, double *def,
                           double *lo, double *hi, const char **unit, const char **help)
{
  const TlTypeEntry *e = NULL;
  TL_CHECK(tl_registry_lookup(kind, name, &e));
  if (n) *n = e->n_params;
  if (k < 0) return TL_OK;
  if (k >= e->n_params)
    TL_ERROR(TL_ERR_ARG, "%s type '%s' has %d parameters, none of index %d", kind, name, e->n_params, k);
  const TlParam *p = &e->params[k];
  if (pname) *pname = p->name;
  if (def) *def = p->def;
  if (lo) *lo = p->lo;
  if (hi) *hi = p->hi;
  if (unit) *unit = p->unit ? p->unit : "";
  if (help) *help = p->help ? p->help : "";
  return TL_OK;
}
