/* The total-Lagrangian finite-strain solid (seeds/001 Eqs. 3-5).
 *
 * Unknowns are nodal displacements u (X = xi + u); per Gauss point
 *   F = 1 + grad_xi u,  E = (F^T F - 1)/2,  S = law(F)   (second Piola-Kirchhoff),
 * and the element residual of Eq. 5,
 *   R_ai = int F_ik S_kj dN_a/dxi_j dV - int (b_i - rho a_i) N_a dV - int t_i N_a dA,
 * with its consistent tangent (material part B^T D B plus the geometric part
 * dN_a . S dN_b).  In 2-D the elements are plane strain (F_33 = 1).
 *
 * A TlSolid is a TlMechSystem (tl_mech_system.h; its first member), so the
 * steppers drive it directly.  Life cycle:
 *   tl_solid_create(mesh) -> set materials, loads, boundary conditions ->
 *   tl_solid_setup() -> tl_solid_system() to a stepper -> tl_solid_destroy().
 * The mesh and the materials are borrowed and must outlive the solid.
 *
 * Dof numbering: node n, component c.  Components clamped at zero for all
 * time (tl_solid_fix) are eliminated (tl_solid_dof() = -1); prescribed ones
 * (tl_solid_prescribe) stay in the numbering as Dirichlet dofs.
 *
 * Couplings reach the solid in one way: a wrapper over an element block
 * (tl_solid_add_wrapper), the coupling element types of seeds/001 §5.3,
 * which add their internal terms and external loads to the block's. */
#ifndef TL_SOLID_H
#define TL_SOLID_H

#include "tl_element.h"
#include "tl_error.h"
#include "tl_material.h"
#include "tl_math.h"
#include "tl_mech_system.h"
#include "tl_mesh.h"
#include "tl_sparse.h"

typedef struct TlSolid TlSolid;

/* A load amplitude a(t) (NULL means 1). */
typedef double (*TlAmplitude)(double t, void *ctx);
/* A prescribed displacement: out[0] = u, out[1] = du/dt, out[2] = d2u/dt2 of
 * component `component` at the node of reference position X, time t. */
typedef void (*TlPrescribed)(double t, const double X[3], int component, void *ctx, double out[3]);

TlStatus tl_solid_create(const TlMesh *mesh, TlSolid **solid);
void tl_solid_destroy(TlSolid **solid);
/* The system view for the steppers (the same object). */
TlMechSystem *tl_solid_system(TlSolid *solid);

/* Material of a block (NULL block name: every block). */
TlStatus tl_solid_set_material(TlSolid *solid, const char *block, TlMaterial *material);
/* Body force per reference volume b (N/m^3), dead, times a(t). */
TlStatus tl_solid_add_body_force(TlSolid *solid, const char *block, TlVec3 b, TlAmplitude amp,
                                 void *ctx);
/* Gravity: b = rho g on every block. */
TlStatus tl_solid_add_gravity(TlSolid *solid, TlVec3 g);
/* Dead traction per reference area on a face set (Pa), times a(t). */
TlStatus tl_solid_add_traction(TlSolid *solid, const char *face_set, TlVec3 t, TlAmplitude amp,
                               void *ctx);
/* Follower pressure p (Pa, positive pushes against the outward normal of the
 * deformed face), times a(t).  Makes the system non-symmetric. */
TlStatus tl_solid_add_pressure(TlSolid *solid, const char *face_set, double p, TlAmplitude amp,
                               void *ctx);
/* Point force on a node (N), times a(t). */
TlStatus tl_solid_add_point_force(TlSolid *solid, size_t node, TlVec3 f, TlAmplitude amp,
                                  void *ctx);
/* Clamps components (bit c of mask = component c) of a node set at zero. */
TlStatus tl_solid_fix(TlSolid *solid, const char *node_set, int component_mask);
/* Prescribes component c of a node set as a function of time and position. */
TlStatus tl_solid_prescribe(TlSolid *solid, const char *node_set, int component, TlPrescribed fn,
                            void *ctx);
/* K += scale * Ke on the dofs of n nodes (Ke: (n dim)^2, row-major, node
 * major); clamped components are skipped. */
