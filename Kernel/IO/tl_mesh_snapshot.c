#include "tl_mesh_snapshot.h"

#include <stdio.h>
#include <string.h>

#include "tl_atomic_file.h"
#include "tl_hdf5_util.h"
#include "tl_memory.h"

/* ---------------------------------------------------------------- cell types */
static const struct {
  const char *name, *xdmf;
  int vtk, nodes;
} tl_cell_types[TL_CELL_TYPE_COUNT] = {
    [TL_CELL_TRI3] = {"tri3", "Triangle", 5, 3},
    [TL_CELL_TRI6] = {"tri6", "Triangle_6", 22, 6},
    [TL_CELL_QUAD4] = {"quad4", "Quadrilateral", 9, 4},
    [TL_CELL_QUAD8] = {"quad8", "Quadrilateral_8", 23, 8},
    [TL_CELL_QUAD9] = {"quad9", "Quadrilateral_9", 28, 9},
    [TL_CELL_TET4] = {"tet4", "Tetrahedron", 10, 4},
    [TL_CELL_TET10] = {"tet10", "Tetrahedron_10", 24, 10},
    [TL_CELL_HEX8] = {"hex8", "Hexahedron", 12, 8},
    [TL_CELL_HEX20] = {"hex20", "Hexahedron_20", 25, 20},
    [TL_CELL_HEX27] = {"hex27", "Hexahedron_27", 29, 27},
    [TL_CELL_WEDGE6] = {"wedge6", "Wedge", 13, 6},
    [TL_CELL_WEDGE15] = {"wedge15", "Wedge_15", 26, 15},
    [TL_CELL_WEDGE18] = {"wedge18", "Wedge_18", 32, 18},
    [TL_CELL_PYRAMID5] = {"pyramid5", "Pyramid", 14, 5},
    [TL_CELL_PYRAMID13] = {"pyramid13", "Pyramid_13", 27, 13},
};

static int tl_cell_type_valid(TlCellType t) { return (int)t >= 0 && t < TL_CELL_TYPE_COUNT; }
const char *tl_cell_type_name(TlCellType t) { return tl_cell_type_valid(t) ? tl_cell_types[t].name : "?"; }
const char *tl_cell_type_xdmf(TlCellType t) { return tl_cell_type_valid(t) ? tl_cell_types[t].xdmf : "?"; }
int tl_cell_type_vtk(TlCellType t) { return tl_cell_type_valid(t) ? tl_cell_types[t].vtk : 0; }
int tl_cell_type_nodes(TlCellType t) { return tl_cell_type_valid(t) ? tl_cell_types[t].nodes : 0; }

TlStatus tl_cell_type_from_name(const char *name, TlCellType *type)
{
  for (int t = 0; t < TL_CELL_TYPE_COUNT; ++t)
    if (name && strcmp(name, tl_cell_types[t].name) == 0) {
      *type = (TlCellType)t;
      return TL_OK;
    }
  char known[256] = "";
  for (int t = 0; t < TL_CELL_TYPE_COUNT; ++t)
    snprintf(known + strlen(known), sizeof known - strlen(known), " %s", tl_cell_types[t].name);
  TL_ERROR(TL_ERR_NOT_FOUND, "unknown cell type '%s'; known:%s", name ? name : "(null)", known);
}

/* ---------------------------------------------------------------- writer */
struct TlMeshWriter {
  TlSeriesOutput out; /* folder, name, .xmf series, step count, last file, XML buffer */
  char mesh_path[4096], mesh_file[1100];
  size_t mesh_count;
  uint64_t mesh_hash;
  int have_mesh;
};

void tl_mesh_writer_destroy(TlMeshWriter **writer)
{
  if (!writer || !*writer) return;
  TlMeshWriter *w = *writer;
  tl_series_output_close(&w->out);
  tl_free(writer);
}

