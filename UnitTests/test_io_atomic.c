/* Atomic writes: a writer killed by SIGKILL in the middle of overwriting a
 * file (text stream and HDF5 checkpoint) leaves the previous file intact and
 * readable; a failing writer leaves no temporary file; a successful one
 * replaces the content. */
#include <dirent.h>
#include <signal.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "talus.h"
#include "tl_atomic_file.h"
#include "tl_checkpoint.h"
#include "tl_output_dir.h"
#include "tl_particle_snapshot.h"
#include "tl_test.h"

#include <sys/stat.h>

static int is_folder(const char *path)
{
  struct stat st;
  return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* -output_dir: the default results/<program>, or the given folder; created. */
static void test_output_dir(void)
{
  char *argv1[] = {"/usr/bin/some_driver", NULL};
  TlOptions *o;
  char *dir = NULL;
  TL_TEST_STATUS(tl_options_create(1, argv1, "test", &o), TL_OK);
  TL_TEST_STATUS(tl_output_dir(o, &dir), TL_OK);
  TL_TEST_ASSERT(dir && strcmp(dir, "results/some_driver") == 0 && is_folder(dir), "default dir '%s'", dir ? dir : "");
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
  tl_free(&dir);
  tl_options_destroy(&o);
  char *argv2[] = {"drv", "-output_dir", "runs/a/b", NULL};
  TL_TEST_STATUS(tl_options_create(3, argv2, "test", &o), TL_OK);
  TL_TEST_STATUS(tl_output_dir(o, &dir), TL_OK);
  TL_TEST_ASSERT(dir && strcmp(dir, "runs/a/b") == 0 && is_folder(dir), "given dir '%s'", dir ? dir : "");
  TL_TEST_STATUS(tl_options_finish(o, stdout), TL_OK);
  tl_free(&dir);
  tl_options_destroy(&o);
}

typedef struct {
  const char *text;
  int die_midway;
  int fail;
} Payload;

static TlStatus write_payload(FILE *stream, void *context)
{
  const Payload *p = context;
  size_t n = strlen(p->text);
  /* a large write, so the kill lands with bytes already in the temporary */
  for (int rep = 0; rep < 2000; ++rep) {
    if (fwrite(p->text, 1, n, stream) != n) TL_ERROR(TL_ERR_IO, "short write");
    if (rep == 1000) {
      fflush(stream);
      if (p->die_midway) raise(SIGKILL);
      if (p->fail) TL_ERROR(TL_ERR_IO, "simulated failure after %d blocks", rep);
    }
  }
  return TL_OK;
}

static int file_is(const char *path, const char *text, size_t reps)
{
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  size_t n = strlen(text), total = 0;
  char buf[256];
  int ok = 1;
  while (ok) {
    size_t got = fread(buf, 1, n, f);
    if (got == 0) break;
    ok = got == n && memcmp(buf, text, n) == 0;
    ++total;
  }
  fclose(f);
  return ok && total == reps;
}

static int count_temporaries(void)
{
  DIR *d = opendir(".");
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)))
    if (strstr(e->d_name, ".tmp")) ++n;
  closedir(d);
  return n;
}

static void remove_temporaries(void)
{
  DIR *d = opendir(".");
  struct dirent *e;
  while ((e = readdir(d)))
    if (strstr(e->d_name, ".tmp")) unlink(e->d_name);
  closedir(d);
}

/* Runs fn in a child process and returns the signal that ended it (0 if it
 * exited normally). */
