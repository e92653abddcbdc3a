/* Volume coupling with CG-enriched homogenisation (seeds/001 §5.2). */
#include "tl_vcoupling.h"

#include <math.h>
#include <string.h>

#include "tl_cg_kernel.h"
#include "tl_cg_surface.h"
#include "tl_math.h"
#include "tl_memory.h"

/* Uniform bins of points, rebuilt by counting sort into reused arrays. */
typedef struct {
  double lo[3], h;
  size_t dims[3];
  size_t *start, cap_start; /* cells + 1 */
  size_t *item, cap_item;
  size_t *cell, cap_cell;
} Bins;

struct TlVCoupling {
  const TlMesh *mesh;
  int block;
  const TlElementType *type;
  int nn;
  TlVCouplingZone zone;
  double c, epsilon;
  TlVCouplingProfile profile;
  double weight_min;   /* the zone's nodal weights span [weight_min, 1 - weight_min] */
  double reach_shrink; /* particles gathered within max(c - reach_shrink, 0) of an element */
  int lumped;          /* Me row-sum lumped */
  char kernel_name[32];
  TlCGKernel *kernel; /* NULL when c = 0 */
  double *w_node;     /* n_nodes */
  size_t n_elem;
  size_t *elem;       /* coupling elements (block indices) */
  long *elem_slot;    /* block element -> coupling slot or -1 */
  size_t n_cnode;     /* rows of Pi: coupled nodes, or element-node slots */
  size_t *cnode;      /* global node of each row */
  int per_element;    /* rows per element (element-local Eq. 18) */
  double *hcount;     /* n_nodes: rows per node (homogenise) */
  long *node_local;   /* global -> local or -1 */
  size_t *conn;       /* n_elem x nn local node numbers */
  double *Me;         /* n_elem x nn x nn: int N_a N_b dV (reference), or its lumping */
  double *Mc;         /* the consistent one, kept for switching back */
  double h_elem;      /* largest element extent (bin size) */
  TlQuadrature rule;  /* Eq. 18 */
  double *Nq;         /* rule.n x nn */
  /* current geometry */
  double *xe;         /* n_elem x nn x 3 */
  double *box;        /* n_elem x 6, extended by c */
  TlVec3 *xq;         /* n_elem x rule.n */
  double *wq;         /* n_elem x rule.n */
  /* Pi */
  size_t n_pi, cap_pi, cap_pi_p, cap_pi_v;
  size_t *pi_node;    /* local node */
  size_t *pi_part;
  double *pi_val;
  size_t *pi_gnode, cap_pi_g; /* global node numbers (for the operator view) */
  double *denom;      /* n_cnode */
  char *active;
  double *uDE, *r, *F; /* 3 n_cnode */
  size_t np;
  long *owner; size_t cap_owner;
  double *scratch;    /* nn */
  double *res_acc;    /* 7 n_cnode: resolution check (int N x, int N, sum Pi x) */
  Bins bins;
  int updated;
};

static double profile_weight(const TlVCouplingZone *zone, TlVCouplingProfile profile, double wmin, const double x[3])
{
  double s = (x[zone->axis] - zone->lo) / (zone->hi - zone->lo);
  if (wmin == 0.0) {
    if (s <= 0.0) return 1.0;
    if (s >= 1.0) return 0.0;
  } else { /* the zone's own nodes (its closed ends included) take [wmin, 1 - wmin] */
    if (s < -1e-12) return 1.0;
    if (s > 1.0 + 1e-12) return 0.0;
    s = fmin(fmax(s, 0.0), 1.0);
  }
  double r = profile == TL_VCOUPLING_LINEAR ? 1.0 - s : 0.5 * (1.0 + cos(TL_PI * s));
  return wmin + (1.0 - 2.0 * wmin) * r;
}

double tl_vcoupling_zone_weight(const TlVCouplingZone *zone, const double x[3])
{
  return profile_weight(zone, TL_VCOUPLING_COSINE, 0.0, x);
}

static void bins_free(Bins *b)
{
  tl_free(&b->start);
  tl_free(&b->item);
  tl_free(&b->cell);
}

