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
 * Walls by particle ranges: a wall whose contacts are each one particle's
 * own (a particle meets it at most once and its contact changes no other
 * particle's force, as for a plane) may also answer `prepare` and
 * `interact_range`.  The world then evaluates it inside the step's parallel
 * region instead of a region of its own: `prepare` once (one thread), then
 * `interact_range` over the blocks of TL_WALL_BLOCK particles, several
 * blocks at once on different threads, each block's sums kept apart and
 * added in block order by tl_wall_book_blocks, so that nothing depends on the
 * thread count.  tl_wall_interact_blocks does the same on one thread: such a
 * wall's `interact` may simply call it.  A wall without these ops is
 * evaluated through `interact`, as before.
 *
 * Accounting: when step->want_energy is set, `interact` must update the
 * base fields elastic_energy (stored in its contacts after the step),
 * contact_work (+= dt * Σ force·vrel: energy its contacts took from the
 * bodies) and work (+= dt * Σ force·v_wall: work done on the system by the
 * prescribed motion of the wall).  It always updates force and torque (the
 * total the particles exert on the wall, about the origin) and n_contacts.
 *
 * Checkpoints: a wall saves its moving state and contact history into an
 * opaque byte buffer; loading it restores a run bit for bit.
 *
 * Contacts for others (coarse graining, output, tests): `visit_contacts`
 * calls a visitor once per contact of the last `interact`, with the force
 * the wall applied, so nobody needs to know the wall's type.
 *
 * Types by name: a wall type registers a TlTypeEntry of kind "wall" whose
 * `create` is a TlWallConstructor and whose parameter table (TlParam) lists
 * the reals the constructor takes; tl_wall_create builds any registered
 * type, built in or not, from its name and settings of those parameters. */
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
#include "tl_registry.h"

typedef struct TlWall TlWall;

/* One contact of a wall: the particle's index, the force on it, the contact
 * point on the wall's surface and the particle centre the contact was
 * computed with (the nearest periodic image for walls that see images). */
typedef void (*TlWallVisitor)(void *ctx, size_t particle, TlVec3 force_on_particle, TlVec3 contact_point,
                              TlVec3 particle_center);

/* What a wall gets each step. */
typedef struct {
  TlParticles *particles;
  const TlHGrid *grid;      /* built at the last neighbour-list rebuild */
  const TlDomain *domain;
  const TlContactLaw *law;
  double t;                 /* time at which forces are evaluated */
  double dt;
  int want_energy;
  /* What the world promises about the particles' motion, so that a wall may
   * keep candidates between steps: while `version` stays the same (0: no
   * promise), no particle has been added, removed or renumbered, and none is
   * further than `reach` from where it was when the version began. */
  unsigned long version;
  double reach;
} TlWallStep;

/* What one block of particles adds to a wall's accounting (see above). */
typedef struct {
  double elastic;       /* elastic energy stored in the block's contacts */
  double power;         /* Σ force·vrel of the contacts (energy taken from the bodies, per unit time) */
  double work;          /* Σ force·v_wall (work of the wall's prescribed motion, per unit time) */
  TlVec3 force, torque; /* on the wall, torque about the origin */
  size_t n_contacts;
  TlStatus status;      /* the first failure in the block, TL_OK otherwise */
} TlWallSums;

/* Particles per block of a wall evaluated by particle ranges: fixed, so that
 * the blocks (and the order of their sums) are the same on any thread count. */
enum { TL_WALL_BLOCK = 512 };

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
  /* Visits every contact of the last interact (see above); particles are
   * those that interact saw. */
  TlStatus (*visit_contacts)(const TlWall *w, const TlParticles *particles, TlWallVisitor visit, void *ctx);
  /* Optional, together (walls by particle ranges, see above): `prepare`
   * once per step before any block (storage sized to the particles);
   * `interact_range` the contacts of particles [lo, hi) into *sums (zeroed
   * by the caller), safe to run at once on disjoint blocks. */
  TlStatus (*prepare)(TlWall *w, const TlWallStep *step);
  void (*interact_range)(TlWall *w, const TlWallStep *step, size_t lo, size_t hi, TlWallSums *sums);
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

/* ---- construction by name (tl_wall.c) ----
 * A wall type's constructor: `params` is the type's parameter block, a
 * struct of doubles in which parameter k of the entry's table sits at
 * params[k].offset, every value inside its range. */
typedef TlStatus (*TlWallConstructor)(const void *params, TlWall **w);
/* Setting of one parameter by name, for tl_wall_create. */
typedef struct {
  const char *name;
  double value;
} TlWallSetting;
/* Registers a wall type: kind "wall", the constructor, the ops table and
 * the parameter table (which must outlive the registry). */
TlStatus tl_wall_register(const char *name, const char *description, TlWallConstructor create, const TlWallOps *ops,
                          const TlParam *params, int n_params);
/* Creates a wall of the registered type `type`: each parameter takes its
 * setting among the n given, else its default.  A setting that names no
 * parameter of the type, or a value outside the parameter's range, is
 * refused with the type's parameters listed. */
TlStatus tl_wall_create(const char *type, size_t n, const TlWallSetting *settings, TlWall **w);
/* Visits the contacts of the last interact through the type's op; a type
 * without the op is refused with its name. */
TlStatus tl_wall_visit_contacts(const TlWall *w, const TlParticles *particles, TlWallVisitor visit, void *ctx);
/* Whether the wall is evaluated by particle ranges (prepare and
 * interact_range both given). */
int tl_wall_by_ranges(const TlWall *w);
/* Books the sums of a step's nb blocks, added in block order (stride:
 * TlWallSums between one block's and the next's): force, torque and
 * n_contacts, and with step->want_energy the energies.  Returns the first
 * block's failure, if any. */
TlStatus tl_wall_book_blocks(TlWall *w, const TlWallStep *step, const TlWallSums *sums, size_t nb, size_t stride);
/* A wall by particle ranges on one thread: prepare, every block in turn,
 * booked (the same numbers as the world's threaded evaluation). */
TlStatus tl_wall_interact_blocks(TlWall *w, const TlWallStep *step);
/* Calls the type's destroy and nulls *w. */
void tl_wall_destroy(TlWall **w);
/* Whether the bounding box is finite in every component. */
int tl_wall_is_bounded(const TlWall *w);
/* Registers the wall types of this folder (plane and trisurface). */
TlStatus tl_walls_register_all(void);

/* ---- the infinite plane (tl_wall_plane.c) ----
 * Particles live on the side the normal points to; a particle at signed
 * distance s from the plane touches it when s < r (overlap r - s).  The plane
 * may translate with a velocity (prescribed motion; its work is booked).
 * A zero or non-finite normal is refused.  By name: type "plane", parameters
 * point_x, point_y, point_z, normal_x, normal_y, normal_z (default 0, 0, 1),
 * velocity_x, velocity_y, velocity_z. */
TlStatus tl_wall_plane_create(TlVec3 point, TlVec3 normal, TlWall **w);
TlStatus tl_wall_plane_set_velocity(TlWall *w, TlVec3 velocity);
/* Current point and unit normal. */
void tl_wall_plane_get(const TlWall *w, TlVec3 *point, TlVec3 *normal);
/* The plane's contact of particle i at the last evaluation: 1 and the force
 * on the particle if touching, else 0. */
int tl_wall_plane_contact_force(const TlWall *w, size_t i, TlVec3 *force_on_particle);
TlStatus tl_wall_register_plane(void);

#endif
