/* Structured meshes: boxes, rectangles and hollow-cylinder sectors, built
 * on a grid of p * n + 1 points per direction (p = 1 for linear, 2 for
 * quadratic elements) mapped from the unit cube. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_mesh.h"

typedef void (*GridMap)(const double u[3], const void *ctx, double x[3]);

typedef struct {
  double lo[3], hi[3];
} BoxMap;

static void box_map(const double u[3], const void *ctx, double x[3])
{
  const BoxMap *b = ctx;
  for (int i = 0; i < 3; ++i) x[i] = b->lo[i] + u[i] * (b->hi[i] - b->lo[i]);
}

typedef struct {
  double r_in, r_out, theta0, theta1, height;
} SectorMap;

static void sector_map(const double u[3], const void *ctx, double x[3])
{
  const SectorMap *s = ctx;
  double r = s->r_in + u[0] * (s->r_out - s->r_in);
  double t = s->theta0 + u[1] * (s->theta1 - s->theta0);
  x[0] = r * cos(t);
  x[1] = r * sin(t);
  x[2] = u[2] * s->height;
}

static int type_degree(const TlElementType *t)
{
  return t->linear ? 1 : 2;
}

static double tet_volume(const double *x, const size_t *c)
{
  double a[3], b[3], d[3];
  for (int i = 0; i < 3; ++i) {
    a[i] = x[3 * c[1] + i] - x[3 * c[0] + i];
    b[i] = x[3 * c[2] + i] - x[3 * c[0] + i];
    d[i] = x[3 * c[3] + i] - x[3 * c[0] + i];
  }
  return a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
         a[2] * (b[0] * d[1] - b[1] * d[0]);
}

static TlStatus structured(const TlElementType *type, int dim, const size_t n_in[3], GridMap map,
                           const void *ctx, const char *const names[6], TlMesh **out)
{
  int tensor = type->shape == TL_SHAPE_HEX || type->shape == TL_SHAPE_QUAD;
  if (type->dim != dim || !(tensor || type->shape == TL_SHAPE_TET))
    TL_ERROR(TL_ERR_ARG, "structured %d-D mesh: element type %s is not supported", dim,
             type->header.name);
  size_t n[3] = {n_in[0], n_in[1], dim == 3 ? n_in[2] : 1};
  for (int d = 0; d < dim; ++d)
    if (n[d] < 1 || n[d] > 100000)
      TL_ERROR(TL_ERR_ARG, "structured mesh: %zu cells in direction %d, expected 1 to 100000", n[d],
               d);
  int p = type_degree(type);
  size_t np[3] = {p * n[0] + 1, p * n[1] + 1, dim == 3 ? p * n[2] + 1 : 1};
  size_t n_grid = np[0] * np[1] * np[2];
  size_t cells = n[0] * n[1] * n[2];
  size_t per_cell = tensor ? 1 : 6;
  size_t n_el = cells * per_cell, nn = type->n_nodes;
  TlStatus s = TL_OK;
  double *x = NULL;
  size_t *conn = NULL, *renum = NULL, *nodes = NULL;
  int *grid_ijk = NULL;
  TlMesh *mesh = NULL;
  TlFaceRef *faces = NULL;
  TL_CHECK_GOTO(s, tl_calloc(&x, 3 * n_grid, sizeof(double)), done);
  TL_CHECK_GOTO(s, tl_calloc(&conn, n_el * nn, sizeof(size_t)), done);
  TL_CHECK_GOTO(s, tl_calloc(&renum, n_grid, sizeof(size_t)), done);
  for (size_t k = 0; k < np[2]; ++k)
    for (size_t j = 0; j < np[1]; ++j)
      for (size_t i = 0; i < np[0]; ++i) {
        size_t g = i + np[0] * (j + np[1] * k);
        double u[3] = {(double)i / (np[0] - 1), (double)j / (np[1] - 1),
                       np[2] > 1 ? (double)k / (np[2] - 1) : 0.0};
        map(u, ctx, x + 3 * g);
        if (dim == 2) x[3 * g + 2] = 0.0;
      }
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  static const int tet_edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
  size_t el = 0;
  for (size_t ck = 0; ck < n[2]; ++ck)
    for (size_t cj = 0; cj < n[1]; ++cj)
      for (size_t ci = 0; ci < n[0]; ++ci) {
        size_t base[3] = {p * ci, p * cj, p * ck};
        if (tensor) {
          for (size_t a = 0; a < nn; ++a) {
            size_t idx[3] = {base[0], base[1], base[2]};
            for (int d = 0; d < dim; ++d)
              idx[d] += (size_t)lround((type->ref_coords[a * dim + d] + 1.0) * 0.5 * p);
            conn[el * nn + a] = idx[0] + np[0] * (idx[1] + np[1] * idx[2]);
          }
          ++el;
          continue;
        }
        for (int t = 0; t < 6; ++t) {
          size_t cidx[4][3];
          int off[3] = {0, 0, 0};
          for (int v = 0; v < 4; ++v) {
            if (v > 0 && v < 3) off[perms[t][v - 1]] = 1;
            if (v == 3) off[0] = off[1] = off[2] = 1;
            for (int d = 0; d < 3; ++d) cidx[v][d] = base[d] + p * off[d];
          }
          size_t *c = conn + el * nn;
          for (int v = 0; v < 4; ++v) c[v] = cidx[v][0] + np[0] * (cidx[v][1] + np[1] * cidx[v][2]);
          if (tet_volume(x, c) < 0.0) {
            size_t tmp[3];
            memcpy(tmp, cidx[1], sizeof tmp);
            memcpy(cidx[1], cidx[2], sizeof tmp);
            memcpy(cidx[2], tmp, sizeof tmp);
            for (int v = 0; v < 4; ++v)
              c[v] = cidx[v][0] + np[0] * (cidx[v][1] + np[1] * cidx[v][2]);
          }
          if (nn == 10)
            for (int e = 0; e < 6; ++e) {
              size_t m[3];
              for (int d = 0; d < 3; ++d)
                m[d] = (cidx[tet_edges[e][0]][d] + cidx[tet_edges[e][1]][d]) / 2;
              c[4 + e] = m[0] + np[0] * (m[1] + np[1] * m[2]);
            }
          ++el;
        }
      }
  /* Drop grid points no element uses (cell centres of serendipity quads). */
  for (size_t i = 0; i < n_el * nn; ++i) renum[conn[i]] = 1;
  size_t used = 0;
  TL_CHECK_GOTO(s, tl_calloc(&grid_ijk, 3 * n_grid, sizeof(int)), done);
  for (size_t g = 0; g < n_grid; ++g) {
    if (!renum[g]) {
      renum[g] = SIZE_MAX;
      continue;
    }
    renum[g] = used;
    memmove(x + 3 * used, x + 3 * g, 3 * sizeof(double));
    size_t i = g % np[0], j = (g / np[0]) % np[1], k = g / (np[0] * np[1]);
    grid_ijk[3 * used + 0] = i == 0 ? -1 : (i == np[0] - 1 ? 1 : 0);
    grid_ijk[3 * used + 1] = j == 0 ? -1 : (j == np[1] - 1 ? 1 : 0);
    grid_ijk[3 * used + 2] = dim == 2 ? 0 : (k == 0 ? -1 : (k == np[2] - 1 ? 1 : 0));
    ++used;
  }
  for (size_t i = 0; i < n_el * nn; ++i) conn[i] = renum[conn[i]];
  TL_CHECK_GOTO(s, tl_mesh_create(dim, &mesh), done);
  TL_CHECK_GOTO(s, tl_mesh_set_nodes(mesh, used, x), done);
  TL_CHECK_GOTO(s, tl_mesh_add_block(mesh, "body", type, n_el, conn, NULL, NULL), done);
  TL_CHECK_GOTO(s, tl_mesh_finalize(mesh), done);
  /* Face sets: boundary faces whose nodes all lie on one side of the grid. */
  TL_CHECK_GOTO(s, tl_calloc(&faces, mesh->n_boundary ? mesh->n_boundary : 1, sizeof *faces), done);
  for (int side = 0; side < 2 * dim; ++side) {
    int d = side / 2, sign = side % 2 ? 1 : -1;
    size_t nf = 0;
    for (size_t b = 0; b < mesh->n_boundary; ++b) {
      size_t fn[TL_ELEMENT_MAX_FACE_NODES];
      tl_mesh_face_nodes(mesh, mesh->boundary[b], fn, NULL);
      int all = 1;
      for (int k = 0; k < type->face_n_nodes; ++k) all &= grid_ijk[3 * fn[k] + d] == sign;
      if (all) faces[nf++] = mesh->boundary[b];
    }
    TL_CHECK_GOTO(s, tl_mesh_add_face_set(mesh, names[side], nf, faces), done);
    TL_CHECK_GOTO(s, tl_mesh_add_node_set_from_faces(mesh, names[side], names[side]), done);
  }
  *out = mesh;
  mesh = NULL;
