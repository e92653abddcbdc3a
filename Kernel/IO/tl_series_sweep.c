/* Removal of stale snapshot files of a series (tl_series_sweep.h). */
#include "tl_series_sweep.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tl_log.h"

/* The index of "<name>_" + `digits` digits + ".h5" after `prefix`, or -1. */
static long tl_sweep_index(const char *file, const char *prefix, size_t digits)
{
  size_t np = strlen(prefix);
  if (strncmp(file, prefix, np) != 0) return -1;
  const char *p = file + np;
  for (size_t k = 0; k < digits; ++k)
    if (p[k] < '0' || p[k] > '9') return -1;
  if (strcmp(p + digits, ".h5") != 0) return -1;
  return strtol(p, NULL, 10);
}

/* Removes the step files from `first_free` on and the mesh files from
 * `mesh_from` on (-1: none). */
static TlStatus tl_series_sweep(const char *xmf_path, size_t first_free, long mesh_from, size_t *removed)
{
  *removed = 0;
  size_t n = strlen(xmf_path);
  if (n < 5 || strcmp(xmf_path + n - 4, ".xmf") != 0) TL_ERROR(TL_ERR_ARG, "series file '%s' does not end in .xmf", xmf_path);
  char dir[4096], step_prefix[1100], mesh_prefix[1100];
  const char *slash = strrchr(xmf_path, '/');
  const char *base = slash ? slash + 1 : xmf_path;
  size_t nd = slash ? (size_t)(slash - xmf_path) : 0, nb = (size_t)(xmf_path + n - 4 - base);
  if (nd + 1 > sizeof dir || nb + 7 > sizeof step_prefix) TL_ERROR(TL_ERR_ARG, "series file name '%s' is too long", xmf_path);
  if (slash) {
    memcpy(dir, xmf_path, nd ? nd : 1); /* "/x.xmf": the root */
    dir[nd ? nd : 1] = '\0';
  } else {
    snprintf(dir, sizeof dir, ".");
  }
  snprintf(step_prefix, sizeof step_prefix, "%.*s_", (int)nb, base);
  snprintf(mesh_prefix, sizeof mesh_prefix, "%.*s_mesh_", (int)nb, base);
  DIR *d = opendir(dir);
  if (!d) TL_ERROR(TL_ERR_IO, "cannot list the output folder '%s': %s", dir, strerror(errno));
  TlStatus s = TL_OK;
  for (struct dirent *e; s == TL_OK && (e = readdir(d)) != NULL;) {
    long step = tl_sweep_index(e->d_name, step_prefix, 6), mesh = tl_sweep_index(e->d_name, mesh_prefix, 4);
    if (!((step >= 0 && (size_t)step >= first_free) || (mesh_from >= 0 && mesh >= mesh_from))) continue;
    char path[8192];
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    if (unlink(path) != 0 && errno != ENOENT)
      s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "cannot remove the stale snapshot '%s': %s", path, strerror(errno));
    else
      ++*removed;
  }
  closedir(d);
  return s;
}

TlStatus tl_series_sweep_stale(const char *xmf_path, size_t first_free, int fresh, size_t *removed)
{
  return tl_series_sweep(xmf_path, first_free, fresh ? 1 : -1, removed);
}

TlStatus tl_series_sweep_whole(const char *dir, const char *name, size_t *removed)
{
  *removed = 0;
  char xmf[4096];
  int n = snprintf(xmf, sizeof xmf, "%s%s%s.xmf", dir && dir[0] ? dir : "", dir && dir[0] ? "/" : "", name);
  if (n < 0 || (size_t)n >= sizeof xmf) TL_ERROR(TL_ERR_ARG, "series '%s' in '%s': path too long", name, dir ? dir : "");
  TL_CHECK(tl_series_sweep(xmf, 0, 0, removed));
  if (unlink(xmf) == 0)
    ++*removed;
  else if (errno != ENOENT)
    TL_ERROR(TL_ERR_IO, "cannot remove the stale series '%s': %s", xmf, strerror(errno));
  if (*removed)
    tl_info("removed %zu file%s of an earlier run's series %s (this run writes none)", *removed, *removed > 1 ? "s" : "",
            xmf);
  return TL_OK;
}
