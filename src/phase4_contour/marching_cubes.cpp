#include "recon/phase4_contour/marching_cubes.h"

#include "recon/core/detail/parallel_for.h"
#include "recon/core/errors.h"
#include "recon/core/interruption.h"
#include "recon/core/progress.h"
#include "recon/core/timer.h"
#include "recon/phase4_contour/detail/seed_wave.h"
#include "recon/phase4_contour/marching_cubes_table.h"
#include "recon/structures/detail/block_array.h"
#include "recon/structures/lattice_table.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace recon {
namespace {

using Index3 = Lattice<3>::Index;

std::uint64_t pack(const Index3& i) { return Lattice<3>::key(i); }
Index3 unpack(std::uint64_t key) { return Lattice<3>::index(key); }

// Corner c (0..7) of a cube, as marching_cubes_table.h numbers them.
Index3 corner_of_cube(const Index3& cube, int c) {
  return {cube[0] + (c & 1), cube[1] + ((c >> 1) & 1), cube[2] + ((c >> 2) & 1)};
}

constexpr double undefined = std::numeric_limits<double>::quiet_NaN();
constexpr double vertex_margin = 1e-3;  // fraction of an edge kept between a vertex and a corner

// The 4 corners (as bits) of the cube face on axis a at side 0 or 1.
constexpr unsigned face_corners(int a, int side) {
  unsigned bits = 0;
  for (int c = 0; c < 8; ++c)
    if (((c >> a) & 1) == side) bits |= 1u << c;
  return bits;
}

// The corners met by the walk, by slot of the lattice table. A slot holds
// the corner's value of f, the mesh vertex on each of the three lattice
// edges leaving the corner in the + direction, whether f has been evaluated
// there, and whether the cube whose lowest corner it is has been visited.
// One table does the work of a corner map, an edge map and a visited set.
class CornerTable {
 public:
  static constexpr std::uint32_t no_vertex = UINT32_MAX;
  static constexpr std::uint32_t absent = LatticeTable::absent;

  [[nodiscard]] std::size_t size() const { return index_.size(); }
  [[nodiscard]] std::uint32_t find(std::uint64_t key) const { return index_.find(key); }
  [[nodiscard]] std::uint64_t key(std::uint32_t slot) const { return index_.key(slot); }

  /// The slot of `key`, created (not evaluated, no vertices) if new.
  std::uint32_t find_or_insert(std::uint64_t key) {
    const auto [slot, added] = index_.insert(key);
    if (added) {
      value.push_back(undefined);
      flags.push_back(0);
      if (with_vertices_) vertex.push_back({no_vertex, no_vertex, no_vertex});
    }
    return slot;
  }
  /// Until this is called, slots have no vertex entries: a first wave
  /// laid out ahead of the walk (SeedWave) does without their 12 bytes.
  void add_vertices() {
    while (vertex.size() < size()) vertex.push_back({no_vertex, no_vertex, no_vertex});
    with_vertices_ = true;
  }

  detail::BlockArray<double> value;
  detail::BlockArray<std::array<std::uint32_t, 3>> vertex;
  static constexpr std::uint8_t visited_cube = 1, evaluated = 2;
  detail::BlockArray<std::uint8_t> flags;

 private:
  LatticeTable index_;
  bool with_vertices_ = false;
};

}  // namespace

double estimate_visited_cubes(std::size_t samples, double spacing, double cell) {
  // Area ~ samples * spacing^2; a surface of area A crosses about 1.5 A /
  // cell^2 cubes on average over its orientations (a plane along the
  // lattice crosses A / cell^2, a diagonal one up to 3 A / cell^2): the
  // upper figure is taken. A cube smaller than the spacing is still seeded
  // by every sample.
  const double area = static_cast<double>(samples) * spacing * spacing;
  return std::max(3.0 * area / (cell * cell), static_cast<double>(samples));
}

// ---------------------------------------------------------------------------
// The first wave (detail/seed_wave.h)

