/* The hopper of walls_hgrid's part 5: a conical funnel (orifice radius
 * 10 mm, 40 mm high, walls 31 degrees off the vertical: tan = 0.6) standing
 * on a square plate that closes it, both refined to a given triangle count,
 * written as an ASCII STL that LIGGGHTS and Talus both read; the grains'
 * start (a cubic lattice filling the funnel) and the LIGGGHTS deck that
 * runs them.  Header of walls_hgrid.c only (static functions). */
#ifndef WALLS_HGRID_HOPPER_H
#define WALLS_HGRID_HOPPER_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "talus.h"
#include "tl_memory.h"
#include "tl_stl.h"

enum { HOPPER_ANSWER_SPHERES = 8 };

typedef struct {
  double r_orifice, height, slope, plate_half; /* slope: radial over vertical rise of the funnel wall */
  int n_theta, n_z, n_plate;                   /* cone columns and rows, plate cells per side */
} HopperGeometry;

static double hopper_radius_at(const HopperGeometry *g, double z) { return g->r_orifice + g->slope * z; }

/* Column and row counts for about `target` triangles of near-equal size. */
static void hopper_geometry(double target, HopperGeometry *g)
{
  g->r_orifice = 0.01, g->height = 0.04, g->slope = 0.6, g->plate_half = 0.012;
  double r_top = hopper_radius_at(g, g->height), slant = g->height * sqrt(1.0 + g->slope * g->slope);
  double cone_area = TL_PI * (g->r_orifice + r_top) * slant, plate_area = 4.0 * g->plate_half * g->plate_half;
  double h = sqrt(2.0 * (cone_area + plate_area) / target);
  g->n_theta = (int)ceil(TL_PI * (g->r_orifice + r_top) / h);
  g->n_z = (int)ceil(slant / h);
  g->n_plate = (int)ceil(2.0 * g->plate_half / h);
  if (g->n_theta < 8) g->n_theta = 8;
  if (g->n_z < 1) g->n_z = 1;
  if (g->n_plate < 1) g->n_plate = 1;
}

/* The funnel (2 n_theta n_z triangles, normals towards the axis and up)
 * and the plate under it (2 n_plate^2, normals up); the plate is a mesh of
 * its own, not joined to the funnel's bottom ring. */
static TlStatus hopper_mesh(const HopperGeometry *g, TlSurfaceMesh **m)
{
  const int nt = g->n_theta, nz = g->n_z, np = g->n_plate;
  size_t nv = (size_t)nt * (size_t)(nz + 1) + (size_t)(np + 1) * (size_t)(np + 1);
  size_t ntri = 2 * (size_t)nt * (size_t)nz + 2 * (size_t)np * (size_t)np;
  double *x = NULL;
  int *tri = NULL;
  TlStatus st = TL_OK;
  TL_CHECK_GOTO(st, tl_calloc(&x, 3 * nv, sizeof *x), done);
  TL_CHECK_GOTO(st, tl_calloc(&tri, 3 * ntri, sizeof *tri), done);
  size_t v = 0, t = 0;
  for (int i = 0; i <= nz; ++i) {
    double z = g->height * i / nz, r = hopper_radius_at(g, z);
    for (int j = 0; j < nt; ++j) {
      double th = 2.0 * TL_PI * j / nt;
      x[3 * v] = r * cos(th), x[3 * v + 1] = r * sin(th), x[3 * v + 2] = z;
      ++v;
    }
  }
  for (int i = 0; i < nz; ++i)
    for (int j = 0; j < nt; ++j) {
      int a = i * nt + j, b = i * nt + (j + 1) % nt, c = a + nt, d = b + nt;
      /* counter-clockwise seen from the axis */
      int q[6] = {a, c, b, b, c, d};
      for (int k = 0; k < 6; ++k) tri[3 * t + k] = q[k];
      t += 2;
    }
  int base = (int)v;
  for (int i = 0; i <= np; ++i)
    for (int j = 0; j <= np; ++j) {
      x[3 * v] = -g->plate_half + 2.0 * g->plate_half * j / np;
      x[3 * v + 1] = -g->plate_half + 2.0 * g->plate_half * i / np;
      x[3 * v + 2] = 0.0;
      ++v;
    }
  for (int i = 0; i < np; ++i)
    for (int j = 0; j < np; ++j) {
      int a = base + i * (np + 1) + j, b = a + 1, c = a + np + 1, d = c + 1;
      int q[6] = {a, b, d, a, d, c};
      for (int k = 0; k < 6; ++k) tri[3 * t + k] = q[k];
      t += 2;
    }
  TL_CHECK_GOTO(st, tl_surface_mesh_create(nv, x, ntri, tri, m), done);
done:
  tl_free(&x);
  tl_free(&tri);
  return st;
}

