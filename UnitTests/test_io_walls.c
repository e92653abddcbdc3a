/* Walls in the output (tl_wall_snapshot.h): a plane floor and a triangulated
 * ceiling with a grain pressed against each, written and read back: the
 * plane as a patch covering the box, the surface's triangles as they stand,
 * per-triangle contact forces that sum to the force on each wall, the mesh
 * file written again only when a wall moves, refusals; and ParaView's own
 * XDMF reader (pvpython, skipped when absent) opening the series. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "talus.h"
#include "tl_test.h"

static double block_force_z(const TlMeshSnapshotBlock *b)
{
  for (size_t f = 0; f < b->n_fields; ++f)
    if (strcmp(b->field_names[f], "contact_force") == 0) {
      double s = 0;
      for (size_t c = 0; c < b->n_cells; ++c) s += b->field_data[f][3 * c + 2];
      return s;
    }
  return NAN;
}

/* ParaView reads walls.xmf: every step, one block per wall with its
 * triangles (VTK type 5) and the contact force.  0: checked, 1: no pvpython. */
static int paraview_check(void)
{
  FILE *p = popen("command -v pvpython 2>/dev/null", "r");
  char buf[512] = {0};
  int have = p && fgets(buf, sizeof buf, p) && buf[0] == '/';
  if (p) pclose(p);
  if (!have) return 1;
  FILE *f = fopen("walls_check.py", "w");
  fputs("from paraview.simple import *\n"
        "r = XDMFReader(FileNames=['out/walls.xmf'])\n"
        "r.UpdatePipelineInformation()\n"
        "t = list(r.TimestepValues)\n"
        "r.UpdatePipeline(t[-1])\n"
        "d = servermanager.Fetch(r)\n"
        "print('steps=%d blocks=%d' % (len(t), d.GetNumberOfBlocks()))\n"
        "for b in range(d.GetNumberOfBlocks()):\n"
        "    g = d.GetBlock(b)\n"
        "    a = g.GetCellData().GetArray('contact_force')\n"
        "    print('block%d cells=%d type=%d force=%d' % (b, g.GetNumberOfCells(), g.GetCellType(0), a.GetNumberOfComponents()))\n",
        f);
  fclose(f);
  p = popen("pvpython walls_check.py 2>/dev/null", "r");
  static char out[4096];
  size_t n = p ? fread(out, 1, sizeof out - 1, p) : 0;
  if (p) pclose(p);
  out[n] = '\0';
  TL_TEST_ASSERT(strstr(out, "steps=3 blocks=2") && strstr(out, "block0 cells=2 type=5 force=3") &&
                     strstr(out, "block1 cells=64 type=5 force=3"),
                 "ParaView reads walls.xmf as:\n%s", out);
  return 0;
}

