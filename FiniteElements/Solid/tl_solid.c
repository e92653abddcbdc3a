#include "tl_solid.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "tl_memory.h"

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
  TlSolidBlockKernel kernel; /* what evaluates the block (own_block unless wrapped) */
  /* Weights of the block's equations (seeds/001 Eq. 26), NULL when unset.
   * They multiply wdet and wdetm once at setup, so the element kernel
   * carries them without a single extra operation. */
  double *pw;         /* n_el x nq at the stiffness points */
  double *pw_mass;    /* n_el x qm.n at the mass points */
  double *w_nodes;    /* n_nodes: a nodal field interpolated at setup instead */
  double *wdet_plain; /* n_el x nq: unweighted weight x det J0 (volume averages) */
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

typedef struct {
  TlSolidTerm fn;
  void *ctx;
  int symmetric;
  size_t n_groups;
  size_t *group_ptr, *group_nodes;
} Term;

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
  double *un, *fn, *gn; /* node-space work vectors */
  Scratch *scratch;
  int n_threads;
  int max_nd, max_nq;
  Term *terms;
  int n_terms;
  size_t n_pattern; /* elements plus term node groups in the matrix pattern */
  char constraint_sets[256];
  int ready;
  void **adopted; /* wrapper states freed with the solid (tl_solid_adopt) */
  size_t n_adopted;
};

/* ----------------------------------------------------------- utilities */

static int block_of_name(const TlSolid *s, const char *name, int *b)
{
  if (!name) {
    *b = -1;
    return 1;
  }
  return tl_mesh_find_block(s->mesh, name, b) == TL_OK;
}

static TlStatus not_after_setup(const TlSolid *s, const char *what)
{
  if (s->ready)
    TL_ERROR(TL_ERR_STATE, "solid: %s after tl_solid_setup (conditions are frozen)", what);
  return TL_OK;
}

static void note_set(TlSolid *s, const char *name)
{
  if (strstr(s->constraint_sets, name)) return;
  size_t l = strlen(s->constraint_sets);
  if (l + strlen(name) + 3 < sizeof s->constraint_sets)
    snprintf(s->constraint_sets + l, sizeof s->constraint_sets - l, "%s%s", l ? ", " : "", name);
}

/* Records a worker thread's error so the calling thread can re-raise it
 * (messages are thread-local). */
typedef struct {
  TlStatus status;
  char message[1024];
} ParallelError;

static void parallel_error_record(ParallelError *pe, TlStatus s)
{
#pragma omp critical(tl_solid_error)
  {
    if (pe->status == TL_OK) {
      snprintf(pe->message, sizeof pe->message, "%s", tl_error_message());
      pe->status = s;
    }
  }
}

static TlStatus parallel_error_raise(const ParallelError *pe)
{
  if (pe->status == TL_OK) return TL_OK;
  return tl_error_set(pe->status, __FILE__, __LINE__, "%s", pe->message);
}

/* ----------------------------------------------------- create / config */

static const TlMechSystemOps solid_ops, solid_ops_elastic;

TlStatus tl_solid_create(const TlMesh *mesh, TlSolid **solid)
{
  if (!mesh || !solid) TL_ERROR(TL_ERR_ARG, "tl_solid_create: NULL argument");
  if (!mesh->finalized) TL_ERROR(TL_ERR_STATE, "tl_solid_create: mesh not finalized");
  TlSolid *s = NULL;
  TL_CHECK(TL_NEW(s));
  s->base.ops = &solid_ops;
  s->mesh = mesh;
  s->dim = mesh->dim;
  s->n_nodes = mesh->n_nodes;
  TlStatus st = TL_OK;
  TL_CHECK_GOTO(st, tl_calloc(&s->blocks, mesh->n_blocks, sizeof *s->blocks), fail);
  TL_CHECK_GOTO(st, tl_calloc(&s->constraint, s->n_nodes * s->dim, 1), fail);
  *solid = s;
  return TL_OK;
fail:
  tl_free(&s->blocks);
  tl_free(&s);
  return st;
}

TlMechSystem *tl_solid_system(TlSolid *solid) { return &solid->base; }

static void solid_destroy_content(TlMechSystem *sys)
{
  TlSolid *s = (TlSolid *)sys;
  for (int b = 0; b < s->mesh->n_blocks && s->blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    tl_free(&B->grad);
    tl_free(&B->grad_t);
    tl_free(&B->grad_n);
    tl_free(&B->wdet);
    tl_free(&B->Nm);
    tl_free(&B->wdetm);
    tl_free(&B->lumped);
    tl_free(&B->state_old);
    tl_free(&B->state_new);
    tl_free(&B->colour_ptr);
    tl_free(&B->colour_elements);
    tl_free(&B->pw);
    tl_free(&B->pw_mass);
    tl_free(&B->w_nodes);
    tl_free(&B->wdet_plain);
  }
  for (int i = 0; i < s->n_dead; ++i) tl_free(&s->dead[i].f);
  for (int t = 0; t < s->n_threads && s->scratch; ++t) {
    Scratch *w = &s->scratch[t];
    tl_free(&w->F);
    tl_free(&w->S);
    tl_free(&w->Hsoa);
    tl_free(&w->Ssoa);
    tl_free(&w->D);
    tl_free(&w->W);
    tl_free(&w->state_old);
    tl_free(&w->state_new);
    tl_free(&w->fe);
    tl_free(&w->Ke);
    tl_free(&w->B);
    tl_free(&w->DB);
    tl_free(&w->ue);
    tl_free(&w->dofs);
  }
  for (int i = 0; i < s->n_terms; ++i) {
    tl_free(&s->terms[i].group_ptr);
    tl_free(&s->terms[i].group_nodes);
  }
  tl_free(&s->terms);
  for (size_t i = 0; i < s->n_adopted; ++i) tl_free(&s->adopted[i]);
  tl_free(&s->adopted);
  tl_free(&s->scratch);
  tl_free(&s->blocks);
  tl_free(&s->constraint);
  tl_free(&s->prescribed);
  tl_free(&s->body);
  tl_free(&s->surface);
  tl_free(&s->points);
  tl_free(&s->dead);
  tl_free(&s->dof);
  tl_free(&s->elem_ptr);
  tl_free(&s->elem_dofs);
  tl_free(&s->lumped_nodes);
  tl_free(&s->un);
  tl_free(&s->fn);
  tl_free(&s->gn);
  tl_free(&s->base.dirichlet_dofs);
}

void tl_solid_destroy(TlSolid **solid)
{
  if (!solid || !*solid) return;
  TlMechSystem *sys = &(*solid)->base;
  tl_mech_system_destroy(&sys);
  *solid = NULL;
}

TlStatus tl_solid_set_material(TlSolid *s, const char *block, TlMaterial *material)
{
  TL_CHECK(not_after_setup(s, "set_material"));
  if (!material) TL_ERROR(TL_ERR_ARG, "solid: NULL material for block %s", block ? block : "(all)");
  int b;
  if (!block_of_name(s, block, &b))
    TL_ERROR(TL_ERR_NOT_FOUND, "solid: no element block '%s' for the material", block);
  for (int k = 0; k < s->mesh->n_blocks; ++k)
    if (b < 0 || k == b) s->blocks[k].material = material;
  return TL_OK;
}

static TlStatus add_body(TlSolid *s, int block, int gravity, TlVec3 b, TlAmplitude amp, void *ctx)
{
  if (!tl_v3_isfinite(b)) TL_ERROR(TL_ERR_ARG, "solid: body force is not finite");
  TL_CHECK(tl_realloc(&s->body, s->n_body + 1, sizeof *s->body));
  s->body[s->n_body++] = (BodyForce){block, gravity, b, amp, ctx};
  return TL_OK;
}

TlStatus tl_solid_add_body_force(TlSolid *s, const char *block, TlVec3 b, TlAmplitude amp, void *ctx)
{
  TL_CHECK(not_after_setup(s, "add_body_force"));
  int k;
  if (!block_of_name(s, block, &k))
    TL_ERROR(TL_ERR_NOT_FOUND, "solid: no element block '%s' for the body force", block);
  return add_body(s, k, 0, b, amp, ctx);
}

TlStatus tl_solid_add_gravity(TlSolid *s, TlVec3 g)
{
  TL_CHECK(not_after_setup(s, "add_gravity"));
  return add_body(s, -1, 1, g, NULL, NULL);
}

static TlStatus add_surface(TlSolid *s, const char *face_set, int pressure, TlVec3 t, double p,
                            TlAmplitude amp, void *ctx)
{
  TL_CHECK(not_after_setup(s, "add_traction/add_pressure"));
  const TlFaceSet *fs = NULL;
  TL_CHECK(tl_mesh_find_face_set(s->mesh, face_set, &fs));
  if (!tl_v3_isfinite(t) || !isfinite(p))
    TL_ERROR(TL_ERR_ARG, "solid: load on face set %s is not finite", face_set);
  TL_CHECK(tl_realloc(&s->surface, s->n_surface + 1, sizeof *s->surface));
  s->surface[s->n_surface++] =
      (SurfaceLoad){(int)(fs - s->mesh->face_sets), pressure, t, p, amp, ctx};
  return TL_OK;
}

TlStatus tl_solid_add_traction(TlSolid *s, const char *face_set, TlVec3 t, TlAmplitude amp, void *ctx)
{
  return add_surface(s, face_set, 0, t, 0.0, amp, ctx);
}

TlStatus tl_solid_add_pressure(TlSolid *s, const char *face_set, double p, TlAmplitude amp, void *ctx)
{
  return add_surface(s, face_set, 1, tl_v3(0, 0, 0), p, amp, ctx);
}

TlStatus tl_solid_add_point_force(TlSolid *s, size_t node, TlVec3 f, TlAmplitude amp, void *ctx)
{
  TL_CHECK(not_after_setup(s, "add_point_force"));
  if (node >= s->n_nodes)
    TL_ERROR(TL_ERR_ARG, "solid: point force on node %zu, the mesh has %zu nodes", node, s->n_nodes);
  if (!tl_v3_isfinite(f)) TL_ERROR(TL_ERR_ARG, "solid: point force on node %zu is not finite", node);
  TL_CHECK(tl_array_reserve(&s->points, &s->cap_points, s->n_points + 1, sizeof *s->points));
  s->points[s->n_points++] = (PointForce){node, f, amp, ctx};
  return TL_OK;
}

TlStatus tl_solid_fix(TlSolid *s, const char *node_set, int mask)
{
  TL_CHECK(not_after_setup(s, "fix"));
  const TlNodeSet *ns = NULL;
  TL_CHECK(tl_mesh_find_node_set(s->mesh, node_set, &ns));
  if (mask <= 0 || mask >= (1 << s->dim))
    TL_ERROR(TL_ERR_ARG, "solid: component mask %d for node set %s outside [1, %d]", mask, node_set,
             (1 << s->dim) - 1);
  for (size_t i = 0; i < ns->n; ++i)
    for (int c = 0; c < s->dim; ++c)
      if (mask & (1 << c)) {
        unsigned char *k = &s->constraint[ns->nodes[i] * s->dim + c];
        if (*k == 2)
          TL_ERROR(TL_ERR_ARG, "solid: node %zu component %d of set %s is both fixed and prescribed",
                   ns->nodes[i], c, node_set);
        *k = 1;
      }
  note_set(s, node_set);
  return TL_OK;
}

TlStatus tl_solid_prescribe(TlSolid *s, const char *node_set, int component, TlPrescribed fn, void *ctx)
{
  TL_CHECK(not_after_setup(s, "prescribe"));
  const TlNodeSet *ns = NULL;
  TL_CHECK(tl_mesh_find_node_set(s->mesh, node_set, &ns));
  if (component < 0 || component >= s->dim)
    TL_ERROR(TL_ERR_ARG, "solid: component %d for node set %s outside [0, %d]", component, node_set,
             s->dim - 1);
  if (!fn) TL_ERROR(TL_ERR_ARG, "solid: NULL prescribed function for node set %s", node_set);
  for (size_t i = 0; i < ns->n; ++i) {
    unsigned char *k = &s->constraint[ns->nodes[i] * s->dim + component];
    if (*k)
      TL_ERROR(TL_ERR_ARG, "solid: node %zu component %d of set %s is already constrained",
               ns->nodes[i], component, node_set);
    *k = 2;
    TL_CHECK(tl_array_reserve(&s->prescribed, &s->cap_prescribed, s->n_prescribed + 1,
                              sizeof *s->prescribed));
    s->prescribed[s->n_prescribed++] = (Prescribed){ns->nodes[i], component, fn, ctx};
  }
  note_set(s, node_set);
  return TL_OK;
}

