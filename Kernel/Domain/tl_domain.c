#include "tl_domain.h"

#include <math.h>
#include <string.h>

static TlStatus finish(TlDomain *d)
{
  double det = tl_m3_det(d->h);
  if (!(det > 0.0) || !isfinite(det))
    TL_ERROR(TL_ERR_ARG, "domain cell matrix h has det %g; it must be positive (right-handed, non-degenerate)", det);
  if (!tl_m3_inverse(d->h, &d->h_inv))
    TL_ERROR(TL_ERR_ARG, "domain cell matrix h is singular (det %g)", det);
  d->any_periodic = d->periodic[0] || d->periodic[1] || d->periodic[2];
  d->L = tl_m3_mul(d->h_dot, d->h_inv);
  d->deforming = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (d->h_dot.m[i][j] != 0.0) d->deforming = 1;
  return TL_OK;
}

static TlStatus box_frame(TlDomain *d, TlVec3 lo, TlVec3 hi)
{
  if (!tl_v3_isfinite(lo) || !tl_v3_isfinite(hi) || !(hi.x > lo.x) || !(hi.y > lo.y) || !(hi.z > lo.z))
    TL_ERROR(TL_ERR_ARG, "domain box [(%g, %g, %g), (%g, %g, %g)] must have hi > lo in every direction",
             lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
  d->origin = lo;
  d->h = tl_m3_zero();
  d->h.m[0][0] = hi.x - lo.x;
  d->h.m[1][1] = hi.y - lo.y;
  d->h.m[2][2] = hi.z - lo.z;
  d->h_dot = tl_m3_zero();
  return TL_OK;
}

TlStatus tl_domain_init_open(TlDomain *d, TlVec3 lo, TlVec3 hi)
{
  memset(d, 0, sizeof *d);
  d->kind = TL_DOMAIN_OPEN;
  TL_CHECK(box_frame(d, lo, hi));
  return finish(d);
}

TlStatus tl_domain_init_periodic_box(TlDomain *d, TlVec3 lo, TlVec3 hi, const int periodic[3])
{
  memset(d, 0, sizeof *d);
  d->kind = TL_DOMAIN_PERIODIC_BOX;
  TL_CHECK(box_frame(d, lo, hi));
  for (int k = 0; k < 3; ++k) d->periodic[k] = periodic[k] != 0;
  return finish(d);
}

TlStatus tl_domain_init_cell(TlDomain *d, TlVec3 origin, TlMat3 h)
{
  memset(d, 0, sizeof *d);
  d->kind = TL_DOMAIN_DEFORMABLE_CELL;
  if (!tl_v3_isfinite(origin)) TL_ERROR(TL_ERR_ARG, "cell origin is not finite");
  d->origin = origin;
  d->h = h;
  d->h_dot = tl_m3_zero();
  d->periodic[0] = d->periodic[1] = d->periodic[2] = 1;
  return finish(d);
}

/* The z row and column of a planar cell's h (identity: `one` = 1) or ḣ
 * (zero: `one` = 0). */
static TlStatus check_planar(const TlMat3 *m, const char *what, double one)
{
  static const int at[5][2] = {{0, 2}, {1, 2}, {2, 0}, {2, 1}, {2, 2}};
  for (int k = 0; k < 5; ++k) {
    int i = at[k][0], j = at[k][1];
    double want = (i == 2 && j == 2) ? one : 0.0;
    if (m->m[i][j] != want)
      TL_ERROR(TL_ERR_ARG, "planar cell: %s[%d][%d] = %g must be %g (the z row and column are inert)", what, i, j,
               m->m[i][j], want);
  }
  return TL_OK;
}

TlStatus tl_domain_init_cell_2d(TlDomain *d, TlVec3 origin, TlMat3 h)
{
  TL_CHECK(check_planar(&h, "h", 1.0));
  TL_CHECK(tl_domain_init_cell(d, origin, h));
  d->periodic[2] = 0;
  d->planar = 1;
  return finish(d);
}

TlStatus tl_domain_set_h_rate(TlDomain *d, TlMat3 h_dot)
{
  if (d->kind != TL_DOMAIN_DEFORMABLE_CELL)
    TL_ERROR(TL_ERR_STATE, "only a deformable cell has a rate of h (this domain is of kind %d)", (int)d->kind);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!isfinite(h_dot.m[i][j])) TL_ERROR(TL_ERR_ARG, "h_dot[%d][%d] = %g is not finite", i, j, h_dot.m[i][j]);
  if (d->planar) TL_CHECK(check_planar(&h_dot, "h_dot", 0.0));
  d->h_dot = h_dot;
  return finish(d);
}

TlStatus tl_domain_set_h(TlDomain *d, TlMat3 h)
{
  if (d->kind != TL_DOMAIN_DEFORMABLE_CELL)
    TL_ERROR(TL_ERR_STATE, "only a deformable cell can change its h (this domain is of kind %d)", (int)d->kind);
  if (d->planar) TL_CHECK(check_planar(&h, "h", 1.0));
  TlMat3 old = d->h;
  d->h = h;
  TlStatus s = finish(d);
  if (s != TL_OK) {
    d->h = old;
    finish(d);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}

double tl_domain_volume(const TlDomain *d) { return fabs(tl_m3_det(d->h)); }

double tl_domain_area(const TlDomain *d) { return fabs(d->h.m[0][0] * d->h.m[1][1] - d->h.m[0][1] * d->h.m[1][0]); }

double tl_domain_face_distance(const TlDomain *d, int k)
{
  TlVec3 a = {d->h.m[0][(k + 1) % 3], d->h.m[1][(k + 1) % 3], d->h.m[2][(k + 1) % 3]};
  TlVec3 b = {d->h.m[0][(k + 2) % 3], d->h.m[1][(k + 2) % 3], d->h.m[2][(k + 2) % 3]};
  return tl_domain_volume(d) / tl_v3_norm(tl_v3_cross(a, b));
}

TlStatus tl_domain_advance(TlDomain *d, double dt, TlMat3 *affine_map)
{
  *affine_map = tl_m3_identity();
  if (!d->deforming) return TL_OK;
  TlMat3 old_inv = d->h_inv;
  TlMat3 h = tl_m3_add(d->h, tl_m3_scale(d->h_dot, dt));
  double det = tl_m3_det(h);
  if (!(det > 0.0))
    TL_ERROR(TL_ERR_UNSTABLE, "cell deformation over dt = %g would make det h = %g (must stay positive)", dt, det);
  d->h = h;
  TL_CHECK(finish(d));
  *affine_map = tl_m3_mul(d->h, old_inv);
  return TL_OK;
}
