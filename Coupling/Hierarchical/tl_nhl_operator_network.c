/* The tangent operators computed from the cell's contact network, and demqo
 * (tl_nhl_operator.h; specs/fem-x-dem.md §7, whose readings of the operators
 * the paper only cites are Talus's and marked so in the descriptions).
 *
 * Every operator starts from the same linearisation of one contact c
 * between particles i and j (branch b = x_j − x_i of length l, unit normal
 * n = b / l, lever arms a_i, a_j to the contact point, force f on i with
 * repulsive normal magnitude f_N and tangential part f_T, normal and
 * tangential stiffness k_n, k_t).  For an increment of the branch δb and
 * rotations θ_i, θ_j, the relative displacement at the contact point is
 *     δ = δb − (a_i θ_i + a_j θ_j) ∧ n,
 * the force increment on i
 *     δf = k_n (n·δ) n + k_t (δ − (n·δ) n)                    (springs)
 *          − f_N δn − (f_T·δn) n + ½((θ_i + θ_j)·n) n ∧ f_T     (pre-stress)
 * with δn = (δb − (n·δb) n) / l — the existing force turned with the contact
 * plane (Eqs. 11 / 24 agree to first order) and by the mean spin (Eq. 24) —
 * and the torques M_i = a_i n ∧ f, M_j = a_j n ∧ f (on j: the lever −a_j n
 * and the force −f) change by a n ∧ δf + (δa n + a δn) ∧ f, δa = ½ n·δb
 * (the lever r − δ/2; 0 for a law whose lever is the radius).  A rigid
 * rotation ψ (δb = ψ ∧ b, θ = ψ) gives δ = 0 and δf = ψ ∧ f: the
 * linearisation is objective.  The stress increment (Eq. 27 varied, the
 * volume by tr G) is
 *     δσ = (1/V) Σ_c (δf ⊗ b + f ⊗ δb) − σ tr G.
 * Stiffnesses come from the contact's own law, differentiated at the
 * contact's overlap (exact for the linear law, the tangent k_n = dF_N/dδ for
 * Hertz), the tangential one on a fresh spring (the elastic stiffness, so
 * sliding contacts stick: the elastic network of demqo's μ = ∞). */
#include "tl_nhl_operator.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "tl_contact_law.h"
#include "tl_linear_solver.h"
#include "tl_memory.h"
#include "tl_particles.h"
#include "tl_sparse.h"


typedef struct {
  size_t i, j;
  TlVec3 n, b, f, ft;
  double l, ai, aj, fn, kn, kt;
  int sliding, lever_fixed;
} NetContact;

typedef struct {
  NetContact *c;
  size_t n, cap;
  TlDem *dem;
  TlStatus status;
  double V;
  int dim;
} Net;

/* k_n and k_t of a contact from its law: central differences of the normal
 * force in the overlap (no velocity: no damping), and the tangential force
 * of a fresh spring stretched by u over a time T so long that the damping
 * c u / T is below round-off. */
