/* PSTLO, the contact network as a pre-stressed truss with grain rotations
 * (tl_nhl_operator.h, specs/fem-x-dem.md §7): the network's linearised
 * balance solved for the fluctuations of every unit G, over the contacts the
 * network operators share (tl_nhl_operator_network.h). */
#include "tl_nhl_operator_network.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "tl_contact_law.h"
#include "tl_linear_solver.h"
#include "tl_memory.h"
#include "tl_particles.h"
#include "tl_sparse.h"

/* The contact's stiffness K_e = −∂(forces, moments)/∂z over its dofs
 * z = [u_i, θ_i, u_j, θ_j] (12 x 12, row-major). */
static void element_matrix(const NetContact *cc, double *Ke)
{
  for (int a = 0; a < 12; ++a) {
    double y[9] = {0}, out[9];
    /* z_a: δb = u_j − u_i, θ_i, θ_j */
    if (a < 3) y[a] = -1.0;
    else if (a < 6) y[a] = 1.0;
    else if (a < 9) y[a - 6] = 1.0;
    else y[a - 3] = 1.0;
    tl_nhl_net_contact_linear(cc, y, 1, 1, out);
    double g[12] = {out[0], out[1], out[2], out[3], out[4], out[5], -out[0], -out[1], -out[2], out[6], out[7], out[8]};
    for (int r = 0; r < 12; ++r) Ke[r * 12 + a] = -g[r];
  }
}

static size_t find_root(size_t *parent, size_t a)
{
  while (parent[a] != a) {
    parent[a] = parent[parent[a]];
    a = parent[a];
  }
  return a;
}

/* PSTLO (Talus's reading of ref. [31]): unknowns are the fluctuating
 * translations and the rotations of every particle with at least two
 * contacts (rattlers removed, repeatedly); for each unit G the network's
 * linearised balance of forces and moments, K z = −J_G G, is solved with one
 * factorisation; one particle per connected cluster is pinned (its
 * fluctuation is a free translation), and a particle direction without
 * stiffness (a frictionless grain's rotation, the spin about a lone
 * contact's normal) gets a penalty so the factorisation exists — such a
 * direction carries no force. */
typedef struct {
  TlNhlOperator base;
  double solver; /* 0 auto; 1 UMFPACK, 2 KLU on the full matrix (comparisons) */
} Pstlo;

static const TlParam pstlo_params[] = {
    {"solver", 0, 0, 2, "1",
     "0: CHOLMOD, refined on the symmetric part when the network is not symmetric (LU if that fails); 1: UMFPACK "
     "LU of the full matrix; 2: KLU LU of the full matrix", offsetof(Pstlo, solver)},
};

