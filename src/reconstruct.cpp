#include "recon/reconstruct_parts.h"

#include "first_wave.h"
#include "recon/core/errors.h"
#include "recon/core/memory_budget.h"
#include "recon/core/parallel.h"
#include "recon/core/point_cloud.h"  // max_coordinate
#include "recon/core/resource_usage.h"
#include "recon/core/timer.h"
#include "recon/structures/lattice.h"
#include "recon/structures/spatial_order.h"  // permuted

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>
#include <string>

namespace recon {

Method method_from_name(std::string_view name) {
  if (name == "refined") return Method::refined;
  if (name == "hoppe92") return Method::hoppe92;
  throw InvalidInputError("unknown method '" + std::string(name) + "': use refined (the default) or hoppe92");
}

const char* method_name(Method method) { return method == Method::hoppe92 ? "hoppe92" : "refined"; }

namespace {

// The side of the square of surface each sample stands for: k samples
// cover a disc of the neighbourhood radius (its median over the points).
double surface_spacing(const TangentPlanes<3>& planes) {
  std::vector<float> radius(planes.radius);
  if (radius.empty() || planes.k < 1) return planes.rho;
  const auto middle = radius.begin() + static_cast<std::ptrdiff_t>(radius.size() / 2);
  std::nth_element(radius.begin(), middle, radius.end());
  return std::sqrt(std::numbers::pi / planes.k) * static_cast<double>(*middle);
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
    if (ProgressCounter* progress = progress_counter()) progress->expect(2 * r.order.size());
    const double seconds = r.planes.seconds_tree + r.planes.seconds_knn_pca + r.planes.seconds_spacing;
    r.planes = estimate_tangent_planes<3>(std::move(r.planes.point_tree), asked);
    r.planes.seconds_knn_pca += seconds;
    const double first = r.quadrics->seconds;
    r.quadrics = fit_local_quadrics(r.planes, fits);
    r.quadrics->seconds += first;
    // The cell came from the first planes' rho: another cell's fits are not
    // known to be these (phases_1_2_hold_for).
    r.quadrics->same_fits = {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  }
  adopt_second_order(r.planes, *r.quadrics);
}

}  // namespace

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
  WorkingTree working = options.offset ? working_tree(cloud.positions, options.planes.tree, *options.offset)
                                       : working_tree(cloud.positions, options.planes.tree);
  Reconstruction r;
  r.offset = working.offset;
  r.order = std::move(working.order);
  tree = std::move(working.tree);
  if (options.use_input_normals) r.input_normals = permuted<Vec3>(cloud.normals, r.order);
  if (cloud.has_colors()) r.colors = permuted<Color>(cloud.colors, r.order);
  release();
  return r;
}

// A length option beyond any cloud's extent (coordinates are refused past
// +-max_coordinate) means nothing, and its square overflows in the phases.
void check_length_option(const char* name, const std::optional<double>& value) {
  constexpr double longest = 4.0 * max_coordinate;
  if (!value || *value <= longest) return;  // (NaN, 0 and negatives: each phase's own check)
  std::ostringstream message;
  message.precision(3);
  message << name << " of " << *value << " is longer than any cloud can be (at most " << longest
          << ": coordinates are refused beyond +-" << max_coordinate << ")";
  throw InvalidInputError(message.str());
}

// Phase VI's values, before anything runs: a bad one found after an hour
// of phases I-V would waste the hour.
void check_simplify_step(const SimplifyStep& step) {
  // isfinite first: an ordered comparison with a NaN raises the invalid
  // exception (trapped in the sanitizer build).
  if (step.ratio != 0.0 && (!std::isfinite(step.ratio) || step.ratio <= 0.0 || step.ratio >= 1.0))
    throw InvalidInputError("simplify: a ratio must lie between 0 and 1 (exclusive), not " +
                            std::to_string(step.ratio));
  if (!std::isfinite(step.max_error) || step.max_error < 0.0)
    throw InvalidInputError("simplify: the error bound must be a finite multiple of rho >= 0, not " +
                            std::to_string(step.max_error));
}