static TlStatus law_stiffness(const TlContactLaw *law, double overlap, double meff, double reff, TlVec3 n,
                              double *kn, double *kt)
{
  double hist[64] = {0};
  if (law->history_doubles > 64) TL_ERROR(TL_ERR_ARG, "contact law keeps %zu history doubles (limit 64 here)", law->history_doubles);
  TlContactGeometry g;
  memset(&g, 0, sizeof g);
  g.normal = n;
  g.meff = meff;
  g.reff = reff;
  g.history = hist;
  double h = 1e-3 * overlap;
  if (!(h > 1e-12 * reff)) h = 1e-12 * reff;
  TlContactResult r;
  double F[2];
  for (int s = 0; s < 2; ++s) {
    memset(hist, 0, sizeof hist);
    g.overlap = overlap + (s ? h : -h);
    if (g.overlap <= 0.0) g.overlap = overlap;
    TL_CHECK(tl_contact_law_evaluate_one(law, &g, 1e-30, &r));
    F[s] = -tl_v3_dot(r.force, n);
  }
  double o_lo = overlap - h > 0.0 ? overlap - h : overlap;
  *kn = (F[1] - F[0]) / (overlap + h - o_lo);
  /* tangential: a direction perpendicular to n */
  TlVec3 t = fabs(n.x) < 0.9 ? tl_v3_cross(n, tl_v3(1, 0, 0)) : tl_v3_cross(n, tl_v3(0, 1, 0));
  t = tl_v3_normalize(t);
  double u = 1e-9 * reff, T = 1e12 * sqrt(meff / fmax(*kn, 1e-300));
  memset(hist, 0, sizeof hist);
  g.overlap = overlap;
  g.vrel = tl_v3_scale(t, u / T);
  TL_CHECK(tl_contact_law_evaluate_one(law, &g, T, &r));
  *kt = tl_v3_dot(r.force, t) / u;
  /* a law without a tangential part leaves round-off of the normal force */
  if (!(*kt >= 1e-9 * *kn)) *kt = 0.0;
  return TL_OK;
}

static void visit(void *ctx, size_t i, size_t j, TlVec3 f, TlVec3 b, TlVec3 cp)
{
  Net *N = ctx;
  (void)cp;
  if (N->status != TL_OK) return;
  TlParticles *P = tl_dem_particles(N->dem);
  double l = tl_v3_norm(b);
  if (!(l > 0.0)) return;
  TlStatus s = tl_array_reserve(&N->c, &N->cap, N->n + 1, sizeof *N->c);
  if (s != TL_OK) {
    N->status = s;
    return;
  }
  NetContact *c = &N->c[N->n++];
  memset(c, 0, sizeof *c);
  c->i = i, c->j = j, c->b = b, c->l = l, c->f = f;
  c->n = tl_v3_scale(b, 1.0 / l);
  c->fn = -tl_v3_dot(f, c->n);
  c->ft = tl_v3_axpy(f, c->fn, c->n);
  double ri = P->radius[i], rj = P->radius[j], ov = ri + rj - l;
  const TlContactLaw *law = tl_dem_law(N->dem, tl_dem_pair_law(N->dem, P->species[i], P->species[j]));
  if (!law) {
    N->status = TL_ERR_STATE;
    return;
  }
  c->lever_fixed = law->lever_radius;
  c->ai = tl_contact_lever(law, ri, ov);
  c->aj = tl_contact_lever(law, rj, ov);
  double mi = P->mass[i], mj = P->mass[j];
  double meff = P->motion[j] != TL_MOTION_FREE ? mi : mi * mj / (mi + mj);
  s = law_stiffness(law, ov, meff, ri * rj / (ri + rj), c->n, &c->kn, &c->kt);
  if (s != TL_OK) {
    N->status = s;
    return;
  }
  double mu;
  if (tl_contact_law_get(law, "mu", &mu) == TL_OK && mu > 0.0 && c->fn > 0.0)
    c->sliding = tl_v3_norm(c->ft) >= (1.0 - 1e-9) * mu * c->fn;
}

static TlStatus gather(const TlNhlOperatorInput *in, Net *N)
{
  memset(N, 0, sizeof *N);
  N->dem = in->dem;
  N->dim = in->dim;
  N->V = tl_domain_volume(tl_dem_domain(in->dem));
  /* disks: per unit thickness, the cell's area (what tl_dem_stress divides by) */
  if (in->dim == 2) N->V = tl_domain_area(tl_dem_domain(in->dem));
  TL_CHECK(tl_dem_visit_contacts(in->dem, visit, N));
  if (N->status != TL_OK) {
    tl_free(&N->c);
    TL_ERROR(N->status, "nhl operator: reading the cell's contacts failed");
  }
  return TL_OK;
}

/* The contact's linearisation: y = [δb, θ_i, θ_j] -> [δf on i, δM_i, δM_j].
 * springs: the stiffness part; geo: the pre-stress part. */
