/* Meshes: structured generators (counts, volumes, named sets, outward face
 * normals), refusal of inverted and degenerate elements, and the Gmsh 4.1
 * reader on a file made by gmsh (checked in below) and on malformed files,
 * whose errors must name the line.  Meshes gmsh makes at test time are read
 * by test_mesh_gmsh_generated (gmsh is optional). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_mesh.h"
#include "tl_mesh_locator.h"
#include "tl_test.h"
#include "tl_test_mesh.h"

static void test_box(const TlElementType *t, size_t expect_nodes, size_t expect_elems)
{
  size_t n[3] = {3, 2, 2};
  double lo[3] = {0, -1, 0.5}, hi[3] = {3, 1, 1.5};
  TlMesh *m = NULL;
  TL_TEST_STATUS(tl_mesh_create_box(t, n, lo, hi, &m), TL_OK);
  if (!m) return;
  TL_TEST_ASSERT(m->n_nodes == expect_nodes, "%s box: %zu nodes, expected %zu", t->header.name, m->n_nodes, expect_nodes);
  TL_TEST_ASSERT(m->blocks[0].n_elements == expect_elems, "%s box: %zu elements, expected %zu", t->header.name,
                 m->blocks[0].n_elements, expect_elems);
  TL_TEST_CLOSE(tl_mesh_volume(m), 6.0, 1e-13);
  check_outward(m);
  const char *names[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
  for (int s = 0; s < 6; ++s) check_set_normal(m, names[s], s / 2, s % 2 ? 1.0 : -1.0);
  /* Boundary faces: 2 (3x2 + 3x2 + 2x2) = 32 cells' faces, times 2 for tets. */
  size_t faces = t->shape == TL_SHAPE_TET ? 64 : 32;
  TL_TEST_ASSERT(m->n_boundary == faces, "%s box: %zu boundary faces, expected %zu", t->header.name, m->n_boundary, faces);
  const TlNodeSet *ns = NULL;
  TL_TEST_STATUS(tl_mesh_find_node_set(m, "xmin", &ns), TL_OK);
  size_t p = t->n_nodes == t->n_corners ? 1 : 2;
  if (ns) TL_TEST_ASSERT(ns->n == (p * 2 + 1) * (p * 2 + 1), "%s box: xmin has %zu nodes", t->header.name, ns->n);
  TL_TEST_STATUS(tl_mesh_find_node_set(m, "nonexistent", &ns), TL_ERR_NOT_FOUND);
  TL_TEST_ASSERT(strstr(tl_error_message(), "xmin") != NULL, "lookup error lists the sets: %s", tl_error_message());
  tl_mesh_destroy(&m);
  TL_TEST_ASSERT(m == NULL, "destroy nulls");
}

static void test_rectangle(const TlElementType *t, size_t expect_nodes)
{
  size_t n[2] = {4, 3};
  double lo[2] = {0, 0}, hi[2] = {2, 1.5};
  TlMesh *m = NULL;
  TL_TEST_STATUS(tl_mesh_create_rectangle(t, n, lo, hi, &m), TL_OK);
  if (!m) return;
  TL_TEST_ASSERT(m->n_nodes == expect_nodes, "%s rectangle: %zu nodes, expected %zu", t->header.name, m->n_nodes, expect_nodes);
  TL_TEST_CLOSE(tl_mesh_volume(m), 3.0, 1e-13);
  check_outward(m);
  check_set_normal(m, "xmin", 0, -1.0);
  check_set_normal(m, "xmax", 0, 1.0);
  check_set_normal(m, "ymin", 1, -1.0);
  check_set_normal(m, "ymax", 1, 1.0);
  TL_TEST_ASSERT(m->n_boundary == 14, "%s rectangle: %zu boundary edges", t->header.name, m->n_boundary);
  tl_mesh_destroy(&m);
}

