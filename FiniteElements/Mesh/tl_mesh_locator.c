#include "tl_mesh_locator.h"

#include <math.h>
#include <string.h>

#include "tl_memory.h"

struct TlMeshLocator {
  const TlMesh *mesh;
  double *x;          /* 3 per node */
  double lo[3], h[3]; /* grid origin and cell size */
  size_t n[3];
  size_t *cell_ptr;   /* n[0] n[1] n[2] + 1 */
  size_t *cell_items; /* global element indices */
  size_t *block_offset;
  size_t n_elements;
};

static void element_box(const TlMeshLocator *l, int b, size_t e, double lo[3], double hi[3])
{
  const TlElementBlock *blk = &l->mesh->blocks[b];
  int nn = blk->type->n_nodes;
  for (int i = 0; i < 3; ++i) lo[i] = INFINITY, hi[i] = -INFINITY;
  for (int a = 0; a < nn; ++a) {
    const double *p = l->x + 3 * blk->conn[e * nn + a];
    for (int i = 0; i < 3; ++i) lo[i] = fmin(lo[i], p[i]), hi[i] = fmax(hi[i], p[i]);
  }
  /* Curved quadratic elements may bulge past their nodes a little. */
  double pad = 0.0;
  for (int i = 0; i < 3; ++i) pad = fmax(pad, hi[i] - lo[i]);
  pad *= blk->type->linear ? 1e-9 : 0.1;
  for (int i = 0; i < 3; ++i) lo[i] -= pad, hi[i] += pad;
}

static void cell_range(const TlMeshLocator *l, const double lo[3], const double hi[3], size_t c0[3], size_t c1[3])
{
  for (int i = 0; i < 3; ++i) {
    double a = floor((lo[i] - l->lo[i]) / l->h[i]), b = floor((hi[i] - l->lo[i]) / l->h[i]);
    a = fmax(0.0, fmin(a, (double)l->n[i] - 1)), b = fmax(0.0, fmin(b, (double)l->n[i] - 1));
    c0[i] = (size_t)a, c1[i] = (size_t)b;
  }
}

static TlStatus build(TlMeshLocator *l)
{
  const TlMesh *m = l->mesh;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < m->n_nodes; ++i)
    for (int k = 0; k < 3; ++k) {
      if (!isfinite(l->x[3 * i + k])) TL_ERROR(TL_ERR_NUMERIC, "locator: node %zu position is not finite", i);
      lo[k] = fmin(lo[k], l->x[3 * i + k]), hi[k] = fmax(hi[k], l->x[3 * i + k]);
    }
  double ext = 0.0;
  for (int k = 0; k < 3; ++k) ext = fmax(ext, hi[k] - lo[k]);
  /* About one element per cell: cell size from the volume per element. */
  double vol = 1.0;
  int dims = 0;
  for (int k = 0; k < 3; ++k)
    if (hi[k] - lo[k] > 1e-12 * ext) vol *= hi[k] - lo[k], ++dims;
  double h = dims ? pow(vol / (double)(l->n_elements ? l->n_elements : 1), 1.0 / dims) : 1.0;
  for (int k = 0; k < 3; ++k) {
    double span = fmax(hi[k] - lo[k], 1e-12 * ext);
    size_t n = (size_t)fmin(fmax(1.0, ceil(span / h)), 256.0);
    l->n[k] = n;
    l->lo[k] = lo[k] - 1e-9 * ext;
    l->h[k] = (span + 2e-9 * ext) / n;
  }
  size_t ncell = l->n[0] * l->n[1] * l->n[2];
  tl_free(&l->cell_ptr);
  tl_free(&l->cell_items);
  TL_CHECK(tl_calloc(&l->cell_ptr, ncell + 1, sizeof(size_t)));
  for (int pass = 0; pass < 2; ++pass) {
    for (int b = 0; b < m->n_blocks; ++b)
      for (size_t e = 0; e < m->blocks[b].n_elements; ++e) {
        double blo[3], bhi[3];
        size_t c0[3], c1[3];
        element_box(l, b, e, blo, bhi);
        cell_range(l, blo, bhi, c0, c1);
        for (size_t k = c0[2]; k <= c1[2]; ++k)
          for (size_t j = c0[1]; j <= c1[1]; ++j)
            for (size_t i = c0[0]; i <= c1[0]; ++i) {
              size_t c = i + l->n[0] * (j + l->n[1] * k);
              if (pass == 0) l->cell_ptr[c + 1]++;
              else l->cell_items[l->cell_ptr[c]++] = l->block_offset[b] + e;
            }
      }
    if (pass == 0) {
      for (size_t c = 0; c < ncell; ++c) l->cell_ptr[c + 1] += l->cell_ptr[c];
      TL_CHECK(tl_calloc(&l->cell_items, l->cell_ptr[ncell] ? l->cell_ptr[ncell] : 1, sizeof(size_t)));
    } else {
      for (size_t c = ncell; c > 0; --c) l->cell_ptr[c] = l->cell_ptr[c - 1];
      l->cell_ptr[0] = 0;
    }
  }
  return TL_OK;
}