static TlStatus bins_build(Bins *b, size_t n, const double *x, double h)
{
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d) {
      double v = x[3 * k + d];
      if (!isfinite(v)) TL_ERROR(TL_ERR_NUMERIC, "point %zu has a non-finite coordinate %g", k, v);
      if (v < lo[d]) lo[d] = v;
      if (v > hi[d]) hi[d] = v;
    }
  if (n == 0)
    for (int d = 0; d < 3; ++d) lo[d] = hi[d] = 0.0;
  /* cells no more than 8 n + 64, so a scattered set cannot blow up memory */
  for (;;) {
    size_t total = 1;
    for (int d = 0; d < 3; ++d) {
      b->dims[d] = (size_t)floor((hi[d] - lo[d]) / h) + 1;
      total *= b->dims[d];
    }
    if (total <= 8 * n + 64) break;
    h *= 1.5;
  }
  b->h = h;
  memcpy(b->lo, lo, sizeof lo);
  size_t nc = b->dims[0] * b->dims[1] * b->dims[2];
  TL_CHECK(tl_array_reserve(&b->start, &b->cap_start, nc + 1, sizeof *b->start));
  TL_CHECK(tl_array_reserve(&b->item, &b->cap_item, n ? n : 1, sizeof *b->item));
  TL_CHECK(tl_array_reserve(&b->cell, &b->cap_cell, n ? n : 1, sizeof *b->cell));
  memset(b->start, 0, (nc + 1) * sizeof *b->start);
  for (size_t k = 0; k < n; ++k) {
    size_t i[3];
    for (int d = 0; d < 3; ++d) {
      i[d] = (size_t)((x[3 * k + d] - lo[d]) / h);
      if (i[d] >= b->dims[d]) i[d] = b->dims[d] - 1;
    }
    b->cell[k] = (i[2] * b->dims[1] + i[1]) * b->dims[0] + i[0];
    b->start[b->cell[k] + 1]++;
  }
  for (size_t q = 0; q < nc; ++q) b->start[q + 1] += b->start[q];
  for (size_t k = 0; k < n; ++k) b->item[b->start[b->cell[k]]++] = k;
  for (size_t q = nc; q > 0; --q) b->start[q] = b->start[q - 1];
  b->start[0] = 0;
  return TL_OK;
}

/* Cell index range [i0, i1] covering the box along d; empty when i0 > i1. */
static void bins_range(const Bins *b, const double *box, size_t i0[3], size_t i1[3], int *empty)
{
  *empty = 0;
  for (int d = 0; d < 3; ++d) {
    double a = (box[d] - b->lo[d]) / b->h, z = (box[3 + d] - b->lo[d]) / b->h;
    if (z < 0.0 || a >= (double)b->dims[d]) {
      *empty = 1;
      return;
    }
    i0[d] = a < 0.0 ? 0 : (size_t)a;
    i1[d] = z >= (double)b->dims[d] ? b->dims[d] - 1 : (size_t)z;
  }
}

static int in_box(const double *box, const double *p)
{
  for (int d = 0; d < 3; ++d)
    if (p[d] < box[d] || p[d] > box[3 + d]) return 0;
  return 1;
}

#define BINS_FOR(b, box, k, body)                                                     \
  do {                                                                                \
    size_t i0_[3], i1_[3];                                                            \
    int empty_;                                                                       \
    bins_range((b), (box), i0_, i1_, &empty_);                                        \
    if (!empty_)                                                                      \
      for (size_t iz_ = i0_[2]; iz_ <= i1_[2]; ++iz_)                                 \
        for (size_t iy_ = i0_[1]; iy_ <= i1_[1]; ++iy_)                               \
          for (size_t ix_ = i0_[0]; ix_ <= i1_[0]; ++ix_) {                           \
            size_t c_ = (iz_ * (b)->dims[1] + iy_) * (b)->dims[0] + ix_;              \
            for (size_t j_ = (b)->start[c_]; j_ < (b)->start[c_ + 1]; ++j_) {         \
              size_t k = (b)->item[j_];                                               \
              body                                                                    \
            }                                                                         \
          }                                                                           \
  } while (0)

static TlStatus make_kernel(TlVCoupling *vc)
{
  tl_cg_kernel_destroy(&vc->kernel);
  if (vc->c > 0.0) TL_CHECK(tl_cg_kernel_create(vc->kernel_name, vc->c, 3, &vc->kernel));
  return TL_OK;
}

