/* The VCoupling element type: the solid side of the volume coupling as a
 * wrapper over the element block (seeds/001 §5.3.2, Eqs. 26 and 31). */
#include "tl_vcoupling_element.h"

#include <math.h>
#include <string.h>

#include "tl_memory.h"

struct TlVCouplingElement {
  TlVCoupling *vc;
  TlSolid *solid;
  int block;
  size_t n_nodes;
  TlSolidWrapper *wrapper;  /* the element type over the block */
  double *w_solid;          /* n_nodes: 1 - w_i */
  double *du_p, *u_start;   /* the step's data */
  size_t cap_p, np;
  double *du_n, *F;         /* 3 n_nodes scratch */
  double *Ke;               /* (3 nn)^2 */
  double *Kab;              /* nn^2 */
  size_t *nodes;            /* nn */
  int nn;
  int active;               /* set_step called since the last clear */
  int lagged;               /* the mismatch fixed before the step (set_step_lagged) */
  double *du_fixed;         /* 3 n_nodes: its solid displacements */
};

/* After the weighted elements of the block: -F (the coupling force on the
 * solid, in the residual f_int - f_ext) and its derivative +eps M in the
 * tangent, inside every evaluation (the penalty depends on the iterate). */
static TlStatus vcoupling_terms(void *ctx, TlSolid *solid, int b, double t, const double *u_nodes, double *f_nodes,
                                double c_u, TlSparse *K, double *W)
{
  (void)b, (void)t, (void)W;
  TlVCouplingElement *el = ctx;
  if (!el->active) return TL_OK;
  if (f_nodes) {
    memset(el->F, 0, 3 * el->n_nodes * sizeof *el->F);
    TL_CHECK(tl_vcoupling_element_nodal_forces(el, u_nodes, el->F));
    for (size_t k = 0; k < 3 * el->n_nodes; ++k) f_nodes[k] -= el->F[k];
  }
  if (K && !el->lagged) { /* a lagged force does not depend on the iterate */
    size_t n_elem;
    const size_t *elements;
    tl_vcoupling_elements(el->vc, &n_elem, &elements);
    const int nn = el->nn, nd = 3 * nn;
    for (size_t s = 0; s < n_elem; ++s) {
      TL_CHECK(tl_vcoupling_force_derivative(el->vc, s, el->Kab, el->nodes));
      memset(el->Ke, 0, (size_t)nd * nd * sizeof *el->Ke);
      for (int a = 0; a < nn; ++a)
        for (int q = 0; q < nn; ++q)
          for (int i = 0; i < 3; ++i) el->Ke[(3 * a + i) * nd + 3 * q + i] = -el->Kab[a * nn + q];
      TL_CHECK(tl_solid_matrix_add_nodes(solid, K, nn, el->nodes, c_u, el->Ke));
    }
  }
  return TL_OK;
}

static const TlSolidWrapperOps vcoupling_element_ops = {
    .header = {"solid_wrapper", "vcoupling", "VCoupling element: the volume coupling's penalty on its elements"},
    .internal = vcoupling_terms,
};

static void free_arrays(TlVCouplingElement *el)
{
  tl_free(&el->w_solid);
  tl_free(&el->du_p);
  tl_free(&el->u_start);
  tl_free(&el->du_n);
  tl_free(&el->du_fixed);
  tl_free(&el->F);
  tl_free(&el->Ke);
  tl_free(&el->Kab);
  tl_free(&el->nodes);
}

