#include "tl_particle_snapshot.h"

#include <stdio.h>
#include <string.h>

#include "tl_atomic_file.h"
#include "tl_hdf5_util.h"
#include "tl_memory.h"
#include "tl_provenance.h"

_Static_assert(sizeof(TlVec3) == 3 * sizeof(double), "TlVec3 must be three packed doubles");

struct TlParticleWriter {
  TlSeriesOutput out; /* folder, name, .xmf series, step count, last file, XML buffer */
  int csv;            /* also <name>_<k>.csv, one row per particle */
  int *vertices; /* 0..n-1, the vertex cells; grown, never shrunk */
  size_t vertices_capacity;
};

void tl_particle_writer_destroy(TlParticleWriter **writer)
{
  if (!writer || !*writer) return;
  TlParticleWriter *w = *writer;
  tl_series_output_close(&w->out);
  tl_free(&w->vertices);
  tl_free(writer);
}

TlStatus tl_particle_writer_create(const char *dir, const char *name, TlParticleWriter **writer)
{
  *writer = NULL;
  TlParticleWriter *w;
  TL_CHECK(TL_NEW(w));
  TlStatus s;
  TL_CHECK_GOTO(s, tl_series_output_open(&w->out, dir, name, "particle"), fail);
  *writer = w;
  return TL_OK;
fail:
  tl_particle_writer_destroy(&w);
  return s;
}

size_t tl_particle_writer_count(const TlParticleWriter *writer) { return writer->out.count; }
void tl_particle_writer_set_csv(TlParticleWriter *writer, int on) { writer->csv = on != 0; }

typedef struct {
  const TlParticleView *v;
  double time;
  int64_t step;
} TlPwCsv;

/* One row per particle: id, species, position, radius, velocity (the
 * columns the view has), after the provenance lines. */
static TlStatus tl_pw_write_csv(FILE *f, void *context)
{
  const TlPwCsv *c = context;
  const TlParticleView *v = c->v;
  TL_CHECK(tl_provenance_write_text(f, "# "));
  fprintf(f, "# time: %.17g s, step %lld\n", c->time, (long long)c->step);
  if (v->id) fputs("id,", f);
  if (v->species) fputs("species,", f);
  fputs("x [m],y [m],z [m],radius [m]", f);
  if (v->velocity) fputs(",vx [m/s],vy [m/s],vz [m/s]", f);
  fputc('\n', f);
  for (size_t i = 0; i < v->n; ++i) {
    if (v->id) fprintf(f, "%lld,", (long long)v->id[i]);
    if (v->species) fprintf(f, "%d,", v->species[i]);
    fprintf(f, "%.17g,%.17g,%.17g,%.17g", v->position[i].x, v->position[i].y, v->position[i].z, v->radius[i]);
    if (v->velocity) fprintf(f, ",%.17g,%.17g,%.17g", v->velocity[i].x, v->velocity[i].y, v->velocity[i].z);
    if (fputc('\n', f) == EOF) TL_ERROR(TL_ERR_IO, "write error at particle %zu", i);
  }
  return TL_OK;
}
const char *tl_particle_writer_last_path(const TlParticleWriter *writer) { return writer->out.last_path; }

static TlStatus tl_pw_vec3(TlH5File *f, const char *path, size_t n, const TlVec3 *v)
{
  hsize_t dims[2] = {n, 3};
  TL_CHECK(tl_h5_write(f, path, H5T_NATIVE_DOUBLE, 2, dims, v));
  return TL_OK;
}

