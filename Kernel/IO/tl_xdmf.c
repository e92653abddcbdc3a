#include "tl_xdmf.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include <time.h>

#include "tl_atomic_file.h"
#include "tl_log.h"
#include "tl_memory.h"
#include "tl_series_sweep.h"

/* ---------------------------------------------------------------- text */
TlStatus tl_text_printf(TlText *t, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(NULL, 0, fmt, ap);
  va_end(ap);
  if (n < 0) TL_ERROR(TL_ERR_ARG, "cannot format '%s'", fmt);
  TL_CHECK(tl_array_reserve(&t->text, &t->capacity, t->length + (size_t)n + 1, 1));
  va_start(ap, fmt);
  vsnprintf(t->text + t->length, (size_t)n + 1, fmt, ap);
  va_end(ap);
  t->length += (size_t)n;
  return TL_OK;
}

void tl_text_clear(TlText *t)
{
  t->length = 0;
  if (t->text) t->text[0] = '\0';
}

void tl_text_free(TlText *t)
{
  tl_free(&t->text);
  t->length = t->capacity = 0;
}

/* ---------------------------------------------------------------- fields */
TlStatus tl_field_check(const TlField *field, const char *owner)
{
  const char *name = field->name;
  int ok = name && name[0];
  for (const char *c = name; ok && *c; ++c) ok = isalnum((unsigned char)*c) || *c == '_' || *c == '.' || *c == '-';
  if (!ok)
    TL_ERROR(TL_ERR_ARG, "%s: field name '%s' must be letters, digits, '_', '.', '-'", owner, name ? name : "(null)");
  if (field->components < 1 || field->components > 64)
    TL_ERROR(TL_ERR_ARG, "%s: field '%s' has %d components, expected 1 to 64", owner, name, field->components);
  return TL_OK;
}

const char *tl_xdmf_attribute_type(int components)
{
  switch (components) {
  case 1: return "Scalar";
  case 3: return "Vector";
  case 6: return "Tensor6";
  case 9: return "Tensor";
  default: return "Matrix";
  }
}

TlStatus tl_xdmf_data_item(TlText *xml, const char *indent, size_t n, size_t cols, const char *number_type,
                           int precision, const char *h5file, const char *dataset)
{
  if (cols > 0)
    TL_CHECK(tl_text_printf(xml, "%s<DataItem Dimensions=\"%zu %zu\" NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">%s:%s</DataItem>\n",
                            indent, n, cols, number_type, precision, h5file, dataset));
  else
    TL_CHECK(tl_text_printf(xml, "%s<DataItem Dimensions=\"%zu\" NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">%s:%s</DataItem>\n",
                            indent, n, number_type, precision, h5file, dataset));
  return TL_OK;
}

TlStatus tl_xdmf_attribute(TlText *xml, const char *indent, const char *name, int components, const char *center,
                           size_t n, const char *h5file, const char *dataset)
{
  char inner[64];
  snprintf(inner, sizeof inner, "%s  ", indent);
  TL_CHECK(tl_text_printf(xml, "%s<Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"%s\">\n", indent, name,
                          tl_xdmf_attribute_type(components), center));
  TL_CHECK(tl_xdmf_data_item(xml, inner, n, components == 1 ? 0 : (size_t)components, "Float", 8, h5file, dataset));
  TL_CHECK(tl_text_printf(xml, "%s</Attribute>\n", indent));
  return TL_OK;
}

/* ---------------------------------------------------------------- series */
struct TlXdmfSeries {
  char *path;
  TlText grids; /* every step's <Grid> element, in order */
  size_t steps;
  int dirty;                  /* steps added since the file was last written */
  double last_cost, next_due; /* seconds: last rewrite's duration, earliest next one */
  int swept;                  /* stale files of an earlier run removed (tl_series_sweep.h) */
};

static double tl_xdmf_now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

TlStatus tl_series_output_open(TlSeriesOutput *out, const char *dir, const char *name, const char *what)
{
  int ok = name && name[0];
  for (const char *c = name; ok && *c; ++c)
    ok = !(*c == '/' || *c == '"' || *c == '<' || *c == '>' || *c == '&' || *c == ':' || *c == ' ');
  if (!ok)
    TL_ERROR(TL_ERR_ARG, "%s output name '%s' must be non-empty without '/', ':', space, quotes or <>&", what,
             name ? name : "(null)");
  if (dir && dir[0]) TL_CHECK(tl_mkdir_p(dir));
  char xmf[1024];
  snprintf(xmf, sizeof xmf, "%s.xmf", name);
  TL_CHECK(tl_strdup(dir ? dir : "", &out->dir));
  TL_CHECK(tl_strdup(name, &out->name));
  TL_CHECK(tl_path_join(dir, xmf, &out->xmf_path));
  TL_CHECK(tl_xdmf_series_create(out->xmf_path, &out->series));
  return TL_OK;
}