TlStatus tl_vcoupling_create(const TlMesh *mesh, int block, const TlVCouplingParams *p, TlVCoupling **out)
{
  *out = NULL;
  if (!mesh || !mesh->finalized) TL_ERROR(TL_ERR_STATE, "the mesh must be finalized before coupling");
  if (mesh->dim != 3) TL_ERROR(TL_ERR_ARG, "volume coupling needs a 3-D mesh (dim %d)", mesh->dim);
  if (block < 0 || block >= mesh->n_blocks)
    TL_ERROR(TL_ERR_ARG, "block %d out of range [0, %d)", block, mesh->n_blocks);
  if (p->zone.axis < 0 || p->zone.axis > 2) TL_ERROR(TL_ERR_ARG, "zone axis %d must be 0, 1 or 2", p->zone.axis);
  if (!(p->zone.hi > p->zone.lo) || !isfinite(p->zone.lo) || !isfinite(p->zone.hi))
    TL_ERROR(TL_ERR_ARG, "coupling zone [%g, %g] must have lo < hi, both finite", p->zone.lo, p->zone.hi);
  if (!(p->c >= 0.0) || !isfinite(p->c)) TL_ERROR(TL_ERR_ARG, "CG width c = %g must be >= 0 and finite", p->c);
  if (!(p->epsilon >= 0.0) || !isfinite(p->epsilon))
    TL_ERROR(TL_ERR_ARG, "penalty epsilon = %g must be >= 0 and finite", p->epsilon);
  int order = p->quad_order ? p->quad_order : 4;
  if (order < 1 || order > 5) TL_ERROR(TL_ERR_ARG, "quadrature order %d must lie in [1, 5]", order);
  const char *kname = p->kernel ? p->kernel : "lucy";
  if (strlen(kname) >= 32) TL_ERROR(TL_ERR_ARG, "kernel name '%s' too long (31 characters at most)", kname);

  TlVCoupling *vc;
  TL_CHECK(TL_NEW(vc));
  TlStatus s = TL_OK;
  const TlElementBlock *B = &mesh->blocks[block];
  vc->mesh = mesh;
  vc->block = block;
  vc->type = B->type;
  vc->nn = B->type->n_nodes;
  vc->zone = p->zone;
  vc->c = p->c;
  vc->epsilon = p->epsilon;
  strcpy(vc->kernel_name, kname);
  const int nn = vc->nn;
  if (vc->type->dim != 3) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "block %d holds %s elements, not solid 3-D ones", block,
                     vc->type->header.name);
    goto fail;
  }
  TL_CHECK_GOTO(s, make_kernel(vc), fail);

  TL_CHECK_GOTO(s, tl_calloc(&vc->w_node, mesh->n_nodes, sizeof *vc->w_node), fail);
  for (size_t i = 0; i < mesh->n_nodes; ++i) vc->w_node[i] = profile_weight(&vc->zone, vc->profile, vc->weight_min, mesh->x + 3 * i);

  /* coupling elements: those reaching into the open zone */
  TL_CHECK_GOTO(s, tl_calloc(&vc->elem, B->n_elements ? B->n_elements : 1, sizeof *vc->elem), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->elem_slot, B->n_elements ? B->n_elements : 1, sizeof *vc->elem_slot), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->node_local, mesh->n_nodes, sizeof *vc->node_local), fail);
  for (size_t i = 0; i < mesh->n_nodes; ++i) vc->node_local[i] = -1;
  for (size_t e = 0; e < B->n_elements; ++e) {
    double a = INFINITY, z = -INFINITY;
    for (int k = 0; k < nn; ++k) {
      double v = mesh->x[3 * B->conn[e * nn + k] + p->zone.axis];
      a = fmin(a, v);
      z = fmax(z, v);
    }
    vc->elem_slot[e] = -1;
    if (a < p->zone.hi && z > p->zone.lo) {
      vc->elem_slot[e] = (long)vc->n_elem;
      vc->elem[vc->n_elem++] = e;
    }
  }
  if (vc->n_elem == 0) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "no element of block '%s' reaches into the zone (%g, %g) along axis %d",
                     B->name, p->zone.lo, p->zone.hi, p->zone.axis);
    goto fail;
  }
  TL_CHECK_GOTO(s, tl_calloc(&vc->conn, vc->n_elem * nn, sizeof *vc->conn), fail);
  size_t rows_max = mesh->n_nodes > vc->n_elem * nn ? mesh->n_nodes : vc->n_elem * nn;
  TL_CHECK_GOTO(s, tl_calloc(&vc->cnode, rows_max, sizeof *vc->cnode), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->hcount, mesh->n_nodes, sizeof *vc->hcount), fail);
  for (size_t s_ = 0; s_ < vc->n_elem; ++s_)
    for (int k = 0; k < nn; ++k) {
      size_t g = B->conn[vc->elem[s_] * nn + k];
      if (vc->node_local[g] < 0) {
        vc->node_local[g] = (long)vc->n_cnode;
        vc->cnode[vc->n_cnode++] = g;
      }
      vc->conn[s_ * nn + k] = (size_t)vc->node_local[g];
    }
  vc->per_element = p->per_element != 0;
  if (vc->per_element) {
    /* one row per element and node: Eq. 18 normalised over Omega_e alone */
    vc->n_cnode = vc->n_elem * nn;
    for (size_t s_ = 0; s_ < vc->n_elem; ++s_)
      for (int k = 0; k < nn; ++k) {
        vc->cnode[s_ * nn + k] = B->conn[vc->elem[s_] * nn + k];
        vc->conn[s_ * nn + k] = s_ * nn + k;
      }
  }

  /* reference mass-type matrix M_ab = int N_a N_b dV and element size */
  TlQuadrature mrule;
  int morder = vc->type->order_mass > 0 ? vc->type->order_mass : 3;
  TL_CHECK_GOTO(s, tl_element_quadrature(vc->type, morder, &mrule), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->Me, vc->n_elem * nn * nn, sizeof *vc->Me), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->Mc, vc->n_elem * nn * nn, sizeof *vc->Mc), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->xe, vc->n_elem * nn * 3, sizeof *vc->xe), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->scratch, (size_t)nn * TL_QUADRATURE_MAX, sizeof *vc->scratch), fail);
  for (size_t s_ = 0; s_ < vc->n_elem; ++s_) {
    double *x = vc->xe + s_ * nn * 3;
    tl_mesh_element_coords(mesh, block, vc->elem[s_], x);
    double lo3[3] = {INFINITY, INFINITY, INFINITY}, hi3[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int k = 0; k < nn; ++k)
      for (int d = 0; d < 3; ++d) {
        lo3[d] = fmin(lo3[d], x[3 * k + d]);
        hi3[d] = fmax(hi3[d], x[3 * k + d]);
      }
    for (int d = 0; d < 3; ++d) vc->h_elem = fmax(vc->h_elem, hi3[d] - lo3[d]);
    vc->type->eval(mrule.n, &mrule.xi[0][0], vc->scratch, NULL);
    double *M = vc->Me + s_ * nn * nn;
    for (int q = 0; q < mrule.n; ++q) {
      double J[3][3], detJ;
      TL_CHECK_GOTO(s, tl_element_jacobian(vc->type, 3, x, mrule.xi[q], J, &detJ), fail);
      const double *N = vc->scratch + q * nn;
      double wdv = mrule.w[q] * detJ;
      for (int a = 0; a < nn; ++a)
        for (int b = 0; b < nn; ++b) M[a * nn + b] += wdv * N[a] * N[b];
    }
  }
  memcpy(vc->Mc, vc->Me, vc->n_elem * nn * nn * sizeof *vc->Mc);

  /* Eq. 18 quadrature */
  TL_CHECK_GOTO(s, tl_element_quadrature(vc->type, order, &vc->rule), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->Nq, (size_t)vc->rule.n * nn, sizeof *vc->Nq), fail);
  vc->type->eval(vc->rule.n, &vc->rule.xi[0][0], vc->Nq, NULL);
  TL_CHECK_GOTO(s, tl_calloc(&vc->xq, vc->n_elem * vc->rule.n, sizeof *vc->xq), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->wq, vc->n_elem * vc->rule.n, sizeof *vc->wq), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->box, vc->n_elem * 6, sizeof *vc->box), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->denom, vc->n_cnode, sizeof *vc->denom), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->active, vc->n_cnode, sizeof *vc->active), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->uDE, 3 * vc->n_cnode, sizeof *vc->uDE), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->r, 3 * vc->n_cnode, sizeof *vc->r), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->F, 3 * vc->n_cnode, sizeof *vc->F), fail);
  TL_CHECK_GOTO(s, tl_calloc(&vc->res_acc, 7 * vc->n_cnode, sizeof *vc->res_acc), fail);
  *out = vc;
  return TL_OK;
