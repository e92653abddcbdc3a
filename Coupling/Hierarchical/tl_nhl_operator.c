/* The NHL tangent operator registry, the conversions of the operator to the
 * solid's D = dS/dE, and the perturbation recipe of demqo / cto / aeo
 * (tl_nhl_operator.h).  The network operators are in
 * tl_nhl_operator_network.c. */
#include "tl_nhl_operator.h"

#include <math.h>
#include <string.h>
#include "tl_material.h"
#include "tl_memory.h"
#include "tl_timer.h"

static const char *const KIND = "nhl_operator";

static const TlParam base_params[] = {
    {"eps", 1e-5, 1e-12, 1e-1, "1", "perturbation size of demqo and cto (a reading; the paper gives none)",
     offsetof(TlNhlOperator, eps)},
    {"directions", 9, 6, 9, "1",
     "9: the nine directions of Eq. 30 (4 in 2-D); 6: symmetric increments only (3 in 2-D), rotations by "
     "objectivity", offsetof(TlNhlOperator, directions)},
    {"sliding_kt", 1, 0, 1, "1", "1: sliding contacts keep k_t in uko/ucko/kao (the upper bound as printed); 0: k_t = 0",
     offsetof(TlNhlOperator, sliding_kt)},
    {"symmetrise", 0, 0, 1, "1", "1: pstlo symmetrises its stiffness (CHOLMOD); 0: the full matrix (CHOLMOD, refined when not symmetric)",
     offsetof(TlNhlOperator, symmetrise)},
};
enum { N_BASE = (int)(sizeof base_params / sizeof base_params[0]) };

TlStatus tl_nhl_operator_register(const TlNhlOperatorOps *ops)
{
  if (!ops || !ops->header.name || !ops->compute)
    TL_ERROR(TL_ERR_ARG, "nhl operator: ops table, its name and compute() are required");
  if (!ops->header.kind || strcmp(ops->header.kind, KIND) != 0)
    TL_ERROR(TL_ERR_ARG, "nhl operator '%s': kind '%s' must be '%s'", ops->header.name,
             ops->header.kind ? ops->header.kind : "(null)", KIND);
  if (ops->size < sizeof(TlNhlOperator))
    TL_ERROR(TL_ERR_ARG, "nhl operator '%s': size %zu is below the base struct's %zu", ops->header.name, ops->size,
             sizeof(TlNhlOperator));
  for (int k = 0; k < ops->n_params; ++k) {
    const TlParam *p = &ops->params[k];
    if (p->offset < sizeof(TlNhlOperator) || p->offset + sizeof(double) > ops->size)
      TL_ERROR(TL_ERR_ARG, "nhl operator '%s': parameter '%s' at offset %zu lies outside the derived struct (%zu..%zu)",
               ops->header.name, p->name, p->offset, sizeof(TlNhlOperator), ops->size);
    if (!(p->def >= p->lo && p->def <= p->hi))
      TL_ERROR(TL_ERR_ARG, "nhl operator '%s': default %g of '%s' outside [%g, %g]", ops->header.name, p->def,
               p->name, p->lo, p->hi);
  }
  TlTypeEntry e = {KIND, ops->header.name, ops->header.description, NULL, ops, ops->params, ops->n_params};
  return tl_registry_register(&e);
}

TlStatus tl_nhl_operator_create(const char *name, TlNhlOperator **out)
{
  const TlTypeEntry *e;
  TL_CHECK(tl_registry_lookup(KIND, name, &e));
  const TlNhlOperatorOps *ops = e->ops;
  TlNhlOperator *op;
  TL_CHECK(tl_calloc(&op, 1, ops->size));
  op->ops = ops;
  for (int k = 0; k < N_BASE; ++k) *(double *)((char *)op + base_params[k].offset) = base_params[k].def;
  for (int k = 0; k < ops->n_params; ++k) *(double *)((char *)op + ops->params[k].offset) = ops->params[k].def;
  *out = op;
  return TL_OK;
}

static const TlParam *find_param(const TlNhlOperator *op, const char *name)
{
  const TlParam *p = tl_param_find(base_params, N_BASE, name);
  return p ? p : tl_param_find(op->ops->params, op->ops->n_params, name);
}

