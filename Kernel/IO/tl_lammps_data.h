/* Reader of LAMMPS data files of spheres (atom_style sphere, and LIGGGHTS's
 * atom_style granular, which has the same columns), so that Talus can run on
 * exactly the particles a peer code runs on.
 *
 * What is read:
 *   - the header: "N atoms", "N atom types", "xlo xhi", "ylo yhi", "zlo zhi"
 *     and the tilt factors "xy xz yz" (other LAMMPS header keywords are
 *     accepted; their sections are skipped by count);
 *   - the Atoms section, one line per atom:
 *       id type diameter density x y z [ix iy iz]
 *     (image flags optional, as LAMMPS's write_data and read_data allow);
 *   - the Velocities section if present:
 *       id vx vy vz wx wy wz
 *     matched to atoms by id;
 *   - Masses, Pair Coeffs and PairIJ Coeffs sections are skipped.
 *
 * The first line is a title and is never parsed.  Text after '#' is a
 * comment; the comment on the Atoms line ("Atoms # sphere"), when present,
 * must name a style with the sphere columns.  Numbers are LAMMPS units as
 * they stand in the file: no conversion.  The LAMMPS meaning of `density` is
 * kept: mass = density * pi/6 * diameter^3 (tl_lammps_data_mass).
 *
 * Every malformed input gives TL_ERR_FORMAT (TL_ERR_IO when the file cannot
 * be opened, TL_ERR_UNSUPPORTED for a section this reader does not know) and
 * a message that names the file and line and what was expected. */
#ifndef TL_LAMMPS_DATA_H
#define TL_LAMMPS_DATA_H

#include <stddef.h>
#include <stdint.h>

#include "tl_error.h"
#include "tl_math.h"

typedef struct {
  char *title;         /* the first line, without its newline */
  size_t n;            /* number of atoms */
  int n_types;         /* number of atom types declared in the header */
  double lo[3], hi[3]; /* box bounds (LAMMPS's default -0.5 0.5 when absent) */
  double tilt[3];      /* xy xz yz; zeros for an orthogonal box */
  int triclinic;       /* 1 when the header has the "xy xz yz" line */
  /* per atom, in the order of the Atoms section */
  int64_t *id;      /* atom id (positive, unique) */
  int32_t *type;    /* atom type, 1..n_types */
  double *diameter; /* > 0 */
  double *density;  /* > 0 */
  TlVec3 *x;        /* position */
  int32_t *image;   /* 3n image flags (ix iy iz per atom); zeros when absent */
  int has_images;   /* 1 when the Atoms lines carried image flags */
  int has_velocities; /* 1 when the file has a Velocities section */
  TlVec3 *v;        /* velocity; zeros when no Velocities section */
  TlVec3 *omega;    /* angular velocity; zeros when no Velocities section */
} TlLammpsData;

/* Reads the data file at `path` into a newly allocated *data. */
TlStatus tl_lammps_data_read(const char *path, TlLammpsData **data);
/* Frees *data and sets it to NULL (harmless on NULL). */
void tl_lammps_data_destroy(TlLammpsData **data);

/* Mass of atom i in LAMMPS's convention for spheres: density * pi/6 * d^3. */
double tl_lammps_data_mass(const TlLammpsData *data, size_t i);
/* Unwrapped position of atom i: x + ix (xhi - xlo) + ... (orthogonal box;
 * with tilt factors the tilt is applied as LAMMPS does). */
TlVec3 tl_lammps_data_unwrapped(const TlLammpsData *data, size_t i);
/* Number of atoms of the given type. */
size_t tl_lammps_data_count_type(const TlLammpsData *data, int type);

#endif
