/* libFuzzer harness of the Gmsh .msh 4.1 reader. */
#include "fuzz_common.h"
#include "tl_mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  tl_fuzz_init();
  const char *path = tl_fuzz_file("fuzz_gmsh", data, size);
  if (!path) return 0;
  TlMesh *m = NULL;
  if (tl_mesh_read_gmsh(path, &m) == TL_OK) (void)tl_mesh_volume(m);
  tl_mesh_destroy(&m);
  return 0;
}
