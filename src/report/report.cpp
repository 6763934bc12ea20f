#include "recon/report/report.h"

#include "recon/core/detail/float_chars.h"

#include "recon/core/errors.h"
#include "recon/core/version.h"
#include "recon/io/atomic_file.h"
#include "recon/reconstruct.h"
#include "recon/structures/mesh.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

namespace recon {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the report stores little-endian arrays as they lie in memory");

// Every stride-th element of n so that at most `budget` are taken.
std::size_t stride_for(std::size_t n, std::size_t budget) {
  if (budget == 0) return n + 1;  // nothing drawn
  return n <= budget ? 1 : (n + budget - 1) / budget;
}

void push(std::vector<float>& out, const Vec3& p) {
  out.push_back(static_cast<float>(p.x()));
  out.push_back(static_cast<float>(p.y()));
  out.push_back(static_cast<float>(p.z()));
}

void push_normal(std::vector<std::int8_t>& out, const Vec3& n) {
  for (int c = 0; c < 3; ++c) out.push_back(static_cast<std::int8_t>(std::lround(127.0 * std::clamp(n[c], -1.0, 1.0))));
}

void push_segment(std::vector<float>& out, const Vec3& a, const Vec3& b) {
  push(out, a);
  push(out, b);
}

void add_kdtree(const KdTree<3>& tree, const Vec3& centre, int max_depth, ReportLayers& layers) {
  layers.kdtree_depth = tree.depth();
  layers.kdtree_drawn_depth = std::min(max_depth, tree.depth());
  const auto& nodes = tree.nodes();
  const auto& boxes = tree.boxes();
  if (nodes.empty()) return;
  // Pre-order walk with an explicit stack of (node, depth).
  std::vector<std::pair<std::uint32_t, int>> stack{{0u, 0}};
  while (!stack.empty()) {
    const auto [id, depth] = stack.back();
    stack.pop_back();
    const auto& node = nodes[id];
    push(layers.kdtree_boxes, boxes[id].min - centre);
    push(layers.kdtree_boxes, boxes[id].max - centre);
    const bool shallow_leaf = node.is_leaf() && depth < layers.kdtree_drawn_depth;
    layers.kdtree_level.push_back(static_cast<std::uint8_t>(depth + (shallow_leaf ? 128 : 0)));
    if (!node.is_leaf() && depth < layers.kdtree_drawn_depth) {
      stack.emplace_back(node.right, depth + 1);
      stack.emplace_back(node.left, depth + 1);
    }
  }
}

// A graph's edges as layer 4 draws them: those of every sv-th vertex (its
// whole row: about k edges), an edge between two such vertices once. sv is
// at least the points' stride, so that the edges drawn start at drawn
// points, and grows from the average row until the edges fit the budget, in
// multiples of the points' stride. Point i is drawn at points[i] + shift.
void draw_edges(const Graph& g, std::span<const Vec3> points, const Vec3& shift, std::size_t point_stride,
                std::size_t max_edges, ReportGraph& out) {
  const std::size_t n = points.size();
  const auto drawn = [&](std::size_t sv, auto&& edge) {
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; i += sv)
      for (const std::uint32_t j : g.neighbors(static_cast<std::uint32_t>(i)))
        if (j % sv != 0 || j > i) {
          ++count;
          edge(i, j);
        }
    return count;
  };
  out.edges_total = g.edge_count();
  const std::size_t row = n > 0 ? std::max<std::size_t>(1, 2 * g.edge_count() / n) : 1;
  const std::size_t ps = point_stride;
  const auto multiple = [ps](std::size_t s) { return (s + ps - 1) / ps * ps; };
  // At stride 1 every edge is drawn once; beyond, a drawn vertex brings
  // about its whole row.
  std::size_t sv = g.edge_count() <= max_edges ? ps : multiple(std::max(ps, stride_for(n, max_edges / row)));
  while (sv <= n && drawn(sv, [](std::size_t, std::size_t) {}) > max_edges)
    sv = multiple(sv + std::max<std::size_t>(1, sv / 8));
  out.vertex_stride = sv;
  drawn(sv, [&](std::size_t i, std::size_t j) { push_segment(out.segments, points[i] + shift, points[j] + shift); });
}

