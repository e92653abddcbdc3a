/* Particle snapshots: one HDF5 file per output step plus an XDMF series.
 *
 * tl_particle_writer_write() writes <dir>/<name>_<k>.h5 (k = 000000, 000001,
 * ... counts the snapshots of this writer) and rewrites <dir>/<name>.xmf so
 * that it lists every snapshot so far as a temporal collection: ParaView
 * opens <name>.xmf as a time series of point clouds (Polyvertex), with the
 * radius and every other array as point data (Glyph filter: Sphere, scale by
 * "radius", scale factor 2 since the sphere source has radius 0.5).
 *
 * Layout of a snapshot file (all doubles are native IEEE 754 binary64):
 *   /                      attributes: format = "talus-particles",
 *                          format_version, time (double), step (int64)
 *   /particles/position          n x 3
 *   /particles/radius            n
 *   /particles/vertices          n       int32 0..n-1 (the vertex cells of the XDMF topology)
 *   /particles/velocity          n x 3   (optional)
 *   /particles/angular_velocity  n x 3   (optional)
 *   /particles/force             n x 3   (optional)
 *   /particles/torque            n x 3   (optional)
 *   /particles/species           n       int32 (optional)
 *   /particles/id                n       int64 (optional; written by every
 *                                driver): the particle's persistent id, which
 *                                follows it when the DEM renumbers its arrays
 *                                (an XDMF attribute "id": ParaView's
 *                                Temporal Particles To Pathlines takes it as
 *                                the Id channel array)
 *   /particles/fields/<name>     n or n x c  (optional extra fields; the
 *                                group lists them in attribute "names")
 *   /provenance            attributes: version, revision, command line,
 *                          options (tl_provenance.h)
 * All files are written atomically (temporary name, then rename). */
#ifndef TL_PARTICLE_SNAPSHOT_H
#define TL_PARTICLE_SNAPSHOT_H

#include <stddef.h>
#include <stdint.h>

#include "tl_checkpoint.h"
#include "tl_error.h"
#include "tl_math.h"
#include "tl_particles.h"
#include "tl_xdmf.h"

#define TL_PARTICLE_FORMAT_VERSION 1

/* What to write: pointers into the caller's arrays (nothing is copied).
 * position and radius are required; any other pointer may be NULL. */
typedef struct {
  size_t n;
  const TlVec3 *position;
  const double *radius;
  const TlVec3 *velocity;
  const TlVec3 *angular_velocity;
  const TlVec3 *force;
  const TlVec3 *torque;
  const int *species;
  size_t n_fields; /* extra per-particle fields */
  const TlField *fields;
  const int64_t *id; /* persistent ids (last, so positional initialisers stay valid) */
} TlParticleView;

/* The view of every array of a particle store: positions, radii, velocities,
 * spins, forces, torques (those allocated), species and ids; no extra
 * fields.  The usual way to write a DEM world's particles:
 *   TlParticleView v;  tl_particle_view_of(tl_dem_particles(dem), &v);
 *   tl_particle_writer_write(writer, step, t, &v); */
void tl_particle_view_of(const TlParticles *particles, TlParticleView *view);

typedef struct TlParticleWriter TlParticleWriter;

/* A writer of <dir>/<name>_*.h5 and <dir>/<name>.xmf; creates dir if needed. */
TlStatus tl_particle_writer_create(const char *dir, const char *name, TlParticleWriter **writer);
void tl_particle_writer_destroy(TlParticleWriter **writer);
/* With on != 0 each snapshot also writes <dir>/<name>_<k>.csv: the
 * provenance lines (tl_provenance.h), a "# time: ..." line, then one row per
 * particle "id,species,x [m],y [m],z [m],radius [m],vx [m/s],vy [m/s],vz [m/s]"
 * (id, species and velocity when the view has them), for per-particle
 * analysis in a spreadsheet or pandas (pandas.read_csv(path, comment='#')). */
void tl_particle_writer_set_csv(TlParticleWriter *writer, int on);
/* Writes one snapshot at simulation time `time` and step `step`. */
TlStatus tl_particle_writer_write(TlParticleWriter *writer, int64_t step, double time, const TlParticleView *view);
/* Number of snapshots written so far, and the path of the last one ("" before any). */
size_t tl_particle_writer_count(const TlParticleWriter *writer);
const char *tl_particle_writer_last_path(const TlParticleWriter *writer);
/* Saves the snapshot counter and the XDMF list, so a restarted run continues
 * the numbering and the same .xmf series. */
extern const TlCheckpointOps tl_particle_writer_checkpoint_ops;

/* ---------------------------------------------------------------- reading */
typedef struct {
  size_t n;
  double time;
  int64_t step;
  TlVec3 *position;
  double *radius;
  TlVec3 *velocity, *angular_velocity, *force, *torque; /* NULL when absent */
  int *species;                                         /* NULL when absent */
  int64_t *id;                                          /* NULL when absent */
  size_t n_fields;
  char **field_names;
  int *field_components;
  double **field_data;
} TlParticleSnapshot;

TlStatus tl_particle_snapshot_read(const char *path, TlParticleSnapshot *snapshot);
void tl_particle_snapshot_free(TlParticleSnapshot *snapshot);

#endif
