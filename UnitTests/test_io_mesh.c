/* Mesh snapshots: round trip of nodes, displacement, blocks of different
 * cell types, nodal and cell fields; the mesh file is written once and again
 * only when the mesh changes; single-block and multi-block XDMF; bad
 * connectivity refused with the block, cell and node named. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "talus.h"
#include "tl_io.h"
#include "tl_test.h"

/* two hex8 cells side by side (12 nodes) and a quad4 face on x = 0 */
enum { NN = 12 };
static TlVec3 ref[NN], disp[NN];
static double temperature[NN], strain[2 * 9], pressure[1];
static const int hex_conn[2 * 8] = {0, 1, 4, 3, 6, 7, 10, 9, 1, 2, 5, 4, 7, 8, 11, 10};
static const int quad_conn[4] = {0, 3, 9, 6};

static void build(double scale)
{
  int k = 0;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x, ++k) {
        ref[k] = tl_v3(scale * x, scale * y, scale * z);
        disp[k] = tl_v3(1e-3 * x * z, -0.0, 1.0 / (3.0 + k));
        temperature[k] = 293.15 + k / 7.0;
      }
  for (int i = 0; i < 18; ++i) strain[i] = (i - 9) / 11.0;
  pressure[0] = 1e5 / 3.0;
}