static TlStatus pstlo_run(const TlNhlOperator *op, const TlNhlOperatorInput *in, int symm, double c[81],
                          TlNhlOperatorStats *st, int *not_definite)
{
  *not_definite = 0;
  Net N;
  TL_CHECK(tl_nhl_net_gather(in, &N));
  TlParticles *P = tl_dem_particles(in->dem);
  const size_t np = P->n;
  const int dim = in->dim;
  TlStatus s = TL_OK;
  size_t *count = NULL, *parent = NULL, *root_pin = NULL;
  unsigned char *alive = NULL;
  TlSparseIndex *dof = NULL, *eptr = NULL, *edofs = NULL;
  double *Ke = NULL, *rhs = NULL, *z = NULL, *blocks = NULL, *r2 = NULL, *dz = NULL;
  TlSparse *A = NULL, *Ps = NULL;
  TlLinearSolver *ls = NULL;
  memset(c, 0, 81 * sizeof *c);
#define TRY(x) TL_CHECK_GOTO(s, (x), done)
  TRY(tl_calloc(&count, np + 1, sizeof *count));
  TRY(tl_calloc(&alive, N.n + 1, 1));
  for (size_t q = 0; q < N.n; ++q) alive[q] = 1;
  /* rattlers: fewer than two live contacts, removed until none is left */
  for (int changed = 1; changed;) {
    changed = 0;
    memset(count, 0, np * sizeof *count);
    for (size_t q = 0; q < N.n; ++q)
      if (alive[q]) count[N.c[q].i]++, count[N.c[q].j]++;
    for (size_t q = 0; q < N.n; ++q)
      if (alive[q] && (count[N.c[q].i] < 2 || count[N.c[q].j] < 2)) alive[q] = 0, changed = 1;
  }
  size_t n_live = 0, n_part = 0;
  for (size_t q = 0; q < N.n; ++q) n_live += alive[q];
  for (size_t p = 0; p < np; ++p) n_part += count[p] >= 2;
  st->contacts = n_live;
  st->particles = n_part;
  st->rattlers = np - n_part;
  if (n_live == 0) TRY(tl_error_set(TL_ERR_STATE, __FILE__, __LINE__, "pstlo: the cell has no load-bearing contact (%zu contacts, all rattlers')", N.n));
  /* clusters: pin one particle of each */
  TRY(tl_calloc(&parent, np + 1, sizeof *parent));
  TRY(tl_calloc(&root_pin, np + 1, sizeof *root_pin));
  for (size_t p = 0; p < np; ++p) parent[p] = p;
  for (size_t q = 0; q < N.n; ++q)
    if (alive[q]) {
      size_t a = find_root(parent, N.c[q].i), b = find_root(parent, N.c[q].j);
      if (a != b) parent[a] = b;
    }
  size_t clusters = 0;
  for (size_t p = 0; p < np; ++p)
    if (count[p] >= 2 && find_root(parent, p) == p) clusters++;
  /* dof map: 6 per particle (u, θ); 2-D keeps u_x, u_y, θ_z */
  TRY(tl_calloc(&dof, 6 * np + 1, sizeof *dof));
  for (size_t p = 0; p < np; ++p) root_pin[p] = 0;
  TlSparseIndex nd = 0;
  for (size_t p = 0; p < np; ++p) {
    int pin = 0;
    if (count[p] >= 2 && P->motion[p] == TL_MOTION_FREE) {
      size_t r = find_root(parent, p);
      if (!root_pin[r]) root_pin[r] = 1, pin = 1;
    }
    for (int k = 0; k < 6; ++k) {
      int keep = count[p] >= 2 && P->motion[p] == TL_MOTION_FREE;
      if (dim == 2 && (k == 2 || k == 3 || k == 4)) keep = 0;
      if (k < 3 && pin) keep = 0;
      dof[6 * p + k] = keep ? nd++ : -1;
    }
  }
  st->rigid_modes = clusters * (size_t)dim;
  if (nd == 0) TRY(tl_error_set(TL_ERR_STATE, __FILE__, __LINE__, "pstlo: no free degree of freedom"));
  /* pattern: one 12-dof element per live contact */
  TRY(tl_calloc(&eptr, n_live + 1, sizeof *eptr));
  TRY(tl_calloc(&edofs, 12 * n_live + 1, sizeof *edofs));
  size_t e = 0;
  for (size_t q = 0; q < N.n; ++q) {
    if (!alive[q]) continue;
    for (int k = 0; k < 6; ++k) edofs[12 * e + k] = dof[6 * N.c[q].i + k], edofs[12 * e + 6 + k] = dof[6 * N.c[q].j + k];
    eptr[e + 1] = (TlSparseIndex)(12 * (e + 1));
    e++;
  }
  TRY(tl_calloc(&Ke, 144, sizeof *Ke));
  if (symm < 0) {
    /* symmetric to round-off (no tangential force yet: fresh springs, or a
     * frictionless network): CHOLMOD, exactly what the full matrix gives */
    symm = 1;
    for (size_t q = 0; q < N.n && symm; ++q) {
      if (!alive[q]) continue;
      element_matrix(&N.c[q], Ke);
      double big = 0.0;
      for (int r = 0; r < 144; ++r) big = fmax(big, fabs(Ke[r]));
      for (int r = 0; r < 12 && symm; ++r)
        for (int a = 0; a < r; ++a)
          if (fabs(Ke[r * 12 + a] - Ke[a * 12 + r]) > 1e-13 * big) {
            symm = 0;
            break;
          }
    }
  }
  /* symm: 1 symmetrised values, CHOLMOD; 2 symmetrised values, LU; 0 the
   * full matrix solved by iterative refinement on CHOLMOD's factor of its
   * symmetric part (the non-symmetric part, the tangential forces'
   * transport, is of order f_T/(k l) of the springs); 3 the full matrix, LU */
  const int upper = symm == 1, sym_values = symm == 1 || symm == 2, refine = symm == 0;
  TRY(tl_sparse_create_from_elements(nd, upper, (TlSparseIndex)n_live, eptr, edofs, 0, &A));
  if (refine) TRY(tl_sparse_create_from_elements(nd, 1, (TlSparseIndex)n_live, eptr, edofs, 0, &Ps));
  TRY(tl_calloc(&blocks, 18 * np + 1, sizeof *blocks)); /* per particle: u-block and θ-block, 3x3 each */
  e = 0;
  for (size_t q = 0; q < N.n; ++q) {
    if (!alive[q]) continue;
    const NetContact *cc = &N.c[q];
    element_matrix(cc, Ke);
    double Ks[144];
    for (int r = 0; r < 12; ++r)
      for (int a = 0; a < 12; ++a) Ks[r * 12 + a] = 0.5 * (Ke[r * 12 + a] + Ke[a * 12 + r]);
    if (sym_values) memcpy(Ke, Ks, sizeof Ks);
    TRY(tl_sparse_add_element(A, 12, edofs + 12 * e, 1.0, Ke));
    if (refine) TRY(tl_sparse_add_element(Ps, 12, edofs + 12 * e, 1.0, Ks));
    for (int side = 0; side < 2; ++side) {
      size_t p = side ? cc->j : cc->i;
      for (int blk = 0; blk < 2; ++blk)
        for (int r = 0; r < 3; ++r)
          for (int a = 0; a < 3; ++a) blocks[18 * p + 9 * blk + 3 * r + a] += Ke[(6 * side + 3 * blk + r) * 12 + 6 * side + 3 * blk + a];
    }
    e++;
  }
  /* directions of a particle without stiffness: penalty */
  double ref[2] = {0, 0};
  for (size_t p = 0; p < np; ++p)
    for (int blk = 0; blk < 2; ++blk) {
      double w[3], S[9];
      const double *B = blocks + 18 * p + 9 * blk;
      for (int r = 0; r < 3; ++r)
        for (int a = 0; a < 3; ++a) S[3 * r + a] = 0.5 * (B[3 * r + a] + B[3 * a + r]);
      tl_nhl_sym_eigen(3, S, w, NULL);
      for (int r = 0; r < 3; ++r) ref[blk] = fmax(ref[blk], fabs(w[r]));
    }
  {
    /* frictionless grains: no rotational stiffness anywhere; the penalty's
     * scale from the translations and the lever arms */
    double a2 = 0.0;
    for (size_t q = 0; q < N.n; ++q) a2 += N.c[q].ai * N.c[q].ai;
    a2 /= (double)N.n;
    /* the rotational scale is at least the translational one times a²: round-off in a
     * frictionless network's rotation block must not pass for stiffness */
    ref[1] = fmax(ref[1], ref[0] * a2);
    if (!(ref[0] > 0.0) || !(ref[1] > 0.0))
      TRY(tl_error_set(TL_ERR_STATE, __FILE__, __LINE__, "pstlo: the network has no stiffness (scale %g)", ref[0]));
  }
  for (size_t p = 0; p < np; ++p)
    for (int blk = 0; blk < 2; ++blk) {
      if (count[p] < 2) continue;
      double w[3], V[9], S[9];
      const double *B = blocks + 18 * p + 9 * blk;
      for (int r = 0; r < 3; ++r)
        for (int a = 0; a < 3; ++a) {
          int keep = 1;
          if (dim == 2) keep = blk == 0 ? (r < 2 && a < 2) : (r == 2 && a == 2);
          S[3 * r + a] = keep ? 0.5 * (B[3 * r + a] + B[3 * a + r]) : 0.0;
        }
      tl_nhl_sym_eigen(3, S, w, V);
      for (int m = 0; m < 3; ++m) {
        TlVec3 v = {V[0 * 3 + m], V[1 * 3 + m], V[2 * 3 + m]};
        if (dim == 2) {
          /* only in-plane directions of the kept dofs count */
          if (blk == 0 && fabs(v.z) > 0.5) continue;
          if (blk == 1 && fabs(v.z) < 0.5) continue;
        }
        if (fabs(w[m]) > 1e-9 * ref[blk]) continue;
        double vv[3] = {v.x, v.y, v.z};
        int pinned = 0;
        for (int r = 0; r < 3; ++r)
          if (dof[6 * p + 3 * blk + r] < 0 && fabs(vv[r]) > 1e-12) pinned = 1;
        if (pinned) continue;
        for (int r = 0; r < 3; ++r)
          for (int a = 0; a < 3; ++a) {
            TlSparseIndex dr = dof[6 * p + 3 * blk + r], da = dof[6 * p + 3 * blk + a];
            if (dr >= 0 && da >= 0 && vv[r] * vv[a] != 0.0 && (!upper || dr <= da))
              TRY(tl_sparse_add(A, dr, da, ref[blk] * vv[r] * vv[a]));
            if (refine && dr >= 0 && da >= 0 && vv[r] * vv[a] != 0.0 && dr <= da)
              TRY(tl_sparse_add(Ps, dr, da, ref[blk] * vv[r] * vv[a]));
          }
        st->rigid_modes++;
      }
    }
  {
    /* LU: UMFPACK (BLAS on the dense fronts of a 3-D network: 3x faster than
     * KLU on 864 spheres) */
    TlSparse *M = refine ? Ps : A;
    const char *lu = ((const Pstlo *)op)->solver > 1.5 ? "klu" : "umfpack";
    snprintf(st->solver, sizeof st->solver, "%s", refine ? "cholmod+refinement" : upper ? "cholmod" : lu);
    TRY(tl_linear_solver_create(upper || refine ? "cholmod" : lu, M, &ls));
    s = tl_linear_solver_factor(ls, M);
    if (s != TL_OK && (upper || refine)) *not_definite = 1;
    if (s != TL_OK) goto done;
  }
  TRY(tl_calloc(&rhs, (size_t)nd, sizeof *rhs));
  TRY(tl_calloc(&z, (size_t)nd, sizeof *z));
  TRY(tl_calloc(&r2, (size_t)nd, sizeof *r2));
  if (refine) TRY(tl_calloc(&dz, (size_t)nd, sizeof *dz));
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      if (dim == 2 && (k == 2 || l == 2)) continue;
      TlMat3 G = tl_nhl_net_unit_G(k, l);
      memset(rhs, 0, (size_t)nd * sizeof *rhs);
      for (size_t q = 0; q < N.n; ++q) {
        if (!alive[q]) continue;
        const NetContact *cc = &N.c[q];
        TlVec3 db = tl_m3_mulv(G, cc->b);
        double y[9] = {db.x, db.y, db.z, 0, 0, 0, 0, 0, 0}, out[9];
        tl_nhl_net_contact_linear(cc, y, 1, 1, out);
        double g[12] = {out[0], out[1], out[2], out[3], out[4], out[5], -out[0], -out[1], -out[2], out[6], out[7], out[8]};
        for (int r = 0; r < 12; ++r) {
          TlSparseIndex d = (r < 6 ? dof[6 * cc->i + r] : dof[6 * cc->j + r - 6]);
          if (d >= 0) rhs[d] += g[r];
        }
      }
      TRY(tl_linear_solver_solve(ls, rhs, z));
      double rn = 0.0, bn = 0.0, rprev = INFINITY;
      for (TlSparseIndex d = 0; d < nd; ++d) bn += rhs[d] * rhs[d];
      for (int it = 0;; ++it) {
        tl_sparse_matvec(A, z, r2);
        rn = 0.0;
        for (TlSparseIndex d = 0; d < nd; ++d) r2[d] = rhs[d] - r2[d], rn += r2[d] * r2[d];
        if (!refine || !(rn > 1e-26 * bn)) break;
        if (it >= 60 || (it >= 3 && !(rn < 0.25 * rprev))) {
          /* the non-symmetric part is too large for the refinement: LU */
          *not_definite = 1;
          s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__,
                           "pstlo: refinement on the symmetric part stalls at residual %g after %d sweeps",
                           sqrt(rn / bn), it);
          goto done;
        }
        rprev = rn;
        TRY(tl_linear_solver_solve(ls, r2, dz));
        for (TlSparseIndex d = 0; d < nd; ++d) z[d] += dz[d];
        st->refinements++;
      }
      if (bn > 0.0) st->residual = fmax(st->residual, sqrt(rn / bn));
      TlMat3 ds = tl_m3_zero();
      for (size_t q = 0; q < N.n; ++q) {
        if (!alive[q]) continue;
        const NetContact *cc = &N.c[q];
        double zi[6], zj[6];
        for (int r = 0; r < 6; ++r) {
          TlSparseIndex di = dof[6 * cc->i + r], dj = dof[6 * cc->j + r];
          zi[r] = di >= 0 ? z[di] : 0.0;
          zj[r] = dj >= 0 ? z[dj] : 0.0;
        }
        TlVec3 db = tl_m3_mulv(G, cc->b);
        double y[9] = {db.x + zj[0] - zi[0], db.y + zj[1] - zi[1], db.z + zj[2] - zi[2], zi[3], zi[4], zi[5],
                       zj[3], zj[4], zj[5]},
               out[9];
        tl_nhl_net_contact_linear(cc, y, 1, 1, out);
        tl_nhl_net_add_stress(cc, y, out, &ds);
      }
      tl_nhl_net_finish(c, k, l, ds, N.V, in->sigma, G);
    }
  if (!(st->residual <= 1e-6))
    s = tl_error_set(TL_ERR_NUMERIC, __FILE__, __LINE__, "pstlo: the condensation solve left a relative residual %g (limit 1e-6): the network has a floppy mode", st->residual);
