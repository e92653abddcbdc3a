/* The wave-propagation scene of seeds/001 §6.2 with the volume coupling. */
#include "tl_vcoupling_wave.h"

#include <math.h>
#include <string.h>

#include "tl_element.h"
#include "tl_math.h"
#include "tl_memory.h"
#include "tl_progress.h"
#include "tl_timer.h"
#include "tl_mesh.h"
#include "tl_vcoupling.h"

struct TlWave {
  TlWaveParams p;
  double d, m, k, dt, t;
  long step;
  /* particles: layer j along y, (i, k) across */
  size_t np, nb;
  int nxp, nyp, nyp_full;
  double *x, *x0, *v, *f, *w, *du, *mass, *xb, *wb;
  size_t *ba, *bb;
  /* solid */
  TlMesh *mesh;
  size_t nn;
  double *u, *vn, *an, *fn, *dun, *Mw, *Ke;
  char *fixed;
  TlVCoupling *vc;
  double eq41, residual, work, spring;
  double vmax_allowed, eps;
  /* snapshots */
  double *radius;
  int *conn_int;
  /* penalty stability estimate: power-iteration vectors */
  double *pi_xp, *pi_xn, *pi_fp, *pi_fn;
};

/* Snapshots hand the IO module the scene's 3-per-point arrays as TlVec3. */
_Static_assert(sizeof(TlVec3) == 3 * sizeof(double), "TlVec3 must be three packed doubles");

void tl_wave_params_default(TlWaveParams *p)
{
  *p = (TlWaveParams){.n = 1, .dx = 0.4, .width = 0.8, .length = 20.0, .dem_end = 12.0, .fem_start = 8.0,
                      .E = 100e6, .nu = 0.0, .rho = 1309.0, .v0 = 0.1, .excitation = TL_WAVE_PULSE,
                      .omega = 1950.0, .cycles = 1, .dt_over_tc = 0.01, .c = 0.0, .kernel = "lucy",
                      .epsilon = 0.0, .quad_order = 4, .full_dem = 0, .variant = TL_WAVE_PAPER};
}

static TlStatus check_penalty(TlWave *w);

/* The resolution check of Pi (tl_vcoupling_check_resolution). */
static TlStatus check_resolution(TlWave *w)
{
  if (w->p.resolution_limit < 0.0) return TL_OK;
  double lim = w->p.resolution_limit > 0.0 ? w->p.resolution_limit : TL_VCOUPLING_BIAS_LIMIT;
  TL_CHECK(tl_vcoupling_check_resolution(w->vc, w->x, lim, w->step, NULL));
  return TL_OK;
}

static size_t pid(const TlWave *w, int i, int j, int k) { return ((size_t)j * w->nxp + k) * w->nxp + i; }

/* Weighted stiffness and lumped mass of the small-strain hex8 solid. */
static TlStatus build_solid(TlWave *w)
{
  const TlWaveParams *p = &w->p;
  const TlElementBlock *B = &w->mesh->blocks[0];
  const TlElementType *T = B->type;
  TlQuadrature q;
  TL_CHECK(tl_element_quadrature(T, 3, &q));
  double lam = p->E * p->nu / ((1 + p->nu) * (1 - 2 * p->nu)), mu = p->E / (2 * (1 + p->nu));
  double N[TL_QUADRATURE_MAX * 8], dN[TL_QUADRATURE_MAX * 8 * 3];
  T->eval(q.n, &q.xi[0][0], N, dN);
  for (size_t e = 0; e < B->n_elements; ++e) {
    double xe[8 * 3], *K = w->Ke + e * 576;
    tl_mesh_element_coords(w->mesh, 0, e, xe);
    for (int g = 0; g < q.n; ++g) {
      double J[3][3], detJ;
      TL_CHECK(tl_element_jacobian(T, 3, xe, q.xi[g], J, &detJ));
      TlMat3 Jm, Ji;
      memcpy(Jm.m, J, sizeof Jm.m);
      if (!tl_m3_inverse(Jm, &Ji) || !(detJ > 0.0))
        TL_ERROR(TL_ERR_NUMERIC, "element %zu has det J = %g at Gauss point %d", e, detJ, g);
      double G[8][3]; /* dN_a/dX_i = sum_r dN_a/dxi_r (J^-1)_ri */
      for (int a = 0; a < 8; ++a)
        for (int i = 0; i < 3; ++i) {
          G[a][i] = 0.0;
          for (int r = 0; r < 3; ++r) G[a][i] += dN[(g * 8 + a) * 3 + r] * Ji.m[r][i];
        }
      double sw = w->vc ? tl_vcoupling_solid_weight(w->vc, e, q.xi[g]) : 1.0;
      double dv = q.w[g] * detJ * sw;
      /* K_ai,bj = lam G_ai G_bj + mu (G_aj G_bi + delta_ij G_a.G_b) */
      for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b) {
          double gg = G[a][0] * G[b][0] + G[a][1] * G[b][1] + G[a][2] * G[b][2];
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              K[(3 * a + i) * 24 + 3 * b + j] +=
                  dv * (lam * G[a][i] * G[b][j] + mu * (G[a][j] * G[b][i] + (i == j ? gg : 0.0)));
        }
      for (int a = 0; a < 8; ++a) w->Mw[B->conn[8 * e + a]] += dv * p->rho * N[g * 8 + a];
    }
  }
  for (size_t i = 0; i < w->nn; ++i)
    if (!w->fixed[i] && !(w->Mw[i] > 0.0))
      TL_ERROR(TL_ERR_NUMERIC, "node %zu has weighted mass %g: the zone leaves it no solid", i, w->Mw[i]);
  return TL_OK;
}

