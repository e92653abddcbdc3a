/* Small-vector algebra: 3-vectors, 3x3 matrices (row-major) and unit
 * quaternions.  Header-only and inline because it sits in every hot loop. */
#ifndef TL_MATH_H
#define TL_MATH_H

#include <math.h>

#define TL_PI 3.14159265358979323846

/* Hot loops over independent points: an AVX2 copy beside the baseline one,
 * chosen when the program starts by what the processor has.  Without FMA,
 * so both copies round every operation alike and give the same bits. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define TL_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define TL_VECTOR_CLONES
#endif

typedef struct { double x, y, z; } TlVec3;
typedef struct { double m[3][3]; } TlMat3;            /* m[row][col] */
typedef struct { double w, x, y, z; } TlQuat;         /* w + xi + yj + zk */

/* ---- vectors ---- */
/* max/min of two doubles as one instruction (libm's fmax/fmin are calls);
 * a NaN in b is ignored, as fmax does, a NaN in a is not. */
static inline double tl_max(double a, double b) { return b > a ? b : a; }
static inline double tl_min(double a, double b) { return b < a ? b : a; }
/* The running largest (smallest) of a figure that is reported or checked: a
 * NaN anywhere makes the result NaN, so that a tracker never drops the
 * evidence of a blown-up value (fmax and fmin return the other argument). */
static inline double tl_track_max(double acc, double x) { return (isnan(acc) || isnan(x)) ? NAN : fmax(acc, x); }
static inline double tl_track_min(double acc, double x) { return (isnan(acc) || isnan(x)) ? NAN : fmin(acc, x); }