done:
#undef TRY
  tl_linear_solver_destroy(&ls);
  tl_sparse_destroy(&A);
  tl_sparse_destroy(&Ps);
  tl_free(&dz);
  tl_free(&count), tl_free(&parent), tl_free(&root_pin), tl_free(&alive);
  tl_free(&dof), tl_free(&eptr), tl_free(&edofs);
  tl_free(&Ke), tl_free(&rhs), tl_free(&z), tl_free(&blocks), tl_free(&r2);
  tl_free(&N.c);
  return s;
}

static TlStatus pstlo_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *so, double *sn,
                              double c[81], TlNhlOperatorStats *st)
{
  (void)so, (void)sn;
  /* full (symm = -1): a symmetric network goes to CHOLMOD, a non-symmetric
   * one to iterative refinement on CHOLMOD's factor of its symmetric part
   * (the full matrix's answer, at the symmetric factorisation's cost);
   * symmetrised: CHOLMOD on the symmetric part alone.  When CHOLMOD finds
   * the matrix indefinite (a pre-stress beyond what the springs hold) or the
   * refinement stalls: LU (UMFPACK). */
  int not_definite = 0, symmetrise = op->symmetrise > 0.5, lu = ((const Pstlo *)op)->solver > 0.5;
  TlStatus s = pstlo_run(op, in, lu ? (symmetrise ? 2 : 3) : symmetrise ? 1 : -1, c, st, &not_definite);
  if (s != TL_OK && not_definite) {
    tl_error_clear();
    memset(st, 0, sizeof *st);
    s = pstlo_run(op, in, symmetrise ? 2 : 3, c, st, &not_definite);
  }
  return s;
}

const TlNhlOperatorOps tl_nhl_pstlo_ops = {
    {"nhl_operator", "pstlo",
     "pre-stressed truss-like (Talus's reading): network stiffness with rotations, fluctuations condensed (CHOLMOD)"},
    sizeof(Pstlo), pstlo_params, 1, 0, NULL, pstlo_compute, NULL};
