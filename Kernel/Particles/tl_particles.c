#include "tl_particles.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "tl_memory.h"

TlStatus tl_particles_create(TlParticles **p)
{
  TL_CHECK(TL_NEW(*p));
  return TL_OK;
}

void tl_particles_destroy(TlParticles **pp)
{
  TlParticles *p = *pp;
  if (!p) return;
  tl_free(&p->x); tl_free(&p->v); tl_free(&p->f);
  tl_free(&p->radius); tl_free(&p->mass); tl_free(&p->inv_mass);
  tl_free(&p->species); tl_free(&p->motion); tl_free(&p->id);
  tl_free(&p->q); tl_free(&p->w); tl_free(&p->torque); tl_free(&p->inv_inertia);
  tl_free(&p->f_ext); tl_free(&p->f_coupling); tl_free(&p->weight); tl_free(&p->species_table);
  tl_free(pp);
}

TlStatus tl_particles_add_species(TlParticles *p, const char *name, double density, double r_min,
                                  double r_max, int *index)
{
  if (!(density > 0.0) || !isfinite(density))
    TL_ERROR(TL_ERR_ARG, "species '%s': density %g must be positive and finite", name, density);
  if (!(r_min > 0.0) || !(r_max >= r_min) || !isfinite(r_max))
    TL_ERROR(TL_ERR_ARG, "species '%s': radii [%g, %g] must satisfy 0 < r_min <= r_max", name, r_min,
             r_max);
  TL_CHECK(tl_array_reserve(&p->species_table, &p->species_capacity, p->n_species + 1,
                            sizeof *p->species_table));
  TlSpecies *s = &p->species_table[p->n_species];
  memset(s, 0, sizeof *s);
  snprintf(s->name, sizeof s->name, "%s", name ? name : "species");
  s->density = density;
  s->r_min = r_min;
  s->r_max = r_max;
  if (index) *index = (int)p->n_species;
  p->n_species++;
  return TL_OK;
}

double tl_random_uniform(uint64_t *state)
{
  uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  return (double)(z >> 11) * 0x1.0p-53;
}

double tl_species_sample_radius(const TlSpecies *s, uint64_t *state)
{
  return s->r_min + (s->r_max - s->r_min) * tl_random_uniform(state);
}

static TlStatus grow(TlParticles *p, size_t need)
{
  if (need <= p->capacity) return TL_OK;
  size_t cap = p->capacity ? p->capacity : 64;
  while (cap < need) cap *= 2;
  TL_CHECK(tl_realloc(&p->x, cap, sizeof *p->x));
  TL_CHECK(tl_realloc(&p->v, cap, sizeof *p->v));
  TL_CHECK(tl_realloc(&p->f, cap, sizeof *p->f));
  TL_CHECK(tl_realloc(&p->radius, cap, sizeof *p->radius));
  TL_CHECK(tl_realloc(&p->mass, cap, sizeof *p->mass));
  TL_CHECK(tl_realloc(&p->inv_mass, cap, sizeof *p->inv_mass));
  TL_CHECK(tl_realloc(&p->species, cap, sizeof *p->species));
  TL_CHECK(tl_realloc(&p->motion, cap, sizeof *p->motion));
  TL_CHECK(tl_realloc(&p->id, cap, sizeof *p->id));
  if (p->q) {
    TL_CHECK(tl_realloc(&p->q, cap, sizeof *p->q));
    TL_CHECK(tl_realloc(&p->w, cap, sizeof *p->w));
    TL_CHECK(tl_realloc(&p->torque, cap, sizeof *p->torque));
    TL_CHECK(tl_realloc(&p->inv_inertia, cap, sizeof *p->inv_inertia));
  }
  if (p->f_ext) TL_CHECK(tl_realloc(&p->f_ext, cap, sizeof *p->f_ext));
  if (p->f_coupling) TL_CHECK(tl_realloc(&p->f_coupling, cap, sizeof *p->f_coupling));
  if (p->weight) TL_CHECK(tl_realloc(&p->weight, cap, sizeof *p->weight));
  p->capacity = cap;
  return TL_OK;
}

TlStatus tl_particles_reserve(TlParticles *p, size_t n) { return grow(p, n); }

static double sphere_inv_inertia(double mass, double radius) { return 1.0 / (0.4 * mass * radius * radius); }
/* a solid cylinder about its axis; the sphere's arithmetic is kept as it was */
static double inv_inertia_of(const TlParticles *p, double mass, double radius)
{
  return p->disks ? 1.0 / (0.5 * mass * radius * radius) : sphere_inv_inertia(mass, radius);
}
static double mass_of(const TlParticles *p, double density, double radius)
{
  return p->disks ? density * TL_PI * radius * radius : density * 4.0 / 3.0 * TL_PI * radius * radius * radius;
}

