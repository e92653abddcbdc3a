/* The DEM contact loop: body forces, then every contact of the neighbour
 * list and the bonds evaluated by chunks of one law, then the walls. */
#include "tl_dem_private.h"

#include <math.h>
#include <omp.h>
#include <string.h>
#include "tl_contact_kernels.h"
#include "tl_memory.h"
#include "tl_parallel.h"

typedef struct {
  double elastic, power;
  size_t touching;
} Accum;

/* What one chunk of contacts needs; filled once per list evaluation. */
typedef struct {
  TlDem *d;
  TlContactList *L;
  const TlVec3 *x, *v, *w;
  const double *radius, *inv_mass, *mass;
  const double (*xr)[4];
  const double *cw; /* per-contact weights, NULL: unweighted */
  TlVec3 *F, *T;
  double len[3], half[3];
  double hm[4], hinv[4], lm[4]; /* in-plane blocks of h, h⁻¹ and L (2-D world) */
  int bonded, want_energy;
  size_t hd;
  double el, pw;
  double *chunk_el, *chunk_pw; /* per chunk, when energy is tracked */
  size_t touching;
  TlStatus status;
  /* threads (Split): the owners of the particles, this thread, its
   * deferred contributions; owner NULL on one thread */
  const uint8_t *owner;
  int tid;
  Deferred *def;
  size_t n_def, def_cap;
  TlVec3 spin_mean[CHUNK], spin_rel[CHUNK]; /* staged spins of a chunk */
} ChunkCtx;

/* The nearest periodic image of a branch vector in an orthogonal box. */
static inline void minimum_image_ortho(const ChunkCtx *c, TlVec3 *b)
{
  double *bc = &b->x;
  for (int q = 0; q < 3; ++q) {
    if (c->len[q] <= 0.0) continue;
    if (bc[q] > c->half[q]) bc[q] -= c->len[q];
    else if (bc[q] < -c->half[q]) bc[q] += c->len[q];
  }
}

/* A pair that has separated: its force and history start again from zero. */
static inline void release_contact(TlContactList *L, size_t k, size_t hd)
{
  if (!L->touching[k]) return;
  L->touching[k] = 0;
  L->force[k] = tl_v3(0, 0, 0);
  if (hd) memset(L->history + k * hd, 0, hd * sizeof(double));
}

/* A contribution to a particle another thread owns, kept for later. */
static inline void defer(ChunkCtx *c, uint32_t p, TlVec3 f, TlVec3 t)
{
  if (c->n_def >= c->def_cap) {
    c->status = TL_ERR_STATE; /* the split counted too few: a bug, never silent */
    return;
  }
  c->def[c->n_def++] = (Deferred){p, f, t};
}

_Static_assert((int)CHUNK <= (int)TL_CONTACT_CHUNK, "a chunk of the contact list must fit a TlContactChunk");

/* Spins of a scene without rotation. */
static const TlVec3 no_spin[TL_CONTACT_CHUNK];

/* The contact loop of one chunk, specialised at compile time on the domain
 * kind (ORTHO: orthogonal periodic box; GENERAL: sheared or deforming cell),
 * on rotation and on the dimension (PLANAR: a 2-D world, in-plane branch
 * vectors, normals and relative velocities, spins about z, forces in x, y
 * and torques about z only), so the common cases carry no dead branches.  It stages
 * the touching contacts' geometry in cc, has the chunk's law evaluate them
 * (one call per chunk, whatever the law), then scatters the forces.  The
 * same path serves every law: the built-in parts, a composition of them and
 * a law or part defined outside the library. */
