/* Surface files: ASCII and binary STL and Gmsh surfaces read into the same
 * indexed mesh; the refusals (truncated, NaN, facet of 4 corners, zero-area
 * facet, open surface where a closed one is required) naming the facet or
 * edge; repair (duplicates merged, degenerate facets removed, a flipped
 * facet reoriented, the closed surface turned outward); enclosed volume and
 * the inside test on exactly degenerate points (on a face, on an edge, on
 * a vertex, rays through edges). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "talus.h"
#include "tl_predicates.h"
#include "tl_stl.h"
#include "tl_test.h"

/* The unit cube [0, 1]^3 (scaled by s) as 12 facets, normals outward;
 * flip_one reverses facet 5. */
static void write_cube_ascii(const char *path, double s, int flip_one, const char *extra)
{
  static const int quad[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  FILE *f = fopen(path, "w");
  fprintf(f, "solid cube\n");
  int t = 0;
  for (int q = 0; q < 6; ++q)
    for (int h = 0; h < 2; ++h, ++t) {
      int c[3] = {quad[q][0], quad[q][1 + h], quad[q][2 + h]};
      if (flip_one && t == 5) {
        int a = c[1];
        c[1] = c[2], c[2] = a;
      }
      fprintf(f, "facet normal 0 0 0\n outer loop\n");
      for (int k = 0; k < 3; ++k)
        fprintf(f, "  vertex %g %g %g\n", s * (c[k] & 1), s * ((c[k] >> 1) & 1), s * ((c[k] >> 2) & 1));
      fprintf(f, " endloop\nendfacet\n");
    }
  if (extra) fputs(extra, f);
  fprintf(f, "endsolid cube\n");
  fclose(f);
}

static void write_text(const char *path, const char *text)
{
  FILE *f = fopen(path, "w");
  fputs(text, f);
  fclose(f);
}

static void expect_refusal(const char *path, int closed, const char *needle)
{
  TlSurfaceMesh *m = NULL;
  TlStatus s = tl_surface_mesh_read(path, &m);
  if (s == TL_OK) s = tl_surface_mesh_check(m, closed ? TL_SURFACE_CLOSED : 0);
  TL_TEST_ASSERT(s != TL_OK, "%s accepted", path);
  TL_TEST_ASSERT(strstr(tl_error_message(), needle) != NULL, "%s: message lacks '%s': %s", path, needle,
                 tl_error_message());
  tl_surface_mesh_destroy(&m);
  tl_error_clear();
}

static void test_ascii_binary(void)
{
  write_cube_ascii("cube.stl", 2.0, 0, NULL);
  TlSurfaceMesh *m = NULL;
  TL_TEST_STATUS(tl_stl_read("cube.stl", &m), TL_OK);
  if (!m) return;
  TL_TEST_ASSERT(m->n_vertices == 8 && m->n_triangles == 12, "cube: %zu vertices, %zu triangles", m->n_vertices,
                 m->n_triangles);
  TL_TEST_ASSERT(strcmp(m->name, "cube") == 0, "name '%s'", m->name);
  TL_TEST_STATUS(tl_surface_mesh_check(m, TL_SURFACE_CLOSED), TL_OK);
  TL_TEST_ASSERT(tl_surface_mesh_is_closed(m), "cube closed");
  double v = 0;
  TL_TEST_STATUS(tl_surface_mesh_volume(m, &v), TL_OK);
  TL_TEST_CLOSE(v, 8.0, 1e-14);
  TL_TEST_CLOSE(tl_surface_mesh_area(m), 24.0, 1e-14);
  /* binary round trip: same mesh */
  TL_TEST_STATUS(tl_stl_write("cube_bin.stl", m, 1), TL_OK);
  TlSurfaceMesh *b = NULL;
  TL_TEST_STATUS(tl_surface_mesh_read("cube_bin.stl", &b), TL_OK);
  if (b) {
    TL_TEST_ASSERT(b->n_vertices == 8 && b->n_triangles == 12, "binary cube: %zu, %zu", b->n_vertices, b->n_triangles);
    int same = 1;
    for (size_t t = 0; t < 12; ++t)
      for (int k = 0; k < 3; ++k)
        same &= tl_v3_norm(tl_v3_sub(b->x[b->tri[t][k]], m->x[m->tri[t][k]])) == 0.0;
    TL_TEST_ASSERT(same, "binary facets are the ASCII facets");
    /* truncated binary: the facet it ends in is named */
    FILE *f = fopen("cube_bin.stl", "rb");
    unsigned char buf[1024];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    TL_TEST_ASSERT(n == 84 + 12 * 50, "binary size %zu", n);
    TlSurfaceMesh *c = NULL;
    TL_TEST_STATUS(tl_stl_read_memory(buf, 84 + 7 * 50 + 20, "cut", &c), TL_ERR_FORMAT);
    TL_TEST_ASSERT(strstr(tl_error_message(), "truncated in facet 7"), "message: %s", tl_error_message());
    /* NaN in binary facet 3, vertex 1 */
    float nan = NAN;
    memcpy(buf + 84 + 3 * 50 + 12 + 12 + 4, &nan, 4);
    TL_TEST_STATUS(tl_stl_read_memory(buf, n, "nan", &c), TL_ERR_FORMAT);
    TL_TEST_ASSERT(strstr(tl_error_message(), "facet 3, vertex 1"), "message: %s", tl_error_message());
    tl_error_clear();
  }
  /* ASCII and ASCII write round trip */
  TL_TEST_STATUS(tl_stl_write("cube_ascii.stl", m, 0), TL_OK);
  TlSurfaceMesh *a = NULL;
  TL_TEST_STATUS(tl_stl_read("cube_ascii.stl", &a), TL_OK);
  if (a) TL_TEST_ASSERT(a->n_vertices == 8 && a->n_triangles == 12, "ascii round trip");
  tl_surface_mesh_destroy(&a);
  tl_surface_mesh_destroy(&b);
  tl_surface_mesh_destroy(&m);
}

static void test_refusals(void)
{
  write_text("truncated.stl", "solid t\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n");
  expect_refusal("truncated.stl", 0, "truncated in facet 0");
  write_text("nan.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
                        "endfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 nan 0\nvertex 0 1 0\nendloop\n"
                        "endfacet\nendsolid\n");
  expect_refusal("nan.stl", 0, "facet 1, vertex 1");
  write_text("quad.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\n"
                         "endloop\nendfacet\nendsolid\n");
  expect_refusal("quad.stl", 0, "facet 0 (line 6) has more than 3 vertices");
  write_text("word.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 x 0\n");
  expect_refusal("word.stl", 0, "'x' is not a number");
  /* zero area: a facet with collinear corners after the 12 of the cube */
  write_cube_ascii("sliver.stl", 1.0, 0,
                   "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0.5 0 0\nvertex 1 0 0\nendloop\nendfacet\n");
  expect_refusal("sliver.stl", 0, "facet 12 has zero area");
  write_cube_ascii("repeat.stl", 1.0, 0,
                   "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n");
  expect_refusal("repeat.stl", 0, "facet 12 has zero area");
  /* open: the cube without its last facet */
  FILE *f = fopen("open.stl", "w");
  fprintf(f, "solid open\n");
  double tri[2][3][3] = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {0, 1, 0}}};
  for (int t = 0; t < 2; ++t) {
    fprintf(f, "facet normal 0 0 1\nouter loop\n");
    for (int k = 0; k < 3; ++k) fprintf(f, "vertex %g %g %g\n", tri[t][k][0], tri[t][k][1], tri[t][k][2]);
    fprintf(f, "endloop\nendfacet\n");
  }
  fprintf(f, "endsolid\n");
  fclose(f);
  expect_refusal("open.stl", 1, "open where a closed one is required: boundary edge");
  TlSurfaceMesh *m = NULL;
  TL_TEST_STATUS(tl_stl_read("open.stl", &m), TL_OK);
  if (m) {
    TL_TEST_STATUS(tl_surface_mesh_check(m, 0), TL_OK); /* an open floor is a valid wall */
    TL_TEST_ASSERT(!tl_surface_mesh_is_closed(m), "open");
    double v;
    TL_TEST_STATUS(tl_surface_mesh_volume(m, &v), TL_ERR_ARG);
  }
  tl_surface_mesh_destroy(&m);
  /* non-manifold: three facets on one edge */
  write_text("fin.stl", "solid fin\n"
                        "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
                        "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 0 0\nvertex 0 -1 0\nendloop\nendfacet\n"
                        "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
                        "endsolid\n");
  expect_refusal("fin.stl", 0, "edge (0, 1) is non-manifold: shared by 3 facets (0, 1, 2)");
  write_text("empty.stl", "");
  expect_refusal("empty.stl", 0, "empty STL");
  expect_refusal("no_such_file.stl", 0, "cannot open");
}

