/* The rigid-mode check of the boundary conditions. */
#include "tl_solid_private.h"

#include <math.h>

#include "tl_memory.h"

static size_t find_root(size_t *parent, size_t i)
{
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

TlStatus tl_solid_check_constraints(const TlSolid *s)
{
  const TlMesh *mesh = s->mesh;
  int dim = s->dim, nm = dim == 3 ? 6 : 3;
  size_t n = s->n_nodes;
  size_t *parent = NULL;
  TL_CHECK(tl_calloc(&parent, n, sizeof(size_t)));
  for (size_t i = 0; i < n; ++i) parent[i] = i;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    int nn = blk->type->n_nodes;
    for (size_t e = 0; e < blk->n_elements; ++e)
      for (int a = 1; a < nn; ++a) {
        size_t r0 = find_root(parent, blk->conn[e * nn]), r1 = find_root(parent, blk->conn[e * nn + a]);
        if (r0 != r1) parent[r1] = r0;
      }
  }
  TlStatus st = TL_OK;
  for (size_t root = 0; root < n && st == TL_OK; ++root) {
    if (find_root(parent, root) != root) continue;
    /* Rigid modes of this component about its centroid; Gram matrix of
     * their values at the constrained dofs. */
    double c[3] = {0, 0, 0}, count = 0, scale = 0.0;
    for (size_t i = 0; i < n; ++i)
      if (find_root(parent, i) == root) {
        for (int k = 0; k < 3; ++k) c[k] += mesh->x[3 * i + k];
        count += 1;
      }
    for (int k = 0; k < 3; ++k) c[k] /= count;
    for (size_t i = 0; i < n; ++i)
      if (find_root(parent, i) == root)
        for (int k = 0; k < 3; ++k) scale = fmax(scale, fabs(mesh->x[3 * i + k] - c[k]));
    if (scale == 0.0) scale = 1.0;
    double G[6][6] = {{0}};
    for (size_t i = 0; i < n; ++i) {
      if (find_root(parent, i) != root) continue;
      double r[3];
      for (int k = 0; k < 3; ++k) r[k] = (mesh->x[3 * i + k] - c[k]) / scale;
      for (int comp = 0; comp < dim; ++comp) {
        if (!s->constraint[i * dim + comp]) continue;
        double m[6] = {0};
        m[comp] = 1.0; /* translations */
        if (dim == 3) {
          /* rotation about axis k: (e_k x r)_comp */
          double e0[3] = {0, -r[2], r[1]}, e1[3] = {r[2], 0, -r[0]}, e2[3] = {-r[1], r[0], 0};
          m[3] = e0[comp], m[4] = e1[comp], m[5] = e2[comp];
        } else {
          m[2] = comp == 0 ? -r[1] : r[0];
        }
        for (int p = 0; p < nm; ++p)
          for (int q = 0; q < nm; ++q) G[p][q] += m[p] * m[q];
      }
    }
    /* Cholesky with a relative pivot test: a (near-)zero pivot is a mode
     * that no constraint touches. */
    double L[6][6] = {{0}};
    int free_mode = -1;
    for (int j = 0; j < nm && free_mode < 0; ++j) {
      double d = G[j][j];
      for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
      if (!(d > 1e-10 * (G[j][j] > 1.0 ? G[j][j] : 1.0))) {
        free_mode = j;
        break;
      }
      L[j][j] = sqrt(d);
      for (int i = j + 1; i < nm; ++i) {
        double v = G[i][j];
        for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
        L[i][j] = v / L[j][j];
      }
    }
    if (free_mode >= 0) {
      static const char *const names3[6] = {"translation along x", "translation along y", "translation along z",
                                            "rotation about x",    "rotation about y",    "rotation about z"};
      static const char *const names2[3] = {"translation along x", "translation along y", "rotation in the plane"};
      int block = 0;
      for (int b = 0; b < mesh->n_blocks; ++b)
        for (size_t e = 0; e < mesh->blocks[b].n_elements; ++e)
          if (find_root(parent, mesh->blocks[b].conn[e * mesh->blocks[b].type->n_nodes]) == root) {
            block = b;
            b = mesh->n_blocks;
            break;
          }
      st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                        "solid: the part of element block '%s' containing node %zu can move rigidly "
                        "(%s is not constrained); constrained node sets: %s",
                        mesh->blocks[block].name, root, dim == 3 ? names3[free_mode] : names2[free_mode],
                        s->constraint_sets[0] ? s->constraint_sets : "none");
    }
  }
  tl_free(&parent);
  return st;
}