TlStatus tl_solid_add_term(TlSolid *s, TlSolidTerm fn, void *ctx, int symmetric, size_t n_groups,
                           const size_t *group_ptr, const size_t *group_nodes)
{
  TL_CHECK(not_after_setup(s, "add_term"));
  if (!fn) TL_ERROR(TL_ERR_ARG, "solid: NULL force term");
  size_t total = n_groups ? group_ptr[n_groups] : 0;
  for (size_t i = 0; i < total; ++i)
    if (group_nodes[i] >= s->n_nodes)
      TL_ERROR(TL_ERR_ARG, "solid: force term group node %zu, the mesh has %zu nodes", group_nodes[i], s->n_nodes);
  TL_CHECK(tl_realloc(&s->terms, s->n_terms + 1, sizeof *s->terms));
  Term *t = &s->terms[s->n_terms];
  memset(t, 0, sizeof *t);
  t->fn = fn;
  t->ctx = ctx;
  t->symmetric = symmetric;
  t->n_groups = n_groups;
  s->n_terms++;
  if (n_groups) {
    TL_CHECK(tl_calloc(&t->group_ptr, n_groups + 1, sizeof(size_t)));
    TL_CHECK(tl_calloc(&t->group_nodes, total ? total : 1, sizeof(size_t)));
    memcpy(t->group_ptr, group_ptr, (n_groups + 1) * sizeof(size_t));
    memcpy(t->group_nodes, group_nodes, total * sizeof(size_t));
  }
  return TL_OK;
}

TlStatus tl_solid_matrix_add_nodes(const TlSolid *s, TlSparse *K, int n, const size_t *nodes, double scale,
                                   const double *Ke)
{
  TlSparseIndex dofs[3 * TL_ELEMENT_MAX_NODES * 4];
  int nd = n * s->dim;
  if (nd > (int)(sizeof dofs / sizeof dofs[0]))
    TL_ERROR(TL_ERR_ARG, "solid: matrix block of %d nodes exceeds %d", n, (int)(sizeof dofs / sizeof dofs[0]) / s->dim);
  for (int a = 0; a < n; ++a)
    for (int c = 0; c < s->dim; ++c) dofs[a * s->dim + c] = s->dof[nodes[a] * s->dim + c];
  TL_CHECK(tl_sparse_add_element(K, nd, dofs, scale, Ke));
  return TL_OK;
}

/* --------------------------------------------------------------- setup */

/* Greedy colouring of a block's elements so that no two elements of one
 * colour share a node: assembly of one colour is race-free. */
static TlStatus colour_block(const TlSolid *s, const TlElementBlock *blk, SolidBlock *B)
{
  uint64_t *used = NULL;
  int *colour = NULL;
  TlStatus st = TL_OK;
  TL_CHECK_GOTO(st, tl_calloc(&used, s->n_nodes, sizeof *used), done);
  TL_CHECK_GOTO(st, tl_calloc(&colour, blk->n_elements ? blk->n_elements : 1, sizeof *colour), done);
  int nn = blk->type->n_nodes, nc = 0;
  for (size_t e = 0; e < blk->n_elements; ++e) {
    uint64_t forbidden = 0;
    for (int a = 0; a < nn; ++a) forbidden |= used[blk->conn[e * nn + a]];
    int c = 0;
    while (c < 64 && (forbidden >> c & 1u)) ++c;
    if (c == 64) {
      st = tl_error_set(TL_ERR_UNSUPPORTED, __FILE__, __LINE__,
                        "block %s: element %zu needs more than 64 colours (too many elements per node)",
                        blk->name, e);
      goto done;
    }
    colour[e] = c;
    if (c + 1 > nc) nc = c + 1;
    for (int a = 0; a < nn; ++a) used[blk->conn[e * nn + a]] |= (uint64_t)1 << c;
  }
  B->n_colours = nc;
  TL_CHECK_GOTO(st, tl_calloc(&B->colour_ptr, nc + 1, sizeof(size_t)), done);
  TL_CHECK_GOTO(st, tl_calloc(&B->colour_elements, blk->n_elements ? blk->n_elements : 1, sizeof(size_t)), done);
  for (size_t e = 0; e < blk->n_elements; ++e) B->colour_ptr[colour[e] + 1]++;
  for (int c = 0; c < nc; ++c) B->colour_ptr[c + 1] += B->colour_ptr[c];
  {
    size_t fill[64] = {0};
    for (size_t e = 0; e < blk->n_elements; ++e)
      B->colour_elements[B->colour_ptr[colour[e]] + fill[colour[e]]++] = e;
  }
done:
  tl_free(&used);
  tl_free(&colour);
  return st;
}

/* ------------------------------------------------------------ weights */

static TlStatus check_weights(const TlSolid *s, int b, const char *where, size_t n, int per, const double *w)
{
  for (size_t k = 0; k < n; ++k)
    if (!(w[k] >= 0.0) || !isfinite(w[k]))
      TL_ERROR(TL_ERR_ARG, "solid: block %s weight %g at element %zu, %s point %d: weights must be finite and >= 0",
               s->mesh->blocks[b].name, w[k], k / (size_t)per, where, (int)(k % (size_t)per));
  return TL_OK;
}

static TlStatus weights_block(TlSolid *s, int b, const char *what)
{
  TL_CHECK(not_after_setup(s, what));
  if (b < 0 || b >= s->mesh->n_blocks) TL_ERROR(TL_ERR_ARG, "solid: block %d outside [0, %d)", b, s->mesh->n_blocks);
  SolidBlock *B = &s->blocks[b];
  tl_free(&B->pw);
  tl_free(&B->pw_mass);
  tl_free(&B->w_nodes);
  return TL_OK;
}

TlStatus tl_solid_weight_points(const TlSolid *s, int b, int *nq, int *nq_mass)
{
  if (b < 0 || b >= s->mesh->n_blocks) TL_ERROR(TL_ERR_ARG, "solid: block %d outside [0, %d)", b, s->mesh->n_blocks);
  const TlElementType *t = s->mesh->blocks[b].type;
  TlQuadrature q;
  TL_CHECK(tl_element_quadrature(t, t->order_stiffness, &q));
  if (nq) *nq = q.n;
  TL_CHECK(tl_element_quadrature(t, t->order_mass, &q));
  if (nq_mass) *nq_mass = q.n;
  return TL_OK;
}

TlStatus tl_solid_set_point_weights(TlSolid *s, int b, const double *w, const double *w_mass)
{
  TL_CHECK(weights_block(s, b, "set_point_weights"));
  if (!w && !w_mass) return TL_OK;
  if (!w || !w_mass)
    TL_ERROR(TL_ERR_ARG, "solid: block %s needs weights at both the stiffness and the mass points (or neither)",
             s->mesh->blocks[b].name);
  int nq, nqm;
  TL_CHECK(tl_solid_weight_points(s, b, &nq, &nqm));
  size_t ne = s->mesh->blocks[b].n_elements;
  TL_CHECK(check_weights(s, b, "stiffness", ne * nq, nq, w));
  TL_CHECK(check_weights(s, b, "mass", ne * nqm, nqm, w_mass));
  SolidBlock *B = &s->blocks[b];
  TL_CHECK(tl_calloc(&B->pw, ne ? ne * nq : 1, sizeof(double)));
  TL_CHECK(tl_calloc(&B->pw_mass, ne ? ne * nqm : 1, sizeof(double)));
  memcpy(B->pw, w, ne * nq * sizeof(double));
  memcpy(B->pw_mass, w_mass, ne * nqm * sizeof(double));
  return TL_OK;
}

TlStatus tl_solid_set_node_weights(TlSolid *s, int b, const double *w_nodes)
{
  TL_CHECK(weights_block(s, b, "set_node_weights"));
  if (!w_nodes) return TL_OK;
  for (size_t i = 0; i < s->n_nodes; ++i)
    if (!(w_nodes[i] >= 0.0) || !isfinite(w_nodes[i]))
      TL_ERROR(TL_ERR_ARG, "solid: block %s nodal weight %g at node %zu: weights must be finite and >= 0",
               s->mesh->blocks[b].name, w_nodes[i], i);
  SolidBlock *B = &s->blocks[b];
  TL_CHECK(tl_calloc(&B->w_nodes, s->n_nodes ? s->n_nodes : 1, sizeof(double)));
  memcpy(B->w_nodes, w_nodes, s->n_nodes * sizeof(double));
  return TL_OK;
}

/* The nodal weight field at the stiffness points (shape values Nq) and the
 * mass points (B->Nm), at setup. */
static TlStatus interpolate_weights(TlSolid *s, int b, const double *Nq)
{
  const TlElementBlock *blk = &s->mesh->blocks[b];
  SolidBlock *B = &s->blocks[b];
  int nn = B->nn, nq = B->q.n, nqm = B->qm.n;
  size_t ne = blk->n_elements ? blk->n_elements : 1;
  TL_CHECK(tl_calloc(&B->pw, ne * nq, sizeof(double)));
  TL_CHECK(tl_calloc(&B->pw_mass, ne * nqm, sizeof(double)));
  for (size_t e = 0; e < blk->n_elements; ++e)
    for (int pass = 0; pass < 2; ++pass) {
      int np = pass ? nqm : nq;
      const double *N = pass ? B->Nm : Nq;
      double *out = (pass ? B->pw_mass : B->pw) + e * np;
      for (int p = 0; p < np; ++p) {
        double v = 0.0;
        for (int a = 0; a < nn; ++a) v += N[p * nn + a] * B->w_nodes[blk->conn[e * nn + a]];
        /* shape functions that dip below zero (quadratic types) must not
         * make a weight of a non-negative field negative */
        out[p] = v > 0.0 ? v : 0.0;
      }
    }
  return TL_OK;
}

/* Reference geometry of one block: gradients dN/dxi and weights at the
 * stiffness points, weights at the mass points, lumped masses. */