fail:
  tl_vcoupling_destroy(&vc);
  return s;
}

void tl_vcoupling_destroy(TlVCoupling **pvc)
{
  TlVCoupling *vc = *pvc;
  if (!vc) return;
  tl_cg_kernel_destroy(&vc->kernel);
  tl_free(&vc->w_node);
  tl_free(&vc->elem);
  tl_free(&vc->elem_slot);
  tl_free(&vc->cnode);
  tl_free(&vc->hcount);
  tl_free(&vc->node_local);
  tl_free(&vc->conn);
  tl_free(&vc->Me);
  tl_free(&vc->Mc);
  tl_free(&vc->Nq);
  tl_free(&vc->xe);
  tl_free(&vc->box);
  tl_free(&vc->xq);
  tl_free(&vc->wq);
  tl_free(&vc->pi_node);
  tl_free(&vc->pi_part);
  tl_free(&vc->pi_val);
  tl_free(&vc->pi_gnode);
  tl_free(&vc->denom);
  tl_free(&vc->active);
  tl_free(&vc->uDE);
  tl_free(&vc->r);
  tl_free(&vc->F);
  tl_free(&vc->owner);
  tl_free(&vc->scratch);
  tl_free(&vc->res_acc);
  bins_free(&vc->bins);
  tl_free(pvc);
}

TlStatus tl_vcoupling_set_width(TlVCoupling *vc, double c)
{
  if (!(c >= 0.0) || !isfinite(c)) TL_ERROR(TL_ERR_ARG, "CG width c = %g must be >= 0 and finite", c);
  vc->c = c;
  TL_CHECK(make_kernel(vc));
  vc->updated = 0;
  return TL_OK;
}

static TlStatus pi_push(TlVCoupling *vc, size_t node, size_t part, double val)
{
  size_t need = vc->n_pi + 1;
  TL_CHECK(tl_array_reserve(&vc->pi_node, &vc->cap_pi, need, sizeof *vc->pi_node));
  TL_CHECK(tl_array_reserve(&vc->pi_part, &vc->cap_pi_p, need, sizeof *vc->pi_part));
  TL_CHECK(tl_array_reserve(&vc->pi_val, &vc->cap_pi_v, need, sizeof *vc->pi_val));
  vc->pi_node[vc->n_pi] = node;
  vc->pi_part[vc->n_pi] = part;
  vc->pi_val[vc->n_pi] = val;
  vc->n_pi++;
  return TL_OK;
}

TlStatus tl_vcoupling_set_profile(TlVCoupling *vc, TlVCouplingProfile profile)
{
  if (profile != TL_VCOUPLING_COSINE && profile != TL_VCOUPLING_LINEAR)
    TL_ERROR(TL_ERR_ARG, "weight profile %d must be TL_VCOUPLING_COSINE (0) or TL_VCOUPLING_LINEAR (1)", (int)profile);
  vc->profile = profile;
  for (size_t i = 0; i < vc->mesh->n_nodes; ++i)
    vc->w_node[i] = profile_weight(&vc->zone, vc->profile, vc->weight_min, vc->mesh->x + 3 * i);
  vc->updated = 0;
  return TL_OK;
}

TlStatus tl_vcoupling_set_weight_min(TlVCoupling *vc, double weight_min)
{
  if (!(weight_min >= 0.0 && weight_min < 0.5))
    TL_ERROR(TL_ERR_ARG, "weight_min = %g outside [0, 0.5)", weight_min);
  vc->weight_min = weight_min;
  return tl_vcoupling_set_profile(vc, vc->profile);
}