void check_cloud(PointCloudView cloud, const ReconstructionOptions& options) {
  check_length_option("rho", options.planes.rho);
  check_length_option("a cell", options.cell);
  check_length_option("delta", options.distance.delta);
  check_simplify_step(options.simplify);
  if (options.use_input_normals && !cloud.has_normals())
    throw InvalidInputError("the input has no normals to use; run without the option to estimate them");
  if (cloud.has_colors() && cloud.colors.size() != cloud.size())
    throw InvalidInputError("the cloud has " + std::to_string(cloud.colors.size()) + " colours for " +
                            std::to_string(cloud.size()) + " points");
}

// One run's settings besides the result: its options and memory limit.
struct Run {
  const ReconstructionOptions& options;
  std::size_t limit;
  void starting(const char* phase, std::uint64_t work = 0) const {
    if (options.on_phase) options.on_phase(phase);
    if (options.progress) options.progress->start(work);
  }
  [[nodiscard]] bool refined() const { return options.method == Method::refined; }
};

// Phase I: the planes (and the refined method's second-order fits).
Reconstruction phase_1(PointCloudView cloud, const Run& run, const std::function<void()>& release) {
  check_memory_planes_and_graph(cloud.size(), run.options.planes.k, run.limit, run.refined());
  run.starting("tangent planes", cloud.size() * (run.refined() ? 2 : 1));
  Timer tree_timer;
  KdTree<3> tree;
  Reconstruction r = take_the_cloud(cloud, run.options, release, tree);
  const double seconds_tree = tree_timer.lap();
  r.planes = estimate_tangent_planes<3>(std::move(tree), run.options.planes);
  r.planes.seconds_tree += seconds_tree;
  r.method = run.options.method;
  if (run.refined()) fit_second_order(r, run.options, lattice_cell(r.points(), r.planes, run.options));
  return r;
}

// Refuse a lattice (or a phase II raised k) that would not fit, before
// building anything large.
void check_memory_after_phase_1(const Reconstruction& r, const Run& run, double cell) {
  // (A cell so small that a sample's share of the surface spans more cubes
  // than a lattice axis holds is refused first, with the lattice's own
  // message: the estimate below would overflow on it. A cloud merely wider
  // than one lattice is split into far-apart clusters in phase IV, each on a
  // lattice of its own, and each checked there.)
  if (!(surface_spacing(r.planes) / cell <= Lattice<3>::max_cells_per_axis))
    static_cast<void>(make_lattice<3>(bounding_box<3>(r.points()), cell));
  const double cubes = estimate_visited_cubes(r.order.size(), surface_spacing(r.planes), cell);
  std::ostringstream what;
  what.precision(3);
  what << "a lattice cell of " << cell << " (about " << cubes << " cubes visited)";
  check_memory(estimated_bytes_lattice(r.order.size(), cubes), run.limit, what.str(),
               "use a larger --cell or a smaller --resolution");
  if (!run.options.use_input_normals)  // phase I may have raised k
    check_memory_planes_and_graph(r.order.size(), r.planes.k, run.limit, run.refined());
}

// The input's own normals, made unit, take phase II's place.
void use_input_normals(Reconstruction& r) {
  for (Vec3& n : r.input_normals) {
    const double norm = n.norm();
    if (!(norm > 0.0) || !std::isfinite(norm))
      throw InvalidInputError("the input normals include a zero or non-finite one; run without using them");
    n /= norm;
  }
  r.planes.neighbors = {};
}

// Phase II, with phase III's first wave beside it (first_wave.h)
// when there is one lattice (`wave` not null); without, phase III's tree
// over the plane origins after it.
void phase_2(Reconstruction& r, const Run& run, double cell, const SignedDistanceOptions& distance,
             detail::FirstWave* wave, double& seconds_wave) {
  run.starting("orientation", 3 * r.order.size());
  const OrientationOptions orientation = orientation_options(r, run.options);
  RiemannianGraph<3> graph = build_riemannian_graph<3>(r.planes, orientation.graph);
  r.planes.neighbors = {};  // the graph's source, no longer needed
  if (wave != nullptr) {
    detail::orient_with_first_wave(r, std::move(graph), cell, orientation, distance, *wave, seconds_wave);
  } else {
    r.oriented = orient_normals<3>(r.planes, std::move(graph), orientation);
    Timer timer;
    r.origin_tree = r.planes.point_tree.refit(r.planes.origins);
    seconds_wave = timer.lap();
  }
  if (r.quadrics) r.quadrics->guide = {};
  if (!run.options.keep_graph) {
    r.oriented->graph.graph = {};
    r.oriented->graph.emst = {};
    r.oriented->tree = {};
  }
}

