#include "tl_cantilever.h"

#include <math.h>
#include <string.h>

#include "tl_memory.h"

void tl_cantilever_params_default(TlCantileverParams *p)
{
  p->type = &tl_element_hex8;
  p->nx = 2;
  p->ny = 30;
  p->nz = 2;
  p->b = 0.8;
  p->h = 0.8;
  p->L = 12.0;
  p->E = 1e8;
  p->nu = 0.0;
  p->rho = 1309.0;
  p->load = 1644.0;
  p->material = "hooke";
  p->mesh_file = NULL;
}

static double tip_amplitude(double t, void *ctx)
{
  (void)t;
  return ((const TlCantilever *)ctx)->load_scale;
}

/* 1-D consistent weight of a face node at coordinate s on n cells of size
 * d starting at s0 (linear: d/2 per adjacent cell; quadratic: Simpson d/6
 * at cell ends, 4d/6 at mid-points). */
static double weight_1d(double s, double s0, double d, size_t n, int quadratic)
{
  double r = (s - s0) / d;
  long i = lround(quadratic ? 2.0 * r : r);
  if (quadratic && (i % 2)) return 4.0 * d / 6.0;
  long cell = quadratic ? i / 2 : i;
  int adjacent = (cell > 0) + (cell < (long)n);
  return adjacent * (quadratic ? d / 6.0 : d / 2.0);
}

/* Consistent weights w_a = (1/A) \int_ymax N_a dA of the nodes of face set
 * "ymax" (any face type: the face's shape functions and a Gauss rule). */
static TlStatus tip_weights_from_faces(TlCantilever *c, const char *path)
{
  const TlMesh *m = c->mesh;
  const TlFaceSet *fs = NULL;
  TlStatus s = tl_mesh_find_face_set(m, "ymax", &fs);
  if (s != TL_OK || fs->n == 0)
    TL_ERROR(TL_ERR_ARG, "mesh %s has no face set \"ymax\"%s (a physical surface on y = L carrying the tip load)",
             path, s == TL_OK ? " with faces" : "");
  double *w = NULL, area = 0.0;
  char *on = NULL;
  TL_CHECK(tl_calloc(&w, m->n_nodes, sizeof *w));
  TL_CHECK_GOTO(s, tl_calloc(&on, m->n_nodes, 1), done);
  for (size_t f = 0; f < fs->n; ++f) {
    const TlElementType *ft = m->blocks[fs->faces[f].block].type->face_type;
    size_t nodes[TL_ELEMENT_MAX_FACE_NODES];
    double x[3 * TL_ELEMENT_MAX_FACE_NODES];
    tl_mesh_face_nodes(m, fs->faces[f], nodes, x);
    TlQuadrature q;
    TL_CHECK_GOTO(s, tl_element_quadrature(ft, ft->order_mass, &q), done);
    double N[TL_ELEMENT_MAX_FACE_NODES], dN[2 * TL_ELEMENT_MAX_FACE_NODES];
    for (int g = 0; g < q.n; ++g) {
      ft->eval(1, q.xi[g], N, dN);
      double t[2][3] = {{0, 0, 0}, {0, 0, 0}};
      for (int a = 0; a < ft->n_nodes; ++a)
        for (int d = 0; d < 2; ++d)
          for (int i = 0; i < 3; ++i) t[d][i] += dN[2 * a + d] * x[3 * a + i];
      double nx = t[0][1] * t[1][2] - t[0][2] * t[1][1], ny = t[0][2] * t[1][0] - t[0][0] * t[1][2],
             nz = t[0][0] * t[1][1] - t[0][1] * t[1][0], dA = sqrt(nx * nx + ny * ny + nz * nz) * q.w[g];
      for (int a = 0; a < ft->n_nodes; ++a) {
        w[nodes[a]] += N[a] * dA;
        on[nodes[a]] = 1;
      }
      area += dA;
    }
  }
  size_t n = 0;
  for (size_t i = 0; i < m->n_nodes; ++i) n += on[i];
  TL_CHECK_GOTO(s, tl_calloc(&c->tip_nodes, n ? n : 1, sizeof *c->tip_nodes), done);
  TL_CHECK_GOTO(s, tl_calloc(&c->tip_weight, n ? n : 1, sizeof *c->tip_weight), done);
  c->n_tip = 0;
  for (size_t i = 0; i < m->n_nodes; ++i)
    if (on[i]) {
      c->tip_nodes[c->n_tip] = i;
      c->tip_weight[c->n_tip++] = w[i] / area;
    }
  if (!(fabs(area - c->p.b * c->p.h) <= 1e-9 * c->p.b * c->p.h))
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                     "mesh %s: the ymax faces have an area %.10g m^2, not the section b h = %g x %g m", path, area,
                     c->p.b, c->p.h);