// The spanning tree: the edge from each drawn point to its parent, marked
// where the orientation turned across it, and the flips of the whole tree.
void draw_tree(const OrientedNormals<3>& o, std::span<const Vec3> points, const Vec3& shift, std::size_t point_stride,
               ReportGraph& out) {
  const auto& parent = o.tree.parent;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (parent[i] == SpanningForest::no_parent) continue;
    ++out.tree_edges_total;
    const bool flip = o.flipped[i] != o.flipped[parent[i]];
    out.tree_flips_total += flip ? 1 : 0;
    if (i % point_stride != 0) continue;
    push_segment(out.tree_segments, points[i] + shift, points[parent[i]] + shift);
    out.tree_flip.push_back(flip ? 1 : 0);
  }
}

// Precondition: o's graph, tree and signs have one entry per point.
ReportGraph draw_graph(const OrientedNormals<3>& o, std::span<const Vec3> points, const Vec3& shift,
                       std::size_t point_stride, std::size_t max_edges) {
  ReportGraph out;
  draw_edges(o.graph.graph, points, shift, point_stride, max_edges, out);
  draw_tree(o, points, shift, point_stride, out);
  return out;
}

bool has_whole_graph(const OrientedNormals<3>& o, std::size_t n) {
  return o.graph.graph.vertex_count() == n && o.tree.parent.size() == n && o.flipped.size() == n;
}

void add_graph(const ReportInput& in, const ReportOptions& options, ReportLayers& layers) {
  if (!has_whole_graph(*in.oriented, in.points.size())) return;  // graph released
  layers.has_graph = true;
  const Vec3 shift = in.offset - layers.centre;
  layers.graph = draw_graph(*in.oriented, in.points, shift, layers.point_stride, options.max_edges);
}

void add_corners(const MarchingCubesResult& c, const ReportInput& in, const ReportOptions& options,
                 ReportLayers& layers) {
  layers.cell = c.cell;
  layers.corners_total = c.evaluated_corners;
  layers.undefined_corners_total = c.undefined_corners;
  if (c.corners.empty()) return;  // not kept
  layers.has_corners = true;
  layers.corner_stride = stride_for(c.corners.size(), options.max_corners);
  const Vec3 shift = c.origin + in.offset - layers.centre;
  for (std::size_t i = 0; i < c.corners.size(); i += layers.corner_stride) {
    const LatticeCorner& corner = c.corners[i];
    const Vec3 position(corner.index[0], corner.index[1], corner.index[2]);
    push(layers.corners, shift + c.cell * position);
    layers.corner_values.push_back(corner.defined ? static_cast<float>(corner.value)
                                                  : std::numeric_limits<float>::quiet_NaN());
  }
}