static void test_repair(void)
{
  if (!tl_predicates_use_cgal()) {
    TlSurfaceMesh *m = NULL;
    write_cube_ascii("flip.stl", 1.0, 1, NULL);
    TL_TEST_STATUS(tl_stl_read("flip.stl", &m), TL_OK);
    if (m) TL_TEST_STATUS(tl_surface_mesh_repair(m, NULL, NULL), TL_ERR_UNSUPPORTED);
    tl_surface_mesh_destroy(&m);
    return;
  }
  /* one facet flipped, and a zero-area facet and a duplicate facet added */
  write_cube_ascii("flip.stl", 1.0, 1,
                   "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0.5 0 0\nvertex 1 0 0\nendloop\nendfacet\n"
                   "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\n");
  TlSurfaceMesh *m = NULL;
  TL_TEST_STATUS(tl_stl_read("flip.stl", &m), TL_OK);
  if (!m) return;
  TL_TEST_STATUS(tl_surface_mesh_check(m, 0), TL_ERR_NUMERIC);
  tl_error_clear();
  /* inward orientation asked for: the container seen from inside */
  TlSurfaceRepairOptions o;
  tl_surface_repair_options_default(&o);
  o.outward = 0;
  TlSurfaceReport r;
  TL_TEST_STATUS(tl_surface_mesh_repair(m, &o, &r), TL_OK);
  printf("repair: merged %zu, removed %zu, flipped %zu, split %zu, holes %zu, closed %d, volume %g\n", r.vertices_merged,
         r.triangles_removed, r.triangles_flipped, r.vertices_split, r.holes, r.closed, r.volume);
  TL_TEST_ASSERT(m->n_triangles == 12, "12 triangles after repair, got %zu", m->n_triangles);
  TL_TEST_ASSERT(r.triangles_removed == 2, "2 removed, got %zu", r.triangles_removed);
  TL_TEST_ASSERT(r.closed && r.holes == 0, "closed after repair");
  TL_TEST_CLOSE(r.volume, -1.0, 1e-14); /* inward: negative */
  TL_TEST_STATUS(tl_surface_mesh_check(m, TL_SURFACE_CLOSED), TL_OK);
  o.outward = 1;
  TL_TEST_STATUS(tl_surface_mesh_repair(m, &o, &r), TL_OK);
  TL_TEST_CLOSE(r.volume, 1.0, 1e-14);
  TL_TEST_ASSERT(r.triangles_flipped == 12, "all 12 reversed to face out, got %zu", r.triangles_flipped);
  tl_surface_mesh_destroy(&m);

  /* holes named */
  write_cube_ascii("holed.stl", 1.0, 0, NULL);
  TL_TEST_STATUS(tl_stl_read("holed.stl", &m), TL_OK);
  if (!m) return;
  m->n_triangles = 10; /* the last face (x = 1) missing: a hole of 4 edges */
  TL_TEST_STATUS(tl_surface_mesh_repair(m, NULL, &r), TL_OK);
  TL_TEST_ASSERT(!r.closed && r.holes == 1 && r.boundary_edges == 4, "holes %zu, boundary edges %zu", r.holes,
                 r.boundary_edges);
  TL_TEST_ASSERT(strstr(r.first_hole, "hole of 4 edges"), "hole named: '%s'", r.first_hole);
  tl_surface_mesh_destroy(&m);

  /* a cap (an angle of 180 - 2e-7 degrees) on the border of a flat floor is
   * removed, leaving a notch of its area */
  double x[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 1e-9, 0};
  int tri[] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
  TL_TEST_STATUS(tl_surface_mesh_create(5, x, 4, tri, &m), TL_OK);
  TL_TEST_STATUS(tl_surface_mesh_check(m, 0), TL_ERR_NUMERIC);
  TL_TEST_ASSERT(strstr(tl_error_message(), "facet 0") && strstr(tl_error_message(), "cap"), "%s", tl_error_message());
  tl_error_clear();
  TL_TEST_STATUS(tl_surface_mesh_repair(m, NULL, &r), TL_OK);
  TL_TEST_STATUS(tl_surface_mesh_check(m, 0), TL_OK);
  double area = tl_surface_mesh_area(m);
  TL_TEST_ASSERT(area <= 1.0 && area >= 1.0 - 1e-9, "area %.17g", area);
  TL_TEST_ASSERT(r.triangles_removed == 1, "removed %zu", r.triangles_removed);
  tl_surface_mesh_destroy(&m);
}

