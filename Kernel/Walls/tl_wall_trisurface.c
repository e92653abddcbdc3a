#include "tl_wall_trisurface.h"

#include "tl_trisurface_bins.h"
#include "tl_wall_trisurface_private.h"

#include <math.h>
#include <omp.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "tl_memory.h"
#include "tl_parallel.h"
#include "tl_registry.h"

static const TlWallOps tl_wall_trisurface_ops;

static TlWallTriSurface *tl_as_trisurface(TlWall *w) { return (TlWallTriSurface *)w; }

/* The type's own check, by its registered name, that a wall handed to its
 * accessors is one of its kind (a downcast guard, not a dispatch). */
static int tl_wall_is_trisurface(const TlWall *w) { return w && strcmp(tl_type_name(w), "trisurface") == 0; }

TlTriSurface *tl_wall_trisurface_surface(TlWall *w)
{
  return tl_wall_is_trisurface(w) ? tl_as_trisurface(w)->surface : NULL;
}

const TlTriContactSet *tl_wall_trisurface_contacts(const TlWall *w)
{
  return tl_wall_is_trisurface(w) ? ((const TlWallTriSurface *)w)->current : NULL;
}

#define TL_REQUIRE_TRISURFACE(w)                                                              \
  do {                                                                                        \
    if (!tl_wall_is_trisurface(w))                                                            \
      TL_ERROR(TL_ERR_ARG, "wall '%s' is not a triangulated surface",                         \
               (w) ? tl_type_name(w) : "(null)");                                             \
  } while (0)

TlStatus tl_wall_trisurface_set_corrections(TlWall *w, int on)
{
  TL_REQUIRE_TRISURFACE(w);
  tl_as_trisurface(w)->corrections = on != 0;
  return TL_OK;
}

TlStatus tl_wall_trisurface_set_brute_force(TlWall *w, int on)
{
  TL_REQUIRE_TRISURFACE(w);
  tl_as_trisurface(w)->brute_force = on != 0;
  return TL_OK;
}

TlStatus tl_wall_trisurface_set_feature_angle(TlWall *w, double degrees)
{
  TL_REQUIRE_TRISURFACE(w);
  TlWallTriSurface *t = tl_as_trisurface(w);
  if (t->surface) TL_CHECK(tl_trisurface_set_feature_angle(t->surface, degrees));
  else if (!(degrees >= 0.0 && degrees <= 180.0))
    TL_ERROR(TL_ERR_ARG, "wall '%s': feature angle %g degrees outside [0, 180]", w->name, degrees);
  t->feature_angle = degrees;
  return TL_OK;
}

TlStatus tl_wall_trisurface_set_motion(TlWall *w, const TlRigidMotion *motion, double time)
{
  TL_REQUIRE_TRISURFACE(w);
  TlWallTriSurface *t = tl_as_trisurface(w);
  TL_REQUIRE_SURFACE(t);
  if (!motion) TL_ERROR(TL_ERR_ARG, "wall '%s': NULL motion", w->name);
  if (!tl_v3_isfinite(motion->velocity) || !tl_v3_isfinite(motion->omega) || !tl_v3_isfinite(motion->center))
    TL_ERROR(TL_ERR_ARG, "wall '%s': motion velocity (%g, %g, %g), omega (%g, %g, %g) or centre (%g, %g, %g) not finite",
             w->name, motion->velocity.x, motion->velocity.y, motion->velocity.z, motion->omega.x, motion->omega.y,
             motion->omega.z, motion->center.x, motion->center.y, motion->center.z);
  if (!(motion->start >= 0.0) || !(motion->stop >= motion->start))
    TL_ERROR(TL_ERR_ARG, "wall '%s': motion from %g s to %g s: start must be >= 0 and stop >= start", w->name,
             motion->start, motion->stop);
  TlTriSurface *s = t->surface;
  TL_CHECK(tl_realloc(&t->x_ref, s->n_vertices, sizeof *t->x_ref));
  memcpy(t->x_ref, s->x, s->n_vertices * sizeof *s->x);
  t->motion = *motion;
  t->moving = 1;
  t->drift = 0;
  TL_CHECK(tl_wall_trisurface_place(t, time));
  return TL_OK;
}

