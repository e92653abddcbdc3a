/* Periodic ties of a solid's node sets (tl_solid_tie.h). */
#include "tl_solid_tie.h"

#include <math.h>
#include <stdlib.h>

#include "tl_memory.h"

typedef struct {
  double key;
  size_t node;
} Keyed;

static int cmp_keyed(const void *a, const void *b)
{
  double x = ((const Keyed *)a)->key, y = ((const Keyed *)b)->key;
  return (x > y) - (x < y);
}

/* Master node of each slave node: the masters sorted by their first
 * coordinate, each slave searched in the window [key - tol, key + tol]. */
static TlStatus pair_sets(TlSolid *solid, const TlPeriodicPair *p, double tol, TlSparseIndex *master)
{
  const TlMesh *mesh = tl_solid_mesh(solid);
  const TlNodeSet *ms, *ss;
  TL_CHECK(tl_mesh_find_node_set(mesh, p->master, &ms));
  TL_CHECK(tl_mesh_find_node_set(mesh, p->slave, &ss));
  int dim = mesh->dim;
  Keyed *keys = NULL;
  TL_CHECK(tl_calloc(&keys, ms->n + 1, sizeof *keys));
  for (size_t k = 0; k < ms->n; ++k) keys[k] = (Keyed){mesh->x[3 * ms->nodes[k]] + p->offset[0], ms->nodes[k]};
  qsort(keys, ms->n, sizeof *keys, cmp_keyed);
  TlStatus s = TL_OK;
  for (size_t k = 0; k < ss->n && s == TL_OK; ++k) {
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
      for (int c = 0; c < 3; ++c) d2 += (xm[c] + p->offset[c] - xs[c]) * (xm[c] + p->offset[c] - xs[c]);
      if (d2 <= tol * tol) {
        found = keys[j].node;
        break;
      }
    }
    if (found == (size_t)-1) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "periodic tie: node %zu of '%s' at (%g, %g, %g) has no node of '%s' within %g m of "
                       "itself minus the offset (%g, %g, %g)",
                       sn, p->slave, xs[0], xs[1], xs[2], p->master, tol, p->offset[0], p->offset[1],
                       p->offset[2]);
      break;
    }
    if (found == sn) continue;
    for (int c = 0; c < dim; ++c) {
      TlSparseIndex ds = tl_solid_dof(solid, sn, c), dm = tl_solid_dof(solid, found, c);
      if ((ds < 0) != (dm < 0)) {
        s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                         "periodic tie: component %d of node %zu ('%s') is %s but of its master %zu ('%s') %s", c,
                         sn, p->slave, ds < 0 ? "clamped" : "free", found, p->master,
                         dm < 0 ? "clamped" : "free");
        break;
      }
      if (ds >= 0 && master[ds] == ds) master[ds] = dm; /* an edge node keeps its first master */
    }
  }
  tl_free(&keys);
  return s;
}

TlStatus tl_solid_periodic_tie(TlSolid *solid, int n_pairs, const TlPeriodicPair *pairs, double tol,
                               TlMechSystem **tied)
{
  if (!solid || !tied || (n_pairs > 0 && !pairs)) TL_ERROR(TL_ERR_ARG, "periodic tie: NULL argument");
  if (!(tol > 0.0) || !isfinite(tol)) TL_ERROR(TL_ERR_ARG, "periodic tie: tolerance %g m must be > 0", tol);
  TlMechSystem *sys = tl_solid_system(solid);
  TlSparseIndex n = sys->ndof;
  TlSparseIndex *master = NULL;
  TL_CHECK(tl_calloc(&master, (size_t)n + 1, sizeof *master));
  for (TlSparseIndex i = 0; i < n; ++i) master[i] = i;
  TlStatus s = TL_OK;
  for (int k = 0; k < n_pairs && s == TL_OK; ++k) s = pair_sets(solid, &pairs[k], tol, master);
  if (s == TL_OK) s = tl_mech_tie_create(sys, master, tied);
  tl_free(&master);
  return s;
}
