// CGAL's answer to recon's phases I and II: pca_estimate_normals (a
// least-squares plane per k-neighbourhood) and mst_orient_normals (Hoppe's
// orientation: MST of the Riemannian graph, seeded at the highest point).
//
//   cgal_normals IN.ply -o OUT.ply [--k K] [--threads T]
//
// K counts the point itself, as recon's --k does. CGAL's k does not (its
// neighbour query asks for k + 1 points and the first is the query point), so
// CGAL is given K - 1 and sees the same neighbourhoods as recon.
// OUT.ply holds the input's points in the input's order with CGAL's normals
// and a uchar `oriented`, 0 for the points mst_orient_normals left unoriented
// (it moves those to the end of the range; an index travels with each point).
// The input's own normals are ignored. Prints one `step <name> <seconds> s`
// line per step. T limits TBB's threads (0: all cores); the orientation is
// sequential whatever T says.
#include "arguments.h"
#include "ply_points.h"
#include "steps.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/pca_estimate_normals.h>
#include <CGAL/property_map.h>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/global_control.h>
#endif

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using Entry = std::tuple<Point, Vector, std::size_t>;  // position, normal, input index
using PointMap = CGAL::Nth_of_tuple_property_map<0, Entry>;
using NormalMap = CGAL::Nth_of_tuple_property_map<1, Entry>;

using Options = peers::Arguments;

Options parse(int argc, char** argv) {
  return peers::parse_arguments(argc, argv, 15, 3, "cgal_normals IN.ply -o OUT.ply [--k K] [--threads T]");
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
#ifdef CGAL_LINKED_WITH_TBB
  std::unique_ptr<tbb::global_control> limit;
  if (o.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, o.threads);
  std::printf("threads: TBB, at most %zu for the normals; orientation sequential\n",
              tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
#else
  std::printf("threads: 1 (CGAL built without TBB)\n");
#endif
  peers::Steps steps;

  const peers::PlyPoints input = peers::read_ply_points(o.input);
  std::vector<Entry> points;
  points.reserve(input.positions.size());
  for (std::size_t i = 0; i < input.positions.size(); ++i) {
    const auto& p = input.positions[i];
    points.emplace_back(Point(p[0], p[1], p[2]), Vector(0, 0, 0), i);
  }
  steps.done("read");

  const auto parameters = CGAL::parameters::point_map(PointMap()).normal_map(NormalMap());
  CGAL::pca_estimate_normals<CGAL::Parallel_if_available_tag>(points, o.k - 1, parameters);
  steps.done("pca_normals");

  const auto first_unoriented = CGAL::mst_orient_normals(points, o.k - 1, parameters);
  steps.done("mst_orient");

  peers::PlyPoints output;
  output.positions = input.positions;
  output.normals.resize(points.size());
  std::vector<std::uint8_t> oriented(points.size(), 0);
  for (auto it = points.begin(); it != points.end(); ++it) {
    const auto& [position, normal, index] = *it;
    output.normals[index] = {normal.x(), normal.y(), normal.z()};
    oriented[index] = it < first_unoriented ? 1 : 0;
  }
  const auto unoriented = static_cast<std::size_t>(points.end() - first_unoriented);
  peers::write_ply_points(o.output, output, oriented);
  steps.done("write");
  std::printf("unoriented: %zu of %zu points\n", unoriented, points.size());
  return 0;
} catch (const std::exception& e) {
  std::cerr << "cgal_normals: " << e.what() << "\n";
  return 1;
}
