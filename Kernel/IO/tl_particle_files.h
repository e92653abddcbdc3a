/* Scenes from files: the particles of a LAMMPS data file or of a Talus
 * particle snapshot added to a DEM world.
 *
 *   TlDem *dem;  tl_dem_create(&dem);
 *   int sp;  tl_particles_add_species(tl_dem_particles(dem), "grain", 2500, 1e-3, 1e-2, &sp);
 *   size_t n;  tl_dem_add_particles_from_file(dem, "packing.data", sp, &n);
 *
 * The format is told by the file's first bytes (HDF5's signature: a
 * snapshot, tl_particle_snapshot.h; anything else: a LAMMPS data file,
 * tl_lammps_data.h).  Each particle keeps its position, radius (LAMMPS:
 * diameter / 2) and velocity; its mass follows from its species' density,
 * as for every particle of a world (a LAMMPS density other than the
 * species' is named in a warning).  Species: with `species` >= 0 every
 * particle gets it; with `species` < 0 they come from the file (LAMMPS atom
 * type t is species t - 1, a snapshot's species as stored), and each must
 * exist in the world.  Ids are the world's (the file's LAMMPS ids and a
 * snapshot's ids are not kept: a world numbers its particles itself); spins
 * in the file are not applied (the world allocates them at set-up) and are
 * named in a warning when non-zero.  Call before tl_dem_setup, or after it
 * like tl_dem_add_particle.  Errors name the file and the particle. */
#ifndef TL_PARTICLE_FILES_H
#define TL_PARTICLE_FILES_H

#include <stddef.h>

#include "tl_dem.h"
#include "tl_error.h"

TlStatus tl_dem_add_particles_from_file(TlDem *dem, const char *path, int species, size_t *n_added);

#endif