// Phase III: f over the oriented planes.
SignedDistance<3> phase_3(Reconstruction& r, const Run& run, const SignedDistanceOptions& distance,
                          double seconds_wave) {
  run.starting("signed distance");
  Timer timer;
  // (Built beside phase II otherwise, once the graph's construction had
  // passed its peak of memory: the two need not add up.)
  if (run.options.use_input_normals) r.origin_tree = r.planes.point_tree.refit(r.planes.origins);
  SignedDistance<3> f = make_signed_distance<3>(r.planes, r.normals(), r.origin_tree, distance);
  r.delta = f.delta();
  r.delta_given = f.delta_given();
  r.seconds_distance_setup = timer.lap() + seconds_wave;
  return f;
}

// Phase IV's start: the count for the progress display, and the walk's options.
MarchingCubesOptions start_contouring(const Reconstruction& r, const Run& run, double cell) {
  const double cubes =
      run.options.progress ? expected_visited_cubes(r.order.size(), surface_spacing(r.planes), cell) : 0.0;
  run.starting("contouring", static_cast<std::uint64_t>(cubes));
  MarchingCubesOptions mc;
  mc.cell = cell;
  mc.max_cubes = max_cubes_within(run.limit, r.order.size());
  mc.keep_corners = run.options.keep_corners;
  return mc;
}

// Phase IV, from the first wave when phase II computed one.
void phase_4(Reconstruction& r, const Run& run, const SignedDistance<3>& f, double cell, detail::FirstWave& wave) {
  const MarchingCubesOptions mc = start_contouring(r, run, cell);
  r.contour =
      wave.ready() ? marching_cubes(std::cref(f), wave.take_wave(), mc) : marching_cubes(std::cref(f), r.points(), mc);
}

// Where the contour is empty: what the lattice saw, and what to change.
// An empty mesh is never the surface of a cloud that passed phases I-III
// (they refuse too few, coincident and collinear points), so it is an
// error, not a result: the caller would otherwise write a file of nothing.
// The usual cause is a cell about as large as the cloud (a given --cell, or
// a given rho, of which the default cell is a fraction): its few cubes see
// f of one sign at every corner.
void refuse_an_empty_contour(const Reconstruction& r, const ReconstructionOptions& options, double cell) {
  if (!r.contour.mesh.triangles.empty()) return;
  const double longest = bounding_box<3>(r.points()).extent().maxCoeff();
  std::ostringstream figures;
  figures.precision(3);
  figures << "the signed distance changes sign in none of the " << r.contour.visited_cubes
          << " lattice cubes visited (cell " << cell << ", rho " << r.planes.rho << ", delta " << r.delta << ")";
  std::string smaller_cell = "--cell";
  if (!options.cell && options.resolution)
    smaller_cell = "a larger --resolution";
  else if (!options.cell)
    smaller_cell = std::string("the cell is rho") + (options.method == Method::hoppe92 ? "" : " / sqrt 2") +
                   " by default: a smaller --rho, or --cell";
  refuse_no_surface(figures.str(), cell, longest, smaller_cell);
}

// Phase V (refined): the mesh moved onto the fits, creases sharpened.
void phase_5(Reconstruction& r, const Run& run, const SignedDistance<3>& f, double cell) {
  run.starting("refinement", r.contour.mesh.vertices.size());
  // The triangles in their cubes' order, not the walk's: the same order as
  // a tile's (tiles.h), so that phase V makes the same choices there. (Far-
  // apart clusters: each cluster's were sorted on its own lattice.)
  if (r.clusters.empty()) sort_by_cube(r.contour);
  RefinementOptions options = refinement_options(run.options.refinement, cell);
  options.fitted_normals = run.options.vertex_normals;
  r.refinement = refine_mesh(r.contour.mesh, refinement_input_of(r, f), options);
}

// Phase VI: the final mesh simplified, its bound in rho's units turned into
// a distance. The vertices keep their places, so the colours given after
// are those the unsimplified mesh would have had there.
void phase_6(Reconstruction& r, const Run& run) {
  run.starting("simplification");
  const SimplifyStep& step = run.options.simplify;
  const Mesh& mesh = r.mesh();
  if (step.triangles > mesh.triangles.size())
    throw InvalidInputError("simplify to " + std::to_string(step.triangles) + " triangles: the mesh has only " +
                            std::to_string(mesh.triangles.size()));
  SimplifyOptions options;
  options.target_triangles = step.triangles;
  options.ratio = step.ratio;
  options.max_error = step.max_error * r.planes.rho;
  r.simplification = simplify(mesh, options);
}

