/* talus.h alone, in C11 without extensions: a world, a solid and a writer
 * from one include. */
#include "talus.h"

int main(void)
{
  TlDem *dem = NULL;
  TlMesh *mesh = NULL;
  const size_t n[3] = {1, 1, 1};
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  int ok = tl_initialize() == TL_OK && tl_dem_create(&dem) == TL_OK &&
           tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &mesh) == TL_OK && mesh->n_nodes == 8;
  tl_mesh_destroy(&mesh);
  tl_dem_destroy(&dem);
  printf("talus.h from C: %s\n", ok ? "ok" : tl_error_message());
  return ok ? 0 : 1;
}
