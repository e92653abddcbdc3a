/* Constitutive laws for the total-Lagrangian solid.
 *
 * A law maps the deformation gradient F (and the elastic Green strain
 * gamma = E - E0, E = (F^T F - 1)/2, E0 an eigenstrain) to the second
 * Piola-Kirchhoff stress S and its tangent D = dS/dE, evaluated for a batch
 * of points in one call.  Path-dependent laws keep state_size doubles per
 * point: evaluate() reads the COMMITTED state and writes a TRIAL state; the
 * solid keeps both arrays and swaps them on commit, drops the trial on
 * rollback.  A law built on a sub-scale model (a periodic DEM cell at each
 * Gauss point) fits the same interface: it keeps F of the last committed
 * step in its state, deforms its cell by the increment F F_n^-1 and returns
 * the homogenised stress and a tangent.
 *
 * Voigt order for 6-vectors and 6x6 matrices: 11, 22, 33, 12, 23, 13.
 * D[I*6 + J] = dS_I / d eps_J with engineering shear eps_J = 2 E_ij (i != j).
 *
 * Eigenstrain and initial stress are handled here for every law:
 * gamma = E - E0 is what the law sees as strain, and S0 is added to S
 * (seeds/000 pre-stresses its FEM this way). */
#ifndef TL_MATERIAL_H
#define TL_MATERIAL_H

#include <stddef.h>
#include "tl_checkpoint.h"
#include "tl_error.h"
#include "tl_math.h"
#include "tl_object.h"
#include "tl_registry.h"

typedef struct TlMaterial TlMaterial;

/* A real parameter of a law (tl_registry.h), stored as a double at
 * `offset` in the derived struct; drivers list them with their units. */
typedef TlParam TlMaterialParam;

typedef struct {
  TlOpsHeader header; /* kind "material" */
  size_t size;        /* sizeof the derived struct */
  int n_params;
  const TlMaterialParam *params;
  /* Checks parameters against each other, computes derived constants and
   * sets m->state_size. */
  TlStatus (*setup)(TlMaterial *m);
  /* For p < npts: S[p], and optionally D[36 p ..] and W[p] (stored energy
   * density per reference volume), from F[p] and gamma[p].  state_old and
   * state_new hold state_size doubles per point (NULL when zero). */
  TlStatus (*evaluate)(const TlMaterial *m, size_t npts, const TlMat3 *F, const TlMat3 *gamma,
                       const double *state_old, double *state_new, TlMat3 *S, double *D,
                       double *W);
  /* Optional fast path for a law without state: S from gamma alone for npts
   * points stored component-major, gamma[I * ldg + p] and S[I * lds + p]
   * (Voigt order I).  NULL: the solid goes through evaluate(). */
  TlStatus (*stress_soa)(const TlMaterial *m, size_t npts, const double *gamma, size_t ldg, double *S,
                         size_t lds);
  /* Whether D is symmetric for every F (then the solid may use a symmetric
   * solver).  NULL: no. */
  int (*symmetric_tangent)(const TlMaterial *m);
  /* Optional: initial state of npts points (default zeros). */
  TlStatus (*init_state)(const TlMaterial *m, size_t npts, double *state);
  /* Optional: the solid accepted the step (commit) or rejected it
   * (rollback); `state` holds the npts committed states after the call.  A
   * law with state outside these arrays (a DEM cell's particles) keeps or
   * restores it here.  evaluate() may be called from several threads at
   * once on disjoint points; commit and rollback are called from one. */
  TlStatus (*commit)(TlMaterial *m, size_t npts, const double *state);
  TlStatus (*rollback)(TlMaterial *m, size_t npts, const double *state);
  /* Optional: frees what the derived type owns. */
  void (*destroy)(TlMaterial *m);
  /* Optional: state the law keeps outside the solid's arrays (the DEM cell
   * of every point), written with the solid's checkpoint in a group of its
   * own and restored on load; the object is the TlMaterial, its committed
   * state is what is saved. */
  const TlCheckpointOps *checkpoint;
} TlMaterialOps;

struct TlMaterial {
  const TlMaterialOps *ops;
  double density;     /* reference mass density, kg/m^3 */
  size_t state_size;  /* doubles of internal state per point */
  int has_eigenstrain;
  TlMat3 eigenstrain; /* E0, symmetric */
  int has_initial_stress;
  TlMat3 initial_stress; /* S0, symmetric */
  int ready;             /* setup done */
};