TlStatus tl_solid_matrix_add_nodes(const TlSolid *solid, TlSparse *K, int n, const size_t *nodes,
                                   double scale, const double *Ke);
/* Weights of a block's equations (the 1 - w of seeds/001 Eq. 26 for the
 * solid side of an Arlequin overlap), set before tl_solid_setup: every
 * integral over the block is taken with the weight as a factor of the
 * quadrature weight, so the internal force, its tangent, the stored energy,
 * the consistent and the lumped (HRZ) mass and the dead body loads of the
 * block are all weighted.  The weights enter the quadrature weights once at
 * setup; the element kernel is the same code with or without them.
 *   tl_solid_set_point_weights: w at the stiffness points (n_el x nq) and
 *     w_mass at the mass points (n_el x nq_mass), element major, in the
 *     order of the type's rules (tl_solid_weight_points gives nq and
 *     nq_mass); both NULL: unweighted (the default).
 *   tl_solid_set_node_weights: a nodal field (n_nodes) interpolated with the
 *     shape functions at both point sets (negative values of quadratic shape
 *     functions clipped at 0); NULL: unweighted.
 * Weights must be finite and >= 0; a node whose elements all weigh 0 has no
 * mass and is refused at setup.  Volume averages of stress stay
 * unweighted.  Each call replaces what the block had. */
TlStatus tl_solid_weight_points(const TlSolid *solid, int b, int *nq, int *nq_mass);
TlStatus tl_solid_set_point_weights(TlSolid *solid, int b, const double *w, const double *w_mass);
TlStatus tl_solid_set_node_weights(TlSolid *solid, int b, const double *w_nodes);
/* Weights of the lumped mass per node (n_nodes, finite and > 0), set
 * before tl_solid_setup: the lumped (HRZ) mass of node n, every component,
 * is multiplied by w_nodes[n] after assembly (the nodal weighted masses
 * alpha(X_I) M_I of the bridging domain method, seeds/000 §2), so the
 * explicit steppers, the lumped kinetic energy and tl_solid_total_mass see
 * the weighted masses; the consistent mass and the body loads are left to
 * the point weights.  NULL: none (the default); a call replaces the last. */
TlStatus tl_solid_set_lumped_mass_weights(TlSolid *solid, const double *w_nodes);
/* Numbers the dofs, checks materials and elements, precomputes geometry,
 * masses and dead loads.  After it, the loads and conditions are frozen. */
TlStatus tl_solid_setup(TlSolid *solid);

/* Refuses boundary conditions that leave a rigid-body mode free (needed by
 * quasi-static solves; dynamics may run free bodies): the error names the
 * block, the free mode and the node sets that carry conditions. */
TlStatus tl_solid_check_constraints(const TlSolid *solid);

/* Dof of (node, component), -1 when clamped. */
TlSparseIndex tl_solid_dof(const TlSolid *solid, size_t node, int component);
/* Node-space displacements (n_nodes x dim; clamped components 0) from a dof
 * vector, and back (gathers the dof entries of a node-space vector). */
void tl_solid_dofs_to_nodes(const TlSolid *solid, const double *u, double *u_nodes);
void tl_solid_nodes_to_dofs(const TlSolid *solid, const double *f_nodes, double *f);

/* The block's own elements (what its wrappers wrap): adds the
 * internal force of every element of block b at node-space displacements
 * u_nodes into f_nodes (n_nodes x dim; may be NULL), c_u times the tangent
 * into K (may be NULL), and the stored energy into *W (may be NULL).
 * Material state: trial from committed. */
TlStatus tl_solid_block_forces(TlSolid *solid, int b, const double *u_nodes, double *f_nodes,
                               double c_u, TlSparse *K, double *W);

