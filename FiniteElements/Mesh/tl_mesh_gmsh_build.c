/* The mesh a Gmsh file describes, from the reader's raw data (both formats):
 * blocks of the highest dimension, face and node sets from the physical
 * groups of the dimension below. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_mesh.h"
#include "tl_mesh_gmsh_private.h"

/* Copies a name, truncated to the mesh's limit. */
void tl_gmsh_copy_name(char *dst, const char *src)
{
  size_t n = strlen(src);
  if (n >= TL_MESH_NAME_MAX) n = TL_MESH_NAME_MAX - 1;
  memcpy(dst, src, n);
  dst[n] = '\0';
}

long tl_gmsh_entity_phys(const GmshData *g, int dim, long tag)
{
  for (size_t i = 0; i < g->n_entities; ++i)
    if (g->entities[i].dim == dim && g->entities[i].tag == tag) return g->entities[i].phys;
  return 0;
}

static void phys_name(const GmshData *g, int dim, long phys, char *out)
{
  for (size_t i = 0; i < g->n_names; ++i)
    if (g->names[i].dim == dim && g->names[i].tag == phys) {
      tl_gmsh_copy_name(out, g->names[i].name);
      return;
    }
  snprintf(out, TL_MESH_NAME_MAX, "physical%ld", phys);
}

