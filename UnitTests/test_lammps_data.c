/* The LAMMPS data reader: on the peers' chute data file (every atom compared
 * with the file text parsed here independently), on files written here in
 * the layouts of LAMMPS's and LIGGGHTS's write_data, and on malformed files,
 * each of which must give an error that names the offending line. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tl_error.h"
#include "tl_lammps_data.h"
#include "tl_memory.h"
#include "tl_test.h"

static void write_text(const char *path, const char *text)
{
  FILE *f = fopen(path, "w");
  if (!f) {
    perror(path);
    exit(2);
  }
  fputs(text, f);
  fclose(f);
}

/* The peers' folder: $TALUS_PEERS_DIR, else ../shared/peers next to the
 * repository holding this source file. */
static int find_chute(char *path, size_t cap)
{
  const char *env = getenv("TALUS_PEERS_DIR");
  if (env && *env) {
    snprintf(path, cap, "%s/chute/data.chute", env);
  } else {
    char root[4096];
    snprintf(root, sizeof root, "%s", __FILE__);
    for (int up = 0; up < 2; ++up) {
      char *slash = strrchr(root, '/');
      if (!slash) return 0;
      *slash = '\0';
    }
    snprintf(path, cap, "%s/../shared/peers/chute/data.chute", root);
  }
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  fclose(f);
  return 1;
}

/* Reads data.chute with plain sscanf, line by line, and compares with the
 * reader's arrays: every atom, every velocity. */
static void test_chute(const char *path)
{
  TlLammpsData *d = NULL;
  TL_TEST_STATUS(tl_lammps_data_read(path, &d), TL_OK);
  if (!d) return;
  TL_TEST_ASSERT(d->n == 32000, "n = %zu", d->n);
  TL_TEST_ASSERT(d->n_types == 2, "n_types = %d", d->n_types);
  TL_TEST_CLOSE(d->lo[0], 0.0, 0.0);
  TL_TEST_CLOSE(d->hi[0], 40.0, 0.0);
  TL_TEST_CLOSE(d->hi[1], 20.0, 0.0);
  TL_TEST_CLOSE(d->hi[2], 37.2886, 0.0);
  TL_TEST_ASSERT(!d->triclinic, "triclinic");
  TL_TEST_ASSERT(d->has_images && d->has_velocities, "images %d velocities %d", d->has_images, d->has_velocities);
  TL_TEST_ASSERT(strstr(d->title, "LAMMPS data file") == d->title, "title \"%s\"", d->title);

  FILE *f = fopen(path, "r");
  char line[512];
  size_t n_atoms = 0, n_vel = 0, n_base = 0, mismatches = 0;
  int section = 0; /* 0 header, 1 atoms, 2 velocities */
  double maxv = 0.0;
  while (f && fgets(line, sizeof line, f)) {
    if (!strncmp(line, "Atoms", 5)) section = 1;
    if (!strncmp(line, "Velocities", 10)) section = 2;
    long long id;
    int type, ix, iy, iz;
    double dia, rho, x, y, z, v[6];
    if (section == 1 && sscanf(line, "%lld %d %lf %lf %lf %lf %lf %d %d %d", &id, &type, &dia, &rho, &x, &y, &z,
                               &ix, &iy, &iz) == 10) {
      size_t i = n_atoms++;
      n_base += type == 2;
      if (i >= d->n || d->id[i] != id || d->type[i] != type || d->diameter[i] != dia || d->density[i] != rho ||
          d->x[i].x != x || d->x[i].y != y || d->x[i].z != z || d->image[3 * i] != ix ||
          d->image[3 * i + 1] != iy || d->image[3 * i + 2] != iz)
        ++mismatches;
    }
    if (section == 2 && sscanf(line, "%lld %lf %lf %lf %lf %lf %lf", &id, &v[0], &v[1], &v[2], &v[3], &v[4],
                               &v[5]) == 7) {
      ++n_vel;
      /* data.chute lists velocities in id order with ids 1..N, and atoms too */
      size_t i = (size_t)(id - 1);
      if (i >= d->n || d->id[i] != id || d->v[i].x != v[0] || d->v[i].y != v[1] || d->v[i].z != v[2] ||
          d->omega[i].x != v[3] || d->omega[i].y != v[4] || d->omega[i].z != v[5])
        ++mismatches;
      if (v[0] > maxv) maxv = v[0];
    }
  }
  if (f) fclose(f);
  TL_TEST_ASSERT(n_atoms == 32000 && n_vel == 32000, "independent parse found %zu atoms, %zu velocities", n_atoms,
                 n_vel);
  TL_TEST_ASSERT(mismatches == 0, "%zu atoms differ from the file text", mismatches);
  TL_TEST_ASSERT(tl_lammps_data_count_type(d, 2) == n_base && n_base == 912, "base atoms %zu (file %zu)",
                 tl_lammps_data_count_type(d, 2), n_base);
  TL_TEST_ASSERT(maxv > 1.0, "the flowing layer moves: max vx %g", maxv);

  /* atom 1: "1 1 1 1 19.4061 6.46569 14.5438 33 0 0", flowing along x */
  TL_TEST_CLOSE(tl_lammps_data_mass(d, 0), 3.14159265358979323846 / 6.0, 1e-15);
  TlVec3 u = tl_lammps_data_unwrapped(d, 0);
  TL_TEST_CLOSE(u.x, 19.4061 + 33 * 40.0, 1e-14);
  TL_TEST_CLOSE(u.y, 6.46569, 0.0);
  /* every atom inside the box in x and y (periodic, wrapped) */
  size_t outside = 0;
  for (size_t i = 0; i < d->n; ++i)
    outside += d->x[i].x < d->lo[0] || d->x[i].x > d->hi[0] || d->x[i].y < d->lo[1] || d->x[i].y > d->hi[1];
  TL_TEST_ASSERT(outside == 0, "%zu atoms outside the periodic box", outside);
  tl_lammps_data_destroy(&d);
  TL_TEST_ASSERT(d == NULL, "destroy nulls the pointer");
}

