#include "recon/marching_cubes.h"

#include "recon/errors.h"
#include "recon/interruption.h"
#include "recon/marching_cubes_table.h"
#include "recon/timer.h"

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

// Lattice coordinates packed 21 bits per axis into one 64-bit key.
constexpr int key_bits = 21;
constexpr std::int32_t max_cubes_per_axis = (1 << key_bits) - 2;
constexpr std::uint64_t key_mask = (std::uint64_t{1} << key_bits) - 1;

using Index3 = std::array<std::int32_t, 3>;

std::uint64_t pack(const Index3& i) {
  return static_cast<std::uint64_t>(i[0]) | (static_cast<std::uint64_t>(i[1]) << key_bits) |
         (static_cast<std::uint64_t>(i[2]) << (2 * key_bits));
}

Index3 unpack(std::uint64_t key) {
  return {static_cast<std::int32_t>(key & key_mask), static_cast<std::int32_t>((key >> key_bits) & key_mask),
          static_cast<std::int32_t>((key >> (2 * key_bits)) & key_mask)};
}

Index3 corner_of_cube(const Index3& cube, int c) {
  return {cube[0] + (c & 1), cube[1] + ((c >> 1) & 1), cube[2] + ((c >> 2) & 1)};
}

constexpr double undefined = std::numeric_limits<double>::quiet_NaN();

// The 4 corners (as bits) of the cube face on axis a at side 0 or 1.
constexpr unsigned face_corners(int a, int side) {
  unsigned bits = 0;
  for (int c = 0; c < 8; ++c)
    if (((c >> a) & 1) == side) bits |= 1u << c;
  return bits;
}
constexpr double vertex_margin = 1e-3;  // fraction of an edge kept between a vertex and a corner

// Where a lattice key goes in a hash table of 2^bits cells (bits >= 6). The
// corners of each 4 x 4 x 4 block stay together: the block is hashed, the
// place inside it is not. A cube's corners and its neighbours' then share a
// few cache lines of the table rather than one each: lookups are much of
// the walk's time once the table outgrows the caches (at 10M points the
// walk took 10.2 s with this hash against 12.4 s with one that scatters
// every corner, in one pair of runs).
std::size_t lattice_hash(std::uint64_t key, int bits) {
  constexpr std::uint64_t low = 3u | (std::uint64_t{3} << key_bits) | (std::uint64_t{3} << (2 * key_bits));
  const std::uint64_t inside = (key & 3u) | ((key >> key_bits) & 3u) << 2 | ((key >> (2 * key_bits)) & 3u) << 4;
  const std::uint64_t block = ((key & ~low) * 0x9E3779B97F4A7C15ull) >> (64 - (bits - 6));
  return static_cast<std::size_t>((block << 6) | inside);
}

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

namespace {

// An array that grows by fixed blocks rather than by reallocation: no
// moment holds both an old and a new copy (with tens of millions of corners,
// a doubling vector's growth alone can add hundreds of megabytes to the peak).
template <class T>
class BlockArray {
 public:
  [[nodiscard]] std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return blocks_[i >> block_bits][i & block_mask]; }
  const T& operator[](std::size_t i) const { return blocks_[i >> block_bits][i & block_mask]; }
  void push_back(const T& value) {
    if ((size_ & block_mask) == 0) blocks_.push_back(std::make_unique<T[]>(block_mask + 1));
    (*this)[size_++] = value;
  }

 private:
  static constexpr int block_bits = 16;
  static constexpr std::size_t block_mask = (std::size_t{1} << block_bits) - 1;
  std::vector<std::unique_ptr<T[]>> blocks_;
  std::size_t size_ = 0;
};

// Lattice keys numbered in the order first inserted ("slots"), found
// through an open-addressing hash table (linear probing) over lattice_hash.
class LatticeIndex {
 public:
  static constexpr std::uint32_t absent = UINT32_MAX;  // no such slot; also marks an empty table cell

