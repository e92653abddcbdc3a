/* The particle store: spheres in a structure of arrays.
 *
 * Every field is one contiguous array indexed by the particle's current
 * index 0..n-1.  Vectors are stored as TlVec3 (x, y, z together), fields
 * apart, so a loop touching positions and forces streams two arrays.
 *
 * Indices are not stable: the world may reorder particles for memory locality
 * (at neighbour-list rebuilds) and removal moves the last particle into the
 * hole.  `id` is the stable name of a particle; whoever keeps per-particle
 * data keyed by index (walls, contact lists) receives the permutation through
 * its remap hook (see tl_wall.h) and must apply it.
 *
 * Rotational state (orientation, angular velocity, torque, inertia) is
 * allocated only after tl_particles_enable_rotation(); until then the arrays
 * q, w, torque, inv_inertia are NULL and nothing rotational is computed.  The
 * world enables it when any contact law in the scene needs rotation.
 *
 * Velocities: in a deforming periodic cell (tl_domain.h) v is the velocity
 * relative to the affine field of the cell (the fluctuation h·ṡ of seeds/004
 * Eq. 14); in any other domain it is the plain velocity.
 *
 * Motion kinds: TL_MOTION_FREE particles follow Newton's law; TL_MOTION_FIXED
 * never move (their velocity stays what it was set to, usually zero, and is
 * used by the contact laws; the position does not change); TL_MOTION_PRESCRIBED
 * particles take position and velocity from a TlPrescribedMotion at each step
 * (wave sources, moving boundaries).  Forces on fixed and prescribed
 * particles are still accumulated, so the reaction they carry can be read. */
#ifndef TL_PARTICLES_H
#define TL_PARTICLES_H

#include <stddef.h>
#include <stdint.h>
#include "tl_error.h"
#include "tl_math.h"

enum { TL_MOTION_FREE = 0, TL_MOTION_FIXED = 1, TL_MOTION_PRESCRIBED = 2 };

/* A material and its size distribution.  Radii are drawn uniformly in
 * diameter between 2 r_min and 2 r_max (r_min == r_max: monodisperse). */
typedef struct {
  char name[32];
  double density; /* kg/m^3, > 0 */
  double r_min, r_max;
} TlSpecies;

/* Position and velocity prescribed as a function of time for a set of
 * particles (by stable id).  `eval` is called once per step with all of them
 * (a batch): for k < n it sets x[k] and v[k] at time t given the particle's
 * position x0[k] at the moment the motion was attached.  It must return TL_OK
 * or an error; a NaN or Inf it returns is caught and reported by the world. */
typedef TlStatus (*TlPrescribedEval)(void *ctx, double t, size_t n, const int64_t *id,
                                     const TlVec3 *x0, TlVec3 *x, TlVec3 *v);

typedef struct {
  size_t n, capacity;
  /* translational state, always present */
  TlVec3 *x;           /* centre position */
  TlVec3 *v;           /* velocity (see the note on deforming cells above) */
  TlVec3 *f;           /* accumulated force of the current step */
  double *radius;
  double *mass;
  double *inv_mass;    /* 0 for fixed and prescribed particles */
  int32_t *species;
  uint8_t *motion;     /* TL_MOTION_* */
  int64_t *id;         /* stable identifier, unique, assigned at insertion */
  /* rotational state, NULL until tl_particles_enable_rotation() */
  TlQuat *q;           /* orientation */
  TlVec3 *w;           /* angular velocity (world frame) */
  TlVec3 *torque;
  double *inv_inertia; /* 1 / (2/5 m r^2) for a solid sphere, 1 / (1/2 m r^2) for a disk; 0 if not free */
  /* optional per-particle external force (besides gravity), NULL until
   * tl_particles_enable_external_force() */
  TlVec3 *f_ext;
  /* optional per-particle coupling force, added to the force as it is
   * (never weighted), NULL until tl_particles_enable_coupling_force(): the
   * f^C_a of a volume coupling (seeds/001 Eq. 32) */
  TlVec3 *f_coupling;
  /* optional weight w_a of each particle's equation (seeds/001 Eq. 25: the
   * Arlequin partition of unity; 1 outside an overlap), NULL until
   * tl_particles_enable_weights() (unweighted); the world evaluates it
   * (tl_dem_set_weight_field) */
  double *weight;
  /* species table */
  TlSpecies *species_table;
  size_t n_species, species_capacity;
  int64_t next_id;
  /* 0: spheres (mass 4/3 π r³ ρ, inertia 2/5 m r²); 1: disks, i.e. cylinders
   * of unit thickness (mass per unit thickness π r² ρ in kg/m, inertia
   * 1/2 m r² about the axis), the particles of a two-dimensional world
   * (tl_dem_set_dimension); set by tl_particles_set_disks */
  int disks;
} TlParticles;

TlStatus tl_particles_create(TlParticles **p);
void tl_particles_destroy(TlParticles **p);

/* Adds a species; density and radii are checked (density > 0,
 * 0 < r_min <= r_max).  *index is its number for tl_particles_add. */
TlStatus tl_particles_add_species(TlParticles *p, const char *name, double density, double r_min,
                                  double r_max, int *index);
/* Draws a radius from the species' size distribution (uniform in diameter);
 * *state is a 64-bit random state advanced by the call. */
double tl_species_sample_radius(const TlSpecies *s, uint64_t *state);
/* A uniform random number in [0, 1) from a 64-bit state (splitmix64). */
double tl_random_uniform(uint64_t *state);

/* Disks (1) or spheres (0): recomputes the mass, inverse mass and inertia of
 * every particle from its radius and species density, and those inserted
 * later follow (see `disks` above). */
TlStatus tl_particles_set_disks(TlParticles *p, int disks);

/* Inserts a free particle; mass from the species density (per unit
 * thickness for disks).  Refuses radius
 * <= 0, non-finite position or velocity, unknown species.  *index (may be
 * NULL) receives its current index, its id is p->id[index]. */
TlStatus tl_particles_add(TlParticles *p, TlVec3 x, TlVec3 v, double radius, int species,
                          size_t *index);
/* Removes particle `index`: the last particle moves into its slot.  Callers
 * that keep per-index data must be told (the world does this for walls and
 * contacts through tl_dem_remove_particle). */
TlStatus tl_particles_remove(TlParticles *p, size_t index);
/* Sets the motion kind of a particle (TL_MOTION_*): fixed and prescribed
 * particles get inv_mass = inv_inertia = 0. */
TlStatus tl_particles_set_motion(TlParticles *p, size_t index, int motion);
/* Allocates the rotational arrays (identity orientation, zero spin). */
TlStatus tl_particles_enable_rotation(TlParticles *p);
TlStatus tl_particles_enable_external_force(TlParticles *p);
/* Allocates f_coupling (zero) / weight (one); no-ops when present. */
TlStatus tl_particles_enable_coupling_force(TlParticles *p);
TlStatus tl_particles_enable_weights(TlParticles *p);
/* Reserves room for n particles so that insertion does not reallocate. */
TlStatus tl_particles_reserve(TlParticles *p, size_t n);
/* Applies a permutation: the particle at old index perm[k] moves to index k. */
TlStatus tl_particles_permute(TlParticles *p, const size_t *perm);
/* Current index of a stable id (linear search; for drivers and tests, not
 * for loops), or TL_ERR_NOT_FOUND. */
TlStatus tl_particles_find(const TlParticles *p, int64_t id, size_t *index);
/* Checks every particle for non-finite position, velocity or force; the
 * error names the first one found. */
TlStatus tl_particles_check_finite(const TlParticles *p);

#endif
