/* Shape-function families shared by the built-in element types: tensor
 * products of 1-D Lagrange polynomials on the reference cube, the 8-node
 * serendipity quadrilateral, and linear/quadratic polynomials on simplices.
 * An element type file fills its ops table and calls one of these. */
#ifndef TL_ELEMENT_FAMILY_H
#define TL_ELEMENT_FAMILY_H

/* Tensor-product Lagrange of degree 1 or 2 in dim directions; node a sits at
 * ref[a*dim + d] in {-1, 0, 1}. */
void tl_family_tensor_eval(int dim, int degree, int n_nodes, const double *ref, int npts,
                           const double *xi, double *N, double *dN);
/* Simplex of degree 1 (dim + 1 vertices) or 2 (vertices, then one node per
 * edge; edges[2*e], edges[2*e+1] are its end vertices). */
void tl_family_simplex_eval(int dim, int degree, int n_edges, const int *edges, int npts,
                            const double *xi, double *N, double *dN);
/* The 8-node serendipity quadrilateral (Gmsh order: corners, then edges
 * 0-1, 1-2, 2-3, 3-0). */
void tl_family_serendipity8_eval(int npts, const double *xi, double *N, double *dN);

#endif
