// recon_pipeline_bench: time and memory of the phases on large tori.
//
//   recon_pipeline_bench [--points N ...] [--seed S]
//
// For each N (default 100000 and 1000000), samples a torus (fixed seed) and
// runs, with all cores:
//   phase I   estimate_tangent_planes<3>
//   phase II  orient_normals<3> (Riemannian graph, EMST, Prim, vote)
//   full      reconstruct(): phases I to IV
// then phases I and II again with one thread, and once more with all cores
// on the same points sorted along a Morton curve (recon::spatial_order, as
// reconstruct() does before phase I), which shows what the random order of
// the samples costs when the phases are called directly. Prints one markdown table
// row per step: wall time (our own Timer around the call), "cores" (process
// CPU time / wall time: how many cores the step really got, which shows when
// the machine was busy), the time the phase reports itself (its seconds_*
// fields, broken down), peak memory,
// components, mesh size, and how many oriented normals agree with the true
// ones (dot > 0).
//
// Peak memory is VmHWM from /proc/self/status, the peak resident set of the
// whole PROCESS (input cloud and anything still held included). Before each
// step the peak is reset to the current resident size (writing 5 to
// /proc/self/clear_refs, Linux 4.0+), so each row shows the peak reached
// during that step; where the reset is refused, the figure is the peak since
// the program started, and the output says so.

#include "recon/orientation.h"
#include "recon/parallel.h"
#include "recon/reconstruct.h"
#include "recon/shapes.h"
#include "recon/spatial_order.h"
#include "recon/tangent_planes.h"
#include "recon/timer.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <fstream>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace {

using recon::Vec3;

// ---------------------------------------------------------------------------
// Memory

// A "kB" field of /proc/self/status (VmHWM, VmRSS), in MiB.
std::optional<double> status_mib(std::string_view field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.compare(0, field.size(), field) == 0 && line.size() > field.size() && line[field.size()] == ':') {
      std::istringstream value(line.substr(field.size() + 1));
      double kib = 0.0;
      if (value >> kib) return kib / 1024.0;
    }
  }
  return std::nullopt;
}

// Resets VmHWM to the current resident size; false when the kernel refuses.
bool reset_peak_memory() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

// ---------------------------------------------------------------------------
// Report

struct Row {
  std::size_t points = 0;
  int threads = 0;
  std::string step;
  double wall_s = 0.0;      // our Timer around the call
  double cpu_s = 0.0;       // process CPU time during the call (all threads)
  double reported_s = 0.0;  // sum of the result's seconds_* fields
  std::string breakdown;    // those fields, named
  std::optional<double> start_mib, peak_mib;
  std::string components, mesh_vertices, mesh_faces, normals_right;
};

Row new_row(std::size_t points, int threads, std::string step) {
  Row row;
  row.points = points;
  row.threads = threads;
  row.step = std::move(step);
  return row;
}

std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string mib(const std::optional<double>& value) { return value ? fixed(*value, 0) : "n/a"; }

void print_header() {
  std::printf("| points | threads | step | wall s | cores | reported s | breakdown (s) | RSS before MiB |"
              " peak RSS MiB | components | mesh V | mesh F | normals right |\n");
  std::printf("|---:|---:|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|\n");
}

void print_row(const Row& row) {
  std::printf("| %zu | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", row.points, row.threads,
              row.step.c_str(), fixed(row.wall_s, 3).c_str(),
              fixed(row.wall_s > 0.0 ? row.cpu_s / row.wall_s : 0.0, 1).c_str(), fixed(row.reported_s, 3).c_str(),
              row.breakdown.c_str(), mib(row.start_mib).c_str(), mib(row.peak_mib).c_str(), row.components.c_str(),
              row.mesh_vertices.c_str(), row.mesh_faces.c_str(), row.normals_right.c_str());
  std::fflush(stdout);
}

// Fraction of normals pointing the same way as the true ones, and how many
// do not. normals[j] belongs to input point order[j] (identity when empty).
std::string agreement(const std::vector<Vec3>& normals, const std::vector<Vec3>& truth,
                      std::span<const std::uint32_t> order = {}) {
  std::size_t right = 0;
  for (std::size_t j = 0; j < normals.size(); ++j) {
    const std::size_t i = order.empty() ? j : order[j];
    right += normals[j].dot(truth[i]) > 0.0 ? 1u : 0u;
  }
  return fixed(static_cast<double>(right) / static_cast<double>(normals.size()), 6) + " (" +
         std::to_string(normals.size() - right) + " wrong)";
}

// ---------------------------------------------------------------------------
// Steps

// Runs `step` after resetting the peak, filling the memory columns. Memory
// freed by the previous step is handed back to the system first (glibc
// keeps it otherwise), so that "RSS before" is what is really still held.
template <class Step>
void measured(Row& row, Step&& step) {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
  reset_peak_memory();
  row.start_mib = status_mib("VmRSS");
  recon::Timer timer;
  const std::clock_t cpu_start = std::clock();
  step();
  row.wall_s = timer.elapsed();
  row.cpu_s = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  row.peak_mib = status_mib("VmHWM");
}

