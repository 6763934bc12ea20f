// Steps 2 to 5 of a tiled run (tiles.h): orient each tile, reconcile the
// signs, contour each tile, stitch.
#include "recon/tiles.h"

#include "recon/errors.h"
#include "recon/io/mesh_stream.h"
#include "recon/memory_budget.h"
#include "recon/parallel.h"
#include "recon/timer.h"
#include "recon/union_find.h"
#include "tile_files.h"

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
using tile_files::PieceTop;
using tile_files::PointRecord;

namespace {

// A tile's points as its file holds them, in input order.
struct TilePoints {
  std::vector<Vec3> positions;
  std::vector<std::uint64_t> index;  // in the input
};

TilePoints read_points(const std::filesystem::path& dir, const TileInfo& info) {
  detail::BinaryReader in(tile_files::of_tile(dir, info.id, "points"), tile_files::points_magic);
  const std::vector<PointRecord> records = in.get_rest<PointRecord>();
  TilePoints t;
  t.positions.reserve(records.size());
  t.index.reserve(records.size());
  for (const PointRecord& r : records) {
    t.positions.emplace_back(r.x, r.y, r.z);
    t.index.push_back(r.index);
  }
  return t;
}

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
  in.points = read_points(dir, in.info);
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

// ---------------------------------------------------------------------------
// Step 2.

struct Orientation {
  std::vector<std::int8_t> sign;     // per tile point (file order): its normal against phase I's
  std::vector<std::uint32_t> piece;  // per tile point: its piece
  std::vector<PieceTop> tops;        // per piece
  std::vector<BorderRecord> border;
  std::uint64_t inexact = 0;
};

void write_orientation(const std::filesystem::path& path, const Orientation& o) {
  detail::BinaryWriter out(path, tile_files::orient_magic);
  out.put_vector<std::int8_t>(o.sign);
  out.put_vector<std::uint32_t>(o.piece);
  out.put_vector<PieceTop>(o.tops);
  out.put_vector<BorderRecord>(o.border);
  out.put(o.inexact);
  out.commit();
}

Orientation read_orientation(const std::filesystem::path& path) {
  detail::BinaryReader in(path, tile_files::orient_magic);
  Orientation o;
  o.sign = in.get_vector<std::int8_t>();
  o.piece = in.get_vector<std::uint32_t>();
  o.tops = in.get_vector<PieceTop>();
  o.border = in.get_vector<BorderRecord>();
  o.inexact = in.get<std::uint64_t>();
  return o;
}

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
// sample (spatial order) the plane, rho_i and the crease band, and the
// order that the kd-tree over the tile's points gives (step 4 builds the
// same tree, and checks it is the same).
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
  out.commit();
}

}  // namespace

TileOrientation orient_tile(const std::filesystem::path& work_dir, std::size_t tile) {
  Timer timer;
  const auto& [plan, info, points] = load_tile(work_dir, tile);
  std::optional<Reconstruction> r = tile_phase_1(plan, points);
  Orientation o;
  if (r) {
    o = orient_points(plan, tile_files::core_of(plan, tile), *r, points);
    write_planes(tile_files::of_tile(work_dir, info.id, "planes"), *r);
  }
  write_orientation(tile_files::of_tile(work_dir, info.id, "orient"), o);
  TileOrientation result;
  result.points = points.positions.size();
  result.pieces = o.tops.size();
  result.border_samples = o.border.size();
  result.inexact_samples = o.inexact;
  result.seconds = timer.elapsed();
  return result;
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
    Orientation o = read_orientation(tile_files::of_tile(dir, info.id, "orient"));
    g.first_node.push_back(g.tops.size());
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
std::vector<std::int8_t> reconcile(const SignGraph& g, TileReconciliation& result) {
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
  std::vector<std::int8_t> flip(n, 0);
  for (std::uint32_t v = 0; v < n; ++v) {
    if (root[v] == UINT32_MAX) continue;
    if (g.tops[root[v]].index != UINT64_MAX) ++result.objects;  // (pieces of halos alone are no object)
    std::vector<std::uint32_t> queue{root[v]};
    flip[root[v]] = 1;
    for (std::size_t q = 0; q < queue.size(); ++q)
      for (const auto& [next, relation] : tree[queue[q]])
        if (flip[next] == 0) {
          flip[next] = static_cast<std::int8_t>(flip[queue[q]] * relation);
          queue.push_back(next);
        }
  }
  return flip;
}

}  // namespace

