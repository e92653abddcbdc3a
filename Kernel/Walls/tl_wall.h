/* Walls: the interface every wall type implements, and the infinite plane.
 *
 * A wall is a base struct (first member: its ops table) embedded first in
 * the derived type.  The world holds a list of walls and, once per step,
 * calls each wall's `interact` with everything it needs (TlWallStep): the
 * wall finds its contacts, fills TlContactGeometry records (tl_contact_law.h;
 * i = the particle, j = the wall, normal from the particle's centre towards
 * the wall), evaluates them through the law's batch op, and adds the forces
 * and torques to the particles.  The wall keeps its own per-contact history
 * (law->history_doubles doubles per contact, zeroed when a contact begins)
 * across steps, keyed by particle index; when particle indices change it is
 * told through `remap`.
 *
 * Finding contacts: a wall with a finite bounding box must get its candidate
 * particles from tl_hgrid_query_box (seeds/001 Algorithm 2); only an unbounded
 * wall (bounding box with infinite components) may loop over all particles.
 *
 * Threads: the world calls walls one after another; a wall may use OpenMP
 * inside `interact` but must add to particle forces without races (for
 * instance by accumulating per particle in a contact-ordered pass).
 *
 * Accounting: when step->want_energy is set, `interact` must update the
 * base fields elastic_energy (stored in its contacts after the step),
 * contact_work (+= dt * Σ force·vrel: energy its contacts took from the
 * bodies) and work (+= dt * Σ force·v_wall: work done on the system by the
 * prescribed motion of the wall).  It always updates force and torque (the
 * total the particles exert on the wall, about the origin) and n_contacts.
 *
 * Checkpoints: a wall saves its moving state and contact history into an
 * opaque byte buffer; loading it restores a run bit for bit. */
#ifndef TL_WALL_H
#define TL_WALL_H

#include <stddef.h>
#include "tl_contact_law.h"
#include "tl_domain.h"
#include "tl_error.h"
#include "tl_hgrid.h"
#include "tl_math.h"
#include "tl_object.h"
#include "tl_particles.h"

typedef struct TlWall TlWall;

/* What a wall gets each step. */
typedef struct {
  TlParticles *particles;
  const TlHGrid *grid;      /* built at the last neighbour-list rebuild */
  const TlDomain *domain;
  const TlContactLaw *law;
  double t;                 /* time at which forces are evaluated */
  double dt;
  int want_energy;
} TlWallStep;

typedef struct {
  TlOpsHeader header; /* kind "wall" */
  /* The region the wall occupies; components are ±INFINITY for unbounded
   * walls. */
  void (*bounding_box)(const TlWall *w, TlVec3 *lo, TlVec3 *hi);
  /* Contacts, forces and torques of this step (see above). */
  TlStatus (*interact)(TlWall *w, const TlWallStep *step);
  /* Particle indices changed: the particle at old index k is now at
   * old_to_new[k], or was removed when old_to_new[k] == SIZE_MAX. */
  TlStatus (*remap)(TlWall *w, const size_t *old_to_new, size_t n_old);
  /* Moves the wall's own kinematics to time t (prescribed motion); may be
   * NULL for walls that never move. */
  TlStatus (*advance)(TlWall *w, double t, double dt);
  /* Checkpoint hooks: size of the state, save into a buffer of that size,
   * load from it. */
  size_t (*checkpoint_size)(const TlWall *w);
  TlStatus (*checkpoint_save)(const TlWall *w, void *buffer, size_t size);
  TlStatus (*checkpoint_load)(TlWall *w, const void *buffer, size_t size);
  void (*destroy)(TlWall *w);
} TlWallOps;

struct TlWall {
  const TlWallOps *ops;
  char name[32];
  int law;               /* index of its contact law in the world */
  /* accounting (see above) */
  double elastic_energy;
  double contact_work;
  double work;
  TlVec3 force, torque;  /* exerted on the wall by the particles, this step */
  size_t n_contacts;
};

/* Calls the type's destroy and nulls *w.  (These two helpers live in
 * tl_wall_plane.c with the plane.) */
void tl_wall_destroy(TlWall **w);
/* Whether the bounding box is finite in every component. */
int tl_wall_is_bounded(const TlWall *w);

/* ---- the infinite plane ----
 * Particles live on the side the normal points to; a particle at signed
 * distance s from the plane touches it when s < r (overlap r - s).  The plane
 * may translate with a velocity (prescribed motion; its work is booked).
 * A zero or non-finite normal is refused. */
TlStatus tl_wall_plane_create(TlVec3 point, TlVec3 normal, TlWall **w);
TlStatus tl_wall_plane_set_velocity(TlWall *w, TlVec3 velocity);
/* Current point and unit normal. */
void tl_wall_plane_get(const TlWall *w, TlVec3 *point, TlVec3 *normal);
/* The plane's contact of particle i at the last evaluation: 1 and the force
 * on the particle if touching, else 0. */
int tl_wall_plane_contact_force(const TlWall *w, size_t i, TlVec3 *force_on_particle);
TlStatus tl_wall_register_plane(void);

#endif