static TlStatus setup_block_geometry(TlSolid *s, int b)
{
  const TlElementBlock *blk = &s->mesh->blocks[b];
  SolidBlock *B = &s->blocks[b];
  const TlElementType *t = blk->type;
  int dim = s->dim, nn = t->n_nodes;
  TL_CHECK(tl_element_quadrature(t, t->order_stiffness, &B->q));
  TL_CHECK(tl_element_quadrature(t, t->order_mass, &B->qm));
  B->nn = nn;
  B->nd = nn * dim;
  B->symmetric = tl_material_symmetric_tangent(B->material);
  B->nq = B->q.n;
  size_t ne = blk->n_elements ? blk->n_elements : 1;
  TL_CHECK(tl_calloc(&B->grad, ne * B->nq * nn * dim, sizeof(double)));
  if (dim == 3) TL_CHECK(tl_calloc(&B->grad_t, ne * B->nq * nn * 3, sizeof(double)));
  if (dim == 3) TL_CHECK(tl_calloc(&B->grad_n, ne * B->nq * nn * 3, sizeof(double)));
  TL_CHECK(tl_calloc(&B->wdet, ne * B->nq, sizeof(double)));
  TL_CHECK(tl_calloc(&B->Nm, (size_t)B->qm.n * nn, sizeof(double)));
  TL_CHECK(tl_calloc(&B->wdetm, ne * B->qm.n, sizeof(double)));
  TL_CHECK(tl_calloc(&B->lumped, ne * nn, sizeof(double)));
  double dNq[TL_QUADRATURE_MAX * TL_ELEMENT_MAX_NODES * 3];
  double dNm[TL_QUADRATURE_MAX * TL_ELEMENT_MAX_NODES * 3];
  double Nq[TL_QUADRATURE_MAX * TL_ELEMENT_MAX_NODES];
  t->eval(B->q.n, &B->q.xi[0][0], Nq, dNq);
  t->eval(B->qm.n, &B->qm.xi[0][0], B->Nm, dNm);
  double rho = B->material->density;
  if (B->w_nodes) TL_CHECK(interpolate_weights(s, b, Nq));
  if (B->pw) TL_CHECK(tl_calloc(&B->wdet_plain, ne * B->nq, sizeof(double)));
  for (size_t e = 0; e < blk->n_elements; ++e) {
    double x[TL_ELEMENT_MAX_NODES * 3];
    tl_mesh_element_coords(s->mesh, b, e, x);
    for (int pass = 0; pass < 2; ++pass) {
      const TlQuadrature *q = pass ? &B->qm : &B->q;
      const double *dN = pass ? dNm : dNq;
      for (int p = 0; p < q->n; ++p) {
        double J[3][3];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) J[i][j] = (i == j && i >= dim) ? 1.0 : 0.0;
        for (int a = 0; a < nn; ++a)
          for (int i = 0; i < dim; ++i)
            for (int j = 0; j < dim; ++j) J[i][j] += x[3 * a + i] * dN[(p * nn + a) * dim + j];
        TlMat3 Jm, Ji;
        memcpy(Jm.m, J, sizeof J);
        double det = tl_m3_det(Jm);
        if (!(det > 0.0) || !tl_m3_inverse(Jm, &Ji))
          TL_ERROR(TL_ERR_NUMERIC, "block %s element %zu: Jacobian determinant %g at Gauss point %d",
                   blk->name, e, det, p);
        if (pass) {
          B->wdetm[e * q->n + p] = q->w[p] * det * (B->pw_mass ? B->pw_mass[e * q->n + p] : 1.0);
          continue;
        }
        B->wdet[e * B->nq + p] = q->w[p] * det;
        if (B->pw) {
          B->wdet_plain[e * B->nq + p] = B->wdet[e * B->nq + p];
          B->wdet[e * B->nq + p] *= B->pw[e * B->nq + p];
        }
        double *g = B->grad + ((e * B->nq + p) * nn) * dim;
        for (int a = 0; a < nn; ++a)
          for (int d = 0; d < dim; ++d) {
            double v = 0.0;
            for (int j = 0; j < dim; ++j) v += dN[(p * nn + a) * dim + j] * Ji.m[j][d];
            g[a * dim + d] = v;
          }
      }
    }
    if (dim == 3)
      for (int p = 0; p < B->nq; ++p)
        for (int a = 0; a < nn; ++a)
          for (int j = 0; j < 3; ++j)
            B->grad_t[((e * nn + a) * 3 + j) * B->nq + p] = B->grad_n[((e * 3 + j) * B->nq + p) * nn + a] =
                B->grad[((e * B->nq + p) * nn + a) * 3 + j];
    /* HRZ lumping: diagonal of the consistent mass scaled to the element
     * mass; positive for every element type (row sums are not for
     * quadratic serendipity and simplex elements). */
    double diag[TL_ELEMENT_MAX_NODES] = {0}, total = 0.0, dsum = 0.0;
    for (int p = 0; p < B->qm.n; ++p) {
      double w = rho * B->wdetm[e * B->qm.n + p];
      total += w;
      for (int a = 0; a < nn; ++a) diag[a] += w * B->Nm[p * nn + a] * B->Nm[p * nn + a];
    }
    for (int a = 0; a < nn; ++a) dsum += diag[a];
    /* an element weighted out entirely has no mass */
    for (int a = 0; a < nn; ++a) B->lumped[e * nn + a] = dsum > 0.0 ? diag[a] * total / dsum : 0.0;
  }
  return TL_OK;
}

static TlStatus setup_dead_loads(TlSolid *s)
{
  int dim = s->dim;
  size_t n = s->n_nodes * dim;
  int count = s->n_body;
  for (int i = 0; i < s->n_surface; ++i) count += !s->surface[i].pressure;
  TL_CHECK(tl_calloc(&s->dead, count ? count : 1, sizeof *s->dead));
  for (int i = 0; i < s->n_body; ++i) {
    const BodyForce *bf = &s->body[i];
    DeadLoad *dl = &s->dead[s->n_dead++];
    dl->amp = bf->amp;
    dl->ctx = bf->ctx;
    TL_CHECK(tl_calloc(&dl->f, n, sizeof(double)));
    for (int b = 0; b < s->mesh->n_blocks; ++b) {
      if (bf->block >= 0 && bf->block != b) continue;
      const TlElementBlock *blk = &s->mesh->blocks[b];
      const SolidBlock *B = &s->blocks[b];
      double scale = bf->gravity ? B->material->density : 1.0;
      double bv[3] = {bf->b.x * scale, bf->b.y * scale, bf->b.z * scale};
      for (size_t e = 0; e < blk->n_elements; ++e)
        for (int p = 0; p < B->qm.n; ++p)
          for (int a = 0; a < B->nn; ++a) {
            double w = B->wdetm[e * B->qm.n + p] * B->Nm[p * B->nn + a];
            size_t node = blk->conn[e * B->nn + a];
            for (int c = 0; c < dim; ++c) dl->f[node * dim + c] += w * bv[c];
          }
    }
  }
  for (int i = 0; i < s->n_surface; ++i) {
    const SurfaceLoad *sl = &s->surface[i];
    if (sl->pressure) continue;
    DeadLoad *dl = &s->dead[s->n_dead++];
    dl->amp = sl->amp;
    dl->ctx = sl->ctx;
    TL_CHECK(tl_calloc(&dl->f, n, sizeof(double)));
    const TlFaceSet *fs = &s->mesh->face_sets[sl->face_set];
    double tv[3] = {sl->t.x, sl->t.y, sl->t.z};
    for (size_t k = 0; k < fs->n; ++k) {
      const TlElementType *ft = s->mesh->blocks[fs->faces[k].block].type->face_type;
      size_t fnodes[TL_ELEMENT_MAX_FACE_NODES];
      double fx[TL_ELEMENT_MAX_FACE_NODES * 3];
      tl_mesh_face_nodes(s->mesh, fs->faces[k], fnodes, fx);
      TlQuadrature q;
      TL_CHECK(tl_element_quadrature(ft, ft->order_mass, &q));
      for (int p = 0; p < q.n; ++p) {
        double N[TL_ELEMENT_MAX_FACE_NODES], nA[3];
        ft->eval(1, q.xi[p], N, NULL);
        tl_element_face_normal(ft, dim, fx, q.xi[p], nA);
        double dA = q.w[p] * sqrt(nA[0] * nA[0] + nA[1] * nA[1] + nA[2] * nA[2]);
        for (int a = 0; a < ft->n_nodes; ++a)
          for (int c = 0; c < dim; ++c) dl->f[fnodes[a] * dim + c] += dA * N[a] * tv[c];
      }
    }
  }
  return TL_OK;
}

TlStatus tl_solid_setup(TlSolid *s)
{
  if (s->ready) return TL_OK;
  const TlMesh *mesh = s->mesh;
  int dim = s->dim;
  int symmetric = 1;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    if (!s->blocks[b].material)
      TL_ERROR(TL_ERR_STATE, "solid: element block '%s' has no material", mesh->blocks[b].name);
    TlMaterial *m = s->blocks[b].material;
    if (!m->ready) TL_CHECK(tl_material_setup(m));
    symmetric &= tl_material_symmetric_tangent(m);
  }
  for (int i = 0; i < s->n_surface; ++i) symmetric &= !s->surface[i].pressure;
  for (int i = 0; i < s->n_terms; ++i) symmetric &= s->terms[i].symmetric;
  /* Without path-dependent state the system has no commit or rollback
   * (the contract's "elastic"): a stepper then need not evaluate the
   * accepted iterate to commit its trial state. */
  int stateful = 0;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlMaterial *m = s->blocks[b].material;
    stateful |= m->state_size > 0 || m->ops->commit || m->ops->rollback;
  }
  s->base.ops = stateful ? &solid_ops : &solid_ops_elastic;
  /* Dof numbering. */
  size_t nc = s->n_nodes * dim;
  TL_CHECK(tl_calloc(&s->dof, nc, sizeof *s->dof));
  TlSparseIndex ndof = 0, ndir = 0;
  for (size_t i = 0; i < nc; ++i) {
    s->dof[i] = s->constraint[i] == 1 ? -1 : ndof++;
    ndir += s->constraint[i] == 2;
  }
  if (ndof == 0) TL_ERROR(TL_ERR_ARG, "solid: every dof is clamped, nothing to solve");
  TL_CHECK(tl_calloc(&s->base.dirichlet_dofs, ndir ? ndir : 1, sizeof(TlSparseIndex)));
  for (size_t i = 0, k = 0; i < nc; ++i)
    if (s->constraint[i] == 2) s->base.dirichlet_dofs[k++] = s->dof[i];
  s->base.ndof = ndof;
  s->base.n_dirichlet = ndir;
  s->base.symmetric = symmetric;
  s->base.damped = 0;
  /* Geometry, state, colours, element dof lists. */
  s->n_elements = 0;
  s->max_nd = 0;
  s->max_nq = 0;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    TL_CHECK(setup_block_geometry(s, b));
    TL_CHECK(colour_block(s, &mesh->blocks[b], B));
    B->offset = s->n_elements;
    s->n_elements += mesh->blocks[b].n_elements;
    if (B->nd > s->max_nd) s->max_nd = B->nd;
    if (B->nq > s->max_nq) s->max_nq = B->nq;
    size_t ss = B->material->state_size, nst = mesh->blocks[b].n_elements * B->nq;
    if (ss) {
      TL_CHECK(tl_calloc(&B->state_old, nst * ss, sizeof(double)));
      TL_CHECK(tl_calloc(&B->state_new, nst * ss, sizeof(double)));
      if (B->material->ops->init_state) TL_CHECK(B->material->ops->init_state(B->material, nst, B->state_old));
      memcpy(B->state_new, B->state_old, nst * ss * sizeof(double));
    }
  }
  size_t n_groups = 0, total = 0;
  for (int i = 0; i < s->n_terms; ++i) {
    n_groups += s->terms[i].n_groups;
    if (s->terms[i].n_groups) total += s->terms[i].group_ptr[s->terms[i].n_groups] * dim;
  }
  s->n_pattern = s->n_elements + n_groups;
  TL_CHECK(tl_calloc(&s->elem_ptr, s->n_pattern + 1, sizeof(TlSparseIndex)));
  for (int b = 0; b < mesh->n_blocks; ++b) total += mesh->blocks[b].n_elements * s->blocks[b].nd;
  TL_CHECK(tl_calloc(&s->elem_dofs, total ? total : 1, sizeof(TlSparseIndex)));
  size_t k = 0, g = 0;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    for (size_t e = 0; e < blk->n_elements; ++e, ++g) {
      s->elem_ptr[g] = (TlSparseIndex)k;
      for (int a = 0; a < blk->type->n_nodes; ++a)
        for (int c = 0; c < dim; ++c) s->elem_dofs[k++] = s->dof[blk->conn[e * blk->type->n_nodes + a] * dim + c];
    }
  }
  /* Node groups of the force terms: extra entries of the pattern. */
  for (int i = 0; i < s->n_terms; ++i)
    for (size_t q = 0; q < s->terms[i].n_groups; ++q, ++g) {
      s->elem_ptr[g] = (TlSparseIndex)k;
      for (size_t j = s->terms[i].group_ptr[q]; j < s->terms[i].group_ptr[q + 1]; ++j)
        for (int c = 0; c < dim; ++c) s->elem_dofs[k++] = s->dof[s->terms[i].group_nodes[j] * dim + c];
    }
  s->elem_ptr[g] = (TlSparseIndex)k;
  /* Lumped masses. */
  TL_CHECK(tl_calloc(&s->lumped_nodes, nc, sizeof(double)));
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    const SolidBlock *B = &s->blocks[b];
    for (size_t e = 0; e < blk->n_elements; ++e)
      for (int a = 0; a < B->nn; ++a)
        for (int c = 0; c < dim; ++c) s->lumped_nodes[blk->conn[e * B->nn + a] * dim + c] += B->lumped[e * B->nn + a];
  }
  for (size_t i = 0; i < nc; ++i)
    if (!(s->lumped_nodes[i] > 0.0))
      TL_ERROR(TL_ERR_ARG, "solid: node %zu has zero mass: it belongs to no element, or the weights of every "
               "element around it vanish", i / dim);
  TL_CHECK(setup_dead_loads(s));
  TL_CHECK(tl_calloc(&s->un, nc, sizeof(double)));
  TL_CHECK(tl_calloc(&s->fn, nc, sizeof(double)));
  TL_CHECK(tl_calloc(&s->gn, nc, sizeof(double)));
  /* Per-thread scratch. */
  s->n_threads = omp_get_max_threads();
  TL_CHECK(tl_calloc(&s->scratch, s->n_threads, sizeof *s->scratch));
  size_t maxss = 0;
  for (int b = 0; b < mesh->n_blocks; ++b)
    if (s->blocks[b].material->state_size > maxss) maxss = s->blocks[b].material->state_size;
  size_t npts = (size_t)CHUNK * s->max_nq, nd = s->max_nd;
  for (int t = 0; t < s->n_threads; ++t) {
    Scratch *w = &s->scratch[t];
    TL_CHECK(tl_calloc(&w->F, npts, sizeof(TlMat3)));
    TL_CHECK(tl_calloc(&w->S, npts, sizeof(TlMat3)));
    TL_CHECK(tl_calloc(&w->Hsoa, 9 * npts, sizeof(double)));
    TL_CHECK(tl_calloc(&w->Ssoa, 6 * npts, sizeof(double)));
    TL_CHECK(tl_calloc(&w->D, 36 * npts, sizeof(double)));
    TL_CHECK(tl_calloc(&w->W, npts, sizeof(double)));
    TL_CHECK(tl_calloc(&w->state_old, npts * (maxss ? maxss : 1), sizeof(double)));
    TL_CHECK(tl_calloc(&w->state_new, npts * (maxss ? maxss : 1), sizeof(double)));
    TL_CHECK(tl_calloc(&w->fe, nd, sizeof(double)));
    TL_CHECK(tl_calloc(&w->Ke, nd * nd, sizeof(double)));
    TL_CHECK(tl_calloc(&w->B, 6 * nd, sizeof(double)));
    TL_CHECK(tl_calloc(&w->DB, 6 * nd, sizeof(double)));
    TL_CHECK(tl_calloc(&w->ue, nd, sizeof(double)));
    TL_CHECK(tl_calloc(&w->dofs, nd, sizeof(TlSparseIndex)));
  }
  s->ready = 1;
  return TL_OK;
}