// The drawn triangles of `mesh` (every stride-th), with their vertices
// relative to `centre`; returns the mesh's index of each drawn vertex.
std::vector<std::uint32_t> add_triangles(const Mesh& mesh, std::size_t budget, const Vec3& centre, ReportMesh& out) {
  out.triangles_total = mesh.triangles.size();
  out.triangle_stride = stride_for(mesh.triangles.size(), budget);
  std::vector<std::uint32_t> source;
  if (out.triangle_stride == 1) {
    source.resize(mesh.vertices.size());
    for (std::uint32_t v = 0; v < source.size(); ++v) source[v] = v;
    for (const auto& t : mesh.triangles) out.triangles.insert(out.triangles.end(), t.begin(), t.end());
  } else {
    // Only the vertices of the drawn triangles, renumbered in order of use.
    constexpr std::uint32_t unused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> renumbered(mesh.vertices.size(), unused);
    for (std::size_t t = 0; t < mesh.triangles.size(); t += out.triangle_stride)
      for (const std::uint32_t v : mesh.triangles[t]) {
        if (renumbered[v] == unused) {
          renumbered[v] = static_cast<std::uint32_t>(source.size());
          source.push_back(v);
        }
        out.triangles.push_back(renumbered[v]);
      }
  }
  out.vertices.reserve(3 * source.size());
  for (const std::uint32_t v : source) push(out.vertices, mesh.vertices[v] - centre);
  if (mesh.has_colors()) {
    if (mesh.colors.size() != mesh.vertices.size())
      throw InvalidInputError("report: a mesh has " + std::to_string(mesh.colors.size()) + " colours for " +
                              std::to_string(mesh.vertices.size()) + " vertices");
    out.colors.reserve(3 * source.size());
    for (const std::uint32_t v : source)
      out.colors.insert(out.colors.end(), mesh.colors[v].begin(), mesh.colors[v].end());
  }
  return source;
}

void add_boundary(const Mesh& mesh, std::size_t budget, const Vec3& centre, ReportMesh& out) {
  const auto boundary = boundary_edges(mesh);
  out.boundary_edges_total = boundary.size();
  out.boundary_stride = stride_for(boundary.size(), budget);
  for (std::size_t e = 0; e < boundary.size(); e += out.boundary_stride)
    push_segment(out.boundary_segments, mesh.vertices[boundary[e][0]] - centre, mesh.vertices[boundary[e][1]] - centre);
}

// Distances from points to the surface of a mesh (its triangles). The
// nearest point q lies on some triangle, and every point of a triangle lies
// within L / sqrt 3 of one of its vertices, L its longest edge (the
// equilateral triangle's centre is the worst case; an obtuse triangle's
// worst points lie on its edges, within L / 2). So, with d an upper bound
// (the distance to the triangles around the nearest vertex), only the
// triangles around the vertices within d + L / sqrt 3 can hold q: they are
// measured, nearest first, until the vertices lie farther than the best
// distance found + L / sqrt 3.
class MeshDistance {
 public:
  explicit MeshDistance(const Mesh& mesh) : mesh_(mesh) {
    std::vector<std::uint32_t> count(mesh.vertices.size() + 1, 0);
    double longest = 0.0;  // L
    for (const auto& t : mesh.triangles) {
      for (const std::uint32_t v : t) ++count[v + 1];
      for (std::size_t c = 0; c < 3; ++c)
        longest = std::max(longest, (mesh.vertices[t[c]] - mesh.vertices[t[(c + 1) % 3]]).norm());
    }
    std::vector<Vec3> used;  // vertices of some triangle: an unused one bounds nothing
    for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v)
      if (count[v + 1] > 0) {
        used.push_back(mesh.vertices[v]);
        used_id_.push_back(v);
      }
    for (std::size_t v = 1; v < count.size(); ++v) count[v] += count[v - 1];
    first_ = count;
    around_.resize(3 * mesh.triangles.size());
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
      for (const std::uint32_t v : mesh.triangles[t]) around_[count[v]++] = t;
    tree_ = KdTree<3>(used);
    cover_ = 0.58 * longest;  // 1 / sqrt 3 = 0.5774
  }

  /// NaN when the mesh has no triangle.
  [[nodiscard]] double operator()(const Vec3& p) const {
    if (tree_.empty()) return std::numeric_limits<double>::quiet_NaN();
    double best = around(used_id_[tree_.nearest(p).index], p, std::numeric_limits<double>::infinity());
    const double reach = best + cover_;
    for (const Neighbor& n : tree_.radius(p, reach * reach)) {
      if (std::sqrt(n.distance2) > best + cover_) break;
      best = around(used_id_[n.index], p, best);
    }
    return best;
  }

 private:
  // The least of `best` and the distances from p to the triangles around vertex v.
  [[nodiscard]] double around(std::uint32_t v, const Vec3& p, double best) const {
    for (std::uint32_t i = first_[v]; i < first_[v + 1]; ++i) {
      const auto& t = mesh_.triangles[around_[i]];
      best =
          std::min(best, point_triangle_distance(p, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]));
    }
    return best;
  }

  const Mesh& mesh_;
  double cover_ = 0.0;                         // L / sqrt 3 (see above), with a margin for rounding
  std::vector<std::uint32_t> used_id_;         // the mesh's index of each tree point
  std::vector<std::uint32_t> first_, around_;  // the triangles around vertex v: around_[first_[v] .. first_[v + 1])
  KdTree<3> tree_;
};

