/* The consistent mass of 27-node hexahedra (cantilever_fem -mode vibration
 * -elements hex27): the assembled matrix M gives the same kinetic energy
 * v^T M v / 2 as the element-by-element product of tl_solid_kinetic_energy,
 * for a velocity with every component different.  The element block
 * (27 x 27) used to be written into a scratch area sized for 8-node
 * elements. */
#include <math.h>

#include "talus.h"
#include "tl_cantilever.h"
#include "tl_test.h"

static void check(const TlElementType *type)
{
  TlCantileverParams p;
  tl_cantilever_params_default(&p);
  p.type = type;
  p.nx = 1, p.ny = 3, p.nz = 1;
  TlCantilever *beam = NULL;
  TL_TEST_STATUS(tl_cantilever_create(&p, &beam), TL_OK);
  if (!beam) return;
  TlMechSystem *sys = tl_solid_system(beam->solid);
  TlSparse *M = NULL;
  TL_TEST_STATUS(sys->ops->create_matrix(sys, 1, &M), TL_OK);
  TL_TEST_STATUS(sys->ops->consistent_mass(sys, 1.0, M), TL_OK);
  size_t n = (size_t)sys->ndof;
  double *v = calloc(n, sizeof *v), *Mv = calloc(n, sizeof *Mv);
  for (size_t i = 0; i < n; ++i) v[i] = sin(0.7 * (double)i + 0.3);
  tl_sparse_matvec(M, v, Mv);
  double k_matrix = 0.0, k_elements = NAN;
  for (size_t i = 0; i < n; ++i) k_matrix += 0.5 * v[i] * Mv[i];
  TL_TEST_STATUS(tl_solid_kinetic_energy(beam->solid, v, &k_elements), TL_OK);
  TL_TEST_ASSERT(k_elements > 0.0 && fabs(k_matrix - k_elements) <= 1e-12 * k_elements,
                 "%d nodes: kinetic energy from M %.17g, element by element %.17g", type->n_nodes, k_matrix, k_elements);
  free(v);
  free(Mv);
  tl_sparse_destroy(&M);
  tl_cantilever_destroy(&beam);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  check(&tl_element_hex8);
  check(&tl_element_hex27);
  return tl_test_report();
}
