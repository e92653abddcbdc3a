/* The cost of meshing a closed surface into tetrahedra against the size of
 * the surface (tl_mesh_from_surface: CGAL Mesh_3), with Gmsh's 3-D Delaunay
 * mesher on the same surface in the same invocation as the peer.
 *
 * Surfaces: unit spheres, icosahedra subdivided -levels times (20 4^l
 * triangles, vertices on the sphere).  The element size follows the
 * surface: h = -h_factor times the surface's mean edge length, so the
 * tetrahedra grow with the triangles.  Talus meshes the enclosed volume
 * with cell and facet size h and facet distance h / 20 (Mesh_3 remeshes
 * the surface, then refines and exudes slivers); Gmsh (`gmsh -3`, its
 * default Delaunay algorithm, Mesh.MeshSizeMax = h) keeps the given
 * triangles as the boundary and fills the volume.  The tasks differ (the
 * remeshed surface against the given one), so the ratio printed is of the
 * times per tetrahedron produced, besides the raw times.  Gmsh is started
 * as a process per size (its start-up, about 0.05 s, is timed alone and
 * subtracted); without gmsh on PATH the table has no peer column and says
 * so.
 *
 * Output: a table on stdout and <output_dir>/mesh_from_surface.csv; last
 * line summary: ... ratio=<Talus / Gmsh time per tetrahedron at the largest
 * size with a peer> wall=... */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "talus.h"
#include "tl_bench.h"
#include "tl_mesh_from_surface.h"
#include "tl_stl.h"

static double mean_edge(const TlSurfaceArrays *s)
{
  double sum = 0.0;
  for (size_t t = 0; t < s->n_triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      const double *a = s->x + 3 * s->tri[3 * t + k], *b = s->x + 3 * s->tri[3 * t + (k + 1) % 3];
      sum += sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
    }
  return sum / (3.0 * (double)s->n_triangles);
}

/* Runs gmsh on path.geo; *seconds the wall time, *tets the tetrahedra of the
 * written mesh (counted from its $Elements section: type 4). */
static int run_gmsh(const char *dir, const char *stl, double h, double *seconds, long *tets)
{
  char geo[4096], msh[4096], cmd[12288];
  snprintf(geo, sizeof geo, "%s/peer.geo", dir);
  snprintf(msh, sizeof msh, "%s/peer.msh", dir);
  FILE *f = fopen(geo, "w");
  if (!f) return 0;
  fprintf(f, "Merge \"%s\";\nSurface Loop(1) = {1};\nVolume(1) = {1};\nMesh.MeshSizeMax = %.17g;\n"
             "Mesh.MeshSizeMin = %.17g;\nMesh.MeshSizeFromPoints = 0;\nMesh.MeshSizeExtendFromBoundary = 0;\n",
          stl, h, 0.1 * h);
  fclose(f);
  snprintf(cmd, sizeof cmd, "gmsh -3 -format msh2 -nt 1 -v 0 '%s' -o '%s' > /dev/null 2>&1", geo, msh);
  double t0 = tl_wtime();
  int rc = system(cmd);
  *seconds = tl_wtime() - t0;
  if (rc != 0) return 0;
  f = fopen(msh, "r");
  if (!f) return 0;
  char line[512];
  long n = 0, count = 0;
  int in = 0;
  while (fgets(line, sizeof line, f)) {
    if (!strncmp(line, "$Elements", 9)) {
      in = 1;
      if (!fgets(line, sizeof line, f)) break;
      continue;
    }
    if (!strncmp(line, "$EndElements", 12)) break;
    long id, type;
    if (in && sscanf(line, "%ld %ld", &id, &type) == 2 && type == 4) ++count;
    ++n;
  }
  fclose(f);
  *tets = count;
  return count > 0;
}

