/* Periodic packings as files, and the gouge contact law they are made with.
 *
 * A packing file is a particle snapshot (tl_particle_snapshot.h, the
 * packing_*.h5 that periodic_compress writes) plus the periodic cell it lives
 * in, as two extra datasets the snapshot reader ignores:
 *   /cell/origin  3      the cell origin o (m)
 *   /cell/h       3 x 3  the cell matrix h, row-major, columns the edge
 *                        vectors (x = o + h s, s in [0, 1)^3), as TlDomain
 * Velocities and spins are those of the end of the preparation (a packing at
 * rest has them near zero); radii in m.  Densities are not stored: the loader
 * takes the grain density (seeds/000 Table 1: 2500 kg/m^3).
 *
 * Loading into a world (the usual way to start from a fixture):
 *   TlDem *dem;  tl_dem_create(&dem);
 *   int sp;  tl_dem_packing_load(dem, "SelfTests/data/gouge_6d0.h5", 2500.0, &sp);
 *   TlContactLaw *law;  tl_contact_law_build(&tl_gouge_law_spec, &law);
 *   tl_dem_add_law(dem, law, NULL);  tl_dem_set_timestep(dem, 1e-8, 0);  tl_dem_setup(dem);
 * The world's domain becomes the periodic cell (a deformable cell with ḣ = 0),
 * the particles get the stored positions, velocities and (when stored) spins.
 * tl_dem_packing_read gives the same content without a world (to replicate a
 * cell, or to build a periodic box of another shape around it). */
#ifndef TL_DEM_PACKING_H
#define TL_DEM_PACKING_H

#include "tl_contact_law.h"
#include "tl_dem.h"
#include "tl_particle_snapshot.h"

/* The gouge contact law of seeds/000 (supplementary Eqs. 18-20, Table 1) =
 * LAMMPS pair_style gran/hertz/history Kn Kt gamma_n NULL mu 1 with
 * Kn = (2/3) E/(1 - nu^2) = 3.663e10 Pa, Kt = 2E/((1 + nu)(2 - nu)) =
 * 4.5249e10 Pa (E = 50 GPa, nu = 0.3), gamma_n = 0.2 1/(m s), gamma_t =
 * gamma_n/2 = 0.1 1/(m s), mu = 0.5: the parts lammps_hertz + lammps_history
 * (displacement history, spring + dashpot capped at mu |f_n|, radius lever
 * arms).  On the command line of a driver reading its law from options:
 *   -contact lammps_hertz -contact_k_n 36630036630.03663 -contact_gamma_n 0.2
 *   -friction lammps_history -contact_k_t 45248868778.28054 -contact_mu 0.5
 * (gamma_t defaults to gamma_n/2, dampflag to 1). */
extern const TlContactSpec tl_gouge_law_spec;
/* The same law without its tangential part: the frictionless compaction of
 * the scripts (gran/hertz/history Kn 0 gamma_n 0 0 0). */
extern const TlContactSpec tl_gouge_law_frictionless_spec;

/* Writes the world's particles and cell as <dir>/<name>_<k>.h5 (+ .xmf), k
 * counted by `writer`, with the /cell datasets; the world's domain must be
 * periodic in all three directions.  *path (optional) receives the file
 * written (valid until the writer writes again). */
TlStatus tl_dem_packing_write(TlDem *dem, TlParticleWriter *writer, int64_t step, const char **path);
/* Writes the world's particles as a LAMMPS data file (atom_style sphere:
 * id type diameter density x y z, then Velocities) at `path`, density
 * `density` for every grain, positions wrapped into the box; the cell must
 * be orthogonal (a diagonal h).  Numbers as %.17g, so LAMMPS reads the same
 * doubles. */
TlStatus tl_dem_packing_write_lammps(TlDem *dem, double density, const char *path);

/* Reads a packing file: the snapshot and its cell (origin, h). */
TlStatus tl_dem_packing_read(const char *path, TlParticleSnapshot *snapshot, TlVec3 *origin, TlMat3 *h);
/* Loads a packing file into an empty world, before tl_dem_setup: sets the
 * domain to the cell, adds one species "gouge" of density `density` spanning
 * the radii found (*species, optional), and the particles with their
 * velocities and spins. */
TlStatus tl_dem_packing_load(TlDem *dem, const char *path, double density, int *species);

#endif