TlStatus tl_mesh_writer_create(const char *dir, const char *name, TlMeshWriter **writer)
{
  *writer = NULL;
  TlMeshWriter *w;
  TL_CHECK(TL_NEW(w));
  TlStatus s;
  TL_CHECK_GOTO(s, tl_series_output_open(&w->out, dir, name, "mesh"), fail);
  *writer = w;
  return TL_OK;
fail:
  tl_mesh_writer_destroy(&w);
  return s;
}

size_t tl_mesh_writer_count(const TlMeshWriter *w) { return w->out.count; }
const char *tl_mesh_writer_last_path(const TlMeshWriter *w) { return w->out.last_path; }
const char *tl_mesh_writer_mesh_path(const TlMeshWriter *w) { return w->mesh_path; }

static uint64_t tl_fnv1a(uint64_t h, const void *data, size_t n)
{
  const unsigned char *p = data;
  for (size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

static uint64_t tl_mesh_hash(const TlMeshView *v)
{
  uint64_t h = 0xcbf29ce484222325ULL;
  h = tl_fnv1a(h, &v->n_nodes, sizeof v->n_nodes);
  h = tl_fnv1a(h, v->reference, v->n_nodes * sizeof *v->reference);
  for (size_t b = 0; b < v->n_blocks; ++b) {
    const TlMeshBlock *bl = &v->blocks[b];
    h = tl_fnv1a(h, bl->name, strlen(bl->name) + 1);
    h = tl_fnv1a(h, &bl->type, sizeof bl->type);
    h = tl_fnv1a(h, &bl->n_cells, sizeof bl->n_cells);
    h = tl_fnv1a(h, bl->connectivity, bl->n_cells * (size_t)tl_cell_type_nodes(bl->type) * sizeof(int));
  }
  return h;
}

static TlStatus tl_fields_check(const char *owner, size_t n_fields, const TlField *fields, size_t rows)
{
  if (n_fields > 0 && !fields) TL_ERROR(TL_ERR_ARG, "%s: %zu fields announced, none given", owner, n_fields);
  for (size_t i = 0; i < n_fields; ++i) {
    TL_CHECK(tl_field_check(&fields[i], owner));
    if (rows > 0 && !fields[i].data) TL_ERROR(TL_ERR_ARG, "%s: field '%s' has no data", owner, fields[i].name);
    if (strcmp(fields[i].name, "displacement") == 0)
      TL_ERROR(TL_ERR_ARG, "%s: field name 'displacement' is reserved", owner);
    for (size_t k = 0; k < i; ++k)
      if (strcmp(fields[i].name, fields[k].name) == 0)
        TL_ERROR(TL_ERR_ARG, "%s: field '%s' given twice", owner, fields[i].name);
  }
  return TL_OK;
}

static TlStatus tl_mw_check(const TlMeshWriter *w, const TlMeshView *v)
{
  if (!v) TL_ERROR(TL_ERR_ARG, "mesh output '%s': no view given", w->out.name);
  if (v->n_nodes > 0 && !v->reference)
    TL_ERROR(TL_ERR_ARG, "mesh output '%s': reference coordinates are required", w->out.name);
  if (v->n_nodes > (size_t)0x7fffffff)
    TL_ERROR(TL_ERR_ARG, "mesh output '%s': %zu nodes exceed the int32 connectivity limit 2^31-1", w->out.name, v->n_nodes);
  if (v->n_blocks == 0 || !v->blocks) TL_ERROR(TL_ERR_ARG, "mesh output '%s': no element block given", w->out.name);
  char owner[600];
  snprintf(owner, sizeof owner, "mesh output '%s' nodes", w->out.name);
  TL_CHECK(tl_fields_check(owner, v->n_node_fields, v->node_fields, v->n_nodes));
  for (size_t b = 0; b < v->n_blocks; ++b) {
    const TlMeshBlock *bl = &v->blocks[b];
    TlField as_name = {bl->name, 1, NULL};
    snprintf(owner, sizeof owner, "mesh output '%s' block %zu", w->out.name, b);
    TL_CHECK(tl_field_check(&as_name, owner));
    for (size_t k = 0; k < b; ++k)
      if (strcmp(bl->name, v->blocks[k].name) == 0)
        TL_ERROR(TL_ERR_ARG, "mesh output '%s': block name '%s' used twice", w->out.name, bl->name);
    if (!tl_cell_type_valid(bl->type))
      TL_ERROR(TL_ERR_ARG, "mesh output '%s' block '%s': cell type %d outside [0, %d)", w->out.name, bl->name, (int)bl->type,
               TL_CELL_TYPE_COUNT);
    if (bl->n_cells > 0 && !bl->connectivity)
      TL_ERROR(TL_ERR_ARG, "mesh output '%s' block '%s': no connectivity", w->out.name, bl->name);
    size_t m = bl->n_cells * (size_t)tl_cell_type_nodes(bl->type);
    for (size_t i = 0; i < m; ++i)
      if (bl->connectivity[i] < 0 || (size_t)bl->connectivity[i] >= v->n_nodes)
        TL_ERROR(TL_ERR_ARG, "mesh output '%s' block '%s': cell %zu node %zu is %d, outside [0, %zu)", w->out.name, bl->name,
                 i / (size_t)tl_cell_type_nodes(bl->type), i % (size_t)tl_cell_type_nodes(bl->type), bl->connectivity[i],
                 v->n_nodes);
    snprintf(owner, sizeof owner, "mesh output '%s' block '%s'", w->out.name, bl->name);
    TL_CHECK(tl_fields_check(owner, bl->n_fields, bl->fields, bl->n_cells));
  }
  return TL_OK;
}

static TlStatus tl_write_fields(TlH5File *f, const char *group, size_t rows, size_t n_fields, const TlField *fields)
{
  if (n_fields == 0) return TL_OK;
  const char **names = NULL;
  TL_CHECK(tl_calloc(&names, n_fields, sizeof *names));
  TlStatus s = TL_OK;
  for (size_t i = 0; i < n_fields; ++i) {
    char dset[1024];
    snprintf(dset, sizeof dset, "%s/%s", group, fields[i].name);
    hsize_t dims[2] = {rows, (hsize_t)fields[i].components};
    TL_CHECK_GOTO(s, tl_h5_write(f, dset, H5T_NATIVE_DOUBLE, fields[i].components == 1 ? 1 : 2, dims, fields[i].data),
                  done);
    names[i] = fields[i].name;
  }
  TL_CHECK_GOTO(s, tl_h5_attr_write_strings(f, group, "names", n_fields, names), done);
done:
  tl_free(&names);
  return s;
}

static TlStatus tl_mw_write_mesh(const char *path, const TlMeshView *v)
{
  TlH5File f;
  TL_CHECK(tl_h5_create(path, &f));
  TlStatus s;
  hsize_t dims[2] = {v->n_nodes, 3};
  const char **names = NULL;
  TL_CHECK_GOTO(s, tl_h5_attr_write_string(&f, "/", "format", "talus-mesh"), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_int64(&f, "/", "format_version", TL_MESH_FORMAT_VERSION), fail);
  TL_CHECK_GOTO(s, tl_h5_write(&f, "/mesh/reference_coordinates", H5T_NATIVE_DOUBLE, 2, dims, v->reference), fail);
  TL_CHECK_GOTO(s, tl_calloc(&names, v->n_blocks, sizeof *names), fail);
  for (size_t b = 0; b < v->n_blocks; ++b) {
    const TlMeshBlock *bl = &v->blocks[b];
    char group[512], dset[600];
    snprintf(group, sizeof group, "/mesh/blocks/%s", bl->name);
    snprintf(dset, sizeof dset, "%s/connectivity", group);
    hsize_t cdims[2] = {bl->n_cells, (hsize_t)tl_cell_type_nodes(bl->type)};
    TL_CHECK_GOTO(s, tl_h5_write(&f, dset, H5T_NATIVE_INT, 2, cdims, bl->connectivity), fail);
    TL_CHECK_GOTO(s, tl_h5_attr_write_string(&f, group, "cell_type", tl_cell_type_name(bl->type)), fail);
    TL_CHECK_GOTO(s, tl_h5_attr_write_string(&f, group, "xdmf_topology", tl_cell_type_xdmf(bl->type)), fail);
    names[b] = bl->name;
  }
  TL_CHECK_GOTO(s, tl_h5_attr_write_strings(&f, "/mesh/blocks", "names", v->n_blocks, names), fail);
  tl_free(&names);
  TL_CHECK(tl_h5_commit(&f));
  return TL_OK;
fail:
  tl_free(&names);
  tl_h5_abort(&f);
  return s;
}

static TlStatus tl_mw_write_step(const char *path, const char *mesh_file, int64_t step, double time,
                                 const TlMeshView *v)
{
  TlH5File f;
  TL_CHECK(tl_h5_create(path, &f));
  TlStatus s;
  TL_CHECK_GOTO(s, tl_h5_attr_write_string(&f, "/", "format", "talus-mesh-step"), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_int64(&f, "/", "format_version", TL_MESH_FORMAT_VERSION), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_double(&f, "/", "time", time), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_int64(&f, "/", "step", step), fail);
  TL_CHECK_GOTO(s, tl_h5_attr_write_string(&f, "/", "mesh_file", mesh_file), fail);
  TL_CHECK_GOTO(s, tl_h5_group(&f, "/mesh"), fail);
  if (v->displacement) {
    hsize_t dims[2] = {v->n_nodes, 3};
    TL_CHECK_GOTO(s, tl_h5_write(&f, "/mesh/displacement", H5T_NATIVE_DOUBLE, 2, dims, v->displacement), fail);
  }
  TL_CHECK_GOTO(s, tl_write_fields(&f, "/mesh/node_fields", v->n_nodes, v->n_node_fields, v->node_fields), fail);
  for (size_t b = 0; b < v->n_blocks; ++b) {
    char group[600];
    snprintf(group, sizeof group, "/mesh/blocks/%s/cell_fields", v->blocks[b].name);
    TL_CHECK_GOTO(s, tl_write_fields(&f, group, v->blocks[b].n_cells, v->blocks[b].n_fields, v->blocks[b].fields), fail);
  }
  TL_CHECK(tl_h5_commit(&f));
  return TL_OK;
fail:
  tl_h5_abort(&f);
  return s;
}

static TlStatus tl_mw_block_grid(TlText *x, const char *in, const char *mesh_file, const char *file,
                                 const TlMeshView *v, const TlMeshBlock *bl)
{
  int npc = tl_cell_type_nodes(bl->type);
  char in2[64], in3[64], dset[700];
  snprintf(in2, sizeof in2, "%s  ", in);
  snprintf(in3, sizeof in3, "%s    ", in);
  TL_CHECK(tl_text_printf(x, "%s<Grid Name=\"%s\" GridType=\"Uniform\">\n", in, bl->name));
  TL_CHECK(tl_text_printf(x, "%s<Topology TopologyType=\"%s\" NumberOfElements=\"%zu\" NodesPerElement=\"%d\">\n", in2,
                          tl_cell_type_xdmf(bl->type), bl->n_cells, npc));
  snprintf(dset, sizeof dset, "/mesh/blocks/%s/connectivity", bl->name);
  TL_CHECK(tl_xdmf_data_item(x, in3, bl->n_cells, (size_t)npc, "Int", (int)sizeof(int), mesh_file, dset));
  TL_CHECK(tl_text_printf(x, "%s</Topology>\n%s<Geometry GeometryType=\"XYZ\">\n", in2, in2));
  TL_CHECK(tl_xdmf_data_item(x, in3, v->n_nodes, 3, "Float", 8, mesh_file, "/mesh/reference_coordinates"));
  TL_CHECK(tl_text_printf(x, "%s</Geometry>\n", in2));
  if (v->displacement)
    TL_CHECK(tl_xdmf_attribute(x, in2, "displacement", 3, "Node", v->n_nodes, file, "/mesh/displacement"));
  for (size_t i = 0; i < v->n_node_fields; ++i) {
    snprintf(dset, sizeof dset, "/mesh/node_fields/%s", v->node_fields[i].name);
    TL_CHECK(tl_xdmf_attribute(x, in2, v->node_fields[i].name, v->node_fields[i].components, "Node", v->n_nodes, file, dset));
  }
  for (size_t i = 0; i < bl->n_fields; ++i) {
    snprintf(dset, sizeof dset, "/mesh/blocks/%s/cell_fields/%s", bl->name, bl->fields[i].name);
    TL_CHECK(tl_xdmf_attribute(x, in2, bl->fields[i].name, bl->fields[i].components, "Cell", bl->n_cells, file, dset));
  }
  TL_CHECK(tl_text_printf(x, "%s</Grid>\n", in));
  return TL_OK;
}

static TlStatus tl_mw_grid(TlText *x, const char *mesh_file, const char *file, size_t count, double time,
                           const TlMeshView *v)
{
  tl_text_clear(x);
  if (v->n_blocks == 1) {
    /* one block: a Uniform grid carrying its own Time */
    TlText inner = {0};
    TlStatus s = tl_mw_block_grid(&inner, "      ", mesh_file, file, v, &v->blocks[0]);
    if (s == TL_OK) {
      /* insert <Time> after the opening line */
      char *eol = strchr(inner.text, '\n');
      size_t head = (size_t)(eol - inner.text) + 1;
      s = tl_text_printf(x, "%.*s        <Time Value=\"%.17g\"/>\n%s", (int)head, inner.text, time, inner.text + head);
    }
    tl_text_free(&inner);
    TL_CHECK(s);
    return TL_OK;
  }
  TL_CHECK(tl_text_printf(x, "      <Grid Name=\"step_%06zu\" GridType=\"Collection\" CollectionType=\"Spatial\">\n", count));
  TL_CHECK(tl_text_printf(x, "        <Time Value=\"%.17g\"/>\n", time));
  for (size_t b = 0; b < v->n_blocks; ++b) TL_CHECK(tl_mw_block_grid(x, "        ", mesh_file, file, v, &v->blocks[b]));
  TL_CHECK(tl_text_printf(x, "      </Grid>\n"));
  return TL_OK;
}

TlStatus tl_mesh_writer_write(TlMeshWriter *w, int64_t step, double time, const TlMeshView *v)
{
  TL_CHECK(tl_mw_check(w, v));
  uint64_t h = tl_mesh_hash(v);
  if (!w->have_mesh || h != w->mesh_hash) {
    char file[1100];
    snprintf(file, sizeof file, "%s_mesh_%04zu.h5", w->out.name, w->mesh_count);
    char *path;
    TL_CHECK(tl_path_join(w->out.dir, file, &path));
    TlStatus s = tl_mw_write_mesh(path, v);
    if (s == TL_OK) snprintf(w->mesh_path, sizeof w->mesh_path, "%s", path);
    tl_free(&path);
    TL_CHECK(s);
    snprintf(w->mesh_file, sizeof w->mesh_file, "%s", file);
    w->mesh_hash = h;
    w->have_mesh = 1;
    w->mesh_count++;
  }
  char file[1100];
  snprintf(file, sizeof file, "%s_%06zu.h5", w->out.name, w->out.count);
  char *path;
  TL_CHECK(tl_path_join(w->out.dir, file, &path));
  TlStatus s = tl_mw_write_step(path, w->mesh_file, step, time, v);
  if (s == TL_OK) snprintf(w->out.last_path, sizeof w->out.last_path, "%s", path);
  tl_free(&path);
  TL_CHECK(s);
  TL_CHECK(tl_mw_grid(&w->out.grid, w->mesh_file, file, w->out.count, time, v));
  TL_CHECK(tl_xdmf_series_add(w->out.series, w->out.grid.text));
  w->out.count++;
  return TL_OK;
}

/* ---------------------------------------------------------------- checkpoint */
static TlStatus tl_mw_save(const void *object, TlCheckpointWriter *cw, const char *group)
{
  const TlMeshWriter *w = object;
  char sub[512];
  snprintf(sub, sizeof sub, "%s/series", group);
  TL_CHECK(tl_checkpoint_write_int64(cw, group, "count", (int64_t)w->out.count));
  TL_CHECK(tl_checkpoint_write_int64(cw, group, "mesh_count", (int64_t)w->mesh_count));
  TL_CHECK(tl_checkpoint_write_int64(cw, group, "have_mesh", w->have_mesh));
  TL_CHECK(tl_checkpoint_write_bytes(cw, group, "mesh_hash", sizeof w->mesh_hash, &w->mesh_hash));
  TL_CHECK(tl_checkpoint_write_string(cw, group, "mesh_file", w->mesh_file));
  TL_CHECK(tl_xdmf_series_checkpoint_ops.save(w->out.series, cw, sub));
  return TL_OK;
}

static TlStatus tl_mw_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlMeshWriter *w = object;
  char sub[512];
  snprintf(sub, sizeof sub, "%s/series", group);
  int64_t count, mesh_count, have;
  char *mesh_file = NULL;
  TL_CHECK(tl_checkpoint_read_int64(r, group, "count", &count));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "mesh_count", &mesh_count));
  TL_CHECK(tl_checkpoint_read_int64(r, group, "have_mesh", &have));
  if (count < 0 || mesh_count < 0)
    TL_ERROR(TL_ERR_FORMAT, "checkpoint '%s': mesh writer '%s' has counts %lld, %lld", tl_checkpoint_reader_path(r),
             group, (long long)count, (long long)mesh_count);
  TL_CHECK(tl_checkpoint_read_bytes(r, group, "mesh_hash", sizeof w->mesh_hash, &w->mesh_hash));
  TL_CHECK(tl_checkpoint_read_string(r, group, "mesh_file", &mesh_file));
  snprintf(w->mesh_file, sizeof w->mesh_file, "%s", mesh_file);
  tl_free(&mesh_file);
  TL_CHECK(tl_xdmf_series_checkpoint_ops.load(w->out.series, r, sub));
  w->out.count = (size_t)count;
  w->mesh_count = (size_t)mesh_count;
  w->have_mesh = have != 0;
  if (w->have_mesh) {
    char *path;
    TL_CHECK(tl_path_join(w->out.dir, w->mesh_file, &path));
    snprintf(w->mesh_path, sizeof w->mesh_path, "%s", path);
    tl_free(&path);
  }
  return TL_OK;
}