static int run_child(void (*fn)(void))
{
  fflush(NULL);
  pid_t pid = fork();
  if (pid == 0) {
    fn();
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFSIGNALED(status) ? WTERMSIG(status) : 0;
}

static void child_overwrite_text(void)
{
  Payload p = {"new content, never complete\n", 1, 0};
  tl_atomic_write("data.txt", write_payload, &p);
}

static void test_text(void)
{
  Payload old = {"the previous, complete file\n", 0, 0};
  TL_TEST_STATUS(tl_atomic_write("data.txt", write_payload, &old), TL_OK);
  TL_TEST_ASSERT(file_is("data.txt", old.text, 2000), "first write incomplete");
  TL_TEST_ASSERT(count_temporaries() == 0, "temporary left after success");

  int sig = run_child(child_overwrite_text);
  TL_TEST_ASSERT(sig == SIGKILL, "child ended by signal %d, expected SIGKILL", sig);
  TL_TEST_ASSERT(file_is("data.txt", old.text, 2000), "previous file damaged by the killed writer");
  /* the killed writer's temporary exists (it had written bytes) and is hidden */
  TL_TEST_ASSERT(count_temporaries() == 1, "%d temporaries after the kill, expected 1", count_temporaries());
  remove_temporaries();

  Payload failing = {"failing writer\n", 0, 1};
  TL_TEST_STATUS(tl_atomic_write("data.txt", write_payload, &failing), TL_ERR_IO);
  TL_TEST_ASSERT(file_is("data.txt", old.text, 2000), "previous file damaged by the failing writer");
  TL_TEST_ASSERT(count_temporaries() == 0, "temporary left after a failing writer");

  Payload fresh = {"replacement\n", 0, 0};
  TL_TEST_STATUS(tl_atomic_write("data.txt", write_payload, &fresh), TL_OK);
  TL_TEST_ASSERT(file_is("data.txt", fresh.text, 2000), "replacement not in place");

  /* a folder that does not exist is an error naming the path */
  TL_TEST_STATUS(tl_atomic_write("no/such/folder/x.txt", write_payload, &fresh), TL_ERR_IO);
  TL_TEST_ASSERT(strstr(tl_error_message(), "no/such/folder") != NULL, "message: %s", tl_error_message());
  TL_TEST_STATUS(tl_mkdir_p("made/deep/folder"), TL_OK);
  TL_TEST_STATUS(tl_mkdir_p("made/deep/folder/"), TL_OK);
  TL_TEST_STATUS(tl_atomic_write("made/deep/folder/x.txt", write_payload, &fresh), TL_OK);
  TL_TEST_STATUS(tl_mkdir_p("data.txt"), TL_ERR_IO);
}

/* A checkpoint section that dies while being saved. */
typedef struct {
  double values[4096];
  int die;
} Big;

static TlStatus big_save(const void *object, TlCheckpointWriter *w, const char *group)
{
  const Big *b = object;
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "first", 4096, b->values));
  if (b->die) raise(SIGKILL);
  TL_CHECK(tl_checkpoint_write_doubles(w, group, "second", 4096, b->values));
  return TL_OK;
}

static TlStatus big_load(void *object, TlCheckpointReader *r, const char *group)
{
  Big *b = object;
  double second[4096];
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "first", 4096, b->values));
  TL_CHECK(tl_checkpoint_read_doubles(r, group, "second", 4096, second));
  if (memcmp(second, b->values, sizeof second) != 0) TL_ERROR(TL_ERR_FORMAT, "halves differ");
  return TL_OK;
}

static const TlCheckpointOps big_ops = {{"checkpoint", "big", "test"}, big_save, big_load};
static Big big;

static void child_overwrite_checkpoint(void)
{
  TlCheckpoint *cp;
  if (tl_checkpoint_create(&cp) != TL_OK) return;
  for (int i = 0; i < 4096; ++i) big.values[i] = -1.0;
  big.die = 1;
  tl_checkpoint_add(cp, "big", &big_ops, &big);
  tl_checkpoint_save(cp, "restart.h5", 2.0, 2);
}

static void test_checkpoint(void)
{
  TlCheckpoint *cp;
  TL_TEST_STATUS(tl_checkpoint_create(&cp), TL_OK);
  for (int i = 0; i < 4096; ++i) big.values[i] = i * 0.5;
  big.die = 0;
  TL_TEST_STATUS(tl_checkpoint_add(cp, "big", &big_ops, &big), TL_OK);
  TL_TEST_STATUS(tl_checkpoint_save(cp, "restart.h5", 1.0, 1), TL_OK);

  int sig = run_child(child_overwrite_checkpoint);
  TL_TEST_ASSERT(sig == SIGKILL, "child ended by signal %d, expected SIGKILL", sig);
  TL_TEST_ASSERT(count_temporaries() == 1, "%d temporaries after the kill, expected 1", count_temporaries());
  remove_temporaries();

  for (int i = 0; i < 4096; ++i) big.values[i] = 0.0;
  double t = 0;
  int64_t step = 0;
  TL_TEST_STATUS(tl_checkpoint_load(cp, "restart.h5", &t, &step), TL_OK);
  TL_TEST_ASSERT(t == 1.0 && step == 1, "the previous checkpoint was not kept: time %g step %lld", t, (long long)step);
  int same = 1;
  for (int i = 0; i < 4096; ++i) same &= big.values[i] == i * 0.5;
  TL_TEST_ASSERT(same, "previous checkpoint values damaged");
  tl_checkpoint_destroy(&cp);
}