TlStatus tl_wall_trisurface_get_motion(const TlWall *w, TlRigidMotion *motion)
{
  TL_REQUIRE_TRISURFACE(w);
  if (!motion) TL_ERROR(TL_ERR_ARG, "tl_wall_trisurface_get_motion: NULL output");
  const TlWallTriSurface *t = (const TlWallTriSurface *)w;
  if (t->moving) *motion = t->motion;
  else *motion = (TlRigidMotion){tl_v3(0, 0, 0), tl_v3(0, 0, 0), tl_v3(0, 0, 0), 0.0, 0.0};
  return TL_OK;
}

TlStatus tl_wall_trisurface_set_drift(TlWall *w, int on)
{
  TL_REQUIRE_TRISURFACE(w);
  tl_as_trisurface(w)->drift = on != 0;
  return TL_OK;
}

static void tl_wall_trisurface_destroy_impl(TlWall *w)
{
  TlWallTriSurface *t = tl_as_trisurface(w);
  tl_trisurface_destroy(&t->surface);
  tl_tricontacts_destroy(&t->current);
  tl_tricontacts_destroy(&t->previous);
  if (t->thread)
    for (int k = 0; k < t->n_threads; ++k) {
      tl_tricontacts_destroy(&t->thread[k].found);
      tl_free(&t->thread[k].candidates);
      tl_free(&t->thread[k].pairs);
    }
  tl_free(&t->thread);
  tl_free(&t->geometry);
  tl_free(&t->result);
  tl_tribins_free(&t->bins);
  tl_free(&t->pair);
  tl_free(&t->x_list);
  tl_free(&t->vertex_list);
  tl_free(&t->listed);
  tl_free(&t->seen);
  tl_free(&t->x_ref);
  tl_free(&t);
}

/* The parameter block of the constructor by name: switches as 0 or 1. */
typedef struct {
  double corrections, brute_force, drift, feature_angle;
  double velocity[3], omega[3], center[3], motion_start, motion_stop;
} TriSurfaceParams;

static const TlParam tl_wall_trisurface_params[] = {
    {"corrections", 1.0, 0.0, 1.0, "1", "1: the triangle-edge corrections of Algorithm 1; 0: the naive sum",
     offsetof(TriSurfaceParams, corrections)},
    {"brute_force", 0.0, 0.0, 1.0, "1", "1: test every particle against every triangle (test oracle); 0: the grid",
     offsetof(TriSurfaceParams, brute_force)},
    {"drift", 0.0, 0.0, 1.0, "1", "1: advance moves the vertices with their velocities; 0: the owner sets them",
     offsetof(TriSurfaceParams, drift)},
    {"feature_angle", TL_TRISURFACE_FEATURE_ANGLE, 0.0, 180.0, "deg",
     "concave folds sharper than this are corners between faces, whose contacts add; flatter ones are folds of one "
     "smooth surface, whose contacts are averaged (seeds/001 Modification 2); 180: average all",
     offsetof(TriSurfaceParams, feature_angle)},
    {"velocity_x", 0.0, -1e6, 1e6, "m/s", "prescribed translation velocity, x", offsetof(TriSurfaceParams, velocity[0])},
    {"velocity_y", 0.0, -1e6, 1e6, "m/s", "prescribed translation velocity, y", offsetof(TriSurfaceParams, velocity[1])},
    {"velocity_z", 0.0, -1e6, 1e6, "m/s", "prescribed translation velocity, z", offsetof(TriSurfaceParams, velocity[2])},
    {"omega_x", 0.0, -1e6, 1e6, "rad/s", "prescribed angular velocity, x", offsetof(TriSurfaceParams, omega[0])},
    {"omega_y", 0.0, -1e6, 1e6, "rad/s", "prescribed angular velocity, y", offsetof(TriSurfaceParams, omega[1])},
    {"omega_z", 0.0, -1e6, 1e6, "rad/s", "prescribed angular velocity, z", offsetof(TriSurfaceParams, omega[2])},
    {"center_x", 0.0, -1e12, 1e12, "m", "a point of the rotation axis at motion_start, x", offsetof(TriSurfaceParams, center[0])},
    {"center_y", 0.0, -1e12, 1e12, "m", "a point of the rotation axis at motion_start, y", offsetof(TriSurfaceParams, center[1])},
    {"center_z", 0.0, -1e12, 1e12, "m", "a point of the rotation axis at motion_start, z", offsetof(TriSurfaceParams, center[2])},
    {"motion_start", 0.0, 0.0, 1e12, "s", "time at which the prescribed motion starts (the surface as given holds then)",
     offsetof(TriSurfaceParams, motion_start)},
    {"motion_stop", 1e12, 0.0, 1e12, "s", "time at which the prescribed motion stops", offsetof(TriSurfaceParams, motion_stop)},
};

