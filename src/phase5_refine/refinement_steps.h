#pragma once
// Phase V's steps (refinement.h), one source each: step1_project.cpp,
// step2_sharpen.cpp, step3_balance.cpp, step4_clean.cpp; refinement.cpp
// runs them (refine_patch, refine_mesh). What they share: the projected
// vertices, the mesh under construction, and each step's functions.
// Private to phase5_refine/.

#include "recon/phase5_refine/refinement.h"

#include <array>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

namespace recon::refinement_steps {

constexpr std::uint32_t none = UINT32_MAX;

// A contoured vertex after step 1: where it went, the surface's normal
// there (unoriented), and the plane whose quadric it went onto.
struct Projected {
  std::vector<std::uint8_t> covered;  // a sample lies within the local spacing (not past an open boundary)
  std::vector<Vec3> point;
  std::vector<Vec3> normal;  // oriented
  std::vector<std::uint32_t> plane;
  std::vector<std::uint32_t> partner;  // the vertex across the crease it was brought back to, or none
  std::vector<std::uint8_t> trusted;   // moved onto its quadric (not left where it was: max_move)
  std::size_t unmoved = 0;
};

// The refined mesh under construction: the projected vertices, then the
// crease and corner vertices added (each crease vertex once, by its edge).
struct Builder {
  Mesh mesh;
  std::vector<float> displacement;
  /// The tangent planes each vertex lies on, by the projected vertex they
  /// belong to: its own for a projected vertex, both ends' for a crease vertex.
  std::vector<std::array<std::uint32_t, 2>> planes;
  std::vector<std::array<std::uint32_t, 2>> stem;                   // per vertex (RefinedPatch::stem)
  std::vector<std::uint32_t> source;                                // per triangle (RefinedPatch::source)
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

// A corner found in one or more triangles (candidates within an edge's
// length of one another count as one, the first found standing for them)
// is taken by the nearest vertex of those triangles: the mesh then has a
// vertex on it, where the crease lines of its faces meet.
struct CornerCandidate {
  Vec3 point;
  double reach;
  std::array<std::uint32_t, 3> triangle;
};

// A split can leave a sliver: a triangle (a, b, c) with c on the segment ab
// (a crease vertex in line with two others). Its longest edge ab is flipped
// with the triangle (b, a, d) across it: (c, a, d) and (c, d, b) split that
// triangle at c instead, unless c and d are joined already. Where the
// triangle across is a sliver too (several crease vertices in a row), no
// flip helps: one of the sliver's edges is collapsed instead. Both repeat
// until no sliver is left (a few passes at most).
using Triangles = std::vector<std::array<std::uint32_t, 3>>;

// One pass of flips; returns the slivers left as they were (a flip may make
// a new one: the next pass looks again).
struct Slivers {
  std::size_t flipped = 0;
  std::vector<std::uint32_t> left;
};

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

// Step 4: components (through shared vertices), the piece of data each is
// drawn from (the most common piece among its vertices' planes), and which
// to keep.
struct Fragments {
  std::vector<std::uint8_t> keep_triangle;
  std::size_t dropped = 0, dropped_triangles = 0;
};

// Step 1 (step1_project.cpp): every vertex onto a quadric.
Projected project_vertices(const Mesh& mesh, const RefinementInput& in, double max_move);
double curvature_along(const RefinementInput& in, std::uint32_t i, const Vec3& d);

// Step 2 (step2_sharpen.cpp): creases and corners; then welds and slivers.
std::size_t bring_back(Projected& pr, const Mesh& contoured, const RefinementInput& in, double cos_crease,
                       double max_move);
void sharpen(Builder& b, const Projected& pr, const Mesh& contoured, const RefinementInput& in, double cos_crease);

// Step 3 (step3_balance.cpp): the mean sag.
std::vector<double> mean_sag(const Mesh& contoured, const Projected& pr, double cos_crease);

// After step 3 (untangle.cpp): vertices put back where triangles cross or a
// vertex is pinched; per vertex 0 (kept), 1 (halfway back) or 2 (home).
std::vector<std::uint8_t> untangle(Builder& b, const Mesh& contoured);

// Step 4 (step4_clean.cpp): trimming, strays, fragments.
std::vector<std::uint8_t> covered_vertices(const Builder& b, const Projected& pr);
std::size_t trim_boundaries(RefinedPatch& patch);
std::vector<std::uint8_t> far_vertices(const Builder& b, const Projected& pr, const RefinementInput& in);
std::size_t drop_strays(RefinedPatch& patch);
Fragments find_fragments(const Mesh& mesh, const std::vector<std::uint32_t>& piece_of_vertex, double fraction);

// Around the steps (refinement.cpp).
void compact(Builder& b, const std::vector<std::uint8_t>& keep_triangle);

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

}  // namespace recon::refinement_steps
