/* The linearised mechanical system (tl_mech_linear.h). */
#include "tl_mech_linear.h"

#include <math.h>
#include <string.h>

#include "tl_memory.h"

typedef struct {
  TlMechSystem base;
  TlMechSystem *inner;
  TlSparse *K;
  double *u_ref, *f_ref, *du, *work;
  double W_ref;
  int subtract;
} Linear;

static TlStatus lin_create_matrix(TlMechSystem *sys, int upper, TlSparse **K)
{
  Linear *l = (Linear *)sys;
  return l->inner->ops->create_matrix(l->inner, upper, K);
}

static TlStatus lin_internal_force(TlMechSystem *sys, double t, const double *u, const double *v, double *f)
{
  (void)t, (void)v;
  Linear *l = (Linear *)sys;
  TlSparseIndex n = sys->ndof;
  for (TlSparseIndex i = 0; i < n; ++i) l->du[i] = u[i] - l->u_ref[i];
  tl_sparse_matvec(l->K, l->du, f);
  if (!l->subtract)
    for (TlSparseIndex i = 0; i < n; ++i) f[i] += l->f_ref[i];
  return TL_OK;
}

static TlStatus lin_internal_tangent(TlMechSystem *sys, double t, const double *u, const double *v, double c_u,
                                     double c_v, TlSparse *K)
{
  (void)t, (void)u, (void)v, (void)c_v;
  Linear *l = (Linear *)sys;
  if (K->nnz == l->K->nnz && K->symmetric == l->K->symmetric) return tl_sparse_axpy(c_u, l->K, K);
  for (TlSparseIndex j = 0; j < l->K->n; ++j)
    for (TlSparseIndex p = l->K->colptr[j]; p < l->K->colptr[j + 1]; ++p)
      if (l->K->values[p] != 0.0) TL_CHECK(tl_sparse_add(K, l->K->rowind[p], j, c_u * l->K->values[p]));
  return TL_OK;
}

static TlStatus lin_external_force(TlMechSystem *sys, double t, const double *u, double *f)
{
  Linear *l = (Linear *)sys;
  return l->inner->ops->external_force(l->inner, t, u, f);
}

static TlStatus lin_external_tangent(TlMechSystem *sys, double t, const double *u, double c, TlSparse *K)
{
  Linear *l = (Linear *)sys;
  return l->inner->ops->external_tangent ? l->inner->ops->external_tangent(l->inner, t, u, c, K) : TL_OK;
}

static TlStatus lin_lumped_mass(TlMechSystem *sys, double *m)
{
  Linear *l = (Linear *)sys;
  return l->inner->ops->lumped_mass(l->inner, m);
}

static TlStatus lin_consistent_mass(TlMechSystem *sys, double c, TlSparse *M)
{
  Linear *l = (Linear *)sys;
  if (!l->inner->ops->consistent_mass)
    TL_ERROR(TL_ERR_UNSUPPORTED, "mech_linear: the inner system '%s' has no consistent mass",
             l->inner->ops->header.name);
  return l->inner->ops->consistent_mass(l->inner, c, M);
}

static TlStatus lin_dirichlet(TlMechSystem *sys, double t, double *u, double *v, double *a)
{
  Linear *l = (Linear *)sys;
  return l->inner->ops->dirichlet ? l->inner->ops->dirichlet(l->inner, t, u, v, a) : TL_OK;
}

static TlStatus lin_strain_energy(TlMechSystem *sys, const double *u, double *W)
{
  Linear *l = (Linear *)sys;
  TlSparseIndex n = sys->ndof;
  for (TlSparseIndex i = 0; i < n; ++i) l->du[i] = u[i] - l->u_ref[i];
  tl_sparse_matvec(l->K, l->du, l->work);
  double w = 0.0, fr = 0.0;
  for (TlSparseIndex i = 0; i < n; ++i) {
    w += l->du[i] * l->work[i];
    fr += l->f_ref[i] * l->du[i];
  }
  *W = 0.5 * w + (l->subtract ? 0.0 : l->W_ref + fr);
  return TL_OK;
}