TlStatus tl_nhl_operator_set(TlNhlOperator *op, const char *name, double value)
{
  const TlParam *p = find_param(op, name);
  if (!p) TL_ERROR(TL_ERR_ARG, "nhl operator '%s' has no parameter '%s'", op->ops->header.name, name);
  if (!(value >= p->lo && value <= p->hi))
    TL_ERROR(TL_ERR_ARG, "nhl operator '%s': %s = %g outside [%g, %g]", op->ops->header.name, name, value, p->lo,
             p->hi);
  if (strcmp(name, "directions") == 0 && value != 6 && value != 9)
    TL_ERROR(TL_ERR_ARG, "nhl operator '%s': directions = %g must be 6 or 9", op->ops->header.name, value);
  *(double *)((char *)op + p->offset) = value;
  op->ready = 0;
  return TL_OK;
}

TlStatus tl_nhl_operator_get(const TlNhlOperator *op, const char *name, double *value)
{
  const TlParam *p = find_param(op, name);
  if (!p) TL_ERROR(TL_ERR_ARG, "nhl operator '%s' has no parameter '%s'", op->ops->header.name, name);
  *value = *(const double *)((const char *)op + p->offset);
  return TL_OK;
}

TlStatus tl_nhl_operator_setup(TlNhlOperator *op)
{
  if (op->ops->setup) TL_CHECK(op->ops->setup(op));
  op->ready = 1;
  return TL_OK;
}

void tl_nhl_operator_destroy(TlNhlOperator **op)
{
  if (!op || !*op) return;
  if ((*op)->ops->destroy) (*op)->ops->destroy(*op);
  tl_free(op);
}

size_t tl_nhl_operator_state_size(const TlNhlOperator *op) { return op->ops->state_size; }

TlStatus tl_nhl_operator_compute(const TlNhlOperator *op, const TlNhlOperatorInput *in, const double *state_old,
                                 double *state_new, double c[81], TlNhlOperatorStats *stats)
{
  if (!op->ready) TL_ERROR(TL_ERR_STATE, "nhl operator '%s' is not set up (tl_nhl_operator_setup)", op->ops->header.name);
  if (!in || !in->dem) TL_ERROR(TL_ERR_ARG, "nhl operator '%s': no cell given", op->ops->header.name);
  if (in->dim != 2 && in->dim != 3) TL_ERROR(TL_ERR_ARG, "nhl operator '%s': dim = %d must be 2 or 3", op->ops->header.name, in->dim);
  if (tl_dem_dimension(in->dem) != in->dim)
    TL_ERROR(TL_ERR_ARG, "nhl operator '%s': dim = %d but the cell's world has dimension %d", op->ops->header.name,
             in->dim, tl_dem_dimension(in->dem));
  TlNhlOperatorStats local;
  TlNhlOperatorStats *st = stats ? stats : &local;
  memset(st, 0, sizeof *st);
  size_t ns = op->ops->state_size;
  if (ns > 0 && (!state_old || !state_new))
    TL_ERROR(TL_ERR_ARG, "nhl operator '%s' keeps %zu doubles per point: state arrays required", op->ops->header.name, ns);
  if (ns > 0 && state_new != state_old) memcpy(state_new, state_old, ns * sizeof *state_new);
  double t0 = tl_wtime();
  TL_CHECK(op->ops->compute(op, in, state_old, state_new, c, st));
  st->seconds = tl_wtime() - t0;
  /* disks: the 3-D operator restricted to the plane (a spring's k_t along z,
   * for one, acts on nothing a disk can do) */
  if (in->dim == 2)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l)
            if (i == 2 || j == 2 || k == 2 || l == 2) c[TL_NHL_C(i, j, k, l)] = 0.0;
  for (int q = 0; q < 81; ++q)
    if (!isfinite(c[q]))
      TL_ERROR(TL_ERR_NUMERIC, "nhl operator '%s': component %d of c is %g", op->ops->header.name, q, c[q]);
  int sym = 1;
  double cmax = 0.0;
  for (int q = 0; q < 81; ++q) cmax = fmax(cmax, fabs(c[q]));
  for (int a = 0; a < 9 && sym; ++a)
    for (int b = 0; b < a; ++b)
      if (fabs(c[a * 9 + b] - c[b * 9 + a]) > 1e-12 * cmax) sym = 0;
  st->symmetric = sym;
  return TL_OK;
}

/* ---------------------------------------------------------------- conversions */

