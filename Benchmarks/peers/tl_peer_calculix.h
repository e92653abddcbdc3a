/* Running CalculiX (Debian calculix-ccx) on the S1 cantilever of a Talus
 * program, on Talus's own mesh and loads (see README.md next to this file):
 *
 *   #include "peers/tl_peer_calculix.h"
 *
 *   TL_CHECK(tl_ccx_ensure());                        installs ccx as root
 *   TL_CHECK(tl_ccx_write_model(dir, beam));          model.inp, tip_load.inp
 *   TL_CHECK(tl_ccx_write_line(dir, "modes.inp", "6"));
 *   TL_CHECK(tl_ccx_run(dir, "cantilever_modal", &seconds));
 *   TL_CHECK(tl_ccx_read_eigenvalues(dir, "cantilever_modal", 6, omega2));
 *
 * The decks are checked in (calculix/<name>.inp next to this header;
 * tl_ccx_deck_path says where they are looked for) and *INCLUDE what Talus writes: the nodes and the
 * Hex8 elements as C3D8 (full 2 x 2 x 2 Gauss integration of stiffness and
 * mass, Talus's hex8 rule, order_stiffness = order_mass = 2; the node order
 * of Gmsh's hexahedron is Abaqus's), the clamped face, the material (E, nu,
 * density: *ELASTIC, which CalculiX reads as Saint Venant-Kirchhoff under
 * NLGEOM) and the tip load as Talus's consistent nodal forces.  CalculiX
 * has no 27-node brick: a Hex27 beam is refused.
 *
 * Digits: CalculiX prints displacements in its .dat file with 7 significant
 * digits (%13.6E), a rounding of at most 5e-7 relative per value (and of
 * their weighted mean of one sign); eigenvalues come from the binary .eig
 * file at full precision.  Header-only, every function static, so that the
 * library carries no benchmark code. */
#ifndef TL_PEER_CALCULIX_H
#define TL_PEER_CALCULIX_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "talus.h"
#include "tl_atomic_file.h"
#include "tl_cantilever.h"

/* Whether ccx runs; as root, installs calculix-ccx when it is missing.
 * TL_ERR_UNSUPPORTED (with the command to run) when it cannot. */
static inline TlStatus tl_ccx_ensure(void)
{
  if (system("command -v ccx > /dev/null 2>&1") == 0) return TL_OK;
  if (geteuid() != 0)
    TL_ERROR(TL_ERR_UNSUPPORTED, "CalculiX (ccx) is not installed; as root: apt-get install -y calculix-ccx");
  printf("installing calculix-ccx (apt-get install -y calculix-ccx) ...\n");
  fflush(stdout);
  if (system("DEBIAN_FRONTEND=noninteractive apt-get install -y calculix-ccx > /dev/null 2>&1") != 0 &&
      system("apt-get update > /dev/null 2>&1 && DEBIAN_FRONTEND=noninteractive apt-get install -y calculix-ccx "
             "> /dev/null 2>&1") != 0)
    TL_ERROR(TL_ERR_UNSUPPORTED, "apt-get install -y calculix-ccx failed");
  if (system("command -v ccx > /dev/null 2>&1") != 0)
    TL_ERROR(TL_ERR_UNSUPPORTED, "ccx still missing after installing calculix-ccx");
  return TL_OK;
}

/* The path of the checked-in deck `name` (without .inp): in
 * $TALUS_CALCULIX_DECKS, else in TL_CALCULIX_DECKS_DIR (the build defines
 * it: __FILE__ may be relative to the compiler's folder, as under ccache
 * with a base directory), else next to this header. */
static inline void tl_ccx_deck_path(const char *name, char *path, size_t cap)
{
  const char *env = getenv("TALUS_CALCULIX_DECKS");
  if (env && *env) {
    snprintf(path, cap, "%s/%s.inp", env, name);
    return;
  }
#ifdef TL_CALCULIX_DECKS_DIR
  snprintf(path, cap, "%s/%s.inp", TL_CALCULIX_DECKS_DIR, name);
  return;
#endif
  snprintf(path, cap, "%s", __FILE__);
  char *slash = strrchr(path, '/');
  if (slash) snprintf(slash + 1, cap - (size_t)(slash + 1 - path), "calculix/%s.inp", name);
  else snprintf(path, cap, "calculix/%s.inp", name);
}

