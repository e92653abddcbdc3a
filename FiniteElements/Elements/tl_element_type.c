/* Element types in the registry: the checks a type's table must pass, its
 * registration, and look-up by name and by Gmsh code (the Gmsh reader finds
 * every type through here, so a type registered from outside the library
 * is read from files too). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_element.h"
#include "tl_registry.h"

/* The centroid of the reference element. */
static void reference_centroid(const TlElementType *t, double c[3])
{
  c[0] = c[1] = c[2] = 0.0;
  if (t->shape == TL_SHAPE_TRI || t->shape == TL_SHAPE_TET)
    for (int d = 0; d < t->dim; ++d) c[d] = 1.0 / (t->dim + 1);
}

static TlStatus check_shape_functions(const TlElementType *t)
{
  const char *name = t->header.name;
  int nn = t->n_nodes, dim = t->dim;
  double xi[3], N[TL_ELEMENT_MAX_NODES], dN[TL_ELEMENT_MAX_NODES * 3];
  for (int b = 0; b < nn; ++b) {
    xi[0] = xi[1] = xi[2] = 0.0;
    for (int d = 0; d < dim; ++d) xi[d] = t->ref_coords[b * dim + d];
    t->eval(1, xi, N, dN);
    for (int a = 0; a < nn; ++a)
      if (fabs(N[a] - (a == b)) > 1e-12)
        TL_ERROR(TL_ERR_ARG, "element type %s: N_%d at node %d is %.3g, expected %d", name, a, b, N[a], a == b);
    for (int d = 0; d < dim; ++d) {
      double sum = 0.0;
      for (int a = 0; a < nn; ++a) sum += dN[a * dim + d];
      if (fabs(sum) > 1e-11)
        TL_ERROR(TL_ERR_ARG, "element type %s: sum of dN/dxi_%d at node %d is %.3g, expected 0", name, d, b, sum);
    }
  }
  return TL_OK;
}

/* Each face's normal at its centre points away from the element's centre
 * (the reference element taken as the physical one). */
static TlStatus check_faces(const TlElementType *t)
{
  const char *name = t->header.name;
  const TlElementType *ft = t->face_type;
  if (t->n_faces < 0 || t->n_faces > TL_ELEMENT_MAX_FACES)
    TL_ERROR(TL_ERR_ARG, "element type %s: %d faces, outside [0, %d]", name, t->n_faces, TL_ELEMENT_MAX_FACES);
  if (t->face_n_nodes < 0 || t->face_n_nodes > TL_ELEMENT_MAX_FACE_NODES)
    TL_ERROR(TL_ERR_ARG, "element type %s: %d nodes per face, outside [0, %d]", name, t->face_n_nodes,
             TL_ELEMENT_MAX_FACE_NODES);
  if (t->n_faces > 0 && !t->face_nodes) TL_ERROR(TL_ERR_ARG, "element type %s: no face node lists", name);
  for (int k = 0; k < t->n_faces * t->face_n_nodes; ++k)
    if (t->face_nodes[k] < 0 || t->face_nodes[k] >= t->n_nodes)
      TL_ERROR(TL_ERR_ARG, "element type %s: face %d node %d is %d, outside [0, %d)", name, k / t->face_n_nodes,
               k % t->face_n_nodes, t->face_nodes[k], t->n_nodes);
  if (t->dim == 1) return TL_OK;
  if (!ft) TL_ERROR(TL_ERR_ARG, "element type %s of dimension %d has no face type", name, t->dim);
  if (ft->dim != t->dim - 1 || ft->n_nodes != t->face_n_nodes)
    TL_ERROR(TL_ERR_ARG, "element type %s: face type %s has dimension %d and %d nodes, expected %d and %d", name,
             ft->header.name, ft->dim, ft->n_nodes, t->dim - 1, t->face_n_nodes);
  double centre[3], fc[3] = {0, 0, 0};
  reference_centroid(t, centre);
  reference_centroid(ft, fc);
  for (int f = 0; f < t->n_faces; ++f) {
    double x[TL_ELEMENT_MAX_FACE_NODES * 3] = {0}, n_dA[3], xi[3];
    for (int k = 0; k < ft->n_nodes; ++k)
      for (int d = 0; d < t->dim; ++d) x[3 * k + d] = t->ref_coords[t->face_nodes[f * t->face_n_nodes + k] * t->dim + d];
    tl_element_face_normal(ft, t->dim, x, fc, n_dA);
    tl_element_face_to_element(t, f, fc, xi);
    double out = 0.0;
    for (int d = 0; d < t->dim; ++d) out += n_dA[d] * (xi[d] - centre[d]);
    if (!(out > 0.0))
      TL_ERROR(TL_ERR_ARG, "element type %s: face %d is oriented inward (list its nodes the other way round)", name, f);
  }
  return TL_OK;
}

