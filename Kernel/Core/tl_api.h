/* The C API's conveniences and the accessors for foreign-function bindings
 * (the Python package, Python/talus).
 *
 * Conveniences (tl_api_scene.c, tl_api_vcoupling.c): the steps every scene
 * repeats, each one call composed of the modules' own calls: a contact law
 * from its parts and named settings added to a world; the world's box with
 * plane walls on chosen faces; a solid with its material and clamped node
 * set; a CSV table in an output folder; one writer for a scene's particles,
 * walls and solid; a triangulated wall from an STL or Gmsh file with its
 * placement; the volume-coupled loop of a world and a solid.
 *
 * Accessors:
 * A binding reaches the library through plain functions and handles; it
 * should neither mirror large structs (a field added in C would silently
 * shift its copy) nor allocate the library's option structs.  These
 * functions give it what the headers otherwise hand out as struct fields:
 *   - the particle arrays by field name, with their element type and shape
 *     (so a binding can wrap the library's own memory without copying);
 *   - the open or periodic box of a world, a wall's force account, a mesh's
 *     nodes, a triangulated surface's vertices, a stepper's state;
 *   - steppers, surface couplings and coupled loops created from named
 *     numeric settings over the library's defaults, an unknown name or a
 *     non-integer value for an integer setting refused by name;
 *   - the size of the small plain-data structs a binding does mirror
 *     (energies, statistics), to check its layout when it loads.
 * They sit above every module (the only Core files that do) and add no
 * physics: each calls the modules' own API. */
#ifndef TL_API_H
#define TL_API_H

#include <stddef.h>
#include <stdint.h>
#include "tl_coupled_loop.h"
#include "tl_dem.h"
#include "tl_error.h"
#include "tl_mesh.h"
#include "tl_particle_snapshot.h"
#include "tl_scoupling.h"
#include "tl_solid.h"
#include "tl_stepper.h"
#include "tl_solid_output.h"
#include "tl_timeseries.h"
#include "tl_trisurface.h"
#include "tl_vcoupling.h"
#include "tl_vcoupling_element.h"
#include "tl_wall.h"
#include "tl_wall_snapshot.h"
#include "tl_wall_trisurface.h"

/* Element types of the arrays handed out. */
enum { TL_API_FLOAT64 = 0, TL_API_INT64 = 1, TL_API_INT32 = 2, TL_API_UINT8 = 3 };

/* sizeof of a plain-data struct by its C name ("TlVec3", "TlDemEnergy",
 * "TlDemStats", "TlCoupledEnergy", "TlEnergies", "TlWallSetting", "TlVCouplingDiag",
 * "TlVCouplingParams"); 0 for any
 * other name. */
size_t tl_api_sizeof(const char *type_name);

/* The parameter table of the registered type `name` of `kind` (the
 * catalogue's): *n (may be NULL) receives its length; for 0 <= k < n, the
 * parameter's name, default (NaN: none, the caller gives it), closed range,
 * unit ("1": dimensionless) and meaning (any output may be NULL); k < 0
 * asks for the count alone.  An unknown type is refused with the kind's
 * names. */
TlStatus tl_api_type_param(const char *kind, const char *name, int k, int *n, const char **pname, double *def,
                           double *lo, double *hi, const char **unit, const char **help);

/* A numeric setting of a named field of a C struct, for the create
 * functions below. */
typedef struct {
  const char *name;
  int kind; /* 0 double, 1 int, 2 long */
  size_t offset;
} TlApiField;
/* Applies n settings (names[k] = values[k]) to object through the table;
 * an unknown name is refused with the table's names, a fractional or
 * out-of-range value for an integer field with the value. */
TlStatus tl_api_set_fields(const char *what, const TlApiField *table, int n_table, void *object, size_t n,
                           const char *const *names, const double *values);

/* ---- particles (tl_api_dem.c) ----
 * The array of particle field `name` (x, v, f, radius, mass, inv_mass,
 * species, motion, id, q, w, torque, inv_inertia, f_ext, f_coupling,
 * weight): its address, the particle count, the components per particle (3
 * for vectors, 4 for quaternions, 1 for scalars) and the element type
 * (TL_API_*).  The address is the store's own array: it stays valid until
 * the store reallocates (an insertion beyond the capacity) and its rows
 * follow the particles' current indices (a renumbering sort or a removal
 * moves them).  An optional array not yet allocated (the rotational state
 * before rotation is enabled, f_ext, f_coupling, weight) is refused with
 * TL_ERR_STATE, naming it. */
TlStatus tl_api_particles_field(TlParticles *p, const char *name, void **data, size_t *n, int *components,
                                int *scalar);
/* Count and capacity of the store. */
void tl_api_particles_size(const TlParticles *p, size_t *n, size_t *capacity);
/* A box for the world: open (periodic NULL or all 0) or periodic along the
 * directions flagged. */
TlStatus tl_api_dem_set_box(TlDem *dem, const double lo[3], const double hi[3], const int periodic[3]);
/* A wall's account of the last step: force and torque the particles exert
 * on it (about the origin), its contact count, stored elastic energy and
 * the work its prescribed motion did. */
