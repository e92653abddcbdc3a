/* Surface couplings and coupled loops from named settings for bindings
 * (tl_api.h). */
#include "tl_api.h"

#include <stddef.h>

TlStatus tl_api_scoupling_create_boundary(TlSolid *solid, int n_excluded, const char *const *excluded,
                                          const char *kernel, size_t n, const char *const *names,
                                          const double *values, TlSCoupling **sc)
{
  static const TlApiField fields[] = {
      {"width", 0, offsetof(TlSCouplingOptions, width)},
      {"subdivisions", 1, offsetof(TlSCouplingOptions, subdivisions)},
      {"support", 1, offsetof(TlSCouplingOptions, support)},
  };
  TlSCouplingOptions o;
  tl_scoupling_options_default(&o);
  if (kernel && kernel[0]) o.kernel = kernel;
  TL_CHECK(tl_api_set_fields("surface coupling", fields, (int)(sizeof fields / sizeof fields[0]), &o, n, names, values));
  TL_CHECK(tl_scoupling_create_boundary(solid, n_excluded, excluded, &o, sc));
  return TL_OK;
}

TlStatus tl_api_coupled_loop_create(TlDem *dem, TlSolid *solid, TlStepper *stepper, int n_couplings,
                                    TlSCoupling *const *couplings, size_t n, const char *const *names,
                                    const double *values, TlCoupledLoop **loop)
{
  static const TlApiField fields[] = {
      {"substeps", 1, offsetof(TlCoupledLoopOptions, substeps)},
      {"one_way", 1, offsetof(TlCoupledLoopOptions, one_way)},
      {"scheme", 1, offsetof(TlCoupledLoopOptions, scheme)},
      {"average_forces", 1, offsetof(TlCoupledLoopOptions, average_forces)},
  };
  TlCoupledLoopOptions o;
  tl_coupled_loop_options_default(&o);
  TL_CHECK(tl_api_set_fields("coupled loop", fields, (int)(sizeof fields / sizeof fields[0]), &o, n, names, values));
  TL_CHECK(tl_coupled_loop_create(dem, solid, stepper, n_couplings, couplings, &o, loop));
  return TL_OK;
}

void tl_api_coupled_loop_arrays(const TlCoupledLoop *loop, const double **u, const double **v, const double **f)
{
  *u = tl_coupled_loop_u_nodes(loop);
  *v = tl_coupled_loop_v_nodes(loop);
  *f = tl_coupled_loop_forces(loop);
}

void tl_api_coupled_loop_wall_force(const TlCoupledLoop *loop, double f[3])
{
  const TlVec3 w = tl_coupled_loop_wall_force(loop);
  f[0] = w.x, f[1] = w.y, f[2] = w.z;
}
