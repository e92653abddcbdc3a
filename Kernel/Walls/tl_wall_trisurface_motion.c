/* Triangulated walls from surface files, and their prescribed rigid motion
 * (tl_wall_trisurface.h). */
#include <math.h>
#include <string.h>

#include "tl_memory.h"
#include "tl_wall_trisurface_private.h"

TlStatus tl_wall_trisurface_place(TlWallTriSurface *t, double time)
{
  TlTriSurface *s = t->surface;
  const TlRigidMotion *m = &t->motion;
  int active = time >= m->start && time < m->stop;
  double tau = fmin(fmax(time, m->start), m->stop) - m->start;
  double w = tl_v3_norm(m->omega);
  TlMat3 R = w > 0.0 ? tl_m3_rotation(tl_v3_scale(m->omega, 1.0 / w), w * tau) : tl_m3_identity();
  TlVec3 c = tl_v3_axpy(m->center, tau, m->velocity);
  for (size_t i = 0; i < s->n_vertices; ++i) {
    TlVec3 r = tl_m3_mulv(R, tl_v3_sub(t->x_ref[i], m->center));
    s->x[i] = tl_v3_add(c, r);
    s->v[i] = active ? tl_v3_add(m->velocity, tl_v3_cross(m->omega, r)) : tl_v3(0, 0, 0);
  }
  TL_CHECK(tl_trisurface_vertices_moved(s));
  return TL_OK;
}

TlStatus tl_wall_trisurface_from_mesh(const TlSurfaceMesh *m, TlWall **w)
{
  if (!w) TL_ERROR(TL_ERR_ARG, "tl_wall_trisurface_from_mesh: NULL wall pointer");
  *w = NULL;
  TL_CHECK(tl_surface_mesh_check(m, 0));
  TlTriSurface *s = NULL;
  TL_CHECK(tl_trisurface_create(m->n_vertices, &m->x[0].x, m->n_triangles, &m->tri[0][0], &s));
  TL_CHECK(tl_wall_trisurface_create(s, w));
  return TL_OK;
}

void tl_wall_placement_default(TlWallPlacement *p)
{
  p->scale = 1.0;
  p->rotation = tl_m3_identity();
  p->shift = tl_v3(0, 0, 0);
  p->repair = 1;
  p->require_closed = 0;
}

TlStatus tl_wall_trisurface_from_file(const char *path, const TlWallPlacement *placement, TlWall **w,
                                      TlSurfaceReport *report)
{
  if (!w) TL_ERROR(TL_ERR_ARG, "tl_wall_trisurface_from_file: NULL wall pointer");
  *w = NULL;
  TlWallPlacement p;
  tl_wall_placement_default(&p);
  if (placement) p = *placement;
  TlSurfaceMesh *m = NULL;
  TL_CHECK(tl_surface_mesh_read(path, &m));
  TlStatus status = TL_OK;
  TlSurfaceReport r;
  memset(&r, 0, sizeof r);
  TL_CHECK_GOTO(status, tl_surface_mesh_transform(m, p.scale, p.rotation, p.shift), done);
  if (p.repair) {
    /* keep the side the file's normals face: a container whose normals
     * point in (the grains' side) stays so */
    double v = 0.0;
    TlSurfaceRepairOptions o;
    tl_surface_repair_options_default(&o);
    if (tl_surface_mesh_is_closed(m) && tl_surface_mesh_volume(m, &v) == TL_OK) o.outward = tl_surface_mesh_volume_sign(m) >= 0;
    tl_error_clear();
    TL_CHECK_GOTO(status, tl_surface_mesh_repair(m, &o, &r), done);
  }
  TL_CHECK_GOTO(status, tl_surface_mesh_check(m, p.require_closed ? TL_SURFACE_CLOSED : 0), done);
  r.closed = tl_surface_mesh_is_closed(m);
  TL_CHECK_GOTO(status, tl_wall_trisurface_from_mesh(m, w), done);
  if (report) *report = r;
done:
  tl_surface_mesh_destroy(&m);
  return status;
}