static inline __attribute__((always_inline)) void process_chunk(ChunkCtx *c, TlContactChunk *cc, Chunk ch,
                                                                const int ORTHO, const int GENERAL, const int ROT,
                                                                const int PLANAR, const int WEIGHTED)
{
  TlDem *d = c->d;
  TlContactList *L = c->L;
  const TlVec3 *x = c->x, *v = c->v, *w = c->w;
  const double *radius = c->radius, *inv_mass = c->inv_mass;
  const TlDomain *dom = &d->domain;
  const size_t hd = c->hd;
  const int bonded = c->bonded, want = c->want_energy;
  const double(*xr)[4] = c->xr;
  TlVec3 *spin_mean = c->spin_mean, *spin_rel = c->spin_rel;
  double li_[CHUNK], lj_[CHUNK]; /* lever arms along ±n */
  uint32_t idx[CHUNK];
  size_t m = 0;
  const TlContactLaw *law = d->laws[ch.law];
  /* r - δ/2 (the middle of the overlap) or, for a law that asks, the radius
   * (tl_contact_lever): the same subtraction either way, so that the default
   * rounds as before */
  const double half = law->lever_radius ? 0.0 : 0.5;
  /* spins staged for the laws that read them (and for the power of
   * couples when energy is tracked) */
  const int spins = ROT && (!law->ignores_spins || want);
  for (size_t k = ch.start; k < ch.end; ++k) {
    const uint32_t i = L->i[k], j = L->j[k];
    TlVec3 b;
    double ri, rj;
    if (GENERAL && PLANAR) {
      /* Eq. 20 in the plane */
      const double bx = xr[j][0] - xr[i][0], by = xr[j][1] - xr[i][1];
      const double sx = c->hinv[0] * bx + c->hinv[1] * by, sy = c->hinv[2] * bx + c->hinv[3] * by;
      const double rx = sx - nearbyint(sx), ry = sy - nearbyint(sy);
      b.x = c->hm[0] * rx + c->hm[1] * ry;
      b.y = c->hm[2] * rx + c->hm[3] * ry;
      b.z = 0.0;
      ri = xr[i][3];
      rj = xr[j][3];
    } else if (GENERAL) {
      b = tl_domain_branch(dom, x[i], x[j]);
      ri = radius[i];
      rj = radius[j];
    } else if (PLANAR) {
      b.x = xr[j][0] - xr[i][0];
      b.y = xr[j][1] - xr[i][1];
      b.z = 0.0;
      ri = xr[i][3];
      rj = xr[j][3];
      if (ORTHO)
        for (int q = 0; q < 2; ++q) {
          double *bc = q ? &b.y : &b.x;
          if (c->len[q] <= 0.0) continue;
          if (*bc > c->half[q]) *bc -= c->len[q];
          else if (*bc < -c->half[q]) *bc += c->len[q];
        }
    } else {
      b.x = xr[j][0] - xr[i][0];
      b.y = xr[j][1] - xr[i][1];
      b.z = xr[j][2] - xr[i][2];
      ri = xr[i][3];
      rj = xr[j][3];
      if (ORTHO) minimum_image_ortho(c, &b);
    }
    const double cut = ri + rj;
    const double r2 = PLANAR ? b.x * b.x + b.y * b.y : b.x * b.x + b.y * b.y + b.z * b.z;
    if (r2 >= cut * cut && !bonded) {
      release_contact(L, k, hd);
      continue;
    }
    const double dist = sqrt(r2);
    const double inv = dist > 0.0 ? 1.0 / dist : 0.0;
    const TlVec3 n = dist > 0.0 ? tl_v3_scale(b, inv) : tl_v3(1, 0, 0);
    const double delta = cut - dist;
    const double li = ri - half * delta, lj = rj - half * delta;
    TlVec3 vr = {v[j].x - v[i].x, v[j].y - v[i].y, PLANAR ? 0.0 : v[j].z - v[i].z};
    if (PLANAR && GENERAL && dom->deforming) {
      vr.x += c->lm[0] * b.x + c->lm[1] * b.y;
      vr.y += c->lm[2] * b.x + c->lm[3] * b.y;
    } else if (GENERAL && dom->deforming) {
      vr = tl_v3_add(vr, tl_m3_mulv(dom->L, b));
    }
    if (ROT && PLANAR) {
      /* -(lj ω_j + li ω_i) × n with spins about z */
      const double wi = w[i].z, wj = w[j].z;
      const double sz = lj * wj + li * wi;
      vr.x += sz * n.y;
      vr.y -= sz * n.x;
      if (spins) {
        spin_mean[m] = (TlVec3){0.0, 0.0, 0.5 * (wi + wj)};
        spin_rel[m] = (TlVec3){0.0, 0.0, wj - wi};
      }
    } else if (ROT) {
      const TlVec3 wi = w[i], wj = w[j];
      /* ω_j × (-lj n) - ω_i × (li n) = -(lj ω_j + li ω_i) × n */
      TlVec3 s = {lj * wj.x + li * wi.x, lj * wj.y + li * wi.y, lj * wj.z + li * wi.z};
      vr = tl_v3_sub(vr, tl_v3_cross(s, n));
      if (spins) {
        spin_mean[m] = tl_v3_scale(tl_v3_add(wi, wj), 0.5);
        spin_rel[m] = tl_v3_sub(wj, wi);
      }
    }
#if defined(__x86_64__) && defined(__GNUC__)
    /* vr stays three scalars, as in a loop that uses it at once: staged as a
     * vector, the compiler would contract the cross product into fused
     * multiply-adds in another order and move the last bit of the forces */
    __asm__("" : "+x"(vr.x), "+x"(vr.y), "+x"(vr.z));
#endif
    const double isum = inv_mass[i] + inv_mass[j];
    cc->normal[m] = n;
    cc->overlap[m] = delta;
    cc->vrel[m] = vr;
    cc->meff[m] = isum > 0.0 ? 1.0 / isum : 0.5 * (c->mass[i] + c->mass[j]);
    cc->reff[m] = ri * rj / cut;
    cc->history[m] = hd ? L->history + k * hd : NULL;
    cc->bonded[m] = (unsigned char)bonded;
    li_[m] = li;
    lj_[m] = lj;
    idx[m++] = (uint32_t)k;
  }
  if (!m) return;
  cc->n = m;
  cc->spin_mean = spins ? spin_mean : no_spin;
  cc->spin_rel = spins ? spin_rel : no_spin;
  TlStatus st = law->ops->evaluate_chunk(law, cc);
  if (st != TL_OK) {
    c->status = st;
    return;
  }
  TlVec3 *F = c->F, *T = c->T;
  for (size_t q = 0; q < m; ++q) {
    const size_t k = idx[q];
    if (!cc->on[q]) {
      if (L->touching[k]) {
        L->touching[k] = 0;
        L->force[k] = tl_v3(0, 0, 0);
      }
      continue;
    }
    const uint32_t i = L->i[k], j = L->j[k];
    TlVec3 f = cc->force[q], cpl = cc->couple[q];
    /* a weighted contact (seeds/001 Eq. 24) acts with w_ab f on both
     * particles and stores w_ab of its energy; its history is the law's */
    const double wk = WEIGHTED ? c->cw[k] : 1.0;
    if (want) {
      /* work of the contact over the step by the trapezoidal rule on the
       * relative displacement dt vrel (vrel is the half-step velocity), so
       * the dissipation booked is second-order accurate */
      const TlVec3 fo = L->touching[k] ? L->force[k] : tl_v3(0, 0, 0);
      const double e = cc->energy[q];
      const double p = 0.5 * tl_v3_dot(tl_v3_add(fo, f), cc->vrel[q]) + tl_v3_dot(cpl, cc->spin_rel[q]);
      c->el += WEIGHTED ? wk * e : e;
      c->pw += WEIGHTED ? wk * p : p;
    }
    L->force[k] = f;
    L->touching[k] = 1;
    if (WEIGHTED) {
      f = tl_v3_scale(f, wk);
      cpl = tl_v3_scale(cpl, wk);
    }
    /* torques: branch_i = li n, branch_j = -lj n; each term formed once, so
     * that a deferred contribution adds the same number */
    TlVec3 ti = {0.0, 0.0, 0.0}, tj = {0.0, 0.0, 0.0};
    if (ROT && PLANAR) {
      const TlVec3 n = cc->normal[q];
      const double nfz = n.x * f.y - n.y * f.x;
      ti.z = li_[q] * nfz + cpl.z;
      tj.z = lj_[q] * nfz - cpl.z;
    } else if (ROT) {
      const TlVec3 n = cc->normal[q];
      const double li = li_[q], lj = lj_[q];
      const TlVec3 nf = tl_v3_cross(n, f);
      ti = (TlVec3){li * nf.x + cpl.x, li * nf.y + cpl.y, li * nf.z + cpl.z};
      tj = (TlVec3){lj * nf.x - cpl.x, lj * nf.y - cpl.y, lj * nf.z - cpl.z};
    }
#if defined(__x86_64__) && defined(__GNUC__)
    /* the terms are fixed here, before the paths part: left free, the
     * compiler forms them in each path with its own fused multiply-adds */
    __asm__("" : "+x"(ti.x), "+x"(ti.y), "+x"(ti.z));
    __asm__("" : "+x"(tj.x), "+x"(tj.y), "+x"(tj.z));
#endif
    if (!c->owner || c->owner[i] == c->tid) {
      if (PLANAR) {
        F[i].x += f.x; F[i].y += f.y;
      } else {
        F[i].x += f.x; F[i].y += f.y; F[i].z += f.z;
      }
      if (ROT && PLANAR) T[i].z += ti.z;
      else if (ROT) {
        T[i].x += ti.x; T[i].y += ti.y; T[i].z += ti.z;
      }
    } else {
      defer(c, i, f, ti);
    }
    if (!c->owner || c->owner[j] == c->tid) {
      if (PLANAR) {
        F[j].x -= f.x; F[j].y -= f.y;
      } else {
        F[j].x -= f.x; F[j].y -= f.y; F[j].z -= f.z;
      }
      if (ROT && PLANAR) T[j].z += tj.z;
      else if (ROT) {
        T[j].x += tj.x; T[j].y += tj.y; T[j].z += tj.z;
      }
    } else {
      /* a - b and a + (-b) round alike: the sum is the one thread's */
      defer(c, j, tl_v3_neg(f), tj);
    }
    c->touching++;
  }
}

