#pragma once
// The alternatives lab's results made by hand, for the report's tests
// (report_test.cpp, and report_lab_page.cpp for the browser tests), so
// that the report is tested on graphs known apart from the lab that makes
// them. The five graphs are made as orientation_graphs.h describes them,
// from phase I's planes and the Riemannian graph, and each is walked by
// orient_normals; the runs are a hand-written text in the form of `recon
// lab --stats` (app/lab_command.cpp), whose graph runs carry these graphs' figures.

#include "recon/alternatives/lab.h"
#include "recon/core/point_cloud.h"

#include <algorithm>
#include <charconv>
#include <span>
#include <string>
#include <vector>

namespace recon::testing {

struct HandMadeLab {
  std::vector<Vec3> points;
  TangentPlanes<3> planes;
  OrientedNormals<3> default_orientation;  ///< the Riemannian graph's
  std::vector<LabGraph> graphs;            ///< in all_orientation_graphs order
  std::string runs_json;
  std::size_t runs = 0, skipped = 0;  ///< in runs_json
};

inline RiemannianGraph<3> graph_of_edges(std::size_t n, const std::vector<Edge>& edges) {
  RiemannianGraph<3> g;
  g.graph = make_graph(n, edges);
  g.graph.weights.clear();  // costs come from the normals
  g.components = connected_components(g.graph);
  g.edge_count = g.graph.edge_count();
  return g;
}

// The first k of each neighbourhood (itself excluded): symmetric, or mutual.
inline std::vector<Edge> knn_edges(const TangentPlanes<3>& planes, std::size_t k, bool mutual) {
  const auto lists = [&](std::uint32_t i, std::uint32_t j) {
    const auto row = planes.neighbors.row(i).first(k);
    return std::find(row.begin(), row.end(), j) != row.end();
  };
  std::vector<Edge> edges;
  for (std::uint32_t i = 0; i < planes.neighbors.size(); ++i)
    for (const std::uint32_t j : planes.neighbors.row(i).first(k))
      if (j != i && (!mutual || lists(j, i))) edges.push_back({std::min(i, j), std::max(i, j), 0.0});
  return edges;
}

// The complete graph's minimum spanning tree is the EMST, whole; the emst
// graph is the EMST with the Riemannian graph's gaps cut.
inline RiemannianGraph<3> hand_made_graph(const TangentPlanes<3>& planes, OrientationGraph kind) {
  const std::size_t n = planes.origins.size();
  RiemannianGraph<3> riemannian = build_riemannian_graph<3>(planes);
  std::vector<Edge> kept;
  for (const Edge& e : riemannian.emst) {
    const auto row = riemannian.graph.neighbors(e.u);
    if (std::find(row.begin(), row.end(), e.v) != row.end()) kept.push_back(e);
  }
  const auto k = static_cast<std::size_t>(planes.neighbors.k);
  switch (kind) {
    case OrientationGraph::complete:
      return graph_of_edges(n, riemannian.emst);
    case OrientationGraph::emst:
      return graph_of_edges(n, kept);
    case OrientationGraph::knn:
      return graph_of_edges(n, knn_edges(planes, k, false));
    case OrientationGraph::mutual_knn:
      return graph_of_edges(n, knn_edges(planes, k, true));
    case OrientationGraph::riemannian:
      break;
  }
  return riemannian;
}

inline std::string json_number(double v) {
  char buffer[32];
  return {buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr};
}

// The share of `normals` on the same side as `reference`.
inline double agreement(const std::vector<Vec3>& normals, std::span<const Vec3> reference) {
  std::size_t agree = 0;
  for (std::size_t i = 0; i < normals.size(); ++i) agree += normals[i].dot(reference[i]) > 0.0 ? 1U : 0U;
  return normals.empty() ? 1.0 : static_cast<double>(agree) / static_cast<double>(normals.size());
}

inline std::string graph_run(std::string_view name, const LabGraph& g, const HandMadeLab& lab,
                             std::span<const Vec3> truth) {
  const OrientedNormals<3>& o = g.oriented;
  return R"({"name":")" + std::string(name) + R"(","kind":"graph","graph":")" + std::string(name) + R"(","seconds":)" +
         json_number(0.004 + 0.001 * static_cast<double>(o.graph.edge_count) / 1e4) + R"(,"counts":{"pushes":)" +
         std::to_string(o.normals.size()) + R"(,"pops":)" + std::to_string(o.normals.size()) + R"(},"tree_weight":)" +
         json_number(o.tree.total_weight) + R"(,"edges":)" + std::to_string(o.graph.edge_count) + R"(,"components":)" +
         std::to_string(o.component_count()) + R"(,"flips":)" + std::to_string(o.flip_count) + R"(,"agree_default":)" +
         json_number(agreement(o.normals, lab.default_orientation.normals)) +
         (truth.empty() ? "" : R"(,"agree_truth":)" + json_number(agreement(o.normals, truth))) + "}";
}

// Runs of the other kinds, as `recon lab --stats` writes them (figures made up);
// two are skipped.
inline constexpr std::string_view other_runs =
    R"json({"name":"kd-tree","kind":"search","seconds":0.0021,"counts":{"distance_evaluations":151234}},)json"
    R"json({"name":"uniform-grid","kind":"search","seconds":0.0034,"counts":{"distance_evaluations":201377}},)json"
    R"json({"name":"brute-force","kind":"search",)json"
    R"json("skipped":"25,000 points: more than max_points_brute_force (20,000)"},)json"
    R"json({"name":"prim/binary-heap","kind":"queue","graph":"riemannian","seconds":0.0051,)json"
    R"json("counts":{"pushes":4000,"pops":4000,"decrease_keys":9120,"comparisons":101234},"tree_weight":3.25},)json"
    R"json({"name":"prim/fibonacci-heap","kind":"queue","graph":"riemannian","seconds":0.0113,)json"
    R"json("counts":{"pushes":4000,"pops":4000,"decrease_keys":9120,"comparisons":71234},"tree_weight":3.25},)json"
    R"json({"name":"prim/pairing-heap","kind":"queue","graph":"riemannian","seconds":0.0062,)json"
    R"json("counts":{"pushes":4000,"pops":4000,"decrease_keys":9120,"comparisons":64020},"tree_weight":3.25},)json"
    R"json({"name":"prim/list-heap","kind":"queue","graph":"riemannian",)json"
    R"json("skipped":"more than max_points_list_heap points (a scan per pop)"},)json"
    R"json({"name":"prim","kind":"mst","graph":"riemannian","seconds":0.0050,"counts":{"pushes":4000,)json"
    R"json("pops":4000,"decrease_keys":9120,"comparisons":101234},"tree_weight":3.25},)json"
    R"json({"name":"kruskal","kind":"mst","graph":"riemannian","seconds":0.0071,"counts":{"finds":88000,)json"
    R"json("unions":3998},"tree_weight":3.25},)json"
    R"json({"name":"boruvka","kind":"mst","graph":"riemannian","seconds":0.0066,"counts":{"finds":120000,)json"
    R"json("unions":3998,"rounds":6},"tree_weight":3.25},)json"
    R"json({"name":"prim-array","kind":"mst","graph":"complete","seconds":0.081,)json"
    R"json("counts":{"distance_evaluations":7998000},"tree_weight":61.5},)json"
    R"json({"name":"boruvka-emst","kind":"mst","graph":"complete","seconds":0.0049,)json"
    R"json("counts":{"distance_evaluations":402113,"rounds":5},"tree_weight":61.5})json";

/// Phase I on `cloud`, the five graphs walked, and their runs; `truth`
/// (the cloud's normals) gives the graph runs their agreement with it.
inline HandMadeLab hand_made_lab(const PointCloud& cloud) {
  HandMadeLab lab;
  lab.points = cloud.positions;
  lab.planes = estimate_tangent_planes<3>(std::span<const Vec3>(lab.points));
  lab.runs_json = R"({"runs":[)" + std::string(other_runs);
  for (const OrientationGraph kind : all_orientation_graphs) {
    LabGraph& g = lab.graphs.emplace_back();
    g.kind = kind;
    g.oriented = orient_normals<3>(lab.planes, hand_made_graph(lab.planes, kind));
    if (kind == OrientationGraph::riemannian) lab.default_orientation = g.oriented;
  }
  constexpr std::string_view names[] = {"complete", "emst", "knn", "mutual-knn", "riemannian"};
  for (std::size_t i = 0; i < lab.graphs.size(); ++i)
    lab.runs_json += "," + graph_run(names[i], lab.graphs[i], lab, cloud.normals);
  lab.runs_json += "]}";
  lab.runs = 12 + lab.graphs.size();
  lab.skipped = 2;
  return lab;
}

}  // namespace recon::testing