TlStatus tl_vcoupling_set_lumped_penalty(TlVCoupling *vc, int lumped)
{
  const int nn = vc->nn;
  vc->lumped = lumped != 0;
  memcpy(vc->Me, vc->Mc, vc->n_elem * nn * nn * sizeof *vc->Me);
  if (vc->lumped) /* row sums on the diagonal: node a feels its own mismatch alone */
    for (size_t s = 0; s < vc->n_elem; ++s) {
      double *M = vc->Me + s * nn * nn;
      for (int a = 0; a < nn; ++a) {
        double sum = 0.0;
        for (int b = 0; b < nn; ++b) {
          sum += M[a * nn + b];
          M[a * nn + b] = 0.0;
        }
        M[a * nn + a] = sum;
      }
    }
  return TL_OK;
}

TlStatus tl_vcoupling_set_reach_shrink(TlVCoupling *vc, double reach_shrink)
{
  if (!(reach_shrink >= 0.0) || !isfinite(reach_shrink))
    TL_ERROR(TL_ERR_ARG, "reach_shrink = %g m must be >= 0 and finite", reach_shrink);
  vc->reach_shrink = reach_shrink;
  vc->updated = 0;
  return TL_OK;
}

/* How far beyond an element its particles are gathered for Eq. 18. */
static double box_pad(const TlVCoupling *vc) { return fmax(vc->c - vc->reach_shrink, 0.0); }

/* Current nodal coordinates and bounding boxes (extended by box_pad). */
static TlStatus update_geometry(TlVCoupling *vc, const double *u_nodes)
{
  const int nn = vc->nn;
  const TlElementBlock *B = &vc->mesh->blocks[vc->block];
  for (size_t s = 0; s < vc->n_elem; ++s) {
    double *x = vc->xe + s * nn * 3, *box = vc->box + 6 * s;
    for (int d = 0; d < 3; ++d) {
      box[d] = INFINITY;
      box[3 + d] = -INFINITY;
    }
    for (int k = 0; k < nn; ++k) {
      size_t g = B->conn[vc->elem[s] * nn + k];
      for (int d = 0; d < 3; ++d) {
        double v = vc->mesh->x[3 * g + d] + (u_nodes ? u_nodes[3 * g + d] : 0.0);
        if (!isfinite(v)) TL_ERROR(TL_ERR_NUMERIC, "node %zu has a non-finite position (%g)", g, v);
        x[3 * k + d] = v;
        box[d] = fmin(box[d], v);
        box[3 + d] = fmax(box[3 + d], v);
      }
    }
    double pad = box_pad(vc) + 1e-9 * vc->h_elem;
    for (int d = 0; d < 3; ++d) {
      box[d] -= pad;
      box[3 + d] += pad;
    }
    if (vc->c > 0.0) {
      for (int q = 0; q < vc->rule.n; ++q) {
        double J[3][3], detJ, xq[3];
        TL_CHECK(tl_element_jacobian(vc->type, 3, x, vc->rule.xi[q], J, &detJ));
        if (!(detJ > 0.0))
          TL_ERROR(TL_ERR_NUMERIC, "coupling element %zu inverted (det J = %g at quadrature point %d)", vc->elem[s],
                   detJ, q);
        tl_element_interpolate(vc->type, x, vc->rule.xi[q], xq);
        vc->xq[s * vc->rule.n + q] = tl_v3(xq[0], xq[1], xq[2]);
        vc->wq[s * vc->rule.n + q] = vc->rule.w[q] * detJ;
      }
    }
  }
  return TL_OK;
}

