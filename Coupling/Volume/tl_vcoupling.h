/* Volume coupling (Arlequin) of particles and a solid overlapping in a zone,
 * with CG-enriched homogenisation (seeds/001 §5.2, Eqs. 17-32, Appendix B).
 *
 * The coupling wraps one element block of a mesh through its element type's
 * ops (shape functions, quadrature, inverse map), so any solid element type
 * works.  Per step:
 *
 *   1. tl_vcoupling_update(): the current geometry of the coupling elements
 *      (bounding boxes extended by the CG width c), and the homogenisation
 *      operator Pi of Eq. 27 for the particles near each element:
 *        c = 0: Eq. 19, Pi_ia ~ m_a N_i(xi_a) through the inverse map;
 *        c > 0: Eq. 18, Pi_ia ~ m_a sum_q w_q W(x_q - x_a) N_i(x_q) by
 *               quadrature on the element, no inverse map.
 *      Rows are normalised (sum_a Pi_ia = 1) either per element, as Eq. 18
 *      is written (each element its own u_i^DE, forces assembled), or over
 *      the whole support of node i (one u_i^DE per node); see
 *      TlVCouplingParams.per_element.  Rows no particle reaches are left out
 *      of the constraint.
 *   2. tl_vcoupling_forces(): u_i^DE = sum_a Pi_ia du_a, the nodal
 *      mismatch r_j = u_j^DE - u_j^FE (Eq. 29), the nodal force of the
 *      body force b^C = eps r (Eq. 31) on the solid, F_i = eps sum_j M_ij r_j
 *      with M_ij = int_{Omega^C} N_i N_j dV (or its row-sum lumping,
 *      tl_vcoupling_set_lumped_penalty), and the particle forces
 *      f_a^C = -sum_i Pi_ia F_i (Eq. 32), so sum_a f_a^C = -sum_i F_i
 *      (Eq. 41) up to round-off.
 *
 * Weights (Eqs. 22-26): w = 1 on the particle side, 0 on the solid side, a
 * half-cycle cosine (or a linear ramp, tl_vcoupling_set_profile) across the
 * zone [lo, hi] along one axis.  Nodal values
 * w_i are set once; inside the coupling elements w is interpolated by the
 * shape functions, so the weight field moves with the solid.  The particle
 * equations are weighted by w (at centres, w_a, and contact points, w_ab),
 * the solid's by 1 - w.
 *
 * No allocation after the first steps: every buffer grows to its working
 * size and is reused. */
#ifndef TL_VCOUPLING_H
#define TL_VCOUPLING_H

#include <stddef.h>
#include "tl_error.h"
#include "tl_mesh.h"

/* The coupling zone: w = 1 for x[axis] <= lo, 0 for x[axis] >= hi. */
typedef struct {
  int axis;
  double lo, hi;
} TlVCouplingZone;

typedef struct {
  TlVCouplingZone zone;
  double c;           /* CG width (m); 0 selects the classical Eq. 19 */
  const char *kernel; /* CG kernel name for c > 0 ("lucy", "gaussian", "heaviside") */
  double epsilon;     /* penalty (Pa/m^2) */
  int quad_order;     /* Gauss points per direction for Eq. 18 (1..5) */
  int per_element;    /* 0: rows of Pi normalised over the whole support of
                         node i (a node has one u_i^DE); 1: per element, as
                         Eq. 18 is written (sum over Omega_e alone, each
                         element its own u_i^DE, forces assembled) */
} TlVCouplingParams;

typedef struct {
  size_t n_active;      /* coupled nodes (reached by particles) */
  size_t n_entries;     /* nonzeros of Pi */
  double residual_max;  /* max_j |u_j^DE - u_j^FE| over coupled nodes (m) */
  double residual_rms;
  double force_fem[3];  /* sum of the nodal coupling forces on the solid */
  double force_dem[3];  /* sum of the particle coupling forces */
  double eq41;          /* |force_fem + force_dem| / sum of |nodal forces| (0 if no force) */
  double work_fem;      /* sum_i F_i . du_i (coupling work on the solid in the step) */
  double work_dem;      /* sum_a f_a . du_a */
} TlVCouplingDiag;

