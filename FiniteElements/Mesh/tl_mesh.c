#include "tl_mesh.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"

TlStatus tl_mesh_create(int dim, TlMesh **mesh)
{
  if (!mesh) TL_ERROR(TL_ERR_ARG, "tl_mesh_create: NULL output");
  if (dim != 2 && dim != 3) TL_ERROR(TL_ERR_ARG, "mesh dimension %d is not 2 or 3", dim);
  TlMesh *m = NULL;
  TL_CHECK(TL_NEW(m));
  m->dim = dim;
  *mesh = m;
  return TL_OK;
}

void tl_mesh_destroy(TlMesh **mesh)
{
  if (!mesh || !*mesh) return;
  TlMesh *m = *mesh;
  for (int b = 0; b < m->n_blocks; ++b) {
    tl_free(&m->blocks[b].conn);
    tl_free(&m->blocks[b].tags);
  }
  for (int s = 0; s < m->n_node_sets; ++s) tl_free(&m->node_sets[s].nodes);
  for (int s = 0; s < m->n_face_sets; ++s) tl_free(&m->face_sets[s].faces);
  tl_free(&m->blocks);
  tl_free(&m->node_sets);
  tl_free(&m->face_sets);
  tl_free(&m->boundary);
  tl_free(&m->x);
  tl_free(mesh);
}

static TlStatus check_name(const char *name, const char *what)
{
  if (!name || !name[0]) TL_ERROR(TL_ERR_ARG, "%s without a name", what);
  if (strlen(name) >= TL_MESH_NAME_MAX)
    TL_ERROR(TL_ERR_ARG, "%s name '%s' longer than %d characters", what, name,
             TL_MESH_NAME_MAX - 1);
  return TL_OK;
}

TlStatus tl_mesh_set_nodes(TlMesh *mesh, size_t n, const double *x)
{
  for (size_t i = 0; i < 3 * n; ++i)
    if (!isfinite(x[i]))
      TL_ERROR(TL_ERR_ARG, "node %zu has a non-finite coordinate %g", i / 3, x[i]);
  tl_free(&mesh->x);
  TL_CHECK(tl_calloc(&mesh->x, 3 * (n ? n : 1), sizeof(double)));
  memcpy(mesh->x, x, 3 * n * sizeof(double));
  mesh->n_nodes = n;
  mesh->finalized = 0;
  return TL_OK;
}

TlStatus tl_mesh_add_block(TlMesh *mesh, const char *name, const TlElementType *type,
                           size_t n_elements, const size_t *conn, const long *tags, int *index)
{
  TL_CHECK(check_name(name, "element block"));
  if (!type) TL_ERROR(TL_ERR_ARG, "element block %s without an element type", name);
  if (type->dim != mesh->dim)
    TL_ERROR(TL_ERR_ARG, "element block %s: %s elements have dimension %d, the mesh %d", name,
             type->header.name, type->dim, mesh->dim);
  for (int b = 0; b < mesh->n_blocks; ++b)
    if (!strcmp(mesh->blocks[b].name, name))
      TL_ERROR(TL_ERR_ARG, "element block name '%s' used twice", name);
  for (size_t i = 0; i < n_elements * (size_t)type->n_nodes; ++i)
    if (conn[i] >= mesh->n_nodes)
      TL_ERROR(TL_ERR_ARG, "element block %s: element %zu refers to node %zu, the mesh has %zu",
               name, i / type->n_nodes, conn[i], mesh->n_nodes);
  TL_CHECK(tl_realloc(&mesh->blocks, mesh->n_blocks + 1, sizeof *mesh->blocks));
  TlElementBlock *blk = &mesh->blocks[mesh->n_blocks];
  memset(blk, 0, sizeof *blk);
  snprintf(blk->name, sizeof blk->name, "%s", name);
  blk->type = type;
  blk->n_elements = n_elements;
  size_t nc = n_elements * type->n_nodes;
  TL_CHECK(tl_calloc(&blk->conn, nc ? nc : 1, sizeof(size_t)));
  memcpy(blk->conn, conn, nc * sizeof(size_t));
  if (tags) {
    TL_CHECK(tl_calloc(&blk->tags, n_elements ? n_elements : 1, sizeof(long)));
    memcpy(blk->tags, tags, n_elements * sizeof(long));
  }
  if (index) *index = mesh->n_blocks;
  mesh->n_blocks++;
  mesh->finalized = 0;
  return TL_OK;
}

