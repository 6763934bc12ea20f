#include "first_wave.h"

#include "recon/core/detail/parallel_for.h"
#include "recon/core/parallel.h"
#include "recon/core/timer.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <future>
#include <limits>
#include <thread>

namespace recon::detail {

void FirstWave::prepare(Reconstruction& r, double cell, const SignedDistanceOptions& options) {
  r.origin_tree = r.planes.point_tree.refit(r.planes.origins);
  unoriented_ = make_signed_distance<3>(r.planes, r.planes.normals, r.origin_tree, options);
  wave_.emplace(r.points(), cell);
  plane_.resize(wave_->corner_count());
}

void FirstWave::drain() {
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

void FirstWave::abandon() { next_.store(std::numeric_limits<std::size_t>::max() / 2, std::memory_order_relaxed); }

void FirstWave::orient(std::span<const std::uint8_t> flipped) {
  parallel_for(plane_.size(), [&](std::size_t c) {
    const double v = wave_->value(c);
    if (flipped[plane_[c]] && !std::isnan(v)) wave_->set_value(c, -v);
  });
  plane_ = {};
}

namespace {
// The helper thread's work: prepare (reporting success or failure through
// `prepared`), then drain; a failure while draining lands in `failure`.
void prepare_and_drain(Reconstruction& r, double cell, const SignedDistanceOptions& distance, FirstWave& wave,
                       std::promise<void>& prepared, std::exception_ptr& failure) {
  Timer beside;
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
}
}  // namespace

void orient_with_first_wave(Reconstruction& r, RiemannianGraph<3>&& graph, double cell,
                            const OrientationOptions& options, const SignedDistanceOptions& distance, FirstWave& wave,
                            double& seconds_after) {
  const int threads = thread_count();
  if (threads <= 1) {  // the textbook order
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
  std::thread helper([&] { prepare_and_drain(r, cell, distance, wave, prepared, failure); });
  try {
    r.oriented = orient_normals<3>(r.planes, std::move(graph), options);  // Prim, meanwhile
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
  wave.drain();  // the corners still unclaimed, on the other threads too
  helper.join();
  if (failure) std::rethrow_exception(failure);
  wave.orient(r.oriented->flipped);
  seconds_after = timer.lap();
}

}  // namespace recon::detail
