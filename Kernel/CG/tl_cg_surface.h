/* Surface-restricted CG kernels for surface coupling (seeds/001 §5.1.2).
 *
 * A surface is a set of faces (triangles, quadrilaterals, or any face type
 * of the finite-element module) sharing nodes.  Each face carries a
 * quadrature: points x_q, weights w_q (area element included) and the
 * values N_qa of its nodes' shape functions.  The kernel W restricted to the
 * surface is normalised through that quadrature, as Eq. 15 prescribes:
 *
 *   W_G(x_q - x^c) = W(|x_q - x^c|) / sum_q' w_q' W(|x_q' - x^c|)
 *
 * so that sum_q w_q W_G = 1 exactly for every contact point, on a face, an
 * edge or a corner, and on a surface that deforms (the quadrature follows
 * the nodes).  The traction of Eq. 14 at the quadrature points and the nodal
 * forces of Eq. 15,
 *
 *   F_i = sum_contacts -f^w sum_q w_q N_qi W_G(x_q - x^c),
 *
 * therefore sum to minus the contact forces to round-off (shape functions
 * form a partition of unity).  The c = 0 limit (Dirac kernel) is Eq. 16 in
 * closed form: F_i = -f^w N_i(x^c) with the shape functions of the contact's
 * face at the contact point.
 *
 * Signs: f^w is the force on the particle from the wall, as in Eqs. 12-16;
 * the nodal forces are those acting on the surface (-f^w distributed).
 *
 * A new face type plugs in through TlCGSurfaceOps: fill the quadrature of
 * all faces from the current node positions (one call per surface), and
 * evaluate the shape functions at points of given faces (one call per batch
 * of contacts).  Built-in: linear triangles and bilinear quadrilaterals, each
 * face's reference domain split into s x s sub-cells with a fixed rule on
 * each (degree 4, 6 points, on triangles; 3 x 3 Gauss on quadrilaterals),
 * so a narrow kernel can be resolved by raising s.
 *
 * A contact visits only the faces near it: faces are binned by the centre
 * of their bounding boxes (cells as wide as the widest face) at every
 * update.  The per-call scratch lives in the surface, so one surface is
 * used by one thread at a time; nothing is allocated after creation except
 * when the bins outgrow their buffer after a large deformation. */
#ifndef TL_CG_SURFACE_H
#define TL_CG_SURFACE_H

#include <stddef.h>
#include "tl_cg_kernel.h"
#include "tl_error.h"
#include "tl_math.h"
#include "tl_object.h"

#define TL_CG_SURFACE_KIND "cg_surface"

typedef struct TlCGSurface TlCGSurface;

typedef struct {
  TlOpsHeader header;
  /* For the faces faces[k], k < n (NULL: faces 0 .. n-1), and each point q
   * (slot f * qp_per_face + q): position, weight (with the area element)
   * and the shape values of the face's nodes (Nq[slot * nodes_per_face +
   * a]), from the node positions s->x. */
  TlStatus (*quadrature)(const TlCGSurface *s, size_t n, const size_t *faces, TlVec3 *xq, double *wq, double *Nq);
  /* Shape values of the nodes of face[k] at point[k] (projected onto the
   * face), for k < n: N[k * nodes_per_face + a]. */
  TlStatus (*shape_at)(const TlCGSurface *s, size_t n, const size_t *face, const TlVec3 *point, double *N);
} TlCGSurfaceOps;

struct TlCGSurface {
  const TlCGSurfaceOps *ops;
  size_t n_nodes, n_faces;
  int nodes_per_face, qp_per_face;
  int subdivisions;    /* built-in types: sub-cells per reference direction */
  int *face_node;      /* n_faces x nodes_per_face (copied) */
  const TlVec3 *x;     /* node positions, borrowed; refreshed by update */
  void *context;       /* user data of a plugged-in face type */
  /* quadrature, recomputed by tl_cg_surface_update */
  TlVec3 *xq;
  double *wq, *Nq;
  TlVec3 *face_lo, *face_hi; /* bounding box of each face's points and nodes */
};

/* A surface of any face type given by its ops.  x: n_nodes positions
 * (borrowed; the caller keeps them alive and calls update when they move). */
TlStatus tl_cg_surface_create(const TlCGSurfaceOps *ops, size_t n_nodes, const TlVec3 *x, size_t n_faces,
                              int nodes_per_face, const int *face_node, int qp_per_face, void *context,
                              TlCGSurface **surface);
/* Linear triangles (3 nodes per face, counter-clockwise). */
TlStatus tl_cg_surface_create_triangles(size_t n_nodes, const TlVec3 *x, size_t n_faces, const int *tri,
                                        int subdivisions, TlCGSurface **surface);
