/* Walls in the output (tl_wall_snapshot.h): outlines by wall type, and a
 * writer that gathers them into the blocks of a mesh snapshot. */
#include "tl_wall_snapshot.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_mesh_snapshot.h"
#include "tl_registry.h"
#include "tl_wall_trisurface.h"

/* ---------------------------------------------------------------- outlines */
TlStatus tl_wall_outline_reserve(TlWallOutline *o, size_t nv, size_t nt)
{
  size_t cap_f = o->cap_triangles;
  TL_CHECK(tl_array_reserve(&o->x, &o->cap_vertices, nv ? nv : 1, sizeof *o->x));
  TL_CHECK(tl_array_reserve(&o->tri, &o->cap_triangles, 3 * (nt ? nt : 1), sizeof *o->tri));
  /* force has one entry per triangle: keep its capacity in step with tri's */
  if (o->cap_triangles != cap_f || !o->force) TL_CHECK(tl_realloc(&o->force, o->cap_triangles, sizeof *o->force));
  memset(o->force, 0, (nt ? nt : 1) * sizeof *o->force);
  return TL_OK;
}

void tl_wall_outline_free(TlWallOutline *o)
{
  tl_free(&o->x);
  tl_free(&o->tri);
  tl_free(&o->force);
  memset(o, 0, sizeof *o);
}

TlStatus tl_wall_outline_register(const TlWallOutlineOps *ops)
{
  if (!ops || !ops->outline || !ops->header.name || !ops->header.kind || strcmp(ops->header.kind, "wall_outline") != 0)
    TL_ERROR(TL_ERR_ARG, "a wall outline needs kind \"wall_outline\", the wall type's name and an outline op");
  return tl_registry_add(&ops->header);
}

TlStatus tl_wall_outline(const TlWall *w, const TlParticles *P, TlVec3 lo, TlVec3 hi, TlWallOutline *out)
{
  const TlOpsHeader *h;
  TlStatus s = tl_registry_find("wall_outline", w->ops->header.name, &h);
  if (s != TL_OK)
    TL_ERROR(TL_ERR_UNSUPPORTED, "wall type '%s' has no outline for the output (register one with tl_wall_outline_register)",
             w->ops->header.name);
  out->n_vertices = out->n_triangles = 0;
  TL_CHECK(((const TlWallOutlineOps *)h)->outline(w, P, lo, hi, out));
  return TL_OK;
}

/* A plane: the rectangle of the plane covering the box's projection, in
 * axis-aligned directions where the plane allows (a floor z = c gives the
 * box's x-y rectangle), split into two triangles. */
typedef struct {
  TlWall *w;
  TlVec3 c, t1, t2;
  double u0, u1, v0, v1;
  TlVec3 *force;
} PlanePatch;

static void plane_force(void *ctx, size_t i, TlVec3 f, TlVec3 point, TlVec3 center)
{
  (void)i;
  (void)center;
  PlanePatch *p = ctx;
  TlVec3 d = tl_v3_sub(point, p->c);
  double u = (tl_v3_dot(d, p->t1) - p->u0) / (p->u1 - p->u0), v = (tl_v3_dot(d, p->t2) - p->v0) / (p->v1 - p->v0);
  /* triangle 0 holds (0,0) (1,0) (1,1), triangle 1 (0,0) (1,1) (0,1); points
   * beyond the patch count to the nearer triangle */
  int k = v > u ? 1 : 0;
  p->force[k] = tl_v3_sub(p->force[k], f);
}