done:
  tl_mesh_destroy(&mesh);
  tl_free(&x);
  tl_free(&conn);
  tl_free(&renum);
  tl_free(&nodes);
  tl_free(&grid_ijk);
  tl_free(&faces);
  return s;
}

static const char *const box_names[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};

TlStatus tl_mesh_create_box(const TlElementType *type, const size_t n[3], const double lo[3],
                            const double hi[3], TlMesh **mesh)
{
  BoxMap b;
  for (int i = 0; i < 3; ++i) {
    if (!(hi[i] > lo[i]))
      TL_ERROR(TL_ERR_ARG, "box: hi[%d] = %g must exceed lo[%d] = %g", i, hi[i], i, lo[i]);
    b.lo[i] = lo[i], b.hi[i] = hi[i];
  }
  TL_CHECK(structured(type, 3, n, box_map, &b, box_names, mesh));
  return TL_OK;
}

TlStatus tl_mesh_create_rectangle(const TlElementType *type, const size_t n[2], const double lo[2],
                                  const double hi[2], TlMesh **mesh)
{
  BoxMap b = {{lo[0], lo[1], 0.0}, {hi[0], hi[1], 0.0}};
  for (int i = 0; i < 2; ++i)
    if (!(hi[i] > lo[i]))
      TL_ERROR(TL_ERR_ARG, "rectangle: hi[%d] = %g must exceed lo[%d] = %g", i, hi[i], i, lo[i]);
  size_t n3[3] = {n[0], n[1], 1};
  TL_CHECK(structured(type, 2, n3, box_map, &b, box_names, mesh));
  return TL_OK;
}

