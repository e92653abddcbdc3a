/* Unstructured finite-element meshes.
 *
 * Nodes (coordinates stored as x, y, z triples even in 2-D, where z = 0),
 * element blocks (one element type per block), named node sets and named
 * face sets (a face is element e of block b, local face f, whose outward
 * normal is given by the element type's face orientation), and the list of
 * all boundary faces.  Build one with the structured generators, the Gmsh
 * reader, or by hand (create, set nodes, add blocks and sets, finalize).
 * tl_mesh_finalize() refuses degenerate and inverted elements, naming the
 * block and the element. */
#ifndef TL_MESH_H
#define TL_MESH_H

#include <stddef.h>
#include "tl_element.h"
#include "tl_error.h"

#define TL_MESH_NAME_MAX 64

typedef struct {
  char name[TL_MESH_NAME_MAX];
  const TlElementType *type;
  size_t n_elements;
  size_t *conn; /* n_elements x type->n_nodes */
  long *tags;   /* element numbers of the source file, or NULL */
} TlElementBlock;

typedef struct {
  char name[TL_MESH_NAME_MAX];
  size_t n;
  size_t *nodes; /* sorted, unique */
} TlNodeSet;

typedef struct {
  int block;
  int face;
  size_t element;
} TlFaceRef;

typedef struct {
  char name[TL_MESH_NAME_MAX];
  size_t n;
  TlFaceRef *faces;
} TlFaceSet;

typedef struct {
  int dim; /* 2 (plane strain) or 3 */
  size_t n_nodes;
  double *x; /* 3 * n_nodes */
  int n_blocks;
  TlElementBlock *blocks;
  int n_node_sets;
  TlNodeSet *node_sets;
  int n_face_sets;
  TlFaceSet *face_sets;
  size_t n_boundary;
  TlFaceRef *boundary; /* every face not shared by two elements */
  int finalized;
} TlMesh;

TlStatus tl_mesh_create(int dim, TlMesh **mesh);
void tl_mesh_destroy(TlMesh **mesh);
/* Copies n nodes (3 coordinates each). */
TlStatus tl_mesh_set_nodes(TlMesh *mesh, size_t n, const double *x);
/* Copies a block; tags may be NULL.  *index (may be NULL) receives its index. */
TlStatus tl_mesh_add_block(TlMesh *mesh, const char *name, const TlElementType *type,
                           size_t n_elements, const size_t *conn, const long *tags, int *index);
/* Node set from a list (duplicates removed); a taken name is an error. */
TlStatus tl_mesh_add_node_set(TlMesh *mesh, const char *name, size_t n, const size_t *nodes);
TlStatus tl_mesh_add_face_set(TlMesh *mesh, const char *name, size_t n, const TlFaceRef *faces);
/* Node set holding every node of the faces of a face set. */
TlStatus tl_mesh_add_node_set_from_faces(TlMesh *mesh, const char *face_set, const char *name);
/* Checks connectivity, refuses degenerate or inverted elements (Jacobian
 * determinant not positive at a corner or a Gauss point), computes the
 * boundary faces. */
TlStatus tl_mesh_finalize(TlMesh *mesh);

/* Lookup by name; the error lists the names that exist. */
TlStatus tl_mesh_find_node_set(const TlMesh *mesh, const char *name, const TlNodeSet **set);
TlStatus tl_mesh_find_face_set(const TlMesh *mesh, const char *name, const TlFaceSet **set);
TlStatus tl_mesh_find_block(const TlMesh *mesh, const char *name, int *index);

/* Coordinates of the nodes of element e of block b (n_nodes x 3). */
void tl_mesh_element_coords(const TlMesh *mesh, int b, size_t e, double *x);
/* Global node numbers and coordinates of a face (face_n_nodes of them). */
void tl_mesh_face_nodes(const TlMesh *mesh, TlFaceRef f, size_t *nodes, double *x);
/* Total reference volume (area in 2-D). */
double tl_mesh_volume(const TlMesh *mesh);

/* Structured generators.  Face sets and node sets "xmin", "xmax", "ymin",
 * "ymax" (and "zmin", "zmax" in 3-D); one block "body".
 * Box [lo, hi] of n[0] x n[1] x n[2] cells: hex8 or hex27 elements, or
 * tet4 / tet10 (each cell split into six tetrahedra around its diagonal). */
TlStatus tl_mesh_create_box(const TlElementType *type, const size_t n[3], const double lo[3],
                            const double hi[3], TlMesh **mesh);
/* Rectangle [lo, hi] of n[0] x n[1] quad4 or quad8 elements (plane strain). */
TlStatus tl_mesh_create_rectangle(const TlElementType *type, const size_t n[2], const double lo[2],
                                  const double hi[2], TlMesh **mesh);
/* Hollow-cylinder sector r in [r_in, r_out], angle in [theta0, theta1] (rad,
 * about z), z in [0, height], n = (radial, angular, axial) hex8 or hex27
 * cells; nodes lie exactly on the arcs.  Sets "inner", "outer", "theta0",
 * "theta1", "zmin", "zmax". */
TlStatus tl_mesh_create_cylinder_sector(const TlElementType *type, double r_in, double r_out,
                                        double theta0, double theta1, double height,
                                        const size_t n[3], TlMesh **mesh);

/* Reads a Gmsh .msh file, format 4.1 or 2.2, ASCII or binary (either byte
 * order; size_t of 4 or 8 bytes).  Elements of the highest dimension form
 * the blocks (one per physical group name and element type; "body" when no
 * physical groups exist); elements of one dimension less with a physical
 * group become face sets of that name (and node sets of their nodes);
 * physical points and curves of lower dimension become node sets.  Nodes
 * used by no element are dropped.  Errors name the line and the problem. */
TlStatus tl_mesh_read_gmsh(const char *path, TlMesh **mesh);

#endif