TlStatus tl_wave_create(const TlWaveParams *p, TlWave **out)
{
  *out = NULL;
  if (p->n < 1 || p->n > 16) TL_ERROR(TL_ERR_ARG, "particles per element edge n = %d outside [1, 16]", p->n);
  if (!(p->dx > 0) || !(p->width > 0) || !(p->length > 0))
    TL_ERROR(TL_ERR_ARG, "dx = %g, width = %g, length = %g must be > 0", p->dx, p->width, p->length);
  if (!p->full_dem && !(p->fem_start < p->dem_end && p->dem_end <= p->length && p->fem_start >= 0))
    TL_ERROR(TL_ERR_ARG, "overlap [%g, %g] must lie inside the bar [0, %g] with fem_start < dem_end", p->fem_start,
             p->dem_end, p->length);
  if (!(p->E > 0) || !(p->rho > 0) || !(p->nu >= 0 && p->nu < 0.5))
    TL_ERROR(TL_ERR_ARG, "E = %g, rho = %g must be > 0 and nu = %g in [0, 0.5)", p->E, p->rho, p->nu);
  if (!(p->dt_over_tc > 0 && p->dt_over_tc <= 0.3))
    TL_ERROR(TL_ERR_ARG, "dt / t_c = %g outside (0, 0.3]", p->dt_over_tc);
  if (p->excitation != TL_WAVE_PULSE && !(p->omega > 0))
    TL_ERROR(TL_ERR_ARG, "omega = %g rad/s must be > 0", p->omega);
  if (p->excitation == TL_WAVE_CYCLES && p->cycles < 1) TL_ERROR(TL_ERR_ARG, "cycles = %d must be >= 1", p->cycles);
  TlWave *w;
  TL_CHECK(TL_NEW(w));
  TlStatus s = TL_OK;
  w->p = *p;
  w->d = p->dx / p->n;
  double rho_g = 6.0 * p->rho / TL_PI;
  w->m = rho_g * TL_PI * w->d * w->d * w->d / 6.0;
  w->k = p->E * w->d;
  double tc = TL_PI * sqrt(0.5 * w->m / w->k);
  w->dt = p->dt_over_tc * tc;
  w->nxp = (int)lround(p->width / w->d);
  w->nyp_full = (int)lround(p->length / w->d);
  w->nyp = p->full_dem ? w->nyp_full : (int)lround(p->dem_end / w->d);
  w->np = (size_t)w->nxp * w->nxp * w->nyp;
  w->vmax_allowed = 100.0 * fmax(p->v0, 1e-12) * 2.0;
  size_t np = w->np;
  TL_CHECK_GOTO(s, tl_calloc(&w->x, 3 * np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->x0, 3 * np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->v, 3 * np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->f, 3 * np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->du, 3 * np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->w, np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->mass, np, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->radius, np, sizeof(double)), fail);
  for (size_t a = 0; a < np; ++a) w->radius[a] = 0.5 * w->d;
  for (int j = 0; j < w->nyp; ++j)
    for (int k = 0; k < w->nxp; ++k)
      for (int i = 0; i < w->nxp; ++i) {
        size_t a = pid(w, i, j, k);
        w->x[3 * a] = (i + 0.5) * w->d;
        w->x[3 * a + 1] = (j + 0.5) * w->d;
        w->x[3 * a + 2] = (k + 0.5) * w->d;
        w->mass[a] = w->m;
        w->w[a] = 1.0;
        if (j == 0 && p->excitation == TL_WAVE_PULSE) w->v[3 * a + 1] = -p->v0;
      }
  memcpy(w->x0, w->x, 3 * np * sizeof(double));
  /* bonds to the +x, +y, +z neighbours */
  size_t nbmax = 3 * np;
  TL_CHECK_GOTO(s, tl_calloc(&w->ba, nbmax, sizeof(size_t)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->bb, nbmax, sizeof(size_t)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->wb, nbmax, sizeof(double)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&w->xb, 3 * nbmax, sizeof(double)), fail);
  for (int j = 0; j < w->nyp; ++j)
    for (int k = 0; k < w->nxp; ++k)
      for (int i = 0; i < w->nxp; ++i) {
        size_t a = pid(w, i, j, k);
        if (i + 1 < w->nxp) w->ba[w->nb] = a, w->bb[w->nb++] = pid(w, i + 1, j, k);
        if (j + 1 < w->nyp) w->ba[w->nb] = a, w->bb[w->nb++] = pid(w, i, j + 1, k);
        if (k + 1 < w->nxp) w->ba[w->nb] = a, w->bb[w->nb++] = pid(w, i, j, k + 1);
      }
  for (size_t b = 0; b < w->nb; ++b) w->wb[b] = 1.0;
  if (!p->full_dem) {
    size_t ncell[3] = {(size_t)lround(p->width / p->dx), (size_t)lround((p->length - p->fem_start) / p->dx),
                       (size_t)lround(p->width / p->dx)};
    double lo[3] = {0, p->fem_start, 0}, hi[3] = {p->width, p->length, p->width};
    TL_CHECK_GOTO(s, tl_mesh_create_box(&tl_element_hex8, ncell, lo, hi, &w->mesh), fail);
    w->nn = w->mesh->n_nodes;
    TL_CHECK_GOTO(s, tl_calloc(&w->u, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->vn, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->an, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->fn, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->dun, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->Mw, w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->fixed, w->nn, 1), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->Ke, w->mesh->blocks[0].n_elements * 576, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->pi_xp, 3 * np, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->pi_fp, 3 * np, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->pi_xn, 3 * w->nn, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&w->pi_fn, 3 * w->nn, sizeof(double)), fail);
    /* hex8 node order is VTK's */
    TL_CHECK_GOTO(s, tl_calloc(&w->conn_int, w->mesh->blocks[0].n_elements * 8, sizeof(int)), fail);
    for (size_t k = 0; k < w->mesh->blocks[0].n_elements * 8; ++k) w->conn_int[k] = (int)w->mesh->blocks[0].conn[k];
    for (size_t i = 0; i < w->nn; ++i) w->fixed[i] = fabs(w->mesh->x[3 * i + 1] - p->length) < 1e-9 * p->length;
    double eps = p->epsilon > 0 ? p->epsilon : 1.6e9 / (w->d * w->d);
    w->eps = eps;
    TlVCouplingParams cp = {{1, p->fem_start, p->dem_end}, p->c, p->kernel, eps, p->quad_order, p->per_element};
    TL_CHECK_GOTO(s, tl_vcoupling_create(w->mesh, 0, &cp, &w->vc), fail);
    TL_CHECK_GOTO(s, build_solid(w), fail);
    TL_CHECK_GOTO(s, tl_vcoupling_update(w->vc, w->u, np, w->x, w->mass), fail);
    TL_CHECK_GOTO(s, check_resolution(w), fail);
    TL_CHECK_GOTO(s, tl_vcoupling_point_weights(w->vc, np, w->x, w->w), fail);
    for (size_t b = 0; b < w->nb; ++b)
      for (int d = 0; d < 3; ++d) w->xb[3 * b + d] = 0.5 * (w->x[3 * w->ba[b] + d] + w->x[3 * w->bb[b] + d]);
    TL_CHECK_GOTO(s, tl_vcoupling_point_weights(w->vc, w->nb, w->xb, w->wb), fail);
    if (!p->no_penalty_check) TL_CHECK_GOTO(s, check_penalty(w), fail);
  }
  *out = w;
  return TL_OK;