/* The constructor by name: a wall without a surface yet. */
static TlStatus tl_wall_trisurface_construct(const void *params, TlWall **w)
{
  const TriSurfaceParams *q = params;
  *w = NULL;
  TlWallTriSurface *t = NULL;
  TL_CHECK(TL_NEW(t));
  TlStatus status;
  t->base.ops = &tl_wall_trisurface_ops;
  snprintf(t->base.name, sizeof t->base.name, "trisurface");
  t->corrections = q->corrections != 0.0;
  t->brute_force = q->brute_force != 0.0;
  t->drift = q->drift != 0.0;
  t->feature_angle = q->feature_angle;
  t->motion.velocity = tl_v3(q->velocity[0], q->velocity[1], q->velocity[2]);
  t->motion.omega = tl_v3(q->omega[0], q->omega[1], q->omega[2]);
  t->motion.center = tl_v3(q->center[0], q->center[1], q->center[2]);
  t->motion.start = q->motion_start;
  t->motion.stop = q->motion_stop;
  t->n_threads = omp_get_max_threads();
  if (t->n_threads < 1) t->n_threads = 1;
  TL_CHECK_GOTO(status, tl_tricontacts_create(&t->current), fail);
  TL_CHECK_GOTO(status, tl_tricontacts_create(&t->previous), fail);
  TL_CHECK_GOTO(status, tl_calloc(&t->thread, (size_t)t->n_threads, sizeof *t->thread), fail);
  for (int k = 0; k < t->n_threads; ++k)
    TL_CHECK_GOTO(status, tl_tricontacts_create(&t->thread[k].found), fail);
  *w = &t->base;
  return TL_OK;
fail:
  tl_wall_trisurface_destroy_impl(&t->base);
  return status;
}

TlStatus tl_wall_trisurface_set_surface(TlWall *w, TlTriSurface *surface)
{
  if (!surface) TL_ERROR(TL_ERR_ARG, "tl_wall_trisurface_set_surface: NULL surface");
  if (!tl_wall_is_trisurface(w) || tl_as_trisurface(w)->surface) {
    tl_trisurface_destroy(&surface);
    if (!tl_wall_is_trisurface(w))
      TL_ERROR(TL_ERR_ARG, "wall '%s' is not a triangulated surface", w ? tl_type_name(w) : "(null)");
    TL_ERROR(TL_ERR_STATE, "wall '%s' has a surface already", w->name);
  }
  TlWallTriSurface *t = tl_as_trisurface(w);
  snprintf(t->base.name, sizeof t->base.name, "%s", surface->n_triangles == 1 ? "triangle" : "trisurface");
  t->surface = surface;
  /* the wall's feature angle classifies the surface's edges */
  TL_CHECK(tl_trisurface_set_feature_angle(surface, t->feature_angle));
  /* a motion given by name starts now */
  if (tl_v3_norm2(t->motion.velocity) > 0.0 || tl_v3_norm2(t->motion.omega) > 0.0) {
    TlRigidMotion m = t->motion;
    TL_CHECK(tl_wall_trisurface_set_motion(w, &m, m.start));
  }
  return TL_OK;
}

