// Step 4 of a tiled run (tiles.h): phases III to V on each tile's core,
// with the reconciled signs, and the tile's own part of the mesh written
// for the stitch.
#include "recon/core/errors.h"
#include "recon/core/timer.h"
#include "recon/reconstruct_parts.h"
#include "recon/tiles/tiles.h"
#include "tiles/files.h"
#include "tiles/tile_input.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace recon {

using tile_files::CoreBox;
using tile_files::MeshVertex;
using tile_files::Orientation;
using tile_files::TilePoints;
using namespace tile_input;

namespace {

// Phase I's planes as step 2 wrote them, over the tile's own kd-tree.
struct TileSurface {
  TangentPlanes<3> planes;
  std::vector<std::uint32_t> order;
  std::vector<std::uint8_t> near_crease;
  std::vector<Curvature> curvature;  // (the refined method's)
};

TileSurface read_surface(const std::filesystem::path& path, const TilePlan& plan, const TilePoints& points) {
  detail::BinaryReader in(path, tile_files::planes_magic);
  TileSurface s;
  s.order = in.get_vector<std::uint32_t>();
  const std::vector<double> coordinates = in.get_vector<double>();
  s.planes.local_rho = in.get_vector<float>();
  s.near_crease = in.get_vector<std::uint8_t>();
  s.planes.noise = in.get<double>();
  const std::vector<float> curvature = in.get_vector<float>();
  s.planes.local_gap = in.get_vector<float>();
  s.planes.rho = in.get<double>();
  in.finish();
  const std::size_t n = s.order.size();
  WorkingTree w = working_tree(points.positions, TangentPlaneOptions{}.tree, plan.offset);
  if (w.order != s.order || coordinates.size() != 6 * n || s.planes.local_rho.size() != n ||
      (!s.near_crease.empty() && s.near_crease.size() != n) ||
      curvature.size() != (plan.method == Method::refined ? 3 * n : 0) || s.planes.local_gap.size() != n)
    throw ParseError(path.string() + ": these planes are not those of the tile's points");
  for (const double c : coordinates)
    if (!std::isfinite(c)) throw ParseError(path.string() + ": a plane's origin or normal is not finite");
  s.planes.point_tree = std::move(w.tree);
  for (std::size_t j = 0; j < n; ++j) {
    s.planes.origins.emplace_back(coordinates[3 * j], coordinates[3 * j + 1], coordinates[3 * j + 2]);
    const std::size_t m = 3 * (n + j);
    s.planes.normals.emplace_back(coordinates[m], coordinates[m + 1], coordinates[m + 2]);
  }
  for (std::size_t c = 0; c < curvature.size(); c += 3)
    s.curvature.push_back({curvature[c], curvature[c + 1], curvature[c + 2]});
  return s;
}

// The tile's normals, oriented as reconciled, and the object each belongs
// to (spatial order).
struct Reconciled {
  std::vector<Vec3> normals;
  std::vector<std::uint32_t> object;
};

Reconciled reconciled_planes(const std::filesystem::path& dir, const Orientation& o, std::size_t tile,
                             const TileSurface& s) {
  const tile_files::Flips flips = tile_files::read_flips(dir);
  if (o.sign.size() != s.order.size())
    throw ParseError(dir.string() + ": the orientation of tile " + std::to_string(tile) + " does not match its points");
  if (tile >= flips.first_node.size() || flips.pieces_of(tile).second - flips.pieces_of(tile).first != o.tops.size())
    throw ParseError(tile_files::flips(dir).string() + ": its pieces of tile " + std::to_string(tile) +
                     " are not those of the tile's orientation");
  const std::uint64_t first = flips.pieces_of(tile).first;
  Reconciled r;
  r.normals.resize(s.order.size());
  r.object.resize(s.order.size());
  for (std::size_t j = 0; j < s.order.size(); ++j) {
    const std::uint32_t t = s.order[j];             // (< o.piece.size(): read_surface checked the order)
    const std::uint64_t node = first + o.piece[t];  // (o.piece[t] < o.tops.size(): read_orientation checked)
    r.normals[j] = s.planes.normals[j] * static_cast<double>(o.sign[t] * flips.flip[node]);
    r.object[j] = flips.object[node];
  }
  return r;
}

// The walk: the core and the ring around it emit triangles, and the walk
// may go 2 cubes further.
LatticeRegion region_of(const TilePlan& plan, const CoreBox& core) {
  LatticeRegion region;
  region.lattice = plan.lattice;
  for (std::size_t a = 0; a < 3; ++a) {
    region.own_lo[a] = std::max(0, core.lo[a] - plan.ring);
    region.own_hi[a] = std::min(plan.lattice.size[a], core.hi[a] + plan.ring);
    region.walk_lo[a] = std::max(0, core.lo[a] - plan.walk_margin);
    region.walk_hi[a] = std::min(plan.lattice.size[a], core.hi[a] + plan.walk_margin);
  }
  return region;
}

// The tile's mesh before its own triangles are picked: the core's and the
// ring's triangles, in their cubes' order (sort_by_cube), refined when the
// method is (phase V's steps 1-3, refinement.h), or as contoured.
struct TilePatch {
  MarchingCubesResult contour;
  RefinedPatch refined;
};

RefinedPatch unrefined(const Mesh& contoured) {
  RefinedPatch p;
  p.mesh = contoured;
  const std::size_t n = contoured.vertices.size();
  p.displacement.assign(n, 0.0f);
  p.stem.resize(n);
  for (std::uint32_t v = 0; v < n; ++v) p.stem[v] = {v, RefinedPatch::none};
  p.covered.assign(n, 1);
  p.far.assign(n, 0);
  p.piece.assign(n, RefinedPatch::none);
  p.source.resize(contoured.triangles.size());
  for (std::uint32_t t = 0; t < p.source.size(); ++t) p.source[t] = t;
  return p;
}

// Phase V's options in a tile: reconstruct()'s, with the fitted normals
// recorded when the mesh gets normals.
RefinementOptions tile_refinement_options(const TilePlan& plan) {
  RefinementOptions options = refinement_options(plan.refinement, plan.lattice.cell);
  options.fitted_normals = plan.normals;
  return options;
}

TilePatch tile_patch(const TilePlan& plan, std::size_t tile, const TileSurface& surface, const Reconciled& reconciled,
                     std::size_t points) {
  const KdTree<3> origin_tree = surface.planes.point_tree.refit(surface.planes.origins);
  const ReconstructionOptions options = tile_files::tile_options(plan);
  SignedDistanceOptions distance = signed_distance_options(plan.method, options.distance, std::nullopt);
  distance.near_crease = surface.near_crease;
  const SignedDistance<3> f = make_signed_distance<3>(surface.planes, reconciled.normals, origin_tree, distance);
  MarchingCubesOptions mc;
  mc.cell = plan.lattice.cell;
  mc.max_cubes = max_cubes_within(memory_limit_or_default(options.max_memory), points);
  mc.region = region_of(plan, tile_files::core_of(plan, tile));
  mc.keep_vertex_edges = true;
  TilePatch patch;
  patch.contour = marching_cubes(std::cref(f), surface.planes.point_tree.points(), mc);
  sort_by_cube(patch.contour);
  patch.refined = plan.method == Method::refined
                      ? refine_patch(patch.contour.mesh,
                                     refinement_input(surface.planes, reconciled.normals, surface.curvature,
                                                      reconciled.object, f, origin_tree),
                                     tile_refinement_options(plan))
                      : unrefined(patch.contour.mesh);
  return patch;
}

// The name of a patch vertex in the whole mesh (MeshVertex).
void name_vertex(const TilePatch& patch, std::uint32_t v, MeshVertex& out) {
  const auto& stem = patch.refined.stem[v];
  VertexEdge a = patch.contour.vertex_edges[stem[0]];
  out.corner[0] = a.corner;
  out.axis[0] = a.axis;
  if (stem[1] == RefinedPatch::none) return;
  VertexEdge b = patch.contour.vertex_edges[stem[1]];
  if (std::tie(b.corner, b.axis) < std::tie(a.corner, a.axis)) std::swap(a, b);  // (the lesser first)
  out.corner[0] = a.corner;
  out.axis[0] = a.axis;
  out.corner[1] = b.corner;
  out.axis[1] = b.axis;
}

// Step 4 of phase V is decided over the whole mesh at the stitch; each tile
// marks what it needs among its own triangles (see stitch_tiles):
//   - peelable components: own triangles whose three vertices are
//     uncovered, joined across edges; open where one of them has an edge
//     no other triangle of the patch shares (the mesh's open boundary);
//   - atoms: components of the own triangles that stay whatever is peeled
//     (not peelable, not strays), joined through vertices; a vertex only
//     peelable triangles use is an atom of its own;
//   - the votes of the vertices no other tile uses for the objects they
//     stand for (a shared vertex votes at the stitch, once).
void mark_peelable(const RefinedPatch& p, const std::vector<std::uint32_t>& own, tile_files::TileMesh& out) {
  std::vector<std::uint32_t> peelable;  // indices into own
  for (std::uint32_t o = 0; o < own.size(); ++o) {
    const auto& t = p.mesh.triangles[own[o]];
    if (!p.covered[t[0]] && !p.covered[t[1]] && !p.covered[t[2]]) peelable.push_back(o);
  }
  if (peelable.empty()) return;
  std::unordered_map<std::uint64_t, std::uint32_t>
      sides;  // edge of a peelable triangle -> triangles of the patch on it
  for (const std::uint32_t o : peelable)
    for (std::size_t e = 0; e < 3; ++e)
      sides.emplace(edge_key(p.mesh.triangles[own[o]][e], p.mesh.triangles[own[o]][(e + 1) % 3]), 0);
  for (const auto& t : p.mesh.triangles)
    for (std::size_t e = 0; e < 3; ++e)
      if (const auto it = sides.find(edge_key(t[e], t[(e + 1) % 3])); it != sides.end()) ++it->second;
  UnionFind sets(peelable.size());
  std::unordered_map<std::uint64_t, std::uint32_t> first;  // edge -> the first peelable triangle on it
  for (std::uint32_t q = 0; q < peelable.size(); ++q)
    for (std::size_t e = 0; e < 3; ++e) {
      const auto& t = p.mesh.triangles[own[peelable[q]]];
      const auto [it, added] = first.emplace(edge_key(t[e], t[(e + 1) % 3]), q);
      if (!added) sets.unite(it->second, q);
    }
  std::vector<std::uint32_t> number(peelable.size(), tile_files::none);  // per set (root): its component
  for (std::uint32_t q = 0; q < peelable.size(); ++q) {
    std::uint32_t& c = number[sets.find(q)];
    if (c == tile_files::none) {
      c = static_cast<std::uint32_t>(out.peel_open.size());
      out.peel_open.push_back(0);
    }
    out.triangles[peelable[q]].peel = c;
    const auto& t = p.mesh.triangles[own[peelable[q]]];
    for (std::size_t e = 0; e < 3; ++e)
      if (sides.at(edge_key(t[e], t[(e + 1) % 3])) == 1) out.peel_open[c] = 1;
  }
}

void mark_atoms(const RefinedPatch& p, const std::vector<std::uint32_t>& own, tile_files::TileMesh& out,
                const std::vector<std::uint32_t>& written) {
  UnionFind sets(p.mesh.vertices.size());
  for (std::uint32_t o = 0; o < own.size(); ++o) {
    const auto& t = p.mesh.triangles[own[o]];
    if (out.triangles[o].peel != tile_files::none || out.triangles[o].stray) continue;
    sets.unite(t[0], t[1]);
    sets.unite(t[0], t[2]);
  }
  std::vector<std::uint32_t> atom_of_root(p.mesh.vertices.size(), tile_files::none);
  auto atom_of = [&](std::uint32_t root) {
    std::uint32_t& a = atom_of_root[root];
    if (a == tile_files::none) {
      a = static_cast<std::uint32_t>(out.atom_triangles.size());
      out.atom_triangles.push_back(0);
    }
    return a;
  };
  for (std::uint32_t o = 0; o < own.size(); ++o) {  // the lasting triangles first, then the peelable ones
    const auto& t = p.mesh.triangles[own[o]];
    if (out.triangles[o].peel != tile_files::none || out.triangles[o].stray) continue;
    const std::uint32_t a = atom_of(sets.find(t[0]));
    ++out.atom_triangles[a];
    for (const std::uint32_t v : t) out.vertices[written[v]].atom = a;
  }
  for (std::uint32_t o = 0; o < own.size(); ++o) {
    const auto& t = p.mesh.triangles[own[o]];
    if (out.triangles[o].peel == tile_files::none || out.triangles[o].stray) continue;
    for (const std::uint32_t v : t)
      if (out.vertices[written[v]].atom == tile_files::none) out.vertices[written[v]].atom = atom_of(sets.find(v));
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint64_t> votes;
  for (const MeshVertex& v : out.vertices)
    if (!v.shared && v.atom != tile_files::none && v.object != tile_files::none) ++votes[{v.atom, v.object}];
  for (const auto& [key, count] : votes) out.votes.push_back({key.first, key.second, count});
}

// The colours of the vertices `at` (working coordinates), blended from the
// tile's samples' as reconstruct() blends them (vertex_colors.h).
void blend_colors(const TilePlan& plan, const TileSurface& surface, const TilePoints& points,
                  const std::vector<Vec3>& at, tile_files::TileMesh& out) {
  std::vector<Color> colors(surface.order.size());  // (spatial order, as the tree's points)
  for (std::size_t j = 0; j < colors.size(); ++j) colors[j] = points.colors[surface.order[j]];
  const std::vector<Color> blended = vertex_colors(at, surface.planes.point_tree, colors, plan.color_blend);
  for (std::size_t v = 0; v < at.size(); ++v)
    out.vertices[v].color =
        std::uint32_t{blended[v][0]} | std::uint32_t{blended[v][1]} << 8 | std::uint32_t{blended[v][2]} << 16;
}

// The tile's own triangles (those cut from its core's cubes) and the
// vertices they use, named for the stitch; `at`: those vertices in working
// coordinates.
tile_files::TileMesh own_mesh(const TilePlan& plan, std::size_t tile, const TilePatch& patch, std::vector<Vec3>& at) {
  const RefinedPatch& p = patch.refined;
  const CoreBox core = tile_files::core_of(plan, tile);
  std::vector<std::uint32_t> own;  // patch triangles
  std::vector<std::uint8_t> used_own(p.mesh.vertices.size(), 0), used_other(p.mesh.vertices.size(), 0);
  for (std::uint32_t t = 0; t < p.mesh.triangles.size(); ++t) {
    const auto cube = Lattice<3>::index(triangle_cube(patch.contour, p.source[t]));
    const bool mine = LatticeRegion::inside(cube, core.lo, core.hi);
    if (mine) own.push_back(t);
    for (const std::uint32_t v : p.mesh.triangles[t]) (mine ? used_own : used_other)[v] = 1;
  }
  tile_files::TileMesh out;
  std::vector<std::uint32_t> written(p.mesh.vertices.size(), tile_files::none);
  for (std::uint32_t v = 0; v < p.mesh.vertices.size(); ++v) {
    if (!used_own[v]) continue;
    written[v] = static_cast<std::uint32_t>(out.vertices.size());
    at.push_back(p.mesh.vertices[v]);
    MeshVertex m;
    const Vec3 x = p.mesh.vertices[v] + plan.offset;
    m.x = x.x();
    m.y = x.y();
    m.z = x.z();
    name_vertex(patch, v, m);
    m.shared = used_other[v];
    m.object = p.piece[v];
    if (p.mesh.has_normals())
      for (std::size_t k = 0; k < 3; ++k)
        m.normal[k] = static_cast<float>(p.mesh.normals[v][static_cast<Eigen::Index>(k)]);
    out.vertices.push_back(m);
  }
  for (const std::uint32_t t : own) {
    const auto& tri = p.mesh.triangles[t];
    tile_files::MeshTriangle m;
    for (std::size_t c = 0; c < 3; ++c) m.v[c] = written[tri[c]];
    m.stray = p.far[tri[0]] && p.far[tri[1]] && p.far[tri[2]] ? 1 : 0;
    out.triangles.push_back(m);
  }
  if (plan.method == Method::refined) {
    mark_peelable(p, own, out);
    mark_atoms(p, own, out, written);
  }
  return out;
}

TileContour contour_one_tile(const std::filesystem::path& work_dir, std::size_t tile) {
  Timer timer;
  const auto& [plan, info, points] = load_tile(work_dir, tile);
  const Orientation orientation = tile_files::read_orientation(tile_files::of_tile(work_dir, info.id, "orient"));
  tile_files::TileMesh mesh;
  TileContour result;
  if (!orientation.sign.empty()) {  // (none when the tile makes no plane: then no planes file either)
    const TileSurface surface = read_surface(tile_files::of_tile(work_dir, info.id, "planes"), plan, points);
    const TilePatch patch = tile_patch(plan, tile, surface, reconciled_planes(work_dir, orientation, tile, surface),
                                       points.positions.size());
    std::vector<Vec3> at;
    mesh = own_mesh(plan, tile, patch, at);
    if (plan.colors) blend_colors(plan, surface, points, at, mesh);
    result.visited_cubes = patch.contour.visited_cubes;
  }
  tile_files::write_mesh(tile_files::of_tile(work_dir, info.id, "mesh"), mesh);
  result.vertices = mesh.vertices.size();
  result.triangles = mesh.triangles.size();
  result.seconds = timer.elapsed();
  return result;
}

}  // namespace

TileContour contour_tile(const std::filesystem::path& work_dir, std::size_t tile) {
  return naming_tile("contouring", tile, [&] { return contour_one_tile(work_dir, tile); });
}

}  // namespace recon