static void test_two_blocks(void)
{
  build(1.0);
  TlField node_fields[1] = {{"temperature", 1, temperature}};
  TlField hex_fields[1] = {{"strain", 9, strain}};
  TlField quad_fields[1] = {{"pressure", 1, pressure}};
  TlMeshBlock blocks[2] = {{"solid", TL_CELL_HEX8, 2, hex_conn, 1, hex_fields},
                           {"surface", TL_CELL_QUAD4, 1, quad_conn, 1, quad_fields}};
  TlMeshView v = {.n_nodes = NN, .reference = ref, .displacement = disp, .n_node_fields = 1,
                  .node_fields = node_fields, .n_blocks = 2, .blocks = blocks};
  /* the scratch folder may hold a previous run's files */
  unlink("fem/beam_mesh_0001.h5");
  TlMeshWriter *w;
  TL_TEST_STATUS(tl_mesh_writer_create("fem", "beam", &w), TL_OK);
  if (!w) return;
  TL_TEST_STATUS(tl_mesh_writer_write(w, 0, 0.0, &v), TL_OK);
  for (int i = 0; i < NN; ++i) disp[i].x += 0.5; /* fields change, mesh does not */
  TL_TEST_STATUS(tl_mesh_writer_write(w, 10, 1e-3, &v), TL_OK);
  TL_TEST_ASSERT(access("fem/beam_mesh_0000.h5", F_OK) == 0, "mesh file missing");
  TL_TEST_ASSERT(access("fem/beam_mesh_0001.h5", F_OK) != 0, "mesh rewritten although unchanged");

  TlMeshSnapshot m;
  TL_TEST_STATUS(tl_mesh_snapshot_read("fem/beam_000001.h5", &m), TL_OK);
  TL_TEST_ASSERT(m.n_nodes == NN && m.step == 10 && m.time == 1e-3, "nodes %zu step %lld", m.n_nodes, (long long)m.step);
  if (m.n_nodes == NN && m.n_blocks == 2) {
    TL_TEST_ASSERT(memcmp(m.reference, ref, sizeof ref) == 0, "reference coordinates differ");
    TL_TEST_ASSERT(m.displacement && memcmp(m.displacement, disp, sizeof disp) == 0, "displacement differs");
    TL_TEST_ASSERT(m.n_node_fields == 1 && strcmp(m.node_field_names[0], "temperature") == 0, "node field name");
    TL_TEST_ASSERT(m.n_node_fields == 1 && memcmp(m.node_field_data[0], temperature, sizeof temperature) == 0,
                   "temperature differs");
    TlMeshSnapshotBlock *h = &m.blocks[0], *q = &m.blocks[1];
    TL_TEST_ASSERT(strcmp(h->name, "solid") == 0 && h->type == TL_CELL_HEX8 && h->n_cells == 2, "hex block");
    TL_TEST_ASSERT(memcmp(h->connectivity, hex_conn, sizeof hex_conn) == 0, "hex connectivity differs");
    TL_TEST_ASSERT(h->n_fields == 1 && h->field_components[0] == 9 && memcmp(h->field_data[0], strain, sizeof strain) == 0,
                   "strain differs");
    TL_TEST_ASSERT(strcmp(q->name, "surface") == 0 && q->type == TL_CELL_QUAD4 && q->n_cells == 1, "quad block");
    TL_TEST_ASSERT(memcmp(q->connectivity, quad_conn, sizeof quad_conn) == 0, "quad connectivity differs");
    TL_TEST_ASSERT(q->n_fields == 1 && q->field_data[0][0] == pressure[0], "pressure differs");
  } else {
    TL_TEST_ASSERT(0, "%zu blocks read", m.n_blocks);
  }
  tl_mesh_snapshot_free(&m);

  char *xmf = tl_test_read_file("fem/beam.xmf");
  TL_TEST_ASSERT(xmf != NULL, "no beam.xmf");
  if (xmf) {
    TL_TEST_ASSERT(tl_test_count(xmf, "CollectionType=\"Spatial\"") == 2, "two steps of two blocks make spatial collections");
    TL_TEST_ASSERT(tl_test_count(xmf, "TopologyType=\"Hexahedron\" NumberOfElements=\"2\" NodesPerElement=\"8\"") == 2, "hex");
    TL_TEST_ASSERT(tl_test_count(xmf, "TopologyType=\"Quadrilateral\" NumberOfElements=\"1\" NodesPerElement=\"4\"") == 2, "quad");
    TL_TEST_ASSERT(tl_test_count(xmf, ">beam_mesh_0000.h5:/mesh/reference_coordinates<") == 4, "geometry references");
    TL_TEST_ASSERT(tl_test_count(xmf, "<Attribute Name=\"strain\" AttributeType=\"Tensor\" Center=\"Cell\">") == 2, "strain");
    TL_TEST_ASSERT(tl_test_count(xmf, ">beam_000001.h5:/mesh/displacement<") == 2, "displacement of step 1 per block");
  }
  free(xmf);

  /* a moved mesh writes a new mesh file that later steps point at */
  build(2.0);
  TL_TEST_STATUS(tl_mesh_writer_write(w, 20, 2e-3, &v), TL_OK);
  TL_TEST_ASSERT(access("fem/beam_mesh_0001.h5", F_OK) == 0, "changed mesh not rewritten");
  TL_TEST_ASSERT(strcmp(tl_mesh_writer_mesh_path(w), "fem/beam_mesh_0001.h5") == 0, "mesh path %s",
                 tl_mesh_writer_mesh_path(w));
  TL_TEST_STATUS(tl_mesh_snapshot_read("fem/beam_000002.h5", &m), TL_OK);
  TL_TEST_ASSERT(m.n_nodes == NN && memcmp(m.reference, ref, sizeof ref) == 0, "new reference not read back");
  tl_mesh_snapshot_free(&m);
  TL_TEST_STATUS(tl_mesh_snapshot_read("fem/beam_000000.h5", &m), TL_OK);
  TL_TEST_ASSERT(m.n_nodes == NN && m.reference[1].x == 1.0, "old step lost its mesh");
  tl_mesh_snapshot_free(&m);

  /* errors */
  int bad_conn[8] = {0, 1, 4, 3, 6, 7, 10, 12};
  TlMeshBlock bad = {"broken", TL_CELL_HEX8, 1, bad_conn, 0, NULL};
  TlMeshView bv = {.n_nodes = NN, .reference = ref, .n_blocks = 1, .blocks = &bad};
  TL_TEST_STATUS(tl_mesh_writer_write(w, 30, 3e-3, &bv), TL_ERR_ARG);
  TL_TEST_ASSERT(strstr(tl_error_message(), "'broken'") && strstr(tl_error_message(), "node 7 is 12"), "message: %s",
                 tl_error_message());
  TlMeshBlock twice[2] = {{"a", TL_CELL_QUAD4, 1, quad_conn, 0, NULL}, {"a", TL_CELL_QUAD4, 1, quad_conn, 0, NULL}};
  bv.blocks = twice;
  bv.n_blocks = 2;
  TL_TEST_STATUS(tl_mesh_writer_write(w, 30, 3e-3, &bv), TL_ERR_ARG);
  TlMeshBlock weird = {"w", (TlCellType)99, 1, quad_conn, 0, NULL};
  bv.blocks = &weird;
  bv.n_blocks = 1;
  TL_TEST_STATUS(tl_mesh_writer_write(w, 30, 3e-3, &bv), TL_ERR_ARG);
  bv.n_blocks = 0;
  TL_TEST_STATUS(tl_mesh_writer_write(w, 30, 3e-3, &bv), TL_ERR_ARG);
  TL_TEST_ASSERT(tl_mesh_writer_count(w) == 3, "count %zu", tl_mesh_writer_count(w));
  tl_mesh_writer_destroy(&w);
  TL_TEST_ASSERT(w == NULL, "destroy must null");
}