static TlStatus tl_pw_write_h5(const char *path, int64_t step, double time, const TlParticleView *v, const int *vertices)
{
  TlH5File f;
  TL_CHECK(tl_h5_create(path, &f));
  TlStatus s;
  hsize_t n = v->n;
  const char **names = NULL;
  TL_CHECK_GOTO(s, tl_h5_attr_write_string(&f, "/", "format", "talus-particles"), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_int64(&f, "/", "format_version", TL_PARTICLE_FORMAT_VERSION), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_double(&f, "/", "time", time), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_int64(&f, "/", "step", step), fail);
  TL_CHECK_GOTO(s, tl_pw_vec3(&f, "/particles/position", v->n, v->position), fail);
  TL_CHECK_GOTO(s, tl_h5_write(&f, "/particles/radius", H5T_NATIVE_DOUBLE, 1, &n, v->radius), fail);
  TL_CHECK_GOTO(s, tl_h5_write(&f, "/particles/vertices", H5T_NATIVE_INT, 1, &n, vertices), fail);
  if (v->velocity) TL_CHECK_GOTO(s, tl_pw_vec3(&f, "/particles/velocity", v->n, v->velocity), fail);
  if (v->angular_velocity) TL_CHECK_GOTO(s, tl_pw_vec3(&f, "/particles/angular_velocity", v->n, v->angular_velocity), fail);
  if (v->force) TL_CHECK_GOTO(s, tl_pw_vec3(&f, "/particles/force", v->n, v->force), fail);
  if (v->torque) TL_CHECK_GOTO(s, tl_pw_vec3(&f, "/particles/torque", v->n, v->torque), fail);
  if (v->species) TL_CHECK_GOTO(s, tl_h5_write(&f, "/particles/species", H5T_NATIVE_INT, 1, &n, v->species), fail);
  if (v->id) TL_CHECK_GOTO(s, tl_h5_write(&f, "/particles/id", H5T_NATIVE_INT64, 1, &n, v->id), fail);
  if (v->n_fields > 0) {
    TL_CHECK_GOTO(s, tl_calloc(&names, v->n_fields, sizeof *names), fail);
    for (size_t i = 0; i < v->n_fields; ++i) {
      const TlField *fd = &v->fields[i];
      char dset[512];
      snprintf(dset, sizeof dset, "/particles/fields/%s", fd->name);
      hsize_t dims[2] = {v->n, (hsize_t)fd->components};
      TL_CHECK_GOTO(s, tl_h5_write(&f, dset, H5T_NATIVE_DOUBLE, fd->components == 1 ? 1 : 2, dims, fd->data), fail);
      names[i] = fd->name;
    }
    TL_CHECK_GOTO(s, tl_h5_attr_write_strings(&f, "/particles/fields", "names", v->n_fields, names), fail);
    tl_free(&names);
  }
  TL_CHECK(tl_h5_commit(&f));
  return TL_OK;
fail:
  tl_free(&names);
  tl_h5_abort(&f);
  return s;
}

static TlStatus tl_pw_grid(TlText *x, const char *file, size_t count, double time, const TlParticleView *v)
{
  const char *in = "        ";
  tl_text_clear(x);
  TL_CHECK(tl_text_printf(x, "      <Grid Name=\"step_%06zu\" GridType=\"Uniform\">\n", count));
  TL_CHECK(tl_text_printf(x, "        <Time Value=\"%.17g\"/>\n", time));
  /* explicit vertex list: without it some XDMF readers make points but no cells */
  TL_CHECK(tl_text_printf(x, "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"%zu\" NodesPerElement=\"1\">\n", v->n));
  TL_CHECK(tl_xdmf_data_item(x, "          ", v->n, 0, "Int", (int)sizeof(int), file, "/particles/vertices"));
  TL_CHECK(tl_text_printf(x, "        </Topology>\n"));
  TL_CHECK(tl_text_printf(x, "        <Geometry GeometryType=\"XYZ\">\n"));
  TL_CHECK(tl_xdmf_data_item(x, "          ", v->n, 3, "Float", 8, file, "/particles/position"));
  TL_CHECK(tl_text_printf(x, "        </Geometry>\n"));
  TL_CHECK(tl_xdmf_attribute(x, in, "radius", 1, "Node", v->n, file, "/particles/radius"));
  if (v->velocity) TL_CHECK(tl_xdmf_attribute(x, in, "velocity", 3, "Node", v->n, file, "/particles/velocity"));
  if (v->angular_velocity)
    TL_CHECK(tl_xdmf_attribute(x, in, "angular_velocity", 3, "Node", v->n, file, "/particles/angular_velocity"));
  if (v->force) TL_CHECK(tl_xdmf_attribute(x, in, "force", 3, "Node", v->n, file, "/particles/force"));
  if (v->torque) TL_CHECK(tl_xdmf_attribute(x, in, "torque", 3, "Node", v->n, file, "/particles/torque"));
  if (v->species) {
    TL_CHECK(tl_text_printf(x, "        <Attribute Name=\"species\" AttributeType=\"Scalar\" Center=\"Node\">\n"));
    TL_CHECK(tl_xdmf_data_item(x, "          ", v->n, 0, "Int", (int)sizeof(int), file, "/particles/species"));
    TL_CHECK(tl_text_printf(x, "        </Attribute>\n"));
  }
  if (v->id) {
    TL_CHECK(tl_text_printf(x, "        <Attribute Name=\"id\" AttributeType=\"Scalar\" Center=\"Node\">\n"));
    TL_CHECK(tl_xdmf_data_item(x, "          ", v->n, 0, "Int", 8, file, "/particles/id"));
    TL_CHECK(tl_text_printf(x, "        </Attribute>\n"));
  }
  for (size_t i = 0; i < v->n_fields; ++i) {
    char dset[512];
    snprintf(dset, sizeof dset, "/particles/fields/%s", v->fields[i].name);
    TL_CHECK(tl_xdmf_attribute(x, in, v->fields[i].name, v->fields[i].components, "Node", v->n, file, dset));
  }
  TL_CHECK(tl_text_printf(x, "      </Grid>\n"));
  return TL_OK;
}