typedef struct TlVCoupling TlVCoupling;

/* The half-cycle cosine profile of the zone at point x (1 on the lo side). */
double tl_vcoupling_zone_weight(const TlVCouplingZone *zone, const double x[3]);

/* Coupling on block `block` of a finalized 3-D mesh: the coupling elements
 * are those reaching into the open zone (lo, hi).  Errors name a bad axis,
 * an empty or inverted zone, a negative or non-finite c or epsilon, an
 * unknown kernel, a zone holding no element. */
TlStatus tl_vcoupling_create(const TlMesh *mesh, int block, const TlVCouplingParams *params,
                             TlVCoupling **vc);
void tl_vcoupling_destroy(TlVCoupling **vc);

/* Changes the CG width (0: classical); takes effect at the next update. */
TlStatus tl_vcoupling_set_width(TlVCoupling *vc, double c);

/* Choices of the authors' published runs, each off by default; set them
 * before the first update (the nodal weights and M_ij are rebuilt).
 *   profile: the weight across the zone, TL_VCOUPLING_COSINE (default, the
 *     half-cycle cosine of tl_vcoupling_zone_weight) or TL_VCOUPLING_LINEAR
 *     (1 - s, s the zone coordinate in [0, 1]);
 *   weight_min in [0, 0.5): the zone's nodes (its closed ends included)
 *     take weights in [weight_min, 1 - weight_min], the profile scaled
 *     into that range (the published explicit runs: 0.1, so that no
 *     particle of the zone weighs less than a tenth); outside the zone 1
 *     and 0 as before, so the weight jumps at the zone's ends and the
 *     solid's weight 1 - w is interpolated across the elements next to it;
 *   lumped_penalty: 1 puts the row sums of M_ij on the diagonal, F_i = eps
 *     (int N_i dV) r_i: each node penalised on its own mismatch alone;
 *   reach_shrink (m, >= 0): Eq. 18 (c > 0) gathers the particles within
 *     max(c - reach_shrink, 0) of each element instead of the kernel's
 *     whole reach c; with reach_shrink = d (a particle diameter: the
 *     published runs' bounding box before their search widens it to whole
 *     cells, which gives back the reach c) an element sees its own
 *     particles alone up to c = d. */
typedef enum { TL_VCOUPLING_COSINE = 0, TL_VCOUPLING_LINEAR } TlVCouplingProfile;
TlStatus tl_vcoupling_set_profile(TlVCoupling *vc, TlVCouplingProfile profile);
TlStatus tl_vcoupling_set_weight_min(TlVCoupling *vc, double weight_min);
TlStatus tl_vcoupling_set_lumped_penalty(TlVCoupling *vc, int lumped);
TlStatus tl_vcoupling_set_reach_shrink(TlVCoupling *vc, double reach_shrink);

/* Current geometry (u_nodes: total nodal displacements, 3 per mesh node, or
 * NULL for the reference configuration) and Pi for np particles at xp
 * (3 per particle) with masses mp. */
TlStatus tl_vcoupling_update(TlVCoupling *vc, const double *u_nodes, size_t np, const double *xp,
                             const double *mp);

/* Weights w(x) at n points (particle centres or contact points) in the
 * geometry of the last update: interpolated from the nodal weights inside a
 * coupling element, the zone profile elsewhere. */
TlStatus tl_vcoupling_point_weights(TlVCoupling *vc, size_t n, const double *x, double *w);

/* Coupling forces for the last step's particle displacements du_p (3 per
 * particle, e.g. v dt) and nodal displacement increments du_n (3 per mesh
 * node): adds the nodal forces to f_nodes and the particle forces to
 * f_particles (either may be NULL); diag (may be NULL) gets the residual,
 * the force sums and Eq. 41. */
TlStatus tl_vcoupling_forces(TlVCoupling *vc, const double *du_p, const double *du_n, double *f_nodes,
                             double *f_particles, TlVCouplingDiag *diag);