static void contact_linear(const NetContact *c, const double y[9], int springs, int geo, double out[9])
{
  TlVec3 db = {y[0], y[1], y[2]}, ti = {y[3], y[4], y[5]}, tj = {y[6], y[7], y[8]};
  TlVec3 n = c->n, df = {0, 0, 0};
  double bn = tl_v3_dot(n, db);
  TlVec3 dn = tl_v3_scale(tl_v3_axpy(db, -bn, n), 1.0 / c->l);
  if (springs) {
    TlVec3 d = tl_v3_sub(db, tl_v3_cross(tl_v3_add(tl_v3_scale(ti, c->ai), tl_v3_scale(tj, c->aj)), n));
    double dnn = tl_v3_dot(n, d);
    df = tl_v3_add(tl_v3_scale(n, c->kn * dnn), tl_v3_scale(tl_v3_axpy(d, -dnn, n), c->kt));
  }
  if (geo) {
    df = tl_v3_axpy(df, -c->fn, dn);
    df = tl_v3_axpy(df, -tl_v3_dot(c->ft, dn), n);
    df = tl_v3_axpy(df, 0.5 * tl_v3_dot(tl_v3_add(ti, tj), n), tl_v3_cross(n, c->ft));
  }
  TlVec3 Mi = tl_v3_scale(tl_v3_cross(n, df), c->ai), Mj = tl_v3_scale(tl_v3_cross(n, df), c->aj);
  if (geo) {
    double da = c->lever_fixed ? 0.0 : 0.5 * bn;
    Mi = tl_v3_add(Mi, tl_v3_cross(tl_v3_add(tl_v3_scale(n, da), tl_v3_scale(dn, c->ai)), c->f));
    Mj = tl_v3_add(Mj, tl_v3_cross(tl_v3_add(tl_v3_scale(n, da), tl_v3_scale(dn, c->aj)), c->f));
  }
  out[0] = df.x, out[1] = df.y, out[2] = df.z;
  out[3] = Mi.x, out[4] = Mi.y, out[5] = Mi.z;
  out[6] = Mj.x, out[7] = Mj.y, out[8] = Mj.z;
}

/* δσ (before / V and the volume term) of one contact. */
static void add_stress(const NetContact *c, const double y[9], const double out[9], TlMat3 *ds)
{
  TlVec3 df = {out[0], out[1], out[2]}, db = {y[0], y[1], y[2]};
  *ds = tl_m3_add(*ds, tl_m3_add(tl_m3_outer(df, c->b), tl_m3_outer(c->f, db)));
}

static TlMat3 unit_G(int k, int l)
{
  TlMat3 G = tl_m3_zero();
  G.m[k][l] = 1.0;
  return G;
}

static TlVec3 spin_of(TlMat3 G)
{
  /* ω with ω ∧ x = skew(G) x */
  return tl_v3(0.5 * (G.m[2][1] - G.m[1][2]), 0.5 * (G.m[0][2] - G.m[2][0]), 0.5 * (G.m[1][0] - G.m[0][1]));
}

static void finish(double c[81], int k, int l, TlMat3 ds, double V, TlMat3 sigma, TlMat3 G)
{
  TlMat3 s = tl_m3_add(tl_m3_scale(ds, 1.0 / V), tl_m3_scale(sigma, -tl_m3_trace(G)));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c[TL_NHL_C(i, j, k, l)] = s.m[i][j];
}

/* ---------------------------------------------------------------- uko, kao */

/* Eq. 33 (Talus: every contact's own k_n, k_t; sliding ones with k_t or 0):
 * the normal part in cn, the tangential one in ct, of the network of in;
 * the contacts counted in st. */
