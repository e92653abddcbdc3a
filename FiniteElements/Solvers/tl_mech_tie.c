/* The tied mechanical system (tl_mech_tie.h): P, P^T and P^T K P around an
 * inner system.  Every op expands the tied vectors onto the inner dofs,
 * calls the inner op and sums the results back over each root's slaves. */
#include "tl_mech_tie.h"

#include <string.h>

#include "tl_memory.h"

typedef struct {
  TlMechSystem base;
  TlMechSystem *inner;
  TlSparseIndex n_inner;
  TlSparseIndex *map;       /* n_inner: tied dof of each inner dof */
  double *ui, *vi, *fi, *ai; /* inner-length work vectors */
  TlSparse *K_inner;         /* inner tangent scratch (lazily created) */
  int K_inner_upper;
  TlSparseIndex *dirichlet;  /* tied Dirichlet dofs */
  /* The ops: the inner system's optional ops are forwarded exactly when it
   * has them (so the steppers see the same capabilities), hence a table per
   * tie, held here. */
  TlMechSystemOps ops;
} Tie;

void tl_mech_tie_expand(const TlMechSystem *sys, const double *u, double *u_inner)
{
  const Tie *t = (const Tie *)sys;
  for (TlSparseIndex i = 0; i < t->n_inner; ++i) u_inner[i] = u[t->map[i]];
}

void tl_mech_tie_reduce(const TlMechSystem *sys, const double *f_inner, double *f)
{
  const Tie *t = (const Tie *)sys;
  memset(f, 0, (size_t)sys->ndof * sizeof(double));
  for (TlSparseIndex i = 0; i < t->n_inner; ++i) f[t->map[i]] += f_inner[i];
}

TlSparseIndex tl_mech_tie_dof(const TlMechSystem *sys, TlSparseIndex i)
{
  const Tie *t = (const Tie *)sys;
  return (i >= 0 && i < t->n_inner) ? t->map[i] : -1;
}

TlMechSystem *tl_mech_tie_inner(const TlMechSystem *sys) { return ((const Tie *)sys)->inner; }
TlSparseIndex tl_mech_tie_inner_ndof(const TlMechSystem *sys) { return ((const Tie *)sys)->n_inner; }

static TlStatus tie_create_matrix(TlMechSystem *sys, int upper, TlSparse **K)
{
  Tie *t = (Tie *)sys;
  TlSparse *Ki = NULL;
  TL_CHECK(t->inner->ops->create_matrix(t->inner, upper, &Ki));
  /* One two-dof "element" per stored inner entry: the tied pattern is the
   * image of the inner one. */
  TlSparseIndex *ptr = NULL, *dofs = NULL;
  TlStatus s = tl_calloc(&ptr, (size_t)Ki->nnz + 1, sizeof *ptr);
  if (s == TL_OK) s = tl_calloc(&dofs, 2 * (size_t)Ki->nnz + 1, sizeof *dofs);
  if (s == TL_OK) {
    TlSparseIndex k = 0;
    for (TlSparseIndex j = 0; j < Ki->n; ++j)
      for (TlSparseIndex p = Ki->colptr[j]; p < Ki->colptr[j + 1]; ++p, ++k) {
        ptr[k] = 2 * k;
        dofs[2 * k] = t->map[Ki->rowind[p]];
        dofs[2 * k + 1] = t->map[j];
      }
    ptr[k] = 2 * k;
    s = tl_sparse_create_from_elements(sys->ndof, upper, Ki->nnz, ptr, dofs, 0, K);
  }
  tl_free(&ptr);
  tl_free(&dofs);
  tl_sparse_destroy(&Ki);
  return s;
}

static TlStatus tie_internal_force(TlMechSystem *sys, double time, const double *u, const double *v, double *f)
{
  Tie *t = (Tie *)sys;
  tl_mech_tie_expand(sys, u, t->ui);
  if (v) tl_mech_tie_expand(sys, v, t->vi);
  TL_CHECK(t->inner->ops->internal_force(t->inner, time, t->ui, v ? t->vi : NULL, t->fi));
  tl_mech_tie_reduce(sys, t->fi, f);
  return TL_OK;
}