/* Energy and power of a chunk, kept per chunk and summed in chunk order
 * after the loop, so that they too do not depend on the thread count. */
static inline void chunk_sums(ChunkCtx *c, size_t k)
{
  if (!c->want_energy) return;
  c->chunk_el[k] = c->el;
  c->chunk_pw[k] = c->pw;
  c->el = c->pw = 0.0;
}

#define TL_DISPATCH_ROT(FN, G, O, P, ...)                                               \
  do {                                                                                  \
    if (rot) for (size_t k = lo; k < hi; ++k) { FN(c, cc, chunks[k], O, G, 1, P __VA_ARGS__); chunk_sums(c, k); } \
    else for (size_t k = lo; k < hi; ++k) { FN(c, cc, chunks[k], O, G, 0, P __VA_ARGS__); chunk_sums(c, k); }     \
  } while (0)
#define TL_DISPATCH_CHUNKS(FN, ...)                                                  \
  do {                                                                               \
    if (planar) {                                                                    \
      if (general) TL_DISPATCH_ROT(FN, 1, 0, 1, __VA_ARGS__);                        \
      else if (ortho) TL_DISPATCH_ROT(FN, 0, 1, 1, __VA_ARGS__);                     \
      else TL_DISPATCH_ROT(FN, 0, 0, 1, __VA_ARGS__);                                \
    } else if (general) {                                                            \
      TL_DISPATCH_ROT(FN, 1, 0, 0, __VA_ARGS__);                                     \
    } else if (ortho) {                                                              \
      TL_DISPATCH_ROT(FN, 0, 1, 0, __VA_ARGS__);                                     \
    } else {                                                                         \
      TL_DISPATCH_ROT(FN, 0, 0, 0, __VA_ARGS__);                                     \
    }                                                                                \
  } while (0)