/* Bilinear quadrilaterals (4 nodes per face, counter-clockwise). */
TlStatus tl_cg_surface_create_quads(size_t n_nodes, const TlVec3 *x, size_t n_faces, const int *quad,
                                    int subdivisions, TlCGSurface **surface);
void tl_cg_surface_destroy(TlCGSurface **surface);
/* New node positions (or NULL: same array, moved in place); recomputes the
 * quadrature.  Refuses non-finite positions and non-positive weights. */
TlStatus tl_cg_surface_update(TlCGSurface *s, const TlVec3 *x);
/* The same for the faces whose nodes' box lies within `reach` of one of n
 * points (contact points; reach = the kernel's width plus the largest
 * bulge of a face beyond its nodes' box), in place: the next evaluations
 * for contacts at those points see only these faces, exactly as after a
 * full update up to the order of summation.  A coupling whose particles
 * touch a small part of a large surface pays O(faces near them). */
TlStatus tl_cg_surface_update_near(TlCGSurface *s, size_t n, const TlVec3 *points, double reach);

/* Normalised weights of one contact point: weight[k] = w_q W_G(x_q - x^c)
 * for the quadrature slots slot[k], k < *count, summing to 1.  Up to max
 * entries; an error names the count needed if more.  Not for the Dirac
 * kernel (use tl_cg_surface_nodal_forces, which takes Eq. 16). */
TlStatus tl_cg_surface_weights(const TlCGSurface *s, const TlCGKernel *k, TlVec3 point, size_t max,
                               size_t *count, size_t *slot, double *weight);
/* Eq. 15 (or Eq. 16 for the Dirac kernel) per face: for n contacts,
 * contact k on face[k] at point[k] with force f_wall[k] on the particle,
 * adds to face_nodal[f * nodes_per_face + a] (n_faces x nodes_per_face, not
 * cleared) the integral over face f of N_a t dA, the face's share of the
 * element residual of the SCoupling element owning it.  With c > 0 every
 * face whose quadrature meets the kernel receives its share, for c = 0 the
 * contact's face alone.  face_touched (n_faces flags, may be NULL) gets 1
 * for every face that received a contribution; when touched is given too,
 * each face flagged here for the first time is appended at
 * touched[(*n_touched)++] (flags already set are the caller's: it clears
 * them with the forces).  face[] is needed by the Dirac kernel only (may be
 * NULL otherwise). */
TlStatus tl_cg_surface_face_forces(const TlCGSurface *s, const TlCGKernel *k, size_t n, const size_t *face,
                                   const TlVec3 *point, const TlVec3 *f_wall, TlVec3 *face_nodal,
                                   unsigned char *face_touched, size_t *touched, size_t *n_touched);
/* Adds the per-face forces of faces[k], k < n (NULL: faces 0 .. n-1), to
 * the nodes: nodal[face_node[f][a]] += face_nodal[f][a]. */
void tl_cg_surface_assemble_faces(const TlCGSurface *s, size_t n, const size_t *faces, const TlVec3 *face_nodal,
                                  TlVec3 *nodal);
/* Adds Eq. 15 (or Eq. 16) for n contacts to nodal (n_nodes entries, not
 * cleared): tl_cg_surface_face_forces assembled over the touched faces. */
TlStatus tl_cg_surface_nodal_forces(const TlCGSurface *s, const TlCGKernel *k, size_t n, const size_t *face,
                                    const TlVec3 *point, const TlVec3 *f_wall, TlVec3 *nodal);
/* Adds the traction of Eq. 14 at every quadrature point (n_faces *
 * qp_per_face entries, not cleared).  Not for the Dirac kernel. */
TlStatus tl_cg_surface_traction(const TlCGSurface *s, const TlCGKernel *k, size_t n, const TlVec3 *point,
                                const TlVec3 *f_wall, TlVec3 *traction);

/* CG-enriched homogenisation (seeds/001 Eq. 18): for one particle at
 * `point`, out[a] += scale * sum_q w_q W(x_q - point) N_qa over the
 * quadrature of one element (n_qp points x_q, weights w_q with the volume
 * element, shape values N_qa of n_shape nodes).  The numerator and the
 * denominator of Eq. 18 are this with scale = m v and scale = m.  The
 * kernel is the 3D one, not renormalised; c = 0 is Eq. 19, N_a(x_alpha),
 * which the element evaluates itself: the Dirac kernel is refused here. */
TlStatus tl_cg_project_to_element(const TlCGKernel *k, size_t n_qp, const TlVec3 *xq, const double *wq,
                                  int n_shape, const double *Nq, TlVec3 point, double scale, double *out);

#endif
