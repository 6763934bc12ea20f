#pragma once
// `recon reconstruct` on 2D points: curves instead of a surface. The
// command's options are parsed in commands.cpp, which hands a 2D run over
// here.

#include "command_parts.h"

#include <filesystem>
#include <optional>
#include <string>

namespace recon::cli {

/// True when the run should make curves: the input holds 2D points (two
/// columns, or Hoppe's .pts with a constant x; see io/curve_io.h), or the
/// output is a curve-only format (.svg, .txt), which reads a flat 3D cloud
/// as 2D.
/// `opened`: the input already opened (a stream), or null.
[[nodiscard]] bool wants_curves(const std::filesystem::path& input, const std::string& format,
                                const std::filesystem::path& output, const io::PointSource* opened);

/// Reads the points, runs reconstruct_curve, reports each phase and writes
/// the curves (.svg, .obj or .txt) and the --stats JSON. Refuses the
/// options that have no meaning in 2D (--report, --use-normals).
/// `opened`: as read_input's (command_parts.h).
void reconstruct_curves(const ReconstructCommandOptions& o, bool quiet, std::optional<io::PointSource>& opened);

}  // namespace recon::cli
