#include "recon/reconstruct.h"

#include "recon/detail/seed_wave.h"
#include "recon/errors.h"
#include "recon/parallel.h"
#include "recon/resource_usage.h"
#include "recon/spatial_order.h"  // permuted
#include "recon/timer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <future>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <thread>


namespace recon {

double chosen_cell(std::optional<double> cell, std::optional<int> resolution, const std::function<double()>& longest_side,
                   double fallback) {
  if (cell && resolution) throw InvalidInputError("give either a cell size or a resolution, not both");
  if (cell) {
    if (!std::isfinite(*cell) || !(*cell > 0.0)) throw InvalidInputError("the cell size must be a positive length");
    return *cell;
  }
  if (resolution) {
    if (*resolution < 1) throw InvalidInputError("the resolution must be at least 1 cell");
    return longest_side() / *resolution;
  }
  return fallback;
}

double lattice_cell(std::span<const Vec3> points, const TangentPlanes<3>& planes, const ReconstructionOptions& options) {
  const double fallback = options.method == Method::hoppe92 ? planes.rho : planes.rho / std::numbers::sqrt2;
  return chosen_cell(
      options.cell, options.resolution, [&] { return bounding_box<3>(points).extent().maxCoeff(); }, fallback);
}

Method method_from_name(std::string_view name) {
  if (name == "refined") return Method::refined;
  if (name == "hoppe92") return Method::hoppe92;
  throw InvalidInputError("unknown method '" + std::string(name) + "': use refined (the default) or hoppe92");
}

const char* method_name(Method method) { return method == Method::hoppe92 ? "hoppe92" : "refined"; }

namespace {
// Measured peaks (docs/benchmarks.md), rounded up: a million points at k = 20
// peak at about 230 MB in phase I and 350 MB in phase II; a lattice walk
// holds under 250 bytes a visited cube, besides about 190 bytes a point
// still held from phases I and II.
constexpr double bytes_per_point_planes = 170.0, bytes_per_neighbour_planes = 4.0;
constexpr double bytes_per_point_graph = 210.0, bytes_per_neighbour_graph = 8.0;
constexpr double bytes_per_point_held = 190.0, bytes_per_cube = 250.0;
// The refined method: the fits' curvature (12 bytes), misfit (4), crease
// flags (1) and single-precision guide normals (12) during phase II, where
// a million points peak at 390 MB; 40 rounds that up.
constexpr double bytes_per_point_refined = 40.0;

std::string megabytes_or_gigabytes(double bytes) {
  std::ostringstream out;
  out.precision(3);
  if (bytes < 1e9) {
    out << bytes / 1e6 << " MB";
  } else {
    out << bytes / 1e9 << " GB";
  }
  return out.str();
}

// The side of the square of surface each sample stands for: k samples
// cover a disc of the neighbourhood radius (its median over the points).
double surface_spacing(const TangentPlanes<3>& planes) {
  std::vector<float> radius(planes.radius);
  if (radius.empty() || planes.k < 1) return planes.rho;
  const auto middle = radius.begin() + static_cast<std::ptrdiff_t>(radius.size() / 2);
  std::nth_element(radius.begin(), middle, radius.end());
  return std::sqrt(std::numbers::pi / planes.k) * static_cast<double>(*middle);
}

// Phase III beside phase II. Prim's algorithm runs on one thread; meanwhile
// another evaluates f at the corners of the walk's first wave (every cube
// holding a sample: most of the corners the walk will need), with the
// unoriented PCA normals. Orientation only turns normals round, and f turns
// with them exactly: (p - o).(-n) is -((p - o).n) in floating point, and
// the foot point and the tests of definedness are unchanged. So the value
// with the PCA normal, negated where the orientation flipped that plane, is
// the value phase III gives, and the mesh is the same as without this.
class FirstWave {
 public:
  // The origin tree, the lattice and the first wave's cubes and corners: a
  // few tenths of the work.
  void prepare(Reconstruction& r, double cell, const SignedDistanceOptions& options) {
    r.origin_tree = r.planes.point_tree.refit(r.planes.origins);
    unoriented_ = make_signed_distance<3>(r.planes, r.planes.normals, r.origin_tree, options);
    wave_.emplace(r.points(), cell);
    plane_.resize(wave_->corner_count());
  }
  // Evaluates corners until none is left unclaimed; from any number of
  // threads at once, after prepare().
  void drain() {
    const std::size_t count = plane_.size();
    const Lattice<3>& lattice = wave_->lattice();
    for (;;) {
      const std::size_t begin = next_.fetch_add(chunk, std::memory_order_relaxed);
      if (begin >= count) return;
      std::uint32_t hint = SignedDistance<3>::no_hint;  // the corners come in spatial order
      for (std::size_t c = begin; c < std::min(begin + chunk, count); ++c) {
        const auto e = unoriented_.evaluate(lattice.position(wave_->corner(c)), hint);
        hint = e.plane;
        plane_[c] = e.plane;
        // (A value that depends on the normals' signs beyond a flip is left
        // to the walk, which evaluates it with the oriented normals.)
        if (!e.by_orientation) wave_->set_value(c, e.value ? *e.value : std::numeric_limits<double>::quiet_NaN());
      }
    }
  }
  // Leaves the corners no thread has claimed yet unevaluated (on failure).
  void abandon() { next_.store(std::numeric_limits<std::size_t>::max() / 2, std::memory_order_relaxed); }
  // Turns the values to the oriented normals' (negated where the plane
  // they came from was flipped); then the wave is the walk's.
  void orient(std::span<const std::uint8_t> flipped) {
    const auto count = static_cast<std::int64_t>(plane_.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto c = static_cast<std::size_t>(s);
      const double v = wave_->value(c);
      if (flipped[plane_[c]] && !std::isnan(v)) wave_->set_value(c, -v);
    }
    plane_ = {};
  }
  [[nodiscard]] bool ready() const { return wave_.has_value(); }
  [[nodiscard]] SeedWave take_wave() { return std::move(*wave_); }

