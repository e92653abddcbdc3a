/* DEM time integration: Velocity-Verlet with prescribed motions. */
#include "tl_dem_private.h"

#include <math.h>
#include "tl_parallel.h"

static TlStatus prescribe(TlDem *d, double t)
{
  TlParticles *P = d->P;
  for (size_t g = 0; g < d->n_presc; ++g) {
    Prescribed *p = &d->presc[g];
    TL_CHECK(p->eval(p->ctx, t, p->n, p->ids, p->x0, p->xs, p->vs));
    for (size_t k = 0; k < p->n; ++k) {
      if (!tl_v3_isfinite(p->xs[k]) || !tl_v3_isfinite(p->vs[k]))
        TL_ERROR(TL_ERR_NUMERIC, "prescribed motion of particle id %lld at t = %g gave x = (%g, %g, %g), v = (%g, %g, %g)",
                 (long long)p->ids[k], t, p->xs[k].x, p->xs[k].y, p->xs[k].z, p->vs[k].x, p->vs[k].y, p->vs[k].z);
      size_t i = p->idx[k];
      if (d->track_energy) {
        TlVec3 dx = tl_v3_sub(p->xs[k], P->x[i]);
        double mg = P->mass[i] * (d->weight_fn && P->weight ? P->weight[i] : 1.0);
        d->work_ext -= tl_v3_dot(P->f[i], dx) - tl_v3_dot(tl_v3_scale(d->gravity, mg), dx);
      }
      P->x[i] = p->xs[k];
      P->v[i] = p->vs[k];
    }
  }
  return TL_OK;
}

static TlStatus report_blowup(TlDem *d, double dt)
{
  TlParticles *P = d->P;
  for (size_t i = 0; i < P->n; ++i) {
    TlVec3 v = P->v[i];
    if (!tl_v3_isfinite(v) || !tl_v3_isfinite(P->x[i]))
      TL_ERROR(TL_ERR_UNSTABLE, "step %ld, t = %g: particle id %lld has a non-finite state (v = (%g, %g, %g), force (%g, %g, %g))",
               d->steps, d->t, (long long)P->id[i], v.x, v.y, v.z, P->f[i].x, P->f[i].y, P->f[i].z);
    if (P->motion[i] == TL_MOTION_FREE && !(tl_v3_norm(v) * dt < P->radius[i]))
      TL_ERROR(TL_ERR_UNSTABLE,
               "step %ld, t = %g: particle id %lld moved %g in one step, more than its radius %g (v = (%g, %g, %g)); "
               "the time step %g is too large for this scene or a force blew up",
               d->steps, d->t, (long long)P->id[i], tl_v3_norm(v) * dt, P->radius[i], v.x, v.y, v.z, dt);
  }
  return TL_OK;
}

/* One Velocity-Verlet step.  With defer_kick, the second half kick is left
 * pending and done by the next step's first pass, in the same arithmetic
 * (the two half kicks one after the other per particle), which saves a
 * parallel region per step; tl_dem_step defers only between two steps of
 * one call, when nothing reads the full-step velocities in between. */
