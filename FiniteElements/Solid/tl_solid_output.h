/* Snapshots of a solid through the IO module's mesh writer (HDF5 + XDMF,
 * opened in ParaView): the reference mesh once, and per step the
 * displacement, the velocity (optional) and per element the volume-averaged
 * second Piola-Kirchhoff stress, Cauchy stress and von Mises stress.
 * Each element type names its output cell and node order (its
 * TlElementOutput); the connectivity is converted to that order once. */
#ifndef TL_SOLID_OUTPUT_H
#define TL_SOLID_OUTPUT_H

#include <stdint.h>
#include "tl_checkpoint.h"
#include "tl_error.h"
#include "tl_solid.h"

typedef struct TlSolidOutput TlSolidOutput;

/* Files <dir>/<name>*.h5 and <dir>/<name>.xmf. */
TlStatus tl_solid_output_create(TlSolid *solid, const char *dir, const char *name, TlSolidOutput **out);
/* u and v are the system's dof vectors (v may be NULL). */
TlStatus tl_solid_output_write(TlSolidOutput *out, int64_t step, double t, const double *u, const double *v);
/* The step file written last ("" before any). */
const char *tl_solid_output_last_path(const TlSolidOutput *out);
void tl_solid_output_destroy(TlSolidOutput **out);
/* Checkpoint section (object: the TlSolidOutput): the series written so
 * far, so that a restarted run appends to it. */
extern const TlCheckpointOps tl_solid_output_checkpoint_ops;

#endif
