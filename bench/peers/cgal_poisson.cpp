// CGAL's Poisson surface reconstruction (not screened), as CGAL's own
// tutorial runs it on a cloud without normals: jet_estimate_normals,
// mst_orient_normals (Hoppe's MST orientation), then
// poisson_surface_reconstruction_delaunay at the cloud's average spacing
// (6 neighbours) with the default meshing criteria (angle 20, radius 30,
// distance 0.375 spacings).
//
//   cgal_poisson IN.ply -o MESH.ply [--k K] [--threads T]
//
// K counts the point itself, as recon's --k does (CGAL is given K - 1).
// Points left unoriented by mst_orient_normals are dropped, as the tutorial
// does. Prints one `step <name> <seconds> s` line per step.
#include "arguments.h"
#include "ply_points.h"
#include "steps.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/poisson_surface_reconstruction.h>
#include <CGAL/property_map.h>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/global_control.h>
#endif

#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using Entry = std::pair<Point, Vector>;
using PointMap = CGAL::First_of_pair_property_map<Entry>;
using NormalMap = CGAL::Second_of_pair_property_map<Entry>;
using Polyhedron = CGAL::Polyhedron_3<Kernel>;

using Options = peers::Arguments;

Options parse(int argc, char** argv) {
  return peers::parse_arguments(argc, argv, 24, 7, "cgal_poisson IN.ply -o MESH.ply [--k K] [--threads T]");
}

// Binary little-endian PLY: double vertices, int faces.
void write_mesh(const std::string& path, const Polyhedron& mesh) {
  std::map<Polyhedron::Vertex_const_handle, int> index;
  std::vector<std::array<double, 3>> vertices;
  for (auto v = mesh.vertices_begin(); v != mesh.vertices_end(); ++v) {
    index[v] = static_cast<int>(vertices.size());
    vertices.push_back({v->point().x(), v->point().y(), v->point().z()});
  }
  std::vector<std::array<int, 3>> faces;
  for (auto f = mesh.facets_begin(); f != mesh.facets_end(); ++f) {
    auto h = f->facet_begin();
    std::array<int, 3> t{};
    for (int j = 0; j < 3; ++j, ++h) t[j] = index[h->vertex()];
    faces.push_back(t);
  }
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << vertices.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << faces.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  out.write(reinterpret_cast<const char*>(vertices.data()), static_cast<std::streamsize>(vertices.size() * 24));
  for (const auto& t : faces) {
    const unsigned char three = 3;
    out.write(reinterpret_cast<const char*>(&three), 1);
    out.write(reinterpret_cast<const char*>(t.data()), 12);
  }
  if (!out) throw std::runtime_error("could not write " + path);
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
#ifdef CGAL_LINKED_WITH_TBB
  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, o.threads);
#endif
  peers::Steps steps;
  const peers::PlyPoints input = peers::read_ply_points(o.input);
  std::vector<Entry> points;
  points.reserve(input.positions.size());
  for (const auto& p : input.positions) points.emplace_back(Point(p[0], p[1], p[2]), Vector(0, 0, 0));
  steps.done("read");

  const auto parameters = CGAL::parameters::point_map(PointMap()).normal_map(NormalMap());
  CGAL::jet_estimate_normals<CGAL::Parallel_if_available_tag>(points, o.k - 1, parameters);
  steps.done("jet_normals");
  const auto first_unoriented = CGAL::mst_orient_normals(points, o.k - 1, parameters);
  points.erase(first_unoriented, points.end());
  steps.done("mst_orient");

  const double spacing = CGAL::compute_average_spacing<CGAL::Parallel_if_available_tag>(
      points, 6, CGAL::parameters::point_map(PointMap()));
  Polyhedron mesh;
  if (!CGAL::poisson_surface_reconstruction_delaunay(points.begin(), points.end(), PointMap(), NormalMap(), mesh,
                                                     spacing))
    throw std::runtime_error("poisson_surface_reconstruction_delaunay failed");
  steps.done("poisson");
  write_mesh(o.output, mesh);
  steps.done("write");
  std::printf("mesh: %zu vertices, %zu faces\n", mesh.size_of_vertices(), mesh.size_of_facets());
  return 0;
} catch (const std::exception& e) {
  std::cerr << "cgal_poisson: " << e.what() << "\n";
  return 1;
}