void add_refinement(const Mesh& refined, const Mesh& contoured, std::size_t budget, const ReportOptions& options,
                    ReportLayers& layers) {
  layers.has_refinement = true;
  const std::vector<std::uint32_t> source = add_triangles(refined, budget, layers.centre, layers.refined);
  add_boundary(refined, options.max_boundary_edges, layers.centre, layers.refined);
  const MeshDistance distance(contoured);
  layers.refined_distance.reserve(source.size());
  double sum = 0.0;
  for (const std::uint32_t v : source) {
    const double d = distance(refined.vertices[v]);
    layers.refined_distance.push_back(static_cast<float>(d));
    sum += d;
    layers.distance_max = std::max(layers.distance_max, d);
  }
  if (source.empty()) return;
  layers.distance_mean = sum / static_cast<double>(source.size());
  std::vector<float> sorted = layers.refined_distance;
  const std::size_t at = std::min(sorted.size() - 1, sorted.size() * 98 / 100);
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(at), sorted.end());
  layers.distance_scale = static_cast<double>(sorted[at]);
}

void extend(Box<3>& box, const std::vector<float>& xyz) {
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    box.extend(Vec3(static_cast<double>(xyz[i]), static_cast<double>(xyz[i + 1]), static_cast<double>(xyz[i + 2])));
}

// Everything drawn: the points (the kd-tree's cells and the planes lie
// within a sample spacing of them), the corners and the meshes.
Box<3> drawn_box(const ReportLayers& layers) {
  Box<3> box;
  for (const auto* xyz : {&layers.points, &layers.corners, &layers.mesh.vertices, &layers.refined.vertices})
    extend(box, *xyz);
  return box;
}

// ---- writing

void append_base64(std::string& out, const void* data, std::size_t bytes) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* b = static_cast<const unsigned char*>(data);
  out.reserve(out.size() + (bytes + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes; i += 3) {
    const unsigned v = (unsigned{b[i]} << 16) | (unsigned{b[i + 1]} << 8) | b[i + 2];
    out += digits[v >> 18];
    out += digits[(v >> 12) & 63];
    out += digits[(v >> 6) & 63];
    out += digits[v & 63];
  }
  if (i < bytes) {
    const unsigned v = (unsigned{b[i]} << 16) | (i + 1 < bytes ? unsigned{b[i + 1]} << 8 : 0u);
    out += digits[v >> 18];
    out += digits[(v >> 12) & 63];
    out += i + 1 < bytes ? digits[(v >> 6) & 63] : '=';
    out += '=';
  }
}

