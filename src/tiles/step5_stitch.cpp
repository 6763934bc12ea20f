// Step 5 of a tiled run (tiles.h): the tiles' own triangles into one mesh,
// welded where tiles meet, with phase V's step 4 (refinement.h) decided
// over the whole mesh, as refine_mesh decides it in memory:
//   - trim: a peelable component (triangles with three uncovered vertices,
//     joined across edges) goes when it reaches the mesh's open boundary.
//     Each tile numbers its own components and marks those that reach
//     it; here they are joined across tile borders by the edges they share;
//   - strays go (each tile marked them);
//   - fragments: a component smaller than fragment_fraction of the largest
//     drawn from the same object goes. Each tile joins its own triangles
//     into atoms (see step4_contour.cpp); here atoms are joined through the
//     vertices tiles share and the peelable triangles that stay, and their
//     triangles and votes are added up.
//   - normals (when the plan has them): a vertex's fitted normal, written by
//     its tile, or else the area-weighted mean of the kept triangles around
//     it (vertex_normals.h): summed over its tile's triangles as it is
//     written, and for a vertex tiles share, over every tile's, in a pass
//     of its own before the writing. The sums add the same triangles as
//     reconstruct()'s, in another order: the same normals to rounding.
// The stitch reads every tile's mesh twice: once to decide, once to write
// (three times with normals).
#include "recon/tiles/tiles.h"

#include "recon/core/errors.h"
#include "recon/core/timer.h"
#include "recon/io/mesh_stream.h"
#include "recon/reconstruct_parts.h"  // refuse_no_surface
#include "recon/structures/union_find.h"
#include "tiles/files.h"

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

