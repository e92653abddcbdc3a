/* The 4-node linear tetrahedron (Gmsh type 4). */
#include "tl_element.h"
#include "tl_element_family.h"

static const double ref[4 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
/* Faces counter-clockwise seen from outside. */
static const int faces[4 * 3] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

static const TlElementOutput output = {TL_CELL_TET4, NULL};

static void eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_simplex_eval(3, 1, 0, NULL, npts, xi, N, dN);
}

const TlElementType tl_element_tet4 = {
    .header = {"element", "tet4", "4-node linear tetrahedron"},
    .dim = 3, .n_nodes = 4, .n_corners = 4, .shape = TL_SHAPE_TET, .ref_coords = ref,
    .n_faces = 4, .face_n_nodes = 3, .face_nodes = faces, .face_type = &tl_element_tri3,
    .order_stiffness = 2, .order_mass = 3, .gmsh_type = 4, .linear = 1, .output = &output, .eval = eval};
