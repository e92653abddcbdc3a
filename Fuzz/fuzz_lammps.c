/* libFuzzer harness of the LAMMPS data-file reader. */
#include "fuzz_common.h"
#include "tl_lammps_data.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  tl_fuzz_init();
  const char *path = tl_fuzz_file("fuzz_lammps", data, size);
  if (!path) return 0;
  TlLammpsData *d = NULL;
  if (tl_lammps_data_read(path, &d) == TL_OK)
    for (size_t i = 0; i < d->n; ++i) {
      (void)tl_lammps_data_mass(d, i);
      (void)tl_lammps_data_unwrapped(d, i);
    }
  tl_lammps_data_destroy(&d);
  return 0;
}
