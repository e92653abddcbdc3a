/* A new contact-law part from outside the library, in one file: the
 * viscoelastic Hertz normal force of Brilliantov, Spahn, Hertzsch and
 * Pöschel (Phys. Rev. E 53, 5382, 1996, doi:10.1103/PhysRevE.53.5382),
 *
 *   f_n = k_n sqrt(R*) (δ^(3/2) + A δ^(1/2) dδ/dt),  k_n = (2/3) E / (1 - ν²),
 *
 * whose dissipation follows from the grains' bulk viscosity through the
 * single time constant A (s).  Unlike a dashpot tuned to one restitution,
 * its coefficient of restitution falls with the impact speed, as measured
 * for real grains: 1 - e ∝ A (v / ...)^(1/5) at small A.
 *
 * A normal part fills, for each contact of a chunk that touches (on[q]):
 * fn[q], the repulsive normal force; scale[q], the factor of a friction
 * part's stiffness and damping (here the contact radius sqrt(δ R*), as for
 * the built-in Hertz part, so `-friction coulomb` gives a Mindlin-type
 * spring); energy[q], the stored elastic energy, when asked.  It also
 * tells the world its largest stiffness and damping (critical time step) and
 * a default tangential stiffness (Mindlin's 2 E / ((1 + ν)(2 - ν))). */
#include <math.h>
#include <stddef.h>

#include "examples.h"
#include "tl_contact_part.h"

typedef struct {
  TlContactPart base; /* first: the law allocates sizeof(Viscoelastic) and fills base */
  double k_n_given, E, nu, A;
  double k_n; /* given, or from E and ν */
} Viscoelastic;

static const TlParam params[] = {
    {"k_n", 0.0, 0.0, 1e300, "Pa", "normal stiffness, f_n = k_n sqrt(R*) delta^1.5 (0: (2/3) E / (1 - nu^2))",
     offsetof(Viscoelastic, k_n_given)},
    {"E", 0.0, 0.0, 1e300, "Pa", "Young's modulus of the grains", offsetof(Viscoelastic, E)},
    {"nu", 0.3, -0.999999, 0.499999, "", "Poisson's ratio of the grains", offsetof(Viscoelastic, nu)},
    {"A", 0.0, 0.0, 1.0, "s", "dissipative constant: f_n += k_n sqrt(R*) A delta^0.5 d(delta)/dt",
     offsetof(Viscoelastic, A)},
};

static TlStatus setup(TlContactPart *part, const TlContactPart *normal)
{
  (void)normal; /* a normal part is its own */
  Viscoelastic *h = (Viscoelastic *)part;
  h->k_n = h->k_n_given;
  if (!(h->k_n > 0.0)) {
    if (!(h->E > 0.0) || !isfinite(h->E))
      TL_ERROR(TL_ERR_ARG, "viscoelastic_hertz: Young's modulus E = %g Pa must be positive (or give k_n)", h->E);
    h->k_n = (2.0 / 3.0) * h->E / (1.0 - h->nu * h->nu);
  }
  part->active = 1; /* no history of its own, no rotation, not bonded */
  return TL_OK;
}

/* One loop over the chunk; TL_CONTACT_PART_LOOPS compiles it twice, once
 * as the world's contact loop is compiled. */
static inline void loop(const TlContactPart *part, TlContactChunk *c)
{
  const Viscoelastic *h = (const Viscoelastic *)part;
  for (size_t q = 0; q < c->n; ++q) {
    const double delta = c->overlap[q];
    c->on[q] = delta > 0.0;
    if (!c->on[q]) continue;
    const double a = sqrt(delta * c->reff[q]);             /* contact radius */
    const double rate = -tl_v3_dot(c->vrel[q], c->normal[q]); /* dδ/dt */
    c->fn[q] = h->k_n * a * (delta + h->A * rate);
    c->scale[q] = a;
    if (c->want_energy) c->energy[q] = 0.4 * h->k_n * a * delta * delta;
  }
}
TL_CONTACT_PART_LOOPS(viscoelastic, loop)

static double max_stiffness(const TlContactPart *part, double reff, double overlap)
{
  return 1.5 * ((const Viscoelastic *)part)->k_n * sqrt(reff * overlap);
}

static double max_damping(const TlContactPart *part, double meff, double reff, double overlap)
{
  (void)meff;
  const Viscoelastic *h = (const Viscoelastic *)part;
  return h->k_n * h->A * sqrt(reff * overlap);
}

static double tangential_scale(const TlContactPart *part, double reff, double overlap)
{
  (void)part;
  return sqrt(reff * overlap);
}

static double tangential_stiffness(const TlContactPart *part)
{
  const Viscoelastic *h = (const Viscoelastic *)part;
  return h->E > 0.0 ? 2.0 * h->E / ((1.0 + h->nu) * (2.0 - h->nu)) : 0.0;
}

static const TlContactPartOps ops = {
    .header = {"contact_normal", "viscoelastic_hertz", "Hertz with the viscoelastic damping of Brilliantov et al. 1996"},
    .size = sizeof(Viscoelastic),
    .n_params = (int)(sizeof params / sizeof params[0]),
    .params = params,
    .setup = setup,
    .evaluate = viscoelastic_evaluate,
    .evaluate_hot = viscoelastic_evaluate_hot,
    .max_stiffness = max_stiffness,
    .max_damping = max_damping,
    .tangential_scale = tangential_scale,
    .tangential_stiffness = tangential_stiffness,
};

TlStatus example_viscoelastic_hertz_register(void) { return tl_contact_part_register(&ops); }