static TlStatus run(int argc, char **argv, TlSummary *sum)
{
  TlOptions *o = NULL;
  double levels[8], h_factor;
  int n_levels = 0, peer;
  long repeat;
  const char *out;
  TL_CHECK(tl_options_create(argc, argv,
                             "Cost of meshing a closed surface into tetrahedra (CGAL Mesh_3) against the surface's "
                             "size, beside Gmsh's 3-D mesher on the same surface.",
                             &o));
  TlStatus st = tl_options_get_real_list_range(o, "-levels", "2,3,4,5", 0, 6, "", "icosphere subdivision levels "
                                               "(20 4^l triangles)", levels, 8, &n_levels);
  if (!st) st = tl_options_get_real(o, "-h_factor", 2.0, 0.5, 100.0, "", "element size over the mean surface edge", &h_factor);
  if (!st) st = tl_options_get_int(o, "-repeat", 1, 1, 100, "repetitions (the fastest is kept)", &repeat);
  if (!st) st = tl_options_get_bool(o, "-peer", 1, "run Gmsh beside", &peer);
  if (!st) st = tl_options_get_string(o, "-output_dir", "results/mesh_from_surface", "output folder", &out);
  if (!st) st = tl_options_finish(o, stdout);
  if (!st) st = tl_output_dir_prepare(out);
  if (st) {
    tl_options_destroy(&o);
    return st;
  }
  int have_gmsh = peer && system("gmsh -version > /dev/null 2>&1") == 0;
  double gmsh_startup = 0.0;
  if (have_gmsh) {
    double t0 = tl_wtime();
    if (system("gmsh -version > /dev/null 2>&1") != 0) have_gmsh = 0;
    gmsh_startup = tl_wtime() - t0;
  }
  char csv[4096];
  snprintf(csv, sizeof csv, "%s/mesh_from_surface.csv", out);
  FILE *fc = fopen(csv, "w");
  if (fc) fprintf(fc, "triangles,h,talus_tets,talus_s,gmsh_tets,gmsh_s,ratio_per_tet\n");
  printf("%s\n", have_gmsh ? "peer: gmsh (same surface as binary STL, -nt 1)"
                           : "peer: none (gmsh not on PATH or -peer 0): Talus times only");
  printf("%10s %9s %10s %9s %12s %10s %9s %12s %8s\n", "triangles", "h", "tets", "s", "tets/s", "gmsh tets", "gmsh s",
         "gmsh tets/s", "ratio");
  double last_ratio = NAN, last_rate = NAN;
  long last_tris = 0;
  for (int l = 0; l < n_levels && !st; ++l) {
    TlSurfaceArrays s;
    const double c[3] = {0, 0, 0};
    TL_CHECK_GOTO(st, tl_surface_sphere(c, 1.0, (int)levels[l], &s), done);
    const double h = h_factor * mean_edge(&s);
    TlMeshFromSurfaceOptions mo;
    tl_mesh_from_surface_options_default(&mo);
    mo.cell_size = mo.facet_size = h;
    mo.facet_distance = h / 20.0;
    double best = INFINITY;
    TlMeshFromSurfaceInfo info;
    for (long r = 0; r < repeat && !st; ++r) {
      TlMesh *m = NULL;
      double t0 = tl_wtime();
      st = tl_mesh_from_surface(&s, &mo, &m, &info);
      best = fmin(best, tl_wtime() - t0);
      tl_mesh_destroy(&m);
    }
    double g_s = NAN, g_rate = NAN, ratio = NAN;
    long g_tets = 0;
    if (!st && have_gmsh) {
      int *tri = NULL;
      TlSurfaceMesh *sm = NULL;
      st = tl_calloc(&tri, 3 * s.n_triangles, sizeof *tri);
      for (size_t i = 0; !st && i < 3 * s.n_triangles; ++i) tri[i] = (int)s.tri[i];
      if (!st) st = tl_surface_mesh_create(s.n_vertices, s.x, s.n_triangles, tri, &sm);
      char stl[4200];
      snprintf(stl, sizeof stl, "%s/peer.stl", out);
      if (!st) st = tl_stl_write(stl, sm, 1);
      tl_surface_mesh_destroy(&sm);
      tl_free(&tri);
      double gbest = INFINITY;
      for (long r = 0; r < repeat && !st; ++r) {
        double sec;
        if (run_gmsh(out, stl, h, &sec, &g_tets)) gbest = fmin(gbest, sec - gmsh_startup);
      }
      if (isfinite(gbest) && g_tets > 0) {
        g_s = gbest;
        g_rate = (double)g_tets / g_s;
        ratio = (best / (double)info.n_tetrahedra) / (g_s / (double)g_tets);
        last_ratio = ratio;
      }
    }
    if (!st) {
      printf("%10zu %9.4g %10zu %9.3f %12.4g %10ld %9.3f %12.4g %8.3g\n", s.n_triangles, h, info.n_tetrahedra, best,
             (double)info.n_tetrahedra / best, g_tets, g_s, g_rate, ratio);
      if (fc) fprintf(fc, "%zu,%.6g,%zu,%.6g,%ld,%.6g,%.6g\n", s.n_triangles, h, info.n_tetrahedra, best, g_tets, g_s, ratio);
      last_rate = (double)info.n_tetrahedra / best;
      last_tris = (long)s.n_triangles;
    }
    tl_surface_arrays_free(&s);
  }
done:
  if (fc) fclose(fc);
  if (!st) {
    tl_summary_int(sum, "triangles", last_tris);
    tl_summary_real(sum, "tets_per_s", last_rate);
    if (isfinite(last_ratio)) tl_summary_real(sum, "ratio", last_ratio);
    double load = tl_bench_load_average();
    if (isfinite(load)) tl_summary_real(sum, "load", load);
  }
  tl_options_destroy(&o);
  return st;
}

int main(int argc, char **argv) { return tl_bench_main_summary(argc, argv, run); }
