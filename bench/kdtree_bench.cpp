// recon's kd-tree measured against nanoflann on the kind of data phase I
// sees: a Poisson sample of a torus, every point asking for its k = 15
// nearest neighbours (itself included).
//
// Both trees get the same points in the same order, at n = 100k and 1M:
//   - "sampled": the order make_torus()->sample() returns them in, which is
//     random: consecutive points are far apart on the surface;
//   - "morton": sorted along a Morton (Z-order) curve first, with
//     recon::spatial_order (reconstruct() uses its kd-tree's leaf order, to
//     the same effect), so consecutive points are
//     close: this shows how much of a k-NN loop's time is memory order
//     rather than search.
// Our all_knn always visits the points in its own leaf order, whatever the
// input order; nanoflann's loop visits them in input order. knn_ours_loop
// runs our single-point knn() in input order too, to tell the search itself
// from the visiting order.
//
// Benchmarks:
//   build_*        tree construction only
//   knn_*          all k-NN (tree built before the timed loop); threads = 1
//                  or 2 (OpenMP, the same dynamic schedule for both trees)
//   planes_*       phase I's floor: build + k-NN + PCA plane fit for every
//                  point, Morton order, 1 and 2 threads. Ours is the whole of
//                  estimate_tangent_planes (k = 15, no k adaptation: it also
//                  keeps the neighbour lists and measures the spacing);
//                  the reference is nanoflann's knnSearch + centroid and
//                  covariance + Eigen's closed-form 3x3 eigen-solver
//                  (SelfAdjointEigenSolver::computeDirect), the fastest
//                  pairing a user would write.
//   leaf_sweep_*   build + all_knn(15) on 1M points, one thread, per leaf
//                  size: the measurement behind KdTreeOptions::leaf_size
//                  (ours on the sampled order, nanoflann on the Morton one)
// The two trees are checked to find the same neighbours before any timing.
//
// Run through bench/run.sh; results are discussed in docs/benchmarks.md.

#include "recon/core/parallel.h"
#include "recon/core/shapes.h"
#include "recon/core/timer.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/structures/kdtree.h"
#include "recon/structures/spatial_order.h"

#include <benchmark/benchmark.h>

// nanoflann is a system header for this target (imported target), but keep
// its warnings out of our -Werror build even if it is found elsewhere.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wnull-dereference"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#include <nanoflann.hpp>
#pragma GCC diagnostic pop
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <map>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace {

using recon::Vec3;

// The neighbourhood size compared (in Hoppe's 4..20; phase I's own default
// is TangentPlaneOptions{}.k).
constexpr int k = 15;
constexpr std::uint64_t seed = 1;  // same data on every run
constexpr int our_default_leaf = recon::KdTreeOptions{}.leaf_size;
constexpr int nanoflann_default_leaf = 10;  // KDTreeSingleIndexAdaptorParams' default

// ---------------------------------------------------------------------------
// Data

// Torus samples, generated once per (n, order) and kept for every benchmark.
const std::vector<Vec3>& torus_points(std::size_t n, bool morton) {
  static std::map<std::pair<std::size_t, bool>, std::vector<Vec3>> cache;
  const auto key = std::make_pair(n, morton);
  auto found = cache.find(key);
  if (found != cache.end()) return found->second;
  std::vector<Vec3> points = recon::make_torus()->sample(n, seed).positions;
  if (morton) points = recon::permuted<Vec3>(points, recon::spatial_order(points));
  return cache.emplace(key, std::move(points)).first->second;
}

// ---------------------------------------------------------------------------
// nanoflann over the same std::vector<Vec3>, read in place through an adaptor.

struct PointsAdaptor {
  std::span<const Vec3> points;

  [[nodiscard]] std::size_t kdtree_get_point_count() const { return points.size(); }
  [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t axis) const {
    return points[i][static_cast<Eigen::Index>(axis)];
  }
  // false: let nanoflann compute the bounding box itself.
  template <class BoundingBox>
  bool kdtree_get_bbox(BoundingBox& /*box*/) const {
    return false;
  }
};

using NanoflannTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor, double, std::uint32_t>,
                                        PointsAdaptor, 3, std::uint32_t>;

// What nanoflann's all-k-NN loop fills: the same n x k table as KnnTable,
// as two arrays.
struct NanoflannTable {
  std::vector<std::uint32_t> indices;
  std::vector<double> distances2;
};

NanoflannTable nanoflann_all_knn(const NanoflannTree& tree, std::span<const Vec3> points) {
  const std::size_t n = points.size();
  const auto kk = static_cast<std::size_t>(k);
  NanoflannTable table{std::vector<std::uint32_t>(n * kk), std::vector<double>(n * kk)};
  const auto count = static_cast<std::int64_t>(n);
  // The same schedule as KdTree::all_knn.
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 4096)
#endif
  for (std::int64_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    tree.knnSearch(points[i].data(), kk, table.indices.data() + i * kk, table.distances2.data() + i * kk);
  }
  return table;
}

