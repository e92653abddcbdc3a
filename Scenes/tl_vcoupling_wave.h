/* The wave-propagation scene of Cheng et al. 2022, §6.2 (V1): a bar along
 * y, bonded simple-cubic particles on [0, dem_end], hex8 elements on
 * [fem_start, length], coupled by TlVCoupling in the overlap; or the same
 * particles over the whole bar (the full-DEM reference).
 *
 * Built from the library's models: the particles are a TlDem world (linear
 * bonds k_n = E d along the bond, tension and compression; Velocity-Verlet)
 * with the weighted equations of Eq. 25 (tl_dem_set_weight_field: w_a at
 * the centres, w_ab at the contact points); the solid is a TlSolid
 * (finite-strain total Lagrangian, Hooke's law of Appendix A, HRZ lumped
 * mass) whose overlap block is wrapped by the VCoupling element type
 * (weights 1 - w at its quadrature points, the coupling body force of
 * Eq. 31 inside every evaluation), advanced by a library stepper (explicit
 * central difference by default, or implicit Newmark) on the DEM's step.
 * One coupled step: the particles drift to t + dt, then (the DEM's step
 * hook) Pi is rebuilt at the new positions, the solid takes its step with
 * the coupling force of the particles' step displacement, and the
 * particles' share f^C (Eq. 32) completes their forces at t + dt. */
#ifndef TL_VCOUPLING_WAVE_H
#define TL_VCOUPLING_WAVE_H

#include <stddef.h>
#include <stdio.h>
#include "tl_checkpoint.h"
#include "tl_error.h"
#include "tl_mesh_snapshot.h"
#include "tl_particle_snapshot.h"

typedef enum { TL_WAVE_PULSE = 0, TL_WAVE_COSINE, TL_WAVE_CYCLES } TlWaveExcitation;
/* TL_WAVE_PAPER: the penalty on the displacement over the last step
 * (Eq. 29), which acts as a viscous damper between the two velocity fields.
 * TL_WAVE_SPRING: the same operator and penalty on the total displacement
 * since the start, u^DE = sum_a Pi_ia (x_a - x_a0), a spring that stores
 * the mismatch energy 1/2 eps r.M r instead of dissipating it. */
typedef enum { TL_WAVE_PAPER = 0, TL_WAVE_SPRING } TlWaveVariant;

typedef struct {
  int n;               /* particles per element edge: case nP */
  double dx;           /* element size (m) */
  double width;        /* cross-section edge (m) */
  double length;       /* bar length (m) */
  double dem_end;      /* particles on y in [0, dem_end] */
  double fem_start;    /* elements on y in [fem_start, length] */
  double E, nu, rho;   /* solid; particles: rho_g = 6 rho / pi, k_n = E d */
  double v0;           /* excitation amplitude (m/s) */
  TlWaveExcitation excitation;
  double omega;        /* rad/s */
  int cycles;
  double dt_over_tc;   /* dt / t_c */
  double c;            /* CG width (m), 0: classical */
  const char *kernel;
  double epsilon;      /* penalty (Pa/m^2); <= 0: Table 6, 1e4 Pa/mm^2 (n = 1)
                          scaled with 1/d^2, i.e. 1.6e9 Pa / d^2 (the text's
                          4e8 Pa / d^2 is not consistent with Table 6) */
  int quad_order;
  int per_element;     /* Pi rows per element (Eq. 18 over Omega_e) instead of per node */
  int full_dem;        /* 1: particles over the whole bar, no solid */
  TlWaveVariant variant;
  double resolution_limit; /* largest resolution bias of Pi in element sizes
                              (tl_vcoupling_check_resolution), checked at the
                              start and every 100 steps; 0: the default
                              TL_VCOUPLING_BIAS_LIMIT (half an element), < 0: no check */
  int no_penalty_check;    /* 1: skip the penalty's stability check at creation
                              (tl_wave_penalty_ratio; for studies of the blow-up) */
  const char *fem;         /* the solid's stepper: "central_difference" (the
                              paper's explicit run; NULL: this) or "newmark"
                              (implicit, beta = 1/4, gamma = 1/2) */
  /* Choices of the authors' published runs (all 0: the paper's text as
   * implemented before them) */
  int compression_only;    /* 1: the particle bonds push but do not pull
                              (their species has no tensile range) */
  int pulse_in;            /* 1: the pulse layer moves into the bar (+y, a
                              compression pulse, as published); 0: -y */
  int linear_weight;       /* 1: w a linear ramp across the overlap; 0: cosine */
  double weight_min;       /* the overlap's nodal weights in [weight_min, 1 - weight_min] */
  int lumped_penalty;      /* 1: the penalty's M_ij row-sum lumped */
  int lagged;              /* 1: both sides' coupling forces from the previous
                              step's mismatch, fixed before either steps (the
                              published explicit loop); 0: this step's */
  int cg_reach_less_d;     /* 1: Eq. 18 over the particles within c - d of an
                              element; 0: within c (also the published runs,
                              whose search gathers whole cells) */
} TlWaveParams;

/* The paper's values: 1P, pulse, c = 0. */
void tl_wave_params_default(TlWaveParams *p);

