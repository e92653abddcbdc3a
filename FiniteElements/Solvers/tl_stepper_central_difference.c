/* Explicit central difference with the lumped mass, in velocity-Verlet
 * form (one internal-force evaluation per step):
 *
 *   v_{n+1/2} = v_n + dt/2 a_n,   u_{n+1} = u_n + dt v_{n+1/2}
 *   a_{n+1}   = m^-1 (f_ext(t_{n+1}, u_{n+1}) - f_int(u_{n+1}, v_{n+1/2}))
 *   v_{n+1}   = v_{n+1/2} + dt/2 a_{n+1}
 *
 * Stable for dt <= 2 / omega_max (undamped); omega_max^2 is the largest
 * eigenvalue of m^-1 K at the initial state. */
#include <math.h>
#include <string.h>

#include "tl_stepper.h"

static TlStatus cd_setup(TlStepper *st)
{
  (void)st;
  return TL_OK;
}

static TlStatus cd_accelerations(TlStepper *st, double t, const double *vel)
{
  TlMechSystem *sys = st->sys;
  TL_CHECK(sys->ops->internal_force(sys, t, st->u, vel, st->f_int));
  TL_CHECK(sys->ops->external_force(sys, t, st->u, st->f_ext));
  for (TlSparseIndex i = 0; i < st->n; ++i)
    st->a[i] = (st->f_ext[i] - st->f_int[i]) / st->m[i];
  for (TlSparseIndex k = 0; k < sys->n_dirichlet; ++k) st->a[sys->dirichlet_dofs[k]] = 0.0;
  if (sys->ops->dirichlet) TL_CHECK(sys->ops->dirichlet(sys, t, NULL, NULL, st->a));
  return TL_OK;
}

static TlStatus cd_initialise(TlStepper *st)
{
  TL_CHECK(cd_accelerations(st, st->t, st->v));
  TL_CHECK(tl_stepper_critical_dt(st, &st->dt_crit));
  TlEnergies e;
  TL_CHECK(tl_stepper_energies(st, &e));
  st->energy_budget = e.kinetic + fabs(e.strain);
  return TL_OK;
}

static TlStatus cd_step(TlStepper *st, double dt)
{
  TlMechSystem *sys = st->sys;
  if (dt > st->dt_crit && !st->opt.allow_unstable)
    TL_ERROR(TL_ERR_UNSTABLE,
             "time step dt = %.6g exceeds the critical step 2/omega_max = %.6g of the central "
             "difference scheme (omega_max^2 of M^-1 K at t = %g)",
             dt, st->dt_crit, st->t);
  tl_stepper_save_start(st);
  double *vh = st->work;
  for (TlSparseIndex i = 0; i < st->n; ++i) {
    vh[i] = st->v[i] + 0.5 * dt * st->a[i];
    st->u[i] += dt * vh[i];
  }
  const double t1 = st->t + dt;
  if (sys->ops->dirichlet) TL_CHECK(sys->ops->dirichlet(sys, t1, st->u, vh, NULL));
  TlStatus s = cd_accelerations(st, t1, vh);
  if (s != TL_OK) return tl_stepper_reject(st, s, "central-difference", dt);
  double kin = 0.0, work = 0.0;
  for (TlSparseIndex i = 0; i < st->n; ++i) {
    st->v[i] = vh[i] + 0.5 * dt * st->a[i];
    kin += st->m[i] * st->v[i] * st->v[i];
    work += (st->u[i] - st->u0[i]) * (0.5 * (st->f_ext0[i] + st->f_ext[i]));
  }
  if (sys->ops->dirichlet) TL_CHECK(sys->ops->dirichlet(sys, t1, NULL, st->v, NULL));
  kin *= 0.5;
  st->W_ext += work;
  st->energy_budget += fabs(work);
  if (!isfinite(kin) || (st->energy_budget > 0.0 && kin > st->opt.blowup * st->energy_budget)) {
    double e0 = st->energy_budget;
    TlStatus r = tl_stepper_reject(st, TL_ERR_UNSTABLE, "central-difference", dt);
    (void)r;
    TL_ERROR(TL_ERR_UNSTABLE,
             "blow-up at t = %.9g: kinetic energy %.3e exceeds %.0e x the energy put in (%.3e); "
             "dt = %.6g, critical step %.6g",
             st->t + dt, kin, st->opt.blowup, e0, dt, st->dt_crit);
  }
  if (sys->ops->commit) TL_CHECK(sys->ops->commit(sys));
  st->t = t1;
  return TL_OK;
}

static void cd_destroy(TlStepper *st) { (void)st; }

static const TlParam cd_params[] = {
    {"allow_unstable", 0, 0, 1, "1", "1: run above the critical step 2/omega_max (for tests); 0: refuse it",
     offsetof(TlStepperOptions, allow_unstable)},
    {"blowup", 1e6, 1, 1e300, "1",
     "a kinetic energy beyond blowup x the energy budget stops the run as unstable (> 1)",
     offsetof(TlStepperOptions, blowup)},
    {"critical_bound", 0, 0, 1, "1",
     "1: omega_max^2 from the system's conservative bound; 0: Lanczos on M^-1 K (sharp, from below)",
     offsetof(TlStepperOptions, critical_bound)},
};

const TlStepperOps tl_stepper_central_difference_ops = {
    .header = {"stepper", "central_difference", "explicit central difference, lumped mass"},
    .implicit = 0,
    .setup = cd_setup,
    .initialise = cd_initialise,
    .step = cd_step,
    .destroy = cd_destroy,
    .params = cd_params,
    .n_params = (int)(sizeof cd_params / sizeof cd_params[0]),
};
