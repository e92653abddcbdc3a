/* CG fields: the arrays of one evaluation, their zeroing and time averaging
 * (tl_cg_fields.h). */
#include "tl_cg_fields.h"

#include <string.h>

#include "tl_memory.h"

/* ---------------------------------------------------------------- fields */

TlStatus tl_cg_fields_create(size_t n, unsigned which, TlCGFields **fields)
{
  *fields = NULL;
  if (which == 0 || (which & ~(unsigned)TL_CG_ALL))
    TL_ERROR(TL_ERR_ARG, "field mask 0x%x is empty or has unknown bits (known 0x%x)", which, (unsigned)TL_CG_ALL);
  /* velocity needs the density, the kinetic stress the velocity */
  if (which & TL_CG_STRESS_KINETIC) which |= TL_CG_MOMENTUM;
  if (which & TL_CG_MOMENTUM) which |= TL_CG_DENSITY;
  TlCGFields *f;
  TL_CHECK(TL_NEW(f));
  f->n = n;
  f->which = which;
  TlStatus s = TL_OK;
  size_t m = n ? n : 1;
  if (which & TL_CG_DENSITY) TL_CHECK_GOTO(s, tl_calloc(&f->density, m, sizeof(double)), fail);
  if (which & TL_CG_MOMENTUM) {
    TL_CHECK_GOTO(s, tl_calloc(&f->momentum, m, sizeof(TlVec3)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&f->velocity, m, sizeof(TlVec3)), fail);
  }
  if (which & TL_CG_STRESS_KINETIC) TL_CHECK_GOTO(s, tl_calloc(&f->stress_kinetic, m, sizeof(TlMat3)), fail);
  if (which & TL_CG_STRESS_CONTACT) TL_CHECK_GOTO(s, tl_calloc(&f->stress_contact, m, sizeof(TlMat3)), fail);
  if (which & TL_CG_BOUNDARY_FORCE) TL_CHECK_GOTO(s, tl_calloc(&f->boundary_force, m, sizeof(TlVec3)), fail);
  if (which & TL_CG_FABRIC) TL_CHECK_GOTO(s, tl_calloc(&f->fabric, m, sizeof(TlMat3)), fail);
  *fields = f;
  return TL_OK;
fail:
  tl_cg_fields_destroy(&f);
  return s;
}

void tl_cg_fields_destroy(TlCGFields **fields)
{
  if (!fields || !*fields) return;
  TlCGFields *f = *fields;
  tl_free(&f->density);
  tl_free(&f->momentum);
  tl_free(&f->velocity);
  tl_free(&f->stress_kinetic);
  tl_free(&f->stress_contact);
  tl_free(&f->boundary_force);
  tl_free(&f->fabric);
  tl_free(fields);
}

void tl_cg_fields_zero(TlCGFields *f)
{
  size_t n = f->n;
  if (f->density) memset(f->density, 0, n * sizeof(double));
  if (f->momentum) memset(f->momentum, 0, n * sizeof(TlVec3));
  if (f->velocity) memset(f->velocity, 0, n * sizeof(TlVec3));
  if (f->stress_kinetic) memset(f->stress_kinetic, 0, n * sizeof(TlMat3));
  if (f->stress_contact) memset(f->stress_contact, 0, n * sizeof(TlMat3));
  if (f->boundary_force) memset(f->boundary_force, 0, n * sizeof(TlVec3));
  if (f->fabric) memset(f->fabric, 0, n * sizeof(TlMat3));
  f->weight = 0.0;
}

static void axpy_d(size_t n, double a, const double *x, double *y)
{
  for (size_t i = 0; i < n; ++i) y[i] += a * x[i];
}

TlStatus tl_cg_fields_accumulate(TlCGFields *avg, const TlCGFields *snap, double weight)
{
  if (avg->n != snap->n)
    TL_ERROR(TL_ERR_ARG, "average has %zu points, snapshot %zu", avg->n, snap->n);
  if ((avg->which & snap->which) != avg->which)
    TL_ERROR(TL_ERR_ARG, "average wants fields 0x%x, snapshot has only 0x%x", avg->which, snap->which);
  if (!(weight >= 0.0) || !isfinite(weight))
    TL_ERROR(TL_ERR_ARG, "time-average weight %g must be non-negative and finite", weight);
  size_t n = avg->n;
  if (avg->density) axpy_d(n, weight, snap->density, avg->density);
  if (avg->momentum) axpy_d(3 * n, weight, &snap->momentum[0].x, &avg->momentum[0].x);
  if (avg->stress_kinetic) axpy_d(9 * n, weight, &snap->stress_kinetic[0].m[0][0], &avg->stress_kinetic[0].m[0][0]);
  if (avg->stress_contact) axpy_d(9 * n, weight, &snap->stress_contact[0].m[0][0], &avg->stress_contact[0].m[0][0]);
  if (avg->boundary_force) axpy_d(3 * n, weight, &snap->boundary_force[0].x, &avg->boundary_force[0].x);
  if (avg->fabric) axpy_d(9 * n, weight, &snap->fabric[0].m[0][0], &avg->fabric[0].m[0][0]);
  avg->weight += weight;
  return TL_OK;
}

TlStatus tl_cg_fields_average_finish(TlCGFields *avg)
{
  if (!(avg->weight > 0.0)) TL_ERROR(TL_ERR_STATE, "time average has total weight %g: nothing accumulated", avg->weight);
  double s = 1.0 / avg->weight;
  size_t n = avg->n;
  if (avg->density) for (size_t i = 0; i < n; ++i) avg->density[i] *= s;
  if (avg->momentum) for (size_t i = 0; i < n; ++i) avg->momentum[i] = tl_v3_scale(avg->momentum[i], s);
  if (avg->stress_kinetic) for (size_t i = 0; i < n; ++i) avg->stress_kinetic[i] = tl_m3_scale(avg->stress_kinetic[i], s);
  if (avg->stress_contact) for (size_t i = 0; i < n; ++i) avg->stress_contact[i] = tl_m3_scale(avg->stress_contact[i], s);
  if (avg->boundary_force) for (size_t i = 0; i < n; ++i) avg->boundary_force[i] = tl_v3_scale(avg->boundary_force[i], s);
  if (avg->fabric) for (size_t i = 0; i < n; ++i) avg->fabric[i] = tl_m3_scale(avg->fabric[i], s);
  if (avg->velocity)
    for (size_t i = 0; i < n; ++i)
      avg->velocity[i] = avg->density && avg->density[i] > 0.0 ? tl_v3_scale(avg->momentum[i], 1.0 / avg->density[i])
                                                              : tl_v3(0, 0, 0);
  avg->weight = 1.0;
  return TL_OK;
}
