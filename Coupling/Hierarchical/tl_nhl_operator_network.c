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
#include "tl_nhl_operator_network.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include "tl_contact_law.h"
#include "tl_linear_solver.h"
#include "tl_memory.h"
#include "tl_particles.h"
#include "tl_sparse.h"



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

TlStatus tl_nhl_net_gather(const TlNhlOperatorInput *in, Net *N)
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
void tl_nhl_net_contact_linear(const NetContact *c, const double y[9], int springs, int geo, double out[9])
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
void tl_nhl_net_add_stress(const NetContact *c, const double y[9], const double out[9], TlMat3 *ds)
{
  TlVec3 df = {out[0], out[1], out[2]}, db = {y[0], y[1], y[2]};
  *ds = tl_m3_add(*ds, tl_m3_add(tl_m3_outer(df, c->b), tl_m3_outer(c->f, db)));
}

TlMat3 tl_nhl_net_unit_G(int k, int l)
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

void tl_nhl_net_finish(double c[81], int k, int l, TlMat3 ds, double V, TlMat3 sigma, TlMat3 G)
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
  TL_CHECK(tl_nhl_net_gather(in, &net));
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
    {"rotations", 1, 0, 1, "1",
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
  TL_CHECK(tl_nhl_net_gather(in, &N));
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
        tl_nhl_net_contact_linear(&N.c[q], yi, 1, 1, oi);
        tl_nhl_net_contact_linear(&N.c[q], yj, 1, 1, oj);
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
      TlMat3 G = tl_nhl_net_unit_G(k, l), ds = tl_m3_zero();
      TlVec3 w = spin_of(G);
      if (own) {
        memset(M, 0, 3 * np * sizeof *M);
        for (size_t q = 0; q < N.n; ++q) {
          TlVec3 db = tl_m3_mulv(G, N.c[q].b);
          double y[9] = {db.x, db.y, db.z, w.x, w.y, w.z, w.x, w.y, w.z}, out[9];
          tl_nhl_net_contact_linear(&N.c[q], y, 1, 1, out);
          for (int r = 0; r < 3; ++r) M[3 * N.c[q].i + r] += out[3 + r], M[3 * N.c[q].j + r] += out[6 + r];
        }
        for (size_t p = 0; p < np; ++p)
          th[p] = grain_rotation(T + 9 * p, tl_v3(M[3 * p], M[3 * p + 1], M[3 * p + 2]), w, dim, ref);
      }
      for (size_t q = 0; q < N.n; ++q) {
        const NetContact *cc = &N.c[q];
        TlVec3 db = tl_m3_mulv(G, cc->b), ti = own ? th[cc->i] : w, tj = own ? th[cc->j] : w;
        double y[9] = {db.x, db.y, db.z, ti.x, ti.y, ti.z, tj.x, tj.y, tj.z}, out[9];
        tl_nhl_net_contact_linear(cc, y, 1, 1, out);
        tl_nhl_net_add_stress(cc, y, out, &ds);
      }
      tl_nhl_net_finish(c, k, l, ds, N.V, in->sigma, G);
    }
  st->contacts = N.n;
done:
  tl_free(&T), tl_free(&M), tl_free(&th);
  tl_free(&N.c);
  return s;
}

/* ---------------------------------------------------------------- demqo */

static TlStatus demqo_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *so, double *sn,
                              double c[81], TlNhlOperatorStats *st)
{
  (void)so, (void)sn;
  TL_CHECK(tl_nhl_operator_perturb(op, in, TL_NHL_EVAL_PROBE, c, st));
  Net N;
  TL_CHECK(tl_nhl_net_gather(in, &N));
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
    {"reference", 0, 0, 2, "1", "operator the coefficients are fitted to: 0 cto (the paper), 1 demqo, 2 pstlo",
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
  const TlNhlOperatorOps *all[] = {&uko_ops, &ucko_ops, &ucko2_ops, &kao_ops, &tl_nhl_pstlo_ops, &demqo_ops};
  for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k) TL_CHECK(tl_nhl_operator_register(all[k]));
  return TL_OK;
}