static void test_sector(const TlElementType *t)
{
  size_t n[3] = {2, 6, 1};
  double ri = 1.0, ro = 2.0, t0 = 0.1, t1 = 0.1 + M_PI / 2, h = 0.5;
  TlMesh *m = NULL;
  TL_TEST_STATUS(tl_mesh_create_cylinder_sector(t, ri, ro, t0, t1, h, n, &m), TL_OK);
  if (!m) return;
  double exact = 0.5 * (t1 - t0) * (ro * ro - ri * ri) * h;
  double V = tl_mesh_volume(m);
  if (t == &tl_element_hex8) {
    /* Straight-sided cells: the polygon area, exactly. */
    double dth = (t1 - t0) / n[1];
    double poly = 0.5 * n[1] * sin(dth) * (ro * ro - ri * ri) * h;
    TL_TEST_CLOSE(V, poly, 1e-13);
  } else {
    TL_TEST_ASSERT(fabs(V - exact) < 2e-4 * exact, "hex27 sector volume %g, exact %g", V, exact);
  }
  check_outward(m);
  check_set_normal(m, "zmin", 2, -1.0);
  check_set_normal(m, "zmax", 2, 1.0);
  /* Every node of the outer set lies on the outer radius. */
  const TlNodeSet *ns = NULL;
  TL_TEST_STATUS(tl_mesh_find_node_set(m, "outer", &ns), TL_OK);
  double err = 0.0;
  for (size_t i = 0; ns && i < ns->n; ++i) {
    const double *x = m->x + 3 * ns->nodes[i];
    err = fmax(err, fabs(hypot(x[0], x[1]) - ro));
  }
  TL_TEST_ASSERT(err < 1e-14, "outer nodes off the radius by %g", err);
  TL_TEST_STATUS(tl_mesh_create_cylinder_sector(t, 2.0, 1.0, t0, t1, h, n, &m), TL_ERR_ARG);
  tl_mesh_destroy(&m);
}

