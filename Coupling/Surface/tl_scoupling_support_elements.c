/* The element support of the surface coupling's CG kernel (c > 0): the
 * kernel normalised and integrated over the SCoupling elements'
 * integration points, each contact force spread over all the nodes of the
 * elements within reach (the code of the published S1 runs;
 * tl_scoupling_faces.h).  The items are the SCoupling elements. */
#include "tl_scoupling_private.h"

#include <stdint.h>

#include "tl_memory.h"

typedef struct {
  size_t n_vlocal;
  size_t *vnode;     /* local -> global node of the elements' nodes */
  int *elem_local;   /* n_elements x ne local node numbers */
  int ne;            /* nodes per element */
  TlVec3 *xv;        /* current positions of the local nodes */
  TlSCouplingVolumeType *vt;
  TlCGSurface *cg;   /* over the elements' integration points */
  TlVec3 *F;         /* n_elements x ne accumulated nodal forces */
  unsigned char *touched;
  size_t *list, n_touched; /* the elements holding forces, in the order first touched */
} Elements;

static void elements_destroy(TlSCoupling *sc)
{
  Elements *el = sc->support_data;
  if (!el) return;
  tl_cg_surface_destroy(&el->cg);
  tl_scoupling_volume_type_destroy(&el->vt);
  tl_free(&el->vnode);
  tl_free(&el->elem_local);
  tl_free(&el->xv);
  tl_free(&el->F);
  tl_free(&el->touched);
  tl_free(&el->list);
  tl_free(&sc->support_data);
  sc->cg_support = NULL;
}

/* Their nodes, one element type (refused otherwise, naming both), their
 * integration points. */
static TlStatus elements_setup(TlSCoupling *sc)
{
  const TlMesh *m = sc->mesh;
  const TlElementType *type = m->blocks[sc->elements[0].block].type;
  for (size_t e = 1; e < sc->n_elements; e++) {
    const TlElementType *t = m->blocks[sc->elements[e].block].type;
    if (t != type)
      TL_ERROR(TL_ERR_UNSUPPORTED, "element CG support needs one element type: SCoupling elements are %s and %s",
               type->header.name, t->header.name);
  }
  Elements *el = NULL;
  TL_CHECK(TL_NEW(el));
  sc->support_data = el;
  TL_CHECK(tl_scoupling_volume_type_create(type, &el->vt));
  if (type->n_nodes != type->n_corners) sc->bulge = sc->face_size;
  const int ne = el->ne = type->n_nodes;
  size_t *map = NULL;
  TL_CHECK(tl_calloc(&map, m->n_nodes, sizeof *map));
  for (size_t i = 0; i < m->n_nodes; i++) map[i] = SIZE_MAX;
  TlStatus s = TL_OK;
  if ((s = tl_calloc(&el->elem_local, sc->n_elements * (size_t)ne, sizeof *el->elem_local)) != TL_OK ||
      (s = tl_calloc(&el->vnode, sc->n_elements * (size_t)ne, sizeof *el->vnode)) != TL_OK)
    goto done;
  el->n_vlocal = 0;
  for (size_t e = 0; e < sc->n_elements; e++) {
    const size_t *conn = m->blocks[sc->elements[e].block].conn + sc->elements[e].element * (size_t)ne;
    for (int a = 0; a < ne; a++) {
      if (map[conn[a]] == SIZE_MAX) {
        map[conn[a]] = el->n_vlocal;
        el->vnode[el->n_vlocal++] = conn[a];
      }
      el->elem_local[e * (size_t)ne + (size_t)a] = (int)map[conn[a]];
    }
  }
  if ((s = tl_calloc(&el->xv, el->n_vlocal, sizeof *el->xv)) != TL_OK ||
      (s = tl_calloc(&el->F, sc->n_elements * (size_t)ne, sizeof *el->F)) != TL_OK ||
      (s = tl_calloc(&el->touched, sc->n_elements, 1)) != TL_OK ||
      (s = tl_calloc(&el->list, sc->n_elements, sizeof *el->list)) != TL_OK)
    goto done;
  for (size_t i = 0; i < el->n_vlocal; i++) {
    const double *X = m->x + 3 * el->vnode[i];
    el->xv[i] = tl_v3(X[0], X[1], X[2]);
  }
  s = tl_cg_surface_create_element_volumes(el->vt, el->n_vlocal, el->xv, sc->n_elements, el->elem_local, &el->cg);
  sc->cg_support = el->cg;
done:
  tl_free(&map);
  return s;
}

static void elements_move(TlSCoupling *sc, const double *u)
{
  Elements *el = sc->support_data;
  if (!el) return; /* the wall is placed before the support is set up */
  for (size_t i = 0; i < el->n_vlocal; i++) {
    const size_t n = el->vnode[i];
    const double *X = sc->mesh->x + 3 * n;
    el->xv[i] = u ? tl_v3(X[0] + u[3 * n], X[1] + u[3 * n + 1], X[2] + u[3 * n + 2]) : tl_v3(X[0], X[1], X[2]);
  }
}

static TlSCouplingForceSet element_set(const TlSCoupling *sc)
{
  Elements *el = sc->support_data;
  return (TlSCouplingForceSet){.item = "element", .n_items = sc->n_elements, .per_item = el->ne, .F = el->F,
                               .touched = el->touched, .list = el->list, .n_touched = &el->n_touched,
                               .local = el->elem_local, .node = el->vnode, .owner = NULL};
}

static TlStatus elements_spread(TlSCoupling *sc)
{
  Elements *el = sc->support_data;
  const size_t n0 = el->n_touched;
  TL_CHECK(tl_cg_surface_face_forces(el->cg, sc->kernel, sc->n_contacts, sc->c_elem, sc->c_point, sc->c_force, el->F,
                                     el->touched, el->list, &el->n_touched));
  const TlSCouplingForceSet fs = element_set(sc);
  tl_scoupling_activate_touched(sc, &fs, n0);
  return TL_OK;
}

static void elements_element_load(const TlSCoupling *sc, size_t e, double *f_nodes)
{
  const TlSCouplingForceSet fs = element_set(sc);
  if (fs.touched[e]) tl_scoupling_add_item(&fs, e, f_nodes);
}

const TlSCouplingSupportOps tl_scoupling_support_elements = {
    .header = {"scoupling_support", "elements", "CG kernel over the SCoupling elements' integration points"},
    .id = TL_SCOUPLING_SUPPORT_ELEMENTS,
    .setup = elements_setup,
    .destroy = elements_destroy,
    .move = elements_move,
    .spread = elements_spread,
    .element_load = elements_element_load,
    .forces = element_set,
};