/* The inner matrix scratch, zeroed, in the storage of K. */
static TlStatus tie_inner_matrix(Tie *t, const TlSparse *K, TlSparse **Ki)
{
  if (t->K_inner && t->K_inner_upper != K->symmetric) tl_sparse_destroy(&t->K_inner);
  if (!t->K_inner) {
    TL_CHECK(t->inner->ops->create_matrix(t->inner, K->symmetric, &t->K_inner));
    t->K_inner_upper = K->symmetric;
  }
  tl_sparse_zero(t->K_inner);
  *Ki = t->K_inner;
  return TL_OK;
}

/* K += P^T Ki P. */
static TlStatus tie_add_reduced(const Tie *t, const TlSparse *Ki, TlSparse *K)
{
  for (TlSparseIndex j = 0; j < Ki->n; ++j)
    for (TlSparseIndex p = Ki->colptr[j]; p < Ki->colptr[j + 1]; ++p) {
      TlSparseIndex i = Ki->rowind[p], I = t->map[i], J = t->map[j];
      double val = Ki->values[p];
      if (val == 0.0) continue;
      /* An upper-stored off-diagonal entry stands for K_ij and K_ji: both
       * land on the diagonal when i and j are tied together. */
      if (Ki->symmetric && i != j && I == J) val *= 2.0;
      TL_CHECK(tl_sparse_add(K, I, J, val));
    }
  return TL_OK;
}

static TlStatus tie_internal_tangent(TlMechSystem *sys, double time, const double *u, const double *v, double c_u,
                                     double c_v, TlSparse *K)
{
  Tie *t = (Tie *)sys;
  TlSparse *Ki = NULL;
  TL_CHECK(tie_inner_matrix(t, K, &Ki));
  tl_mech_tie_expand(sys, u, t->ui);
  if (v) tl_mech_tie_expand(sys, v, t->vi);
  TL_CHECK(t->inner->ops->internal_tangent(t->inner, time, t->ui, v ? t->vi : NULL, c_u, c_v, Ki));
  return tie_add_reduced(t, Ki, K);
}

static TlStatus tie_external_tangent(TlMechSystem *sys, double time, const double *u, double c, TlSparse *K)
{
  Tie *t = (Tie *)sys;
  TlSparse *Ki = NULL;
  TL_CHECK(tie_inner_matrix(t, K, &Ki));
  tl_mech_tie_expand(sys, u, t->ui);
  TL_CHECK(t->inner->ops->external_tangent(t->inner, time, t->ui, c, Ki));
  return tie_add_reduced(t, Ki, K);
}

static TlStatus tie_external_force(TlMechSystem *sys, double time, const double *u, double *f)
{
  Tie *t = (Tie *)sys;
  tl_mech_tie_expand(sys, u, t->ui);
  TL_CHECK(t->inner->ops->external_force(t->inner, time, t->ui, t->fi));
  tl_mech_tie_reduce(sys, t->fi, f);
  return TL_OK;
}

static TlStatus tie_lumped_mass(TlMechSystem *sys, double *m)
{
  Tie *t = (Tie *)sys;
  TL_CHECK(t->inner->ops->lumped_mass(t->inner, t->fi));
  tl_mech_tie_reduce(sys, t->fi, m);
  return TL_OK;
}

