/* The surface support of the surface coupling's CG kernel: Eq. 15 as
 * printed, the kernel normalised and integrated over the coupled faces
 * (and, with the Dirac kernel, the point-source limit of Eq. 16).  The
 * items are the coupled faces; their forces are the coupling's per-face
 * forces (tl_scoupling_face_forces). */
#include "tl_scoupling_private.h"

#include <string.h>

static TlStatus surface_setup(TlSCoupling *sc)
{
  sc->cg_support = sc->cg;
  return TL_OK;
}

static void surface_destroy(TlSCoupling *sc) { (void)sc; }

/* The owners of the faces touched since position n0 of the list become
 * active (in the order their faces were first touched). */
static void activate_faces(TlSCoupling *sc, size_t n0)
{
  for (size_t t = n0; t < sc->n_touched; t++) tl_scoupling_activate_element(sc, sc->face_element[sc->touched_faces[t]]);
}

static TlStatus surface_spread(TlSCoupling *sc)
{
  const size_t n0 = sc->n_touched;
  TL_CHECK(tl_cg_surface_face_forces(sc->cg, sc->kernel, sc->n_contacts, sc->c_face, sc->c_point, sc->c_force,
                                     sc->face_F, sc->face_touched, sc->touched_faces, &sc->n_touched));
  activate_faces(sc, n0);
  return TL_OK;
}

static void surface_clear(TlSCoupling *sc)
{
  const size_t nf = (size_t)sc->nf;
  for (size_t t = 0; t < sc->n_touched; t++) {
    const size_t f = sc->touched_faces[t];
    memset(sc->face_F + f * nf, 0, nf * sizeof *sc->face_F);
    sc->face_touched[f] = 0;
  }
  sc->n_touched = 0;
}

static void add_face(const TlSCoupling *sc, size_t face, double *f_nodes)
{
  const size_t nf = (size_t)sc->nf;
  const int *q = sc->face_local + face * nf;
  const TlVec3 *F = sc->face_F + face * nf;
  for (size_t a = 0; a < nf; a++) {
    double *f = f_nodes + 3 * sc->node[q[a]];
    f[0] += F[a].x;
    f[1] += F[a].y;
    f[2] += F[a].z;
  }
}

static void surface_element_load(const TlSCoupling *sc, size_t e, double *f_nodes)
{
  for (size_t j = sc->elem_face_ptr[e]; j < sc->elem_face_ptr[e + 1]; j++)
    if (sc->face_touched[sc->elem_face[j]]) add_face(sc, sc->elem_face[j], f_nodes);
}

static void surface_assemble(const TlSCoupling *sc, double *f_nodes)
{
  for (size_t t = 0; t < sc->n_touched; t++) add_face(sc, sc->touched_faces[t], f_nodes);
}

static TlSCouplingForceSet face_set(const TlSCoupling *sc)
{
  return (TlSCouplingForceSet){"face", sc->n_faces, sc->nf, sc->face_F, sc->face_touched, sc->touched_faces,
                               (size_t *)&sc->n_touched};
}

static TlStatus surface_save(const TlSCoupling *sc, TlCheckpointWriter *w, const char *group, const char *prefix)
{
  const TlSCouplingForceSet fs = face_set(sc);
  return tl_scoupling_save_force_set(&fs, w, group, prefix);
}

static TlStatus surface_load(TlSCoupling *sc, TlCheckpointReader *r, const char *group, const char *prefix)
{
  const TlSCouplingForceSet fs = face_set(sc);
  TL_CHECK(tl_scoupling_load_force_set(&fs, r, group, prefix));
  activate_faces(sc, 0);
  return TL_OK;
}

const TlSCouplingSupportOps tl_scoupling_support_surface = {
    .header = {"scoupling_support", "surface", "CG kernel over the coupled faces (Eq. 15; Eq. 16 for c = 0)"},
    .id = TL_SCOUPLING_SUPPORT_SURFACE,
    .setup = surface_setup,
    .destroy = surface_destroy,
    .spread = surface_spread,
    .clear = surface_clear,
    .element_load = surface_element_load,
    .assemble = surface_assemble,
    .save = surface_save,
    .load = surface_load,
};
