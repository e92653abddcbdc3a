/* Element types: isoparametric reference elements as const ops tables.
 *
 * An element type knows its reference geometry (node coordinates in the
 * reference cube [-1,1]^d or the unit simplex), its shape functions and
 * their reference gradients, its Gauss rules, its faces (as element types of
 * one dimension less, with node lists ordered so that the face normal
 * dx/ds x dx/dt, or (dy/ds, -dx/ds) for an edge, points out of the element)
 * its Gmsh element code, whether it is linear, and the output cell that
 * draws it.  Node ordering is Gmsh's for every type, so imported meshes need
 * no renumbering.  Everything other modules need to know about a type is in
 * its table: no module compares a type with a built-in one, so a type
 * defined outside the library (one file filling a TlElementType, registered
 * with tl_element_type_register) is meshed, read from Gmsh files, solved,
 * written and coupled like a built-in one.
 *
 * Everything here is callable from outside the finite-element module: a
 * coupling that wraps an element type evaluates shape functions at any local
 * point, inverts the geometric map and integrates over faces through these
 * functions.  Shape functions are evaluated in batches (all quadrature points
 * of a rule at once), so the indirect call is paid once per block. */
#ifndef TL_ELEMENT_H
#define TL_ELEMENT_H

#include <stddef.h>
#include "tl_error.h"
#include "tl_mesh_snapshot.h"
#include "tl_object.h"

#define TL_ELEMENT_MAX_NODES 27
#define TL_ELEMENT_MAX_FACES 6
#define TL_ELEMENT_MAX_FACE_NODES 9
#define TL_QUADRATURE_MAX 125

typedef enum {
  TL_SHAPE_LINE = 0, /* [-1, 1] */
  TL_SHAPE_QUAD,     /* [-1, 1]^2 */
  TL_SHAPE_HEX,      /* [-1, 1]^3 */
  TL_SHAPE_TRI,      /* xi, eta >= 0, xi + eta <= 1 */
  TL_SHAPE_TET       /* xi, eta, zeta >= 0, sum <= 1 */
} TlReferenceShape;

typedef struct TlElementType TlElementType;

/* How the output draws an element: the cell type (its XDMF topology and VTK
 * cell code, tl_mesh_snapshot.h) and where the type's nodes go there:
 * output position k holds the type's node order[k] (NULL: the same order). */
typedef struct {
  TlCellType cell;
  const int *order;
} TlElementOutput;

struct TlElementType {
  TlOpsHeader header;      /* kind "element" */
  int dim;                 /* reference dimension: 1, 2 or 3 */
  int n_nodes;
  int n_corners;           /* vertices: the first n_corners nodes */
  TlReferenceShape shape;
  const double *ref_coords; /* n_nodes x dim */
  int n_faces;
  int face_n_nodes;
  const int *face_nodes;          /* n_faces x face_n_nodes, outward-oriented */
  const TlElementType *face_type; /* NULL for line elements */
  int order_stiffness;     /* Gauss points per direction (cube) or collapsed rule order */
  int order_mass;          /* rule integrating N_a N_b exactly on an affine element */
  int gmsh_type;           /* Gmsh element code (0: none) */
  int linear;              /* degree 1: the nodes are the corners, the shape functions are
                              non-negative, so the element lies within its nodes' hull */
  const TlElementOutput *output; /* NULL: not drawn (the line types) */
  /* Shape functions at npts points xi (stride 3): N[p*n_nodes + a] and
   * dN[(p*n_nodes + a)*dim + d] = dN_a/dxi_d.  Either output may be NULL. */
  void (*eval)(int npts, const double *xi, double *N, double *dN);
};

/* A quadrature rule on the reference element; xi has stride 3. */
typedef struct {
  int n;
  int dim;
  double xi[TL_QUADRATURE_MAX][3];
  double w[TL_QUADRATURE_MAX];
} TlQuadrature;