static TlStatus tie_dirichlet(TlMechSystem *sys, double time, double *u, double *v, double *a)
{
  Tie *t = (Tie *)sys;
  TlMechSystem *in = t->inner;
  if (!in->ops->dirichlet) return TL_OK;
  /* The inner op writes its Dirichlet dofs only; read them back at the
   * roots (a slave's value equals its root's: both are prescribed). */
  double *vec[3] = {u, v, a};
  for (int k = 0; k < 3; ++k) {
    if (!vec[k]) continue;
    memset(t->ui, 0, (size_t)t->n_inner * sizeof(double));
    TL_CHECK(in->ops->dirichlet(in, time, k == 0 ? t->ui : NULL, k == 1 ? t->ui : NULL, k == 2 ? t->ui : NULL));
    for (TlSparseIndex d = 0; d < in->n_dirichlet; ++d) {
      TlSparseIndex i = in->dirichlet_dofs[d];
      vec[k][t->map[i]] = t->ui[i];
    }
  }
  return TL_OK;
}

static TlStatus tie_strain_energy(TlMechSystem *sys, const double *u, double *W)
{
  Tie *t = (Tie *)sys;
  tl_mech_tie_expand(sys, u, t->ui);
  return t->inner->ops->strain_energy(t->inner, t->ui, W);
}

static TlStatus tie_commit(TlMechSystem *sys)
{
  Tie *t = (Tie *)sys;
  return t->inner->ops->commit ? t->inner->ops->commit(t->inner) : TL_OK;
}

static TlStatus tie_rollback(TlMechSystem *sys)
{
  Tie *t = (Tie *)sys;
  return t->inner->ops->rollback ? t->inner->ops->rollback(t->inner) : TL_OK;
}

static TlStatus tie_max_frequency_squared(TlMechSystem *sys, const double *u, double *omega2)
{
  Tie *t = (Tie *)sys;
  tl_mech_tie_expand(sys, u, t->ui);
  return t->inner->ops->max_frequency_squared(t->inner, t->ui, omega2);
}

static TlStatus tie_consistent_mass(TlMechSystem *sys, double c, TlSparse *M)
{
  Tie *t = (Tie *)sys;
  TlSparse *Mi = NULL;
  TL_CHECK(tie_inner_matrix(t, M, &Mi));
  TL_CHECK(t->inner->ops->consistent_mass(t->inner, c, Mi));
  return tie_add_reduced(t, Mi, M);
}

/* The inner state under the same group (the tie itself holds no state). */
static TlStatus tie_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const Tie *t = object;
  const TlCheckpointOps *in = t->inner->ops->checkpoint;
  return in ? in->save(t->inner, w, group) : TL_OK;
}

static TlStatus tie_load(void *object, TlCheckpointReader *r, const char *group)
{
  Tie *t = object;
  const TlCheckpointOps *in = t->inner->ops->checkpoint;
  return in ? in->load(t->inner, r, group) : TL_OK;
}

static const TlCheckpointOps tie_checkpoint = {{"checkpoint", "mech_tie", "the inner system's state"}, tie_save, tie_load};

static void tie_destroy(TlMechSystem *sys)
{
  Tie *t = (Tie *)sys;
  tl_free(&t->map);
  tl_free(&t->ui);
  tl_free(&t->vi);
  tl_free(&t->fi);
  tl_free(&t->ai);
  tl_free(&t->dirichlet);
  tl_sparse_destroy(&t->K_inner);
}

