/* Constant directional rolling resistance: a couple on i of magnitude
 * mu_roll reff <f_N>_+ opposing the relative rolling spin (tl_rolling_couple).
 * mu_roll = 0 switches the part off. */
#include <stddef.h>
#include "tl_contact_kernels.h"
#include "tl_contact_part.h"

typedef struct {
  TlContactPart base;
  double mu_roll;
} Rolling;

static const TlParam params[] = {
    {"mu_roll", 0.1, 0.0, 1e300, "1", "rolling friction coefficient: couple mu_roll reff f_n (0: none)",
     offsetof(Rolling, mu_roll)},
};

static TlStatus rolling_setup(TlContactPart *part, const TlContactPart *normal)
{
  (void)normal;
  part->active = ((Rolling *)part)->mu_roll > 0.0;
  part->needs_rotation = 1;
  return TL_OK;
}

static inline void rolling_loop(const TlContactPart *part, TlContactChunk *c)
{
  const double mu_r = ((const Rolling *)part)->mu_roll;
  for (size_t q = 0; q < c->n; ++q) {
    if (!c->on[q]) continue;
    const double fn = c->fn[q], fn_plus = fn > 0.0 ? fn : 0.0;
    c->couple[q] = tl_rolling_couple(c->normal[q], c->spin_rel[q], mu_r, c->reff[q], fn_plus);
  }
}
TL_CONTACT_PART_LOOPS(rolling, rolling_loop)

static const TlContactPartOps rolling_ops = {
    {"contact_rolling", "constant", "constant directional rolling torque mu_roll reff f_n"},
    sizeof(Rolling), (int)(sizeof params / sizeof params[0]), params, rolling_setup, rolling_evaluate,
    rolling_evaluate_hot, NULL, NULL, NULL, NULL, NULL, NULL};

TlStatus tl_contact_register_rolling(void);
TlStatus tl_contact_register_rolling(void) { return tl_contact_part_register(&rolling_ops); }
