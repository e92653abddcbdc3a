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
 * (friction on or off), so they are fields of the object, set at creation. */
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

typedef struct TlContactLaw TlContactLaw;

typedef struct {
  TlOpsHeader header; /* kind "contact_law" */
  /* Evaluates every contact of the batch.  Must be thread-safe for
   * distinct batches (the world calls it from several threads at once). */
  TlStatus (*evaluate)(const TlContactLaw *law, const TlContactBatch *batch);
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
} TlContactLawOps;

struct TlContactLaw {
  const TlContactLawOps *ops;
  size_t history_doubles; /* per-contact state the law keeps */
  int needs_rotation;     /* the law produces torques or reads spins */
  int bonded;             /* the law acts in tension on bonded contacts */
};

/* Parameters common to the built-in laws; each constructor reads the ones it
 * uses and refuses out-of-range values (negative stiffness, restitution
 * outside (0, 1], friction < 0 ...) with a message naming them. */
typedef struct {
  /* linear spring-dashpot */
  double k_n;          /* N/m */
  double restitution;  /* e in (0, 1]; sets the normal damping for a given meff */
  double gamma_n_linear; /* N s/m, used when restitution <= 0 (explicit damping) */
  /* Hertz (seeds/000 supplementary Eqs. 18-20) */
  double youngs_modulus; /* Pa, gives k_n = (2/3) E / (1 - nu^2) if hertz_k_n <= 0 */
  double poisson_ratio;
  double hertz_k_n;    /* Pa: F_n = sqrt(δ reff) (k_n δ + γ_n meff dδ/dt) */
  double hertz_k_t;    /* Pa: tangential stiffness k_t sqrt(δ reff) */
  double gamma_n, gamma_t; /* Hertz viscous damping, normal and tangential, 1/(m s) (the
                            * form of Eq. 18 and LAMMPS); gamma_n is also the LAMMPS-form
                            * rate 1/s of the linear law when restitution <= 0 */
  /* Coulomb friction (seeds/004 Eqs. 22-26) */
  double mu;           /* 0 switches friction (and its history) off */
  double k_t;          /* N/m tangential stiffness for the linear law (0: k_t = 2/7 k_n) */
  double gamma_t_linear; /* N s/m tangential damping for the linear law */
  /* rolling resistance (optional) */
  double mu_roll;      /* 0: none; couple of magnitude mu_roll reff f_n opposing the
                        * relative rolling velocity (constant directional torque) */
  /* constant adhesion (optional) */
  double adhesion_force; /* N, attractive while in contact; 0: none */
  int bonded;          /* linear law only: bonds act in tension */
} TlContactParameters;

/* Defaults: every optional part off, e = 1. */
void tl_contact_parameters_default(TlContactParameters *p);

/* The built-in laws. */
TlStatus tl_contact_law_create_linear(const TlContactParameters *p, TlContactLaw **law);
TlStatus tl_contact_law_create_hertz(const TlContactParameters *p, TlContactLaw **law);
/* By registered name ("linear", "hertz"). */
TlStatus tl_contact_law_create(const char *name, const TlContactParameters *p, TlContactLaw **law);
void tl_contact_law_destroy(TlContactLaw **law);
TlStatus tl_contact_register_all(void);

/* Convenience: evaluates a single contact (tests, walls with one contact). */
TlStatus tl_contact_law_evaluate_one(const TlContactLaw *law, const TlContactGeometry *g, double dt,
                                     TlContactResult *r);

#endif