/* A run starting in a folder removes the temporaries of killed writes
 * (tl_output_dir_prepare), and only those: a live writer's temporary, this
 * process's, look-alike names and the complete files stay. */
static void child_killed_in_folder(void)
{
  Payload p = {"a write killed midway\n", 1, 0};
  tl_atomic_write("stale_dir/table.csv", write_payload, &p);
}

static int exists(const char *path)
{
  struct stat st;
  return lstat(path, &st) == 0;
}

static void touch(const char *path)
{
  FILE *f = fopen(path, "w");
  if (f) fclose(f);
}

static int count_in(const char *dir, const char *needle)
{
  DIR *d = opendir(dir);
  int n = 0;
  if (!d) return -1;
  for (struct dirent *e; (e = readdir(d));)
    if (strstr(e->d_name, needle)) ++n;
  closedir(d);
  return n;
}

static void test_stale_temporaries(void)
{
  TL_TEST_STATUS(tl_mkdir_p("stale_dir"), TL_OK);
  Payload old = {"complete\n", 0, 0};
  TL_TEST_STATUS(tl_atomic_write("stale_dir/table.csv", write_payload, &old), TL_OK);
  TL_TEST_ASSERT(run_child(child_killed_in_folder) == SIGKILL, "the writer was not killed");
  TL_TEST_ASSERT(count_in("stale_dir", ".table.csv.") == 1, "the killed write left %d temporaries, expected 1",
                 count_in("stale_dir", ".table.csv."));
  /* a temporary of this live process, of a live parent, and names that only look alike */
  char own[256], parent[256];
  snprintf(own, sizeof own, "stale_dir/.table.csv.%ld.7.tmp", (long)getpid());
  snprintf(parent, sizeof parent, "stale_dir/.table.csv.%ld.3.tmp", (long)getppid());
  const char *kept[] = {own, parent, "stale_dir/.notes.tmp", "stale_dir/table.1.2.tmp", "stale_dir/.x.12.tmp.bak",
                        "stale_dir/.a.b.tmp"};
  for (size_t k = 0; k < sizeof kept / sizeof kept[0]; ++k) touch(kept[k]);
  TL_TEST_STATUS(tl_output_dir_prepare("stale_dir"), TL_OK);
  TL_TEST_ASSERT(count_in("stale_dir", ".table.csv.") == 2, "%d temporaries of table.csv left, expected the 2 of live processes",
                 count_in("stale_dir", ".table.csv."));
  for (size_t k = 0; k < sizeof kept / sizeof kept[0]; ++k) TL_TEST_ASSERT(exists(kept[k]), "'%s' was removed", kept[k]);
  TL_TEST_ASSERT(file_is("stale_dir/table.csv", old.text, 2000), "the complete file was touched");
  size_t removed = 99;
  TL_TEST_STATUS(tl_atomic_remove_stale("stale_dir", &removed), TL_OK);
  TL_TEST_ASSERT(removed == 0, "a second pass removed %zu files", removed);
  TL_TEST_STATUS(tl_atomic_remove_stale("no_such_folder_here", &removed), TL_OK);
  TL_TEST_STATUS(tl_output_dir_prepare(""), TL_ERR_ARG);
  for (size_t k = 0; k < sizeof kept / sizeof kept[0]; ++k) unlink(kept[k]);
}

/* A restart into another folder: the particle series restored from a
 * checkpoint is written whole there (the earlier snapshots copied from the
 * checkpoint's folder), or refused by the missing file's name. */
static int same_bytes(const char *a, const char *b)
{
  FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
  int same = fa && fb;
  while (same) {
    int ca = fgetc(fa), cb = fgetc(fb);
    same = ca == cb;
    if (ca == EOF) break;
  }
  if (fa) fclose(fa);
  if (fb) fclose(fb);
  return same;
}

