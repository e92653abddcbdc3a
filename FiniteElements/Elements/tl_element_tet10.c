/* The 10-node quadratic tetrahedron (Gmsh type 11: mid-edge nodes on edges
 * 0-1, 1-2, 0-2, 0-3, 2-3, 1-3). */
#include "tl_element.h"
#include "tl_element_family.h"

static const double ref[10 * 3] = {0, 0, 0,   1,   0,   0,   0, 1,   0,   0,   0,   1,   0.5, 0, 0,
                                   0.5, 0.5, 0, 0, 0.5, 0, 0, 0, 0.5, 0, 0.5, 0.5, 0.5, 0,   0.5};
static const int edges[6 * 2] = {0, 1, 1, 2, 0, 2, 0, 3, 2, 3, 1, 3};
/* Faces as 6-node triangles, corners counter-clockwise seen from outside,
 * then the mid-edge nodes of edges c0-c1, c1-c2, c2-c0. */
static const int faces[4 * 6] = {0, 2, 1, 6, 5, 4, 0, 1, 3, 4, 9, 7,
                                 0, 3, 2, 7, 8, 6, 1, 2, 3, 5, 8, 9};

/* VTK lists the edges 01 12 20 03 13 23: positions 8 and 9 swap. */
static const int order[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
static const TlElementOutput output = {TL_CELL_TET10, order};

static void eval(int npts, const double *xi, double *N, double *dN)
{
  tl_family_simplex_eval(3, 2, 6, edges, npts, xi, N, dN);
}

const TlElementType tl_element_tet10 = {
    .header = {"element", "tet10", "10-node quadratic tetrahedron"},
    .dim = 3, .n_nodes = 10, .n_corners = 4, .shape = TL_SHAPE_TET, .ref_coords = ref,
    .n_faces = 4, .face_n_nodes = 6, .face_nodes = faces, .face_type = &tl_element_tri6,
    .order_stiffness = 3, .order_mass = 4, .gmsh_type = 11, .output = &output, .eval = eval};