TlStatus tl_particles_set_disks(TlParticles *p, int disks)
{
  p->disks = disks != 0;
  for (size_t k = 0; k < p->n; ++k) {
    p->mass[k] = mass_of(p, p->species_table[p->species[k]].density, p->radius[k]);
    p->inv_mass[k] = p->motion[k] == TL_MOTION_FREE ? 1.0 / p->mass[k] : 0.0;
    if (p->q) p->inv_inertia[k] = p->motion[k] == TL_MOTION_FREE ? inv_inertia_of(p, p->mass[k], p->radius[k]) : 0.0;
  }
  return TL_OK;
}

TlStatus tl_particles_add(TlParticles *p, TlVec3 x, TlVec3 v, double radius, int species, size_t *index)
{
  if (!(radius > 0.0) || !isfinite(radius))
    TL_ERROR(TL_ERR_ARG, "particle radius %g must be positive and finite", radius);
  if (species < 0 || (size_t)species >= p->n_species)
    TL_ERROR(TL_ERR_ARG, "particle species %d unknown (%zu species defined)", species, p->n_species);
  if (!tl_v3_isfinite(x) || !tl_v3_isfinite(v))
    TL_ERROR(TL_ERR_ARG, "particle position (%g, %g, %g) or velocity (%g, %g, %g) is not finite", x.x,
             x.y, x.z, v.x, v.y, v.z);
  TL_CHECK(grow(p, p->n + 1));
  size_t k = p->n++;
  double density = p->species_table[species].density;
  p->x[k] = x;
  p->v[k] = v;
  p->f[k] = tl_v3(0, 0, 0);
  p->radius[k] = radius;
  p->mass[k] = mass_of(p, density, radius);
  p->inv_mass[k] = 1.0 / p->mass[k];
  p->species[k] = species;
  p->motion[k] = TL_MOTION_FREE;
  p->id[k] = p->next_id++;
  if (p->q) {
    p->q[k] = tl_q_identity();
    p->w[k] = tl_v3(0, 0, 0);
    p->torque[k] = tl_v3(0, 0, 0);
    p->inv_inertia[k] = inv_inertia_of(p, p->mass[k], radius);
  }
  if (p->f_ext) p->f_ext[k] = tl_v3(0, 0, 0);
  if (p->f_coupling) p->f_coupling[k] = tl_v3(0, 0, 0);
  if (p->weight) p->weight[k] = 1.0;
  if (index) *index = k;
  return TL_OK;
}

#define MOVE_FIELD(arr, to, from) \
  do {                            \
    if (arr) (arr)[to] = (arr)[from]; \
  } while (0)

TlStatus tl_particles_remove(TlParticles *p, size_t index)
{
  if (index >= p->n) TL_ERROR(TL_ERR_ARG, "particle index %zu out of range (n = %zu)", index, p->n);
  size_t last = p->n - 1;
  if (index != last) {
    MOVE_FIELD(p->x, index, last); MOVE_FIELD(p->v, index, last); MOVE_FIELD(p->f, index, last);
    MOVE_FIELD(p->radius, index, last); MOVE_FIELD(p->mass, index, last);
    MOVE_FIELD(p->inv_mass, index, last); MOVE_FIELD(p->species, index, last);
    MOVE_FIELD(p->motion, index, last); MOVE_FIELD(p->id, index, last);
    MOVE_FIELD(p->q, index, last); MOVE_FIELD(p->w, index, last);
    MOVE_FIELD(p->torque, index, last); MOVE_FIELD(p->inv_inertia, index, last);
    MOVE_FIELD(p->f_ext, index, last); MOVE_FIELD(p->f_coupling, index, last);
    MOVE_FIELD(p->weight, index, last);
  }
  p->n--;
  return TL_OK;
}

TlStatus tl_particles_set_motion(TlParticles *p, size_t index, int motion)
{
  if (index >= p->n) TL_ERROR(TL_ERR_ARG, "particle index %zu out of range (n = %zu)", index, p->n);
  if (motion < TL_MOTION_FREE || motion > TL_MOTION_PRESCRIBED)
    TL_ERROR(TL_ERR_ARG, "motion kind %d unknown (0 free, 1 fixed, 2 prescribed)", motion);
  p->motion[index] = (uint8_t)motion;
  p->inv_mass[index] = motion == TL_MOTION_FREE ? 1.0 / p->mass[index] : 0.0;
  if (p->q)
    p->inv_inertia[index] =
        motion == TL_MOTION_FREE ? inv_inertia_of(p, p->mass[index], p->radius[index]) : 0.0;
  return TL_OK;
}

