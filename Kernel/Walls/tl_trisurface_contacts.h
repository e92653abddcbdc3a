/* The contacts of particles with one triangulated surface in one step, and
 * the triangle-edge corrections of seeds/001 §5.1.1 (Algorithm 1, Fig. 3).
 *
 * Pipeline of one step (tl_wall_trisurface.c runs it; tests run the pieces):
 *
 *   1. detection: one record per (particle, triangle) that overlap
 *      (tl_tricontacts_append, or tl_tricontacts_detect_brute as oracle);
 *   2. tl_tricontacts_sort: records ordered by (particle, triangle) and
 *      grouped per particle, so every later pass gives one particle to one
 *      thread: the corrections are race-free by construction and their
 *      result does not depend on the thread count;
 *   3. tl_tricontacts_merge_shared_edges (Modification 1): two contacts whose
 *      triangles share an edge, at least one of them lying on that edge (its
 *      contact point on the edge or on one of its end vertices), and the edge
 *      seen flat or convex from the particle, touch the same piece of
 *      surface.  Such links are followed transitively (a flat fan of
 *      triangles around a vertex is one cluster), and in each cluster only
 *      the contact of largest overlap is kept (ties: lowest triangle index).
 *      Contacts across concave edges stay separate.  The same pass joins
 *      the particle's touched triangles into pieces of smooth surface:
 *      triangles sharing an edge are one piece unless the edge, seen from
 *      the particle, is a valley sharper than the surface's feature angle
 *      (edge_sharp): such an edge, or a vertex where such edges meet,
 *      separates different faces (of a box, a hopper, a blade);
 *   4. tl_tricontacts_carry_history: each kept contact finds its history in
 *      the previous step's set: the same triangle, or else (the particle
 *      moved to a neighbouring triangle) the nearest contact of that particle
 *      that disappeared, so friction survives crossing an edge;
 *   5. forces from the contact law (by the wall);
 *   6. tl_tricontacts_apply_weights (Modification 2): the remaining forces
 *      of a particle on each piece of this surface are scaled by
 *      w = |f| / Σ|f| over that piece, so the total of a piece is a weighted
 *      mean, continuous when an edge changes from flat to concave as the
 *      surface deforms (seeds/001), and the pieces add, as separate walls
 *      do: a sphere in the corner of a box of triangles feels the force of
 *      the box of planes.  (The total jumps when a fold crosses the feature
 *      angle: the angle separates folds of a mesh from corners of a design,
 *      which a deforming surface should not cross.)
 *
 * The records also serve the coupling: after a step each kept record holds
 * the triangle, the contact point and its barycentric coordinates, and the
 * force on the particle (the wall receives its opposite). */
#ifndef TL_TRISURFACE_CONTACTS_H
#define TL_TRISURFACE_CONTACTS_H

#include <stddef.h>
#include <stdint.h>
#include "tl_domain.h"
#include "tl_error.h"
#include "tl_math.h"
#include "tl_trisurface.h"

typedef struct {
  int32_t particle, triangle;
  int32_t feature;  /* TlTriFeature of the contact point */
  int32_t active;   /* cleared by Modification 1 */
  TlVec3 point;     /* contact point on the triangle */
  TlVec3 normal;    /* unit, from the wall towards the particle centre */
  double overlap;   /* > 0 */
  double bary[3];   /* barycentric coordinates of point in the triangle */
  TlVec3 center;    /* particle centre used (nearest periodic image) */
  double radius;
  TlVec3 force;     /* on the particle, after the corrections */
  TlVec3 torque;    /* on the particle, about its centre */
  double weight;    /* Modification 2 weight (1 for a lone contact) */
  TlVec3 force_prev; /* force of this contact at the previous step (energy by the trapezoidal rule) */
} TlTriContactRecord;

typedef struct {
  size_t count, capacity;
  TlTriContactRecord *c;
  /* contacts of one particle: c[group[g] .. group[g+1]) */
  size_t n_groups, group_capacity;
  size_t *group;
  /* per-contact history, history_doubles each, aligned with c */
  size_t history_doubles, history_capacity;
  double *history;
  /* scratch */
  int32_t *link; size_t link_capacity;
  /* piece of smooth surface of each record (a label), aligned with c; valid
   * after tl_tricontacts_merge_shared_edges until the set changes */
  int32_t *region; size_t region_capacity;
  int regions_valid;
  unsigned char *used; size_t used_capacity;
  size_t *bucket; size_t bucket_capacity;
  TlTriContactRecord *sorted; size_t sorted_capacity;
} TlTriContactSet;

TlStatus tl_tricontacts_create(TlTriContactSet **set);
void tl_tricontacts_destroy(TlTriContactSet **set);
void tl_tricontacts_clear(TlTriContactSet *set);
/* Appends a record (active). */
TlStatus tl_tricontacts_append(TlTriContactSet *set, const TlTriContactRecord *r);
/* Tests particle (index p, centre x, radius r) against triangle t and
 * appends a record when they overlap.  In a periodic domain (domain not NULL)
 * the particle image nearest the triangle's first vertex is used. */
TlStatus tl_tricontacts_test(TlTriContactSet *set, const TlTriSurface *s, const TlDomain *domain,
                             int32_t t, int32_t p, TlVec3 x, double r);
/* Whether the centre x (nearest image to the triangle in a periodic domain)
 * lies closer than `reach` to triangle t: the test that builds candidate
 * lists with a skin. */
int tl_trisurface_within(const TlTriSurface *s, const TlDomain *domain, int32_t t, TlVec3 x, double reach);
/* Oracle: every particle against every triangle. */
TlStatus tl_tricontacts_detect_brute(TlTriContactSet *set, const TlTriSurface *s,
                                     const TlDomain *domain, size_t n, const TlVec3 *x,
                                     const double *radius);
/* Orders by (particle, triangle) and builds the per-particle groups. */
TlStatus tl_tricontacts_sort(TlTriContactSet *set);
/* Modification 1, then drops the contacts it eliminated (groups kept);
 * labels the pieces of smooth surface (set->region). */
TlStatus tl_tricontacts_merge_shared_edges(TlTriContactSet *set, const TlTriSurface *s);
/* Sizes set->history for history_doubles per contact and fills it from prev
 * (which holds last step's kept contacts and their history; may be NULL):
 * zeros for contacts that begin now.  The previous force (force_prev)
 * follows the same match, with or without history. */
TlStatus tl_tricontacts_carry_history(TlTriContactSet *set, const TlTriContactSet *prev,
                                      size_t history_doubles);
/* Modification 2 on the force and torque of every record, the weighted mean
 * within each piece of smooth surface (all of a particle's contacts are one
 * piece when the merge did not run); sets weight. */
void tl_tricontacts_apply_weights(TlTriContactSet *set);
/* Appends every record of src to dst. */
TlStatus tl_tricontacts_append_all(TlTriContactSet *dst, const TlTriContactSet *src);
/* Particle indices changed: the particle at old index k is now at
 * old_to_new[k] (SIZE_MAX: removed).  Records of removed particles are
 * dropped, the rest re-sorted with their history. */
TlStatus tl_tricontacts_remap(TlTriContactSet *set, const size_t *old_to_new, size_t n_old);
/* Swaps the contents of two sets (current becomes previous without copying). */
void tl_tricontacts_swap(TlTriContactSet *a, TlTriContactSet *b);

#endif
