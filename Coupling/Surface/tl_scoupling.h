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
 * interpolated with the face shape functions), and after the step
 * accumulates the coupling forces per (face, face node)
 * (tl_scoupling_accumulate_forces): the integral over the face of N_a t dA
 * with the traction t of the particle–wall forces f^w coarse-grained with
 * width c (Eqs. 14-15) or, for c = 0, the point-source limit of Eq. 16 in
 * closed form.  They sum to minus the particle–wall forces to round-off
 * (momentum balance).
 *
 * The SCoupling element type (§5.3.1, Fig. 7): at creation the coupling
 * installs a wrapper over every block holding coupled faces
 * (tl_solid_add_wrapper; any 3-D element type, FiniteElements/ untouched).
 * The block's elements are evaluated as before, and for each ACTIVE
 * SCoupling element the wrapper adds its faces' accumulated coupling forces
 * at the element's nodes to the external load:
 * R_a = f_int - f_ext - int_{Gamma_e} N_a t dA, so the steppers count their
 * work as that of any external load.  The active
 * elements (step 1 of §5.3.1) are the owners of the faces that received a
 * contribution since the forces were last cleared: the contacts' faces, and
 * with c > 0 every face within the kernel's reach of a contact.  Within an
 * FE step the load is dead (the DEM forces of the step are fixed before
 * it), so the wrapper adds no tangent and no stored energy.  Destroying the
 * coupling removes its wrappers (in any order among the block's wrappers).
 */
#ifndef TL_SCOUPLING_H
#define TL_SCOUPLING_H

#include <stddef.h>
#include "tl_cg_kernel.h"
#include "tl_cg_surface.h"
#include "tl_checkpoint.h"
#include "tl_dem.h"
#include "tl_error.h"
#include "tl_mesh.h"
#include "tl_solid.h"
#include "tl_wall_trisurface.h"

/* Where the kernel of c > 0 is normalised and integrated: over the coupled
 * surface (Eq. 15 as printed) or over the SCoupling elements' integration
 * points (the code of the published runs; tl_scoupling_faces.h); one
 * strategy each, tl_scoupling_support_*.c. */
enum { TL_SCOUPLING_SUPPORT_SURFACE = 0, TL_SCOUPLING_SUPPORT_ELEMENTS = 1 };

typedef struct {
  double width;      /* CG width c (m); 0 = Dirac (Eq. 16) */
  const char *kernel; /* CG kernel for c > 0 ["lucy"] */
  int subdivisions;  /* CG quadrature sub-cells per face direction; 0 = enough for the width [0] */
  int support;       /* TL_SCOUPLING_SUPPORT_SURFACE or _ELEMENTS, for c > 0 [SURFACE] */
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
/* Adds scale times the per-face coupling forces of the wall's current
 * contacts to the accumulated ones, the load the SCoupling elements put on
 * the solid's residual (scale 1 once per FE step: the last DEM step's
 * forces; 1/k after each of k sub-steps: their average).  *total_wall (may
 * be NULL) receives the sum of the particle–wall forces (on the particles,
 * unscaled).  The owners of the faces reached become active. */
TlStatus tl_scoupling_accumulate_forces(TlSCoupling *sc, double scale, TlVec3 *total_wall);
/* Zeroes the accumulated forces; no SCoupling element is active after it. */
void tl_scoupling_clear_forces(TlSCoupling *sc);
/* Adds the accumulated forces, assembled node-wise, to f_nodes (n_nodes x 3,
 * forces acting on the solid): for work, energy and momentum diagnostics.
 * Equals what the wrappers add to the external force. */
void tl_scoupling_assemble_forces(const TlSCoupling *sc, double *f_nodes);
/* The accumulated per-face forces (n_faces x nodes_per_face, in the order
 * of tl_scoupling_faces) and the faces holding them, in the order first
 * reached. */
size_t tl_scoupling_n_faces(const TlSCoupling *sc);
const TlFaceRef *tl_scoupling_faces(const TlSCoupling *sc);
int tl_scoupling_nodes_per_face(const TlSCoupling *sc);
const TlVec3 *tl_scoupling_face_forces(const TlSCoupling *sc);
size_t tl_scoupling_n_touched_faces(const TlSCoupling *sc);
const size_t *tl_scoupling_touched_faces(const TlSCoupling *sc);
/* The accumulated forces and their faces into / from a checkpoint group,
 * datasets named <prefix>face_forces and <prefix>touched_faces; loading
 * restores the active elements in the same order (bit-for-bit restarts). */
TlStatus tl_scoupling_save_forces(const TlSCoupling *sc, TlCheckpointWriter *w, const char *group, const char *prefix);
TlStatus tl_scoupling_load_forces(TlSCoupling *sc, TlCheckpointReader *r, const char *group, const char *prefix);

/* Adds scale times the coupling forces of the wall's current contacts,
 * assembled node-wise, to f_nodes (n_nodes x 3, forces acting on the
 * solid), without touching the accumulated forces; *total_wall (may be
 * NULL) receives the sum of the particle–wall forces (on the particles). */
TlStatus tl_scoupling_add_nodal_forces(TlSCoupling *sc, double scale, double *f_nodes, TlVec3 *total_wall);

/* SCoupling elements: all of them, and the active ones (block, element
 * pairs as TlFaceRef with face = -1). */
size_t tl_scoupling_n_elements(const TlSCoupling *sc);
size_t tl_scoupling_n_active_elements(const TlSCoupling *sc);
const TlFaceRef *tl_scoupling_elements(const TlSCoupling *sc);
const TlFaceRef *tl_scoupling_active_elements(const TlSCoupling *sc);
/* Number of wall contacts at the last force evaluation. */
size_t tl_scoupling_n_contacts(const TlSCoupling *sc);
double tl_scoupling_width(const TlSCoupling *sc);
/* The solid coupled. */
TlSolid *tl_scoupling_solid(const TlSCoupling *sc);
/* The CG surface over the coupled faces (quadrature of Eq. 15), as of the
 * last force evaluation. */
const TlCGSurface *tl_scoupling_cg_surface(const TlSCoupling *sc);

#endif
