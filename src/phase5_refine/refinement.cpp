#include "recon/phase5_refine/refinement.h"

#include "recon/core/errors.h"
#include "recon/core/interruption.h"
#include "recon/core/progress.h"
#include "recon/core/timer.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace recon {
namespace {

constexpr std::uint32_t none = UINT32_MAX;

// A contoured vertex after step 1: where it went, the surface's normal
// there (unoriented), and the plane whose quadric it went onto.
struct Projected {
  std::vector<std::uint8_t> covered;   // a sample lies within the local spacing (not past an open boundary)
  std::vector<Vec3> point;
  std::vector<Vec3> normal;           // oriented
  std::vector<std::uint32_t> plane;
  std::vector<std::uint32_t> partner;  // the vertex across the crease it was brought back to, or none
  std::vector<std::uint8_t> trusted;   // moved onto its quadric (not left where it was: max_move)
  std::size_t unmoved = 0;
};

// On noisy data each quadric carries its neighbourhood's noise: the point
// is projected onto the quadrics of the `blend` origins nearest to it that
// face the same way as plane i (not across a crease), and the results are
// averaged with weights falling off with the distance to each origin (a
// Gaussian of the farthest one's distance): a moving least-squares surface.
SurfacePoint blended_projection(const RefinementInput& in, std::uint32_t i, const Vec3& p) {
  constexpr std::size_t most = 32;
  std::array<Neighbor, most> found;
  const std::size_t count =
      in.origin_tree->knn(p, std::span<Neighbor>(found.data(), std::min<std::size_t>(most, static_cast<std::size_t>(in.blend))));
  const double h2 = std::max(found[count - 1].distance2, 1e-300);
  Vec3 point = Vec3::Zero(), normal = Vec3::Zero();
  double total = 0.0;
  for (std::size_t c = 0; c < count; ++c) {
    const std::uint32_t j = found[c].index;
    if (std::abs(in.normals[j].dot(in.normals[i])) < 0.9063077870366499) continue;  // across a crease
    const SurfacePoint q = project_onto_quadric(in.origins[j], in.normals[j], in.curvature[j], p);
    const double w = std::exp(-found[c].distance2 / h2);
    point += w * q.point;
    normal += w * (q.normal.dot(in.normals[i]) < 0.0 ? Vec3(-q.normal) : q.normal);
    total += w;
  }
  if (!(total > 0.0)) return project_onto_quadric(in.origins[i], in.normals[i], in.curvature[i], p);
  return {point / total, normal.normalized()};
}

// Step 1: every vertex onto the quadric of the plane f takes there (so the
// faces meeting at a crease split the space as f does). A vertex that would
// move further than max_move stays put.
Projected project_vertices(const Mesh& mesh, const RefinementInput& in, double max_move) {
  const std::size_t n = mesh.vertices.size();
  Projected out;
  out.point.resize(n);
  out.normal.resize(n);
  out.plane.resize(n);
  out.partner.assign(n, none);
  out.covered.assign(n, 1);
  out.trusted.assign(n, 1);
  std::size_t unmoved = 0;
  const auto count = static_cast<std::int64_t>(n);
  ProgressCounter* const progress = progress_counter();
#pragma omp parallel reduction(+ : unmoved)
  {
    // The walk emits neighbouring vertices one after another: the previous
    // vertex's plane bounds the search for the next (the answer is the same).
    std::uint32_t hint = SignedDistance<3>::no_hint;
#pragma omp for schedule(dynamic, 1024)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto v = static_cast<std::size_t>(s);
      if (progress != nullptr && (s & 4095) == 4095) progress->advance(4096);
      const Vec3& p = mesh.vertices[v];
      const std::uint32_t i = in.distance->plane_for(p, hint);
      hint = i;
      const SurfacePoint q = in.blend > 1 ? blended_projection(in, i, p)
                                          : project_onto_quadric(in.origins[i], in.normals[i], in.curvature[i], p);
      const bool trusted = max_move <= 0.0 || (q.point - p).norm() <= max_move;
      out.point[v] = trusted ? q.point : p;
      out.normal[v] = in.oriented[i].dot(in.normals[i]) < 0.0 ? Vec3(-q.normal) : q.normal;
      out.plane[v] = i;
      out.trusted[v] = trusted ? 1 : 0;
      if (!in.spacing.empty())
        out.covered[v] = (p - in.origins[i]).norm() <= static_cast<double>(in.spacing[i]) ? 1 : 0;
      unmoved += trusted ? 0 : 1;
    }
  }
  out.unmoved = unmoved;
  return out;
}