static TlStatus tl_pw_check(const TlParticleWriter *w, const TlParticleView *v)
{
  if (!v) TL_ERROR(TL_ERR_ARG, "particle output '%s': no view given", w->out.name);
  if (v->n > (size_t)0x7fffffff)
    TL_ERROR(TL_ERR_ARG, "particle output '%s': n = %zu particles exceeds 2^31-1 per file", w->out.name, v->n);
  if (v->n > 0 && (!v->position || !v->radius))
    TL_ERROR(TL_ERR_ARG, "particle output '%s': position and radius are required (got %s, %s)", w->out.name,
             v->position ? "position" : "no position", v->radius ? "radius" : "no radius");
  if (v->n_fields > 0 && !v->fields)
    TL_ERROR(TL_ERR_ARG, "particle output '%s': %zu fields announced, none given", w->out.name, v->n_fields);
  static const char *const reserved[] = {"radius", "velocity", "angular_velocity", "force", "torque", "species", "id"};
  for (size_t i = 0; i < v->n_fields; ++i) {
    TL_CHECK(tl_field_check(&v->fields[i], w->out.name));
    if (v->n > 0 && !v->fields[i].data)
      TL_ERROR(TL_ERR_ARG, "particle output '%s': field '%s' has no data", w->out.name, v->fields[i].name);
    for (size_t k = 0; k < sizeof reserved / sizeof *reserved; ++k)
      if (strcmp(v->fields[i].name, reserved[k]) == 0)
        TL_ERROR(TL_ERR_ARG, "particle output '%s': extra field name '%s' is reserved", w->out.name, reserved[k]);
    for (size_t k = 0; k < i; ++k)
      if (strcmp(v->fields[i].name, v->fields[k].name) == 0)
        TL_ERROR(TL_ERR_ARG, "particle output '%s': field '%s' given twice", w->out.name, v->fields[i].name);
  }
  return TL_OK;
}

