// The shared part of the `recon` program's end-to-end tests (tests/cli/*_test.cpp):
// each test runs the built binary in a fresh temporary folder, with stdout and
// stderr captured, and checks what a user sees (messages, exit status) and what
// lands on disk (files read back with the library's readers, topology, --stats
// figures).
//
// The program runs with the folder as its working directory, so it is
// given bare file names and its messages name them the same way; its
// captured output goes beside the folder, so a listing of the folder shows
// exactly what the program left there.

#pragma once

#include "io/io_test_helpers.h"
#include "mesh_compare.h"
#include "test_data.h"

#include "recon/core/shapes.h"
#include "recon/core/version.h"
#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"
#include "recon/structures/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

// The helpers live in a named namespace (not an anonymous one) so that the
// fixture is one type in every file of tests/cli/, as GoogleTest requires of a
// suite spread over files.
namespace recon::cli_testing {

namespace fs = std::filesystem;
using io::testing::read_bytes;
using io::testing::TempFolder;
using io::testing::write_file;

// Seconds a single run may take before `timeout` stops it; the largest run
// here (30,000 points) takes about 15 s in a Debug build.
inline constexpr int run_time_limit = 120;

/// What one run of the program produced.
struct RunResult {
  std::string command;
  int exit_code = -1;  ///< -1 when the shell could not report one
  std::string out;
  std::string err;
};

inline std::string describe(const RunResult& run) {
  std::ostringstream text;
  text << "\n  command: " << run.command << "\n  exit status: " << run.exit_code;
  if (run.exit_code == 124) text << " (timed out after " << run_time_limit << " s)";
  if (run.exit_code > 128) text << " (killed by signal " << run.exit_code - 128 << ")";
  text << "\n  stdout: [" << run.out << "]\n  stderr: [" << run.err << "]";
  return text.str();
}

/// One argument for /bin/sh, single-quoted.
inline std::string shell_quoted(std::string_view argument) {
  std::string quoted = "'";
  for (const char c : argument) {
    if (c == '\'')
      quoted += "'\\''";
    else
      quoted += c;
  }
  return quoted + "'";
}

inline std::size_t count_lines(std::string_view text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

/// The lines of `text` that start with `prefix`.
inline std::vector<std::string> lines_starting_with(const std::string& text, std::string_view prefix) {
  std::vector<std::string> found;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.starts_with(prefix)) found.push_back(line);
  return found;
}

/// A run that succeeded quietly on stderr: exit status 0, nothing on stderr.
inline ::testing::AssertionResult succeeded(const RunResult& run) {
  if (run.exit_code == 0 && run.err.empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "expected success with an empty stderr" << describe(run);
}

/// A run refused the way the program promises: exit status 1 (2 would be an
/// internal error, above 128 a crash), exactly one line on stderr starting
/// with "recon: error:", containing every one of `parts`.
inline ::testing::AssertionResult refused(const RunResult& run, std::initializer_list<std::string_view> parts = {}) {
  if (run.exit_code != 1) return ::testing::AssertionFailure() << "expected exit status 1" << describe(run);
  if (!run.err.starts_with("recon: error: ") || count_lines(run.err) != 1 || !run.err.ends_with('\n'))
    return ::testing::AssertionFailure() << "expected one line on stderr starting with 'recon: error: '"
                                         << describe(run);
  for (const std::string_view part : parts)
    if (run.err.find(part) == std::string::npos)
      return ::testing::AssertionFailure() << "the message lacks '" << part << "'" << describe(run);
  return ::testing::AssertionSuccess();
}

/// The number after `"key": ` in the object `"section": {...}` of a --stats
/// file (the whole file when section is empty). The program writes one
/// level of objects holding numbers, so this is enough; it is no JSON parser.
inline std::optional<double> stat(const std::string& json, std::string_view section, std::string_view key) {
  std::string_view scope = json;
  if (!section.empty()) {
    const std::string opening = "\"" + std::string(section) + "\": {";
    const std::size_t begin = json.find(opening);
    if (begin == std::string::npos) return std::nullopt;
    const std::size_t end = json.find('}', begin);
    if (end == std::string::npos) return std::nullopt;
    scope = scope.substr(begin + opening.size(), end - begin - opening.size());
  }
  const std::string label = "\"" + std::string(key) + "\": ";
  const std::size_t at = scope.find(label);
  if (at == std::string_view::npos) return std::nullopt;
  const std::string_view number = scope.substr(at + label.size());
  double value = 0.0;
  const auto [end, error] = std::from_chars(number.data(), number.data() + number.size(), value);
  if (error != std::errc{} || end == number.data()) return std::nullopt;
  return value;
}

/// Like stat(), as a whole count; -1 when absent, so comparisons fail visibly.
inline long stat_count(const std::string& json, std::string_view section, std::string_view key) {
  const std::optional<double> value = stat(json, section, key);
  return value ? static_cast<long>(*value) : -1;
}

// n points uniform in the cube [-1, 1]^3.
inline std::vector<Vec3> random_cube_points(int n, std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) points.emplace_back(unit(random), unit(random), unit(random));
  return points;
}

inline std::string xyz_text(const std::vector<Vec3>& points) {
  std::ostringstream text;
  text.precision(17);
  for (const Vec3& p : points) text << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  return text.str();
}

/// Checks a mesh that should be a closed torus: watertight, one piece,
/// Euler characteristic 0, facing outward.
inline void expect_closed_torus(const Mesh& mesh) {
  const MeshTopology t = analyze_topology(mesh);
  EXPECT_TRUE(t.watertight()) << t.boundary_edges << " boundary, " << t.non_manifold_edges << " non-manifold, "
                              << t.inconsistent_edges << " inconsistently oriented edges";
  EXPECT_EQ(t.components, 1U);
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_GT(t.signed_volume, 0.0);
  EXPECT_EQ(t.degenerate_triangles, 0U);
}

/// No run of 20 digits or more in `text`.
inline bool has_no_long_number(const std::string& text) {
  std::size_t digits = 0;
  for (const char c : text) {
    digits = std::isdigit(static_cast<unsigned char>(c)) ? digits + 1 : 0;
    if (digits >= 20) return false;
  }
  return true;
}

/// An option refused while the command line is read: exit status 2, one
/// line naming the option and `part`, and no number of 20 digits or more
/// (CLI11's own checks printed the largest double, 310 digits, as a bound).
inline ::testing::AssertionResult option_refused(const RunResult& run, std::string_view option, std::string_view part) {
  if (run.exit_code != 2) return ::testing::AssertionFailure() << "expected exit status 2" << describe(run);
  if (count_lines(run.err) != 1 || !run.err.starts_with("recon: error: " + std::string(option) + ": "))
    return ::testing::AssertionFailure() << "expected one line naming " << option << describe(run);
  if (run.err.find(part) == std::string::npos)
    return ::testing::AssertionFailure() << "the message lacks '" << part << "'" << describe(run);
  if (!has_no_long_number(run.err))
    return ::testing::AssertionFailure() << "a number of 20 digits or more" << describe(run);
  return ::testing::AssertionSuccess();
}

// A sphere's samples, red above the equator and blue below, as a binary PLY
// with "uchar red green blue" (made from `recon generate`'s cloud).
inline void add_red_above_blue_below(const fs::path& from, const fs::path& to) {
  PointCloud cloud = io::read_points(from);
  for (const Vec3& p : cloud.positions) cloud.colors.push_back(p.z() > 0.0 ? Color{255, 0, 0} : Color{0, 0, 255});
  io::write_points(to, cloud);
}

/// "x y" lines of n points stratified around a circle (one random point in
/// each of n equal arcs, seeded).
inline std::string circle_xy_text(const Vec2& centre, double radius, int n, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::ostringstream text;
  text.precision(17);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * 3.141592653589793 * (i + unit(random)) / n;
    text << centre.x() + radius * std::cos(a) << ' ' << centre.y() + radius * std::sin(a) << '\n';
  }
  return text.str();
}

