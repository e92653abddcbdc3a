#include "tl_material.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_registry.h"

extern const TlMaterialOps tl_material_hooke_ops, tl_material_hooke_covariant_ops,
    tl_material_neo_hookean_ops;

TlStatus tl_material_register(const TlMaterialOps *ops)
{
  if (!ops || !ops->header.name || !ops->header.name[0] || !ops->header.kind || strcmp(ops->header.kind, "material"))
    TL_ERROR(TL_ERR_ARG, "material ops table without a name or of kind '%s' (expected \"material\")",
             ops && ops->header.kind ? ops->header.kind : "(null)");
  const char *name = ops->header.name;
  if (ops->size < sizeof(TlMaterial))
    TL_ERROR(TL_ERR_ARG, "material type %s declares size %zu, below the base size %zu", name, ops->size,
             sizeof(TlMaterial));
  if (!ops->evaluate) TL_ERROR(TL_ERR_ARG, "material type %s has no evaluate", name);
  if (ops->n_params < 0 || (ops->n_params > 0 && !ops->params))
    TL_ERROR(TL_ERR_ARG, "material type %s announces %d parameters and gives %s", name, ops->n_params,
             ops->params ? "a table" : "none");
  for (int i = 0; i < ops->n_params; ++i) {
    const TlParam *p = &ops->params[i];
    if (!p->name || !strcmp(p->name, "density") || tl_param_find(ops->params, i, p->name))
      TL_ERROR(TL_ERR_ARG, "material type %s: parameter %d is unnamed, named 'density' or named twice", name, i);
    if (p->offset < sizeof(TlMaterial) || p->offset + sizeof(double) > ops->size)
      TL_ERROR(TL_ERR_ARG, "material type %s: parameter %s at offset %zu lies outside the derived part [%zu, %zu)",
               name, p->name, p->offset, sizeof(TlMaterial), ops->size);
    if (!(p->lo <= p->def && p->def <= p->hi))
      TL_ERROR(TL_ERR_ARG, "material type %s: parameter %s has default %g outside [%g, %g]", name, p->name, p->def,
               p->lo, p->hi);
  }
  TlTypeEntry e = {"material", name, ops->header.description, NULL, ops, ops->params, ops->n_params};
  TL_CHECK(tl_registry_register(&e));
  return TL_OK;
}

TlStatus tl_material_register_all(void)
{
  TL_CHECK(tl_material_register(&tl_material_hooke_ops));
  TL_CHECK(tl_material_register(&tl_material_hooke_covariant_ops));
  TL_CHECK(tl_material_register(&tl_material_neo_hookean_ops));
  return TL_OK;
}

static const double density_default = 1000.0;

TlStatus tl_material_create(const char *name, TlMaterial **m)
{
  if (!name || !m) TL_ERROR(TL_ERR_ARG, "tl_material_create: NULL argument");
  const TlOpsHeader *h = NULL;
  TL_CHECK(tl_registry_find("material", name, &h));
  const TlMaterialOps *ops = (const TlMaterialOps *)h;
  if (ops->size < sizeof(TlMaterial))
    TL_ERROR(TL_ERR_ARG, "material type %s declares size %zu, below the base size %zu", name,
             ops->size, sizeof(TlMaterial));
  char *mem = NULL;
  TL_CHECK(tl_calloc(&mem, 1, ops->size));
  TlMaterial *mat = (TlMaterial *)mem;
  mat->ops = ops;
  mat->density = density_default;
  mat->eigenstrain = tl_m3_zero();
  mat->initial_stress = tl_m3_zero();
  for (int i = 0; i < ops->n_params; ++i)
    *(double *)(mem + ops->params[i].offset) = ops->params[i].def;
  *m = mat;
  return TL_OK;
}

void tl_material_destroy(TlMaterial **m)
{
  if (!m || !*m) return;
  if ((*m)->ops->destroy) (*m)->ops->destroy(*m);
  tl_free(m);
}