void tl_series_output_close(TlSeriesOutput *out)
{
  tl_xdmf_series_destroy(&out->series);
  tl_text_free(&out->grid);
  tl_free(&out->dir);
  tl_free(&out->name);
  tl_free(&out->xmf_path);
}

TlStatus tl_xdmf_series_create(const char *path, TlXdmfSeries **series)
{
  TlXdmfSeries *s;
  *series = NULL;
  TL_CHECK(TL_NEW(s));
  size_t n = strlen(path);
  TlStatus st = tl_calloc(&s->path, n + 1, 1);
  if (st != TL_OK) {
    tl_free(&s);
    return tl_error_trace(st, __FILE__, __LINE__);
  }
  memcpy(s->path, path, n);
  *series = s;
  return TL_OK;
}

void tl_xdmf_series_destroy(TlXdmfSeries **series)
{
  if (!series || !*series) return;
  if ((*series)->dirty && tl_xdmf_series_flush(*series) != TL_OK)
    tl_warn("the XDMF series '%s' misses its last steps: %s", (*series)->path, tl_error_message());
  tl_text_free(&(*series)->grids);
  tl_free(&(*series)->path);
  tl_free(series);
}

static TlStatus tl_xdmf_series_write_stream(FILE *f, void *context)
{
  const TlXdmfSeries *s = context;
  fputs("<?xml version=\"1.0\" ?>\n"
        "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
        "<Xdmf Version=\"2.0\">\n"
        "  <Domain>\n"
        "    <Grid Name=\"series\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
        f);
  if (s->grids.length) fwrite(s->grids.text, 1, s->grids.length, f);
  if (fputs("    </Grid>\n  </Domain>\n</Xdmf>\n", f) == EOF) TL_ERROR(TL_ERR_IO, "write error");
  return TL_OK;
}

TlStatus tl_xdmf_series_flush(TlXdmfSeries *s)
{
  double start = tl_xdmf_now();
  TL_CHECK(tl_atomic_write(s->path, tl_xdmf_series_write_stream, s));
  double end = tl_xdmf_now();
  s->dirty = 0;
  s->last_cost = end - start;
  s->next_due = end + 20.0 * s->last_cost;
  return TL_OK;
}

TlStatus tl_xdmf_series_add(TlXdmfSeries *series, const char *grid)
{
  if (!series->swept) { /* the step being added is index steps: later files are an older run's */
    size_t removed = 0;
    TL_CHECK(tl_series_sweep_stale(series->path, series->steps + 1, series->steps == 0, &removed));
    series->swept = 1;
    if (removed)
      tl_info("removed %zu stale snapshot file%s of an earlier run beside %s", removed, removed > 1 ? "s" : "", series->path);
  }
  size_t before = series->grids.length;
  TL_CHECK(tl_text_printf(&series->grids, "%s", grid));
  series->steps++;
  series->dirty = 1;
  /* A file under 1 MB is rewritten at every step.  A longer series costs
   * O(steps) per rewrite, so the next rewrite waits until 20 times the last
   * one's duration has passed: at most ~5% of the wall time goes to it. */
  if (series->grids.length > ((size_t)1 << 20) && tl_xdmf_now() < series->next_due) return TL_OK;
  TlStatus s = tl_xdmf_series_flush(series);
  if (s != TL_OK) { /* the file keeps the previous steps; so does the list */
    series->grids.length = before;
    series->grids.text[before] = '\0';
    series->steps--;
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}

size_t tl_xdmf_series_steps(const TlXdmfSeries *series) { return series->steps; }

static TlStatus tl_xdmf_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlXdmfSeries *s = object;
  TL_CHECK(tl_checkpoint_write_int64(w, group, "steps", (int64_t)s->steps));
  TL_CHECK(tl_checkpoint_write_bytes(w, group, "grids", s->grids.length, s->grids.text));
  return TL_OK;
}

