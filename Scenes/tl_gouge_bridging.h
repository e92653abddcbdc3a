/* The pre-stressed granular gouge between two elastic bars of Voisin-Leprince et al. 2023
 * (§4-5, the B1 scene),
 * coupled by the bridging domain method (Coupling/Bridging/tl_bdm.h).
 *
 * Geometry (the scripts' canonical scene).  A relaxed periodic
 * packing of side a (a LAMMPS data file, e.g. the 5 MPa gouge cells) is
 * replicated cells_section x cells_y x cells_section times: the DEM bar
 * spans y in [-Y, Y], Y = cells_y a / 2, periodic in x and z (section
 * L = cells_section a).  Two hex8 bars of the same section, periodic in x
 * and z through the solid's ties (tl_solid_tie.h), overlap the DEM by one
 * bridging zone of length `bridge` (a by default) at each end: the right
 * bar spans [Y - bridge, Y - bridge + fe_length], the left one mirrors it.
 * alpha = 0 at the FE end face inside the DEM (y = ±(Y - bridge)), 1 at
 * the DEM's free surface (y = ±Y).  Elements: n = round(L / h) across the
 * section, and a size along y that puts a node plane on both ends of each
 * zone.  FE: Saint Venant-Kirchhoff with Table 2's E, nu, the scripts'
 * density 1643 (Table 2 prints 1543), pre-stressed by the eigenstrain
 * eps0 1 (scripts: 0.0025, sigma = -3 K eps0 = -4.98 MPa); far ends held
 * in y; in wave mode the left far end carries the pulse (Eq. 15, a
 * Gaussian; or a true Ricker): u_y for P, u_x for S (u_y held).  DEM:
 * LAMMPS gran/hertz/history with Table 1's constants.
 *
 * FE paths: the paper's finite-strain solid stepped on the DEM's step, or
 * its linearisation about the pre-stressed rest state (tl_mech_linear.h:
 * K assembled once, weights and pre-stress included), the same equations
 * to second order in u at a fraction of the cost.
 *
 * Records: the section average of u (3 components) at every node plane of
 * both bars (tl_gouge_planes; the driver samples it into the ct diagram
 * of Figs. 7-8, whose rows at the monitored planes are the histories of
 * Fig. 4).  Monitored planes (y_monitor): rest: three zone lengths into the
 * right bar, y = Y - bridge + 3 bridge (the text's 0.138 m), and its
 * mirror; wave: the middle planes of the left bar (incident, reflected)
 * and of the right bar (transmitted); third: the scripts' plane, one
 * element past the right bar's end face. */
#ifndef TL_GOUGE_BRIDGING_H
#define TL_GOUGE_BRIDGING_H

#include <stddef.h>
#include <stdio.h>

#include "tl_bdm.h"
#include "tl_checkpoint.h"
#include "tl_error.h"

typedef enum { TL_GOUGE_REST = 0, TL_GOUGE_WAVE } TlGougeMode;

typedef struct {
  const char *packing;   /* LAMMPS data file of the periodic cell (required) */
  int cells_section;     /* cells across x and z [2] */
  int cells_y;           /* cells along y [4] */
  double h;              /* element size asked for (m) [0.036 = 12 d0] */
  double bridge;         /* bridging zone length (m; 0: the cell side a) [0] */
  double fe_length;      /* length of each FE bar (m) [0.4] */
  double E, nu, rho;     /* FE continuum (Table 2; rho of the scripts) */
  double eigenstrain;    /* isotropic eigenstrain of the FE [0.0025] */
  int linear_fe;         /* 1: the linear fast path [0] */
  /* DEM law (Table 1; LAMMPS gran/hertz/history) */
  double k_n, k_t, gamma_n, gamma_t, mu; /* gamma_t < 0: gamma_n / 2 */
  double grain_density;  /* kg/m^3 [2500] */
  double dt;             /* s [1e-8] */
  int threads;           /* DEM OpenMP threads (0: default) */
  TlBdmOptions bdm;
  TlGougeMode mode;
  int wave_component;    /* 1: P (u_y), 0: S (u_x) */
  int pulse_shape;       /* TL_PULSE_GAUSSIAN (Eq. 15) or TL_PULSE_RICKER */
  double wavelength;     /* m [0.6 = 200 d0] */
  double intensity;      /* m [5e-4] */
  int subtract_initial;  /* pulse: u(t) - u(0) [0] */
} TlGougeParams;

void tl_gouge_params_default(TlGougeParams *p);

typedef struct TlGouge TlGouge;

TlStatus tl_gouge_create(const TlGougeParams *p, TlGouge **g);
void tl_gouge_destroy(TlGouge **g);

/* Sizes and derived values of the built scene. */
typedef struct {
  double a;            /* cell side (m) */
  double section;      /* L (m) */
  double Y;            /* DEM half length (m) */
  double fe_start;     /* right bar's first plane Y - bridge (m) */
  double hx, hy;       /* element sizes (m) */
  int n_section, n_bar; /* elements across, elements along each bar */
  size_t n_particles, n_coupled, n_nodes, n_dofs;
  double c_p, c_s, c;  /* FE wave speeds, the pulse's speed (m/s) */
  double sigma0;       /* FE pre-stress (Pa, negative: compression) */
  double dem_dt_critical;
  size_t n_planes;     /* node planes recorded */
  double y_monitor[3]; /* rest: right, left planes; wave: left mid, right mid */
} TlGougeInfo;
void tl_gouge_info(const TlGouge *g, TlGougeInfo *info);

/* One coupled step: DEM, FE, correction; the times go to the counters. */
TlStatus tl_gouge_step(TlGouge *g);
long tl_gouge_steps(const TlGouge *g);
double tl_gouge_time(const TlGouge *g);

typedef struct {
  double t_dem, t_fe, t_correct; /* cumulative seconds */
  long steps;
} TlGougeTimes;
void tl_gouge_times(const TlGouge *g, TlGougeTimes *t);

/* Section averages of u at every recorded plane: y[n_planes] and
 * u[3 * n_planes] at the current state. */
void tl_gouge_planes(const TlGouge *g, double *y, double *u);
/* The last correction's report. */
void tl_gouge_report(const TlGouge *g, TlBdmReport *rep);
/* Snapshots (HDF5 + XDMF): particles (position, radius, velocity, weight
 * 1 - alpha) and the bars (displacement, velocity, stress) under dir. */
TlStatus tl_gouge_snapshot(TlGouge *g, const char *dir);
/* Opens the snapshot series under dir without writing (tl_gouge_snapshot
 * opens them at its first call): open series are part of the checkpoint,
 * so a restarted run with snapshots opens them before loading. */
TlStatus tl_gouge_open_snapshots(TlGouge *g, const char *dir);

/* The full dynamic state: the DEM, the FE stepper, the coupling, the
 * scene's step count and the open snapshot series, so that the same scene
 * loaded continues bit for bit. */
TlStatus tl_gouge_checkpoint_save(TlGouge *g, const char *path);
TlStatus tl_gouge_checkpoint_load(TlGouge *g, const char *path);

#endif
