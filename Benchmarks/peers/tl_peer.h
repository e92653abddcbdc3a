/* Running a peer code from a benchmark program, in the same invocation as the
 * Talus run, through run_peer.sh (see README.md next to this file).
 *
 *   #include "peers/tl_peer.h"            (from a program in Benchmarks/)
 *
 *   char data[4096], stl[4096];
 *   TL_CHECK(tl_peer_prepare("hertz_lammps_classic", data, sizeof data, stl, sizeof stl));
 *   ... read `data` with tl_lammps_data_read, run Talus on it ...
 *   TlPeerResult peer;
 *   TL_CHECK(tl_peer_run("hertz_lammps_classic", 1, 0, 3, &peer));
 *   ratio = peer.us_median / talus_us_median;
 *
 * The script is found as $TALUS_PEER_SCRIPT, else next to this header (the
 * source tree the benchmark was built from).  Header-only so that the library
 * carries no benchmark code; every function is static. */
#ifndef TL_PEER_H
#define TL_PEER_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "tl_error.h"

typedef struct {
  char scene[64];
  char code[16];     /* "lammps" or "liggghts" */
  int ranks;
  long particles;    /* atoms in the timed run */
  long steps;        /* timed steps */
  double loop_time;  /* peer's own Loop time of the fastest repeat, s */
  double us_min;     /* microseconds per particle-step, fastest repeat */
  double us_median;  /* microseconds per particle-step, median over repeats */
  double ke, erot;   /* the deck's last thermo line (translational, rotational
                        kinetic energy; 8 digits), NAN when it prints none */
} TlPeerResult;

/* The path of run_peer.sh. */
static inline void tl_peer_script(char *path, size_t cap)
{
  const char *env = getenv("TALUS_PEER_SCRIPT");
  if (env && *env) {
    snprintf(path, cap, "%s", env);
    return;
  }
  snprintf(path, cap, "%s", __FILE__);
  char *slash = strrchr(path, '/');
  if (slash) snprintf(slash + 1, cap - (size_t)(slash + 1 - path), "run_peer.sh");
  else snprintf(path, cap, "run_peer.sh");
}

/* Runs `command`, passes the lines that do not start with `key` through to
 * stdout, and keeps the last line that starts with `key` in `out`. */
static inline TlStatus tl_peer_command(const char *command, const char *key, char *out, size_t cap)
{
  out[0] = '\0';
  fflush(stdout);
  FILE *pipe = popen(command, "r");
  if (!pipe) TL_ERROR(TL_ERR_IO, "cannot start the peer script: %s", command);
  char line[2048];
  size_t klen = strlen(key);
  while (fgets(line, sizeof line, pipe)) {
    if (!strncmp(line, key, klen)) {
      snprintf(out, cap, "%s", line);
      out[strcspn(out, "\n")] = '\0';
    } else {
      fputs(line, stdout);
    }
  }
  int status = pclose(pipe);
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    TL_ERROR(TL_ERR_IO, "peer script failed (exit status %d; its message is on stderr): %s",
             WIFEXITED(status) ? WEXITSTATUS(status) : -1, command);
  if (!out[0]) TL_ERROR(TL_ERR_FORMAT, "peer script printed no \"%s\" line: %s", key, command);
  return TL_OK;
}

/* The value of `key=` in a line of key=value words, copied into val. */
static inline int tl_peer_field(const char *line, const char *key, char *val, size_t cap)
{
  size_t klen = strlen(key);
  for (const char *p = line; (p = strstr(p, key)) != NULL; p += klen) {
    if ((p == line || p[-1] == ' ') && p[klen] == '=') {
      const char *v = p + klen + 1;
      size_t n = strcspn(v, " \t\n");
      if (n >= cap) n = cap - 1;
      memcpy(val, v, n);
      val[n] = '\0';
      return 1;
    }
  }
  return 0;
}

/* Runs `scene` on `ranks` MPI ranks for `steps` timed steps (0: the scene's
 * default) `repeat` times, and parses the script's last line. */
static inline TlStatus tl_peer_run(const char *scene, int ranks, long steps, int repeat, TlPeerResult *r)
{
  if (ranks < 1 || repeat < 1 || steps < 0)
    TL_ERROR(TL_ERR_ARG, "tl_peer_run: ranks %d and repeat %d must be >= 1, steps %ld >= 0", ranks, repeat, steps);
  char script[4096], command[8192], line[2048];
  tl_peer_script(script, sizeof script);
  if (steps > 0)
    snprintf(command, sizeof command, "'%s' '%s' --ranks %d --steps %ld --repeat %d", script, scene, ranks, steps,
             repeat);
  else
    snprintf(command, sizeof command, "'%s' '%s' --ranks %d --repeat %d", script, scene, ranks, repeat);
  TL_CHECK(tl_peer_command(command, "peer:", line, sizeof line));
  memset(r, 0, sizeof *r);
  char v[256];
  int ok = tl_peer_field(line, "scene", r->scene, sizeof r->scene) &&
           tl_peer_field(line, "code", r->code, sizeof r->code);
  ok = ok && tl_peer_field(line, "ranks", v, sizeof v) && sscanf(v, "%d", &r->ranks) == 1;
  ok = ok && tl_peer_field(line, "particles", v, sizeof v) && sscanf(v, "%ld", &r->particles) == 1;
  ok = ok && tl_peer_field(line, "steps", v, sizeof v) && sscanf(v, "%ld", &r->steps) == 1;
  ok = ok && tl_peer_field(line, "loop_time", v, sizeof v) && sscanf(v, "%lf", &r->loop_time) == 1;
  ok = ok && tl_peer_field(line, "us_per_particle_step", v, sizeof v) && sscanf(v, "%lf", &r->us_min) == 1;
  ok = ok && tl_peer_field(line, "median", v, sizeof v) && sscanf(v, "%lf", &r->us_median) == 1;
  r->ke = r->erot = NAN;
  if (tl_peer_field(line, "ke", v, sizeof v)) sscanf(v, "%lf", &r->ke);
  if (tl_peer_field(line, "erot", v, sizeof v)) sscanf(v, "%lf", &r->erot);
  if (!ok || r->particles <= 0 || !(r->us_min > 0.0))
    TL_ERROR(TL_ERR_FORMAT, "cannot parse the peer line \"%s\"", line);
  return TL_OK;
}

/* Prepares `scene` (settling runs, STL files; cached) and returns the data
 * file the peer starts from and, for mesh scenes, the STL floor ("" if none). */
static inline TlStatus tl_peer_prepare(const char *scene, char *data, size_t data_cap, char *stl, size_t stl_cap)
{
  char script[4096], command[8192], line[2048];
  tl_peer_script(script, sizeof script);
  snprintf(command, sizeof command, "'%s' '%s' --prepare", script, scene);
  TL_CHECK(tl_peer_command(command, "peer-data:", line, sizeof line));
  if (!tl_peer_field(line, "data", data, data_cap))
    TL_ERROR(TL_ERR_FORMAT, "cannot parse the peer line \"%s\"", line);
  if (stl && stl_cap > 0 && !tl_peer_field(line, "stl", stl, stl_cap)) stl[0] = '\0';
  return TL_OK;
}

#endif
