// CGAL shim: repair of a triangle soup through CGAL's polygon-mesh
// processing, behind one C function (tl_surface_mesh.c calls it).
// Compiled only with -DTALUS_WITH_CGAL=ON.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <vector>

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

// Whether polygon q is polygon p traversed the same way (same corners by
// position, a cyclic rotation).
bool same_turn(const std::vector<Point> &pts, const std::vector<std::size_t> &p, const std::vector<std::size_t> &q)
{
  if (p.size() != 3 || q.size() != 3) return true;
  for (int r = 0; r < 3; ++r)
    if (pts[p[0]] == pts[q[r]] && pts[p[1]] == pts[q[(r + 1) % 3]] && pts[p[2]] == pts[q[(r + 2) % 3]]) return true;
  return false;
}
} // namespace

// stats: [0] points merged, [1] triangles removed, [2] triangles flipped,
// [3] points duplicated to undo non-manifold vertices.  Returns 0, or 1
// with a message.
extern "C" int tl_cgal_surface_repair(std::size_t nv, const double *x, std::size_t nt, const int *tri,
                                      double needle_ratio, double cap_cosine, int outward, std::size_t *nv_out,
                                      double **x_out, std::size_t *nt_out, int **tri_out, std::size_t stats[4],
                                      char *message, std::size_t message_size)
{
  *x_out = nullptr;
  *tri_out = nullptr;
  try {
    std::vector<Point> points;
    points.reserve(nv);
    for (std::size_t i = 0; i < nv; ++i) points.emplace_back(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    std::vector<std::vector<std::size_t>> polygons(nt);
    for (std::size_t t = 0; t < nt; ++t)
      polygons[t] = {std::size_t(tri[3 * t]), std::size_t(tri[3 * t + 1]), std::size_t(tri[3 * t + 2])};

    // Duplicate points, repeated and invalid (repeated corner) polygons,
    // isolated points.
    PMP::repair_polygon_soup(points, polygons);
    stats[0] = nv > points.size() ? nv - points.size() : 0;
    // Exactly collinear corners: zero area (the exact predicate decides).
    std::size_t kept = 0;
    for (auto &p : polygons)
      if (!CGAL::collinear(points[p[0]], points[p[1]], points[p[2]])) polygons[kept++] = p;
    polygons.resize(kept);
    // Consistent orientation; points are duplicated where none exists.
    std::vector<std::vector<std::size_t>> before = polygons;
    std::size_t np_before = points.size();
    PMP::orient_polygon_soup(points, polygons);
    stats[3] = points.size() - np_before;
    std::size_t flipped = 0;
    for (std::size_t t = 0; t < polygons.size(); ++t) flipped += !same_turn(points, before[t], polygons[t]);

    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
    // Needles and caps by collapses and flips, which keep a closed surface
    // closed (removing the triangle would open a slit).
    PMP::experimental::remove_almost_degenerate_faces(mesh, cap_cosine, needle_ratio, 0.0);
    PMP::remove_degenerate_faces(mesh);
    mesh.collect_garbage();
    stats[1] = nt - std::size_t(mesh.number_of_faces());
    if (CGAL::is_closed(mesh) && mesh.number_of_faces() > 0) {
      bool out = PMP::is_outward_oriented(mesh);
      if (out != (outward != 0)) {
        PMP::reverse_face_orientations(mesh);
        flipped = std::size_t(mesh.number_of_faces()) - flipped;
      }
    }
    stats[2] = flipped;

    std::size_t n = mesh.number_of_vertices(), m = mesh.number_of_faces();
    double *xo = static_cast<double *>(std::malloc(3 * (n + 1) * sizeof(double)));
    int *to = static_cast<int *>(std::malloc(3 * (m + 1) * sizeof(int)));
    if (!xo || !to) {
      std::free(xo);
      std::free(to);
      std::snprintf(message, message_size, "out of memory for %zu vertices, %zu triangles", n, m);
      return 1;
    }
    std::size_t k = 0;
    for (auto v : mesh.vertices()) {
      const Point &p = mesh.point(v);
      xo[3 * k] = p.x(), xo[3 * k + 1] = p.y(), xo[3 * k + 2] = p.z();
      ++k;
    }
    k = 0;
    for (auto f : mesh.faces()) {
      int c = 0;
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
        if (c < 3) to[3 * k + c] = int(std::size_t(v));
        ++c;
      }
      if (c != 3) {
        std::free(xo);
        std::free(to);
        std::snprintf(message, message_size, "face %zu has %d corners after repair", k, c);
        return 1;
      }
      ++k;
    }
    *nv_out = n;
    *nt_out = m;
    *x_out = xo;
    *tri_out = to;
    return 0;
  } catch (const std::exception &e) {
    std::snprintf(message, message_size, "%s", e.what());
    return 1;
  } catch (...) {
    std::snprintf(message, message_size, "unknown CGAL exception");
    return 1;
  }
}