static void test_single_block_and_types(void)
{
  /* every cell type knows its XDMF name, VTK code and node count */
  static const int nodes[TL_CELL_TYPE_COUNT] = {3, 6, 4, 8, 9, 4, 10, 8, 20, 27, 6, 15, 18, 5, 13};
  static const int vtk[TL_CELL_TYPE_COUNT] = {5, 22, 9, 23, 28, 10, 24, 12, 25, 29, 13, 26, 32, 14, 27};
  for (int t = 0; t < TL_CELL_TYPE_COUNT; ++t) {
    TlCellType back;
    TL_TEST_ASSERT(tl_cell_type_nodes((TlCellType)t) == nodes[t], "type %d nodes", t);
    TL_TEST_ASSERT(tl_cell_type_vtk((TlCellType)t) == vtk[t], "type %d VTK code", t);
    TL_TEST_STATUS(tl_cell_type_from_name(tl_cell_type_name((TlCellType)t), &back), TL_OK);
    TL_TEST_ASSERT(back == (TlCellType)t, "type %d name round trip", t);
  }
  TL_TEST_ASSERT(strcmp(tl_cell_type_xdmf(TL_CELL_HEX27), "Hexahedron_27") == 0, "hex27 xdmf");
  TL_TEST_ASSERT(strcmp(tl_cell_type_xdmf(TL_CELL_TET10), "Tetrahedron_10") == 0, "tet10 xdmf");
  TlCellType t;
  TL_TEST_STATUS(tl_cell_type_from_name("hex9", &t), TL_ERR_NOT_FOUND);

  /* one tet10 */
  TlVec3 x[10] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {.5, 0, 0}, {.5, .5, 0}, {0, .5, 0}, {0, 0, .5}, {.5, 0, .5}, {0, .5, .5}};
  int conn[10] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  TlMeshBlock b = {"tet", TL_CELL_TET10, 1, conn, 0, NULL};
  TlMeshView v = {.n_nodes = 10, .reference = x, .n_blocks = 1, .blocks = &b};
  TlMeshWriter *w;
  TL_TEST_STATUS(tl_mesh_writer_create(NULL, "one", &w), TL_OK);
  if (!w) return;
  TL_TEST_STATUS(tl_mesh_writer_write(w, 0, 0.0, &v), TL_OK);
  char *xmf = tl_test_read_file("one.xmf");
  TL_TEST_ASSERT(xmf && tl_test_count(xmf, "CollectionType=\"Spatial\"") == 0, "single block must be a uniform grid");
  TL_TEST_ASSERT(xmf && strstr(xmf, "<Grid Name=\"tet\" GridType=\"Uniform\">\n        <Time Value=\"0\"/>"),
                 "time inside the uniform grid");
  TL_TEST_ASSERT(xmf && tl_test_count(xmf, "Name=\"displacement\"") == 0, "displacement listed though absent");
  free(xmf);
  TlMeshSnapshot m;
  TL_TEST_STATUS(tl_mesh_snapshot_read("one_000000.h5", &m), TL_OK);
  TL_TEST_ASSERT(m.n_blocks == 1 && m.blocks[0].type == TL_CELL_TET10 && m.displacement == NULL, "tet10 read back");
  tl_mesh_snapshot_free(&m);
  tl_mesh_writer_destroy(&w);
}

/* A run restarted from a checkpoint continues the numbering, the mesh file
 * and the series exactly as an uninterrupted run. */
static void test_restart(void)
{
  build(1.0);
  TlMeshBlock block = {"solid", TL_CELL_HEX8, 2, hex_conn, 0, NULL};
  TlMeshView v = {.n_nodes = NN, .reference = ref, .displacement = disp, .n_blocks = 1, .blocks = &block};
  TlMeshWriter *a, *b, *c;
  TL_TEST_STATUS(tl_mesh_writer_create("straight", "m", &a), TL_OK);
  TL_TEST_STATUS(tl_mesh_writer_create("restarted", "m", &b), TL_OK);
  if (!a || !b) return;
  TlCheckpoint *cp;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "mesh_output", &tl_mesh_writer_checkpoint_ops, b), TL_OK);
  for (int k = 0; k < 4; ++k) {
    TL_TEST_STATUS(tl_mesh_writer_write(a, k, 0.1 * k, &v), TL_OK);
    TL_TEST_STATUS(tl_mesh_writer_write(b, k, 0.1 * k, &v), TL_OK);
    if (k == 1) TL_TEST_STATUS(tl_checkpoint_save(cp, "mesh_restart.h5", 0.1, 1), TL_OK);
  }
  tl_checkpoint_destroy(&cp);
  tl_mesh_writer_destroy(&b);
  TL_TEST_STATUS(tl_mesh_writer_create("restarted", "m", &c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_add(cp, "mesh_output", &tl_mesh_writer_checkpoint_ops, c), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_load(cp, "mesh_restart.h5", NULL, NULL), TL_OK);
  TL_TEST_ASSERT(tl_mesh_writer_count(c) == 2, "restored count %zu", tl_mesh_writer_count(c));
  for (int k = 2; k < 4; ++k) TL_TEST_STATUS(tl_mesh_writer_write(c, k, 0.1 * k, &v), TL_OK);
  TL_TEST_ASSERT(access("restarted/m_mesh_0001.h5", F_OK) != 0, "restart rewrote an unchanged mesh");
  char *x = tl_test_read_file("straight/m.xmf"), *y = tl_test_read_file("restarted/m.xmf");
  TL_TEST_ASSERT(x && y && strcmp(x, y) == 0, "restarted series differs from the straight one");
  free(x);
  free(y);
  tl_checkpoint_destroy(&cp);
  tl_mesh_writer_destroy(&a);
  tl_mesh_writer_destroy(&c);
}

int main(void)
{
  test_two_blocks();
  test_single_block_and_types();
  test_restart();
  return tl_test_report();
}
