/* The surface support of the surface coupling's CG kernel: Eq. 15 as
 * printed, the kernel normalised and integrated over the coupled faces
 * (and, with the Dirac kernel, the point-source limit of Eq. 16).  The
 * items are the coupled faces; their forces are the coupling's per-face
 * forces (tl_scoupling_face_forces). */
#include "tl_scoupling_private.h"

static TlStatus surface_setup(TlSCoupling *sc)
{
  sc->cg_support = sc->cg;
  return TL_OK;
}

static void surface_destroy(TlSCoupling *sc) { (void)sc; }

static TlSCouplingForceSet face_set(const TlSCoupling *sc)
{
  return (TlSCouplingForceSet){.item = "face", .n_items = sc->n_faces, .per_item = sc->nf, .F = sc->face_F,
                               .touched = sc->face_touched, .list = sc->touched_faces,
                               .n_touched = (size_t *)&sc->n_touched, .local = sc->face_local, .node = sc->node,
                               .owner = sc->face_element};
}

static TlStatus surface_spread(TlSCoupling *sc)
{
  const size_t n0 = sc->n_touched;
  TL_CHECK(tl_cg_surface_face_forces(sc->cg, sc->kernel, sc->n_contacts, sc->c_face, sc->c_point, sc->c_force,
                                     sc->face_F, sc->face_touched, sc->touched_faces, &sc->n_touched));
  const TlSCouplingForceSet fs = face_set(sc);
  tl_scoupling_activate_touched(sc, &fs, n0);
  return TL_OK;
}

static void surface_element_load(const TlSCoupling *sc, size_t e, double *f_nodes)
{
  const TlSCouplingForceSet fs = face_set(sc);
  for (size_t j = sc->elem_face_ptr[e]; j < sc->elem_face_ptr[e + 1]; j++)
    if (sc->face_touched[sc->elem_face[j]]) tl_scoupling_add_item(&fs, sc->elem_face[j], f_nodes);
}

const TlSCouplingSupportOps tl_scoupling_support_surface = {
    .header = {"scoupling_support", "surface", "CG kernel over the coupled faces (Eq. 15; Eq. 16 for c = 0)"},
    .id = TL_SCOUPLING_SUPPORT_SURFACE,
    .setup = surface_setup,
    .destroy = surface_destroy,
    .spread = surface_spread,
    .element_load = surface_element_load,
    .forces = face_set,
};
