/* ParaView itself opens the XDMF series: pvpython's XDMF reader must see
 * every time step, one vertex cell per particle with its arrays, and mesh
 * blocks of the right VTK cell types with the connectivity unchanged.
 * Skipped (ctest's skip code, reported as a skip) when pvpython is absent
 * (ParaView is optional). */
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_io.h"
#include "tl_test.h"

static const char *script =
    "from paraview.simple import *\n"
    "def grid(name):\n"
    "    r = XDMFReader(FileNames=[name])\n"
    "    r.UpdatePipelineInformation()\n"
    "    t = list(r.TimestepValues)\n"
    "    r.UpdatePipeline(t[-1])\n"
    "    return t, servermanager.Fetch(r)\n"
    "t, d = grid('pv/grains.xmf')\n"
    "print('particles_times=' + ','.join('%g' % x for x in t))\n"
    "print('particles_points=%d' % d.GetNumberOfPoints())\n"
    "print('particles_cells=%d' % d.GetNumberOfCells())\n"
    "print('particles_celltypes=%s' % ','.join(str(d.GetCellType(i)) for i in range(d.GetNumberOfCells())))\n"
    "a = d.GetPointData().GetArray('radius')\n"
    "print('particles_radius=%s' % ','.join('%.17g' % a.GetValue(i) for i in range(a.GetNumberOfTuples())))\n"
    "v = d.GetPointData().GetArray('velocity')\n"
    "print('particles_velocity_components=%d' % v.GetNumberOfComponents())\n"
    "t, d = grid('pv/solid.xmf')\n"
    "print('mesh_times=' + ','.join('%g' % x for x in t))\n"
    "print('mesh_blocks=%d' % d.GetNumberOfBlocks())\n"
    "for b in range(d.GetNumberOfBlocks()):\n"
    "    g = d.GetBlock(b)\n"
    "    ids = g.GetCell(0).GetPointIds()\n"
    "    print('mesh_block%d_type=%d' % (b, g.GetCellType(0)))\n"
    "    print('mesh_block%d_ids=%s' % (b, ','.join(str(ids.GetId(i)) for i in range(ids.GetNumberOfIds()))))\n"
    "    u = g.GetPointData().GetArray('displacement')\n"
    "    print('mesh_block%d_displacement=%.17g' % (b, u.GetComponent(4, 2)))\n"
    "print('done=1')\n";

static int have_pvpython(void)
{
  FILE *p = popen("command -v pvpython 2>/dev/null", "r");
  char buf[512] = {0};
  int ok = p && fgets(buf, sizeof buf, p) && buf[0] == '/';
  if (p) pclose(p);
  return ok;
}

/* The value of "key=value" in the output ("" when absent). */
static const char *value_of(const char *out, const char *key, char *buf, size_t cap)
{
  char pattern[128];
  snprintf(pattern, sizeof pattern, "\n%s=", key);
  const char *p = strstr(out, pattern);
  buf[0] = '\0';
  if (!p) return buf;
  p += strlen(pattern);
  size_t n = strcspn(p, "\n");
  snprintf(buf, cap, "%.*s", (int)(n < cap ? n : cap - 1), p);
  return buf;
}

int main(void)
{
  if (!have_pvpython()) {
    return tl_test_skip("ParaView check (pvpython not found on PATH)");
  }
  enum { N = 4 };
  TlVec3 x[N] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, v[N] = {{0}};
  double r[N] = {0.25, 0.5, 0.125, 1.0 / 3.0};
  TlParticleView pv = {.n = N, .position = x, .radius = r, .velocity = v};
  TlParticleWriter *pw;
  TL_TEST_STATUS(tl_particle_writer_create("pv", "grains", &pw), TL_OK);
  for (int k = 0; pw && k < 3; ++k) TL_TEST_STATUS(tl_particle_writer_write(pw, k, 0.5 * k, &pv), TL_OK);
  tl_particle_writer_destroy(&pw);

  TlVec3 nodes[33], disp[33];
  for (int i = 0; i < 33; ++i) {
    nodes[i] = tl_v3(i % 3, (i / 3) % 3, i / 9);
    disp[i] = tl_v3(0, 0, 0.001 * i);
  }
  int hex[27], tet[10];
  for (int i = 0; i < 27; ++i) hex[i] = 26 - i; /* a permutation ParaView must keep */
  for (int i = 0; i < 10; ++i) tet[i] = 23 + i;
  TlMeshBlock blocks[2] = {{"body", TL_CELL_HEX27, 1, hex, 0, NULL}, {"tip", TL_CELL_TET10, 1, tet, 0, NULL}};
  TlMeshView mv = {.n_nodes = 33, .reference = nodes, .displacement = disp, .n_blocks = 2, .blocks = blocks};
  TlMeshWriter *mw;
  TL_TEST_STATUS(tl_mesh_writer_create("pv", "solid", &mw), TL_OK);
  for (int k = 0; mw && k < 2; ++k) TL_TEST_STATUS(tl_mesh_writer_write(mw, k, 2.0 * k, &mv), TL_OK);
  tl_mesh_writer_destroy(&mw);

  FILE *f = fopen("check.py", "w");
  fputs(script, f);
  fclose(f);
  FILE *p = popen("pvpython check.py 2>/dev/null", "r");
  static char out[16384];
  size_t n = 1;
  out[0] = '\n';
  if (p) {
    n += fread(out + 1, 1, sizeof out - 2, p);
    pclose(p);
  }
  out[n] = '\0';
  char buf[1024];
  TL_TEST_ASSERT(strcmp(value_of(out, "done", buf, sizeof buf), "1") == 0, "pvpython did not finish:\n%s", out);
  TL_TEST_ASSERT(strcmp(value_of(out, "particles_times", buf, sizeof buf), "0,0.5,1") == 0, "particle times '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "particles_points", buf, sizeof buf), "4") == 0, "points '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "particles_cells", buf, sizeof buf), "4") == 0, "cells '%s'", buf);
  /* VTK_POLY_VERTEX = 2 */
  TL_TEST_ASSERT(strcmp(value_of(out, "particles_celltypes", buf, sizeof buf), "2,2,2,2") == 0, "cell types '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "particles_radius", buf, sizeof buf), "0.25,0.5,0.125,0.33333333333333331") == 0,
                 "radius '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "particles_velocity_components", buf, sizeof buf), "3") == 0, "velocity '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "mesh_times", buf, sizeof buf), "0,2") == 0, "mesh times '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "mesh_blocks", buf, sizeof buf), "2") == 0, "blocks '%s'", buf);
  /* VTK_TRIQUADRATIC_HEXAHEDRON = 29, VTK_QUADRATIC_TETRA = 24 */
  TL_TEST_ASSERT(strcmp(value_of(out, "mesh_block0_type", buf, sizeof buf), "29") == 0, "block 0 type '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "mesh_block1_type", buf, sizeof buf), "24") == 0, "block 1 type '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "mesh_block0_ids", buf, sizeof buf),
                        "26,25,24,23,22,21,20,19,18,17,16,15,14,13,12,11,10,9,8,7,6,5,4,3,2,1,0") == 0,
                 "hex27 connectivity reordered: '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "mesh_block1_ids", buf, sizeof buf), "23,24,25,26,27,28,29,30,31,32") == 0,
                 "tet10 connectivity '%s'", buf);
  TL_TEST_ASSERT(strcmp(value_of(out, "mesh_block0_displacement", buf, sizeof buf), "0.0040000000000000001") == 0,
                 "displacement '%s'", buf);
  return tl_test_report();
}
