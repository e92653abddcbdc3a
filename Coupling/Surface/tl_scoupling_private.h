/* Internal to the surface coupling (tl_scoupling*.c): the coupling's
 * state and the strategies that spread a contact force over nodes.
 *
 * A support strategy decides where the CG kernel of c > 0 is normalised and
 * integrated (TlSCouplingOptions.support):
 *   tl_scoupling_support_surface.c   over the coupled faces (Eq. 15; also
 *                                    the Dirac limit of Eq. 16, c = 0);
 *   tl_scoupling_support_elements.c  over the SCoupling elements'
 *                                    integration points (the code of the
 *                                    published runs).
 * Each holds per-item accumulated nodal forces (items: faces or elements)
 * with the items reached in the order first touched, and activates the
 * SCoupling elements owning them. */
#ifndef TL_SCOUPLING_PRIVATE_H
#define TL_SCOUPLING_PRIVATE_H

#include "tl_scoupling.h"
#include "tl_scoupling_faces.h"

/* The per-item nodal forces of a support, with the items holding them in
 * the order first touched: checkpointed as <prefix>touched_<item>s and
 * <prefix><item>_forces. */
typedef struct {
  const char *item;
  size_t n_items;
  int per_item;          /* nodes per item */
  TlVec3 *F;             /* n_items x per_item */
  unsigned char *touched;
  size_t *list, *n_touched;
  const int *local;      /* n_items x per_item local node numbers */
  const size_t *node;    /* local -> global node */
  const size_t *owner;   /* the SCoupling element of each item (NULL: the item is one) */
} TlSCouplingForceSet;

typedef struct {
  TlOpsHeader header; /* kind "scoupling_support" */
  int id;             /* TL_SCOUPLING_SUPPORT_*: the option's value, checkpointed */
  /* Builds the support after the faces' topology and CG surface exist;
   * sets sc->cg_support and may grow sc->bulge (how far the support's
   * points reach beyond its nodes' box). */
  TlStatus (*setup)(TlSCoupling *sc);
  void (*destroy)(TlSCoupling *sc);
  /* Moves the support's own nodes to X + u (u node-space, NULL: at rest). */
  void (*move)(TlSCoupling *sc, const double *u);
  /* Spreads the collected contacts (sc->c_*) over the support's items,
   * adding into their accumulated forces, and activates the SCoupling
   * elements owning the items reached. */
  TlStatus (*spread)(TlSCoupling *sc);
  /* ADDS the accumulated load of SCoupling element e to f_nodes (3 per node). */
  void (*element_load)(const TlSCoupling *sc, size_t e, double *f_nodes);
  /* The accumulated forces, which the coupling clears, assembles and
   * checkpoints (tl_scoupling.c). */
  TlSCouplingForceSet (*forces)(const TlSCoupling *sc);
} TlSCouplingSupportOps;

extern const TlSCouplingSupportOps tl_scoupling_support_surface;
extern const TlSCouplingSupportOps tl_scoupling_support_elements;

_Static_assert(sizeof(TlVec3) == 3 * sizeof(double), "TlVec3 arrays are checkpointed as doubles");

struct TlSCoupling {
  TlSolid *solid;
  const TlMesh *mesh;
  double width;
  size_t n_faces;
  TlFaceRef *faces;
  int nf;            /* nodes per face */
  TlSCouplingFaceType *ft; /* wall pieces and CG quadrature of the face type */
  size_t n_local;    /* distinct FE nodes of the faces */
  size_t *node;      /* local -> global node */
  int *face_local;   /* n_faces x nf local node numbers */
  TlVec3 *X0, *xs;   /* reference and current positions of the local nodes */
  size_t n_vertices; /* wall vertices: local nodes, then the extra points of each face */
  double *vx, *vv;   /* 3 x n_vertices scratch for the wall */
  TlWall *wall;
  int wall_given;    /* the world owns the wall */
  TlCGKernel *kernel;
  TlCGSurface *cg;
  int cg_stale;      /* the nodes moved since the last quadrature update */
  double face_size;  /* largest corner-to-corner edge of a face at creation */
  double bulge;      /* how far a face's (or element's) points reach beyond its nodes' box: 0 when linear */
  /* SCoupling elements, the element of each face and the faces of each
   * element (elem_face[elem_face_ptr[e] .. elem_face_ptr[e + 1] - 1]) */
  size_t n_elements, n_active;
  TlFaceRef *elements, *active;
  size_t *active_index;  /* n_active: element numbers (into elements) of the active ones */
  size_t *face_element;
  size_t *elem_face_ptr, *elem_face;
  unsigned char *elem_active;
  /* accumulated per-face coupling forces (Eq. 15/16, n_faces x nf): the
   * load the wrappers put on the next FE step; the faces holding them, in
   * the order first touched */
  TlVec3 *face_F;
  unsigned char *face_touched;
  size_t *touched_faces, n_touched;
  /* the SCoupling element type over each block holding coupled faces */
  int n_wrappers;
  TlSolidWrapper **wrappers;
  /* per-contact scratch */
  size_t capacity, n_contacts;
  size_t *c_face;
  TlVec3 *c_point, *c_force;
  TlVec3 *nodal;
  /* How contact forces are spread for c > 0 (one strategy per file): its
   * ops, its own data, and the CG surface it spreads over */
  const TlSCouplingSupportOps *support;
  void *support_data;
  TlCGSurface *cg_support;
  size_t *c_elem;    /* per contact: its face's element */
};

/* ADDS the forces of item k to f_nodes (3 per node). */
void tl_scoupling_add_item(const TlSCouplingForceSet *fs, size_t k, double *f_nodes);
/* The owners of the items touched since position n0 of the list become
 * active (in the order their items were first touched). */
void tl_scoupling_activate_touched(TlSCoupling *sc, const TlSCouplingForceSet *fs, size_t n0);
/* SCoupling element e becomes active (step 1 of §5.3.1), once. */
void tl_scoupling_activate_element(TlSCoupling *sc, size_t e);

#endif