static int cmp_size(const void *a, const void *b)
{
  size_t x = *(const size_t *)a, y = *(const size_t *)b;
  return x < y ? -1 : x > y;
}

TlStatus tl_mesh_add_node_set(TlMesh *mesh, const char *name, size_t n, const size_t *nodes)
{
  TL_CHECK(check_name(name, "node set"));
  for (int s = 0; s < mesh->n_node_sets; ++s)
    if (!strcmp(mesh->node_sets[s].name, name))
      TL_ERROR(TL_ERR_ARG, "node set name '%s' used twice", name);
  for (size_t i = 0; i < n; ++i)
    if (nodes[i] >= mesh->n_nodes)
      TL_ERROR(TL_ERR_ARG, "node set %s: node %zu, the mesh has %zu", name, nodes[i],
               mesh->n_nodes);
  TL_CHECK(tl_realloc(&mesh->node_sets, mesh->n_node_sets + 1, sizeof *mesh->node_sets));
  TlNodeSet *s = &mesh->node_sets[mesh->n_node_sets];
  memset(s, 0, sizeof *s);
  snprintf(s->name, sizeof s->name, "%s", name);
  TL_CHECK(tl_calloc(&s->nodes, n ? n : 1, sizeof(size_t)));
  memcpy(s->nodes, nodes, n * sizeof(size_t));
  qsort(s->nodes, n, sizeof(size_t), cmp_size);
  size_t k = 0;
  for (size_t i = 0; i < n; ++i)
    if (k == 0 || s->nodes[i] != s->nodes[k - 1]) s->nodes[k++] = s->nodes[i];
  s->n = k;
  mesh->n_node_sets++;
  return TL_OK;
}

TlStatus tl_mesh_add_face_set(TlMesh *mesh, const char *name, size_t n, const TlFaceRef *faces)
{
  TL_CHECK(check_name(name, "face set"));
  for (int s = 0; s < mesh->n_face_sets; ++s)
    if (!strcmp(mesh->face_sets[s].name, name))
      TL_ERROR(TL_ERR_ARG, "face set name '%s' used twice", name);
  for (size_t i = 0; i < n; ++i) {
    TlFaceRef f = faces[i];
    if (f.block < 0 || f.block >= mesh->n_blocks || f.element >= mesh->blocks[f.block].n_elements ||
        f.face < 0 || f.face >= mesh->blocks[f.block].type->n_faces)
      TL_ERROR(TL_ERR_ARG, "face set %s: face %zu (block %d, element %zu, face %d) does not exist",
               name, i, f.block, f.element, f.face);
  }
  TL_CHECK(tl_realloc(&mesh->face_sets, mesh->n_face_sets + 1, sizeof *mesh->face_sets));
  TlFaceSet *s = &mesh->face_sets[mesh->n_face_sets];
  memset(s, 0, sizeof *s);
  snprintf(s->name, sizeof s->name, "%s", name);
  TL_CHECK(tl_calloc(&s->faces, n ? n : 1, sizeof(TlFaceRef)));
  memcpy(s->faces, faces, n * sizeof(TlFaceRef));
  s->n = n;
  mesh->n_face_sets++;
  return TL_OK;
}

TlStatus tl_mesh_add_node_set_from_faces(TlMesh *mesh, const char *face_set, const char *name)
{
  const TlFaceSet *fs = NULL;
  TL_CHECK(tl_mesh_find_face_set(mesh, face_set, &fs));
  size_t total = 0;
  for (size_t i = 0; i < fs->n; ++i)
    total += mesh->blocks[fs->faces[i].block].type->face_n_nodes;
  size_t *nodes = NULL;
  TL_CHECK(tl_calloc(&nodes, total ? total : 1, sizeof(size_t)));
  size_t k = 0;
  for (size_t i = 0; i < fs->n; ++i) {
    const TlElementBlock *blk = &mesh->blocks[fs->faces[i].block];
    tl_mesh_face_nodes(mesh, fs->faces[i], nodes + k, NULL);
    k += blk->type->face_n_nodes;
  }
  TlStatus s = tl_mesh_add_node_set(mesh, name, k, nodes);
  tl_free(&nodes);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}

