/* Constant adhesion: an attraction of adhesion_force newtons while the
 * bodies overlap (not across a stretched bond), lowering the normal force
 * before friction and rolling see it; its energy -adhesion_force δ.
 * adhesion_force = 0 switches the part off. */
#include <stddef.h>
#include "tl_contact_part.h"

typedef struct {
  TlContactPart base;
  double force;
} Adhesion;

static const TlParam params[] = {
    {"adhesion_force", 0.0, 0.0, 1e300, "N", "attractive force while in contact (0: none)", offsetof(Adhesion, force)},
};

static TlStatus adhesion_setup(TlContactPart *part, const TlContactPart *normal)
{
  (void)normal;
  part->active = ((Adhesion *)part)->force > 0.0;
  part->ignores_spins = 1; /* forces along n from the overlap and v_rel only */
  return TL_OK;
}

static inline void adhesion_loop(const TlContactPart *part, TlContactChunk *c)
{
  const double fa = ((const Adhesion *)part)->force;
  const int want = c->want_energy;
  for (size_t q = 0; q < c->n; ++q) {
    const double delta = c->overlap[q];
    if (!c->on[q] || !(delta > 0.0)) continue;
    c->fn[q] -= fa;
    if (want) c->energy[q] -= fa * delta;
  }
}
TL_CONTACT_PART_LOOPS(adhesion, adhesion_loop)

static const TlContactPartOps adhesion_ops = {
    {"contact_adhesion", "constant", "constant attractive force while in contact"},
    sizeof(Adhesion), (int)(sizeof params / sizeof params[0]), params, adhesion_setup, adhesion_evaluate,
    adhesion_evaluate_hot, NULL, NULL, NULL, NULL, NULL, NULL};

TlStatus tl_contact_register_adhesion(void);
TlStatus tl_contact_register_adhesion(void) { return tl_contact_part_register(&adhesion_ops); }