/* ----------------------------------------------------- element kernel */

/* Displacement gradients H = F - 1 at every stiffness point of element e
 * from its displacements ue.  The 3-D body is inlined with the node count
 * as a constant for the common element types (the loops then unroll: two
 * to three times faster than with a run-time count). */
static inline __attribute__((always_inline)) void gradients_3d(const double *restrict g, int nq, int nn,
                                                               const double *restrict ue, TlMat3 *restrict F)
{
  for (int p = 0; p < nq; ++p, g += 3 * nn) {
    double f[3][3] = {{0}};
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) f[i][j] += ue[3 * a + i] * g[3 * a + j];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F[p].m[i][j] = f[i][j];
  }
}

static void deformation_gradients(const SolidBlock *B, int dim, size_t e, const double *ue, TlMat3 *F)
{
  const double *g0 = B->grad + e * (size_t)B->nq * (size_t)B->nn * (size_t)dim;
  if (dim == 3) {
    switch (B->nn) {
    case 8: gradients_3d(g0, B->nq, 8, ue, F); return;
    case 27: gradients_3d(g0, B->nq, 27, ue, F); return;
    case 4: gradients_3d(g0, B->nq, 4, ue, F); return;
    case 10: gradients_3d(g0, B->nq, 10, ue, F); return;
    default: gradients_3d(g0, B->nq, B->nn, ue, F); return;
    }
  }
  for (int p = 0; p < B->nq; ++p) {
    const double *g = g0 + (size_t)p * B->nn * dim;
    TlMat3 f = tl_m3_zero();
    for (int a = 0; a < B->nn; ++a)
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) f.m[i][j] += ue[a * dim + i] * g[a * dim + j];
    F[p] = f;
  }
}

/* Residual alone in 3-D, R_ai = sum_p w_p (F S)_ij dN_a/dX_j, with the node
 * count a constant as above. */
static inline __attribute__((always_inline)) void residual_3d(const double *restrict g, const double *restrict wdet,
                                                              int nq, int nn, const TlMat3 *restrict H,
                                                              const TlMat3 *restrict S, double *restrict fe)
{
  for (int k = 0; k < 3 * nn; ++k) fe[k] = 0.0;
  for (int p = 0; p < nq; ++p, g += 3 * nn) {
    double FS[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double v = S[p].m[i][j];
        for (int k = 0; k < 3; ++k) v += H[p].m[i][k] * S[p].m[k][j];
        FS[i][j] = wdet[p] * v;
      }
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < 3; ++i)
        fe[3 * a + i] += FS[i][0] * g[3 * a] + FS[i][1] * g[3 * a + 1] + FS[i][2] * g[3 * a + 2];
  }
}

static int residual_fixed(const SolidBlock *B, size_t e, const TlMat3 *H, const TlMat3 *S, double *fe)
{
  const double *g = B->grad + e * (size_t)B->nq * (size_t)B->nn * 3;
  const double *w = B->wdet + e * (size_t)B->nq;
  switch (B->nn) {
  case 8: residual_3d(g, w, B->nq, 8, H, S, fe); return 1;
  case 27: residual_3d(g, w, B->nq, 27, H, S, fe); return 1;
  case 4: residual_3d(g, w, B->nq, 4, H, S, fe); return 1;
  case 10: residual_3d(g, w, B->nq, 10, H, S, fe); return 1;
  default: return 0;
  }
}

/* Element residual fe and tangent Ke (either may be NULL) from the
 * displacement gradients H (F = 1 + H), S and D at its stiffness points. */
static void element_forces(const SolidBlock *B, int dim, size_t e, const TlMat3 *F, const TlMat3 *S,
                           const double *D, double *fe, double *Ke, double *Bm, double *DB)
{
  /* With a symmetric material tangent only the upper triangle of B^T D B is
   * formed, then mirrored. */
  int sym = B->symmetric;
  int nn = B->nn, nd = B->nd;
  if (fe && !Ke && dim == 3 && residual_fixed(B, e, F, S, fe)) return;
  if (fe) memset(fe, 0, nd * sizeof(double));
  if (Ke) memset(Ke, 0, (size_t)nd * nd * sizeof(double));
  static const int vi[6] = {0, 1, 2, 0, 1, 0}, vj[6] = {0, 1, 2, 1, 2, 2};
  for (int p = 0; p < B->nq; ++p) {
    const double *g = B->grad + ((e * B->nq + p) * nn) * dim;
    double w = B->wdet[e * B->nq + p];
    TlMat3 Fp = F[p];
    for (int i = 0; i < 3; ++i) Fp.m[i][i] += 1.0;
    const TlMat3 *f = &Fp, *s = &S[p];
    if (fe) {
      /* R_ai = F_ik S_kj dN_a/dxi_j */
      double FS[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double v = 0.0;
          for (int k = 0; k < 3; ++k) v += f->m[i][k] * s->m[k][j];
          FS[i][j] = v;
        }
      for (int a = 0; a < nn; ++a)
        for (int i = 0; i < dim; ++i) {
          double v = 0.0;
          for (int j = 0; j < dim; ++j) v += FS[i][j] * g[a * dim + j];
          fe[a * dim + i] += w * v;
        }
    }
    if (!Ke) continue;
    /* B: engineering strain variation of dof (a, i):
     * dE_rs = (F_ir dN_a/dxi_s + F_is dN_a/dxi_r)/2, shear doubled. */
    for (int a = 0; a < nn; ++a) {
      double ga[3] = {0, 0, 0};
      for (int d = 0; d < dim; ++d) ga[d] = g[a * dim + d];
      for (int i = 0; i < dim; ++i) {
        int col = a * dim + i;
        for (int I = 0; I < 6; ++I) {
          int r = vi[I], c = vj[I];
          Bm[I * nd + col] = r == c ? f->m[i][r] * ga[r] : f->m[i][r] * ga[c] + f->m[i][c] * ga[r];
        }
      }
    }
    const double *Dp = D + 36 * p;
    for (int I = 0; I < 6; ++I)
      for (int col = 0; col < nd; ++col) {
        double v = 0.0;
        for (int J = 0; J < 6; ++J) v += Dp[6 * I + J] * Bm[J * nd + col];
        DB[I * nd + col] = v;
      }
    /* Ke += w B^T (D B), rows outer and the contiguous column loop inner
     * so the compiler vectorises it. */
    for (int I = 0; I < 6; ++I)
      for (int r = 0; r < nd; ++r) {
        double b = w * Bm[I * nd + r];
        if (b == 0.0) continue;
        const double *db = DB + I * nd;
        double *krow = Ke + r * nd;
        for (int c = sym ? r : 0; c < nd; ++c) krow[c] += b * db[c];
      }
    /* Geometric stiffness: (dN_a . S dN_b) delta_ik. */
    for (int a = 0; a < nn; ++a)
      for (int b = 0; b < nn; ++b) {
        double v = 0.0;
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) v += g[a * dim + i] * s->m[i][j] * g[b * dim + j];
        v *= w;
        for (int i = 0; i < dim; ++i) Ke[(a * dim + i) * nd + b * dim + i] += v;
      }
  }
  if (Ke && sym)
    for (int r = 0; r < nd; ++r)
      for (int c = 0; c < r; ++c) Ke[r * nd + c] = Ke[c * nd + r];
}

/* ------------------------------------------------- residual-only path
 *
 * The residual of a 3-D block whose law keeps no state is the hot path of
 * implicit dynamics (every Newton iteration): chunks of elements run
 * gradients -> stress (one material call per chunk) -> nodal forces, with
 * the loops over an element's points innermost on contiguous data
 * (grad_t), where the compiler unrolls and vectorises them.  Elements are
 * taken in colour order, so the forces accumulate in the same order
 * whether the chunks of a colour run on one thread or several. */

/* The chunk's points are stored component-major (point p of element k at
 * k nq + p, stride ld = the chunk's points): H_ij in 9 arrays, S in 6
 * (Voigt order), so that every loop over points runs on contiguous data. */
static const int voigt[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};

/* H_p = sum_a ue_a (x) dN_a/dX at the nq points of one element. */
static inline __attribute__((always_inline)) void gradients_t(const double *restrict gt, int nq, int nn,
                                                              const double *restrict ue, double *restrict H,
                                                              size_t ld)
{
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double acc[TL_QUADRATURE_MAX];
      for (int p = 0; p < nq; ++p) acc[p] = 0.0;
      for (int a = 0; a < nn; ++a) {
        const double u = ue[3 * a + i], *g = gt + (3 * a + j) * nq;
        for (int p = 0; p < nq; ++p) acc[p] += u * g[p];
      }
      for (int p = 0; p < nq; ++p) H[(3 * i + j) * ld + p] = acc[p];
    }
}

/* R_ai = sum_p w_p ((1 + H_p) S_p)_ij dN_a/dX_j of one element; the sums
 * run over (p, j) with the element's nodes in the vector lanes (gn is
 * node-innermost). */
static inline __attribute__((always_inline)) void residual_t(const double *restrict gn, const double *restrict wdet,
                                                             int nq, int nn, const double *restrict H,
                                                             const double *restrict S, size_t ld,
                                                             double *restrict fe)
{
  double P[9][TL_QUADRATURE_MAX]; /* w (1 + H) S */
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double *h0 = H + (3 * i) * ld, *h1 = h0 + ld, *h2 = h1 + ld, *sij = S + voigt[i][j] * ld,
                   *s0j = S + voigt[0][j] * ld, *s1j = S + voigt[1][j] * ld, *s2j = S + voigt[2][j] * ld;
      for (int p = 0; p < nq; ++p)
        P[3 * i + j][p] = wdet[p] * (sij[p] + h0[p] * s0j[p] + h1[p] * s1j[p] + h2[p] * s2j[p]);
    }
  double f0[TL_ELEMENT_MAX_NODES], f1[TL_ELEMENT_MAX_NODES], f2[TL_ELEMENT_MAX_NODES];
  for (int a = 0; a < nn; ++a) f0[a] = f1[a] = f2[a] = 0.0;
  for (int p = 0; p < nq; ++p)
    for (int j = 0; j < 3; ++j) {
      const double *g = gn + ((size_t)j * nq + p) * nn;
      const double p0 = P[j][p], p1 = P[3 + j][p], p2 = P[6 + j][p];
      for (int a = 0; a < nn; ++a) {
        f0[a] += p0 * g[a];
        f1[a] += p1 * g[a];
        f2[a] += p2 * g[a];
      }
    }
  for (int a = 0; a < nn; ++a) fe[3 * a] = f0[a], fe[3 * a + 1] = f1[a], fe[3 * a + 2] = f2[a];
}

