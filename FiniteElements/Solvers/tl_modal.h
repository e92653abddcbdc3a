/* Modal analysis of a mechanical system (tl_mech_system.h): the lowest
 * eigenpairs of
 *
 *     K phi = omega^2 M phi,   K = d f_int / du at u = 0,
 *
 * with the consistent mass (or the lumped one), by ARPACK's implicitly
 * restarted Lanczos method (dsaupd / dseupd, Debian libarpack2) in
 * shift-invert mode: the operator (K - sigma M)^-1 M, applied through one
 * CHOLMOD factorisation of K - sigma M, whose largest eigenvalues
 * 1 / (omega^2 - sigma) are the frequencies nearest the shift.  Clamped
 * dofs left out of the numbering need nothing; Dirichlet dofs kept in it
 * are held at zero (their rows and columns eliminated: an infinite
 * eigenvalue each, never among the ones found).  With sigma = 0 the
 * stiffness must be positive definite (a body that cannot move rigidly);
 * a free body needs a negative shift.  Modes are M-orthonormal:
 * phi_i . M phi_j = delta_ij.
 *
 * ARPACK is optional at build time: tl_modal_available() says whether this
 * build has it; without it tl_modal_solve returns TL_ERR_UNSUPPORTED. */
#ifndef TL_MODAL_H
#define TL_MODAL_H

#include "tl_error.h"
#include "tl_mech_system.h"

typedef struct {
  int n_modes;         /* eigenpairs wanted [6] */
  double shift;        /* sigma, (rad/s)^2 [0] */
  int lumped;          /* the lumped mass instead of the consistent one [0] */
  double tol;          /* ARPACK's relative accuracy of the Ritz values [0: machine precision] */
  int ncv;             /* Lanczos vectors [0: max(2 n_modes + 1, 20), at most ndof] */
  long max_restarts;   /* [1000] */
} TlModalOptions;

typedef struct {
  TlSparseIndex ndof;
  int consistent;               /* the consistent mass was used */
  long restarts, operator_applications;
  double t_assemble, t_factor, t_lanczos; /* seconds */
  double residual;              /* max_i ||K phi_i - omega_i^2 M phi_i|| / ||K phi_i|| */
} TlModalStats;

void tl_modal_options_default(TlModalOptions *o);
/* 1 when built with ARPACK. */
int tl_modal_available(void);
/* omega2[n_modes] ascending, and when modes != NULL the mode shapes,
 * modes[k * ndof + i] for mode k.  stats may be NULL. */
TlStatus tl_modal_solve(TlMechSystem *sys, const TlModalOptions *o, double *omega2, double *modes,
                        TlModalStats *stats);

#endif
