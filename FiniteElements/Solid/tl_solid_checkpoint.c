/* Checkpoint of a solid. */
#include "tl_solid_private.h"

#include <stdio.h>
#include <string.h>

/* The state a law keeps outside the solid's arrays (TlMaterialOps.checkpoint),
 * once per distinct material, under group/block<b>_material for the first
 * block b that uses it. */
static TlStatus materials_checkpoint(const TlSolid *s, TlCheckpointWriter *w, TlCheckpointReader *r, const char *group)
{
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    TlMaterial *m = s->blocks[b].material;
    int first = 1;
    for (int a = 0; a < b; ++a) first &= s->blocks[a].material != m;
    if (!first || !m->ops->checkpoint) continue;
    char sub[512];
    snprintf(sub, sizeof sub, "%s/block%d_material", group ? group : "", b);
    if (w) TL_CHECK(m->ops->checkpoint->save(m, w, sub));
    else TL_CHECK(m->ops->checkpoint->load(m, r, sub));
  }
  return TL_OK;
}

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
  TL_CHECK(materials_checkpoint(s, w, NULL, group));
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
  TL_CHECK(materials_checkpoint(s, NULL, r, group));
  return TL_OK;
}

const TlCheckpointOps tl_solid_checkpoint_ops = {
    .header = {"checkpoint", "solid_v1", "committed material state of a finite-strain solid"},
    .save = solid_checkpoint_save,
    .load = solid_checkpoint_load,
};
