/* The plot command a driver prints before its summary line.
 *
 * The command names Debian's interpreter, /usr/bin/python3 (the one
 * python3-matplotlib installs into; a python3 first on the PATH, a venv's,
 * may lack matplotlib), the script by its absolute path in the source tree
 * the driver was built from (TALUS_TOOLS_DIR, set by Drivers/CMakeLists.txt),
 * and the output folder by its absolute path, so that it runs from any
 * folder.  An installed driver whose source tree is gone says where the
 * script lives instead.  Drivers print
 *   printf("plots: %s %s\n", tl_plot_command(TALUS_TOOLS_DIR, "plot_x.py", cmd, sizeof cmd),
 *          tl_plot_abs_dir(dir, abs, sizeof abs)); */
#ifndef TL_PLOT_HINT_H
#define TL_PLOT_HINT_H

#include <stddef.h>

/* "/usr/bin/python3 <tools_dir>/<script>" when the script is readable there;
 * otherwise "tools/<script> of the Talus sources, with Debian's
 * /usr/bin/python3 and python3-matplotlib, on".  Returns buf. */
const char *tl_plot_command(const char *tools_dir, const char *script, char *buf, size_t n);
/* The absolute path of the folder `dir` (as given when it cannot be
 * resolved).  Returns buf. */
const char *tl_plot_abs_dir(const char *dir, char *buf, size_t n);

#endif