void set_rate(benchmark::State& state, std::size_t n) {
  state.counters["points/s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

// ---------------------------------------------------------------------------
// Build

void build_ours(benchmark::State& state) {
  const auto& points = torus_points(static_cast<std::size_t>(state.range(0)), state.range(1) != 0);
  const recon::KdTreeOptions options{static_cast<int>(state.range(2))};
  for (auto _ : state) {
    recon::KdTree<3> tree(points, options);
    benchmark::DoNotOptimize(tree.nodes().data());
    benchmark::ClobberMemory();
  }
  set_rate(state, points.size());
}

void build_nanoflann(benchmark::State& state) {
  const auto& points = torus_points(static_cast<std::size_t>(state.range(0)), state.range(1) != 0);
  const PointsAdaptor adaptor{points};
  const nanoflann::KDTreeSingleIndexAdaptorParams params(static_cast<std::size_t>(state.range(2)));
  for (auto _ : state) {
    NanoflannTree tree(3, adaptor, params);
    benchmark::DoNotOptimize(&tree);
    benchmark::ClobberMemory();
  }
  set_rate(state, points.size());
}

// ---------------------------------------------------------------------------
// All k-NN

void knn_ours(benchmark::State& state) {
  const auto& points = torus_points(static_cast<std::size_t>(state.range(0)), state.range(2) != 0);
  recon::set_thread_count(static_cast<int>(state.range(1)));
  const recon::KdTree<3> tree(points, {our_default_leaf});
  for (auto _ : state) {
    const recon::KnnTable table = tree.all_knn(k);
    benchmark::DoNotOptimize(table.entries.data());
    benchmark::ClobberMemory();
  }
  set_rate(state, points.size());
}

// Our single-point query in a loop over the input order, like nanoflann's.
void knn_ours_loop(benchmark::State& state) {
  const auto& points = torus_points(static_cast<std::size_t>(state.range(0)), state.range(2) != 0);
  recon::set_thread_count(static_cast<int>(state.range(1)));
  const recon::KdTree<3> tree(points, {our_default_leaf});
  const auto kk = static_cast<std::size_t>(k);
  for (auto _ : state) {
    std::vector<recon::Neighbor> table(points.size() * kk);
    const auto count = static_cast<std::int64_t>(points.size());
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 4096)
#endif
    for (std::int64_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      tree.knn(points[i], std::span<recon::Neighbor>(table.data() + i * kk, kk));
    }
    benchmark::DoNotOptimize(table.data());
    benchmark::ClobberMemory();
  }
  set_rate(state, points.size());
}

void knn_nanoflann(benchmark::State& state) {
  const auto& points = torus_points(static_cast<std::size_t>(state.range(0)), state.range(2) != 0);
  recon::set_thread_count(static_cast<int>(state.range(1)));  // the same OpenMP runtime
  const PointsAdaptor adaptor{points};
  const NanoflannTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(nanoflann_default_leaf));
  for (auto _ : state) {
    const NanoflannTable table = nanoflann_all_knn(tree, points);
    benchmark::DoNotOptimize(table.indices.data());
    benchmark::DoNotOptimize(table.distances2.data());
    benchmark::ClobberMemory();
  }
  set_rate(state, points.size());
}

// ---------------------------------------------------------------------------
// Leaf-size sweep: build + all_knn(15), 1M points, one thread. Reports the
// two parts separately, as wall and process CPU seconds per iteration.

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

struct SplitTimes {
  double build_s = 0.0, knn_s = 0.0, build_cpu_s = 0.0, knn_cpu_s = 0.0;