// The final mesh's colours from the samples' (vertex_colors.h). Called
// before the mesh moves back to the input's coordinates: its vertices and
// phase I's tree over the samples are both in working coordinates then.
void color_mesh(Reconstruction& r, const Run& run) {
  run.starting("colours");
  Timer timer;
  Mesh& mesh = r.mesh();
  mesh.colors = vertex_colors(mesh.vertices, r.planes.point_tree, r.colors, run.options.colors);
  r.seconds_colors = timer.elapsed();
}

void move_back_to_input_coordinates(Reconstruction& r) {
  if (r.offset == Vec3::Zero()) return;
  for (Vec3& v : r.contour.mesh.vertices) v += r.offset;
  if (r.refinement)
    for (Vec3& v : r.refinement->mesh.vertices) v += r.offset;
  if (r.simplification)
    for (Vec3& v : r.simplification->mesh.vertices) v += r.offset;
}

// ---------------------------------------------------------------------------
// Far-apart clusters, each on a lattice of its own (see reconstruct.h).

// A cluster: sample indices (spatial order), ascending.
using Cluster = std::vector<std::uint32_t>;

// How far from its samples any phase reaches: the widest neighbourhood of a
// sample that draws (phases I and II; an isolated sample draws nothing),
// f's reach past a plane and phase V's (RefinementInput::reach rho_i +
// delta, refinement.h), and a lattice's margin, each with a cube to spare.
double reach_of_phases(const Reconstruction& r, double cell) {
  float widest = 0.0f, rho = 0.0f;
  for (std::size_t j = 0; j < r.planes.local_rho.size(); ++j) {
    if (!(r.planes.local_rho[j] > 0.0f)) continue;
    widest = std::max(widest, r.planes.radius[j]);
    rho = std::max(rho, r.planes.local_rho[j]);
  }
  const double field = std::max(1.5, RefinementInput{}.reach) * static_cast<double>(rho) + r.delta;
  return std::max({static_cast<double>(widest), field, lattice_margin * cell}) + cell;
}

// Splits `group` at every empty slab along `axis` wider than `gap`, into
// `parts` (each ascending); false when there is none.
bool split_at_gaps(std::span<const Vec3> points, Cluster group, int axis, double gap, std::vector<Cluster>& parts) {
  std::sort(group.begin(), group.end(), [&](std::uint32_t a, std::uint32_t b) {
    return points[a][axis] < points[b][axis] || (points[a][axis] == points[b][axis] && a < b);
  });
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= group.size(); ++i) {
    if (i < group.size() && !(points[group[i]][axis] - points[group[i - 1]][axis] > gap)) continue;
    if (begin == 0 && i == group.size()) return false;  // no gap: one part
    Cluster part(group.begin() + static_cast<std::ptrdiff_t>(begin), group.begin() + static_cast<std::ptrdiff_t>(i));
    std::sort(part.begin(), part.end());
    parts.push_back(std::move(part));
    begin = i;
  }
  return true;
}

// The samples split at every empty axis slab wider than `gap`, again within
// each part until none has one; ordered by their first sample.
std::vector<Cluster> far_apart_clusters(std::span<const Vec3> points, double gap) {
  Cluster all(points.size());
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  std::vector<Cluster> pending{std::move(all)}, clusters;
  while (!pending.empty()) {
    Cluster group = std::move(pending.back());
    pending.pop_back();
    std::vector<Cluster> parts;
    int axis = 0;
    while (axis < 3 && !split_at_gaps(points, group, axis, gap, parts)) ++axis;
    if (axis == 3) {
      clusters.push_back(std::move(group));
    } else {
      for (Cluster& part : parts) pending.push_back(std::move(part));
    }
  }
  std::sort(clusters.begin(), clusters.end(), [](const Cluster& a, const Cluster& b) { return a.front() < b.front(); });
  return clusters;
}

