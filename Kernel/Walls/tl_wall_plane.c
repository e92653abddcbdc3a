/* The infinite plane wall. */
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "tl_memory.h"
#include "tl_registry.h"
#include "tl_wall.h"

typedef struct {
  TlWall base;
  TlVec3 point, normal, velocity;
  /* per-particle contact state, indexed by particle index */
  size_t n, capacity, hd;
  double *history;
  uint8_t *touching;
  TlVec3 *force_prev; /* force on the particle at the last step (work by the trapezoidal rule) */
  /* Candidates: the particles that can reach the plane before the world's
   * next version (TlWallStep), ascending; the others are not scanned.  Kept
   * for `version` (0: none, every particle is scanned) while the plane has
   * moved less than `slack` along its normal since `point_cand`. */
  uint32_t *cand;
  size_t n_cand, cand_cap, n_cand_for;
  unsigned long version;
  TlVec3 point_cand;
  double slack;
} TlWallPlane;

enum { PLANE_CHUNK = 64 };

static void plane_bbox(const TlWall *w, TlVec3 *lo, TlVec3 *hi)
{
  const TlWallPlane *p = (const TlWallPlane *)w;
  /* an axis-aligned plane is bounded along its normal; any plane is
   * unbounded along at least two directions */
  *lo = tl_v3(-INFINITY, -INFINITY, -INFINITY);
  *hi = tl_v3(INFINITY, INFINITY, INFINITY);
  (void)p;
}

static TlStatus plane_fit(TlWallPlane *p, size_t n, size_t hd)
{
  if (hd != p->hd) {
    /* first use with this law: (re)start the history */
    p->hd = hd;
    p->capacity = 0;
    tl_free(&p->history);
    tl_free(&p->touching);
    tl_free(&p->force_prev);
    p->n = 0;
  }
  if (n > p->capacity) {
    size_t cap = n + n / 2 + 16;
    if (hd) TL_CHECK(tl_realloc(&p->history, cap * hd, sizeof *p->history));
    TL_CHECK(tl_realloc(&p->touching, cap, sizeof *p->touching));
    TL_CHECK(tl_realloc(&p->force_prev, cap, sizeof *p->force_prev));
    p->capacity = cap;
  }
  if (n > p->n) {
    if (hd) memset(p->history + p->n * hd, 0, (n - p->n) * hd * sizeof *p->history);
    memset(p->touching + p->n, 0, n - p->n);
    memset(p->force_prev + p->n, 0, (n - p->n) * sizeof *p->force_prev);
  }
  p->n = n;
  return TL_OK;
}

/* Evaluates a batch of contacts and adds their forces (the particles'
 * own: no other range touches them). */
static void flush(TlWallPlane *p, const TlWallStep *st, TlContactGeometry *g, TlContactResult *r, const size_t *idx,
                  size_t m, TlWallSums *sum)
{
  if (!m) return;
  TlContactBatch b = {m, g, r, st->dt, st->want_energy};
  TlStatus s = st->law->ops->evaluate(st->law, &b);
  if (s != TL_OK && sum->status == TL_OK) sum->status = s;
  TlParticles *P = st->particles;
  for (size_t c = 0; c < m; ++c) {
    size_t i = idx[c];
    TlVec3 F = r[c].force;
    P->f[i] = tl_v3_add(P->f[i], F);
    if (P->torque)
      P->torque[i] = tl_v3_add(P->torque[i], tl_v3_add(tl_v3_cross(g[c].branch_i, F), r[c].couple));
    TlVec3 cp = tl_v3_add(P->x[i], g[c].branch_i);
    sum->force = tl_v3_sub(sum->force, F);
    sum->torque = tl_v3_sub(sum->torque, tl_v3_cross(cp, F));
    if (st->want_energy) {
      /* trapezoidal rule over the step, as for particle contacts */
      TlVec3 Fm = tl_v3_scale(tl_v3_add(F, p->force_prev[i]), 0.5);
      sum->elastic += r[c].elastic_energy;
      sum->power += tl_v3_dot(Fm, g[c].vrel) + tl_v3_dot(r[c].couple, g[c].spin_rel);
      sum->work += tl_v3_dot(Fm, p->velocity);
    }
    p->force_prev[i] = F;
  }
}

