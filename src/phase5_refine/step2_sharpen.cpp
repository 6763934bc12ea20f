// Phase V, step 2 (refinement.h): creases and corners. Ends projected past
// a crease brought back onto it, crease edges split on the line where the
// planes meet, corners snapped where three planes meet; then coincident
// vertices welded and slivers removed.
#include "phase5_refine/refinement_steps.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <unordered_set>

namespace recon::refinement_steps {

namespace {

// Step 2's test: whether the edge (a, b) crosses a crease. The ends'
// normals must differ by more than the crease angle and by more than twice
// what the curvature at either end turns a normal along the edge.
bool is_crease(const Projected& pr, const RefinementInput& in, std::uint32_t a, std::uint32_t b, double cos_crease) {
  const double cosine = std::abs(pr.normal[a].dot(pr.normal[b]));
  if (cosine >= cos_crease) return false;
  const Vec3 e = pr.point[b] - pr.point[a];
  const double turn =
      e.norm() * std::max(std::abs(curvature_along(in, pr.plane[a], e)), std::abs(curvature_along(in, pr.plane[b], e)));
  return std::acos(std::min(1.0, cosine)) > 2.0 * turn;
}

// The point of the line where the tangent planes at a and b meet nearest
// to `near`: x = near + s n_a + t n_b on both planes.
Vec3 on_crease_line(const Projected& pr, std::uint32_t a, std::uint32_t b, const Vec3& near) {
  const Vec3 &na = pr.normal[a], &nb = pr.normal[b];
  const double c = na.dot(nb);
  const double ra = na.dot(pr.point[a] - near), rb = nb.dot(pr.point[b] - near);
  const double det = 1.0 - c * c;
  return near + ((ra - c * rb) / det) * na + ((rb - c * ra) / det) * nb;
}

// The crease point of a crease edge: where the crease line passes nearest
// the edge's midpoint, if that lies within the edge.
std::optional<Vec3> crease_point(const Projected& pr, std::uint32_t a, std::uint32_t b) {
  const Vec3 &pa = pr.point[a], &pb = pr.point[b];
  const Vec3 e = pb - pa;
  const double length2 = e.squaredNorm();
  const Vec3 x = on_crease_line(pr, a, b, 0.5 * (pa + pb));
  const double along = (x - pa).dot(e) / length2;
  if (along < 0.02 || along > 0.98 || (x - (pa + along * e)).squaredNorm() > 0.25 * length2) return std::nullopt;
  return x;
}

}  // namespace

// Step 2a: an end of a crease edge that lies past the crease, on its own
// face's plane but outside the other face's half-space at a convex edge
// (inside it at a concave one), is moved onto the crease line, once.
std::size_t bring_back(Projected& pr, const Mesh& contoured, const RefinementInput& in, double cos_crease,
                       double max_move) {
  std::size_t moved = 0;
  auto check = [&](std::uint32_t a, std::uint32_t b) {
    if (pr.partner[a] != none) return;
    const Vec3 &na = pr.normal[a], &nb = pr.normal[b];
    // Convex or concave, from the planes' origins (samples of the faces:
    // a itself may be the one past the crease).
    const Vec3 between = in.origins[pr.plane[b]] - in.origins[pr.plane[a]];
    const bool convex = na.dot(between) < 0.0 && nb.dot(between) > 0.0;
    const bool concave = na.dot(between) > 0.0 && nb.dot(between) < 0.0;
    const double beyond = nb.dot(pr.point[a] - pr.point[b]);  // f of b's plane at a
    if (!((convex && beyond > 0.0) || (concave && beyond < 0.0))) return;
    const Vec3 x = on_crease_line(pr, a, b, pr.point[a]);
    if (max_move > 0.0 && (x - pr.point[a]).norm() > max_move) return;
    pr.point[a] = x;
    pr.partner[a] = b;
    ++moved;
  };
  for (const auto& t : contoured.triangles)
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t a = t[e], b = t[(e + 1) % 3];
      if (!is_crease(pr, in, a, b, cos_crease)) continue;
      check(a, b);
      check(b, a);
    }
  return moved;
}