void tl_api_wall_account(const TlWall *w, double force[3], double torque[3], size_t *n_contacts,
                         double *elastic_energy, double *work);
/* The registered name of a wall's type ("plane", "trisurface", ...). */
const char *tl_api_wall_type(const TlWall *w);
/* The vertex arrays (3 doubles each: positions, velocities) and triangles
 * (3 ints each) of a surface. */
void tl_api_trisurface_arrays(TlTriSurface *s, double **x, double **v, size_t *n_vertices, int **tri,
                              size_t *n_triangles);

/* The touching particle-particle contacts of the last force evaluation
 * (tl_dem_visit_contacts): *count receives how many there are, and the
 * first `max` are written: particle indices i and j (int64), the force on i,
 * the branch vector from i to j and the contact point (3 doubles each); any
 * output may be NULL.  Call with max = 0 to size the arrays. */
TlStatus tl_api_dem_contacts(TlDem *dem, size_t max, size_t *count, int64_t *i, int64_t *j, double *force,
                             double *branch, double *point);

/* Writes a snapshot of the world's particles (positions, radii, velocities,
 * forces, species, ids and, when allocated, spins and torques:
 * tl_particle_view_of) at its current time; step < 0 takes the world's
 * step count. */
TlStatus tl_api_particle_writer_write_dem(TlParticleWriter *writer, TlDem *dem, int64_t step);

/* ---- meshes and steppers (tl_api_fem.c) ---- */
/* Dimension, node count and reference coordinates (3 doubles a node). */
void tl_api_mesh_nodes(const TlMesh *mesh, int *dim, size_t *n_nodes, const double **x);
/* Node count of a named node set (0 and TL_ERR_NOT_FOUND when absent) and
 * its sorted node indices. */
TlStatus tl_api_mesh_node_set(const TlMesh *mesh, const char *name, size_t *n, const size_t **nodes);
/* A stepper of registered type `type` over `sys`: the library's default
 * options (tl_stepper_options_default) with n named numeric settings over
 * them, each a parameter of the type (tl_stepper_options_set: the
 * catalogue's table of the type, e.g. beta, gamma, rtol, max_iterations,
 * keep_factors for newmark; blowup, critical_bound for central_difference),
 * and the linear solver's name (NULL: the default). */
TlStatus tl_api_stepper_create(const char *type, TlMechSystem *sys, const char *solver, size_t n,
                               const char *const *names, const double *values, TlStepper **st);
/* The stepper's time and its dof-space state arrays (n doubles each). */
void tl_api_stepper_state(TlStepper *st, double *t, size_t *n, double **u, double **v, double **a);

/* ---- surface coupling (tl_api_coupling.c) ---- */
/* tl_scoupling_create_boundary with the default options and n named
 * settings over them (width, subdivisions, support) and the CG kernel's
 * name (NULL: the default). */
TlStatus tl_api_scoupling_create_boundary(TlSolid *solid, int n_excluded, const char *const *excluded,
                                          const char *kernel, size_t n, const char *const *names,
                                          const double *values, TlSCoupling **sc);
/* tl_coupled_loop_create with the default options and n named settings
 * over them (substeps, one_way, scheme, average_forces). */
TlStatus tl_api_coupled_loop_create(TlDem *dem, TlSolid *solid, TlStepper *stepper,
                                    int n_couplings, TlSCoupling *const *couplings, size_t n,
                                    const char *const *names, const double *values, TlCoupledLoop **loop);
/* The loop's node-space arrays (n_nodes x 3 each, n_nodes those of the
 * solid's mesh): displacements, velocities and the coupling forces of the
 * last FE step; they live as long as the loop. */
void tl_api_coupled_loop_arrays(const TlCoupledLoop *loop, const double **u, const double **v, const double **f);
/* The particle–wall force total the coupling forces balance. */
void tl_api_coupled_loop_wall_force(const TlCoupledLoop *loop, double f[3]);
/* The momentum defect of the last step (Eq. 41): the particle–wall force
 * plus the coupling forces on the n_nodes nodes of the solid's mesh (zero
 * up to round-off when the beam receives exactly minus what the grains
 * do). */
TlVec3 tl_api_coupled_loop_imbalance(const TlCoupledLoop *loop, size_t n_nodes);
/* The surface-coupled loop in one call: every boundary face of the solid
 * (set up) but those of the face set `excluded` (NULL: none) coupled
 * (SCoupling, default options: the Dirac limit) and handed to the world as
 * a wall of law `law`; the world is set up (its particles, laws and time
 * step given first); a stepper of type `stepper` (NULL:
 * central_difference) with the default options at rest at t = 0; and the
 * coupled loop over them, one FE step per DEM step.  Step it with
 * tl_coupled_loop_step(tl_api_scoupled_loop(c)).  Destroy it before the
 * world and the solid. */
typedef struct TlSCoupledLoop TlSCoupledLoop;
TlStatus tl_api_scoupled_create(TlDem *dem, TlSolid *solid, const char *excluded, int law, const char *stepper,
                                TlSCoupledLoop **loop);
