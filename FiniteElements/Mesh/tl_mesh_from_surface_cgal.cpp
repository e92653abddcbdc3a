// CGAL shim of tl_mesh_from_surface.c: self-intersection test and Mesh_3
// meshing of a closed, outward-oriented triangle soup already checked in C.
// Kept in one file because Mesh_3 is heavy to compile.
// Boost.Graph (feature detection) trips GCC 12's maybe-uninitialized
// analysis inside its own headers; the warning is not about this code.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/make_mesh_3.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <map>
#include <vector>

#include "tl_mesh_from_surface_cgal.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Polyhedron = CGAL::Mesh_polyhedron_3<K>::type;
using Domain = CGAL::Polyhedral_mesh_domain_with_features_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;
namespace PMP = CGAL::Polygon_mesh_processing;

void soup(const TlCgalSurface *s, std::vector<Point> &pts, std::vector<std::vector<std::size_t>> &polys)
{
  pts.reserve(s->n_vertices);
  for (std::size_t i = 0; i < s->n_vertices; ++i) pts.emplace_back(s->x[3 * i], s->x[3 * i + 1], s->x[3 * i + 2]);
  polys.reserve(s->n_triangles);
  for (std::size_t t = 0; t < s->n_triangles; ++t) polys.push_back({s->tri[3 * t], s->tri[3 * t + 1], s->tri[3 * t + 2]});
}

void say(char *msg, std::size_t len, const char *what)
{
  if (msg && len) std::snprintf(msg, len, "%s", what);
}

} // namespace

extern "C" int tl_cgal_self_intersection(const TlCgalSurface *s, std::size_t pair[2], std::size_t *n_pairs,
                                         char *msg, std::size_t msg_len)
{
  try {
    std::vector<Point> pts;
    std::vector<std::vector<std::size_t>> polys;
    soup(s, pts, polys);
    SurfaceMesh sm;
    PMP::polygon_soup_to_polygon_mesh(pts, polys, sm);
    if (sm.number_of_faces() != s->n_triangles) {
      say(msg, msg_len, "the triangles do not form a polygon mesh");
      return -1;
    }
    // Surface_mesh numbers faces in the order they were added: the soup's.
    std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> found;
    PMP::self_intersections(faces(sm), sm, std::back_inserter(found));
    *n_pairs = found.size();
    if (!found.empty()) {
      pair[0] = (std::size_t)found[0].first;
      pair[1] = (std::size_t)found[0].second;
    }
    return 0;
  } catch (const std::exception &e) {
    say(msg, msg_len, e.what());
    return -1;
  }
}

extern "C" int tl_cgal_mesh_3(const TlCgalSurface *s, const TlCgalMeshCriteria *c, TlCgalTetMesh *out,
                              char *msg, std::size_t msg_len)
{
  std::memset(out, 0, sizeof *out);
  try {
    std::vector<Point> pts;
    std::vector<std::vector<std::size_t>> polys;
    soup(s, pts, polys);
    Polyhedron poly;
    PMP::polygon_soup_to_polygon_mesh(pts, polys, poly);
    // Every random choice of the mesher (initial points on the surface,
    // refinement and exudation) from one seeded generator: reproducible meshes.
    CGAL::get_default_random() = CGAL::Random(c->seed);
    CGAL::Random rng(c->seed);
    Domain domain(poly, &rng);
    domain.detect_features(c->feature_angle);
    Criteria criteria(CGAL::parameters::edge_size = c->edge_size, CGAL::parameters::facet_angle = c->facet_angle,
                      CGAL::parameters::facet_size = c->facet_size,
                      CGAL::parameters::facet_distance = c->facet_distance,
                      CGAL::parameters::cell_radius_edge_ratio = c->radius_edge,
                      CGAL::parameters::cell_size = c->cell_size);
    // Exudation runs to completion (time limit 0): CGAL's default stops it
    // after as long as the refinement took, a wall-clock limit that made
    // the mesh differ from run to run.
    C3t3 c3t3 = c->exude ? CGAL::make_mesh_3<C3t3>(domain, criteria, CGAL::parameters::no_perturb(),
                                                   CGAL::parameters::exude(CGAL::parameters::time_limit = 0,
                                                                           CGAL::parameters::sliver_bound = 0))
                         : CGAL::make_mesh_3<C3t3>(domain, criteria, CGAL::parameters::no_perturb(),
                                                   CGAL::parameters::no_exude());
    // Nodes: the vertices of the cells in the complex, numbered as first met.
    std::map<Tr::Vertex_handle, std::size_t> index;
    std::vector<double> x;
    std::vector<std::size_t> tets;
    tets.reserve(4 * c3t3.number_of_cells_in_complex());
    for (auto cit = c3t3.cells_in_complex_begin(); cit != c3t3.cells_in_complex_end(); ++cit)
      for (int k = 0; k < 4; ++k) {
        Tr::Vertex_handle v = cit->vertex(k);
        auto it = index.find(v);
        if (it == index.end()) {
          it = index.emplace(v, index.size()).first;
          const auto &p = v->point();
          x.push_back(CGAL::to_double(p.x()));
          x.push_back(CGAL::to_double(p.y()));
          x.push_back(CGAL::to_double(p.z()));
        }
        tets.push_back(it->second);
      }
    out->n_nodes = index.size();
    out->n_tets = tets.size() / 4;
    out->x = static_cast<double *>(std::malloc((x.size() ? x.size() : 1) * sizeof(double)));
    out->tets = static_cast<std::size_t *>(std::malloc((tets.size() ? tets.size() : 1) * sizeof(std::size_t)));
    if (!out->x || !out->tets) {
      std::free(out->x);
      std::free(out->tets);
      std::memset(out, 0, sizeof *out);
      say(msg, msg_len, "out of memory copying the tetrahedra");
      return -1;
    }
    if (!x.empty()) std::memcpy(out->x, x.data(), x.size() * sizeof(double));
    if (!tets.empty()) std::memcpy(out->tets, tets.data(), tets.size() * sizeof(std::size_t));
    return 0;
  } catch (const std::exception &e) {
    say(msg, msg_len, e.what());
    return -1;
  }
}
