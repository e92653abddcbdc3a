#include "tl_solid_output.h"

#include <math.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_mesh_snapshot.h"

struct TlSolidOutput {
  TlSolid *solid;
  TlMeshWriter *writer;
  int dim;
  size_t n_nodes;
  TlVec3 *reference, *displacement, *velocity;
  double *u_nodes;
  int n_blocks;
  TlMeshBlock *blocks;
  int **connectivity;
  double **pk2, **cauchy, **mises;
  TlField (*fields)[3];
};

/* The cell that draws an element type and its node order, from the type. */
static TlStatus cell_type_of(const TlElementType *t, TlCellType *c, const int **order)
{
  if (!t->output) TL_ERROR(TL_ERR_UNSUPPORTED, "element type %s has no output cell type", t->header.name);
  *c = t->output->cell;
  *order = t->output->order;
  return TL_OK;
}

void tl_solid_output_destroy(TlSolidOutput **out)
{
  if (!out || !*out) return;
  TlSolidOutput *o = *out;
  tl_mesh_writer_destroy(&o->writer);
  for (int b = 0; b < o->n_blocks; ++b) {
    if (o->connectivity) tl_free(&o->connectivity[b]);
    if (o->pk2) tl_free(&o->pk2[b]);
    if (o->cauchy) tl_free(&o->cauchy[b]);
    if (o->mises) tl_free(&o->mises[b]);
  }
  tl_free(&o->connectivity);
  tl_free(&o->pk2);
  tl_free(&o->cauchy);
  tl_free(&o->mises);
  tl_free(&o->fields);
  tl_free(&o->blocks);
  tl_free(&o->reference);
  tl_free(&o->displacement);
  tl_free(&o->velocity);
  tl_free(&o->u_nodes);
  tl_free(out);
}

TlStatus tl_solid_output_create(TlSolid *solid, const char *dir, const char *name, TlSolidOutput **out)
{
  const TlMesh *mesh = tl_solid_mesh(solid);
  TlSolidOutput *o = NULL;
  TL_CHECK(TL_NEW(o));
  TlStatus s = TL_OK;
  o->solid = solid;
  o->dim = mesh->dim;
  o->n_nodes = mesh->n_nodes;
  o->n_blocks = mesh->n_blocks;
  TL_CHECK_GOTO(s, tl_calloc(&o->reference, o->n_nodes, sizeof(TlVec3)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&o->displacement, o->n_nodes, sizeof(TlVec3)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&o->velocity, o->n_nodes, sizeof(TlVec3)), fail);
  TL_CHECK_GOTO(s, tl_calloc(&o->u_nodes, o->n_nodes * o->dim, sizeof(double)), fail);
  for (size_t i = 0; i < o->n_nodes; ++i)
    o->reference[i] = tl_v3(mesh->x[3 * i], mesh->x[3 * i + 1], mesh->x[3 * i + 2]);
  TL_CHECK_GOTO(s, tl_calloc(&o->blocks, o->n_blocks, sizeof *o->blocks), fail);
  TL_CHECK_GOTO(s, tl_calloc(&o->connectivity, o->n_blocks, sizeof *o->connectivity), fail);
  TL_CHECK_GOTO(s, tl_calloc(&o->pk2, o->n_blocks, sizeof *o->pk2), fail);
  TL_CHECK_GOTO(s, tl_calloc(&o->cauchy, o->n_blocks, sizeof *o->cauchy), fail);
  TL_CHECK_GOTO(s, tl_calloc(&o->mises, o->n_blocks, sizeof *o->mises), fail);
  TL_CHECK_GOTO(s, tl_calloc(&o->fields, o->n_blocks, sizeof *o->fields), fail);
  for (int b = 0; b < o->n_blocks; ++b) {
    const TlElementBlock *blk = &mesh->blocks[b];
    int nn = blk->type->n_nodes;
    size_t ne = blk->n_elements ? blk->n_elements : 1;
    const int *order = NULL;
    TlCellType ct = TL_CELL_HEX8;
    TL_CHECK_GOTO(s, cell_type_of(blk->type, &ct, &order), fail);
    TL_CHECK_GOTO(s, tl_calloc(&o->connectivity[b], ne * nn, sizeof(int)), fail);
    for (size_t e = 0; e < blk->n_elements; ++e)
      for (int k = 0; k < nn; ++k) o->connectivity[b][e * nn + k] = (int)blk->conn[e * nn + (order ? order[k] : k)];
    TL_CHECK_GOTO(s, tl_calloc(&o->pk2[b], 6 * ne, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&o->cauchy[b], 6 * ne, sizeof(double)), fail);
    TL_CHECK_GOTO(s, tl_calloc(&o->mises[b], ne, sizeof(double)), fail);
    o->fields[b][0] = (TlField){"stress_pk2", 6, o->pk2[b]};
    o->fields[b][1] = (TlField){"stress_cauchy", 6, o->cauchy[b]};
    o->fields[b][2] = (TlField){"von_mises", 1, o->mises[b]};
    o->blocks[b] = (TlMeshBlock){blk->name, ct, blk->n_elements, o->connectivity[b], 3, o->fields[b]};
  }
  TL_CHECK_GOTO(s, tl_mesh_writer_create(dir, name, &o->writer), fail);
  *out = o;
  return TL_OK;
fail:
  tl_solid_output_destroy(&o);
  return s;
}

