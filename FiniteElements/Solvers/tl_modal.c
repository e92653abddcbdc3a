#include "tl_modal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_config.h"
#include "tl_linear_solver.h"
#include "tl_memory.h"
#include "tl_timer.h"

#if TALUS_WITH_ARPACK
#include <arpack.h>
#endif

void tl_modal_options_default(TlModalOptions *o)
{
  memset(o, 0, sizeof *o);
  o->n_modes = 6;
  o->shift = 0.0;
  o->lumped = 0;
  o->tol = 0.0;
  o->ncv = 0;
  o->max_restarts = 1000;
}

int tl_modal_available(void) { return TALUS_WITH_ARPACK; }

#if TALUS_WITH_ARPACK
/* The shift-invert operator's pieces, shared by the reverse-communication
 * loop and the residual check. */
typedef struct {
  TlMechSystem *sys;
  TlSparse *K, *M, *A; /* stiffness, consistent mass (or NULL), K - sigma M */
  double *m;           /* lumped mass (when M == NULL), zero at Dirichlet dofs */
  TlLinearSolver *ls;
} Pencil;

static void mass_apply(const Pencil *p, const double *x, double *y)
{
  const TlSparseIndex n = p->sys->ndof;
  if (p->M) tl_sparse_matvec(p->M, x, y);
  else
    for (TlSparseIndex i = 0; i < n; ++i) y[i] = p->m[i] * x[i];
}

static TlStatus assemble(Pencil *p, const TlModalOptions *o, TlModalStats *st)
{
  TlMechSystem *sys = p->sys;
  const TlMechSystemOps *ops = sys->ops;
  const TlSparseIndex n = sys->ndof;
  double *zero = NULL;
  TlStatus s = TL_OK;
  TL_CHECK(tl_calloc(&zero, (size_t)n + 1, sizeof *zero));
  TL_CHECK_GOTO(s, ops->create_matrix(sys, 1, &p->K), done);
  TL_CHECK_GOTO(s, ops->internal_tangent(sys, 0.0, zero, zero, 1.0, 0.0, p->K), done);
  TL_CHECK_GOTO(s, tl_sparse_duplicate(p->K, &p->A), done);
  TL_CHECK_GOTO(s, tl_sparse_axpy(1.0, p->K, p->A), done);
  st->consistent = ops->consistent_mass && !o->lumped;
  if (st->consistent) {
    TL_CHECK_GOTO(s, tl_sparse_duplicate(p->K, &p->M), done);
    TL_CHECK_GOTO(s, ops->consistent_mass(sys, 1.0, p->M), done);
    TL_CHECK_GOTO(s, ops->consistent_mass(sys, -o->shift, p->A), done);
    tl_sparse_constrain(p->M, sys->n_dirichlet, sys->dirichlet_dofs, 0.0);
  } else {
    TL_CHECK_GOTO(s, tl_calloc(&p->m, (size_t)n + 1, sizeof *p->m), done);
    TL_CHECK_GOTO(s, ops->lumped_mass(sys, p->m), done);
    for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) p->m[sys->dirichlet_dofs[k]] = 0.0;
    for (TlSparseIndex i = 0; i < n; ++i) p->A->values[p->A->diag[i]] -= o->shift * p->m[i];
  }
  tl_sparse_constrain(p->K, sys->n_dirichlet, sys->dirichlet_dofs, 1.0);
  tl_sparse_constrain(p->A, sys->n_dirichlet, sys->dirichlet_dofs, 1.0);
done:
  tl_free(&zero);
  return s;
}

static TlStatus factor(Pencil *p, const TlModalOptions *o)
{
  TL_CHECK(tl_linear_solver_create("cholmod", p->A, &p->ls));
  TlStatus s = tl_linear_solver_factor(p->ls, p->A);
  if (s == TL_ERR_NUMERIC) {
    char why[512];
    snprintf(why, sizeof why, "%s", tl_error_message());
    TL_ERROR(TL_ERR_NUMERIC,
             "K - sigma M is not positive definite at the shift sigma = %g (rad/s)^2 (%s): the shift must lie "
             "below the lowest eigenvalue; a body free to move rigidly needs sigma < 0",
             o->shift, why);
  }
  return s;
}

/* ARPACK's info codes that concern the caller. */
static const char *arpack_message(int info)
{
  switch (info) {
  case 1: return "maximum number of restarts reached";
  case 3: return "no shifts could be applied (increase ncv)";
  case -1: return "ndof must be positive";
  case -2: return "n_modes must be positive";
  case -3: return "need n_modes < ncv <= ndof";
  case -9: return "the starting vector is zero";
  case -9999: return "could not build a Lanczos factorisation";
  default: return "see ARPACK's dsaupd/dseupd documentation";
  }
}

