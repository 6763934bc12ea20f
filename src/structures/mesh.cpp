// Topology of an indexed triangle mesh.
//
// Choices beyond the field descriptions in mesh.h:
// - A triangle with a repeated vertex index ("collapsed") is counted in
//   `triangles` and `degenerate_triangles` and otherwise left out: it adds no
//   edges, no vertices, nothing to the Euler characteristic, area or volume.
//   `vertices`, `edges`, `euler_characteristic` and the components are those
//   of the remaining triangles.
// - A triangle with three distinct corners is also degenerate when its area
//   is at most 1e-14 * d^2, d the diagonal of the bounding box of the used
//   vertices: about a hundred times the rounding error of a cross product of
//   edges as long as the box, so only numerically flat triangles are flagged.
//   Such triangles still count in the topology (they are topologically sound).
// - Components are sets of triangles connected through shared edges (two
//   triangles that share only a vertex are in different components), listed
//   largest first (ties: the one with the lower first triangle index first).
//   A vertex shared by two components counts in both per-component Euler
//   characteristics but once in the global one.
// - An edge is inconsistent when exactly two triangles use it and traverse it
//   in the same direction; an edge of three or more triangles is counted as
//   non-manifold only.
// - Boundary loops are the connected components of the graph of boundary
//   edges, so two holes touching at one vertex count as one loop.
// - Volumes are signed tetrahedron volumes taken from the centre of the
//   bounding box rather than the origin (the same sum for a closed surface,
//   but without the cancellation a far-away origin causes).

#include "recon/structures/mesh.h"

#include "recon/core/errors.h"
#include "recon/structures/union_find.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <string>

namespace recon {
namespace {

struct HalfEdge {
  std::uint64_t key;  ///< smaller vertex in the high half, larger in the low half
  std::uint32_t triangle;
  bool forward;  ///< traversed from the smaller to the larger vertex
};

constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();

// The bounding box of the used vertices; throws for an index past the end.
Box<3> used_vertex_box(const Mesh& mesh) {
  Box<3> box;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t v : mesh.triangles[t]) {
      if (v >= mesh.vertices.size())
        throw InvalidInputError("analyze_topology: triangle " + std::to_string(t) + " uses vertex " +
                                std::to_string(v) + ", but the mesh has " + std::to_string(mesh.vertices.size()) +
                                " vertices");
      box.extend(mesh.vertices[v]);
    }
  }
  return box;
}

// What step 1 learns of the triangles.
struct TriangleScan {
  std::vector<double> volume;         // per triangle: its signed volume from the centre
  std::vector<std::uint32_t> proper;  // triangles with three distinct corners
  std::vector<std::uint32_t> start;   // per vertex v: the first half-edge whose smaller vertex is v
};

// Step 1, per triangle: degenerate or not, area, volume, and its half-edges
// counted under their smaller vertex (the counting sort's first pass).
TriangleScan measure_triangles(const Mesh& mesh, const Box<3>& box, MeshTopology& topology) {
  const double diagonal = box.diagonal();
  const double flat_area = 1e-14 * diagonal * diagonal;
  const Vec3 centre = box.empty() ? Vec3::Zero() : Vec3(0.5 * (box.min + box.max));
  TriangleScan scan;
  scan.volume.assign(mesh.triangles.size(), 0.0);
  scan.proper.reserve(mesh.triangles.size());
  scan.start.assign(mesh.vertices.size() + 1, 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& [a, b, c] = mesh.triangles[t];
    if (a == b || b == c || c == a) {
      ++topology.degenerate_triangles;
      continue;
    }
    const Vec3 pa = mesh.vertices[a] - centre;
    const Vec3 pb = mesh.vertices[b] - centre;
    const Vec3 pc = mesh.vertices[c] - centre;
    const double area = 0.5 * (pb - pa).cross(pc - pa).norm();
    if (area <= flat_area) ++topology.degenerate_triangles;
    topology.area += area;
    scan.volume[t] = pa.dot(pb.cross(pc)) / 6.0;
    topology.signed_volume += scan.volume[t];
    scan.proper.push_back(static_cast<std::uint32_t>(t));
    ++scan.start[std::min(a, b) + 1];
    ++scan.start[std::min(b, c) + 1];
    ++scan.start[std::min(c, a) + 1];
  }
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) scan.start[v + 1] += scan.start[v];
  return scan;
}