// The normal curvature of plane i's quadric along the direction d (any
// length; its part in the tangent plane counts).
double curvature_along(const RefinementInput& in, std::uint32_t i, const Vec3& d) {
  const auto t = tangent_basis(in.normals[i]);
  const double a = d.dot(t[0]), b = d.dot(t[1]);
  const double length2 = a * a + b * b;
  if (!(length2 > 0.0)) return 0.0;
  const Curvature& c = in.curvature[i];
  const auto cp = static_cast<double>(c.p), cq = static_cast<double>(c.q), cr = static_cast<double>(c.r);
  return 2.0 * (cp * a * a + cq * a * b + cr * b * b) / length2;
}

// Step 2's test: whether the edge (a, b) crosses a crease. The ends'
// normals must differ by more than the crease angle and by more than twice
// what the curvature at either end turns a normal along the edge.
bool is_crease(const Projected& pr, const RefinementInput& in, std::uint32_t a, std::uint32_t b, double cos_crease) {
  const double cosine = std::abs(pr.normal[a].dot(pr.normal[b]));
  if (cosine >= cos_crease) return false;
  const Vec3 e = pr.point[b] - pr.point[a];
  const double turn = e.norm() * std::max(std::abs(curvature_along(in, pr.plane[a], e)),
                                          std::abs(curvature_along(in, pr.plane[b], e)));
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

// The refined mesh under construction: the projected vertices, then the
// crease and corner vertices added (each crease vertex once, by its edge).
struct Builder {
  Mesh mesh;
  std::vector<float> displacement;
  /// The tangent planes each vertex lies on, by the projected vertex they
  /// belong to: its own for a projected vertex, both ends' for a crease vertex.
  std::vector<std::array<std::uint32_t, 2>> planes;
  std::vector<std::array<std::uint32_t, 2>> stem;  // per vertex (RefinedPatch::stem)
  std::vector<std::uint32_t> source;               // per triangle (RefinedPatch::source)
  std::unordered_map<std::uint64_t, std::uint32_t> crease_of_edge;  // none: tested, no crease
  std::size_t creases = 0, corners = 0;

  std::uint32_t add(const Vec3& p, float moved, std::array<std::uint32_t, 2> on) {
    mesh.vertices.push_back(p);
    displacement.push_back(moved);
    planes.push_back(on);
    stem.push_back(on);
    return static_cast<std::uint32_t>(mesh.vertices.size() - 1);
  }

  // The crease vertices by grid cell (of side `grid`), to find one near a point.
  double grid = 0.0;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> crease_cells;
  [[nodiscard]] std::uint64_t cell_key(const Vec3& p, int dx, int dy, int dz) const {
    auto c = [this](double x, int d) {
      return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x / grid)) + d) & 0x1FFFFF;
    };
    return c(p.x(), dx) | c(p.y(), dy) << 21 | c(p.z(), dz) << 42;
  }
  void note_crease(std::uint32_t v) { crease_cells[cell_key(mesh.vertices[v], 0, 0, 0)].push_back(v); }
  [[nodiscard]] bool crease_near(const Vec3& p, double tolerance) const {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto cell = crease_cells.find(cell_key(p, dx, dy, dz));
          if (cell == crease_cells.end()) continue;
          for (const std::uint32_t v : cell->second)
            if ((mesh.vertices[v] - p).norm() <= tolerance) return true;
        }
    return false;
  }
};

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

