/* Mesh nodes and steppers from named settings for bindings (tl_api.h). */
#include "tl_api.h"

#include <stddef.h>

void tl_api_mesh_nodes(const TlMesh *mesh, int *dim, size_t *n_nodes, const double **x)
{
  *dim = mesh->dim;
  *n_nodes = mesh->n_nodes;
  *x = mesh->x;
}

TlStatus tl_api_mesh_node_set(const TlMesh *mesh, const char *name, size_t *n, const size_t **nodes)
{
  const TlNodeSet *set = NULL;
  *n = 0;
  *nodes = NULL;
  TL_CHECK(tl_mesh_find_node_set(mesh, name, &set));
  *n = set->n;
  *nodes = set->nodes;
  return TL_OK;
}

TlStatus tl_api_stepper_create(const char *type, TlMechSystem *sys, const char *solver, size_t n,
                               const char *const *names, const double *values, TlStepper **st)
{
  TlStepperOptions o;
  tl_stepper_options_default(&o);
  if (solver && solver[0]) o.solver = solver;
  for (size_t k = 0; k < n; ++k) TL_CHECK(tl_stepper_options_set(&o, type, names[k], values[k]));
  TL_CHECK(tl_stepper_create(type, sys, &o, st));
  return TL_OK;
}

void tl_api_stepper_state(TlStepper *st, double *t, size_t *n, double **u, double **v, double **a)
{
  *t = st->t;
  *n = (size_t)st->n;
  *u = st->u;
  *v = st->v;
  *a = st->a;
}