TlStatus tl_material_set(TlMaterial *m, const char *param, double value)
{
  if (!m || !param) TL_ERROR(TL_ERR_ARG, "tl_material_set: NULL argument");
  if (!isfinite(value))
    TL_ERROR(TL_ERR_ARG, "material %s: parameter %s = %g is not finite", m->ops->header.name,
             param, value);
  if (!strcmp(param, "density")) {
    if (!(value > 0.0))
      TL_ERROR(TL_ERR_ARG, "material %s: density = %g kg/m^3 must be > 0", m->ops->header.name,
               value);
    m->density = value;
    m->ready = 0;
    return TL_OK;
  }
  for (int i = 0; i < m->ops->n_params; ++i) {
    const TlMaterialParam *p = &m->ops->params[i];
    if (strcmp(p->name, param)) continue;
    if (value < p->lo || value > p->hi)
      TL_ERROR(TL_ERR_ARG, "material %s: %s = %g %s outside [%g, %g]", m->ops->header.name, param,
               value, p->unit, p->lo, p->hi);
    *(double *)((char *)m + p->offset) = value;
    m->ready = 0;
    return TL_OK;
  }
  TL_ERROR(TL_ERR_NOT_FOUND, "material %s has no parameter '%s'", m->ops->header.name, param);
}

TlStatus tl_material_get(const TlMaterial *m, const char *param, double *value)
{
  if (!strcmp(param, "density")) {
    *value = m->density;
    return TL_OK;
  }
  for (int i = 0; i < m->ops->n_params; ++i)
    if (!strcmp(m->ops->params[i].name, param)) {
      *value = *(const double *)((const char *)m + m->ops->params[i].offset);
      return TL_OK;
    }
  TL_ERROR(TL_ERR_NOT_FOUND, "material %s has no parameter '%s'", m->ops->header.name, param);
}

static TlStatus check_symmetric(const TlMaterial *m, TlMat3 a, const char *what)
{
  double scale = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (!isfinite(a.m[i][j]))
        TL_ERROR(TL_ERR_ARG, "material %s: %s[%d][%d] = %g is not finite", m->ops->header.name,
                 what, i, j, a.m[i][j]);
      scale = fmax(scale, fabs(a.m[i][j]));
    }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < i; ++j)
      if (fabs(a.m[i][j] - a.m[j][i]) > 1e-12 * scale)
        TL_ERROR(TL_ERR_ARG, "material %s: %s is not symmetric ([%d][%d] = %g, [%d][%d] = %g)",
                 m->ops->header.name, what, i, j, a.m[i][j], j, i, a.m[j][i]);
  return TL_OK;
}

TlStatus tl_material_set_eigenstrain(TlMaterial *m, TlMat3 E0)
{
  TL_CHECK(check_symmetric(m, E0, "eigenstrain"));
  m->eigenstrain = E0;
  m->has_eigenstrain = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (E0.m[i][j] != 0.0) m->has_eigenstrain = 1;
  m->ready = 0;
  return TL_OK;
}

TlStatus tl_material_set_initial_stress(TlMaterial *m, TlMat3 S0)
{
  TL_CHECK(check_symmetric(m, S0, "initial stress"));
  m->initial_stress = S0;
  m->has_initial_stress = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (S0.m[i][j] != 0.0) m->has_initial_stress = 1;
  return TL_OK;
}

TlStatus tl_material_setup(TlMaterial *m)
{
  if (!m) TL_ERROR(TL_ERR_ARG, "tl_material_setup: NULL material");
  if (m->ops->setup) TL_CHECK(m->ops->setup(m));
  m->ready = 1;
  return TL_OK;
}

TlStatus tl_material_create_hooke(double E, double nu, double density, TlMaterial **m)
{
  TlMaterial *mat = NULL;
  TL_CHECK(tl_material_create("hooke", &mat));
  TlStatus s = TL_OK;
  TL_CHECK_GOTO(s, tl_material_set(mat, "E", E), fail);
  TL_CHECK_GOTO(s, tl_material_set(mat, "nu", nu), fail);
  TL_CHECK_GOTO(s, tl_material_set(mat, "density", density), fail);
  TL_CHECK_GOTO(s, tl_material_setup(mat), fail);
  *m = mat;
  return TL_OK;
fail:
  tl_material_destroy(&mat);
  return s;
}