namespace {

// Where the tangent planes at the projected vertices `on` meet, if they
// meet at a well-defined point within `reach` of `centre`.
std::optional<Vec3> corner_point(const Projected& pr, const std::array<std::uint32_t, 3>& on, const Vec3& centre,
                                 double reach) {
  Eigen::Matrix3d normals;
  Eigen::Vector3d offsets;
  for (std::size_t r = 0; r < 3; ++r) {
    normals.row(static_cast<Eigen::Index>(r)) = pr.normal[on[r]].transpose();
    offsets[static_cast<Eigen::Index>(r)] = pr.normal[on[r]].dot(pr.point[on[r]]);
  }
  if (std::abs(normals.determinant()) < 0.2) return std::nullopt;
  const Vec3 x = normals.partialPivLu().solve(offsets);
  if ((x - centre).norm() > reach) return std::nullopt;
  return x;
}

double longest_edge(const std::vector<Vec3>& x, const std::array<std::uint32_t, 3>& t) {
  return std::max({(x[t[0]] - x[t[1]]).norm(), (x[t[1]] - x[t[2]]).norm(), (x[t[2]] - x[t[0]]).norm()});
}

std::uint32_t split_vertex(Builder& b, const Projected& pr, const Mesh& contoured, const RefinementInput& in,
                           std::uint32_t u, std::uint32_t v, double cos_crease) {
  if (std::abs(pr.normal[u].dot(pr.normal[v])) >= cos_crease) return none;  // the common case, no lookup
  const std::uint64_t key = edge_key(u, v);
  const auto found = b.crease_of_edge.find(key);
  if (found != b.crease_of_edge.end()) return found->second;
  std::uint32_t id = none;
  const std::uint32_t low = std::min(u, v), high = std::max(u, v);
  const auto x = is_crease(pr, in, low, high, cos_crease) ? crease_point(pr, low, high) : std::nullopt;
  // Where a crease pierces the mesh across a lattice face, the edges there
  // all meet it at one point: only the first is split (a second vertex at
  // the same place would pinch the surface).
  if (x && !b.crease_near(*x, 1e-4 * (pr.point[u] - pr.point[v]).norm())) {
    const Vec3 mid = 0.5 * (contoured.vertices[u] + contoured.vertices[v]);
    id = b.add(*x, static_cast<float>((*x - mid).norm()), {u, v});
    b.note_crease(id);
    ++b.creases;
  }
  b.crease_of_edge.emplace(key, id);
  return id;
}

// The triangle (a, b, c) with crease vertices m[e] on its edges e = ab, bc,
// ca (none where the edge has none), as triangles of the same winding. (A
// triangle crossed by three creases holds a corner: snap_corners puts a
// vertex on it afterwards.)
void emit(Builder& b, const std::array<std::uint32_t, 3>& t, const std::array<std::uint32_t, 3>& m,
          std::uint32_t source) {
  auto& out = b.mesh.triangles;
  const int splits = (m[0] != none) + (m[1] != none) + (m[2] != none);
  if (splits == 0) {
    out.push_back(t);
  } else if (splits == 1) {
    const std::size_t e = m[0] != none ? 0 : (m[1] != none ? 1 : 2);
    const std::uint32_t p = t[e], q = t[(e + 1) % 3], r = t[(e + 2) % 3];
    out.push_back({p, m[e], r});
    out.push_back({m[e], q, r});
  } else if (splits == 2) {
    // The corner between the two split edges is cut off along the crease;
    // the rest, a quadrilateral, is split along its shorter diagonal.
    const std::size_t lone = m[0] == none ? 2 : (m[1] == none ? 0 : 1);  // the vertex between the split edges
    const std::uint32_t q = t[lone], r = t[(lone + 1) % 3], p = t[(lone + 2) % 3];
    const std::uint32_t before = m[(lone + 2) % 3], after = m[lone];  // on edges p-q and q-r
    out.push_back({before, q, after});
    const auto& x = b.mesh.vertices;
    if ((x[p] - x[after]).squaredNorm() <= (x[before] - x[r]).squaredNorm()) {
      out.push_back({p, before, after});
      out.push_back({p, after, r});
    } else {
      out.push_back({p, before, r});
      out.push_back({before, after, r});
    }
  } else {
    out.push_back({t[0], m[0], m[2]});
    out.push_back({m[0], t[1], m[1]});
    out.push_back({m[2], m[1], t[2]});
    out.push_back({m[0], m[1], m[2]});
  }
  b.source.resize(out.size(), source);
}

}  // namespace