/* Lattice sites of pitch 2.02 r inside the funnel, at least 1.05 r from
 * its wall and from the plate, from the bottom up: at most `max`. */
static TlStatus hopper_sites(const HopperGeometry *g, double r, size_t max, TlVec3 **x, size_t *n)
{
  double pitch = 2.02 * r, cosa = 1.0 / sqrt(1.0 + g->slope * g->slope);
  double r_top = hopper_radius_at(g, g->height);
  int m = (int)ceil(r_top / pitch);
  TL_CHECK(tl_calloc(x, max ? max : 1, sizeof **x));
  *n = 0;
  for (int k = 0; *n < max; ++k) {
    double z = 1.05 * r + k * pitch;
    if (z > g->height - r) break;
    for (int i = -m; i <= m && *n < max; ++i)
      for (int j = -m; j <= m && *n < max; ++j) {
        double px = i * pitch, py = j * pitch, rho = sqrt(px * px + py * py);
        if ((hopper_radius_at(g, z) - rho) * cosa >= 1.05 * r) (*x)[(*n)++] = tl_v3(px, py, z);
      }
  }
  return TL_OK;
}

/* The same-answer spheres: touching the funnel wall on the midlines of
 * eight facet columns, 60 % of the way up, so that each rolls straight
 * down its column (crossing the columns' flat row edges). */
static TlVec3 hopper_answer_position(const HopperGeometry *g, double r, int k)
{
  int j = k * g->n_theta / HOPPER_ANSWER_SPHERES;
  double th0 = 2.0 * TL_PI * j / g->n_theta, th1 = 2.0 * TL_PI * (j + 1) / g->n_theta, thm = 0.5 * (th0 + th1);
  double z = 0.6 * g->height, rm = hopper_radius_at(g, z) * cos(TL_PI / g->n_theta);
  TlVec3 q = tl_v3(rm * cos(thm), rm * sin(thm), z);
  /* the column's plane: its two generator lines */
  TlVec3 a0 = tl_v3(g->r_orifice * cos(th0), g->r_orifice * sin(th0), 0.0);
  TlVec3 a1 = tl_v3(g->r_orifice * cos(th1), g->r_orifice * sin(th1), 0.0);
  double rt = hopper_radius_at(g, g->height);
  TlVec3 b0 = tl_v3(rt * cos(th0), rt * sin(th0), g->height);
  TlVec3 n = tl_v3_normalize(tl_v3_cross(tl_v3_sub(a1, a0), tl_v3_sub(b0, a0)));
  if (n.z < 0.0) n = tl_v3_neg(n);
  return tl_v3_axpy(q, r, n);
}

/* Writes a LIGGGHTS deck running spheres of radius r from `x` in the hopper
 * `stl`: a warm-up run, then the timed run (or, with dump_every > 0, one run
 * dumping positions at its end).  The law's numbers as in the floors' deck. */
