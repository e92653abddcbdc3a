/* The volume-coupled loop (tl_api.h): a DEM world and a solid stepped in
 * lock-step through a TlVCoupling, composed of the coupling's own calls.
 *
 * One step (the world's step hook, after its drift): Pi at the particles'
 * new positions, the element wrapper told the particles' displacement
 * increment v dt and the nodes' displacements at the start of the step,
 * one step of the solid's stepper, then the particle coupling forces from
 * the new nodal displacements, which the world applies in its kick.  The
 * world weights its particle equations by the coupling's weights
 * (tl_dem_set_weight_field). */
#include "tl_api.h"

#include <math.h>
#include <string.h>

#include "tl_memory.h"

struct TlVCoupledLoop {
  TlDem *dem;
  TlSolid *solid;
  TlVCoupling *vc;
  TlVCouplingElement *el;
  TlStepper *st;
  double *u;   /* nodal displacements (3 per mesh node) */
  double *dup; /* particle displacement increments of the step */
  size_t dup_capacity;
  TlVCouplingDiag last;
  double eq41_max;
};

static TlStatus weights(void *ctx, size_t n, const TlVec3 *x, double *w)
{
  return tl_vcoupling_point_weights(((TlVCoupledLoop *)ctx)->vc, n, (const double *)x, w);
}

static TlStatus coupled_step(void *ctx, TlDem *dem)
{
  TlVCoupledLoop *c = ctx;
  TlParticles *P = tl_dem_particles(dem);
  const double dt = tl_dem_timestep(dem);
  if (P->n > c->dup_capacity) { /* only when particles were added */
    tl_free(&c->dup);
    c->dup_capacity = 0;
    TL_CHECK(tl_calloc(&c->dup, 3 * P->n, sizeof *c->dup));
    c->dup_capacity = P->n;
  }
  for (size_t a = 0; a < P->n; ++a)
    c->dup[3 * a] = dt * P->v[a].x, c->dup[3 * a + 1] = dt * P->v[a].y, c->dup[3 * a + 2] = dt * P->v[a].z;
  TL_CHECK(tl_vcoupling_update(c->vc, c->u, P->n, (const double *)P->x, P->mass));
  TL_CHECK(tl_vcoupling_element_set_step(c->el, c->dup, c->u));
  TL_CHECK(tl_stepper_step(c->st, dt));
  tl_solid_dofs_to_nodes(c->solid, c->st->u, c->u);
  memset(P->f_coupling, 0, P->n * sizeof *P->f_coupling);
  TL_CHECK(tl_vcoupling_element_particle_forces(c->el, c->u, (double *)P->f_coupling, &c->last));
  c->eq41_max = fmax(c->eq41_max, c->last.eq41);
  return TL_OK;
}

TlStatus tl_api_vcoupled_create(TlDem *dem, TlSolid *solid, const TlVCouplingParams *params, const char *stepper,
                                TlVCoupledLoop **out)
{
  TlVCoupledLoop *c;
  *out = NULL;
  if (!dem || !solid || !params) TL_ERROR(TL_ERR_ARG, "a volume-coupled loop needs a world, a solid and parameters");
  TL_CHECK(TL_NEW(c));
  c->dem = dem, c->solid = solid;
  const TlMesh *mesh = tl_solid_mesh(solid);
  TlParticles *P = tl_dem_particles(dem);
  TlStatus s = tl_vcoupling_create(mesh, 0, params, &c->vc);
  if (s == TL_OK) s = tl_vcoupling_element_create(c->vc, solid, &c->el); /* before set-up: it weights the masses */
  if (s == TL_OK) s = tl_solid_setup(solid);
  if (s == TL_OK) s = tl_stepper_create(stepper ? stepper : "central_difference", tl_solid_system(solid), NULL, &c->st);
  if (s == TL_OK) s = tl_stepper_set_state(c->st, 0.0, NULL, NULL);
  if (s == TL_OK) s = tl_calloc(&c->u, 3 * mesh->n_nodes, sizeof *c->u);
  if (s == TL_OK) s = tl_particles_enable_coupling_force(P);
  if (s == TL_OK) s = tl_vcoupling_update(c->vc, c->u, P->n, (const double *)P->x, P->mass);
  if (s != TL_OK) {
    tl_api_vcoupled_destroy(&c);
    TL_CHECK(s);
  }
  tl_dem_set_weight_field(dem, weights, c);
  tl_dem_set_step_hook(dem, coupled_step, c);
  *out = c;
  return TL_OK;
}

TlStepper *tl_api_vcoupled_stepper(const TlVCoupledLoop *c) { return c->st; }

const double *tl_api_vcoupled_u_nodes(const TlVCoupledLoop *c) { return c->u; }

void tl_api_vcoupled_diag(const TlVCoupledLoop *c, TlVCouplingDiag *last, double *eq41_max)
{
  if (last) *last = c->last;
  if (eq41_max) *eq41_max = c->eq41_max;
}

void tl_api_vcoupled_destroy(TlVCoupledLoop **pc)
{
  if (!pc || !*pc) return;
  TlVCoupledLoop *c = *pc;
  if (c->el || c->st) { /* installed (or about to be): the world no longer calls back */
    tl_dem_set_weight_field(c->dem, NULL, NULL);
    tl_dem_set_step_hook(c->dem, NULL, NULL);
  }
  tl_stepper_destroy(&c->st);
  tl_vcoupling_element_destroy(&c->el);
  tl_vcoupling_destroy(&c->vc);
  tl_free(&c->u);
  tl_free(&c->dup);
  tl_free(pc);
}