static TlStatus run(int *no_paraview)
{
  TlDem *dem;
  TL_CHECK(tl_dem_create(&dem));
  TlParticles *P = tl_dem_particles(dem);
  int sp;
  double r = 0.05;
  TL_CHECK(tl_particles_add_species(P, "grain", 2500, r, r, &sp));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0.3, 0.4, 0.99 * r), tl_v3(0, 0, 0), r, sp, NULL));
  TL_CHECK(tl_dem_add_particle(dem, tl_v3(0.55, 0.45, 0.5 - 0.98 * r), tl_v3(0, 0, 0), r, sp, NULL));
  TlContactLaw *law;
  TL_CHECK(tl_contact_law_create("linear", NULL, NULL, NULL, &law));
  TL_CHECK(tl_contact_law_set(law, "k_n", 1e4));
  TL_CHECK(tl_contact_law_setup(law));
  TL_CHECK(tl_dem_add_law(dem, law, NULL));
  TlWall *floor, *ceiling;
  TL_CHECK(tl_wall_plane_create(tl_v3(0, 0, 0), tl_v3(0, 0, 1), &floor));
  TL_CHECK(tl_dem_add_wall(dem, floor, 0));
  TlTriSurface *s;
  TL_CHECK(tl_trisurface_create_rectangle(0, 0, 1, 1, 0.5, 4, 4, 2, &s));
  TL_CHECK(tl_wall_trisurface_create(s, &ceiling));
  TL_CHECK(tl_dem_add_wall(dem, ceiling, 0));
  TL_CHECK(tl_dem_set_timestep(dem, 1e-5, 0));
  TL_CHECK(tl_dem_setup(dem));
  TL_CHECK(tl_dem_compute_forces(dem));

  TlWallWriter *ww;
  TL_CHECK(tl_wall_writer_create("out", "walls", &ww));
  TL_TEST_STATUS(tl_wall_writer_set_box(ww, tl_v3(0, 0, 0), tl_v3(1, 1, 0)), TL_ERR_ARG);
  TL_TEST_STATUS(tl_wall_writer_set_box(ww, tl_v3(0, 0, 0), tl_v3(NAN, 1, 1)), TL_ERR_ARG);
  TL_CHECK(tl_wall_writer_set_box(ww, tl_v3(-0.5, 0, 0), tl_v3(1.5, 1, 0.5)));
  TL_CHECK(tl_wall_writer_write_dem(ww, 0, dem));
  char mesh0[4096];
  snprintf(mesh0, sizeof mesh0, "%s", tl_wall_writer_mesh_path(ww));
  TL_CHECK(tl_dem_step(dem, 1)); /* each snapshot at its own time */
  TL_CHECK(tl_wall_writer_write_dem(ww, 1, dem));
  TL_TEST_ASSERT(strcmp(mesh0, tl_wall_writer_mesh_path(ww)) == 0, "still walls rewrote the mesh: %s then %s", mesh0,
                 tl_wall_writer_mesh_path(ww));

  TlMeshSnapshot m;
  TL_CHECK(tl_mesh_snapshot_read(tl_wall_writer_last_path(ww), &m));
  TL_TEST_ASSERT(m.n_blocks == 2, "%zu blocks", m.n_blocks);
  if (m.n_blocks == 2) {
    const TlMeshSnapshotBlock *pl = &m.blocks[0], *ts = &m.blocks[1];
    TL_TEST_ASSERT(strcmp(pl->name, "wall0_plane") == 0 && strcmp(ts->name, "wall1_trisurface") == 0, "names %s %s",
                   pl->name, ts->name);
    TL_TEST_ASSERT(pl->type == TL_CELL_TRI3 && pl->n_cells == 2, "plane: %zu cells", pl->n_cells);
    TL_TEST_ASSERT(ts->n_cells == s->n_triangles, "surface: %zu cells of %zu", ts->n_cells, s->n_triangles);
    /* the plane patch is the box's x-y rectangle at z = 0 */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < 6; ++i) {
      TlVec3 x = m.reference[pl->connectivity[i]];
      double c[3] = {x.x, x.y, x.z};
      for (int k = 0; k < 3; ++k) lo[k] = fmin(lo[k], c[k]), hi[k] = fmax(hi[k], c[k]);
    }
    TL_TEST_CLOSE(lo[0], -0.5, 1e-14);
    TL_TEST_CLOSE(hi[0], 1.5, 1e-14);
    TL_TEST_CLOSE(lo[1], 0.0, 1e-14);
    TL_TEST_CLOSE(hi[1], 1.0, 1e-14);
    TL_TEST_CLOSE(hi[2] - lo[2], 0.0, 1e-14);
    /* the surface's vertices as they stand */
    double dmax = 0;
    for (size_t t = 0; t < ts->n_cells; ++t)
      for (int j = 0; j < 3; ++j) {
        TlVec3 a = m.reference[ts->connectivity[3 * t + j]], b = s->x[s->tri[3 * t + j]];
        dmax = fmax(dmax, tl_v3_norm(tl_v3_sub(a, b)));
      }
    TL_TEST_ASSERT(dmax == 0.0, "surface vertices off by %g m", dmax);
    /* contact forces: the floor is pushed down, the ceiling up, each by
     * what the DEM says the particles exert on it */
    TL_TEST_ASSERT(floor->force.z < 0 && ceiling->force.z > 0, "wall forces %g %g", floor->force.z, ceiling->force.z);
    TL_TEST_REL(block_force_z(pl), floor->force.z, 1e-12);
    TL_TEST_REL(block_force_z(ts), ceiling->force.z, 1e-12);
    /* normals: the floor's +z, the wall index field */
    for (size_t f = 0; f < pl->n_fields; ++f) {
      if (strcmp(pl->field_names[f], "normal") == 0) TL_TEST_CLOSE(pl->field_data[f][2], 1.0, 1e-15);
      if (strcmp(pl->field_names[f], "wall") == 0) TL_TEST_ASSERT(pl->field_data[f][0] == 0.0, "wall index");
    }
  }
  tl_mesh_snapshot_free(&m);

  /* moving the ceiling writes a new mesh file with the moved triangles */
  for (size_t v = 0; v < s->n_vertices; ++v) s->x[v].z += 0.1;
  TL_CHECK(tl_trisurface_update(s));
  TL_CHECK(tl_dem_step(dem, 1));
  TL_CHECK(tl_wall_writer_write_dem(ww, 2, dem));
  TL_TEST_ASSERT(strcmp(mesh0, tl_wall_writer_mesh_path(ww)) != 0, "moved wall kept the mesh file %s", mesh0);
  TL_CHECK(tl_mesh_snapshot_read(tl_wall_writer_last_path(ww), &m));
  if (m.n_blocks == 2) TL_TEST_CLOSE(m.reference[m.blocks[1].connectivity[0]].z, 0.6, 1e-15);
  tl_mesh_snapshot_free(&m);
  TL_TEST_ASSERT(tl_wall_writer_count(ww) == 3, "%zu steps", tl_wall_writer_count(ww));
  char *xmf = tl_test_read_file("out/walls.xmf");
  TL_TEST_ASSERT(xmf && tl_test_count(xmf, "<Time ") == 3 && strstr(xmf, "wall1_trisurface") &&
                     strstr(xmf, "contact_force"),
                 "walls.xmf lacks steps or blocks");
  free(xmf);
  tl_wall_writer_destroy(&ww);
  *no_paraview = paraview_check();

  /* without a box, planes are sized by the domain and the particles */
  TL_CHECK(tl_wall_writer_create("out", "walls_auto", &ww));
  TL_CHECK(tl_wall_writer_write_dem(ww, 0, dem));
  TlVec3 blo, bhi;
  TL_TEST_ASSERT(tl_wall_writer_box(ww, &blo, &bhi) && blo.x <= 0.0 && bhi.x >= 1.0 && bhi.z >= 0.6,
                 "box [%g %g %g] [%g %g %g]", blo.x, blo.y, blo.z, bhi.x, bhi.y, bhi.z);
  tl_wall_writer_destroy(&ww);
  tl_dem_destroy(&dem);
  return TL_OK;
}

int main(void)
{
  TL_TEST_STATUS(tl_initialize(), TL_OK);
  int no_paraview = 0;
  TL_TEST_STATUS(run(&no_paraview), TL_OK);
  if (no_paraview) return tl_test_skip("the ParaView check (pvpython not found on PATH); the file checks ran");
  return tl_test_report();
}