static TlMat3 contract(const double c[81], TlMat3 G)
{
  TlMat3 s = tl_m3_zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double v = 0.0;
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) v += c[TL_NHL_C(i, j, k, l)] * G.m[k][l];
      s.m[i][j] = v;
    }
  return s;
}

void tl_nhl_operator_to_D(const double c[81], TlMat3 F, TlMat3 sigma, double D[36])
{
  TlMat3 Fi;
  tl_m3_inverse(F, &Fi);
  double J = tl_m3_det(F);
  TlMat3 FiT = tl_m3_transpose(Fi);
  for (int K = 0; K < 6; ++K) {
    /* the symmetric spatial increment d with Fᵀ d F = the unit engineering strain K */
    TlMat3 d = tl_m3_mul(FiT, tl_m3_mul(tl_voigt_unit_strain(K), Fi));
    TlMat3 ds = contract(c, d);
    /* an operator whose response is not symmetric (uko: grains that do not
     * turn) contributes its symmetric part: the stress is symmetric */
    ds = tl_m3_scale(tl_m3_add(ds, tl_m3_transpose(ds)), 0.5);
    TlMat3 t = tl_m3_add(ds, tl_m3_scale(sigma, tl_m3_trace(d)));
    t = tl_m3_add(t, tl_m3_scale(tl_m3_add(tl_m3_mul(d, sigma), tl_m3_mul(sigma, d)), -1.0));
    TlMat3 dS = tl_m3_scale(tl_m3_mul(Fi, tl_m3_mul(t, FiT)), J);
    double v[6];
    tl_voigt_from_sym(dS, v);
    for (int I = 0; I < 6; ++I) D[I * 6 + K] = v[I];
  }
}

void tl_nhl_operator_from_D(const double D[36], TlMat3 F, TlMat3 sigma, double c[81])
{
  double J = tl_m3_det(F);
  memset(c, 0, 81 * sizeof *c);
  for (int k = 0; k < 3; ++k)
    for (int l = k; l < 3; ++l) {
      TlMat3 d = tl_m3_zero();
      d.m[k][l] = d.m[l][k] = k == l ? 1.0 : 0.5;
      TlMat3 dE = tl_m3_mul(tl_m3_transpose(F), tl_m3_mul(d, F));
      double e[6], s[6];
      tl_voigt_from_sym(dE, e);
      for (int q = 3; q < 6; ++q) e[q] *= 2.0; /* engineering shear */
      for (int I = 0; I < 6; ++I) {
        s[I] = 0.0;
        for (int K = 0; K < 6; ++K) s[I] += D[I * 6 + K] * e[K];
      }
      TlMat3 dS = tl_voigt_to_sym(s);
      /* c : d = F dS Fᵀ / J + d σ + σ d − tr(d) σ */
      TlMat3 cd = tl_m3_scale(tl_m3_mul(F, tl_m3_mul(dS, tl_m3_transpose(F))), 1.0 / J);
      cd = tl_m3_add(cd, tl_m3_add(tl_m3_mul(d, sigma), tl_m3_mul(sigma, d)));
      cd = tl_m3_add(cd, tl_m3_scale(sigma, -tl_m3_trace(d)));
      /* d = ½ (Λ^{kl} + Λ^{lk}) for k ≠ l: both slots carry c : d */
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          c[TL_NHL_C(i, j, k, l)] = cd.m[i][j];
          c[TL_NHL_C(i, j, l, k)] = cd.m[i][j];
        }
    }
  tl_nhl_operator_objective(c, sigma);
}

void tl_nhl_operator_voigt(const double c[81], double C[36])
{
  for (int J = 0; J < 6; ++J) {
    double v[6];
    TlMat3 s = contract(c, tl_voigt_unit_strain(J));
    tl_voigt_from_sym(tl_m3_scale(tl_m3_add(s, tl_m3_transpose(s)), 0.5), v);
    for (int I = 0; I < 6; ++I) C[I * 6 + J] = v[I];
  }
}