// The clusters of a cloud too wide for one lattice; ResourceLimitError when
// one of them is too wide for one too.
std::vector<Cluster> clusters_on_lattices(const Reconstruction& r, double cell) {
  const std::span<const Vec3> points = r.points();
  const double gap = 2.0 * reach_of_phases(r, cell);
  std::vector<Cluster> clusters = far_apart_clusters(points, gap);
  for (const Cluster& cluster : clusters) {
    Box<3> box;
    for (const std::uint32_t i : cluster) box.extend(points[i]);
    if (lattice_fits<3>(box, cell)) continue;
    std::ostringstream what;
    what.precision(3);
    if (clusters.size() == 1) {
      what << "the cloud is too wide for one lattice, and no empty gap wider than " << gap
           << " (twice the phases' reach) splits it into clusters to mesh on lattices of their own: ";
    } else {
      what << "a cluster of " << cluster.size() << " points (of " << clusters.size()
           << " separated by empty gaps wider than " << gap << ") is too wide for one lattice: ";
    }
    try {
      (void)make_lattice<3>(box, cell);
    } catch (const ResourceLimitError& e) {
      throw ResourceLimitError(what.str() + e.what());
    }
  }
  return clusters;
}

// Whether any sample of `cluster` draws a surface (one isolated sample
// draws none: its rho_i is 0, tangent_planes.h).
bool draws(const TangentPlanes<3>& planes, const Cluster& cluster) {
  return std::any_of(cluster.begin(), cluster.end(), [&](std::uint32_t i) { return planes.local_rho[i] > 0.0f; });
}

// Appends `part`'s mesh and statistics to `all` (the same cell).
void append_contour(MarchingCubesResult& all, MarchingCubesResult&& part) {
  const auto first = static_cast<std::uint32_t>(all.mesh.vertices.size());
  all.mesh.vertices.insert(all.mesh.vertices.end(), part.mesh.vertices.begin(), part.mesh.vertices.end());
  for (const auto& t : part.mesh.triangles) all.mesh.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
  all.seed_cubes += part.seed_cubes;
  all.visited_cubes += part.visited_cubes;
  all.undefined_cubes += part.undefined_cubes;
  all.evaluated_corners += part.evaluated_corners;
  all.undefined_corners += part.undefined_corners;
  all.seconds += part.seconds;
  all.seconds_field += part.seconds_field;
}

// Phase IV on a cloud too wide for one lattice: each cluster from its own
// samples on a lattice over them (in the refined method its triangles in
// their cubes' order, as phase V wants them), into r.contour and r.clusters.
void phase_4_by_cluster(Reconstruction& r, const Run& run, const SignedDistance<3>& f, double cell) {
  const std::vector<Cluster> clusters = clusters_on_lattices(r, cell);
  MarchingCubesOptions mc = start_contouring(r, run, cell);
  mc.keep_corners = false;  // (the corners of several lattices: see reconstruct.h)
  r.contour = {};
  r.contour.cell = cell;
  for (const Cluster& cluster : clusters) {
    if (!draws(r.planes, cluster)) continue;  // stray samples, far from all else: no surface, no lattice
    std::vector<Vec3> seeds;
    seeds.reserve(cluster.size());
    for (const std::uint32_t i : cluster) seeds.push_back(r.points()[i]);
    MarchingCubesResult part = marching_cubes(std::cref(f), seeds, mc);
    if (run.refined()) sort_by_cube(part);
    r.clusters.push_back({cluster.size(), part.origin, part.size, part.mesh.triangles.size()});
    append_contour(r.contour, std::move(part));
  }
}

}  // namespace

Reconstruction reconstruct_phase_1(PointCloudView cloud, const ReconstructionOptions& options) {
  check_cloud(cloud, options);
  return phase_1(cloud, Run{options, memory_limit_or_default(options.max_memory)}, [] {});
}

namespace {

// Phases III to VI and the colours on `r`, whose phases I and II are done
// (with phase III's first wave beside phase II when `wave` holds it).
void later_phases(Reconstruction& r, const Run& run, double cell, const SignedDistanceOptions& distance,
                  detail::FirstWave& wave, double seconds_wave) {
  const ReconstructionOptions& options = run.options;
  const SignedDistance<3> f = phase_3(r, run, distance, seconds_wave);
  if (lattice_fits<3>(bounding_box<3>(r.points()), cell)) {
    phase_4(r, run, f, cell, wave);
  } else {  // far-apart clusters, a lattice each (see reconstruct.h)
    phase_4_by_cluster(r, run, f, cell);
  }
  refuse_an_empty_contour(r, options, cell);
  if (run.refined()) phase_5(r, run, f, cell);
  if (options.simplify.requested()) phase_6(r, run);
  if (options.mesh_colors && !r.colors.empty()) color_mesh(r, run);
  move_back_to_input_coordinates(r);
  // Last, in the input's coordinates (as a tiled run's stitched mesh has them).
  if (options.vertex_normals) r.face_normals = fill_face_normals(r.mesh());
}

}  // namespace

