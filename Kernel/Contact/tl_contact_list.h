/* The persistent contact list: particle pairs (i < j) with their law, the
 * law's per-contact history and the last force, in a structure of arrays.
 *
 * In the world it is the Verlet neighbour list: every pair within
 * r_i + r_j + skin, rebuilt when particles have moved by half the skin.  A
 * rebuild makes a new list and carries the history of every touching pair
 * over from the old one through an open-addressing hash keyed by the pair
 * (O(1) per lookup); pairs that stopped touching have their history zeroed
 * at once, so a contact that ends and begins again starts afresh.  Buffers
 * grow by doubling and are reused: once the list has reached its working
 * size, rebuilding allocates nothing. */
#ifndef TL_CONTACT_LIST_H
#define TL_CONTACT_LIST_H

#include <stddef.h>
#include <stdint.h>
#include "tl_error.h"
#include "tl_math.h"

typedef struct {
  size_t n, capacity;
  size_t history_doubles;  /* stride of `history` */
  uint32_t *i, *j;
  uint8_t *law;            /* law index (the world's table) */
  uint8_t *touching;       /* overlapping at the last evaluation */
  TlVec3 *force;           /* force on i at the last evaluation (0 if apart) */
  double *history;         /* n * history_doubles */
  /* pair-keyed hash: slot -> contact index + 1 (0 empty) */
  uint64_t *keys;
  uint32_t *slots;
  size_t hash_capacity;    /* table size in use, a power of two */
  size_t hash_allocated;   /* allocated slots */
} TlContactList;

TlStatus tl_contact_list_init(TlContactList *c, size_t history_doubles);
void tl_contact_list_free(TlContactList *c);
/* Makes room for n contacts (keeps contents). */
TlStatus tl_contact_list_reserve(TlContactList *c, size_t n);
/* Empties the list (keeps buffers). */
static inline void tl_contact_list_clear(TlContactList *c) { c->n = 0; }
/* Appends pair (i, j) stored as (min, max), with zero history; returns its
 * index.  (After a renumbering of particles an entry may hold i > j.) */
TlStatus tl_contact_list_push(TlContactList *c, uint32_t i, uint32_t j, int law, size_t *k);
/* Builds the hash of the current entries (only touching ones when
 * `touching_only`). */
TlStatus tl_contact_list_index(TlContactList *c, int touching_only);
/* Index of pair (i, j) (any order) through the hash, or SIZE_MAX. */
size_t tl_contact_list_find(const TlContactList *c, uint32_t i, uint32_t j);
/* Copies the history of every pair of `to` found in `from`'s hash (built
 * with tl_contact_list_index), and its touching flag and force; `from` may
 * hold a pair as (j, i), whose history and force are then negated. */
void tl_contact_list_transfer(TlContactList *to, const TlContactList *from);

#endif