static TlStatus lanczos(Pencil *p, const TlModalOptions *o, double *omega2, double *modes, TlModalStats *st)
{
  const TlSparseIndex ndof = p->sys->ndof;
  if (ndof > 2147483647) TL_ERROR(TL_ERR_UNSUPPORTED, "%lld dofs exceed ARPACK's 32-bit index", (long long)ndof);
  const a_int n = (a_int)ndof, nev = o->n_modes;
  a_int ncv = o->ncv > 0 ? o->ncv : (2 * nev + 1 > 20 ? 2 * nev + 1 : 20);
  if (ncv > n) ncv = n;
  if (!(nev < ncv))
    TL_ERROR(TL_ERR_ARG, "%d modes wanted with %d Lanczos vectors on %lld dofs: need n_modes < ncv <= ndof",
             (int)nev, (int)ncv, (long long)ndof);
  const a_int lworkl = ncv * (ncv + 8);
  double *resid = NULL, *v = NULL, *workd = NULL, *workl = NULL, *z = NULL, *d = NULL, *Kx = NULL, *Mx = NULL;
  a_int *select = NULL;
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_calloc(&resid, (size_t)n, sizeof *resid), done);
  TL_CHECK_GOTO(s, tl_calloc(&v, (size_t)n * (size_t)ncv, sizeof *v), done);
  TL_CHECK_GOTO(s, tl_calloc(&workd, 3 * (size_t)n, sizeof *workd), done);
  TL_CHECK_GOTO(s, tl_calloc(&workl, (size_t)lworkl, sizeof *workl), done);
  TL_CHECK_GOTO(s, tl_calloc(&z, (size_t)n * (size_t)nev, sizeof *z), done);
  TL_CHECK_GOTO(s, tl_calloc(&d, (size_t)nev, sizeof *d), done);
  TL_CHECK_GOTO(s, tl_calloc(&select, (size_t)ncv, sizeof *select), done);
  TL_CHECK_GOTO(s, tl_calloc(&Kx, (size_t)n, sizeof *Kx), done);
  TL_CHECK_GOTO(s, tl_calloc(&Mx, (size_t)n, sizeof *Mx), done);
  a_int iparam[11] = {0}, ipntr[14] = {0}, ido = 0, info = 0;
  iparam[0] = 1;                       /* exact shifts */
  iparam[2] = (a_int)o->max_restarts; /* restarts */
  iparam[6] = 3;                       /* shift-invert: OP = (K - sigma M)^-1 M, B = M */
  /* ARPACK's random start vector (info = 0): a fixed one could be
   * orthogonal to the modes of a symmetric body (torsion, lateral bending)
   * and leave them to round-off. */
  double t0 = tl_wtime();
  for (;;) {
    dsaupd_c(&ido, "G", n, "LM", nev, o->tol, resid, ncv, v, n, iparam, ipntr, workd, workl, lworkl, &info);
    double *x = workd + ipntr[0] - 1, *y = workd + ipntr[1] - 1;
    if (ido == -1) { /* y = OP x */
      mass_apply(p, x, y);
      TL_CHECK_GOTO(s, tl_linear_solver_solve(p->ls, y, y), done);
      st->operator_applications++;
    } else if (ido == 1) { /* y = (K - sigma M)^-1 (M x), M x given */
      TL_CHECK_GOTO(s, tl_linear_solver_solve(p->ls, workd + ipntr[2] - 1, y), done);
      st->operator_applications++;
    } else if (ido == 2) { /* y = M x */
      mass_apply(p, x, y);
    } else {
      break;
    }
  }
  st->restarts = iparam[2];
  if (info < 0 || info == 3) {
    s = tl_error_set(TL_ERR_CONVERGENCE, __FILE__, __LINE__, "ARPACK dsaupd: info = %d (%s)", (int)info,
                     arpack_message((int)info));
    goto done;
  }
  if (info == 1 || iparam[4] < nev) {
    s = tl_error_set(TL_ERR_CONVERGENCE, __FILE__, __LINE__,
                     "ARPACK found %d of %d eigenpairs in %d restarts (%s); raise max_restarts or ncv (%d)",
                     (int)iparam[4], (int)nev, (int)iparam[2], arpack_message((int)info), (int)ncv);
    goto done;
  }
  a_int rinfo = 0;
  dseupd_c(1, "A", select, d, z, n, o->shift, "G", n, "LM", nev, o->tol, resid, ncv, v, n, iparam, ipntr, workd,
           workl, lworkl, &rinfo);
  if (rinfo != 0) {
    s = tl_error_set(TL_ERR_CONVERGENCE, __FILE__, __LINE__, "ARPACK dseupd: info = %d", (int)rinfo);
    goto done;
  }
  st->t_lanczos = tl_wtime() - t0;
  /* Ascending order, then the residual of each pair. */
  for (a_int i = 1; i < nev; ++i)
    for (a_int j = i; j > 0 && d[j - 1] > d[j]; --j) {
      double tmp = d[j];
      d[j] = d[j - 1], d[j - 1] = tmp;
      for (a_int k = 0; k < n; ++k) {
        tmp = z[j * n + k];
        z[j * n + k] = z[(j - 1) * n + k], z[(j - 1) * n + k] = tmp;
      }
    }
  st->residual = 0.0;
  for (a_int i = 0; i < nev; ++i) {
    const double *phi = z + (size_t)i * (size_t)n;
    tl_sparse_matvec(p->K, phi, Kx);
    mass_apply(p, phi, Mx);
    double rn = 0.0, kn = 0.0;
    for (a_int k = 0; k < n; ++k) {
      const double r = Kx[k] - d[i] * Mx[k];
      rn += r * r, kn += Kx[k] * Kx[k];
    }
    st->residual = fmax(st->residual, sqrt(rn / fmax(kn, 1e-300)));
    if (!isfinite(d[i]) || !isfinite(rn)) {
      s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "eigenvalue %d = %g", (int)i, d[i]);
      goto done;
    }
    omega2[i] = d[i];
  }
  if (modes) memcpy(modes, z, (size_t)n * (size_t)nev * sizeof *z);