struct SeedWave::Walk {
  Lattice<3> lattice;
  CornerTable corners;               // the first wave's corners, then every corner the walk meets
  std::vector<std::uint64_t> cubes;  // the first wave: the cubes holding a seed, each once
};

struct SeedWaveAccess {
  static SeedWave::Walk& walk(SeedWave& wave) {
    if (!wave.walk_) throw InvalidInputError("this first wave was moved away (a wave is walked once)");
    return *wave.walk_;
  }
};

namespace {
void check_corner(const SeedWave& wave, std::size_t i) {
  if (i >= wave.corner_count())
    throw InvalidInputError("corner " + std::to_string(i) + " of a first wave of " +
                            std::to_string(wave.corner_count()) + " corners");
}
}  // namespace

SeedWave::SeedWave(std::span<const Vec3> seeds, double cell) : walk_(std::make_unique<Walk>()) {
  if (seeds.empty()) throw InvalidInputError("the lattice walk needs at least one seed");
  walk_->lattice = make_lattice<3>(seeds, cell);
  add_seeds(seeds, nullptr);
}

SeedWave::SeedWave(std::span<const Vec3> seeds, double cell, const LatticeRegion& region)
    : walk_(std::make_unique<Walk>()) {
  if (region.lattice.cell != cell) throw InvalidInputError("the region's lattice has another cell than the walk's");
  walk_->lattice = region.lattice;
  add_seeds(seeds, &region);
}

// A cube's key is that of its lowest corner (corner 0): the cube and its
// corners share the table, and the corners come in the order first met.
// Seeds in spatial order repeat their cube often: a run of seeds in one
// cube is looked at once.
void SeedWave::add_seeds(std::span<const Vec3> seeds, const LatticeRegion* region) {
  CornerTable& corners = walk_->corners;
  std::uint64_t previous = UINT64_MAX;
  for (const Vec3& p : seeds) {
    const Index3 cube = walk_->lattice.cell_of(p);
    if (pack(cube) == previous) continue;
    previous = pack(cube);
    if (region && !LatticeRegion::inside(cube, region->walk_lo, region->walk_hi)) continue;
    const std::uint32_t slot = corners.find_or_insert(pack(cube));
    if (corners.flags[slot] & CornerTable::visited_cube) continue;
    corners.flags[slot] |= CornerTable::visited_cube;
    walk_->cubes.push_back(pack(cube));
    for (int c = 1; c < 8; ++c) corners.find_or_insert(pack(corner_of_cube(cube, c)));
  }
}
SeedWave::SeedWave(SeedWave&&) noexcept = default;
SeedWave& SeedWave::operator=(SeedWave&&) noexcept = default;
SeedWave::~SeedWave() = default;

const Lattice<3>& SeedWave::lattice() const { return walk_->lattice; }
std::size_t SeedWave::cube_count() const { return walk_ ? walk_->cubes.size() : 0; }
std::size_t SeedWave::corner_count() const { return walk_ ? walk_->corners.size() : 0; }
Index3 SeedWave::corner(std::size_t i) const {
  check_corner(*this, i);
  return unpack(walk_->corners.key(static_cast<std::uint32_t>(i)));
}
void SeedWave::set_value(std::size_t i, double value) {
  check_corner(*this, i);
  CornerTable& corners = walk_->corners;
  corners.value[i] = value;
  corners.flags[i] |= CornerTable::evaluated;
}
double SeedWave::value(std::size_t i) const {
  check_corner(*this, i);
  return walk_->corners.flags[i] & CornerTable::evaluated ? walk_->corners.value[i] : undefined;
}

// ---------------------------------------------------------------------------
// The walk