static void test_inverted(void)
{
  /* One hexahedron with two nodes swapped (inverted) and one squashed flat
   * (degenerate). */
  double x[8 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  size_t good[8] = {0, 1, 2, 3, 4, 5, 6, 7}, bad[8] = {4, 5, 6, 7, 0, 1, 2, 3};
  TlMesh *m = NULL;
  TL_TEST_STATUS(tl_mesh_create(3, &m), TL_OK);
  TL_TEST_STATUS(tl_mesh_set_nodes(m, 8, x), TL_OK);
  TL_TEST_STATUS(tl_mesh_add_block(m, "ok", &tl_element_hex8, 1, good, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_mesh_finalize(m), TL_OK);
  tl_mesh_destroy(&m);
  TL_TEST_STATUS(tl_mesh_create(3, &m), TL_OK);
  TL_TEST_STATUS(tl_mesh_set_nodes(m, 8, x), TL_OK);
  long tags[1] = {42};
  TL_TEST_STATUS(tl_mesh_add_block(m, "upside_down", &tl_element_hex8, 1, bad, tags, NULL), TL_OK);
  TL_TEST_STATUS(tl_mesh_finalize(m), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(strstr(tl_error_message(), "upside_down") && strstr(tl_error_message(), "tag 42") &&
                     strstr(tl_error_message(), "inverted"),
                 "message names block, element and problem: %s", tl_error_message());
  tl_mesh_destroy(&m);
  double flat[8 * 3];
  memcpy(flat, x, sizeof flat);
  for (int a = 4; a < 8; ++a) flat[3 * a + 2] = 0.0;
  TL_TEST_STATUS(tl_mesh_create(3, &m), TL_OK);
  TL_TEST_STATUS(tl_mesh_set_nodes(m, 8, flat), TL_OK);
  TL_TEST_STATUS(tl_mesh_add_block(m, "flat", &tl_element_hex8, 1, good, NULL, NULL), TL_OK);
  TL_TEST_STATUS(tl_mesh_finalize(m), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(strstr(tl_error_message(), "flat") && strstr(tl_error_message(), "degenerate"),
                 "message names the degenerate element: %s", tl_error_message());
  /* Bad node index. */
  size_t out_of_range[8] = {0, 1, 2, 3, 4, 5, 6, 99};
  TL_TEST_STATUS(tl_mesh_add_block(m, "oops", &tl_element_hex8, 1, out_of_range, NULL, NULL), TL_ERR_ARG);
  tl_mesh_destroy(&m);
}

/* A plane 8-node-quadrilateral mesh written by gmsh 4.8 (msh 4.1) from:
 *   Point(1..4) = corners of [0,1] x [0,0.5]; Plane Surface(1); Transfinite;
 *   Recombine; Physical Surface("plate"), Curve("bottom") = {1},
 *   Point("corner") = {1}; ElementOrder 2, SecondOrderIncomplete. */
static const char quad8_msh[] =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
    "$PhysicalNames\n3\n0 3 \"corner\"\n1 2 \"bottom\"\n2 1 \"plate\"\n$EndPhysicalNames\n"
    "$Entities\n4 4 1 0\n1 0 0 0 1 3 \n2 1 0 0 0 \n3 1 0.5 0 0 \n4 0 0.5 0 0 \n"
    "1 0 0 0 1 0 0 1 2 2 1 -2 \n2 1 0 0 1 0.5 0 0 2 2 -3 \n3 0 0.5 0 1 0.5 0 0 2 3 -4 \n"
    "4 0 0 0 0 0.5 0 0 2 4 -1 \n1 0 0 0 1 0.5 0 1 1 4 1 2 3 4 \n$EndEntities\n"
    "$Nodes\n9 21 1 21\n0 1 0 1\n1\n0 0 0\n0 2 0 1\n2\n1 0 0\n0 3 0 1\n3\n1 0.5 0\n0 4 0 1\n4\n0 0.5 0\n"
    "1 1 0 3\n5\n6\n7\n0.499999999998694 0 0\n0.2499999999994194 0 0\n0.749999999999347 0 0\n"
    "1 2 0 3\n8\n9\n10\n1 0.249999999999347 0\n1 0.1249999999997097 0\n1 0.3749999999996735 0\n"
    "1 3 0 3\n11\n12\n13\n0.5000000000020591 0.5 0\n0.7500000000009891 0.5 0\n0.2500000000010296 0.5 0\n"
    "1 4 0 3\n14\n15\n16\n0 0.2500000000010296 0\n0 0.3750000000004945 0\n0 0.1250000000005148 0\n"
    "2 1 0 5\n17\n18\n19\n20\n21\n0.5000000000003766 0.2500000000001883 0\n"
    "0.4999999999995353 0.1250000000000941 0\n0.2500000000001883 0.250000000000609 0\n"
    "0.5000000000012179 0.3750000000000941 0\n0.7500000000001883 0.2499999999997676 0\n$EndNodes\n"
    "$Elements\n3 7 1 7\n0 1 15 1\n1 1 \n1 1 8 2\n2 1 5 6 \n3 5 2 7 \n2 1 16 4\n"
    "4 1 5 17 14 6 18 19 16 \n5 14 17 11 4 19 20 13 15 \n6 5 2 8 17 7 9 21 18 \n"
    "7 17 8 3 11 21 10 12 20 \n$EndElements\n";

static void write_file(const char *path, const char *text)
{
  FILE *f = fopen(path, "w");
  if (!f) return;
  fputs(text, f);
  fclose(f);
}

/* Writes quad8_msh with `from` replaced by `to` and expects an error that
 * mentions `line` and `fragment`. */
static void malformed(const char *from, const char *to, const char *line, const char *fragment)
{
  char text[sizeof quad8_msh + 256];
  const char *at = strstr(quad8_msh, from);
  TL_TEST_ASSERT(at != NULL, "test text '%s' not found", from);
  if (!at) return;
  size_t pre = (size_t)(at - quad8_msh);
  memcpy(text, quad8_msh, pre);
  snprintf(text + pre, sizeof text - pre, "%s%s", to, at + strlen(from));
  write_file("bad.msh", text);
  TlMesh *m = NULL;
  TlStatus s = tl_mesh_read_gmsh("bad.msh", &m);
  TL_TEST_ASSERT(s == TL_ERR_FORMAT, "malformed file (%s -> %s) gave status %d", from, to, (int)s);
  TL_TEST_ASSERT(strstr(tl_error_message(), line) && strstr(tl_error_message(), fragment),
                 "message should name '%s' and '%s': %s", line, fragment, tl_error_message());
  TL_TEST_ASSERT(m == NULL, "no mesh on error");
}

static void test_gmsh_quad8(void)
{
  write_file("quad8.msh", quad8_msh);
  TlMesh *m = NULL;
  TL_TEST_STATUS(tl_mesh_read_gmsh("quad8.msh", &m), TL_OK);
  if (!m) return;
  TL_TEST_ASSERT(m->dim == 2 && m->n_nodes == 21 && m->n_blocks == 1, "dim %d nodes %zu blocks %d", m->dim,
                 m->n_nodes, m->n_blocks);
  TL_TEST_ASSERT(m->blocks[0].type == &tl_element_quad8 && !strcmp(m->blocks[0].name, "plate") &&
                     m->blocks[0].n_elements == 4,
                 "block %s of %zu %s", m->blocks[0].name, m->blocks[0].n_elements, m->blocks[0].type->header.name);
  TL_TEST_CLOSE(tl_mesh_volume(m), 0.5, 1e-12);
  check_outward(m);
  check_set_normal(m, "bottom", 1, -1.0);
  const TlFaceSet *fs = NULL;
  TL_TEST_STATUS(tl_mesh_find_face_set(m, "bottom", &fs), TL_OK);
  if (fs) TL_TEST_ASSERT(fs->n == 2, "bottom has %zu faces", fs->n);
  const TlNodeSet *ns = NULL;
  TL_TEST_STATUS(tl_mesh_find_node_set(m, "corner", &ns), TL_OK);
  if (ns) TL_TEST_ASSERT(ns->n == 1 && m->x[3 * ns->nodes[0]] == 0.0 && m->x[3 * ns->nodes[0] + 1] == 0.0, "corner node");
  TL_TEST_STATUS(tl_mesh_find_node_set(m, "bottom", &ns), TL_OK);
  if (ns) TL_TEST_ASSERT(ns->n == 5, "bottom has %zu nodes", ns->n);
  tl_mesh_destroy(&m);

  malformed("4.1 0 8", "3.0 0 8", "line 2", "version 3 is not supported");
  malformed("4.1 0 8", "2.2 0 8", "line 10", "$Entities section in a 2.2 file");
  malformed("4.1 0 8", "4.1 1 8", "byte 20", "the byte-order integer reads");
  malformed("0.4999999999995353 0.1250000000000941 0", "0.49999 abc 0", "line 71", "real number");
  malformed("4 1 5 17 14 6 18 19 16 ", "4 1 5 17 14 6 18 19 99 ", "line 84", "node 99");
  malformed("2 1 16 4", "2 1 7 4", "line 83", "element type 7");
  malformed("7 17 8 3 11 21 10 12 20 \n", "7 17 8 3 11 21 10 12\n", "line 87", "7 of 8");
  malformed("$EndNodes\n", "", "line", "$EndNodes");
  malformed("$MeshFormat\n", "MeshFormat\n", "line 1", "section header");
  TlMesh *none = NULL;
  TL_TEST_STATUS(tl_mesh_read_gmsh("no_such_file.msh", &none), TL_ERR_IO);
}

/* Point location: random points of random elements (and every node) are
 * found in an element whose map reproduces them; outside points are not;
 * a moved configuration is located after an update. */
static void test_locator(TlMesh *m)
{
  if (!m) return;
  TlMeshLocator *loc = NULL;
  TL_TEST_STATUS(tl_mesh_locator_create(m, NULL, &loc), TL_OK);
  if (!loc) return;
  const TlElementBlock *blk = &m->blocks[0];
  const TlElementType *t = blk->type;
  double worst = 0.0;
  size_t misses = 0;
  for (int k = 0; k < 200 + (int)m->n_nodes; ++k) {
    double p[3];
    if (k < 200) {
      size_t e = (size_t)rand() % blk->n_elements;
      double xi[3] = {0, 0, 0}, s = 0.0, x[TL_ELEMENT_MAX_NODES * 3];
      for (int d = 0; d < t->dim; ++d) {
        xi[d] = t->shape == TL_SHAPE_TET ? (double)rand() / RAND_MAX : 2.0 * rand() / RAND_MAX - 1.0;
        s += xi[d];
      }
      if (t->shape == TL_SHAPE_TET && s > 1.0)
        for (int d = 0; d < 3; ++d) xi[d] /= s;
      tl_mesh_element_coords(m, 0, e, x);
      tl_element_interpolate(t, x, xi, p);
    } else {
      memcpy(p, m->x + 3 * (k - 200), sizeof p);
    }
    TlFaceRef where;
    double xi[3], x[TL_ELEMENT_MAX_NODES * 3], back[3];
    if (tl_mesh_locate(loc, p, 1e-10, &where, xi) != TL_OK) {
      ++misses;
      continue;
    }
    tl_mesh_element_coords(m, where.block, where.element, x);
    tl_element_interpolate(m->blocks[where.block].type, x, xi, back);
    for (int i = 0; i < 3; ++i) worst = fmax(worst, fabs(back[i] - p[i]));
  }
  TL_TEST_ASSERT(misses == 0 && worst < 1e-12, "%s: %zu points not located, worst mismatch %g", t->header.name, misses, worst);
  double far[3] = {100.0, 0.0, 0.0};
  TlFaceRef where;
  double xi[3];
  TL_TEST_STATUS(tl_mesh_locate(loc, far, 1e-10, &where, xi), TL_ERR_NOT_FOUND);
  /* Translate the whole mesh by (1, 2, 3): the moved centroid of element 0
   * is found in element 0 after an update. */
  double *moved = malloc(3 * m->n_nodes * sizeof *moved);
  for (size_t i = 0; i < m->n_nodes; ++i)
    for (int k = 0; k < 3; ++k) moved[3 * i + k] = m->x[3 * i + k] + (m->dim == 3 || k < 2 ? k + 1.0 : 0.0);
  TL_TEST_STATUS(tl_mesh_locator_update(loc, moved), TL_OK);
  double c[3] = {0, 0, 0};
  int nc = t->n_corners;
  for (int a = 0; a < nc; ++a)
    for (int k = 0; k < 3; ++k) c[k] += moved[3 * blk->conn[a] + k] / nc;
  TL_TEST_STATUS(tl_mesh_locate(loc, c, 1e-10, &where, xi), TL_OK);
  TL_TEST_ASSERT(where.block == 0 && where.element == 0, "moved centroid found in element %zu", where.element);
  free(moved);
  tl_mesh_locator_destroy(&loc);
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  test_box(&tl_element_hex8, 4 * 3 * 3, 12);
  test_box(&tl_element_hex27, 7 * 5 * 5, 12);
  test_box(&tl_element_tet4, 4 * 3 * 3, 72);
  test_box(&tl_element_tet10, 7 * 5 * 5, 72);
  test_rectangle(&tl_element_quad4, 5 * 4);
  test_rectangle(&tl_element_quad8, 9 * 7 - 12);
  test_sector(&tl_element_hex8);
  test_sector(&tl_element_hex27);
  test_inverted();
  {
    size_t n[3] = {4, 3, 2};
    double lo[3] = {0, 0, 0}, hi[3] = {2, 1.5, 1};
    TlMesh *m = NULL;
    tl_mesh_create_box(&tl_element_tet10, n, lo, hi, &m);
    test_locator(m);
    tl_mesh_destroy(&m);
    size_t ns[3] = {2, 5, 2};
    tl_mesh_create_cylinder_sector(&tl_element_hex27, 1.0, 1.5, 0.0, 1.2, 0.4, ns, &m);
    test_locator(m);
    tl_mesh_destroy(&m);
    size_t nr[2] = {5, 3};
    double lr[2] = {0, 0}, hr[2] = {1, 0.6};
    tl_mesh_create_rectangle(&tl_element_quad8, nr, lr, hr, &m);
    test_locator(m);
    tl_mesh_destroy(&m);
  }
  test_gmsh_quad8();
  return tl_test_report();
}
