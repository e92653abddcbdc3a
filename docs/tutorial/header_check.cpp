// talus.h from C++: the library's functions with C linkage, next to the
// C++ standard library.
#include <cmath>
#include <iostream>
#include <vector>
#include "talus.h"

int main()
{
  TlDem *dem = nullptr;
  TlMesh *mesh = nullptr;
  const size_t n[3] = {1, 1, 1};
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  std::vector<double> r(1, std::sqrt(4.0));
  bool ok = tl_initialize() == TL_OK && tl_dem_create(&dem) == TL_OK &&
            tl_mesh_create_box(&tl_element_hex8, n, lo, hi, &mesh) == TL_OK && mesh->n_nodes == 8 && r[0] == 2.0;
  tl_mesh_destroy(&mesh);
  tl_dem_destroy(&dem);
  std::cout << "talus.h from C++: " << (ok ? "ok" : tl_error_message()) << "\n";
  return ok ? 0 : 1;
}