// Step 2: the half-edges sorted by (key, triangle), by a counting sort on
// the smaller vertex (the key's high half), each vertex's few half-edges
// then ordered by insertion: linear time and one array, where a comparison
// sort of tens of millions took seconds.
std::vector<HalfEdge> sorted_half_edges(const Mesh& mesh, const TriangleScan& scan) {
  const std::vector<std::uint32_t>& start = scan.start;
  std::vector<HalfEdge> half_edges(start.back());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (const std::uint32_t id : scan.proper) {
    const auto& [a, b, c] = mesh.triangles[id];
    half_edges[fill[std::min(a, b)]++] = {edge_key(a, b), id, a < b};
    half_edges[fill[std::min(b, c)]++] = {edge_key(b, c), id, b < c};
    half_edges[fill[std::min(c, a)]++] = {edge_key(c, a), id, c < a};
  }
  auto before = [](const HalfEdge& x, const HalfEdge& y) {
    return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
  };
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    for (std::uint32_t i = start[v] + 1; i < start[v + 1]; ++i)
      for (std::uint32_t j = i; j > start[v] && before(half_edges[j], half_edges[j - 1]); --j)
        std::swap(half_edges[j], half_edges[j - 1]);
  return half_edges;
}

// What step 3 learns of the edges.
struct EdgeScan {
  UnionFind triangle_sets;                       // triangles joined through their edges
  std::vector<std::uint64_t> boundary;           // keys of the boundary edges
  std::vector<std::uint32_t> boundary_triangle;  // and their triangles
  std::vector<std::uint32_t> edge_triangle;      // one triangle of each edge
};

// Step 3, per edge (a run of half-edges with one key): classify it, and
// join the triangles around it into one component.
EdgeScan classify_edges(const std::vector<HalfEdge>& half_edges, std::size_t triangles, MeshTopology& topology) {
  EdgeScan scan{UnionFind(triangles), {}, {}, {}};
  for (std::size_t i = 0; i < half_edges.size();) {
    std::size_t end = i + 1;
    while (end < half_edges.size() && half_edges[end].key == half_edges[i].key) ++end;
    const std::size_t uses = end - i;
    ++topology.edges;
    scan.edge_triangle.push_back(half_edges[i].triangle);
    if (uses == 1) {
      ++topology.boundary_edges;
      scan.boundary.push_back(half_edges[i].key);
      scan.boundary_triangle.push_back(half_edges[i].triangle);
    } else if (uses == 2 && half_edges[i].forward == half_edges[i + 1].forward) {
      ++topology.inconsistent_edges;
    } else if (uses >= 3) {
      ++topology.non_manifold_edges;
    }
    for (std::size_t k = i + 1; k < end; ++k) scan.triangle_sets.unite(half_edges[i].triangle, half_edges[k].triangle);
    i = end;
  }
  return scan;
}

// Step 4: the components numbered largest first (ties: the one with the
// lower first triangle first).
struct Components {
  std::size_t count = 0;
  std::vector<std::uint32_t> of_root;    // per triangle that is a root of the union-find: its component
  std::vector<std::uint32_t> of_proper;  // per proper triangle (in TriangleScan::proper's order): its component
};

Components number_components(const TriangleScan& scan, UnionFind& sets, std::size_t triangles) {
  Components components;
  std::vector<std::uint32_t>& root_of = components.of_proper;  // roots first, numbered below
  root_of.resize(scan.proper.size());
  for (std::size_t k = 0; k < scan.proper.size(); ++k) root_of[k] = sets.find(scan.proper[k]);
  std::vector<std::uint32_t> roots;  // in order of their first triangle
  std::vector<bool> seen(triangles, false);
  for (const std::uint32_t r : root_of) {
    if (!seen[r]) {
      seen[r] = true;
      roots.push_back(r);
    }
  }
  std::stable_sort(roots.begin(), roots.end(),
                   [&](std::uint32_t x, std::uint32_t y) { return sets.set_size(x) > sets.set_size(y); });
  components.count = roots.size();
  components.of_root.assign(triangles, none);
  for (std::size_t k = 0; k < roots.size(); ++k) components.of_root[roots[k]] = static_cast<std::uint32_t>(k);
  for (std::uint32_t& r : root_of) r = components.of_root[r];
  return components;
}