void tl_mesh_element_coords(const TlMesh *mesh, int b, size_t e, double *x)
{
  const TlElementBlock *blk = &mesh->blocks[b];
  int nn = blk->type->n_nodes;
  for (int a = 0; a < nn; ++a) memcpy(x + 3 * a, mesh->x + 3 * blk->conn[e * nn + a], 3 * sizeof(double));
}

void tl_mesh_face_nodes(const TlMesh *mesh, TlFaceRef f, size_t *nodes, double *x)
{
  const TlElementBlock *blk = &mesh->blocks[f.block];
  const TlElementType *t = blk->type;
  for (int k = 0; k < t->face_n_nodes; ++k) {
    size_t node = blk->conn[f.element * t->n_nodes + t->face_nodes[f.face * t->face_n_nodes + k]];
    if (nodes) nodes[k] = node;
    if (x) memcpy(x + 3 * k, mesh->x + 3 * node, 3 * sizeof(double));
  }
}

TlStatus tl_mesh_find_node_set(const TlMesh *mesh, const char *name, const TlNodeSet **set)
{
  char known[512] = "";
  for (int s = 0; s < mesh->n_node_sets; ++s) {
    if (!strcmp(mesh->node_sets[s].name, name)) {
      *set = &mesh->node_sets[s];
      return TL_OK;
    }
    size_t l = strlen(known);
    snprintf(known + l, sizeof known - l, "%s%s", s ? ", " : "", mesh->node_sets[s].name);
  }
  TL_ERROR(TL_ERR_NOT_FOUND, "no node set '%s' in the mesh (node sets: %s)", name,
           known[0] ? known : "none");
}

TlStatus tl_mesh_find_face_set(const TlMesh *mesh, const char *name, const TlFaceSet **set)
{
  char known[512] = "";
  for (int s = 0; s < mesh->n_face_sets; ++s) {
    if (!strcmp(mesh->face_sets[s].name, name)) {
      *set = &mesh->face_sets[s];
      return TL_OK;
    }
    size_t l = strlen(known);
    snprintf(known + l, sizeof known - l, "%s%s", s ? ", " : "", mesh->face_sets[s].name);
  }
  TL_ERROR(TL_ERR_NOT_FOUND, "no face set '%s' in the mesh (face sets: %s)", name,
           known[0] ? known : "none");
}

TlStatus tl_mesh_find_block(const TlMesh *mesh, const char *name, int *index)
{
  for (int b = 0; b < mesh->n_blocks; ++b)
    if (!strcmp(mesh->blocks[b].name, name)) {
      *index = b;
      return TL_OK;
    }
  TL_ERROR(TL_ERR_NOT_FOUND, "no element block '%s' in the mesh", name);
}

/* --------------------------------------------------------- boundary faces */

typedef struct {
  size_t key[4];
  TlFaceRef ref;
} FaceKey;

static int cmp_face_key(const void *a, const void *b)
{
  const FaceKey *x = a, *y = b;
  for (int i = 0; i < 4; ++i)
    if (x->key[i] != y->key[i]) return x->key[i] < y->key[i] ? -1 : 1;
  return 0;
}