fail:
  tl_wave_destroy(&w);
  return s;
}

void tl_wave_destroy(TlWave **pw)
{
  TlWave *w = *pw;
  if (!w) return;
  double **arr[] = {&w->x, &w->x0, &w->v, &w->f, &w->w, &w->du, &w->mass, &w->xb, &w->wb,
                    &w->u, &w->vn, &w->an, &w->fn, &w->dun, &w->Mw, &w->Ke, &w->radius,
                    &w->pi_xp, &w->pi_xn, &w->pi_fp, &w->pi_fn};
  for (size_t k = 0; k < sizeof arr / sizeof arr[0]; ++k) tl_free(arr[k]);
  tl_free(&w->ba);
  tl_free(&w->bb);
  tl_free(&w->fixed);
  tl_free(&w->conn_int);
  tl_vcoupling_destroy(&w->vc);
  tl_mesh_destroy(&w->mesh);
  tl_free(pw);
}

double tl_wave_dt(const TlWave *w) { return w->dt; }
size_t tl_wave_n_particles(const TlWave *w) { return w->np; }

/* Prescribed velocity of the driven layer (Table 4); pulse: none. */
static int driven(const TlWave *w, double t, double *vy)
{
  const TlWaveParams *p = &w->p;
  if (p->excitation == TL_WAVE_PULSE) return 0;
  double t0 = 2.0 * TL_PI * (p->excitation == TL_WAVE_CYCLES ? p->cycles : 1) / p->omega;
  *vy = t <= t0 ? p->v0 * (cos(p->omega * t) - 1.0) : 0.0;
  return 1;
}

static void forces(TlWave *w)
{
  size_t np = w->np;
  memset(w->f, 0, 3 * np * sizeof(double));
  for (size_t b = 0; b < w->nb; ++b) {
    size_t a = w->ba[b], c = w->bb[b];
    double dxv[3], r2 = 0.0;
    for (int d = 0; d < 3; ++d) {
      dxv[d] = w->x[3 * c + d] - w->x[3 * a + d];
      r2 += dxv[d] * dxv[d];
    }
    double r = sqrt(r2), fmag = w->wb[b] * w->k * (r - w->d) / r; /* tension positive */
    for (int d = 0; d < 3; ++d) {
      w->f[3 * a + d] += fmag * dxv[d];
      w->f[3 * c + d] -= fmag * dxv[d];
    }
  }
  if (!w->mesh) return;
  memset(w->fn, 0, 3 * w->nn * sizeof(double));
  const TlElementBlock *B = &w->mesh->blocks[0];
  for (size_t e = 0; e < B->n_elements; ++e) {
    const double *K = w->Ke + e * 576;
    const size_t *cn = B->conn + 8 * e;
    double ue[24];
    for (int a = 0; a < 8; ++a)
      for (int d = 0; d < 3; ++d) ue[3 * a + d] = w->u[3 * cn[a] + d];
    for (int r = 0; r < 24; ++r) {
      double s = 0.0;
      for (int c = 0; c < 24; ++c) s += K[r * 24 + c] * ue[c];
      w->fn[3 * cn[r / 3] + r % 3] -= s;
    }
  }
}