TlStatus tl_mech_tie_create(TlMechSystem *inner, const TlSparseIndex *master, TlMechSystem **tied)
{
  if (!inner || !master || !tied) TL_ERROR(TL_ERR_ARG, "mech_tie: NULL argument");
  *tied = NULL;
  TlSparseIndex n = inner->ndof;
  for (TlSparseIndex i = 0; i < n; ++i)
    if (master[i] < 0 || master[i] >= n)
      TL_ERROR(TL_ERR_ARG, "mech_tie: master of dof %lld is %lld, outside [0, %lld)", (long long)i,
               (long long)master[i], (long long)n);
  Tie *t = NULL;
  TlSparseIndex *root = NULL;
  unsigned char *is_dir = NULL;
  TlStatus s = TL_NEW(t);
  if (s == TL_OK) s = tl_calloc(&root, (size_t)n + 1, sizeof *root);
  if (s == TL_OK) s = tl_calloc(&is_dir, (size_t)n + 1, 1);
  if (s) goto fail;
  TlMechSystemOps *ops = &t->ops;
  t->base.ops = ops;
  t->inner = inner;
  t->n_inner = n;
  /* Roots: follow each chain; more than n links is a cycle. */
  for (TlSparseIndex i = 0; i < n; ++i) {
    TlSparseIndex r = i, k = 0;
    while (master[r] != r) {
      r = master[r];
      if (++k > n) {
        s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "mech_tie: the masters of dof %lld form a cycle",
                         (long long)i);
        goto fail;
      }
    }
    root[i] = r;
  }
  for (TlSparseIndex d = 0; d < inner->n_dirichlet; ++d) is_dir[inner->dirichlet_dofs[d]] = 1;
  for (TlSparseIndex i = 0; i < n; ++i)
    if (is_dir[i] != is_dir[root[i]]) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "mech_tie: dof %lld is %s but its master %lld is %s: tied dofs must share their "
                       "boundary condition",
                       (long long)i, is_dir[i] ? "prescribed" : "free", (long long)root[i],
                       is_dir[root[i]] ? "prescribed" : "free");
      goto fail;
    }
  if ((s = tl_calloc(&t->map, (size_t)n + 1, sizeof *t->map))) goto fail;
  TlSparseIndex m = 0;
  for (TlSparseIndex i = 0; i < n; ++i)
    if (root[i] == i) t->map[i] = m++;
  for (TlSparseIndex i = 0; i < n; ++i) t->map[i] = t->map[root[i]];
  TlSparseIndex nd = 0;
  for (TlSparseIndex i = 0; i < n; ++i) nd += (root[i] == i && is_dir[i]);
  if ((s = tl_calloc(&t->dirichlet, (size_t)nd + 1, sizeof *t->dirichlet))) goto fail;
  nd = 0;
  for (TlSparseIndex i = 0; i < n; ++i)
    if (root[i] == i && is_dir[i]) t->dirichlet[nd++] = t->map[i];
  if ((s = tl_calloc(&t->ui, (size_t)n + 1, sizeof(double)))) goto fail;
  if ((s = tl_calloc(&t->vi, (size_t)n + 1, sizeof(double)))) goto fail;
  if ((s = tl_calloc(&t->fi, (size_t)n + 1, sizeof(double)))) goto fail;
  if ((s = tl_calloc(&t->ai, (size_t)n + 1, sizeof(double)))) goto fail;
  const TlMechSystemOps *io = inner->ops;
  *ops = (TlMechSystemOps){
      .header = {"mech_system", "tie", "dofs tied to masters (periodic boundaries)"},
      .create_matrix = tie_create_matrix,
      .internal_force = tie_internal_force,
      .internal_tangent = tie_internal_tangent,
      .external_force = tie_external_force,
      .lumped_mass = tie_lumped_mass,
      .external_tangent = io->external_tangent ? tie_external_tangent : NULL,
      .consistent_mass = io->consistent_mass ? tie_consistent_mass : NULL,
      .dirichlet = tie_dirichlet,
      .strain_energy = io->strain_energy ? tie_strain_energy : NULL,
      .commit = io->commit ? tie_commit : NULL,
      .rollback = io->rollback ? tie_rollback : NULL,
      .max_frequency_squared = io->max_frequency_squared ? tie_max_frequency_squared : NULL,
      .checkpoint = io->checkpoint ? &tie_checkpoint : NULL,
      .destroy = tie_destroy,
  };
  t->base.ndof = m;
  t->base.symmetric = inner->symmetric;
  t->base.damped = inner->damped;
  t->base.n_dirichlet = nd;
  t->base.dirichlet_dofs = t->dirichlet;
  tl_free(&root);
  tl_free(&is_dir);
  *tied = &t->base;
  return TL_OK;
fail:
  tl_free(&root);
  tl_free(&is_dir);
  if (t) {
    tie_destroy(&t->base);
    tl_free(&t);
  }
  return s;
}