const TlCheckpointOps tl_mesh_writer_checkpoint_ops = {
    {"checkpoint", "mesh_writer_v1", "counters, mesh checksum and XDMF series of a mesh writer"}, tl_mw_save, tl_mw_load};

/* ---------------------------------------------------------------- reading */
static void tl_free_fields(size_t n, char ***names, int **comps, double ***data)
{
  for (size_t i = 0; i < n; ++i) {
    if (*names) tl_free(&(*names)[i]);
    if (*data) tl_free(&(*data)[i]);
  }
  tl_free(names);
  tl_free(comps);
  tl_free(data);
}

void tl_mesh_snapshot_free(TlMeshSnapshot *m)
{
  tl_free(&m->reference);
  tl_free(&m->displacement);
  tl_free_fields(m->n_node_fields, &m->node_field_names, &m->node_field_components, &m->node_field_data);
  for (size_t b = 0; b < m->n_blocks && m->blocks; ++b) {
    TlMeshSnapshotBlock *bl = &m->blocks[b];
    tl_free(&bl->name);
    tl_free(&bl->connectivity);
    tl_free_fields(bl->n_fields, &bl->field_names, &bl->field_components, &bl->field_data);
  }
  tl_free(&m->blocks);
  memset(m, 0, sizeof *m);
}