  [[nodiscard]] std::size_t size() const { return keys_.size(); }
  /// The slot of `key`, or `absent`. Safe from many threads while nothing is
  /// inserted.
  [[nodiscard]] std::uint32_t find(std::uint64_t key) const {
    for (std::size_t h = hash(key);; h = (h + 1) & (table_.size() - 1)) {
      const std::uint32_t slot = table_[h];
      if (slot == absent || keys_[slot] == key) return slot;
    }
  }
  [[nodiscard]] std::uint64_t key(std::uint32_t slot) const { return keys_[slot]; }
  /// The slot of `key`, and whether it was added (as slot size() - 1).
  std::pair<std::uint32_t, bool> insert(std::uint64_t key) {
    if (2 * (keys_.size() + 1) > table_.size()) grow();
    std::size_t h = hash(key);
    for (; table_[h] != absent; h = (h + 1) & (table_.size() - 1))
      if (keys_[table_[h]] == key) return {table_[h], false};
    const auto slot = static_cast<std::uint32_t>(keys_.size());
    table_[h] = slot;
    keys_.push_back(key);
    return {slot, true};
  }

 private:
  [[nodiscard]] std::size_t hash(std::uint64_t key) const { return lattice_hash(key, bits_); }
  void grow() {
    table_.assign(table_.size() * 2, absent);
    ++bits_;
    for (std::uint32_t slot = 0; slot < keys_.size(); ++slot) {
      std::size_t h = hash(keys_[slot]);
      while (table_[h] != absent) h = (h + 1) & (table_.size() - 1);
      table_[h] = slot;
    }
  }
  std::vector<std::uint32_t> table_ = std::vector<std::uint32_t>(1024, absent);
  BlockArray<std::uint64_t> keys_;
  int bits_ = 10;
};

// The corners met by the walk, by slot. A slot holds the corner's value of
// f, the mesh vertex on each of the three lattice edges leaving the corner
// in the + direction, whether f has been evaluated there, and whether the
// cube whose lowest corner it is has been visited. One table does the work
// of a corner map, an edge map and a visited set.
class CornerTable {
 public:
  static constexpr std::uint32_t no_vertex = UINT32_MAX;
  static constexpr std::uint32_t absent = LatticeIndex::absent;

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

  BlockArray<double> value;
  BlockArray<std::array<std::uint32_t, 3>> vertex;
  static constexpr std::uint8_t visited_cube = 1, evaluated = 2;
  BlockArray<std::uint8_t> flags;

 private:
  LatticeIndex index_;
  bool with_vertices_ = false;
};

}  // namespace

namespace {
void check_cell(double cell) {
  if (!(cell > 0.0) || !std::isfinite(cell)) throw InvalidInputError("the lattice cell size must be a positive length");
}

Index3 cube_of(const Lattice& lattice, const Vec3& p) {
  Index3 cube;
  for (int a = 0; a < 3; ++a)
    cube[static_cast<std::size_t>(a)] = static_cast<std::int32_t>(std::floor((p[a] - lattice.origin[a]) / lattice.cell));
  return cube;
}

// Calls visit(cube) with the cube of each seed, in seed order, once per run
// of seeds in one cube (seeds in spatial order repeat their cube often);
// a cube met again later is passed again.
template <class Visit>
void for_each_seed_cube(const Lattice& lattice, std::span<const Vec3> seeds, Visit&& visit) {
  std::uint64_t previous = UINT64_MAX;
  for (const Vec3& p : seeds) {
    const Index3 cube = cube_of(lattice, p);
    if (pack(cube) == previous) continue;
    previous = pack(cube);
    visit(cube);
  }
}
}  // namespace

