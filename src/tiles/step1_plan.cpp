// Step 1 of a tiled run (tiles.h): the passes over the input, the
// cloud-wide choices, the tile size and the binning; and the plan's file.
#include "recon/tiles/tiles.h"

#include "recon/core/detail/mix64.h"
#include "recon/core/errors.h"
#include "recon/core/memory_budget.h"
#include "recon/core/timer.h"
#include "recon/io/point_stream.h"
#include "recon/reconstruct_parts.h"
#include "tiles/files.h"
#include "tiles/statistics.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <string>
#include <unordered_map>

namespace recon {

using tile_files::PointRecord;
using Index3 = Lattice<3>::Index;

PointPass pass_over(PointCloudView cloud, std::size_t chunk) {
  return [cloud, chunk](const ChunkTaker& take) {
    for (std::size_t first = 0; first < cloud.size(); first += chunk) {
      const std::size_t n = std::min(chunk, cloud.size() - first);
      const auto part = [&](auto span) { return span.empty() ? span : span.subspan(first, n); };
      take(PointCloudView(part(cloud.positions), part(cloud.normals), part(cloud.colors)), first);
    }
  };
}

PointPass pass_over_file(const std::filesystem::path& path, const io::ReadPointsOptions& options) {
  return [path, options](const ChunkTaker& take) {
    io::PointChunkOptions chunks;
    chunks.read = options;
    io::read_points_in_chunks(path, chunks, take);
  };
}

namespace tile_files {

CoreBox core_of(const TilePlan& plan, std::size_t tile) { return core_at(plan, plan.tiles[tile].index); }

Index3 tile_at(const TilePlan& plan, const Vec3& w) {
  Index3 t;
  for (int a = 0; a < 3; ++a) {
    const auto size = plan.lattice.size[static_cast<std::size_t>(a)];
    const double last = std::floor((size - 1) / static_cast<double>(plan.tile_cubes));
    const double cube = std::floor((w[a] - plan.lattice.origin[a]) / plan.lattice.cell);
    t[static_cast<std::size_t>(a)] =
        static_cast<std::int32_t>(std::clamp(std::floor(cube / plan.tile_cubes), 0.0, last));
  }
  return t;
}

double outside_core(const TilePlan& plan, const CoreBox& core, const Vec3& w) {
  double d = -1e300;
  for (std::size_t a = 0; a < 3; ++a) {
    const double lo = plan.lattice.origin[static_cast<int>(a)] + core.lo[a] * plan.lattice.cell;
    const double hi = plan.lattice.origin[static_cast<int>(a)] + core.hi[a] * plan.lattice.cell;
    d = std::max({d, lo - w[static_cast<int>(a)], w[static_cast<int>(a)] - hi});
  }
  return d;
}

CoreBox core_at(const TilePlan& plan, const Lattice<3>::Index& grid) {
  CoreBox box;
  for (std::size_t a = 0; a < 3; ++a) {
    box.lo[a] = grid[a] * plan.tile_cubes;
    box.hi[a] = std::min(box.lo[a] + plan.tile_cubes, plan.lattice.size[a]);
  }
  return box;
}

ReconstructionOptions tile_options(const TilePlan& plan) {
  ReconstructionOptions o;
  o.method = plan.method;
  o.planes.k = plan.k;
  o.planes.adapt_k = false;
  o.planes.rho = plan.rho;
  if (!plan.rho) o.planes.cloud = plan.spacing;
  if (plan.has_quadric_medians) o.quadrics.cloud = plan.quadric_medians;
  o.cell = plan.lattice.cell;
  o.offset = plan.offset;
  o.distance.delta = plan.delta;
  o.orientation.vote_rounds = plan.vote_rounds;
  o.orientation.graph.gap_factor = plan.gap_factor;
  o.orientation.graph.min_component_points = plan.min_component_points;
  o.keep_graph = false;
  o.mesh_colors = false;
  return o;
}

}  // namespace tile_files

namespace {

// The cubes the walk may cross around those it emits triangles for, and
// the ring of cubes around the core a tile refines too: phase V's choices
// (which crease vertex comes first, which sliver flips) depend on the
// triangles a few cubes around, never farther in the meshes tried.
constexpr std::int32_t walk_ring = 2;
constexpr std::int32_t refine_ring = 3;
constexpr std::int32_t plain_ring = 1;

// The one lattice a tiled run lays over the whole cloud. Its tiles share it,
// so far-apart clusters cannot have a lattice each as in memory
// (reconstruct.h): too wide a cloud is refused, saying where it can run.
Lattice<3> tiles_lattice(const Box<3>& box, double cell) {
  try {
    return make_lattice<3>(box, cell);
  } catch (const ResourceLimitError& e) {
    throw ResourceLimitError(std::string("a tiled run lays one lattice over the whole cloud, and ") + e.what() +
                             "; or reconstruct it in memory (not tiled), which meshes far-apart clusters on "
                             "lattices of their own");
  }
}

// ---------------------------------------------------------------------------
// Pass 1: the count and the bounding box (input coordinates).

// A pass that counts its points on `counter` (when there is one) against `total`.
void counted_pass(const PointPass& pass, ProgressCounter* counter, std::uint64_t total, const ChunkTaker& take) {
  if (counter) counter->start(total);
  pass([&](PointCloudView chunk, std::size_t first) {
    take(chunk, first);
    if (counter) counter->advance(chunk.size());
  });
}

void bounds_pass(const PointPass& pass, ProgressCounter* counter, TilePlan& plan, Box<3>& box) {
  counted_pass(pass, counter, 0, [&](PointCloudView chunk, std::size_t) {
    check_coordinates<3>(chunk.positions);
    for (const Vec3& p : chunk.positions) box.extend(p);
    plan.input_points += chunk.size();
  });
  if (plan.input_points == 0) throw InvalidInputError("the cloud has no points");
  plan.offset = working_offset(box);
  plan.box.min = box.min - plan.offset;  // (rounding is monotonic: the box of the moved points)
  plan.box.max = box.max - plan.offset;
}

// ---------------------------------------------------------------------------
// Pass 2: the points phase I measures the cloud on, and a histogram of the
// density for the tile size.

// Bytes a point of a tile needs through phases I-IV (memory_budget.h).
double bytes_per_point(int k, bool refined) {
  constexpr std::size_t n = 1'000'000;
  return estimated_bytes_reconstruction(n, k, refined) / n;
}

struct Sample {
  PointCloud cloud;
  std::unordered_map<std::uint64_t, std::uint32_t> histogram;  // points per bin
  double bin = 0.0;
  double patch = 0.0;  // side of the patches drawn; 0: the whole cloud
};

std::uint64_t bin_key(const Vec3& w, const Vec3& low, double side) {
  std::uint64_t key = 0;
  for (int a = 0; a < 3; ++a) key = key << 21 | static_cast<std::uint64_t>(std::floor((w[a] - low[a]) / side));
  return key;
}

// The whole cloud when it has at most `budget` points; else the points of
// spatial patches (a grid of 16 along the longest side) drawn at random,
// as many as the budget holds on average.
Sample sample_pass(const PointPass& pass, ProgressCounter* counter, const TilePlan& plan, std::size_t budget,
                   std::uint64_t seed) {
  Sample s;
  const double longest = std::max(plan.box.extent().maxCoeff(), 1e-300);
  s.bin = longest / 128.0 * (1.0 + 1e-9);
  const double patch = longest / 16.0 * (1.0 + 1e-9);
  const bool whole = plan.input_points <= budget;
  s.patch = whole ? 0.0 : patch;
  // (A patch is drawn when its hash falls below `threshold`: 0.8 of the
  // budget on average, whole patches, and never more than the budget.)
  const double fraction = whole ? 0.0 : 0.8 * static_cast<double>(budget) / static_cast<double>(plan.input_points);
  const auto threshold = static_cast<std::uint64_t>(fraction * 18446744073709551615.0);
  counted_pass(pass, counter, plan.input_points, [&](PointCloudView chunk, std::size_t) {
    for (const Vec3& p : chunk.positions) {
      const Vec3 w = p - plan.offset;
      ++s.histogram[bin_key(w, plan.box.min, s.bin)];
      if (s.cloud.positions.size() >= budget) continue;
      if (whole || detail::mix64(bin_key(w, plan.box.min, patch) ^ seed) < threshold) s.cloud.positions.push_back(p);
    }
  });
  return s;
}

// The samples whose neighbourhoods the patches did not cut: farther than
// `margin` from their patch's sides (all of them for the whole cloud).
std::vector<std::uint8_t> inside_patches(const Sample& s, const Reconstruction& r, const TilePlan& plan,
                                         double margin) {
  std::vector<std::uint8_t> inside(r.order.size(), 1);
  if (s.patch == 0.0) return inside;
  for (std::size_t j = 0; j < inside.size(); ++j)
    for (int a = 0; a < 3; ++a) {
      const double at = (r.points()[j][a] - plan.box.min[a]) / s.patch;
      const double edge = std::min(at - std::floor(at), std::ceil(at) - at) * s.patch;
      if (edge < margin) inside[j] = 0;
    }
  return inside;
}

float quantile(std::vector<float> values, double q) {
  if (values.empty()) return 0.0f;
  const auto at = values.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

// Phase I over the sample, as reconstruct() runs it: the cloud-wide measures.
tile_statistics::Measures measure_sample(const Sample& sample, const TilingOptions& options, const TilePlan& plan) {
  ReconstructionOptions o = options.reconstruction;
  o.offset = plan.offset;
  const Reconstruction r = reconstruct_phase_1(PointCloudView(sample.cloud), o);
  tile_statistics::Measures m;
  m.k = r.planes.k;
  m.spacing = r.planes.spacing();
  if (r.quadrics) m.quadric_medians = r.quadrics->medians;
  m.samples = sample.cloud.size();
  // (Quantiles over the samples whose neighbourhoods the patches left whole.)
  const std::vector<std::uint8_t> inside =
      inside_patches(sample, r, plan, 3.0 * static_cast<double>(quantile(r.planes.radius, 0.5)));
  std::vector<float> radius, rho;
  for (std::size_t j = 0; j < inside.size(); ++j)
    if (inside[j]) {
      radius.push_back(r.planes.radius[j]);
      rho.push_back(r.planes.local_rho[j]);
    }
  m.radius_q = 1.5 * static_cast<double>(quantile(radius.empty() ? r.planes.radius : radius, 0.999));
  m.rho_q = static_cast<double>(quantile(rho.empty() ? r.planes.local_rho : rho, 0.999));
  return m;
}

// The plan's cloud-wide choices from the measures: k, rho, delta, the
// lattice, the halo.
void choose(const tile_statistics::Measures& m, const TilingOptions& options, TilePlan& plan) {
  const ReconstructionOptions& o = options.reconstruction;
  plan.method = o.method;
  plan.k = m.k;
  plan.spacing = m.spacing;
  plan.has_quadric_medians = m.quadric_medians.has_value();
  plan.quadric_medians = m.quadric_medians.value_or(QuadricMedians{});
  plan.rho = o.planes.rho;
  plan.delta = o.distance.delta;
  plan.vote_rounds = o.orientation.vote_rounds;
  plan.gap_factor = o.orientation.graph.gap_factor;
  plan.min_component_points = o.orientation.graph.min_component_points;
  plan.refinement = o.refinement;
  plan.color_blend = o.colors;
  plan.normals = o.vertex_normals;
  plan.ring = o.method == Method::refined ? refine_ring : plain_ring;
  plan.walk_margin = walk_ring + plan.ring;
  plan.radius_q = m.radius_q;
  plan.rho_q = m.rho_q;
  // (m.spacing.rho is the given rho, when one is.)
  const double cell = lattice_cell([&] { return plan.box.extent().maxCoeff(); }, m.spacing.rho, o);
  plan.lattice = tiles_lattice(plan.box, cell);
  const double delta = o.distance.delta ? *o.distance.delta : 2.0 * m.spacing.noise;
  // (Distances to a core are taken on the axes: a ball of radius R around
  // a point within d of the core lies within d + R of it.)
  const double reach = 1.5 * plan.rho_q + delta + 2.0 * cell;
  plan.exact_margin = plan.walk_margin * cell + reach + plan.radius_q;
  plan.halo = plan.exact_margin + 2.0 * plan.radius_q;
  // Phase V drops a triangle whose vertices lie beyond reach * rho_i + delta
  // of every sample: the samples that far around the walk must be there.
  if (o.method == Method::refined)
    plan.halo = std::max(plan.halo, plan.walk_margin * cell + RefinementInput{}.reach * plan.rho_q + delta);
  plan.statistics_points = m.samples;
  plan.statistics_inexact = m.inexact;
}

// ---------------------------------------------------------------------------
// The tile size: the largest core (in cubes) whose densest tile, halo
// included, fits the points one tile may hold, judged on the histogram.

std::size_t densest_tile(const Sample& s, const TilePlan& plan, std::int32_t cubes) {
  const double side = cubes * plan.lattice.cell;
  std::unordered_map<std::uint64_t, std::size_t> count;
  for (const auto& [key, n] : s.histogram) {
    std::uint64_t tile = 0;
    for (int a = 0; a < 3; ++a) {
      const auto bin = static_cast<double>((key >> (21 * (2 - a))) & ((1u << 21) - 1));
      const double centre = plan.box.min[a] + (bin + 0.5) * s.bin - plan.lattice.origin[a];
      tile = tile << 21 | static_cast<std::uint64_t>(std::max(0.0, std::floor(centre / side)));
    }
    count[tile] += n;
  }
  std::size_t most = 0;
  for (const auto& [tile, n] : count) most = std::max(most, n);
  const double grow = (side + 2.0 * plan.halo) / side;  // a surface's halo, on two axes
  return static_cast<std::size_t>(static_cast<double>(most) * grow * grow);
}

// A core narrower than twice the halo would hold more halo than core: four
// times the points it owns, or more.
std::int32_t choose_tile_cubes(const Sample& s, const TilingOptions& options, const TilePlan& plan) {
  const auto least =
      std::max(2 * plan.walk_margin + 2, static_cast<std::int32_t>(std::ceil(2.0 * plan.halo / plan.lattice.cell)));
  if (options.tile_size != 0.0) {
    if (!std::isfinite(options.tile_size) || !(options.tile_size > 0.0))
      throw InvalidInputError("the tile size must be a finite positive length");
    // (A core wider than the lattice is one tile: compared as a double, the
    // count of cubes cannot overflow the int.)
    const double whole = *std::max_element(plan.lattice.size.begin(), plan.lattice.size.end());
    return std::max(least,
                    static_cast<std::int32_t>(std::min(std::ceil(options.tile_size / plan.lattice.cell), whole)));
  }
  const std::size_t limit = memory_limit_or_default(options.reconstruction.max_memory);
  const double fits = 0.5 * static_cast<double>(limit) / bytes_per_point(plan.k, plan.method == Method::refined);
  std::int32_t cubes = *std::max_element(plan.lattice.size.begin(), plan.lattice.size.end());
  double densest = static_cast<double>(densest_tile(s, plan, cubes));
  while (cubes > least && densest > fits) {
    cubes = std::max(least, static_cast<std::int32_t>(0.8 * cubes));
    densest = static_cast<double>(densest_tile(s, plan, cubes));
  }
  if (densest > fits)
    check_memory(densest * bytes_per_point(plan.k, plan.method == Method::refined) * 2.0, limit,
                 "working in tiles, the densest (a core edge of " + std::to_string(cubes * plan.lattice.cell) +
                     " and a halo of " + std::to_string(plan.halo) + ") with about " +
                     std::to_string(static_cast<std::size_t>(densest)) + " points",
                 "tiles no smaller than twice their halo fit no better");
  return cubes;
}

// ---------------------------------------------------------------------------
// Pass 3: every point into the files of the tiles whose core, widened by
// the halo, holds it.

class Binner {
 public:
  Binner(TilePlan& plan, const std::filesystem::path& dir) : plan_(plan), dir_(dir) {}

  // (`color` null when the plan has no colours.)
  void add(const Vec3& p, std::uint64_t index, const Color* color) {
    const Vec3 w = p - plan_.offset;
    const Index3 lo = tile_files::tile_at(plan_, w - Vec3::Constant(plan_.halo));
    const Index3 hi = tile_files::tile_at(plan_, w + Vec3::Constant(plan_.halo));
    const Index3 own = tile_files::tile_at(plan_, w);
    for (std::int32_t x = lo[0]; x <= hi[0]; ++x)
      for (std::int32_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int32_t z = lo[2]; z <= hi[2]; ++z) {
          Tile& t = put({x, y, z}, w, PointRecord{index, p.x(), p.y(), p.z()}, own);
          if (color) t.colors.push_back(*color);
          if (t.buffer.size() == 4096) t.flush(dir_);
        }
  }

  // Keeps the tiles whose cores could own triangles: with a point within
  // the exact margin of the core. In the order the tiles were first met.
  void finish() {
    std::vector<Tile*> order(tiles_.size());
    for (auto& [key, tile] : tiles_) order[tile.id] = &tile;
    for (Tile* t : order) {
      if (t->near == 0) {
        std::filesystem::remove(tile_files::of_tile(dir_, t->id, "points"));
        std::filesystem::remove(tile_files::of_tile(dir_, t->id, "colors"));
        continue;
      }
      t->flush(dir_);
      t->seal(dir_);
      plan_.tiles.push_back({t->index, t->id, t->points, t->core});
    }
    tiles_.clear();
  }

 private:
  // A tile's file is appended to a buffer at a time (a cloud may make more
  // tiles than a process may hold files open); it counts only once the plan,
  // written last, names it. Its checksum (binary_file.h) runs along and is
  // appended last (seal).
  // Colours, when the cloud has them, go to a file of their own beside
  // the points (tile-N.colors), one per point in the same order.
  struct Tile {
    Index3 index{};
    std::uint32_t id = 0;
    std::vector<PointRecord> buffer;
    std::vector<Color> colors;
    std::uint64_t points = 0, core = 0, near = 0;
    detail::Checksum points_sum, colors_sum;
    bool has_colors = false;
    void flush(const std::filesystem::path& dir) {
      const bool first = points == buffer.size();
      append(tile_files::of_tile(dir, id, "points"), first ? tile_files::points_magic : nullptr, points_sum,
             buffer.data(), buffer.size() * sizeof(PointRecord));
      if (!colors.empty()) {
        append(tile_files::of_tile(dir, id, "colors"), first ? tile_files::colors_magic : nullptr, colors_sum,
               colors.data(), colors.size() * sizeof(Color));
        has_colors = true;
      }
      buffer.clear();
      colors.clear();
    }
    void seal(const std::filesystem::path& dir) {
      append_trailer(tile_files::of_tile(dir, id, "points"), points_sum);
      if (has_colors) append_trailer(tile_files::of_tile(dir, id, "colors"), colors_sum);
    }
    static void append(const std::filesystem::path& path, const char* magic, detail::Checksum& sum, const void* data,
                       std::size_t bytes) {
      std::ofstream out(path, std::ios::binary | std::ios::app);
      if (magic) {
        out.write(magic, 8);
        sum.add(magic, 8);
      }
      out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
      sum.add(data, bytes);
      if (!out.flush()) throw IoError(path.string() + ": cannot write the tile (disk full?)");
    }
    static void append_trailer(const std::filesystem::path& path, const detail::Checksum& sum) {
      const detail::ChecksumTrailer trailer = sum.trailer();
      std::ofstream out(path, std::ios::binary | std::ios::app);
      out.write(reinterpret_cast<const char*>(&trailer), sizeof trailer);
      if (!out.flush()) throw IoError(path.string() + ": cannot write the tile (disk full?)");
    }
  };

  Tile& tile(const Index3& t) {
    auto [at, added] = tiles_.try_emplace(Lattice<3>::key(t));
    Tile& tile = at->second;
    if (added) {
      tile.index = t;
      tile.id = static_cast<std::uint32_t>(tiles_.size() - 1);
    }
    return tile;
  }

  Tile& put(const Index3& t, const Vec3& w, const PointRecord& record, const Index3& own) {
    Tile& tile = this->tile(t);
    tile.buffer.push_back(record);
    ++tile.points;
    if (t == own) ++tile.core;
    if (tile_files::outside_core(plan_, tile_files::core_at(plan_, t), w) <= plan_.exact_margin) ++tile.near;
    return tile;
  }

  TilePlan& plan_;
  std::filesystem::path dir_;
  std::unordered_map<std::uint64_t, Tile> tiles_;
};

}  // namespace

namespace {

// Pass 3 (and 4, after exact measures): every point into its tiles' files.
void bin_points(const PointPass& pass, const TilingOptions& options, TilePlan& plan,
                const std::filesystem::path& work_dir) {
  // (Each tile holds a buffer of 4096 records, 128 KiB, while binning.)
  Binner binner(plan, work_dir);
  // (Whether the cloud has colours, the reader says of every chunk alike.)
  counted_pass(pass, options.progress, plan.input_points, [&](PointCloudView chunk, std::size_t first) {
    plan.colors = options.reconstruction.mesh_colors && chunk.has_colors();
    for (std::size_t i = 0; i < chunk.size(); ++i)
      binner.add(chunk.positions[i], first + i, plan.colors ? &chunk.colors[i] : nullptr);
  });
  binner.finish();
}

// The files of a plan's tiles, for binning again under another plan.
void remove_tiles(TilePlan& plan, const std::filesystem::path& work_dir) {
  for (const TileInfo& info : plan.tiles)
    for (const char* kind : {"points", "colors", "stats"})
      std::filesystem::remove(tile_files::of_tile(work_dir, info.id, kind));
  plan.tiles.clear();
}

}  // namespace

TilePlan plan_tiles(const PointPass& pass, const TilingOptions& options, const std::filesystem::path& work_dir) {
  if (std::filesystem::exists(tile_files::plan(work_dir)))
    throw InvalidInputError(work_dir.string() + ": holds the plan of another tiled run already");
  std::filesystem::create_directories(work_dir);
  TilePlan plan;
  Timer timer;
  Box<3> box;
  bounds_pass(pass, options.progress, plan, box);
  plan.seconds_bounds = timer.lap();
  const std::size_t limit = memory_limit_or_default(options.reconstruction.max_memory);
  const int k = options.reconstruction.planes.k;
  const std::size_t budget =
      options.statistics_points > 0
          ? options.statistics_points
          : static_cast<std::size_t>(0.25 * static_cast<double>(limit) /
                                     bytes_per_point(k, options.reconstruction.method == Method::refined));
  const Sample sample = sample_pass(pass, options.progress, plan, std::max<std::size_t>(budget, 1), options.seed);
  if (options.statistics_points == 0) check_statistics_sample(sample.cloud.size(), budget, plan.input_points, k, limit);
  choose(measure_sample(sample, options, plan), options, plan);
  plan.tile_cubes = choose_tile_cubes(sample, options, plan);
  plan.seconds_statistics = timer.lap();
  bin_points(pass, options, plan, work_dir);
  plan.seconds_binning = timer.lap();
  if (sample.patch > 0.0) {
    // The sample was part of the cloud: its measures made a first plan,
    // whose tiles now measure the whole cloud exactly (tiles/statistics.h);
    // the points are binned again under the plan those measures make.
    const tile_statistics::Measures exact = tile_statistics::measure_over_tiles(plan, work_dir, options.reconstruction);
    remove_tiles(plan, work_dir);
    choose(exact, options, plan);
    plan.statistics_over_tiles = true;
    plan.tile_cubes = choose_tile_cubes(sample, options, plan);
    plan.seconds_statistics += timer.lap();
    bin_points(pass, options, plan, work_dir);
    plan.seconds_binning += timer.lap();
  }
  tile_files::write_plan(plan, work_dir);
  return plan;
}

}  // namespace recon