/// The curves of an OBJ file written by recon: its "v" vertices (x, y) and
/// one index list per "l" line (0-based; a closed curve ends where it began).
struct ObjCurves {
  std::vector<Vec2> vertices;
  std::vector<std::vector<std::size_t>> lines;
};

inline ObjCurves read_obj_curves(const fs::path& path) {
  ObjCurves obj;
  std::istringstream text(read_bytes(path));
  for (std::string line; std::getline(text, line);) {
    std::istringstream fields(line);
    std::string keyword;
    fields >> keyword;
    if (keyword == "v") {
      double x = 0.0, y = 0.0, z = 1.0;
      fields >> x >> y >> z;
      EXPECT_EQ(z, 0.0) << line;
      obj.vertices.emplace_back(x, y);
    } else if (keyword == "l") {
      std::vector<std::size_t>& indices = obj.lines.emplace_back();
      for (std::size_t i = 0; fields >> i;) indices.push_back(i - 1);
    }
  }
  return obj;
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override { fs::create_directory(work_folder()); }

  [[nodiscard]] fs::path work_folder() const { return temp_ / "run"; }
  /// A file in the folder the program runs in.
  [[nodiscard]] fs::path at(std::string_view name) const { return work_folder() / name; }

  /// Runs `recon args...` in the work folder, under `timeout`.
  [[nodiscard]] RunResult recon(const std::vector<std::string>& args) const {
    RunResult run;
    run.command = "recon";
    std::string command = "cd " + shell_quoted(work_folder().string()) + " && exec timeout -k 10 " +
                          std::to_string(run_time_limit) + " " + shell_quoted(RECON_CLI_PATH);
#ifdef RECON_TRAP_FP
    command += " --trap-fp";  // the program traps what the library would (see fp_traps_test.cpp)
#endif
    for (const std::string& argument : args) {
      command += " " + shell_quoted(argument);
      run.command += " " + argument;
    }
    const fs::path out = temp_ / "stdout.txt";
    const fs::path err = temp_ / "stderr.txt";
    command += " </dev/null >" + shell_quoted(out.string()) + " 2>" + shell_quoted(err.string());
    const int status = std::system(command.c_str());
    if (status != -1 && WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
    if (fs::exists(out)) run.out = read_bytes(out);
    if (fs::exists(err)) run.err = read_bytes(err);
    return run;
  }

  /// Starts the program in the background, sends SIGINT after `delay`
  /// seconds, and returns the exit status the shell reports for it (130 when
  /// SIGINT ended it) and, in `out`, the milliseconds it took to end after
  /// the signal.
  [[nodiscard]] RunResult interrupted(const std::vector<std::string>& args, double delay) const {
    RunResult run;
    run.command = "recon";
    std::string command = "cd " + shell_quoted(work_folder().string()) + " && { " + shell_quoted(RECON_CLI_PATH);
    for (const std::string& argument : args) {
      command += " " + shell_quoted(argument);
      run.command += " " + argument;
    }
    const fs::path err = temp_ / "stderr.txt";
    command += " </dev/null >/dev/null 2>" + shell_quoted(err.string()) + " & pid=$!; sleep " + std::to_string(delay) +
               "; start=$(date +%s%N); kill -INT $pid; wait $pid; status=$?; end=$(date +%s%N); " +
               "echo $(( (end - start) / 1000000 )) > elapsed.txt; exit $status; }";
    const int status = std::system(command.c_str());
    if (status != -1 && WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
    if (fs::exists(err)) run.err = read_bytes(err);
    run.out = read_bytes(at("elapsed.txt"));
    fs::remove(at("elapsed.txt"));
    return run;
  }

  /// `recon --quiet generate shape -n points -o name`, which must succeed.
  void generate(const std::string& shape, int points, const std::string& name) const {
    const RunResult run = recon({"--quiet", "generate", shape, "-n", std::to_string(points), "-o", name});
    ASSERT_TRUE(succeeded(run));
    ASSERT_TRUE(run.out.empty()) << describe(run);
    ASSERT_TRUE(fs::is_regular_file(at(name)));
  }

  /// Names in the work folder, sorted.
  [[nodiscard]] std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(work_folder())) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  /// The names in the work folder starting with "." (the writers' temporaries).
  [[nodiscard]] std::vector<std::string> hidden_entries() const {
    std::vector<std::string> hidden;
    for (const std::string& name : entries())
      if (name.starts_with('.')) hidden.push_back(name);
    return hidden;
  }

 private:
  TempFolder temp_;
};

}  // namespace recon::cli_testing