namespace {
// After the creases (defined below, in the order they run).
void snap_corners(Builder& b, const Projected& pr, double cos_crease);
void weld_coincident(Builder& b, std::size_t projected);
void remove_slivers(Builder& b);
}  // namespace

// Step 2 over the whole mesh, in triangle order; then the corners.
void sharpen(Builder& b, const Projected& pr, const Mesh& contoured, const RefinementInput& in, double cos_crease) {
  // The crease grid's side: a ten-thousandth of the longest edge, no less
  // than any tolerance asked of it (so the answers do not depend on it).
  double edge = 0.0;
  for (const auto& t : contoured.triangles) edge = std::max(edge, longest_edge(pr.point, t));
  b.grid = edge > 0.0 ? 1e-4 * edge : 1.0;
  for (std::uint32_t s = 0; s < contoured.triangles.size(); ++s) {
    const auto& t = contoured.triangles[s];
    std::array<std::uint32_t, 3> m{};
    for (std::size_t e = 0; e < 3; ++e) m[e] = split_vertex(b, pr, contoured, in, t[e], t[(e + 1) % 3], cos_crease);
    emit(b, t, m, s);
  }
  snap_corners(b, pr, cos_crease);
  weld_coincident(b, pr.point.size());
  remove_slivers(b);
}

namespace {

// Three or more tangent planes far apart in direction among a triangle's
// vertices (the planes a crease vertex lies on count for it): a corner
// where they meet, if they meet nearby.
std::optional<Vec3> triangle_corner(const Builder& b, const Projected& pr, const std::array<std::uint32_t, 3>& t,
                                    double cos_crease) {
  std::array<std::uint32_t, 6> distinct{};
  std::size_t count = 0;
  for (const std::uint32_t v : t)
    for (const std::uint32_t plane : b.planes[v]) {
      if (plane == none) continue;
      bool apart = true;
      for (std::size_t d = 0; d < count && apart; ++d)
        apart = std::abs(pr.normal[plane].dot(pr.normal[distinct[d]])) < cos_crease;
      if (apart) distinct[count++] = plane;
    }
  if (count < 3) return std::nullopt;
  // The three planes most nearly perpendicular to one another.
  std::array<std::uint32_t, 3> best{};
  double best_det = -1.0;
  for (std::size_t i = 0; i < count; ++i)
    for (std::size_t j = i + 1; j < count; ++j)
      for (std::size_t k = j + 1; k < count; ++k) {
        const double det = std::abs(pr.normal[distinct[i]].dot(pr.normal[distinct[j]].cross(pr.normal[distinct[k]])));
        if (det > best_det) {
          best_det = det;
          best = {distinct[i], distinct[j], distinct[k]};
        }
      }
  const Vec3 centre = (b.mesh.vertices[t[0]] + b.mesh.vertices[t[1]] + b.mesh.vertices[t[2]]) / 3.0;
  return corner_point(pr, best, centre, longest_edge(b.mesh.vertices, t));
}

std::vector<std::vector<std::uint32_t>> cluster_corners(const std::vector<CornerCandidate>& found) {
  double size = 0.0;
  for (const auto& c : found) size = std::max(size, c.reach);
  auto cell_of = [size](const Vec3& p, int dx, int dy, int dz) {
    auto coordinate = [size](double x, int d) {
      return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x / size)) + d) & 0x1FFFFF;
    };
    return coordinate(p.x(), dx) | coordinate(p.y(), dy) << 21 | coordinate(p.z(), dz) << 42;
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;  // cell -> clusters started there
  std::vector<std::vector<std::uint32_t>> clusters;                    // candidates; the first stands for all
  for (std::uint32_t c = 0; c < found.size(); ++c) {
    std::uint32_t joined = none;
    for (int dx = -1; dx <= 1 && joined == none; ++dx)
      for (int dy = -1; dy <= 1 && joined == none; ++dy)
        for (int dz = -1; dz <= 1 && joined == none; ++dz) {
          const auto cell = grid.find(cell_of(found[c].point, dx, dy, dz));
          if (cell == grid.end()) continue;
          for (const std::uint32_t k : cell->second) {
            const CornerCandidate& first = found[clusters[k][0]];
            if ((first.point - found[c].point).norm() <= std::max(first.reach, found[c].reach)) {
              joined = k;
              break;
            }
          }
        }
    if (joined == none) {
      joined = static_cast<std::uint32_t>(clusters.size());
      clusters.emplace_back();
      grid[cell_of(found[c].point, 0, 0, 0)].push_back(joined);
    }
    clusters[joined].push_back(c);
  }
  return clusters;
}

