/* Periodic ties of a solid's node sets (tl_solid_tie.h): the pairing;
 * the numbering is done at set-up (tl_solid_setup.c). */
#include "tl_solid_tie.h"

#include <math.h>
#include <stdlib.h>

#include "tl_memory.h"
#include "tl_solid_private.h"

typedef struct {
  double key;
  size_t node;
} Keyed;

static int cmp_keyed(const void *a, const void *b)
{
  double x = ((const Keyed *)a)->key, y = ((const Keyed *)b)->key;
  return (x > y) - (x < y);
}

TlStatus tl_solid_tie(TlSolid *s, const char *master, const char *slave, const double offset[3], double tol)
{
  if (!s || !master || !slave || !offset) TL_ERROR(TL_ERR_ARG, "solid tie: NULL argument");
  TL_CHECK(tl_solid_not_after_setup(s, "tl_solid_tie"));
  if (!(tol > 0.0) || !isfinite(tol)) TL_ERROR(TL_ERR_ARG, "solid tie: tolerance %g m must be > 0 and finite", tol);
  for (int c = 0; c < 3; ++c)
    if (!isfinite(offset[c])) TL_ERROR(TL_ERR_ARG, "solid tie: offset component %d = %g is not finite", c, offset[c]);
  const TlMesh *mesh = s->mesh;
  const TlNodeSet *ms, *ss;
  TL_CHECK(tl_mesh_find_node_set(mesh, master, &ms));
  TL_CHECK(tl_mesh_find_node_set(mesh, slave, &ss));
  if (!s->tie_master) {
    TL_CHECK(tl_calloc(&s->tie_master, s->n_nodes, sizeof *s->tie_master));
    for (size_t k = 0; k < s->n_nodes; ++k) s->tie_master[k] = k;
  }
  /* Masters sorted by their translated x; each slave searched in the
   * window [x - tol, x + tol]. */
  Keyed *keys = NULL;
  TL_CHECK(tl_calloc(&keys, ms->n + 1, sizeof *keys));
  for (size_t k = 0; k < ms->n; ++k) keys[k] = (Keyed){mesh->x[3 * ms->nodes[k]] + offset[0], ms->nodes[k]};
  qsort(keys, ms->n, sizeof *keys, cmp_keyed);
  TlStatus st = TL_OK;
  for (size_t k = 0; k < ss->n; ++k) {
    size_t sn = ss->nodes[k];
    const double *xs = mesh->x + 3 * sn;
    size_t lo = 0, hi = ms->n;
    while (lo < hi) {
      size_t mid = (lo + hi) / 2;
      if (keys[mid].key < xs[0] - tol) lo = mid + 1;
      else hi = mid;
    }
    size_t found = (size_t)-1;
    for (size_t j = lo; j < ms->n && keys[j].key <= xs[0] + tol; ++j) {
      const double *xm = mesh->x + 3 * keys[j].node;
      double d2 = 0.0;
      for (int c = 0; c < 3; ++c) d2 += (xm[c] + offset[c] - xs[c]) * (xm[c] + offset[c] - xs[c]);
      if (d2 <= tol * tol) {
        found = keys[j].node;
        break;
      }
    }
    if (found == (size_t)-1) {
      st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                        "solid tie: node %zu of '%s' at (%g, %g, %g) has no node of '%s' within %g m of itself "
                        "minus the offset (%g, %g, %g)",
                        sn, slave, xs[0], xs[1], xs[2], master, tol, offset[0], offset[1], offset[2]);
      break;
    }
    if (found != sn && s->tie_master[sn] == sn) s->tie_master[sn] = found; /* an edge keeps its first master */
  }
  tl_free(&keys);
  return st;
}

TlStatus tl_solid_tie_roots(const TlSolid *s, size_t *root)
{
  for (size_t k = 0; k < s->n_nodes; ++k) {
    size_t r = k, hops = 0;
    while (s->tie_master[r] != r) {
      r = s->tie_master[r];
      if (++hops > s->n_nodes)
        TL_ERROR(TL_ERR_ARG, "solid tie: the masters of node %zu form a cycle (tie offsets of opposite signs?)", k);
    }
    root[k] = r;
  }
  return TL_OK;
}

size_t tl_solid_n_tied(const TlSolid *s)
{
  size_t n = 0;
  if (s && s->tie_master)
    for (size_t k = 0; k < s->n_nodes; ++k) n += s->tie_master[k] != k;
  return n;
}