static inline TlVec3 tl_v3(double x, double y, double z) { return (TlVec3){x, y, z}; }
static inline TlVec3 tl_v3_add(TlVec3 a, TlVec3 b) { return (TlVec3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline TlVec3 tl_v3_sub(TlVec3 a, TlVec3 b) { return (TlVec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline TlVec3 tl_v3_scale(TlVec3 a, double s) { return (TlVec3){s * a.x, s * a.y, s * a.z}; }
/* a + s b */
static inline TlVec3 tl_v3_axpy(TlVec3 a, double s, TlVec3 b) { return (TlVec3){a.x + s * b.x, a.y + s * b.y, a.z + s * b.z}; }
static inline double tl_v3_dot(TlVec3 a, TlVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline TlVec3 tl_v3_cross(TlVec3 a, TlVec3 b)
{
  return (TlVec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline double tl_v3_norm2(TlVec3 a) { return tl_v3_dot(a, a); }
static inline double tl_v3_norm(TlVec3 a) { return sqrt(tl_v3_dot(a, a)); }
/* a / |a|; the zero vector stays zero rather than becoming NaN. */
static inline TlVec3 tl_v3_normalize(TlVec3 a)
{
  double n = tl_v3_norm(a);
  return n > 0.0 ? tl_v3_scale(a, 1.0 / n) : a;
}
static inline TlVec3 tl_v3_neg(TlVec3 a) { return (TlVec3){-a.x, -a.y, -a.z}; }
static inline int tl_v3_isfinite(TlVec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static inline double tl_v3_get(TlVec3 a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }

/* ---- matrices ---- */
static inline TlMat3 tl_m3_zero(void) { return (TlMat3){{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}; }
static inline TlMat3 tl_m3_identity(void) { return (TlMat3){{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }
static inline TlMat3 tl_m3_add(TlMat3 a, TlMat3 b)
{
  TlMat3 c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c.m[i][j] = a.m[i][j] + b.m[i][j];
  return c;
}
static inline TlMat3 tl_m3_scale(TlMat3 a, double s)
{
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a.m[i][j] *= s;
  return a;
}
static inline TlMat3 tl_m3_mul(TlMat3 a, TlMat3 b)
{
  TlMat3 c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  return c;
}
static inline TlMat3 tl_m3_transpose(TlMat3 a)
{
  TlMat3 t;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t.m[i][j] = a.m[j][i];
  return t;
}
static inline TlVec3 tl_m3_mulv(TlMat3 a, TlVec3 v)
{
  return (TlVec3){a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
                  a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
                  a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}
/* a^T v */
static inline TlVec3 tl_m3_tmulv(TlMat3 a, TlVec3 v)
{
  return (TlVec3){a.m[0][0] * v.x + a.m[1][0] * v.y + a.m[2][0] * v.z,
                  a.m[0][1] * v.x + a.m[1][1] * v.y + a.m[2][1] * v.z,
                  a.m[0][2] * v.x + a.m[1][2] * v.y + a.m[2][2] * v.z};
}
/* a b^T */
static inline TlMat3 tl_m3_outer(TlVec3 a, TlVec3 b)
{
  return (TlMat3){{{a.x * b.x, a.x * b.y, a.x * b.z}, {a.y * b.x, a.y * b.y, a.y * b.z}, {a.z * b.x, a.z * b.y, a.z * b.z}}};
}
static inline double tl_m3_trace(TlMat3 a) { return a.m[0][0] + a.m[1][1] + a.m[2][2]; }
static inline double tl_m3_det(TlMat3 a)
{
  return a.m[0][0] * (a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1]) -
         a.m[0][1] * (a.m[1][0] * a.m[2][2] - a.m[1][2] * a.m[2][0]) +
         a.m[0][2] * (a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0]);
}
/* Inverse; returns 0 and leaves *inv untouched when |det| is not positive
 * relative to the matrix scale. */
static inline int tl_m3_inverse(TlMat3 a, TlMat3 *inv)
{
  double det = tl_m3_det(a);
  double scale = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) scale = fmax(scale, fabs(a.m[i][j]));
  if (!(fabs(det) > 1e-300 && fabs(det) > 1e-14 * scale * scale * scale)) return 0;
  double r = 1.0 / det;
  TlMat3 c;
  c.m[0][0] = (a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1]) * r;
  c.m[0][1] = (a.m[0][2] * a.m[2][1] - a.m[0][1] * a.m[2][2]) * r;
  c.m[0][2] = (a.m[0][1] * a.m[1][2] - a.m[0][2] * a.m[1][1]) * r;
  c.m[1][0] = (a.m[1][2] * a.m[2][0] - a.m[1][0] * a.m[2][2]) * r;
  c.m[1][1] = (a.m[0][0] * a.m[2][2] - a.m[0][2] * a.m[2][0]) * r;
  c.m[1][2] = (a.m[0][2] * a.m[1][0] - a.m[0][0] * a.m[1][2]) * r;
  c.m[2][0] = (a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0]) * r;
  c.m[2][1] = (a.m[0][1] * a.m[2][0] - a.m[0][0] * a.m[2][1]) * r;
  c.m[2][2] = (a.m[0][0] * a.m[1][1] - a.m[0][1] * a.m[1][0]) * r;
  *inv = c;
  return 1;
}
/* Rotation matrix of angle theta (rad) about a unit axis (Rodrigues). */
static inline TlMat3 tl_m3_rotation(TlVec3 axis, double theta)
{
  TlVec3 k = tl_v3_normalize(axis);
  double c = cos(theta), s = sin(theta), t = 1.0 - c;
  return (TlMat3){{{t * k.x * k.x + c, t * k.x * k.y - s * k.z, t * k.x * k.z + s * k.y},
                   {t * k.x * k.y + s * k.z, t * k.y * k.y + c, t * k.y * k.z - s * k.x},
                   {t * k.x * k.z - s * k.y, t * k.y * k.z + s * k.x, t * k.z * k.z + c}}};
}

/* ---- quaternions (unit quaternions represent rotations) ---- */
static inline TlQuat tl_q_identity(void) { return (TlQuat){1, 0, 0, 0}; }
static inline TlQuat tl_q_mul(TlQuat a, TlQuat b)
{
  return (TlQuat){a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
                  a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                  a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                  a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
static inline TlQuat tl_q_conj(TlQuat q) { return (TlQuat){q.w, -q.x, -q.y, -q.z}; }
static inline double tl_q_norm(TlQuat q) { return sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z); }
static inline TlQuat tl_q_normalize(TlQuat q)
{
  double n = tl_q_norm(q);
  return n > 0.0 ? (TlQuat){q.w / n, q.x / n, q.y / n, q.z / n} : tl_q_identity();
}
static inline TlQuat tl_q_from_axis_angle(TlVec3 axis, double theta)
{
  TlVec3 k = tl_v3_normalize(axis);
  double s = sin(0.5 * theta);
  return (TlQuat){cos(0.5 * theta), s * k.x, s * k.y, s * k.z};
}
/* Rotates v by the unit quaternion q: q v q*. */
static inline TlVec3 tl_q_rotate(TlQuat q, TlVec3 v)
{
  TlVec3 u = {q.x, q.y, q.z};
  TlVec3 t = tl_v3_scale(tl_v3_cross(u, v), 2.0);
  return tl_v3_add(tl_v3_add(v, tl_v3_scale(t, q.w)), tl_v3_cross(u, t));
}
static inline TlMat3 tl_q_to_m3(TlQuat q)
{
  double w = q.w, x = q.x, y = q.y, z = q.z;
  return (TlMat3){{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                   {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                   {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}
/* Advances orientation q by angular velocity omega (world frame) over dt:
 * exact exponential map of a constant spin, then renormalised. */
static inline TlQuat tl_q_integrate(TlQuat q, TlVec3 omega, double dt)
{
  double w = tl_v3_norm(omega);
  if (w * dt < 1e-300) return q;
  TlQuat dq = tl_q_from_axis_angle(omega, w * dt);
  return tl_q_normalize(tl_q_mul(dq, q));
}

#endif