static TlStatus one_step(TlDem *d, int defer_kick)
{
  TlParticles *P = d->P;
  const int pending = d->kick_pending;
  d->kick_pending = 0;
  const size_t n = P->n;
  const double dt = d->dt, h = 0.5 * dt;
  const int rot = P->w != NULL;
  double t0 = tl_dem_clock(d);
  TlVec3 *restrict x = P->x, *restrict v = P->v;
  const TlVec3 *restrict f = P->f;
  /* a weighted world kicks with 1 / (w m) and 1 / (w I), refreshed by
   * every force evaluation in place (the same arrays all step long) */
  if (d->weight_fn) TL_CHECK(tl_dem_weighted_inverses(d));
  const double *restrict im = d->weight_fn ? d->im_w : P->inv_mass;
  const uint8_t *restrict motion = P->motion;
  /* first half kick and drift; the largest step and the largest distance
   * from the build positions are tracked in the same pass */
  TlMat3 A;
  TL_CHECK(tl_domain_advance(&d->domain, dt, &A));
  const int deforming = d->domain.deforming;
  const TlVec3 o = d->domain.origin;
  double v2max = 0.0, disp2max = 0.0;
  const TlVec3 *restrict xb = d->x_build;
  if (d->track_energy && (P->f_ext || P->f_coupling))
    for (size_t i = 0; i < n; ++i)
      if (motion[i] == TL_MOTION_FREE) {
        TlVec3 vv = tl_v3_axpy(v[i], h * im[i], f[i]);
        TlVec3 fe = tl_v3(0, 0, 0);
        if (P->f_ext) fe = d->weight_fn ? tl_v3_scale(P->f_ext[i], P->weight[i]) : P->f_ext[i];
        if (P->f_coupling) fe = tl_v3_add(fe, P->f_coupling[i]);
        d->work_ext += dt * tl_v3_dot(fe, vv);
      }
  const int nt = n >= 8192 ? d->nt : 1;
  const int planar = d->dim == 2;
  /* translation and rotation in one pass (one parallel region, not two) */
  TlVec3 *w = P->w;
  const TlVec3 *tq = P->torque;
  const double *ii = rot ? (d->weight_fn ? d->ii_w : P->inv_inertia) : NULL;
  const int orient = d->orientation;
  double ksum = 0.0; /* the pending kick's velocities: a NaN is located */
  if (planar) {
    /* 2-D: x, y and the spin about z only; z, v_z, ω_x, ω_y never change */
    const double a00 = A.m[0][0], a01 = A.m[0][1], a10 = A.m[1][0], a11 = A.m[1][1];
    TL_PARALLEL_IF(nt > 1, "omp parallel for num_threads(nt) schedule(static) reduction(max : v2max, disp2max) reduction(+ : ksum)",
      for (size_t i = 0; i < n; ++i) {
        if (pending) {
          const double hk = h * im[i];
          const double kx = v[i].x + hk * f[i].x, ky = v[i].y + hk * f[i].y;
          v[i].x = kx;
          v[i].y = ky;
          ksum += kx + ky;
          if (rot) w[i].z += h * ii[i] * tq[i].z;
        }
        if (motion[i] != TL_MOTION_FREE) continue;
        const double hi = h * im[i];
        const double vx = v[i].x + hi * f[i].x, vy = v[i].y + hi * f[i].y;
        v[i].x = vx;
        v[i].y = vy;
        const double v2 = vx * vx + vy * vy;
        v2max = v2 > v2max ? v2 : v2max;
        if (deforming) {
          const double px = x[i].x - o.x, py = x[i].y - o.y;
          x[i].x = o.x + a00 * px + a01 * py + dt * vx;
          x[i].y = o.y + a10 * px + a11 * py + dt * vy;
        } else {
          const double xx = x[i].x + dt * vx, xy = x[i].y + dt * vy;
          x[i].x = xx;
          x[i].y = xy;
          const double dx = xx - xb[i].x, dy = xy - xb[i].y;
          const double d2 = dx * dx + dy * dy;
          disp2max = d2 > disp2max ? d2 : disp2max;
        }
        if (!rot) continue;
        const double wz = w[i].z + h * ii[i] * tq[i].z;
        w[i].z = wz;
        if (!orient) continue;
        /* dq/dt = ½ (0, ω) ⊗ q with ω = ω_z e_z */
        TlQuat q = P->q[i];
        const double hw = h * wz;
        TlQuat r = {q.w - hw * q.z, q.x - hw * q.y, q.y + hw * q.x, q.z + hw * q.w};
        double nq = 1.0 / sqrt(r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
        P->q[i] = (TlQuat){r.w * nq, r.x * nq, r.y * nq, r.z * nq};
      });
  } else
  TL_PARALLEL_IF(nt > 1, "omp parallel for num_threads(nt) schedule(static) reduction(max : v2max, disp2max) reduction(+ : ksum)",
    for (size_t i = 0; i < n; ++i) {
      if (pending) {
        /* the previous step's second half kick, as its own pass did it */
        const double hk = h * im[i];
        const TlVec3 vk = {v[i].x + hk * f[i].x, v[i].y + hk * f[i].y, v[i].z + hk * f[i].z};
        v[i] = vk;
        ksum += vk.x + vk.y + vk.z;
        if (rot) {
          const double hr = h * ii[i];
          w[i] = (TlVec3){w[i].x + hr * tq[i].x, w[i].y + hr * tq[i].y, w[i].z + hr * tq[i].z};
        }
      }
      if (motion[i] != TL_MOTION_FREE) continue;
      const double hi = h * im[i];
      TlVec3 vv = {v[i].x + hi * f[i].x, v[i].y + hi * f[i].y, v[i].z + hi * f[i].z};
      v[i] = vv;
      double v2 = vv.x * vv.x + vv.y * vv.y + vv.z * vv.z;
      v2max = v2 > v2max ? v2 : v2max;
      if (deforming) {
        x[i] = tl_v3_axpy(tl_v3_add(o, tl_m3_mulv(A, tl_v3_sub(x[i], o))), dt, vv);
      } else {
        TlVec3 xn = {x[i].x + dt * vv.x, x[i].y + dt * vv.y, x[i].z + dt * vv.z};
        x[i] = xn;
        double dx = xn.x - xb[i].x, dy = xn.y - xb[i].y, dz = xn.z - xb[i].z;
        double d2 = dx * dx + dy * dy + dz * dz;
        disp2max = d2 > disp2max ? d2 : disp2max;
      }
      if (!rot) continue;
      const double hr = h * ii[i];
      TlVec3 ww = {w[i].x + hr * tq[i].x, w[i].y + hr * tq[i].y, w[i].z + hr * tq[i].z};
      w[i] = ww;
      if (!orient) continue;
      /* seeds/001 Eq. 2: dq/dt = ½ (0, ω) ⊗ q, with the half-step spin,
       * then renormalised */
      TlQuat q = P->q[i];
      TlQuat dq = tl_q_mul((TlQuat){0.0, ww.x, ww.y, ww.z}, q);
      q.w += h * dq.w; q.x += h * dq.x; q.y += h * dq.y; q.z += h * dq.z;
      double nq = 1.0 / sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
      P->q[i] = (TlQuat){q.w * nq, q.x * nq, q.y * nq, q.z * nq};
    });
  d->disp2max = disp2max;
  if (!(v2max * dt * dt < d->r_min * d->r_min) || !isfinite(ksum)) TL_CHECK(report_blowup(d, dt));
  tl_dem_tick(d, TL_DEM_PHASE_INTEGRATE, &t0);
  for (size_t k = 0; k < d->n_walls; ++k)
    if (d->walls[k]->ops->advance) TL_CHECK(d->walls[k]->ops->advance(d->walls[k], d->t, dt));
  d->t += dt;
  TL_CHECK(prescribe(d, d->t));
  if (tl_dem_needs_rebuild(d)) {
    tl_dem_tick(d, TL_DEM_PHASE_OTHER, &t0);
    TL_CHECK(tl_dem_rebuild(d)); /* books its own phases */
    t0 = tl_dem_clock(d);
  }
  if (d->hook) TL_CHECK(d->hook(d->hook_ctx, d));
  tl_dem_tick(d, TL_DEM_PHASE_OTHER, &t0);
  TL_CHECK(tl_dem_eval_forces(d)); /* books its own phases */
  t0 = tl_dem_clock(d);
  /* second half kick, spins in the same pass; a NaN anywhere poisons the
   * sum and is then located (the spin arrays read again: the force
   * evaluation refreshes the weighted inverses) */
  w = P->w;
  tq = P->torque;
  ii = rot ? (d->weight_fn ? d->ii_w : P->inv_inertia) : NULL;
  if (defer_kick) {
    d->kick_pending = 1;
    tl_dem_tick(d, TL_DEM_PHASE_INTEGRATE, &t0);
    d->steps++;
    return TL_OK;
  }
  double sum = 0.0;
  if (planar)
    TL_PARALLEL_IF(nt > 1, "omp parallel for num_threads(nt) schedule(static) reduction(+ : sum)",
      for (size_t i = 0; i < n; ++i) {
        const double hi = h * im[i];
        const double vx = v[i].x + hi * f[i].x, vy = v[i].y + hi * f[i].y;
        v[i].x = vx;
        v[i].y = vy;
        sum += vx + vy;
        if (rot) w[i].z += h * ii[i] * tq[i].z;
      });
  else
  TL_PARALLEL_IF(nt > 1, "omp parallel for num_threads(nt) schedule(static) reduction(+ : sum)",
    for (size_t i = 0; i < n; ++i) {
      const double hi = h * im[i]; /* 0 for fixed and prescribed particles */
      TlVec3 vv = {v[i].x + hi * f[i].x, v[i].y + hi * f[i].y, v[i].z + hi * f[i].z};
      v[i] = vv;
      sum += vv.x + vv.y + vv.z;
      if (rot) {
        const double hr = h * ii[i];
        w[i] = (TlVec3){w[i].x + hr * tq[i].x, w[i].y + hr * tq[i].y, w[i].z + hr * tq[i].z};
      }
    });
  if (!isfinite(sum)) TL_CHECK(report_blowup(d, dt));
  tl_dem_tick(d, TL_DEM_PHASE_INTEGRATE, &t0);
  d->steps++;
  return TL_OK;
}

TlStatus tl_dem_step(TlDem *d, long n)
{
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "tl_dem_setup must precede tl_dem_step");
  /* the second half kick joins the next step's first pass unless something
   * reads the full-step velocities before it: the work of external forces
   * (energy tracking), the weights' inverses refreshed at each step */
  const TlParticles *P = d->P;
  const int join = !d->weight_fn && !(d->track_energy && (P->f_ext || P->f_coupling));
  for (long s = 0; s < n; ++s) {
    /* inside a step the displacement check, after the drift, covers any
     * move since the build, the caller's between two calls included */
    d->in_steps = 1;
    TlStatus st = one_step(d, join && s + 1 < n);
    if (st != TL_OK) {
      d->kick_pending = 0;
      d->in_steps = 0;
      return tl_error_trace(st, __FILE__, __LINE__);
    }
  }
  d->in_steps = 0;
  return TL_OK;
}