static void test_contains(void)
{
  write_cube_ascii("cube1.stl", 1.0, 0, NULL);
  TlSurfaceMesh *m = NULL;
  TL_TEST_STATUS(tl_stl_read("cube1.stl", &m), TL_OK);
  if (!m) return;
  struct {
    TlVec3 p;
    int want;
  } cases[] = {
      {{0.5, 0.5, 0.5}, 1},     /* centre: axis rays would cross diagonals of the faces */
      {{0.25, 0.25, 0.25}, 1},  /* on the plane x = y = z of the diagonals */
      {{1e-300, 0.5, 0.5}, 1},  /* a hair inside */
      {{-1e-300, 0.5, 0.5}, 0}, /* a hair outside */
      {{0.0, 0.5, 0.5}, -1},    /* on a face */
      {{0.0, 0.0, 0.5}, -1},    /* on an edge */
      {{1.0, 1.0, 1.0}, -1},    /* on a vertex */
      {{0.5, 0.5, 1.5}, 0},     /* above */
      {{2.0, 2.0, 2.0}, 0},     /* outside the box */
      {{1.0, 0.5, 1.0 + 2.3e-16}, 0}, /* one ulp above an edge */
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
    int in = 7;
    TL_TEST_STATUS(tl_surface_mesh_contains(m, cases[k].p, &in), TL_OK);
    TL_TEST_ASSERT(in == cases[k].want, "point %zu (%g, %g, %g): %d, want %d", k, cases[k].p.x, cases[k].p.y,
                   cases[k].p.z, in, cases[k].want);
  }
  /* scaled, rotated and placed: volume and inside follow */
  TL_TEST_STATUS(tl_surface_mesh_transform(m, 3.0, tl_m3_rotation(tl_v3(1, 1, 0), 0.7), tl_v3(10, -5, 2)), TL_OK);
  double v = 0;
  TL_TEST_STATUS(tl_surface_mesh_volume(m, &v), TL_OK);
  TL_TEST_CLOSE(v, 27.0, 1e-12);
  int in = 0;
  TlVec3 c = tl_v3_add(tl_m3_mulv(tl_m3_rotation(tl_v3(1, 1, 0), 0.7), tl_v3(1.5, 1.5, 1.5)), tl_v3(10, -5, 2));
  TL_TEST_STATUS(tl_surface_mesh_contains(m, c, &in), TL_OK);
  TL_TEST_ASSERT(in == 1, "moved centre inside");
  TlMat3 reflect = tl_m3_identity();
  reflect.m[0][0] = -1;
  TL_TEST_STATUS(tl_surface_mesh_transform(m, 1.0, reflect, tl_v3(0, 0, 0)), TL_ERR_ARG);
  TL_TEST_STATUS(tl_surface_mesh_transform(m, -1.0, tl_m3_identity(), tl_v3(0, 0, 0)), TL_ERR_ARG);
  tl_error_clear();
  tl_surface_mesh_destroy(&m);
}