// A small writer for the data block: keys and values in order, no indentation.
class JsonWriter {
 public:
  explicit JsonWriter(std::string& out) : out_(out) {}
  void open(std::string_view key) { begin(key, '{'); }
  void close() { end('}'); }
  // A list; its elements are opened with an empty key.
  void open_list(std::string_view key) { begin(key, '['); }
  void close_list() { end(']'); }
  void number(std::string_view k, double v) {
    key(k);
    if (!std::isfinite(v)) {
      out_ += "null";
      return;
    }
    append(v);
  }
  void count(std::string_view k, std::size_t v) { number(k, static_cast<double>(v)); }
  void string(std::string_view k, std::string_view v) {
    key(k);
    out_ += '"';
    for (const char c : v) {
      if (c == '"' || c == '\\') {
        out_ += '\\';
        out_ += c;
      } else if (static_cast<unsigned char>(c) < 0x20) {
        char buffer[8];
        std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(c));
        out_ += buffer;
      } else {
        out_ += c;
      }
    }
    out_ += '"';
  }
  // A binary array goes into its own element after the JSON (see
  // report_html); the JSON holds its number.
  template <class T>
  void array(std::string_view k, const std::vector<T>& v) {
    key(k);
    char buffer[24];
    out_.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, arrays_.size()).ptr);
    arrays_.push_back({v.data(), v.size() * sizeof(T)});
  }
  struct Bytes {
    const void* data;
    std::size_t size;
  };
  [[nodiscard]] const std::vector<Bytes>& arrays() const { return arrays_; }
  void raw(std::string_view k, std::string_view json) {
    key(k);
    out_ += json;
  }
  void vec(std::string_view k, const Vec3& v) {
    key(k);
    out_ += '[';
    for (int i = 0; i < 3; ++i) {
      if (i > 0) out_ += ',';
      append(v[i]);
    }
    out_ += ']';
  }

 private:
  // An object's or a list's brackets: what follows the opening one is its first member.
  void begin(std::string_view k, char bracket) {
    key(k);
    out_ += bracket;
    first_ = true;
  }
  void end(char bracket) {
    out_ += bracket;
    first_ = false;
  }
  // A finite number, shortest round-trip form.
  void append(double v) {
    char buffer[32];
    out_.append(buffer, detail::float_to_chars(buffer, buffer + sizeof buffer, v).ptr);
  }
  void key(std::string_view k) {
    if (!first_) out_ += ',';
    first_ = false;
    if (k.empty()) return;
    out_ += '"';
    out_ += k;
    out_ += "\":";
  }
  std::string& out_;
  bool first_ = true;
  std::vector<Bytes> arrays_;
};

// A mesh layer's figures and arrays, inside the object the caller opened.
void write_mesh(JsonWriter& w, const ReportMesh& mesh) {
  w.count("triangles_total", mesh.triangles_total);
  w.count("stride", mesh.triangle_stride);
  w.count("drawn", mesh.triangles.size() / 3);
  w.count("boundary_drawn", mesh.boundary_segments.size() / 6);
  w.array("vertices", mesh.vertices);
  w.array("triangles", mesh.triangles);
  if (!mesh.colors.empty()) w.array("colors", mesh.colors);
  w.count("boundary_total", mesh.boundary_edges_total);
  w.count("boundary_stride", mesh.boundary_stride);
  w.array("boundary", mesh.boundary_segments);
}

// The box the first view frames (a point at the centre when nothing is drawn).
void write_drawn_box(JsonWriter& w, const Box<3>& box) {
  w.open("drawn_box");
  w.vec("min", box.empty() ? Vec3::Zero() : box.min);
  w.vec("max", box.empty() ? Vec3::Zero() : box.max);
  w.close();
}

// Layers 6, 7 and 8; each mesh layer has the triangle budget to itself.
void add_surfaces(const ReportInput& in, const ReportOptions& options, ReportLayers& layers) {
  add_corners(*in.contour, in, options, layers);
  const Mesh& contoured = in.mesh != nullptr ? *in.mesh : in.contour->mesh;
  layers.has_mesh = true;
  add_triangles(contoured, options.max_triangles, layers.centre, layers.mesh);
  add_boundary(contoured, options.max_boundary_edges, layers.centre, layers.mesh);
  if (in.refinement != nullptr) add_refinement(in.refinement->mesh, contoured, options.max_triangles, options, layers);
}

// ---- the lab panel

