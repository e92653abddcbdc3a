#include "tl_checkpoint.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_hdf5_util.h"
#include "tl_memory.h"

/* A checkpoint in memory: the datasets in the order written, each a path,
 * a kind, a rank and its bytes.  Buffers stay allocated from one save to the
 * next (a cell saved at every step writes the same paths again). */
enum { TL_CKPT_DOUBLE = 0, TL_CKPT_INT64, TL_CKPT_BYTES, TL_CKPT_STRING };

typedef struct {
  char *path;
  int kind, rank;
  size_t n, bytes, cap; /* elements, bytes used, bytes allocated */
  void *data;
} TlCkptEntry;

struct TlCheckpointMemory {
  TlCkptEntry *entries;
  size_t n, cap;
};

static char tl_ckpt_memory_name[] = "(checkpoint in memory)";

struct TlCheckpointWriter {
  TlH5File file;
  TlCheckpointMemory *mem; /* non-NULL: writes go here, not to a file */
};

struct TlCheckpointReader {
  TlH5File file;
  const TlCheckpointMemory *mem;
  size_t cursor; /* where the next lookup starts: loads read in save order */
};

enum { TL_CKPT_PATH_MAX = 1024 };

/* "/group/name" into buf. */
static TlStatus tl_ckpt_path(const char *file, const char *group, const char *name, char *buf)
{
  if (!name || !name[0]) TL_ERROR(TL_ERR_ARG, "checkpoint '%s': empty dataset name in group '%s'", file, group ? group : "");
  while (group && *group == '/') ++group;
  int n = (group && group[0]) ? snprintf(buf, TL_CKPT_PATH_MAX, "/%s/%s", group, name)
                              : snprintf(buf, TL_CKPT_PATH_MAX, "/%s", name);
  if (n < 0 || n >= TL_CKPT_PATH_MAX)
    TL_ERROR(TL_ERR_ARG, "checkpoint '%s': path of '%s' longer than %d characters", file, name, TL_CKPT_PATH_MAX - 1);
  return TL_OK;
}

/* ---------------------------------------------------------------- writer */
TlStatus tl_checkpoint_writer_open(const char *path, TlCheckpointWriter **writer)
{
  TlCheckpointWriter *w;
  *writer = NULL;
  TL_CHECK(TL_NEW(w));
  TlStatus s;
  TL_CHECK_GOTO(s, tl_h5_create_sealed(path, &w->file), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_int64(&w->file, "/", "talus_checkpoint_version", TL_CHECKPOINT_VERSION), fail);
  *writer = w;
  return TL_OK;
fail:
  tl_h5_abort(&w->file);
  tl_free(&w);
  return s;
}

TlStatus tl_checkpoint_writer_commit(TlCheckpointWriter **writer)
{
  if (!*writer) TL_ERROR(TL_ERR_STATE, "commit of a checkpoint writer that is not open");
  if ((*writer)->mem) {
    tl_free(writer);
    return TL_OK;
  }
  TlStatus s = tl_h5_commit(&(*writer)->file);
  tl_free(writer);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}

void tl_checkpoint_writer_abort(TlCheckpointWriter **writer)
{
  if (!writer || !*writer) return;
  if ((*writer)->mem) (*writer)->mem->n = 0;
  else tl_h5_abort(&(*writer)->file);
  tl_free(writer);
}

/* Appends a dataset to a memory checkpoint, reusing the buffer of the entry
 * that held this slot in the previous save. */
static TlStatus tl_ckpt_mem_put(TlCheckpointMemory *m, const char *path, int kind, int rank, size_t n, size_t bytes,
                                const void *data)
{
  for (size_t k = 0; k < m->n; ++k)
    if (strcmp(m->entries[k].path, path) == 0)
      TL_ERROR(TL_ERR_ARG, "%s: dataset '%s' written twice", tl_ckpt_memory_name, path);
  if (m->n == m->cap) {
    size_t cap = m->cap ? 2 * m->cap : 32;
    TL_CHECK(tl_realloc(&m->entries, cap, sizeof *m->entries));
    memset(m->entries + m->cap, 0, (cap - m->cap) * sizeof *m->entries);
    m->cap = cap;
  }
  TlCkptEntry *e = &m->entries[m->n];
  if (!e->path || strcmp(e->path, path)) {
    tl_free(&e->path);
    TL_CHECK(tl_strdup(path, &e->path));
  }
  if (bytes > e->cap) {
    TL_CHECK(tl_realloc(&e->data, bytes, 1));
    e->cap = bytes;
  }
  if (bytes) memcpy(e->data, data, bytes);
  e->kind = kind, e->rank = rank, e->n = n, e->bytes = bytes;
  m->n++;
  return TL_OK;
}

