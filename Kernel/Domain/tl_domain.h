/* The simulation domain: an open box, an orthogonal periodic box, or a
 * deformable periodic cell (seeds/004 §2.4, Eqs. 13-21).
 *
 * All three are one affine frame: an origin o and a matrix h whose columns
 * are the cell's edge vectors, so that x = o + h s with reduced coordinates
 * s in [0, 1)^3 along periodic directions (Eq. 13).  An open box is the same
 * frame with no periodic direction (its h only bounds where the grid
 * expects particles; particles may leave it).  A periodic box has a diagonal
 * h; a deformable cell any invertible h, changing in time at the rate
 * h_dot (set by the user: constant ḣ as in Eq. 18, or per step).
 *
 * Velocities: particle velocities are stored relative to the affine field
 * v_aff(x) = L (x - o), L = ḣ h⁻¹ (the fluctuation h ṡ of Eq. 14); the
 * relative velocity of two particles at branch vector b is then
 * v_j - v_i + L b (Eq. 21 written with the real branch vector).  With ḣ = 0
 * (every open box and fixed periodic box) this is the plain velocity.
 *
 * Planar cell (the two-dimensional world of disks, tl_dem_set_dimension):
 * a deformable cell periodic along x and y only, whose z row and column of h
 * are those of the identity (a unit thickness, h_zz = 1) and never change
 * (ḣ has no z row or column).  Its branch vectors and rounding (Eq. 20) are
 * two-dimensional; z is inert.  tl_domain_area gives the in-plane area
 * |det h₂ₓ₂|, what a stress per unit thickness divides by.
 *
 * The hot functions are inline: the branch vector uses the rounding trick of
 * Eq. 20 in reduced coordinates. */
#ifndef TL_DOMAIN_H
#define TL_DOMAIN_H

#include "tl_error.h"
#include "tl_math.h"

typedef enum { TL_DOMAIN_OPEN = 0, TL_DOMAIN_PERIODIC_BOX, TL_DOMAIN_DEFORMABLE_CELL } TlDomainKind;

typedef struct {
  TlDomainKind kind;
  int periodic[3];   /* per reduced direction */
  TlVec3 origin;
  TlMat3 h, h_inv;   /* columns of h are the cell vectors */
  TlMat3 h_dot;      /* rate of h (deformable cell) */
  TlMat3 L;          /* velocity gradient ḣ h⁻¹ of the affine field */
  int any_periodic;
  int deforming;     /* h_dot nonzero */
  int planar;        /* the planar cell: x, y periodic, z inert (tl_domain_init_cell_2d) */
} TlDomain;

/* Open box [lo, hi] (a hint for the grid; particles may leave it). */
TlStatus tl_domain_init_open(TlDomain *d, TlVec3 lo, TlVec3 hi);
/* Orthogonal box [lo, hi], periodic along the directions flagged. */
TlStatus tl_domain_init_periodic_box(TlDomain *d, TlVec3 lo, TlVec3 hi, const int periodic[3]);
/* Deformable cell, periodic in all three directions, with cell matrix h
 * (columns = edge vectors, det h > 0) and origin o. */
TlStatus tl_domain_init_cell(TlDomain *d, TlVec3 origin, TlMat3 h);
/* Planar deformable cell (two-dimensional world), periodic along x and y:
 * the upper-left 2 x 2 block of h holds the in-plane edge vectors (columns,
 * det > 0); its z row and column must be those of the identity (refused
 * otherwise, naming the entry).  Wrapping and branch vectors leave z alone
 * (a two-dimensional world keeps its disks at z = 0). */
TlStatus tl_domain_init_cell_2d(TlDomain *d, TlVec3 origin, TlMat3 h);
/* Sets ḣ (deformable cell only; a planar cell refuses a z row or column). */
TlStatus tl_domain_set_h_rate(TlDomain *d, TlMat3 h_dot);
/* Replaces h (deformable cell), refusing det h <= 0 (and, planar, a z row
 * or column other than the identity's). */
TlStatus tl_domain_set_h(TlDomain *d, TlMat3 h);
/* Volume |det h| (a planar cell: its area times the unit thickness). */
double tl_domain_volume(const TlDomain *d);
/* In-plane area |h_xx h_yy - h_xy h_yx| (per unit thickness of a
 * two-dimensional world). */