namespace {

// The walk is breadth-first, one wave (the cubes at the same number of
// steps from the seeds) at a time, in batches of cubes (the first wave
// holds every cube with a sample: millions on a large scan), so the
// per-batch arrays stay small. Per batch: find the corners already met (in
// parallel: the table does not change meanwhile), add the new ones in wave
// order, evaluate f at those not evaluated yet (in parallel: f is by far
// the costliest part), classify each cube (in parallel), then emit, in wave
// order, each cube's vertices and triangles and the next wave. The order of
// cubes, and so the mesh, is the same for any number of threads.
class CubeWalk {
 public:
  CubeWalk(const ScalarField& f, SeedWave::Walk& start, const MarchingCubesOptions& options,
           MarchingCubesResult& result)
      : f_(f), lattice_(start.lattice), corners_(start.corners), options_(options), result_(result) {
    next_ = std::move(start.cubes);
    visited_ = next_.size();
    check_visited();
    result_.seed_cubes = visited_;
    corners_.add_vertices();
  }

  void run() {
    while (!next_.empty()) {
      wave_.swap(next_);
      next_.clear();
      for (std::size_t first = 0; first < wave_.size(); first += batch) {
        interruption_point();
        const std::size_t count = std::min(batch, wave_.size() - first);
        if (ProgressCounter* progress = progress_counter()) progress->advance_estimated(count);
        find_corners(first, count);
        add_corners(first, count);
        evaluate_corners();
        classify_cubes(count);
        emit_cubes(first, count);
      }
    }
    summarise();
  }

 private:
  static constexpr std::size_t batch = 65536;
  static constexpr std::uint16_t incomplete = 256;  // a configuration with an undefined corner

  void find_corners(std::size_t first, std::size_t count);
  void add_corners(std::size_t first, std::size_t count);
  void evaluate_corners();
  void classify_cubes(std::size_t count);
  void emit_cubes(std::size_t first, std::size_t count);
  void emit_triangles(const Index3& cube, const std::array<std::uint32_t, 8>& slots, unsigned config);
  void visit(const Index3& cube);
  void add_vertex(const Vec3& p, std::uint64_t corner, std::uint32_t axis);
  [[nodiscard]] bool owned(const Index3& cube) const {
    return !options_.region || LatticeRegion::inside(cube, options_.region->own_lo, options_.region->own_hi);
  }
  [[nodiscard]] bool walked(const Index3& cube) const {
    return !options_.region || LatticeRegion::inside(cube, options_.region->walk_lo, options_.region->walk_hi);
  }
  void check_visited() const;
  void summarise();

