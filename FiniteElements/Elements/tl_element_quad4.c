/* The 4-node bilinear quadrilateral (Gmsh type 3): a plane-strain element in
 * 2-D and the face of the 8-node hexahedron in 3-D. */
#include "tl_element.h"
#include "tl_element_family.h"

static const double ref[4 * 2] = {-1, -1, 1, -1, 1, 1, -1, 1};
/* Edges of a counter-clockwise element: outward normal (dy/ds, -dx/ds). */
static const int faces[4 * 2] = {0, 1, 1, 2, 2, 3, 3, 0};

static const TlElementOutput output = {TL_CELL_QUAD4, NULL};

static void eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_tensor_eval(2, 1, 4, ref, npts, xi, N, dN);
}

const TlElementType tl_element_quad4 = {
    .header = {"element", "quad4", "4-node bilinear quadrilateral (plane strain)"},
    .dim = 2, .n_nodes = 4, .n_corners = 4, .shape = TL_SHAPE_QUAD, .ref_coords = ref,
    .n_faces = 4, .face_n_nodes = 2, .face_nodes = faces, .face_type = &tl_element_line2,
    .order_stiffness = 2, .order_mass = 2, .gmsh_type = 3, .linear = 1, .output = &output, .eval = eval};
