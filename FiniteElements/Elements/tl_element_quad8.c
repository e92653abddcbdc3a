/* The 8-node serendipity quadrilateral (Gmsh type 16), plane strain. */
#include "tl_element.h"
#include "tl_element_family.h"

static const double ref[8 * 2] = {-1, -1, 1, -1, 1, 1, -1, 1, 0, -1, 1, 0, 0, 1, -1, 0};
/* Edges as 3-node lines (end, end, middle) of a counter-clockwise element. */
static const int faces[4 * 3] = {0, 1, 4, 1, 2, 5, 2, 3, 6, 3, 0, 7};

static const TlElementOutput output = {TL_CELL_QUAD8, NULL};

static void eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_serendipity8_eval(npts, xi, N, dN);
}

const TlElementType tl_element_quad8 = {
    .header = {"element", "quad8", "8-node serendipity quadrilateral (plane strain)"},
    .dim = 2, .n_nodes = 8, .n_corners = 4, .shape = TL_SHAPE_QUAD, .ref_coords = ref,
    .n_faces = 4, .face_n_nodes = 3, .face_nodes = faces, .face_type = &tl_element_line3,
    .order_stiffness = 3, .order_mass = 3, .gmsh_type = 16, .output = &output, .eval = eval};