TlStatus tl_particle_writer_write(TlParticleWriter *writer, int64_t step, double time, const TlParticleView *view)
{
  TL_CHECK(tl_pw_check(writer, view));
  char file[1100];
  snprintf(file, sizeof file, "%s_%06zu.h5", writer->out.name, writer->out.count);
  if (view->n > writer->vertices_capacity) {
    TL_CHECK(tl_realloc(&writer->vertices, view->n, sizeof *writer->vertices));
    for (size_t i = writer->vertices_capacity; i < view->n; ++i) writer->vertices[i] = (int)i;
    writer->vertices_capacity = view->n;
  }
  char *path;
  TL_CHECK(tl_path_join(writer->out.dir, file, &path));
  TlStatus s = tl_pw_write_h5(path, step, time, view, writer->vertices);
  if (s == TL_OK) snprintf(writer->out.last_path, sizeof writer->out.last_path, "%s", path);
  tl_free(&path);
  TL_CHECK(s);
  if (writer->csv) {
    char csv[1100];
    snprintf(csv, sizeof csv, "%s_%06zu.csv", writer->out.name, writer->out.count);
    TL_CHECK(tl_path_join(writer->out.dir, csv, &path));
    TlPwCsv ctx = {view, time, step};
    s = tl_atomic_write(path, tl_pw_write_csv, &ctx);
    tl_free(&path);
    TL_CHECK(s);
  }
  TL_CHECK(tl_pw_grid(&writer->out.grid, file, writer->out.count, time, view));
  TL_CHECK(tl_xdmf_series_add(writer->out.series, writer->out.grid.text));
  writer->out.count++;
  return TL_OK;
}

void tl_particle_view_of(const TlParticles *P, TlParticleView *v)
{
  _Static_assert(sizeof(int) == sizeof(int32_t), "species are int32 in the store, int in the view");
  memset(v, 0, sizeof *v);
  v->n = P->n;
  v->position = P->x;
  v->radius = P->radius;
  v->velocity = P->v;
  v->angular_velocity = P->w;
  v->force = P->f;
  v->torque = P->torque;
  v->species = (const int *)P->species;
  v->id = P->id;
}

/* ---------------------------------------------------------------- checkpoint */
static TlStatus tl_pw_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlParticleWriter *pw = object;
  char sub[512];
  snprintf(sub, sizeof sub, "%s/series", group);
  TL_CHECK(tl_checkpoint_write_int64(w, group, "count", (int64_t)pw->out.count));
  TL_CHECK(tl_xdmf_series_checkpoint_ops.save(pw->out.series, w, sub));
  return TL_OK;
}

static TlStatus tl_pw_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlParticleWriter *pw = object;
  char sub[512];
  snprintf(sub, sizeof sub, "%s/series", group);
  int64_t count;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "count", &count));
  if (count < 0) TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': %s/count = %lld", tl_checkpoint_reader_path(r), group, (long long)count);
  TL_CHECK(tl_xdmf_series_checkpoint_ops.load(pw->out.series, r, sub));
  pw->out.count = (size_t)count;
  return TL_OK;
}

const TlCheckpointOps tl_particle_writer_checkpoint_ops = {
    {"checkpoint", "particle_writer_v1", "snapshot counter and XDMF series of a particle writer"}, tl_pw_save, tl_pw_load};

/* ---------------------------------------------------------------- reading */
void tl_particle_snapshot_free(TlParticleSnapshot *p)
{
  tl_free(&p->position);
  tl_free(&p->radius);
  tl_free(&p->velocity);
  tl_free(&p->angular_velocity);
  tl_free(&p->force);
  tl_free(&p->torque);
  tl_free(&p->species);
  tl_free(&p->id);
  for (size_t i = 0; i < p->n_fields; ++i) {
    if (p->field_names) tl_free(&p->field_names[i]);
    if (p->field_data) tl_free(&p->field_data[i]);
  }
  tl_free(&p->field_names);
  tl_free(&p->field_data);
  tl_free(&p->field_components);
  memset(p, 0, sizeof *p);
}

static TlStatus tl_pr_vec3(const TlH5File *f, const char *path, size_t n, int required, TlVec3 **v)
{
  if (!required && !tl_h5_exists(f, path)) return TL_OK;
  TL_CHECK(tl_calloc(v, n ? n : 1, sizeof **v));
  hsize_t dims[2] = {n, 3};
  TL_CHECK(tl_h5_read(f, path, H5T_NATIVE_DOUBLE, 2, dims, *v));
  return TL_OK;
}

