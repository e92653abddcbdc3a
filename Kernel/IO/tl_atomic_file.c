#include "tl_atomic_file.h"

#include <errno.h>
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "tl_memory.h"

struct TlAtomicFile {
  FILE *stream;
  char *path;
  char *temp;
};

static TlStatus tl_strdup_printf(char **out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static TlStatus tl_strdup_printf(char **out, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(NULL, 0, fmt, ap);
  va_end(ap);
  if (n < 0) TL_ERROR(TL_ERR_ARG, "cannot format string '%s'", fmt);
  TL_CHECK(tl_calloc(out, (size_t)n + 1, 1));
  va_start(ap, fmt);
  vsnprintf(*out, (size_t)n + 1, fmt, ap);
  va_end(ap);
  return TL_OK;
}

TlStatus tl_path_join(const char *dir, const char *name, char **path)
{
  if (!name || !name[0]) TL_ERROR(TL_ERR_ARG, "empty file name");
  if (!dir || !dir[0]) return tl_strdup_printf(path, "%s", name);
  size_t n = strlen(dir);
  return tl_strdup_printf(path, "%s%s%s", dir, dir[n - 1] == '/' ? "" : "/", name);
}

TlStatus tl_atomic_temp_name(const char *path, char **temp_name)
{
  static unsigned long counter = 0;
  if (!path || !path[0]) TL_ERROR(TL_ERR_ARG, "empty output path");
  unsigned long k = __atomic_fetch_add(&counter, 1UL, __ATOMIC_RELAXED);
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  if (!base[0]) TL_ERROR(TL_ERR_ARG, "output path '%s' names a folder, not a file", path);
  int dir_len = slash ? (int)(slash - path + 1) : 0;
  return tl_strdup_printf(temp_name, "%.*s.%s.%ld.%lu.tmp", dir_len, path, base, (long)getpid(), k);
}

/* A name of the pattern ".<base>.<pid>.<counter>.tmp" (base not empty);
 * its pid in *pid. */
static int tl_atomic_temp_pid(const char *name, long *pid)
{
  size_t n = strlen(name);
  if (n < 9 || name[0] != '.' || strcmp(name + n - 4, ".tmp") != 0) return 0;
  /* back from ".tmp": the counter's digits, a dot, the pid's digits, a dot */
  size_t e = n - 4, k = e;
  while (k > 0 && name[k - 1] >= '0' && name[k - 1] <= '9') --k;
  if (k == e || k < 2 || name[k - 1] != '.') return 0;
  size_t pe = k - 1, pk = pe;
  while (pk > 0 && name[pk - 1] >= '0' && name[pk - 1] <= '9') --pk;
  if (pk == pe || pk < 3 || name[pk - 1] != '.' || pe - pk > 18) return 0; /* ".x." at least before */
  char digits[20];
  memcpy(digits, name + pk, pe - pk);
  digits[pe - pk] = '\0';
  *pid = strtol(digits, NULL, 10);
  return *pid > 0;
}

TlStatus tl_atomic_remove_stale(const char *dir, size_t *removed)
{
  if (removed) *removed = 0;
  if (!dir || !dir[0]) TL_ERROR(TL_ERR_ARG, "empty folder name");
  DIR *d = opendir(dir);
  if (!d) {
    if (errno == ENOENT) return TL_OK;
    TL_ERROR(TL_ERR_IO, "cannot read folder '%s': %s", dir, strerror(errno));
  }
  TlStatus s = TL_OK;
  const long self = (long)getpid();
  for (struct dirent *e; s == TL_OK && (e = readdir(d)) != NULL;) {
    long pid;
    if (!tl_atomic_temp_pid(e->d_name, &pid) || pid == self) continue;
    if (kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue; /* its writer may still run */
    char *path = NULL;
    s = tl_path_join(dir, e->d_name, &path);
    if (s != TL_OK) break;
    struct stat st;
    if (lstat(path, &st) == 0 && S_ISREG(st.st_mode)) {
      if (unlink(path) == 0) {
        if (removed) ++*removed;
      } else if (errno != ENOENT) {
        s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "cannot remove the stale temporary '%s': %s", path, strerror(errno));
      }
    }
    tl_free(&path);
  }
  closedir(d);
  return s;
}

/* fsync of a folder makes the rename itself durable. */
static void tl_sync_folder_of(const char *path)
{
  const char *slash = strrchr(path, '/');
  char *dir = NULL;
  if (!slash) {
    if (tl_strdup_printf(&dir, ".") != TL_OK) return;
  } else if (tl_strdup_printf(&dir, "%.*s", slash == path ? 1 : (int)(slash - path), path) != TL_OK) {
    return;
  }
  int fd = open(dir, O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    (void)fsync(fd); /* some file systems refuse fsync on folders: not an error */
    close(fd);
  }
  tl_free(&dir);
}

TlStatus tl_atomic_commit_path(const char *temp_name, const char *path)
{
  int fd = open(temp_name, O_RDONLY);
  if (fd < 0) {
    int e = errno;
    unlink(temp_name);
    TL_ERROR(TL_ERR_IO, "cannot reopen temporary file '%s' for '%s': %s", temp_name, path, strerror(e));
  }
  if (fsync(fd) != 0 && errno != EINVAL) {
    int e = errno;
    close(fd);
    unlink(temp_name);
    TL_ERROR(TL_ERR_IO, "cannot sync '%s' (temporary for '%s'): %s", temp_name, path, strerror(e));
  }
  close(fd);
  if (rename(temp_name, path) != 0) {
    int e = errno;
    unlink(temp_name);
    TL_ERROR(TL_ERR_IO, "cannot rename '%s' to '%s': %s", temp_name, path, strerror(e));
  }
  tl_sync_folder_of(path);
  return TL_OK;
}

TlStatus tl_atomic_file_open(const char *path, TlAtomicFile **file)
{
  TlStatus s;
  TlAtomicFile *f = NULL;
  *file = NULL;
  TL_CHECK(TL_NEW(f));
  TL_CHECK_GOTO(s, tl_strdup_printf(&f->path, "%s", path), fail);
  TL_CHECK_GOTO(s, tl_atomic_temp_name(path, &f->temp), fail);
  f->stream = fopen(f->temp, "wb");
  if (!f->stream) {
    s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "cannot create '%s' (temporary for '%s'): %s", f->temp,
                     path, strerror(errno));
    goto fail;
  }
  *file = f;
  return TL_OK;
fail:
  tl_free(&f->path);
  tl_free(&f->temp);
  tl_free(&f);
  return s;
}