/* A particle's contact state, cleared when it leaves the plane. */
static inline void plane_release(TlWallPlane *p, size_t i)
{
  p->touching[i] = 0;
  p->force_prev[i] = tl_v3(0, 0, 0);
  if (p->hd) memset(p->history + i * p->hd, 0, p->hd * sizeof *p->history);
}

/* The candidates for the world's version: every particle within reach of
 * the plane, counting both the particles' moves (2 reach: from where they
 * were when the version began to here, and on) and the plane's (slack, one
 * reach); the others, which cannot touch before the next version, are
 * released now. */
static TlStatus plane_candidates(TlWallPlane *p, const TlWallStep *st)
{
  const TlParticles *P = st->particles;
  const size_t n = P->n;
  p->version = 0;
  if (n > UINT32_MAX) return TL_OK; /* indices too large to keep: scan every particle */
  TL_CHECK(tl_array_reserve(&p->cand, &p->cand_cap, n + 1, sizeof *p->cand));
  const double reach = st->reach, margin = 3.0 * reach;
  const TlVec3 nrm = p->normal, pt = p->point;
  size_t m = 0;
  for (size_t i = 0; i < n; ++i) {
    const double s = tl_v3_dot(tl_v3_sub(P->x[i], pt), nrm);
    if (s < P->radius[i] + margin) p->cand[m++] = (uint32_t)i;
    else if (p->touching[i]) plane_release(p, i);
  }
  p->n_cand = m;
  p->n_cand_for = n;
  p->point_cand = pt;
  p->slack = reach;
  p->version = st->version;
  return TL_OK;
}

static TlStatus plane_prepare(TlWall *w, const TlWallStep *st)
{
  TlWallPlane *p = (TlWallPlane *)w;
  const size_t n = st->particles->n;
  TL_CHECK(plane_fit(p, n, st->law->history_doubles));
  const int promise = st->version != 0 && isfinite(st->reach) && st->reach > 0.0;
  if (!promise) {
    p->version = 0;
    return TL_OK;
  }
  const double moved = fabs(tl_v3_dot(tl_v3_sub(p->point, p->point_cand), p->normal));
  if (p->version != st->version || p->n_cand_for != n || !(moved <= p->slack)) TL_CHECK(plane_candidates(p, st));
  return TL_OK;
}

/* The contacts of particles [lo, hi).  Every particle touches a plane at
 * most once, so disjoint ranges write disjoint forces and contact state:
 * race-free by construction.  The scan reads through local pointers so that
 * the far particles (most of them) cost a few instructions each. */
static void plane_range(TlWall *w, const TlWallStep *st, size_t lo, size_t hi, TlWallSums *sum)
{
  TlWallPlane *p = (TlWallPlane *)w;
  const TlParticles *P = st->particles;
  const size_t hd = p->hd;
  const TlVec3 nrm = p->normal, pt = p->point;
  const TlVec3 *x = P->x;
  const double *restrict radius = P->radius;
  const uint8_t *restrict motion = P->motion;
  uint8_t *touching = p->touching;
  const int lever_radius = st->law->lever_radius;
  TlContactGeometry g[PLANE_CHUNK];
  TlContactResult r[PLANE_CHUNK];
  size_t idx[PLANE_CHUNK], m = 0;
  /* the candidates in [lo, hi), or every particle of it */
  const uint32_t *cand = p->cand;
  size_t k = 0, k_end = hi - lo;
  if (p->version) {
    size_t a = 0, b = p->n_cand;
    while (a < b) {
      const size_t c = a + (b - a) / 2;
      if (cand[c] < lo) a = c + 1;
      else b = c;
    }
    k = a;
    for (k_end = a; k_end < p->n_cand && cand[k_end] < hi; ++k_end) {}
  }
  for (; k < k_end; ++k) {
    const size_t i = p->version ? cand[k] : lo + k;
    const double s = tl_v3_dot(tl_v3_sub(x[i], pt), nrm);
    const double ri = radius[i];
    if (s >= ri || motion[i] != TL_MOTION_FREE) {
      if (touching[i]) plane_release(p, i);
      continue;
    }
    touching[i] = 1;
    sum->n_contacts++;
    TlContactGeometry *c = &g[m];
    c->normal = tl_v3_neg(nrm);
    c->overlap = ri - s;
    /* the middle of the overlap, as between particles, or the radius for a
     * law that asks for it (tl_contact_lever) */
    c->branch_i = lever_radius ? tl_v3_scale(nrm, -ri) : tl_v3_scale(nrm, -0.5 * (ri + s));
    c->branch_j = tl_v3(0, 0, 0);
    TlVec3 vi = P->v[i];
    if (P->w) {
      vi = tl_v3_add(vi, tl_v3_cross(P->w[i], c->branch_i));
      c->spin_mean = tl_v3_scale(P->w[i], 0.5);
      c->spin_rel = tl_v3_neg(P->w[i]);
    } else {
      c->spin_mean = c->spin_rel = tl_v3(0, 0, 0);
    }
    c->vrel = tl_v3_sub(p->velocity, vi);
    c->meff = P->mass[i];
    c->reff = ri;
    c->history = hd ? p->history + i * hd : NULL;
    c->bonded = 0;
    idx[m++] = i;
    if (m == PLANE_CHUNK) {
      flush(p, st, g, r, idx, m, sum);
      m = 0;
    }
  }
  flush(p, st, g, r, idx, m, sum);
}