TlStatus tl_wave_step(TlWave *w)
{
  const double dt = w->dt;
  size_t np = w->np;
  double vd;
  for (size_t a = 0; a < np; ++a) {
    int j = (int)(a / ((size_t)w->nxp * w->nxp));
    double am[3];
    for (int d = 0; d < 3; ++d) am[d] = w->f[3 * a + d] / (w->w[a] * w->mass[a]);
    if (w->p.full_dem && j == w->nyp - 1) { /* fixed right end of the reference bar */
      for (int d = 0; d < 3; ++d) w->v[3 * a + d] = w->du[3 * a + d] = 0.0;
      continue;
    }
    if (j == 0 && driven(w, w->t + 0.5 * dt, &vd)) {
      am[0] = am[1] = am[2] = 0.0;
      w->v[3 * a] = w->v[3 * a + 2] = 0.0;
      w->v[3 * a + 1] = vd;
    } else {
      for (int d = 0; d < 3; ++d) w->v[3 * a + d] += 0.5 * dt * am[d];
    }
    for (int d = 0; d < 3; ++d) {
      w->du[3 * a + d] = dt * w->v[3 * a + d];
      w->x[3 * a + d] += w->du[3 * a + d];
    }
  }
  if (w->mesh)
    for (size_t i = 0; i < w->nn; ++i)
      for (int d = 0; d < 3; ++d) {
        size_t k = 3 * i + d;
        w->vn[k] = w->fixed[i] ? 0.0 : w->vn[k] + 0.5 * dt * w->an[k];
        w->dun[k] = dt * w->vn[k];
        w->u[k] += w->dun[k];
      }
  w->t += dt;
  w->step++;
  if (w->vc) {
    TL_CHECK(tl_vcoupling_update(w->vc, w->u, np, w->x, w->mass));
    if (w->step % 100 == 0) TL_CHECK(check_resolution(w));
    TL_CHECK(tl_vcoupling_point_weights(w->vc, np, w->x, w->w));
    for (size_t b = 0; b < w->nb; ++b)
      for (int d = 0; d < 3; ++d) w->xb[3 * b + d] = 0.5 * (w->x[3 * w->ba[b] + d] + w->x[3 * w->bb[b] + d]);
    TL_CHECK(tl_vcoupling_point_weights(w->vc, w->nb, w->xb, w->wb));
    for (size_t a = 0; a < np; ++a)
      if (!(w->w[a] > 1e-12))
        TL_ERROR(TL_ERR_NUMERIC, "particle %zu at y = %g has weight %g: it left the particle side of the zone", a,
                 w->x[3 * a + 1], w->w[a]);
  }
  forces(w);
  if (w->vc) {
    TlVCouplingDiag dg;
    const double *dp = w->du, *dn = w->dun;
    if (w->p.variant == TL_WAVE_SPRING) {
      /* total displacements since the start: reuse du / dun as scratch */
      for (size_t k = 0; k < 3 * np; ++k) w->du[k] = w->x[k] - w->x0[k];
      dn = w->u;
    }
    TL_CHECK(tl_vcoupling_forces(w->vc, dp, dn, w->fn, w->f, &dg));
    w->eq41 = dg.eq41;
    w->residual = dg.residual_max;
    if (w->p.variant == TL_WAVE_SPRING)
      w->spring = -0.5 * (dg.work_fem + dg.work_dem);
    else
      w->work += dg.work_fem + dg.work_dem;
  }
  double vmax = 0.0;
  for (size_t a = 0; a < np; ++a) {
    int j = (int)(a / ((size_t)w->nxp * w->nxp));
    if (j == 0 && driven(w, w->t, &vd)) {
      w->v[3 * a + 1] = vd;
      continue;
    }
    if (w->p.full_dem && j == w->nyp - 1) continue;
    for (int d = 0; d < 3; ++d) {
      w->v[3 * a + d] += 0.5 * dt * w->f[3 * a + d] / (w->w[a] * w->mass[a]);
      double s = fabs(w->v[3 * a + d]);
      vmax = s > vmax || s != s ? (s != s ? INFINITY : s) : vmax;
    }
  }
  if (w->mesh)
    for (size_t i = 0; i < w->nn; ++i)
      for (int d = 0; d < 3; ++d) {
        size_t k = 3 * i + d;
        w->an[k] = w->fixed[i] ? 0.0 : w->fn[k] / w->Mw[i];
        w->vn[k] += 0.5 * dt * w->an[k];
        double s = fabs(w->vn[k]);
        vmax = s > vmax || s != s ? (s != s ? INFINITY : s) : vmax;
      }
  if (!(vmax <= w->vmax_allowed))
    TL_ERROR(TL_ERR_UNSTABLE,
             "the wave run diverged at t = %g s (step %ld): largest speed %g m/s, over 100 times the amplitude "
             "%g m/s, with CG width c = %g m (%.3g element sizes) and penalty eps = %g Pa/m^2 (eps d^2 = %g Pa). "
             "The explicit penalty acts as a damper eps M dt on the step displacement; its stable range is "
             "checked at creation (tl_wave_penalty_ratio) unless -penalty_check 0",
             w->t, w->step, vmax, w->p.v0, w->p.c, w->p.c / w->p.dx, w->eps, w->eps * w->d * w->d);
  return TL_OK;
}

