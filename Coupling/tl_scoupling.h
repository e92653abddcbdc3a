/* Surface coupling of a DEM world and a finite-element solid
 * (seeds/001 §5.1, §5.3.1).
 *
 * One TlSCoupling serves one coupled boundary: a set of boundary faces of
 * the solid.  At creation it
 *   - finds the SCoupling elements (those owning a coupled face),
 *   - builds one DEM triangulated-surface wall from the faces, of any face
 *     type through its element type's ops (tl_scoupling_faces.h): each
 *     bilinear quadrilateral becomes four triangles around its interpolated
 *     centre (the paper's choice), each linear triangle stays as it is,
 *     quadratic faces are subdivided; the surface is one piece so the
 *     triangle-edge corrections (Algorithm 1) apply across the faces,
 *   - builds the CG surface (Eq. 15 quadrature) over the same faces.
 * Every DEM step the owner moves the wall from the FE state
 * (tl_scoupling_set_kinematics: vertices = X + u, velocities v, centres
 * interpolated with the face shape functions), and after the step adds the
 * coupling forces to the FE nodes (tl_scoupling_add_nodal_forces): the
 * particle–wall forces f^w coarse-grained with width c (Eq. 15) or, for
 * c = 0, the point-source limit of Eq. 16 in closed form.  The nodal forces
 * sum to minus the particle–wall forces to round-off (momentum balance).
 *
 * The solid's residual receives the nodal forces through the mechanical
 * system's step hook (the coupled loop does this), which is how the
 * SCoupling element's residual contribution enters without editing the
 * element types: R_a -= F_a on the nodes of the SCoupling elements.  The
 * list of SCoupling elements currently touched by particles (step 1 of
 * §5.3.1) is refreshed at every force evaluation.
 */
#ifndef TL_SCOUPLING_H
#define TL_SCOUPLING_H

#include <stddef.h>
#include "tl_cg_kernel.h"
#include "tl_cg_surface.h"
#include "tl_dem.h"
#include "tl_error.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_wall_trisurface.h"

typedef struct {
  double width;      /* CG width c (m); 0 = Dirac (Eq. 16) */
  const char *kernel; /* CG kernel for c > 0 ["lucy"] */
  int subdivisions;  /* CG quadrature sub-cells per face direction; 0 = enough for the width [0] */
} TlSCouplingOptions;

typedef struct TlSCoupling TlSCoupling;

void tl_scoupling_options_default(TlSCouplingOptions *o);

/* A coupled boundary of n_faces faces of the solid's mesh (borrowed mesh and
 * solid, which must outlive the coupling).  The wall is created too and
 * handed to the DEM world by tl_scoupling_add_to_dem. */
TlStatus tl_scoupling_create(TlSolid *solid, size_t n_faces, const TlFaceRef *faces,
                             const TlSCouplingOptions *options, TlSCoupling **sc);
/* All boundary faces of the mesh except those in the named face sets
 * (e.g. the clamped end), as one coupled boundary. */
TlStatus tl_scoupling_create_boundary(TlSolid *solid, int n_excluded, const char *const *excluded,
                                      const TlSCouplingOptions *options, TlSCoupling **sc);
void tl_scoupling_destroy(TlSCoupling **sc);

/* Hands the wall to the world (it takes ownership) with contact law `law`.
 * Call once, before tl_dem_setup, after a first set_kinematics. */
TlStatus tl_scoupling_add_to_dem(TlSCoupling *sc, TlDem *dem, int law);
/* The wall (valid once added, owned by the world). */
TlWall *tl_scoupling_wall(TlSCoupling *sc);

/* Moves the wall: node-space displacements and velocities of the solid
 * (n_nodes x 3; v may be NULL for a wall at rest). */
TlStatus tl_scoupling_set_kinematics(TlSCoupling *sc, const double *u_nodes, const double *v_nodes);
/* Adds scale times the coupling forces of the wall's current contacts to
 * f_nodes (n_nodes x 3, forces acting on the solid); *total_wall (may be
 * NULL) receives the sum of the particle–wall forces (on the particles).
 * Refreshes the list of touched SCoupling elements. */
TlStatus tl_scoupling_add_nodal_forces(TlSCoupling *sc, double scale, double *f_nodes, TlVec3 *total_wall);

/* SCoupling elements: all of them, and those touched at the last force
 * evaluation (block, element pairs as TlFaceRef with face = -1). */
size_t tl_scoupling_n_elements(const TlSCoupling *sc);
size_t tl_scoupling_n_active_elements(const TlSCoupling *sc);
const TlFaceRef *tl_scoupling_elements(const TlSCoupling *sc);
const TlFaceRef *tl_scoupling_active_elements(const TlSCoupling *sc);
/* Number of wall contacts at the last force evaluation. */
size_t tl_scoupling_n_contacts(const TlSCoupling *sc);
double tl_scoupling_width(const TlSCoupling *sc);
/* The CG surface over the coupled faces (quadrature of Eq. 15), as of the
 * last force evaluation. */
const TlCGSurface *tl_scoupling_cg_surface(const TlSCoupling *sc);

#endif