/* On its own (outside the world's step): the blocks one after another. */
static TlStatus plane_interact(TlWall *w, const TlWallStep *st) { return tl_wall_interact_blocks(w, st); }

static TlStatus plane_remap(TlWall *w, const size_t *old_to_new, size_t n_old)
{
  TlWallPlane *p = (TlWallPlane *)w;
  if (!p->n) return TL_OK;
  size_t n = p->n < n_old ? p->n : n_old, hd = p->hd, n_new = 0;
  for (size_t k = 0; k < n; ++k)
    if (old_to_new[k] != SIZE_MAX && old_to_new[k] + 1 > n_new) n_new = old_to_new[k] + 1;
  double *h = NULL;
  uint8_t *t = NULL;
  size_t cap = p->capacity > n_new ? p->capacity : n_new + 16;
  if (hd) TL_CHECK(tl_calloc(&h, cap * hd, sizeof *h));
  TL_CHECK(tl_calloc(&t, cap, sizeof *t));
  TlVec3 *fp = NULL;
  TL_CHECK(tl_calloc(&fp, cap, sizeof *fp));
  for (size_t k = 0; k < n; ++k) {
    size_t q = old_to_new[k];
    if (q == SIZE_MAX) continue;
    t[q] = p->touching[k];
    fp[q] = p->force_prev[k];
    if (hd) memcpy(h + q * hd, p->history + k * hd, hd * sizeof *h);
  }
  tl_free(&p->history);
  tl_free(&p->touching);
  tl_free(&p->force_prev);
  p->history = h;
  p->touching = t;
  p->force_prev = fp;
  p->capacity = cap;
  p->n = n_new;
  p->version = 0; /* indices changed: the candidates go */
  return TL_OK;
}

static TlStatus plane_advance(TlWall *w, double t, double dt)
{
  TlWallPlane *p = (TlWallPlane *)w;
  p->point = tl_v3_axpy(p->point, dt, p->velocity);
  return TL_OK;
}

static size_t plane_checkpoint_size(const TlWall *w)
{
  const TlWallPlane *p = (const TlWallPlane *)w;
  return 6 * sizeof(double) + 2 * sizeof(size_t) + p->n * (p->hd * sizeof(double) + 1 + sizeof(TlVec3));
}