Lattice make_lattice(std::span<const Vec3> seeds, double cell) {
  check_cell(cell);
  Box<3> box;
  for (const Vec3& p : seeds) box.extend(p);
  Lattice lattice;
  lattice.cell = cell;
  const double margin = lattice_margin * cell;
  lattice.origin = box.min - Vec3::Constant(margin);
  for (int a = 0; a < 3; ++a) {
    const double cubes = std::ceil((box.max[a] - box.min[a] + 2.0 * margin) / cell);
    if (cubes > max_cubes_per_axis)
      throw ResourceLimitError("the lattice would need " + std::to_string(static_cast<long long>(cubes)) +
                               " cubes along axis " + "xyz"[a] + " (at most " + std::to_string(max_cubes_per_axis) +
                               "): use a larger --cell or a smaller --resolution");
    lattice.size[static_cast<std::size_t>(a)] = static_cast<std::int32_t>(cubes);
  }
  return lattice;
}

struct SeedWave::Walk {
  Lattice lattice;
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
  walk_->lattice = make_lattice(seeds, cell);
  CornerTable& corners = walk_->corners;
  // A cube's key is that of its lowest corner (corner 0): the cube and its
  // corners share the table, and the corners come in the order first met.
  for_each_seed_cube(walk_->lattice, seeds, [&](const Index3& cube) {
    const std::uint32_t slot = corners.find_or_insert(pack(cube));
    if (corners.flags[slot] & CornerTable::visited_cube) return;
    corners.flags[slot] |= CornerTable::visited_cube;
    walk_->cubes.push_back(pack(cube));
    for (int c = 1; c < 8; ++c) corners.find_or_insert(pack(corner_of_cube(cube, c)));
  });
}
SeedWave::SeedWave(SeedWave&&) noexcept = default;
SeedWave& SeedWave::operator=(SeedWave&&) noexcept = default;
SeedWave::~SeedWave() = default;

const Lattice& SeedWave::lattice() const { return walk_->lattice; }
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

MarchingCubesResult marching_cubes(const ScalarField& f, std::span<const Vec3> seeds,
                                   const MarchingCubesOptions& options, bool keep_corners) {
  check_cell(options.cell);
  if (seeds.empty()) {
    MarchingCubesResult result;
    result.cell = options.cell;
    return result;
  }
  Timer timer;
  SeedWave wave(seeds, options.cell);
  const double seconds_wave = timer.lap();
  MarchingCubesResult result = marching_cubes(f, std::move(wave), options, keep_corners);
  result.seconds += seconds_wave;
  return result;
}

