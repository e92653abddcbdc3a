/* A new element type from outside the library: the 20-node serendipity
 * hexahedron (Gmsh type 17, Gmsh node order), in one file.
 *
 * An element type is a const TlElementType table (tl_element.h): reference
 * node coordinates, a batched shape-function evaluation, Gauss orders, the
 * faces (as an existing face type with outward node lists), the Gmsh code
 * and the output cell.  Registered once, it is found by name
 * (tl_element_type_find("hex20")), by the Gmsh reader, the structured
 * meshers, the solid, its output and the surface coupling. */
#include "examples.h"

#include "tl_element.h"
#include "tl_registry.h"

/* Corners, then the mid-edge nodes of edges 01 03 04 12 15 23 26 37 45 47
 * 56 67 (Gmsh's order). */
static const double ref[20 * 3] = {
    -1, -1, -1, 1,  -1, -1, 1,  1, -1, -1, 1,  -1, -1, -1, 1, 1,  -1, 1, 1, 1, 1, -1, 1, 1,
    0,  -1, -1, -1, 0,  -1, -1, -1, 0, 1,  0,  -1, 1,  -1, 0, 0,  1,  -1, 1, 1, 0,
    -1, 1,  0,  0,  -1, 1,  -1, 0,  1, 1,  0,  1,  0,  1,  1};

/* Faces as 8-node quadrilaterals (the library's quad8): corners
 * counter-clockwise seen from outside, then the mid-edge nodes of the
 * face's edges c0-c1, c1-c2, c2-c3, c3-c0.  Order: z = -1, z = 1, y = -1,
 * y = 1, x = -1, x = 1. */
static const int faces[6 * 8] = {0, 3, 2, 1, 9,  13, 11, 8,  4, 5, 6, 7, 16, 18, 19, 17,
                                 0, 1, 5, 4, 8,  12, 16, 10, 2, 3, 7, 6, 13, 15, 19, 14,
                                 0, 4, 7, 3, 10, 17, 15, 9,  1, 2, 6, 5, 11, 14, 18, 12};

/* VTK's Hexahedron_20 (cell 25) lists the edges 01 12 23 30, 45 56 67 74,
 * 04 15 26 37: output position k holds node order[k]. */
static const int order[20] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15};
static const TlElementOutput output = {TL_CELL_HEX20, order};

/* Corner node at c (all +-1):  N = 1/8 q0 q1 q2 (c.xi - 2), q_d = 1 + c_d xi_d;
 * mid-edge node (one c_d = 0): N = 1/4 q0 q1 q2 with q_d = 1 - xi_d^2 there. */
static void eval(int npts, const double *xi, double *N, double *dN)
{
  for (int p = 0; p < npts; ++p) {
    const double *x = xi + 3 * p;
    for (int a = 0; a < 20; ++a) {
      const double *c = ref + 3 * a;
      double q[3], dq[3];
      for (int d = 0; d < 3; ++d) {
        q[d] = c[d] == 0.0 ? 1.0 - x[d] * x[d] : 1.0 + c[d] * x[d];
        dq[d] = c[d] == 0.0 ? -2.0 * x[d] : c[d];
      }
      double prod = q[0] * q[1] * q[2];
      if (a < 8) {
        double s = c[0] * x[0] + c[1] * x[1] + c[2] * x[2] - 2.0;
        if (N) N[p * 20 + a] = 0.125 * prod * s;
        if (dN)
          for (int d = 0; d < 3; ++d)
            dN[(p * 20 + a) * 3 + d] = 0.125 * (dq[d] * q[(d + 1) % 3] * q[(d + 2) % 3] * s + prod * c[d]);
      } else {
        if (N) N[p * 20 + a] = 0.25 * prod;
        if (dN)
          for (int d = 0; d < 3; ++d) dN[(p * 20 + a) * 3 + d] = 0.25 * dq[d] * q[(d + 1) % 3] * q[(d + 2) % 3];
      }
    }
  }
}

static const TlElementType hex20 = {
    .header = {"element", "hex20", "20-node serendipity hexahedron"},
    .dim = 3, .n_nodes = 20, .n_corners = 8, .shape = TL_SHAPE_HEX, .ref_coords = ref,
    .n_faces = 6, .face_n_nodes = 8, .face_nodes = faces, .face_type = &tl_element_quad8,
    .order_stiffness = 3, .order_mass = 3, /* 3 x 3 x 3 Gauss points: full integration */
    .gmsh_type = 17, .linear = 0, .output = &output, .eval = eval};

TlStatus example_hex20_register(void)
{
  TL_CHECK(tl_element_type_register(&hex20));
  return TL_OK;
}