static TlStatus tl_read_fields(const TlH5File *f, const char *group, size_t rows, size_t *n, char ***names, int **comps,
                               double ***data)
{
  *n = 0;
  if (!tl_h5_exists(f, group)) return TL_OK;
  size_t k;
  TL_CHECK(tl_h5_attr_read_strings(f, group, "names", &k, names));
  *n = k;
  TL_CHECK(tl_calloc(comps, k, sizeof **comps));
  TL_CHECK(tl_calloc(data, k, sizeof **data));
  for (size_t i = 0; i < k; ++i) {
    char dset[1024];
    snprintf(dset, sizeof dset, "%s/%s", group, (*names)[i]);
    int rank;
    hsize_t dims[TL_H5_MAX_RANK];
    TL_CHECK(tl_h5_dims(f, dset, &rank, dims));
    if (rank < 1 || rank > 2 || dims[0] != rows)
      TL_ERROR(TL_ERR_FORMAT, "'%s': %s has rank %d and %llu rows, expected %zu rows", f->path, dset, rank,
               (unsigned long long)dims[0], rows);
    size_t c = rank == 2 ? (size_t)dims[1] : 1;
    (*comps)[i] = (int)c;
    TL_CHECK(tl_calloc(&(*data)[i], rows * c > 0 ? rows * c : 1, sizeof(double)));
    TL_CHECK(tl_h5_read(f, dset, H5T_NATIVE_DOUBLE, rank, dims, (*data)[i]));
  }
  return TL_OK;
}