void tl_wave_state(const TlWave *w, TlWaveState *s)
{
  memset(s, 0, sizeof *s);
  s->t = w->t;
  for (size_t a = 0; a < w->np; ++a) {
    double mw = w->w[a] * w->mass[a], v2 = 0.0;
    for (int d = 0; d < 3; ++d) v2 += w->v[3 * a + d] * w->v[3 * a + d];
    s->mass_dem += mw;
    s->mom_dem += mw * w->v[3 * a + 1];
    s->kin_dem += 0.5 * mw * v2;
  }
  for (size_t b = 0; b < w->nb; ++b) {
    size_t a = w->ba[b], c = w->bb[b];
    double r2 = 0.0;
    for (int d = 0; d < 3; ++d) r2 += (w->x[3 * c + d] - w->x[3 * a + d]) * (w->x[3 * c + d] - w->x[3 * a + d]);
    double dl = sqrt(r2) - w->d;
    s->pot_dem += 0.5 * w->wb[b] * w->k * dl * dl;
  }
  if (w->mesh) {
    for (size_t i = 0; i < w->nn; ++i) {
      double v2 = 0.0;
      for (int d = 0; d < 3; ++d) v2 += w->vn[3 * i + d] * w->vn[3 * i + d];
      s->mass_fem += w->Mw[i];
      s->mom_fem += w->Mw[i] * w->vn[3 * i + 1];
      s->kin_fem += 0.5 * w->Mw[i] * v2;
    }
    /* 1/2 u.K u = -1/2 u.f_int (f_int from the last force evaluation minus
     * the coupling part is not kept, so recompute element-wise) */
    const TlElementBlock *B = &w->mesh->blocks[0];
    for (size_t e = 0; e < B->n_elements; ++e) {
      const double *K = w->Ke + e * 576;
      const size_t *cn = B->conn + 8 * e;
      double ue[24];
      for (int a = 0; a < 8; ++a)
        for (int d = 0; d < 3; ++d) ue[3 * a + d] = w->u[3 * cn[a] + d];
      for (int r = 0; r < 24; ++r)
        for (int c = 0; c < 24; ++c) s->pot_fem += 0.5 * ue[r] * K[r * 24 + c] * ue[c];
    }
  }
  s->pot_coupling = w->spring;
  s->total = s->kin_dem + s->pot_dem + s->kin_fem + s->pot_fem + s->pot_coupling;
  s->eq41 = w->eq41;
  s->residual = w->residual;
  s->coupling_work = w->work;
}

/* Power iteration on W^-1 K, K = eps B^T M B applied through the coupling
 * forces; the Rayleigh quotient in the W inner product bounds lambda_max
 * from below. */
TlStatus tl_wave_penalty_ratio(TlWave *w, int iterations, double *ratio, size_t *particle, size_t *node)
{
  *ratio = 0.0;
  if (particle) *particle = 0;
  if (node) *node = 0;
  if (!w->vc) return TL_OK;
  const size_t np = w->np, nn = w->nn;
  double *xp = w->pi_xp, *xn = w->pi_xn, *fp = w->pi_fp, *fn = w->pi_fn;
  unsigned seed = 2463534242u;
  for (size_t k = 0; k < 3 * np; ++k) {
    seed ^= seed << 13, seed ^= seed >> 17, seed ^= seed << 5;
    xp[k] = (double)(seed & 0xffff) / 65536.0 - 0.5;
  }
  for (size_t k = 0; k < 3 * nn; ++k) {
    seed ^= seed << 13, seed ^= seed >> 17, seed ^= seed << 5;
    xn[k] = w->fixed[k / 3] ? 0.0 : (double)(seed & 0xffff) / 65536.0 - 0.5;
  }
  double lambda = 0.0;
  for (int it = 0; it < iterations; ++it) {
    memset(fp, 0, 3 * np * sizeof *fp);
    memset(fn, 0, 3 * nn * sizeof *fn);
    TL_CHECK(tl_vcoupling_forces(w->vc, xp, xn, fn, fp, NULL));
    /* K x = -(f_p, f_n); Rayleigh quotient x.Kx / x.Wx, then x <- W^-1 K x */
    double xkx = 0.0, xwx = 0.0;
    for (size_t k = 0; k < 3 * np; ++k) {
      double m = w->w[k / 3] * w->mass[k / 3];
      xkx -= xp[k] * fp[k];
      xwx += xp[k] * m * xp[k];
    }
    for (size_t k = 0; k < 3 * nn; ++k) {
      if (w->fixed[k / 3]) continue;
      xkx -= xn[k] * fn[k];
      xwx += xn[k] * w->Mw[k / 3] * xn[k];
    }
    lambda = xwx > 0.0 ? xkx / xwx : 0.0;
    double norm = 0.0;
    for (size_t k = 0; k < 3 * np; ++k) {
      xp[k] = -fp[k] / (w->w[k / 3] * w->mass[k / 3]);
      norm = fmax(norm, fabs(xp[k]));
    }
    for (size_t k = 0; k < 3 * nn; ++k) {
      xn[k] = w->fixed[k / 3] ? 0.0 : -fn[k] / w->Mw[k / 3];
      norm = fmax(norm, fabs(xn[k]));
    }
    if (!(norm > 0.0)) break;
    for (size_t k = 0; k < 3 * np; ++k) xp[k] /= norm;
    for (size_t k = 0; k < 3 * nn; ++k) xn[k] /= norm;
  }
  *ratio = w->dt * w->dt * lambda; /* lambda carries eps (the forces do) */
  double big = -1.0;
  for (size_t k = 0; k < 3 * np; ++k)
    if (fabs(xp[k]) > big) big = fabs(xp[k]), particle ? (void)(*particle = k / 3) : (void)0;
  big = -1.0;
  for (size_t k = 0; k < 3 * nn; ++k)
    if (fabs(xn[k]) > big) big = fabs(xn[k]), node ? (void)(*node = k / 3) : (void)0;
  return TL_OK;
}

/* 200 power iterations converge to well under 1 % for V1 (0.2 % between
 * 80 and 160 at 1P). */
static TlStatus check_penalty(TlWave *w)
{
  double ratio, lim = TL_WAVE_PENALTY_LIMIT(w->p.variant);
  size_t a, i;
  TL_CHECK(tl_wave_penalty_ratio(w, 200, &ratio, &a, &i));
  if (!(ratio <= lim))
    TL_ERROR(TL_ERR_UNSTABLE,
             "penalty eps = %g Pa/m^2 (eps d^2 = %g Pa) with CG width c = %g m is beyond the explicit stable range "
             "for dt = %.4g s, at step %ld: eps dt^2 lambda_max(W^-1 M_C) = %.4g over the limit %g of the %s (W: "
             "the weighted masses; the stiffest mode sits where a weight goes to zero, near particle %zu at y = %g m "
             "with w = %.3g and node %zu at y = %g m with 1 - w = %.3g). The largest stable penalty is about %.3g Pa/m^2",
             w->eps, w->eps * w->d * w->d, w->p.c, w->dt, w->step, ratio, lim,
             w->p.variant == TL_WAVE_SPRING ? "penalty spring under central differences" : "penalty damper eps M dt",
             a, w->x[3 * a + 1], w->w[a], i, w->mesh->x[3 * i + 1], 1.0 - tl_vcoupling_node_weights(w->vc)[i],
             w->eps * lim / ratio);
  return TL_OK;
}