static TlStatus plane_save(const TlWall *w, void *buffer, size_t size)
{
  const TlWallPlane *p = (const TlWallPlane *)w;
  if (size < plane_checkpoint_size(w)) TL_ERROR(TL_ERR_ARG, "plane checkpoint buffer %zu bytes < %zu", size, plane_checkpoint_size(w));
  char *b = buffer;
  double v[6] = {p->point.x, p->point.y, p->point.z, p->velocity.x, p->velocity.y, p->velocity.z};
  memcpy(b, v, sizeof v); b += sizeof v;
  memcpy(b, &p->n, sizeof p->n); b += sizeof p->n;
  memcpy(b, &p->hd, sizeof p->hd); b += sizeof p->hd;
  if (p->hd) { memcpy(b, p->history, p->n * p->hd * sizeof(double)); b += p->n * p->hd * sizeof(double); }
  memcpy(b, p->touching, p->n);
  b += p->n;
  memcpy(b, p->force_prev, p->n * sizeof(TlVec3));
  return TL_OK;
}

static TlStatus plane_load(TlWall *w, const void *buffer, size_t size)
{
  TlWallPlane *p = (TlWallPlane *)w;
  const char *b = buffer;
  size_t n, hd;
  double v[6];
  if (size < sizeof v + 2 * sizeof(size_t)) TL_ERROR(TL_ERR_FORMAT, "plane checkpoint of %zu bytes is too short", size);
  memcpy(v, b, sizeof v); b += sizeof v;
  memcpy(&n, b, sizeof n); b += sizeof n;
  memcpy(&hd, b, sizeof hd); b += sizeof hd;
  /* Counts bounded by the buffer before they are multiplied (no overflow). */
  if (n > size || hd > size || size != sizeof v + 2 * sizeof(size_t) + n * (hd * sizeof(double) + 1 + sizeof(TlVec3)))
    TL_ERROR(TL_ERR_FORMAT, "plane checkpoint of %zu bytes does not hold %zu particles of %zu history doubles", size, n,
             hd);
  for (int k = 0; k < 6; ++k)
    if (!isfinite(v[k]))
      TL_ERROR(TL_ERR_FORMAT, "plane checkpoint: %s component %d is %g, not a finite number", k < 3 ? "point" : "velocity",
               k % 3, v[k]);
  for (size_t k = 0; k < n * hd; ++k) {
    double h;
    memcpy(&h, b + k * sizeof h, sizeof h);
    if (!isfinite(h)) TL_ERROR(TL_ERR_FORMAT, "plane checkpoint: history value %zu is %g, not a finite number", k, h);
  }
  p->point = tl_v3(v[0], v[1], v[2]);
  p->velocity = tl_v3(v[3], v[4], v[5]);
  p->hd = SIZE_MAX; /* force a reset in plane_fit */
  p->version = 0;
  TL_CHECK(plane_fit(p, n, hd));
  if (hd) { memcpy(p->history, b, n * hd * sizeof(double)); b += n * hd * sizeof(double); }
  memcpy(p->touching, b, n);
  b += n;
  memcpy(p->force_prev, b, n * sizeof(TlVec3));
  return TL_OK;
}

int tl_wall_plane_contact_force(const TlWall *w, size_t i, TlVec3 *force)
{
  const TlWallPlane *p = (const TlWallPlane *)w;
  if (i >= p->n || !p->touching[i]) return 0;
  *force = p->force_prev[i];
  return 1;
}

static TlStatus plane_visit_contacts(const TlWall *w, const TlParticles *P, TlWallVisitor visit, void *ctx)
{
  const TlWallPlane *p = (const TlWallPlane *)w;
  for (size_t i = 0; i < P->n && i < p->n; ++i) {
    if (!p->touching[i]) continue;
    double s = tl_v3_dot(tl_v3_sub(P->x[i], p->point), p->normal);
    visit(ctx, i, p->force_prev[i], tl_v3_axpy(P->x[i], -s, p->normal), P->x[i]);
  }
  return TL_OK;
}

static void plane_destroy(TlWall *w)
{
  TlWallPlane *p = (TlWallPlane *)w;
  tl_free(&p->force_prev);
  tl_free(&p->history);
  tl_free(&p->touching);
  tl_free(&p->cand);
  tl_free(&p);
}

static const TlWallOps plane_ops = {{"wall", "plane", "infinite plane, particles on the side of its normal"},
                                    plane_bbox, plane_interact, plane_remap, plane_advance,
                                    plane_checkpoint_size, plane_save, plane_load, plane_destroy,
                                    plane_visit_contacts, plane_prepare, plane_range};