static TlStatus compute_boundary(TlMesh *mesh)
{
  size_t total = 0;
  for (int b = 0; b < mesh->n_blocks; ++b)
    total += mesh->blocks[b].n_elements * mesh->blocks[b].type->n_faces;
  FaceKey *keys = NULL;
  TL_CHECK(tl_calloc(&keys, total ? total : 1, sizeof *keys));
  size_t k = 0;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    const TlElementType *t = blk->type;
    int nc = t->face_type ? t->face_type->n_corners : 1;
    for (size_t e = 0; e < blk->n_elements; ++e)
      for (int f = 0; f < t->n_faces; ++f) {
        FaceKey *fk = &keys[k++];
        for (int i = 0; i < 4; ++i) fk->key[i] = SIZE_MAX;
        for (int i = 0; i < nc; ++i)
          fk->key[i] = blk->conn[e * t->n_nodes + t->face_nodes[f * t->face_n_nodes + i]];
        qsort(fk->key, nc, sizeof(size_t), cmp_size);
        fk->ref = (TlFaceRef){.block = b, .face = f, .element = e};
      }
  }
  qsort(keys, total, sizeof *keys, cmp_face_key);
  tl_free(&mesh->boundary);
  size_t nb = 0;
  for (size_t i = 0; i < total;) {
    size_t j = i + 1;
    while (j < total && !cmp_face_key(&keys[i], &keys[j])) ++j;
    if (j - i == 1) keys[nb++] = keys[i];
    if (j - i > 2) {
      TlFaceRef r = keys[i].ref;
      TlStatus s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                                "block %s element %zu face %d is shared by %zu elements "
                                "(non-manifold or duplicated elements)",
                                mesh->blocks[r.block].name, r.element, r.face, j - i);
      tl_free(&keys);
      return s;
    }
    i = j;
  }
  TlStatus s = tl_calloc(&mesh->boundary, nb ? nb : 1, sizeof(TlFaceRef));
  if (s == TL_OK) {
    for (size_t i = 0; i < nb; ++i) mesh->boundary[i] = keys[i].ref;
    mesh->n_boundary = nb;
  }
  tl_free(&keys);
  return s;
}

static TlStatus check_elements(const TlMesh *mesh)
{
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    const TlElementType *t = blk->type;
    TlQuadrature q;
    TL_CHECK(tl_element_quadrature(t, t->order_stiffness, &q));
    for (size_t e = 0; e < blk->n_elements; ++e) {
      double x[TL_ELEMENT_MAX_NODES * 3];
      tl_mesh_element_coords(mesh, b, e, x);
      double h = 0.0;
      for (int a = 1; a < t->n_corners; ++a) {
        double d2 = 0.0;
        for (int i = 0; i < 3; ++i) d2 += (x[3 * a + i] - x[i]) * (x[3 * a + i] - x[i]);
        h = fmax(h, sqrt(d2));
      }
      double tol = 1e-10 * pow(h, mesh->dim);
      long tag = blk->tags ? blk->tags[e] : (long)e;
      for (int p = 0; p < t->n_corners + q.n; ++p) {
        double xi[3] = {0, 0, 0}, J[3][3], det;
        if (p < t->n_corners)
          for (int d = 0; d < t->dim; ++d) xi[d] = t->ref_coords[p * t->dim + d];
        else
          memcpy(xi, q.xi[p - t->n_corners], sizeof xi);
        TL_CHECK(tl_element_jacobian(t, mesh->dim, x, xi, J, &det));
        if (!(det > tol))
          TL_ERROR(TL_ERR_NUMERIC,
                   "block %s element %zu (tag %ld, %s): Jacobian determinant %g %s at %s %d; the "
                   "element is %s",
                   blk->name, e, tag, t->header.name, det, det < 0 ? "< 0" : "~ 0",
                   p < t->n_corners ? "corner" : "Gauss point",
                   p < t->n_corners ? p : p - t->n_corners,
                   det < -tol ? "inverted (node order or geometry)" : "degenerate");
      }
    }
  }
  return TL_OK;
}

TlStatus tl_mesh_finalize(TlMesh *mesh)
{
  if (mesh->n_nodes == 0) TL_ERROR(TL_ERR_ARG, "mesh without nodes");
  if (mesh->n_blocks == 0) TL_ERROR(TL_ERR_ARG, "mesh without element blocks");
  TL_CHECK(check_elements(mesh));
  TL_CHECK(compute_boundary(mesh));
  mesh->finalized = 1;
  return TL_OK;
}

double tl_mesh_volume(const TlMesh *mesh)
{
  double V = 0.0;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    TlQuadrature q;
    if (tl_element_quadrature(blk->type, blk->type->order_mass, &q) != TL_OK) return NAN;
    for (size_t e = 0; e < blk->n_elements; ++e) {
      double x[TL_ELEMENT_MAX_NODES * 3], J[3][3], det;
      tl_mesh_element_coords(mesh, b, e, x);
      for (int p = 0; p < q.n; ++p) {
        tl_element_jacobian(blk->type, mesh->dim, x, q.xi[p], J, &det);
        V += q.w[p] * det;
      }
    }
  }
  return V;
}