TlStatus tl_wall_trisurface_create(TlTriSurface *surface, TlWall **w)
{
  if (!w) {
    tl_trisurface_destroy(&surface);
    TL_ERROR(TL_ERR_ARG, "tl_wall_trisurface_create: NULL wall pointer");
  }
  *w = NULL;
  if (!surface) TL_ERROR(TL_ERR_ARG, "tl_wall_trisurface_create: NULL surface");
  /* the surface keeps the feature angle it was given */
  TlWallSetting angle = {"feature_angle", surface->feature_angle};
  TlStatus status = tl_wall_create("trisurface", 1, &angle, w);
  if (status == TL_OK) status = tl_wall_trisurface_set_surface(*w, surface);
  else tl_trisurface_destroy(&surface);
  if (status != TL_OK) {
    tl_wall_destroy(w);
    return tl_error_trace(status, __FILE__, __LINE__);
  }
  return TL_OK;
}

TlStatus tl_wall_triangle_create(TlVec3 a, TlVec3 b, TlVec3 c, TlWall **w)
{
  if (!w) TL_ERROR(TL_ERR_ARG, "tl_wall_triangle_create: NULL wall pointer");
  *w = NULL;
  double x[9] = {a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
  int tri[3] = {0, 1, 2};
  TlTriSurface *s = NULL;
  TL_CHECK(tl_trisurface_create(3, x, 1, tri, &s));
  TL_CHECK(tl_wall_trisurface_create(s, w));
  return TL_OK;
}

static void tl_wall_trisurface_bounding_box(const TlWall *w, TlVec3 *lo, TlVec3 *hi)
{
  const TlWallTriSurface *t = (const TlWallTriSurface *)w;
  if (!t->surface) { /* nothing yet: an empty box */
    *lo = tl_v3(INFINITY, INFINITY, INFINITY);
    *hi = tl_v3(-INFINITY, -INFINITY, -INFINITY);
    return;
  }
  *lo = t->surface->surface_lo;
  *hi = t->surface->surface_hi;
}

static TlStatus tl_wall_trisurface_threads(TlWallTriSurface *t, int *nthreads)
{
  int want = omp_get_max_threads();
  if (want > t->n_threads) {
    /* more threads than at creation: grow the per-thread buffers once */
    TL_CHECK(tl_realloc(&t->thread, (size_t)want, sizeof *t->thread));
    memset(t->thread + t->n_threads, 0, (size_t)(want - t->n_threads) * sizeof *t->thread);
    for (int k = t->n_threads; k < want; ++k) {
      TL_CHECK(tl_tricontacts_create(&t->thread[k].found));
      t->n_threads = k + 1;
    }
  }
  *nthreads = want < 1 ? 1 : want;
  return TL_OK;
}

/* Whether the candidate list must be rebuilt: never built, the particle
 * count or the skin changed, or the largest particle displacement plus the
 * largest vertex displacement since the build exceeds skin/2.  (A pair left
 * out was farther than radius + skin apart; every point of a triangle moves
 * at most as far as its farthest vertex.) */
static int tl_wall_trisurface_list_stale(const TlWallTriSurface *t, const TlParticles *p, double skin)
{
  if (!t->list_valid || t->n_list != p->n || skin != t->list_skin || skin <= 0.0) return 1;
  const TlTriSurface *s = t->surface;
  double dv2 = 0.0;
  if (t->list_version != s->version)
    for (size_t i = 0; i < s->n_vertices; ++i) {
      double d2 = tl_v3_norm2(tl_v3_sub(s->x[i], t->vertex_list[i]));
      dv2 = d2 > dv2 ? d2 : dv2;
    }
  double dp2 = 0.0;
  for (size_t i = 0; i < p->n; ++i) {
    double d2 = tl_v3_norm2(tl_v3_sub(p->x[i], t->x_list[i]));
    dp2 = d2 > dp2 ? d2 : dp2;
  }
  return sqrt(dp2) + sqrt(dv2) > 0.5 * skin;
}

/* Algorithm 2 with a skin: the triangles near particles (bins), each
 * triangle's box through the grid, every candidate within radius + skin
 * kept as a pair. */
static TlStatus tl_wall_trisurface_build_list(TlWallTriSurface *t, const TlWallStep *step, double skin)
{
  const TlTriSurface *s = t->surface;
  const TlParticles *p = step->particles;
  const TlDomain *domain = step->domain;
  TL_CHECK(tl_tribins_select(&t->bins, s, domain, p->n, p->x, p->radius, p->motion, skin));
  const int32_t *selected = t->bins.selected;
  long nt = (long)t->bins.n_selected;
  int nthreads;
  TL_CHECK(tl_wall_trisurface_threads(t, &nthreads));
  for (int k = 0; k < t->n_threads; ++k) t->thread[k].n_pairs = 0;
  TlStatus status = TL_OK;
  TL_PARALLEL_IF(nt > 4096, "omp parallel num_threads(nthreads)", {
    TlTriThread *th = &t->thread[omp_get_thread_num()];
    TlStatus local = TL_OK;
    _Pragma("omp for schedule(dynamic, 32)")
    for (long it = 0; it < nt; ++it) {
      int32_t tri = selected[it];
      if (local != TL_OK) continue;
      local = tl_hgrid_query_box(step->grid, s->box_lo[tri], s->box_hi[tri], &th->candidates,
                                 &th->candidate_capacity, &th->n_candidates);
      for (size_t m = 0; local == TL_OK && m < th->n_candidates; ++m) {
        size_t i = th->candidates[m];
        if (p->motion[i] != TL_MOTION_FREE) continue;
        if (!tl_trisurface_within(s, domain, tri, p->x[i], p->radius[i] + skin)) continue;
        local = tl_array_reserve(&th->pairs, &th->pair_capacity, 2 * th->n_pairs + 2, sizeof *th->pairs);
        if (local != TL_OK) break;
        th->pairs[2 * th->n_pairs] = tri;
        th->pairs[2 * th->n_pairs + 1] = (int32_t)i;
        ++th->n_pairs;
      }
    }
    if (local != TL_OK) {
      _Pragma("omp critical(tl_wall_trisurface_error)")
      status = local;
    }
  });
  if (status != TL_OK) return tl_error_trace(status, __FILE__, __LINE__);
  size_t total = 0;
  for (int k = 0; k < t->n_threads; ++k) total += t->thread[k].n_pairs;
  TL_CHECK(tl_array_reserve(&t->pair, &t->pair_capacity, 2 * total, sizeof *t->pair));
  t->n_pairs = 0;
  for (int k = 0; k < t->n_threads; ++k) {
    if (t->thread[k].n_pairs)
      memcpy(t->pair + 2 * t->n_pairs, t->thread[k].pairs, 2 * t->thread[k].n_pairs * sizeof *t->pair);
    t->n_pairs += t->thread[k].n_pairs;
  }
  TL_CHECK(tl_array_reserve(&t->x_list, &t->x_list_capacity, p->n, sizeof *t->x_list));
  if (p->n) memcpy(t->x_list, p->x, p->n * sizeof *p->x);
  t->n_list = p->n;
  TL_CHECK(tl_array_reserve(&t->vertex_list, &t->vertex_list_capacity, s->n_vertices, sizeof *t->vertex_list));
  memcpy(t->vertex_list, s->x, s->n_vertices * sizeof *s->x);
  t->list_version = s->version;
  t->list_skin = skin;
  t->list_valid = 1;
  ++t->list_builds;
  return TL_OK;
}

/* The distinct triangles of the candidate list (once per list build). */
static TlStatus tl_wall_trisurface_listed_triangles(TlWallTriSurface *t)
{
  if (t->listed_version == (unsigned long)t->list_builds) return TL_OK;
  const size_t nt = t->surface->n_triangles;
  TL_CHECK(tl_array_reserve(&t->listed, &t->listed_capacity, nt, sizeof *t->listed));
  /* a triangle appears once per particle near it: keep the first */
  TL_CHECK(tl_array_reserve(&t->seen, &t->seen_capacity, nt ? nt : 1, 1));
  unsigned char *seen = t->seen;
  memset(seen, 0, nt);
  t->n_listed = 0;
  for (size_t k = 0; k < t->n_pairs; ++k) {
    int32_t tri = t->pair[2 * k];
    if (!seen[tri]) seen[tri] = 1, t->listed[t->n_listed++] = tri;
  }
  t->listed_version = (unsigned long)t->list_builds;
  return TL_OK;
}

/* Contacts of this step into t->current (unsorted): the listed pairs
 * tested exactly, or every particle against every triangle (oracle, or no
 * grid given). */
static TlStatus tl_wall_trisurface_detect(TlWallTriSurface *t, const TlWallStep *step)
{
  const TlTriSurface *s = t->surface;
  const TlParticles *p = step->particles;
  const TlDomain *domain = step->domain;
  int use_list = step->grid && !t->brute_force;
  if (use_list) {
    double skin = step->grid->skin > 0.0 ? step->grid->skin : 0.0;
    if (tl_wall_trisurface_list_stale(t, p, skin)) {
      if (s->geometry_stale) TL_CHECK(tl_trisurface_update(t->surface));
      TL_CHECK(tl_wall_trisurface_build_list(t, step, skin));
    } else if (s->geometry_stale) {
      /* The surface moved without its geometry: refresh the listed
       * triangles only (the rest cannot be touched before the next build). */
      TL_CHECK(tl_wall_trisurface_listed_triangles(t));
      TL_CHECK(tl_trisurface_update_triangles(t->surface, t->n_listed, t->listed));
    }
  } else if (s->geometry_stale) {
    TL_CHECK(tl_trisurface_update(t->surface));
  }
  long n = use_list ? (long)t->n_pairs : (long)s->n_triangles;
  int nthreads;
  TL_CHECK(tl_wall_trisurface_threads(t, &nthreads));
  for (int k = 0; k < t->n_threads; ++k) tl_tricontacts_clear(t->thread[k].found);
  TlStatus status = TL_OK;
  long work = use_list ? n : n * (long)p->n;
  TL_PARALLEL_IF(work > 8192, "omp parallel num_threads(nthreads)", {
    TlTriThread *th = &t->thread[omp_get_thread_num()];
    TlStatus local = TL_OK;
    _Pragma("omp for schedule(static)")
    for (long it = 0; it < n; ++it) {
      if (local != TL_OK) continue;
      if (use_list) {
        int32_t tri = t->pair[2 * it], i = t->pair[2 * it + 1];
        local = tl_tricontacts_test(th->found, s, domain, tri, i, p->x[i], p->radius[i]);
      } else {
        for (size_t i = 0; local == TL_OK && i < p->n; ++i)
          if (p->motion[i] == TL_MOTION_FREE)
            local = tl_tricontacts_test(th->found, s, domain, (int32_t)it, (int32_t)i, p->x[i], p->radius[i]);
      }
    }
    if (local != TL_OK) {
      _Pragma("omp critical(tl_wall_trisurface_error)")
      status = local;
    }
  });
  if (status != TL_OK) return tl_error_trace(status, __FILE__, __LINE__);
  for (int k = 0; k < t->n_threads; ++k) TL_CHECK(tl_tricontacts_append_all(t->current, t->thread[k].found));
  return TL_OK;
}

static TlStatus tl_wall_trisurface_interact(TlWall *w, const TlWallStep *step)
{
  TlWallTriSurface *t = tl_as_trisurface(w);
  TlParticles *p = step->particles;
  const TlContactLaw *law = step->law;
  if (!p || !law) TL_ERROR(TL_ERR_ARG, "wall '%s': interact needs particles and a contact law", w->name);
  TL_REQUIRE_SURFACE(t);
  if (p->n > (size_t)INT32_MAX) TL_ERROR(TL_ERR_ARG, "%zu particles exceed the wall limit %d", p->n, INT32_MAX);

  /* last step's kept contacts (with history) become `previous` */
  tl_tricontacts_swap(t->current, t->previous);
  tl_tricontacts_clear(t->current);
  TL_CHECK(tl_wall_trisurface_detect(t, step));
  TL_CHECK(tl_tricontacts_sort(t->current));
  if (t->corrections) TL_CHECK(tl_tricontacts_merge_shared_edges(t->current, t->surface));
  TL_CHECK(tl_tricontacts_carry_history(t->current, t->previous, law->history_doubles));

  TlTriContactSet *set = t->current;
  size_t n = set->count, hd = law->history_doubles;
  TL_CHECK(tl_array_reserve(&t->geometry, &t->geometry_capacity, n, sizeof *t->geometry));
  TL_CHECK(tl_array_reserve(&t->result, &t->result_capacity, n, sizeof *t->result));
  const TlTriSurface *s = t->surface;
  const int rot = p->w != NULL;
  /* geometry records, i = particle, j = wall (tl_contact_law.h) */
  long nl = (long)n;
  TL_PARALLEL_IF(nl > 8192, "omp parallel for schedule(static)",
    for (long k = 0; k < nl; ++k) {
      const TlTriContactRecord *r = &set->c[k];
      size_t i = (size_t)r->particle;
      TlContactGeometry *g = &t->geometry[k];
      /* lever arm to the middle of the overlap, as between particles and for
       * the plane (or the radius, for a law that asks: tl_contact_lever); the
       * record keeps the point on the triangle for coupling */
      TlVec3 branch = tl_v3_scale(r->normal, -tl_contact_lever(law, r->radius, r->overlap));
      TlVec3 v_wall = tl_trisurface_velocity_at(s, r->triangle, r->bary);
      TlVec3 v_part = p->v[i];
      if (rot) v_part = tl_v3_add(v_part, tl_v3_cross(p->w[i], branch));
      g->normal = tl_v3_neg(r->normal);
      g->overlap = r->overlap;
      g->branch_i = branch;
      g->branch_j = tl_v3(0, 0, 0);
      g->vrel = tl_v3_sub(v_wall, v_part);
      g->spin_mean = rot ? tl_v3_scale(p->w[i], 0.5) : tl_v3(0, 0, 0);
      g->spin_rel = rot ? tl_v3_neg(p->w[i]) : tl_v3(0, 0, 0);
      g->meff = p->mass[i];
      g->reff = p->radius[i];
      g->history = hd ? set->history + (size_t)k * hd : NULL;
      g->bonded = 0;
    });
  /* the law: one batch per thread */
  TlStatus status = TL_OK;
  int nb = n > 8192 ? t->n_threads : 1;
  TL_PARALLEL_IF(nb > 1, "omp parallel for num_threads(nb) schedule(static)",
    for (int b = 0; b < nb; ++b) {
      size_t lo = n * (size_t)b / (size_t)nb, hi = n * (size_t)(b + 1) / (size_t)nb;
      TlContactBatch batch = {.n = hi - lo, .geometry = t->geometry + lo, .result = t->result + lo,
                              .dt = step->dt, .want_energy = step->want_energy};
      TlStatus local = hi > lo ? law->ops->evaluate(law, &batch) : TL_OK;
      if (local != TL_OK) {
        _Pragma("omp critical(tl_wall_trisurface_error)")
        status = local;
      }
    });
  if (status != TL_OK) return tl_error_trace(status, __FILE__, __LINE__);
  for (size_t k = 0; k < n; ++k) {
    set->c[k].force = t->result[k].force;
    set->c[k].torque = tl_v3_add(tl_v3_cross(t->geometry[k].branch_i, t->result[k].force), t->result[k].couple);
    set->c[k].weight = 1.0;
  }
  if (t->corrections) tl_tricontacts_apply_weights(set);

  /* forces on the particles, one group (particle) per iteration: race-free */
  long ng = (long)set->n_groups;
  TL_PARALLEL_IF(ng > 8192, "omp parallel for schedule(static)",
    for (long g = 0; g < ng; ++g) {
      size_t g0 = set->group[g], g1 = set->group[g + 1], i = (size_t)set->c[g0].particle;
      TlVec3 f = tl_v3(0, 0, 0), tq = tl_v3(0, 0, 0);
      for (size_t k = g0; k < g1; ++k) {
        f = tl_v3_add(f, set->c[k].force);
        tq = tl_v3_add(tq, set->c[k].torque);
      }
      p->f[i] = tl_v3_add(p->f[i], f);
      if (rot) p->torque[i] = tl_v3_add(p->torque[i], tq);
    });
  /* accounting */
  TlVec3 fw = tl_v3(0, 0, 0), tw = tl_v3(0, 0, 0);
  double energy = 0.0, power = 0.0, wall_power = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const TlTriContactRecord *r = &set->c[k];
    double wgt = r->weight;
    TlVec3 couple = tl_v3_scale(t->result[k].couple, wgt);
    fw = tl_v3_sub(fw, r->force);
    TlVec3 cp = tl_v3_add(r->center, t->geometry[k].branch_i);
    tw = tl_v3_sub(tw, tl_v3_add(tl_v3_cross(cp, r->force), couple));
    if (step->want_energy) {
      /* trapezoidal rule over the step, as for the plane and particle pairs */
      TlVec3 fm = tl_v3_scale(tl_v3_add(r->force, r->force_prev), 0.5);
      energy += wgt * t->result[k].elastic_energy;
      power += tl_v3_dot(fm, t->geometry[k].vrel) + tl_v3_dot(couple, t->geometry[k].spin_rel);
      wall_power += tl_v3_dot(fm, tl_trisurface_velocity_at(s, r->triangle, r->bary));
    }
  }
  w->force = fw;
  w->torque = tw;
  w->n_contacts = n;
  if (step->want_energy) {
    w->elastic_energy = energy;
    w->contact_work += step->dt * power;
    w->work += step->dt * wall_power;
  }
  return TL_OK;
}