/* The parameter block of the plane's constructor by name. */
typedef struct {
  double point_x, point_y, point_z, normal_x, normal_y, normal_z, velocity_x, velocity_y, velocity_z;
} PlaneParams;

static const TlParam plane_params[] = {
    {"point_x", 0.0, -DBL_MAX, DBL_MAX, "m", "a point of the plane, x", offsetof(PlaneParams, point_x)},
    {"point_y", 0.0, -DBL_MAX, DBL_MAX, "m", "a point of the plane, y", offsetof(PlaneParams, point_y)},
    {"point_z", 0.0, -DBL_MAX, DBL_MAX, "m", "a point of the plane, z", offsetof(PlaneParams, point_z)},
    {"normal_x", 0.0, -DBL_MAX, DBL_MAX, "1", "normal towards the particles, x (normalised)", offsetof(PlaneParams, normal_x)},
    {"normal_y", 0.0, -DBL_MAX, DBL_MAX, "1", "normal towards the particles, y (normalised)", offsetof(PlaneParams, normal_y)},
    {"normal_z", 1.0, -DBL_MAX, DBL_MAX, "1", "normal towards the particles, z (normalised)", offsetof(PlaneParams, normal_z)},
    {"velocity_x", 0.0, -DBL_MAX, DBL_MAX, "m/s", "velocity of the plane, x", offsetof(PlaneParams, velocity_x)},
    {"velocity_y", 0.0, -DBL_MAX, DBL_MAX, "m/s", "velocity of the plane, y", offsetof(PlaneParams, velocity_y)},
    {"velocity_z", 0.0, -DBL_MAX, DBL_MAX, "m/s", "velocity of the plane, z", offsetof(PlaneParams, velocity_z)},
};

static TlStatus plane_construct(const void *params, TlWall **w)
{
  const PlaneParams *q = params;
  TL_CHECK(tl_wall_plane_create(tl_v3(q->point_x, q->point_y, q->point_z), tl_v3(q->normal_x, q->normal_y, q->normal_z), w));
  ((TlWallPlane *)*w)->velocity = tl_v3(q->velocity_x, q->velocity_y, q->velocity_z);
  return TL_OK;
}

TlStatus tl_wall_register_plane(void)
{
  return tl_wall_register("plane", plane_ops.header.description, plane_construct, &plane_ops, plane_params,
                          (int)(sizeof plane_params / sizeof plane_params[0]));
}

TlStatus tl_wall_plane_create(TlVec3 point, TlVec3 normal, TlWall **w)
{
  double len = tl_v3_norm(normal);
  if (!(len > 0.0) || !isfinite(len))
    TL_ERROR(TL_ERR_ARG, "plane wall: normal (%g, %g, %g) must be non-zero and finite", normal.x, normal.y, normal.z);
  if (!tl_v3_isfinite(point)) TL_ERROR(TL_ERR_ARG, "plane wall: point (%g, %g, %g) not finite", point.x, point.y, point.z);
  TlWallPlane *p;
  TL_CHECK(TL_NEW(p));
  p->base.ops = &plane_ops;
  snprintf(p->base.name, sizeof p->base.name, "plane");
  p->base.law = 0;
  p->point = point;
  p->normal = tl_v3_scale(normal, 1.0 / len);
  *w = &p->base;
  return TL_OK;
}

TlStatus tl_wall_plane_set_velocity(TlWall *w, TlVec3 velocity)
{
  /* the type's own downcast guard (not a dispatch) */
  if (w->ops != &plane_ops) TL_ERROR(TL_ERR_ARG, "wall '%s' is not a plane", w->ops->header.name);
  if (!tl_v3_isfinite(velocity)) TL_ERROR(TL_ERR_ARG, "plane wall: velocity not finite");
  ((TlWallPlane *)w)->velocity = velocity;
  return TL_OK;
}

void tl_wall_plane_get(const TlWall *w, TlVec3 *point, TlVec3 *normal)
{
  const TlWallPlane *p = (const TlWallPlane *)w;
  *point = p->point;
  *normal = p->normal;
}