static TlStatus uko_parts(const TlNhlOperator *op, const TlNhlOperatorInput *in, double cn[81], double ct[81],
                          TlNhlOperatorStats *st)
{
  Net net;
  TL_CHECK(gather(in, &net));
  const Net *N = &net;
  memset(cn, 0, 81 * sizeof *cn);
  memset(ct, 0, 81 * sizeof *ct);
  for (size_t q = 0; q < N->n; ++q) {
    const NetContact *c = &N->c[q];
    double kt = c->sliding && !(op->sliding_kt > 0.5) ? 0.0 : c->kt;
    double n[3] = {c->n.x, c->n.y, c->n.z}, b[3] = {c->b.x, c->b.y, c->b.z};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) {
        double Kn = c->kn * n[i] * n[k], Kt = kt * ((i == k) - n[i] * n[k]);
        for (int j = 0; j < 3; ++j)
          for (int l = 0; l < 3; ++l) {
            cn[TL_NHL_C(i, j, k, l)] += Kn * b[j] * b[l] / N->V;
            ct[TL_NHL_C(i, j, k, l)] += Kt * b[j] * b[l] / N->V;
          }
      }
  }
  /* disks: the k_t δ_zz term acts on nothing a disk does (fits use this) */
  if (N->dim == 2)
    for (int q = 0; q < 81; ++q)
      if (q / 27 == 2 || (q / 9) % 3 == 2 || (q / 3) % 3 == 2 || q % 3 == 2) cn[q] = ct[q] = 0.0;
  st->contacts = N->n;
  tl_free(&net.c);
  return TL_OK;
}

static TlStatus uko_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *so, double *sn,
                            double c[81], TlNhlOperatorStats *st)
{
  (void)so, (void)sn;
  double ct[81];
  TL_CHECK(uko_parts(op, in, c, ct, st));
  for (int q = 0; q < 81; ++q) c[q] += ct[q];
  return TL_OK;
}

/* KAO (Talus's reading): uko plus the pre-stress terms of the existing forces
 * carried by the affine deformation, and the grain rotations as extra
 * unknowns eliminated grain by grain with no global solve: each grain's
 * rotation balances its own moments with its neighbours turning with the
 * macro spin ω = skew(G) (rotations = 1, the default; one block-Jacobi step
 * of pstlo's moment equations from the spin, translations kept affine), or
 * every grain turns with the spin (rotations = 0).  Both are objective.
 * (The literal "contact by contact" elimination would relax every
 * tangential spring entirely: k_t would drop out.) */
typedef struct {
  TlNhlOperator base;
  double rotations;
} Kao;

static const TlParam kao_params[] = {
    {"rotations", 1, 0, 1, "",
     "1: each grain's rotation from its own moment balance, neighbours at the macro spin; 0: every grain at the spin",
     offsetof(Kao, rotations)},
};

/* θ = ω − (T + ρ 1)⁻¹ M: the grain's moment balance, ρ a round-off
 * regularisation for directions without rotational stiffness (a frictionless
 * grain, the spin about a lone contact's normal: no moment there either). */
static TlVec3 grain_rotation(const double T[9], TlVec3 M, TlVec3 w, int dim, double ref)
{
  /* ref: the network's k_n a², the scale below which T is round-off */
  if (dim == 2) return fabs(T[8]) > 1e-9 * ref ? tl_v3(w.x, w.y, w.z - M.z / T[8]) : w;
  if (!(fabs(T[0]) + fabs(T[4]) + fabs(T[8]) > 1e-9 * ref)) return w;
  TlMat3 A = {{{T[0], T[1], T[2]}, {T[3], T[4], T[5]}, {T[6], T[7], T[8]}}}, Ai;
  for (int i = 0; i < 3; ++i) A.m[i][i] += 1e-9 * ref;
  if (!tl_m3_inverse(A, &Ai)) return w;
  return tl_v3_sub(w, tl_m3_mulv(Ai, M));
}