static void test_gmsh(void)
{
  /* a tetrahedron's surface in 4.1 (with a line element and an unused node)
   * and 2.2 */
  write_text("tet41.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 5 1 50\n2 1 0 5\n10\n20\n30\n40\n50\n"
                          "0 0 0\n1 0 0\n0 1 0\n0 0 1\n9 9 9\n$EndNodes\n$Elements\n2 5 1 5\n1 1 1 1\n1 10 20\n"
                          "2 1 2 4\n2 10 30 20\n3 10 20 40\n4 20 30 40\n5 30 10 40\n$EndElements\n");
  TlSurfaceMesh *m = NULL;
  TL_TEST_STATUS(tl_surface_mesh_read("tet41.msh", &m), TL_OK);
  if (m) {
    TL_TEST_ASSERT(m->n_vertices == 4 && m->n_triangles == 4, "tet 4.1: %zu, %zu", m->n_vertices, m->n_triangles);
    double v = 0;
    TL_TEST_STATUS(tl_surface_mesh_volume(m, &v), TL_OK);
    TL_TEST_CLOSE(v, 1.0 / 6.0, 1e-15);
  }
  tl_surface_mesh_destroy(&m);
  write_text("tet22.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                          "$EndNodes\n$Elements\n4\n1 2 2 0 1 1 3 2\n2 2 2 0 1 1 2 4\n3 2 2 0 1 2 3 4\n4 2 2 0 1 3 1 4\n"
                          "$EndElements\n");
  TL_TEST_STATUS(tl_gmsh_surface_read("tet22.msh", &m), TL_OK);
  if (m) TL_TEST_STATUS(tl_surface_mesh_check(m, TL_SURFACE_CLOSED), TL_OK);
  tl_surface_mesh_destroy(&m);
  write_text("bad.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                        "$Elements\n1\n1 2 2 0 1 1 2 7\n$EndElements\n");
  expect_refusal("bad.msh", 0, "triangle 0 uses node 7");
}

int main(void)
{
  if (tl_initialize() != TL_OK) return 1;
  tl_log_set_level(TL_LOG_ERROR);
  test_ascii_binary();
  test_refusals();
  test_repair();
  test_contains();
  test_gmsh();

  return tl_test_report();
}
