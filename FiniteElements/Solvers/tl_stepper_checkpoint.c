/* Checkpoint section of the steppers: everything a later step reads.
 *
 * Per step the steppers recompute u0/v0/a0, the force scale, the predictor
 * from the state at t, so the state is t, u, v, a,
 * f_ext (the start-of-step external force of the work integral), W_ext, the
 * last dt (kept factors are dropped when it changes), the explicit
 * stepper's critical step and energy budget, and the kept factors. */
#include <limits.h>
#include <stdio.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_stepper.h"

static TlStatus stepper_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlStepper *st = object;
  size_t n = (size_t)st->n;
  TL_CHECK(tl_checkpoint_write_string(w, group, "stepper", st->ops->header.name));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "ndof", (int64_t)st->n));
  TL_CHECK(tl_checkpoint_write_double(w, group, "t", st->t));
  TL_CHECK(tl_checkpoint_write_double(w, group, "dt", st->dt));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "u", n, st->u));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "v", n, st->v));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "a", n, st->a));
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "f_ext", n, st->f_ext));
  TL_CHECK(tl_checkpoint_write_double(w, group, "external_work", st->W_ext));
  TL_CHECK(tl_checkpoint_write_double(w, group, "dt_crit", st->dt_crit));
  TL_CHECK(tl_checkpoint_write_double(w, group, "energy_budget", st->energy_budget));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "steps", st->stats.steps));
  TL_CHECK(tl_checkpoint_write_int64(w, group, "rejected", st->stats.rejected));
  /* Factors matter only when kept across steps (otherwise every solve
   * starts with a fresh factorisation). */
  int factored = st->newton && st->opt.keep_factors && tl_newton_has_factors(st->newton);
  TL_CHECK(tl_checkpoint_write_int64(w, group, "factored", factored));
  if (factored) {
    TL_CHECK(tl_checkpoint_write_doubles(w, group, "jacobian", (size_t)st->J->nnz, st->J->values));
    TL_CHECK(tl_checkpoint_write_int64(w, group, "iterations_since_factor", tl_newton_iterations_since_factor(st->newton)));
    /* The correction test's rate estimate lives with the factors. */
    TL_CHECK(tl_checkpoint_write_double(w, group, "convergence_rate", tl_newton_convergence_rate(st->newton)));
  }
  const TlCheckpointOps *sys_ops = st->sys->ops->checkpoint;
  if (sys_ops) {
    char sub[512];
    snprintf(sub, sizeof sub, "%s/system", group ? group : "");
    TL_CHECK(tl_checkpoint_write_string(w, group, "system_type", sys_ops->header.name));
    TL_CHECK(sys_ops->save(st->sys, w, sub));
  }
  return TL_OK;
}

/* The state as the stepper would have made it: a finite time, a finite
 * last step >= 0 (0 before the first step; no larger than the critical step
 * of an explicit scheme that computed one, unless allowed), finite vectors, work and budget, non-negative counters. */
static TlStatus check_state(const TlStepper *st, TlCheckpointReader *r, const char *group, int64_t steps,
                            int64_t rejected)
{
  size_t n = (size_t)st->n;
  TL_CHECK(tl_checkpoint_check_range(r, group, "t", st->t, -1e300, 1e300));
  TL_CHECK(tl_checkpoint_check_range(r, group, "dt", st->dt, 0.0, 1e300));
  TL_CHECK(tl_checkpoint_check_positive(r, group, "dt_crit", 1, &st->dt_crit, 1));
  if (st->dt_crit > 0.0 && !st->opt.allow_unstable && st->dt > st->dt_crit * (1.0 + 1e-12))
    TL_ERROR(TL_ERR_FORMAT, "%s: %s/dt = %g s exceeds the saved critical step dt_crit = %g s",
             tl_checkpoint_reader_path(r), group, st->dt, st->dt_crit);
  TL_CHECK(tl_checkpoint_check_finite(r, group, "u", n, st->u));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "v", n, st->v));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "a", n, st->a));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "f_ext", n, st->f_ext));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "external_work", 1, &st->W_ext));
  TL_CHECK(tl_checkpoint_check_finite(r, group, "energy_budget", 1, &st->energy_budget));
  TL_CHECK(tl_checkpoint_check_count(r, group, "steps", steps, 0, LONG_MAX));
  TL_CHECK(tl_checkpoint_check_count(r, group, "rejected", rejected, 0, LONG_MAX));
  return TL_OK;
}

