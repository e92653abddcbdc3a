#define _GNU_SOURCE /* memmem */
/* The Gmsh reader on the four layouts of one mesh: msh 4.1 and 2.2, ASCII
 * and binary (4.1 binary also in the other byte order), written here byte
 * by byte so the test needs no gmsh: two hex8 cells with a physical volume
 * "solid" and a physical surface "left", node tags that are not 1..n.  Every
 * layout must give the same nodes, blocks, face and node sets; a truncated
 * binary file is refused by name.  When the gmsh program is installed, a
 * box it meshes and saves in the four layouts must read the same as well
 * (skipped with a message otherwise). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_mesh.h"
#include "tl_test.h"

enum { NN = 12 };

static double X[NN][3];
static long TAG[NN];
/* hex8 in Gmsh's node order (bottom face, then top), and the x = 0 face */
static long HEX[2][8], QUAD[4];

static void make_mesh(void)
{
  for (int iz = 0; iz < 2; ++iz)
    for (int iy = 0; iy < 2; ++iy)
      for (int ix = 0; ix < 3; ++ix) {
        int i = ix + 3 * iy + 6 * iz;
        X[i][0] = ix;
        X[i][1] = 0.5 * iy;
        X[i][2] = 0.25 * iz;
        TAG[i] = 101 + 2 * i; /* sparse tags */
      }
  for (int e = 0; e < 2; ++e) {
    const int c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int k = 0; k < 8; ++k) HEX[e][k] = TAG[(e + c[k][0]) + 3 * c[k][1] + 6 * c[k][2]];
  }
  const int q[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}}; /* (y, z) at x = 0 */
  for (int k = 0; k < 4; ++k) QUAD[k] = TAG[3 * q[k][0] + 6 * q[k][1]];
}

static int swap_bytes; /* write binary numbers in the other byte order */

static void put(FILE *f, const void *p, size_t n)
{
  unsigned char b[8];
  memcpy(b, p, n);
  if (swap_bytes)
    for (size_t i = 0; i < n / 2; ++i) {
      unsigned char t = b[i];
      b[i] = b[n - 1 - i];
      b[n - 1 - i] = t;
    }
  fwrite(b, 1, n, f);
}
static void put_i(FILE *f, long v) { int32_t x = (int32_t)v; put(f, &x, 4); }
static void put_z(FILE *f, long v) { uint64_t x = (uint64_t)v; put(f, &x, 8); }
static void put_d(FILE *f, double v) { put(f, &v, 8); }

static const char names[] = "$PhysicalNames\n2\n2 2 \"left\"\n3 1 \"solid\"\n$EndPhysicalNames\n";