// Step 2 over the whole mesh, in triangle order; then the corners.
void snap_corners(Builder& b, const Projected& pr, double cos_crease);
void weld_coincident(Builder& b, std::size_t projected);
void remove_slivers(Builder& b);
void compact(Builder& b, const std::vector<std::uint8_t>& keep_triangle);

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

// A corner found in one or more triangles (candidates within an edge's
// length of one another count as one, the first found standing for them)
// is taken by the nearest vertex of those triangles: the mesh then has a
// vertex on it, where the crease lines of its faces meet.
struct CornerCandidate {
  Vec3 point;
  double reach;
  std::array<std::uint32_t, 3> triangle;
};

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
  std::vector<std::vector<std::uint32_t>> clusters;                   // candidates; the first stands for all
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
    if (const auto x = triangle_corner(b, pr, t, cos_crease)) found.push_back({*x, longest_edge(b.mesh.vertices, t), t});
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

// A split can leave a sliver: a triangle (a, b, c) with c on the segment ab
// (a crease vertex in line with two others). Its longest edge ab is flipped
// with the triangle (b, a, d) across it: (c, a, d) and (c, d, b) split that
// triangle at c instead, unless c and d are joined already. Where the
// triangle across is a sliver too (several crease vertices in a row), no
// flip helps: one of the sliver's edges is collapsed instead. Both repeat
// until no sliver is left (a few passes at most).
using Triangles = std::vector<std::array<std::uint32_t, 3>>;

// The edge e (tri[e] -> tri[e + 1]) that is a sliver's longest, or 3 when
// the triangle is no sliver.
std::size_t sliver_edge(const std::vector<Vec3>& x, const std::array<std::uint32_t, 3>& tri) {
  const double longest = longest_edge(x, tri);
  if ((x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]).norm() > 1e-8 * longest * longest) return 3;
  std::size_t e = 0;
  while ((x[tri[e]] - x[tri[(e + 1) % 3]]).norm() < longest) ++e;
  return e;
}

// One pass of flips; returns the slivers left as they were (a flip may make
// a new one: the next pass looks again).
struct Slivers {
  std::size_t flipped = 0;
  std::vector<std::uint32_t> left;
};

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

// Step 3: the mean sag of each vertex's smooth edges, |e|^2 kappa / 12 with
// kappa = (n_b - n_a) . e / |e|^2 (both normals on one side), signed along
// the vertex's own normal: positive where the surface bulges that way.
std::vector<double> mean_sag(const Mesh& contoured, const Projected& pr, double cos_crease) {
  const std::size_t n = contoured.vertices.size();
  std::vector<double> sum(n, 0.0);
  std::vector<std::uint32_t> edges(n, 0);
  auto add = [&](std::uint32_t a, std::uint32_t b) {
    const double c = pr.normal[a].dot(pr.normal[b]);
    if (std::abs(c) < cos_crease) return;
    const Vec3 nb = c < 0.0 ? Vec3(-pr.normal[b]) : pr.normal[b];
    sum[a] += (nb - pr.normal[a]).dot(pr.point[b] - pr.point[a]) / 12.0;
    ++edges[a];
  };
  for (const auto& t : contoured.triangles)
    for (std::size_t e = 0; e < 3; ++e) {
      add(t[e], t[(e + 1) % 3]);
      add(t[(e + 1) % 3], t[e]);
    }
  for (std::size_t v = 0; v < n; ++v) sum[v] = edges[v] > 0 && pr.partner[v] == none ? sum[v] / edges[v] : 0.0;
  return sum;
}

