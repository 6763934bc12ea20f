#pragma once
// What `recon reconstruct` and `recon normals` say about a finished run, and
// the same figures as --stats JSON, phase by phase: one place for the
// program and the Python package (python/), so that a mesh's `stats` in
// Python holds what --stats writes.

#include "summary.h"

#include "recon/reconstruct.h"
#include "recon/report.h"
#include "recon/resource_usage.h"

#include <filesystem>

namespace recon::cli {

/// Phase I's line and statistics.
void report_phase_1(const TangentPlanes<3>& planes, std::size_t points, Summary& summary);
/// Phase II's line and statistics.
void report_phase_2(const OrientedNormals<3>& oriented, Summary& summary);

/// Every phase of a finished reconstruction of `points` points made with
/// `options` (lines and statistics), then its mesh. Without `keep_all` (no
/// report to draw), everything but the mesh is released before the mesh's
/// topology is measured, the run's last large allocation.
void report_reconstruction(Reconstruction& r, const ReconstructionOptions& options, std::size_t points, bool keep_all,
                           Summary& summary);

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
