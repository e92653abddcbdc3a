/* Library start-up: registers every built-in type (contact-law parts,
 * walls, element types, materials, steppers, CG kernels, ...) so they can be
 * found by name.  Idempotent; registry look-ups call it themselves. */
#ifndef TL_INIT_H
#define TL_INIT_H

#include "tl_error.h"

TlStatus tl_initialize(void);
/* After tl_registry_clear(): the next tl_initialize() registers again. */
void tl_initialize_forget(void);

/* The Talus version ("0.1.0") and the git revision the library was built
 * from ("a533486f0c1d", "-dirty" appended for uncommitted changes; "unknown"
 * when built outside git), both fixed at build time. */
const char *tl_version(void);
const char *tl_revision(void);

/* The exit status of a program for a status: 0 for TL_OK and TL_HELP; 2 for
 * a refused option or input (TL_ERR_ARG, TL_ERR_FORMAT, TL_ERR_IO,
 * TL_ERR_NOT_FOUND, TL_ERR_UNSUPPORTED); 1 for a run stopped on a diagnosis
 * (TL_ERR_NUMERIC, TL_ERR_UNSTABLE, TL_ERR_CONVERGENCE) and for anything
 * else (TL_ERR_MEM, TL_ERR_STATE). */
int tl_exit_code(TlStatus status);
/* The word scripts read in a summary's status=: "ok", "refused" (exit 2),
 * "stopped" (exit 1, a physical diagnosis: blow-up, energy guard, a
 * non-finite value, divergence), "failed" (exit 1, any other error); a
 * summary with undefined figures says "undefined" (tl_summary.h). */
const char *tl_exit_word(TlStatus status);
/* For main(): on failure prints the error to stderr and, unless the last
 * summary already reported this failure, a final line
 * "summary: status=<word> exit=<code> error=<status name>" on stdout, so
 * every run's last summary line says how it ended; returns the exit code. */
int tl_driver_exit(TlStatus status);

#endif
