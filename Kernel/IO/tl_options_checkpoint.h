/* A driver's options as a checkpoint section: saved with the state, and on
 * restart compared with the options of the continuing run.  A restart must
 * continue the same physics: a value that differs (another -E, -dt_factor,
 * particle count or density) is refused by name with both values, except
 * for the options declared restart-safe (tl_options_is_restart_safe: end
 * time, output folder and cadence, threads).  Add this section first, so
 * that the comparison comes before any state is overwritten. */
#ifndef TL_OPTIONS_CHECKPOINT_H
#define TL_OPTIONS_CHECKPOINT_H

#include "tl_checkpoint.h"
#include "tl_options.h"

/* The object is the driver's TlOptions (after tl_options_finish). */
extern const TlCheckpointOps tl_options_checkpoint_ops;

#endif