TlStatus tl_gmsh_build(const char *path, const GmshData *g, TlMesh **out)
{
  int top = 0;
  for (size_t i = 0; i < g->n_elements; ++i)
    if (g->elements[i].type && g->elements[i].dim > top) top = g->elements[i].dim;
  if (top < 2)
    TL_ERROR(TL_ERR_FORMAT, "%s: no elements of dimension 2 or 3 (highest dimension %d)", path, top);
  TlStatus s = TL_OK;
  long *new_index = NULL;
  double *x = NULL;
  size_t *conn = NULL, *nodes = NULL;
  long *tags = NULL;
  TlFaceRef *faces = NULL;
  TlMesh *mesh = NULL;
  TL_CHECK_GOTO(s, tl_calloc(&new_index, g->n_nodes ? g->n_nodes : 1, sizeof(long)), done);
  for (size_t i = 0; i < g->n_nodes; ++i) new_index[i] = -1;
  /* Keep the nodes of top-dimensional elements, in file order. */
  for (size_t i = 0; i < g->n_elements; ++i) {
    const RawElement *e = &g->elements[i];
    if (e->dim != top) continue;
    for (int k = 0; k < e->n_nodes; ++k) new_index[g->node_tag_to_index[g->element_nodes[e->first + k]]] = 0;
  }
  size_t used = 0;
  TL_CHECK_GOTO(s, tl_calloc(&x, 3 * (g->n_nodes ? g->n_nodes : 1), sizeof(double)), done);
  for (size_t i = 0; i < g->n_nodes; ++i)
    if (new_index[i] == 0) {
      new_index[i] = (long)used;
      memcpy(x + 3 * used, g->x + 3 * i, 3 * sizeof(double));
      if (top == 2) x[3 * used + 2] = 0.0;
      ++used;
    } else {
      new_index[i] = -1;
    }
  TL_CHECK_GOTO(s, tl_mesh_create(top, &mesh), done);
  TL_CHECK_GOTO(s, tl_mesh_set_nodes(mesh, used, x), done);
  /* Blocks: one per (physical group, element type). */
  TL_CHECK_GOTO(s, tl_calloc(&conn, g->n_element_nodes ? g->n_element_nodes : 1, sizeof(size_t)), done);
  TL_CHECK_GOTO(s, tl_calloc(&tags, g->n_elements ? g->n_elements : 1, sizeof(long)), done);
  for (size_t i = 0; i < g->n_elements; ++i) {
    RawElement *e = &g->elements[i];
    if (e->dim != top || e->n_nodes < 0) continue;
    long phys = tl_gmsh_entity_phys(g, top, e->entity);
    /* Gather every element of the same group and type, then mark them done. */
    size_t ne = 0;
    for (size_t j = i; j < g->n_elements; ++j) {
      RawElement *f = &g->elements[j];
      if (f->dim != top || f->n_nodes < 0 || f->type != e->type ||
          tl_gmsh_entity_phys(g, top, f->entity) != phys)
        continue;
      for (int k = 0; k < f->n_nodes; ++k)
        conn[ne * f->n_nodes + k] = (size_t)new_index[g->node_tag_to_index[g->element_nodes[f->first + k]]];
      tags[ne++] = f->tag;
      if (j != i) f->n_nodes = -f->n_nodes - 1;
    }
    const TlElementType *type = e->type;
    e->n_nodes = -e->n_nodes - 1;
    char name[TL_MESH_NAME_MAX];
    if (phys) phys_name(g, top, phys, name);
    else snprintf(name, sizeof name, "body");
    int taken = 0;
    for (int b = 0; b < mesh->n_blocks; ++b) taken |= !strcmp(mesh->blocks[b].name, name);
    if (taken) {
      char longer[TL_MESH_NAME_MAX + 16];
      snprintf(longer, sizeof longer, "%s_%s", name, type->header.name);
      tl_gmsh_copy_name(name, longer);
    }
    TL_CHECK_GOTO(s, tl_mesh_add_block(mesh, name, type, ne, conn, tags, NULL), done);
  }
  for (size_t i = 0; i < g->n_elements; ++i)
    if (g->elements[i].n_nodes < 0) g->elements[i].n_nodes = -g->elements[i].n_nodes - 1;
  TL_CHECK_GOTO(s, tl_mesh_finalize(mesh), done);
  /* Physical groups of lower dimension: face sets (dimension top - 1) and
   * node sets. */
  TL_CHECK_GOTO(s, tl_calloc(&faces, g->n_elements ? g->n_elements : 1, sizeof *faces), done);
  TL_CHECK_GOTO(s, tl_calloc(&nodes, g->n_element_nodes ? g->n_element_nodes : 1, sizeof(size_t)), done);
  for (size_t n = 0; n < g->n_names; ++n) {
    const PhysName *p = &g->names[n];
    if (p->dim >= top) continue;
    size_t nf = 0, nn = 0;
    for (size_t i = 0; i < g->n_elements; ++i) {
      const RawElement *e = &g->elements[i];
      if (e->dim != p->dim || tl_gmsh_entity_phys(g, e->dim, e->entity) != p->tag) continue;
      size_t key[TL_ELEMENT_MAX_FACE_NODES];
      for (int k = 0; k < e->n_nodes; ++k) {
        long idx = new_index[g->node_tag_to_index[g->element_nodes[e->first + k]]];
        if (idx < 0) {
          s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                           "%s line %d: element %ld of physical group '%s' uses node %ld, which "
                           "belongs to no %d-D element",
                           path, e->line, e->tag, p->name, g->element_nodes[e->first + k], top);
          goto done;
        }
        nodes[nn++] = (size_t)idx;
        if (k < TL_ELEMENT_MAX_FACE_NODES) key[k] = (size_t)idx;
      }
      if (p->dim != top - 1 || !e->type) continue;
      /* Match the face element with a boundary face by its corner nodes. */
      int nc = e->type->n_corners, found = 0;
      for (size_t b = 0; b < mesh->n_boundary && !found; ++b) {
        size_t fn[TL_ELEMENT_MAX_FACE_NODES];
        tl_mesh_face_nodes(mesh, mesh->boundary[b], fn, NULL);
        const TlElementType *ft = mesh->blocks[mesh->boundary[b].block].type->face_type;
        if (ft->n_corners != nc) continue;
        int match = 1;
        for (int k = 0; k < nc && match; ++k) {
          int any = 0;
          for (int m = 0; m < nc; ++m) any |= fn[m] == key[k];
          match = any;
        }
        if (match) {
          faces[nf++] = mesh->boundary[b];
          found = 1;
        }
      }
      if (!found) {
        s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                         "%s line %d: element %ld of physical group '%s' is not a boundary face "
                         "of the mesh",
                         path, e->line, e->tag, p->name);
        goto done;
      }
    }
    if (p->dim == top - 1) TL_CHECK_GOTO(s, tl_mesh_add_face_set(mesh, p->name, nf, faces), done);
    TL_CHECK_GOTO(s, tl_mesh_add_node_set(mesh, p->name, nn, nodes), done);
  }
  *out = mesh;
  mesh = NULL;
done:
  tl_mesh_destroy(&mesh);
  tl_free(&new_index);
  tl_free(&x);
  tl_free(&conn);
  tl_free(&tags);
  tl_free(&faces);
  tl_free(&nodes);
  return s;
}
