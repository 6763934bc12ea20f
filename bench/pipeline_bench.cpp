// recon_pipeline_bench: the whole reconstruction on generated surfaces,
// phase by phase: time, peak memory, accuracy against the true surface.
//
//   recon_pipeline_bench [--shape torus|terrain] [--points N ...] [--seed S]
//                        [--one-thread] [--refine]
//
// For each N (default 100000 and 1000000), samples the shape (fixed seed),
// then runs reconstruct() with all cores (and with one, given --one-thread),
// timing each phase from the result's own seconds_* fields and taking each
// phase's peak memory: the resident size of the whole process, sampled
// while the phase runs (recon/core/resource_usage.h's StepPeaks), so a phase's
// figure includes everything still held from the phases before it.
//
// Accuracy is the Chamfer distance between the mesh and the true surface,
// in % of the bounding-box diagonal:
//   - mesh -> true: the mean over the mesh's area of the exact distance to
//     the shape (each triangle split in four, the distance taken at each
//     quarter's centroid);
//   - true -> mesh: the mean over 200k fresh samples of the shape (another
//     seed) of the distance to the mesh (the nearest of the triangles around
//     the 8 mesh vertices nearest to the sample);
//   - Chamfer: the mean of the two.
// "normals right" is the fraction of oriented normals on the same side as the
// true ones.
//
// --refine reruns the largest N <= 1M with the cell halved twice (rho, rho/2,
// rho/4): contouring should cost about 4x per halving (the surface), not 8x
// (the volume).

#include "recon/core/parallel.h"
#include "recon/core/resource_usage.h"
#include "recon/core/shapes.h"
#include "recon/core/timer.h"
#include "recon/reconstruct.h"
#include "recon/structures/kdtree.h"
#include "recon/structures/mesh.h"

