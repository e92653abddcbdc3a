/* Checkpoint of a solid. */
#include "tl_solid_private.h"

#include <stdio.h>
#include <string.h>

/* Checkpoint of the committed material state, block by block (the trial
 * state equals it between steps).  Loads and prescribed motions are
 * functions of t: the stepper's time restores them. */
static TlStatus solid_checkpoint_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlSolid *s = object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_blocks", s->mesh->n_blocks));
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    const SolidBlock *B = &s->blocks[b];
    size_t n = B->material->state_size * s->mesh->blocks[b].n_elements * (size_t)B->nq;
    char name[64];
    snprintf(name, sizeof name, "block%d_state", b);
    TL_CHECK(tl_checkpoint_write_doubles(w, group, name, n, B->state_old));
  }
  return TL_OK;
}

static TlStatus solid_checkpoint_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlSolid *s = object;
  int64_t nb = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_blocks", &nb));
  if (nb != s->mesh->n_blocks)
    TL_ERROR(TL_ERR_ARG, "%s: solid state of %lld blocks; this mesh has %d", tl_checkpoint_reader_path(r),
             (long long)nb, s->mesh->n_blocks);
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    size_t n = B->material->state_size * s->mesh->blocks[b].n_elements * (size_t)B->nq;
    char name[64];
    snprintf(name, sizeof name, "block%d_state", b);
    TL_CHECK(tl_checkpoint_read_doubles(r, group, name, n, B->state_old));
    TL_CHECK(tl_checkpoint_check_finite(r, group, name, n, B->state_old));
    if (n) memcpy(B->state_new, B->state_old, n * sizeof(double));
  }
  return TL_OK;
}

const TlCheckpointOps tl_solid_checkpoint_ops = {
    .header = {"checkpoint", "solid_v1", "committed material state of a finite-strain solid"},
    .save = solid_checkpoint_save,
    .load = solid_checkpoint_load,
};