static TlStatus save_series(const char *dir, const char *cp_path, int steps)
{
  TlVec3 x[2] = {{0, 0, 0}, {1, 0, 0}};
  double r[2] = {0.5, 0.25};
  TlParticleView v = {.n = 2, .position = x, .radius = r};
  TlParticleWriter *w = NULL;
  TlCheckpoint *cp = NULL;
  TlStatus s = tl_particle_writer_create(dir, "grains", &w);
  for (int k = 0; s == TL_OK && k < steps; ++k) s = tl_particle_writer_write(w, k, 0.1 * k, &v);
  if (s == TL_OK) s = tl_checkpoint_create(&cp);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "snapshots", &tl_particle_writer_checkpoint_ops, w);
  if (s == TL_OK) s = tl_checkpoint_save(cp, cp_path, 0.1 * steps, steps);
  tl_checkpoint_destroy(&cp);
  tl_particle_writer_destroy(&w);
  return s;
}

static TlStatus restart_series(const char *dir, const char *cp_path)
{
  TlVec3 x[2] = {{0, 0, 0}, {1, 0, 0}};
  double r[2] = {0.5, 0.25};
  TlParticleView v = {.n = 2, .position = x, .radius = r};
  TlParticleWriter *w = NULL;
  TlCheckpoint *cp = NULL;
  TlStatus s = tl_particle_writer_create(dir, "grains", &w);
  if (s == TL_OK) s = tl_checkpoint_create(&cp);
  if (s == TL_OK) s = tl_checkpoint_add(cp, "snapshots", &tl_particle_writer_checkpoint_ops, w);
  if (s == TL_OK) s = tl_checkpoint_load(cp, cp_path, NULL, NULL);
  if (s == TL_OK) s = tl_particle_writer_write(w, 2, 0.2, &v);
  tl_checkpoint_destroy(&cp);
  tl_particle_writer_destroy(&w);
  return s;
}

static int text_has(const char *path, const char *needle)
{
  static char buf[1 << 16];
  FILE *f = fopen(path, "rb");
  if (!f) return 0;
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  fclose(f);
  buf[n] = '\0';
  return strstr(buf, needle) != NULL;
}

static void remove_folder_files(const char *dir)
{
  DIR *d = opendir(dir);
  if (!d) return;
  for (struct dirent *e; (e = readdir(d));) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    if (e->d_name[0] != '.' || strlen(e->d_name) > 2) unlink(path);
  }
  closedir(d);
}

static void test_restart_new_folder(void)
{
  const char *folders[] = {"runA", "runB", "runC", "runD", "moved"};
  for (int k = 0; k < 5; ++k) remove_folder_files(folders[k]); /* a rerun starts clean */
  /* a file of the same name from another run in the new folder is replaced */
  TL_TEST_STATUS(tl_mkdir_p("runB"), TL_OK);
  touch("runB/grains_000001.h5");
  TL_TEST_STATUS(save_series("runA", "runA/checkpoint.h5", 2), TL_OK);
  TL_TEST_STATUS(restart_series("runB", "runA/checkpoint.h5"), TL_OK);
  const char *files[] = {"grains_000000.h5", "grains_000001.h5"};
  for (int k = 0; k < 2; ++k) {
    char a[256], b[256];
    snprintf(a, sizeof a, "runA/%s", files[k]);
    snprintf(b, sizeof b, "runB/%s", files[k]);
    TL_TEST_ASSERT(same_bytes(a, b), "%s is not in the new folder as written", b);
  }
  TL_TEST_ASSERT(exists("runB/grains_000002.h5"), "the restarted run's snapshot is missing");
  TL_TEST_ASSERT(text_has("runB/grains.xmf", "grains_000000.h5:") && text_has("runB/grains.xmf", "grains_000002.h5:"),
                 "the new series does not list every step");
  /* the checkpoint moved away from the snapshots: refused by name */
  TL_TEST_STATUS(tl_mkdir_p("moved"), TL_OK);
  TL_TEST_ASSERT(rename("runA/checkpoint.h5", "moved/checkpoint.h5") == 0, "cannot move the checkpoint");
  TL_TEST_STATUS(restart_series("runC", "moved/checkpoint.h5"), TL_ERR_IO);
  TL_TEST_ASSERT(strstr(tl_error_message(), "grains_000000.h5") != NULL, "the refusal does not name the snapshot: %s",
                 tl_error_message());
  /* restarting in the same folder needs no copy */
  TL_TEST_STATUS(save_series("runD", "runD/checkpoint.h5", 2), TL_OK);
  TL_TEST_STATUS(restart_series("runD", "runD/checkpoint.h5"), TL_OK);
}

int main(void)
{
  test_output_dir();
  test_text();
  test_checkpoint();
  test_stale_temporaries();
  test_restart_new_folder();
  return tl_test_report();
}