  void report(benchmark::State& state) const {
    const auto per_iteration = benchmark::Counter::kAvgIterations;
    state.counters["build_s"] = benchmark::Counter(build_s, per_iteration);
    state.counters["knn_s"] = benchmark::Counter(knn_s, per_iteration);
    state.counters["build_cpu_s"] = benchmark::Counter(build_cpu_s, per_iteration);
    state.counters["knn_cpu_s"] = benchmark::Counter(knn_cpu_s, per_iteration);
  }
};

template <class Build, class AllKnn>
void sweep_iteration(SplitTimes& times, Build&& build, AllKnn&& all_knn) {
  recon::Timer timer;
  const double cpu_start = cpu_seconds();
  const auto tree = build();
  times.build_s += timer.lap();
  const double cpu_built = cpu_seconds();
  times.build_cpu_s += cpu_built - cpu_start;
  all_knn(*tree);
  times.knn_s += timer.lap();
  times.knn_cpu_s += cpu_seconds() - cpu_built;
}

void leaf_sweep_ours(benchmark::State& state) {
  const auto& points = torus_points(1'000'000, state.range(1) != 0);
  recon::set_thread_count(1);
  const recon::KdTreeOptions options{static_cast<int>(state.range(0))};
  SplitTimes times;
  for (auto _ : state) {
    sweep_iteration(
        times, [&] { return std::make_unique<const recon::KdTree<3>>(points, options); },
        [&](const recon::KdTree<3>& tree) {
          const recon::KnnTable table = tree.all_knn(k);
          benchmark::DoNotOptimize(table.entries.data());
          benchmark::ClobberMemory();
        });
  }
  times.report(state);
  set_rate(state, points.size());
}

void leaf_sweep_nanoflann(benchmark::State& state) {
  const auto& points = torus_points(1'000'000, state.range(1) != 0);
  recon::set_thread_count(1);
  const PointsAdaptor adaptor{points};
  const nanoflann::KDTreeSingleIndexAdaptorParams params(static_cast<std::size_t>(state.range(0)));
  SplitTimes times;
  for (auto _ : state) {
    sweep_iteration(
        times, [&] { return std::make_unique<const NanoflannTree>(3, adaptor, params); },
        [&](const NanoflannTree& tree) {
          const NanoflannTable table = nanoflann_all_knn(tree, points);
          benchmark::DoNotOptimize(table.indices.data());
          benchmark::ClobberMemory();
        });
  }
  times.report(state);
  set_rate(state, points.size());
}

// ---------------------------------------------------------------------------
// Phase I: k-NN + PCA

void planes_ours(benchmark::State& state) {
  const auto& points = torus_points(static_cast<std::size_t>(state.range(0)), true);
  recon::set_thread_count(static_cast<int>(state.range(1)));
  recon::TangentPlaneOptions options;
  options.k = k;
  options.adapt_k = false;
  for (auto _ : state) {
    const auto planes = recon::estimate_tangent_planes<3>(points, options);
    benchmark::DoNotOptimize(planes.normals.data());
    benchmark::ClobberMemory();
  }
  set_rate(state, points.size());
}

void planes_nanoflann_eigen(benchmark::State& state) {
  const auto& points = torus_points(static_cast<std::size_t>(state.range(0)), true);
  recon::set_thread_count(static_cast<int>(state.range(1)));
  const PointsAdaptor adaptor{points};
  const auto kk = static_cast<std::size_t>(k);
  for (auto _ : state) {
    const NanoflannTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(nanoflann_default_leaf));
    std::vector<Vec3> origins(points.size()), normals(points.size()), eigenvalues(points.size());
    const auto count = static_cast<std::int64_t>(points.size());
#ifdef _OPENMP
#pragma omp parallel
#endif
    {
      std::vector<std::uint32_t> index(kk);
      std::vector<double> distance2(kk);
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 4096)
#endif
      for (std::int64_t s = 0; s < count; ++s) {
        const auto i = static_cast<std::size_t>(s);
        tree.knnSearch(points[i].data(), kk, index.data(), distance2.data());
        Vec3 centroid = Vec3::Zero();
        for (const std::uint32_t j : index) centroid += points[j];
        centroid /= static_cast<double>(kk);
        Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
        for (const std::uint32_t j : index) {
          const Vec3 d = points[j] - centroid;
          covariance += d * d.transpose();
        }
        covariance /= static_cast<double>(kk);
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
        solver.computeDirect(covariance);
        origins[i] = centroid;
        normals[i] = solver.eigenvectors().col(0);
        eigenvalues[i] = solver.eigenvalues();
      }
    }
    benchmark::DoNotOptimize(normals.data());
    benchmark::ClobberMemory();
  }
  set_rate(state, points.size());
}

