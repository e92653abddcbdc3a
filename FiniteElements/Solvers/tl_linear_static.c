#include "tl_linear_static.h"

#include <math.h>
#include <string.h>

#include "tl_linear_solver.h"
#include "tl_memory.h"
#include "tl_timer.h"

TlStatus tl_linear_static_solve(TlMechSystem *sys, const char *solver, double t, double *u,
                                TlLinearStaticStats *stats)
{
  if (!sys || !u) TL_ERROR(TL_ERR_ARG, "tl_linear_static_solve: NULL system or solution vector");
  const TlMechSystemOps *ops = sys->ops;
  if (!ops->create_matrix || !ops->internal_tangent || !ops->external_force)
    TL_ERROR(TL_ERR_ARG, "system %s lacks create_matrix, internal_tangent or external_force",
             ops->header.name);
  const char *type = solver ? solver : sys->symmetric ? "cholmod" : "klu";
  int upper = 0;
  TL_CHECK(tl_linear_solver_needs_upper(type, &upper));
  if (upper && !sys->symmetric)
    TL_ERROR(TL_ERR_ARG, "solver %s needs a symmetric system; system %s is not (use klu or umfpack)", type,
             ops->header.name);
  const TlSparseIndex n = sys->ndof;
  TlLinearStaticStats st;
  memset(&st, 0, sizeof st);
  st.ndof = n;
  TlSparse *K = NULL;
  TlLinearSolver *ls = NULL;
  double *zero = NULL, *f = NULL, *r = NULL;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_calloc(&zero, (size_t)n + 1, sizeof *zero), done);
  TL_CHECK_GOTO(s, tl_calloc(&f, (size_t)n + 1, sizeof *f), done);
  TL_CHECK_GOTO(s, tl_calloc(&r, (size_t)n + 1, sizeof *r), done);
  double t0 = tl_wtime();
  TL_CHECK_GOTO(s, ops->create_matrix(sys, upper, &K), done);
  TL_CHECK_GOTO(s, ops->internal_tangent(sys, t, zero, zero, 1.0, 0.0, K), done);
  TL_CHECK_GOTO(s, ops->external_force(sys, t, zero, f), done);
  /* Prescribed values g: f -= K g, then the identity rows u_D = g. */
  memset(u, 0, (size_t)n * sizeof *u);
  if (sys->n_dirichlet > 0) {
    if (ops->dirichlet) TL_CHECK_GOTO(s, ops->dirichlet(sys, t, u, NULL, NULL), done);
    tl_sparse_matvec(K, u, r);
    for (TlSparseIndex i = 0; i < n; ++i) f[i] -= r[i];
    for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) f[sys->dirichlet_dofs[k]] = u[sys->dirichlet_dofs[k]];
    tl_sparse_constrain(K, sys->n_dirichlet, sys->dirichlet_dofs, 1.0);
  }
  st.t_assemble = tl_wtime() - t0;
  t0 = tl_wtime();
  TL_CHECK_GOTO(s, tl_linear_solver_create(type, K, &ls), done);
  TL_CHECK_GOTO(s, tl_linear_solver_factor(ls, K), done);
  st.t_factor = tl_wtime() - t0;
  t0 = tl_wtime();
  TL_CHECK_GOTO(s, tl_linear_solver_solve(ls, f, u), done);
  st.t_solve = tl_wtime() - t0;
  /* The relative residual, a check on the factorisation's accuracy. */
  tl_sparse_matvec(K, u, r);
  double rmax = 0.0, fmax_ = 0.0;
  for (TlSparseIndex i = 0; i < n; ++i) {
    rmax = fmax(rmax, fabs(r[i] - f[i]));
    fmax_ = fmax(fmax_, fabs(f[i]));
  }
  st.residual = rmax / fmax(fmax_, 1e-300);
  for (TlSparseIndex i = 0; i < n; ++i)
    if (!isfinite(u[i])) {
      s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "linear static solution u[%lld] = %g", (long long)i, u[i]);
      goto done;
    }
  if (stats) *stats = st;
done:
  tl_linear_solver_destroy(&ls);
  tl_sparse_destroy(&K);
  tl_free(&zero);
  tl_free(&f);
  tl_free(&r);
  return s;
}