static void write_41(const char *path, int binary)
{
  FILE *f = fopen(path, "wb");
  if (!f) return;
  fprintf(f, "$MeshFormat\n4.1 %d 8\n", binary);
  if (binary) {
    put_i(f, 1);
    fputc('\n', f);
  }
  fprintf(f, "$EndMeshFormat\n%s$Entities\n", names);
  if (!binary) {
    fprintf(f, "0 0 1 1\n7 0 0 0 0 0.5 0.25 1 2 0\n1 0 0 0 2 0.5 0.25 1 1 0\n$EndEntities\n");
    fprintf(f, "$Nodes\n1 %d %ld %ld\n3 1 0 %d\n", NN, TAG[0], TAG[NN - 1], NN);
    for (int i = 0; i < NN; ++i) fprintf(f, "%ld\n", TAG[i]);
    for (int i = 0; i < NN; ++i) fprintf(f, "%.17g %.17g %.17g\n", X[i][0], X[i][1], X[i][2]);
    fprintf(f, "$EndNodes\n$Elements\n2 3 1 3\n2 7 3 1\n1 %ld %ld %ld %ld\n3 1 5 2\n", QUAD[0], QUAD[1], QUAD[2],
            QUAD[3]);
    for (int e = 0; e < 2; ++e) {
      fprintf(f, "%d", 2 + e);
      for (int k = 0; k < 8; ++k) fprintf(f, " %ld", HEX[e][k]);
      fputc('\n', f);
    }
    fprintf(f, "$EndElements\n");
  } else {
    put_z(f, 0), put_z(f, 0), put_z(f, 1), put_z(f, 1);
    const double bs[6] = {0, 0, 0, 0, 0.5, 0.25}, bv[6] = {0, 0, 0, 2, 0.5, 0.25};
    put_i(f, 7);
    for (int k = 0; k < 6; ++k) put_d(f, bs[k]);
    put_z(f, 1), put_i(f, 2), put_z(f, 0);
    put_i(f, 1);
    for (int k = 0; k < 6; ++k) put_d(f, bv[k]);
    put_z(f, 1), put_i(f, 1), put_z(f, 0);
    fprintf(f, "\n$EndEntities\n$Nodes\n");
    put_z(f, 1), put_z(f, NN), put_z(f, TAG[0]), put_z(f, TAG[NN - 1]);
    put_i(f, 3), put_i(f, 1), put_i(f, 0), put_z(f, NN);
    for (int i = 0; i < NN; ++i) put_z(f, TAG[i]);
    for (int i = 0; i < NN; ++i)
      for (int k = 0; k < 3; ++k) put_d(f, X[i][k]);
    fprintf(f, "\n$EndNodes\n$Elements\n");
    put_z(f, 2), put_z(f, 3), put_z(f, 1), put_z(f, 3);
    put_i(f, 2), put_i(f, 7), put_i(f, 3), put_z(f, 1);
    put_z(f, 1);
    for (int k = 0; k < 4; ++k) put_z(f, QUAD[k]);
    put_i(f, 3), put_i(f, 1), put_i(f, 5), put_z(f, 2);
    for (int e = 0; e < 2; ++e) {
      put_z(f, 2 + e);
      for (int k = 0; k < 8; ++k) put_z(f, HEX[e][k]);
    }
    fprintf(f, "\n$EndElements\n");
  }
  fclose(f);
}

static void write_22(const char *path, int binary)
{
  FILE *f = fopen(path, "wb");
  if (!f) return;
  fprintf(f, "$MeshFormat\n2.2 %d 8\n", binary);
  if (binary) {
    put_i(f, 1);
    fputc('\n', f);
  }
  fprintf(f, "$EndMeshFormat\n%s$Nodes\n%d\n", names, NN);
  for (int i = 0; i < NN; ++i) {
    if (binary) {
      put_i(f, TAG[i]);
      for (int k = 0; k < 3; ++k) put_d(f, X[i][k]);
    } else {
      fprintf(f, "%ld %.17g %.17g %.17g\n", TAG[i], X[i][0], X[i][1], X[i][2]);
    }
  }
  fprintf(f, "%s$EndNodes\n$Elements\n3\n", binary ? "\n" : "");
  if (binary) {
    put_i(f, 3), put_i(f, 1), put_i(f, 2);
    put_i(f, 1), put_i(f, 2), put_i(f, 7);
    for (int k = 0; k < 4; ++k) put_i(f, QUAD[k]);
    put_i(f, 5), put_i(f, 2), put_i(f, 2);
    for (int e = 0; e < 2; ++e) {
      put_i(f, 2 + e), put_i(f, 1), put_i(f, 1);
      for (int k = 0; k < 8; ++k) put_i(f, HEX[e][k]);
    }
    fputc('\n', f);
  } else {
    fprintf(f, "1 3 2 2 7 %ld %ld %ld %ld\n", QUAD[0], QUAD[1], QUAD[2], QUAD[3]);
    for (int e = 0; e < 2; ++e) {
      fprintf(f, "%d 5 2 1 1", 2 + e);
      for (int k = 0; k < 8; ++k) fprintf(f, " %ld", HEX[e][k]);
      fputc('\n', f);
    }
  }
  fprintf(f, "$EndElements\n");
  fclose(f);
}

