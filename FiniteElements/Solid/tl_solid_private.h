/* Internal to FiniteElements/Solid: the solid's state and what its files
 * share.  tl_solid.h is the interface; the files are one concern each:
 *   tl_solid.c            life cycle, block lookup, dof maps
 *   tl_solid_loads.c      loads and boundary conditions, external force
 *   tl_solid_weights.c    weights of a block's equations
 *   tl_solid_setup.c      dof numbering, geometry, colours, pattern, masses
 *   tl_solid_kernel.c     the general element kernel (any dim, any law)
 *   tl_solid_residual.c   the component-major residual path (3-D, no state)
 *   tl_solid_system.c     the TlMechSystem ops the steppers call
 *   tl_solid_wrapper.c    wrappers over blocks (coupling element types)
 *   tl_solid_post.c       stresses, energies, work, reactions
 *   tl_solid_checkpoint.c committed material state
 *   tl_solid_rigid.c      the rigid-mode check
 *   tl_solid_tie.c        periodic ties (slave nodes numbered as their masters) */
#ifndef TL_SOLID_PRIVATE_H
#define TL_SOLID_PRIVATE_H

#include "tl_checkpoint.h"
#include "tl_solid.h"

/* Elements per material call: F, S and D of a chunk are evaluated in one
 * batch. */
#define CHUNK 32

typedef struct {
  TlMaterial *material;
  TlQuadrature q;  /* stiffness rule */
  TlQuadrature qm; /* mass rule */
  int nn, nd, nq;
  int symmetric; /* material tangent symmetric */
  double *grad;      /* n_el x nq x nn x dim: dN_a/dxi (reference gradients) */
  double *grad_t;    /* 3-D: the same point-innermost, n_el x nn x 3 x nq (residual path's H) */
  double *grad_n;    /* 3-D: node-innermost, n_el x 3 x nq x nn (residual path's nodal forces) */
  double *wdet;      /* n_el x nq: weight x det J0 */
  double *Nm;        /* qm.n x nn: shape values at the mass points */
  double *wdetm;     /* n_el x qm.n */
  double *lumped;    /* n_el x nn: element lumped (HRZ) masses */
  double *state_old; /* n_el x nq x state_size */
  double *state_new;
  int n_colours;
  size_t *colour_ptr; /* n_colours + 1 */
  size_t *colour_elements;
  size_t offset; /* index of the block's first element in the global list */
  TlSolidWrapper *wrappers; /* the block's wrappers, in installation order */
  /* Weights of the block's equations (seeds/001 Eq. 26), NULL when unset.
   * They multiply wdet and wdetm once at setup, so the element kernel
   * carries them without a single extra operation. */
  double *pw;         /* n_el x nq at the stiffness points */
  double *pw_mass;    /* n_el x qm.n at the mass points */
  double *w_nodes;    /* n_nodes: a nodal field interpolated at setup instead */
  double *wdet_plain; /* n_el x nq: unweighted weight x det J0 (volume averages) */
  /* POINTS evaluation (tl_solid_set_evaluation), allocated on first use:
   * H = F - 1, S and D of every point from the last evaluation, which was
   * at node-space displacements pu; p_valid until the next commit or
   * rollback. */
  TlMat3 *pH, *pS;
  double *pD;     /* 36 per point */
  double *pcost;  /* last measured seconds per point */
  size_t *porder; /* points by decreasing cost (LPT) */
  double *pu;     /* n_nodes x dim */
  double p_total; /* summed cost of the last evaluation */
  int p_valid;
} SolidBlock;

typedef struct {
  int block; /* -1: all */
  int gravity;
  TlVec3 b;
  TlAmplitude amp;
  void *ctx;
} BodyForce;

typedef struct {
  int face_set;
  int pressure; /* follower pressure (p) or dead traction (t) */
  TlVec3 t;
  double p;
  TlAmplitude amp;
  void *ctx;
} SurfaceLoad;

typedef struct {
  size_t node;
  TlVec3 f;
  TlAmplitude amp;
  void *ctx;
} PointForce;

typedef struct {
  size_t node;
  int component;
  TlPrescribed fn;
  void *ctx;
} Prescribed;

typedef struct {
  double *f; /* node-space vector of a dead load at amplitude 1 */
  TlAmplitude amp;
  void *ctx;
} DeadLoad;

/* A wrapper over a block (tl_solid_add_wrapper): one link of its list. */
struct TlSolidWrapper {
  const TlSolidWrapperOps *ops;
  void *ctx;
  int block;
  TlSolidWrapper *next;
};

/* Per-thread scratch, sized at setup. */
typedef struct {
  TlMat3 *F, *S;
  double *Hsoa, *Ssoa; /* the residual path's H and S, component-major */
  double *D, *W;
  double *state_old, *state_new;
  double *fe, *Ke, *B, *DB, *ue;
  TlSparseIndex *dofs;
} Scratch;