static void lin_destroy(TlMechSystem *sys)
{
  Linear *l = (Linear *)sys;
  tl_sparse_destroy(&l->K);
  tl_free(&l->u_ref);
  tl_free(&l->f_ref);
  tl_free(&l->du);
  tl_free(&l->work);
}

static const TlMechSystemOps linear_ops = {
    .header = {"mech_system", "linear", "small-strain system about a reference state, K assembled once"},
    .create_matrix = lin_create_matrix,
    .internal_force = lin_internal_force,
    .internal_tangent = lin_internal_tangent,
    .external_force = lin_external_force,
    .lumped_mass = lin_lumped_mass,
    .external_tangent = lin_external_tangent,
    .consistent_mass = lin_consistent_mass,
    .dirichlet = lin_dirichlet,
    .strain_energy = lin_strain_energy,
    .destroy = lin_destroy,
};

const TlSparse *tl_mech_linear_matrix(const TlMechSystem *sys) { return ((const Linear *)sys)->K; }
const double *tl_mech_linear_reference_force(const TlMechSystem *sys) { return ((const Linear *)sys)->f_ref; }

TlStatus tl_mech_linear_create(TlMechSystem *inner, double t, const double *u_ref, int subtract_reference,
                               TlMechSystem **linear)
{
  if (!inner || !linear) TL_ERROR(TL_ERR_ARG, "mech_linear: NULL argument");
  *linear = NULL;
  if (inner->damped)
    TL_ERROR(TL_ERR_UNSUPPORTED, "mech_linear: the inner system '%s' is damped (f_int depends on v)",
             inner->ops->header.name);
  Linear *l = NULL;
  TL_CHECK(TL_NEW(l));
  l->base.ops = &linear_ops;
  l->inner = inner;
  l->subtract = subtract_reference != 0;
  TlSparseIndex n = inner->ndof;
  TlMechSystem *b = &l->base;
  TlStatus s = tl_calloc(&l->u_ref, (size_t)n + 1, sizeof(double));
  if (s == TL_OK) s = tl_calloc(&l->f_ref, (size_t)n + 1, sizeof(double));
  if (s == TL_OK) s = tl_calloc(&l->du, (size_t)n + 1, sizeof(double));
  if (s == TL_OK) s = tl_calloc(&l->work, (size_t)n + 1, sizeof(double));
  if (s) goto fail;
  if (u_ref) memcpy(l->u_ref, u_ref, (size_t)n * sizeof(double));
  /* Full storage: the product then reads each entry once (no mirrored
   * pass), which is what the explicit loop pays every step. */
  if ((s = inner->ops->create_matrix(inner, 0, &l->K))) goto fail;
  if ((s = inner->ops->internal_tangent(inner, t, l->u_ref, NULL, 1.0, 0.0, l->K))) goto fail;
  if ((s = inner->ops->internal_force(inner, t, l->u_ref, NULL, l->f_ref))) goto fail;
  if (inner->ops->strain_energy && (s = inner->ops->strain_energy(inner, l->u_ref, &l->W_ref))) goto fail;
  for (TlSparseIndex p = 0; p < l->K->nnz; ++p)
    if (!isfinite(l->K->values[p])) {
      s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "mech_linear: tangent entry %lld is %g",
                       (long long)p, l->K->values[p]);
      goto fail;
    }
  l->base.ndof = n;
  l->base.symmetric = inner->symmetric;
  l->base.damped = 0;
  l->base.n_dirichlet = inner->n_dirichlet;
  l->base.dirichlet_dofs = inner->dirichlet_dofs;
  *linear = b;
  return TL_OK;
fail:
  tl_mech_system_destroy(&b);
  return s;
}