/* Two meshes the same: nodes, blocks, connectivity, sets. */
static void same(const TlMesh *a, const TlMesh *b, const char *what)
{
  TL_TEST_ASSERT(a->dim == b->dim && a->n_nodes == b->n_nodes && a->n_blocks == b->n_blocks, "%s: dim %d/%d nodes %zu/%zu blocks %d/%d",
                 what, a->dim, b->dim, a->n_nodes, b->n_nodes, a->n_blocks, b->n_blocks);
  if (a->n_nodes != b->n_nodes || a->n_blocks != b->n_blocks) return;
  int xs = memcmp(a->x, b->x, 3 * a->n_nodes * sizeof(double)) == 0;
  TL_TEST_ASSERT(xs, "%s: node coordinates differ", what);
  for (int k = 0; k < a->n_blocks; ++k) {
    const TlElementBlock *p = &a->blocks[k], *q = &b->blocks[k];
    TL_TEST_ASSERT(!strcmp(p->name, q->name) && p->type == q->type && p->n_elements == q->n_elements,
                   "%s: block %d %s/%s", what, k, p->name, q->name);
    if (p->type == q->type && p->n_elements == q->n_elements)
      TL_TEST_ASSERT(!memcmp(p->conn, q->conn, p->n_elements * (size_t)p->type->n_nodes * sizeof(size_t)),
                     "%s: block %s connectivity differs", what, p->name);
  }
  TL_TEST_ASSERT(a->n_face_sets == b->n_face_sets && a->n_node_sets == b->n_node_sets, "%s: %d/%d face sets, %d/%d node sets",
                 what, a->n_face_sets, b->n_face_sets, a->n_node_sets, b->n_node_sets);
}

static void test_written_here(void)
{
  make_mesh();
  struct {
    const char *path;
    int v2, binary, swapped;
  } files[] = {{"f41a.msh", 0, 0, 0}, {"f41b.msh", 0, 1, 0}, {"f41s.msh", 0, 1, 1}, {"f22a.msh", 1, 0, 0}, {"f22b.msh", 1, 1, 0}};
  TlMesh *ref = NULL;
  for (size_t i = 0; i < sizeof files / sizeof files[0]; ++i) {
    swap_bytes = files[i].swapped;
    if (files[i].v2)
      write_22(files[i].path, files[i].binary);
    else
      write_41(files[i].path, files[i].binary);
    swap_bytes = 0;
    TlMesh *m = NULL;
    TL_TEST_STATUS(tl_mesh_read_gmsh(files[i].path, &m), TL_OK);
    if (!m) {
      printf("%s: %s\n", files[i].path, tl_error_message());
      continue;
    }
    TL_TEST_ASSERT(m->dim == 3 && m->n_nodes == NN && m->n_blocks == 1 && !strcmp(m->blocks[0].name, "solid") &&
                       m->blocks[0].type == &tl_element_hex8 && m->blocks[0].n_elements == 2,
                   "%s: dim %d, %zu nodes, %d blocks", files[i].path, m->dim, m->n_nodes, m->n_blocks);
    TL_TEST_CLOSE(tl_mesh_volume(m), 2 * 0.5 * 0.25, 1e-14);
    const TlFaceSet *fs = NULL;
    const TlNodeSet *ns = NULL;
    TL_TEST_STATUS(tl_mesh_find_face_set(m, "left", &fs), TL_OK);
    TL_TEST_STATUS(tl_mesh_find_node_set(m, "left", &ns), TL_OK);
    TL_TEST_ASSERT(fs && fs->n == 1 && ns && ns->n == 4, "%s: face set left %zu faces, node set %zu nodes", files[i].path,
                   fs ? fs->n : 0, ns ? ns->n : 0);
    if (ns)
      for (size_t k = 0; k < ns->n; ++k) TL_TEST_ASSERT(m->x[3 * ns->nodes[k]] == 0.0, "%s: left node off x = 0", files[i].path);
    if (!ref)
      ref = m;
    else {
      same(ref, m, files[i].path);
      tl_mesh_destroy(&m);
    }
  }
  tl_mesh_destroy(&ref);

  /* A binary file cut short is refused with the byte offset. */
  FILE *f = fopen("f41b.msh", "rb");
  char buf[8192];
  size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
  if (f) fclose(f);
  char *nodes = n ? memmem(buf, n, "$Nodes\n", 7) : NULL;
  TL_TEST_ASSERT(nodes != NULL, "binary test file has a $Nodes section");
  if (nodes) {
    f = fopen("cut.msh", "wb");
    fwrite(buf, 1, (size_t)(nodes - buf) + 7 + 100, f);
    fclose(f);
    TlMesh *m = NULL;
    TL_TEST_STATUS(tl_mesh_read_gmsh("cut.msh", &m), TL_ERR_FORMAT);
    TL_TEST_ASSERT(strstr(tl_error_message(), "cut.msh byte") && strstr(tl_error_message(), "the file ends inside"),
                   "%s", tl_error_message());
  }
  /* A byte-order word that is neither 1 nor its swap. */
  f = fopen("order.msh", "wb");
  fprintf(f, "$MeshFormat\n4.1 1 8\n");
  put_i(f, 7);
  fprintf(f, "\n$EndMeshFormat\n");
  fclose(f);
  TlMesh *m = NULL;
  TL_TEST_STATUS(tl_mesh_read_gmsh("order.msh", &m), TL_ERR_FORMAT);
  TL_TEST_ASSERT(strstr(tl_error_message(), "byte-order integer reads 7"), "%s", tl_error_message());
}

