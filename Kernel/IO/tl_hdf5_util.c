#include "tl_hdf5_util.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "tl_atomic_file.h"
#include "tl_memory.h"
#include "tl_provenance.h"

/* ------------------------------------------------------------ errors */
static herr_t tl_h5_walk(unsigned n, const H5E_error2_t *err, void *data)
{
  if (n == 0) snprintf((char *)data, 256, "%s in %s()", err->desc ? err->desc : "?", err->func_name ? err->func_name : "?");
  return 0;
}

/* The innermost entry of HDF5's error stack, for our messages. */
static const char *tl_h5_reason(void)
{
  static _Thread_local char reason[256];
  reason[0] = '\0';
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, tl_h5_walk, reason);
  if (!reason[0]) snprintf(reason, sizeof reason, "no HDF5 detail");
  return reason;
}

static void tl_h5_silence(void) { H5Eset_auto2(H5E_DEFAULT, NULL, NULL); }

/* File access without HDF5's file locks: every file is written once under a
 * private temporary name and only read after the rename, so locks protect
 * nothing here, and they fail on file systems without lock support (some
 * network and container mounts). */
static hid_t tl_h5_fapl(void)
{
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
#if H5_VERSION_GE(1, 10, 7)
  if (fapl >= 0) H5Pset_file_locking(fapl, 0, 1);
#endif
  return fapl;
}

#define TL_H5_FAIL(file, what, obj)                                                                  \
  tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "HDF5: cannot %s '%s' in '%s' (%s)", (what), (obj),   \
               (file)->path, tl_h5_reason())