static TlStatus plane_outline(const TlWall *w, const TlParticles *P, TlVec3 lo, TlVec3 hi, TlWallOutline *out)
{
  TlVec3 point, n;
  tl_wall_plane_get(w, &point, &n);
  /* the axis least aligned with n, projected onto the plane */
  double a[3] = {fabs(n.x), fabs(n.y), fabs(n.z)};
  int k = a[0] <= a[1] && a[0] <= a[2] ? 0 : (a[1] <= a[2] ? 1 : 2);
  TlVec3 e = tl_v3(k == 0, k == 1, k == 2);
  PlanePatch p = {(TlWall *)w, point, tl_v3_normalize(tl_v3_axpy(e, -tl_v3_dot(e, n), n)), {0, 0, 0},
                  INFINITY, -INFINITY, INFINITY, -INFINITY, NULL};
  p.t2 = tl_v3_cross(n, p.t1);
  for (int c = 0; c < 8; ++c) {
    TlVec3 q = tl_v3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
    TlVec3 d = tl_v3_sub(q, point);
    double u = tl_v3_dot(d, p.t1), v = tl_v3_dot(d, p.t2);
    p.u0 = fmin(p.u0, u), p.u1 = fmax(p.u1, u), p.v0 = fmin(p.v0, v), p.v1 = fmax(p.v1, v);
  }
  TL_CHECK(tl_wall_outline_reserve(out, 4, 2));
  double uv[4][2] = {{p.u0, p.v0}, {p.u1, p.v0}, {p.u1, p.v1}, {p.u0, p.v1}};
  for (int c = 0; c < 4; ++c) out->x[c] = tl_v3_axpy(tl_v3_axpy(point, uv[c][0], p.t1), uv[c][1], p.t2);
  static const int tri[6] = {0, 1, 2, 0, 2, 3};
  memcpy(out->tri, tri, sizeof tri);
  out->n_vertices = 4;
  out->n_triangles = 2;
  p.force = out->force;
  if (P && w->ops->visit_contacts) TL_CHECK(tl_wall_visit_contacts(w, P, plane_force, &p));
  return TL_OK;
}

static TlStatus trisurface_outline(const TlWall *w, const TlParticles *P, TlVec3 lo, TlVec3 hi, TlWallOutline *out)
{
  (void)P;
  (void)lo;
  (void)hi;
  const TlTriSurface *s = tl_wall_trisurface_surface((TlWall *)w);
  if (!s) TL_ERROR(TL_ERR_STATE, "trisurface wall '%s' has no surface yet", w->name);
  TL_CHECK(tl_wall_outline_reserve(out, s->n_vertices, s->n_triangles));
  memcpy(out->x, s->x, s->n_vertices * sizeof *out->x);
  memcpy(out->tri, s->tri, 3 * s->n_triangles * sizeof *out->tri);
  out->n_vertices = s->n_vertices;
  out->n_triangles = s->n_triangles;
  const TlTriContactSet *c = tl_wall_trisurface_contacts(w);
  for (size_t k = 0; c && k < c->count; ++k) {
    const TlTriContactRecord *r = &c->c[k];
    if (r->triangle >= 0 && (size_t)r->triangle < s->n_triangles)
      out->force[r->triangle] = tl_v3_sub(out->force[r->triangle], r->force);
  }
  return TL_OK;
}

static const TlWallOutlineOps plane_outline_ops = {
    {"wall_outline", "plane", "a rectangle of the plane covering the scene's box, two triangles"}, plane_outline};
static const TlWallOutlineOps trisurface_outline_ops = {
    {"wall_outline", "trisurface", "the surface's triangles as they stand"}, trisurface_outline};

TlStatus tl_wall_snapshot_register_all(void)
{
  TL_CHECK(tl_wall_outline_register(&plane_outline_ops));
  TL_CHECK(tl_wall_outline_register(&trisurface_outline_ops));
  return TL_OK;
}

/* ---------------------------------------------------------------- writer */
struct TlWallWriter {
  TlMeshWriter *mesh;
  TlVec3 lo, hi;
  int have_box;
  TlWallOutline outline;
  /* the gathered view: all walls' vertices, one block per wall */
  TlVec3 *x;
  size_t cap_x;
  int *tri;
  size_t cap_tri;
  double *normal, *force, *index;
  size_t cap_normal, cap_force, cap_index;
  TlMeshBlock *blocks;
  TlField *fields;
  char (*names)[64];
  size_t cap_blocks, cap_fields, cap_names;
};

