#pragma once
// Pieces the subcommands share (commands.cpp, lab_command.cpp): reading the input,
// checking the outputs, the options of phases I and II, the report.

#include "run_reports.h"
#include "summary.h"

#include "recon/core/point_cloud.h"
#include "recon/core/resource_usage.h"
#include "recon/io/point_io.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/report/report.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace recon::cli {

// Options every command that reads a cloud shares.
struct InputOptions {
  std::filesystem::path path;
  std::string format;
  std::string columns;        ///< --columns x,y,z,_,r,g,b (text without a header)
  bool skip_invalid = false;  ///< --skip-invalid
  bool no_colors = false;     ///< --no-colors: drop the input's colours
};
void add_input(CLI::App& app, InputOptions& in);
/// The reader's options the command line asks for (--format, --columns, --skip-invalid).
io::ReadPointsOptions read_options(const InputOptions& in);
/// Reads the cloud, says so, and records it in the statistics; `notes`,
/// when given, receives what the reader said. `opened`, when it holds the
/// input already opened (a stream, which can be read only once: see
/// open_if_stream), is read instead of the path, and emptied (its memory
/// goes back).
PointCloud read_input(const InputOptions& in, Summary& summary, io::ReadNotes* notes = nullptr,
                      std::optional<io::PointSource>* opened = nullptr);
/// The input opened (read whole) when it is a stream (a pipe, a FIFO, `-`),
/// for a command that must look at it before reading it; empty for a file,
/// which is opened where it is read.
[[nodiscard]] std::optional<io::PointSource> open_if_stream(const InputOptions& in);

/// Checks made before any work, so that a run that cannot write its results
/// fails at once: outputs must not be the input or each other, and their
/// folders must exist. Empty paths are skipped.
void check_outputs(const std::filesystem::path& input, const std::vector<std::filesystem::path>& outputs);

/// --report FILE.html.
void add_report_option(CLI::App& app, std::filesystem::path& report);

/// The two ways to simplify, as reconstruct and simplify both offer them: a
/// target (`target_flag`: a count, ratio or percentage of the triangles of
/// `subject`) and a bound (`bound_flag`: how far, in `measure`, a vertex of
/// `reference` may end from the result).
void add_simplify_options(CLI::App& app, const std::string& target_flag, std::string& target,
                          const std::string& subject, const std::string& bound_flag, std::optional<double>& bound,
                          const std::string& reference, const std::string& measure);

/// --method refined|hoppe92: `refined` says what the default does in the
/// command, `phases` which of the paper's phases hoppe92 runs exactly.
void add_method_option(CLI::App& app, std::string& method, const std::string& refined, const std::string& phases);

/// The options of a command that writes a mesh: --ascii, --normals (whose
/// help starts with where the normals come from: `source`) and --stats.
void add_mesh_output_options(CLI::App& app, bool& ascii, bool& normals, const std::string& source,
                             std::filesystem::path& stats);

// Options of phases I and II, and the memory limit.
struct PhaseOptions {
  int k = TangentPlaneOptions{}.k;
  std::optional<double> rho;
  CLI::Option* k_option = nullptr;  // to tell a given k from the default
  std::size_t max_memory = 0;       // bytes; 0: default_memory_limit()
};
void add_phase_options(CLI::App& app, PhaseOptions& p);
TangentPlaneOptions phase_1_options(const PhaseOptions& p);

/// `recon reconstruct`'s options, for 3D runs (commands.cpp) and 2D ones
/// (curves.cpp) alike.
struct ReconstructCommandOptions {
  InputOptions in;
  PhaseOptions phases;
  std::filesystem::path output, stats, report;
  std::optional<double> delta, cell;
  std::optional<int> resolution;
  bool ascii = false, use_normals = false, keep_fragments = false;
  bool embedded = false;  ///< --embedded: phase V puts back the moves that make triangles cross
  bool normals = false;   ///< --normals: vertex normals in the mesh (always in a .glb)
  std::string method = "refined";
  double tile_size = 0.0;           ///< --tile-size: work in tiles (tiled.h)
  std::filesystem::path tmpdir;     ///< --tmpdir: where the tiles go (default: the output's folder)
  std::string simplify;             ///< --simplify: a triangle count, a ratio below 1, or a percentage (empty: off)
  std::optional<double> max_error;  ///< --max-error: multiple of rho
};

}  // namespace recon::cli