// Step 5: per component, its triangles, volume, vertices, edges, boundary
// edges and Euler characteristic; and the vertices used at all. Distinct
// (component, vertex) pairs: a vertex is nearly always in one component,
// noted in first_component; the rare others go to a short list that is
// sorted.
void measure_components(const Mesh& mesh, const TriangleScan& triangles, EdgeScan& edges, const Components& components,
                        MeshTopology& topology) {
  const std::vector<std::uint32_t>& component = components.of_proper;
  std::vector<long> component_edges(topology.components, 0);
  std::vector<long> component_vertices(topology.components, 0);
  std::vector<std::uint32_t> first_component(mesh.vertices.size(), none);
  std::vector<std::uint64_t> also;  // (component << 32) | vertex, beyond the first component
  for (std::size_t k = 0; k < triangles.proper.size(); ++k) {
    MeshTopology::Component& entry = topology.component_list[component[k]];
    ++entry.triangles;
    entry.signed_volume += triangles.volume[triangles.proper[k]];
    for (const std::uint32_t v : mesh.triangles[triangles.proper[k]]) {
      if (first_component[v] == none) {
        first_component[v] = component[k];
        ++component_vertices[component[k]];
      } else if (first_component[v] != component[k]) {
        also.push_back((std::uint64_t{component[k]} << 32) | v);
      }
    }
  }
  std::sort(also.begin(), also.end());
  also.erase(std::unique(also.begin(), also.end()), also.end());
  for (const std::uint64_t entry : also) ++component_vertices[entry >> 32];

  const std::vector<std::uint32_t>& of_root = components.of_root;
  for (const std::uint32_t t : edges.edge_triangle) ++component_edges[of_root[edges.triangle_sets.find(t)]];
  for (const std::uint32_t t : edges.boundary_triangle)
    ++topology.component_list[of_root[edges.triangle_sets.find(t)]].boundary_edges;
  for (std::size_t c = 0; c < topology.components; ++c) {
    MeshTopology::Component& entry = topology.component_list[c];
    entry.euler_characteristic = component_vertices[c] - component_edges[c] + static_cast<long>(entry.triangles);
  }
  topology.vertices = static_cast<std::size_t>(
      std::count_if(first_component.begin(), first_component.end(), [](std::uint32_t c) { return c != none; }));
}

// Step 6: boundary loops, the connected pieces of the boundary-edge graph.
std::size_t count_boundary_loops(const std::vector<std::uint64_t>& boundary) {
  if (boundary.empty()) return 0;
  std::vector<std::uint32_t> ends;
  ends.reserve(2 * boundary.size());
  for (const std::uint64_t key : boundary) {
    ends.push_back(static_cast<std::uint32_t>(key >> 32));
    ends.push_back(static_cast<std::uint32_t>(key));
  }
  std::sort(ends.begin(), ends.end());
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  const auto local = [&ends](std::uint32_t v) {
    return static_cast<std::uint32_t>(std::lower_bound(ends.begin(), ends.end(), v) - ends.begin());
  };
  UnionFind loops(ends.size());
  for (const std::uint64_t key : boundary)
    loops.unite(local(static_cast<std::uint32_t>(key >> 32)), local(static_cast<std::uint32_t>(key)));
  return loops.set_count();
}

}  // namespace

MeshTopology analyze_topology(const Mesh& mesh) {
  MeshTopology topology;
  topology.triangles = mesh.triangles.size();
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    throw InvalidInputError("analyze_topology: more than 2^32 - 1 triangles");
  const Box<3> box = used_vertex_box(mesh);
  const TriangleScan triangles = measure_triangles(mesh, box, topology);
  EdgeScan edges = classify_edges(sorted_half_edges(mesh, triangles), mesh.triangles.size(), topology);
  const Components components = number_components(triangles, edges.triangle_sets, mesh.triangles.size());
  topology.components = components.count;
  topology.component_list.resize(components.count);
  measure_components(mesh, triangles, edges, components, topology);
  topology.euler_characteristic = static_cast<long>(topology.vertices) - static_cast<long>(topology.edges) +
                                  static_cast<long>(triangles.proper.size());
  topology.boundary_loops = count_boundary_loops(edges.boundary);
  return topology;
}

std::vector<std::array<std::uint32_t, 2>> boundary_edges(const Mesh& mesh) {
  // Directed edges keyed by their undirected pair; a key met once is a
  // boundary edge.
  std::vector<std::pair<std::uint64_t, std::array<std::uint32_t, 2>>> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = t[static_cast<std::size_t>(c)], b = t[static_cast<std::size_t>((c + 1) % 3)];
      edges.push_back({edge_key(a, b), {a, b}});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<std::array<std::uint32_t, 2>> boundary;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    if (j == i + 1) boundary.push_back(edges[i].second);
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());
  return boundary;
}

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

}  // namespace recon