TlStatus tl_wall_writer_create(const char *dir, const char *name, TlWallWriter **writer)
{
  *writer = NULL;
  TlWallWriter *w;
  TL_CHECK(TL_NEW(w));
  TlStatus s = tl_mesh_writer_create(dir, name, &w->mesh);
  if (s != TL_OK) {
    tl_free(&w);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  *writer = w;
  return TL_OK;
}

void tl_wall_writer_destroy(TlWallWriter **writer)
{
  if (!writer || !*writer) return;
  TlWallWriter *w = *writer;
  tl_mesh_writer_destroy(&w->mesh);
  tl_wall_outline_free(&w->outline);
  tl_free(&w->x);
  tl_free(&w->tri);
  tl_free(&w->normal);
  tl_free(&w->force);
  tl_free(&w->index);
  tl_free(&w->blocks);
  tl_free(&w->fields);
  tl_free(&w->names);
  tl_free(writer);
}

TlStatus tl_wall_writer_set_box(TlWallWriter *w, TlVec3 lo, TlVec3 hi)
{
  double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
  for (int k = 0; k < 3; ++k)
    if (!(isfinite(l[k]) && isfinite(h[k]) && l[k] < h[k]))
      TL_ERROR(TL_ERR_ARG, "wall output box: component %d is [%g, %g] m; it must be finite with lo < hi", k, l[k], h[k]);
  w->lo = lo;
  w->hi = hi;
  w->have_box = 1;
  return TL_OK;
}

int tl_wall_writer_box(const TlWallWriter *w, TlVec3 *lo, TlVec3 *hi)
{
  if (w->have_box) *lo = w->lo, *hi = w->hi;
  return w->have_box;
}

static void box_add(TlVec3 *lo, TlVec3 *hi, TlVec3 a, TlVec3 b)
{
  *lo = tl_v3(fmin(lo->x, a.x), fmin(lo->y, a.y), fmin(lo->z, a.z));
  *hi = tl_v3(fmax(hi->x, b.x), fmax(hi->y, b.y), fmax(hi->z, b.z));
}

/* The scene's box: the domain's cell (if given), the particles and the
 * bounded walls. */
static TlStatus scene_box(TlWallWriter *w, const TlDomain *D, size_t n, TlWall *const *walls, const TlParticles *P)
{
  TlVec3 lo = tl_v3(INFINITY, INFINITY, INFINITY), hi = tl_v3(-INFINITY, -INFINITY, -INFINITY);
  if (D)
    for (int c = 0; c < 8; ++c) {
      TlVec3 q = D->origin;
      for (int k = 0; k < 3; ++k)
        if (c >> k & 1) q = tl_v3_add(q, tl_v3(D->h.m[0][k], D->h.m[1][k], D->h.m[2][k]));
      box_add(&lo, &hi, q, q);
    }
  for (size_t i = 0; P && i < P->n; ++i) {
    TlVec3 r = tl_v3(P->radius[i], P->radius[i], P->radius[i]);
    box_add(&lo, &hi, tl_v3_sub(P->x[i], r), tl_v3_add(P->x[i], r));
  }
  for (size_t k = 0; k < n; ++k)
    if (tl_wall_is_bounded(walls[k])) {
      TlVec3 a, b;
      walls[k]->ops->bounding_box(walls[k], &a, &b);
      box_add(&lo, &hi, a, b);
    }
  if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z))
    TL_ERROR(TL_ERR_STATE, "wall output: no domain, particle or bounded wall to size the planes by (set a box with "
             "tl_wall_writer_set_box)");
  /* a flat scene (all in one plane) still gives a patch of some size */
  double size = fmax(hi.x - lo.x, fmax(hi.y - lo.y, hi.z - lo.z));
  double pad = size > 0 ? 1e-3 * size : 1.0;
  return tl_wall_writer_set_box(w, tl_v3_sub(lo, tl_v3(pad, pad, pad)), tl_v3_add(hi, tl_v3(pad, pad, pad)));
}