TlStatus tl_mesh_create_cylinder_sector(const TlElementType *type, double r_in, double r_out,
                                        double theta0, double theta1, double height,
                                        const size_t n[3], TlMesh **mesh)
{
  if (!(r_in > 0.0 && r_out > r_in))
    TL_ERROR(TL_ERR_ARG, "cylinder sector: radii r_in = %g, r_out = %g must satisfy 0 < r_in < r_out",
             r_in, r_out);
  if (!(theta1 > theta0 && theta1 - theta0 < 2.0 * M_PI))
    TL_ERROR(TL_ERR_ARG, "cylinder sector: angles [%g, %g] rad must increase by less than 2 pi",
             theta0, theta1);
  if (!(height > 0.0)) TL_ERROR(TL_ERR_ARG, "cylinder sector: height %g must be > 0", height);
  if (type->shape != TL_SHAPE_HEX)
    TL_ERROR(TL_ERR_ARG, "cylinder sector: element type %s is not a hexahedron", type->header.name);
  SectorMap m = {r_in, r_out, theta0, theta1, height};
  static const char *const names[6] = {"inner", "outer", "theta0", "theta1", "zmin", "zmax"};
  TL_CHECK(structured(type, 3, n, sector_map, &m, names, mesh));
  return TL_OK;
}