#include <Eigen/Geometry>  // cross products

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {

using recon::Vec3;

std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

struct Accuracy {
  double mesh_to_true = 0.0, true_to_mesh = 0.0;  // mean distances
  [[nodiscard]] double chamfer() const { return 0.5 * (mesh_to_true + true_to_mesh); }
};

Accuracy accuracy(const recon::Shape& shape, const recon::Mesh& mesh, std::uint64_t seed) {
  Accuracy a;
  double area = 0.0, weighted = 0.0;
  for (const auto& tri : mesh.triangles) {
    const Vec3 &p = mesh.vertices[tri[0]], &q = mesh.vertices[tri[1]], &r = mesh.vertices[tri[2]];
    const double quarter = 0.125 * (q - p).cross(r - p).norm();
    const Vec3 pq = (p + q) / 2, qr = (q + r) / 2, rp = (r + p) / 2;
    const std::array<Vec3, 4> centroids = {(p + pq + rp) / 3, (pq + q + qr) / 3, (rp + qr + r) / 3, (pq + qr + rp) / 3};
    for (const Vec3& c : centroids) {
      area += quarter;
      weighted += quarter * shape.distance(c);
    }
  }
  a.mesh_to_true = area > 0.0 ? weighted / area : 0.0;

  std::vector<std::vector<std::uint32_t>> around(mesh.vertices.size());
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    for (const auto v : mesh.triangles[t]) around[v].push_back(t);
  const recon::KdTree<3> tree(mesh.vertices);
  const recon::PointCloud truth = shape.sample(200'000, seed + 1000);
  double sum = 0.0;
  for (const Vec3& x : truth.positions) {
    double best = std::numeric_limits<double>::infinity();
    for (const recon::Neighbor& nb : tree.knn(x, 8))
      for (const auto t : around[nb.index]) {
        const auto& tri = mesh.triangles[t];
        best = std::min(best, recon::point_triangle_distance(x, mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                                             mesh.vertices[tri[2]]));
      }
    sum += best;
  }
  a.true_to_mesh = sum / static_cast<double>(truth.positions.size());
  return a;
}

double fraction_right(const recon::Reconstruction& r, const std::vector<Vec3>& truth) {
  const auto normals = r.normals();
  std::size_t right = 0;
  for (std::size_t j = 0; j < normals.size(); ++j) right += normals[j].dot(truth[r.order[j]]) > 0.0 ? 1u : 0u;
  return static_cast<double>(right) / static_cast<double>(normals.size());
}

struct Run {
  double wall = 0.0;
  recon::StepPeaks memory;  // per phase
  std::optional<recon::Reconstruction> r;
};

Run run(const recon::PointCloud& cloud, int threads, std::optional<double> cell = std::nullopt) {
  recon::set_thread_count(threads);
#if defined(__GLIBC__)
  malloc_trim(0);  // hand back what earlier runs freed, so peaks are this run's
#endif
  Run out;
  recon::ReconstructionOptions options;
  options.cell = cell;
  options.on_phase = [&](const char* next) { out.memory.start(next); };
  recon::Timer timer;
  out.r.emplace(recon::reconstruct(cloud, options));
  out.wall = timer.elapsed();
  out.memory.finish();
  return out;
}

void print_header() {
  std::printf(
      "| points | threads | wall s | s per 1M points | I: tree / knn+pca / spacing | II: emst / graph / "
      "prim+vote | III: f after II (+ beside II's Prim) | IV: walk | peak MiB I / II / III / IV | mesh V / F | closed, "
      "chi, components "
      "| "
      "normals right | mesh->true / true->mesh / Chamfer, %% of diagonal |\n");
  std::printf("|---:|---:|---:|---:|---|---|---:|---:|---|---|---|---:|---|\n");
}

void print_run(const recon::Shape& shape, const recon::PointCloud& cloud, const Run& run, int threads,
               std::uint64_t seed) {
  const recon::Reconstruction& r = *run.r;
  const auto& p = r.planes;
  const auto& g = r.oriented->graph;
  const auto& c = r.contour;
  const recon::MeshTopology t = recon::analyze_topology(c.mesh);
  const Accuracy a = accuracy(shape, c.mesh, seed);
  const double diagonal = recon::bounding_box<3>(cloud.positions).diagonal();
  auto peak = [&](std::string_view phase) {
    for (const auto& [step, mib] : run.memory.peaks())
      if (step == phase) return fixed(mib, 0);
    return std::string("n/a");
  };
  std::printf(
      "| %zu | %d | %s | %s | %s / %s / %s | %s / %s / %s | %s (+ %s) | %s | %s / %s / %s / %s | %zu / %zu | "
      "%s, %ld, %zu | %s | %s / %s / %s |\n",
      cloud.size(), threads, fixed(run.wall, 3).c_str(),
      fixed(run.wall / (static_cast<double>(cloud.size()) / 1e6), 3).c_str(), fixed(p.seconds_tree, 3).c_str(),
      fixed(p.seconds_knn_pca, 3).c_str(), fixed(p.seconds_spacing, 3).c_str(), fixed(g.seconds_emst, 3).c_str(),
      fixed(g.seconds_graph, 3).c_str(), fixed(r.oriented->seconds_mst, 3).c_str(),
      fixed(r.seconds_distance_setup + c.seconds_field, 3).c_str(), fixed(r.seconds_distance_beside, 3).c_str(),
      fixed(c.seconds - c.seconds_field, 3).c_str(), peak("tangent planes").c_str(), peak("orientation").c_str(),
      peak("signed distance").c_str(), peak("contouring").c_str(), c.mesh.vertices.size(), c.mesh.triangles.size(),
      t.boundary_edges == 0 && t.watertight() ? "closed" : "open", t.euler_characteristic, t.components,
      fixed(fraction_right(r, cloud.normals), 6).c_str(), fixed(100.0 * a.mesh_to_true / diagonal, 4).c_str(),
      fixed(100.0 * a.true_to_mesh / diagonal, 4).c_str(), fixed(100.0 * a.chamfer() / diagonal, 4).c_str());
  std::fflush(stdout);
}

[[noreturn]] void usage(int code) {
  std::fprintf(code == 0 ? stdout : stderr,
               "usage: recon_pipeline_bench [--shape torus|terrain] [--points N ...] [--seed S] [--one-thread] "
               "[--refine]\n"
               "  --points N    sample size; repeat for several (default: 100000 and 1000000)\n"
               "  --seed S      sampling seed (default 1)\n"
               "  --one-thread  also run each size with one thread\n"
               "  --refine      also contour the largest size <= 1M at cells rho, rho/2, rho/4\n");
  std::exit(code);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes;
  std::uint64_t seed = 1;
  std::string shape_name = "torus";
  bool one_thread = false, refine = false;
  for (int a = 1; a < argc; ++a) {
    const std::string_view arg = argv[a];
    if (arg == "--help" || arg == "-h") usage(0);
    if (arg == "--one-thread") {
      one_thread = true;
    } else if (arg == "--refine") {
      refine = true;
    } else if (arg == "--shape" && a + 1 < argc) {
      shape_name = argv[++a];
    } else if ((arg == "--points" || arg == "--seed") && a + 1 < argc) {
      char* end = nullptr;
      const unsigned long long value = std::strtoull(argv[++a], &end, 10);
      if (*end != '\0' || value == 0) usage(2);
      if (arg == "--points")
        sizes.push_back(static_cast<std::size_t>(value));
      else
        seed = value;
    } else {
      usage(2);
    }
  }
  if (sizes.empty()) sizes = {100'000, 1'000'000};

  try {
    const auto shape = recon::make_shape(shape_name);
    const bool measurable = recon::resident_bytes().has_value();
    recon::set_thread_count(0);
    const int all = recon::thread_count();
    std::printf("%s, seed %llu, %d threads available; peak memory %s\n\n", shape_name.c_str(),
                static_cast<unsigned long long>(seed), all,
                measurable ? "sampled as each phase runs (whole process: includes what earlier phases hold)"
                           : "unknown here (no /proc)");
    print_header();
    for (const std::size_t n : sizes) {
      const recon::PointCloud cloud = shape->sample(n, seed);
      print_run(*shape, cloud, run(cloud, 0), all, seed);
      if (one_thread) print_run(*shape, cloud, run(cloud, 1), 1, seed);
    }
    if (refine) {
      std::size_t n = 0;
      for (const std::size_t s : sizes)
        if (s <= 1'000'000) n = std::max(n, s);
      if (n == 0) n = sizes.front();
      const recon::PointCloud cloud = shape->sample(n, seed);
      // Phases III and IV alone, as one walk that evaluates every corner
      // itself, over one reconstruction's planes and normals: inside
      // reconstruct() most corners of the default lattice are evaluated
      // beside phase II, which would hide part of the first row's cost.
      const Run base = run(cloud, 0);
      const recon::Reconstruction& r = *base.r;
      const recon::SignedDistance<3> f = recon::make_signed_distance<3>(r.planes, r.normals(), r.origin_tree);
      std::printf(
          "\nLattice refinement, %zu points, all threads (phases III and IV as one walk, no overlap with "
          "phase II):\n\n",
          n);
      std::printf(
          "| cell | visited cubes | corners | III: f s | IV: walk s | III+IV s | ratio to previous | mesh F |\n");
      std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
      double previous = 0.0;
      for (int level = 0; level < 3; ++level) {
        recon::MarchingCubesOptions mc;
        mc.cell = r.planes.rho / (1 << level);
        const recon::MarchingCubesResult c = recon::marching_cubes(std::cref(f), r.points(), mc);
        const double both = c.seconds;
        std::printf("| rho/%d = %s | %zu | %zu | %s | %s | %s | %s | %zu |\n", 1 << level, fixed(c.cell, 5).c_str(),
                    c.visited_cubes, c.evaluated_corners, fixed(c.seconds_field, 3).c_str(),
                    fixed(c.seconds - c.seconds_field, 3).c_str(), fixed(both, 3).c_str(),
                    level == 0 ? "" : fixed(both / previous, 2).c_str(), c.mesh.triangles.size());
        previous = both;
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "recon_pipeline_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
