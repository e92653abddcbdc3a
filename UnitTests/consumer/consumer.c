/* Uses the installed library: options, math and the error mechanism. */
#include <stdio.h>
#include "talus.h"

int main(int argc, char **argv)
{
  TlOptions *o;
  if (tl_options_create(argc, argv, "consumer of an installed Talus", &o)) return 1;
  double r;
  if (tl_options_get_real(o, "-radius", 0.5, 0.0, 1e3, "m", "radius", &r)) return 1;
  TlStatus s = tl_options_finish(o, stdout);
  tl_options_destroy(&o);
  if (s) return 1;
  TlVec3 v = tl_v3_cross(tl_v3(1, 0, 0), tl_v3(0, 1, 0));
  printf("talus %s: z = %g, radius = %g\n", TALUS_VERSION, v.z, r);
  return v.z == 1.0 && r == 0.25 ? 0 : 1;
}