/* Compiled twice: for x86-64 with AVX2 and FMA (three-operand forms and
 * fused multiply-adds shorten this register-hungry loop by a third) and for
 * the baseline; the loader picks the one the processor runs.  The parts'
 * chunk loops carry the same clones (evaluate_hot), so the arithmetic of a
 * contact is the one of a single fused loop. */
#define TL_HOT_CLONES TL_CONTACT_HOT_CLONES

/* The contact loop of a range of chunks, every law through the same path.
 * It is compiled twice: unweighted (the plain world's loop, its code
 * untouched by the weights) and with per-contact weights (a volume
 * coupling's overlap), both for the same processors so that weights of 1
 * give the same arithmetic. */
#define TL_DEFINE_PROCESS_RANGE(name, weighted)                                                              \
  TL_HOT_CLONES static void name(ChunkCtx *c, const Chunk *chunks, size_t lo, size_t hi)                     \
  {                                                                                                          \
    const TlDomain *dom = &c->d->domain;                                                                     \
    const int general = dom->any_periodic && (dom->kind != TL_DOMAIN_PERIODIC_BOX || dom->deforming);       \
    const int ortho = dom->any_periodic && !general;                                                         \
    const int rot = c->w != NULL;                                                                            \
    const int planar = c->d->dim == 2;                                                                       \
    TlContactChunk chunk;                                                                                    \
    TlContactChunk *cc = &chunk;                                                                             \
    cc->dt = c->d->dt;                                                                                       \
    cc->want_energy = c->want_energy;                                                                        \
    TL_DISPATCH_CHUNKS(process_chunk, , weighted);                                                           \
  }
TL_DEFINE_PROCESS_RANGE(process_range, 0)
TL_DEFINE_PROCESS_RANGE(process_range_weighted, 1)

/* Cuts the list between nt threads at equal estimated cost and finds each
 * particle's owner (Split). */
