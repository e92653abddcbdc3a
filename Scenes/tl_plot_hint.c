/* The plot command printed by drivers (tl_plot_hint.h). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "tl_plot_hint.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

const char *tl_plot_command(const char *tools_dir, const char *script, char *buf, size_t n)
{
  char path[PATH_MAX];
  snprintf(path, sizeof path, "%s/%s", tools_dir ? tools_dir : ".", script);
  if (access(path, R_OK) == 0)
    snprintf(buf, n, "/usr/bin/python3 %s", path);
  else
    snprintf(buf, n, "tools/%s of the Talus sources, with Debian's /usr/bin/python3 and python3-matplotlib, on", script);
  return buf;
}

const char *tl_plot_abs_dir(const char *dir, char *buf, size_t n)
{
  char abs[PATH_MAX];
  snprintf(buf, n, "%s", realpath(dir, abs) ? abs : dir);
  return buf;
}