static TlStatus tl_check_format(const TlH5File *f, const char *expected)
{
  char *format = NULL;
  TL_CHECK(tl_h5_attr_read_string(f, "/", "format", &format));
  int ok = strcmp(format, expected) == 0;
  tl_free(&format);
  if (!ok) TL_ERROR(TL_ERR_FORMAT, "'%s' is not a %s file (attribute format)", f->path, expected);
  int64_t version;
  TL_CHECK(tl_h5_attr_read_int64(f, "/", "format_version", &version));
  if (version != TL_MESH_FORMAT_VERSION)
    TL_ERROR(TL_ERR_FORMAT, "'%s' has format version %lld; this build reads %d", f->path, (long long)version,
             TL_MESH_FORMAT_VERSION);
  return TL_OK;
}

static TlStatus tl_mr_mesh(const TlH5File *f, TlMeshSnapshot *m)
{
  TL_CHECK(tl_check_format(f, "talus-mesh"));
  int rank;
  hsize_t dims[TL_H5_MAX_RANK];
  TL_CHECK(tl_h5_dims(f, "/mesh/reference_coordinates", &rank, dims));
  if (rank != 2 || dims[1] != 3)
    TL_ERROR(TL_ERR_FORMAT, "'%s': /mesh/reference_coordinates is not n x 3", f->path);
  m->n_nodes = (size_t)dims[0];
  TL_CHECK(tl_calloc(&m->reference, m->n_nodes ? m->n_nodes : 1, sizeof *m->reference));
  TL_CHECK(tl_h5_read(f, "/mesh/reference_coordinates", H5T_NATIVE_DOUBLE, 2, dims, m->reference));
  char **names = NULL;
  size_t nb = 0;
  TL_CHECK(tl_h5_attr_read_strings(f, "/mesh/blocks", "names", &nb, &names));
  TlStatus s = tl_calloc(&m->blocks, nb, sizeof *m->blocks);
  if (s == TL_OK) {
    m->n_blocks = nb;
    for (size_t b = 0; b < nb; ++b) {
      m->blocks[b].name = names[b];
      names[b] = NULL;
    }
  }
  tl_h5_free_strings(nb, &names);
  TL_CHECK(s);
  for (size_t b = 0; b < nb; ++b) {
    TlMeshSnapshotBlock *bl = &m->blocks[b];
    char group[512], dset[600], *type = NULL;
    snprintf(group, sizeof group, "/mesh/blocks/%s", bl->name);
    snprintf(dset, sizeof dset, "%s/connectivity", group);
    TL_CHECK(tl_h5_attr_read_string(f, group, "cell_type", &type));
    s = tl_cell_type_from_name(type, &bl->type);
    tl_free(&type);
    TL_CHECK(s);
    TL_CHECK(tl_h5_dims(f, dset, &rank, dims));
    if (rank != 2 || dims[1] != (hsize_t)tl_cell_type_nodes(bl->type))
      TL_ERROR(TL_ERR_FORMAT, "'%s': %s does not have %d columns", f->path, dset, tl_cell_type_nodes(bl->type));
    bl->n_cells = (size_t)dims[0];
    TL_CHECK(tl_calloc(&bl->connectivity, bl->n_cells * dims[1] > 0 ? bl->n_cells * dims[1] : 1, sizeof(int)));
    TL_CHECK(tl_h5_read(f, dset, H5T_NATIVE_INT, 2, dims, bl->connectivity));
  }
  return TL_OK;
}

