/* Contact laws: the force between two touching bodies, evaluated on a batch.
 *
 * A contact is described to a law by a TlContactGeometry, filled by whoever
 * found the contact: the world for particle-particle pairs, a wall for
 * particle-wall contacts.  The law never knows which; the same evaluation
 * serves both.
 *
 * Conventions (seeds/004 §2.3.1, the contact oriented from body i to body j):
 *   - body i is always a particle; body j is a particle or a wall;
 *   - `normal` is the unit vector from i towards j (from the centre of i to
 *     the centre of j for two spheres, from the centre of i to its nearest
 *     point on the wall for a wall);
 *   - `overlap` = r_i + r_j - |branch| > 0 in contact (for a wall:
 *     r_i - distance to the wall).  Bonded contacts may have overlap < 0;
 *   - `branch_i`, `branch_j` go from the centres of i and j to the contact
 *     point (the lever arms of the torques; branch_j is unused for walls
 *     except for a rotating wall's velocity, already folded into `vrel`);
 *   - `vrel` is the velocity of j minus that of i at the contact point,
 *     rotations included (seeds/004 Eq. 6, Eq. 21 in a deforming cell);
 *   - `spin_mean` is (ω_i + ω_j)/2, the mean spin that carries the tangential
 *     history with the contact plane (seeds/004 Eqs. 9, 24-25); zero vectors
 *     when the scene has no rotation; `spin_rel` is ω_j - ω_i (rolling);
 *   - `meff` = m_i m_j / (m_i + m_j) (m_i for a wall or a fixed partner),
 *     `reff` = r_i r_j / (r_i + r_j) (r_i for a flat wall);
 *   - `history` points at the law's per-contact state (history_doubles
 *     doubles, zero at the first touch), owned by the contact list or wall.
 *     It must be odd under exchange of i and j (a tangential force, a
 *     normal): when the world reorders a pair it negates every history
 *     double.
 *
 * Output, per contact: `force` is the force ON i (the action of j on i,
 * applied at the contact point); j receives its opposite.  `couple` is a pure
 * torque on i beyond branch_i x force (rolling resistance), j receives its
 * opposite; zero when the law has none.  When the batch asks for energies,
 * `elastic_energy` is the energy stored in the contact after the step (J) and
 * `power` = force . vrel (+ couple . (ω_j - ω_i) for rolling), the rate at
 * which the contact takes energy from the bodies (W); the world integrates it
 * and books dissipation = contact work - stored elastic energy.
 *
 * A law declares what it needs: history_doubles (0 for a frictionless,
 * history-free law, so no history storage exists) and needs_rotation (the
 * world then allocates rotational state).  Those depend on the parameters
 * (friction on or off), so they are fields of the object, set by
 * tl_contact_law_setup.  A law may also ask for the radius as the lever arm
 * of its contacts instead of r - δ/2 (lever_radius, below). */
#ifndef TL_CONTACT_LAW_H
#define TL_CONTACT_LAW_H

#include <stddef.h>
#include "tl_error.h"
#include "tl_math.h"
#include "tl_object.h"

typedef struct {
  TlVec3 normal;
  double overlap;
  TlVec3 branch_i, branch_j;
  TlVec3 vrel;
  TlVec3 spin_mean;
  TlVec3 spin_rel;
  double meff, reff;
  double *history;
  int bonded; /* nonzero: a bond, acting in tension too if the law allows */
} TlContactGeometry;

typedef struct {
  TlVec3 force;  /* on i */
  TlVec3 couple; /* pure torque on i */
  double elastic_energy;
  double power;
} TlContactResult;

/* One batch: n contacts; dt is the time step (incremental laws integrate
 * their history over it); want_energy asks for elastic_energy and power
 * (otherwise they may be left unset). */
typedef struct {
  size_t n;
  const TlContactGeometry *geometry;
  TlContactResult *result;
  double dt;
  int want_energy;
} TlContactBatch;

