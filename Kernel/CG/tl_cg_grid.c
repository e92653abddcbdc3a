/* CG fields on grids: cell averages of the Dirac kernel and the scatter of
 * smooth kernels onto the nodes (tl_cg_fields.h). */
#include "tl_cg_private.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tl_memory.h"
#ifdef _OPENMP
#include <omp.h>
#endif

/* ------------------------------------------------ Dirac: cell averages */

typedef struct {
  const TlCGGrid *g;
  int wrap[3]; /* periodic direction that the grid spans exactly */
  double inv_volume;
} TlCGDeposit;

/* Node owning point x, or -1 outside the grid. */
static long long deposit_node(const TlCGDeposit *dp, TlVec3 x)
{
  const TlCGGrid *g = dp->g;
  long idx[3];
  for (int d = 0; d < 3; ++d) {
    long i = (long)floor(((&x.x)[d] - (&g->lo.x)[d]) / (&g->h.x)[d] + 0.5);
    if (dp->wrap[d]) i = tl_cg_wrap_index(i, g->n[d]);
    if (i < 0 || i >= g->n[d]) return -1;
    idx[d] = i;
  }
  return idx[0] + (long long)g->n[0] * (idx[1] + (long long)g->n[1] * idx[2]);
}

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static TlStatus evaluate_dirac_grid(TlCG *c, const TlCGGrid *g, TlCGFields *out)
{
  TlCGDeposit dp = {g, {0, 0, 0}, 1.0 / (g->h.x * g->h.y * g->h.z)};
  if (c->has_box)
    for (int d = 0; d < 3; ++d)
      dp.wrap[d] = c->box.periodic[d] &&
                   fabs(g->n[d] * (&g->h.x)[d] - (&c->length.x)[d]) <= 1e-12 * (&c->length.x)[d];
  unsigned which = out->which;
  const TlCGParticleArrays *p = &c->particles;
  TlMat3 *mvv = NULL;
  if (which & TL_CG_STRESS_KINETIC) TL_CHECK(tl_calloc(&mvv, out->n, sizeof(TlMat3)));
  double *rho = out->density;
  if (!rho && (which & (TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC))) {
    tl_free(&mvv);
    TL_ERROR(TL_ERR_ARG, "velocity and kinetic stress on a grid need the density field as well (TL_CG_DENSITY)");
  }
  for (size_t i = 0; i < p->n; ++i) {
    long long node = deposit_node(&dp, p->x[i]);
    if (node < 0) continue;
    double m = p->mass[i] * dp.inv_volume;
    if (rho) rho[node] += m;
    if (p->v && out->momentum) out->momentum[node] = tl_v3_axpy(out->momentum[node], m, p->v[i]);
    if (p->v && mvv) mvv[node] = tl_m3_add(mvv[node], tl_m3_scale(tl_m3_outer(p->v[i], p->v[i]), m));
  }
  for (size_t n = 0; n < out->n; ++n) {
    TlVec3 V = rho && rho[n] > 0.0 && out->momentum ? tl_v3_scale(out->momentum[n], 1.0 / rho[n]) : tl_v3(0, 0, 0);
    if (out->velocity) out->velocity[n] = V;
    if (mvv && rho[n] > 0.0) {
      TlVec3 j = tl_v3_scale(V, rho[n]);
      out->stress_kinetic[n] = tl_m3_add(tl_m3_scale(mvv[n], -1.0), tl_m3_outer(j, V));
    }
  }
  tl_free(&mvv);
  if (out->boundary_force)
    for (size_t i = 0; i < c->walls.n; ++i) {
      long long node = deposit_node(&dp, c->walls.point[i]);
      if (node >= 0) out->boundary_force[node] = tl_v3_axpy(out->boundary_force[node], -dp.inv_volume, c->walls.force[i]);
    }
  if (which & (TL_CG_STRESS_CONTACT | TL_CG_FABRIC)) {
    double t[TL_CG_MAX_CROSSINGS];
    for (size_t i = 0; i < c->n_lines; ++i) {
      TlVec3 a = c->la[i], b = c->lb[i];
      int m = 0;
      t[m++] = 0.0;
      t[m++] = 1.0;
      for (int d = 0; d < 3; ++d) {
        double bd = (&b.x)[d], ad = (&a.x)[d], h = (&g->h.x)[d], lo = (&g->lo.x)[d] - 0.5 * h;
        if (bd == 0.0) continue;
        double u0 = (ad - lo) / h, u1 = (ad + bd - lo) / h; /* cell-boundary coordinate */
        for (double k = ceil(fmin(u0, u1)); k <= floor(fmax(u0, u1)); k += 1.0) {
          if (m == TL_CG_MAX_CROSSINGS)
            TL_ERROR(TL_ERR_ARG, "contact %zu: branch vector of length %g crosses more than %d grid cells",
                     i, tl_v3_norm(b), TL_CG_MAX_CROSSINGS);
          double s = (lo + k * h - ad) / bd;
          if (s > 0.0 && s < 1.0) t[m++] = s;
        }
      }
      qsort(t, (size_t)m, sizeof(double), cmp_double);
      TlMat3 fb = tl_m3_outer(c->lf[i], b);
      TlVec3 nb = tl_v3_normalize(b);
      TlMat3 nn = tl_m3_outer(nb, nb);
      for (int k = 0; k + 1 < m; ++k) {
        double len = t[k + 1] - t[k];
        if (len <= 0.0) continue;
        long long node = deposit_node(&dp, tl_v3_axpy(a, 0.5 * (t[k] + t[k + 1]), b));
        if (node < 0) continue;
        if (out->stress_contact) out->stress_contact[node] = tl_m3_add(out->stress_contact[node], tl_m3_scale(fb, len * dp.inv_volume));
        if (out->fabric) out->fabric[node] = tl_m3_add(out->fabric[node], tl_m3_scale(nn, len * dp.inv_volume));
      }
    }
  }
  return TL_OK;
}