TlStatus tl_element_type_check(const TlElementType *t)
{
  if (!t) TL_ERROR(TL_ERR_ARG, "tl_element_type_check: NULL type");
  const char *name = t->header.name ? t->header.name : "(unnamed)";
  if (!t->header.kind || strcmp(t->header.kind, "element") || !t->header.name || !t->header.name[0])
    TL_ERROR(TL_ERR_ARG, "element type %s: header kind '%s' must be \"element\" and the name non-empty", name,
             t->header.kind ? t->header.kind : "(null)");
  if (t->dim < 1 || t->dim > 3) TL_ERROR(TL_ERR_ARG, "element type %s: dimension %d outside [1, 3]", name, t->dim);
  static const int shape_dim[] = {[TL_SHAPE_LINE] = 1, [TL_SHAPE_QUAD] = 2, [TL_SHAPE_HEX] = 3,
                                  [TL_SHAPE_TRI] = 2, [TL_SHAPE_TET] = 3};
  if ((int)t->shape < 0 || t->shape > TL_SHAPE_TET || shape_dim[t->shape] != t->dim)
    TL_ERROR(TL_ERR_ARG, "element type %s: reference shape %d does not have dimension %d", name, (int)t->shape,
             t->dim);
  if (t->n_nodes < 1 || t->n_nodes > TL_ELEMENT_MAX_NODES)
    TL_ERROR(TL_ERR_ARG, "element type %s: %d nodes, outside [1, %d]", name, t->n_nodes, TL_ELEMENT_MAX_NODES);
  if (t->n_corners < 1 || t->n_corners > t->n_nodes)
    TL_ERROR(TL_ERR_ARG, "element type %s: %d corners, outside [1, %d nodes]", name, t->n_corners, t->n_nodes);
  if (t->linear && t->n_corners != t->n_nodes)
    TL_ERROR(TL_ERR_ARG, "element type %s is marked linear but has %d nodes and %d corners", name, t->n_nodes,
             t->n_corners);
  if (!t->ref_coords || !t->eval) TL_ERROR(TL_ERR_ARG, "element type %s: no reference coordinates or eval", name);
  if (t->order_stiffness < 1 || t->order_stiffness > 5 || t->order_mass < 1 || t->order_mass > 5)
    TL_ERROR(TL_ERR_ARG, "element type %s: quadrature orders %d (stiffness), %d (mass) outside [1, 5]", name,
             t->order_stiffness, t->order_mass);
  TL_CHECK(check_shape_functions(t));
  TL_CHECK(check_faces(t));
  if (t->output) {
    int nc = tl_cell_type_nodes(t->output->cell);
    if (nc != t->n_nodes)
      TL_ERROR(TL_ERR_ARG, "element type %s (%d nodes) is drawn as cell %s of %d nodes", name, t->n_nodes,
               tl_cell_type_name(t->output->cell), nc);
    if (t->output->order) {
      int seen[TL_ELEMENT_MAX_NODES] = {0};
      for (int k = 0; k < t->n_nodes; ++k) {
        int a = t->output->order[k];
        if (a < 0 || a >= t->n_nodes || seen[a]++)
          TL_ERROR(TL_ERR_ARG, "element type %s: output order entry %d is %d, not a permutation of [0, %d)", name,
                   k, a, t->n_nodes);
      }
    }
  }
  return TL_OK;
}

TlStatus tl_element_type_register(const TlElementType *type)
{
  TL_CHECK(tl_element_type_check(type));
  TL_CHECK(tl_registry_add(&type->header));
  return TL_OK;
}

TlStatus tl_element_type_find(const char *name, const TlElementType **type)
{
  const TlOpsHeader *h = NULL;
  TL_CHECK(tl_registry_find("element", name, &h));
  *type = (const TlElementType *)h;
  return TL_OK;
}

TlStatus tl_element_type_find_gmsh(int gmsh_type, const TlElementType **type)
{
  enum { MAX_TYPES = 256 };
  const char *names[MAX_TYPES];
  size_t n = tl_registry_list("element", names, MAX_TYPES);
  if (n > MAX_TYPES) n = MAX_TYPES;
  char codes[1024] = "";
  *type = NULL;
  for (size_t i = 0; i < n; ++i) {
    const TlElementType *t = NULL;
    TL_CHECK(tl_element_type_find(names[i], &t));
    if (t->gmsh_type == gmsh_type && gmsh_type > 0) {
      *type = t;
      return TL_OK;
    }
    if (t->gmsh_type > 0)
      snprintf(codes + strlen(codes), sizeof codes - strlen(codes), " %d (%s)", t->gmsh_type, t->header.name);
  }
  TL_ERROR(TL_ERR_NOT_FOUND, "no element type with Gmsh code %d is registered (registered:%s)", gmsh_type,
           n ? codes : " none; call tl_initialize() first");
}

TlStatus tl_element_register_all(void)
{
  static const TlElementType *const builtin[] = {
      &tl_element_line2, &tl_element_line3, &tl_element_tri3, &tl_element_tri6,  &tl_element_quad4, &tl_element_quad8,
      &tl_element_quad9, &tl_element_tet4,  &tl_element_tet10, &tl_element_hex8, &tl_element_hex27};
  for (size_t i = 0; i < sizeof builtin / sizeof builtin[0]; ++i) TL_CHECK(tl_element_type_register(builtin[i]));
  return TL_OK;
}
