/* The parts a contact law is composed of, and how to write a new one.
 *
 * A part is one of four kinds, each a registry kind of its own:
 *   "contact_normal"    the normal force (required): linear, bonded_linear, hertz
 *   "contact_friction"  the tangential force: coulomb
 *   "contact_rolling"   a rolling couple: constant
 *   "contact_adhesion"  an attraction while in contact: constant
 * A law runs its parts on a chunk of contacts (TlContactChunk,
 * tl_contact_law.h) in the order normal, adhesion, friction, rolling, each
 * part one loop over the chunk (one indirect call per part per chunk):
 *   normal    sets on[c], fn[c] (repulsive > 0), scale[c] and energy[c];
 *   adhesion  lowers fn[c] (and energy[c]) of the contacts that are on;
 *   (the law sets force[c] = -fn[c] normal[c] and couple[c] = 0)
 *   friction  adds the tangential force on i to force[c], from fn[c]'s
 *             positive part, with stiffness k_t scale[c] (adds to energy[c]);
 *   rolling   sets couple[c] from fn[c]'s positive part.
 * A part reads and writes the contacts that are on only (on[c] != 0).
 *
 * What the friction part needs from the normal part is its `scale`, per
 * contact (1 for a linear spring, sqrt(δ R*) for Hertz, which scales the
 * tangential stiffness and damping with the contact radius), and a default
 * tangential stiffness (2/7 k_n for a linear spring, 2 E / ((1 + ν)(2 - ν))
 * for Hertz), used when the friction part's own k_t is 0.
 *
 * A new part is one file: a struct beginning with TlContactPart, its
 * parameter table (TlParam, offsets into that struct), a setup, a chunk
 * loop, an ops table, and a call to tl_contact_part_register(&ops) before
 * it is named (a driver's main, a plug-in's init function).  It is then
 * created by name like a built-in part: tl_contact_law_create("mine", ...),
 * -contact mine, its parameters -contact_<name>.  A sketch of a normal part:
 *
 *   typedef struct { TlContactPart base; double k; } Mine;
 *   static const TlParam params[] = {
 *       {"k", 1e5, 0.0, 1e300, "N/m", "stiffness", offsetof(Mine, k)}};
 *   static inline void mine_loop(const TlContactPart *p, TlContactChunk *c)
 *   {
 *     const Mine *m = (const Mine *)p;
 *     for (size_t q = 0; q < c->n; ++q) {
 *       c->on[q] = c->overlap[q] > 0.0;
 *       c->fn[q] = m->k * c->overlap[q];
 *       c->scale[q] = 1.0;
 *       if (c->want_energy) c->energy[q] = 0.5 * m->k * c->overlap[q] * c->overlap[q];
 *     }
 *   }
 *   TL_CONTACT_PART_LOOPS(mine, mine_loop)   // defines mine_evaluate, mine_evaluate_hot
 *   static const TlContactPartOps ops = {
 *       {"contact_normal", "mine", "my spring"}, sizeof(Mine), 1, params,
 *       setup, mine_evaluate, mine_evaluate_hot, ...};
 */
#ifndef TL_CONTACT_PART_H
#define TL_CONTACT_PART_H

#include <stddef.h>
#include "tl_contact_law.h"
#include "tl_error.h"
#include "tl_object.h"
#include "tl_registry.h"

/* In the order a law runs them. */
typedef enum {
  TL_CONTACT_NORMAL,
  TL_CONTACT_ADHESION,
  TL_CONTACT_FRICTION,
  TL_CONTACT_ROLLING,
  TL_CONTACT_N_KINDS
} TlContactPartKind;

/* Registry kinds, by TlContactPartKind. */
extern const char *const tl_contact_part_kinds[TL_CONTACT_N_KINDS];

typedef struct TlContactPart TlContactPart;

typedef struct {
  TlOpsHeader header; /* kind: one of tl_contact_part_kinds */
  size_t size;        /* sizeof the derived struct */
  int n_params;
  const TlParam *params; /* doubles at `offset` in the derived struct */
  /* Checks the parameters (naming the value and the limit), derives
   * constants and sets history_doubles, needs_rotation, bonded and active.
   * `normal` is the law's normal part, already set up (NULL for a normal
   * part itself). */
  TlStatus (*setup)(TlContactPart *part, const TlContactPart *normal);
  /* The chunk loop, as described above.  evaluate_hot is the same loop
   * compiled as the world's contact loop is (TL_CONTACT_HOT_CLONES), which
   * the world's chunks use; NULL: evaluate serves both. */
  TlStatus (*evaluate)(const TlContactPart *part, TlContactChunk *chunk);
  TlStatus (*evaluate_hot)(const TlContactPart *part, TlContactChunk *chunk);
  /* Normal parts (NULL for the others): the largest stiffness dF/dδ and
   * damping (N s/m) for the critical time step; the tangential scale of a
   * contact (as scale[c] of the chunk); the default tangential stiffness,
   * in N/m per unit of scale (0: none, the friction part must be given one). */
  double (*max_stiffness)(const TlContactPart *part, double reff, double overlap);
  double (*max_damping)(const TlContactPart *part, double meff, double reff, double overlap);
  double (*tangential_scale)(const TlContactPart *part, double reff, double overlap);
  double (*tangential_stiffness)(const TlContactPart *part);
  /* Friction parts: the largest tangential stiffness (N/m); NULL: none. */
  double (*max_tangential_stiffness)(const TlContactPart *part, double reff, double overlap);
  /* Optional: frees what the derived type owns (the struct itself is freed
   * by the law). */
  void (*destroy)(TlContactPart *part);
} TlContactPartOps;

struct TlContactPart {
  const TlContactPartOps *ops;
  size_t history_offset;  /* where this part's doubles start in a contact's history */
  size_t history_doubles; /* set by setup */
  int needs_rotation;     /* set by setup: reads spins or makes couples */
  int bonded;             /* normal parts, set by setup: acts in tension on bonds */
  int active;             /* set by setup: 0 drops the part (e.g. mu = 0) */
  int lever_radius;       /* set by setup: the law's contacts use the radius as lever arm
                             (TlContactLaw.lever_radius) */
  int ignores_spins;      /* set by setup: reads neither spin_mean nor spin_rel and makes no
                             couple (TlContactLaw.ignores_spins); 0, the default, is always safe */
  const TlContactPart *normal; /* the law's normal part (self for a normal part) */
};

/* Registers a part type (its header's kind says which). */
TlStatus tl_contact_part_register(const TlContactPartOps *ops);

/* Defines name##_evaluate and name##_evaluate_hot from a chunk loop
 * `static inline void loop(const TlContactPart *, TlContactChunk *)`. */
#define TL_CONTACT_PART_LOOPS(name, loop)                                                       \
  static TlStatus name##_evaluate(const TlContactPart *part, TlContactChunk *chunk)             \
  {                                                                                             \
    loop(part, chunk);                                                                          \
    return TL_OK;                                                                               \
  }                                                                                             \
  TL_CONTACT_HOT_CLONES static TlStatus name##_evaluate_hot(const TlContactPart *part,          \
                                                            TlContactChunk *chunk)              \
  {                                                                                             \
    loop(part, chunk);                                                                          \
    return TL_OK;                                                                               \
  }

#endif