MarchingCubesResult marching_cubes(const ScalarField& f, SeedWave wave, const MarchingCubesOptions& options,
                                   bool keep_corners) {
  check_cell(options.cell);
  Timer timer;
  SeedWave::Walk& start = SeedWaveAccess::walk(wave);
  const Lattice& lattice = start.lattice;
  if (lattice.cell != options.cell)
    throw InvalidInputError("the first wave was laid out at another cell than the walk's");
  MarchingCubesResult result;
  result.cell = options.cell;
  result.origin = lattice.origin;
  result.size = lattice.size;
  auto position = [&](const Index3& i) { return lattice.position(i); };
  auto inside_lattice = [&](const Index3& cube) {
    for (std::size_t a = 0; a < 3; ++a)
      if (cube[a] < 0 || cube[a] >= result.size[a]) return false;
    return true;
  };

  // The walk is breadth-first, one wave (the cubes at the same number of
  // steps from the seeds) at a time, in batches: first every corner the
  // batch needs and has not met is evaluated, in parallel (f is by far the
  // costliest part), then the batch's cubes are processed in order,
  // producing triangles and the next wave. The order of cubes, and so the
  // mesh, is the same for any number of threads.
  CornerTable& corners = start.corners;
  std::size_t visited = start.cubes.size();
  std::vector<std::uint64_t> wave_cubes, next = std::move(start.cubes);
  auto check_visited = [&] {
    if (visited > options.max_cubes)
      throw ResourceLimitError("the lattice walk passed " + std::to_string(options.max_cubes) +
                               " cubes, the most the memory limit allows: use a larger --cell or a smaller "
                               "--resolution, or raise --max-memory");
  };
  check_visited();
  auto visit = [&](const Index3& cube) {
    if (!inside_lattice(cube)) return;
    const std::uint32_t slot = corners.find_or_insert(pack(cube));
    if (corners.flags[slot] & CornerTable::visited_cube) return;
    corners.flags[slot] |= CornerTable::visited_cube;
    ++visited;
    check_visited();
    next.push_back(pack(cube));
  };
  result.seed_cubes = visited;
  corners.add_vertices();

  std::vector<std::array<std::uint32_t, 8>> cube_slots;  // per cube of a batch: its corners' slots
  std::vector<std::uint8_t> pending, faces_of;
  std::vector<std::uint16_t> config_of;  // 256: a corner is undefined
  std::vector<std::uint32_t> fresh;
  std::chrono::steady_clock::duration field_time{};
  // A wave is taken in batches of cubes (the first wave holds every cube
  // with a sample: millions on a large scan), so the per-batch arrays stay
  // small. Cubes are still processed in wave order: the mesh is the same.
  constexpr std::size_t batch = 65536;
  while (!next.empty()) {
    wave_cubes.swap(next);
    next.clear();
    for (std::size_t first = 0; first < wave_cubes.size(); first += batch) {
      interruption_point();
      const std::size_t count = std::min(batch, wave_cubes.size() - first);
      cube_slots.resize(count);
      fresh.clear();
      // The corners already met are looked up in parallel (the table does not
      // change meanwhile); the new ones are then added in wave order.
      // Corners met and evaluated need nothing more: `pending` marks the
      // others, the only ones the one-thread loop below touches.
      pending.resize(count);
#pragma omp parallel for schedule(static)
      for (std::int64_t s = 0; s < static_cast<std::int64_t>(count); ++s) {
        const auto w = static_cast<std::size_t>(s);
        const Index3 cube = unpack(wave_cubes[first + w]);
        std::uint8_t mask = 0;
        for (int c = 0; c < 8; ++c) {
          const std::uint32_t slot = corners.find(pack(corner_of_cube(cube, c)));
          cube_slots[w][static_cast<std::size_t>(c)] = slot;
          if (slot == CornerTable::absent || !(corners.flags[slot] & CornerTable::evaluated))
            mask = static_cast<std::uint8_t>(mask | (1u << c));
        }
        pending[w] = mask;
      }
      for (std::size_t w = 0; w < count; ++w) {
        if (pending[w] == 0) continue;
        const Index3 cube = unpack(wave_cubes[first + w]);
        for (int c = 0; c < 8; ++c) {
          if (!((static_cast<unsigned>(pending[w]) >> c) & 1u)) continue;
          std::uint32_t& slot = cube_slots[w][static_cast<std::size_t>(c)];
          if (slot == CornerTable::absent) slot = corners.find_or_insert(pack(corner_of_cube(cube, c)));
          if (!(corners.flags[slot] & CornerTable::evaluated)) {
            corners.flags[slot] |= CornerTable::evaluated;
            fresh.push_back(slot);
          }
        }
      }
      const auto started = std::chrono::steady_clock::now();
      std::exception_ptr failure;
      const auto fresh_count = static_cast<std::int64_t>(fresh.size());
#pragma omp parallel for schedule(dynamic, 256)
      for (std::int64_t s = 0; s < fresh_count; ++s) {
        const std::uint32_t slot = fresh[static_cast<std::size_t>(s)];
        try {
          const std::optional<double> v = f(position(unpack(corners.key(slot))));
          corners.value[slot] = v ? *v : undefined;
        } catch (...) {
#pragma omp critical(recon_marching_cubes_failure)
          if (!failure) failure = std::current_exception();
        }
      }
      if (failure) std::rethrow_exception(failure);
      field_time += std::chrono::steady_clock::now() - started;

      // Each cube's configuration and the faces the walk goes on through,
      // in parallel; then, in order, vertices, triangles and the next wave.
      // Faces crossed by the surface, or touched at a corner where f = 0
      // (the surface may go on in the neighbour only), lead on.
      config_of.resize(count);
      faces_of.resize(count);
#pragma omp parallel for schedule(static)
      for (std::int64_t s = 0; s < static_cast<std::int64_t>(count); ++s) {
        const auto w = static_cast<std::size_t>(s);
        unsigned config = 0, zero = 0;
        bool complete = true;
        for (std::size_t c = 0; c < 8; ++c) {
          const double v = corners.value[cube_slots[w][c]];
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
        config_of[w] = complete ? static_cast<std::uint16_t>(config) : std::uint16_t{256};
        faces_of[w] = faces;
      }
      for (std::size_t w = 0; w < count; ++w) {
        if (config_of[w] == 256) {
          ++result.undefined_cubes;
          continue;
        }
        const Index3 cube = unpack(wave_cubes[first + w]);
        const auto& slots = cube_slots[w];
        const unsigned config = config_of[w];
        const mc::CubeCase& cube_case = mc::cube_case(config);
        // Vertices: one per crossed lattice edge, kept in the slot of the
        // edge's lower corner (shared with the neighbouring cubes); then the
        // centres of the loops that need one (private to this cube).
        std::array<std::uint32_t, 12 + 4> vertex{};
        for (int l = 0; l < cube_case.loop_count; ++l) {
          const auto& loop = cube_case.loops[static_cast<std::size_t>(l)];
          Vec3 centre = Vec3::Zero();
          for (int j = 0; j < loop.size; ++j) {
            const int e = loop.edges[static_cast<std::size_t>(j)];
            const auto ends = mc::edge_corners(e);
            const int axis = mc::edge_axis(e);
            std::uint32_t& id =
                corners.vertex[slots[static_cast<std::size_t>(ends[0])]][static_cast<std::size_t>(axis)];
            if (id == CornerTable::no_vertex) {
              id = static_cast<std::uint32_t>(result.mesh.vertices.size());
              const double v0 = corners.value[slots[static_cast<std::size_t>(ends[0])]];
              const double v1 = corners.value[slots[static_cast<std::size_t>(ends[1])]];
              const double t = std::clamp(v0 / (v0 - v1), vertex_margin, 1.0 - vertex_margin);
              Vec3 p = position(corner_of_cube(cube, ends[0]));
              p[axis] += t * options.cell;
              result.mesh.vertices.push_back(p);
            }
            vertex[static_cast<std::size_t>(e)] = id;
            centre += result.mesh.vertices[id];
          }
          if (loop.centred) {
            vertex[static_cast<std::size_t>(mc::loop_centre + l)] =
                static_cast<std::uint32_t>(result.mesh.vertices.size());
            result.mesh.vertices.push_back(centre / loop.size);
          }
        }
        for (int t = 0; t < cube_case.triangle_count; ++t) {
          const auto& tri = cube_case.triangles[static_cast<std::size_t>(t)];
          result.mesh.triangles.push_back({vertex[tri[0]], vertex[tri[1]], vertex[tri[2]]});
        }

        for (int a = 0; a < 3; ++a)
          for (int side = 0; side < 2; ++side) {
            if (!((static_cast<unsigned>(faces_of[w]) >> (2 * a + side)) & 1u)) continue;
            Index3 neighbour = cube;
            neighbour[static_cast<std::size_t>(a)] += side == 0 ? -1 : 1;
            visit(neighbour);
          }
      }
    }
  }

  result.visited_cubes = visited;
  result.evaluated_corners = corners.size();
  for (std::uint32_t slot = 0; slot < corners.size(); ++slot) {
    const double v = corners.value[slot];
    if (std::isnan(v)) ++result.undefined_corners;
    if (keep_corners) result.corners.push_back({unpack(corners.key(slot)), std::isnan(v) ? 0.0 : v, !std::isnan(v)});
  }
  result.seconds = timer.lap();
  result.seconds_field = std::chrono::duration<double>(field_time).count();
  return result;
}

}  // namespace recon