static TlStatus kao_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *so, double *sn,
                            double c[81], TlNhlOperatorStats *st)
{
  (void)so, (void)sn;
  const int own = ((const Kao *)op)->rotations > 0.5, dim = in->dim;
  Net N;
  TL_CHECK(gather(in, &N));
  for (size_t q = 0; q < N.n; ++q)
    if (N.c[q].sliding && !(op->sliding_kt > 0.5)) N.c[q].kt = 0.0;
  const size_t np = tl_dem_particles(in->dem)->n;
  double *T = NULL, *M = NULL;
  TlVec3 *th = NULL;
  TlStatus s = TL_OK;
  double ref = 0.0;
  if (own) {
    TL_CHECK_GOTO(s, tl_calloc(&T, 9 * np + 1, sizeof *T), done);
    TL_CHECK_GOTO(s, tl_calloc(&M, 3 * np + 1, sizeof *M), done);
    TL_CHECK_GOTO(s, tl_calloc(&th, np + 1, sizeof *th), done);
    for (size_t q = 0; q < N.n; ++q) ref = fmax(ref, N.c[q].kn * N.c[q].ai * N.c[q].ai);
    /* T_p = ∂M_p/∂θ_p, summed over the grain's contacts */
    for (size_t q = 0; q < N.n; ++q)
      for (int a = 0; a < 3; ++a) {
        double yi[9] = {0}, yj[9] = {0}, oi[9], oj[9];
        yi[3 + a] = 1.0, yj[6 + a] = 1.0;
        contact_linear(&N.c[q], yi, 1, 1, oi);
        contact_linear(&N.c[q], yj, 1, 1, oj);
        for (int r = 0; r < 3; ++r) {
          T[9 * N.c[q].i + 3 * r + a] += oi[3 + r];
          T[9 * N.c[q].j + 3 * r + a] += oj[6 + r];
        }
      }
  }
  memset(c, 0, 81 * sizeof *c);
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      if (dim == 2 && (k == 2 || l == 2)) continue;
      TlMat3 G = unit_G(k, l), ds = tl_m3_zero();
      TlVec3 w = spin_of(G);
      if (own) {
        memset(M, 0, 3 * np * sizeof *M);
        for (size_t q = 0; q < N.n; ++q) {
          TlVec3 db = tl_m3_mulv(G, N.c[q].b);
          double y[9] = {db.x, db.y, db.z, w.x, w.y, w.z, w.x, w.y, w.z}, out[9];
          contact_linear(&N.c[q], y, 1, 1, out);
          for (int r = 0; r < 3; ++r) M[3 * N.c[q].i + r] += out[3 + r], M[3 * N.c[q].j + r] += out[6 + r];
        }
        for (size_t p = 0; p < np; ++p)
          th[p] = grain_rotation(T + 9 * p, tl_v3(M[3 * p], M[3 * p + 1], M[3 * p + 2]), w, dim, ref);
      }
      for (size_t q = 0; q < N.n; ++q) {
        const NetContact *cc = &N.c[q];
        TlVec3 db = tl_m3_mulv(G, cc->b), ti = own ? th[cc->i] : w, tj = own ? th[cc->j] : w;
        double y[9] = {db.x, db.y, db.z, ti.x, ti.y, ti.z, tj.x, tj.y, tj.z}, out[9];
        contact_linear(cc, y, 1, 1, out);
        add_stress(cc, y, out, &ds);
      }
      finish(c, k, l, ds, N.V, in->sigma, G);
    }
  st->contacts = N.n;
done:
  tl_free(&T), tl_free(&M), tl_free(&th);
  tl_free(&N.c);
  return s;
}

/* ---------------------------------------------------------------- pstlo */

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
    contact_linear(cc, y, 1, 1, out);
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
    {"solver", 0, 0, 2, "",
     "0: CHOLMOD, refined on the symmetric part when the network is not symmetric (LU if that fails); 1: UMFPACK "
     "LU of the full matrix; 2: KLU LU of the full matrix", offsetof(Pstlo, solver)},
};