// Step 4a: an open boundary is cut back to the data. f is defined up to
// about 1.5 rho + delta past the last samples (signed_distance.h), so the
// contoured surface runs on past an open edge of the data; triangles whose
// three vertices lie farther from their plane's sample than the local
// spacing there are peeled off, starting from the boundary and moving
// inwards only (a closed surface has no boundary and loses nothing, and no
// hole is made inside the surface).
// Whether each vertex lies within the spacing of its plane's sample (or of
// one of its two planes' samples, on a crease).
std::vector<std::uint8_t> covered_vertices(const Builder& b, const Projected& pr) {
  std::vector<std::uint8_t> covered(b.mesh.vertices.size(), 1);
  for (std::size_t v = 0; v < covered.size(); ++v) {
    const auto& on = b.planes[v];
    if (on[0] != none) covered[v] = pr.covered[on[0]] || (on[1] != none && pr.covered[on[1]]);
  }
  return covered;
}

// The peeling's state: the triangles touching an uncovered vertex (the
// candidates), the (up to) two triangles of each of their edges with an
// uncovered end (all of whose triangles are candidates), and those removed.
class Peeling {
 public:
  Peeling(const Mesh& mesh, const std::vector<std::uint8_t>& covered)
      : mesh_(mesh), covered_(covered), removed_(mesh.triangles.size(), 0) {
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      if (!covered[tri[0]] || !covered[tri[1]] || !covered[tri[2]]) candidates_.push_back(t);
    }
    for (const std::uint32_t t : candidates_) {
      const auto& tri = mesh.triangles[t];
      for (std::size_t e = 0; e < 3; ++e) {
        const std::uint32_t u = tri[e], v = tri[(e + 1) % 3];
        if (covered[u] && covered[v]) continue;
        auto [it, added] = sides_.try_emplace(edge_key(u, v), std::array<std::uint32_t, 2>{t, none});
        if (!added) it->second[1] = t;
      }
    }
  }
  // Peels from the open boundary inwards, breadth first: a triangle whose
  // three vertices are uncovered goes once an edge of it is on the boundary.
  std::size_t peel() {
    std::vector<std::uint32_t> queue;
    for (const std::uint32_t t : candidates_)
      if (peelable(t) && on_boundary(t)) queue.push_back(t);
    std::size_t peeled = 0;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t t = queue[q];
      if (!peelable(t)) continue;
      removed_[t] = 1;
      ++peeled;
      const auto& tri = mesh_.triangles[t];
      for (std::size_t e = 0; e < 3; ++e) {
        const std::uint32_t other = across(t, tri[e], tri[(e + 1) % 3]);
        if (other != none && peelable(other)) queue.push_back(other);
      }
    }
    return peeled;
  }
  // 1 for each triangle kept.
  [[nodiscard]] std::vector<std::uint8_t> kept() const {
    std::vector<std::uint8_t> keep(removed_.size());
    for (std::size_t t = 0; t < keep.size(); ++t) keep[t] = removed_[t] ? 0 : 1;
    return keep;
  }

 private:
  [[nodiscard]] bool peelable(std::uint32_t t) const {
    const auto& tri = mesh_.triangles[t];
    return !removed_[t] && !covered_[tri[0]] && !covered_[tri[1]] && !covered_[tri[2]];
  }
  // Across edge (u, v) of t: the other triangle, or none at the boundary.
  [[nodiscard]] std::uint32_t across(std::uint32_t t, std::uint32_t u, std::uint32_t v) const {
    const auto& two = sides_.at(edge_key(u, v));
    const std::uint32_t other = two[0] == t ? two[1] : two[0];
    return other != none && !removed_[other] ? other : none;
  }
  [[nodiscard]] bool on_boundary(std::uint32_t t) const {
    const auto& tri = mesh_.triangles[t];
    for (std::size_t e = 0; e < 3; ++e)
      if (across(t, tri[e], tri[(e + 1) % 3]) == none) return true;
    return false;
  }

  const Mesh& mesh_;
  const std::vector<std::uint8_t>& covered_;
  std::vector<std::uint32_t> candidates_;
  std::unordered_map<std::uint64_t, std::array<std::uint32_t, 2>> sides_;
  std::vector<std::uint8_t> removed_;
};

std::size_t trim_boundaries(RefinedPatch& patch) {
  Peeling peeling(patch.mesh, patch.covered);
  const std::size_t peeled = peeling.peel();
  if (peeled > 0) patch.keep(peeling.kept());
  return peeled;
}