// Whether moving vertex v to p keeps every triangle around it a triangle
// facing the way it did.
bool can_move(const Builder& b, const std::vector<std::uint32_t>& around, std::uint32_t v, const Vec3& p) {
  for (const std::uint32_t t : around) {
    const auto& tri = b.mesh.triangles[t];
    std::array<Vec3, 3> before{}, after{};
    for (std::size_t c = 0; c < 3; ++c) {
      before[c] = b.mesh.vertices[tri[c]];
      after[c] = tri[c] == v ? p : before[c];
    }
    const Vec3 n0 = (before[1] - before[0]).cross(before[2] - before[0]);
    const Vec3 n1 = (after[1] - after[0]).cross(after[2] - after[0]);
    const double scale = longest_edge(b.mesh.vertices, tri);
    if (!(n1.norm() > 1e-6 * scale * scale) || n0.dot(n1) <= 0.0) return false;
  }
  return true;
}

void snap_corners(Builder& b, const Projected& pr, double cos_crease) {
  std::vector<CornerCandidate> found;
  for (const auto& t : b.mesh.triangles)
    if (const auto x = triangle_corner(b, pr, t, cos_crease))
      found.push_back({*x, longest_edge(b.mesh.vertices, t), t});
  if (found.empty()) return;
  const auto clusters = cluster_corners(found);
  // The triangles around each vertex that might move.
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> around;
  for (const auto& c : found)
    for (const std::uint32_t v : c.triangle) around[v];
  for (std::uint32_t t = 0; t < b.mesh.triangles.size(); ++t)
    for (const std::uint32_t v : b.mesh.triangles[t])
      if (const auto it = around.find(v); it != around.end()) it->second.push_back(t);
  for (const auto& cluster : clusters) {
    const Vec3& corner = found[cluster[0]].point;
    // The cluster's vertices, nearest first; the first that can move there does.
    std::vector<std::pair<double, std::uint32_t>> nearest;
    for (const std::uint32_t c : cluster)
      for (const std::uint32_t v : found[c].triangle)
        if (b.planes[v][0] != none || b.planes[v][1] != none)  // not snapped already
          nearest.emplace_back((b.mesh.vertices[v] - corner).squaredNorm(), v);
    std::sort(nearest.begin(), nearest.end());
    nearest.erase(std::unique(nearest.begin(), nearest.end()), nearest.end());
    for (const auto& [d2, v] : nearest) {
      if (!can_move(b, around[v], v, corner)) continue;
      b.displacement[v] += static_cast<float>(std::sqrt(d2));
      b.mesh.vertices[v] = corner;
      b.planes[v] = {none, none};
      ++b.corners;
      break;
    }
  }
}