size_t tl_wave_profile_size(const TlWave *w) { return (size_t)w->nyp_full; }

/* v_y of the solid at y: the mean over a node layer, linear between layers. */
static double solid_vy(const TlWave *w, double y)
{
  int nyn = (int)lround((w->p.length - w->p.fem_start) / w->p.dx) + 1;
  double r = (y - w->p.fem_start) / w->p.dx;
  int l = (int)floor(r);
  if (l < 0) l = 0;
  if (l >= nyn - 1) l = nyn - 2;
  double f = r - l, avg[2] = {0, 0};
  for (int side = 0; side < 2; ++side) {
    double yl = w->p.fem_start + (l + side) * w->p.dx;
    int cnt = 0;
    for (size_t i = 0; i < w->nn; ++i)
      if (fabs(w->mesh->x[3 * i + 1] - yl) < 1e-9) {
        avg[side] += w->vn[3 * i + 1];
        ++cnt;
      }
    avg[side] /= cnt > 0 ? cnt : 1;
  }
  return (1 - f) * avg[0] + f * avg[1];
}

static void profile(const TlWave *w, int blend, double *y, double *vy)
{
  size_t per = (size_t)w->nxp * w->nxp;
  for (int j = 0; j < w->nyp_full; ++j) {
    y[j] = (j + 0.5) * w->d;
    if (j < w->nyp) {
      double s = 0.0, sw = 0.0;
      for (size_t q = 0; q < per; ++q) {
        s += w->v[3 * (j * per + q) + 1];
        sw += w->w[j * per + q];
      }
      vy[j] = s / (double)per;
      /* the Arlequin field in the overlap: w v_particles + (1 - w) v_solid */
      if (blend && w->mesh && y[j] > w->p.fem_start) {
        double wl = sw / (double)per;
        vy[j] = wl * vy[j] + (1.0 - wl) * solid_vy(w, y[j]);
      }
      continue;
    }
    vy[j] = solid_vy(w, y[j]);
  }
}

void tl_wave_profile(const TlWave *w, double *y, double *vy) { profile(w, 0, y, vy); }
void tl_wave_profile_weighted(const TlWave *w, double *y, double *vy) { profile(w, 1, y, vy); }

/* ------------------------------------------------------------ checkpoint */
static TlStatus wave_save(const void *object, TlCheckpointWriter *cw, const char *g)
{
  const TlWave *w = object;
  size_t np = w->np, nb = w->nb, nn = w->nn;
  TL_CHECK(tl_checkpoint_write_int64(cw, g, "step", w->step));
  TL_CHECK(tl_checkpoint_write_double(cw, g, "time", w->t));
  double sc[4] = {w->eq41, w->residual, w->work, w->spring};
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "diagnostics", 4, sc));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "position", 3 * np, w->x));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "velocity", 3 * np, w->v));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "force", 3 * np, w->f));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "step_displacement", 3 * np, w->du));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "weight", np, w->w));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "bond_midpoint", 3 * nb, w->xb));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "bond_weight", nb, w->wb));
  if (w->mesh) {
    TL_CHECK(tl_checkpoint_write_doubles(cw, g, "solid_displacement", 3 * nn, w->u));
    TL_CHECK(tl_checkpoint_write_doubles(cw, g, "solid_velocity", 3 * nn, w->vn));
    TL_CHECK(tl_checkpoint_write_doubles(cw, g, "solid_acceleration", 3 * nn, w->an));
    TL_CHECK(tl_checkpoint_write_doubles(cw, g, "solid_force", 3 * nn, w->fn));
    TL_CHECK(tl_checkpoint_write_doubles(cw, g, "solid_step_displacement", 3 * nn, w->dun));
  }
  return TL_OK;
}

static TlStatus wave_load(void *object, TlCheckpointReader *cr, const char *g)
{
  TlWave *w = object;
  size_t np = w->np, nb = w->nb, nn = w->nn;
  int64_t step;
  double sc[4];
  TL_CHECK(tl_checkpoint_read_int64(cr, g, "step", &step));
  TL_CHECK(tl_checkpoint_read_double(cr, g, "time", &w->t));
  w->step = (long)step;
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "diagnostics", 4, sc));
  w->eq41 = sc[0];
  w->residual = sc[1];
  w->work = sc[2];
  w->spring = sc[3];
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "position", 3 * np, w->x));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "velocity", 3 * np, w->v));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "force", 3 * np, w->f));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "step_displacement", 3 * np, w->du));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "weight", np, w->w));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "bond_midpoint", 3 * nb, w->xb));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "bond_weight", nb, w->wb));
  if (w->mesh != NULL) {
    if (!tl_checkpoint_has(cr, g, "solid_displacement"))
      TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s' holds a full-DEM scene, this one is coupled",
               tl_checkpoint_reader_path(cr));
    TL_CHECK(tl_checkpoint_read_doubles(cr, g, "solid_displacement", 3 * nn, w->u));
    TL_CHECK(tl_checkpoint_read_doubles(cr, g, "solid_velocity", 3 * nn, w->vn));
    TL_CHECK(tl_checkpoint_read_doubles(cr, g, "solid_acceleration", 3 * nn, w->an));
    TL_CHECK(tl_checkpoint_read_doubles(cr, g, "solid_force", 3 * nn, w->fn));
    TL_CHECK(tl_checkpoint_read_doubles(cr, g, "solid_step_displacement", 3 * nn, w->dun));
    /* Pi and the weights follow from the restored geometry, as after a step */
    TL_CHECK(tl_vcoupling_update(w->vc, w->u, np, w->x, w->mass));
  } else if (tl_checkpoint_has(cr, g, "solid_displacement")) {
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s' holds a coupled scene, this one is full DEM",
             tl_checkpoint_reader_path(cr));
  }
  return TL_OK;
}