static TlStatus tl_pr_read(const TlH5File *f, TlParticleSnapshot *p)
{
  char *format = NULL;
  TL_CHECK(tl_h5_attr_read_string(f, "/", "format", &format));
  int ok = strcmp(format, "talus-particles") == 0;
  tl_free(&format);
  if (!ok) TL_ERROR(TL_ERR_FORMAT, "'%s' is not a particle snapshot (attribute format)", f->path);
  int64_t version;
  TL_CHECK(tl_h5_attr_read_int64(f, "/", "format_version", &version));
  if (version != TL_PARTICLE_FORMAT_VERSION)
    TL_ERROR(TL_ERR_FORMAT, "'%s' has particle format version %lld; this build reads %d", f->path, (long long)version,
             TL_PARTICLE_FORMAT_VERSION);
  TL_CHECK(tl_h5_attr_read_double(f, "/", "time", &p->time));
  TL_CHECK(tl_h5_attr_read_int64(f, "/", "step", &p->step));
  int rank;
  hsize_t dims[TL_H5_MAX_RANK];
  TL_CHECK(tl_h5_dims(f, "/particles/radius", &rank, dims));
  if (rank != 1) TL_ERROR(TL_ERR_FORMAT, "'%s': /particles/radius has rank %d, expected 1", f->path, rank);
  size_t n = p->n = (size_t)dims[0];
  hsize_t hn = n;
  TL_CHECK(tl_calloc(&p->radius, n ? n : 1, sizeof *p->radius));
  TL_CHECK(tl_h5_read(f, "/particles/radius", H5T_NATIVE_DOUBLE, 1, &hn, p->radius));
  TL_CHECK(tl_pr_vec3(f, "/particles/position", n, 1, &p->position));
  TL_CHECK(tl_pr_vec3(f, "/particles/velocity", n, 0, &p->velocity));
  TL_CHECK(tl_pr_vec3(f, "/particles/angular_velocity", n, 0, &p->angular_velocity));
  TL_CHECK(tl_pr_vec3(f, "/particles/force", n, 0, &p->force));
  TL_CHECK(tl_pr_vec3(f, "/particles/torque", n, 0, &p->torque));
  if (tl_h5_exists(f, "/particles/species")) {
    TL_CHECK(tl_calloc(&p->species, n ? n : 1, sizeof *p->species));
    TL_CHECK(tl_h5_read(f, "/particles/species", H5T_NATIVE_INT, 1, &hn, p->species));
  }
  if (tl_h5_exists(f, "/particles/id")) {
    TL_CHECK(tl_calloc(&p->id, n ? n : 1, sizeof *p->id));
    TL_CHECK(tl_h5_read(f, "/particles/id", H5T_NATIVE_INT64, 1, &hn, p->id));
  }
  if (tl_h5_exists(f, "/particles/fields")) {
    size_t k;
    TL_CHECK(tl_h5_attr_read_strings(f, "/particles/fields", "names", &k, &p->field_names));
    p->n_fields = k;
    TL_CHECK(tl_calloc(&p->field_components, k, sizeof *p->field_components));
    TL_CHECK(tl_calloc(&p->field_data, k, sizeof *p->field_data));
    for (size_t i = 0; i < k; ++i) {
      char dset[512];
      snprintf(dset, sizeof dset, "/particles/fields/%s", p->field_names[i]);
      TL_CHECK(tl_h5_dims(f, dset, &rank, dims));
      if (rank < 1 || rank > 2 || dims[0] != n)
        TL_ERROR(TL_ERR_FORMAT, "'%s': %s has rank %d and %llu rows, expected %zu rows", f->path, dset, rank,
                 (unsigned long long)dims[0], n);
      size_t c = rank == 2 ? (size_t)dims[1] : 1;
      p->field_components[i] = (int)c;
      TL_CHECK(tl_calloc(&p->field_data[i], n * c > 0 ? n * c : 1, sizeof(double)));
      TL_CHECK(tl_h5_read(f, dset, H5T_NATIVE_DOUBLE, rank, dims, p->field_data[i]));
    }
  }
  return TL_OK;
}

TlStatus tl_particle_snapshot_read(const char *path, TlParticleSnapshot *snapshot)
{
  memset(snapshot, 0, sizeof *snapshot);
  TlH5File f;
  TL_CHECK(tl_h5_open(path, &f));
  TlStatus s = tl_pr_read(&f, snapshot);
  tl_h5_close(&f);
  if (s != TL_OK) {
    tl_particle_snapshot_free(snapshot);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}