void phase_one_and_two(const recon::PointCloud& cloud, int threads, const std::string& input = "") {
  recon::set_thread_count(threads);
  const int used = recon::thread_count();

  Row one = new_row(cloud.size(), used, "I tangent planes" + input);
  std::optional<recon::TangentPlanes<3>> planes;
  measured(one, [&] { planes.emplace(recon::estimate_tangent_planes<3>(cloud.positions)); });
  one.reported_s = planes->seconds_tree + planes->seconds_knn_pca + planes->seconds_spacing;
  one.breakdown = "k " + std::to_string(planes->k) + ": tree " + fixed(planes->seconds_tree, 3) + ", knn+pca " +
                  fixed(planes->seconds_knn_pca, 3) + ", spacing " + fixed(planes->seconds_spacing, 3);
  print_row(one);

  Row two = new_row(cloud.size(), used, "II orientation" + input);
  std::optional<recon::OrientedNormals<3>> oriented;
  measured(two, [&] { oriented.emplace(recon::orient_normals<3>(*planes)); });
  const auto& graph = oriented->graph;
  two.reported_s = graph.seconds_tree + graph.seconds_emst + graph.seconds_graph + oriented->seconds_mst;
  two.breakdown = "tree " + fixed(graph.seconds_tree, 3) + ", emst " + fixed(graph.seconds_emst, 3) +
                  ", graph " + fixed(graph.seconds_graph, 3) + ", prim+vote " + fixed(oriented->seconds_mst, 3);
  two.components = std::to_string(oriented->component_count());
  two.normals_right = agreement(oriented->normals, cloud.normals);
  print_row(two);
}

void full_reconstruction(const recon::PointCloud& cloud) {
  recon::set_thread_count(0);
  Row row = new_row(cloud.size(), recon::thread_count(), "full reconstruct()");
  std::optional<recon::Reconstruction> r;
  measured(row, [&] { r.emplace(recon::reconstruct(cloud)); });
  const auto& planes = r->planes;
  const auto& graph = r->oriented->graph;
  const double one = planes.seconds_tree + planes.seconds_knn_pca + planes.seconds_spacing;
  const double two = graph.seconds_tree + graph.seconds_emst + graph.seconds_graph + r->oriented->seconds_mst;
  row.reported_s = one + two + r->seconds_distance_setup + r->contour.seconds;
  row.breakdown = "I " + fixed(one, 3) + ", II " + fixed(two, 3) + ", III setup " +
                  fixed(r->seconds_distance_setup, 3) + ", III+IV marching cubes " + fixed(r->contour.seconds, 3);
  row.components = std::to_string(r->oriented->component_count());
  row.mesh_vertices = std::to_string(r->contour.mesh.vertices.size());
  row.mesh_faces = std::to_string(r->contour.mesh.triangles.size());
  row.normals_right = agreement(r->oriented->normals, cloud.normals, r->order);  // reconstruct() works in spatial order
  print_row(row);
}

[[noreturn]] void usage(int code) {
  std::fprintf(code == 0 ? stdout : stderr,
               "usage: recon_pipeline_bench [--points N ...] [--seed S]\n"
               "  --points N  torus sample size; repeat for several (default: 100000 and 1000000)\n"
               "  --seed S    sampling seed (default 1)\n");
  std::exit(code);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes;
  std::uint64_t seed = 1;
  for (int a = 1; a < argc; ++a) {
    const std::string_view arg = argv[a];
    if (arg == "--help" || arg == "-h") usage(0);
    if ((arg == "--points" || arg == "--seed") && a + 1 < argc) {
      char* end = nullptr;
      const unsigned long long value = std::strtoull(argv[++a], &end, 10);
      if (*end != '\0' || value == 0) usage(2);
      if (arg == "--points")
        sizes.push_back(static_cast<std::size_t>(value));
      else
        seed = value;
      continue;
    }
    usage(2);
  }
  if (sizes.empty()) sizes = {100'000, 1'000'000};

  const bool reset_works = reset_peak_memory();
  recon::set_thread_count(0);
  std::printf("torus (R = 1, r = 0.35), seed %llu, %d threads available; peak RSS %s\n\n",
              static_cast<unsigned long long>(seed), recon::thread_count(),
              reset_works ? "is reset before each step (peak during the step, whole process)"
                          : "could NOT be reset: it is the peak since the program started");
  print_header();
  try {
    for (const std::size_t n : sizes) {
      const recon::PointCloud cloud = recon::make_torus()->sample(n, seed);
      phase_one_and_two(cloud, 0);
      full_reconstruction(cloud);
      phase_one_and_two(cloud, 1);
      recon::PointCloud sorted;
      const std::vector<std::uint32_t> order = recon::spatial_order(cloud.positions);
      sorted.positions = recon::permuted<Vec3>(cloud.positions, order);
      sorted.normals = recon::permuted<Vec3>(cloud.normals, order);
      phase_one_and_two(sorted, 0, ", Morton-sorted input");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "recon_pipeline_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