TlStatus tl_vcoupling_update(TlVCoupling *vc, const double *u_nodes, size_t np, const double *xp, const double *mp)
{
  const int nn = vc->nn;
  TL_CHECK(update_geometry(vc, u_nodes));
  for (size_t a = 0; a < np; ++a)
    if (!(mp[a] > 0.0) || !isfinite(mp[a])) TL_ERROR(TL_ERR_ARG, "particle %zu has mass %g (must be > 0)", a, mp[a]);
  TL_CHECK(bins_build(&vc->bins, np, xp, vc->h_elem > 0 ? vc->h_elem : 1.0));
  vc->n_pi = 0;
  vc->np = np;
  memset(vc->denom, 0, vc->n_cnode * sizeof *vc->denom);
  double *N = vc->scratch;
  if (vc->c == 0.0) {
    /* Eq. 19: each particle belongs to the first coupling element holding it */
    TL_CHECK(tl_array_reserve(&vc->owner, &vc->cap_owner, np ? np : 1, sizeof *vc->owner));
    for (size_t a = 0; a < np; ++a) vc->owner[a] = -1;
    for (size_t s = 0; s < vc->n_elem; ++s) {
      const double *x = vc->xe + s * nn * 3, *box = vc->box + 6 * s;
      TlStatus st = TL_OK;
      BINS_FOR(&vc->bins, box, a, {
        if (st == TL_OK && vc->owner[a] < 0 && in_box(box, xp + 3 * a)) {
          double xi[3];
          int inside = 0;
          if (tl_element_inverse_map(vc->type, 3, x, xp + 3 * a, xi, &inside) == TL_OK && inside) {
            vc->owner[a] = (long)s;
            vc->type->eval(1, xi, N, NULL);
            for (int k = 0; k < nn; ++k)
              if (N[k] != 0.0 && st == TL_OK) st = pi_push(vc, vc->conn[s * nn + k], a, mp[a] * N[k]);
          }
        }
      });
      TL_CHECK(st);
    }
  } else {
    /* Eq. 18 by quadrature on each element, for the particles in its box
     * extended by c */
    const int nq = vc->rule.n;
    for (size_t s = 0; s < vc->n_elem; ++s) {
      const double *box = vc->box + 6 * s;
      TlStatus st = TL_OK;
      BINS_FOR(&vc->bins, box, a, {
        if (st == TL_OK && in_box(box, xp + 3 * a)) {
          for (int k = 0; k < nn; ++k) N[k] = 0.0;
          st = tl_cg_project_to_element(vc->kernel, (size_t)nq, vc->xq + s * nq, vc->wq + s * nq, nn, vc->Nq,
                                        tl_v3(xp[3 * a], xp[3 * a + 1], xp[3 * a + 2]), mp[a], N);
          for (int k = 0; k < nn; ++k)
            if (N[k] != 0.0 && st == TL_OK) st = pi_push(vc, vc->conn[s * nn + k], a, N[k]);
        }
      });
      TL_CHECK(st);
    }
  }
  for (size_t j = 0; j < vc->n_pi; ++j) vc->denom[vc->pi_node[j]] += vc->pi_val[j];
  for (size_t i = 0; i < vc->n_cnode; ++i) vc->active[i] = vc->denom[i] > 0.0;
  TL_CHECK(tl_array_reserve(&vc->pi_gnode, &vc->cap_pi_g, vc->n_pi ? vc->n_pi : 1, sizeof *vc->pi_gnode));
  for (size_t j = 0; j < vc->n_pi; ++j) {
    size_t i = vc->pi_node[j];
    vc->pi_val[j] = vc->active[i] ? vc->pi_val[j] / vc->denom[i] : 0.0;
    vc->pi_gnode[j] = vc->cnode[i];
  }
  vc->updated = 1;
  return TL_OK;
}

TlStatus tl_vcoupling_point_weights(TlVCoupling *vc, size_t n, const double *x, double *w)
{
  if (!vc->updated) TL_ERROR(TL_ERR_STATE, "tl_vcoupling_update must run before the point weights");
  const int nn = vc->nn;
  const TlElementBlock *B = &vc->mesh->blocks[vc->block];
  for (size_t k = 0; k < n; ++k) w[k] = profile_weight(&vc->zone, vc->profile, vc->weight_min, x + 3 * k);
  TL_CHECK(bins_build(&vc->bins, n, x, vc->h_elem > 0 ? vc->h_elem : 1.0));
  TL_CHECK(tl_array_reserve(&vc->owner, &vc->cap_owner, n ? n : 1, sizeof *vc->owner));
  for (size_t k = 0; k < n; ++k) vc->owner[k] = -1;
  double *N = vc->scratch;
  for (size_t s = 0; s < vc->n_elem; ++s) {
    const double *xe = vc->xe + s * nn * 3;
    double box[6];
    for (int d = 0; d < 6; ++d) box[d] = vc->box[6 * s + d] + (d < 3 ? box_pad(vc) : -box_pad(vc));
    BINS_FOR(&vc->bins, box, k, {
      if (vc->owner[k] < 0 && in_box(box, x + 3 * k)) {
        double xi[3];
        int inside = 0;
        if (tl_element_inverse_map(vc->type, 3, xe, x + 3 * k, xi, &inside) == TL_OK && inside) {
          vc->owner[k] = (long)s;
          vc->type->eval(1, xi, N, NULL);
          double v = 0.0;
          for (int a = 0; a < nn; ++a) v += N[a] * vc->w_node[B->conn[vc->elem[s] * nn + a]];
          w[k] = v;
        }
      }
    });
  }
  return TL_OK;
}

