/* Point location in a mesh: which element holds a point, and where in it.
 *
 * Element bounding boxes are binned on a uniform grid (about one element
 * per cell), so a query inspects the few elements whose boxes cover the
 * point's cell and inverts their geometric maps (tl_element_inverse_map).
 * The nodal positions may be the reference ones or any current
 * configuration (rebuild with tl_mesh_locator_update after they move).
 * Couplings use it to find the element of a particle or a contact point. */
#ifndef TL_MESH_LOCATOR_H
#define TL_MESH_LOCATOR_H

#include "tl_error.h"
#include "tl_mesh.h"

typedef struct TlMeshLocator TlMeshLocator;

/* x: nodal positions (3 per node), NULL for the reference ones; copied. */
TlStatus tl_mesh_locator_create(const TlMesh *mesh, const double *x, TlMeshLocator **loc);
TlStatus tl_mesh_locator_update(TlMeshLocator *loc, const double *x);
void tl_mesh_locator_destroy(TlMeshLocator **loc);
/* The element containing point (within tol in reference coordinates, e.g.
 * 1e-10) and its local coordinates; TL_ERR_NOT_FOUND when outside the mesh.
 * A point on a shared face or edge is reported in one of its elements. */
TlStatus tl_mesh_locate(const TlMeshLocator *loc, const double point[3], double tol, TlFaceRef *where,
                        double xi[3]);

#endif