/* Gradients of the nk elements, then nodal forces; the common element
 * types get copies with their sizes known to the compiler. */
static inline __attribute__((always_inline)) void chunk_gradients(const SolidBlock *B, const TlElementBlock *blk,
                                                                  const size_t *elements, size_t nk, int nq, int nn,
                                                                  const double *u_nodes, double *ue, double *H,
                                                                  size_t ld)
{
  for (size_t k = 0; k < nk; ++k) {
    const size_t *conn = blk->conn + elements[k] * nn;
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < 3; ++i) ue[3 * a + i] = u_nodes[conn[a] * 3 + i];
    gradients_t(B->grad_t + elements[k] * (size_t)nn * 3 * (size_t)nq, nq, nn, ue, H + k * nq, ld);
  }
}

static inline __attribute__((always_inline)) void chunk_forces(const SolidBlock *B, const TlElementBlock *blk,
                                                               const size_t *elements, size_t nk, int nq, int nn,
                                                               const double *H, const double *S, size_t ld,
                                                               double *fe, double *f_nodes)
{
  for (size_t k = 0; k < nk; ++k) {
    const size_t e = elements[k];
    residual_t(B->grad_n + e * (size_t)nn * 3 * (size_t)nq, B->wdet + e * (size_t)nq, nq, nn, H + k * nq,
               S + k * nq, ld, fe);
    const size_t *conn = blk->conn + e * nn;
    for (int a = 0; a < nn; ++a)
      for (int i = 0; i < 3; ++i) f_nodes[conn[a] * 3 + i] += fe[3 * a + i];
  }
}

TL_VECTOR_CLONES
static void kernel_gradients(const SolidBlock *B, const TlElementBlock *blk, const size_t *elements, size_t nk,
                             const double *u_nodes, double *ue, double *H, size_t ld)
{
  if (B->nn == 8 && B->nq == 8) chunk_gradients(B, blk, elements, nk, 8, 8, u_nodes, ue, H, ld);
  else if (B->nn == 27 && B->nq == 27) chunk_gradients(B, blk, elements, nk, 27, 27, u_nodes, ue, H, ld);
  else if (B->nn == 10 && B->nq == 4) chunk_gradients(B, blk, elements, nk, 4, 10, u_nodes, ue, H, ld);
  else if (B->nn == 4 && B->nq == 1) chunk_gradients(B, blk, elements, nk, 1, 4, u_nodes, ue, H, ld);
  else chunk_gradients(B, blk, elements, nk, B->nq, B->nn, u_nodes, ue, H, ld);
}

TL_VECTOR_CLONES
static void kernel_forces(const SolidBlock *B, const TlElementBlock *blk, const size_t *elements, size_t nk,
                          const double *H, const double *S, size_t ld, double *fe, double *f_nodes)
{
  if (B->nn == 8 && B->nq == 8) chunk_forces(B, blk, elements, nk, 8, 8, H, S, ld, fe, f_nodes);
  else if (B->nn == 27 && B->nq == 27) chunk_forces(B, blk, elements, nk, 27, 27, H, S, ld, fe, f_nodes);
  else if (B->nn == 10 && B->nq == 4) chunk_forces(B, blk, elements, nk, 4, 10, H, S, ld, fe, f_nodes);
  else if (B->nn == 4 && B->nq == 1) chunk_forces(B, blk, elements, nk, 1, 4, H, S, ld, fe, f_nodes);
  else chunk_forces(B, blk, elements, nk, B->nq, B->nn, H, S, ld, fe, f_nodes);
}

/* Flags points with det(1 + H) <= 0 (or NaN). */
TL_VECTOR_CLONES
static int any_inverted(const double *restrict H, size_t np, size_t ld)
{
  int bad = 0;
  for (size_t p = 0; p < np; ++p) {
    const double h00 = H[p], h01 = H[ld + p], h02 = H[2 * ld + p], h10 = H[3 * ld + p], h12 = H[5 * ld + p],
                 h20 = H[6 * ld + p], h21 = H[7 * ld + p];
    const double a00 = 1.0 + h00, a11 = 1.0 + H[4 * ld + p], a22 = 1.0 + H[8 * ld + p];
    const double J = a00 * (a11 * a22 - h12 * h21) - h01 * (h10 * a22 - h12 * h20) + h02 * (h10 * h21 - a11 * h20);
    bad |= !(J > 0.0);
  }
  return bad;
}

/* Residual of the nk elements `elements` (disjoint nodes unless run
 * serially) added into f_nodes. */
static TlStatus residual_chunk(const TlSolid *s, int b, const size_t *elements, size_t nk, const double *u_nodes,
                               double *f_nodes, Scratch *w)
{
  const TlElementBlock *blk = &s->mesh->blocks[b];
  const SolidBlock *B = &s->blocks[b];
  const int nq = B->nq;
  const size_t np = nk * (size_t)nq, ld = np;
  double *H = w->Hsoa, *S = w->Ssoa;
  kernel_gradients(B, blk, elements, nk, u_nodes, w->ue, H, ld);
  if (any_inverted(H, np, ld))
    for (size_t p = 0; p < np; ++p) {
      TlMat3 Fq;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) Fq.m[i][j] = (i == j ? 1.0 : 0.0) + H[(3 * i + j) * ld + p];
      double J = tl_m3_det(Fq);
      if (!(J > 0.0)) {
        size_t e = elements[p / (size_t)nq];
        TL_ERROR(TL_ERR_NUMERIC,
                 "block %s element %zu (tag %ld): det F = %g at Gauss point %d; the element is inverted "
                 "(displacements too large or unstable run)",
                 blk->name, e, blk->tags ? blk->tags[e] : (long)e, J, (int)(p % (size_t)nq));
      }
    }
  TlStatus st = tl_material_stress_soa(B->material, np, H, S, ld);
  if (st != TL_OK) {
    tl_error_trace(st, __FILE__, __LINE__);
    char msg[900];
    snprintf(msg, sizeof msg, "%s", tl_error_message());
    TL_ERROR(st, "block %s, elements from %zu (chunk of %zu, %d points each): %s", blk->name, elements[0], nk, nq,
             msg);
  }
  kernel_forces(B, blk, elements, nk, H, S, ld, w->fe, f_nodes);
  return TL_OK;
}

static TlStatus block_residual(TlSolid *s, int b, const double *u_nodes, double *f_nodes)
{
  const SolidBlock *B = &s->blocks[b];
  int parallel = 0;
  for (int c = 0; c < B->n_colours && s->n_threads > 1; ++c)
    parallel |= B->colour_ptr[c + 1] - B->colour_ptr[c] >= 4 * (size_t)CHUNK;
  if (!parallel) {
    /* One thread: chunks may span colours (same accumulation order). */
    size_t total = B->colour_ptr[B->n_colours];
    for (size_t c0 = 0; c0 < total; c0 += CHUNK)
      TL_CHECK(residual_chunk(s, b, B->colour_elements + c0, total - c0 < CHUNK ? total - c0 : CHUNK, u_nodes,
                              f_nodes, &s->scratch[0]));
    return TL_OK;
  }
  ParallelError pe = {TL_OK, ""};
  for (int colour = 0; colour < B->n_colours; ++colour) {
    size_t first = B->colour_ptr[colour], count = B->colour_ptr[colour + 1] - first;
    long n_chunks = (long)((count + CHUNK - 1) / CHUNK);
#pragma omp parallel for schedule(dynamic) if (n_chunks >= 4) num_threads(s->n_threads)
    for (long ch = 0; ch < n_chunks; ++ch) {
      TlStatus seen;
#pragma omp critical(tl_solid_error)
      seen = pe.status;
      if (seen != TL_OK) continue;
      size_t c0 = first + (size_t)ch * CHUNK, nk = count - (size_t)ch * CHUNK < CHUNK ? count - (size_t)ch * CHUNK : CHUNK;
      TlStatus st = residual_chunk(s, b, B->colour_elements + c0, nk, u_nodes, f_nodes, &s->scratch[omp_get_thread_num()]);
      if (st != TL_OK) parallel_error_record(&pe, st);
    }
    TL_CHECK(parallel_error_raise(&pe));
  }
  return TL_OK;
}

TlStatus tl_solid_block_forces(TlSolid *s, int b, const double *u_nodes, double *f_nodes, double c_u,
                               TlSparse *K, double *W)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: block forces before tl_solid_setup");
  if (f_nodes && !K && !W && s->dim == 3 && s->blocks[b].material->state_size == 0)
    return block_residual(s, b, u_nodes, f_nodes);
  const TlElementBlock *blk = &s->mesh->blocks[b];
  SolidBlock *B = &s->blocks[b];
  int dim = s->dim, nn = B->nn, nd = B->nd, nq = B->nq;
  const TlMaterial *mat = B->material;
  size_t ss = mat->state_size;
  int indexed = K && K->elem_pos_ptr && K->n_elements == (TlSparseIndex)s->n_pattern;
  ParallelError pe = {TL_OK, ""};
  double energy = 0.0;
  for (int colour = 0; colour < B->n_colours; ++colour) {
    size_t first = B->colour_ptr[colour], count = B->colour_ptr[colour + 1] - first;
    long n_chunks = (long)((count + CHUNK - 1) / CHUNK);
/* Threads only where a colour holds several chunks: below that the
     * fork and barrier cost more than the work.  Never more threads than
     * the scratch areas sized at setup (the thread count may have been
     * raised since). */
#pragma omp parallel for schedule(dynamic) reduction(+ : energy) if (n_chunks >= 4) num_threads(s->n_threads)
    for (long ch = 0; ch < n_chunks; ++ch) {
      TlStatus seen;
#pragma omp critical(tl_solid_error)
      seen = pe.status;
      if (seen != TL_OK) continue;
      Scratch *w = &s->scratch[omp_get_thread_num()];
      size_t c0 = first + (size_t)ch * CHUNK;
      size_t nk = count - (size_t)ch * CHUNK < CHUNK ? count - (size_t)ch * CHUNK : CHUNK;
      for (size_t k = 0; k < nk; ++k) {
        size_t e = B->colour_elements[c0 + k];
        for (int a = 0; a < nn; ++a)
          for (int i = 0; i < dim; ++i) w->ue[a * dim + i] = u_nodes[blk->conn[e * nn + a] * dim + i];
        deformation_gradients(B, dim, e, w->ue, w->F + k * nq);
        for (int q = 0, bad = 0; q < nq && !bad; ++q) {
          TlMat3 Fq = w->F[k * nq + q];
          for (int i = 0; i < 3; ++i) Fq.m[i][i] += 1.0;
          double J = tl_m3_det(Fq);
          if (!(J > 0.0)) {
            TlStatus se = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__,
                                       "block %s element %zu (tag %ld): det F = %g at Gauss point %d; the "
                                       "element is inverted (displacements too large or unstable run)",
                                       blk->name, e, blk->tags ? blk->tags[e] : (long)e, J, q);
            parallel_error_record(&pe, se);
            bad = 1;
          }
        }
        if (ss) memcpy(w->state_old + k * nq * ss, B->state_old + e * nq * ss, nq * ss * sizeof(double));
      }
#pragma omp critical(tl_solid_error)
      seen = pe.status;
      if (seen != TL_OK) continue;
      TlStatus st = tl_material_evaluate_gradient(mat, nk * nq, w->F, ss ? w->state_old : NULL,
                                         ss ? w->state_new : NULL, w->S, K ? w->D : NULL,
                                         W ? w->W : NULL);
      if (st != TL_OK) {
        size_t e = B->colour_elements[c0];
        tl_error_trace(st, __FILE__, __LINE__);
        char msg[900];
        snprintf(msg, sizeof msg, "%s", tl_error_message());
        tl_error_set(st, __FILE__, __LINE__, "block %s, elements from %zu (chunk of %zu, %d points each): %s",
                     blk->name, e, nk, nq, msg);
        parallel_error_record(&pe, st);
        continue;
      }
      for (size_t k = 0; k < nk; ++k) {
        size_t e = B->colour_elements[c0 + k];
        if (ss) memcpy(B->state_new + e * nq * ss, w->state_new + k * nq * ss, nq * ss * sizeof(double));
        if (W)
          for (int p = 0; p < nq; ++p) energy += B->wdet[e * nq + p] * w->W[k * nq + p];
        if (!f_nodes && !K) continue;
        element_forces(B, dim, e, w->F + k * nq, w->S + k * nq, K ? w->D + 36 * k * nq : NULL,
                       f_nodes ? w->fe : NULL, K ? w->Ke : NULL, w->B, w->DB);
        if (f_nodes)
          for (int a = 0; a < nn; ++a)
            for (int i = 0; i < dim; ++i) f_nodes[blk->conn[e * nn + a] * dim + i] += w->fe[a * dim + i];
        if (K) {
          size_t g = B->offset + e;
          TlStatus sk = indexed ? tl_sparse_add_element_indexed(K, (TlSparseIndex)g, c_u, w->Ke)
                                : tl_sparse_add_element(K, nd, s->elem_dofs + s->elem_ptr[g], c_u, w->Ke);
          if (sk != TL_OK) parallel_error_record(&pe, sk);
        }
      }
    }
  }
  TL_CHECK(parallel_error_raise(&pe));
  if (W) *W += energy;
  return TL_OK;
}