// Step 4, triangles beyond f's reach. f is defined only within about
// 1.5 rho_i + delta of a sample, and a mesh on the surface lies within a
// cell of it; where sheets lie closer than a cell the lattice cannot
// follow them, and the zero set drawn between the planes of both can run
// off into empty space (a fin). A triangle whose three vertices are all
// farther than in.reach * rho_i + delta from every sample is dropped.
// (Vertices that near their plane's own origin are not searched.)
std::vector<std::uint8_t> far_vertices(const Builder& b, const Projected& pr, const RefinementInput& in) {
  const std::size_t n = b.mesh.vertices.size();
  std::vector<std::uint8_t> far(n, 0);
  if (in.sample_tree == nullptr) return far;
  const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto v = static_cast<std::size_t>(s);
    const std::uint32_t own = b.planes[v][0];
    if (own == none) continue;  // a corner: where its planes meet
    const std::uint32_t plane = pr.plane[own];
    const double reach = in.reach * static_cast<double>(in.local_rho[plane]) + in.delta;
    const Vec3& p = b.mesh.vertices[v];
    if ((p - in.origins[plane]).squaredNorm() <= reach * reach) continue;
    far[v] = in.sample_tree->any_within(p, reach * reach) ? 0 : 1;
  }
  return far;
}

std::size_t drop_strays(RefinedPatch& patch) {
  std::vector<std::uint8_t> keep(patch.mesh.triangles.size(), 1);
  std::size_t dropped = 0;
  for (std::size_t t = 0; t < keep.size(); ++t) {
    const auto& tri = patch.mesh.triangles[t];
    if (patch.far[tri[0]] && patch.far[tri[1]] && patch.far[tri[2]]) {
      keep[t] = 0;
      ++dropped;
    }
  }
  if (dropped > 0) patch.keep(keep);
  return dropped;
}

// Step 4: components (through shared vertices), the piece of data each is
// drawn from (the most common piece among its vertices' planes), and which
// to keep.
struct Fragments {
  std::vector<std::uint8_t> keep_triangle;
  std::size_t dropped = 0, dropped_triangles = 0;
};

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

