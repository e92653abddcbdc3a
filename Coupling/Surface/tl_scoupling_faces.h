/* The faces of the SCoupling elements seen through their element type's
 * ops (seeds/001 §5.1): how a face of any 2-D face type becomes DEM wall
 * triangles, and its CG quadrature for Eq. 15.
 *
 * Wall pieces, built from the face type's reference coordinates:
 *   tri3   the triangle itself;
 *   quad4  four triangles around the interpolated centre (the paper's
 *          choice);
 *   tri6   four sub-triangles on the corner and mid-side nodes;
 *   quad9  four sub-quadrilaterals on the nodes, each as four triangles
 *          around its interpolated centre.
 * Interpolated points (centres) are "extra" vertices: x = sum_a N_a(s) x_a
 * with the face's own shape functions, every time the face moves.
 *
 * CG quadrature: the reference face split into s x s sub-cells (squares or
 * triangles), the face type's 3-point-per-direction Gauss rule on each,
 * positions, area elements and shape values from the face's nodes: a
 * TlCGSurfaceOps plug-in (tl_cg_surface.h) for any face type; the Dirac
 * limit (Eq. 16) projects the contact point onto the curved face. */
#ifndef TL_SCOUPLING_FACES_H
#define TL_SCOUPLING_FACES_H

#include "tl_cg_surface.h"
#include "tl_element.h"
#include "tl_error.h"

enum { TL_SCOUPLING_MAX_EXTRA = 8, TL_SCOUPLING_MAX_PIECES = 16 };

typedef struct {
  const TlElementType *type; /* the face type (dim 2) */
  int nf;                    /* nodes per face */
  /* wall pieces: vertex k < nf is face node k, k >= nf extra point k - nf */
  int n_extra;
  double extra_ref[TL_SCOUPLING_MAX_EXTRA][2];
  double extra_N[TL_SCOUPLING_MAX_EXTRA][TL_ELEMENT_MAX_FACE_NODES];
  int n_pieces;
  int piece[TL_SCOUPLING_MAX_PIECES][3];
  /* CG quadrature on the reference face */
  int subdivisions, nq;
  double *w_ref; /* nq reference weights (sub-cell scaling included) */
  double *N;     /* nq x nf shape values */
  double *dN;    /* nq x nf x 2 reference derivatives */
} TlSCouplingFaceType;

/* Wall pieces and a quadrature of `subdivisions` sub-cells per direction
 * (1..64) for a 2-D face type (tri3, quad4, tri6, quad9); others are
 * refused with their name. */
TlStatus tl_scoupling_face_type_create(const TlElementType *face_type, int subdivisions, TlSCouplingFaceType **ft);
void tl_scoupling_face_type_destroy(TlSCouplingFaceType **ft);

/* A CG surface over n_faces faces of this type (face_node: n_faces x nf
 * local node numbers into x, borrowed as tl_cg_surface_create does); the
 * face type must outlive it.  Quadrature computed. */
TlStatus tl_cg_surface_create_element_faces(const TlSCouplingFaceType *ft, size_t n_nodes, const TlVec3 *x,
                                            size_t n_faces, const int *face_node, TlCGSurface **surface);

/* The SCoupling elements themselves as the CG support: each "face" of the
 * CG surface is a solid element, its quadrature the element type's
 * stiffness rule at the current node positions (weights w |det J|), so the
 * kernel is normalised over the elements' integration points and the
 * contact force spread over all their nodes.  This is what the code of the
 * published S1 runs does for c > 0 (MercuryDPM's surface coupling evaluates
 * the CG function at the bulk elements' integration points), in place of
 * Eq. 15's integral over the coupled surface. */
typedef struct {
  const TlElementType *type; /* a 3-D solid element type */
  int ne, nq;                /* nodes per element, integration points */
  double w_ref[TL_QUADRATURE_MAX];
  double *N;  /* nq x ne shape values */
  double *dN; /* nq x ne x 3 reference derivatives */
} TlSCouplingVolumeType;

TlStatus tl_scoupling_volume_type_create(const TlElementType *type, TlSCouplingVolumeType **vt);
void tl_scoupling_volume_type_destroy(TlSCouplingVolumeType **vt);
/* A CG support over n_elements elements of this type (elem_node:
 * n_elements x ne local node numbers into x, borrowed); the volume type
 * must outlive it.  Quadrature computed. */
TlStatus tl_cg_surface_create_element_volumes(const TlSCouplingVolumeType *vt, size_t n_nodes, const TlVec3 *x,
                                              size_t n_elements, const int *elem_node, TlCGSurface **surface);

#endif