void check_lab_graph(const LabGraph& g, std::size_t n) {
  const OrientedNormals<3>& o = g.oriented;
  if (has_whole_graph(o, n) && o.graph.components.label.size() == n) return;
  throw InvalidInputError("report: the lab's " + std::string(name_of(g.kind)) + " graph has " +
                          std::to_string(o.graph.graph.vertex_count()) + " vertices, " +
                          std::to_string(o.tree.parent.size()) + " tree entries, " + std::to_string(o.flipped.size()) +
                          " signs and " + std::to_string(o.graph.components.label.size()) +
                          " component labels; the report has " + std::to_string(n) + " points");
}

ReportLabGraph lab_graph(const LabGraph& g, std::span<const Vec3> points, const Vec3& shift, const ReportLayers& layers,
                         const ReportOptions& options) {
  const OrientedNormals<3>& o = g.oriented;
  ReportLabGraph out;
  out.name = name_of(g.kind);
  out.drawn = draw_graph(o, points, shift, layers.point_stride, options.max_edges);
  out.component_count = o.graph.components.sizes.size();
  for (std::size_t i = 0; i < points.size(); i += layers.point_stride)
    out.component.push_back(o.graph.components.label[i]);
  out.flips = static_cast<std::size_t>(std::count(o.flipped.begin(), o.flipped.end(), std::uint8_t{1}));
  return out;
}

}  // namespace

ReportLab make_report_lab(std::span<const LabGraph> graphs, std::string runs_json, std::span<const Vec3> points,
                          Vec3 offset, const ReportLayers& layers, const ReportOptions& options) {
  const std::size_t n = points.size();
  if (n != layers.points_total)
    throw InvalidInputError("report: the lab has " + std::to_string(n) + " points but the layers were made from " +
                            std::to_string(layers.points_total));
  for (const LabGraph& g : graphs) check_lab_graph(g, n);
  ReportLab lab;
  lab.runs_json = runs_json.empty() ? std::string("{}") : std::move(runs_json);
  for (const LabGraph& g : graphs) lab.graphs.push_back(lab_graph(g, points, offset - layers.centre, layers, options));
  return lab;
}

ReportInput report_input(const Reconstruction& r) {
  ReportInput in;
  in.points = r.points();
  in.offset = r.offset;
  in.planes = &r.planes;
  in.oriented = r.oriented ? &*r.oriented : nullptr;
  in.normals = r.normals();
  in.colors = r.colors;
  in.contour = &r.contour;
  in.refinement = r.refinement ? &*r.refinement : nullptr;
  return in;
}

ReportLayers make_report_layers(const ReportInput& in, const ReportOptions& options) {
  if (in.planes == nullptr) throw InvalidInputError("report: the tangent planes are required");
  const TangentPlanes<3>& planes = *in.planes;
  const std::size_t n = in.points.size();
  if (planes.origins.size() != n || planes.normals.size() != n || (in.normals.size() != n && !in.normals.empty()))
    throw InvalidInputError("report: " + std::to_string(n) + " points but " + std::to_string(planes.origins.size()) +
                            " planes and " + std::to_string(in.normals.size()) + " oriented normals");
  if (!in.colors.empty() && in.colors.size() != n)
    throw InvalidInputError("report: " + std::to_string(n) + " points but " + std::to_string(in.colors.size()) +
                            " colours");

  ReportLayers layers;
  const Box<3> box = bounding_box<3>(in.points);
  layers.centre = box.empty() ? in.offset : Vec3(0.5 * (box.min + box.max) + in.offset);
  layers.diagonal = box.diagonal();
  layers.rho = planes.rho;
  const auto p = [&](const Vec3& q) -> Vec3 { return q + in.offset - layers.centre; };

  layers.points_total = n;
  layers.point_stride = stride_for(n, options.max_points);
  const Components* components = in.oriented != nullptr && in.oriented->graph.components.label.size() == n
                                     ? &in.oriented->graph.components
                                     : nullptr;
  layers.component_count = components != nullptr ? std::max<std::size_t>(1, components->sizes.size()) : 1;
  for (std::size_t i = 0; i < n; i += layers.point_stride) {
    push(layers.points, p(in.points[i]));
    layers.component.push_back(components != nullptr ? components->label[i] : 0);
    push(layers.origins, p(planes.origins[i]));
    push_normal(layers.pca_normals, planes.normals[i]);
    layers.planarity.push_back(static_cast<float>(planes.surface_variation(i)));
    layers.no_plane.push_back(planes.local_rho[i] > 0.0F ? 0 : 1);
    if (!in.normals.empty()) {
      push_normal(layers.normals, in.normals[i]);
      layers.flipped.push_back(planes.normals[i].dot(in.normals[i]) < 0.0 ? 1 : 0);
    }
    if (!in.colors.empty())
      layers.point_colors.insert(layers.point_colors.end(), in.colors[i].begin(), in.colors[i].end());
  }

  add_kdtree(planes.point_tree, layers.centre - in.offset, options.max_kdtree_depth, layers);
  if (in.oriented != nullptr) add_graph(in, options, layers);
  if (in.contour != nullptr) add_surfaces(in, options, layers);
  layers.drawn_box = drawn_box(layers);
  return layers;
}