/* ------------------------------------------- smooth kernels on a grid */

/* Grid scatter: every source visits the nodes within its reach (its
 * bounding box enlarged by c, for each periodic image that reaches the
 * grid), so a grid costs O(sources x nodes per kernel) with no search.
 * Threads own slabs of node layers along z and each visits every source
 * whose box meets its slab: no two threads write the same node. */
typedef struct {
  int i0[3], i1[3];
  TlVec3 shift;
} TlCGImageBox;

static int image_boxes(const TlCG *c, const TlCGGrid *g, TlVec3 blo, TlVec3 bhi, int k0, int k1, TlCGImageBox *out)
{
  int span[3];
  for (int d = 0; d < 3; ++d) span[d] = c->has_box && c->box.periodic[d] ? 1 : 0;
  int m = 0;
  for (int sz = -span[2]; sz <= span[2]; ++sz)
    for (int sy = -span[1]; sy <= span[1]; ++sy)
      for (int sx = -span[0]; sx <= span[0]; ++sx) {
        TlVec3 sh = tl_v3(sx * c->length.x, sy * c->length.y, sz * c->length.z);
        TlCGImageBox b;
        b.shift = sh;
        int empty = 0;
        for (int d = 0; d < 3 && !empty; ++d) {
          double glo = (&g->lo.x)[d], h = (&g->h.x)[d];
          double a = ceil(((&blo.x)[d] + (&sh.x)[d] - glo) / h), z = floor(((&bhi.x)[d] + (&sh.x)[d] - glo) / h);
          double lo_lim = d == 2 ? k0 : 0, hi_lim = d == 2 ? k1 - 1 : g->n[d] - 1;
          a = fmax(a, lo_lim);
          z = fmin(z, hi_lim);
          if (!(a <= z)) empty = 1;
          else {
            b.i0[d] = (int)a;
            b.i1[d] = (int)z;
          }
        }
        if (!empty) out[m++] = b;
      }
  return m;
}

static TlStatus scatter_particle(const TlCG *c, TlCGWork *w, size_t i, TlCGFields *out, TlMat3 *mvv)
{
  if (!w->count) return TL_OK;
  TL_CHECK(tl_cg_kernel_eval(c->kernel, w->count, w->r2, w->w, NULL));
  const TlCGParticleArrays *p = &c->particles;
  double m = p->mass[i];
  TlVec3 v = p->v ? p->v[i] : tl_v3(0, 0, 0);
  TlMat3 vv = tl_m3_outer(v, v);
  for (size_t e = 0; e < w->count; ++e) {
    size_t n = w->src[e];
    double mw = m * w->w[e];
    if (out->density) out->density[n] += mw;
    if (out->momentum) out->momentum[n] = tl_v3_axpy(out->momentum[n], mw, v);
    if (mvv) mvv[n] = tl_m3_add(mvv[n], tl_m3_scale(vv, mw));
  }
  w->count = 0;
  return TL_OK;
}