void tl_nhl_operator_objective(double c[81], TlMat3 sigma)
{
  for (int k = 0; k < 3; ++k)
    for (int l = k + 1; l < 3; ++l) {
      /* G = Λ^{kl} = d + W with d = ½(Λ^{kl} + Λ^{lk}), W = ½(Λ^{kl} − Λ^{lk}) */
      TlMat3 d = tl_m3_zero(), W = tl_m3_zero();
      d.m[k][l] = d.m[l][k] = 0.5;
      W.m[k][l] = 0.5, W.m[l][k] = -0.5;
      TlMat3 cd = contract(c, d);
      TlMat3 cw = tl_m3_add(tl_m3_mul(W, sigma), tl_m3_scale(tl_m3_mul(sigma, W), -1.0));
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          c[TL_NHL_C(i, j, k, l)] = cd.m[i][j] + cw.m[i][j];
          c[TL_NHL_C(i, j, l, k)] = cd.m[i][j] - cw.m[i][j];
        }
    }
}

/* ---------------------------------------------------------------- perturbation */

TlStatus tl_nhl_operator_perturb(const TlNhlOperator *op, const TlNhlOperatorInput *in, TlNhlEvalMode mode,
                                 double c[81], TlNhlOperatorStats *st)
{
  if (!in->evaluate)
    TL_ERROR(TL_ERR_STATE, "nhl operator '%s' perturbs the law but the cell's owner gave no evaluate callback",
             op->ops->header.name);
  const double eps = op->eps;
  const int nine = op->directions > 7.5, nd = in->dim;
  memset(c, 0, 81 * sizeof *c);
  for (int k = 0; k < nd; ++k)
    for (int l = nine ? 0 : k; l < nd; ++l) {
      TlMat3 G = tl_m3_zero();
      if (nine) G.m[k][l] = 1.0;
      else G.m[k][l] = G.m[l][k] = k == l ? 1.0 : 0.5;
      TlMat3 Ft = tl_m3_add(in->F, tl_m3_scale(tl_m3_mul(G, in->F), eps));
      TlMat3 s;
      TlNhlEvalStats es = {0};
      TL_CHECK(in->evaluate(in->ctx, mode, Ft, &s, &es));
      st->evaluations++;
      st->dem_steps += es.dem_steps;
      st->tau += es.tau;
      st->imbalance = fmax(st->imbalance, es.imbalance);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (!isfinite(s.m[i][j]))
            TL_ERROR(TL_ERR_NUMERIC, "nhl operator '%s': the cell probed along (%d,%d) returned stress[%d][%d] = %g",
                     op->ops->header.name, k, l, i, j, s.m[i][j]);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double v = (s.m[i][j] - in->sigma.m[i][j]) / eps;
          c[TL_NHL_C(i, j, k, l)] = v;
          if (!nine) c[TL_NHL_C(i, j, l, k)] = v;
        }
    }
  if (!nine) tl_nhl_operator_objective(c, in->sigma);
  return TL_OK;
}

/* ---------------------------------------------------------------- eigen */

void tl_nhl_sym_eigen(int n, const double *A, double *w, double *V)
{
  double a[36], v[36];
  for (int q = 0; q < n * n; ++q) a[q] = A[q];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) v[i * n + j] = i == j;
  for (int sweep = 0; sweep < 60; ++sweep) {
    double off = 0.0, tot = 0.0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        double a2 = a[i * n + j] * a[i * n + j];
        if (i == j) tot += a2;
        else off += a2;
      }
    if (!(off > 1e-30 * (tot + off))) break;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        double apq = a[p * n + q];
        if (apq == 0.0) continue;
        double theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
        double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
        double cs = 1.0 / sqrt(t * t + 1.0), sn = t * cs;
        for (int k = 0; k < n; ++k) {
          double akp = a[k * n + p], akq = a[k * n + q];
          a[k * n + p] = cs * akp - sn * akq;
          a[k * n + q] = sn * akp + cs * akq;
        }
        for (int k = 0; k < n; ++k) {
          double apk = a[p * n + k], aqk = a[q * n + k];
          a[p * n + k] = cs * apk - sn * aqk;
          a[q * n + k] = sn * apk + cs * aqk;
        }
        for (int k = 0; k < n; ++k) {
          double vkp = v[k * n + p], vkq = v[k * n + q];
          v[k * n + p] = cs * vkp - sn * vkq;
          v[k * n + q] = sn * vkp + cs * vkq;
        }
      }
  }
  for (int i = 0; i < n; ++i) w[i] = a[i * n + i];
  if (V)
    for (int q = 0; q < n * n; ++q) V[q] = v[q];
}