typedef struct {
  const TlCantilever *beam;
} TlCcxModel;

static TlStatus tl_ccx_model_write(FILE *f, void *ctx)
{
  const TlCantilever *beam = ((const TlCcxModel *)ctx)->beam;
  const TlMesh *m = beam->mesh;
  const TlCantileverParams *p = &beam->p;
  const TlElementBlock *b = &m->blocks[0];
  fprintf(f, "** Written by Talus: the S1 cantilever's mesh (%zu nodes, %zu Hex8 = C3D8), clamp and material\n",
          m->n_nodes, b->n_elements);
  fprintf(f, "*NODE, NSET=NALL\n");
  for (size_t i = 0; i < m->n_nodes; ++i)
    fprintf(f, "%zu, %.17g, %.17g, %.17g\n", i + 1, m->x[3 * i], m->x[3 * i + 1], m->x[3 * i + 2]);
  fprintf(f, "*ELEMENT, TYPE=C3D8, ELSET=EALL\n");
  for (size_t e = 0; e < b->n_elements; ++e) {
    fprintf(f, "%zu", e + 1);
    for (int a = 0; a < 8; ++a) fprintf(f, ", %zu", b->conn[8 * e + a] + 1);
    fprintf(f, "\n");
  }
  const TlNodeSet *fix = NULL;
  TL_CHECK(tl_mesh_find_node_set(m, "ymin", &fix));
  fprintf(f, "*NSET, NSET=FIX\n");
  for (size_t k = 0; k < fix->n; ++k) fprintf(f, "%zu,\n", fix->nodes[k] + 1);
  fprintf(f, "*NSET, NSET=TIP\n");
  for (size_t k = 0; k < beam->n_tip; ++k) fprintf(f, "%zu,\n", beam->tip_nodes[k] + 1);
  fprintf(f, "*BOUNDARY\nFIX, 1, 3\n*MATERIAL, NAME=BEAM\n*ELASTIC\n%.17g, %.17g\n*DENSITY\n%.17g\n", p->E, p->nu,
          p->rho);
  fprintf(f, "*SOLID SECTION, ELSET=EALL, MATERIAL=BEAM\n");
  return TL_OK;
}

static TlStatus tl_ccx_load_write(FILE *f, void *ctx)
{
  const TlCantilever *beam = ((const TlCcxModel *)ctx)->beam;
  for (size_t k = 0; k < beam->n_tip; ++k)
    fprintf(f, "%zu, 3, %.17g\n", beam->tip_nodes[k] + 1, -beam->p.load * beam->tip_weight[k]);
  return TL_OK;
}

/* <dir>/model.inp and <dir>/tip_load.inp from the beam (Hex8 only). */
static inline TlStatus tl_ccx_write_model(const char *dir, const TlCantilever *beam)
{
  if (beam->mesh->n_blocks != 1 || beam->mesh->blocks[0].type != &tl_element_hex8)
    TL_ERROR(TL_ERR_UNSUPPORTED, "CalculiX comparison: the beam must be one block of hex8 (C3D8), not %s",
             beam->mesh->blocks[0].type->header.name);
  TlCcxModel ctx = {beam};
  char *path = NULL;
  TL_CHECK(tl_mkdir_p(dir));
  TL_CHECK(tl_path_join(dir, "model.inp", &path));
  TlStatus s = tl_atomic_write(path, tl_ccx_model_write, &ctx);
  tl_free(&path);
  TL_CHECK(s);
  TL_CHECK(tl_path_join(dir, "tip_load.inp", &path));
  s = tl_atomic_write(path, tl_ccx_load_write, &ctx);
  tl_free(&path);
  return s;
}

static TlStatus tl_ccx_line_write(FILE *f, void *ctx)
{
  fprintf(f, "%s\n", (const char *)ctx);
  return TL_OK;
}

