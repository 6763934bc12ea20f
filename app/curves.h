#pragma once
// `recon reconstruct` on 2D points: curves instead of a surface. The
// command's options are parsed in commands.cpp, which hands a 2D run over
// here.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

namespace recon::cli {

struct CurveRun {
  std::filesystem::path input, output, stats;
  std::string format;            ///< --format, or empty
  std::optional<int> k;          ///< when given (otherwise the curve default, raised for noisy data)
  std::optional<double> rho, delta, cell;
  std::optional<int> resolution;
  std::size_t max_memory = 0;    ///< bytes; 0: default_memory_limit()
  bool use_normals = false;      ///< refused: 2D inputs carry no normals
  bool quiet = false;
};

/// True when the run should make curves: the input holds 2D points (two
/// columns, or Hoppe's .pts with a constant x; see io/curve_io.h), or the
/// output is a curve-only format (.svg, .txt), which reads a flat 3D cloud
/// as 2D.
[[nodiscard]] bool wants_curves(const std::filesystem::path& input, const std::string& format,
                                const std::filesystem::path& output);

/// Reads the points, runs reconstruct_curve, reports each phase and writes
/// the curves (.svg, .obj or .txt) and the --stats JSON.
void reconstruct_curves(const CurveRun& run);

}  // namespace recon::cli