TileReconciliation reconcile_tiles(const std::filesystem::path& work_dir) {
  Timer timer;
  const TilePlan plan = read_tile_plan(work_dir);
  const SignGraph g = sign_graph(work_dir, plan);
  TileReconciliation result;
  const std::vector<std::int8_t> flip = reconcile(g, result);
  result.nodes = g.tops.size();
  result.edges = g.edges.size();
  result.shared_samples = g.shared;
  result.turned = static_cast<std::size_t>(std::count(flip.begin(), flip.end(), std::int8_t{-1}));
  for (const auto& [nodes, agreement] : g.edges)
    result.disagreeing += flip[nodes.first] == flip[nodes.second] ? agreement.disagree : agreement.agree;
  detail::BinaryWriter out(tile_files::flips(work_dir), tile_files::flips_magic);
  out.put_vector<std::uint64_t>(g.first_node);
  out.put_vector<std::int8_t>(flip);
  out.commit();
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
};

TileSurface read_surface(const std::filesystem::path& path, const TilePlan& plan, const TilePoints& points) {
  detail::BinaryReader in(path, tile_files::planes_magic);
  TileSurface s;
  s.order = in.get_vector<std::uint32_t>();
  const std::vector<double> coordinates = in.get_vector<double>();
  s.planes.local_rho = in.get_vector<float>();
  s.near_crease = in.get_vector<std::uint8_t>();
  s.planes.noise = in.get<double>();
  const std::size_t n = s.order.size();
  WorkingTree w = working_tree(points.positions, TangentPlaneOptions{}.tree, plan.offset);
  if (w.order != s.order || coordinates.size() != 6 * n || s.planes.local_rho.size() != n ||
      (!s.near_crease.empty() && s.near_crease.size() != n))
    throw ParseError(path.string() + ": these planes are not those of the tile's points");
  s.planes.point_tree = std::move(w.tree);
  for (std::size_t j = 0; j < n; ++j) {
    s.planes.origins.emplace_back(coordinates[3 * j], coordinates[3 * j + 1], coordinates[3 * j + 2]);
    const std::size_t m = 3 * (n + j);
    s.planes.normals.emplace_back(coordinates[m], coordinates[m + 1], coordinates[m + 2]);
  }
  return s;
}

// The tile's normals, oriented as reconciled (spatial order).
std::vector<Vec3> reconciled_normals(const std::filesystem::path& dir, const Orientation& o, std::size_t tile,
                                     const TileSurface& s) {
  detail::BinaryReader in(tile_files::flips(dir), tile_files::flips_magic);
  const std::vector<std::uint64_t> first_node = in.get_vector<std::uint64_t>();
  const std::vector<std::int8_t> flip = in.get_vector<std::int8_t>();
  if (o.sign.size() != s.order.size() || tile >= first_node.size())
    throw ParseError(dir.string() + ": the orientation of tile " + std::to_string(tile) + " does not match its points");
  std::vector<Vec3> normals(s.order.size());
  for (std::size_t j = 0; j < normals.size(); ++j) {
    const std::uint32_t t = s.order[j];
    const std::uint64_t node = first_node[tile] + o.piece[t];
    if (node >= flip.size()) throw ParseError(tile_files::flips(dir).string() + ": too few pieces");
    normals[j] = s.planes.normals[j] * static_cast<double>(o.sign[t] * flip[node]);
  }
  return normals;
}

LatticeRegion region_of(const TilePlan& plan, const CoreBox& core) {
  LatticeRegion region;
  region.lattice = plan.lattice;
  region.own_lo = core.lo;
  region.own_hi = core.hi;
  for (std::size_t a = 0; a < 3; ++a) {
    region.walk_lo[a] = std::max(0, core.lo[a] - plan.walk_margin);
    region.walk_hi[a] = std::min(plan.lattice.size[a], core.hi[a] + plan.walk_margin);
  }
  return region;
}

void write_mesh(const std::filesystem::path& path, const MarchingCubesResult& contour, const Vec3& offset) {
  std::vector<MeshVertex> vertices(contour.mesh.vertices.size());
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const Vec3 p = contour.mesh.vertices[v] + offset;
    vertices[v] = {p.x(), p.y(), p.z(), contour.vertex_edges[v].corner, contour.vertex_edges[v].axis, 0};
  }
  detail::BinaryWriter out(path, tile_files::mesh_magic);
  out.put_vector<MeshVertex>(vertices);
  out.put_vector<std::array<std::uint32_t, 3>>(contour.mesh.triangles);
  out.commit();
}

}  // namespace