TlStatus tl_particles_enable_rotation(TlParticles *p)
{
  if (p->q) return TL_OK;
  size_t cap = p->capacity ? p->capacity : 1;
  TL_CHECK(tl_calloc(&p->q, cap, sizeof *p->q));
  TL_CHECK(tl_calloc(&p->w, cap, sizeof *p->w));
  TL_CHECK(tl_calloc(&p->torque, cap, sizeof *p->torque));
  TL_CHECK(tl_calloc(&p->inv_inertia, cap, sizeof *p->inv_inertia));
  for (size_t k = 0; k < p->n; ++k) {
    p->q[k] = tl_q_identity();
    p->inv_inertia[k] =
        p->motion[k] == TL_MOTION_FREE ? inv_inertia_of(p, p->mass[k], p->radius[k]) : 0.0;
  }
  return TL_OK;
}

TlStatus tl_particles_enable_external_force(TlParticles *p)
{
  if (p->f_ext) return TL_OK;
  TL_CHECK(tl_calloc(&p->f_ext, p->capacity ? p->capacity : 1, sizeof *p->f_ext));
  return TL_OK;
}

TlStatus tl_particles_enable_coupling_force(TlParticles *p)
{
  if (p->f_coupling) return TL_OK;
  TL_CHECK(tl_calloc(&p->f_coupling, p->capacity ? p->capacity : 1, sizeof *p->f_coupling));
  return TL_OK;
}

TlStatus tl_particles_enable_weights(TlParticles *p)
{
  if (p->weight) return TL_OK;
  TL_CHECK(tl_calloc(&p->weight, p->capacity ? p->capacity : 1, sizeof *p->weight));
  for (size_t k = 0; k < p->n; ++k) p->weight[k] = 1.0;
  return TL_OK;
}

/* Gathers one array through the permutation using a scratch buffer. */
static TlStatus permute_array(void *arr, size_t elem, size_t n, const size_t *perm, void *scratch)
{
  if (!arr) return TL_OK;
  char *a = arr, *s = scratch;
  for (size_t k = 0; k < n; ++k) memcpy(s + k * elem, a + perm[k] * elem, elem);
  memcpy(a, s, n * elem);
  return TL_OK;
}

TlStatus tl_particles_permute(TlParticles *p, const size_t *perm)
{
  void *scratch = NULL;
  TL_CHECK(tl_calloc(&scratch, p->n ? p->n : 1, sizeof(TlQuat)));
  permute_array(p->x, sizeof *p->x, p->n, perm, scratch);
  permute_array(p->v, sizeof *p->v, p->n, perm, scratch);
  permute_array(p->f, sizeof *p->f, p->n, perm, scratch);
  permute_array(p->radius, sizeof *p->radius, p->n, perm, scratch);
  permute_array(p->mass, sizeof *p->mass, p->n, perm, scratch);
  permute_array(p->inv_mass, sizeof *p->inv_mass, p->n, perm, scratch);
  permute_array(p->species, sizeof *p->species, p->n, perm, scratch);
  permute_array(p->motion, sizeof *p->motion, p->n, perm, scratch);
  permute_array(p->id, sizeof *p->id, p->n, perm, scratch);
  permute_array(p->q, sizeof *p->q, p->n, perm, scratch);
  permute_array(p->w, sizeof *p->w, p->n, perm, scratch);
  permute_array(p->torque, sizeof *p->torque, p->n, perm, scratch);
  permute_array(p->inv_inertia, sizeof *p->inv_inertia, p->n, perm, scratch);
  permute_array(p->f_ext, sizeof *p->f_ext, p->n, perm, scratch);
  permute_array(p->f_coupling, sizeof *p->f_coupling, p->n, perm, scratch);
  permute_array(p->weight, sizeof *p->weight, p->n, perm, scratch);
  tl_free(&scratch);
  return TL_OK;
}

TlStatus tl_particles_find(const TlParticles *p, int64_t id, size_t *index)
{
  for (size_t k = 0; k < p->n; ++k)
    if (p->id[k] == id) {
      *index = k;
      return TL_OK;
    }
  TL_ERROR(TL_ERR_NOT_FOUND, "no particle with id %lld", (long long)id);
}

TlStatus tl_particles_check_finite(const TlParticles *p)
{
  for (size_t k = 0; k < p->n; ++k) {
    if (!tl_v3_isfinite(p->x[k]) || !tl_v3_isfinite(p->v[k]) || !tl_v3_isfinite(p->f[k]))
      TL_ERROR(TL_ERR_NUMERIC,
               "particle %zu (id %lld): non-finite state x = (%g, %g, %g), v = (%g, %g, %g), f = (%g, %g, %g)",
               k, (long long)p->id[k], p->x[k].x, p->x[k].y, p->x[k].z, p->v[k].x, p->v[k].y, p->v[k].z,
               p->f[k].x, p->f[k].y, p->f[k].z);
    if (p->w && !tl_v3_isfinite(p->w[k]))
      TL_ERROR(TL_ERR_NUMERIC, "particle %zu (id %lld): non-finite angular velocity", k,
               (long long)p->id[k]);
  }
  return TL_OK;
}
