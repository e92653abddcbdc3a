/* The cantilever of S1 (Cheng et al. 2022, §6.1) as a ready scene, and its analytic
 * references, shared by the cantilever driver, its tests and benchmarks.
 *
 * Beam along y: cross-section [-b/2, b/2] x [-h/2, h/2] (x, z), length L;
 * the face y = 0 clamped; a dead tip load P in -z on the face y = L,
 * applied as the consistent nodal forces of a uniform shear traction
 * (so another code given the same nodal forces sees the same load). */
#ifndef TL_CANTILEVER_H
#define TL_CANTILEVER_H

#include "tl_element.h"
#include "tl_material.h"
#include "tl_mesh.h"
#include "tl_solid.h"

typedef struct {
  const TlElementType *type; /* hex8 or hex27 */
  size_t nx, ny, nz;         /* cells across x, along y, across z */
  double b, h, L;            /* m */
  double E, nu, rho;         /* Pa, -, kg/m^3 */
  double load;               /* tip load P (N), in -z */
  const char *material;      /* the law's registered name, with E and nu ("hooke") */
  /* A Gmsh mesh (any 3-D element type, msh 4.1 or 2.2) in place of the
   * generated nx x ny x nz box, NULL or "" for the box: it must span the
   * beam [-b/2, b/2] x [0, L] x [-h/2, h/2] (the references use b, h, L)
   * and name the clamped face "ymin" and the loaded face "ymax" (physical
   * surfaces); the tip load and the tip displacement use the consistent
   * weights of the ymax faces. */
  const char *mesh_file;
} TlCantileverParams;

typedef struct {
  TlCantileverParams p;
  TlMesh *mesh;
  TlMaterial *material;
  TlSolid *solid;
  double load_scale; /* amplitude of the tip load (set by the caller) */
  size_t n_tip;
  size_t *tip_nodes;
  double *tip_weight; /* consistent weights, summing to 1 */
} TlCantilever;

/* S1 defaults: hex8 2 x 30 x 2, 0.8 x 0.8 x 12 m, E = 100 MPa, nu = 0,
 * rho = 1309 kg/m^3, P = 1644 N (twice the weight of S1's particles),
 * material "hooke". */
void tl_cantilever_params_default(TlCantileverParams *p);
/* The longest cell side over the shortest beyond which create refuses. */
#define TL_CANTILEVER_MAX_ASPECT 1000.0
TlStatus tl_cantilever_create(const TlCantileverParams *p, TlCantilever **c);
void tl_cantilever_destroy(TlCantilever **c);
/* Mean tip displacement (consistent weights) from a dof vector: out[3]. */
void tl_cantilever_tip(const TlCantilever *c, const double *u, double out[3]);

/* Timoshenko tip deflection P L^3/(3 E I) + P L/(kappa G A), kappa = 10(1+nu)/(12+11nu). */
double tl_cantilever_timoshenko(const TlCantileverParams *p);
/* Inextensible elastica under a dead tip load, k = P L^2 / (E I): tip
 * deflection w/L and axial shortening (L - y_tip)/L (shooting with RK4). */
TlStatus tl_cantilever_elastica(double k, double *w_over_L, double *shortening_over_L);
/* First bending frequency (rad/s) of the Euler-Bernoulli cantilever. */
double tl_cantilever_omega1(const TlCantileverParams *p);

#endif