done:
  tl_free(&w);
  tl_free(&on);
  return s;
}

/* The beam from a Gmsh file: it must span the beam the references
 * describe. */
static TlStatus read_beam(TlCantilever *c, const char *path)
{
  const TlCantileverParams *p = &c->p;
  TL_CHECK(tl_mesh_read_gmsh(path, &c->mesh));
  const TlMesh *m = c->mesh;
  if (m->dim != 3) TL_ERROR(TL_ERR_ARG, "mesh %s is %d-D: the cantilever needs a 3-D mesh", path, m->dim);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (size_t i = 0; i < m->n_nodes; ++i)
    for (int d = 0; d < 3; ++d) {
      lo[d] = fmin(lo[d], m->x[3 * i + d]);
      hi[d] = fmax(hi[d], m->x[3 * i + d]);
    }
  const double want_lo[3] = {-0.5 * p->b, 0.0, -0.5 * p->h}, want_hi[3] = {0.5 * p->b, p->L, 0.5 * p->h};
  for (int d = 0; d < 3; ++d)
    if (!(fabs(lo[d] - want_lo[d]) <= 1e-9 * p->L && fabs(hi[d] - want_hi[d]) <= 1e-9 * p->L))
      TL_ERROR(TL_ERR_ARG, "mesh %s spans [%g, %g] m along %c, the beam (-width %g, -length %g, -height %g m) "
               "[%g, %g] m: the references need the beam's dimensions",
               path, lo[d], hi[d], "xyz"[d], p->b, p->L, p->h, want_lo[d], want_hi[d]);
  return TL_OK;
}