double tl_material_trace_series(TlMat3 M, int kind)
{
  double norm = sqrt(tl_m3_ddot(M, M));
  if (norm > 0.3) {
    TlMat3 IM = tl_m3_add(tl_m3_identity(), M), inv = tl_m3_identity();
    double logdet = log(tl_m3_det(IM));
    if (kind == 1) return tl_m3_trace(M) - logdet;
    tl_m3_inverse(IM, &inv);
    return logdet + tl_m3_trace(inv) - 3.0;
  }
  TlMat3 P = tl_m3_mul(M, M); /* M^k, from k = 2 */
  double sum = 0.0;
  for (int k = 2; k < 80; ++k) {
    double coef = (k % 2 ? -1.0 : 1.0) * (kind == 0 ? (double)(k - 1) / k : 1.0 / k);
    double term = coef * tl_m3_trace(P);
    sum += term;
    if (fabs(term) <= 1e-18 * fabs(sum)) break;
    P = tl_m3_mul(P, M);
  }
  return sum;
}

int tl_material_symmetric_tangent(const TlMaterial *m)
{
  return m->ops->symmetric_tangent ? m->ops->symmetric_tangent(m) : 0;
}

/* Points per internal batch: gamma is computed into a stack buffer. */
#define TL_MATERIAL_CHUNK 64

/* One chunk: from displacement gradients H (F = 1 + H) when `gradient`,
 * otherwise from F.  The Green strain is formed from H as
 * (H + H^T + H^T H)/2, which keeps its relative precision at small strain
 * (F^T F - 1 would cancel about log10(1/strain) digits).  The checks
 * (det F > 0, finite stress) only flag in the loops, which stay free of
 * branches; the offending point is looked up once something is flagged. */
static TlStatus evaluate_chunk(const TlMaterial *m, size_t p0, size_t n, const TlMat3 *in, int gradient,
                               const double *state_old, double *state_new, TlMat3 *S, double *D,
                               double *W)
{
  TlMat3 gamma[TL_MATERIAL_CHUNK], F[TL_MATERIAL_CHUNK];
  const double shift = gradient ? 0.0 : 1.0; /* H = in - shift 1 */
  const double(*e0)[3] = m->eigenstrain.m;
  int bad = 0;
  for (size_t k = 0; k < n; ++k) {
    const double(*a)[3] = in[k].m;
    const double h00 = a[0][0] - shift, h01 = a[0][1], h02 = a[0][2], h10 = a[1][0], h11 = a[1][1] - shift,
                 h12 = a[1][2], h20 = a[2][0], h21 = a[2][1], h22 = a[2][2] - shift;
    double(*f)[3] = F[k].m, (*g)[3] = gamma[k].m;
    f[0][0] = 1.0 + h00, f[0][1] = h01, f[0][2] = h02;
    f[1][0] = h10, f[1][1] = 1.0 + h11, f[1][2] = h12;
    f[2][0] = h20, f[2][1] = h21, f[2][2] = 1.0 + h22;
    const double J = f[0][0] * (f[1][1] * f[2][2] - h12 * h21) - h01 * (h10 * f[2][2] - h12 * h20) +
                     h02 * (h10 * h21 - f[1][1] * h20);
    bad |= !(J > 0.0);
    g[0][0] = h00 + 0.5 * (h00 * h00 + h10 * h10 + h20 * h20) - e0[0][0];
    g[1][1] = h11 + 0.5 * (h01 * h01 + h11 * h11 + h21 * h21) - e0[1][1];
    g[2][2] = h22 + 0.5 * (h02 * h02 + h12 * h12 + h22 * h22) - e0[2][2];
    g[0][1] = g[1][0] = 0.5 * (h01 + h10 + h00 * h01 + h10 * h11 + h20 * h21) - e0[0][1];
    g[1][2] = g[2][1] = 0.5 * (h12 + h21 + h01 * h02 + h11 * h12 + h21 * h22) - e0[1][2];
    g[0][2] = g[2][0] = 0.5 * (h02 + h20 + h00 * h02 + h10 * h12 + h20 * h22) - e0[0][2];
  }
  if (bad)
    for (size_t k = 0; k < n; ++k) {
      double J = tl_m3_det(F[k]);
      if (!(J > 0.0))
        TL_ERROR(TL_ERR_NUMERIC, "material %s: det F = %g at point %zu is not positive (inverted element)",
                 m->ops->header.name, J, p0 + k);
    }
  TL_CHECK(m->ops->evaluate(m, n, F, gamma, state_old, state_new, S, D, W));
  if (m->has_initial_stress)
    for (size_t k = 0; k < n; ++k) {
      S[k] = tl_m3_add(S[k], m->initial_stress);
      if (W) W[k] += tl_m3_ddot(m->initial_stress, gamma[k]);
    }
  for (size_t k = 0; k < n; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) bad |= !(fabs(S[k].m[i][j]) <= DBL_MAX);
  if (bad)
    for (size_t k = 0; k < n; ++k)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (!isfinite(S[k].m[i][j]))
            TL_ERROR(TL_ERR_NUMERIC, "material %s: stress S[%d][%d] = %g at point %zu", m->ops->header.name, i,
                     j, S[k].m[i][j], p0 + k);
  return TL_OK;
}