static TlStatus tl_wall_trisurface_remap(TlWall *w, const size_t *old_to_new, size_t n_old)
{
  TlWallTriSurface *t = tl_as_trisurface(w);
  /* `current` holds the contacts whose history the next step will read;
   * the candidate list names old indices: rebuild it */
  TL_CHECK(tl_tricontacts_remap(t->current, old_to_new, n_old));
  t->list_valid = 0;
  return TL_OK;
}

static TlStatus tl_wall_trisurface_advance(TlWall *w, double time, double dt)
{
  TlWallTriSurface *t = tl_as_trisurface(w);
  if (t->moving) return tl_wall_trisurface_place(t, time + dt);
  if (!t->drift) return TL_OK;
  TL_REQUIRE_SURFACE(t);
  TlTriSurface *s = t->surface;
  for (size_t i = 0; i < s->n_vertices; ++i) s->x[i] = tl_v3_axpy(s->x[i], dt, s->v[i]);
  TL_CHECK(tl_trisurface_update(s));
  return TL_OK;
}

static TlStatus tl_wall_trisurface_visit_contacts(const TlWall *w, const TlParticles *particles, TlWallVisitor visit,
                                                  void *ctx)
{
  const TlTriContactSet *c = ((const TlWallTriSurface *)w)->current;
  (void)particles; /* the records hold what a visitor needs */
  for (size_t q = 0; c && q < c->count; ++q) {
    const TlTriContactRecord *r = &c->c[q];
    if (!r->active) continue;
    visit(ctx, (size_t)r->particle, r->force, r->point, r->center);
  }
  return TL_OK;
}

static const TlWallOps tl_wall_trisurface_ops = {
    .header = {"wall", "trisurface",
               "triangulated surface (triangle walls sharing vertices) with the triangle-edge corrections"},
    .bounding_box = tl_wall_trisurface_bounding_box,
    .interact = tl_wall_trisurface_interact,
    .remap = tl_wall_trisurface_remap,
    .advance = tl_wall_trisurface_advance,
    .checkpoint_size = tl_wall_trisurface_checkpoint_size,
    .checkpoint_save = tl_wall_trisurface_checkpoint_save,
    .checkpoint_load = tl_wall_trisurface_checkpoint_load,
    .destroy = tl_wall_trisurface_destroy_impl,
    .visit_contacts = tl_wall_trisurface_visit_contacts,
};

TlStatus tl_wall_register_trisurface(void)
{
  return tl_wall_register("trisurface", tl_wall_trisurface_ops.header.description, tl_wall_trisurface_construct,
                          &tl_wall_trisurface_ops, tl_wall_trisurface_params,
                          (int)(sizeof tl_wall_trisurface_params / sizeof tl_wall_trisurface_params[0]));
}