static TlStatus pstlo_run(const TlNhlOperator *op, const TlNhlOperatorInput *in, int symm, double c[81],
                          TlNhlOperatorStats *st, int *not_definite)
{
  *not_definite = 0;
  Net N;
  TL_CHECK(gather(in, &N));
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
      TlMat3 G = unit_G(k, l);
      memset(rhs, 0, (size_t)nd * sizeof *rhs);
      for (size_t q = 0; q < N.n; ++q) {
        if (!alive[q]) continue;
        const NetContact *cc = &N.c[q];
        TlVec3 db = tl_m3_mulv(G, cc->b);
        double y[9] = {db.x, db.y, db.z, 0, 0, 0, 0, 0, 0}, out[9];
        contact_linear(cc, y, 1, 1, out);
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
        contact_linear(cc, y, 1, 1, out);
        add_stress(cc, y, out, &ds);
      }
      finish(c, k, l, ds, N.V, in->sigma, G);
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

/* ---------------------------------------------------------------- demqo */

static TlStatus demqo_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *so, double *sn,
                              double c[81], TlNhlOperatorStats *st)
{
  (void)so, (void)sn;
  TL_CHECK(tl_nhl_operator_perturb(op, in, TL_NHL_EVAL_PROBE, c, st));
  Net N;
  TL_CHECK(gather(in, &N));
  st->contacts = N.n;
  tl_free(&N.c);
  return TL_OK;
}

/* ---------------------------------------------------------------- ucko */

typedef struct {
  TlNhlOperator base;
  double reference; /* 0 cto, 1 demqo, 2 pstlo */
} Ucko;

static const TlParam ucko_params[] = {
    {"reference", 0, 0, 2, "", "operator the coefficients are fitted to: 0 cto (the paper), 1 demqo, 2 pstlo",
     offsetof(Ucko, reference)},
};

static TlStatus reference_operator(const TlNhlOperator *op, const TlNhlOperatorInput *in, double c[81],
                                   TlNhlOperatorStats *st)
{
  static const char *const names[] = {"cto", "demqo", "pstlo"};
  int r = (int)((const Ucko *)op)->reference;
  TlNhlOperator *ref;
  TL_CHECK(tl_nhl_operator_create(names[r], &ref));
  TlStatus s = TL_OK;
  for (int k = 0; k < 4 && s == TL_OK; ++k) {
    static const char *const p[] = {"eps", "directions", "sliding_kt", "symmetrise"};
    double v;
    tl_nhl_operator_get(op, p[k], &v);
    s = tl_nhl_operator_set(ref, p[k], v);
  }
  if (s == TL_OK) s = tl_nhl_operator_setup(ref);
  TlNhlOperatorStats rs;
  if (s == TL_OK) s = tl_nhl_operator_compute(ref, in, NULL, NULL, c, &rs);
  if (s == TL_OK) st->evaluations += rs.evaluations, st->dem_steps += rs.dem_steps, st->imbalance = rs.imbalance;
  tl_nhl_operator_destroy(&ref);
  return s;
}

/* UCKO (Talus's reading): c = α c^uko with α = (c^ref : c^uko)/(c^uko : c^uko)
 * fitted while in->calibrate and kept in the point's state; before any
 * calibration α = 1. */
static TlStatus ucko_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *so, double *sn,
                             double c[81], TlNhlOperatorStats *st)
{
  double cn[81], ct[81];
  TL_CHECK(uko_parts(op, in, cn, ct, st));
  for (int q = 0; q < 81; ++q) c[q] = cn[q] + ct[q];
  double alpha = so[1] > 0.5 ? so[0] : 1.0;
  if (in->calibrate) {
    double r[81], num = 0.0, den = 0.0;
    TL_CHECK(reference_operator(op, in, r, st));
    for (int q = 0; q < 81; ++q) num += r[q] * c[q], den += c[q] * c[q];
    if (!(den > 0.0)) TL_ERROR(TL_ERR_NUMERIC, "ucko: the uko operator is zero (no contact stiffness) at calibration");
    alpha = num / den;
    sn[0] = alpha, sn[1] = 1.0;
  }
  for (int q = 0; q < 81; ++q) c[q] *= alpha;
  return TL_OK;
}