// Crease vertices of one triangle that coincide (an edge of the lattice
// and its neighbour in the same lattice plane can cross a crease at the
// same point) become one vertex; the triangles between them, now with a
// repeated vertex, go.
void weld_coincident(Builder& b, std::size_t projected) {
  std::vector<std::uint32_t> same(b.mesh.vertices.size());
  for (std::uint32_t v = 0; v < same.size(); ++v) same[v] = v;
  auto root = [&same](std::uint32_t v) {
    while (same[v] != v) v = same[v] = same[same[v]];
    return v;
  };
  bool any = false;
  for (const auto& t : b.mesh.triangles) {
    const double tolerance = 1e-4 * longest_edge(b.mesh.vertices, t);
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint32_t u = t[e], v = t[(e + 1) % 3];
      if (u < projected || v < projected || (b.mesh.vertices[u] - b.mesh.vertices[v]).norm() > tolerance) continue;
      const std::uint32_t a = root(u), c = root(v);
      if (a != c) same[std::max(a, c)] = std::min(a, c);
      any = true;
    }
  }
  if (!any) return;
  std::vector<std::uint8_t> keep(b.mesh.triangles.size(), 1);
  for (std::size_t i = 0; i < b.mesh.triangles.size(); ++i) {
    auto& t = b.mesh.triangles[i];
    for (auto& v : t) v = root(v);
    keep[i] = t[0] != t[1] && t[1] != t[2] && t[2] != t[0];
  }
  compact(b, keep);
}

// The edge e (tri[e] -> tri[e + 1]) that is a sliver's longest, or 3 when
// the triangle is no sliver.
std::size_t sliver_edge(const std::vector<Vec3>& x, const std::array<std::uint32_t, 3>& tri) {
  const double longest = longest_edge(x, tri);
  if ((x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]).norm() > 1e-8 * longest * longest) return 3;
  std::size_t e = 0;
  while ((x[tri[e]] - x[tri[(e + 1) % 3]]).norm() < longest) ++e;
  return e;
}

Slivers flip_slivers(Triangles& tris, const std::vector<Vec3>& x) {
  std::vector<std::uint8_t> longest(tris.size());
  const auto count = static_cast<std::int64_t>(tris.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t t = 0; t < count; ++t)
    longest[static_cast<std::size_t>(t)] = static_cast<std::uint8_t>(sliver_edge(x, tris[static_cast<std::size_t>(t)]));
  std::vector<std::uint32_t> slivers;
  std::unordered_map<std::uint64_t, std::uint32_t> sliver_of;  // a sliver's longest edge -> the sliver
  for (std::uint32_t t = 0; t < tris.size(); ++t) {
    const std::size_t e = longest[t];
    if (e == 3) continue;
    slivers.push_back(t);
    sliver_of.emplace(edge_key(tris[t][e], tris[t][(e + 1) % 3]), t);
  }
  if (slivers.empty()) return {};
  std::unordered_set<std::uint64_t> edges;
  std::vector<std::uint32_t> across(tris.size(), none);  // sliver -> the triangle across its longest edge
  for (std::uint32_t t = 0; t < tris.size(); ++t)
    for (std::size_t e = 0; e < 3; ++e) {
      const std::uint64_t k = edge_key(tris[t][e], tris[t][(e + 1) % 3]);
      edges.insert(k);
      const auto s = sliver_of.find(k);
      if (s != sliver_of.end() && s->second != t) across[s->second] = t;
    }
  std::vector<std::uint8_t> touched(tris.size(), 0);
  Slivers result;
  for (const std::uint32_t sliver : slivers) {
    const std::uint32_t other = across[sliver];
    const std::size_t e = sliver_edge(x, tris[sliver]);
    const std::uint32_t a = tris[sliver][e], bb = tris[sliver][(e + 1) % 3], c = tris[sliver][(e + 2) % 3];
    std::uint32_t d = none;
    if (other != none && !touched[sliver] && !touched[other] && sliver_edge(x, tris[other]) == 3)
      for (const std::uint32_t v : tris[other])
        if (v != a && v != bb) d = v;
    if (d == none || edges.count(edge_key(c, d)) != 0) {
      result.left.push_back(sliver);
      continue;
    }
    tris[sliver] = {c, a, d};
    tris[other] = {c, d, bb};
    edges.insert(edge_key(c, d));
    touched[sliver] = touched[other] = 1;
    ++result.flipped;
  }
  return result;
}