  const ScalarField& f_;
  const Lattice<3>& lattice_;
  CornerTable& corners_;
  const MarchingCubesOptions& options_;
  MarchingCubesResult& result_;
  std::size_t visited_ = 0;
  std::vector<std::uint64_t> wave_, next_;
  // Per cube of a batch: its corners' slots, the corners still to add or
  // evaluate (bits), its configuration, and the faces the walk goes on
  // through (bit 2 a + side).
  std::vector<std::array<std::uint32_t, 8>> slots_;
  std::vector<std::uint8_t> pending_, faces_;
  std::vector<std::uint16_t> config_;
  std::vector<std::uint32_t> fresh_;  // the batch's corners to evaluate
  std::chrono::steady_clock::duration field_time_{};
};

// Find: each cube's corners among those met so far. Corners met and
// evaluated need nothing more: `pending_` marks the others.
void CubeWalk::find_corners(std::size_t first, std::size_t count) {
  slots_.resize(count);
  pending_.resize(count);
  detail::parallel_for(count, [&](std::size_t w) {
    const Index3 cube = unpack(wave_[first + w]);
    std::uint8_t mask = 0;
    for (int c = 0; c < 8; ++c) {
      const std::uint32_t slot = corners_.find(pack(corner_of_cube(cube, c)));
      slots_[w][static_cast<std::size_t>(c)] = slot;
      if (slot == CornerTable::absent || !(corners_.flags[slot] & CornerTable::evaluated))
        mask = static_cast<std::uint8_t>(mask | (1u << c));
    }
    pending_[w] = mask;
  });
}

// Add: the corners not met yet, in wave order, and the list of corners to
// evaluate (each once).
void CubeWalk::add_corners(std::size_t first, std::size_t count) {
  fresh_.clear();
  for (std::size_t w = 0; w < count; ++w) {
    if (pending_[w] == 0) continue;
    const Index3 cube = unpack(wave_[first + w]);
    for (int c = 0; c < 8; ++c) {
      if (!((static_cast<unsigned>(pending_[w]) >> c) & 1u)) continue;
      std::uint32_t& slot = slots_[w][static_cast<std::size_t>(c)];
      if (slot == CornerTable::absent) slot = corners_.find_or_insert(pack(corner_of_cube(cube, c)));
      if (!(corners_.flags[slot] & CornerTable::evaluated)) {
        corners_.flags[slot] |= CornerTable::evaluated;
        fresh_.push_back(slot);
      }
    }
  }
}

// Evaluate: f at the new corners (NaN where undefined). The first failure
// is thrown once every thread is done.
void CubeWalk::evaluate_corners() {
  const auto started = std::chrono::steady_clock::now();
  std::exception_ptr failure;
  detail::parallel_for_dynamic(fresh_.size(), 256, [&](std::size_t i) {
    const std::uint32_t slot = fresh_[i];
    try {
      const std::optional<double> v = f_(lattice_.position(unpack(corners_.key(slot))));
      corners_.value[slot] = v ? *v : undefined;
    } catch (...) {
#pragma omp critical(recon_marching_cubes_failure)
      if (!failure) failure = std::current_exception();
    }
  });
  if (failure) std::rethrow_exception(failure);
  field_time_ += std::chrono::steady_clock::now() - started;
}

// Classify: each cube's configuration (bit c: corner c inside, f < 0), and
// the faces the walk goes on through: those crossed by the surface, or
// touched at a corner where f = 0 (the surface may go on in the neighbour
// only).
void CubeWalk::classify_cubes(std::size_t count) {
  config_.resize(count);
  faces_.resize(count);
  detail::parallel_for(count, [&](std::size_t w) {
    unsigned config = 0, zero = 0;
    bool complete = true;
    for (std::size_t c = 0; c < 8; ++c) {
      const double v = corners_.value[slots_[w][c]];
      // An undefined corner (NaN) is never compared: `<` on a NaN raises
      // the invalid-operation exception (see fp_traps.h).
      if (std::isnan(v)) {
        complete = false;
        continue;
      }
      if (v < 0.0) config |= 1u << c;
      if (v == 0.0) zero |= 1u << c;
    }
    std::uint8_t faces = 0;
    for (int a = 0; a < 3 && complete; ++a)
      for (int side = 0; side < 2; ++side) {
        const unsigned on_face = face_corners(a, side);
        const unsigned inside = config & on_face;
        if ((inside != 0 && inside != on_face) || (zero & on_face) != 0)
          faces = static_cast<std::uint8_t>(faces | (1u << (2 * a + side)));
      }
    config_[w] = complete ? static_cast<std::uint16_t>(config) : incomplete;
    faces_[w] = faces;
  });
}

// Emit, in wave order: each complete cube's triangles, and its neighbours
// across the faces the walk goes on through into the next wave.
void CubeWalk::emit_cubes(std::size_t first, std::size_t count) {
  for (std::size_t w = 0; w < count; ++w) {
    if (config_[w] == incomplete) {
      ++result_.undefined_cubes;
      continue;
    }
    const Index3 cube = unpack(wave_[first + w]);
    if (owned(cube)) emit_triangles(cube, slots_[w], config_[w]);
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        if (!((static_cast<unsigned>(faces_[w]) >> (2 * a + side)) & 1u)) continue;
        Index3 neighbour = cube;
        neighbour[static_cast<std::size_t>(a)] += side == 0 ? -1 : 1;
        visit(neighbour);
      }
  }
}