/* UCKO-2DOF (reading): c = α_n c_n^uko + α_t c_t^uko, the normal and
 * tangential parts of Eq. 33, least squares against the reference. */
static TlStatus ucko2_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *so, double *sn,
                              double c[81], TlNhlOperatorStats *st)
{
  double cn[81], ct[81];
  TL_CHECK(uko_parts(op, in, cn, ct, st));
  double an = so[2] > 0.5 ? so[0] : 1.0, at = so[2] > 0.5 ? so[1] : 1.0;
  if (in->calibrate) {
    double r[81], a11 = 0, a12 = 0, a22 = 0, b1 = 0, b2 = 0;
    TL_CHECK(reference_operator(op, in, r, st));
    for (int q = 0; q < 81; ++q) {
      a11 += cn[q] * cn[q], a12 += cn[q] * ct[q], a22 += ct[q] * ct[q];
      b1 += cn[q] * r[q], b2 += ct[q] * r[q];
    }
    double det = a11 * a22 - a12 * a12;
    if (a22 > 1e-20 * a11 && fabs(det) > 1e-12 * a11 * a22) {
      an = (b1 * a22 - b2 * a12) / det;
      at = (a11 * b2 - a12 * b1) / det;
    } else if (a11 > 0.0) {
      an = b1 / a11, at = 1.0; /* no tangential stiffness: one coefficient */
    } else
      TL_ERROR(TL_ERR_NUMERIC, "ucko_2dof: the uko operator is zero (no contact stiffness) at calibration");
    sn[0] = an, sn[1] = at, sn[2] = 1.0;
  }
  for (int q = 0; q < 81; ++q) c[q] = an * cn[q] + at * ct[q];
  return TL_OK;
}

/* ---------------------------------------------------------------- registration */

static const TlNhlOperatorOps uko_ops = {
    {"nhl_operator", "uko", "upper-bound Kruyt (Eq. 33): every grain follows the macro field, no rotation"},
    sizeof(TlNhlOperator), NULL, 0, 0, NULL, uko_compute, NULL};
static const TlNhlOperatorOps kao_ops = {
    {"nhl_operator", "kao",
     "augmented Kruyt (Talus's reading): uko + pre-stress terms, grain rotations eliminated grain by grain"},
    sizeof(Kao), kao_params, 1, 0, NULL, kao_compute, NULL};
static const TlNhlOperatorOps pstlo_ops = {
    {"nhl_operator", "pstlo",
     "pre-stressed truss-like (Talus's reading): network stiffness with rotations, fluctuations condensed (CHOLMOD)"},
    sizeof(Pstlo), pstlo_params, 1, 0, NULL, pstlo_compute, NULL};
static const TlNhlOperatorOps demqo_ops = {
    {"nhl_operator", "demqo", "DEM quasi-elastic (Eq. 32): short probes from the equilibrated cell, no sliding"},
    sizeof(TlNhlOperator), NULL, 0, 0, NULL, demqo_compute, NULL};
static const TlNhlOperatorOps ucko_ops = {
    {"nhl_operator", "ucko", "corrected Kruyt (Talus's reading): alpha uko, alpha fitted to the CTO while calibrating"},
    sizeof(Ucko), ucko_params, 1, 2, NULL, ucko_compute, NULL};
static const TlNhlOperatorOps ucko2_ops = {
    {"nhl_operator", "ucko_2dof",
     "corrected Kruyt, two coefficients (Talus's reading): normal and tangential parts of uko fitted separately"},
    sizeof(Ucko), ucko_params, 1, 3, NULL, ucko2_compute, NULL};

TlStatus tl_nhl_operator_register_all(void)
{
  const TlNhlOperatorOps *all[] = {&uko_ops, &ucko_ops, &ucko2_ops, &kao_ops, &pstlo_ops, &demqo_ops};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) TL_CHECK(tl_nhl_operator_register(all[k]));
  return TL_OK;
}