/* <dir>/<name>: one data line for a deck's *INCLUDE. */
static inline TlStatus tl_ccx_write_line(const char *dir, const char *name, const char *line)
{
  char *path = NULL;
  TL_CHECK(tl_path_join(dir, name, &path));
  TlStatus s = tl_atomic_write(path, tl_ccx_line_write, (void *)line);
  tl_free(&path);
  return s;
}

/* The amplitude of the dynamic deck's load at time t: a linear ramp from 0
 * at t = 0 to 1 at t_ramp, then 1 (t_ramp = 0: 1 from t = 0, a sudden
 * load).  The Talus side sets its load factor to this value at the end of
 * each step, where Newmark's equilibrium holds, as CalculiX interpolates
 * its amplitude there. */
static inline double tl_ccx_amplitude(double t, double t_ramp)
{
  return t_ramp > 0.0 && t < t_ramp ? t / t_ramp : 1.0;
}

/* <dir>/amplitude.inp: the *AMPLITUDE data of tl_ccx_amplitude. */
static inline TlStatus tl_ccx_write_amplitude(const char *dir, double t_ramp)
{
  char line[128];
  if (t_ramp > 0.0) snprintf(line, sizeof line, "0., 0., %.17g, 1., 1e30, 1.", t_ramp);
  else snprintf(line, sizeof line, "0., 1., 1e30, 1.");
  return tl_ccx_write_line(dir, "amplitude.inp", line);
}

/* Copies the deck into dir and runs `ccx -i <deck>` there on one thread.
 * *seconds: CalculiX's own "Total CalculiX Time" (the process's wall time
 * when it prints none). */
static inline TlStatus tl_ccx_run(const char *dir, const char *deck, double *seconds)
{
  char src[4096], cmd[16384];
  tl_ccx_deck_path(deck, src, sizeof src);
  if (access(src, R_OK) != 0) TL_ERROR(TL_ERR_IO, "CalculiX deck %s not found (set TALUS_CALCULIX_DECKS)", src);
  snprintf(cmd, sizeof cmd,
           "cp '%s' '%s/%s.inp' && cd '%s' && rm -f '%s.dat' '%s.eig' && OMP_NUM_THREADS=1 "
           "CCX_NPROC_EQUATION_SOLVER=1 CCX_NPROC_STIFFNESS=1 CCX_NPROC_RESULTS=1 ccx -i '%s' > '%s.log' 2>&1",
           src, dir, deck, dir, deck, deck, deck, deck);
  fflush(stdout);
  double t0 = tl_wtime();
  int rc = system(cmd);
  double wall = tl_wtime() - t0;
  if (rc != 0) TL_ERROR(TL_ERR_IO, "ccx failed (exit %d) on %s/%s.inp; see %s/%s.log", rc, dir, deck, dir, deck);
  /* ccx may exit 0 after an *ERROR: the log says. */
  char log[4096], line[1024];
  snprintf(log, sizeof log, "%s/%s.log", dir, deck);
  FILE *f = fopen(log, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "ccx wrote no log %s", log);
  *seconds = wall;
  int error = 0;
  while (fgets(line, sizeof line, f)) {
    if (strstr(line, "*ERROR")) error = 1;
    const char *t = strstr(line, "Total CalculiX Time:");
    if (t) *seconds = atof(t + strlen("Total CalculiX Time:"));
  }
  fclose(f);
  if (error) TL_ERROR(TL_ERR_IO, "ccx reported an error on %s/%s.inp; see %s", dir, deck, log);
  return TL_OK;
}

/* The last "displacements ... for set TIP" block of <dir>/<job>.dat,
 * weighted like tl_cantilever_tip(); *time: that block's time. */