TlStatus tl_vcoupling_element_create(TlVCoupling *vc, TlSolid *solid, TlVCouplingElement **out)
{
  *out = NULL;
  if (!vc || !solid) TL_ERROR(TL_ERR_ARG, "VCoupling element: NULL coupling or solid");
  int block;
  const TlMesh *mesh = tl_vcoupling_mesh(vc, &block);
  if (tl_solid_mesh(solid) != mesh)
    TL_ERROR(TL_ERR_ARG, "VCoupling element: the solid is built on another mesh than the coupling");
  if (mesh->dim != 3) TL_ERROR(TL_ERR_ARG, "VCoupling element: the mesh is %d-D, the coupling 3-D", mesh->dim);
  TlVCouplingElement *el;
  TL_CHECK(TL_NEW(el));
  TlStatus s = TL_OK;
  el->vc = vc;
  el->solid = solid;
  el->block = block;
  el->n_nodes = mesh->n_nodes;
  el->nn = mesh->blocks[block].type->n_nodes;
  const double *w = tl_vcoupling_node_weights(vc);
  TL_CHECK_GOTO(s, tl_calloc(&el->w_solid, el->n_nodes, sizeof *el->w_solid), fail);
  for (size_t i = 0; i < el->n_nodes; ++i) el->w_solid[i] = 1.0 - w[i];
  TL_CHECK_GOTO(s, tl_calloc(&el->u_start, 3 * el->n_nodes, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&el->du_n, 3 * el->n_nodes, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&el->du_fixed, 3 * el->n_nodes, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&el->F, 3 * el->n_nodes, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&el->Ke, (size_t)9 * el->nn * el->nn, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&el->Kab, (size_t)el->nn * el->nn, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&el->nodes, (size_t)el->nn, sizeof(size_t)), fail);
  TL_CHECK_GOTO(s, tl_solid_set_node_weights(solid, block, el->w_solid), fail);
  TL_CHECK_GOTO(s, tl_solid_add_wrapper(solid, block, &vcoupling_element_ops, el, &el->wrapper), fail);
  *out = el;
  return TL_OK;
fail:
  free_arrays(el);
  tl_free(&el);
  return s;
}

void tl_vcoupling_element_destroy(TlVCouplingElement **pel)
{
  TlVCouplingElement *el = *pel;
  if (!el) return;
  tl_solid_remove_wrapper(el->solid, &el->wrapper);
  free_arrays(el);
  tl_free(pel);
}

TlStatus tl_vcoupling_element_set_step(TlVCouplingElement *el, const double *du_p, const double *u_start)
{
  size_t np = tl_vcoupling_n_particles(el->vc);
  if (np && !du_p) TL_ERROR(TL_ERR_ARG, "VCoupling element: no particle displacements for %zu particles", np);
  TL_CHECK(tl_array_reserve(&el->du_p, &el->cap_p, 3 * (np ? np : 1), sizeof *el->du_p));
  if (np) memcpy(el->du_p, du_p, 3 * np * sizeof *el->du_p);
  if (u_start) memcpy(el->u_start, u_start, 3 * el->n_nodes * sizeof *el->u_start);
  else memset(el->u_start, 0, 3 * el->n_nodes * sizeof *el->u_start);
  el->np = np;
  el->active = 1;
  el->lagged = 0;
  return TL_OK;
}

TlStatus tl_vcoupling_element_set_step_lagged(TlVCouplingElement *el, const double *du_p, const double *du_n)
{
  if (!du_n) TL_ERROR(TL_ERR_ARG, "VCoupling element: no solid displacements for the lagged mismatch");
  TL_CHECK(tl_vcoupling_element_set_step(el, du_p, NULL));
  memcpy(el->du_fixed, du_n, 3 * el->n_nodes * sizeof *el->du_fixed);
  el->lagged = 1;
  return TL_OK;
}

void tl_vcoupling_element_clear(TlVCouplingElement *el) { el->active = 0; }

static TlStatus step_increment(TlVCouplingElement *el, const double *u_nodes)
{
  if (!el->active) TL_ERROR(TL_ERR_STATE, "VCoupling element: tl_vcoupling_element_set_step must come first");
  if (tl_vcoupling_n_particles(el->vc) != el->np)
    TL_ERROR(TL_ERR_STATE, "VCoupling element: the step holds %zu particles, the coupling's last update %zu", el->np,
             tl_vcoupling_n_particles(el->vc));
  if (el->lagged) memcpy(el->du_n, el->du_fixed, 3 * el->n_nodes * sizeof *el->du_n);
  else
    for (size_t k = 0; k < 3 * el->n_nodes; ++k) el->du_n[k] = u_nodes[k] - el->u_start[k];
  return TL_OK;
}

TlStatus tl_vcoupling_element_nodal_forces(TlVCouplingElement *el, const double *u_nodes, double *f_nodes)
{
  TL_CHECK(step_increment(el, u_nodes));
  TL_CHECK(tl_vcoupling_forces(el->vc, el->du_p, el->du_n, f_nodes, NULL, NULL));
  return TL_OK;
}

TlStatus tl_vcoupling_element_particle_forces(TlVCouplingElement *el, const double *u_nodes, double *f_particles,
                                              TlVCouplingDiag *diag)
{
  TL_CHECK(step_increment(el, u_nodes));
  TL_CHECK(tl_vcoupling_forces(el->vc, el->du_p, el->du_n, NULL, f_particles, diag));
  return TL_OK;
}

const double *tl_vcoupling_element_weights(const TlVCouplingElement *el) { return el->w_solid; }
