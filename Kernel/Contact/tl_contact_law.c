#include "tl_contact_law.h"

#include <math.h>
#include <string.h>
#include "tl_contact_private.h"
#include "tl_registry.h"

void tl_contact_parameters_default(TlContactParameters *p)
{
  memset(p, 0, sizeof *p);
  p->restitution = 1.0;
  p->poisson_ratio = 0.3;
}

TlStatus tl_contact_check_common(const TlContactParameters *p)
{
  if (!(p->mu >= 0.0) || !isfinite(p->mu))
    TL_ERROR(TL_ERR_ARG, "contact law: friction coefficient mu = %g must be >= 0", p->mu);
  if (!(p->mu_roll >= 0.0) || !isfinite(p->mu_roll))
    TL_ERROR(TL_ERR_ARG, "contact law: rolling friction mu_roll = %g must be >= 0", p->mu_roll);
  if (!(p->adhesion_force >= 0.0) || !isfinite(p->adhesion_force))
    TL_ERROR(TL_ERR_ARG, "contact law: adhesion force %g N must be >= 0", p->adhesion_force);
  return TL_OK;
}

typedef TlStatus (*TlLawCreate)(const TlContactParameters *, TlContactLaw **);
static const struct {
  const TlContactLawOps *ops;
  TlLawCreate create;
} builtin[] = {{&tl_contact_linear_ops, tl_contact_law_create_linear},
               {&tl_contact_hertz_ops, tl_contact_law_create_hertz}};

TlStatus tl_contact_law_create(const char *name, const TlContactParameters *p, TlContactLaw **law)
{
  const TlOpsHeader *ops;
  TL_CHECK(tl_registry_find("contact_law", name, &ops));
  for (size_t k = 0; k < sizeof builtin / sizeof builtin[0]; ++k)
    if (&builtin[k].ops->header == ops) return builtin[k].create(p, law);
  TL_ERROR(TL_ERR_UNSUPPORTED, "contact law '%s' is registered but has no constructor here", name);
}

TlStatus tl_contact_register_all(void)
{
  for (size_t k = 0; k < sizeof builtin / sizeof builtin[0]; ++k)
    TL_CHECK(tl_registry_add(&builtin[k].ops->header));
  return TL_OK;
}

void tl_contact_law_destroy(TlContactLaw **law)
{
  if (!*law) return;
  (*law)->ops->destroy(*law);
  *law = NULL;
}

TlStatus tl_contact_law_evaluate_one(const TlContactLaw *law, const TlContactGeometry *g, double dt,
                                     TlContactResult *r)
{
  TlContactBatch b = {1, g, r, dt, 1};
  return law->ops->evaluate(law, &b);
}