/* The same layouts from the gmsh program, when installed. */
static int test_from_gmsh(void)
{
  if (system("gmsh --version > /dev/null 2>&1") != 0) {
    printf("gmsh not installed: the layouts saved by gmsh itself are not checked (the files written here are)\n");
    return 0;
  }
  FILE *f = fopen("fmt_box.geo", "w");
  if (!f) return 0;
  fprintf(f, "Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5}; Point(3) = {1, 1, 0, 0.5};\n"
             "Point(4) = {0, 1, 0, 0.5}; Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
             "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
             "Extrude {0, 0, 1} { Surface{1}; Layers{2}; Recombine; }\n"
             "Transfinite Surface{1}; Recombine Surface{1}; Transfinite Curve{1, 2, 3, 4} = 3;\n"
             "Physical Volume(\"solid\") = {1}; Physical Surface(\"bottom\") = {1};\n");
  fclose(f);
  const char *const runs[] = {"gmsh -3 -format msh41 -o g41a.msh fmt_box.geo > gmsh_fmt.log 2>&1",
                              "gmsh -3 -format msh41 -bin -o g41b.msh fmt_box.geo >> gmsh_fmt.log 2>&1",
                              "gmsh -3 -format msh22 -o g22a.msh fmt_box.geo >> gmsh_fmt.log 2>&1",
                              "gmsh -3 -format msh22 -bin -o g22b.msh fmt_box.geo >> gmsh_fmt.log 2>&1"};
  const char *const out[] = {"g41a.msh", "g41b.msh", "g22a.msh", "g22b.msh"};
  TlMesh *ref = NULL;
  for (int i = 0; i < 4; ++i) {
    int rc = system(runs[i]);
    TL_TEST_ASSERT(rc == 0, "%s failed (see gmsh_fmt.log)", runs[i]);
    TlMesh *m = NULL;
    TL_TEST_STATUS(tl_mesh_read_gmsh(out[i], &m), TL_OK);
    if (!m) {
      printf("%s: %s\n", out[i], tl_error_message());
      continue;
    }
    TL_TEST_CLOSE(tl_mesh_volume(m), 1.0, 1e-12);
    const TlFaceSet *fs = NULL;
    TL_TEST_STATUS(tl_mesh_find_face_set(m, "bottom", &fs), TL_OK);
    TL_TEST_ASSERT(fs && fs->n == 4, "%s: bottom has %zu faces (2 x 2 quads)", out[i], fs ? fs->n : 0);
    TL_TEST_ASSERT(m->n_blocks == 1 && m->blocks[0].type == &tl_element_hex8 && m->blocks[0].n_elements == 8,
                   "%s: %d blocks", out[i], m->n_blocks);
    if (!ref)
      ref = m;
    else {
      same(ref, m, out[i]);
      tl_mesh_destroy(&m);
    }
  }
  tl_mesh_destroy(&ref);
  return 1;
}

int main(void)
{
  tl_log_set_level(TL_LOG_ERROR);
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_written_here();
  test_from_gmsh();
  return tl_test_report();
}