/* The HDF5 memory type of a kind (called only on the file path: a memory
 * checkpoint never enters the HDF5 library, which is not thread-safe). */
static hid_t tl_ckpt_h5type(int kind)
{
  return kind == TL_CKPT_DOUBLE ? H5T_NATIVE_DOUBLE : kind == TL_CKPT_INT64 ? H5T_NATIVE_INT64 : H5T_NATIVE_UINT8;
}

static TlStatus tl_ckpt_write(TlCheckpointWriter *w, const char *group, const char *name, int kind, int rank,
                              size_t n, const void *data)
{
  char path[TL_CKPT_PATH_MAX];
  TL_CHECK(tl_ckpt_path(w->file.path, group, name, path));
  if (w->mem) return tl_ckpt_mem_put(w->mem, path, kind, rank, n, n * (kind == TL_CKPT_BYTES ? 1 : 8), data);
  hid_t type = tl_ckpt_h5type(kind);
  hsize_t dim = n;
  TL_CHECK(tl_h5_write(&w->file, path, type, rank, &dim, data));
  return TL_OK;
}

TlStatus tl_checkpoint_write_doubles(TlCheckpointWriter *w, const char *group, const char *name, size_t n,
                                     const double *values)
{
  return tl_ckpt_write(w, group, name, TL_CKPT_DOUBLE, 1, n, values);
}

TlStatus tl_checkpoint_write_int64s(TlCheckpointWriter *w, const char *group, const char *name, size_t n,
                                    const int64_t *values)
{
  return tl_ckpt_write(w, group, name, TL_CKPT_INT64, 1, n, values);
}

TlStatus tl_checkpoint_write_bytes(TlCheckpointWriter *w, const char *group, const char *name, size_t n,
                                   const void *bytes)
{
  return tl_ckpt_write(w, group, name, TL_CKPT_BYTES, 1, n, bytes);
}

TlStatus tl_checkpoint_write_double(TlCheckpointWriter *w, const char *group, const char *name, double value)
{
  return tl_ckpt_write(w, group, name, TL_CKPT_DOUBLE, 0, 1, &value);
}

TlStatus tl_checkpoint_write_int64(TlCheckpointWriter *w, const char *group, const char *name, int64_t value)
{
  return tl_ckpt_write(w, group, name, TL_CKPT_INT64, 0, 1, &value);
}

TlStatus tl_checkpoint_write_string(TlCheckpointWriter *w, const char *group, const char *name, const char *value)
{
  char path[TL_CKPT_PATH_MAX];
  TL_CHECK(tl_ckpt_path(w->file.path, group, name, path));
  if (!value) value = "";
  if (w->mem) return tl_ckpt_mem_put(w->mem, path, TL_CKPT_STRING, 0, 1, strlen(value) + 1, value);
  TL_CHECK(tl_h5_write_string(&w->file, path, value));
  return TL_OK;
}

/* ---------------------------------------------------------------- reader */
TlStatus tl_checkpoint_reader_open(const char *path, TlCheckpointReader **reader)
{
  TlCheckpointReader *r;
  *reader = NULL;
  TL_CHECK(TL_NEW(r));
  TlStatus s;
  TL_CHECK_GOTO(s, tl_h5_open_sealed(path, &r->file), fail);
  int64_t version = 0;
  if (tl_h5_attr_read_int64(&r->file, "/", "talus_checkpoint_version", &version) != TL_OK) {
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__,
                     "'%s' is not a Talus checkpoint (no attribute talus_checkpoint_version)", path);
    goto fail;
  }
  if (version != TL_CHECKPOINT_VERSION) {
    s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "checkpoint '%s' has format version %lld; this build reads %d",
                     path, (long long)version, TL_CHECKPOINT_VERSION);
    goto fail;
  }
  *reader = r;
  return TL_OK;