struct TlSolid {
  TlMechSystem base;
  const TlMesh *mesh;
  int dim;
  size_t n_nodes, n_elements;
  SolidBlock *blocks;
  unsigned char *constraint; /* n_nodes x dim: 0 free, 1 clamped, 2 prescribed */
  size_t *tie_master;        /* n_nodes: the node whose dofs a node shares (tl_solid_tie), NULL: no tie */
  Prescribed *prescribed;
  size_t n_prescribed, cap_prescribed;
  BodyForce *body;
  int n_body;
  SurfaceLoad *surface;
  int n_surface;
  PointForce *points;
  size_t n_points, cap_points;
  DeadLoad *dead;
  int n_dead;
  TlSparseIndex *dof; /* n_nodes x dim */
  TlSparseIndex *elem_ptr, *elem_dofs;
  double *lumped_nodes; /* n_nodes x dim */
  double *lumped_weights; /* n_nodes: factors of the lumped mass (NULL: none) */
  double *un, *fn, *gn; /* node-space work vectors */
  Scratch *scratch;
  int n_threads;
  int max_nd, max_nq;
  size_t n_pattern; /* the elements of the matrix pattern */
  char constraint_sets[256];
  int ready;
  int eval_mode, eval_threads; /* tl_solid_set_evaluation */
  TlSolidEvalStats eval_stats;
};


/* Records a worker thread's error so the calling thread can re-raise it
 * (messages are thread-local). */
typedef struct {
  TlStatus status;
  char message[1024];
} ParallelError;

/* Block index of a block name (NULL: -1, every block); 0 if unknown. */
int tl_solid_block_of_name(const TlSolid *s, const char *name, int *b);
/* Refuses a configuration call after set-up. */
TlStatus tl_solid_not_after_setup(const TlSolid *s, const char *what);
void tl_solid_parallel_error_record(ParallelError *pe, TlStatus s);
TlStatus tl_solid_parallel_error_raise(const ParallelError *pe);
/* The content destructor of the system ops. */
void tl_solid_destroy_content(TlMechSystem *sys);

/* Ties (tl_solid_tie.c): the root node of every node (itself when untied)
 * into root (n_nodes), refusing a cycle. */
TlStatus tl_solid_tie_roots(const TlSolid *s, size_t *root);

/* Loads (tl_solid_loads.c). */
TlStatus tl_solid_setup_dead_loads(TlSolid *s);
/* Follower pressure: f_nodes -= its force, K += c times its derivative. */
TlStatus tl_solid_pressure_loads(TlSolid *s, double t, const double *u_nodes, double *f_nodes, double c,
                                 TlSparse *K);
/* The external force at (t, u) in node space. */
TlStatus tl_solid_external_nodes(TlSolid *s, double t, const double *u, double *f_nodes);

/* POINTS evaluation (tl_solid_kernel.c): whether block b is evaluated point
 * by point, and forgetting the kept S and D (commit, rollback). */
int tl_solid_points_mode(const TlSolid *s, int b);
void tl_solid_points_invalidate(TlSolid *s);
void tl_solid_points_free(SolidBlock *B);

/* Weights (tl_solid_weights.c): the nodal weight field at the points. */
TlStatus tl_solid_interpolate_weights(TlSolid *s, int b, const double *Nq);

/* Kernels (tl_solid_kernel.c, tl_solid_residual.c). */
void tl_solid_deformation_gradients(const SolidBlock *B, int dim, size_t e, const double *ue, TlMat3 *F);
void tl_solid_element_forces(const SolidBlock *B, int dim, size_t e, const TlMat3 *F, const TlMat3 *S,
                             const double *D, double *fe, double *Ke, double *Bm, double *DB);
TlStatus tl_solid_block_residual(TlSolid *s, int b, const double *u_nodes, double *f_nodes);
/* Consistent mass of element e of block b: Mab[a][b] = int rho N_a N_b. */
void tl_solid_element_mass(const TlSolid *s, int b, size_t e, double *Mab);

/* Wrappers (tl_solid_wrapper.c): block b with its wrappers' internal terms,
 * and every wrapper's external loads. */
TlStatus tl_solid_block_evaluate(TlSolid *s, int b, double t, const double *u_nodes, double *f_nodes, double c_u,
                                 TlSparse *K, double *W);
TlStatus tl_solid_wrapper_loads(TlSolid *s, double t, const double *u_nodes, double *f_nodes, double c, TlSparse *K);
/* Some wrapper has external loads. */
int tl_solid_has_wrapper_loads(const TlSolid *s);
void tl_solid_free_wrappers(TlSolid *s);

/* System ops (tl_solid_system.c): internal force and tangent in node space. */
TlStatus tl_solid_internal_nodes(TlSolid *s, double t, const double *u, double *f_nodes, double c_u,
                                 TlSparse *K);
/* The ops with and without commit and rollback (chosen at set-up). */
extern const TlMechSystemOps tl_solid_ops_stateful, tl_solid_ops_elastic;
extern const TlCheckpointOps tl_solid_checkpoint_ops;

#endif