namespace {

void write_points(JsonWriter& w, const ReportLayers& layers) {
  w.open("points");
  w.count("total", layers.points_total);
  w.count("stride", layers.point_stride);
  w.count("drawn", layers.points.size() / 3);
  w.count("components", layers.component_count);
  w.array("position", layers.points);
  w.array("component", layers.component);
  w.array("origin", layers.origins);
  w.array("pca_normal", layers.pca_normals);
  w.array("planarity", layers.planarity);
  w.array("no_plane", layers.no_plane);
  if (!layers.normals.empty()) {  // (none before phase II: the web page's view of phase I)
    w.array("normal", layers.normals);
    w.array("flipped", layers.flipped);
  }
  if (!layers.point_colors.empty()) w.array("color", layers.point_colors);
  w.close();

  w.open("kdtree");
  w.number("depth", layers.kdtree_depth);
  w.number("drawn_depth", layers.kdtree_drawn_depth);
  w.array("boxes", layers.kdtree_boxes);
  w.array("level", layers.kdtree_level);
  w.close();
}

// A graph and its tree as drawn: layer 4's keys, and each lab graph's.
void write_drawn_graph(JsonWriter& w, const ReportGraph& g) {
  w.count("edges_total", g.edges_total);
  w.count("vertex_stride", g.vertex_stride);
  w.count("drawn", g.segments.size() / 6);
  w.count("tree_drawn", g.tree_flip.size());
  w.array("segments", g.segments);
  w.count("tree_total", g.tree_edges_total);
  w.count("flips_total", g.tree_flips_total);
  w.array("tree_segments", g.tree_segments);
  w.array("tree_flip", g.tree_flip);
}

void write_graph(JsonWriter& w, const ReportLayers& layers) {
  w.open("graph");
  write_drawn_graph(w, layers.graph);
  w.close();
}

void write_corners(JsonWriter& w, const ReportLayers& layers) {
  w.open("corners");
  w.count("total", layers.corners_total);
  w.count("undefined_total", layers.undefined_corners_total);
  w.count("stride", layers.corner_stride);
  w.count("drawn", layers.corner_values.size());
  w.number("cell", layers.cell);
  w.array("position", layers.corners);
  w.array("value", layers.corner_values);
  w.close();
}

void write_refinement(JsonWriter& w, const ReportLayers& layers) {
  w.open("refinement");
  write_mesh(w, layers.refined);
  w.open("distance");
  w.array("value", layers.refined_distance);
  w.number("mean", layers.distance_mean);
  w.number("max", layers.distance_max);
  w.number("scale", layers.distance_scale);
  w.close();
  w.close();
}

// A lab graph: the keys of layer 4's (write_graph), its pieces and flips.
void write_lab_graph(JsonWriter& w, const ReportLabGraph& g) {
  w.open("");
  w.string("name", g.name);
  w.count("components", g.component_count);
  w.count("flips", g.flips);
  w.array("component", g.component);
  write_drawn_graph(w, g.drawn);
  w.close();
}

void write_lab(JsonWriter& w, const ReportLab& lab) {
  w.open("lab");
  w.raw("stats", lab.runs_json.empty() ? std::string_view("{}") : std::string_view(lab.runs_json));
  w.open_list("graphs");
  for (const ReportLabGraph& g : lab.graphs) write_lab_graph(w, g);
  w.close_list();
  w.close();
}

// The data block's JSON; its arrays are left in w.arrays(), in the order written.
void write_data(JsonWriter& w, const ReportLayers& layers, const ReportOptions& options) {
  w.open("");
  w.string("title", options.title);
  w.string("version", version());  // the page's footer: which recon drew it
  w.vec("centre", layers.centre);
  w.number("diagonal", layers.diagonal);
  w.number("rho", layers.rho);
  write_drawn_box(w, layers.drawn_box);
  w.raw("stats", options.stats_json.empty() ? std::string_view("{}") : std::string_view(options.stats_json));
  write_points(w, layers);
  if (layers.has_graph) write_graph(w, layers);
  if (layers.has_corners) write_corners(w, layers);
  if (layers.has_mesh) {
    w.open("mesh");
    write_mesh(w, layers.mesh);
    w.close();
  }
  if (layers.has_refinement) write_refinement(w, layers);
  if (layers.lab) write_lab(w, *layers.lab);  // last: the other arrays keep their numbers
  w.close();
}

}  // namespace