/* ------------------------------------------------------------ files */
static TlStatus tl_h5_create_impl(const char *path, TlH5File *file, int sealed)
{
  tl_h5_silence();
  file->id = H5I_INVALID_HID;
  file->path = file->temp = NULL;
  file->sealed = sealed;
  TL_CHECK(tl_strdup(path, &file->path));
  TlStatus s;
  TL_CHECK_GOTO(s, tl_atomic_temp_name(path, &file->temp), fail);
  hid_t fapl = tl_h5_fapl(), fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (sealed && fcpl >= 0) H5Pset_userblock(fcpl, TL_H5_SEAL_BYTES);
  file->id = H5Fcreate(file->temp, H5F_ACC_TRUNC, fcpl >= 0 ? fcpl : H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  if (fcpl >= 0) H5Pclose(fcpl);
  if (file->id < 0) {
    s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "HDF5: cannot create '%s' (temporary for '%s'): %s",
                     file->temp, path, tl_h5_reason());
    goto fail;
  }
  /* Every file says what made it (tl_provenance.h). */
  s = tl_provenance_write_h5(file);
  if (s != TL_OK) {
    tl_h5_abort(file);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
fail:
  tl_free(&file->path);
  tl_free(&file->temp);
  file->id = H5I_INVALID_HID;
  return s;
}

TlStatus tl_h5_create(const char *path, TlH5File *file) { return tl_h5_create_impl(path, file, 0); }
TlStatus tl_h5_create_sealed(const char *path, TlH5File *file) { return tl_h5_create_impl(path, file, 1); }

/* ------------------------------------------------------------ seal */
#define TL_H5_SEAL_MAGIC "talus-seal-1"

/* Size and FNV-1a checksum of the bytes of f from offset TL_H5_SEAL_BYTES. */
static int tl_h5_digest(FILE *f, unsigned long long *size, unsigned long long *hash)
{
  unsigned long long h = 1469598103934665603ULL, n = 0;
  unsigned char buf[65536];
  if (fseek(f, TL_H5_SEAL_BYTES, SEEK_SET) != 0) return 0;
  size_t k;
  while ((k = fread(buf, 1, sizeof buf, f)) > 0) {
    for (size_t i = 0; i < k; ++i) h = (h ^ buf[i]) * 1099511628211ULL;
    n += k;
  }
  if (ferror(f)) return 0;
  *size = n;
  *hash = h;
  return 1;
}

TlStatus tl_h5_seal(const char *path)
{
  FILE *f = fopen(path, "r+b");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot open '%s' to write its checksum", path);
  unsigned long long n = 0, h = 0;
  char block[TL_H5_SEAL_BYTES];
  memset(block, 0, sizeof block);
  int ok = tl_h5_digest(f, &n, &h);
  snprintf(block, sizeof block, "%s size=%llu fnv1a64=%016llx\n", TL_H5_SEAL_MAGIC, n, h);
  ok = ok && fseek(f, 0, SEEK_SET) == 0 && fwrite(block, 1, sizeof block, f) == sizeof block;
  ok = (fclose(f) == 0) && ok;
  if (!ok) TL_ERROR(TL_ERR_IO, "cannot write the checksum of '%s'", path);
  return TL_OK;
}

/* Verifies the seal of path before HDF5 reads it. */
static TlStatus tl_h5_verify_seal(const char *path)
{
  FILE *f = fopen(path, "rb");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot read '%s': %s", path, strerror(errno));
  char block[TL_H5_SEAL_BYTES + 1];
  size_t got = fread(block, 1, TL_H5_SEAL_BYTES, f);
  block[got] = '\0';
  unsigned long long n_said = 0, h_said = 0, n = 0, h = 0;
  size_t magic = strlen(TL_H5_SEAL_MAGIC);
  int have = got == TL_H5_SEAL_BYTES && strncmp(block, TL_H5_SEAL_MAGIC, magic) == 0 &&
             sscanf(block + magic, " size=%llu fnv1a64=%llx", &n_said, &h_said) == 2;
  int digest = have && tl_h5_digest(f, &n, &h);
  fclose(f);
  if (!have)
    TL_ERROR(TL_ERR_FORMAT, "'%s' has no checksum block (not a Talus checkpoint, written by a version without "
             "checksums, or its first bytes are damaged)", path);
  if (!digest) TL_ERROR(TL_ERR_IO, "cannot read '%s' to verify its checksum", path);
  if (n != n_said || h != h_said)
    TL_ERROR(TL_ERR_FORMAT, "'%s' is corrupted: %llu bytes with checksum %016llx, its block says %llu bytes with "
             "checksum %016llx", path, n, h, n_said, h_said);
  return TL_OK;
}

TlStatus tl_h5_commit(TlH5File *file)
{
  if (!file->temp || file->id < 0) TL_ERROR(TL_ERR_STATE, "commit of an HDF5 file that is not being written");
  herr_t e = H5Fclose(file->id);
  file->id = H5I_INVALID_HID;
  TlStatus s = TL_OK;
  if (e < 0) {
    s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "HDF5: cannot close '%s' (temporary for '%s'): %s",
                     file->temp, file->path, tl_h5_reason());
    unlink(file->temp);
  } else {
    if (file->sealed) s = tl_h5_seal(file->temp);
    if (s == TL_OK) s = tl_atomic_commit_path(file->temp, file->path);
    else unlink(file->temp);
    if (s != TL_OK) tl_error_trace(s, __FILE__, __LINE__);
  }
  tl_free(&file->temp);
  tl_free(&file->path);
  return s;
}

void tl_h5_abort(TlH5File *file)
{
  if (file->id >= 0) H5Fclose(file->id);
  file->id = H5I_INVALID_HID;
  if (file->temp) unlink(file->temp);
  tl_free(&file->temp);
  tl_free(&file->path);
}

TlStatus tl_h5_open(const char *path, TlH5File *file)
{
  tl_h5_silence();
  file->sealed = 0;
  file->id = H5I_INVALID_HID;
  file->path = file->temp = NULL;
  if (access(path, R_OK) != 0)
    TL_ERROR(TL_ERR_IO, "cannot read '%s': no such file or no permission", path);
  TL_CHECK(tl_strdup(path, &file->path));
  hid_t fapl = tl_h5_fapl();
  file->id = H5Fopen(path, H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  if (file->id < 0) {
    TlStatus s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "HDF5: cannot open '%s' (not an HDF5 file? %s)",
                              path, tl_h5_reason());
    tl_free(&file->path);
    return s;
  }
  return TL_OK;
}

TlStatus tl_h5_open_sealed(const char *path, TlH5File *file)
{
  file->id = H5I_INVALID_HID;
  file->path = file->temp = NULL;
  TL_CHECK(tl_h5_verify_seal(path));
  TL_CHECK(tl_h5_open(path, file));
  file->sealed = 1;
  return TL_OK;
}

void tl_h5_close(TlH5File *file)
{
  if (file->id >= 0) H5Fclose(file->id);
  file->id = H5I_INVALID_HID;
  tl_free(&file->path);
  tl_free(&file->temp);
}