static TlStatus split_list(TlDem *d, const TlContactList *L, const Chunk *chunks, size_t n_chunks, int nt, Split *S)
{
  const size_t n = d->P->n;
  /* a touching contact costs about as much as four pairs that only test
   * their distance */
  double total = 0.0;
  for (size_t k = 0; k < n_chunks; ++k)
    for (size_t e = chunks[k].start; e < chunks[k].end; ++e) total += 1.0 + 4.0 * L->touching[e];
  int t = 1;
  double acc = 0.0;
  S->first[0] = 0;
  for (size_t k = 0; k < n_chunks; ++k) {
    while (t < nt && acc >= total * t / nt) S->first[t++] = k;
    for (size_t e = chunks[k].start; e < chunks[k].end; ++e) acc += 1.0 + 4.0 * L->touching[e];
  }
  while (t <= nt) S->first[t++] = n_chunks;
  TL_CHECK(tl_array_reserve(&S->owner, &S->owner_cap, n + 1, 1));
  memset(S->owner, 0xff, n);
  for (t = 0; t < nt; ++t) {
    size_t deferred = 0;
    for (size_t k = S->first[t]; k < S->first[t + 1]; ++k)
      for (size_t e = chunks[k].start; e < chunks[k].end; ++e) {
        const uint32_t p[2] = {L->i[e], L->j[e]};
        for (int q = 0; q < 2; ++q) {
          if (S->owner[p[q]] == 0xff) S->owner[p[q]] = (uint8_t)t;
          else if (S->owner[p[q]] != t) ++deferred;
        }
      }
    TL_CHECK(tl_array_reserve(&S->def[t], &S->def_cap[t], deferred + 1, sizeof *S->def[t]));
  }
  S->nt = nt;
  S->n = n;
  S->version = d->list_version;
  return TL_OK;
}

/* The body forces of particle i (gravity, f_ext, the weight, f_coupling, in
 * that order), its torque cleared and its packed position. */
static inline void body_force(TlDem *d, size_t i)
{
  TlParticles *P = d->P;
  TlVec3 f = tl_v3_scale(d->gravity, P->mass[i]);
  if (P->f_ext) f = tl_v3_add(f, P->f_ext[i]);
  if (d->weight_fn) f = tl_v3_scale(f, P->weight[i]);
  if (P->f_coupling) f = tl_v3_add(f, P->f_coupling[i]);
  P->f[i] = f;
  if (P->w) P->torque[i] = tl_v3(0, 0, 0);
  d->xr[i][0] = P->x[i].x;
  d->xr[i][1] = P->x[i].y;
  d->xr[i][2] = P->x[i].z;
  d->xr[i][3] = P->radius[i];
}

/* The deferred contributions to particles [lo, hi), in thread order then
 * list order: each particle's sum is the one a single thread makes. */
static void apply_deferred(TlDem *d, const Split *S, int nt, size_t lo, size_t hi)
{
  TlParticles *P = d->P;
  const int planar = d->dim == 2, rot = P->w != NULL;
  TlVec3 *F = P->f, *T = P->torque;
  for (int t = 1; t < nt; ++t)
    for (size_t e = 0; e < S->n_def[t]; ++e) {
      const Deferred q = S->def[t][e];
      if (q.p < lo || q.p >= hi) continue;
      F[q.p].x += q.f.x;
      F[q.p].y += q.f.y;
      if (!planar) F[q.p].z += q.f.z;
      if (rot && planar) T[q.p].z += q.t.z;
      else if (rot) {
        T[q.p].x += q.t.x;
        T[q.p].y += q.t.y;
        T[q.p].z += q.t.z;
      }
    }
}

/* The walls [w0, w1), all by particle ranges, over the blocks of particles
 * b = tid, tid + team, ... (round robin: the particles near a wall are few
 * and grouped by the grid order): block after block, each wall in turn
 * within a block, so that a particle receives its walls' forces in wall
 * order.  With S, the list's deferred contributions to a block go in first,
 * by the same thread: a particle gets its contacts, then its walls, as on
 * one thread, with no barrier in between. */
static void range_walls_blocks(TlDem *d, size_t w0, size_t w1, int tid, int team, const Split *S, int nt)
{
  const size_t nw = w1 - w0, n = d->P->n, nb = (n + TL_WALL_BLOCK - 1) / TL_WALL_BLOCK;
  TlWall *const *walls = d->walls + w0;
  const TlWallStep *steps = d->wall_steps + w0;
  TlWallSums *sums = d->wall_sums;
  for (size_t b = (size_t)tid; b < nb; b += (size_t)team) {
    const size_t lo = b * TL_WALL_BLOCK, hi = lo + TL_WALL_BLOCK < n ? lo + TL_WALL_BLOCK : n;
    if (S) apply_deferred(d, S, nt, lo, hi);
    for (size_t k = 0; k < nw; ++k) {
      TlWallSums *sk = &sums[b * nw + k];
      memset(sk, 0, sizeof *sk);
      walls[k]->ops->interact_range(walls[k], &steps[k], lo, hi, sk);
    }
  }
}