TlStatus tl_cantilever_create(const TlCantileverParams *p, TlCantilever **out)
{
  if (p->mesh_file && p->mesh_file[0]) {
    TlCantilever *c = NULL;
    TlStatus s = TL_OK;
    *out = NULL;
    TL_CHECK(TL_NEW(c));
    c->p = *p;
    c->load_scale = 1.0;
    TL_CHECK_GOTO(s, read_beam(c, p->mesh_file), fail_file);
    c->p.type = c->mesh->blocks[0].type;
    TL_CHECK_GOTO(s, tl_material_create(p->material ? p->material : "hooke", &c->material), fail_file);
    TL_CHECK_GOTO(s, tl_material_set(c->material, "E", p->E), fail_file);
    TL_CHECK_GOTO(s, tl_material_set(c->material, "nu", p->nu), fail_file);
    TL_CHECK_GOTO(s, tl_material_set(c->material, "density", p->rho), fail_file);
    TL_CHECK_GOTO(s, tl_material_setup(c->material), fail_file);
    TL_CHECK_GOTO(s, tl_solid_create(c->mesh, &c->solid), fail_file);
    TL_CHECK_GOTO(s, tl_solid_set_material(c->solid, NULL, c->material), fail_file);
    const TlNodeSet *fixed = NULL;
    if (tl_mesh_find_node_set(c->mesh, "ymin", &fixed) != TL_OK || fixed->n == 0) {
      s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__,
                       "mesh %s has no node set \"ymin\" with nodes (a physical surface on y = 0, the clamped end)",
                       p->mesh_file);
      goto fail_file;
    }
    TL_CHECK_GOTO(s, tl_solid_fix(c->solid, "ymin", 7), fail_file);
    TL_CHECK_GOTO(s, tip_weights_from_faces(c, p->mesh_file), fail_file);
    for (size_t k = 0; k < c->n_tip; ++k) {
      TlVec3 f = {0.0, 0.0, -p->load * c->tip_weight[k]};
      TL_CHECK_GOTO(s, tl_solid_add_point_force(c->solid, c->tip_nodes[k], f, tip_amplitude, c), fail_file);
    }
    TL_CHECK_GOTO(s, tl_solid_setup(c->solid), fail_file);
    *out = c;
    return TL_OK;
  fail_file:
    tl_cantilever_destroy(&c);
    return s;
  }
  TlCantilever *c = NULL;
  TlStatus s = TL_OK;
  *out = NULL;
  /* The tip weights are products of 1-D weights (weight_1d): true of the
   * tensor-product Lagrange hexahedra of degree 1 and 2, whose faces hold
   * (degree + 1)^2 nodes (hex8, hex27). */
  int quad = !p->type->linear, side = quad ? 3 : 2;
  if (p->type->shape != TL_SHAPE_HEX || p->type->face_n_nodes != side * side)
    TL_ERROR(TL_ERR_ARG, "cantilever elements must be tensor-product hexahedra of degree 1 or 2 (hex8, hex27), not %s",
             p->type->header.name);
  if (p->nx < 1 || p->ny < 1 || p->nz < 1)
    TL_ERROR(TL_ERR_ARG, "cantilever cells %zu x %zu x %zu must be >= 1", p->nx, p->ny, p->nz);
  /* Cells far from cubes make elements (and the coupled surface's
   * triangles) too thin to compute with: refuse them by their sizes. */
  const double cell[3] = {p->b / (double)p->nx, p->L / (double)p->ny, p->h / (double)p->nz};
  const double cmax = fmax(cell[0], fmax(cell[1], cell[2])), cmin = fmin(cell[0], fmin(cell[1], cell[2]));
  if (!(cmax <= TL_CANTILEVER_MAX_ASPECT * cmin))
    TL_ERROR(TL_ERR_ARG,
             "cantilever cells of %g x %g x %g m (width / nx, length / ny, height / nz) have an aspect ratio %.3g, "
             "beyond the limit %g: change the length, width or height or the cell counts", cell[0], cell[1], cell[2],
             cmax / cmin, TL_CANTILEVER_MAX_ASPECT);
  TL_CHECK(TL_NEW(c));
  c->p = *p;
  c->load_scale = 1.0;
  const size_t n[3] = {p->nx, p->ny, p->nz};
  const double lo[3] = {-0.5 * p->b, 0.0, -0.5 * p->h}, hi[3] = {0.5 * p->b, p->L, 0.5 * p->h};
  TL_CHECK_GOTO(s, tl_mesh_create_box(p->type, n, lo, hi, &c->mesh), fail);
  TL_CHECK_GOTO(s, tl_material_create(p->material ? p->material : "hooke", &c->material), fail);
  TL_CHECK_GOTO(s, tl_material_set(c->material, "E", p->E), fail);
  TL_CHECK_GOTO(s, tl_material_set(c->material, "nu", p->nu), fail);
  TL_CHECK_GOTO(s, tl_material_set(c->material, "density", p->rho), fail);
  TL_CHECK_GOTO(s, tl_material_setup(c->material), fail);
  TL_CHECK_GOTO(s, tl_solid_create(c->mesh, &c->solid), fail);
  TL_CHECK_GOTO(s, tl_solid_set_material(c->solid, NULL, c->material), fail);
  TL_CHECK_GOTO(s, tl_solid_fix(c->solid, "ymin", 7), fail);
  const TlNodeSet *tip = NULL;
  TL_CHECK_GOTO(s, tl_mesh_find_node_set(c->mesh, "ymax", &tip), fail);
  c->n_tip = tip->n;
  TL_CHECK_GOTO(s, tl_calloc(&c->tip_nodes, tip->n, sizeof *c->tip_nodes), fail);
  TL_CHECK_GOTO(s, tl_calloc(&c->tip_weight, tip->n, sizeof *c->tip_weight), fail);
  double area = p->b * p->h, total = 0.0;
  for (size_t k = 0; k < tip->n; ++k) {
    size_t node = tip->nodes[k];
    const double *X = c->mesh->x + 3 * node;
    double w = weight_1d(X[0], lo[0], p->b / (double)p->nx, p->nx, quad) *
               weight_1d(X[2], lo[2], p->h / (double)p->nz, p->nz, quad) / area;
    c->tip_nodes[k] = node;
    c->tip_weight[k] = w;
    total += w;
    TlVec3 f = {0.0, 0.0, -p->load * w};
    TL_CHECK_GOTO(s, tl_solid_add_point_force(c->solid, node, f, tip_amplitude, c), fail);
  }
  if (fabs(total - 1.0) > 1e-12) {
    s = tl_error_set(TL_ERR_ARG, __FILE__, __LINE__, "tip load weights sum to %.15g, not 1", total);
    goto fail;
  }
  TL_CHECK_GOTO(s, tl_solid_setup(c->solid), fail);
  *out = c;
  return TL_OK;