FILE *tl_atomic_file_stream(TlAtomicFile *file) { return file->stream; }

static void tl_atomic_file_free(TlAtomicFile **file)
{
  tl_free(&(*file)->path);
  tl_free(&(*file)->temp);
  tl_free(file);
}

void tl_atomic_file_abort(TlAtomicFile **file)
{
  if (!file || !*file) return;
  if ((*file)->stream) fclose((*file)->stream);
  unlink((*file)->temp);
  tl_atomic_file_free(file);
}

TlStatus tl_atomic_file_commit(TlAtomicFile **file)
{
  TlAtomicFile *f = *file;
  if (!f) TL_ERROR(TL_ERR_STATE, "commit of an atomic file that is not open");
  int bad = ferror(f->stream) || fflush(f->stream) != 0;
  int e = errno;
  if (!bad && fsync(fileno(f->stream)) != 0 && errno != EINVAL) {
    bad = 1;
    e = errno;
  }
  if (fclose(f->stream) != 0 && !bad) {
    bad = 1;
    e = errno;
  }
  f->stream = NULL;
  if (bad) {
    TlStatus s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "cannot write '%s' (temporary '%s'): %s", f->path,
                              f->temp, strerror(e));
    unlink(f->temp);
    tl_atomic_file_free(file);
    return s;
  }
  if (rename(f->temp, f->path) != 0) {
    TlStatus s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "cannot rename '%s' to '%s': %s", f->temp, f->path,
                              strerror(errno));
    unlink(f->temp);
    tl_atomic_file_free(file);
    return s;
  }
  tl_sync_folder_of(f->path);
  tl_atomic_file_free(file);
  return TL_OK;
}

TlStatus tl_atomic_write(const char *path, TlAtomicWriteFn write, void *context)
{
  TlAtomicFile *f;
  TL_CHECK(tl_atomic_file_open(path, &f));
  TlStatus s = write(f->stream, context);
  if (s != TL_OK) {
    tl_atomic_file_abort(&f);
    return tl_error_trace(s, __FILE__, __LINE__);
  }
  TL_CHECK(tl_atomic_file_commit(&f));
  return TL_OK;
}

TlStatus tl_mkdir_p(const char *path)
{
  if (!path || !path[0]) TL_ERROR(TL_ERR_ARG, "empty folder name");
  char *p;
  TL_CHECK(tl_strdup_printf(&p, "%s", path));
  for (char *c = p + 1;; ++c) {
    if (*c != '/' && *c != '\0') continue;
    char saved = *c;
    *c = '\0';
    if (mkdir(p, 0777) != 0 && errno != EEXIST) {
      TlStatus s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "cannot create folder '%s': %s", p, strerror(errno));
      tl_free(&p);
      return s;
    }
    *c = saved;
    if (saved == '\0') break;
  }
  struct stat st;
  if (stat(p, &st) != 0 || !S_ISDIR(st.st_mode)) {
    TlStatus s = tl_error_set(TL_ERR_IO, __FILE__, __LINE__, "'%s' exists and is not a folder", p);
    tl_free(&p);
    return s;
  }
  tl_free(&p);
  return TL_OK;
}