TileContour contour_tile(const std::filesystem::path& work_dir, std::size_t tile) {
  Timer timer;
  const auto& [plan, info, points] = load_tile(work_dir, tile);
  MarchingCubesResult contour;
  const auto planes_file = tile_files::of_tile(work_dir, info.id, "planes");
  const Orientation orientation = read_orientation(tile_files::of_tile(work_dir, info.id, "orient"));
  if (!orientation.sign.empty()) {  // (none when the tile makes no plane: then no planes file either)
    const TileSurface surface = read_surface(planes_file, plan, points);
    const std::vector<Vec3> normals = reconciled_normals(work_dir, orientation, tile, surface);
    const KdTree<3> origin_tree = surface.planes.point_tree.refit(surface.planes.origins);
    const ReconstructionOptions options = tile_files::tile_options(plan);
    SignedDistanceOptions distance = signed_distance_options(plan.method, options.distance, std::nullopt);
    distance.near_crease = surface.near_crease;
    const SignedDistance<3> f = make_signed_distance<3>(surface.planes, normals, origin_tree, distance);
    MarchingCubesOptions mc;
    mc.cell = plan.lattice.cell;
    mc.max_cubes = max_cubes_within(memory_limit_or_default(options.max_memory), points.positions.size());
    mc.region = region_of(plan, tile_files::core_of(plan, tile));
    mc.keep_vertex_edges = true;
    contour = marching_cubes(std::cref(f), surface.planes.point_tree.points(), mc);
  }
  write_mesh(tile_files::of_tile(work_dir, info.id, "mesh"), contour, plan.offset);
  TileContour result;
  result.vertices = contour.mesh.vertices.size();
  result.triangles = contour.mesh.triangles.size();
  result.visited_cubes = contour.visited_cubes;
  result.seconds = timer.elapsed();
  return result;
}

// ---------------------------------------------------------------------------
// Step 5.

namespace {

// Whether a lattice edge lies on a face of the core's box: another tile's
// cubes share it.
bool on_border(const MeshVertex& v, const CoreBox& core) {
  if (v.axis > 2) return false;
  const Lattice<3>::Index c = Lattice<3>::index(v.corner);
  for (std::size_t b = 0; b < 3; ++b)
    if (b != v.axis && (c[b] == core.lo[b] || c[b] == core.hi[b])) return true;
  return false;
}

}  // namespace

StitchedMesh stitch_tiles(const std::filesystem::path& work_dir, const std::filesystem::path& output) {
  Timer timer;
  const TilePlan plan = read_tile_plan(work_dir);
  io::PlyMeshStream out(output, false);
  std::unordered_map<std::uint64_t, std::array<std::uint32_t, 3>> border;  // per corner: its 3 edges' vertices
  StitchedMesh result;
  for (std::size_t tile = 0; tile < plan.tiles.size(); ++tile) {
    detail::BinaryReader in(tile_files::of_tile(work_dir, plan.tiles[tile].id, "mesh"), tile_files::mesh_magic);
    const std::vector<MeshVertex> vertices = in.get_vector<MeshVertex>();
    const auto triangles = in.get_vector<std::array<std::uint32_t, 3>>();
    const CoreBox core = tile_files::core_of(plan, tile);
    std::vector<std::uint32_t> id(vertices.size());
    for (std::size_t v = 0; v < vertices.size(); ++v) {
      const MeshVertex& m = vertices[v];
      std::uint32_t* slot = nullptr;
      if (on_border(m, core)) {
        auto [at, added] = border.try_emplace(m.corner, std::array<std::uint32_t, 3>{UINT32_MAX, UINT32_MAX, UINT32_MAX});
        slot = &at->second[m.axis];
        if (*slot != UINT32_MAX) {
          id[v] = *slot;
          ++result.welded;
          continue;
        }
      }
      id[v] = out.add_vertex(Vec3(m.x, m.y, m.z));
      if (slot) *slot = id[v];
    }
    for (const auto& t : triangles) {
      if (t[0] >= id.size() || t[1] >= id.size() || t[2] >= id.size())
        throw ParseError(tile_files::of_tile(work_dir, plan.tiles[tile].id, "mesh").string() +
                         ": a triangle names a vertex it does not have");
      out.add_triangle({id[t[0]], id[t[1]], id[t[2]]});
    }
  }
  result.vertices = out.vertex_count();
  result.triangles = out.triangle_count();
  out.finish();
  result.seconds = timer.elapsed();
  return result;
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

}  // namespace recon