static TlStatus stepper_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlStepper *st = object;
  size_t n = (size_t)st->n;
  const char *path = tl_checkpoint_reader_path(r);
  char *name = NULL;
  TL_CHECK(tl_checkpoint_read_string(r, group, "stepper", &name));
  int same = strcmp(name, st->ops->header.name) == 0;
  if (!same) {
    char saved[128];
    snprintf(saved, sizeof saved, "%s", name);
    tl_free(&name);
    TL_ERROR(TL_ERR_ARG, "%s: section '%s' holds a '%s' stepper; this run has '%s'", path, group, saved,
             st->ops->header.name);
  }
  tl_free(&name);
  int64_t ndof = 0, steps = 0, rejected = 0, factored = 0;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "ndof", &ndof));
  if (ndof != (int64_t)st->n)
    TL_ERROR(TL_ERR_ARG, "%s: section '%s' has %lld dofs; this system has %lld", path, group, (long long)ndof,
             (long long)st->n);
  TL_CHECK(tl_checkpoint_read_double(r, group, "t", &st->t));
  TL_CHECK(tl_checkpoint_read_double(r, group, "dt", &st->dt));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "u", n, st->u));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "v", n, st->v));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "a", n, st->a));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "f_ext", n, st->f_ext));
  TL_CHECK(tl_checkpoint_read_double(r, group, "external_work", &st->W_ext));
  TL_CHECK(tl_checkpoint_read_double(r, group, "dt_crit", &st->dt_crit));
  TL_CHECK(tl_checkpoint_read_double(r, group, "energy_budget", &st->energy_budget));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "steps", &steps));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "rejected", &rejected));
  TL_CHECK(check_state(st, r, group, steps, rejected));
  st->stats.steps = (long)steps;
  st->stats.rejected = (long)rejected;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "factored", &factored));
  if (st->newton) {
    tl_newton_invalidate(st->newton);
    if (factored) {
      TL_CHECK(tl_checkpoint_read_doubles(r, group, "jacobian", (size_t)st->J->nnz, st->J->values));
      TL_CHECK(tl_newton_refactor(st->newton));
      int64_t since = 0;
      TL_CHECK(tl_checkpoint_read_int64(r, group, "iterations_since_factor", &since));
      tl_newton_set_iterations_since_factor(st->newton, (long)since);
      double crate = 1.0;
      TL_CHECK(tl_checkpoint_read_double(r, group, "convergence_rate", &crate));
      tl_newton_set_convergence_rate(st->newton, crate);
    }
  } else if (factored) {
    TL_ERROR(TL_ERR_ARG, "%s: section '%s' holds Newton factors; the '%s' stepper has none", path, group,
             st->ops->header.name);
  }
  const TlCheckpointOps *sys_ops = st->sys->ops->checkpoint;
  int has = tl_checkpoint_has(r, group, "system_type");
  if (sys_ops && !has)
    TL_ERROR(TL_ERR_ARG, "%s: section '%s' lacks the state of system '%s'", path, group,
             st->sys->ops->header.name);
  if (!sys_ops && has)
    TL_ERROR(TL_ERR_ARG, "%s: section '%s' holds a system state; system '%s' keeps none", path, group,
             st->sys->ops->header.name);
  if (sys_ops) {
    char sub[512];
    snprintf(sub, sizeof sub, "%s/system", group ? group : "");
    TL_CHECK(tl_checkpoint_read_string(r, group, "system_type", &name));
    same = strcmp(name, sys_ops->header.name) == 0;
    tl_free(&name);
    if (!same)
      TL_ERROR(TL_ERR_ARG, "%s: section '%s' holds the state of another kind of system than '%s'", path, group,
               sys_ops->header.name);
    TL_CHECK(sys_ops->load(st->sys, r, sub));
  }
  return TL_OK;
}

const TlCheckpointOps tl_stepper_checkpoint_ops = {
    .header = {"checkpoint", "stepper_v1", "time stepper state (t, u, v, a, work, kept factors) and its system's state"},
    .save = stepper_save,
    .load = stepper_load,
};