static inline TlStatus tl_ccx_read_tip(const char *dir, const char *job, const TlCantilever *beam, double out[3],
                                       double *time)
{
  char path[4096], line[512];
  snprintf(path, sizeof path, "%s/%s.dat", dir, job);
  FILE *f = fopen(path, "r");
  if (!f) TL_ERROR(TL_ERR_IO, "CalculiX wrote no %s", path);
  int in_block = 0, blocks = 0;
  size_t seen = 0, last_seen = 0;
  double acc[3] = {0, 0, 0};
  *time = NAN;
  while (fgets(line, sizeof line, f)) {
    if (strstr(line, "displacements") && strstr(line, "TIP")) {
      const char *t = strstr(line, "time");
      *time = t ? atof(t + 4) : NAN;
      in_block = 1;
      acc[0] = acc[1] = acc[2] = 0.0;
      seen = 0;
      ++blocks;
      continue;
    }
    if (!in_block) continue;
    long node;
    double u[3];
    if (sscanf(line, "%ld %lf %lf %lf", &node, &u[0], &u[1], &u[2]) == 4) {
      for (size_t k = 0; k < beam->n_tip; ++k)
        if (beam->tip_nodes[k] + 1 == (size_t)node) {
          for (int d = 0; d < 3; ++d) acc[d] += beam->tip_weight[k] * u[d];
          ++seen;
        }
      memcpy(out, acc, sizeof acc);
      last_seen = seen;
    } else if (line[0] != '\n' && line[0] != '\r') {
      in_block = 0;
    }
  }
  fclose(f);
  if (!blocks) TL_ERROR(TL_ERR_FORMAT, "no tip displacements in %s", path);
  if (last_seen != beam->n_tip)
    TL_ERROR(TL_ERR_FORMAT, "%s: the last TIP block lists %zu of the %zu tip nodes", path, last_seen, beam->n_tip);
  return TL_OK;
}

/* The eigenvalues omega^2 of <dir>/<job>.eig (*FREQUENCY, STORAGE=YES), as
 * CalculiX 2.20's arpack.c writes it with 4-byte integers: a cyclic-
 * symmetry flag (0), a Hermitian flag (1), a perturbation flag (0: the
 * frequencies of the unloaded reference state, no displacement record),
 * the number of eigenvalues, then the eigenvalues as doubles (the layout of
 * older versions, without the perturbation flag, is accepted too).  n of
 * them are wanted. */
static inline TlStatus tl_ccx_read_eigenvalues(const char *dir, const char *job, int n, double *omega2)
{
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.eig", dir, job);
  FILE *f = fopen(path, "rb");
  if (!f) TL_ERROR(TL_ERR_IO, "CalculiX wrote no %s (*FREQUENCY, STORAGE=YES)", path);
  int32_t h[4] = {-1, -1, -1, -1};
  size_t got = fread(h, sizeof h[0], 4, f);
  long nev = -1, offset = 0;
  if (got == 4 && h[0] == 0 && h[1] == 1 && h[2] == 0 && h[3] > 0) nev = h[3], offset = 16;
  else if (got >= 3 && h[0] == 0 && h[1] == 1 && h[2] > 0) nev = h[2], offset = 12;
  if (nev < 0) {
    fclose(f);
    TL_ERROR(TL_ERR_FORMAT,
             "%s: header %d %d %d %d is not (cyclic symmetry 0, Hermitian 1, [perturbation 0,] count) in 4-byte "
             "integers",
             path, (int)h[0], (int)h[1], (int)h[2], (int)h[3]);
  }
  if (nev < n) {
    fclose(f);
    TL_ERROR(TL_ERR_FORMAT, "%s holds %ld eigenvalues, %d wanted", path, nev, n);
  }
  int ok = fseek(f, offset, SEEK_SET) == 0 && fread(omega2, sizeof(double), (size_t)n, f) == (size_t)n;
  fclose(f);
  if (!ok) TL_ERROR(TL_ERR_FORMAT, "%s: short eigenvalue record", path);
  for (int k = 0; k < n; ++k)
    if (!(omega2[k] > 0.0) || !isfinite(omega2[k]))
      TL_ERROR(TL_ERR_FORMAT, "%s: eigenvalue %d = %g is not a positive number", path, k + 1, omega2[k]);
  return TL_OK;
}

#endif