Reconstruction reconstruct_from(PointCloudView cloud, const ReconstructionOptions& options,
                                const std::function<void()>& release) {
  check_cloud(cloud, options);
  const ProgressScope counting(options.progress);  // the phases' counts (progress.h)
  const Run run{options, memory_limit_or_default(options.max_memory)};
  Reconstruction r = phase_1(cloud, run, release);
  const double cell = lattice_cell(r.points(), r.planes, options);
  check_memory_after_phase_1(r, run, cell);
  // Else far-apart clusters, a lattice each (see reconstruct.h).
  const bool one_lattice = lattice_fits<3>(bounding_box<3>(r.points()), cell);

  const SignedDistanceOptions distance = signed_distance_options(options.method, options.distance, r.quadrics);
  detail::FirstWave wave;  // phase III's values at the first wave's corners, computed beside phase II
  double seconds_wave = 0.0;
  if (options.use_input_normals) {
    use_input_normals(r);
  } else {
    phase_2(r, run, cell, distance, one_lattice ? &wave : nullptr, seconds_wave);
  }
  later_phases(r, run, cell, distance, wave, seconds_wave);
  return r;
}

Reconstruction reconstruct_phases_1_2(PointCloudView cloud, const ReconstructionOptions& options) {
  check_cloud(cloud, options);
  const ProgressScope counting(options.progress);
  Reconstruction r = phase_1(cloud, Run{options, memory_limit_or_default(options.max_memory)}, [] {});
  reconstruct_phase_2_on(r, options);
  return r;
}

void reconstruct_phase_2_on(Reconstruction& r, const ReconstructionOptions& options) {
  const ProgressScope counting(options.progress);
  const Run run{options, memory_limit_or_default(options.max_memory)};
  check_memory_after_phase_1(r, run, lattice_cell(r.points(), r.planes, options));
  if (options.use_input_normals) {
    use_input_normals(r);  // (phase III builds the origins' tree then)
  } else {
    double seconds_tree = 0.0;  // the tree over the origins, phase III's: counted there, as reconstruct() does
    phase_2(r, run, 0.0, SignedDistanceOptions{}, nullptr, seconds_tree);
    r.seconds_distance_setup = seconds_tree;
  }
}

bool phases_1_2_hold_for(const Reconstruction& r, const ReconstructionOptions& options) {
  if (r.method != options.method) return false;
  if (!r.quadrics || options.quadrics.min_sheet_separation > 0.0) return true;  // the cell plays no part in them
  return r.quadrics->same_fits.holds(1.5 * lattice_cell(r.points(), r.planes, options));  // as fit_second_order
}

void reconstruct_phases_3_on(Reconstruction& r, const ReconstructionOptions& options) {
  check_length_option("a cell", options.cell);
  check_length_option("delta", options.distance.delta);
  check_simplify_step(options.simplify);
  if (r.method != options.method)
    throw InvalidInputError(std::string("phases III-V of the ") + method_name(options.method) +
                            " method asked on phases I-II of the " + method_name(r.method) + " method");
  const ProgressScope counting(options.progress);
  const Run run{options, memory_limit_or_default(options.max_memory)};
  // The previous run's later results go; the origins' tree (phase III's, made with phase II) stays.
  const double seconds_tree = r.seconds_distance_setup;
  r.contour = {};
  r.clusters.clear();
  r.refinement.reset();
  r.simplification.reset();
  r.face_normals = {};
  r.seconds_colors = 0.0;
  const double cell = lattice_cell(r.points(), r.planes, options);
  check_memory_after_phase_1(r, run, cell);
  detail::FirstWave none;
  later_phases(r, run, cell, signed_distance_options(options.method, options.distance, r.quadrics), none, seconds_tree);
}

}  // namespace recon