/* One chunk of contacts in a structure of arrays: what the world's contact
 * loop stages for a law, and what the parts of a composed law work on
 * (tl_contact_part.h).  The caller fills n, dt, want_energy and the
 * geometry (meaning as in TlContactGeometry; spin_mean and spin_rel point at
 * zeros when the scene has no rotation); the law fills on, force, couple and,
 * when want_energy, energy.  fn and scale are the parts' working space. */
enum { TL_CONTACT_CHUNK = 64 };

/* The target the world's contact loop is compiled for: x86-64 with AVX2 and
 * FMA beside the baseline, the loader picking the one the processor runs.
 * A part's evaluate_hot carries it so that its arithmetic in the world's
 * loop is the one of that loop. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define TL_CONTACT_HOT_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define TL_CONTACT_HOT_CLONES
#endif


typedef struct {
  size_t n; /* <= TL_CONTACT_CHUNK */
  double dt;
  int want_energy;
  /* geometry (input) */
  TlVec3 normal[TL_CONTACT_CHUNK];
  double overlap[TL_CONTACT_CHUNK];
  TlVec3 vrel[TL_CONTACT_CHUNK];
  const TlVec3 *spin_mean, *spin_rel;
  double meff[TL_CONTACT_CHUNK], reff[TL_CONTACT_CHUNK];
  double *history[TL_CONTACT_CHUNK]; /* NULL entries when the law keeps no state */
  unsigned char bonded[TL_CONTACT_CHUNK];
  /* output */
  unsigned char on[TL_CONTACT_CHUNK]; /* 0: the contact carries no force (apart, not bonded) */
  TlVec3 force[TL_CONTACT_CHUNK];     /* on i */
  TlVec3 couple[TL_CONTACT_CHUNK];    /* pure torque on i */
  double energy[TL_CONTACT_CHUNK];    /* stored elastic energy */
  /* working space of the parts: the normal force (repulsive > 0) along -normal
   * on i, and the normal part's scale of tangential stiffness and damping */
  double fn[TL_CONTACT_CHUNK], scale[TL_CONTACT_CHUNK];
} TlContactChunk;

typedef struct TlContactLaw TlContactLaw;

typedef struct {
  TlOpsHeader header; /* kind "contact_law" */
  /* Evaluates every contact of the batch.  Must be thread-safe for
   * distinct batches (the world calls it from several threads at once). */
  TlStatus (*evaluate)(const TlContactLaw *law, const TlContactBatch *batch);
  /* Evaluates a staged chunk: the world's particle contact loop calls this
   * for every law, built in or not.  Same thread-safety as evaluate. */
  TlStatus (*evaluate_chunk)(const TlContactLaw *law, TlContactChunk *chunk);
  /* The largest normal stiffness dF/dδ the law reaches for a contact of
   * effective radius reff at overlap `overlap` (for Hertz it grows with the
   * overlap); used for the critical time step. */
  double (*max_stiffness)(const TlContactLaw *law, double reff, double overlap);
  /* Largest normal damping coefficient, N s/m, for a contact of effective
   * mass meff and radius reff (0 if none); enters the critical time step. */
  double (*max_damping)(const TlContactLaw *law, double meff, double reff, double overlap);
  /* One line describing the parameters, for logs. */
  void (*describe)(const TlContactLaw *law, char *text, size_t size);
  void (*destroy)(TlContactLaw *law);
  /* Parameters by name and set-up (tl_contact_law_set, _get, _setup);
   * NULL for a law without named parameters. */
  TlStatus (*set)(TlContactLaw *law, const char *name, double value);
  TlStatus (*get)(const TlContactLaw *law, const char *name, double *value);
  TlStatus (*setup)(TlContactLaw *law);
} TlContactLawOps;