static TlStatus evaluate_all(const TlMaterial *m, size_t npts, const TlMat3 *in, int gradient,
                             const double *state_old, double *state_new, TlMat3 *S, double *D,
                             double *W)
{
  if (!m->ready) TL_ERROR(TL_ERR_STATE, "material %s used before setup", m->ops->header.name);
  size_t ss = m->state_size;
  if (ss > 0 && npts > 0 && (!state_old || !state_new))
    TL_ERROR(TL_ERR_ARG, "material %s keeps %zu state values per point: state_old and state_new are required",
             m->ops->header.name, ss);
  for (size_t p0 = 0; p0 < npts; p0 += TL_MATERIAL_CHUNK) {
    size_t n = npts - p0 < TL_MATERIAL_CHUNK ? npts - p0 : TL_MATERIAL_CHUNK;
    TL_CHECK(evaluate_chunk(m, p0, n, in + p0, gradient, state_old ? state_old + p0 * ss : NULL,
                            state_new ? state_new + p0 * ss : NULL, S + p0, D ? D + 36 * p0 : NULL,
                            W ? W + p0 : NULL));
  }
  return TL_OK;
}

/* gamma = (H + H^T + H^T H)/2 - E0 of n points, component-major, with the
 * arithmetic of evaluate_chunk; one restrict pointer per component of the
 * result, so the loop needs no run-time overlap checks. */
static inline __attribute__((always_inline)) void green_strain_loop(
    const double e0[6], size_t n, const double *restrict H, size_t ld, double *restrict g0, double *restrict g1,
    double *restrict g2, double *restrict g3, double *restrict g4, double *restrict g5)
{
  for (size_t k = 0; k < n; ++k) {
    const double h00 = H[0 * ld + k], h01 = H[1 * ld + k], h02 = H[2 * ld + k], h10 = H[3 * ld + k],
                 h11 = H[4 * ld + k], h12 = H[5 * ld + k], h20 = H[6 * ld + k], h21 = H[7 * ld + k],
                 h22 = H[8 * ld + k];
    g0[k] = h00 + 0.5 * (h00 * h00 + h10 * h10 + h20 * h20) - e0[0];
    g1[k] = h11 + 0.5 * (h01 * h01 + h11 * h11 + h21 * h21) - e0[1];
    g2[k] = h22 + 0.5 * (h02 * h02 + h12 * h12 + h22 * h22) - e0[2];
    g3[k] = 0.5 * (h01 + h10 + h00 * h01 + h10 * h11 + h20 * h21) - e0[3];
    g4[k] = 0.5 * (h12 + h21 + h01 * h02 + h11 * h12 + h21 * h22) - e0[4];
    g5[k] = 0.5 * (h02 + h20 + h00 * h02 + h10 * h12 + h20 * h22) - e0[5];
  }
}