static TlStatus gather(TlWallWriter *w, size_t n, TlWall *const *walls, const TlParticles *P)
{
  size_t nv = 0, nt = 0;
  /* two passes: outlines are small to redo, and the gathered arrays must
   * not move once blocks point into them */
  for (int pass = 0; pass < 2; ++pass) {
    size_t iv = 0, it = 0;
    for (size_t k = 0; k < n; ++k) {
      TL_CHECK(tl_wall_outline(walls[k], P, w->lo, w->hi, &w->outline));
      const TlWallOutline *o = &w->outline;
      if (pass == 1) {
        for (size_t v = 0; v < o->n_vertices; ++v) w->x[iv + v] = o->x[v];
        for (size_t t = 0; t < o->n_triangles; ++t) {
          const int *c = &o->tri[3 * t];
          for (int j = 0; j < 3; ++j) {
            if (c[j] < 0 || (size_t)c[j] >= o->n_vertices)
              TL_ERROR(TL_ERR_STATE, "wall %zu (%s): outline triangle %zu names vertex %d of %zu", k,
                       walls[k]->ops->header.name, t, c[j], o->n_vertices);
            w->tri[3 * (it + t) + j] = (int)iv + c[j];
          }
          TlVec3 nn = tl_v3_cross(tl_v3_sub(o->x[c[1]], o->x[c[0]]), tl_v3_sub(o->x[c[2]], o->x[c[0]]));
          double len = tl_v3_norm(nn);
          nn = len > 0 ? tl_v3_scale(nn, 1.0 / len) : tl_v3(0, 0, 0);
          double *pn = &w->normal[3 * (it + t)], *pf = &w->force[3 * (it + t)];
          pn[0] = nn.x, pn[1] = nn.y, pn[2] = nn.z;
          pf[0] = o->force[t].x, pf[1] = o->force[t].y, pf[2] = o->force[t].z;
          w->index[it + t] = (double)k;
        }
        TlMeshBlock *b = &w->blocks[k];
        snprintf(w->names[k], sizeof w->names[k], "wall%zu_%s", k, walls[k]->ops->header.name);
        /* a name the mesh writer accepts: letters, digits, '_', '.', '-' */
        for (char *c = w->names[k]; *c; ++c)
          if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') || *c == '.' || *c == '-'))
            *c = '_';
        TlField *f = &w->fields[3 * k];
        f[0] = (TlField){"normal", 3, &w->normal[3 * it]};
        f[1] = (TlField){"contact_force", 3, &w->force[3 * it]};
        f[2] = (TlField){"wall", 1, &w->index[it]};
        *b = (TlMeshBlock){w->names[k], TL_CELL_TRI3, o->n_triangles, &w->tri[3 * it], 3, f};
      }
      iv += o->n_vertices;
      it += o->n_triangles;
    }
    if (pass == 0) {
      nv = iv, nt = it;
      TL_CHECK(tl_array_reserve(&w->x, &w->cap_x, nv ? nv : 1, sizeof *w->x));
      TL_CHECK(tl_array_reserve(&w->tri, &w->cap_tri, 3 * (nt ? nt : 1), sizeof *w->tri));
      TL_CHECK(tl_array_reserve(&w->normal, &w->cap_normal, 3 * (nt ? nt : 1), sizeof *w->normal));
      TL_CHECK(tl_array_reserve(&w->force, &w->cap_force, 3 * (nt ? nt : 1), sizeof *w->force));
      TL_CHECK(tl_array_reserve(&w->index, &w->cap_index, nt ? nt : 1, sizeof *w->index));
      TL_CHECK(tl_array_reserve(&w->blocks, &w->cap_blocks, n, sizeof *w->blocks));
      TL_CHECK(tl_array_reserve(&w->fields, &w->cap_fields, 3 * n, sizeof *w->fields));
      TL_CHECK(tl_array_reserve(&w->names, &w->cap_names, n, sizeof *w->names));
    }
  }
  return TL_OK;
}

