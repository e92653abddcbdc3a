/* vec3 / mat3 / quaternion helpers against identities that must hold. */
#include "talus.h"
#include "tl_test.h"

int main(void)
{
  /* trackers keep a NaN (fmax would drop it) */
  TL_TEST_ASSERT(tl_track_max(1.0, 2.0) == 2.0 && tl_track_min(1.0, 2.0) == 1.0, "track max/min");
  TL_TEST_ASSERT(isnan(tl_track_max(1.0, NAN)) && isnan(tl_track_max(NAN, 1.0)) && isnan(tl_track_min(1.0, NAN)),
                 "a NaN is kept by the trackers");
  TL_TEST_ASSERT(tl_track_max(-INFINITY, 3.0) == 3.0, "start from -inf");
  TlVec3 a = tl_v3(1, 2, 3), b = tl_v3(-4, 0.5, 2);
  TL_TEST_CLOSE(tl_v3_dot(a, b), -4 + 1 + 6, 0);
  TlVec3 c = tl_v3_cross(a, b);
  TL_TEST_CLOSE(tl_v3_dot(c, a), 0, 1e-15);
  TL_TEST_CLOSE(tl_v3_dot(c, b), 0, 1e-15);
  TL_TEST_CLOSE(tl_v3_norm(tl_v3_normalize(b)), 1, 1e-15);
  TlVec3 z = tl_v3_normalize(tl_v3(0, 0, 0));
  TL_TEST_ASSERT(tl_v3_isfinite(z) && tl_v3_norm(z) == 0, "normalising zero gave a non-zero or NaN");

  /* Rotation matrices are orthogonal with determinant 1; R(axis, t) axis = axis. */
  TlVec3 axis = tl_v3(0.3, -0.7, 0.2);
  TlMat3 R = tl_m3_rotation(axis, 1.234);
  TlMat3 RtR = tl_m3_mul(tl_m3_transpose(R), R);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) TL_TEST_CLOSE(RtR.m[i][j], i == j, 1e-14);
  TL_TEST_CLOSE(tl_m3_det(R), 1, 1e-14);
  TlVec3 ra = tl_m3_mulv(R, axis);
  TL_TEST_CLOSE(ra.x, axis.x, 1e-15);
  TL_TEST_CLOSE(ra.y, axis.y, 1e-15);

  /* The quaternion of the same rotation rotates vectors the same way. */
  TlQuat q = tl_q_from_axis_angle(axis, 1.234);
  TlVec3 qa = tl_q_rotate(q, a), Ra = tl_m3_mulv(R, a);
  TL_TEST_CLOSE(qa.x, Ra.x, 1e-14);
  TL_TEST_CLOSE(qa.y, Ra.y, 1e-14);
  TL_TEST_CLOSE(qa.z, Ra.z, 1e-14);
  TlMat3 Rq = tl_q_to_m3(q);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) TL_TEST_CLOSE(Rq.m[i][j], R.m[i][j], 1e-14);
  /* Composition: q2 q1 rotates by q1 then q2. */
  TlQuat q2 = tl_q_from_axis_angle(tl_v3(1, 0, 0), 0.4);
  TlVec3 two = tl_q_rotate(tl_q_mul(q2, q), a), seq = tl_q_rotate(q2, tl_q_rotate(q, a));
  TL_TEST_CLOSE(two.x, seq.x, 1e-14);
  TL_TEST_CLOSE(two.z, seq.z, 1e-14);
  /* Integrating a constant spin for 100 steps equals one rotation by the total angle. */
  TlQuat p = tl_q_identity();
  TlVec3 omega = tl_v3(0, 0, 2.0);
  for (int k = 0; k < 100; ++k) p = tl_q_integrate(p, omega, 0.01);
  TlVec3 pe = tl_q_rotate(p, tl_v3(1, 0, 0));
  TL_TEST_CLOSE(pe.x, cos(2.0), 1e-12);
  TL_TEST_CLOSE(pe.y, sin(2.0), 1e-12);
  TL_TEST_CLOSE(tl_q_norm(p), 1, 1e-14);

  /* Inverse, and refusal of a singular matrix. */
  TlMat3 A = {{{4, 1, 0}, {1, 3, -1}, {0, -1, 2}}}, Ai;
  TL_TEST_ASSERT(tl_m3_inverse(A, &Ai), "invertible matrix refused");
  TlMat3 I = tl_m3_mul(A, Ai);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) TL_TEST_CLOSE(I.m[i][j], i == j, 1e-15);
  TlMat3 S = {{{1, 2, 3}, {2, 4, 6}, {0, 1, 1}}};
  TL_TEST_ASSERT(!tl_m3_inverse(S, &Ai), "singular matrix inverted");
  TlMat3 o = tl_m3_outer(a, b);
  TL_TEST_CLOSE(tl_m3_trace(o), tl_v3_dot(a, b), 1e-15);
  TlVec3 tv = tl_m3_tmulv(A, a), tv2 = tl_m3_mulv(tl_m3_transpose(A), a);
  TL_TEST_CLOSE(tv.y, tv2.y, 0);
  return tl_test_report();
}
