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

#endif