TlStatus tl_vcoupling_forces(TlVCoupling *vc, const double *du_p, const double *du_n, double *f_nodes,
                             double *f_particles, TlVCouplingDiag *diag)
{
  if (!vc->updated) TL_ERROR(TL_ERR_STATE, "tl_vcoupling_update must run before the coupling forces");
  const int nn = vc->nn;
  const size_t nc = vc->n_cnode;
  memset(vc->uDE, 0, 3 * nc * sizeof *vc->uDE);
  for (size_t j = 0; j < vc->n_pi; ++j) {
    size_t i = vc->pi_node[j], a = vc->pi_part[j];
    double p = vc->pi_val[j];
    for (int d = 0; d < 3; ++d) vc->uDE[3 * i + d] += p * du_p[3 * a + d];
  }
  double rmax = 0.0, r2 = 0.0;
  size_t n_active = 0;
  for (size_t i = 0; i < nc; ++i) {
    size_t g = vc->cnode[i];
    for (int d = 0; d < 3; ++d) {
      double r = vc->active[i] ? vc->uDE[3 * i + d] - du_n[3 * g + d] : 0.0;
      if (!isfinite(r))
        TL_ERROR(TL_ERR_NUMERIC, "coupling residual at node %zu is %g: the coupled run has blown up", g, r);
      vc->r[3 * i + d] = r;
      rmax = fmax(rmax, fabs(r));
      r2 += r * r;
    }
    n_active += vc->active[i] != 0;
  }
  /* F_i = eps sum_j M_ij r_j over the coupled nodes (Eq. 31 integrated) */
  memset(vc->F, 0, 3 * nc * sizeof *vc->F);
  for (size_t s = 0; s < vc->n_elem; ++s) {
    const double *M = vc->Me + s * nn * nn;
    const size_t *cn = vc->conn + s * nn;
    for (int a = 0; a < nn; ++a) {
      if (!vc->active[cn[a]]) continue;
      double f[3] = {0, 0, 0};
      for (int b = 0; b < nn; ++b)
        for (int d = 0; d < 3; ++d) f[d] += M[a * nn + b] * vc->r[3 * cn[b] + d];
      for (int d = 0; d < 3; ++d) vc->F[3 * cn[a] + d] += vc->epsilon * f[d];
    }
  }
  double sf[3] = {0, 0, 0}, sp[3] = {0, 0, 0}, sabs = 0.0, wf = 0.0, wp = 0.0;
  for (size_t i = 0; i < nc; ++i) {
    size_t g = vc->cnode[i];
    for (int d = 0; d < 3; ++d) {
      double f = vc->F[3 * i + d];
      if (f_nodes) f_nodes[3 * g + d] += f;
      sf[d] += f;
      sabs += fabs(f);
      wf += f * du_n[3 * g + d];
    }
  }
  /* Eq. 32: f_a = -sum_i Pi_ia F_i */
  for (size_t j = 0; j < vc->n_pi; ++j) {
    size_t i = vc->pi_node[j], a = vc->pi_part[j];
    double p = vc->pi_val[j];
    for (int d = 0; d < 3; ++d) {
      double f = -p * vc->F[3 * i + d];
      if (f_particles) f_particles[3 * a + d] += f;
      sp[d] += f;
      wp += f * du_p[3 * a + d];
    }
  }
  if (diag) {
    diag->n_active = n_active;
    diag->n_entries = vc->n_pi;
    diag->residual_max = rmax;
    diag->residual_rms = n_active ? sqrt(r2 / (3.0 * (double)n_active)) : 0.0;
    double v = 0.0;
    for (int d = 0; d < 3; ++d) {
      diag->force_fem[d] = sf[d];
      diag->force_dem[d] = sp[d];
      v = fmax(v, fabs(sf[d] + sp[d]));
    }
    diag->eq41 = sabs > 0.0 ? v / sabs : 0.0;
    diag->work_fem = wf;
    diag->work_dem = wp;
  }
  return TL_OK;
}

TlStatus tl_vcoupling_resolution(TlVCoupling *vc, const double *xp, TlVCouplingResolution *res)
{
  if (!vc->updated) TL_ERROR(TL_ERR_STATE, "tl_vcoupling_update must run before the resolution check");
  const int nn = vc->nn;
  const size_t nc = vc->n_cnode;
  double *ix = vc->res_acc, *iw = ix + 3 * nc, *xde = iw + nc;
  memset(vc->res_acc, 0, 7 * nc * sizeof *vc->res_acc);
  /* X_i: int N_i x dV and int N_i dV over the row's coupled elements */
  TlQuadrature q;
  TL_CHECK(tl_element_quadrature(vc->type, vc->type->order_mass > 0 ? vc->type->order_mass : 3, &q));
  double *N = vc->scratch;
  for (size_t s = 0; s < vc->n_elem; ++s) {
    const double *x = vc->xe + s * nn * 3;
    for (int g = 0; g < q.n; ++g) {
      double J[3][3], detJ, xg[3];
      TL_CHECK(tl_element_jacobian(vc->type, 3, x, q.xi[g], J, &detJ));
      tl_element_interpolate(vc->type, x, q.xi[g], xg);
      vc->type->eval(1, q.xi[g], N, NULL);
      for (int k = 0; k < nn; ++k) {
        size_t i = vc->conn[s * nn + k];
        double wdv = q.w[g] * detJ * N[k];
        iw[i] += wdv;
        for (int d = 0; d < 3; ++d) ix[3 * i + d] += wdv * xg[d];
      }
    }
  }
  for (size_t j = 0; j < vc->n_pi; ++j)
    for (int d = 0; d < 3; ++d) xde[3 * vc->pi_node[j] + d] += vc->pi_val[j] * xp[3 * vc->pi_part[j] + d];
  memset(res, 0, sizeof *res);
  res->h = vc->h_elem;
  for (size_t i = 0; i < nc; ++i) {
    if (!vc->active[i] || !(iw[i] > 0.0)) continue;
    double b = 0.0, xr[3];
    for (int d = 0; d < 3; ++d) {
      xr[d] = ix[3 * i + d] / iw[i];
      b = fmax(b, fabs(xde[3 * i + d] - xr[d]));
    }
    if (!(b <= res->bias_max)) {
      res->bias_max = b;
      res->node = vc->cnode[i];
      for (int d = 0; d < 3; ++d) {
        res->x_de[d] = xde[3 * i + d];
        res->x_ref[d] = xr[d];
      }
    }
  }
  return TL_OK;
}