static TlStatus write_walls(TlWallWriter *w, int64_t step, double time, const TlDomain *D, size_t n,
                            TlWall *const *walls, const TlParticles *P)
{
  if (n == 0) TL_ERROR(TL_ERR_ARG, "wall output: no wall to write");
  if (!walls) TL_ERROR(TL_ERR_ARG, "wall output: %zu walls announced, none given", n);
  if (!w->have_box) TL_CHECK(scene_box(w, D, n, walls, P));
  TL_CHECK(gather(w, n, walls, P));
  size_t nv = 0;
  for (size_t k = 0; k < n; ++k) {
    const TlMeshBlock *b = &w->blocks[k];
    for (size_t i = 0; i < 3 * b->n_cells; ++i)
      if ((size_t)b->connectivity[i] + 1 > nv) nv = (size_t)b->connectivity[i] + 1;
  }
  TlMeshView view = {nv, w->x, NULL, 0, NULL, n, w->blocks};
  TL_CHECK(tl_mesh_writer_write(w->mesh, step, time, &view));
  return TL_OK;
}

TlStatus tl_wall_writer_write(TlWallWriter *w, int64_t step, double time, size_t n, TlWall *const *walls,
                              const TlParticles *P)
{
  TL_CHECK(write_walls(w, step, time, NULL, n, walls, P));
  return TL_OK;
}

TlStatus tl_wall_writer_write_dem(TlWallWriter *w, int64_t step, TlDem *dem)
{
  size_t n = tl_dem_n_walls(dem);
  TlWall **walls = NULL;
  TL_CHECK(tl_calloc(&walls, n ? n : 1, sizeof *walls));
  for (size_t k = 0; k < n; ++k) walls[k] = tl_dem_wall(dem, k);
  TlStatus s = write_walls(w, step, tl_dem_time(dem), tl_dem_domain(dem), n, walls, tl_dem_particles(dem));
  tl_free(&walls);
  TL_CHECK(s);
  return TL_OK;
}

size_t tl_wall_writer_count(const TlWallWriter *w) { return tl_mesh_writer_count(w->mesh); }
const char *tl_wall_writer_last_path(const TlWallWriter *w) { return tl_mesh_writer_last_path(w->mesh); }
const char *tl_wall_writer_mesh_path(const TlWallWriter *w) { return tl_mesh_writer_mesh_path(w->mesh); }

/* ---------------------------------------------------------------- checkpoint */
static TlStatus ww_save(const void *object, TlCheckpointWriter *cw, const char *group)
{
  const TlWallWriter *w = object;
  char sub[512];
  snprintf(sub, sizeof sub, "%s/mesh", group);
  double box[6] = {w->lo.x, w->lo.y, w->lo.z, w->hi.x, w->hi.y, w->hi.z};
  TL_CHECK(tl_checkpoint_write_int64(cw, group, "have_box", w->have_box));
  TL_CHECK(tl_checkpoint_write_doubles(cw, group, "box", 6, box));
  TL_CHECK(tl_mesh_writer_checkpoint_ops.save(w->mesh, cw, sub));
  return TL_OK;
}

static TlStatus ww_load(void *object, TlCheckpointReader *r, const char *group)
{
  TlWallWriter *w = object;
  char sub[512];
  snprintf(sub, sizeof sub, "%s/mesh", group);
  int64_t have;
  double box[6];
  TL_CHECK(tl_checkpoint_read_int64(r, group, "have_box", &have));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "box", 6, box));
  if (have) TL_CHECK(tl_wall_writer_set_box(w, tl_v3(box[0], box[1], box[2]), tl_v3(box[3], box[4], box[5])));
  else w->have_box = 0;
  TL_CHECK(tl_mesh_writer_checkpoint_ops.load(w->mesh, r, sub));
  return TL_OK;
}

const TlCheckpointOps tl_wall_writer_checkpoint_ops = {
    {"checkpoint", "wall_writer_v1", "box, counters and XDMF series of a wall writer"}, ww_save, ww_load};