/* The end of the run of walls by particle ranges that starts at wall w0. */
static size_t range_walls_end(const TlDem *d, size_t w0)
{
  size_t w1 = w0;
  while (w1 < d->n_walls && tl_wall_by_ranges(d->walls[w1])) ++w1;
  return w1;
}

/* The contact loop of one list on d->nt_now threads; with `body`, the body
 * forces first, in the same parallel region; with walls_end > 0, the walls
 * [0, walls_end) (by particle ranges, prepared) after it, in the same region
 * too, once the deferred contributions are in. */
static TlStatus evaluate_list(TlDem *d, TlContactList *L, const Chunk *chunks, size_t n_chunks, Split *S, int bonded,
                              int body, int want_energy, const double *cw, size_t walls_end, Accum *acc)
{
  TlParticles *P = d->P;
  const size_t n = P->n;
  const int rot = P->w != NULL;
  const int nt = d->nt_now;
  const TlDomain *dom = &d->domain;
  size_t touching = 0;
  TlStatus status = TL_OK;
  double busy[TL_DEM_MAX_TIMED_THREADS];
  if (nt > 1 && (S->nt != nt || S->n != n || S->version != d->list_version))
    TL_CHECK(split_list(d, L, chunks, n_chunks, nt, S));
  if (want_energy) {
    size_t cap = S->chunk_cap;
    TL_CHECK(tl_array_reserve(&S->chunk_el, &S->chunk_cap, n_chunks + 1, sizeof *S->chunk_el));
    TL_CHECK(tl_array_reserve(&S->chunk_pw, &cap, n_chunks + 1, sizeof *S->chunk_pw));
  }
  double body_seconds = 0.0, reduce_seconds = 0.0, walls_seconds = 0.0;
  TL_PARALLEL_IF(nt > 1, "omp parallel num_threads(nt) reduction(+ : touching)", {
    int tid = nt > 1 ? omp_get_thread_num() : 0;
    if (body) {
      const double t_body = tl_dem_clock(d);
      _Pragma("omp for schedule(static)")
      for (size_t i = 0; i < n; ++i) body_force(d, i);
      if (tid == 0) body_seconds = tl_dem_clock(d) - t_body; /* after the loop's barrier */
    }
    const double tb = tl_dem_clock(d);
    ChunkCtx c;
    memset(&c, 0, sizeof c);
    c.d = d;
    c.L = L;
    c.x = P->x;
    c.v = P->v;
    c.w = rot ? P->w : NULL;
    c.radius = P->radius;
    c.xr = (const double(*)[4])d->xr;
    c.cw = cw;
    c.inv_mass = P->inv_mass;
    c.mass = P->mass;
    /* every thread adds into the world's arrays: only a particle's owner does */
    c.F = P->f;
    c.T = rot ? P->torque : NULL;
    for (int q = 0; q < 3; ++q) {
      c.len[q] = dom->periodic[q] ? dom->h.m[q][q] : 0.0;
      c.half[q] = 0.5 * c.len[q];
    }
    for (int q = 0; q < 4; ++q) {
      c.hm[q] = dom->h.m[q / 2][q % 2];
      c.hinv[q] = dom->h_inv.m[q / 2][q % 2];
      c.lm[q] = dom->L.m[q / 2][q % 2];
    }
    c.bonded = bonded;
    c.want_energy = want_energy;
    c.chunk_el = S->chunk_el;
    c.chunk_pw = S->chunk_pw;
    c.hd = L->history_doubles;
    if (nt == 1) {
      if (cw) process_range_weighted(&c, chunks, 0, n_chunks);
      else process_range(&c, chunks, 0, n_chunks);
    } else {
      /* range r of the split as its owner; a team smaller than asked (a
       * thread limit) takes the ranges in turn, still each as its owner */
      const int team = omp_get_num_threads();
      c.owner = S->owner;
      for (int r = tid; r < nt; r += team) {
        c.tid = r;
        c.def = S->def[r];
        c.def_cap = S->def_cap[r];
        c.n_def = 0;
        if (cw) process_range_weighted(&c, chunks, S->first[r], S->first[r + 1]);
        else process_range(&c, chunks, S->first[r], S->first[r + 1]);
        S->n_def[r] = c.n_def;
      }
      if (tid == 0)
        for (int r = team; r < nt && r < TL_DEM_MAX_TIMED_THREADS; ++r) busy[r] = 0.0;
    }
    if (tid < TL_DEM_MAX_TIMED_THREADS) busy[tid] = tl_dem_clock(d) - tb;
    touching += c.touching;
    if (c.status != TL_OK) {
      _Pragma("omp critical")
      status = c.status;
    }
    if (walls_end) {
      /* the walls after every contact of the list, as in a step on one
       * thread: each block's deferred contributions, then its walls, by
       * the thread that takes the block */
      const double tw = tl_dem_clock(d);
      if (nt > 1) {
        _Pragma("omp barrier")
        range_walls_blocks(d, 0, walls_end, tid, omp_get_num_threads(), S, nt);
      } else {
        range_walls_blocks(d, 0, walls_end, 0, 1, NULL, 1);
      }
      if (tid == 0) walls_seconds = tl_dem_clock(d) - tw; /* thread 0's share, the barrier's wait included */
    }
  });
  if (status != TL_OK) {
    if (status == TL_ERR_STATE) TL_ERROR(TL_ERR_STATE, "contact loop: a thread deferred more contributions than counted");
    return tl_error_trace(status, __FILE__, __LINE__);
  }
  if (!walls_end) {
    const double tr = tl_dem_clock(d);
    apply_deferred(d, S, nt, 0, n);
    reduce_seconds = tl_dem_clock(d) - tr;
  }
  d->prof.seconds[TL_DEM_PHASE_BODY] += body_seconds;
  d->prof.seconds[TL_DEM_PHASE_CONTACTS] -= body_seconds;
  if (nt > 1) { /* booked as the reduction */
    d->prof.seconds[TL_DEM_PHASE_REDUCE] += reduce_seconds;
    d->prof.seconds[TL_DEM_PHASE_CONTACTS] -= reduce_seconds;
  }
  d->prof.seconds[TL_DEM_PHASE_WALLS] += walls_seconds;
  d->prof.seconds[TL_DEM_PHASE_CONTACTS] -= walls_seconds;
  {
    const int m = nt < TL_DEM_MAX_TIMED_THREADS ? nt : TL_DEM_MAX_TIMED_THREADS;
    double mx = 0.0, mean = 0.0;
    for (int t = 0; t < m; ++t) {
      d->prof.thread_busy[t] += busy[t];
      mx = busy[t] > mx ? busy[t] : mx;
      mean += busy[t] / m;
    }
    d->prof.imbalance += mx - mean;
    d->prof.threads = nt;
  }
  if (want_energy)
    for (size_t k = 0; k < n_chunks; ++k) {
      acc->elastic += S->chunk_el[k];
      acc->power += S->chunk_pw[k];
    }
  acc->touching += touching;
  return TL_OK;
}

