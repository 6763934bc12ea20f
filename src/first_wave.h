#pragma once
// Phase III beside phase II (reconstruct() uses this; not part of the API).
//
// The textbook order is: orient every normal (phase II), then evaluate f at
// the lattice corners (phase III). Prim's algorithm is serial, so while it
// runs, another thread evaluates f at the corners of the walk's first wave
// (every cube holding a sample: most of the corners the walk will need),
// with the UNORIENTED PCA normals. Orientation only turns normals round, and
// f turns with them exactly: (p - o).(-n) is -((p - o).n) in floating point,
// and the foot point and the tests of definedness are unchanged. So the
// value with the PCA normal, negated where the orientation flipped that
// plane, is the value phase III gives, and the mesh is the same bit for bit
// as in the textbook order (reconstruct_test compares them).

#include "recon/phase4_contour/detail/seed_wave.h"
#include "recon/reconstruct.h"

#include <atomic>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace recon::detail {

/// The first wave's corners and their values, filled from any number of
/// threads at once.
class FirstWave {
 public:
  /// The origin tree (into r.origin_tree), the lattice and the first wave's
  /// cubes and corners: a few tenths of the work.
  void prepare(Reconstruction& r, double cell, const SignedDistanceOptions& options);
  /// Evaluates corners until none is left unclaimed; from any number of
  /// threads at once, after prepare().
  void drain();
  /// Leaves the corners no thread has claimed yet unevaluated (on failure).
  void abandon();
  /// Turns the values to the oriented normals' (negated where the plane they
  /// came from was flipped); then the wave is the walk's.
  void orient(std::span<const std::uint8_t> flipped);
  [[nodiscard]] bool ready() const { return wave_.has_value(); }
  [[nodiscard]] SeedWave take_wave() { return std::move(*wave_); }

 private:
  static constexpr std::size_t chunk = 256;
  SignedDistance<3> unoriented_;
  std::optional<SeedWave> wave_;      // holds f's values at its corners as they are evaluated
  std::vector<std::uint32_t> plane_;  // the plane each value came from
  std::atomic<std::size_t> next_{0};  // the first corner not yet claimed
};

/// Phase II (orient_normals over `graph`, into r.oriented) with the first
/// wave evaluated beside it: on a thread of its own while Prim runs, then on
/// every thread. With one thread, the same work one after the other.
/// `seconds_after` receives the time spent on the wave after phase II ended;
/// r.seconds_distance_beside the time beside it. Rethrows what either threw.
void orient_with_first_wave(Reconstruction& r, RiemannianGraph<3>&& graph, double cell,
                            const OrientationOptions& options, const SignedDistanceOptions& distance, FirstWave& wave,
                            double& seconds_after);

}  // namespace recon::detail
