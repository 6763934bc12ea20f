#include "recon/alternatives/reference.h"

#include "recon/alternatives/brute_force_search.h"
#include "recon/alternatives/complete_graph_mst.h"
#include "recon/core/errors.h"
#include "recon/phase1_planes/pca.h"
#include "recon/phase4_contour/marching_cubes_table.h"
#include "recon/structures/lattice.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <queue>
#include <unordered_map>
#include <unordered_set>

namespace recon::reference {
namespace {

using Corner = Lattice<3>::Index;

// ---------------------------------------------------------------------------
// Phase I: a plane through each neighbourhood.

struct Planes {
  std::vector<Vec3> origins, normals;
  KnnTable neighbours;
};

Planes tangent_planes(std::span<const Vec3> points, int k) {
  Planes planes;
  planes.neighbours = brute_force_all_knn<3>(points, k);
  for (std::size_t i = 0; i < points.size(); ++i) {
    Vec3 centroid = Vec3::Zero();
    for (const Neighbor& nb : planes.neighbours.row(i)) centroid += points[nb.index];
    centroid /= k;
    Mat<3> covariance = Mat<3>::Zero();
    for (const Neighbor& nb : planes.neighbours.row(i)) {
      const Vec3 d = points[nb.index] - centroid;
      covariance += d * d.transpose();
    }
    planes.origins.push_back(centroid);
    planes.normals.push_back(symmetric_eigen<3>(covariance / k).vectors.col(0));  // smallest eigenvalue
  }
  return planes;
}

// ---------------------------------------------------------------------------
// Phase II: the Riemannian graph, its minimum spanning tree, the walk.

double cost(const Planes& planes, std::uint32_t i, std::uint32_t j) {
  return 1.0 - std::abs(planes.normals[i].dot(planes.normals[j]));
}

std::vector<Edge> riemannian_graph(const Planes& planes, std::span<const Edge> emst) {
  std::vector<Edge> edges;
  auto join = [&](std::uint32_t i, std::uint32_t j) {
    if (i != j) edges.push_back({std::min(i, j), std::max(i, j), cost(planes, i, j)});
  };
  for (const Edge& e : emst) join(e.u, e.v);
  for (std::size_t i = 0; i < planes.neighbours.size(); ++i)
    for (const Neighbor& nb : planes.neighbours.row(i)) join(static_cast<std::uint32_t>(i), nb.index);
  std::sort(edges.begin(), edges.end(),
            [](const Edge& a, const Edge& b) { return std::tie(a.u, a.v) < std::tie(b.u, b.v); });
  edges.erase(
      std::unique(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) { return a.u == b.u && a.v == b.v; }),
      edges.end());
  return edges;
}

// Prim's algorithm from `root` with a lazy priority queue (an entry whose
// vertex was reached already is skipped); returns the vertices in the order
// reached, and each one's parent.
std::vector<std::uint32_t> prim(std::size_t n, std::span<const Edge> edges, std::uint32_t root,
                                std::vector<std::uint32_t>& parent) {
  std::vector<std::vector<std::pair<std::uint32_t, double>>> adjacent(n);
  for (const Edge& e : edges) {
    adjacent[e.u].push_back({e.v, e.weight});
    adjacent[e.v].push_back({e.u, e.weight});
  }
  struct Entry {
    double weight;
    std::uint32_t vertex, from;
    bool operator>(const Entry& o) const { return weight > o.weight; }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  std::vector<bool> reached(n, false);
  std::vector<std::uint32_t> order;
  parent.assign(n, root);
  queue.push({0.0, root, root});
  while (!queue.empty()) {
    const Entry top = queue.top();
    queue.pop();
    if (reached[top.vertex]) continue;
    reached[top.vertex] = true;
    parent[top.vertex] = top.from;
    order.push_back(top.vertex);
    for (const auto& [next, weight] : adjacent[top.vertex])
      if (!reached[next]) queue.push({weight, next, top.vertex});
  }
  return order;
}

void orient(Planes& planes, std::span<const Edge> graph, Result& result) {
  const std::size_t n = planes.origins.size();
  std::uint32_t root = 0;
  for (std::uint32_t i = 1; i < n; ++i)
    if (planes.origins[i].z() > planes.origins[root].z()) root = i;
  if (planes.normals[root].z() < 0.0) planes.normals[root] = -planes.normals[root];
  for (std::uint32_t i : prim(n, graph, root, result.parent)) {
    if (i == root) continue;
    if (planes.normals[i].dot(planes.normals[result.parent[i]]) < 0.0) {
      planes.normals[i] = -planes.normals[i];
      ++result.flips;
    }
  }
}

// ---------------------------------------------------------------------------
// Phase III: f from the nearest plane, undefined away from the data.

struct SignedDistance {
  std::span<const Vec3> points;
  const Planes& planes;
  double rho, delta;

  [[nodiscard]] bool sample_within(const Vec3& q, double r) const {
    return std::any_of(points.begin(), points.end(), [&](const Vec3& x) { return (x - q).squaredNorm() <= r * r; });
  }
  [[nodiscard]] std::optional<double> operator()(const Vec3& p) const {
    std::size_t nearest = 0;  // the first of equally near origins
    for (std::size_t i = 1; i < planes.origins.size(); ++i)
      if ((p - planes.origins[i]).squaredNorm() < (p - planes.origins[nearest]).squaredNorm()) nearest = i;
    const Vec3& n = planes.normals[nearest];
    const double f = (p - planes.origins[nearest]).dot(n);
    if (sample_within(p - f * n, rho + delta)) return f;
    if (sample_within(p, 1.5 * rho + delta + std::abs(f))) return f;
    return std::nullopt;
  }
};

// ---------------------------------------------------------------------------
// Phase IV: a serial marching-cubes walk over a hash map of corners.

struct CornerHash {
  std::size_t operator()(const Corner& c) const {
    const auto h = [](std::int32_t v) { return static_cast<std::size_t>(static_cast<std::uint32_t>(v)); };
    return (h(c[0]) * 73856093u) ^ (h(c[1]) * 19349663u) ^ (h(c[2]) * 83492791u);
  }
};

Corner corner_of(const Corner& cube, int c) {  // marching-cubes corner c = (c & 1, (c >> 1) & 1, (c >> 2) & 1)
  return {cube[0] + (c & 1), cube[1] + ((c >> 1) & 1), cube[2] + ((c >> 2) & 1)};
}

class Walk {
 public:
  Walk(const SignedDistance& f, const Lattice<3>& lattice) : f_(f), lattice_(lattice) {}

  Mesh run(std::span<const Vec3> seeds) {
    for (const Vec3& p : seeds) visit(lattice_.cell_of(p));  // the cubes holding a sample
    while (!queue_.empty()) {
      const Corner cube = queue_.front();
      queue_.pop();
      contour(cube);
    }
    return std::move(mesh_);
  }

 private:
  void visit(const Corner& cube) {
    if (lattice_.contains(cube) && visited_.insert(cube).second) queue_.push(cube);
  }
  std::optional<double> value(const Corner& corner) {
    const auto found = values_.find(corner);
    if (found != values_.end()) return found->second;
    return values_[corner] = f_(lattice_.position(corner));
  }
  // A cube: its configuration, its triangles, and the faces that lead on.
  void contour(const Corner& cube) {
    std::array<double, 8> v{};
    unsigned inside = 0, zero = 0;
    for (int c = 0; c < 8; ++c) {
      const std::optional<double> fc = value(corner_of(cube, c));
      if (!fc) return;  // undefined: nothing drawn, the walk stops here
      v[static_cast<std::size_t>(c)] = *fc;
      if (*fc < 0.0) inside |= 1u << c;
      if (*fc == 0.0) zero |= 1u << c;
    }
    emit(cube, mc::cube_case(inside), v);
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        unsigned face = 0;  // the corners on this face
        for (int c = 0; c < 8; ++c)
          if (((c >> a) & 1) == side) face |= 1u << c;
        if (((inside & face) != 0 && (inside & face) != face) || (zero & face) != 0) {
          Corner next = cube;
          next[static_cast<std::size_t>(a)] += side == 0 ? -1 : 1;
          visit(next);
        }
      }
  }
  void emit(const Corner& cube, const mc::CubeCase& cube_case, const std::array<double, 8>& v) {
    std::array<std::uint32_t, 16> vertex{};  // per cube edge, then per loop centre
    for (int l = 0; l < cube_case.loop_count; ++l) {
      const auto& loop = cube_case.loops[static_cast<std::size_t>(l)];
      Vec3 centre = Vec3::Zero();
      for (int j = 0; j < loop.size; ++j) {
        const int e = loop.edges[static_cast<std::size_t>(j)];
        vertex[static_cast<std::size_t>(e)] = edge_vertex(cube, e, v);
        centre += mesh_.vertices[vertex[static_cast<std::size_t>(e)]];
      }
      if (loop.centred) {
        vertex[static_cast<std::size_t>(mc::loop_centre + l)] = static_cast<std::uint32_t>(mesh_.vertices.size());
        mesh_.vertices.push_back(centre / loop.size);
      }
    }
    for (int t = 0; t < cube_case.triangle_count; ++t) {
      const auto& tri = cube_case.triangles[static_cast<std::size_t>(t)];
      mesh_.triangles.push_back({vertex[tri[0]], vertex[tri[1]], vertex[tri[2]]});
    }
  }
  // The vertex on cube edge e, made once per lattice edge (keyed by its
  // lower corner and axis).
  std::uint32_t edge_vertex(const Corner& cube, int e, const std::array<double, 8>& v) {
    const auto ends = mc::edge_corners(e);
    const int axis = mc::edge_axis(e);
    const Corner low = corner_of(cube, ends[0]);
    auto& edges = edge_vertices_[static_cast<std::size_t>(axis)];
    if (const auto found = edges.find(low); found != edges.end()) return found->second;
    const double v0 = v[static_cast<std::size_t>(ends[0])], v1 = v[static_cast<std::size_t>(ends[1])];
    const double t = std::clamp(v0 / (v0 - v1), 1e-3, 1.0 - 1e-3);
    Vec3 p = lattice_.position(low);
    p[axis] += t * lattice_.cell;
    mesh_.vertices.push_back(p);
    return edges[low] = static_cast<std::uint32_t>(mesh_.vertices.size() - 1);
  }

  const SignedDistance& f_;
  const Lattice<3>& lattice_;
  std::unordered_map<Corner, std::optional<double>, CornerHash> values_;
  std::unordered_set<Corner, CornerHash> visited_;
  std::array<std::unordered_map<Corner, std::uint32_t, CornerHash>, 3> edge_vertices_;
  std::queue<Corner> queue_;
  Mesh mesh_;
};

void check(std::span<const Vec3> points, const Options& options) {
  if (options.k < 3) throw InvalidInputError("reference::reconstruct: k must be at least 3");
  if (points.size() < static_cast<std::size_t>(options.k))
    throw InvalidInputError("reference::reconstruct: fewer points than k");
  if (!(options.rho > 0.0) || !(options.cell > 0.0) || !(options.delta >= 0.0))
    throw InvalidInputError("reference::reconstruct: rho and cell must be positive, delta not negative");
}

}  // namespace

Result reconstruct(std::span<const Vec3> points, const Options& options) {
  check(points, options);
  Result result;
  Planes planes = tangent_planes(points, options.k);                    // I
  result.emst = complete_graph_minimum_spanning_tree<3>(points).edges;  // II
  result.graph = riemannian_graph(planes, result.emst);
  orient(planes, result.graph, result);
  const SignedDistance f{points, planes, options.rho, options.delta};        // III
  result.mesh = Walk(f, make_lattice<3>(points, options.cell)).run(points);  // IV
  result.origins = std::move(planes.origins);
  result.normals = std::move(planes.normals);
  return result;
}

ReconstructionOptions plain_options(const Options& options) {
  ReconstructionOptions plain;
  plain.method = Method::hoppe92;
  plain.planes.k = options.k;
  plain.planes.adapt_k = false;
  plain.planes.rho = options.rho;
  plain.orientation.vote_rounds = 0;
  plain.orientation.graph.gap_factor = std::numeric_limits<double>::infinity();  // no gaps: one object
  plain.distance.delta = options.delta;
  plain.distance.candidates = 1;
  plain.cell = options.cell;
  return plain;
}

}  // namespace recon::reference