 private:
  static constexpr std::size_t chunk = 256;
  SignedDistance<3> unoriented_;
  std::optional<SeedWave> wave_;      // holds f's values at its corners as they are evaluated
  std::vector<std::uint32_t> plane_;  // the plane each value came from
  std::atomic<std::size_t> next_{0};  // the first corner not yet claimed
};

// Phase II's orientation with the first wave beside it (see FirstWave):
// one thread of its own while Prim runs, then every thread. With one
// thread, the same work one after the other.
void orient_with_first_wave(Reconstruction& r, RiemannianGraph<3>&& graph, double cell,
                            const OrientationOptions& options, const SignedDistanceOptions& distance,
                            FirstWave& wave, double& seconds_after) {
  const int threads = thread_count();
  if (threads <= 1) {
    r.oriented = orient_normals<3>(r.planes, std::move(graph), options);
    Timer timer;
    wave.prepare(r, cell, distance);
    wave.drain();
    wave.orient(r.oriented->flipped);
    seconds_after = timer.lap();
    return;
  }
  std::promise<void> prepared;
  std::future<void> ready = prepared.get_future();
  std::exception_ptr failure;
  Timer beside;
  std::thread helper([&] {
    set_thread_count(1);  // this thread's own parallel regions (the refit): Prim has the other core
    try {
      wave.prepare(r, cell, distance);
    } catch (...) {
      prepared.set_exception(std::current_exception());
      return;
    }
    prepared.set_value();
    try {
      wave.drain();
    } catch (...) {
      failure = std::current_exception();
    }
    r.seconds_distance_beside = beside.elapsed();
  });
  try {
    r.oriented = orient_normals<3>(r.planes, std::move(graph), options);
  } catch (...) {
    wave.abandon();
    helper.join();
    throw;
  }
  Timer timer;
  try {
    ready.get();
  } catch (...) {
    helper.join();
    throw;
  }
#pragma omp parallel num_threads(std::max(1, threads - 1))
  wave.drain();
  helper.join();
  if (failure) std::rethrow_exception(failure);
  wave.orient(r.oriented->flipped);
  seconds_after = timer.lap();
}

// Phase I's second order (refined): the quadrics, whose origins and normals
// replace the planes'. Phase I raises k where the residuals look like
// noise; the two sheets of a thin part look the same (a residual that does
// not grow with the neighbourhood). When most neighbourhoods turn out to
// span two sheets, the raise is undone and the fits are made at the k asked for.
void fit_second_order(Reconstruction& r, const ReconstructionOptions& options, double cell) {
  LocalQuadricOptions fits = options.quadrics;
  if (fits.min_sheet_separation <= 0.0) fits.min_sheet_separation = 1.5 * cell;
  r.quadrics = fit_local_quadrics(r.planes, fits);
  if (r.planes.k > r.planes.k_requested && 4 * r.quadrics->split > r.planes.origins.size()) {
    TangentPlaneOptions asked = options.planes;
    asked.k = r.planes.k_requested;
    asked.adapt_k = false;
    const double seconds = r.planes.seconds_tree + r.planes.seconds_knn_pca + r.planes.seconds_spacing;
    r.planes = estimate_tangent_planes<3>(std::move(r.planes.point_tree), asked);
    r.planes.seconds_knn_pca += seconds;
    const double first = r.quadrics->seconds;
    r.quadrics = fit_local_quadrics(r.planes, fits);
    r.quadrics->seconds += first;
  }
  adopt_second_order(r.planes, *r.quadrics);
}

}  // namespace

double estimated_bytes_planes_and_graph(std::size_t points, int k, Method method) {
  const auto n = static_cast<double>(points);
  const double per_point = std::max(bytes_per_point_planes + bytes_per_neighbour_planes * k,
                                    bytes_per_point_graph + bytes_per_neighbour_graph * k);
  return n * (per_point + (method == Method::refined ? bytes_per_point_refined : 0.0));
}

double estimated_bytes_lattice(std::size_t points, double cubes) {
  return static_cast<double>(points) * bytes_per_point_held + cubes * bytes_per_cube;
}

void check_memory_planes_and_graph(std::size_t points, int k, std::size_t limit, Method method) {
  check_memory(estimated_bytes_planes_and_graph(points, k, method), limit,
               "tangent planes and orientation of " + std::to_string(points) + " points at k = " + std::to_string(k),
               "lower --k or thin the cloud");
}

void check_memory(double bytes, std::size_t limit, std::string_view what, std::string_view remedy) {
  if (bytes <= static_cast<double>(limit)) return;
  std::string message(what);
  message += " would need about " + megabytes_or_gigabytes(bytes) + ", more than the " + megabytes_or_gigabytes(static_cast<double>(limit)) +
             " allowed (--max-memory; default half the physical memory): ";
  message += remedy;
  message += ", or raise --max-memory";
  throw ResourceLimitError(message);
}

namespace {
// Phase III's options for a run: the refined method weighs 8 planes where
// creases are near (signed_distance.h).
SignedDistanceOptions phase_3_options(Method method, const SignedDistanceOptions& given,
                                      const std::optional<LocalQuadrics>& quadrics) {
  SignedDistanceOptions options = given;
  if (!options.candidates) options.candidates = method == Method::refined ? 8 : 1;
  if (quadrics && options.near_crease.empty()) options.near_crease = quadrics->near_crease;
  return options;
}
}  // namespace

RefinementInput refinement_input_of(const Reconstruction& r, const SignedDistance<3>& f) {
  if (!r.quadrics) throw InvalidInputError("refinement_input_of: the reconstruction has no second-order fits (hoppe92)");
  RefinementInput input;
  input.origins = r.planes.origins;
  input.normals = r.planes.normals;
  input.oriented = r.normals();
  input.curvature = r.quadrics->curvature;
  input.distance = &f;
  input.spacing = r.planes.local_gap;
  // Noisy data (the fits miss their samples by over a hundredth of the
  // sampling density): blend the quadrics of 8 planes around each vertex.
  if (r.planes.noise > 0.01 * r.planes.rho) {
    input.blend = 8;
    input.origin_tree = &r.origin_tree;
  }
  if (r.oriented) input.piece = r.oriented->graph.components.label;
  input.sample_tree = &r.planes.point_tree;
  input.local_rho = r.planes.local_rho;
  input.delta = r.delta;
  return input;
}

SignedDistance<3> signed_distance_of(const Reconstruction& r) {
  SignedDistanceOptions given;
  given.delta = r.delta;
  return make_signed_distance<3>(r.planes, r.normals(), r.origin_tree, phase_3_options(r.method, given, r.quadrics));
}

Vec3 working_offset(std::span<const Vec3> points) {
  const Box<3> box = bounding_box<3>(points);
  if (box.empty()) return Vec3::Zero();
  const Vec3 centre = 0.5 * (box.min + box.max);
  // Near the origin already (within its own size): nothing to gain.
  if (centre.cwiseAbs().maxCoeff() <= box.diagonal()) return Vec3::Zero();
  return centre;
}

namespace {
// The final mesh's colours from the samples' (vertex_colors.h). Called
// before the mesh moves back to the input's coordinates: its vertices and
// phase I's tree over the samples are both in working coordinates then.
template <class Starting>
void color_mesh(Reconstruction& r, const VertexColorOptions& options, Starting& starting) {
  starting("colours");
  Timer timer;
  Mesh& mesh = r.refinement ? r.refinement->mesh : r.contour.mesh;
  mesh.colors = vertex_colors(mesh.vertices, r.planes.point_tree, r.colors, options);
  r.seconds_colors = timer.elapsed();
}
}  // namespace

WorkingTree working_tree(std::span<const Vec3> points, const KdTreeOptions& options) {
  check_coordinates<3>(points);  // before the bounding box of working_offset
  WorkingTree w;
  w.offset = working_offset(points);
  w.tree = KdTree<3>(points, options, w.offset);
  w.order = w.tree.renumber_by_leaf_order();
  return w;
}

Reconstruction reconstruct(const PointCloud& cloud, const ReconstructionOptions& options) {
  return reconstruct(PointCloudView(cloud), options);
}

Reconstruction reconstruct(PointCloudView cloud, const ReconstructionOptions& options) {
  return reconstruct_from(cloud, options, [] {});
}

Reconstruction reconstruct(PointCloud&& cloud, const ReconstructionOptions& options) {
  return reconstruct_from(PointCloudView(cloud), options, [&cloud] { cloud = {}; });
}

namespace {

// The start of phase I: the cloud moved near the origin (see working_offset)
// as phase I's kd-tree copies it, in the tree's leaf order; the input
// normals, when used, in the same order. `release` is called once nothing
// more is read from `cloud`.
Reconstruction take_the_cloud(PointCloudView cloud, const ReconstructionOptions& options,
                              const std::function<void()>& release, KdTree<3>& tree) {
  WorkingTree working = working_tree(cloud.positions, options.planes.tree);
  Reconstruction r;
  r.offset = working.offset;
  r.order = std::move(working.order);
  tree = std::move(working.tree);
  if (options.use_input_normals) r.input_normals = permuted<Vec3>(cloud.normals, r.order);
  if (cloud.has_colors()) r.colors = permuted<Color>(cloud.colors, r.order);
  release();
  return r;
}

}  // namespace

Reconstruction reconstruct_from(PointCloudView cloud, const ReconstructionOptions& options,
                                const std::function<void()>& release) {
  if (options.use_input_normals && !cloud.has_normals())
    throw InvalidInputError("the input has no normals to use; run without the option to estimate them");
  if (cloud.has_colors() && cloud.colors.size() != cloud.size())
    throw InvalidInputError("the cloud has " + std::to_string(cloud.colors.size()) + " colours for " +
                            std::to_string(cloud.size()) + " points");
  auto starting = [&](const char* phase) {
    if (options.on_phase) options.on_phase(phase);
  };
  const std::size_t limit = options.max_memory > 0 ? options.max_memory : default_memory_limit();
  check_memory_planes_and_graph(cloud.size(), options.planes.k, limit, options.method);
  starting("tangent planes");
  Timer tree_timer;
  KdTree<3> tree;
  Reconstruction r = take_the_cloud(cloud, options, release, tree);
  const double seconds_tree = tree_timer.lap();
  r.planes = estimate_tangent_planes<3>(std::move(tree), options.planes);
  r.planes.seconds_tree += seconds_tree;
  r.method = options.method;
  if (options.method == Method::refined) fit_second_order(r, options, lattice_cell(r.points(), r.planes, options));

  // Refuse a lattice that would not fit before building anything large.
  const double cell = lattice_cell(r.points(), r.planes, options);
  const double cubes = estimate_visited_cubes(r.order.size(), surface_spacing(r.planes), cell);
  {
    std::ostringstream what;
    what.precision(3);
    what << "a lattice cell of " << cell << " (about " << cubes << " cubes visited)";
    check_memory(estimated_bytes_lattice(r.order.size(), cubes), limit, what.str(),
                 "use a larger --cell or a smaller --resolution");
  }
  if (!options.use_input_normals)  // phase I may have raised k
    check_memory_planes_and_graph(r.order.size(), r.planes.k, limit, options.method);

  if (options.use_input_normals) {
    for (Vec3& n : r.input_normals) {
      const double norm = n.norm();
      if (!(norm > 0.0) || !std::isfinite(norm))
        throw InvalidInputError("the input normals include a zero or non-finite one; run without using them");
      n /= norm;
    }
    r.planes.neighbors = {};
  }
  // The refined method decides each component's side at its best extreme
  // (orientation.h), and phase III's f picks its plane among 8 (signed_distance.h).
  OrientationOptions orientation = options.orientation;
  if (options.method == Method::refined) orientation.sign_by_extremes = true;
  if (r.quadrics) {
    orientation.sheet_misfit = r.quadrics->residual;
    orientation.guide = r.quadrics->guide;
  }
  const SignedDistanceOptions distance = phase_3_options(options.method, options.distance, r.quadrics);
  FirstWave wave;  // phase III's values at the first wave's corners, computed beside phase II
  double seconds_known = 0.0;
  if (!options.use_input_normals) {
    starting("orientation");
    RiemannianGraph<3> graph = build_riemannian_graph<3>(r.planes, orientation.graph);
    r.planes.neighbors = {};  // the graph's source, no longer needed
    orient_with_first_wave(r, std::move(graph), cell, orientation, distance, wave, seconds_known);
    if (r.quadrics) r.quadrics->guide = {};
    if (!options.keep_graph) {
      r.oriented->graph.graph = {};
      r.oriented->graph.emst = {};
      r.oriented->tree = {};
    }
  }

  starting("signed distance");
  Timer timer;
  // (Computed beside phase II, once the graph's construction has passed
  // its peak of memory: the two need not add up.)
  if (options.use_input_normals) r.origin_tree = r.planes.point_tree.refit(r.planes.origins);
  const SignedDistance<3> f = make_signed_distance<3>(r.planes, r.normals(), r.origin_tree, distance);
  r.delta = f.delta();
  r.delta_given = f.delta_given();
  r.seconds_distance_setup = timer.lap() + seconds_known;

  starting("contouring");
  MarchingCubesOptions mc;
  mc.cell = cell;
  // The walk stops where the estimate would have: a lattice estimated
  // wrongly cannot run on until memory is exhausted.
  mc.max_cubes = static_cast<std::size_t>(
      std::max(0.0, (static_cast<double>(limit) - static_cast<double>(r.order.size()) * bytes_per_point_held) /
                        bytes_per_cube));
  mc.keep_corners = options.keep_corners;
  r.contour = wave.ready() ? marching_cubes(std::cref(f), wave.take_wave(), mc)
                           : marching_cubes(std::cref(f), r.points(), mc);
  if (options.method == Method::refined) {
    starting("refinement");
    const RefinementInput input = refinement_input_of(r, f);
    RefinementOptions refinement = options.refinement;
    if (refinement.max_move <= 0.0) refinement.max_move = cell;
    r.refinement = refine_mesh(r.contour.mesh, input, refinement);
  }
  if (options.mesh_colors && !r.colors.empty()) color_mesh(r, options.colors, starting);
  if (r.offset != Vec3::Zero()) {
    for (Vec3& v : r.contour.mesh.vertices) v += r.offset;
    if (r.refinement)
      for (Vec3& v : r.refinement->mesh.vertices) v += r.offset;
  }
  return r;
}

}  // namespace recon
