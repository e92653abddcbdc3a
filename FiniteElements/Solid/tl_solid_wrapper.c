/* Wrappers over element blocks: the one way a coupling element type wraps
 * an element type (tl_solid.h).  Each block holds its wrappers as a list in
 * installation order; the solid calls through on their behalf (the block's
 * own elements first, then each wrapper), so no wrapper points at what it
 * wraps and any of them can come off at any time. */
#include "tl_solid_private.h"

#include "tl_memory.h"

TlStatus tl_solid_add_wrapper(TlSolid *s, int b, const TlSolidWrapperOps *ops, void *ctx, TlSolidWrapper **handle)
{
  if (!s || !ops || !handle) TL_ERROR(TL_ERR_ARG, "tl_solid_add_wrapper: NULL argument");
  *handle = NULL;
  if (b < 0 || b >= s->mesh->n_blocks) TL_ERROR(TL_ERR_ARG, "solid: wrapper '%s' over block %d outside [0, %d)",
                                               ops->header.name ? ops->header.name : "?", b, s->mesh->n_blocks);
  if (!ops->internal && !ops->external)
    TL_ERROR(TL_ERR_ARG, "solid: wrapper '%s' has neither an internal nor an external op",
             ops->header.name ? ops->header.name : "?");
  TlSolidWrapper *w = NULL;
  TL_CHECK(TL_NEW(w));
  w->ops = ops;
  w->ctx = ctx;
  w->block = b;
  TlSolidWrapper **at = &s->blocks[b].wrappers;
  while (*at) at = &(*at)->next;
  *at = w;
  *handle = w;
  return TL_OK;
}

void tl_solid_remove_wrapper(TlSolid *s, TlSolidWrapper **handle)
{
  if (!s || !handle || !*handle) return;
  TlSolidWrapper *w = *handle;
  for (TlSolidWrapper **at = &s->blocks[w->block].wrappers; *at; at = &(*at)->next)
    if (*at == w) {
      *at = w->next;
      tl_free(handle);
      return;
    }
  *handle = NULL; /* not this solid's: nothing to remove */
}

int tl_solid_n_wrappers(const TlSolid *s, int b)
{
  if (b < 0 || b >= s->mesh->n_blocks) return 0;
  int n = 0;
  for (const TlSolidWrapper *w = s->blocks[b].wrappers; w; w = w->next) ++n;
  return n;
}

void tl_solid_free_wrappers(TlSolid *s)
{
  for (int b = 0; b < s->mesh->n_blocks && s->blocks; ++b)
    while (s->blocks[b].wrappers) {
      TlSolidWrapper *w = s->blocks[b].wrappers;
      s->blocks[b].wrappers = w->next;
      tl_free(&w);
    }
}

TlStatus tl_solid_block_evaluate(TlSolid *s, int b, double t, const double *u_nodes, double *f_nodes, double c_u,
                                 TlSparse *K, double *W)
{
  TL_CHECK(tl_solid_block_forces(s, b, u_nodes, f_nodes, c_u, K, W));
  for (const TlSolidWrapper *w = s->blocks[b].wrappers; w; w = w->next)
    if (w->ops->internal) TL_CHECK(w->ops->internal(w->ctx, s, b, t, u_nodes, f_nodes, c_u, K, W));
  return TL_OK;
}

int tl_solid_has_wrapper_loads(const TlSolid *s)
{
  for (int b = 0; b < s->mesh->n_blocks; ++b)
    for (const TlSolidWrapper *w = s->blocks[b].wrappers; w; w = w->next)
      if (w->ops->external) return 1;
  return 0;
}

TlStatus tl_solid_wrapper_loads(TlSolid *s, double t, const double *u_nodes, double *f_nodes, double c, TlSparse *K)
{
  for (int b = 0; b < s->mesh->n_blocks; ++b)
    for (const TlSolidWrapper *w = s->blocks[b].wrappers; w; w = w->next)
      if (w->ops->external) TL_CHECK(w->ops->external(w->ctx, s, b, t, u_nodes, f_nodes, c, K));
  return TL_OK;
}