fail:
  tl_h5_close(&r->file);
  tl_free(&r);
  return s;
}

void tl_checkpoint_reader_close(TlCheckpointReader **reader)
{
  if (!reader || !*reader) return;
  if (!(*reader)->mem) tl_h5_close(&(*reader)->file);
  tl_free(reader);
}

const char *tl_checkpoint_reader_path(const TlCheckpointReader *r) { return r->file.path; }

/* The entry of a memory checkpoint at path, or NULL. */
static const TlCkptEntry *tl_ckpt_mem_find(const TlCheckpointReader *r, const char *path)
{
  const TlCheckpointMemory *m = r->mem;
  TlCheckpointReader *rw = (TlCheckpointReader *)r; /* the cursor is a lookup hint only */
  for (size_t k = 0; k < m->n; ++k) {
    size_t q = (r->cursor + k) % m->n;
    if (strcmp(m->entries[q].path, path) == 0) {
      rw->cursor = q + 1;
      return &m->entries[q];
    }
  }
  return NULL;
}

int tl_checkpoint_has(const TlCheckpointReader *r, const char *group, const char *name)
{
  char path[TL_CKPT_PATH_MAX];
  if (tl_ckpt_path(r->file.path, group, name, path) != TL_OK) return 0;
  if (r->mem) return tl_ckpt_mem_find(r, path) != NULL;
  return tl_h5_exists(&r->file, path);
}

/* Checks the stored element type: class and size must match what is asked. */
static TlStatus tl_ckpt_check_type(const TlCheckpointReader *r, const char *path, H5T_class_t cls, size_t size,
                                   const char *what)
{
  hid_t d = H5Dopen2(r->file.id, path, H5P_DEFAULT);
  if (d < 0) TL_ERROR(TL_ERR_IO, "checkpoint '%s': cannot open dataset '%s'", r->file.path, path);
  hid_t t = H5Dget_type(d);
  H5T_class_t c = H5Tget_class(t);
  size_t sz = H5Tget_size(t);
  H5Tclose(t);
  H5Dclose(d);
  if (c != cls || sz != size)
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': dataset '%s' does not hold %s (type class %d, %zu bytes)", r->file.path,
             path, what, (int)c, sz);
  return TL_OK;
}

TlStatus tl_checkpoint_length(const TlCheckpointReader *r, const char *group, const char *name, size_t *n)
{
  char path[TL_CKPT_PATH_MAX];
  TL_CHECK(tl_ckpt_path(r->file.path, group, name, path));
  if (r->mem) {
    const TlCkptEntry *e = tl_ckpt_mem_find(r, path);
    if (!e || e->kind == TL_CKPT_STRING)
      TL_ERROR(TL_ERR_NOT_FOUND, "checkpoint '%s' has no dataset '%s'", r->file.path, path);
    *n = e->n;
    return TL_OK;
  }
  if (!tl_h5_exists(&r->file, path))
    TL_ERROR(TL_ERR_NOT_FOUND, "checkpoint '%s' has no dataset '%s'", r->file.path, path);
  int rank;
  hsize_t dims[TL_H5_MAX_RANK];
  TL_CHECK(tl_h5_dims(&r->file, path, &rank, dims));
  *n = 1;
  for (int i = 0; i < rank; ++i) *n *= (size_t)dims[i];
  return TL_OK;
}