// A cube's triangles, as the case table gives them. Vertices: one per
// crossed lattice edge, kept in the slot of the edge's lower corner (shared
// with the neighbouring cubes); then the centres of the loops that need one
// (private to this cube).
void CubeWalk::emit_triangles(const Index3& cube, const std::array<std::uint32_t, 8>& slots, unsigned config) {
  Mesh& mesh = result_.mesh;
  const mc::CubeCase& cube_case = mc::cube_case(config);
  std::array<std::uint32_t, 12 + 4> vertex{};
  for (int l = 0; l < cube_case.loop_count; ++l) {
    const auto& loop = cube_case.loops[static_cast<std::size_t>(l)];
    Vec3 centre = Vec3::Zero();
    for (int j = 0; j < loop.size; ++j) {
      const int e = loop.edges[static_cast<std::size_t>(j)];
      const auto ends = mc::edge_corners(e);
      const int axis = mc::edge_axis(e);
      const std::uint32_t lower = slots[static_cast<std::size_t>(ends[0])];
      std::uint32_t& id = corners_.vertex[lower][static_cast<std::size_t>(axis)];
      if (id == CornerTable::no_vertex) {
        id = static_cast<std::uint32_t>(mesh.vertices.size());
        const double v0 = corners_.value[lower];
        const double v1 = corners_.value[slots[static_cast<std::size_t>(ends[1])]];
        const double t = std::clamp(v0 / (v0 - v1), vertex_margin, 1.0 - vertex_margin);
        Vec3 p = lattice_.position(corner_of_cube(cube, ends[0]));
        p[axis] += t * options_.cell;
        add_vertex(p, pack(corner_of_cube(cube, ends[0])), static_cast<std::uint32_t>(axis));
      }
      vertex[static_cast<std::size_t>(e)] = id;
      centre += mesh.vertices[id];
    }
    if (loop.centred) {
      vertex[static_cast<std::size_t>(mc::loop_centre + l)] = static_cast<std::uint32_t>(mesh.vertices.size());
      add_vertex(centre / loop.size, pack(cube), 3);
    }
  }
  for (int t = 0; t < cube_case.triangle_count; ++t) {
    const auto& tri = cube_case.triangles[static_cast<std::size_t>(t)];
    mesh.triangles.push_back({vertex[tri[0]], vertex[tri[1]], vertex[tri[2]]});
    if (options_.keep_triangle_cubes) result_.triangle_cubes.push_back(pack(cube));
  }
}

void CubeWalk::add_vertex(const Vec3& p, std::uint64_t corner, std::uint32_t axis) {
  result_.mesh.vertices.push_back(p);
  if (options_.keep_vertex_edges) result_.vertex_edges.push_back({corner, axis});
}

// A cube of the lattice not visited yet joins the next wave.
void CubeWalk::visit(const Index3& cube) {
  if (!lattice_.contains(cube) || !walked(cube)) return;
  const std::uint32_t slot = corners_.find_or_insert(pack(cube));
  if (corners_.flags[slot] & CornerTable::visited_cube) return;
  corners_.flags[slot] |= CornerTable::visited_cube;
  ++visited_;
  check_visited();
  next_.push_back(pack(cube));
}

void CubeWalk::check_visited() const {
  if (visited_ > options_.max_cubes)
    throw ResourceLimitError("the lattice walk passed " + std::to_string(options_.max_cubes) +
                             " cubes, the most the memory limit allows: use a larger --cell or a smaller "
                             "--resolution, or raise --max-memory");
}

void CubeWalk::summarise() {
  result_.visited_cubes = visited_;
  result_.evaluated_corners = corners_.size();
  for (std::uint32_t slot = 0; slot < corners_.size(); ++slot) {
    const double v = corners_.value[slot];
    if (std::isnan(v)) ++result_.undefined_corners;
    if (options_.keep_corners)
      result_.corners.push_back({unpack(corners_.key(slot)), std::isnan(v) ? 0.0 : v, !std::isnan(v)});
  }
  result_.seconds_field = std::chrono::duration<double>(field_time_).count();
}

}  // namespace