Fragments find_fragments(const Mesh& mesh, const std::vector<std::uint32_t>& piece_of_vertex, double fraction) {
  const std::size_t n = mesh.vertices.size();
  std::vector<std::uint32_t> parent(n);
  for (std::uint32_t v = 0; v < n; ++v) parent[v] = v;
  for (const auto& t : mesh.triangles)
    for (std::size_t e = 1; e < 3; ++e) {
      const std::uint32_t a = find_root(parent, t[0]), b = find_root(parent, t[e]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  Fragments f;
  f.keep_triangle.assign(mesh.triangles.size(), 1);
  std::size_t roots = 0;
  for (std::uint32_t v = 0; v < n && roots < 2; ++v) roots += parent[v] == v ? 1u : 0u;
  if (roots < 2) return f;  // one component (or none): nothing to compare
  // Per component (by root): triangles, and votes for its piece.
  std::unordered_map<std::uint32_t, std::size_t> triangles;
  std::unordered_map<std::uint32_t, std::unordered_map<std::uint32_t, std::size_t>> votes;
  for (const auto& t : mesh.triangles) ++triangles[find_root(parent, t[0])];
  for (std::uint32_t v = 0; v < n; ++v)
    if (piece_of_vertex[v] != none) ++votes[find_root(parent, v)][piece_of_vertex[v]];
  std::unordered_map<std::uint32_t, std::uint32_t> piece_of;
  std::unordered_map<std::uint32_t, std::size_t> largest;  // per piece
  for (const auto& [root, count] : triangles) {
    std::uint32_t piece = 0;
    std::size_t best = 0;
    for (const auto& [p, c] : votes[root])
      if (c > best || (c == best && p < piece)) {
        best = c;
        piece = p;
      }
    piece_of[root] = piece;
    largest[piece] = std::max(largest[piece], count);
  }
  for (const auto& [root, count] : triangles)
    if (static_cast<double>(count) < fraction * static_cast<double>(largest[piece_of[root]])) {
      ++f.dropped;
      f.dropped_triangles += count;
    }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::uint32_t root = find_root(parent, mesh.triangles[t][0]);
    if (static_cast<double>(triangles[root]) < fraction * static_cast<double>(largest[piece_of[root]]))
      f.keep_triangle[t] = 0;
  }
  return f;
}

// Removes the dropped triangles (and their `source`) and the vertices no
// triangle uses any more, keeping the order of the rest; move(to, from) moves
// a kept vertex's other attributes down (to <= from). Returns, per old
// vertex, its new number (none: removed).
template <class MoveVertex>
std::vector<std::uint32_t> compact_mesh(Mesh& mesh, std::vector<std::uint32_t>& source,
                                        const std::vector<std::uint8_t>& keep_triangle, const MoveVertex& move) {
  std::vector<std::uint32_t> renumber(mesh.vertices.size(), none);
  std::size_t kept = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!keep_triangle[t]) continue;
    mesh.triangles[kept] = mesh.triangles[t];
    source[kept] = source[t];
    ++kept;
    for (const std::uint32_t v : mesh.triangles[t]) renumber[v] = 0;
  }
  mesh.triangles.resize(kept);
  source.resize(kept);
  std::uint32_t next = 0;
  for (std::uint32_t v = 0; v < renumber.size(); ++v) {
    if (renumber[v] == none) continue;
    renumber[v] = next;
    mesh.vertices[next] = mesh.vertices[v];
    if (mesh.has_normals()) mesh.normals[next] = mesh.normals[v];
    move(next, v);
    ++next;
  }
  mesh.vertices.resize(next);
  if (mesh.has_normals()) mesh.normals.resize(next);
  for (auto& t : mesh.triangles)
    for (auto& v : t) v = renumber[v];
  return renumber;
}

void compact(Builder& b, const std::vector<std::uint8_t>& keep_triangle) {
  compact_mesh(b.mesh, b.source, keep_triangle, [&b](std::uint32_t to, std::uint32_t from) {
        b.displacement[to] = b.displacement[from];
        b.planes[to] = b.planes[from];
        b.stem[to] = b.stem[from];
      });
  b.displacement.resize(b.mesh.vertices.size());
  b.planes.resize(b.mesh.vertices.size());
  b.stem.resize(b.mesh.vertices.size());
}

// The fitted normal of each vertex (RefinementOptions::fitted_normals):
// a projected vertex's own plane alone, moved onto its quadric, has one;
// a vertex on two planes (a crease vertex, or one brought back onto a
// crease) or none (a corner) has (0, 0, 0). pr.normal is oriented as phase
// II oriented the plane, the side f is positive on, which the contoured
// triangles face.
std::vector<Vec3> fitted_normals(const Builder& b, const Projected& pr) {
  std::vector<Vec3> normals(b.mesh.vertices.size(), Vec3::Zero());
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const auto& on = b.planes[v];
    if (on[0] != none && on[1] == none && pr.trusted[on[0]]) normals[v] = pr.normal[on[0]];
  }
  return normals;
}

void check_input(const RefinementInput& in) {
  const std::size_t n = in.origins.size();
  if (in.normals.size() != n || in.curvature.size() != n || (!in.piece.empty() && in.piece.size() != n) ||
      in.oriented.size() != n || in.distance == nullptr)
    throw InvalidInputError("refine_mesh: the origins, normals (both), curvatures and pieces must all describe the same " +
                            std::to_string(n) + " planes, and f is needed");
  if (n == 0) throw InvalidInputError("refine_mesh: no planes to refine against");
  if (in.blend > 1 && (in.origin_tree == nullptr || in.origin_tree->size() != n))
    throw InvalidInputError("refine_mesh: blending needs the tree over the origins");
}

}  // namespace