static TlStatus scatter_line(const TlCG *c, TlCGWork *w, size_t i, TlCGFields *out)
{
  if (!w->count) return TL_OK;
  TL_CHECK(tl_cg_kernel_line_integral(c->kernel, w->count, w->r2, w->aux, w->lc, w->ls0, w->ls1, c->n_gauss, w->w));
  TlMat3 fb = tl_m3_outer(c->lf[i], c->lb[i]);
  TlVec3 nb = tl_v3_normalize(c->lb[i]);
  TlMat3 nn = tl_m3_outer(nb, nb);
  for (size_t e = 0; e < w->count; ++e) {
    size_t n = w->src[e];
    double s = w->w[e];
    if (out->stress_contact) out->stress_contact[n] = tl_m3_add(out->stress_contact[n], tl_m3_scale(fb, s));
    if (out->fabric) out->fabric[n] = tl_m3_add(out->fabric[n], tl_m3_scale(nn, s));
  }
  w->count = 0;
  return TL_OK;
}

static TlStatus scatter_wall(const TlCG *c, TlCGWork *w, size_t i, TlCGFields *out)
{
  if (!w->count) return TL_OK;
  TL_CHECK(tl_cg_kernel_eval(c->kernel, w->count, w->r2, w->w, NULL));
  for (size_t e = 0; e < w->count; ++e)
    out->boundary_force[w->src[e]] = tl_v3_axpy(out->boundary_force[w->src[e]], -w->w[e], c->walls.force[i]);
  w->count = 0;
  return TL_OK;
}

#define TL_CG_FOR_BOX_NODES(g, b, node, pos, ...)                                                  \
  for (int k_ = (b).i0[2]; k_ <= (b).i1[2]; ++k_)                                                  \
    for (int j_ = (b).i0[1]; j_ <= (b).i1[1]; ++j_)                                                \
      for (int i_ = (b).i0[0]; i_ <= (b).i1[0]; ++i_) {                                            \
        size_t node = (size_t)i_ + (size_t)(g)->n[0] * ((size_t)j_ + (size_t)(g)->n[1] * (size_t)k_); \
        TlVec3 pos = tl_cg_grid_node((g), i_, j_, k_);                                             \
        __VA_ARGS__                                                                                \
      }

static TlStatus scatter_slab(const TlCG *c, TlCGWork *w, const TlCGGrid *g, int k0, int k1, TlCGFields *out,
                             TlMat3 *mvv)
{
  unsigned which = out->which;
  const double cw = c->kernel->c, c2 = cw * cw;
  TlCGImageBox boxes[27];
  if (which & (TL_CG_DENSITY | TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC)) {
    const TlCGParticleArrays *p = &c->particles;
    for (size_t i = 0; i < p->n; ++i) {
      TlVec3 x = p->x[i];
      int nb = image_boxes(c, g, tl_v3(x.x - cw, x.y - cw, x.z - cw), tl_v3(x.x + cw, x.y + cw, x.z + cw), k0, k1, boxes);
      w->count = 0;
      for (int q = 0; q < nb; ++q) {
        TlVec3 xs = tl_v3_add(x, boxes[q].shift);
        TL_CG_FOR_BOX_NODES(g, boxes[q], node, pos, {
          double r2 = tl_v3_norm2(tl_v3_sub(pos, xs));
          if (r2 < c2) {
            if (w->count == TL_CG_CHUNK) TL_CHECK(scatter_particle(c, w, i, out, mvv));
            w->r2[w->count] = r2;
            w->src[w->count++] = node;
          }
        })
      }
      TL_CHECK(scatter_particle(c, w, i, out, mvv));
    }
  }
  if (which & (TL_CG_STRESS_CONTACT | TL_CG_FABRIC)) {
    for (size_t i = 0; i < c->n_lines; ++i) {
      TlVec3 a = c->la[i], b = c->lb[i], e = tl_v3_add(a, b);
      if (!(tl_v3_norm2(b) > 0.0)) continue;
      TlVec3 blo = tl_v3(fmin(a.x, e.x) - cw, fmin(a.y, e.y) - cw, fmin(a.z, e.z) - cw);
      TlVec3 bhi = tl_v3(fmax(a.x, e.x) + cw, fmax(a.y, e.y) + cw, fmax(a.z, e.z) + cw);
      int nb = image_boxes(c, g, blo, bhi, k0, k1, boxes);
      w->count = 0;
      for (int q = 0; q < nb; ++q) {
        TlVec3 as = tl_v3_add(a, boxes[q].shift);
        TL_CG_FOR_BOX_NODES(g, boxes[q], node, pos, {
          double A, B, C, s0, s1;
          if (tl_cg_line_piece(tl_v3_sub(pos, as), b, c2, &A, &B, &C, &s0, &s1)) {
            if (w->count == TL_CG_CHUNK) TL_CHECK(scatter_line(c, w, i, out));
            w->r2[w->count] = A;
            w->aux[w->count] = B;
            w->lc[w->count] = C;
            w->ls0[w->count] = s0;
            w->ls1[w->count] = s1;
            w->src[w->count++] = node;
          }
        })
      }
      TL_CHECK(scatter_line(c, w, i, out));
    }
  }
  if (which & TL_CG_BOUNDARY_FORCE) {
    for (size_t i = 0; i < c->walls.n; ++i) {
      TlVec3 x = c->walls.point[i];
      int nb = image_boxes(c, g, tl_v3(x.x - cw, x.y - cw, x.z - cw), tl_v3(x.x + cw, x.y + cw, x.z + cw), k0, k1, boxes);
      w->count = 0;
      for (int q = 0; q < nb; ++q) {
        TlVec3 xs = tl_v3_add(x, boxes[q].shift);
        TL_CG_FOR_BOX_NODES(g, boxes[q], node, pos, {
          double r2 = tl_v3_norm2(tl_v3_sub(pos, xs));
          if (r2 < c2) {
            if (w->count == TL_CG_CHUNK) TL_CHECK(scatter_wall(c, w, i, out));
            w->r2[w->count] = r2;
            w->src[w->count++] = node;
          }
        })
      }
      TL_CHECK(scatter_wall(c, w, i, out));
    }
  }
  /* velocity and kinetic stress of the slab's nodes */
  size_t layer = (size_t)g->n[0] * (size_t)g->n[1];
  for (size_t n = (size_t)k0 * layer; n < (size_t)k1 * layer; ++n) {
    double rho = out->density ? out->density[n] : 0.0;
    if (!out->momentum) continue;
    TlVec3 V = rho > 0.0 ? tl_v3_scale(out->momentum[n], 1.0 / rho) : tl_v3(0, 0, 0);
    out->velocity[n] = V;
    if (mvv) out->stress_kinetic[n] = tl_m3_add(tl_m3_scale(mvv[n], -1.0), tl_m3_outer(out->momentum[n], V));
  }
  return TL_OK;
}

