#pragma once
// What `recon reconstruct` and `recon normals` say about a finished run, and
// the same figures as --stats JSON, phase by phase: one place for the
// program and the Python package (python/), so that a mesh's `stats` in
// Python holds what --stats writes.

#include "summary.h"

#include "recon/core/resource_usage.h"
#include "recon/estimate_normals.h"
#include "recon/io/point_io.h"  // ReadNotes
#include "recon/reconstruct.h"
#include "recon/report/report.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>

namespace recon::cli {

// Each phase's account (lines and statistics), for 2D and 3D alike. Pure:
// Summary::add prints and records them.

/// The input as read ("input"): `cloud` read from `file` in `seconds`, with
/// the reader's notes (the program and the web page, web/webapp/, say it alike).
[[nodiscard]] StepReport input_report(const std::string& file, const PointCloud& cloud, const io::ReadNotes& notes,
                                      double seconds);
/// Phase I of `points` points ("tangent_planes"; D = 2 and 3).
template <int D>
[[nodiscard]] StepReport phase_1_report(const TangentPlanes<D>& planes, std::size_t points);
/// The refined method's second-order fits ("tangent_planes", "quadrics").
[[nodiscard]] StepReport quadrics_report(const LocalQuadrics& quadrics);
/// Phase II ("orientation"; D = 2 and 3).
template <int D>
[[nodiscard]] StepReport phase_2_report(const OrientedNormals<D>& oriented);
/// Phase III's figures, from the 3D or the 2D walk.
struct SignedDistanceFigures {
  double delta = 0.0;
  bool delta_given = false;
  std::size_t evaluated = 0, undefined = 0;  ///< lattice corners
  double seconds = 0.0;
  double seconds_beside = 0.0;  ///< beside phase II (3D, several threads)
};
/// Phase III ("signed_distance").
[[nodiscard]] StepReport phase_3_report(const SignedDistanceFigures& figures);
/// Phase VI ("simplification"): the vertices' bound in rho's units when
/// `rho` is given (reconstruct), else in the mesh's own (recon simplify).
[[nodiscard]] StepReport simplification_report(const Simplification& s, std::optional<double> rho);
/// A lattice's cubes (or squares) along each axis, as a JSON array.
[[nodiscard]] Json lattice_size_json(std::span<const std::int32_t> size);

/// Phases I and II of a run of `method` on `points` points: phase I's
/// planes, the method (in the statistics), the second-order fits when there
/// are any, and phase II's orientation (null: skipped, the input's normals used).
void report_phases_1_2(const TangentPlanes<3>& planes, Method method, const std::optional<LocalQuadrics>& quadrics,
                       const OrientedNormals<3>* oriented, std::size_t points, Summary& summary);

/// A finished estimate_normals() on `points` points (`recon normals`, the
/// Python package's estimate_normals): its phases I and II, as above.
void report_normal_estimation(const NormalEstimation& estimated, std::size_t points, Summary& summary);

/// Every phase of a finished reconstruction of `points` points made with
/// `options` (lines and statistics), then its mesh. Without `keep_all` (no
/// report to draw), everything but the mesh is released before the mesh's
/// topology is measured, the run's last large allocation.
void report_reconstruction(Reconstruction& r, const ReconstructionOptions& options, std::size_t points, bool keep_all,
                           Summary& summary);

/// The run's last line ("wrote OUTPUT (T); total T") and its "output",
/// "threads" and "seconds_total" statistics.
void finish_run(Summary& summary, const std::filesystem::path& output, double seconds_write, double seconds_total);

/// Peak memory per step for --stats (resource_usage.h): ends the last step
/// and writes "memory": {"peak_mib": {step: MiB, ...}, "peak_mib_total": the largest}.
void report_memory(StepPeaks& memory, Summary& summary);

/// The report options of a run from `source`: its title and the --stats
/// JSON as it will be written, so the page and the file agree.
ReportOptions run_report_options(const std::filesystem::path& source, Summary& summary);
/// Writes the report of a finished run and says so.
void write_run_report(const std::filesystem::path& path, const ReportInput& input, const std::filesystem::path& source,
                      Summary& summary);

}  // namespace recon::cli