/* The folder part of path ("" when it has none), allocated. */
static TlStatus tl_xdmf_folder_of(const char *path, char **dir)
{
  const char *slash = strrchr(path, '/');
  size_t n = slash ? (size_t)(slash - path) + (slash == path) : 0;
  TL_CHECK(tl_calloc(dir, n + 1, 1));
  memcpy(*dir, path, n);
  return TL_OK;
}

static TlStatus tl_xdmf_copy_stream(FILE *out, void *context)
{
  FILE *in = context;
  char buf[1 << 16];
  for (size_t n; (n = fread(buf, 1, sizeof buf, in)) > 0;)
    if (fwrite(buf, 1, n, out) != n) TL_ERROR(TL_ERR_IO, "write error");
  if (ferror(in)) TL_ERROR(TL_ERR_IO, "read error");
  return TL_OK;
}

/* A restart may write its series into another folder than the run it
 * continues: every snapshot file the restored steps reference must then be
 * there too, or the series points at files that are not.  Each one missing
 * from the series' folder is copied from the folder of the checkpoint file
 * (where the run that wrote it kept its output); a file in neither is
 * refused by name. */
static TlStatus tl_xdmf_complete(const TlXdmfSeries *s, const TlCheckpointReader *r, const char *group)
{
  const char *key = "Format=\"HDF\">";
  char *dir = NULL, *from = NULL, *target = NULL, *source = NULL;
  TlStatus st = tl_xdmf_folder_of(s->path, &dir);
  if (st == TL_OK) st = tl_xdmf_folder_of(tl_checkpoint_reader_path(r), &from);
  for (const char *p = s->grids.text ? strstr(s->grids.text, key) : NULL; st == TL_OK && p; p = strstr(p, key)) {
    p += strlen(key);
    size_t n = strcspn(p, ":<\n");
    if (p[n] != ':' || n == 0 || n >= 1024) continue;
    char name[1024];
    memcpy(name, p, n);
    name[n] = '\0';
    if (strchr(name, '/')) continue; /* the writers reference files in their own folder */
    tl_free(&target);
    tl_free(&source);
    st = tl_path_join(dir, name, &target);
    if (st == TL_OK) st = tl_path_join(from, name, &source);
    if (st != TL_OK) break;
    struct stat ts, ss;
    const int have_target = stat(target, &ts) == 0 && S_ISREG(ts.st_mode);
    const int have_source = stat(source, &ss) == 0 && S_ISREG(ss.st_mode);
    /* the same file (a restart in its own folder), or only the series'
     * folder has it (the checkpoint was moved): nothing to copy.  A file of
     * that name from another run is replaced by the checkpoint's. */
    if (have_target && (!have_source || (ts.st_dev == ss.st_dev && ts.st_ino == ss.st_ino))) continue;
    FILE *in = have_source ? fopen(source, "rb") : NULL;
    if (!in) {
      st = tl_error_set(TL_ERR_IO, __FILE__, __LINE__,
                        "restart from '%s': series '%s' (%s) lists snapshot '%s', which is neither in the series' "
                        "folder '%s' nor next to the checkpoint in '%s': restart in the folder of the run that "
                        "wrote it, or copy its snapshot files along", tl_checkpoint_reader_path(r), group, s->path,
                        name, dir[0] ? dir : ".", from[0] ? from : ".");
      break;
    }
    st = tl_atomic_write(target, tl_xdmf_copy_stream, in);
    fclose(in);
  }
  tl_free(&dir);
  tl_free(&from);
  tl_free(&target);
  tl_free(&source);
  return st == TL_OK ? TL_OK : tl_error_trace(st, __FILE__, __LINE__);
}

static TlStatus tl_xdmf_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlXdmfSeries *s = object;
  int64_t steps;
  size_t n;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "steps", &steps));
  TL_CHECK(tl_checkpoint_length(r, group, "grids", &n));
  if (steps < 0) TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': series '%s' has %lld steps", tl_checkpoint_reader_path(r), group, (long long)steps);
  TL_CHECK(tl_array_reserve(&s->grids.text, &s->grids.capacity, n + 1, 1));
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "grids", n, s->grids.text));
  s->grids.text[n] = '\0';
  s->grids.length = n;
  s->steps = (size_t)steps;
  TL_CHECK(tl_xdmf_complete(s, r, group));
  TL_CHECK(tl_xdmf_series_flush(s));
  return TL_OK;
}

const TlCheckpointOps tl_xdmf_series_checkpoint_ops = {
    {"checkpoint", "xdmf_series_v1", "the steps listed in an XDMF time series"}, tl_xdmf_save, tl_xdmf_load};
