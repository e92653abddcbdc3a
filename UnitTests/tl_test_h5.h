/* Test helpers that change a checkpoint file behind the library's back:
 * through HDF5 itself (a value changed, every checksum recomputed) or as raw
 * bytes (a flipped byte, the checksums left stale; tl_h5_seal then renews
 * the whole-file one, leaving the dataset's Fletcher32 stale). */
#ifndef TL_TEST_H5_H
#define TL_TEST_H5_H

#include <hdf5.h>

#include "tl_hdf5_util.h"
#include "tl_test.h"
#include <string.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static inline void tl_test_copy_file(const char *from, const char *to)
{
  FILE *f = fopen(from, "rb"), *g = fopen(to, "wb");
  if (f && g) {
    char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) fwrite(buf, 1, n, g);
  }
  if (f) fclose(f);
  if (g) fclose(g);
}

/* Sets element k of a double or int64 dataset (scalars: k = 0) in place. */
static inline int tl_test_h5_set(const char *file, const char *dataset, size_t k, double value, int is_int)
{
  hid_t f = H5Fopen(file, H5F_ACC_RDWR, H5P_DEFAULT);
  if (f < 0) return 0;
  hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  int ok = 0;
  if (d >= 0) {
    hid_t sp = H5Dget_space(d);
    hssize_t n = H5Sget_simple_extent_npoints(sp);
    H5Sclose(sp);
    hid_t type = is_int ? H5T_NATIVE_INT64 : H5T_NATIVE_DOUBLE;
    size_t size = is_int ? sizeof(int64_t) : sizeof(double);
    char *buf = calloc((size_t)n + 1, size);
    if (n > (hssize_t)k && H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) >= 0) {
      if (is_int) ((int64_t *)buf)[k] = (int64_t)value;
      else ((double *)buf)[k] = value;
      ok = H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) >= 0;
    }
    free(buf);
    H5Dclose(d);
  }
  H5Fclose(f);
  /* the whole-file checksum follows the change: the loader's checks must
   * catch the value itself */
  return ok && tl_h5_seal(file) == TL_OK;
}

/* Flips one byte in the stored data of a chunked dataset. */
static inline int tl_test_flip_stored_byte(const char *file, const char *dataset)
{
  hid_t f = H5Fopen(file, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return 0;
  hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  haddr_t addr = HADDR_UNDEF;
  hsize_t size = 0;
  if (d >= 0) {
    hsize_t coord[2] = {0, 0};
    unsigned mask = 0;
    H5Dget_chunk_info_by_coord(d, coord, &mask, &addr, &size);
    H5Dclose(d);
  }
  /* chunk addresses count from the end of the user block */
  hsize_t userblock = 0;
  hid_t fcpl = H5Fget_create_plist(f);
  if (fcpl >= 0) H5Pget_userblock(fcpl, &userblock), H5Pclose(fcpl);
  if (addr != HADDR_UNDEF) addr += userblock;
  H5Fclose(f);
  if (addr == HADDR_UNDEF || size < 16) return 0;
  FILE *g = fopen(file, "r+b");
  if (!g) return 0;
  fseek(g, (long)(addr + 9), SEEK_SET);
  int c = fgetc(g);
  fseek(g, (long)(addr + 9), SEEK_SET);
  fputc(c ^ 0x20, g);
  fclose(g);
  return 1;
}

/* A copy of good.h5 with element k of `dataset` set to `value` must be
 * refused by `load` with a message containing `fragment`. */
static inline void tl_test_h5_refused(TlStatus (*load)(const char *file), const char *dataset, size_t k, double value,
                                      int is_int, const char *fragment)
{
  tl_test_copy_file("good.h5", "changed.h5");
  int set = tl_test_h5_set("changed.h5", dataset, k, value, is_int);
  TL_TEST_ASSERT(set, "cannot change %s[%zu] in the test file", dataset, k);
  if (!set) return;
  TlStatus s = load("changed.h5");
  TL_TEST_ASSERT(s != TL_OK && strstr(tl_error_message(), fragment),
                 "%s[%zu] = %g: status %d, message '%s' (expected it to name '%s')", dataset, k, value, (int)s,
                 tl_error_message(), fragment);
}

#endif
