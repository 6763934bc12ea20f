// Phase V, after step 3 (refinement.h): the moved mesh untangled. Where two
// triangles now meet other than at what they share, a triangle has no area,
// or a vertex's triangles no longer form one fan, their vertices go back
// toward where the contoured mesh had them, halfway first, then all the way
// (plain vertices before those on creases and corners), and the mesh is
// checked again, until it is embedded or every vertex concerned is home.
#include "phase5_refine/refinement_steps.h"

#include "recon/structures/mesh_embedding.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace recon::refinement_steps {
namespace {

constexpr std::uint8_t home_level = 2;          // 0: as phase V moved it, 1: halfway back, 2: where it was contoured
constexpr int max_rounds = 3 * home_level * 2;  // (each tier to home; 2-6 rounds on the shapes tried)

// Where each vertex was before phase V moved it: a projected vertex its
// contoured vertex; a crease vertex the midpoint of the two vertices of the
// edge it split, where they are now (so that, both ends home, it lies on
// the contoured edge again).
class Homes {
 public:
  Homes(const Builder& b, const Mesh& contoured) : b_(b), contoured_(contoured), at_(contoured.vertices.size(), none) {
    for (std::uint32_t v = 0; v < b.stem.size(); ++v)
      if (b.stem[v][1] == none) at_[b.stem[v][0]] = v;
  }
  [[nodiscard]] Vec3 operator()(std::uint32_t v) const {
    const auto& stem = b_.stem[v];
    if (stem[1] == none) return contoured_.vertices[stem[0]];
    return 0.5 * (end(stem[0]) + end(stem[1]));
  }

 private:
  // An end of a split edge: its vertex now, or its contoured place if it was welded or collapsed away.
  [[nodiscard]] Vec3 end(std::uint32_t c) const {
    return at_[c] != none ? b_.mesh.vertices[at_[c]] : contoured_.vertices[c];
  }
  const Builder& b_;
  const Mesh& contoured_;
  std::vector<std::uint32_t> at_;  // per contoured vertex, the projected vertex it became (none: gone)
};

// What phase V made of v: 0 a plain vertex, 1 a crease vertex or one
// brought back onto a crease, 2 a corner. Creases and corners go back only
// where the plainer vertices of the same offence are home already.
int tier(const Builder& b, std::uint32_t v) {
  if (b.planes[v][0] == none) return 2;
  return b.stem[v][1] != none || b.planes[v][1] != none ? 1 : 0;
}

// The triangles a vertex put back has made numerically flat (as
// analyze_topology counts them: area under 1e-14 d^2, d the box's diagonal).
std::vector<std::uint32_t> flattened(const Mesh& mesh, const std::vector<std::uint8_t>& level) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& p : mesh.vertices) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double flat_area = 1e-14 * (hi - lo).squaredNorm();
  std::vector<std::uint32_t> out;
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& [a, b, c] = mesh.triangles[t];
    if (level[a] + level[b] + level[c] == 0) continue;
    const Vec3 &pa = mesh.vertices[a], &pb = mesh.vertices[b], &pc = mesh.vertices[c];
    if (0.5 * (pb - pa).cross(pc - pa).norm() <= flat_area) out.push_back(t);
  }
  return out;
}

// The vertices to put further back: for each offence (a crossing pair's six
// corners, a degenerate triangle's three, a pinched vertex), those not yet
// home, of the lowest tier among them. Sorted, each once.
std::vector<std::uint32_t> tangled(const Builder& b, const std::vector<std::uint8_t>& level) {
  const Mesh& mesh = b.mesh;
  const MeshEmbedding e = check_embedding(mesh);
  std::vector<std::uint32_t> out, offence;
  auto take = [&]() {
    std::erase_if(offence, [&](std::uint32_t v) { return level[v] >= home_level; });
    int lowest = 2;
    for (const std::uint32_t v : offence) lowest = std::min(lowest, tier(b, v));
    for (const std::uint32_t v : offence)
      if (tier(b, v) == lowest) out.push_back(v);
    offence.clear();
  };
  for (const auto& pair : e.pairs) {
    for (const std::uint32_t t : pair)
      offence.insert(offence.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
    take();
  }
  for (const std::uint32_t t : e.degenerate) {
    offence.assign(mesh.triangles[t].begin(), mesh.triangles[t].end());
    take();
  }
  for (const std::uint32_t t : flattened(mesh, level)) {
    offence.assign(mesh.triangles[t].begin(), mesh.triangles[t].end());
    take();
  }
  for (const std::uint32_t v : e.pinched) {
    offence.assign(1, v);
    take();
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

std::vector<std::uint8_t> untangle(Builder& b, const Mesh& contoured) {
  const std::size_t n = b.mesh.vertices.size();
  std::vector<std::uint8_t> level(n, 0);
  const std::vector<Vec3> moved = b.mesh.vertices;
  for (int round = 0; round < max_rounds; ++round) {
    const std::vector<std::uint32_t> bad = tangled(b, level);
    if (bad.empty()) break;
    for (const std::uint32_t v : bad) ++level[v];
    // Projected vertices first: a crease vertex's home is read from its ends.
    const Homes home(b, contoured);
    for (int pass = 0; pass < 2; ++pass)
      for (std::uint32_t v = 0; v < n; ++v) {
        if (level[v] == 0 || (b.stem[v][1] == none) != (pass == 0)) continue;
        const double back = static_cast<double>(level[v]) / home_level;
        b.mesh.vertices[v] = moved[v] + back * (home(v) - moved[v]);
        const Vec3 from = b.stem[v][1] == none
                              ? contoured.vertices[b.stem[v][0]]
                              : 0.5 * (contoured.vertices[b.stem[v][0]] + contoured.vertices[b.stem[v][1]]);
        b.displacement[v] = static_cast<float>((b.mesh.vertices[v] - from).norm());
      }
  }
  return level;
}

}  // namespace recon::refinement_steps