done:
  tl_free(&resid);
  tl_free(&v);
  tl_free(&workd);
  tl_free(&workl);
  tl_free(&z);
  tl_free(&d);
  tl_free(&select);
  tl_free(&Kx);
  tl_free(&Mx);
  return s;
}
#endif

TlStatus tl_modal_solve(TlMechSystem *sys, const TlModalOptions *o, double *omega2, double *modes,
                        TlModalStats *stats)
{
  if (!sys || !o || !omega2) TL_ERROR(TL_ERR_ARG, "tl_modal_solve: NULL system, options or eigenvalue array");
  if (o->n_modes < 1) TL_ERROR(TL_ERR_ARG, "modal analysis: n_modes = %d must be >= 1", o->n_modes);
  if (o->max_restarts < 1) TL_ERROR(TL_ERR_ARG, "modal analysis: max_restarts = %ld must be >= 1", o->max_restarts);
  if (!(o->tol >= 0.0) || !isfinite(o->shift))
    TL_ERROR(TL_ERR_ARG, "modal analysis: tol = %g must be >= 0 and the shift %g finite", o->tol, o->shift);
  if (!(o->n_modes < sys->ndof))
    TL_ERROR(TL_ERR_ARG, "modal analysis: %d modes wanted of a system with %lld dofs", o->n_modes,
             (long long)sys->ndof);
  if (!sys->symmetric)
    TL_ERROR(TL_ERR_UNSUPPORTED, "modal analysis needs a symmetric system; %s is not", sys->ops->header.name);
#if TALUS_WITH_ARPACK
  TlModalStats st;
  memset(&st, 0, sizeof st);
  st.ndof = sys->ndof;
  Pencil p;
  memset(&p, 0, sizeof p);
  p.sys = sys;
  double t0 = tl_wtime();
  TlStatus s = assemble(&p, o, &st);
  st.t_assemble = tl_wtime() - t0;
  t0 = tl_wtime();
  if (s == TL_OK) s = factor(&p, o);
  st.t_factor = tl_wtime() - t0;
  if (s == TL_OK) s = lanczos(&p, o, omega2, modes, &st);
  if (s == TL_OK && stats) *stats = st;
  tl_linear_solver_destroy(&p.ls);
  tl_sparse_destroy(&p.K);
  tl_sparse_destroy(&p.M);
  tl_sparse_destroy(&p.A);
  tl_free(&p.m);
  return s == TL_OK ? TL_OK : tl_error_trace(s, __FILE__, __LINE__);
#else
  (void)modes, (void)stats;
  TL_ERROR(TL_ERR_UNSUPPORTED,
           "modal analysis: this build of Talus has no ARPACK (install libarpack2-dev and reconfigure)");
#endif
}