ReportData report_data(const ReportLayers& layers, const ReportOptions& options) {
  ReportData out;
  JsonWriter w(out.json);
  write_data(w, layers, options);
  for (const auto& a : w.arrays()) out.arrays.push_back({static_cast<const std::byte*>(a.data), a.size});
  return out;
}

namespace {

// The data block of the page: the JSON element and one base64 element per array.
std::string report_data_elements(const ReportLayers& layers, const ReportOptions& options) {
  std::string data;
  JsonWriter w(data);
  write_data(w, layers, options);

  std::size_t size = data.size() + 200;
  for (const auto& a : w.arrays()) size += (a.size + 2) / 3 * 4 + 80;
  std::string html;
  html.reserve(size);
  // The data: the JSON in one element, each array base64-encoded in its own
  // (the viewer decodes them straight from the page's text, and no large
  // JSON string is ever parsed). Inside <script>, "</script" or "<!--" would
  // end or confuse the element; '<' occurs in JSON only inside strings,
  // where \u003c means the same character.
  html += "<script id=\"recon-data\" type=\"application/json\">";
  for (const char c : data) {
    if (c == '<') {
      html += "\\u003c";
    } else {
      html += c;
    }
  }
  html += "</script>\n";
  for (std::size_t i = 0; i < w.arrays().size(); ++i) {
    html += "<script id=\"recon-array-" + std::to_string(i) + "\" type=\"application/octet-stream\">";
    append_base64(html, w.arrays()[i].data, w.arrays()[i].size);
    html += "</script>\n";
  }
  return html;
}

}  // namespace

std::string report_html(const ReportLayers& layers, const ReportOptions& options) {
  const ReportPage page = report_page();
  const std::string data = report_data_elements(layers, options);
  std::string html;
  html.reserve(page.head.size() + data.size() + page.tail.size());
  html += page.head;
  html += data;
  html += page.tail;
  return html;
}

void write_report(const std::filesystem::path& path, const ReportLayers& layers, const ReportOptions& options) {
  const std::string html = report_html(layers, options);
  io::AtomicFile file(path);
  file.stream().write(html.data(), static_cast<std::streamsize>(html.size()));
  file.commit();
}

}  // namespace recon