TL_VECTOR_CLONES
static void green_strain_soa(const TlMaterial *m, size_t n, const double *H, size_t ld, double *g, size_t ldg)
{
  double e0[6];
  tl_voigt_from_sym(m->eigenstrain, e0);
  green_strain_loop(e0, n, H, ld, g, g + ldg, g + 2 * ldg, g + 3 * ldg, g + 4 * ldg, g + 5 * ldg);
}

/* Whether the 6 component arrays of n points hold finite values only. */
TL_VECTOR_CLONES
static int all_finite(const double *S, size_t n, size_t ld)
{
  long bad = 0; /* as wide as a double: one vector lane per value */
  for (int I = 0; I < 6; ++I)
    for (size_t k = 0; k < n; ++k) bad |= !(fabs(S[I * ld + k]) <= DBL_MAX);
  return !bad;
}

TlStatus tl_material_stress_soa(const TlMaterial *m, size_t npts, const double *H, double *S, size_t ld)
{
  if (!m->ready) TL_ERROR(TL_ERR_STATE, "material %s used before setup", m->ops->header.name);
  if (m->state_size)
    TL_ERROR(TL_ERR_ARG, "material %s keeps %zu state values per point: no stress-only evaluation",
             m->ops->header.name, m->state_size);
  static const int voigt[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};
  double gamma[6 * TL_MATERIAL_CHUNK];
  for (size_t p0 = 0; p0 < npts; p0 += TL_MATERIAL_CHUNK) {
    const size_t n = npts - p0 < TL_MATERIAL_CHUNK ? npts - p0 : TL_MATERIAL_CHUNK;
    green_strain_soa(m, n, H + p0, ld, gamma, TL_MATERIAL_CHUNK);
    if (m->ops->stress_soa) {
      TL_CHECK(m->ops->stress_soa(m, n, gamma, TL_MATERIAL_CHUNK, S + p0, ld));
    } else {
      /* Through the law's own batch form. */
      TlMat3 F[TL_MATERIAL_CHUNK], G[TL_MATERIAL_CHUNK], Sk[TL_MATERIAL_CHUNK];
      for (size_t k = 0; k < n; ++k)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            F[k].m[i][j] = (i == j ? 1.0 : 0.0) + H[(3 * i + j) * ld + p0 + k];
            G[k].m[i][j] = gamma[voigt[i][j] * TL_MATERIAL_CHUNK + k];
          }
      TL_CHECK(m->ops->evaluate(m, n, F, G, NULL, NULL, Sk, NULL, NULL));
      for (size_t k = 0; k < n; ++k)
        for (int i = 0; i < 3; ++i)
          for (int j = i; j < 3; ++j) S[voigt[i][j] * ld + p0 + k] = Sk[k].m[i][j];
    }
    if (m->has_initial_stress)
      for (int I = 0; I < 6; ++I) {
        static const int row[6] = {0, 1, 2, 0, 1, 0}, col[6] = {0, 1, 2, 1, 2, 2};
        const double s0 = m->initial_stress.m[row[I]][col[I]];
        double *s = S + I * ld + p0;
        for (size_t k = 0; k < n; ++k) s[k] = s[k] + s0;
      }
    if (!all_finite(S + p0, n, ld))
      for (int I = 0; I < 6; ++I)
        for (size_t k = 0; k < n; ++k)
          if (!isfinite(S[I * ld + p0 + k]))
            TL_ERROR(TL_ERR_NUMERIC, "material %s: stress S[%d] (Voigt) = %g at point %zu", m->ops->header.name,
                     I, S[I * ld + p0 + k], p0 + k);
  }
  return TL_OK;
}

TlStatus tl_material_evaluate(const TlMaterial *m, size_t npts, const TlMat3 *F,
                              const double *state_old, double *state_new, TlMat3 *S, double *D,
                              double *W)
{
  return evaluate_all(m, npts, F, 0, state_old, state_new, S, D, W);
}

TlStatus tl_material_evaluate_gradient(const TlMaterial *m, size_t npts, const TlMat3 *H,
                                       const double *state_old, double *state_new, TlMat3 *S,
                                       double *D, double *W)
{
  return evaluate_all(m, npts, H, 1, state_old, state_new, S, D, W);
}
