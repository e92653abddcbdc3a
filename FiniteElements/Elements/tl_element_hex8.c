/* The 8-node trilinear hexahedron (Gmsh type 5). */
#include "tl_element.h"
#include "tl_element_family.h"

static const double ref[8 * 3] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                  -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
/* Faces counter-clockwise seen from outside: z = -1, z = 1, y = -1, y = 1,
 * x = -1, x = 1. */
static const int faces[6 * 4] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                 2, 3, 7, 6, 0, 4, 7, 3, 1, 2, 6, 5};

static const TlElementOutput output = {TL_CELL_HEX8, NULL};

static void eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_tensor_eval(3, 1, 8, ref, npts, xi, N, dN);
}

const TlElementType tl_element_hex8 = {
    .header = {"element", "hex8", "8-node trilinear hexahedron"},
    .dim = 3, .n_nodes = 8, .n_corners = 8, .shape = TL_SHAPE_HEX, .ref_coords = ref,
    .n_faces = 6, .face_n_nodes = 4, .face_nodes = faces, .face_type = &tl_element_quad4,
    .order_stiffness = 2, .order_mass = 2, .gmsh_type = 5, .linear = 1, .output = &output, .eval = eval};
