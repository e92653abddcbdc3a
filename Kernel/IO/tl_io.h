/* The IO module in one include: atomic files, particle and mesh snapshots
 * (HDF5 + XDMF), particles from files (LAMMPS data, snapshots), provenance,
 * time-series tables (CSV + HDF5) and checkpoints.  File
 * layouts and how to open them: docs/output.md. */
#ifndef TL_IO_H
#define TL_IO_H

#include "tl_atomic_file.h"
#include "tl_checkpoint.h"
#include "tl_mesh_snapshot.h"
#include "tl_output_dir.h"
#include "tl_particle_files.h"
#include "tl_particle_snapshot.h"
#include "tl_provenance.h"
#include "tl_timeseries.h"
#include "tl_xdmf.h"

#endif
