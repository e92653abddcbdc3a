/* libFuzzer harness of the surface readers: STL (ASCII and binary) and Gmsh
 * surfaces, told apart by content, then the check and the queries a wall or
 * a mesher makes of what was read. */
#include "fuzz_common.h"
#include "tl_stl.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  tl_fuzz_init();
  const char *path = tl_fuzz_file("fuzz_stl", data, size);
  if (!path) return 0;
  TlSurfaceMesh *m = NULL;
  if (tl_surface_mesh_read(path, &m) == TL_OK) {
    if (tl_surface_mesh_check(m, 0) == TL_OK) {
      double v;
      (void)tl_surface_mesh_area(m);
      if (tl_surface_mesh_volume(m, &v) == TL_OK && m->n_triangles < 64) {
        int in;
        (void)tl_surface_mesh_contains(m, m->x[0], &in);
      }
    }
  }
  tl_surface_mesh_destroy(&m);
  tl_error_clear();
  return 0;
}
