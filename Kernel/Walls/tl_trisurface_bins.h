/* Which triangles of a large surface are near any particle.
 *
 * Algorithm 2 of seeds/001 queries the hierarchical grid with the bounding
 * box of every triangle, which costs O(N_w) per step however few triangles
 * the particles touch.  To keep the time per step independent of the size of
 * the surface, the triangles are sorted once per surface update into uniform
 * bins; each step every particle marks the bins its extent [x - r, x + r]
 * covers, and only the triangles in marked bins go on to Algorithm 2's box
 * query.  Cost per step: O(N + triangles near particles).  Exact: a triangle
 * that touches a particle has a bounding box meeting the particle's extent,
 * so they share a bin.  In periodic domains the particle's images across the
 * periodic faces mark bins too.
 *
 * Marks are step stamps, so no per-step clearing over all bins. */
#ifndef TL_TRISURFACE_BINS_H
#define TL_TRISURFACE_BINS_H

#include <stddef.h>
#include <stdint.h>
#include "tl_domain.h"
#include "tl_error.h"
#include "tl_trisurface.h"

typedef struct {
  TlVec3 lo;        /* corner of bin (0, 0, 0) */
  double size;      /* edge of a cubic bin */
  int n[3];
  size_t n_bins, bin_capacity;
  size_t *start;    /* n_bins + 1 offsets into tri */
  int32_t *tri;     /* triangles of each bin */
  size_t tri_capacity;
  uint32_t *bin_stamp;
  uint32_t *tri_stamp;
  size_t tri_stamp_capacity;
  uint32_t now;
  unsigned long built_version; /* surface->version the bins were built from */
  int built;
  int32_t *selected; /* triangles near particles, this step */
  size_t n_selected, selected_capacity;
} TlTriBins;

/* Sorts the triangles of s into bins (when s changed since the last build). */
TlStatus tl_tribins_build(TlTriBins *b, const TlTriSurface *s);
/* Fills b->selected with the triangles whose bins the free particles
 * (motion == NULL or motion[i] == 0) reach, each particle reaching radius +
 * margin around its centre. */
TlStatus tl_tribins_select(TlTriBins *b, const TlTriSurface *s, const TlDomain *domain, size_t n,
                           const TlVec3 *x, const double *radius, const uint8_t *motion, double margin);
void tl_tribins_free(TlTriBins *b);

#endif