/* Each wall's step, and the walls by particle ranges prepared with room
 * for their blocks' sums. */
static TlStatus prepare_walls(TlDem *d)
{
  const size_t n = d->P->n, nb = (n + TL_WALL_BLOCK - 1) / TL_WALL_BLOCK;
  TL_CHECK(tl_array_reserve(&d->wall_steps, &d->wall_steps_cap, d->n_walls + 1, sizeof *d->wall_steps));
  size_t most = 0;
  for (size_t w = 0; w < d->n_walls; ++w) {
    TlWall *W = d->walls[w];
    /* between two builds no particle moves more than half the skin from
     * its build position (tl_dem_needs_rebuild, run after the drift of
     * every step): promised inside tl_dem_step, never to an evaluation on
     * its own (tl_dem_compute_forces: the particles may have been moved by
     * hand since the last check) nor in a deforming cell, which carries
     * them further, affinely */
    const int promise = d->in_steps && !d->domain.deforming && d->skin > 0.0;
    d->wall_steps[w] = (TlWallStep){d->P, d->grid, &d->domain, d->laws[W->law], d->t, d->dt, d->track_energy,
                                    promise ? d->list_version : 0, promise ? 0.5 * d->skin : INFINITY};
    if (!tl_wall_by_ranges(W)) continue;
    TL_CHECK(W->ops->prepare(W, &d->wall_steps[w]));
    const size_t run = range_walls_end(d, w) - w;
    most = run > most ? run : most;
  }
  return tl_array_reserve(&d->wall_sums, &d->wall_sums_cap, nb * most + 1, sizeof *d->wall_sums);
}

