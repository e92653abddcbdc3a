/* Options that were renamed so that one thing has one name in every driver.
 *
 * A driver lists its former names with the names that replaced them; an old
 * name given on the command line (or in an options file) is refused with a
 * message naming the new one, rather than being reported as unknown or,
 * worse, silently meaning something else.  Built on the public tl_options
 * API only. */
#ifndef TL_OPTIONS_RENAMED_H
#define TL_OPTIONS_RENAMED_H

#include "tl_options.h"

typedef struct {
  const char *old_name; /* "-fem" */
  const char *new_name; /* "-stepper" */
  const char *note;     /* optional: how the value changed ("now in seconds"), or NULL */
} TlRenamedOption;

/* TL_ERR_ARG naming the first old name of `table` (n entries) that was given;
 * TL_OK when none was.  Call it before the getters. */
TlStatus tl_options_refuse_renamed(TlOptions *o, const TlRenamedOption *table, int n);

#endif