/* ------------------------------------------------------- system ops */

void tl_solid_dofs_to_nodes(const TlSolid *s, const double *u, double *u_nodes)
{
  size_t nc = s->n_nodes * s->dim;
  for (size_t i = 0; i < nc; ++i) u_nodes[i] = s->dof[i] >= 0 ? u[s->dof[i]] : 0.0;
}

void tl_solid_nodes_to_dofs(const TlSolid *s, const double *f_nodes, double *f)
{
  size_t nc = s->n_nodes * s->dim;
  for (size_t i = 0; i < nc; ++i)
    if (s->dof[i] >= 0) f[s->dof[i]] = f_nodes[i];
}

TlSparseIndex tl_solid_dof(const TlSolid *s, size_t node, int component)
{
  if (!s->ready || node >= s->n_nodes || component < 0 || component >= s->dim) return -1;
  return s->dof[node * s->dim + component];
}

double tl_solid_total_mass(const TlSolid *s)
{
  double m = 0.0;
  for (size_t i = 0; i < s->n_nodes; ++i) m += s->lumped_nodes[i * s->dim];
  return m;
}

/* The block's own kernel, the innermost of any wrappers. */
static TlStatus own_block(void *ctx, TlSolid *s, int b, double t, const double *u_nodes, double *f_nodes,
                          double c_u, TlSparse *K, double *W)
{
  (void)ctx, (void)t;
  return tl_solid_block_forces(s, b, u_nodes, f_nodes, c_u, K, W);
}

TlStatus tl_solid_wrap_block(TlSolid *s, int b, TlSolidBlockKernel kernel, TlSolidBlockKernel *wrapped)
{
  if (b < 0 || b >= s->mesh->n_blocks) TL_ERROR(TL_ERR_ARG, "solid: block %d outside [0, %d)", b, s->mesh->n_blocks);
  if (!kernel.fn) TL_ERROR(TL_ERR_ARG, "solid: block %d wrapped by a kernel without a function", b);
  if (wrapped) *wrapped = tl_solid_block_kernel(s, b);
  s->blocks[b].kernel = kernel;
  return TL_OK;
}

TlStatus tl_solid_adopt(TlSolid *s, void *memory)
{
  TL_CHECK(tl_realloc(&s->adopted, s->n_adopted + 1, sizeof *s->adopted));
  s->adopted[s->n_adopted++] = memory;
  return TL_OK;
}

TlSolidBlockKernel tl_solid_block_kernel(const TlSolid *s, int b)
{
  TlSolidBlockKernel k = s->blocks[b].kernel;
  if (!k.fn) k.fn = own_block, k.ctx = NULL;
  return k;
}

static TlStatus block_kernel(TlSolid *s, int b, double t, const double *u_nodes, double *f_nodes, double c_u,
                             TlSparse *K, double *W)
{
  const TlSolidBlockKernel *k = &s->blocks[b].kernel;
  if (!k->fn) return tl_solid_block_forces(s, b, u_nodes, f_nodes, c_u, K, W);
  return k->fn(k->ctx, s, b, t, u_nodes, f_nodes, c_u, K, W);
}

static TlStatus internal_nodes(TlSolid *s, double t, const double *u, double *f_nodes, double c_u, TlSparse *K)
{
  tl_solid_dofs_to_nodes(s, u, s->un);
  if (f_nodes) memset(f_nodes, 0, s->n_nodes * s->dim * sizeof(double));
  for (int b = 0; b < s->mesh->n_blocks; ++b) TL_CHECK(block_kernel(s, b, t, s->un, f_nodes, c_u, K, NULL));
  for (int i = 0; i < s->n_terms; ++i)
    TL_CHECK(s->terms[i].fn(s->terms[i].ctx, s, t, s->un, f_nodes, c_u, K));
  return TL_OK;
}

static TlStatus op_create_matrix(TlMechSystem *sys, int upper, TlSparse **K)
{
  TlSolid *s = (TlSolid *)sys;
  if (upper && !sys->symmetric)
    TL_ERROR(TL_ERR_ARG, "solid: upper-triangle storage asked for a non-symmetric system");
  TL_CHECK(tl_sparse_create_from_elements(sys->ndof, upper, (TlSparseIndex)s->n_pattern,
                                          s->elem_ptr, s->elem_dofs, 1, K));
  return TL_OK;
}

static TlStatus op_internal_force(TlMechSystem *sys, double t, const double *u, const double *v, double *f)
{
  (void)v;
  TlSolid *s = (TlSolid *)sys;
  TL_CHECK(internal_nodes(s, t, u, s->fn, 0.0, NULL));
  tl_solid_nodes_to_dofs(s, s->fn, f);
  return TL_OK;
}

static TlStatus op_internal_tangent(TlMechSystem *sys, double t, const double *u, const double *v,
                                    double c_u, double c_v, TlSparse *K)
{
  (void)v, (void)c_v;
  TlSolid *s = (TlSolid *)sys;
  TL_CHECK(internal_nodes(s, t, u, NULL, c_u, K));
  return TL_OK;
}

static double amplitude(TlAmplitude amp, void *ctx, double t) { return amp ? amp(t, ctx) : 1.0; }

/* Follower pressure on the deformed faces: f_a = -p int N_a n dA with
 * n dA = x_s x x_t (3-D) or (y_s, -x_s) (2-D), and its derivative. */
static TlStatus pressure_loads(TlSolid *s, double t, const double *u_nodes, double *f_nodes, double c,
                               TlSparse *K)
{
  int dim = s->dim;
  for (int i = 0; i < s->n_surface; ++i) {
    const SurfaceLoad *sl = &s->surface[i];
    if (!sl->pressure) continue;
    double p = sl->p * amplitude(sl->amp, sl->ctx, t);
    const TlFaceSet *fs = &s->mesh->face_sets[sl->face_set];
    for (size_t k = 0; k < fs->n; ++k) {
      const TlElementType *ft = s->mesh->blocks[fs->faces[k].block].type->face_type;
      int nf = ft->n_nodes, fd = ft->dim;
      size_t fnodes[TL_ELEMENT_MAX_FACE_NODES];
      double x[TL_ELEMENT_MAX_FACE_NODES * 3];
      tl_mesh_face_nodes(s->mesh, fs->faces[k], fnodes, x);
      for (int a = 0; a < nf; ++a)
        for (int c_ = 0; c_ < dim; ++c_) x[3 * a + c_] += u_nodes[fnodes[a] * dim + c_];
      TlQuadrature q;
      TL_CHECK(tl_element_quadrature(ft, ft->order_mass, &q));
      double Kf[(TL_ELEMENT_MAX_FACE_NODES * 3) * (TL_ELEMENT_MAX_FACE_NODES * 3)];
      int nd = nf * dim;
      memset(Kf, 0, sizeof(double) * nd * nd);
      for (int qp = 0; qp < q.n; ++qp) {
        double N[TL_ELEMENT_MAX_FACE_NODES], dN[TL_ELEMENT_MAX_FACE_NODES * 2], nA[3];
        ft->eval(1, q.xi[qp], N, dN);
        tl_element_face_normal(ft, dim, x, q.xi[qp], nA);
        double w = q.w[qp];
        if (f_nodes)
          for (int a = 0; a < nf; ++a)
            for (int c_ = 0; c_ < dim; ++c_) f_nodes[fnodes[a] * dim + c_] -= w * p * N[a] * nA[c_];
        if (!K) continue;
        double ts[3] = {0, 0, 0}, tt[3] = {0, 0, 0};
        for (int a = 0; a < nf; ++a)
          for (int c_ = 0; c_ < 3; ++c_) {
            ts[c_] += x[3 * a + c_] * dN[a * fd];
            if (fd > 1) tt[c_] += x[3 * a + c_] * dN[a * fd + 1];
          }
        for (int b = 0; b < nf; ++b)
          for (int kc = 0; kc < dim; ++kc) {
            /* dn/dx_{b,kc} */
            double dn[3] = {0, 0, 0};
            if (dim == 3) {
              double e[3] = {0, 0, 0};
              e[kc] = 1.0;
              double gs = dN[b * fd], gt = dN[b * fd + 1];
              /* gs (e x tt) + gt (ts x e) */
              dn[0] = gs * (e[1] * tt[2] - e[2] * tt[1]) + gt * (ts[1] * e[2] - ts[2] * e[1]);
              dn[1] = gs * (e[2] * tt[0] - e[0] * tt[2]) + gt * (ts[2] * e[0] - ts[0] * e[2]);
              dn[2] = gs * (e[0] * tt[1] - e[1] * tt[0]) + gt * (ts[0] * e[1] - ts[1] * e[0]);
            } else {
              double gs = dN[b];
              if (kc == 0) dn[1] = -gs;
              else dn[0] = gs;
            }
            for (int a = 0; a < nf; ++a)
              for (int ic = 0; ic < dim; ++ic) Kf[(a * dim + ic) * nd + b * dim + kc] -= w * p * N[a] * dn[ic];
          }
      }
      if (K) {
        TlSparseIndex dofs[TL_ELEMENT_MAX_FACE_NODES * 3];
        for (int a = 0; a < nf; ++a)
          for (int c_ = 0; c_ < dim; ++c_) dofs[a * dim + c_] = s->dof[fnodes[a] * dim + c_];
        TL_CHECK(tl_sparse_add_element(K, nd, dofs, c, Kf));
      }
    }
  }
  return TL_OK;
}

static TlStatus external_nodes(TlSolid *s, double t, const double *u, double *f_nodes)
{
  size_t nc = s->n_nodes * s->dim;
  memset(f_nodes, 0, nc * sizeof(double));
  for (int i = 0; i < s->n_dead; ++i) {
    double a = amplitude(s->dead[i].amp, s->dead[i].ctx, t);
    if (a == 0.0) continue;
    for (size_t k = 0; k < nc; ++k) f_nodes[k] += a * s->dead[i].f[k];
  }
  for (size_t i = 0; i < s->n_points; ++i) {
    const PointForce *pf = &s->points[i];
    double a = amplitude(pf->amp, pf->ctx, t);
    double fv[3] = {pf->f.x, pf->f.y, pf->f.z};
    for (int c = 0; c < s->dim; ++c) f_nodes[pf->node * s->dim + c] += a * fv[c];
  }
  /* Follower (pressure) loads need the deformed faces. */
  int follower = 0;
  for (int i = 0; i < s->n_surface; ++i) follower |= s->surface[i].pressure;
  if (!follower) return TL_OK;
  tl_solid_dofs_to_nodes(s, u, s->un);
  TL_CHECK(pressure_loads(s, t, s->un, f_nodes, 0.0, NULL));
  return TL_OK;
}

static TlStatus op_external_force(TlMechSystem *sys, double t, const double *u, double *f)
{
  TlSolid *s = (TlSolid *)sys;
  TL_CHECK(external_nodes(s, t, u, s->gn));
  tl_solid_nodes_to_dofs(s, s->gn, f);
  return TL_OK;
}