static TlStatus tl_mr_step(const TlH5File *f, TlMeshSnapshot *m)
{
  TL_CHECK(tl_check_format(f, "talus-mesh-step"));
  TL_CHECK(tl_h5_attr_read_double(f, "/", "time", &m->time));
  TL_CHECK(tl_h5_attr_read_int64(f, "/", "step", &m->step));
  if (tl_h5_exists(f, "/mesh/displacement")) {
    hsize_t dims[2] = {m->n_nodes, 3};
    TL_CHECK(tl_calloc(&m->displacement, m->n_nodes ? m->n_nodes : 1, sizeof *m->displacement));
    TL_CHECK(tl_h5_read(f, "/mesh/displacement", H5T_NATIVE_DOUBLE, 2, dims, m->displacement));
  }
  TL_CHECK(tl_read_fields(f, "/mesh/node_fields", m->n_nodes, &m->n_node_fields, &m->node_field_names,
                          &m->node_field_components, &m->node_field_data));
  for (size_t b = 0; b < m->n_blocks; ++b) {
    TlMeshSnapshotBlock *bl = &m->blocks[b];
    char group[600];
    snprintf(group, sizeof group, "/mesh/blocks/%s/cell_fields", bl->name);
    TL_CHECK(tl_read_fields(f, group, bl->n_cells, &bl->n_fields, &bl->field_names, &bl->field_components,
                            &bl->field_data));
  }
  return TL_OK;
}