/* The layout of LAMMPS's write_data for atom_style sphere: section comments,
 * a Masses-free file with image flags, velocities in another order than the
 * atoms, a tilted box. */
static void test_write_data_layout(void)
{
  write_text("sphere.data",
             "LAMMPS data file via write_data, version 29 Sep 2021, timestep = 40000\n"
             "\n"
             "3 atoms\n"
             "2 atom types\n"
             "\n"
             "0 25 xlo xhi\n"
             "0 2.5e1 ylo yhi\n"
             "-1.5 40 zlo zhi  # comment\n"
             "0.5 0 0 xy xz yz\n"
             "\n"
             "Atoms # sphere\n"
             "\n"
             "7 1 0.95 1 1.25 2.5 3.75 0 0 0\n"
             "3 2 1.1 2.0 -1e-3 +4 5E0 -1 2 0\n"
             "\n"
             "12 1 0.8 1 24.9 24.9 0.4 0 0 1\n"
             "\n"
             "Velocities\n"
             "\n"
             "12 0.1 0.2 0.3 0.4 0.5 0.6\n"
             "7 1 2 3 4 5 2.02e-320\n"
             "3 -1 -2 -3 -4 -5 -6\n");
  TlLammpsData *d = NULL;
  TL_TEST_STATUS(tl_lammps_data_read("sphere.data", &d), TL_OK);
  if (!d) return;
  TL_TEST_ASSERT(d->n == 3 && d->n_types == 2, "n %zu types %d", d->n, d->n_types);
  TL_TEST_CLOSE(d->lo[2], -1.5, 0.0);
  TL_TEST_CLOSE(d->hi[1], 25.0, 0.0);
  TL_TEST_ASSERT(d->triclinic && d->tilt[0] == 0.5, "tilt %g", d->tilt[0]);
  TL_TEST_ASSERT(d->id[0] == 7 && d->id[1] == 3 && d->id[2] == 12, "ids keep file order");
  TL_TEST_CLOSE(d->x[1].x, -1e-3, 0.0);
  TL_TEST_CLOSE(d->x[1].z, 5.0, 0.0);
  TL_TEST_CLOSE(d->density[1], 2.0, 0.0);
  TL_TEST_CLOSE(tl_lammps_data_mass(d, 1), 2.0 * 3.14159265358979323846 / 6.0 * 1.1 * 1.1 * 1.1, 1e-15);
  /* velocities matched by id, not by line order */
  TL_TEST_CLOSE(d->v[2].z, 0.3, 0.0);
  TL_TEST_CLOSE(d->omega[0].y, 5.0, 0.0);
  /* a subnormal, as LAMMPS's write_data prints them, read exactly */
  TL_TEST_ASSERT(d->omega[0].z == 2.02e-320, "subnormal read as %g", d->omega[0].z);
  TL_TEST_CLOSE(d->omega[1].x, -4.0, 0.0);
  /* unwrapping with a tilt: x + ix Lx + iy xy, y + iy Ly */
  TlVec3 u = tl_lammps_data_unwrapped(d, 1);
  TL_TEST_CLOSE(u.x, -1e-3 - 25.0 + 2 * 0.5, 1e-15);
  TL_TEST_CLOSE(u.y, 4.0 + 2 * 25.0, 1e-15);
  u = tl_lammps_data_unwrapped(d, 2);
  TL_TEST_CLOSE(u.z, 0.4 + 41.5, 1e-15);
  tl_lammps_data_destroy(&d);

  /* LIGGGHTS layout: no image flags, no velocities, a Masses-like section skipped */
  write_text("granular.data",
             "LAMMPS data file via write_data, version LIGGGHTS-PUBLIC 3.8.0\n"
             "2 atoms\n1 atom types\n"
             "0 0.1 xlo xhi\n0 0.1 ylo yhi\n-0.002 0.02 zlo zhi\n"
             "Masses\n\n1 1.0\n\n"
             "Atoms # granular\n\n"
             "1 1 2e-3 2500 0.01 0.02 0.001\n"
             "2 1 2e-3 2500 0.03 0.04 0.001\n");
  TL_TEST_STATUS(tl_lammps_data_read("granular.data", &d), TL_OK);
  if (d) {
    TL_TEST_ASSERT(!d->has_images && !d->has_velocities, "images %d velocities %d", d->has_images,
                   d->has_velocities);
    TL_TEST_CLOSE(d->x[1].y, 0.04, 0.0);
    TL_TEST_CLOSE(d->v[1].x, 0.0, 0.0);
    TL_TEST_CLOSE(tl_lammps_data_mass(d, 0), 2500.0 * 3.14159265358979323846 / 6.0 * 8e-9, 1e-15);
  }
  tl_lammps_data_destroy(&d);
  tl_lammps_data_destroy(&d); /* harmless twice */
}

