/* The 8-node serendipity quadrilateral with 2 x 2 Gauss points for the
 * stiffness ("quad8r", reduced integration), plane strain: the element of
 * the FEM x DEM computations of seeds/004 (128 Q8 x 4 Gauss points, one
 * DEM cell per point), where every stiffness point is a costly law.
 * Geometry, faces and output are those of quad8 (3 x 3 points); the mass
 * keeps the full rule.  Not read from Gmsh files (code 16 stays quad8's). */
#include "tl_element.h"
#include "tl_element_family.h"

static const double ref[8 * 2] = {-1, -1, 1, -1, 1, 1, -1, 1, 0, -1, 1, 0, 0, 1, -1, 0};
static const int faces[4 * 3] = {0, 1, 4, 1, 2, 5, 2, 3, 6, 3, 0, 7};

static const TlElementOutput output = {TL_CELL_QUAD8, NULL};

static void eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_serendipity8_eval(npts, xi, N, dN);
}

const TlElementType tl_element_quad8r = {
    .header = {"element", "quad8r", "8-node serendipity quadrilateral, 2 x 2 Gauss points (plane strain)"},
    .dim = 2, .n_nodes = 8, .n_corners = 4, .shape = TL_SHAPE_QUAD, .ref_coords = ref,
    .n_faces = 4, .face_n_nodes = 3, .face_nodes = faces, .face_type = &tl_element_line3,
    .order_stiffness = 2, .order_mass = 3, .gmsh_type = 0, .output = &output, .eval = eval};

TlStatus tl_element_quad8r_register_all(void)
{
  TL_CHECK(tl_element_type_register(&tl_element_quad8r));
  return TL_OK;
}