TlStatus tl_dem_eval_forces(TlDem *d)
{
  TlParticles *P = d->P;
  const size_t n = P->n;
  const int want = d->track_energy;
  double t0 = tl_dem_clock(d);
  /* weighted equations (seeds/001 Eq. 25): w_a (m_a g + f_ext) */
  const int weighted = d->weight_fn != NULL;
  if (weighted) {
    if (d->n_walls)
      TL_ERROR(TL_ERR_UNSUPPORTED, "a weighted world (tl_dem_set_weight_field) with %zu walls: wall contacts are not "
               "weighted; remove the walls or the weight field", d->n_walls);
    TL_CHECK(tl_dem_particle_weights(d));
  }
  if (n > d->xr_cap) {
    TL_CHECK(tl_realloc(&d->xr, n + n / 2 + 16, sizeof *d->xr));
    d->xr_cap = n + n / 2 + 16;
  }
  /* threads only pay for themselves on large contact lists */
  d->nt_now = d->list.n + (d->bonds.n == (size_t)-1 ? 0 : d->bonds.n) >= 8192 ? d->nt : 1;
  const int ntb = n >= 8192 ? d->nt : 1;
  /* body forces in the contact loop's parallel region when both are
   * threaded alike (one region fewer per step) */
  const int fused = ntb > 1 && ntb == d->nt_now;
  if (!fused) TL_PARALLEL_IF(ntb > 1, "omp parallel for num_threads(ntb) schedule(static)",
    for (size_t i = 0; i < n; ++i) body_force(d, i););
  tl_dem_tick(d, TL_DEM_PHASE_BODY, &t0);
  Accum acc = {0, 0, 0};
  const int has_bonds = d->bonds.n && d->bonds.n != (size_t)-1;
  if (weighted) {
    TL_CHECK(tl_dem_contact_weights(d, &d->list, &d->cw_list, &d->cw_list_cap));
    if (has_bonds) TL_CHECK(tl_dem_contact_weights(d, &d->bonds, &d->cw_bonds, &d->cw_bonds_cap));
  }
  /* the walls by particle ranges are prepared here, and the first run of
   * them joins the list's region when nothing is evaluated in between */
  TL_CHECK(prepare_walls(d));
  const size_t walls_fused = !has_bonds ? range_walls_end(d, 0) : 0;
  TL_CHECK(evaluate_list(d, &d->list, d->chunks, d->n_chunks, &d->split_list, 0, fused, want,
                         weighted ? d->cw_list : NULL, walls_fused, &acc));
  if (has_bonds)
    TL_CHECK(evaluate_list(d, &d->bonds, d->bond_chunks, d->n_bond_chunks, &d->split_bonds, 1, 0, want,
                           weighted ? d->cw_bonds : NULL, 0, &acc));
  tl_dem_tick(d, TL_DEM_PHASE_CONTACTS, &t0);
  d->n_touching = acc.touching;
  if (want) {
    d->elastic_pp = acc.elastic;
    d->contact_work_pp += d->dt * acc.power;
  }
  /* walls, in order: a run of walls by particle ranges in one pass over
   * the blocks (the first run done above), the others one by one */
  for (size_t w = 0; w < d->n_walls;) {
    TlWall *W = d->walls[w];
    if (!tl_wall_by_ranges(W)) {
      TL_CHECK(W->ops->interact(W, &d->wall_steps[w]));
      ++w;
      continue;
    }
    const size_t w1 = range_walls_end(d, w);
    if (w || !walls_fused)
      TL_PARALLEL_IF(ntb > 1, "omp parallel num_threads(ntb)", {
        const int tid = ntb > 1 ? omp_get_thread_num() : 0, team = ntb > 1 ? omp_get_num_threads() : 1;
        range_walls_blocks(d, w, w1, tid, team, NULL, 1);
      });
    const size_t nb = (n + TL_WALL_BLOCK - 1) / TL_WALL_BLOCK;
    for (size_t k = w; k < w1; ++k)
      TL_CHECK(tl_wall_book_blocks(d->walls[k], &d->wall_steps[k], d->wall_sums + (k - w), nb, w1 - w));
    w = w1;
  }
  tl_dem_tick(d, TL_DEM_PHASE_WALLS, &t0);
  return TL_OK;
}

TlStatus tl_dem_compute_forces(TlDem *d)
{
  if (!d->setup_done) TL_ERROR(TL_ERR_STATE, "tl_dem_setup must precede force computation");
  if (tl_dem_needs_rebuild(d)) TL_CHECK(tl_dem_rebuild(d));
  double dt = d->dt;
  int track = d->track_energy;
  /* a pure evaluation must not book work */
  double cw = d->contact_work_pp;
  TL_CHECK(tl_dem_eval_forces(d));
  d->contact_work_pp = cw;
  (void)dt;
  (void)track;
  return TL_OK;
}