/* ------------------------------------------------------------ objects */
int tl_h5_exists(const TlH5File *file, const char *path)
{
  if (!path || path[0] != '/') return 0;
  if (path[1] == '\0') return 1;
  char buf[1024];
  size_t n = strlen(path);
  if (n >= sizeof buf) return 0;
  memcpy(buf, path, n + 1);
  /* every prefix must exist before H5Lexists may be asked about the next */
  for (size_t i = 1; i <= n; ++i) {
    if (buf[i] != '/' && buf[i] != '\0') continue;
    char c = buf[i];
    buf[i] = '\0';
    if (H5Lexists(file->id, buf, H5P_DEFAULT) <= 0) return 0;
    buf[i] = c;
  }
  return H5Oexists_by_name(file->id, path, H5P_DEFAULT) > 0;
}

static hid_t tl_h5_lcpl(void)
{
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  if (lcpl >= 0) H5Pset_create_intermediate_group(lcpl, 1);
  return lcpl;
}

TlStatus tl_h5_group(TlH5File *file, const char *path)
{
  if (tl_h5_exists(file, path)) return TL_OK;
  hid_t lcpl = tl_h5_lcpl();
  hid_t g = H5Gcreate2(file->id, path, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  H5Pclose(lcpl);
  if (g < 0) return TL_H5_FAIL(file, "create group", path);
  H5Gclose(g);
  return TL_OK;
}

/* Creation properties of an array: chunked (at most 2^20 elements a chunk)
 * with the Fletcher32 checksum, which HDF5 verifies on every read, so a
 * corrupted file is refused instead of read as values.  Scalars and empty
 * arrays cannot be chunked: contiguous, without checksum. */
static hid_t tl_h5_dcpl(int rank, const hsize_t *dims)
{
  hsize_t count = 1, row = 1;
  for (int i = 0; i < rank; ++i) count *= dims[i];
  if (rank == 0 || count == 0) return H5P_DEFAULT;
  for (int i = 1; i < rank; ++i) row *= dims[i];
  hsize_t chunk[TL_H5_MAX_RANK];
  for (int i = 0; i < rank; ++i) chunk[i] = dims[i];
  hsize_t rows = ((hsize_t)1 << 20) / row;
  chunk[0] = rows < 1 ? 1 : rows < dims[0] ? rows : dims[0];
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (dcpl < 0) return dcpl;
  if (H5Pset_chunk(dcpl, rank, chunk) < 0 || H5Pset_fletcher32(dcpl) < 0) {
    H5Pclose(dcpl);
    return H5I_INVALID_HID;
  }
  return dcpl;
}

TlStatus tl_h5_write(TlH5File *file, const char *path, hid_t memtype, int rank, const hsize_t *dims,
                     const void *data)
{
  if (rank < 0 || rank > TL_H5_MAX_RANK)
    TL_ERROR(TL_ERR_ARG, "dataset '%s' of '%s': rank %d outside [0, %d]", path, file->path, rank, TL_H5_MAX_RANK);
  if (tl_h5_exists(file, path))
    TL_ERROR(TL_ERR_ARG, "dataset '%s' of '%s' is written twice", path, file->path);
  hsize_t count = 1;
  for (int i = 0; i < rank; ++i) count *= dims[i];
  if (count > 0 && !data) TL_ERROR(TL_ERR_ARG, "dataset '%s' of '%s': no data given", path, file->path);
  hid_t space = rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims, NULL);
  if (space < 0) return TL_H5_FAIL(file, "create dataspace for", path);
  hid_t lcpl = tl_h5_lcpl(), dcpl = tl_h5_dcpl(rank, dims);
  hid_t d = dcpl < 0 ? H5I_INVALID_HID : H5Dcreate2(file->id, path, memtype, space, lcpl, dcpl, H5P_DEFAULT);
  H5Pclose(lcpl);
  if (dcpl >= 0 && dcpl != H5P_DEFAULT) H5Pclose(dcpl);
  H5Sclose(space);
  if (d < 0) return TL_H5_FAIL(file, "create dataset", path);
  herr_t e = count > 0 ? H5Dwrite(d, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0;
  if (e < 0) {
    TlStatus s = TL_H5_FAIL(file, "write dataset", path);
    H5Dclose(d);
    return s;
  }
  if (H5Dclose(d) < 0) return TL_H5_FAIL(file, "close dataset", path);
  return TL_OK;
}

static TlStatus tl_h5_open_dataset(const TlH5File *file, const char *path, hid_t *d)
{
  if (!tl_h5_exists(file, path))
    TL_ERROR(TL_ERR_NOT_FOUND, "'%s' has no dataset '%s'", file->path, path);
  *d = H5Dopen2(file->id, path, H5P_DEFAULT);
  if (*d < 0) return TL_H5_FAIL(file, "open dataset", path);
  return TL_OK;
}

TlStatus tl_h5_dims(const TlH5File *file, const char *path, int *rank, hsize_t dims[TL_H5_MAX_RANK])
{
  hid_t d = H5I_INVALID_HID;
  TL_CHECK(tl_h5_open_dataset(file, path, &d));
  hid_t space = H5Dget_space(d);
  int r = space >= 0 ? H5Sget_simple_extent_ndims(space) : -1;
  if (r < 0 || r > TL_H5_MAX_RANK) {
    if (space >= 0) H5Sclose(space);
    H5Dclose(d);
    TL_ERROR(TL_ERR_FORMAT, "dataset '%s' of '%s' has rank %d, at most %d supported", path, file->path, r,
             TL_H5_MAX_RANK);
  }
  H5Sget_simple_extent_dims(space, dims, NULL);
  *rank = r;
  H5Sclose(space);
  H5Dclose(d);
  return TL_OK;
}

static void tl_shape_string(int rank, const hsize_t *dims, char *buf, size_t cap)
{
  size_t k = (size_t)snprintf(buf, cap, "(");
  for (int i = 0; i < rank && k < cap; ++i)
    k += (size_t)snprintf(buf + k, cap - k, "%s%llu", i ? ", " : "", (unsigned long long)dims[i]);
  if (k < cap) snprintf(buf + k, cap - k, ")");
}

TlStatus tl_h5_read(const TlH5File *file, const char *path, hid_t memtype, int rank, const hsize_t *dims,
                    void *data)
{
  int r;
  hsize_t have[TL_H5_MAX_RANK];
  TL_CHECK(tl_h5_dims(file, path, &r, have));
  int same = r == rank;
  for (int i = 0; same && i < rank; ++i) same = have[i] == dims[i];
  if (!same) {
    char want_s[128], have_s[128];
    tl_shape_string(rank, dims, want_s, sizeof want_s);
    tl_shape_string(r, have, have_s, sizeof have_s);
    TL_ERROR(TL_ERR_FORMAT, "dataset '%s' of '%s' has shape %s, expected %s", path, file->path, have_s, want_s);
  }
  hsize_t count = 1;
  for (int i = 0; i < rank; ++i) count *= dims[i];
  if (count == 0) return TL_OK;
  hid_t d = H5I_INVALID_HID;
  TL_CHECK(tl_h5_open_dataset(file, path, &d));
  herr_t e = H5Dread(d, memtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
  H5Dclose(d);
  /* a Fletcher32 mismatch fails the read (HDF5 checks by default) */
  if (e < 0) return TL_H5_FAIL(file, "read dataset (corrupted? its checksum is verified)", path);
  return TL_OK;
}

static hid_t tl_h5_string_type(size_t len)
{
  hid_t t = H5Tcopy(H5T_C_S1);
  if (t < 0) return t;
  H5Tset_size(t, len > 0 ? len : 1);
  H5Tset_strpad(t, H5T_STR_NULLTERM);
  return t;
}

TlStatus tl_h5_write_string(TlH5File *file, const char *path, const char *value)
{
  hid_t t = tl_h5_string_type(strlen(value) + 1);
  if (t < 0) return TL_H5_FAIL(file, "make string type for", path);
  TlStatus s = tl_h5_write(file, path, t, 0, NULL, value);
  H5Tclose(t);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}

/* Reads a fixed-length string (dataset or attribute) of type ftype. */
static TlStatus tl_h5_read_fixed_string(const TlH5File *file, const char *what, hid_t obj, hid_t ftype, int is_attr,
                                        char **value)
{
  if (H5Tget_class(ftype) != H5T_STRING || H5Tis_variable_str(ftype) > 0)
    TL_ERROR(TL_ERR_FORMAT, "'%s' of '%s' is not a fixed-length string", what, file->path);
  size_t len = H5Tget_size(ftype);
  TL_CHECK(tl_calloc(value, len + 1, 1));
  hid_t t = tl_h5_string_type(len);
  herr_t e = is_attr ? H5Aread(obj, t, *value) : H5Dread(obj, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, *value);
  H5Tclose(t);
  if (e < 0) {
    tl_free(value);
    return TL_H5_FAIL(file, "read string", what);
  }
  return TL_OK;
}

TlStatus tl_h5_read_string(const TlH5File *file, const char *path, char **value)
{
  hid_t d = H5I_INVALID_HID;
  TL_CHECK(tl_h5_open_dataset(file, path, &d));
  hid_t ft = H5Dget_type(d);
  TlStatus s = tl_h5_read_fixed_string(file, path, d, ft, 0, value);
  H5Tclose(ft);
  H5Dclose(d);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}

/* ------------------------------------------------------------ attributes */
static TlStatus tl_h5_attr_write(TlH5File *file, const char *object, const char *name, hid_t type, hid_t space,
                                 const void *value)
{
  if (!tl_h5_exists(file, object)) TL_CHECK(tl_h5_group(file, object));
  hid_t o = H5Oopen(file->id, object, H5P_DEFAULT);
  if (o < 0) return TL_H5_FAIL(file, "open object", object);
  if (H5Aexists(o, name) > 0) H5Adelete(o, name);
  hid_t a = H5Acreate2(o, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  /* an empty array attribute has nothing to write (and HDF5 refuses a NULL buffer) */
  herr_t e = a < 0 ? -1 : H5Sget_simple_extent_npoints(space) == 0 ? 0 : H5Awrite(a, type, value);
  TlStatus s = TL_OK;
  if (e < 0)
    s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "HDF5: cannot write attribute '%s' of '%s' in '%s' (%s)", name,
                     object, file->path, tl_h5_reason());
  if (a >= 0) H5Aclose(a);
  H5Oclose(o);
  return s;
}

TlStatus tl_h5_attr_write_double(TlH5File *file, const char *object, const char *name, double value)
{
  hid_t sp = H5Screate(H5S_SCALAR);
  TlStatus s = tl_h5_attr_write(file, object, name, H5T_NATIVE_DOUBLE, sp, &value);
  H5Sclose(sp);
  return s;
}

TlStatus tl_h5_attr_write_int64(TlH5File *file, const char *object, const char *name, int64_t value)
{
  hid_t sp = H5Screate(H5S_SCALAR);
  TlStatus s = tl_h5_attr_write(file, object, name, H5T_NATIVE_INT64, sp, &value);
  H5Sclose(sp);
  return s;
}

TlStatus tl_h5_attr_write_string(TlH5File *file, const char *object, const char *name, const char *value)
{
  hid_t sp = H5Screate(H5S_SCALAR);
  hid_t t = tl_h5_string_type(strlen(value) + 1);
  TlStatus s = tl_h5_attr_write(file, object, name, t, sp, value);
  H5Tclose(t);
  H5Sclose(sp);
  return s;
}

TlStatus tl_h5_attr_write_strings(TlH5File *file, const char *object, const char *name, size_t n,
                                  const char *const *values)
{
  size_t len = 1;
  for (size_t i = 0; i < n; ++i)
    if (strlen(values[i]) + 1 > len) len = strlen(values[i]) + 1;
  char *buf = NULL;
  if (n > 0) TL_CHECK(tl_calloc(&buf, n, len));
  for (size_t i = 0; i < n; ++i) memcpy(buf + i * len, values[i], strlen(values[i]));
  hsize_t dim = n;
  hid_t sp = H5Screate_simple(1, &dim, NULL);
  hid_t t = tl_h5_string_type(len);
  TlStatus s = tl_h5_attr_write(file, object, name, t, sp, buf);
  H5Tclose(t);
  H5Sclose(sp);
  tl_free(&buf);
  return s;
}

static TlStatus tl_h5_attr_open(const TlH5File *file, const char *object, const char *name, hid_t *o, hid_t *a)
{
  if (!tl_h5_exists(file, object)) TL_ERROR(TL_ERR_NOT_FOUND, "'%s' has no object '%s'", file->path, object);
  *o = H5Oopen(file->id, object, H5P_DEFAULT);
  if (*o < 0) return TL_H5_FAIL(file, "open object", object);
  if (H5Aexists(*o, name) <= 0) {
    H5Oclose(*o);
    TL_ERROR(TL_ERR_NOT_FOUND, "object '%s' of '%s' has no attribute '%s'", object, file->path, name);
  }
  *a = H5Aopen(*o, name, H5P_DEFAULT);
  if (*a < 0) {
    H5Oclose(*o);
    return TL_H5_FAIL(file, "open attribute", name);
  }
  return TL_OK;
}

static TlStatus tl_h5_attr_read_scalar(const TlH5File *file, const char *object, const char *name, hid_t type,
                                       void *value)
{
  hid_t o = H5I_INVALID_HID, a = H5I_INVALID_HID;
  TL_CHECK(tl_h5_attr_open(file, object, name, &o, &a));
  hid_t sp = H5Aget_space(a);
  hssize_t n = H5Sget_simple_extent_npoints(sp);
  H5Sclose(sp);
  herr_t e = n == 1 ? H5Aread(a, type, value) : -1;
  H5Aclose(a);
  H5Oclose(o);
  if (n != 1)
    TL_ERROR(TL_ERR_FORMAT, "attribute '%s' of '%s' in '%s' holds %lld values, expected 1", name, object,
             file->path, (long long)n);
  if (e < 0) return TL_H5_FAIL(file, "read attribute", name);
  return TL_OK;
}

TlStatus tl_h5_attr_read_double(const TlH5File *file, const char *object, const char *name, double *value)
{
  return tl_h5_attr_read_scalar(file, object, name, H5T_NATIVE_DOUBLE, value);
}

TlStatus tl_h5_attr_read_int64(const TlH5File *file, const char *object, const char *name, int64_t *value)
{
  return tl_h5_attr_read_scalar(file, object, name, H5T_NATIVE_INT64, value);
}

TlStatus tl_h5_attr_read_string(const TlH5File *file, const char *object, const char *name, char **value)
{
  hid_t o = H5I_INVALID_HID, a = H5I_INVALID_HID;
  TL_CHECK(tl_h5_attr_open(file, object, name, &o, &a));
  hid_t ft = H5Aget_type(a);
  TlStatus s = tl_h5_read_fixed_string(file, name, a, ft, 1, value);
  H5Tclose(ft);
  H5Aclose(a);
  H5Oclose(o);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}

void tl_h5_free_strings(size_t n, char ***values)
{
  if (!*values) return;
  for (size_t i = 0; i < n; ++i) tl_free(&(*values)[i]);
  tl_free(values);
}

TlStatus tl_h5_attr_read_strings(const TlH5File *file, const char *object, const char *name, size_t *n,
                                 char ***values)
{
  hid_t o = H5I_INVALID_HID, a = H5I_INVALID_HID;
  *n = 0;
  *values = NULL;
  TL_CHECK(tl_h5_attr_open(file, object, name, &o, &a));
  hid_t ft = H5Aget_type(a);
  hid_t sp = H5Aget_space(a);
  hssize_t count = H5Sget_simple_extent_npoints(sp);
  H5Sclose(sp);
  TlStatus s = TL_OK;
  char *buf = NULL;
  if (H5Tget_class(ft) != H5T_STRING || H5Tis_variable_str(ft) > 0 || count < 0) {
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "attribute '%s' of '%s' in '%s' is not a fixed-length string array",
                     name, object, file->path);
    goto done;
  }
  size_t len = H5Tget_size(ft);
  TL_CHECK_GOTO(s, tl_calloc(&buf, (size_t)count + 1, len), done);
  hid_t t = tl_h5_string_type(len);
  herr_t e = H5Aread(a, t, buf);
  H5Tclose(t);
  if (e < 0) {
    s = TL_H5_FAIL(file, "read attribute", name);
    goto done;
  }
  TL_CHECK_GOTO(s, tl_calloc(values, (size_t)count + 1, sizeof **values), done);
  for (size_t i = 0; i < (size_t)count; ++i) {
    TL_CHECK_GOTO(s, tl_calloc(&(*values)[i], len + 1, 1), done);
    memcpy((*values)[i], buf + i * len, len);
    *n = i + 1;
  }
done:
  if (s != TL_OK) tl_h5_free_strings(*n, values), *n = 0;
  tl_free(&buf);
  H5Tclose(ft);
  H5Aclose(a);
  H5Oclose(o);
  return s;
}