struct TlContactLaw {
  const TlContactLawOps *ops;
  size_t history_doubles; /* per-contact state the law keeps */
  int needs_rotation;     /* the law produces torques or reads spins */
  int bonded;             /* the law acts in tension on bonded contacts */
  /* Lever arms, to the contact point, of the relative velocity and the
   * torques: 0 (default) r - δ/2, the middle of the overlap; 1 the radius r,
   * as LAMMPS's granular pair styles and fix wall/gran.  Whoever stages a
   * contact (the world, a wall) reads it through tl_contact_lever. */
  int lever_radius;
  /* 1: the law reads neither spin_mean nor spin_rel of a chunk and makes no
   * couple, so the world's contact loop need not stage the spins (it
   * points them at zeros); 0, the default, stages them. */
  int ignores_spins;
};

/* The lever arm of a body of radius r in a contact of overlap δ under `law`. */
static inline double tl_contact_lever(const TlContactLaw *law, double r, double overlap)
{
  return law->lever_radius ? r : r - 0.5 * overlap;
}

/* ---- contact laws composed from parts ----
 *
 * A law is a normal part (required) with optional tangential (friction),
 * rolling and adhesion parts, each a registered type with its own parameter
 * table and per-contact state (tl_contact_part.h).  The life cycle:
 *
 *   tl_contact_law_create("hertz", "coulomb", NULL, NULL, &law);
 *   tl_contact_law_set(law, "E", 7e10);  tl_contact_law_set(law, "mu", 0.5);
 *   tl_contact_law_setup(law);           // validates, derives constants
 *
 * NULL or "none" leaves a part out.  Parameter names are unique within a
 * law (the parts of one law never share a name).  A law must be set up
 * before it is given to a world or a wall; evaluating one that is not set
 * up is refused. */
TlStatus tl_contact_law_create(const char *normal, const char *friction, const char *rolling,
                               const char *adhesion, TlContactLaw **law);
/* Sets or reads parameter `name` of whichever part owns it; a value outside
 * the part's range is refused with the parameter, the value and the limit. */
TlStatus tl_contact_law_set(TlContactLaw *law, const char *name, double value);
TlStatus tl_contact_law_get(const TlContactLaw *law, const char *name, double *value);
/* Checks the parameters against each other, computes what the parts derive
 * from them (damping ratio, default tangential stiffness) and fixes
 * history_doubles, needs_rotation and bonded.  Setting a parameter again
 * requires another setup. */
TlStatus tl_contact_law_setup(TlContactLaw *law);
void tl_contact_law_destroy(TlContactLaw **law);
TlStatus tl_contact_register_all(void);

/* A law by its parts' names and parameter values: what
 * tl_contact_law_build makes, and a scene's defaults for
 * tl_contact_law_from_options (the parts it uses unless told otherwise and
 * its own values, those of the papers it reproduces).  NULL part names:
 * "linear" normal, no other part; parameters not named keep their part's
 * default. */
typedef struct {
  const char *name;
  double value;
} TlContactValue;

typedef struct {
  const char *normal, *friction, *rolling, *adhesion;
  const TlContactValue *values;
  int n_values;
} TlContactSpec;

/* create + set every value (each must belong to a part) + setup. */
TlStatus tl_contact_law_build(const TlContactSpec *spec, TlContactLaw **law);

struct TlOptions;
/* Reads -contact NAME, -friction NAME, -rolling NAME, -adhesion NAME (each
 * a choice among the registered parts of its kind, "none" for the optional
 * ones) and then every parameter of the chosen parts as -contact_<param>,
 * with the part's unit, range and description (so -help lists them; -help
 * with -contact hertz lists Hertz's), and returns the law set up.  Values of
 * `defaults` for parameters of parts not chosen are ignored (a scene's mu
 * when run with -friction none). */
TlStatus tl_contact_law_from_options(struct TlOptions *options, const TlContactSpec *defaults,
                                     TlContactLaw **law);

/* Convenience: evaluates a single contact (tests, walls with one contact). */
TlStatus tl_contact_law_evaluate_one(const TlContactLaw *law, const TlContactGeometry *g, double dt,
                                     TlContactResult *r);

#endif