std::uint64_t triangle_cube(const MarchingCubesResult& result, std::size_t t) {
  const auto& tri = result.mesh.triangles[t];
  const auto& x = result.mesh.vertices;
  const Vec3 centre = (x[tri[0]] + x[tri[1]] + x[tri[2]]) / 3.0;
  Index3 cube;
  for (std::size_t a = 0; a < 3; ++a) {
    const auto i = static_cast<Eigen::Index>(a);
    cube[a] = static_cast<std::int32_t>(std::floor((centre[i] - result.origin[i]) / result.cell));
  }
  return pack(cube);
}

// The walk emits each cube's triangles together: they are moved as runs,
// one per cube, sorted by the cubes' keys (each cube is emitted once). The
// triangles and vertices are gathered into new arrays (reads from
// everywhere at once, not one after another as a permutation in place
// would make them), one array at a time.
void sort_by_cube(MarchingCubesResult& result) {
  Mesh& mesh = result.mesh;
  const std::size_t count = mesh.triangles.size();
  const bool cubes_kept = result.triangle_cubes.size() == count;
  struct Run {
    std::uint64_t cube;
    std::uint32_t first, end;  // its triangles
  };
  std::vector<Run> runs;
  for (std::uint32_t t = 0; t < count; ++t) {
    const std::uint64_t cube = triangle_cube(result, t);
    if (runs.empty() || runs.back().cube != cube) runs.push_back({cube, t, t});
    runs.back().end = t + 1;
  }
  std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.cube < b.cube; });
  {
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint64_t> cubes;
    triangles.reserve(count);
    for (const Run& r : runs)
      for (std::uint32_t t = r.first; t < r.end; ++t) {
        triangles.push_back(mesh.triangles[t]);
        if (cubes_kept) cubes.push_back(result.triangle_cubes[t]);
      }
    mesh.triangles = std::move(triangles);
    if (cubes_kept) result.triangle_cubes = std::move(cubes);
  }
  runs = {};
  // The vertices in the order the triangles first use them.
  constexpr std::uint32_t unused = UINT32_MAX;
  std::vector<std::uint32_t> renumber(mesh.vertices.size(), unused);
  std::uint32_t next = 0;
  for (auto& tri : mesh.triangles)
    for (std::uint32_t& v : tri) {
      if (renumber[v] == unused) renumber[v] = next++;
      v = renumber[v];
    }
  for (std::uint32_t& id : renumber)
    if (id == unused) id = next++;  // (a walk uses every vertex it makes)
  std::vector<Vec3> vertices(mesh.vertices.size());
  for (std::size_t v = 0; v < vertices.size(); ++v) vertices[renumber[v]] = mesh.vertices[v];
  mesh.vertices = std::move(vertices);
  if (result.vertex_edges.size() == renumber.size()) {
    std::vector<VertexEdge> edges(renumber.size());
    for (std::size_t v = 0; v < edges.size(); ++v) edges[renumber[v]] = result.vertex_edges[v];
    result.vertex_edges = std::move(edges);
  }
}

MarchingCubesResult marching_cubes(const ScalarField& f, std::span<const Vec3> seeds,
                                   const MarchingCubesOptions& options) {
  check_lattice_cell(options.cell);
  if (seeds.empty()) {
    MarchingCubesResult result;
    result.cell = options.cell;
    return result;
  }
  Timer timer;
  SeedWave wave = options.region ? SeedWave(seeds, options.cell, *options.region) : SeedWave(seeds, options.cell);
  const double seconds_wave = timer.lap();
  MarchingCubesResult result = marching_cubes(f, std::move(wave), options);
  result.seconds += seconds_wave;
  return result;
}

MarchingCubesResult marching_cubes(const ScalarField& f, SeedWave wave, const MarchingCubesOptions& options) {
  check_lattice_cell(options.cell);
  Timer timer;
  SeedWave::Walk& start = SeedWaveAccess::walk(wave);
  if (start.lattice.cell != options.cell)
    throw InvalidInputError("the first wave was laid out at another cell than the walk's");
  MarchingCubesResult result;
  result.cell = options.cell;
  result.origin = start.lattice.origin;
  result.size = start.lattice.size;
  CubeWalk(f, start, options, result).run();
  result.seconds = timer.lap();
  return result;
}

}  // namespace recon
