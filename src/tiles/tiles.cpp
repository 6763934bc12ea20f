// Steps 2 to 5 of a tiled run (tiles.h): orient each tile, reconcile the
// signs, contour each tile, stitch.
#include "recon/tiles/tiles.h"

#include "recon/core/errors.h"
#include "recon/reconstruct_parts.h"
#include "recon/core/memory_budget.h"
#include "recon/core/parallel.h"
#include "recon/core/timer.h"
#include "recon/structures/union_find.h"
#include "tiles/files.h"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <exception>
#include <map>
#include <mutex>
#include <thread>
#include <tuple>
#include <unordered_map>

namespace recon {

using tile_files::BorderRecord;
using tile_files::outside_core;
using tile_files::CoreBox;
using tile_files::MeshVertex;
using tile_files::Orientation;
using tile_files::PieceTop;
using tile_files::PointRecord;

namespace {

using tile_files::TilePoints;

const TileInfo& tile_info(const TilePlan& plan, std::size_t tile) {
  if (tile >= plan.tiles.size())
    throw InvalidInputError("tile " + std::to_string(tile) + " of a plan of " + std::to_string(plan.tiles.size()) +
                            " tiles");
  return plan.tiles[tile];
}

// What steps 2 and 4 start from: the plan, the tile and its points.
struct TileInput {
  TilePlan plan;
  TileInfo info;
  TilePoints points;
};

TileInput load_tile(const std::filesystem::path& dir, std::size_t tile) {
  TileInput in;
  in.plan = read_tile_plan(dir);
  in.info = tile_info(in.plan, tile);
  in.points = tile_files::read_points(dir, in.plan, in.info);
  return in;
}

// Phase I over a tile, with the plan's cloud-wide choices. Null when the
// tile's points make no plane: fewer than k + 1 of them, or no k + 1
// distinct ones, or only degenerate neighbourhoods (a tile of strays or of
// copies of one point, which draw nothing in the whole cloud either).
std::optional<Reconstruction> tile_phase_1(const TilePlan& plan, const TilePoints& points) {
  if (points.positions.size() <= static_cast<std::size_t>(plan.k)) return std::nullopt;
  const ReconstructionOptions options = tile_files::tile_options(plan);
  try {
    return reconstruct_phase_1(PointCloudView(points.positions, {}, {}), options);
  } catch (const InvalidInputError&) {  // (the plan's options passed the statistics' run already)
    return std::nullopt;
  }
}

// Runs a step of tile `tile`; a recon error from it (a damaged file, a
// limit) comes out with the same type, its message naming the step and
// the tile: from a Dask task that message is all the user sees.
template <class Step>
auto naming_tile(const char* step, std::size_t tile, const Step& run) -> decltype(run()) {
  const std::string where = std::string(step) + " tile " + std::to_string(tile) + ": ";
  try {
    return run();
  } catch (const ParseError& e) {
    throw ParseError(where + e.what());
  } catch (const IoError& e) {
    throw IoError(where + e.what(), e.error_code());
  } catch (const ResourceLimitError& e) {
    throw ResourceLimitError(where + e.what());
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(where + e.what());
  }
}

// ---------------------------------------------------------------------------
// Step 2.

// What the reconciliation needs of one oriented sample j (spatial order).
void note_sample(const TilePlan& plan, const CoreBox& core, const Reconstruction& r, const TilePoints& points,
                 std::size_t j, Orientation& o) {
  const Vec3 w = r.points()[j];
  const std::uint32_t t = r.order[j];
  const double out = outside_core(plan, core, w);
  const std::uint32_t piece = o.piece[t];
  if (out <= 0.0) {  // a core sample: each is one tile's
    PieceTop& top = o.tops[piece];
    if (std::tie(w.z(), top.index) > std::tie(top.z, points.index[t]) || top.index == UINT64_MAX)
      top = {w.z(), points.index[t]};
  }
  if (out > plan.exact_margin) return;
  if (r.planes.local_rho[j] > 0.0f && out + 2.0 * static_cast<double>(r.planes.radius[j]) > plan.halo) ++o.inexact;
  if (out < -plan.exact_margin) return;
  const Vec3 n = r.oriented->normals[j];
  o.border.push_back({points.index[t], piece, {static_cast<float>(n.x()), static_cast<float>(n.y()),
                                               static_cast<float>(n.z())}});
}

Orientation orient_points(const TilePlan& plan, const CoreBox& core, Reconstruction& r, const TilePoints& points) {
  const ReconstructionOptions options = tile_files::tile_options(plan);
  const OrientationOptions orientation = orientation_options(r, options);
  RiemannianGraph<3> graph = build_riemannian_graph<3>(r.planes, orientation.graph);
  r.planes.neighbors = {};
  r.oriented = orient_normals<3>(r.planes, std::move(graph), orientation);
  Orientation o;
  const std::size_t n = points.positions.size();
  o.sign.resize(n);
  o.piece.resize(n);
  o.tops.resize(r.oriented->component_count());
  for (std::size_t j = 0; j < n; ++j) {
    o.sign[r.order[j]] = r.oriented->normals[j].dot(r.planes.normals[j]) >= 0.0 ? 1 : -1;
    o.piece[r.order[j]] = r.oriented->graph.components.label[j];
  }
  for (std::size_t j = 0; j < n; ++j) note_sample(plan, core, r, points, j, o);
  std::sort(o.border.begin(), o.border.end(),
            [](const BorderRecord& a, const BorderRecord& b) { return a.index < b.index; });
  return o;
}

// What step 4 needs of phase I, so that it does not run it again: per
// sample (spatial order) the plane, rho_i and the crease band, and for
// phase V the curvature and spacing; and the order that the kd-tree over
// the tile's points gives (step 4 builds the same tree, and checks it is
// the same).
void write_planes(const std::filesystem::path& path, const Reconstruction& r) {
  detail::BinaryWriter out(path, tile_files::planes_magic);
  out.put_vector<std::uint32_t>(r.order);
  std::vector<double> coordinates;
  coordinates.reserve(6 * r.order.size());
  for (const auto* vectors : {&r.planes.origins, &r.planes.normals})
    for (const Vec3& v : *vectors) coordinates.insert(coordinates.end(), {v.x(), v.y(), v.z()});
  out.put_vector<double>(coordinates);
  out.put_vector<float>(r.planes.local_rho);
  out.put_vector<std::uint8_t>(r.quadrics ? std::span<const std::uint8_t>(r.quadrics->near_crease)
                                          : std::span<const std::uint8_t>());
  out.put(r.planes.noise);
  std::vector<float> curvature;
  if (r.quadrics) {
    curvature.reserve(3 * r.quadrics->curvature.size());
    for (const Curvature& c : r.quadrics->curvature) curvature.insert(curvature.end(), {c.p, c.q, c.r});
  }
  out.put_vector<float>(curvature);
  out.put_vector<float>(r.planes.local_gap);
  out.put(r.planes.rho);
  out.commit();
}

TileOrientation orient_one_tile(const std::filesystem::path& work_dir, std::size_t tile) {
  Timer timer;
  const auto& [plan, info, points] = load_tile(work_dir, tile);
  std::optional<Reconstruction> r = tile_phase_1(plan, points);
  Orientation o;
  if (r) {
    o = orient_points(plan, tile_files::core_of(plan, tile), *r, points);
    write_planes(tile_files::of_tile(work_dir, info.id, "planes"), *r);
  }
  tile_files::write_orientation(tile_files::of_tile(work_dir, info.id, "orient"), o);
  TileOrientation result;
  result.points = points.positions.size();
  result.pieces = o.tops.size();
  result.border_samples = o.border.size();
  result.inexact_samples = o.inexact;
  result.seconds = timer.elapsed();
  return result;
}

}  // namespace

TileOrientation orient_tile(const std::filesystem::path& work_dir, std::size_t tile) {
  return naming_tile("orienting", tile, [&] { return orient_one_tile(work_dir, tile); });
}

// ---------------------------------------------------------------------------
// Step 3.

namespace {

struct Agreement {
  std::uint64_t agree = 0, disagree = 0;
};
using NodePair = std::pair<std::uint32_t, std::uint32_t>;

struct SignGraph {
  std::vector<std::uint64_t> first_node;  // per tile, its first node
  std::vector<PieceTop> tops;             // per node
  std::map<NodePair, Agreement> edges;
  std::size_t shared = 0;
};

// Nodes, and the edges between the pieces that orient the same samples.
SignGraph sign_graph(const std::filesystem::path& dir, const TilePlan& plan) {
  SignGraph g;
  std::vector<BorderRecord> border;
  for (const TileInfo& info : plan.tiles) {
    Orientation o = tile_files::read_orientation(tile_files::of_tile(dir, info.id, "orient"));
    g.first_node.push_back(g.tops.size());
    if (o.tops.size() >= tile_files::none - g.tops.size())
      throw ResourceLimitError("the tiles hold more than 2^32 pieces between them; use larger tiles");
    for (BorderRecord& b : o.border) b.node += static_cast<std::uint32_t>(g.tops.size());
    g.tops.insert(g.tops.end(), o.tops.begin(), o.tops.end());
    border.insert(border.end(), o.border.begin(), o.border.end());
  }
  std::sort(border.begin(), border.end(), [](const BorderRecord& a, const BorderRecord& b) {
    return std::tie(a.index, a.node) < std::tie(b.index, b.node);
  });
  for (std::size_t s = 0; s < border.size();) {
    std::size_t e = s + 1;
    while (e < border.size() && border[e].index == border[s].index) ++e;
    for (std::size_t a = s; a < e; ++a)
      for (std::size_t b = a + 1; b < e; ++b) {
        const BorderRecord &x = border[a], &y = border[b];
        const float dot = x.normal[0] * y.normal[0] + x.normal[1] * y.normal[1] + x.normal[2] * y.normal[2];
        Agreement& edge = g.edges[{x.node, y.node}];
        (dot >= 0.0f ? edge.agree : edge.disagree) += 1;
        ++g.shared;
      }
    s = e;
  }
  return g;
}

// The maximum spanning forest by margin of agreement (Kruskal), walked
// breadth-first from each object's highest piece, which keeps its sign.
// Per node: its sign, and its object (the node it was walked from).
struct Signs {
  std::vector<std::int8_t> flip;
  std::vector<std::uint32_t> object;
};

Signs reconcile(const SignGraph& g, TileReconciliation& result) {
  const std::size_t n = g.tops.size();
  std::vector<std::pair<NodePair, Agreement>> edges(g.edges.begin(), g.edges.end());
  const auto margin = [](const Agreement& a) { return a.agree > a.disagree ? a.agree - a.disagree : a.disagree - a.agree; };
  std::stable_sort(edges.begin(), edges.end(),
                   [&](const auto& a, const auto& b) { return margin(a.second) > margin(b.second); });
  UnionFind sets(n);
  std::vector<std::vector<std::pair<std::uint32_t, std::int8_t>>> tree(n);
  for (const auto& [nodes, agreement] : edges) {
    if (!sets.unite(nodes.first, nodes.second)) continue;
    const std::int8_t relation = agreement.agree >= agreement.disagree ? 1 : -1;
    tree[nodes.first].emplace_back(nodes.second, relation);
    tree[nodes.second].emplace_back(nodes.first, relation);
  }
  std::vector<std::uint32_t> root(n, UINT32_MAX);  // per set: its highest node
  for (std::uint32_t v = 0; v < n; ++v) {
    std::uint32_t& best = root[sets.find(v)];
    const auto higher = [&](std::uint32_t a, std::uint32_t b) {
      return std::tie(g.tops[a].z, g.tops[b].index) > std::tie(g.tops[b].z, g.tops[a].index);
    };
    if (best == UINT32_MAX || higher(v, best)) best = v;
  }
  Signs s{std::vector<std::int8_t>(n, 0), std::vector<std::uint32_t>(n, UINT32_MAX)};
  for (std::uint32_t v = 0; v < n; ++v) {
    if (root[v] == UINT32_MAX) continue;
    if (g.tops[root[v]].index != UINT64_MAX) ++result.objects;  // (pieces of halos alone are no object)
    std::vector<std::uint32_t> queue{root[v]};
    s.flip[root[v]] = 1;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      s.object[queue[q]] = root[v];
      for (const auto& [next, relation] : tree[queue[q]])
        if (s.flip[next] == 0) {
          s.flip[next] = static_cast<std::int8_t>(s.flip[queue[q]] * relation);
          queue.push_back(next);
        }
    }
  }
  return s;
}

}  // namespace