double tl_domain_area(const TlDomain *d);
/* Distance between opposite faces of the cell along reduced direction k
 * (volume / area of the face spanned by the two other edge vectors). */
double tl_domain_face_distance(const TlDomain *d, int k);

static inline TlVec3 tl_domain_to_reduced(const TlDomain *d, TlVec3 x)
{
  return tl_m3_mulv(d->h_inv, tl_v3_sub(x, d->origin));
}
static inline TlVec3 tl_domain_from_reduced(const TlDomain *d, TlVec3 s)
{
  return tl_v3_add(d->origin, tl_m3_mulv(d->h, s));
}

/* Branch vector from x_i to the nearest image of x_j (Eq. 20). */
static inline TlVec3 tl_domain_branch(const TlDomain *d, TlVec3 xi, TlVec3 xj)
{
  TlVec3 b = tl_v3_sub(xj, xi);
  if (!d->any_periodic) return b;
  if (d->kind == TL_DOMAIN_PERIODIC_BOX) {
    /* diagonal h: per component; positions are wrapped at each neighbour
     * list build and move less than the skin in between, so one correction
     * suffices unless the vector is far off (then round) */
    double *c = &b.x;
    for (int k = 0; k < 3; ++k)
      if (d->periodic[k]) {
        double len = d->h.m[k][k], half = 0.5 * len;
        if (c[k] > half) c[k] -= len;
        else if (c[k] < -half) c[k] += len;
        if (c[k] > half || c[k] < -half) c[k] -= len * nearbyint(c[k] / len);
      }
    return b;
  }
  if (d->planar) {
    /* Eq. 20 in the plane: z is inert */
    const double sx = d->h_inv.m[0][0] * b.x + d->h_inv.m[0][1] * b.y;
    const double sy = d->h_inv.m[1][0] * b.x + d->h_inv.m[1][1] * b.y;
    const double rx = sx - nearbyint(sx), ry = sy - nearbyint(sy);
    b.x = d->h.m[0][0] * rx + d->h.m[0][1] * ry;
    b.y = d->h.m[1][0] * rx + d->h.m[1][1] * ry;
    return b;
  }
  TlVec3 S = tl_m3_mulv(d->h_inv, b);
  S.x -= nearbyint(S.x);
  S.y -= nearbyint(S.y);
  S.z -= nearbyint(S.z);
  return tl_m3_mulv(d->h, S);
}

/* Maps a position back into the cell along periodic directions. */
static inline TlVec3 tl_domain_wrap(const TlDomain *d, TlVec3 x)
{
  if (!d->any_periodic) return x;
  if (d->planar) {
    const double px = x.x - d->origin.x, py = x.y - d->origin.y;
    double sx = d->h_inv.m[0][0] * px + d->h_inv.m[0][1] * py;
    double sy = d->h_inv.m[1][0] * px + d->h_inv.m[1][1] * py;
    sx -= floor(sx);
    sy -= floor(sy);
    return (TlVec3){d->origin.x + d->h.m[0][0] * sx + d->h.m[0][1] * sy,
                    d->origin.y + d->h.m[1][0] * sx + d->h.m[1][1] * sy, x.z};
  }
  TlVec3 s = tl_domain_to_reduced(d, x);
  double *c = &s.x;
  for (int k = 0; k < 3; ++k)
    if (d->periodic[k]) c[k] -= floor(c[k]);
  return tl_domain_from_reduced(d, s);
}

/* Affine relative velocity L b added to v_j - v_i (zero unless deforming). */
static inline TlVec3 tl_domain_affine_velocity(const TlDomain *d, TlVec3 b)
{
  return d->deforming ? tl_m3_mulv(d->L, b) : (TlVec3){0, 0, 0};
}

/* Advances the cell over dt: h += dt ḣ (h⁻¹ and L updated).  The integrator
 * then maps each free particle as x <- o + h_new h_old⁻¹ (x - o) + dt v, so
 * particles keep their reduced coordinates under the affine deformation and
 * drift by their fluctuating velocity (Eqs. 13-14).  Refuses a step that
 * would make det h <= 0. */
TlStatus tl_domain_advance(TlDomain *d, double dt, TlMat3 *affine_map);

#endif
