/* Conveniences for building and writing a scene (tl_api.h): the set-up and
 * output steps every scene repeats, each composed of the modules' own
 * calls. */
#include "tl_api.h"

#include <stdio.h>
#include <string.h>

#include "tl_memory.h"

TlStatus tl_api_dem_add_law(TlDem *dem, const char *normal, const char *friction, const char *rolling,
                            const char *adhesion, size_t n, const TlSetting *settings, int *index)
{
  TlContactLaw *law = NULL;
  TL_CHECK(tl_contact_law_create(normal, friction, rolling, adhesion, &law));
  TlStatus s = TL_OK;
  for (size_t k = 0; k < n && s == TL_OK; ++k) s = tl_contact_law_set(law, settings[k].name, settings[k].value);
  if (s == TL_OK) s = tl_contact_law_setup(law);
  if (s == TL_OK) s = tl_dem_add_law(dem, law, index); /* the world owns the law from here */
  if (s != TL_OK) {
    tl_contact_law_destroy(&law);
    TL_CHECK(s);
  }
  return TL_OK;
}

TlStatus tl_api_dem_set_box_walls(TlDem *dem, TlVec3 lo, TlVec3 hi, const char *walls, int law)
{
  static const char *const faces[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
  TL_CHECK(tl_api_dem_set_box(dem, (const double[3]){lo.x, lo.y, lo.z}, (const double[3]){hi.x, hi.y, hi.z}, NULL));
  for (const char *at = walls ? walls : ""; *at;) {
    size_t len = strcspn(at, " ,");
    int face = -1;
    for (int k = 0; k < 6 && len; ++k)
      if (strlen(faces[k]) == len && !strncmp(at, faces[k], len)) face = k;
    if (len && face < 0)
      TL_ERROR(TL_ERR_ARG, "box wall '%.*s' is none of xmin, xmax, ymin, ymax, zmin, zmax", (int)len, at);
    if (face >= 0) {
      const int axis = face / 2, upper = face % 2;
      double n[3] = {0, 0, 0};
      n[axis] = upper ? -1.0 : 1.0; /* towards the inside */
      const TlVec3 point = upper ? hi : lo, normal = {n[0], n[1], n[2]};
      TlWall *w;
      TL_CHECK(tl_wall_plane_create(point, normal, &w));
      TlStatus s = tl_dem_add_wall(dem, w, law);
      if (s != TL_OK) tl_wall_destroy(&w);
      TL_CHECK(s);
    }
    at += len;
    at += strspn(at, " ,");
  }
  return TL_OK;
}

TlStatus tl_api_solid_create(TlMesh *mesh, TlMaterial *material, const char *clamped, TlSolid **solid)
{
  TL_CHECK(tl_solid_create(mesh, solid));
  TlStatus s = tl_solid_set_material(*solid, NULL, material);
  if (s == TL_OK && clamped && clamped[0]) s = tl_solid_fix(*solid, clamped, 7);
  if (s != TL_OK) {
    tl_solid_destroy(solid);
    TL_CHECK(s);
  }
  return TL_OK;
}

TlStatus tl_api_timeseries_create(const char *dir, const char *name, size_t n_columns, const TlColumn *columns,
                                  TlTimeSeries **ts)
{
  char base[4096];
  const int len = snprintf(base, sizeof base, "%s/%s", dir, name);
  if (len < 0 || len >= (int)sizeof base)
    TL_ERROR(TL_ERR_ARG, "table path of %d characters (folder %.40s..., name %s) longer than the limit %zu", len, dir,
             name, sizeof base - 1);
  TL_CHECK(tl_timeseries_create(base, TL_TIMESERIES_CSV, n_columns, columns, ts));
  return TL_OK;
}

struct TlSceneWriter {
  TlDem *dem;
  TlSolid *solid;
  TlStepper *stepper;
  TlParticleWriter *particles;
  TlWallWriter *walls;
  TlSolidOutput *mesh;
};

TlStatus tl_api_scene_writer_create(const char *dir, TlDem *dem, TlSolid *solid, TlStepper *stepper,
                                    const char *solid_name, TlSceneWriter **out)
{
  TlSceneWriter *w;
  *out = NULL;
  if (!dem && !solid) TL_ERROR(TL_ERR_ARG, "a scene writer needs a world or a solid (both NULL)");
  if (solid && !stepper) TL_ERROR(TL_ERR_ARG, "a scene writer of a solid needs the stepper that holds its state");
  TL_CHECK(TL_NEW(w));
  w->dem = dem, w->solid = solid, w->stepper = stepper;
  TlStatus s = TL_OK;
  if (dem) s = tl_particle_writer_create(dir, "particles", &w->particles);
  if (s == TL_OK && dem && tl_dem_n_walls(dem) > 0) s = tl_wall_writer_create(dir, "walls", &w->walls);
  if (s == TL_OK && solid) s = tl_solid_output_create(solid, dir, solid_name ? solid_name : "solid", &w->mesh);
  if (s != TL_OK) {
    tl_api_scene_writer_destroy(&w);
    TL_CHECK(s);
  }
  *out = w;
  return TL_OK;
}

TlStatus tl_api_scene_writer_write(TlSceneWriter *w, int64_t step)
{
  const double t = w->dem ? tl_dem_time(w->dem) : w->stepper->t;
  if (w->particles) TL_CHECK(tl_api_particle_writer_write_dem(w->particles, w->dem, step));
  if (w->walls) TL_CHECK(tl_wall_writer_write_dem(w->walls, step, w->dem));
  if (w->mesh) TL_CHECK(tl_solid_output_write(w->mesh, step, t, w->stepper->u, w->stepper->v));
  return TL_OK;
}

void tl_api_scene_writer_destroy(TlSceneWriter **w)
{
  if (!w || !*w) return;
  tl_particle_writer_destroy(&(*w)->particles);
  tl_wall_writer_destroy(&(*w)->walls);
  tl_solid_output_destroy(&(*w)->mesh);
  tl_free(w);
}

TlStatus tl_api_wall_from_file(const char *path, double scale, const double rotation[9], const double shift[3],
                               int repair, int require_closed, TlWall **w, double report[9])
{
  TlWallPlacement p;
  tl_wall_placement_default(&p);
  p.scale = scale;
  if (rotation) memcpy(&p.rotation, rotation, sizeof p.rotation);
  if (shift) p.shift = (TlVec3){shift[0], shift[1], shift[2]};
  p.repair = repair;
  p.require_closed = require_closed;
  TlSurfaceReport r;
  memset(&r, 0, sizeof r);
  TL_CHECK(tl_wall_trisurface_from_file(path, &p, w, &r));
  if (report) {
    const double v[9] = {(double)r.vertices_merged, (double)r.triangles_removed, (double)r.triangles_flipped,
                         (double)r.vertices_split, (double)r.nonmanifold_edges, (double)r.holes,
                         (double)r.boundary_edges, (double)r.closed, r.volume};
    memcpy(report, v, sizeof v);
  }
  return TL_OK;
}