/* Wrappers: the one way a coupling element type wraps an element type
 * (the SCoupling and VCoupling elements of seeds/001 §5.3; the
 * finite-element code is not edited).  A wrapper is installed over element
 * block b and evaluated wherever the block is: the solid first evaluates
 * what it wraps (the block's own elements, then the wrappers installed on
 * the block before it), then the wrapper's ops, each optional:
 *   internal  ADDS internal force terms (same sign as f_int) into f_nodes,
 *             c_u times their tangent into K and stored energy into *W
 *             (each output may be NULL; t is NAN when only the energy is
 *             asked).  Called inside every internal-force, tangent and
 *             stored-energy evaluation, so inside Newton iterations.
 *   external  ADDS external loads (same sign as f_ext: the force on the
 *             solid) into f_nodes and c times their derivative d f/du into
 *             K (either may be NULL).  Called inside every external-force
 *             and load-tangent evaluation: the steppers count these loads
 *             as external work, and reactions and tl_solid_work_increment
 *             see them.
 * u_nodes and f_nodes are node-space (n_nodes x dim).  Tangent terms must
 * lie within the block's element pattern (tl_solid_matrix_add_nodes on an
 * element's nodes) and keep the system's symmetry.  A wrapper keeps no
 * pointer to what it wraps: the wrappers of a block are an ordered list
 * (installation order), each removed by its handle in any order, at any
 * time; the solid frees those left when it is destroyed. */
typedef struct {
  TlOpsHeader header; /* kind "solid_wrapper"; the name is used in messages */
  TlStatus (*internal)(void *ctx, TlSolid *solid, int b, double t, const double *u_nodes, double *f_nodes,
                       double c_u, TlSparse *K, double *W);
  TlStatus (*external)(void *ctx, TlSolid *solid, int b, double t, const double *u_nodes, double *f_nodes,
                       double c, TlSparse *K);
} TlSolidWrapperOps;
typedef struct TlSolidWrapper TlSolidWrapper;
/* Installs a wrapper with ops (borrowed, must outlive it) and context ctx
 * over block b, after those already there; *handle identifies it. */
TlStatus tl_solid_add_wrapper(TlSolid *solid, int b, const TlSolidWrapperOps *ops, void *ctx,
                              TlSolidWrapper **handle);
/* Removes the wrapper *handle (NULL: nothing) and nulls *handle. */
void tl_solid_remove_wrapper(TlSolid *solid, TlSolidWrapper **handle);
/* Number of wrappers over block b. */
int tl_solid_n_wrappers(const TlSolid *solid, int b);

/* Energies: kinetic 1/2 v.M v with the consistent mass; strain energy
 * (integral of the stored energy density); external work of the loads over
 * [t0, t1] from u0 to u1 by the trapezoidal rule. */
TlStatus tl_solid_kinetic_energy(TlSolid *solid, const double *v, double *K);
TlStatus tl_solid_strain_energy(TlSolid *solid, const double *u, double *W);
TlStatus tl_solid_work_increment(TlSolid *solid, double t0, const double *u0, double t1,
                                 const double *u1, double *dW);
/* Reaction forces at constrained (clamped and prescribed) node components:
 * R = f_int(u) + M a - f_ext(t, u) there, 0 elsewhere (n_nodes x dim); a may
 * be NULL (static). */
TlStatus tl_solid_reactions(TlSolid *solid, double t, const double *u, const double *a,
                            double *R_nodes);
/* Total mass of the solid (from the lumped mass; equals the integral of rho). */
double tl_solid_total_mass(const TlSolid *solid);
/* Element matrices for tests and wrappers: residual fe (n x dim), tangent
 * Ke (row-major, (n dim)^2) and consistent mass Me of element e of block b
 * at element displacements ue; any output may be NULL. */
TlStatus tl_solid_element_matrices(TlSolid *solid, int b, size_t e, const double *ue, double *fe,
                                   double *Ke, double *Me);
/* Second Piola-Kirchhoff stress and F at Gauss point q of element e of
 * block b for node-space displacements (postprocessing, tests). */
TlStatus tl_solid_gauss_stress(TlSolid *solid, int b, size_t e, int q, const double *u_nodes,
                               TlMat3 *F, TlMat3 *S);

/* Volume averages over element e of block b of the second Piola-Kirchhoff
 * stress S and of the Cauchy stress F S F^T / det F (either may be NULL). */
TlStatus tl_solid_element_stress(TlSolid *solid, int b, size_t e, const double *u_nodes, TlMat3 *S_avg,
                                 TlMat3 *sigma_avg);
/* The mesh the solid was built on. */
const TlMesh *tl_solid_mesh(const TlSolid *solid);

#endif
