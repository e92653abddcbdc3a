/* Lower-dimensional types that serve as faces of the solid elements: 2- and
 * 3-node lines, 3- and 6-node triangles, the 9-node quadrilateral. */
#include "tl_element.h"
#include "tl_element_family.h"

static const double line2_ref[2] = {-1, 1};
static const double line3_ref[3] = {-1, 1, 0};
static const int line_faces[2] = {0, 1};

static void line2_eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_tensor_eval(1, 1, 2, line2_ref, npts, xi, N, dN);
}
static void line3_eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_tensor_eval(1, 2, 3, line3_ref, npts, xi, N, dN);
}

const TlElementType tl_element_line2 = {
    .header = {"element", "line2", "2-node line"},
    .dim = 1, .n_nodes = 2, .n_corners = 2, .shape = TL_SHAPE_LINE, .ref_coords = line2_ref,
    .n_faces = 2, .face_n_nodes = 1, .face_nodes = line_faces, .face_type = NULL,
    .order_stiffness = 2, .order_mass = 2, .gmsh_type = 1, .linear = 1, .eval = line2_eval};
const TlElementType tl_element_line3 = {
    .header = {"element", "line3", "3-node quadratic line (end, end, middle)"},
    .dim = 1, .n_nodes = 3, .n_corners = 2, .shape = TL_SHAPE_LINE, .ref_coords = line3_ref,
    .n_faces = 2, .face_n_nodes = 1, .face_nodes = line_faces, .face_type = NULL,
    .order_stiffness = 3, .order_mass = 3, .gmsh_type = 8, .eval = line3_eval};

static const double tri3_ref[3 * 2] = {0, 0, 1, 0, 0, 1};
static const double tri6_ref[6 * 2] = {0, 0, 1, 0, 0, 1, 0.5, 0, 0.5, 0.5, 0, 0.5};
static const int tri_edges[3 * 2] = {0, 1, 1, 2, 2, 0};
static const int tri3_faces[3 * 2] = {0, 1, 1, 2, 2, 0};
static const int tri6_faces[3 * 3] = {0, 1, 3, 1, 2, 4, 2, 0, 5};

static const TlElementOutput tri3_output = {TL_CELL_TRI3, NULL};
static const TlElementOutput tri6_output = {TL_CELL_TRI6, NULL};

static void tri3_eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_simplex_eval(2, 1, 0, NULL, npts, xi, N, dN);
}
static void tri6_eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_simplex_eval(2, 2, 3, tri_edges, npts, xi, N, dN);
}

const TlElementType tl_element_tri3 = {
    .header = {"element", "tri3", "3-node linear triangle"},
    .dim = 2, .n_nodes = 3, .n_corners = 3, .shape = TL_SHAPE_TRI, .ref_coords = tri3_ref,
    .n_faces = 3, .face_n_nodes = 2, .face_nodes = tri3_faces, .face_type = &tl_element_line2,
    .order_stiffness = 1, .order_mass = 2, .gmsh_type = 2, .linear = 1, .output = &tri3_output, .eval = tri3_eval};
const TlElementType tl_element_tri6 = {
    .header = {"element", "tri6", "6-node quadratic triangle"},
    .dim = 2, .n_nodes = 6, .n_corners = 3, .shape = TL_SHAPE_TRI, .ref_coords = tri6_ref,
    .n_faces = 3, .face_n_nodes = 3, .face_nodes = tri6_faces, .face_type = &tl_element_line3,
    .order_stiffness = 2, .order_mass = 3, .gmsh_type = 9, .output = &tri6_output, .eval = tri6_eval};

static const double quad9_ref[9 * 2] = {-1, -1, 1, -1, 1, 1, -1, 1, 0, -1, 1, 0, 0, 1, -1, 0, 0, 0};
static const int quad9_faces[4 * 3] = {0, 1, 4, 1, 2, 5, 2, 3, 6, 3, 0, 7};

static const TlElementOutput quad9_output = {TL_CELL_QUAD9, NULL};

static void quad9_eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_tensor_eval(2, 2, 9, quad9_ref, npts, xi, N, dN);
}

const TlElementType tl_element_quad9 = {
    .header = {"element", "quad9", "9-node biquadratic quadrilateral"},
    .dim = 2, .n_nodes = 9, .n_corners = 4, .shape = TL_SHAPE_QUAD, .ref_coords = quad9_ref,
    .n_faces = 4, .face_n_nodes = 3, .face_nodes = quad9_faces, .face_type = &tl_element_line3,
    .order_stiffness = 3, .order_mass = 3, .gmsh_type = 10, .output = &quad9_output, .eval = quad9_eval};