/* XDMF Tensor6 order: xx, xy, xz, yy, yz, zz. */
static void tensor6(TlMat3 a, double *v)
{
  v[0] = a.m[0][0], v[1] = a.m[0][1], v[2] = a.m[0][2];
  v[3] = a.m[1][1], v[4] = a.m[1][2], v[5] = a.m[2][2];
}

TlStatus tl_solid_output_write(TlSolidOutput *o, int64_t step, double t, const double *u, const double *v)
{
  const TlMesh *mesh = tl_solid_mesh(o->solid);
  int dim = o->dim;
  if (v) {
    tl_solid_dofs_to_nodes(o->solid, v, o->u_nodes);
    for (size_t i = 0; i < o->n_nodes; ++i)
      o->velocity[i] = tl_v3(o->u_nodes[i * dim], o->u_nodes[i * dim + 1], dim == 3 ? o->u_nodes[i * dim + 2] : 0.0);
  }
  tl_solid_dofs_to_nodes(o->solid, u, o->u_nodes);
  for (size_t i = 0; i < o->n_nodes; ++i)
    o->displacement[i] = tl_v3(o->u_nodes[i * dim], o->u_nodes[i * dim + 1], dim == 3 ? o->u_nodes[i * dim + 2] : 0.0);
  for (int b = 0; b < o->n_blocks; ++b)
    for (size_t e = 0; e < mesh->blocks[b].n_elements; ++e) {
      TlMat3 S, sigma;
      TL_CHECK(tl_solid_element_stress(o->solid, b, e, o->u_nodes, &S, &sigma));
      tensor6(S, o->pk2[b] + 6 * e);
      tensor6(sigma, o->cauchy[b] + 6 * e);
      double p = tl_m3_trace(sigma) / 3.0, J2 = 0.0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          double d = sigma.m[i][j] - (i == j ? p : 0.0);
          J2 += 0.5 * d * d;
        }
      o->mises[b][e] = sqrt(3.0 * J2);
    }
  TlField vel = {"velocity", 3, (const double *)o->velocity};
  TlMeshView view = {o->n_nodes, o->reference, o->displacement, v ? 1 : 0, v ? &vel : NULL,
                     (size_t)o->n_blocks, o->blocks};
  TL_CHECK(tl_mesh_writer_write(o->writer, step, t, &view));
  return TL_OK;
}

const char *tl_solid_output_last_path(const TlSolidOutput *o) { return tl_mesh_writer_last_path(o->writer); }

static TlStatus output_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const TlSolidOutput *o = object;
  return tl_mesh_writer_checkpoint_ops.save(o->writer, w, group);
}

static TlStatus output_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlSolidOutput *o = object;
  return tl_mesh_writer_checkpoint_ops.load(o->writer, r, group);
}

const TlCheckpointOps tl_solid_output_checkpoint_ops = {
    .header = {"checkpoint", "solid_output_v1", "solid snapshot series (its mesh writer's section)"},
    .save = output_save,
    .load = output_load,
};