fail:
  tl_cantilever_destroy(&c);
  return s;
}

void tl_cantilever_destroy(TlCantilever **c)
{
  if (!c || !*c) return;
  tl_solid_destroy(&(*c)->solid);
  tl_material_destroy(&(*c)->material);
  tl_mesh_destroy(&(*c)->mesh);
  tl_free(&(*c)->tip_nodes);
  tl_free(&(*c)->tip_weight);
  tl_free(c);
}

void tl_cantilever_tip(const TlCantilever *c, const double *u, double out[3])
{
  out[0] = out[1] = out[2] = 0.0;
  for (size_t k = 0; k < c->n_tip; ++k)
    for (int d = 0; d < 3; ++d) {
      TlSparseIndex i = tl_solid_dof(c->solid, c->tip_nodes[k], d);
      if (i >= 0) out[d] += c->tip_weight[k] * u[i];
    }
}

double tl_cantilever_timoshenko(const TlCantileverParams *p)
{
  double I = p->b * p->h * p->h * p->h / 12.0, A = p->b * p->h;
  double G = p->E / (2.0 * (1.0 + p->nu)), kappa = 10.0 * (1.0 + p->nu) / (12.0 + 11.0 * p->nu);
  return p->load * pow(p->L, 3) / (3.0 * p->E * I) + p->load * p->L / (kappa * G * A);
}

double tl_cantilever_omega1(const TlCantileverParams *p)
{
  double I = p->b * p->h * p->h * p->h / 12.0, A = p->b * p->h;
  double beta = 1.8751040687119611;
  return beta * beta * sqrt(p->E * I / (p->rho * A * pow(p->L, 4)));
}

/* theta' = kappa, kappa' = -k cos(theta), x' = cos(theta), w' = sin(theta)
 * on s in [0, 1]; returns kappa(1) for kappa(0) = k0. */
static double shoot(double k, double k0, double *x_end, double *w_end)
{
  enum { N = 4000 };
  double y[4] = {0.0, k0, 0.0, 0.0}, h = 1.0 / N;
  for (int i = 0; i < N; ++i) {
    double k1[4], k2[4], k3[4], k4[4], t[4];
#define RHS(o, v)                                                                                  \
  do {                                                                                             \
    o[0] = v[1];                                                                                   \
    o[1] = -k * cos(v[0]);                                                                         \
    o[2] = cos(v[0]);                                                                              \
    o[3] = sin(v[0]);                                                                              \
  } while (0)
    RHS(k1, y);
    for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k1[j];
    RHS(k2, t);
    for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k2[j];
    RHS(k3, t);
    for (int j = 0; j < 4; ++j) t[j] = y[j] + h * k3[j];
    RHS(k4, t);
#undef RHS
    for (int j = 0; j < 4; ++j) y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
  }
  *x_end = y[2];
  *w_end = y[3];
  return y[1];
}

TlStatus tl_cantilever_elastica(double k, double *w_over_L, double *shortening_over_L)
{
  if (!(k >= 0.0) || k > 50.0) TL_ERROR(TL_ERR_ARG, "elastica load parameter %g outside [0, 50]", k);
  /* kappa(1) is increasing in kappa(0) on [0, k]: bisection. */
  double lo = 0.0, hi = k, x = 1.0, w = 0.0;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * fmax(1.0, k); ++it) {
    double mid = 0.5 * (lo + hi);
    if (shoot(k, mid, &x, &w) < 0.0) lo = mid;
    else hi = mid;
  }
  shoot(k, 0.5 * (lo + hi), &x, &w);
  *w_over_L = w;
  *shortening_over_L = 1.0 - x;
  return TL_OK;
}
