/* Talus: everything a scene needs, in one include.
 *
 *   #include "talus.h"
 *
 * gives the core (errors, options, registry, logging, timers), the DEM
 * (world, particles, contact laws, walls, domains, the grid), coarse
 * graining, the finite elements (meshes, element types, materials, the
 * solid, steppers and solvers), the couplings (surface, volume, bridging
 * domain, FEM x DEM), the input and output (LAMMPS data and STL files,
 * particles from files; HDF5 snapshots of particles, meshes and walls with
 * XDMF, time series, checkpoints) and the conveniences of tl_api.h.
 * docs/tutorial/ shows a scene of each kind; docs/catalogue.md lists every
 * registered type with its parameters.
 *
 * The headers are C11; from C++ they are included with C linkage.  The
 * standard headers they use come first, outside the extern "C" block, so
 * that a C++ compiler sees its own <cmath> and friends with C++ linkage. */
#ifndef TALUS_H
#define TALUS_H

#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* core */
#include "tl_config.h"
#include "tl_error.h"
#include "tl_init.h"
#include "tl_log.h"
#include "tl_math.h"
#include "tl_memory.h"
#include "tl_object.h"
#include "tl_options.h"
#include "tl_parallel.h"
#include "tl_predicates.h"
#include "tl_progress.h"
#include "tl_registry.h"
#include "tl_summary.h"
#include "tl_timer.h"

/* output */
#include "tl_io.h"
#include "tl_lammps_data.h"
#include "tl_particle_files.h"
#include "tl_stl.h"
#include "tl_wall_snapshot.h"

/* DEM: particles, contact laws, walls, domains, the world */
#include "tl_particles.h"
#include "tl_contact_law.h"
#include "tl_contact_part.h"
#include "tl_domain.h"
#include "tl_hgrid.h"
#include "tl_wall.h"
#include "tl_trisurface.h"
#include "tl_wall_trisurface.h"
#include "tl_dem.h"
#include "tl_dem_packing.h"
#include "tl_dem_probe.h"

/* coarse graining */
#include "tl_cg_kernel.h"
#include "tl_cg_fields.h"
#include "tl_cg_surface.h"

/* finite elements: meshes, element types, materials, the solid, solvers */
#include "tl_mesh.h"
#include "tl_mesh_locator.h"
#include "tl_element.h"
#include "tl_material.h"
#include "tl_solid.h"
#include "tl_solid_output.h"
#include "tl_solid_tie.h"
#include "tl_pulse.h"
#include "tl_sparse.h"
#include "tl_linear_solver.h"
#include "tl_newton.h"
#include "tl_stepper.h"
#include "tl_linear_static.h"
#include "tl_mech_system.h"
#include "tl_mech_linear.h"
#include "tl_modal.h"

/* couplings */
#include "tl_scoupling.h"
#include "tl_coupled_loop.h"
#include "tl_vcoupling.h"
#include "tl_vcoupling_element.h"
#include "tl_bdm.h"
#include "tl_nhl_cell.h"
#include "tl_nhl_material.h"
#include "tl_nhl_operator.h"

/* the conveniences that compose these (a law with its settings, box walls,
 * a scene's writer, walls from files, the volume-coupled loop) */
#include "tl_api.h"

#ifdef __cplusplus
}
#endif

#endif
