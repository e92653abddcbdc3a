/* The output folder of a driver: option -output_dir, default
 * results/<program name>, created (with its parents) before anything is
 * written into it. */
#ifndef TL_OUTPUT_DIR_H
#define TL_OUTPUT_DIR_H

#include "tl_error.h"
#include "tl_options.h"

/* Reads -output_dir (default "results/<program>"), creates the folder and
 * returns its path in *dir (allocated; free with tl_free). */
TlStatus tl_output_dir(TlOptions *options, char **dir);
/* Refuses an empty -output_dir value by the option's name (drivers that
 * read -output_dir themselves call it before creating the folder). */
TlStatus tl_output_dir_check(const char *dir);
/* A run starts (or restarts) in folder dir: refuses an empty name, creates
 * the folder and removes the temporaries killed writes left in it
 * (tl_atomic_remove_stale).  tl_output_dir calls it. */
TlStatus tl_output_dir_prepare(const char *dir);

#endif
