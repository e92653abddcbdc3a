/* Checkpoint section of the bridging domain coupling: what it keeps beyond
 * the two models' own sections (the reference positions it was built on,
 * the recorded ghost forces, its counters). */
#include <math.h>
#include <string.h>

#include "tl_bdm_private.h"
#include "tl_memory.h"

/* The choices that shape the coupling's operators, compared on load. */
static void choices(const TlBdm *b, int64_t c[6])
{
  c[0] = b->opt.constraint;
  c[1] = b->opt.lumping;
  c[2] = b->opt.jacobi;
  c[3] = b->opt.profile;
  c[4] = b->opt.ghost;
  c[5] = b->opt.mass_weight;
}

static TlStatus bdm_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlBdm *b = object;
  if (!b->ready) TL_ERROR(TL_ERR_STATE, "bdm: checkpoint of a coupling not set up");
  int64_t c[6];
  choices(b, c);
  TL_CHECK(tl_checkpoint_write_int64s(w, group, "choices", 6, c));
  TL_CHECK(tl_checkpoint_write_double(w, group, "alpha_min", b->opt.alpha_min));
  TL_CHECK(tl_checkpoint_write_int64s(w, group, "reference_id", b->n_ref, b->ref_id));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "reference_x", 3 * b->n_ref, (const double *)b->ref_x));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_coupled", (int64_t)b->n_c));
  if (b->ghost_fe)
    TL_CHECK(tl_checkpoint_write_doubles(w, group, "ghost_fe", 3 * tl_solid_mesh(b->solid)->n_nodes, b->ghost_fe));
  if (b->ghost_dem) {
    TL_CHECK(tl_checkpoint_write_int64(w, group, "n_ghost", (int64_t)b->n_g));
    TL_CHECK(tl_checkpoint_write_doubles(w, group, "ghost_dem", 3 * b->n_g, b->ghost_dem));
  }
  TL_CHECK(tl_checkpoint_write_int64(w, group, "steps", b->steps));
  TL_CHECK(tl_checkpoint_write_double(w, group, "energy_removed_total", b->removed_total));
  return TL_OK;
}

static TlStatus bdm_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlBdm *b = object;
  const char *path = tl_checkpoint_reader_path(r);
  if (!b->ready) TL_ERROR(TL_ERR_STATE, "%s: load the coupling after tl_bdm_setup (built as the saved one)", path);
  int64_t c[6], mine[6];
  choices(b, mine);
  TL_CHECK(tl_checkpoint_read_int64s(r, group, "choices", 6, c));
  static const char *what[6] = {"constraint", "lumping", "Jacobi sweeps", "alpha profile", "ghost-force scope",
                                "mass weighting"};
  for (int k = 0; k < 6; ++k)
    if (c[k] != mine[k])
      TL_ERROR(TL_ERR_ARG, "%s: the saved coupling has %s %lld; this one %lld", path, what[k], (long long)c[k],
               (long long)mine[k]);
  double amin;
  TL_CHECK(tl_checkpoint_read_double(r, group, "alpha_min", &amin));
  if (amin != b->opt.alpha_min)
    TL_ERROR(TL_ERR_ARG, "%s: the saved coupling has alpha_min %.17g; this one %.17g", path, amin, b->opt.alpha_min);
  /* the reference configuration the operators were built on */
  size_t n = 0;
  TL_CHECK(tl_checkpoint_length(r, group, "reference_id", &n));
  if (n != b->n_ref)
    TL_ERROR(TL_ERR_ARG, "%s: the saved coupling was built on %zu particles; this one on %zu", path, n, b->n_ref);
  int64_t *ids = NULL;
  TlVec3 *x = NULL;
  TL_CHECK(tl_calloc(&ids, n + 1, sizeof *ids));
  TlStatus s = tl_calloc(&x, n + 1, sizeof *x);
  if (s == TL_OK) s = tl_checkpoint_read_int64s(r, group, "reference_id", n, ids);
  if (s == TL_OK) s = tl_checkpoint_read_doubles(r, group, "reference_x", 3 * n, (double *)x);
  for (size_t i = 0; i < n && s == TL_OK; ++i)
    if (ids[i] != b->ref_id[i] || memcmp(&x[i], &b->ref_x[i], sizeof x[i]))
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "%s: reference particle %zu (id %lld at (%g, %g, %g)) differs from this coupling's (id %lld at "
                       "(%g, %g, %g)): the coupling was built on another configuration",
                       path, i, (long long)ids[i], x[i].x, x[i].y, x[i].z, (long long)b->ref_id[i], b->ref_x[i].x,
                       b->ref_x[i].y, b->ref_x[i].z);
  tl_free(&ids);
  tl_free(&x);
  TL_CHECK(s);
  int64_t nc = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_coupled", &nc));
  if (nc != (int64_t)b->n_c)
    TL_ERROR(TL_ERR_ARG, "%s: the saved coupling ties %lld particles; this one %zu", path, (long long)nc, b->n_c);
  if (b->ghost_fe) {
    size_t m = 3 * tl_solid_mesh(b->solid)->n_nodes;
    TL_CHECK(tl_checkpoint_read_doubles(r, group, "ghost_fe", m, b->ghost_fe));
    TL_CHECK(tl_checkpoint_check_finite(r, group, "ghost_fe", m, b->ghost_fe));
  }
  if (b->ghost_dem) {
    /* the particle set follows from the reference configuration checked above */
    int64_t ng = 0;
    TL_CHECK(tl_checkpoint_read_int64(r, group, "n_ghost", &ng));
    if (ng != (int64_t)b->n_g)
      TL_ERROR(TL_ERR_ARG, "%s: the saved coupling subtracts the initial forces of %lld particles; this one %zu", path,
               (long long)ng, b->n_g);
    TL_CHECK(tl_checkpoint_read_doubles(r, group, "ghost_dem", 3 * b->n_g, b->ghost_dem));
    TL_CHECK(tl_checkpoint_check_finite(r, group, "ghost_dem", 3 * b->n_g, b->ghost_dem));
  }
  int64_t steps = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "steps", &steps));
  TL_CHECK(tl_checkpoint_check_count(r, group, "steps", steps, 0, INT64_MAX));
  double removed = 0.0;
  TL_CHECK(tl_checkpoint_read_double(r, group, "energy_removed_total", &removed));
  TL_CHECK(tl_checkpoint_check_range(r, group, "energy_removed_total", removed, -INFINITY, INFINITY));
  b->steps = (long)steps;
  b->removed_total = removed;
  memset(&b->last, 0, sizeof b->last);
  /* the particles' share (the DEM's own section restores it too) */
  TL_CHECK(tl_bdm_ghost_apply_dem(b));
  return TL_OK;
}

const TlCheckpointOps tl_bdm_checkpoint_ops = {
    .header = {"checkpoint", "bdm_v1", "bridging domain coupling: reference configuration, ghost forces, counters"},
    .save = bdm_save,
    .load = bdm_load,
};