// Whether moving v onto u leaves every triangle around v that does not
// hold u facing the same way (no fold).
bool collapse_keeps_sides(const Triangles& tris, const std::vector<Vec3>& x, const std::vector<std::uint32_t>& around,
                          std::uint32_t u, std::uint32_t v) {
  for (const std::uint32_t t : around) {
    const auto& tri = tris[t];
    if (std::find(tri.begin(), tri.end(), u) != tri.end()) continue;
    auto at = [&](std::size_t i) { return tri[i] == v ? x[u] : x[tri[i]]; };
    const Vec3 before = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);
    const Vec3 after = (at(1) - at(0)).cross(at(2) - at(0));
    if (before.dot(after) <= 0.0) return false;
  }
  return true;
}

// Collapses an edge (u, v) of each sliver left, the shortest that can be,
// moving v onto u (never a corner vertex), where that keeps the surface a
// manifold (u and v share no neighbour but the two triangles' third
// vertices) and turns no triangle around v over. Returns whether any edge
// was collapsed.
bool collapse_slivers(Builder& b, const std::vector<std::uint32_t>& slivers) {
  Triangles& tris = b.mesh.triangles;
  const auto& x = b.mesh.vertices;
  std::vector<std::vector<std::uint32_t>> around(x.size());
  for (std::uint32_t t = 0; t < tris.size(); ++t)
    for (const std::uint32_t v : tris[t]) around[v].push_back(t);
  auto neighbours = [&](std::uint32_t v) {
    std::vector<std::uint32_t> n;
    for (const std::uint32_t t : around[v])
      for (const std::uint32_t w : tris[t])
        if (w != v) n.push_back(w);
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
    return n;
  };
  std::vector<std::uint8_t> changed(x.size(), 0);
  std::vector<std::uint8_t> keep(tris.size(), 1);
  bool any = false;
  auto try_collapse = [&](std::uint32_t u, std::uint32_t v) {
    if (b.planes[v][0] == none || changed[u] || changed[v]) return false;  // a corner stays where it is
    const auto nu = neighbours(u), nv = neighbours(v);
    std::vector<std::uint32_t> common;
    std::set_intersection(nu.begin(), nu.end(), nv.begin(), nv.end(), std::back_inserter(common));
    std::size_t sharing = 0;  // triangles on the edge (u, v)
    for (const std::uint32_t t : around[v]) sharing += std::find(tris[t].begin(), tris[t].end(), u) != tris[t].end();
    if (common.size() != sharing || !collapse_keeps_sides(tris, x, around[v], u, v)) return false;
    for (const std::uint32_t t : around[v]) {
      for (auto& w : tris[t]) w = w == v ? u : w;
      keep[t] = tris[t][0] != tris[t][1] && tris[t][1] != tris[t][2] && tris[t][2] != tris[t][0];
    }
    for (const std::uint32_t w : nv) changed[w] = 1;
    for (const std::uint32_t w : nu) changed[w] = 1;
    changed[u] = changed[v] = 1;
    return true;
  };
  for (const std::uint32_t s : slivers) {
    if (!keep[s]) continue;
    std::array<std::size_t, 3> order{0, 1, 2};  // the sliver's edges, shortest first
    auto length = [&](std::size_t e) { return (x[tris[s][e]] - x[tris[s][(e + 1) % 3]]).norm(); };
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return length(i) < length(j); });
    for (const std::size_t e : order)
      if (try_collapse(tris[s][e], tris[s][(e + 1) % 3]) || try_collapse(tris[s][(e + 1) % 3], tris[s][e])) {
        any = true;
        break;
      }
  }
  if (any) compact(b, keep);
  return any;
}

void remove_slivers(Builder& b) {
  for (int pass = 0; pass < 8; ++pass) {
    const Slivers s = flip_slivers(b.mesh.triangles, b.mesh.vertices);
    const bool collapsed = !s.left.empty() && collapse_slivers(b, s.left);
    if (s.flipped == 0 && !collapsed) return;
  }
}

}  // namespace

}  // namespace recon::refinement_steps