TlStatus tl_vcoupling_check_resolution(TlVCoupling *vc, const double *xp, double limit_fraction, long step,
                                       TlVCouplingResolution *out)
{
  if (!(limit_fraction > 0.0)) TL_ERROR(TL_ERR_ARG, "resolution limit %g (element sizes) must be > 0", limit_fraction);
  TlVCouplingResolution r;
  TL_CHECK(tl_vcoupling_resolution(vc, xp, &r));
  if (out) *out = r;
  if (!(r.bias_max <= limit_fraction * r.h))
    TL_ERROR(TL_ERR_UNSTABLE,
             "CG width c = %g m (%.3g element sizes) is beyond what the mesh resolves, at step %ld: node %zu takes "
             "its homogenised particle displacement from (%.4g, %.4g, %.4g), %.3g m (%.3g element sizes) from the "
             "centroid (%.4g, %.4g, %.4g) of its shape function, over the limit of %.3g element sizes (%.3g m), "
             "past which a node is tied to particles nearer its neighbour than itself. The kernel is cut off where "
             "the particles end; choose a smaller c",
             vc->c, vc->c / r.h, step, r.node, r.x_de[0], r.x_de[1], r.x_de[2], r.bias_max, r.bias_max / r.h,
             r.x_ref[0], r.x_ref[1], r.x_ref[2], limit_fraction, limit_fraction * r.h);
  return TL_OK;
}

TlStatus tl_vcoupling_homogenise(const TlVCoupling *vc, const double *q, double *out, char *reached)
{
  if (!vc->updated) TL_ERROR(TL_ERR_STATE, "tl_vcoupling_update must run before homogenising");
  /* element-local rows: the mean of the node's rows */
  for (size_t i = 0; i < vc->n_cnode; ++i) vc->hcount[vc->cnode[i]] = 0.0;
  for (size_t i = 0; i < vc->n_cnode; ++i) {
    size_t g = vc->cnode[i];
    if (reached) reached[g] = 0;
    if (vc->active[i]) {
      vc->hcount[g] += 1.0;
      for (int d = 0; d < 3; ++d) out[3 * g + d] = 0.0;
    }
  }
  for (size_t i = 0; i < vc->n_cnode; ++i)
    if (reached && vc->active[i]) reached[vc->cnode[i]] = 1;
  for (size_t j = 0; j < vc->n_pi; ++j) {
    size_t g = vc->cnode[vc->pi_node[j]], a = vc->pi_part[j];
    for (int d = 0; d < 3; ++d) out[3 * g + d] += vc->pi_val[j] * q[3 * a + d] / vc->hcount[g];
  }
  return TL_OK;
}

const double *tl_vcoupling_node_weights(const TlVCoupling *vc) { return vc->w_node; }

double tl_vcoupling_solid_weight(const TlVCoupling *vc, size_t e, const double xi[3])
{
  const TlElementBlock *B = &vc->mesh->blocks[vc->block];
  double N[TL_ELEMENT_MAX_NODES];
  vc->type->eval(1, xi, N, NULL);
  double w = 0.0;
  for (int a = 0; a < vc->nn; ++a) w += N[a] * vc->w_node[B->conn[e * vc->nn + a]];
  return 1.0 - w;
}

void tl_vcoupling_operator(const TlVCoupling *vc, size_t *n, const size_t **node, const size_t **particle,
                           const double **value)
{
  *n = vc->n_pi;
  *node = vc->pi_gnode;
  *particle = vc->pi_part;
  *value = vc->pi_val;
}

void tl_vcoupling_elements(const TlVCoupling *vc, size_t *n, const size_t **elements)
{
  *n = vc->n_elem;
  *elements = vc->elem;
}

const TlMesh *tl_vcoupling_mesh(const TlVCoupling *vc, int *block)
{
  if (block) *block = vc->block;
  return vc->mesh;
}

size_t tl_vcoupling_n_particles(const TlVCoupling *vc) { return vc->np; }

TlStatus tl_vcoupling_force_derivative(const TlVCoupling *vc, size_t slot, double *Kab, size_t *nodes)
{
  if (!vc->updated) TL_ERROR(TL_ERR_STATE, "tl_vcoupling_update must run before the force derivative");
  if (slot >= vc->n_elem) TL_ERROR(TL_ERR_ARG, "coupling element slot %zu outside [0, %zu)", slot, vc->n_elem);
  const int nn = vc->nn;
  const TlElementBlock *B = &vc->mesh->blocks[vc->block];
  const double *M = vc->Me + slot * nn * nn;
  const size_t *cn = vc->conn + slot * nn;
  for (int a = 0; a < nn; ++a) {
    nodes[a] = B->conn[vc->elem[slot] * nn + a];
    for (int b = 0; b < nn; ++b)
      Kab[a * nn + b] = vc->active[cn[a]] && vc->active[cn[b]] ? -vc->epsilon * M[a * nn + b] : 0.0;
  }
  return TL_OK;
}