TlStatus tl_mesh_locator_create(const TlMesh *mesh, const double *x, TlMeshLocator **loc)
{
  if (!mesh || !loc) TL_ERROR(TL_ERR_ARG, "tl_mesh_locator_create: NULL argument");
  if (!mesh->finalized) TL_ERROR(TL_ERR_STATE, "locator: mesh not finalized");
  TlMeshLocator *l = NULL;
  TL_CHECK(TL_NEW(l));
  l->mesh = mesh;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_calloc(&l->x, 3 * mesh->n_nodes, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&l->block_offset, mesh->n_blocks + 1, sizeof(size_t)), fail);
  for (int b = 0; b < mesh->n_blocks; ++b) l->block_offset[b + 1] = l->block_offset[b] + mesh->blocks[b].n_elements;
  l->n_elements = l->block_offset[mesh->n_blocks];
  TL_CHECK_GOTO(s, tl_mesh_locator_update(l, x), fail);
  *loc = l;
  return TL_OK;
fail:
  tl_mesh_locator_destroy(&l);
  return s;
}

TlStatus tl_mesh_locator_update(TlMeshLocator *l, const double *x)
{
  memcpy(l->x, x ? x : l->mesh->x, 3 * l->mesh->n_nodes * sizeof(double));
  TL_CHECK(build(l));
  return TL_OK;
}

void tl_mesh_locator_destroy(TlMeshLocator **loc)
{
  if (!loc || !*loc) return;
  tl_free(&(*loc)->x);
  tl_free(&(*loc)->cell_ptr);
  tl_free(&(*loc)->cell_items);
  tl_free(&(*loc)->block_offset);
  tl_free(loc);
}

TlStatus tl_mesh_locate(const TlMeshLocator *l, const double point[3], double tol, TlFaceRef *where, double xi[3])
{
  const TlMesh *m = l->mesh;
  size_t c[3];
  for (int i = 0; i < 3; ++i) {
    double f = floor((point[i] - l->lo[i]) / l->h[i]);
    if (!(f >= 0.0 && f < (double)l->n[i]))
      TL_ERROR(TL_ERR_NOT_FOUND, "point (%g, %g, %g) lies outside the mesh", point[0], point[1], point[2]);
    c[i] = (size_t)f;
  }
  size_t cell = c[0] + l->n[0] * (c[1] + l->n[1] * c[2]);
  for (size_t k = l->cell_ptr[cell]; k < l->cell_ptr[cell + 1]; ++k) {
    size_t g = l->cell_items[k];
    int b = 0;
    while (g >= l->block_offset[b + 1]) ++b;
    size_t e = g - l->block_offset[b];
    const TlElementBlock *blk = &m->blocks[b];
    double x[TL_ELEMENT_MAX_NODES * 3], r[3];
    for (int a = 0; a < blk->type->n_nodes; ++a) memcpy(x + 3 * a, l->x + 3 * blk->conn[e * blk->type->n_nodes + a], 3 * sizeof(double));
    int inside = 0;
    if (tl_element_inverse_map(blk->type, m->dim, x, point, r, &inside) != TL_OK) {
      tl_error_clear();
      continue;
    }
    if (tl_element_contains(blk->type, r, tol)) {
      where->block = b;
      where->element = e;
      where->face = -1;
      memcpy(xi, r, 3 * sizeof(double));
      return TL_OK;
    }
  }
  TL_ERROR(TL_ERR_NOT_FOUND, "point (%g, %g, %g) lies in no element of the mesh", point[0], point[1], point[2]);
}