/* Creates a law of the registered type `name` with default parameters. */
TlStatus tl_material_create(const char *name, TlMaterial **m);
/* Sets a parameter ("density" or one of the type's); checks the range. */
TlStatus tl_material_set(TlMaterial *m, const char *param, double value);
TlStatus tl_material_get(const TlMaterial *m, const char *param, double *value);
/* Symmetric eigenstrain E0 / initial stress S0 (checked for symmetry). */
TlStatus tl_material_set_eigenstrain(TlMaterial *m, TlMat3 E0);
TlStatus tl_material_set_initial_stress(TlMaterial *m, TlMat3 S0);
/* Validates the parameters; called by the solid, may be called earlier. */
TlStatus tl_material_setup(TlMaterial *m);
void tl_material_destroy(TlMaterial **m);

/* Convenience: the generalised Hooke law (seeds/001 Eq. 34) with E, nu,
 * density. */
TlStatus tl_material_create_hooke(double E, double nu, double density, TlMaterial **m);

/* Evaluates npts points from their deformation gradients: computes gamma,
 * calls the law, adds the initial stress.  Checks det F > 0 and finite
 * results; the error names the point index. */
TlStatus tl_material_evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F,
                              const double *state_old, double *state_new, TlMat3 *S, double *D,
                              double *W);
/* The same from displacement gradients H = F - 1, which keeps the Green
 * strain accurate to round-off relative to itself at small strain (the
 * solid uses this form). */
TlStatus tl_material_evaluate_gradient(const TlMaterial *m, size_t npts, const TlMat3 *H,
                                       const double *state_old, double *state_new, TlMat3 *S,
                                       double *D, double *W);
/* The stress of a law without state from displacement gradients stored
 * component-major: H[(3 i + j) ld + p] and S[I ld + p] (Voigt order I) for
 * p < npts, with the arithmetic of tl_material_evaluate_gradient (the same
 * bits).  The caller has checked det F > 0; finite results are checked. */
TlStatus tl_material_stress_soa(const TlMaterial *m, size_t npts, const double *H, double *S, size_t ld);
int tl_material_symmetric_tangent(const TlMaterial *m);

/* Voigt helpers. */
static inline void tl_voigt_from_sym(TlMat3 a, double v[6])
{
  v[0] = a.m[0][0], v[1] = a.m[1][1], v[2] = a.m[2][2];
  v[3] = a.m[0][1], v[4] = a.m[1][2], v[5] = a.m[0][2];
}
static inline TlMat3 tl_voigt_to_sym(const double v[6])
{
  return (TlMat3){{{v[0], v[3], v[5]}, {v[3], v[1], v[4]}, {v[5], v[4], v[2]}}};
}
/* The symmetric unit direction of engineering strain component J. */
static inline TlMat3 tl_voigt_unit_strain(int J)
{
  double v[6] = {0, 0, 0, 0, 0, 0};
  v[J] = J < 3 ? 1.0 : 0.5;
  return tl_voigt_to_sym(v);
}
/* a : b */
static inline double tl_m3_ddot(TlMat3 a, TlMat3 b)
{
  double s = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s += a.m[i][j] * b.m[i][j];
  return s;
}

/* Trace functions of a matrix M near zero that stored energies need free of
 * cancellation at small strain:
 *   kind 0: tr[log(1 + M) - M (1 + M)^-1] = sum_{k>=2} (-1)^k (k-1)/k tr M^k,
 *   kind 1: tr[M - log(1 + M)]             = sum_{k>=2} (-1)^k / k tr M^k.
 * The series is summed for |M|_F <= 0.3, the closed form used above. */
double tl_material_trace_series(TlMat3 M, int kind);

/* Checks a law's ops table (kind "material", size, evaluate, parameter
 * names, offsets inside the derived struct, defaults within their ranges)
 * and registers it with its parameter table, so that tl_material_create
 * makes it by name and -help and catalogues list its parameters.  A law
 * defined outside the library calls this once (e.g. from its driver's main)
 * and is then used exactly like a built-in one.  The table must outlive the
 * registry. */
TlStatus tl_material_register(const TlMaterialOps *ops);
/* Registers the built-in laws: "hooke" (seeds/001 Eq. 34 with the
 * contravariant deformed metric, as oomph-lib evaluates it),
 * "hooke_covariant" (Eq. 34 read literally with the covariant metric) and
 * "neo_hookean" (compressible). */
TlStatus tl_material_register_all(void);

#endif