TlStatus tl_mesh_snapshot_read(const char *path, TlMeshSnapshot *snapshot)
{
  memset(snapshot, 0, sizeof *snapshot);
  TlH5File step, mesh;
  TL_CHECK(tl_h5_open(path, &step));
  char *mesh_file = NULL, *mesh_path = NULL;
  TlStatus s;
  TL_CHECK_GOTO(s, tl_h5_attr_read_string(&step, "/", "mesh_file", &mesh_file), done);
  {
    const char *slash = strrchr(path, '/');
    char dir[4096];
    snprintf(dir, sizeof dir, "%.*s", slash ? (slash == path ? 1 : (int)(slash - path)) : 0, path);
    TL_CHECK_GOTO(s, tl_path_join(dir, mesh_file, &mesh_path), done);
  }
  TL_CHECK_GOTO(s, tl_h5_open(mesh_path, &mesh), done);
  s = tl_mr_mesh(&mesh, snapshot);
  tl_h5_close(&mesh);
  if (s != TL_OK) goto done;
  s = tl_mr_step(&step, snapshot);
done:
  tl_h5_close(&step);
  tl_free(&mesh_file);
  tl_free(&mesh_path);
  if (s != TL_OK) {
    tl_mesh_snapshot_free(snapshot);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  return TL_OK;
}