static TlStatus op_external_tangent(TlMechSystem *sys, double t, const double *u, double c, TlSparse *K)
{
  TlSolid *s = (TlSolid *)sys;
  tl_solid_dofs_to_nodes(s, u, s->un);
  TL_CHECK(pressure_loads(s, t, s->un, NULL, c, K));
  return TL_OK;
}

static TlStatus op_lumped_mass(TlMechSystem *sys, double *m)
{
  TlSolid *s = (TlSolid *)sys;
  tl_solid_nodes_to_dofs(s, s->lumped_nodes, m);
  return TL_OK;
}

/* Consistent mass of element e of block b: Me[a][b] = int rho N_a N_b. */
static void element_mass(const TlSolid *s, int b, size_t e, double *Mab)
{
  const SolidBlock *B = &s->blocks[b];
  int nn = B->nn;
  double rho = B->material->density;
  memset(Mab, 0, (size_t)nn * nn * sizeof(double));
  for (int p = 0; p < B->qm.n; ++p) {
    double w = rho * B->wdetm[e * B->qm.n + p];
    const double *N = B->Nm + p * nn;
    for (int a = 0; a < nn; ++a)
      for (int c = 0; c < nn; ++c) Mab[a * nn + c] += w * N[a] * N[c];
  }
}

static TlStatus op_consistent_mass(TlMechSystem *sys, double c, TlSparse *M)
{
  TlSolid *s = (TlSolid *)sys;
  int dim = s->dim;
  int indexed = M->elem_pos_ptr && M->n_elements == (TlSparseIndex)s->n_pattern;
  double *Mab = s->scratch[0].DB, *Me = s->scratch[0].Ke; /* nn^2 <= 6 nd */
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    const SolidBlock *B = &s->blocks[b];
    int nn = B->nn, nd = B->nd;
    for (size_t e = 0; e < s->mesh->blocks[b].n_elements; ++e) {
      element_mass(s, b, e, Mab);
      memset(Me, 0, (size_t)nd * nd * sizeof(double));
      for (int a = 0; a < nn; ++a)
        for (int q = 0; q < nn; ++q)
          for (int i = 0; i < dim; ++i) Me[(a * dim + i) * nd + q * dim + i] = Mab[a * nn + q];
      size_t g = B->offset + e;
      if (indexed) TL_CHECK(tl_sparse_add_element_indexed(M, (TlSparseIndex)g, c, Me));
      else TL_CHECK(tl_sparse_add_element(M, nd, s->elem_dofs + s->elem_ptr[g], c, Me));
    }
  }
  return TL_OK;
}

static TlStatus op_dirichlet(TlMechSystem *sys, double t, double *u, double *v, double *a)
{
  TlSolid *s = (TlSolid *)sys;
  for (size_t i = 0; i < s->n_prescribed; ++i) {
    const Prescribed *p = &s->prescribed[i];
    double out[3] = {0, 0, 0};
    p->fn(t, s->mesh->x + 3 * p->node, p->component, p->ctx, out);
    for (int k = 0; k < 3; ++k)
      if (!isfinite(out[k]))
        TL_ERROR(TL_ERR_NUMERIC, "solid: prescribed value %d of node %zu component %d at t = %g is %g", k,
                 p->node, p->component, t, out[k]);
    TlSparseIndex d = s->dof[p->node * s->dim + p->component];
    if (u) u[d] = out[0];
    if (v) v[d] = out[1];
    if (a) a[d] = out[2];
  }
  return TL_OK;
}

TlStatus tl_solid_strain_energy(TlSolid *s, const double *u, double *W)
{
  tl_solid_dofs_to_nodes(s, u, s->un);
  *W = 0.0;
  for (int b = 0; b < s->mesh->n_blocks; ++b) TL_CHECK(block_kernel(s, b, NAN, s->un, NULL, 0.0, NULL, W));
  return TL_OK;
}

static TlStatus op_strain_energy(TlMechSystem *sys, const double *u, double *W)
{
  return tl_solid_strain_energy((TlSolid *)sys, u, W);
}

static TlStatus op_commit(TlMechSystem *sys)
{
  TlSolid *s = (TlSolid *)sys;
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    size_t ss = B->material->state_size, np = s->mesh->blocks[b].n_elements * B->nq;
    if (ss) {
      double *tmp = B->state_old;
      B->state_old = B->state_new;
      B->state_new = tmp;
      memcpy(B->state_new, B->state_old, np * ss * sizeof(double));
    }
    if (B->material->ops->commit) TL_CHECK(B->material->ops->commit(B->material, np, B->state_old));
  }
  return TL_OK;
}

static TlStatus op_rollback(TlMechSystem *sys)
{
  TlSolid *s = (TlSolid *)sys;
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    size_t ss = B->material->state_size, np = s->mesh->blocks[b].n_elements * B->nq;
    if (ss) memcpy(B->state_new, B->state_old, np * ss * sizeof(double));
    if (B->material->ops->rollback) TL_CHECK(B->material->ops->rollback(B->material, np, B->state_old));
  }
  return TL_OK;
}

TlStatus tl_solid_element_matrices(TlSolid *s, int b, size_t e, const double *ue, double *fe, double *Ke,
                                   double *Me)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: element matrices before tl_solid_setup");
  if (b < 0 || b >= s->mesh->n_blocks || e >= s->mesh->blocks[b].n_elements)
    TL_ERROR(TL_ERR_ARG, "solid: no element %zu in block %d", e, b);
  const SolidBlock *B = &s->blocks[b];
  Scratch *w = &s->scratch[0];
  size_t ss = B->material->state_size;
  deformation_gradients(B, s->dim, e, ue, w->F);
  if (ss) memcpy(w->state_old, B->state_old + e * B->nq * ss, B->nq * ss * sizeof(double));
  TL_CHECK(tl_material_evaluate_gradient(B->material, B->nq, w->F, ss ? w->state_old : NULL, ss ? w->state_new : NULL,
                                w->S, w->D, NULL));
  if (fe || Ke) element_forces(B, s->dim, e, w->F, w->S, w->D, fe, Ke, w->B, w->DB);
  if (Me) {
    int nn = B->nn, nd = B->nd, dim = s->dim;
    double Mab[TL_ELEMENT_MAX_NODES * TL_ELEMENT_MAX_NODES];
    element_mass(s, b, e, Mab);
    memset(Me, 0, (size_t)nd * nd * sizeof(double));
    for (int a = 0; a < nn; ++a)
      for (int q = 0; q < nn; ++q)
        for (int i = 0; i < dim; ++i) Me[(a * dim + i) * nd + q * dim + i] = Mab[a * nn + q];
  }
  return TL_OK;
}

TlStatus tl_solid_gauss_stress(TlSolid *s, int b, size_t e, int q, const double *u_nodes, TlMat3 *F, TlMat3 *S)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: stress before tl_solid_setup");
  const TlElementBlock *blk = &s->mesh->blocks[b];
  const SolidBlock *B = &s->blocks[b];
  if (q < 0 || q >= B->nq) TL_ERROR(TL_ERR_ARG, "solid: Gauss point %d outside [0, %d)", q, B->nq);
  Scratch *w = &s->scratch[0];
  int dim = s->dim;
  for (int a = 0; a < B->nn; ++a)
    for (int i = 0; i < dim; ++i) w->ue[a * dim + i] = u_nodes[blk->conn[e * B->nn + a] * dim + i];
  deformation_gradients(B, dim, e, w->ue, w->F);
  size_t ss = B->material->state_size;
  if (ss) memcpy(w->state_old, B->state_old + e * B->nq * ss, B->nq * ss * sizeof(double));
  TL_CHECK(tl_material_evaluate_gradient(B->material, B->nq, w->F, ss ? w->state_old : NULL, ss ? w->state_new : NULL,
                                w->S, NULL, NULL));
  *F = w->F[q];
  for (int i = 0; i < 3; ++i) F->m[i][i] += 1.0;
  *S = w->S[q];
  return TL_OK;
}

const TlMesh *tl_solid_mesh(const TlSolid *s) { return s->mesh; }

TlStatus tl_solid_element_stress(TlSolid *s, int b, size_t e, const double *u_nodes, TlMat3 *S_avg,
                                 TlMat3 *sigma_avg)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: stress before tl_solid_setup");
  if (b < 0 || b >= s->mesh->n_blocks || e >= s->mesh->blocks[b].n_elements)
    TL_ERROR(TL_ERR_ARG, "solid: no element %zu in block %d", e, b);
  const TlElementBlock *blk = &s->mesh->blocks[b];
  const SolidBlock *B = &s->blocks[b];
  Scratch *w = &s->scratch[0];
  int dim = s->dim;
  for (int a = 0; a < B->nn; ++a)
    for (int i = 0; i < dim; ++i) w->ue[a * dim + i] = u_nodes[blk->conn[e * B->nn + a] * dim + i];
  deformation_gradients(B, dim, e, w->ue, w->F);
  size_t ss = B->material->state_size;
  if (ss) memcpy(w->state_old, B->state_old + e * B->nq * ss, B->nq * ss * sizeof(double));
  TL_CHECK(tl_material_evaluate_gradient(B->material, B->nq, w->F, ss ? w->state_old : NULL,
                                         ss ? w->state_new : NULL, w->S, NULL, NULL));
  TlMat3 Ssum = tl_m3_zero(), csum = tl_m3_zero();
  double V = 0.0;
  for (int p = 0; p < B->nq; ++p) {
    double wv = (B->wdet_plain ? B->wdet_plain : B->wdet)[e * B->nq + p];
    TlMat3 F = w->F[p];
    for (int i = 0; i < 3; ++i) F.m[i][i] += 1.0;
    TlMat3 sigma = tl_m3_scale(tl_m3_mul(tl_m3_mul(F, w->S[p]), tl_m3_transpose(F)), 1.0 / tl_m3_det(F));
    Ssum = tl_m3_add(Ssum, tl_m3_scale(w->S[p], wv));
    csum = tl_m3_add(csum, tl_m3_scale(sigma, wv));
    V += wv;
  }
  if (S_avg) *S_avg = tl_m3_scale(Ssum, 1.0 / V);
  if (sigma_avg) *sigma_avg = tl_m3_scale(csum, 1.0 / V);
  return TL_OK;
}

/* Element-by-element estimate of the largest eigenvalue of M^-1 K: the
 * largest element eigenvalue of M_e^-1/2 K_e M_e^-1/2 (the element
 * eigenvalue theorem makes it an upper bound of the assembled one),
 * estimated from above as described below. */
static TlStatus op_max_frequency_squared(TlMechSystem *sys, const double *u, double *omega2)
{
  TlSolid *s = (TlSolid *)sys;
  tl_solid_dofs_to_nodes(s, u, s->un);
  double best = 0.0;
  double *ue = NULL, *Ke = NULL;
  TL_CHECK(tl_calloc(&ue, s->max_nd, sizeof(double)));
  TlStatus st = tl_calloc(&Ke, (size_t)s->max_nd * s->max_nd, sizeof(double));
  for (int b = 0; b < s->mesh->n_blocks && st == TL_OK; ++b) {
    const TlElementBlock *blk = &s->mesh->blocks[b];
    const SolidBlock *B = &s->blocks[b];
    int nn = B->nn, nd = B->nd, dim = s->dim;
    for (size_t e = 0; e < blk->n_elements && st == TL_OK; ++e) {
      for (int a = 0; a < nn; ++a)
        for (int i = 0; i < dim; ++i) ue[a * dim + i] = s->un[blk->conn[e * nn + a] * dim + i];
      int massless = 0;
      for (int a = 0; a < nn; ++a) massless |= !(B->lumped[e * nn + a] > 0.0);
      if (massless) continue; /* weighted out: no mass, no stiffness of its own */
      st = tl_solid_element_matrices(s, b, e, ue, NULL, Ke, NULL);
      if (st != TL_OK) break;
      /* A = M^-1/2 K M^-1/2 (similar to M^-1 K).  Gershgorin bounds its
       * largest eigenvalue; for a symmetric tangent power iterations
       * tighten it: the Rayleigh quotient rho plus the residual norm |r|
       * brackets the top eigenvalue once converged, and is capped by the
       * Gershgorin bound. */
      double gersh = 0.0;
      for (int r = 0; r < nd; ++r) {
        double row = 0.0, sr = 1.0 / sqrt(B->lumped[e * nn + r / dim]);
        for (int c = 0; c < nd; ++c) {
          Ke[r * nd + c] *= sr / sqrt(B->lumped[e * nn + c / dim]);
          row += fabs(Ke[r * nd + c]);
        }
        gersh = fmax(gersh, row);
      }
      double lam = gersh;
      if (B->symmetric) {
        double *x = ue, y[3 * TL_ELEMENT_MAX_NODES], rho = 0.0, res = 0.0;
        for (int r = 0; r < nd; ++r) x[r] = 1.0 + 0.5 * sin(1.7 * r + 0.3);
        for (int it = 0; it < 60; ++it) {
          double nx = 0.0;
          for (int r = 0; r < nd; ++r) nx += x[r] * x[r];
          nx = 1.0 / sqrt(nx);
          for (int r = 0; r < nd; ++r) x[r] *= nx;
          rho = 0.0;
          for (int r = 0; r < nd; ++r) {
            double a = 0.0;
            for (int c = 0; c < nd; ++c) a += Ke[r * nd + c] * x[c];
            y[r] = a;
            rho += x[r] * a;
          }
          res = 0.0;
          for (int r = 0; r < nd; ++r) res += (y[r] - rho * x[r]) * (y[r] - rho * x[r]);
          res = sqrt(res);
          for (int r = 0; r < nd; ++r) x[r] = y[r];
          if (res <= 1e-3 * rho) break;
        }
        lam = fmin(gersh, rho + res);
      }
      best = fmax(best, lam);
    }
  }
  tl_free(&ue);
  tl_free(&Ke);
  if (st != TL_OK) return tl_error_trace(st, __FILE__, __LINE__);
  *omega2 = best;
  return TL_OK;
}