/* Gauss rule of `order` points per direction (1..5) on the type's reference
 * element; simplices use the collapsed (Duffy) product rule with positive
 * weights, exact for polynomials of degree 2*order - 1 - dim + 1. */
TlStatus tl_element_quadrature(const TlElementType *type, int order, TlQuadrature *rule);

/* Reference volume (2 for a line, 4 for a quad, 8 for a hex, 1/2 for a
 * triangle, 1/6 for a tetrahedron). */
double tl_element_reference_measure(const TlElementType *type);

/* Whether xi lies in the reference element, up to tol. */
int tl_element_contains(const TlElementType *type, const double *xi, double tol);

/* Geometry at one local point of an element with nodal coordinates
 * x (n_nodes x 3).  For a solid element (dim equal to the space dimension
 * sdim, 2 or 3) J[i][j] = dx_i/dxi_j and *detJ its determinant. */
TlStatus tl_element_jacobian(const TlElementType *type, int sdim, const double *x,
                             const double *xi, double J[3][3], double *detJ);

/* The global -> local inverse map: finds xi with x(xi) = point by damped
 * Newton iterations started at the centroid and, failing that, at each
 * vertex.  *inside tells whether xi lies in the element (tolerance 1e-10 in
 * reference coordinates), so points on faces, edges and corners are found
 * reliably.  Works for solid elements whose dim equals sdim (2: x, y used).
 * TL_ERR_CONVERGENCE when no start converges (degenerate element or a point
 * far outside). */
TlStatus tl_element_inverse_map(const TlElementType *type, int sdim, const double *x,
                                const double *point, double *xi, int *inside);

/* The position of local point xi: out = sum_a N_a(xi) x_a. */
void tl_element_interpolate(const TlElementType *type, const double *x, const double *xi,
                            double *out);

/* Area element of a face: for a face type of dimension 2 in 3-D, the vector
 * n dA/dxi = dx/ds x dx/dt; for a 1-D face in 2-D, (dy/ds, -dx/ds).  x holds
 * the face's nodes (face_n_nodes x 3). */
void tl_element_face_normal(const TlElementType *face_type, int sdim, const double *x,
                            const double *s, double n_dA[3]);

/* Maps a point s of face f (in the face's reference coordinates) to the
 * element's reference coordinates (via the face's own shape functions). */
void tl_element_face_to_element(const TlElementType *type, int f, const double *s, double *xi);

/* Built-in types. */
extern const TlElementType tl_element_line2, tl_element_line3;
extern const TlElementType tl_element_tri3, tl_element_tri6;
extern const TlElementType tl_element_quad4, tl_element_quad8, tl_element_quad9;
extern const TlElementType tl_element_tet4, tl_element_tet10;
extern const TlElementType tl_element_hex8, tl_element_hex27;

/* Checks a type's table for what the rest of Talus relies on: sizes
 * within the TL_ELEMENT_MAX_* limits, N_a(x_b) = delta_ab at the nodes and
 * sum_a dN_a = 0, face node lists in range and oriented outward, the face
 * type's dimension and node count, the output cell's node count and order
 * (a permutation), linear only when the nodes are the corners.  The error
 * names the type and the first failing item. */
TlStatus tl_element_type_check(const TlElementType *type);
/* Checks the type, then registers it (kind "element") so that it is found
 * by name and by Gmsh code.  The table must outlive the registry. */
TlStatus tl_element_type_register(const TlElementType *type);
/* The registered type named `name`; the error lists the known names. */
TlStatus tl_element_type_find(const char *name, const TlElementType **type);
/* The registered type with Gmsh element code `gmsh_type`; TL_ERR_NOT_FOUND
 * (listing the registered codes) when none is. */
TlStatus tl_element_type_find_gmsh(int gmsh_type, const TlElementType **type);
/* Registers the built-in element types. */
TlStatus tl_element_register_all(void);

#endif
