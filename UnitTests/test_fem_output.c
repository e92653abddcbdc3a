/* Solid snapshots through the IO mesh writer: the file read back holds the
 * displacement, the element stresses of a constant-strain state, and the
 * connectivity in VTK order (mid-edge and face-centre nodes of hex27 and
 * tet10 where VTK expects them). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_mesh_snapshot.h"
#include "tl_solid_output.h"
#include "tl_test.h"

static double dist_mid(const TlVec3 *x, const int *c, int m, int a, int b)
{
  double d = 0.0;
  d += fabs(x[c[m]].x - 0.5 * (x[c[a]].x + x[c[b]].x));
  d += fabs(x[c[m]].y - 0.5 * (x[c[a]].y + x[c[b]].y));
  d += fabs(x[c[m]].z - 0.5 * (x[c[a]].z + x[c[b]].z));
  return d;
}

static void run(const TlElementType *t)
{
  size_t n[3] = {2, 1, 1};
  double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 1};
  TlMesh *mesh = NULL;
  TlMaterial *mat = NULL;
  TlSolid *solid = NULL;
  TlSolidOutput *out = NULL;
  TL_TEST_STATUS(tl_mesh_create_box(t, n, lo, hi, &mesh), TL_OK);
  TL_TEST_STATUS(tl_material_create_hooke(1e8, 0.25, 1000.0, &mat), TL_OK);
  TL_TEST_STATUS(tl_solid_create(mesh, &solid), TL_OK);
  if (!solid) return;
  tl_solid_set_material(solid, NULL, mat);
  TL_TEST_STATUS(tl_solid_setup(solid), TL_OK);
  TlMechSystem *sys = tl_solid_system(solid);
  size_t nd = (size_t)sys->ndof;
  double *u = calloc(nd, sizeof *u), *v = calloc(nd, sizeof *v);
  double A[3][3] = {{0.01, 0.002, 0}, {0, -0.003, 0.001}, {0.002, 0, 0.004}};
  for (size_t a = 0; a < mesh->n_nodes; ++a)
    for (int i = 0; i < 3; ++i) {
      double s = 0.0;
      for (int j = 0; j < 3; ++j) s += A[i][j] * mesh->x[3 * a + j];
      u[tl_solid_dof(solid, a, i)] = s;
      v[tl_solid_dof(solid, a, i)] = 0.5 * s;
    }
  TL_TEST_STATUS(tl_solid_output_create(solid, ".", t->header.name, &out), TL_OK);
  if (!out) return;
  TL_TEST_STATUS(tl_solid_output_write(out, 0, 0.0, u, v), TL_OK);
  char path[4096];
  snprintf(path, sizeof path, "%s", tl_solid_output_last_path(out));
  TL_TEST_STATUS(tl_solid_output_write(out, 1, 0.5, u, NULL), TL_OK);
  TlMeshSnapshot snap;
  memset(&snap, 0, sizeof snap);
  TlStatus s = tl_mesh_snapshot_read(path, &snap);
  TL_TEST_STATUS(s, TL_OK);
  if (s == TL_OK) {
    TL_TEST_ASSERT(snap.n_nodes == mesh->n_nodes && snap.n_blocks == 1 && snap.displacement, "snapshot shape");
    double derr = 0.0;
    for (size_t a = 0; a < mesh->n_nodes && snap.displacement; ++a) {
      derr = fmax(derr, fabs(snap.displacement[a].x - u[tl_solid_dof(solid, a, 0)]));
      derr = fmax(derr, fabs(snap.displacement[a].z - u[tl_solid_dof(solid, a, 2)]));
    }
    TL_TEST_ASSERT(derr == 0.0, "displacement read back differs by %g", derr);
    const TlMeshSnapshotBlock *blk = &snap.blocks[0];
    int nn = t->n_nodes;
    /* VTK order checks on the first cell. */
    const int *c = blk->connectivity;
    double err = 0.0;
    if (t == &tl_element_hex27) {
      static const int edges[12][3] = {{8, 0, 1},   {9, 1, 2},   {10, 2, 3},  {11, 3, 0},
                                       {12, 4, 5},  {13, 5, 6},  {14, 6, 7},  {15, 7, 4},
                                       {16, 0, 4},  {17, 1, 5},  {18, 2, 6},  {19, 3, 7}};
      for (int k = 0; k < 12; ++k) err = fmax(err, dist_mid(snap.reference, c, edges[k][0], edges[k][1], edges[k][2]));
      /* Face centres x-, x+, y-, y+, z-, z+: midpoints of face diagonals. */
      static const int faces[6][3] = {{20, 0, 7}, {21, 1, 6}, {22, 0, 5}, {23, 3, 6}, {24, 0, 2}, {25, 4, 6}};
      for (int k = 0; k < 6; ++k) err = fmax(err, dist_mid(snap.reference, c, faces[k][0], faces[k][1], faces[k][2]));
      err = fmax(err, dist_mid(snap.reference, c, 26, 0, 6));
    } else if (t == &tl_element_tet10) {
      static const int edges[6][3] = {{4, 0, 1}, {5, 1, 2}, {6, 2, 0}, {7, 0, 3}, {8, 1, 3}, {9, 2, 3}};
      for (int k = 0; k < 6; ++k) err = fmax(err, dist_mid(snap.reference, c, edges[k][0], edges[k][1], edges[k][2]));
    }
    TL_TEST_ASSERT(err < 1e-14 && nn == tl_cell_type_nodes(blk->type), "%s: VTK node order off by %g", t->header.name, err);
    /* Stress fields: constant PK2 of the imposed F in every cell. */
    TlMat3 F = tl_m3_identity(), S;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F.m[i][j] += A[i][j];
    double st[13] = {0}, st2[13];
    if (mat->state_size) mat->ops->init_state(mat, 1, st);
    tl_material_evaluate(mat, 1, &F, mat->state_size ? st : NULL, mat->state_size ? st2 : NULL, &S, NULL, NULL);
    int found = 0;
    for (size_t k = 0; k < blk->n_fields; ++k) {
      if (strcmp(blk->field_names[k], "stress_pk2")) continue;
      found = 1;
      double serr = 0.0;
      for (size_t e = 0; e < blk->n_cells; ++e) {
        const double *d = blk->field_data[k] + 6 * e;
        serr = fmax(serr, fabs(d[0] - S.m[0][0]) + fabs(d[1] - S.m[0][1]) + fabs(d[5] - S.m[2][2]));
      }
      TL_TEST_ASSERT(serr < 1e-8 * fabs(S.m[0][0]), "%s: stress field off by %g", t->header.name, serr);
    }
    TL_TEST_ASSERT(found, "no stress_pk2 field");
    tl_mesh_snapshot_free(&snap);
  }
  free(u), free(v);
  tl_solid_output_destroy(&out);
  tl_solid_destroy(&solid);
  tl_material_destroy(&mat);
  tl_mesh_destroy(&mesh);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  run(&tl_element_hex27);
  run(&tl_element_tet10);
  run(&tl_element_hex8);
  return tl_test_report();
}
