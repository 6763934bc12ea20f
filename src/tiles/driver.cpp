// A tiled run (tiles.h), the five steps in a row: plan (step1_plan.cpp),
// orient each tile (step2_orient.cpp), reconcile the signs
// (step3_reconcile.cpp), contour each tile (step4_contour.cpp), stitch
// (step5_stitch.cpp); the per-tile steps two tiles at a time when memory
// allows.
#include "recon/core/memory_budget.h"
#include "recon/core/parallel.h"
#include "recon/core/timer.h"
#include "recon/reconstruct_parts.h"
#include "recon/tiles/tiles.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace recon {

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
  for_each_tile(
      tiles, lanes, [&](std::size_t t) { run.orientations[t] = orient_tile(work_dir, t); }, counted("orienting"));
  report("reconciling", 0, 1);
  run.reconciliation = reconcile_tiles(work_dir);
  run.contours.resize(tiles);
  for_each_tile(
      tiles, lanes, [&](std::size_t t) { run.contours[t] = contour_tile(work_dir, t); }, counted("contouring"));
  report("stitching", 0, 1);
  run.mesh = stitch_tiles(work_dir, output);
  run.seconds = timer.elapsed();
  return run;
}

}  // namespace recon