static TlStatus tl_ckpt_read(const TlCheckpointReader *r, const char *group, const char *name, int kind,
                             const char *what, int rank, size_t n, void *data)
{
  char path[TL_CKPT_PATH_MAX];
  TL_CHECK(tl_ckpt_path(r->file.path, group, name, path));
  if (r->mem) {
    const TlCkptEntry *e = tl_ckpt_mem_find(r, path);
    if (!e) TL_ERROR(TL_ERR_NOT_FOUND, "checkpoint '%s' has no dataset '%s' (expected %zu %s)", r->file.path, path, n, what);
    if (e->kind != kind)
      TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': dataset '%s' does not hold %s", r->file.path, path, what);
    if (e->rank != rank || e->n != n)
      TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': dataset '%s' holds %zu %s, expected %zu%s", r->file.path, path, e->n,
               what, n, e->rank != rank ? (rank == 0 ? " (a scalar)" : " (an array)") : "");
    if (e->bytes) memcpy(data, e->data, e->bytes);
    return TL_OK;
  }
  hid_t memtype = tl_ckpt_h5type(kind);
  H5T_class_t cls = kind == TL_CKPT_DOUBLE ? H5T_FLOAT : H5T_INTEGER;
  if (!tl_h5_exists(&r->file, path))
    TL_ERROR(TL_ERR_NOT_FOUND, "checkpoint '%s' has no dataset '%s' (expected %zu %s)", r->file.path, path, n, what);
  TL_CHECK(tl_ckpt_check_type(r, path, cls, H5Tget_size(memtype), what));
  int have_rank;
  hsize_t dims[TL_H5_MAX_RANK];
  TL_CHECK(tl_h5_dims(&r->file, path, &have_rank, dims));
  if (have_rank != rank || (rank == 1 && dims[0] != n))
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': dataset '%s' holds %llu %s, expected %zu%s", r->file.path, path,
             have_rank == 1 ? (unsigned long long)dims[0] : 1ULL, what, n,
             have_rank != rank ? (rank == 0 ? " (a scalar)" : " (an array)") : "");
  hsize_t dim = n;
  TL_CHECK(tl_h5_read(&r->file, path, memtype, rank, &dim, data));
  return TL_OK;
}

TlStatus tl_checkpoint_read_doubles(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                    double *values)
{
  return tl_ckpt_read(r, group, name, TL_CKPT_DOUBLE, "doubles", 1, n, values);
}

TlStatus tl_checkpoint_read_int64s(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                   int64_t *values)
{
  return tl_ckpt_read(r, group, name, TL_CKPT_INT64, "int64 values", 1, n, values);
}

TlStatus tl_checkpoint_read_bytes(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                  void *bytes)
{
  return tl_ckpt_read(r, group, name, TL_CKPT_BYTES, "bytes", 1, n, bytes);
}

TlStatus tl_checkpoint_read_double(const TlCheckpointReader *r, const char *group, const char *name, double *value)
{
  return tl_ckpt_read(r, group, name, TL_CKPT_DOUBLE, "double", 0, 1, value);
}

TlStatus tl_checkpoint_read_int64(const TlCheckpointReader *r, const char *group, const char *name, int64_t *value)
{
  return tl_ckpt_read(r, group, name, TL_CKPT_INT64, "int64", 0, 1, value);
}

/* "group/name" for messages. */
static const char *tl_ckpt_where(const char *group, const char *name, char *buf, size_t cap)
{
  if (group && group[0]) snprintf(buf, cap, "%s/%s", group[0] == '/' ? group + 1 : group, name);
  else snprintf(buf, cap, "%s", name);
  return buf;
}

TlStatus tl_checkpoint_check_finite(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                    const double *values)
{
  char where[TL_CKPT_PATH_MAX];
  for (size_t i = 0; i < n; ++i)
    if (!isfinite(values[i]))
      TL_ERROR(TL_ERR_FORMAT, "%s: %s[%zu] = %g is not a finite number", tl_checkpoint_reader_path(r),
               tl_ckpt_where(group, name, where, sizeof where), i, values[i]);
  return TL_OK;
}

TlStatus tl_checkpoint_check_positive(const TlCheckpointReader *r, const char *group, const char *name, size_t n,
                                      const double *values, int allow_zero)
{
  char where[TL_CKPT_PATH_MAX];
  for (size_t i = 0; i < n; ++i)
    if (!isfinite(values[i]) || !(allow_zero ? values[i] >= 0.0 : values[i] > 0.0))
      TL_ERROR(TL_ERR_FORMAT, "%s: %s[%zu] = %g must be finite and %s", tl_checkpoint_reader_path(r),
               tl_ckpt_where(group, name, where, sizeof where), i, values[i], allow_zero ? ">= 0" : "> 0");
  return TL_OK;
}