TlCoupledLoop *tl_api_scoupled_loop(const TlSCoupledLoop *loop);
TlStepper *tl_api_scoupled_stepper(const TlSCoupledLoop *loop);
void tl_api_scoupled_destroy(TlSCoupledLoop **loop);

/* ---- conveniences for scenes (tl_api_scene.c) ---- */
/* A named setting. */
typedef struct {
  const char *name;
  double value;
} TlSetting;
/* A contact law of the named parts (friction, rolling, adhesion may be
 * NULL) with n settings (tl_contact_law_set), set up and added to the
 * world, which owns it; *index (may be NULL) receives its number.  A
 * refused setting leaves the world unchanged. */
TlStatus tl_api_dem_add_law(TlDem *dem, const char *normal, const char *friction, const char *rolling,
                            const char *adhesion, size_t n, const TlSetting *settings, int *index);
/* The world's open box [lo, hi] and a plane wall of law `law`, facing
 * inwards, on each face named in `walls` ("xmin xmax ymin ymax zmin zmax",
 * any of them, space- or comma-separated; NULL or "": none); an unknown
 * name is refused. */
TlStatus tl_api_dem_set_box_walls(TlDem *dem, TlVec3 lo, TlVec3 hi, const char *walls, int law);
/* A solid over `mesh` with `material` on every block and the node set
 * `clamped` (NULL: none) fixed in x, y and z; not set up (a wrapper such
 * as the volume coupling's comes first). */
TlStatus tl_api_solid_create(TlMesh *mesh, TlMaterial *material, const char *clamped, TlSolid **solid);
/* A CSV table dir/name.csv (tl_timeseries_create). */
TlStatus tl_api_timeseries_create(const char *dir, const char *name, size_t n_columns, const TlColumn *columns,
                                  TlTimeSeries **ts);
/* One writer for a scene in `dir`: particles.xmf (the world's particles,
 * with ids and species) and walls.xmf (its walls, when it has any at
 * creation) for a world, <solid_name>.xmf (NULL: "solid") for a solid with
 * the state of its stepper; dem or solid may be NULL.  Each write is one
 * snapshot of all of them at the world's time (the stepper's without a
 * world). */
typedef struct TlSceneWriter TlSceneWriter;
TlStatus tl_api_scene_writer_create(const char *dir, TlDem *dem, TlSolid *solid, TlStepper *stepper,
                                    const char *solid_name, TlSceneWriter **w);
TlStatus tl_api_scene_writer_write(TlSceneWriter *w, int64_t step);
void tl_api_scene_writer_destroy(TlSceneWriter **w);
/* A triangulated wall from an STL or Gmsh surface file
 * (tl_wall_trisurface_from_file) placed as x <- rotation (scale x) + shift
 * (rotation: 9 doubles row by row, NULL: none; shift NULL: none), repaired
 * or refused when defective, an open surface refused when require_closed.
 * report (may be NULL) receives what repair found and did: vertices
 * merged, triangles removed, triangles flipped, vertices split,
 * non-manifold edges, holes, boundary edges, closed (0/1), enclosed volume
 * (m^3). */
TlStatus tl_api_wall_from_file(const char *path, double scale, const double rotation[9], const double shift[3],
                               int repair, int require_closed, TlWall **w, double report[9]);

/* ---- the volume-coupled loop (tl_api_vcoupling.c) ----
 * A world's particles and a solid coupled through a TlVCoupling (Arlequin
 * weights over params->zone, a penalty tying the particles' homogenised
 * displacement to the elements'), stepped in lock-step: every tl_dem_step
 * of the world also steps the solid by the same dt and applies the
 * coupling forces to both (Eq. 41 balance).  Create it after the particles
 * are in the world and before tl_dem_setup, over a solid not yet set up
 * (material and supports given): it creates the coupling over block 0 and
 * its element wrapper, sets the solid up and creates a stepper of type
 * `stepper` (NULL: central_difference) with the default options, at rest
 * at t = 0.  Destroy it before the world and the solid. */
typedef struct TlVCoupledLoop TlVCoupledLoop;
TlStatus tl_api_vcoupled_create(TlDem *dem, TlSolid *solid, const TlVCouplingParams *params, const char *stepper,
                                TlVCoupledLoop **loop);
/* The solid's stepper (owned by the loop) and the nodal displacements
 * (3 per mesh node) at the world's time. */
TlStepper *tl_api_vcoupled_stepper(const TlVCoupledLoop *loop);
const double *tl_api_vcoupled_u_nodes(const TlVCoupledLoop *loop);
/* The diagnostics of the last step (force sums on both sides, Eq. 41
 * defect, coupling work) and the largest Eq. 41 defect so far; either
 * may be NULL. */
void tl_api_vcoupled_diag(const TlVCoupledLoop *loop, TlVCouplingDiag *last, double *eq41_max);
void tl_api_vcoupled_destroy(TlVCoupledLoop **loop);

#endif