RefinedPatch refine_patch(const Mesh& contoured, const RefinementInput& input, const RefinementOptions& options) {
  check_input(input);
  const double cos_crease = std::cos(options.crease_angle_degrees * std::numbers::pi / 180.0);
  Projected pr = project_vertices(contoured, input, options.max_move);
  interruption_point();
  const std::size_t brought_back = bring_back(pr, contoured, input, cos_crease, options.max_move);
  Builder b;
  b.mesh.vertices = pr.point;
  b.displacement.resize(pr.point.size());
  b.planes.resize(pr.point.size());
  b.stem.resize(pr.point.size());
  for (std::uint32_t v = 0; v < pr.point.size(); ++v) {
    b.planes[v] = {v, pr.partner[v]};
    b.stem[v] = {v, none};
  }
  if (options.chord_balance != 0.0) {
    const std::vector<double> sag = mean_sag(contoured, pr, cos_crease);
    for (std::size_t v = 0; v < sag.size(); ++v) b.mesh.vertices[v] += options.chord_balance * sag[v] * pr.normal[v];
  }
  for (std::size_t v = 0; v < pr.point.size(); ++v)
    b.displacement[v] = static_cast<float>((b.mesh.vertices[v] - contoured.vertices[v]).norm());
  interruption_point();
  sharpen(b, pr, contoured, input, cos_crease);
  interruption_point();
  if (options.fitted_normals) b.mesh.normals = fitted_normals(b, pr);
  RefinedPatch patch;
  patch.covered = covered_vertices(b, pr);
  patch.far = far_vertices(b, pr, input);
  patch.piece.resize(b.mesh.vertices.size());
  for (std::size_t v = 0; v < patch.piece.size(); ++v) {
    const std::uint32_t projected = b.planes[v][0];  // none for a corner; a crease vertex votes with its first end
    patch.piece[v] = projected == none ? none : input.piece.empty() ? 0 : input.piece[pr.plane[projected]];
  }
  patch.crease_vertices = b.creases;
  patch.brought_back = brought_back;
  patch.corner_vertices = b.corners;
  patch.unmoved = pr.unmoved;
  patch.mesh = std::move(b.mesh);
  patch.displacement = std::move(b.displacement);
  patch.stem = std::move(b.stem);
  patch.source = std::move(b.source);
  return patch;
}

void RefinedPatch::keep(const std::vector<std::uint8_t>& keep_triangle) {
  compact_mesh(mesh, source, keep_triangle, [this](std::uint32_t to, std::uint32_t from) {
    displacement[to] = displacement[from];
    stem[to] = stem[from];
    covered[to] = covered[from];
    far[to] = far[from];
    piece[to] = piece[from];
  });
  const std::size_t n = mesh.vertices.size();
  displacement.resize(n);
  stem.resize(n);
  covered.resize(n);
  far.resize(n);
  piece.resize(n);
}

// Steps 1 to 3 (refine_patch), then step 4 over the whole mesh.
Refinement refine_mesh(const Mesh& contoured, const RefinementInput& input, const RefinementOptions& options) {
  Timer timer;
  RefinedPatch patch = refine_patch(contoured, input, options);
  Refinement result;
  result.trimmed = trim_boundaries(patch);
  result.stray_triangles = drop_strays(patch);
  result.crease_vertices = patch.crease_vertices;
  result.brought_back = patch.brought_back;
  result.corner_vertices = patch.corner_vertices;
  result.unmoved = patch.unmoved;
  if (!options.keep_fragments) {
    const Fragments f = find_fragments(patch.mesh, patch.piece, options.fragment_fraction);
    result.fragments = f.dropped;
    result.fragment_triangles = f.dropped_triangles;
    if (f.dropped > 0) patch.keep(f.keep_triangle);
  }
  result.mesh = std::move(patch.mesh);
  result.displacement = std::move(patch.displacement);
  result.seconds = timer.lap();
  return result;
}

}  // namespace recon