typedef struct {
  double t;
  double mass_dem, mass_fem;       /* weighted */
  double mom_dem, mom_fem;         /* y momentum, weighted */
  double kin_dem, pot_dem, kin_fem, pot_fem;
  double pot_coupling;             /* spring variant: 1/2 eps r.M r (0 for the paper's form) */
  double total;                    /* weighted sum of all energies */
  double eq41;                     /* last step */
  double residual;                 /* max |u_DE - u_FE| (m), last step */
  double coupling_work;            /* cumulative penalty work (J, <= 0) */
} TlWaveState;

typedef struct TlWave TlWave;

TlStatus tl_wave_create(const TlWaveParams *p, TlWave **w);
void tl_wave_destroy(TlWave **w);
double tl_wave_dt(const TlWave *w);
/* One step; TL_ERR_UNSTABLE with a diagnosis when the run blows up or the
 * CG width outruns the mesh (the resolution check). */
TlStatus tl_wave_step(TlWave *w);
void tl_wave_state(const TlWave *w, TlWaveState *s);
size_t tl_wave_n_particles(const TlWave *w);
/* Velocity profile v_y along the bar at n_y layer positions y (the particle
 * layers of the full bar): particle layers where particles exist and lie
 * at or left of dem_end, the solid interpolated beyond. */
size_t tl_wave_profile_size(const TlWave *w);
/* The penalty's explicit stability ratio eps dt^2 lambda_max(W^-1 B^T M B)
 * (B = [Pi, -I]: particle and nodal velocities to the nodal mismatch; M =
 * int N_i N_j; W the weighted masses, w_a m_a and the lumped (1 - w) rho V)
 * by `iterations` power iterations in the W inner product (a lower bound
 * converging from below), with the particle and the node that carry most
 * of the stiffest mode.  The paper's penalty is a damper eps M dt on the
 * velocity mismatch, explicit over one step, with amplification
 * 1 - ratio: stable for ratio <= 2; the spring variant, a stiffness eps M
 * under central differences, for ratio <= 4 (TL_WAVE_PENALTY_LIMIT).
 * tl_wave_create refuses a scene beyond it (unless no_penalty_check). */
TlStatus tl_wave_penalty_ratio(TlWave *w, int iterations, double *ratio, size_t *particle, size_t *node);
#define TL_WAVE_PENALTY_LIMIT(variant) ((variant) == TL_WAVE_SPRING ? 4.0 : 2.0)
void tl_wave_profile(const TlWave *w, double *y, double *vy);
/* The same with the Arlequin field in the overlap: w v_particles +
 * (1 - w) v_solid at each particle layer (w: the layer's mean weight), so
 * that particles of vanishing weight count as little as they weigh. */
void tl_wave_profile_weighted(const TlWave *w, double *y, double *vy);

/* The full dynamic state of the scene (time, step, particle positions,
 * velocities, forces and weights, the solid's displacement, velocity,
 * acceleration and forces, the running coupling work), so that a scene
 * built with the same parameters and loaded continues bit for bit. */
extern const TlCheckpointOps tl_wave_checkpoint_ops;

/* One snapshot for ParaView: the particles (position, radius, velocity,
 * force, weight w_a) to pw, and the solid (displacement, velocity, nodal
 * weight w_i, weighted lumped mass) to mw; mw may be NULL, and is ignored
 * for the full-DEM reference. */
TlStatus tl_wave_write_snapshot(const TlWave *w, TlParticleWriter *pw, TlMeshWriter *mw);

/* A whole run: steps to t_end, records the state every `every` steps and
 * the velocity profile at the snapshot times (the first step at or after
 * each).  The record arrays are allocated here; free with
 * tl_wave_record_free. */
#define TL_WAVE_MAX_SNAPSHOTS 8
typedef struct {
  double t_end;
  long every;
  int n_snap;
  double snap[TL_WAVE_MAX_SNAPSHOTS];
  int progress; /* show a progress bar */
  /* output of the run (all optional; output_dir NULL: none of them) */
  const char *output_dir;   /* snapshots particles*.h5 / solid*.h5 (+ .xmf), checkpoint.h5 */
  double snapshot_dt;       /* HDF5 + XDMF snapshots every snapshot_dt (s; 0: none), from t = 0 */
  long checkpoint_every;    /* checkpoint.h5 every n steps (0: none) */
  const char *restart;      /* continue from this checkpoint (NULL or "": start afresh) */
  long stop_step;           /* stop after this step (0: run to t_end) */
  struct TlOptions *options; /* the driver's options, checkpointed first and compared on restart (NULL: none) */
} TlWaveRunOptions;

typedef struct {
  size_t n;             /* recorded states */
  TlWaveState *state;
  size_t ny;            /* profile points */
  double *y;            /* ny */
  double *profile;      /* n_snap x ny */
  double *profile_weighted; /* n_snap x ny: tl_wave_profile_weighted */
  double snap_t[TL_WAVE_MAX_SNAPSHOTS];
  long steps;           /* last step taken */
  long start_step;      /* 0, or the step restarted from */
  int stopped;          /* 1: stopped at stop_step before t_end */
  double dt, wall;
  size_t n_particles;
  size_t n_snapshots;   /* snapshot files written by the whole run so far */
} TlWaveRecord;

TlStatus tl_wave_run(const TlWaveParams *p, const TlWaveRunOptions *o, TlWaveRecord *r);
void tl_wave_record_free(TlWaveRecord *r);

#endif
