/* The Gmsh reader's raw data, shared by its parser (tl_mesh_gmsh.c) and the
 * mesh builder (tl_mesh_gmsh_build.c); not part of the public API. */
#ifndef TL_MESH_GMSH_PRIVATE_H
#define TL_MESH_GMSH_PRIVATE_H

#include "tl_element.h"
#include "tl_mesh.h"

typedef struct {
  int dim;
  long tag;
  long phys; /* first physical tag, 0 when none */
} Entity;

typedef struct {
  int dim;
  long tag;
  char name[TL_MESH_NAME_MAX];
} PhysName;

typedef struct {
  int dim;
  long entity;
  const TlElementType *type; /* NULL for points */
  long tag;
  int line;
  size_t first; /* offset into the node-tag list */
  int n_nodes;
} RawElement;

typedef struct {
  Entity *entities;
  size_t n_entities, cap_entities;
  PhysName *names;
  size_t n_names, cap_names;
  long *node_tag_to_index; /* by tag, -1 undefined */
  long max_node_tag;
  double *x;
  size_t n_nodes;
  RawElement *elements;
  size_t n_elements;
  long *element_nodes; /* node tags */
  size_t n_element_nodes;
} GmshData;

/* Copies a name, cut to TL_MESH_NAME_MAX - 1 characters. */
void tl_gmsh_copy_name(char *dst, const char *src);
/* The first physical tag of entity (dim, tag); 0 when none. */
long tl_gmsh_entity_phys(const GmshData *g, int dim, long tag);
/* The mesh of g; `path` names the file in messages. */
TlStatus tl_gmsh_build(const char *path, const GmshData *g, TlMesh **out);

#endif
