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

#endif