static TlStatus evaluate_grid_scatter(TlCG *c, const TlCGGrid *g, TlCGFields *out)
{
  unsigned which = out->which;
  if ((which & (TL_CG_MOMENTUM | TL_CG_STRESS_KINETIC)) && c->particles.n && !c->particles.v)
    TL_ERROR(TL_ERR_ARG, "momentum or kinetic stress asked for, but no particle velocities were given");
  TlMat3 *mvv = NULL;
  if (which & TL_CG_STRESS_KINETIC) {
    TL_CHECK(tl_array_reserve(&c->mvv, &c->cap_mvv, out->n, sizeof(TlMat3)));
    memset(c->mvv, 0, out->n * sizeof(TlMat3));
    mvv = c->mvv;
  }
  TlStatus status = TL_OK;
  int nz = g->n[2];
#pragma omp parallel num_threads(c->n_threads)
  {
    int t = 0, nt = 1;
#ifdef _OPENMP
    t = omp_get_thread_num();
    nt = omp_get_num_threads();
#endif
    if (t < c->n_threads) {
      int used = nt < c->n_threads ? nt : c->n_threads;
      int k0 = (int)((long)nz * t / used), k1 = (int)((long)nz * (t + 1) / used);
      TlStatus s = k1 > k0 ? scatter_slab(c, &c->work[t], g, k0, k1, out, mvv) : TL_OK;
      if (s != TL_OK) {
#pragma omp critical(tl_cg_error)
        if (status == TL_OK) status = s;
      }
    }
  }
  if (status != TL_OK) return tl_error_trace(status, __FILE__, __LINE__);
  return TL_OK;
}

TlStatus tl_cg_evaluate_grid(TlCG *c, const TlCGGrid *g, TlCGFields *out)
{
  for (int d = 0; d < 3; ++d) {
    if (g->n[d] < 1) TL_ERROR(TL_ERR_ARG, "grid has %d nodes along direction %d (need >= 1)", g->n[d], d);
    if (!((&g->h.x)[d] > 0.0) || !isfinite((&g->h.x)[d]))
      TL_ERROR(TL_ERR_ARG, "grid spacing %g along direction %d must be positive", (&g->h.x)[d], d);
  }
  size_t nodes = (size_t)g->n[0] * (size_t)g->n[1] * (size_t)g->n[2];
  if (out->n != nodes) TL_ERROR(TL_ERR_ARG, "fields hold %zu points, the grid has %zu nodes", out->n, nodes);
  tl_cg_fields_zero(out);
  if (tl_cg_kernel_is_dirac(c->kernel)) {
    TL_CHECK(evaluate_dirac_grid(c, g, out));
  } else {
    TL_CHECK(evaluate_grid_scatter(c, g, out));
  }
  out->weight = 1.0;
  return TL_OK;
}

