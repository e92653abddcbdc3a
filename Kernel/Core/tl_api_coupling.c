/* Surface couplings and coupled loops from named settings for bindings
 * (tl_api.h). */
#include "tl_api.h"

#include <stddef.h>

#include "tl_memory.h"

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

TlVec3 tl_api_coupled_loop_imbalance(const TlCoupledLoop *loop, size_t n_nodes)
{
  const double *F = tl_coupled_loop_forces(loop);
  TlVec3 sum = tl_coupled_loop_wall_force(loop); /* on the particles; the nodes get minus it */
  for (size_t a = 0; a < n_nodes; ++a) sum = tl_v3_add(sum, tl_v3(F[3 * a], F[3 * a + 1], F[3 * a + 2]));
  return sum;
}

struct TlSCoupledLoop {
  TlSCoupling *sc;
  TlStepper *st;
  TlCoupledLoop *loop;
};

TlStatus tl_api_scoupled_create(TlDem *dem, TlSolid *solid, const char *excluded, int law, const char *stepper,
                                TlSCoupledLoop **out)
{
  TlSCoupledLoop *c;
  *out = NULL;
  TL_CHECK(TL_NEW(c));
  const char *const ex[1] = {excluded};
  TlStatus s = tl_scoupling_create_boundary(solid, excluded && excluded[0] ? 1 : 0, ex, NULL, &c->sc);
  if (s == TL_OK) s = tl_scoupling_add_to_dem(c->sc, dem, law);
  if (s == TL_OK) s = tl_dem_setup(dem);
  if (s == TL_OK) s = tl_stepper_create(stepper ? stepper : "central_difference", tl_solid_system(solid), NULL, &c->st);
  if (s == TL_OK) s = tl_stepper_set_state(c->st, 0.0, NULL, NULL);
  if (s == TL_OK) s = tl_coupled_loop_create(dem, solid, c->st, 1, &c->sc, NULL, &c->loop);
  if (s != TL_OK) {
    tl_api_scoupled_destroy(&c);
    TL_CHECK(s);
  }
  *out = c;
  return TL_OK;
}

TlCoupledLoop *tl_api_scoupled_loop(const TlSCoupledLoop *c) { return c->loop; }

TlStepper *tl_api_scoupled_stepper(const TlSCoupledLoop *c) { return c->st; }

void tl_api_scoupled_destroy(TlSCoupledLoop **pc)
{
  if (!pc || !*pc) return;
  tl_coupled_loop_destroy(&(*pc)->loop);
  tl_stepper_destroy(&(*pc)->st);
  tl_scoupling_destroy(&(*pc)->sc);
  tl_free(pc);
}