TileReconciliation reconcile_tiles(const std::filesystem::path& work_dir) {
  Timer timer;
  const TilePlan plan = read_tile_plan(work_dir);
  const SignGraph g = sign_graph(work_dir, plan);
  TileReconciliation result;
  const Signs signs = reconcile(g, result);
  const std::vector<std::int8_t>& flip = signs.flip;
  result.nodes = g.tops.size();
  result.edges = g.edges.size();
  result.shared_samples = g.shared;
  result.turned = static_cast<std::size_t>(std::count(flip.begin(), flip.end(), std::int8_t{-1}));
  for (const auto& [nodes, agreement] : g.edges)
    result.disagreeing += flip[nodes.first] == flip[nodes.second] ? agreement.disagree : agreement.agree;
  tile_files::write_flips(work_dir, {g.first_node, flip, signs.object});
  result.seconds = timer.elapsed();
  return result;
}

// ---------------------------------------------------------------------------
// Step 4.

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
  for (std::size_t c = 0; c < curvature.size(); c += 3) s.curvature.push_back({curvature[c], curvature[c + 1], curvature[c + 2]});
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
    const std::uint32_t t = s.order[j];  // (< o.piece.size(): read_surface checked the order)
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
  patch.refined =
      plan.method == Method::refined
          ? refine_patch(patch.contour.mesh,
                         refinement_input(surface.planes, reconciled.normals, surface.curvature, reconciled.object, f,
                                          origin_tree),
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
  std::unordered_map<std::uint64_t, std::uint32_t> sides;  // edge of a peelable triangle -> triangles of the patch on it
  for (const std::uint32_t o : peelable)
    for (std::size_t e = 0; e < 3; ++e) sides.emplace(edge_key(p.mesh.triangles[own[o]][e], p.mesh.triangles[own[o]][(e + 1) % 3]), 0);
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
    out.vertices[v].color = std::uint32_t{blended[v][0]} | std::uint32_t{blended[v][1]} << 8 |
                            std::uint32_t{blended[v][2]} << 16;
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
      for (std::size_t k = 0; k < 3; ++k) m.normal[k] = static_cast<float>(p.mesh.normals[v][static_cast<Eigen::Index>(k)]);
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
    const TilePatch patch =
        tile_patch(plan, tile, surface, reconciled_planes(work_dir, orientation, tile, surface), points.positions.size());
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

namespace {

// Two tiles at a time, each on half the threads, when two of the largest
// fit in 0.8 of the memory limit: while one tile's Prim runs (serial), the
// other core works on the other tile. The files are the same either way.
int tile_lanes(const TilePlan& plan, const TilingOptions& options) {
  if (thread_count() < 2) return 1;
  std::uint64_t largest = 0;
  for (const TileInfo& t : plan.tiles) largest = std::max(largest, t.points);
  const double tile = estimated_bytes_reconstruction(largest, plan.k, plan.method == Method::refined);
  return 2.0 * tile <= 0.8 * static_cast<double>(memory_limit_or_default(options.reconstruction.max_memory)) ? 2 : 1;
}

// step(t) for every tile, `lanes` at a time; done() after each (one at a time).
void for_each_tile(std::size_t tiles, int lanes, const std::function<void(std::size_t)>& step,
                   const std::function<void()>& done) {
  std::atomic<std::size_t> next{0};
  std::mutex lock;
  std::exception_ptr failure;
  const int threads = std::max(1, thread_count() / lanes);
  const auto lane = [&] {
    if (lanes > 1) set_thread_count(threads);  // (this thread's own setting)
    for (std::size_t t; (t = next++) < tiles;) {
      try {
        step(t);
        const std::lock_guard hold(lock);
        done();
      } catch (...) {
        const std::lock_guard hold(lock);
        if (!failure) failure = std::current_exception();
        next = tiles;
      }
    }
  };
  if (lanes <= 1) {
    lane();
  } else {
    std::vector<std::thread> pool;
    for (int l = 0; l < lanes; ++l) pool.emplace_back(lane);
    for (std::thread& thread : pool) thread.join();
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace

TiledRun reconstruct_tiled(const PointPass& pass, const TilingOptions& options, const std::filesystem::path& work_dir,
                           const std::filesystem::path& output,
                           const std::function<void(const char*, std::size_t, std::size_t)>& on_tile) {
  Timer timer;
  const auto report = [&](const char* step, std::size_t done, std::size_t total) {
    if (on_tile) on_tile(step, done, total);
  };
  TiledRun run;
  report("planning", 0, 1);
  run.plan = plan_tiles(pass, options, work_dir);
  const std::size_t tiles = run.plan.tiles.size();
  const int lanes = tile_lanes(run.plan, options);
  std::size_t finished = 0;
  const auto counted = [&](const char* step) {
    finished = 0;
    report(step, 0, tiles);
    return [&, step] { report(step, ++finished, tiles); };
  };
  run.orientations.resize(tiles);
  for_each_tile(tiles, lanes, [&](std::size_t t) { run.orientations[t] = orient_tile(work_dir, t); },
                counted("orienting"));
  report("reconciling", 0, 1);
  run.reconciliation = reconcile_tiles(work_dir);
  run.contours.resize(tiles);
  for_each_tile(tiles, lanes, [&](std::size_t t) { run.contours[t] = contour_tile(work_dir, t); },
                counted("contouring"));
  report("stitching", 0, 1);
  run.mesh = stitch_tiles(work_dir, output);
  run.seconds = timer.elapsed();
  return run;
}

namespace tile_files {

TilePoints read_points(const std::filesystem::path& dir, const TilePlan& plan, const TileInfo& info) {
  const std::vector<PointRecord> records = read_point_records(of_tile(dir, info.id, "points"));
  TilePoints t;
  t.positions.reserve(records.size());
  t.index.reserve(records.size());
  for (const PointRecord& r : records) {
    t.positions.emplace_back(r.x, r.y, r.z);
    t.index.push_back(r.index);
  }
  if (plan.colors) {
    const auto path = of_tile(dir, info.id, "colors");
    t.colors = read_colors(path);
    if (t.colors.size() != t.positions.size())
      throw ParseError(path.string() + ": " + std::to_string(t.colors.size()) + " colours for " +
                       std::to_string(t.positions.size()) + " points");
  }
  return t;
}

}  // namespace tile_files

}  // namespace recon