namespace recon {

namespace {

using tile_files::MeshTriangle;
using tile_files::MeshVertex;
using tile_files::none;
using tile_files::TileMesh;

// A vertex's name in the whole mesh (MeshVertex).
struct WeldKey {
  std::uint64_t corner[2];
  std::uint32_t axis[2];
  friend bool operator==(const WeldKey& a, const WeldKey& b) {
    return a.corner[0] == b.corner[0] && a.corner[1] == b.corner[1] && a.axis[0] == b.axis[0] && a.axis[1] == b.axis[1];
  }
};
struct WeldKeyHash {
  std::size_t operator()(const WeldKey& k) const {
    std::uint64_t h = k.corner[0] * 0x9E3779B97F4A7C15ull;
    h ^= (k.corner[1] + (std::uint64_t{k.axis[0]} << 2 | k.axis[1])) * 0xC2B2AE3D27D4EB4Full;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
WeldKey key_of(const MeshVertex& v) { return {{v.corner[0], v.corner[1]}, {v.axis[0], v.axis[1]}}; }

// A vertex more than one tile uses.
struct Welded {
  std::uint32_t id = 0;       // among the welded (names the edges between them)
  std::uint32_t atom = none;  // (global) of the first tile where it had one: it voted there
  std::uint32_t out = none;   // in the output, once written
  Vec3 faces = Vec3::Zero();  // with normals: the cross products of the kept triangles around it
};

Vec3 position_of(const MeshVertex& v) { return {v.x, v.y, v.z}; }
bool has_normal(const MeshVertex& v) { return v.normal[0] != 0.0f || v.normal[1] != 0.0f || v.normal[2] != 0.0f; }

// Twice the area of triangle t along its normal.
Vec3 cross_of(const TileMesh& m, const MeshTriangle& t) {
  const Vec3 a = position_of(m.vertices[t.v[0]]);
  return (position_of(m.vertices[t.v[1]]) - a).cross(position_of(m.vertices[t.v[2]]) - a);
}

// A unit vector along `sum`; +z when it is zero (every triangle around the
// vertex has zero area: reconstruct() takes its neighbours' mean there).
Vec3 unit_or_up(const Vec3& sum) {
  const double norm = sum.norm();
  return norm > 0.0 && std::isfinite(norm) ? Vec3(sum / norm) : Vec3::UnitZ();
}

Color color_of(const MeshVertex& v) {
  return {static_cast<std::uint8_t>(v.color & 0xFF), static_cast<std::uint8_t>(v.color >> 8 & 0xFF),
          static_cast<std::uint8_t>(v.color >> 16 & 0xFF)};
}

class Stitch {
 public:
  explicit Stitch(const TilePlan& plan) : plan_(plan) {}

  // Pass 1, per tile: its atoms and peelable components join the global ones.
  void gather(const TileMesh& m, StitchedMesh& result) {
    const auto atom_base = static_cast<std::uint32_t>(atoms_.size());
    const auto peel_base = static_cast<std::uint32_t>(peels_.size());
    atom_base_.push_back(atom_base);
    peel_base_.push_back(peel_base);
    for (const std::uint64_t count : m.atom_triangles) {
      atoms_.add();
      atom_triangles_.push_back(count);
    }
    for (const std::uint8_t open : m.peel_open) {
      peels_.add();
      peel_open_.push_back(open);
    }
    for (const auto& v : m.votes) votes_[{atom_base + v.atom, v.object}] += v.count;
    std::vector<std::uint32_t> weld_id(m.vertices.size(), none);
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
      const MeshVertex& x = m.vertices[v];
      if (!x.shared) continue;
      const auto [at, added] =
          welded_.try_emplace(key_of(x), Welded{static_cast<std::uint32_t>(welded_.size()), none, none});
      if (!added) ++result.welded;
      weld_id[v] = at->second.id;
      if (x.atom == none) continue;
      if (at->second.atom == none) {
        at->second.atom = atom_base + x.atom;
        if (x.object != none) ++votes_[{atom_base + x.atom, x.object}];
      } else {
        atoms_.unite(at->second.atom, atom_base + x.atom);
      }
    }
    for (const MeshTriangle& t : m.triangles) {
      if (t.peel == none) continue;
      const std::uint32_t node = peel_base + t.peel;
      for (std::size_t e = 0; e < 3; ++e) {
        const std::uint32_t a = weld_id[t.v[e]], b = weld_id[t.v[(e + 1) % 3]];
        if (a == none || b == none) continue;
        const auto [at, added] = peel_edges_.try_emplace(edge_key(a, b), node);
        if (!added) peels_.unite(at->second, node);
      }
      if (!t.stray)
        peelable_.push_back({node,
                             {atom_base + m.vertices[t.v[0]].atom, atom_base + m.vertices[t.v[1]].atom,
                              atom_base + m.vertices[t.v[2]].atom}});
    }
  }

  // Between the passes: which peelable components go, then which components.
  void decide(StitchedMesh& result) {
    peeled_.assign(peels_.size(), 0);
    for (std::uint32_t p = 0; p < peels_.size(); ++p)
      if (peel_open_[p]) peeled_[peels_.find(p)] = 1;
    for (const Pending& p : peelable_) {
      if (peeled(p.peel)) continue;
      atoms_.unite(p.atom[0], p.atom[1]);
      atoms_.unite(p.atom[0], p.atom[2]);
      ++atom_triangles_[p.atom[0]];
    }
    kept_.assign(atoms_.size(), 1);
    if (plan_.method == Method::refined && !plan_.refinement.keep_fragments) drop_fragments(result);
  }

  // Pass 1b, per tile (with normals): the kept triangles' cross products
  // added to the shared vertices without a fitted normal.
  void sum_shared_faces(const TileMesh& m, std::size_t tile) {
    for (const MeshTriangle& t : m.triangles) {
      if (fate(m, tile, t) != Fate::kept) continue;
      const Vec3 cross = cross_of(m, t);
      for (const std::uint32_t v : t.v)
        if (m.vertices[v].shared && !has_normal(m.vertices[v])) welded_.at(key_of(m.vertices[v])).faces += cross;
    }
  }

  // Pass 2, per tile: the triangles that stay, and the vertices they use.
  void write(const TileMesh& m, std::size_t tile, io::PlyMeshStream& out, StitchedMesh& result) {
    std::vector<std::uint32_t> id(m.vertices.size(), none);
    const std::vector<Vec3> faces = plan_.normals ? own_faces(m, tile) : std::vector<Vec3>{};
    const auto vertex = [&](std::uint32_t v) {
      if (id[v] != none) return id[v];
      const MeshVertex& x = m.vertices[v];
      Welded* welded = x.shared ? &welded_.at(key_of(x)) : nullptr;
      if (welded && welded->out != none) return id[v] = welded->out;
      const Color color = color_of(x);
      if (plan_.normals) {
        const Vec3 normal = has_normal(x) ? Vec3(static_cast<double>(x.normal[0]), static_cast<double>(x.normal[1]),
                                                 static_cast<double>(x.normal[2]))
                                          : unit_or_up(welded ? welded->faces : faces[v]);
        id[v] = out.add_vertex(position_of(x), plan_.colors ? &color : nullptr, normal);
      } else {
        id[v] = plan_.colors ? out.add_vertex(position_of(x), color) : out.add_vertex(position_of(x));
      }
      if (welded) welded->out = id[v];
      if (x.corner[1] != UINT64_MAX) ++result.crease_vertices;
      return id[v];
    };
    for (const MeshTriangle& t : m.triangles) {
      switch (fate(m, tile, t)) {
        case Fate::trimmed:
          ++result.trimmed;
          break;
        case Fate::stray:
          ++result.stray_triangles;
          break;
        case Fate::fragment:
          break;
        case Fate::kept:
          out.add_triangle({vertex(t.v[0]), vertex(t.v[1]), vertex(t.v[2])});
          break;
      }
    }
  }

 private:
  struct Pending {
    std::uint32_t peel;
    std::array<std::uint32_t, 3> atom;
  };

  [[nodiscard]] bool peeled(std::uint32_t node) { return peeled_[peels_.find(node)] != 0; }

  // What step 4 decided of triangle t of `tile` (after decide()).
  enum class Fate { kept, trimmed, stray, fragment };
  [[nodiscard]] Fate fate(const TileMesh& m, std::size_t tile, const MeshTriangle& t) {
    if (t.peel != none && peeled(peel_base_[tile] + t.peel)) return Fate::trimmed;
    if (t.stray) return Fate::stray;
    const std::uint32_t atom = m.vertices[t.v[0]].atom;
    if (atom != none && !kept_[atoms_.find(atom_base_[tile] + atom)]) return Fate::fragment;
    return Fate::kept;
  }

  // The kept triangles' cross products around each vertex of the tile
  // only it uses, without a fitted normal (its triangles are all here).
  [[nodiscard]] std::vector<Vec3> own_faces(const TileMesh& m, std::size_t tile) {
    std::vector<Vec3> sum(m.vertices.size(), Vec3::Zero());
    for (const MeshTriangle& t : m.triangles) {
      if (fate(m, tile, t) != Fate::kept) continue;
      const Vec3 cross = cross_of(m, t);
      for (const std::uint32_t v : t.v)
        if (!m.vertices[v].shared && !has_normal(m.vertices[v])) sum[v] += cross;
    }
    return sum;
  }

  // As refine_mesh's step 4: a component (a set of atoms) smaller than
  // fragment_fraction of the largest drawn from the same object goes; its
  // object is the one most of its vertices vote for.
  void drop_fragments(StitchedMesh& result) {
    std::map<std::uint32_t, std::uint64_t> triangles;  // per component (root atom)
    for (std::uint32_t a = 0; a < atoms_.size(); ++a)
      if (atom_triangles_[a] > 0) triangles[atoms_.find(a)] += atom_triangles_[a];
    if (triangles.size() < 2) return;
    std::map<std::uint32_t, std::map<std::uint32_t, std::uint64_t>> votes;  // per component, per object
    for (const auto& [key, count] : votes_) votes[atoms_.find(key.first)][key.second] += count;
    std::map<std::uint32_t, std::uint32_t> object;   // per component
    std::map<std::uint32_t, std::uint64_t> largest;  // per object
    for (const auto& [root, count] : triangles) {
      std::uint32_t best = 0;
      std::uint64_t most = 0;
      for (const auto& [o, c] : votes[root])
        if (c > most) {  // (ties: the lower object, met first)
          most = c;
          best = o;
        }
      object[root] = best;
      largest[best] = std::max(largest[best], count);
    }
    for (const auto& [root, count] : triangles)
      if (static_cast<double>(count) <
          plan_.refinement.fragment_fraction * static_cast<double>(largest[object[root]])) {
        kept_[root] = 0;
        ++result.fragments;
        result.fragment_triangles += count;
      }
  }

  const TilePlan& plan_;
  std::unordered_map<WeldKey, Welded, WeldKeyHash> welded_;
  UnionFind atoms_{0};
  std::vector<std::uint64_t> atom_triangles_;
  UnionFind peels_{0};
  std::vector<std::uint8_t> peel_open_, peeled_, kept_;
  std::unordered_map<std::uint64_t, std::uint32_t>
      peel_edges_;                 // edge between welded vertices -> a peelable component on it
  std::vector<Pending> peelable_;  // peelable triangles, strays aside
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint64_t> votes_;  // (atom, object) -> vertices
  std::vector<std::uint32_t> atom_base_, peel_base_;                        // per tile
};

}  // namespace

StitchedMesh stitch_tiles(const std::filesystem::path& work_dir, const std::filesystem::path& output) {
  Timer timer;
  const TilePlan plan = read_tile_plan(work_dir);
  const auto mesh_of = [&](std::size_t tile) {
    return tile_files::read_mesh(tile_files::of_tile(work_dir, plan.tiles[tile].id, "mesh"));
  };
  StitchedMesh result;
  Stitch stitch(plan);
  for (std::size_t tile = 0; tile < plan.tiles.size(); ++tile) stitch.gather(mesh_of(tile), result);
  stitch.decide(result);
  if (plan.normals)
    for (std::size_t tile = 0; tile < plan.tiles.size(); ++tile) stitch.sum_shared_faces(mesh_of(tile), tile);
  io::PlyMeshStream out(output, plan.colors, plan.normals);
  for (std::size_t tile = 0; tile < plan.tiles.size(); ++tile) stitch.write(mesh_of(tile), tile, out, result);
  result.vertices = out.vertex_count();
  result.triangles = out.triangle_count();
  if (result.triangles == 0) {  // (the output is not written: `out` removes its temporaries)
    std::ostringstream figures;
    figures.precision(3);
    figures << "no tile's contour holds a triangle (cell " << plan.lattice.cell << "; tiles: " << plan.tiles.size()
            << ")";
    refuse_no_surface(figures.str(), plan.lattice.cell, plan.box.extent().maxCoeff(), "--cell, or a smaller --rho");
  }
  out.finish();
  result.seconds = timer.elapsed();
  return result;
}

}  // namespace recon