/* Checkpoint of the committed material state, block by block (the trial
 * state equals it between steps).  Loads and prescribed motions are
 * functions of t: the stepper's time restores them. */
static TlStatus solid_checkpoint_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlSolid *s = object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "n_blocks", s->mesh->n_blocks));
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    const SolidBlock *B = &s->blocks[b];
    size_t n = B->material->state_size * s->mesh->blocks[b].n_elements * (size_t)B->nq;
    char name[64];
    snprintf(name, sizeof name, "block%d_state", b);
    TL_CHECK(tl_checkpoint_write_doubles(w, group, name, n, B->state_old));
  }
  return TL_OK;
}

static TlStatus solid_checkpoint_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlSolid *s = object;
  int64_t nb = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "n_blocks", &nb));
  if (nb != s->mesh->n_blocks)
    TL_ERROR(TL_ERR_ARG, "%s: solid state of %lld blocks; this mesh has %d", tl_checkpoint_reader_path(r),
             (long long)nb, s->mesh->n_blocks);
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    SolidBlock *B = &s->blocks[b];
    size_t n = B->material->state_size * s->mesh->blocks[b].n_elements * (size_t)B->nq;
    char name[64];
    snprintf(name, sizeof name, "block%d_state", b);
    TL_CHECK(tl_checkpoint_read_doubles(r, group, name, n, B->state_old));
    if (n) memcpy(B->state_new, B->state_old, n * sizeof(double));
  }
  return TL_OK;
}

static const TlCheckpointOps solid_checkpoint_ops = {
    .header = {"checkpoint", "solid_v1", "committed material state of a finite-strain solid"},
    .save = solid_checkpoint_save,
    .load = solid_checkpoint_load,
};

/* The solid's ops, with and without commit and rollback (see setup). */
#define SOLID_OPS_COMMON                                                                    \
  .header = {"mech_system", "solid", "total-Lagrangian finite-strain solid"},               \
  .create_matrix = op_create_matrix, .internal_force = op_internal_force,                  \
  .internal_tangent = op_internal_tangent, .external_force = op_external_force,            \
  .lumped_mass = op_lumped_mass, .external_tangent = op_external_tangent,                  \
  .consistent_mass = op_consistent_mass, .dirichlet = op_dirichlet,                        \
  .strain_energy = op_strain_energy, .max_frequency_squared = op_max_frequency_squared,    \
  .checkpoint = &solid_checkpoint_ops, .destroy = solid_destroy_content

static const TlMechSystemOps solid_ops = {SOLID_OPS_COMMON, .commit = op_commit, .rollback = op_rollback};
static const TlMechSystemOps solid_ops_elastic = {SOLID_OPS_COMMON};
#undef SOLID_OPS_COMMON

/* ------------------------------------------------ energies, reactions */

/* out_nodes = M a_nodes with the consistent mass, element by element. */
static void mass_times(const TlSolid *s, const double *a_nodes, double *out_nodes)
{
  int dim = s->dim;
  double Mab[TL_ELEMENT_MAX_NODES * TL_ELEMENT_MAX_NODES];
  memset(out_nodes, 0, s->n_nodes * dim * sizeof(double));
  for (int b = 0; b < s->mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &s->mesh->blocks[b];
    int nn = blk->type->n_nodes;
    for (size_t e = 0; e < blk->n_elements; ++e) {
      element_mass(s, b, e, Mab);
      for (int a = 0; a < nn; ++a)
        for (int q = 0; q < nn; ++q)
          for (int i = 0; i < dim; ++i)
            out_nodes[blk->conn[e * nn + a] * dim + i] += Mab[a * nn + q] * a_nodes[blk->conn[e * nn + q] * dim + i];
    }
  }
}

TlStatus tl_solid_kinetic_energy(TlSolid *s, const double *v, double *K)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: kinetic energy before tl_solid_setup");
  tl_solid_dofs_to_nodes(s, v, s->un);
  mass_times(s, s->un, s->gn);
  double k = 0.0;
  for (size_t i = 0; i < s->n_nodes * s->dim; ++i) k += s->un[i] * s->gn[i];
  *K = 0.5 * k;
  return TL_OK;
}

TlStatus tl_solid_work_increment(TlSolid *s, double t0, const double *u0, double t1, const double *u1, double *dW)
{
  size_t nc = s->n_nodes * s->dim;
  double w = 0.0;
  TL_CHECK(external_nodes(s, t0, u0, s->fn));
  double *d = s->gn;
  tl_solid_dofs_to_nodes(s, u1, d);
  tl_solid_dofs_to_nodes(s, u0, s->un);
  for (size_t i = 0; i < nc; ++i) d[i] -= s->un[i];
  for (size_t i = 0; i < nc; ++i) w += 0.5 * s->fn[i] * d[i];
  TL_CHECK(external_nodes(s, t1, u1, s->fn));
  tl_solid_dofs_to_nodes(s, u1, d);
  tl_solid_dofs_to_nodes(s, u0, s->un);
  for (size_t i = 0; i < nc; ++i) w += 0.5 * s->fn[i] * (d[i] - s->un[i]);
  *dW = w;
  return TL_OK;
}

TlStatus tl_solid_reactions(TlSolid *s, double t, const double *u, const double *a, double *R)
{
  if (!s->ready) TL_ERROR(TL_ERR_STATE, "solid: reactions before tl_solid_setup");
  size_t nc = s->n_nodes * s->dim;
  TL_CHECK(internal_nodes(s, t, u, R, 0.0, NULL));
  TL_CHECK(external_nodes(s, t, u, s->fn));
  for (size_t i = 0; i < nc; ++i) R[i] -= s->fn[i];
  if (a) {
    double *an = NULL, *ma = NULL;
    TL_CHECK(tl_calloc(&an, nc, sizeof(double)));
    TlStatus st = tl_calloc(&ma, nc, sizeof(double));
    if (st == TL_OK) {
      tl_solid_dofs_to_nodes(s, a, an);
      mass_times(s, an, ma);
      for (size_t i = 0; i < nc; ++i) R[i] += ma[i];
    }
    tl_free(&an);
    tl_free(&ma);
    if (st != TL_OK) return tl_error_trace(st, __FILE__, __LINE__);
  }
  for (size_t i = 0; i < nc; ++i)
    if (!s->constraint[i]) R[i] = 0.0;
  return TL_OK;
}

/* ------------------------------------------------- rigid-body check */

static size_t find_root(size_t *parent, size_t i)
{
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

TlStatus tl_solid_check_constraints(const TlSolid *s)
{
  const TlMesh *mesh = s->mesh;
  int dim = s->dim, nm = dim == 3 ? 6 : 3;
  size_t n = s->n_nodes;
  size_t *parent = NULL;
  TL_CHECK(tl_calloc(&parent, n, sizeof(size_t)));
  for (size_t i = 0; i < n; ++i) parent[i] = i;
  for (int b = 0; b < mesh->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    int nn = blk->type->n_nodes;
    for (size_t e = 0; e < blk->n_elements; ++e)
      for (int a = 1; a < nn; ++a) {
        size_t r0 = find_root(parent, blk->conn[e * nn]), r1 = find_root(parent, blk->conn[e * nn + a]);
        if (r0 != r1) parent[r1] = r0;
      }
  }
  TlStatus st = TL_OK;
  for (size_t root = 0; root < n && st == TL_OK; ++root) {
    if (find_root(parent, root) != root) continue;
    /* Rigid modes of this component about its centroid; Gram matrix of
     * their values at the constrained dofs. */
    double c[3] = {0, 0, 0}, count = 0, scale = 0.0;
    for (size_t i = 0; i < n; ++i)
      if (find_root(parent, i) == root) {
        for (int k = 0; k < 3; ++k) c[k] += mesh->x[3 * i + k];
        count += 1;
      }
    for (int k = 0; k < 3; ++k) c[k] /= count;
    for (size_t i = 0; i < n; ++i)
      if (find_root(parent, i) == root)
        for (int k = 0; k < 3; ++k) scale = fmax(scale, fabs(mesh->x[3 * i + k] - c[k]));
    if (scale == 0.0) scale = 1.0;
    double G[6][6] = {{0}};
    for (size_t i = 0; i < n; ++i) {
      if (find_root(parent, i) != root) continue;
      double r[3];
      for (int k = 0; k < 3; ++k) r[k] = (mesh->x[3 * i + k] - c[k]) / scale;
      for (int comp = 0; comp < dim; ++comp) {
        if (!s->constraint[i * dim + comp]) continue;
        double m[6] = {0};
        m[comp] = 1.0; /* translations */
        if (dim == 3) {
          /* rotation about axis k: (e_k x r)_comp */
          double e0[3] = {0, -r[2], r[1]}, e1[3] = {r[2], 0, -r[0]}, e2[3] = {-r[1], r[0], 0};
          m[3] = e0[comp], m[4] = e1[comp], m[5] = e2[comp];
        } else {
          m[2] = comp == 0 ? -r[1] : r[0];
        }
        for (int p = 0; p < nm; ++p)
          for (int q = 0; q < nm; ++q) G[p][q] += m[p] * m[q];
      }
    }
    /* Cholesky with a relative pivot test: a (near-)zero pivot is a mode
     * that no constraint touches. */
    double L[6][6] = {{0}};
    int free_mode = -1;
    for (int j = 0; j < nm && free_mode < 0; ++j) {
      double d = G[j][j];
      for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
      if (!(d > 1e-10 * (G[j][j] > 1.0 ? G[j][j] : 1.0))) {
        free_mode = j;
        break;
      }
      L[j][j] = sqrt(d);
      for (int i = j + 1; i < nm; ++i) {
        double v = G[i][j];
        for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
        L[i][j] = v / L[j][j];
      }
    }
    if (free_mode >= 0) {
      static const char *const names3[6] = {"translation along x", "translation along y", "translation along z",
                                            "rotation about x",    "rotation about y",    "rotation about z"};
      static const char *const names2[3] = {"translation along x", "translation along y", "rotation in the plane"};
      int block = 0;
      for (int b = 0; b < mesh->n_blocks; ++b)
        for (size_t e = 0; e < mesh->blocks[b].n_elements; ++e)
          if (find_root(parent, mesh->blocks[b].conn[e * mesh->blocks[b].type->n_nodes]) == root) {
            block = b;
            b = mesh->n_blocks;
            break;
          }
      st = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                        "solid: the part of element block '%s' containing node %zu can move rigidly "
                        "(%s is not constrained); constrained node sets: %s",
                        mesh->blocks[block].name, root, dim == 3 ? names3[free_mode] : names2[free_mode],
                        s->constraint_sets[0] ? s->constraint_sets : "none");
    }
  }
  tl_free(&parent);
  return st;
}
