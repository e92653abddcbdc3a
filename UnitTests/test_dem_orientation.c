/* Orientation integration against the exponential map: a free sphere with a
 * constant spin ω turns by q(t) = exp(½ (0, ω) t) ⊗ q0.  The scheme (one
 * explicit step of dq/dt = ½ (0, ω) ⊗ q, renormalised) turns by
 * 2 atan(|ω| dt / 2) per step, so after n steps the angle lags |ω| t by at
 * n (|ω| dt)³ / 12 to leading order; the test asserts that lag to 1 % and
 * the axis. */
#include <math.h>
#include <stdio.h>
#include "talus.h"
#include "tl_dem.h"
#include "tl_test.h"

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  TlDem *dem;
  TL_TEST_STATUS(tl_dem_create(&dem), TL_OK);
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  TL_TEST_STATUS(tl_particles_add_species(P, "a", 2500.0, 0.01, 0.01, &sp), TL_OK);
  TL_TEST_STATUS(tl_dem_add_particle(dem, tl_v3(0, 0, 0), tl_v3(0, 0, 0), 0.01, sp, NULL), TL_OK);
  TlContactLaw *law; /* friction, so that the world integrates rotation */
  TL_TEST_STATUS(tl_test_law(&law, "linear", "k_n", 1e2, "mu", 0.5, NULL), TL_OK);
  TL_TEST_STATUS(tl_dem_add_law(dem, law, NULL), TL_OK);
  const double dt = 1e-3;
  TL_TEST_STATUS(tl_dem_set_timestep(dem, dt, 0), TL_OK);
  TL_TEST_STATUS(tl_dem_setup(dem), TL_OK);
  const TlVec3 omega = {3.0, -4.0, 12.0}; /* |ω| = 13 rad/s */
  const TlQuat q0 = tl_q_from_axis_angle(tl_v3(1, 1, 0), 0.7);
  P->w[0] = omega;
  P->q[0] = q0;
  const long n = 400;
  TL_TEST_STATUS(tl_dem_step(dem, n), TL_OK);
  /* the turn q q0*: its angle and axis */
  const TlQuat dq = tl_q_mul(P->q[0], tl_q_conj(q0));
  const double s = sqrt(dq.x * dq.x + dq.y * dq.y + dq.z * dq.z);
  const double angle = 2.0 * atan2(s, dq.w), wn = tl_v3_norm(omega), exact = wn * dt * n;
  const TlVec3 axis = tl_v3_scale(tl_v3(dq.x, dq.y, dq.z), 1.0 / s);
  const double off_axis = tl_v3_norm(tl_v3_sub(axis, tl_v3_scale(omega, 1.0 / wn)));
  const double lag = n * pow(wn * dt, 3) / 12.0;
  /* exact = 5.2 rad: the turn read from the quaternion is 5.2 rad as well
   * (atan2 gives it in [0, 2π)) */
  printf("orientation after %ld steps: angle %.10f rad (exponential map %.10f, lag bound %.3e), axis off by %.3e\n",
         n, angle, exact, lag, off_axis);
  TL_TEST_ASSERT(fabs((exact - angle) - lag) <= 0.01 * lag, "angle %.12f rad, exponential map %.12f, lag bound %g",
                 angle, exact, lag);
  TL_TEST_ASSERT(off_axis <= 1e-12, "the axis is off by %g", off_axis);
  TL_TEST_ASSERT(fabs(tl_q_norm(P->q[0]) - 1.0) <= 1e-14, "|q| = %.17g", tl_q_norm(P->q[0]));
  TL_TEST_ASSERT(tl_v3_norm(tl_v3_sub(P->w[0], omega)) <= 1e-14 * wn, "the spin changed with no torque");
  tl_dem_destroy(&dem);
  return tl_test_report();
}