/* One malformed file: expect `status` and a message containing `needle`. */
static void expect_error(const char *text, TlStatus status, const char *needle)
{
  write_text("bad.data", text);
  static TlLammpsData sentinel;
  TlLammpsData *d = &sentinel; /* must be reset to NULL on failure */
  TL_TEST_STATUS(tl_lammps_data_read("bad.data", &d), status);
  TL_TEST_ASSERT(d == NULL, "output pointer not NULL after a failed read");
  TL_TEST_ASSERT(strstr(tl_error_message(), needle) != NULL, "message \"%s\" lacks \"%s\"", tl_error_message(),
                 needle);
  tl_error_clear();
}

#define HEAD "title\n\n2 atoms\n1 atom types\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n\n"

static void test_malformed(void)
{
  TlLammpsData *d = NULL;
  TL_TEST_STATUS(tl_lammps_data_read("no_such_file.data", &d), TL_ERR_IO);
  TL_TEST_ASSERT(strstr(tl_error_message(), "no_such_file.data") != NULL, "message: %s", tl_error_message());
  TL_TEST_STATUS(tl_lammps_data_read(NULL, &d), TL_ERR_ARG);

  expect_error("", TL_ERR_FORMAT, "empty file");
  /* too few columns on line 11 */
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5\n2 1 1 1 0.5 0.5 0.5\n", TL_ERR_FORMAT, "bad.data:11: Atoms line has 6");
  /* a word that is not a number */
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5 0.5\n2 1 1 1 0.5 abc 0.5\n", TL_ERR_FORMAT, "bad.data:12: y \"abc\"");
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5 0.5\n2 1 1 1 0.5 0.5 nan\n", TL_ERR_FORMAT, "z \"nan\"");
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5 0.5\n2 1 1 1 0.5 0.5 1e999\n", TL_ERR_FORMAT, "is not a finite");
  /* type beyond the header's count, non-positive diameter and density */
  expect_error(HEAD "Atoms\n\n1 2 1 1 0.5 0.5 0.5\n2 1 1 1 0.5 0.5 0.5\n", TL_ERR_FORMAT, "bad.data:11: atom type \"2\"");
  expect_error(HEAD "Atoms\n\n1 1 -1 1 0.5 0.5 0.5\n2 1 1 1 0.5 0.5 0.5\n", TL_ERR_FORMAT, "diameter -1 of atom 1");
  expect_error(HEAD "Atoms\n\n1 1 1 0 0.5 0.5 0.5\n2 1 1 1 0.5 0.5 0.5\n", TL_ERR_FORMAT, "density 0 of atom 1");
  expect_error(HEAD "Atoms\n\n1.5 1 1 1 0.5 0.5 0.5\n2 1 1 1 0.5 0.5 0.5\n", TL_ERR_FORMAT, "atom id \"1.5\"");
  /* mixed image flags, duplicate ids */
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5 0.5 0 0 0\n2 1 1 1 0.5 0.5 0.5\n", TL_ERR_FORMAT,
               "bad.data:12: Atoms line has 7 values but the first");
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5 0.5\n1 1 1 1 0.5 0.5 0.5\n", TL_ERR_FORMAT, "atom id 1 appears twice");
  /* truncated file, more lines than the header declares, missing Atoms */
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5 0.5\n", TL_ERR_FORMAT, "after 1 of 2 atoms");
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5 0.5\n2 1 1 1 0.5 0.5 0.5\n3 1 1 1 0.5 0.5 0.5\n", TL_ERR_FORMAT,
               "bad.data:13: 7 values where a section name");
  expect_error(HEAD, TL_ERR_FORMAT, "no Atoms section");
  /* a count the file cannot hold is refused before it sizes an allocation
   * (found by fuzzing: 77777777 atoms asked for 6 GB) */
  expect_error("title\n77777777 atoms\n2 atom types\nAtoms\n\n7 1 1 1 0 0 0\n", TL_ERR_FORMAT,
               "declares 77777777 atoms, but the rest of the file");
  /* header errors */
  expect_error("title\n1 atom types\nAtoms\n\n1 1 1 1 0 0 0\n", TL_ERR_FORMAT, "no \"N atoms\"");
  expect_error("title\n1 atoms\nAtoms\n\n1 1 1 1 0 0 0\n", TL_ERR_FORMAT, "0 atom types");
  expect_error("title\n-3 atoms\n", TL_ERR_FORMAT, "bad.data:2: expected one non-negative integer");
  expect_error("title\n1 atoms\n1 atom types\n1 0 xlo xhi\n", TL_ERR_FORMAT, "bad.data:4: box bounds xlo xhi = 1 0");
  expect_error("title\n1 atoms\n1 atom types\n3 fish\n", TL_ERR_FORMAT, "bad.data:4: unknown header line \"fish\"");
  /* Velocities: wrong count, unknown id, before Atoms */
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5 0.5\n2 1 1 1 0.5 0.5 0.5\n\nVelocities\n\n1 0 0 0 0 0\n",
               TL_ERR_FORMAT, "bad.data:16: Velocities line has 6");
  expect_error(HEAD "Atoms\n\n1 1 1 1 0.5 0.5 0.5\n2 1 1 1 0.5 0.5 0.5\n\nVelocities\n\n1 0 0 0 0 0 0\n5 0 0 0 0 0 0\n",
               TL_ERR_FORMAT, "atom id 5, which is not in the Atoms");
  expect_error(HEAD "Velocities\n\n1 0 0 0 0 0 0\n2 0 0 0 0 0 0\n", TL_ERR_FORMAT, "Velocities section before");
  /* another atom style, an unknown section */
  expect_error(HEAD "Atoms # atomic\n\n1 1 0.5 0.5 0.5\n2 1 0.5 0.5 0.5\n", TL_ERR_UNSUPPORTED, "\"atomic\"");
  expect_error(HEAD "Bonds\n\n1 1 1 2\n", TL_ERR_UNSUPPORTED, "bad.data:9: section \"Bonds\"");
}

int main(void)
{
  char chute[4200];
  if (find_chute(chute, sizeof chute)) {
    test_chute(chute);
  } else {
    /* The peers' folder sits next to the repository on the benchmark
     * machines; elsewhere the file tests below still run. */
    printf("note: data.chute not found (set TALUS_PEERS_DIR): chute checks skipped\n");
  }
  test_write_data_layout();
  test_malformed();
  return tl_test_report();
}