// ---------------------------------------------------------------------------
// Before timing anything: both trees must find the same neighbours (the same
// distances; indices may differ between equidistant points, which nanoflann
// does not order).

bool same_neighbours(std::size_t n) {
  const auto& points = torus_points(n, false);
  recon::set_thread_count(0);
  const recon::KdTree<3> ours(points, {our_default_leaf});
  const recon::KnnTable expected = ours.all_knn(k);
  const PointsAdaptor adaptor{points};
  const NanoflannTree theirs(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(nanoflann_default_leaf));
  const NanoflannTable got = nanoflann_all_knn(theirs, points);
  for (std::size_t e = 0; e < expected.entries.size(); ++e) {
    const double a = expected.entries[e].distance2, b = got.distances2[e];
    if (std::abs(a - b) > 1e-12 * std::max(a, b)) {
      std::fprintf(stderr, "mismatch at point %zu, neighbour %zu: ours %.17g, nanoflann %.17g\n",
                   e / static_cast<std::size_t>(k), e % static_cast<std::size_t>(k), a, b);
      return false;
    }
  }
  std::fprintf(stderr, "check: all-%d-NN distances of ours and nanoflann agree on %zu points\n", k, n);
  return true;
}

// Settings every benchmark shares. Times are wall clock (threads run in
// parallel); the CPU column is the whole process's CPU time, so CPU / wall
// shows how many cores a run really got on a shared machine. With
// --benchmark_repetitions, "min" is the least disturbed repetition.
double min_of(const std::vector<double>& values) { return *std::min_element(values.begin(), values.end()); }

void common(benchmark::internal::Benchmark* b) {
  b->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);
}

}  // namespace

BENCHMARK(build_ours)
    ->ArgsProduct({{100'000, 1'000'000}, {0}, {our_default_leaf}})
    ->ArgNames({"n", "morton", "leaf"})
    ->Apply(common);
BENCHMARK(build_nanoflann)
    ->ArgsProduct({{100'000, 1'000'000}, {0}, {nanoflann_default_leaf}})
    ->ArgNames({"n", "morton", "leaf"})
    ->Apply(common);

BENCHMARK(knn_ours)
    ->ArgsProduct({{100'000, 1'000'000}, {1, 2}, {0, 1}})
    ->ArgNames({"n", "threads", "morton"})
    ->Apply(common);
BENCHMARK(knn_nanoflann)
    ->ArgsProduct({{100'000, 1'000'000}, {1, 2}, {0, 1}})
    ->ArgNames({"n", "threads", "morton"})
    ->Apply(common);
BENCHMARK(knn_ours_loop)
    ->ArgsProduct({{100'000, 1'000'000}, {1}, {0, 1}})
    ->ArgNames({"n", "threads", "morton"})
    ->Apply(common);

BENCHMARK(planes_ours)->ArgsProduct({{100'000, 1'000'000}, {1, 2}})->ArgNames({"n", "threads"})->Apply(common);
BENCHMARK(planes_nanoflann_eigen)
    ->ArgsProduct({{100'000, 1'000'000}, {1, 2}})
    ->ArgNames({"n", "threads"})
    ->Apply(common);

// Ours on the sampled order (what phase I gets from recon::Shape); nanoflann
// on the Morton order, where its time is search rather than cache misses
// (in sampled order one run takes ~8 s and the sweep would take minutes),
// and at fewer sizes: it is context, not a decision.
BENCHMARK(leaf_sweep_ours)
    ->ArgsProduct({{4, 6, 8, 10, 12, 16, 24, 32}, {0}})
    ->ArgNames({"leaf", "morton"})
    ->Apply(common);
BENCHMARK(leaf_sweep_nanoflann)->ArgsProduct({{4, 8, 10, 16, 32}, {1}})->ArgNames({"leaf", "morton"})->Apply(common);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (!same_neighbours(100'000)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