TlStatus tl_checkpoint_check_range(const TlCheckpointReader *r, const char *group, const char *name, double value,
                                   double lo, double hi)
{
  char where[TL_CKPT_PATH_MAX];
  if (!isfinite(value) || !(value >= lo && value <= hi))
    TL_ERROR(TL_ERR_FORMAT, "%s: %s = %g outside [%g, %g]", tl_checkpoint_reader_path(r),
             tl_ckpt_where(group, name, where, sizeof where), value, lo, hi);
  return TL_OK;
}

TlStatus tl_checkpoint_check_count(const TlCheckpointReader *r, const char *group, const char *name, int64_t value,
                                   int64_t lo, int64_t hi)
{
  char where[TL_CKPT_PATH_MAX];
  if (value < lo || value > hi)
    TL_ERROR(TL_ERR_FORMAT, "%s: %s = %lld outside [%lld, %lld]", tl_checkpoint_reader_path(r),
             tl_ckpt_where(group, name, where, sizeof where), (long long)value, (long long)lo, (long long)hi);
  return TL_OK;
}

TlStatus tl_checkpoint_read_string(const TlCheckpointReader *r, const char *group, const char *name, char **value)
{
  char path[TL_CKPT_PATH_MAX];
  TL_CHECK(tl_ckpt_path(r->file.path, group, name, path));
  if (r->mem) {
    const TlCkptEntry *e = tl_ckpt_mem_find(r, path);
    if (!e || e->kind != TL_CKPT_STRING)
      TL_ERROR(TL_ERR_NOT_FOUND, "checkpoint '%s' has no string '%s'", r->file.path, path);
    return tl_strdup((const char *)e->data, value);
  }
  if (!tl_h5_exists(&r->file, path))
    TL_ERROR(TL_ERR_NOT_FOUND, "checkpoint '%s' has no string '%s'", r->file.path, path);
  TL_CHECK(tl_h5_read_string(&r->file, path, value));
  return TL_OK;
}

/* ---------------------------------------------------------------- memory */
TlStatus tl_checkpoint_memory_create(TlCheckpointMemory **mem)
{
  TL_CHECK(TL_NEW(*mem));
  return TL_OK;
}

void tl_checkpoint_memory_destroy(TlCheckpointMemory **mem)
{
  if (!mem || !*mem) return;
  for (size_t k = 0; k < (*mem)->cap; ++k) {
    tl_free(&(*mem)->entries[k].path);
    tl_free(&(*mem)->entries[k].data);
  }
  tl_free(&(*mem)->entries);
  tl_free(mem);
}

size_t tl_checkpoint_memory_bytes(const TlCheckpointMemory *mem)
{
  size_t b = 0;
  for (size_t k = 0; k < mem->n; ++k) b += mem->entries[k].bytes;
  return b;
}

int tl_checkpoint_memory_empty(const TlCheckpointMemory *mem) { return !mem || mem->n == 0; }

TlStatus tl_checkpoint_writer_open_memory(TlCheckpointMemory *mem, TlCheckpointWriter **writer)
{
  if (!mem) TL_ERROR(TL_ERR_ARG, "tl_checkpoint_writer_open_memory: NULL memory checkpoint");
  TlCheckpointWriter *w;
  *writer = NULL;
  TL_CHECK(TL_NEW(w));
  w->file.id = H5I_INVALID_HID;
  w->file.path = tl_ckpt_memory_name;
  w->mem = mem;
  mem->n = 0;
  *writer = w;
  return TL_OK;
}

TlStatus tl_checkpoint_reader_open_memory(const TlCheckpointMemory *mem, TlCheckpointReader **reader)
{
  if (!mem) TL_ERROR(TL_ERR_ARG, "tl_checkpoint_reader_open_memory: NULL memory checkpoint");
  TlCheckpointReader *r;
  *reader = NULL;
  TL_CHECK(TL_NEW(r));
  r->file.id = H5I_INVALID_HID;
  r->file.path = tl_ckpt_memory_name;
  r->mem = mem;
  *reader = r;
  return TL_OK;
}