const TlCheckpointOps tl_wave_checkpoint_ops = {
    {"checkpoint", "wave_volume_coupling", "V1 wave scene: particles, solid, coupling work"}, wave_save, wave_load};

/* ------------------------------------------------------------- snapshots */
TlStatus tl_wave_write_snapshot(const TlWave *w, TlParticleWriter *pw, TlMeshWriter *mw)
{
  TlField pf[1] = {{"weight", 1, w->w}};
  TlParticleView pv = {.n = w->np, .position = (const TlVec3 *)w->x, .radius = w->radius,
                       .velocity = (const TlVec3 *)w->v, .force = (const TlVec3 *)w->f, .n_fields = 1, .fields = pf};
  if (pw) TL_CHECK(tl_particle_writer_write(pw, w->step, w->t, &pv));
  if (!mw || !w->mesh) return TL_OK;
  const TlElementBlock *B = &w->mesh->blocks[0];
  TlField nf[3] = {{"velocity", 3, w->vn}, {"particle_weight", 1, tl_vcoupling_node_weights(w->vc)},
                   {"weighted_mass", 1, w->Mw}};
  TlMeshBlock block = {.name = "bar", .type = TL_CELL_HEX8, .n_cells = B->n_elements, .connectivity = w->conn_int};
  TlMeshView mv = {.n_nodes = w->nn, .reference = (const TlVec3 *)w->mesh->x, .displacement = (const TlVec3 *)w->u,
                   .n_node_fields = 3, .node_fields = nf, .n_blocks = 1, .blocks = &block};
  TL_CHECK(tl_mesh_writer_write(mw, w->step, w->t, &mv));
  return TL_OK;
}

void tl_wave_record_free(TlWaveRecord *r)
{
  tl_free(&r->state);
  tl_free(&r->y);
  tl_free(&r->profile);
  tl_free(&r->profile_weighted);
  memset(r, 0, sizeof *r);
}

/* What a run records, checkpointed with the scene so that a restarted run
 * writes the same tables as one run in one go. */
typedef struct {
  TlWaveRecord *r;
  size_t cap;
  int n_snap, *next;
} RecordSection;

static TlStatus record_save(const void *object, TlCheckpointWriter *cw, const char *g)
{
  const RecordSection *R = object;
  const size_t per = sizeof(TlWaveState) / sizeof(double);
  TL_CHECK(tl_checkpoint_write_int64(cw, g, "rows", (int64_t)R->r->n));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "states", R->r->n * per, (const double *)R->r->state));
  TL_CHECK(tl_checkpoint_write_int64(cw, g, "profiles_taken", *R->next));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "profile_times", TL_WAVE_MAX_SNAPSHOTS, R->r->snap_t));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "profiles", (size_t)(R->n_snap ? R->n_snap : 1) * R->r->ny, R->r->profile));
  TL_CHECK(tl_checkpoint_write_doubles(cw, g, "profiles_weighted", (size_t)(R->n_snap ? R->n_snap : 1) * R->r->ny,
                                       R->r->profile_weighted));
  return TL_OK;
}

static TlStatus record_load(void *object, TlCheckpointReader *cr, const char *g)
{
  RecordSection *R = object;
  const size_t per = sizeof(TlWaveState) / sizeof(double);
  int64_t n, next;
  TL_CHECK(tl_checkpoint_read_int64(cr, g, "rows", &n));
  if (n < 1 || (size_t)n > R->cap)
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s' holds %lld recorded rows, this run records at most %zu (same -t_end "
             "and -record_every?)", tl_checkpoint_reader_path(cr), (long long)n, R->cap);
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "states", (size_t)n * per, (double *)R->r->state));
  R->r->n = (size_t)n;
  TL_CHECK(tl_checkpoint_read_int64(cr, g, "profiles_taken", &next));
  if (next < 0 || next > R->n_snap)
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s' has taken %lld profiles, this run takes %d (same -snapshots?)",
             tl_checkpoint_reader_path(cr), (long long)next, R->n_snap);
  *R->next = (int)next;
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "profile_times", TL_WAVE_MAX_SNAPSHOTS, R->r->snap_t));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "profiles", (size_t)(R->n_snap ? R->n_snap : 1) * R->r->ny, R->r->profile));
  TL_CHECK(tl_checkpoint_read_doubles(cr, g, "profiles_weighted", (size_t)(R->n_snap ? R->n_snap : 1) * R->r->ny,
                                      R->r->profile_weighted));
  return TL_OK;
}

static const TlCheckpointOps record_checkpoint_ops = {
    {"checkpoint", "wave_record", "recorded states and velocity profiles of a V1 run"}, record_save, record_load};

