/* The C face of the CGAL shim tl_mesh_from_surface_cgal.cpp (private to
 * tl_mesh_from_surface.c; compiled only with TALUS_WITH_CGAL).  Functions
 * return 0 on success, -1 with a message in msg otherwise; arrays they
 * return are malloc'ed and freed by the caller with free(). */
#ifndef TL_MESH_FROM_SURFACE_CGAL_H
#define TL_MESH_FROM_SURFACE_CGAL_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  size_t n_vertices;
  const double *x;
  size_t n_triangles;
  const size_t *tri;
} TlCgalSurface;

typedef struct {
  double cell_size, facet_size, facet_distance, facet_angle, radius_edge, edge_size, feature_angle;
  int exude;
  unsigned seed;
} TlCgalMeshCriteria;

typedef struct {
  size_t n_nodes, n_tets;
  double *x;     /* 3 n_nodes */
  size_t *tets;  /* 4 n_tets, CGAL's cell vertex order (positively oriented) */
} TlCgalTetMesh;

/* *n_pairs = number of intersecting triangle pairs; pair = the first. */
int tl_cgal_self_intersection(const TlCgalSurface *s, size_t pair[2], size_t *n_pairs, char *msg,
                              size_t msg_len);
int tl_cgal_mesh_3(const TlCgalSurface *s, const TlCgalMeshCriteria *c, TlCgalTetMesh *out, char *msg,
                   size_t msg_len);

#ifdef __cplusplus
}
#endif

#endif