TlStatus tl_checkpoint_memory_save(TlCheckpointMemory *mem, const TlCheckpointOps *ops, const void *object)
{
  TlCheckpointWriter *w;
  TL_CHECK(tl_checkpoint_writer_open_memory(mem, &w));
  TlStatus s = ops->save(object, w, "");
  if (s != TL_OK) {
    tl_checkpoint_writer_abort(&w);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  TL_CHECK(tl_checkpoint_writer_commit(&w));
  return TL_OK;
}

TlStatus tl_checkpoint_memory_load(const TlCheckpointMemory *mem, const TlCheckpointOps *ops, void *object)
{
  if (!mem || mem->n == 0) TL_ERROR(TL_ERR_STATE, "load of %s from an empty checkpoint in memory", ops->header.name);
  TlCheckpointReader *r;
  TL_CHECK(tl_checkpoint_reader_open_memory(mem, &r));
  TlStatus s = ops->load(object, r, "");
  tl_checkpoint_reader_close(&r);
  if (s != TL_OK) return tl_error_trace(s, __FILE__, __LINE__);
  return TL_OK;
}

TlStatus tl_checkpoint_memory_copy(TlCheckpointMemory *dst, const TlCheckpointMemory *src)
{
  dst->n = 0;
  for (size_t k = 0; k < src->n; ++k) {
    const TlCkptEntry *e = &src->entries[k];
    TL_CHECK(tl_ckpt_mem_put(dst, e->path, e->kind, e->rank, e->n, e->bytes, e->data));
  }
  return TL_OK;
}

size_t tl_checkpoint_memory_count(const TlCheckpointMemory *mem) { return mem ? mem->n : 0; }

TlStatus tl_checkpoint_memory_entry(TlCheckpointMemory *mem, size_t k, TlCheckpointEntry *entry)
{
  if (!mem || k >= mem->n)
    TL_ERROR(TL_ERR_ARG, "%s: entry %zu of %zu", tl_ckpt_memory_name, k, mem ? mem->n : (size_t)0);
  static const char kinds[] = {'d', 'i', 'b', 's'};
  TlCkptEntry *e = &mem->entries[k];
  entry->path = e->path;
  entry->kind = kinds[e->kind];
  entry->n = e->n;
  entry->data = e->data;
  return TL_OK;
}

/* ---------------------------------------------------------------- sections */
typedef struct {
  char *name;
  const TlCheckpointOps *ops;
  void *object;
} TlCheckpointSection;

struct TlCheckpoint {
  TlCheckpointSection *sections;
  size_t n, capacity;
};

TlStatus tl_checkpoint_create(TlCheckpoint **checkpoint)
{
  TL_CHECK(TL_NEW(*checkpoint));
  return TL_OK;
}

void tl_checkpoint_destroy(TlCheckpoint **checkpoint)
{
  if (!checkpoint || !*checkpoint) return;
  for (size_t i = 0; i < (*checkpoint)->n; ++i) tl_free(&(*checkpoint)->sections[i].name);
  tl_free(&(*checkpoint)->sections);
  tl_free(checkpoint);
}

TlStatus tl_checkpoint_add(TlCheckpoint *cp, const char *name, const TlCheckpointOps *ops, void *object)
{
  if (!name || !name[0] || strchr(name, '/') || strlen(name) > 200)
    TL_ERROR(TL_ERR_ARG, "checkpoint section name '%s' must be 1 to 200 characters without '/'", name ? name : "(null)");
  if (!ops || !ops->save || !ops->load || !ops->header.name)
    TL_ERROR(TL_ERR_ARG, "checkpoint section '%s': ops table needs a name, save and load", name);
  for (size_t i = 0; i < cp->n; ++i)
    if (strcmp(cp->sections[i].name, name) == 0) TL_ERROR(TL_ERR_ARG, "checkpoint section '%s' added twice", name);
  TL_CHECK(tl_array_reserve(&cp->sections, &cp->capacity, cp->n + 1, sizeof *cp->sections));
  TlCheckpointSection *s = &cp->sections[cp->n];
  TL_CHECK(tl_calloc(&s->name, strlen(name) + 1, 1));
  memcpy(s->name, name, strlen(name));
  s->ops = ops;
  s->object = object;
  cp->n++;
  return TL_OK;
}

/* Fault injection for the kill-during-write self-tests: with
 * TALUS_CHECKPOINT_KILL_AT=n in the environment, the n-th checkpoint this
 * process writes is killed (SIGKILL) once its sections are written and
 * flushed to the temporary file, before the rename: what a power cut or an
 * OOM kill leaves. */
static void tl_ckpt_maybe_kill(const TlCheckpointWriter *w)
{
  static long saves;
  const char *at = getenv("TALUS_CHECKPOINT_KILL_AT");
  ++saves;
  if (!at || atol(at) != saves) return;
  H5Fflush(w->file.id, H5F_SCOPE_GLOBAL);
  fprintf(stderr, "TALUS_CHECKPOINT_KILL_AT=%s: killed while writing checkpoint %ld (%s)\n", at, saves, w->file.temp);
  fflush(NULL);
  raise(SIGKILL);
}

TlStatus tl_checkpoint_save(const TlCheckpoint *cp, const char *path, double time, int64_t step)
{
  TlCheckpointWriter *w;
  TL_CHECK(tl_checkpoint_writer_open(path, &w));
  TlStatus s;
  const char **names = NULL;
  TL_CHECK_GOTO(s, tl_calloc(&names, cp->n + 1, sizeof *names), fail);
  for (size_t i = 0; i < cp->n; ++i) names[i] = cp->sections[i].name;
  TL_CHECK_GOTO(s, tl_h5_attr_write_double(&w->file, "/", "time", time), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_int64(&w->file, "/", "step", step), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_strings(&w->file, "/", "sections", cp->n, names), fail);
  for (size_t i = 0; i < cp->n; ++i) {
    const TlCheckpointSection *sec = &cp->sections[i];
    char group[256];
    snprintf(group, sizeof group, "/%s", sec->name);
    TL_CHECK_GOTO(s, tl_h5_group(&w->file, group), fail);
    TL_CHECK_GOTO(s, tl_h5_attr_write_string(&w->file, group, "type", sec->ops->header.name), fail);
    s = sec->ops->save(sec->object, w, sec->name);
    if (s != TL_OK) {
      tl_error_trace(s, __FILE__, __LINE__);
      goto fail;
    }
  }
  tl_free(&names);
  tl_ckpt_maybe_kill(w);
  TL_CHECK(tl_checkpoint_writer_commit(&w));
  return TL_OK;
fail:
  tl_free(&names);
  tl_checkpoint_writer_abort(&w);
  return s;
}

TlStatus tl_checkpoint_load(TlCheckpoint *cp, const char *path, double *time, int64_t *step)
{
  TlCheckpointReader *r;
  TL_CHECK(tl_checkpoint_reader_open(path, &r));
  TlStatus s = TL_OK;
  char *type = NULL;
  double t = 0.0;
  int64_t k = 0;
  TL_CHECK_GOTO(s, tl_h5_attr_read_double(&r->file, "/", "time", &t), done);
  TL_CHECK_GOTO(s, tl_h5_attr_read_int64(&r->file, "/", "step", &k), done);
  /* all sections present with the right type before any state is touched */
  for (size_t i = 0; i < cp->n; ++i) {
    const TlCheckpointSection *sec = &cp->sections[i];
    char group[256];
    snprintf(group, sizeof group, "/%s", sec->name);
    if (!tl_h5_exists(&r->file, group)) {
      s = tl_error_set(TL_ERR_NOT_FOUND, __FILE__, __LINE__, "checkpoint '%s' has no section '%s'", path, sec->name);
      goto done;
    }
    TL_CHECK_GOTO(s, tl_h5_attr_read_string(&r->file, group, "type", &type), done);
    if (strcmp(type, sec->ops->header.name) != 0) {
      s = tl_error_set(TL_ERR_FORMAT, __FILE__, __LINE__, "checkpoint '%s': section '%s' holds type '%s', expected '%s'",
                       path, sec->name, type, sec->ops->header.name);
      goto done;
    }
    tl_free(&type);
  }
  for (size_t i = 0; i < cp->n; ++i) {
    const TlCheckpointSection *sec = &cp->sections[i];
    s = sec->ops->load(sec->object, r, sec->name);
    if (s != TL_OK) {
      tl_error_trace(s, __FILE__, __LINE__);
      goto done;
    }
  }
  if (time) *time = t;
  if (step) *step = k;
done:
  tl_free(&type);
  tl_checkpoint_reader_close(&r);
  return s;
}