static TlStatus hopper_deck(const char *path, const char *stl, const TlVec3 *x, size_t n, double r, double density,
                            double youngs, double poisson, double restitution, double mu, double dt, long warmup,
                            long steps, int dump)
{
  FILE *f = fopen(path, "w");
  if (!f) TL_ERROR(TL_ERR_IO, "cannot write the LIGGGHTS deck %s", path);
  fprintf(f, "atom_style granular\natom_modify map array\nboundary f f f\nnewton off\ncommunicate single vel yes\n"
             "units si\nregion box block -0.045 0.045 -0.045 0.045 -0.005 0.05 units box\ncreate_box 1 box\n"
             "neighbor 0.0002 bin\nneigh_modify delay 0\n"
             "fix m1 all property/global youngsModulus peratomtype %.17g\n"
             "fix m2 all property/global poissonsRatio peratomtype %.17g\n"
             "fix m3 all property/global coefficientRestitution peratomtypepair 1 %.17g\n"
             "fix m4 all property/global coefficientFriction peratomtypepair 1 %.17g\n"
             "pair_style gran model hertz tangential history\npair_coeff * *\ntimestep %.17g\n"
             "fix hopper all mesh/surface/stress file %s type 1\n"
             "fix wall all wall/gran model hertz tangential history mesh n_meshes 1 meshes hopper\n",
          youngs, poisson, restitution, mu, dt, stl);
  for (size_t i = 0; i < n; ++i) fprintf(f, "create_atoms 1 single %.17g %.17g %.17g units box\n", x[i].x, x[i].y, x[i].z);
  fprintf(f, "set group all diameter %.17g density %.17g\nfix integr all nve/sphere\n"
             "fix grav all gravity 9.81 vector 0.0 0.0 -1.0\ncompute zmin all reduce min z\n"
             "compute zmax all reduce max z\nthermo_style custom step atoms ke f_hopper[1] f_hopper[2] f_hopper[3] "
             "c_zmin c_zmax\nthermo_modify format float %%.15g lost ignore norm no\n",
          2.0 * r, density);
  if (dump) {
    fprintf(f, "thermo %ld\ndump d all custom %ld answer.dump id x y z\n"
               "dump_modify d sort id format \"%%d %%.17g %%.17g %%.17g\"\nrun %ld\n",
            steps, steps, steps);
  } else {
    fprintf(f, "thermo %ld\nrun %ld\nrun %ld\n", warmup > 0 ? warmup : 1, warmup, steps);
  }
  fclose(f);
  return TL_OK;
}

/* Runs LIGGGHTS on the deck in dir; returns the loop time of its last run. */
static TlStatus hopper_liggghts(const char *dir, const char *deck, double *loop_seconds)
{
  char command[9000], log[4300], line[1024];
  snprintf(command, sizeof command, "cd '%s' && liggghts -in %s -log log.%s -echo none > out.%s 2>&1", dir, deck, deck,
           deck);
  fflush(stdout);
  int rc = system(command);
  if (rc != 0) TL_ERROR(TL_ERR_IO, "LIGGGHTS failed on %s/%s (exit %d; see %s/out.%s)", dir, deck, rc, dir, deck);
  snprintf(log, sizeof log, "%s/log.%s", dir, deck);
  FILE *f = fopen(log, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "no LIGGGHTS log %s", log);
  int found = 0;
  while (fgets(line, sizeof line, f)) {
    double t;
    if (sscanf(line, "Loop time of %lf", &t) == 1) *loop_seconds = t, found = 1;
  }
  fclose(f);
  if (!found) TL_ERROR(TL_ERR_FORMAT, "LIGGGHTS log %s has no loop time", log);
  return TL_OK;
}

/* Positions of the answer spheres in LIGGGHTS's last dump (ids 1..n). */
static TlStatus hopper_read_dump(const char *path, TlVec3 *x, int n)
{
  FILE *f = fopen(path, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "no LIGGGHTS dump %s", path);
  char line[1024];
  int got = 0, in_atoms = 0;
  while (fgets(line, sizeof line, f)) {
    if (!strncmp(line, "ITEM: ATOMS", 11)) {
      in_atoms = 1, got = 0;
      continue;
    }
    if (!strncmp(line, "ITEM:", 5)) {
      in_atoms = 0;
      continue;
    }
    int id;
    double a, b, c;
    if (in_atoms && sscanf(line, "%d %lf %lf %lf", &id, &a, &b, &c) == 4 && id >= 1 && id <= n) x[id - 1] = tl_v3(a, b, c), ++got;
  }
  fclose(f);
  if (got != n) TL_ERROR(TL_ERR_FORMAT, "LIGGGHTS dump %s: %d of %d spheres in its last snapshot", path, got, n);
  return TL_OK;
}

#endif