TlStatus tl_wave_run(const TlWaveParams *p, const TlWaveRunOptions *o, TlWaveRecord *r)
{
  memset(r, 0, sizeof *r);
  if (!(o->t_end > 0)) TL_ERROR(TL_ERR_ARG, "t_end = %g s must be > 0", o->t_end);
  if (o->every < 1) TL_ERROR(TL_ERR_ARG, "recording interval %ld steps must be >= 1", o->every);
  if (o->n_snap < 0 || o->n_snap > TL_WAVE_MAX_SNAPSHOTS)
    TL_ERROR(TL_ERR_ARG, "%d snapshots outside [0, %d]", o->n_snap, TL_WAVE_MAX_SNAPSHOTS);
  if (o->snapshot_dt < 0 || o->checkpoint_every < 0 || o->stop_step < 0)
    TL_ERROR(TL_ERR_ARG, "snapshot_dt = %g s, checkpoint_every = %ld, stop_step = %ld must be >= 0", o->snapshot_dt,
             o->checkpoint_every, o->stop_step);
  const int restart = o->restart && o->restart[0];
  if (!o->output_dir && (o->snapshot_dt > 0 || o->checkpoint_every > 0 || restart))
    TL_ERROR(TL_ERR_ARG, "snapshots, checkpoints and restarts need an output folder");
  double wall0 = tl_wtime();
  TlWave *w = NULL;
  TL_CHECK(tl_wave_create(p, &w));
  TlStatus s = TL_OK;
  TlParticleWriter *pw = NULL;
  TlMeshWriter *mw = NULL;
  TlCheckpoint *cp = NULL;
  char ckpt[4096] = "";
  long steps = (long)ceil(o->t_end / w->dt - 1e-9);
  size_t cap = (size_t)(steps / o->every) + 3;
  int next = 0;
  RecordSection R = {r, cap, o->n_snap, &next};
  r->ny = tl_wave_profile_size(w);
  r->dt = w->dt;
  r->n_particles = w->np;
  TL_CHECK_GOTO(s, tl_calloc(&r->state, cap, sizeof *r->state), out);
  TL_CHECK_GOTO(s, tl_calloc(&r->y, r->ny, sizeof *r->y), out);
  TL_CHECK_GOTO(s, tl_calloc(&r->profile, (size_t)(o->n_snap ? o->n_snap : 1) * r->ny, sizeof *r->profile), out);
  TL_CHECK_GOTO(s, tl_calloc(&r->profile_weighted, (size_t)(o->n_snap ? o->n_snap : 1) * r->ny,
                             sizeof *r->profile_weighted), out);
  tl_wave_profile(w, r->y, r->profile); /* the layer positions; the profile itself is overwritten */
  if (o->snapshot_dt > 0) {
    TL_CHECK_GOTO(s, tl_particle_writer_create(o->output_dir, "particles", &pw), out);
    if (!p->full_dem) TL_CHECK_GOTO(s, tl_mesh_writer_create(o->output_dir, "solid", &mw), out);
  }
  if (o->checkpoint_every > 0 || restart) {
    snprintf(ckpt, sizeof ckpt, "%s/checkpoint.h5", o->output_dir);
    TL_CHECK_GOTO(s, tl_checkpoint_create(&cp), out);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "wave", &tl_wave_checkpoint_ops, w), out);
    TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "record", &record_checkpoint_ops, &R), out);
    if (pw) TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "particle_snapshots", &tl_particle_writer_checkpoint_ops, pw), out);
    if (mw) TL_CHECK_GOTO(s, tl_checkpoint_add(cp, "solid_snapshots", &tl_mesh_writer_checkpoint_ops, mw), out);
  }
  if (restart) {
    TL_CHECK_GOTO(s, tl_checkpoint_load(cp, o->restart, NULL, NULL), out);
    r->start_step = w->step;
  } else {
    tl_wave_state(w, &r->state[r->n++]);
    if (pw) TL_CHECK_GOTO(s, tl_wave_write_snapshot(w, pw, mw), out);
  }
  TlProgress bar;
  if (o->progress) tl_progress_init(&bar, p->full_dem ? "full DEM" : "coupled", (double)steps);
  for (long k = w->step + 1; k <= steps; ++k) {
    TL_CHECK_GOTO(s, tl_wave_step(w), out);
    if ((k % o->every == 0 || k == steps) && r->n < cap) tl_wave_state(w, &r->state[r->n++]);
    while (next < o->n_snap && w->t >= o->snap[next] - 1e-12) {
      tl_wave_profile(w, r->y, r->profile + (size_t)next * r->ny);
      tl_wave_profile_weighted(w, r->y, r->profile_weighted + (size_t)next * r->ny);
      r->snap_t[next++] = w->t;
    }
    /* snapshot n at the first step at or after n snapshot_dt */
    if (pw && w->t >= (double)tl_particle_writer_count(pw) * o->snapshot_dt - 1e-12 * o->snapshot_dt)
      TL_CHECK_GOTO(s, tl_wave_write_snapshot(w, pw, mw), out);
    if (cp && o->checkpoint_every > 0 && k % o->checkpoint_every == 0)
      TL_CHECK_GOTO(s, tl_checkpoint_save(cp, ckpt, w->t, k), out);
    if (o->progress && k % 200 == 0) tl_progress_update(&bar, (double)k);
    if (o->stop_step > 0 && k == o->stop_step && k < steps) {
      r->stopped = 1;
      break;
    }
  }
  if (o->progress) tl_progress_finish(&bar);
  r->steps = w->step;
  r->n_snapshots = pw ? tl_particle_writer_count(pw) : 0;
  if (!r->stopped && next < o->n_snap) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "snapshot time %g s lies beyond t_end = %g s",
                     o->snap[next], o->t_end);
    goto out;
  }
out:
  tl_checkpoint_destroy(&cp);
  tl_particle_writer_destroy(&pw);
  tl_mesh_writer_destroy(&mw);
  tl_wave_destroy(&w);
  r->wall = tl_wtime() - wall0;
  /* on failure what was recorded stays for the diagnosis; the caller frees */
  return s;
}
