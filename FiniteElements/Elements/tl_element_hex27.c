/* The 27-node triquadratic hexahedron (Gmsh type 12, Gmsh node order). */
#include "tl_element.h"
#include "tl_element_family.h"

static const double ref[27 * 3] = {
    -1, -1, -1, 1,  -1, -1, 1,  1,  -1, -1, 1,  -1, -1, -1, 1,  1,  -1, 1,  1, 1, 1,
    -1, 1,  1,  /* corners */
    0,  -1, -1, -1, 0,  -1, -1, -1, 0,  1,  0,  -1, 1,  -1, 0,  0,  1,  -1, 1, 1, 0,
    -1, 1,  0,  0,  -1, 1,  -1, 0,  1,  1,  0,  1,  0,  1,  1, /* edges 8..19 */
    0,  0,  -1, 0,  -1, 0,  -1, 0,  0,  1,  0,  0,  0,  1,  0,  0,  0,  1, /* faces 20..25 */
    0,  0,  0};
/* Faces as 9-node quadrilaterals: corners counter-clockwise seen from
 * outside, then the mid-edge nodes of the face's edges in order, then the
 * face centre. */
static const int faces[6 * 9] = {0, 3, 2, 1, 9,  13, 11, 8,  20, 4, 5, 6, 7, 16, 18, 19, 17, 25,
                                 0, 1, 5, 4, 8,  12, 16, 10, 21, 2, 3, 7, 6, 13, 15, 19, 14, 24,
                                 0, 4, 7, 3, 10, 17, 15, 9,  22, 1, 2, 6, 5, 11, 14, 18, 12, 23};

/* VTK position k holds node order[k]: VTK lists the edges 01 12 23 30,
 * 45 56 67 74, 04 15 26 37 and the face centres x-, x+, y-, y+, z-, z+. */
static const int order[27] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  11, 13, 9,  16, 18,
                              19, 17, 10, 12, 14, 15, 22, 23, 21, 24, 20, 25, 26};
static const TlElementOutput output = {TL_CELL_HEX27, order};

static void eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_tensor_eval(3, 2, 27, ref, npts, xi, N, dN);
}

const TlElementType tl_element_hex27 = {
    .header = {"element", "hex27", "27-node triquadratic hexahedron"},
    .dim = 3, .n_nodes = 27, .n_corners = 8, .shape = TL_SHAPE_HEX, .ref_coords = ref,
    .n_faces = 6, .face_n_nodes = 9, .face_nodes = faces, .face_type = &tl_element_quad9,
    .order_stiffness = 3, .order_mass = 3, .gmsh_type = 12, .output = &output, .eval = eval};
