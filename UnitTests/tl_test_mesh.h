/* Test support for meshes: the checks that every boundary face's normal
 * points outward and that a named face set is flat with a given normal,
 * shared by the mesh tests. */
#ifndef TL_TEST_MESH_H
#define TL_TEST_MESH_H

#include <math.h>
#include "tl_mesh.h"
#include "tl_test.h"

/* Every boundary face's normal points away from its element's centroid;
 * returns the number of faces checked. */
static inline size_t check_outward(const TlMesh *m)
{
  size_t bad = 0;
  for (size_t i = 0; i < m->n_boundary; ++i) {
    TlFaceRef f = m->boundary[i];
    const TlElementType *t = m->blocks[f.block].type;
    double x[TL_ELEMENT_MAX_NODES * 3], fx[TL_ELEMENT_MAX_FACE_NODES * 3], c[3] = {0, 0, 0}, fc[3] = {0, 0, 0};
    tl_mesh_element_coords(m, f.block, f.element, x);
    tl_mesh_face_nodes(m, f, NULL, fx);
    for (int a = 0; a < t->n_corners; ++a)
      for (int k = 0; k < 3; ++k) c[k] += x[3 * a + k] / t->n_corners;
    for (int a = 0; a < t->face_type->n_corners; ++a)
      for (int k = 0; k < 3; ++k) fc[k] += fx[3 * a + k] / t->face_type->n_corners;
    double s[2] = {t->face_type->shape == TL_SHAPE_TRI ? 1.0 / 3 : 0.0, t->face_type->shape == TL_SHAPE_TRI ? 1.0 / 3 : 0.0};
    double n[3];
    tl_element_face_normal(t->face_type, m->dim, fx, s, n);
    double dot = 0.0;
    for (int k = 0; k < 3; ++k) dot += n[k] * (fc[k] - c[k]);
    bad += !(dot > 0.0);
  }
  TL_TEST_ASSERT(bad == 0, "%zu of %zu boundary faces have inward normals", bad, m->n_boundary);
  return m->n_boundary;
}

/* The normal of every face of set `name` is +-e_axis (sign). */
static inline void check_set_normal(const TlMesh *m, const char *name, int axis, double sign)
{
  const TlFaceSet *fs = NULL;
  TL_TEST_STATUS(tl_mesh_find_face_set(m, name, &fs), TL_OK);
  if (!fs) return;
  TL_TEST_ASSERT(fs->n > 0, "face set %s is empty", name);
  double worst = 0.0;
  for (size_t i = 0; i < fs->n; ++i) {
    const TlElementType *ft = m->blocks[fs->faces[i].block].type->face_type;
    double fx[TL_ELEMENT_MAX_FACE_NODES * 3], s[2] = {0.2, 0.1}, n[3];
    tl_mesh_face_nodes(m, fs->faces[i], NULL, fx);
    tl_element_face_normal(ft, m->dim, fx, s, n);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    worst = fmax(worst, fabs(n[axis] / len - sign));
  }
  TL_TEST_ASSERT(worst < 1e-12, "face set %s: normal deviates from %+g e_%d by %g", name, sign, axis, worst);
}

#endif
