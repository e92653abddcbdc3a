/* Talus: everything a driver needs, in one include. */
#ifndef TALUS_H
#define TALUS_H

#include "tl_config.h"
#include "tl_error.h"
#include "tl_init.h"
#include "tl_io.h"
#include "tl_log.h"
#include "tl_math.h"
#include "tl_memory.h"
#include "tl_object.h"
#include "tl_options.h"
#include "tl_progress.h"
#include "tl_registry.h"
#include "tl_summary.h"
#include "tl_timer.h"

#endif
