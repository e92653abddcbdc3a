/* The Gmsh 4.1 reader on meshes that gmsh itself makes from .geo files at
 * test time: a second-order tetrahedral box (OpenCASCADE) and an extruded,
 * recombined box of 27-node hexahedra, each with its exact volume, outward
 * faces and named sets.
 *
 * gmsh is optional (it pulls OpenCASCADE and FLTK): run as root, this test
 * installs Debian's gmsh when it is missing (apt-get update first if the
 * package is unknown); otherwise, or when the install fails, it reports a
 * skip (ctest's code 77) saying so, never a pass. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "talus.h"
#include "tl_mesh.h"
#include "tl_test.h"
#include "tl_test_mesh.h"

static void write_file(const char *path, const char *text)
{
  FILE *f = fopen(path, "w");
  if (!f) return;
  fputs(text, f);
  fclose(f);
}

static int have_gmsh(void) { return system("gmsh --version > /dev/null 2>&1") == 0; }

/* Installs gmsh as root; whether gmsh runs afterwards. */
static int install_gmsh(void)
{
  if (geteuid() != 0) return 0;
  printf("gmsh not installed: installing Debian's gmsh (apt-get install -y gmsh)\n");
  fflush(stdout);
  if (system("apt-get install -y gmsh > apt_gmsh.log 2>&1") != 0 &&
      system("apt-get update > apt_update.log 2>&1 && apt-get install -y gmsh > apt_gmsh.log 2>&1") != 0)
    return 0;
  return have_gmsh();
}

/* A tetrahedral box made by gmsh from a .geo at test time. */
static void test_gmsh_generated(void)
{
  write_file("box.geo",
             "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 2, 1, 1};\n"
             "Physical Volume(\"solid\") = {1};\nPhysical Surface(\"left\") = {1};\n"
             "Physical Surface(\"right\") = {2};\nMesh.MeshSizeMin = 1.0;\nMesh.MeshSizeMax = 1.0;\n"
             "Mesh.ElementOrder = 2;\n");
  int rc = system("gmsh -3 -format msh41 -o box.msh box.geo > gmsh.log 2>&1");
  TL_TEST_ASSERT(rc == 0, "gmsh failed (see gmsh.log)");
  if (rc) return;
  TlMesh *m = NULL;
  TL_TEST_STATUS(tl_mesh_read_gmsh("box.msh", &m), TL_OK);
  if (!m) return;
  TL_TEST_ASSERT(m->dim == 3 && m->blocks[0].type == &tl_element_tet10 && !strcmp(m->blocks[0].name, "solid"),
                 "block %s of %s", m->blocks[0].name, m->blocks[0].type->header.name);
  TL_TEST_CLOSE(tl_mesh_volume(m), 2.0, 1e-12);
  check_outward(m);
  check_set_normal(m, "left", 0, -1.0);
  check_set_normal(m, "right", 0, 1.0);
  tl_mesh_destroy(&m);
  /* Extruded, recombined box of 27-node hexahedra with 9-node quadrilateral
   * faces: gmsh's node order must give positive Jacobians, the exact
   * volume and outward faces. */
  write_file("hex.geo",
             "Point(1) = {0, 0, 0}; Point(2) = {2, 0, 0}; Point(3) = {2, 1, 0}; Point(4) = {0, 1, 0};\n"
             "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
             "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
             "Transfinite Curve {1, 3} = 3; Transfinite Curve {2, 4} = 2;\n"
             "Transfinite Surface {1}; Recombine Surface {1};\n"
             "out[] = Extrude {0, 0, 1} { Surface{1}; Layers{2}; Recombine; };\n"
             "Physical Volume(\"block\") = {out[1]};\nPhysical Surface(\"bottom\") = {1};\n"
             "Physical Surface(\"top\") = {out[0]};\nMesh.ElementOrder = 2;\n");
  rc = system("gmsh -3 -format msh41 -o hex.msh hex.geo > gmsh_hex.log 2>&1");
  TL_TEST_ASSERT(rc == 0, "gmsh failed (see gmsh_hex.log)");
  if (rc) return;
  TL_TEST_STATUS(tl_mesh_read_gmsh("hex.msh", &m), TL_OK);
  if (!m) return;
  TL_TEST_ASSERT(m->blocks[0].type == &tl_element_hex27 && m->blocks[0].n_elements == 4, "block of %zu %s",
                 m->blocks[0].n_elements, m->blocks[0].type->header.name);
  TL_TEST_CLOSE(tl_mesh_volume(m), 2.0, 1e-12);
  check_outward(m);
  check_set_normal(m, "bottom", 2, -1.0);
  check_set_normal(m, "top", 2, 1.0);
  tl_mesh_destroy(&m);
}

int main(void)
{
  if (!have_gmsh() && !install_gmsh())
    return tl_test_skip(geteuid() == 0 ? "gmsh could not be installed (see apt_gmsh.log): the meshes gmsh makes were not read"
                                       : "gmsh is not installed (Debian's gmsh; as root this test installs it): "
                                         "the meshes gmsh makes were not read");
  test_gmsh_generated();
  return tl_test_report();
}