/* Resolution of Pi, the check on the CG width.  For each coupled row i,
 * the homogenised position of its particles, X_i^DE = sum_a Pi_ia x_a (xp:
 * the particle positions of the last update), against the centroid of the
 * row's shape function over its coupled support, X_i = int N_i x dV /
 * int N_i dV (current geometry).  A consistent operator (one that carries a
 * uniform strain of the particles to the nodes) has X_i^DE = X_i up to the
 * particle spacing.  Where the kernel is cut off (the particle region ends,
 * or the body's faces, within c of the element) X_i^DE drifts from X_i by
 * a distance growing with c; once it passes half an element size, node i
 * takes its displacement from particles that lie nearer a neighbouring
 * node than to its own: the coupling no longer resolves the mesh, and a
 * wave through the overlap is distorted (a phase error of that distance). */
typedef struct {
  double bias_max;     /* max over rows i and directions d of |X_id^DE - X_id| (m) */
  size_t node;         /* global mesh node of the row with the largest bias */
  double x_de[3], x_ref[3];
  double h;            /* largest element extent (m), the scale of the limit */
} TlVCouplingResolution;

/* Half an element size: the default limit of tl_vcoupling_check_resolution. */
#define TL_VCOUPLING_BIAS_LIMIT 0.5

TlStatus tl_vcoupling_resolution(TlVCoupling *vc, const double *xp, TlVCouplingResolution *res);

/* The resolution check as a stop: TL_ERR_UNSTABLE, with a message naming
 * the CG width, the bias, the limit (limit_fraction h) and `step`, when the
 * bias exceeds limit_fraction times the element size; res (may be NULL)
 * gets the measurement either way. */
TlStatus tl_vcoupling_check_resolution(TlVCoupling *vc, const double *xp, double limit_fraction, long step,
                                       TlVCouplingResolution *res);

/* The homogenised particle field at the coupled nodes, u_i = sum_a Pi_ia
 * q_a (q: 3 per particle): written into out (3 per mesh node) at the nodes
 * reached by particles, which are flagged 1 in reached (one per mesh node,
 * may be NULL); other entries are left untouched. */
TlStatus tl_vcoupling_homogenise(const TlVCoupling *vc, const double *q, double *out, char *reached);

/* The nodal weights w_i (one per mesh node; 0 at nodes outside the zone on
 * the solid side). */
const double *tl_vcoupling_node_weights(const TlVCoupling *vc);

/* The weight 1 - w of the solid at a local point xi of element e of the
 * block (for weighting the solid's residual at its quadrature points). */
double tl_vcoupling_solid_weight(const TlVCoupling *vc, size_t e, const double xi[3]);

/* Pi in triplet form (node = global mesh node, particle index, value), as
 * built by the last update; rows sum to one. */
void tl_vcoupling_operator(const TlVCoupling *vc, size_t *n, const size_t **node, const size_t **particle,
                           const double **value);

/* Coupling elements (indices into the block). */
void tl_vcoupling_elements(const TlVCoupling *vc, size_t *n, const size_t **elements);

/* The mesh and block the coupling was built on. */
const TlMesh *tl_vcoupling_mesh(const TlVCoupling *vc, int *block);

/* Particles of the last update (the length of du_p in tl_vcoupling_forces). */
size_t tl_vcoupling_n_particles(const TlVCoupling *vc);

/* The derivative of the nodal coupling forces with respect to the solid's
 * displacements on coupling element `slot` (0 <= slot < n_elements of
 * tl_vcoupling_elements): dF_a/du_b = -eps M_ab for rows and columns coupled
 * at the last update, 0 elsewhere; Kab gets it as nn x nn (one component,
 * the same for each) with the element's global nodes in nodes (nn).
 * Summed over the slots it is the derivative of tl_vcoupling_forces'
 * nodal forces. */
TlStatus tl_vcoupling_force_derivative(const TlVCoupling *vc, size_t slot, double *Kab, size_t *nodes);

#endif
