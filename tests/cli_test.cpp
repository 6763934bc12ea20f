// End-to-end tests of the `recon` program: each test runs the built binary
// in a fresh temporary folder, with stdout and stderr captured, and checks
// what a user sees (messages, exit status) and what lands on disk (files read
// back with the library's readers, topology, --stats figures).
//
// The program runs with the folder as its working directory, so it is
// given bare file names and its messages name them the same way; its
// captured output goes beside the folder, so a listing of the folder shows
// exactly what the program left there.

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

namespace recon {
namespace {

namespace fs = std::filesystem;
using io::testing::read_bytes;
using io::testing::TempFolder;
using io::testing::write_file;

// Seconds a single run may take before `timeout` stops it; the largest run
// here (30,000 points) takes about 15 s in a Debug build.
constexpr int run_time_limit = 120;

/// What one run of the program produced.
struct RunResult {
  std::string command;
  int exit_code = -1;  ///< -1 when the shell could not report one
  std::string out;
  std::string err;
};

std::string describe(const RunResult& run) {
  std::ostringstream text;
  text << "\n  command: " << run.command << "\n  exit status: " << run.exit_code;
  if (run.exit_code == 124) text << " (timed out after " << run_time_limit << " s)";
  if (run.exit_code > 128) text << " (killed by signal " << run.exit_code - 128 << ")";
  text << "\n  stdout: [" << run.out << "]\n  stderr: [" << run.err << "]";
  return text.str();
}

/// One argument for /bin/sh, single-quoted.
std::string shell_quoted(std::string_view argument) {
  std::string quoted = "'";
  for (const char c : argument) {
    if (c == '\'')
      quoted += "'\\''";
    else
      quoted += c;
  }
  return quoted + "'";
}

std::size_t count_lines(std::string_view text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

/// The lines of `text` that start with `prefix`.
std::vector<std::string> lines_starting_with(const std::string& text, std::string_view prefix) {
  std::vector<std::string> found;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.starts_with(prefix)) found.push_back(line);
  return found;
}

/// A run that succeeded quietly on stderr: exit status 0, nothing on stderr.
::testing::AssertionResult succeeded(const RunResult& run) {
  if (run.exit_code == 0 && run.err.empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "expected success with an empty stderr" << describe(run);
}

/// A run refused the way the program promises: exit status 1 (2 would be an
/// internal error, above 128 a crash), exactly one line on stderr starting
/// with "recon: error:", containing every one of `parts`.
::testing::AssertionResult refused(const RunResult& run, std::initializer_list<std::string_view> parts = {}) {
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
std::optional<double> stat(const std::string& json, std::string_view section, std::string_view key) {
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
long stat_count(const std::string& json, std::string_view section, std::string_view key) {
  const std::optional<double> value = stat(json, section, key);
  return value ? static_cast<long>(*value) : -1;
}

// n points uniform in the cube [-1, 1]^3.
std::vector<Vec3> random_cube_points(int n, std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) points.emplace_back(unit(random), unit(random), unit(random));
  return points;
}

std::string xyz_text(const std::vector<Vec3>& points) {
  std::ostringstream text;
  text.precision(17);
  for (const Vec3& p : points) text << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  return text.str();
}

/// Checks a mesh that should be a closed torus: watertight, one piece,
/// Euler characteristic 0, facing outward.
void expect_closed_torus(const Mesh& mesh) {
  const MeshTopology t = analyze_topology(mesh);
  EXPECT_TRUE(t.watertight()) << t.boundary_edges << " boundary, " << t.non_manifold_edges << " non-manifold, "
                              << t.inconsistent_edges << " inconsistently oriented edges";
  EXPECT_EQ(t.components, 1U);
  EXPECT_EQ(t.euler_characteristic, 0);
  EXPECT_GT(t.signed_volume, 0.0);
  EXPECT_EQ(t.degenerate_triangles, 0U);
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

// A suite name per theme, so that --gtest_filter can pick one.
using CliHelp = CliTest;
using CliErrors = CliTest;
using CliAtomicOutput = CliTest;
using CliNormals = CliTest;
using CliReconstruct = CliTest;
using CliOutput = CliTest;
using CliLattice = CliTest;
using CliInfo = CliTest;
using CliTextColumns = CliTest;
using CliDeterminism = CliTest;
using CliRealData = CliTest;
using CliReport = CliTest;
using CliTiles = CliTest;

// ---------------------------------------------------------------- help

TEST_F(CliHelp, ProgramListsSubcommandsAndGlobalOptions) {
  const RunResult run = recon({"--help"});
  ASSERT_TRUE(succeeded(run));
  for (const char* part : {"info", "normals", "reconstruct", "generate", "lab", "--quiet", "--threads"})
    EXPECT_NE(run.out.find(part), std::string::npos) << "help lacks " << part << describe(run);
  EXPECT_TRUE(entries().empty());
}

TEST_F(CliHelp, EachSubcommandListsItsOptions) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> expected = {
      {"info", {"input", "--format", "--k"}},
      {"normals", {"input", "--format", "--output", "--k", "--rho", "--ascii", "--stats"}},
      {"reconstruct",
       {"input", "--format", "--output", "--k", "--rho", "--delta", "--cell", "--resolution", "--use-normals",
        "--ascii", "--stats", "--normals", ".glb"}},
      {"generate",
       {"shape", "--output", "--points", "--seed", "--noise", "--with-normals", "--truth", "--truth-points", "sphere",
        "torus", "two", "part", "handle", "conics"}},
      {"lab",
       {"input", "--format", "--k", "--stats", "--report", "--max-complete", "--max-brute-force", "--max-list-heap"}},
  };
  for (const auto& [command, options] : expected) {
    const RunResult run = recon({command, "--help"});
    ASSERT_TRUE(succeeded(run));
    EXPECT_NE(run.out.find("Usage:"), std::string::npos) << describe(run);
    for (const std::string& option : options)
      EXPECT_NE(run.out.find(option), std::string::npos) << command << " --help lacks " << option << describe(run);
  }
  EXPECT_TRUE(entries().empty());
}

// ---------------------------------------------------------------- version

// The program's version is the library's (recon/core/version.h; how it is made is
// tested in python/tests/test_packaging.py), and every --stats file and
// report page says it.
TEST_F(CliHelp, VersionIsTheLibrarysInEveryStatsFileAndReport) {
  const RunResult run = recon({"--version"});
  ASSERT_TRUE(succeeded(run)) << describe(run);
  EXPECT_EQ(run.out, "recon " + std::string(version()) + "\n");
  EXPECT_TRUE(entries().empty());
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 1000, "s.xyz"));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "s.xyz", "-o", "m.ply", "--stats", "r.json"})));
  ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "s.xyz", "-o", "n.ply", "--stats", "n.json"})));
  ASSERT_TRUE(succeeded(recon({"--quiet", "lab", "s.xyz", "--stats", "l.json", "--report", "l.html"})));
  const std::string field = "\"version\": \"" + std::string(version()) + "\"";
  for (const char* stats : {"r.json", "n.json", "l.json"})
    EXPECT_TRUE(read_bytes(at(stats)).starts_with("{\n  " + field)) << stats << ": " << read_bytes(at(stats));
  const std::string page = read_bytes(at("l.html"));
  EXPECT_NE(page.find("\"title\":\"s.xyz\",\"version\":\"" + std::string(version()) + "\""), std::string::npos);
}

// ---------------------------------------------------------------- errors

TEST_F(CliErrors, MissingInputIsNamed) {
  for (const char* command : {"info", "normals", "reconstruct"}) {
    std::vector<std::string> args = {command, "missing.xyz"};
    if (std::string_view(command) != "info") args.insert(args.end(), {"-o", "out.ply"});
    EXPECT_TRUE(refused(recon(args), {"missing.xyz: cannot open"})) << command;
  }
  EXPECT_TRUE(entries().empty());
}

TEST_F(CliErrors, FolderAsInputIsRefused) {
  fs::create_directory(at("folder.xyz"));
  EXPECT_TRUE(refused(recon({"reconstruct", "folder.xyz", "-o", "out.ply"}), {"folder.xyz: cannot open"}));
  EXPECT_TRUE(refused(recon({"info", "folder.xyz"}), {"folder.xyz: cannot open"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"folder.xyz"});
}

TEST_F(CliErrors, UnknownInputExtensionPointsToFormatOption) {
  std::vector<Vec3> points;
  for (int i = 0; i < 40; ++i) points.emplace_back(std::cos(i), std::sin(i), 0.1 * i);
  write_file(at("cloud.dat"), xyz_text(points));
  EXPECT_TRUE(refused(recon({"reconstruct", "cloud.dat", "-o", "out.ply"}), {"cloud.dat", ".dat", "--format"}));
  EXPECT_FALSE(fs::exists(at("out.ply")));

  // The option the message points to does read the file.
  const RunResult named = recon({"info", "cloud.dat", "--format", "xyz"});
  ASSERT_TRUE(succeeded(named));
  EXPECT_NE(named.out.find("points        40\n"), std::string::npos) << describe(named);
  EXPECT_EQ(entries(), std::vector<std::string>{"cloud.dat"});
}

TEST_F(CliErrors, UnknownFormatNameIsRefused) {
  write_file(at("cloud.dat"), "0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_TRUE(refused(recon({"reconstruct", "cloud.dat", "--format", "bogus", "-o", "out.ply"}), {"'bogus'"}));
  EXPECT_TRUE(refused(recon({"info", "cloud.dat", "--format", "bogus"}), {"'bogus'"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"cloud.dat"});
}

TEST_F(CliErrors, MalformedTextNamesFileAndLine) {
  write_file(at("bad.xyz"), "0 0 0\n1 0 0\n1 2 abc\n0 1 0\n");
  const RunResult run = recon({"reconstruct", "bad.xyz", "-o", "out.ply"});
  EXPECT_TRUE(refused(run, {"abc"}));
  EXPECT_TRUE(run.err.starts_with("recon: error: bad.xyz:3:")) << describe(run);
  EXPECT_EQ(entries(), std::vector<std::string>{"bad.xyz"});
}

TEST_F(CliErrors, BadFilesOfEveryKindAreOneLineAndExitOne) {
  // One of each kind of bad file the readers refuse (the messages themselves
  // are checked in tests/io/bad_files_test.cpp): the program says it in one
  // line naming the file and the place, and exits with status 1.
  const std::vector<std::pair<std::string, std::string>> files = {
      {"empty.ply", ""},
      {"header.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n"},
      {"long.xyz", "0 0 0\n" + std::string((std::size_t{1} << 20) + 1, '1') + "\n"},
      {"binary.obj", std::string("v 0 0 0\n\x7f"
                                 "ELF\x02\x01\x01\0\0\0\0",
                                 19)},
      {"huge.off", "OFF\n3 0 0\n0 0 0\n1e16 0 0\n0 1 0\n"},
      {"type.pcd", "FIELDS x y z\nSIZE 1 1 1\nTYPE U U U\nPOINTS 1\nDATA ascii\n1 2 300\n"},
  };
  const std::vector<std::string> where = {
      "empty.ply: the file is empty", "header.ply:7: ", "long.xyz:2: ", "binary.obj:2: ",
      "huge.off: 1 point has",        "type.pcd:6: "};
  for (std::size_t i = 0; i < files.size(); ++i) {
    write_file(at(files[i].first), files[i].second);
    const RunResult run = recon({"reconstruct", files[i].first, "-o", "out.ply"});
    EXPECT_TRUE(refused(run, {where[i]})) << files[i].first;
    EXPECT_TRUE(run.err.starts_with("recon: error: " + where[i])) << describe(run);
  }
  EXPECT_FALSE(fs::exists(at("out.ply")));
}

// recon maps its input; when another program shortens the file meanwhile,
// reading the pages cut off raises SIGBUS. That must end like any other
// bad input: one line naming the file, exit status 1, no output left.
TEST_F(CliErrors, AnInputShortenedWhileReadIsNamed) {
  {
    std::ofstream big(at("big.xyz"));
    std::string block;
    for (int i = 0; i < 1000; ++i) block += std::to_string(i) + " " + std::to_string(i % 37) + " 0.5\n";
    for (int i = 0; i < 10000; ++i) big << block;  // about 100 MB: a read of a tenth of a second or more
  }
  // Start recon, wait until its mapping of the file appears, cut the file
  // to one page.
  const fs::path err = at("stderr.txt");
  const std::string command = "cd " + shell_quoted(work_folder().string()) + " && { " + shell_quoted(RECON_CLI_PATH) +
                              " info big.xyz </dev/null >/dev/null 2>stderr.txt & pid=$!; " +
                              "while [ -e /proc/$pid ] && ! grep -q big.xyz /proc/$pid/maps 2>/dev/null; do :; done; " +
                              "truncate -s 4096 big.xyz; wait $pid; exit $?; }";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(status != -1 && WIFEXITED(status)) << status;
  const std::string message = read_bytes(err);
  fs::remove(err);
  EXPECT_EQ(WEXITSTATUS(status), 1) << message;
  EXPECT_EQ(message,
            "recon: error: big.xyz: the file was shortened, or could not be read, while recon was reading it\n");
  EXPECT_EQ(entries(), (std::vector<std::string>{"big.xyz"}));
}

TEST_F(CliErrors, TruncatedBinaryPlyNamesTheByte) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 200, "whole.ply"));
  const std::string whole = read_bytes(at("whole.ply"));
  ASSERT_GT(whole.size(), 1000U);
  write_file(at("cut.ply"), whole.substr(0, 1000));
  const RunResult run = recon({"reconstruct", "cut.ply", "-o", "out.ply"});
  EXPECT_TRUE(refused(run, {"byte "}));
  EXPECT_TRUE(run.err.starts_with("recon: error: cut.ply: byte ")) << describe(run);
  EXPECT_EQ(entries(), (std::vector<std::string>{"cut.ply", "whole.ply"}));
}

TEST_F(CliErrors, NanCoordinateNamesTheLine) {
  // Line 5, after a comment and a blank line, which count as lines too.
  write_file(at("nan.xyz"), "# a comment\n0 0 0\n\n1 0 0\n1 nan 2\n0 1 0\n");
  const RunResult run = recon({"reconstruct", "nan.xyz", "-o", "out.ply"});
  EXPECT_TRUE(refused(run));
  EXPECT_TRUE(
      run.err.starts_with("recon: error: nan.xyz: 1 point has a coordinate that is not finite or beyond "
                          "+-1e+15; the first at line 5 (y = nan)"))
      << describe(run);
  EXPECT_EQ(entries(), std::vector<std::string>{"nan.xyz"});
}

TEST_F(CliErrors, FewerPointsThanTheNeighbourhoodSaysToLowerK) {
  std::mt19937_64 random(7);
  write_file(at("ten.xyz"), xyz_text(random_cube_points(10, random)));
  EXPECT_TRUE(refused(recon({"reconstruct", "ten.xyz", "-o", "out.ply"}), {"10", "--k"}));
  EXPECT_TRUE(refused(recon({"normals", "ten.xyz", "-o", "out.ply"}), {"10", "--k"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"ten.xyz"});
}

TEST_F(CliErrors, IdenticalPointsAreRefused) {
  write_file(at("same.xyz"), xyz_text(std::vector<Vec3>(50, Vec3(1.5, -2.0, 3.25))));
  EXPECT_TRUE(refused(recon({"reconstruct", "same.xyz", "-o", "out.ply"}), {"distinct"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "same.xyz", "--k", "3", "-o", "out.ply"}), {"distinct"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"same.xyz"});
}

TEST_F(CliErrors, CollinearPointsAreRefused) {
  std::vector<Vec3> points;
  for (int i = 0; i < 60; ++i) points.push_back(Vec3(0.5, -1.0, 2.0) + 0.037 * i * Vec3(1.0, 2.0, -0.5));
  write_file(at("line.xyz"), xyz_text(points));
  EXPECT_TRUE(refused(recon({"reconstruct", "line.xyz", "-o", "out.ply"}), {"line"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"line.xyz"});
}

TEST_F(CliErrors, MaxMemoryRefusesWithTheEstimateAndTheOption) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 20000, "s.ply"));
  // Past the limit, reconstruct works in tiles (tiles.h) as long as one
  // fits; with 2 MB none does.
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--max-memory", "2M"}),
                      {"working in tiles, the densest", "2 MB allowed", "raise --max-memory"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--method", "hoppe92", "--max-memory", "2M"}),
                      {"working in tiles, the densest", "2 MB allowed"}));
  // 370 bytes a point at k = 20 (normals do not work in tiles).
  EXPECT_TRUE(refused(recon({"normals", "s.ply", "-o", "n.ply", "--max-memory", "2MB"}), {"7.4 MB", "lower --k"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--max-memory", "1G", "--cell", "0.0001"}),
                      {"a lattice cell of 0.0001", "use a larger --cell"}));
  const RunResult bad_unit = recon({"reconstruct", "s.ply", "-o", "m.ply", "--max-memory", "3Q"});
  EXPECT_EQ(bad_unit.exit_code, 2) << describe(bad_unit);
  EXPECT_NE(bad_unit.err.find("--max-memory: unknown size unit in '3Q'"), std::string::npos) << describe(bad_unit);
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
  EXPECT_TRUE(succeeded(recon({"--quiet", "reconstruct", "s.ply", "-o", "m.ply", "--max-memory", "1.5GiB"})));
}

TEST_F(CliErrors, OutputEqualToInputIsRefusedAndTheInputKept) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 300, "s.ply"));
  const std::string before = read_bytes(at("s.ply"));
  for (const char* command : {"reconstruct", "normals"}) {
    for (const char* output : {"s.ply", "./s.ply"}) {
      EXPECT_TRUE(refused(recon({command, "s.ply", "-o", output}), {"s.ply"})) << command << " -o " << output;
      EXPECT_EQ(read_bytes(at("s.ply")), before) << command << " -o " << output << " changed the input";
    }
  }
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

TEST_F(CliErrors, OutputIntoMissingFolderIsRefused) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 300, "s.ply"));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "nowhere/out.ply"}), {"nowhere"}));
  EXPECT_TRUE(refused(recon({"normals", "s.ply", "-o", "nowhere/out.ply"}), {"nowhere"}));
  EXPECT_TRUE(refused(recon({"generate", "sphere", "-n", "100", "-o", "nowhere/out.ply"}), {"nowhere"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

TEST_F(CliErrors, UnknownOutputExtensionIsRefusedBeforeAnyWork) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 300, "s.ply"));
  // Nothing on stdout: the input was not even read (its "read" line is
  // the first thing a run prints).
  for (const char* output : {"mesh.xyz", "mesh.foo"}) {
    const RunResult run = recon({"reconstruct", "s.ply", "-o", output});
    EXPECT_TRUE(refused(run, {output}));
    EXPECT_TRUE(run.out.empty()) << "work was done before the refusal" << describe(run);
  }
  const RunResult normals = recon({"normals", "s.ply", "-o", "cloud.foo"});
  EXPECT_TRUE(refused(normals, {"cloud.foo"}));
  EXPECT_TRUE(normals.out.empty()) << "work was done before the refusal" << describe(normals);
  EXPECT_TRUE(refused(recon({"generate", "sphere", "-n", "100", "-o", "cloud.foo"}), {"cloud.foo"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

// ---------------------------------------------------------------- never half-written

TEST_F(CliAtomicOutput, FailedRunKeepsThePreviousOutput) {
  const std::string previous = "a previous mesh, to be kept\n";
  write_file(at("mesh.ply"), previous);
  write_file(at("bad.xyz"), "0 0 0\n1 0 0\n1 2 abc\n");
  std::vector<Vec3> points;
  for (int i = 0; i < 60; ++i) points.emplace_back(0.1 * i, 0.2 * i, 0.3 * i);
  write_file(at("line.xyz"), xyz_text(points));

  // Refused while reading, and refused by phase I after reading.
  for (const char* input : {"bad.xyz", "line.xyz"}) {
    EXPECT_TRUE(refused(recon({"reconstruct", input, "-o", "mesh.ply", "--stats", "stats.json"}))) << input;
    EXPECT_EQ(read_bytes(at("mesh.ply")), previous) << input;
  }
  EXPECT_EQ(entries(), (std::vector<std::string>{"bad.xyz", "line.xyz", "mesh.ply"}));
}

TEST_F(CliAtomicOutput, FailedWriteLeavesNoTemporaryFile) {
  // The output name is taken by a folder: the mesh is computed and written to
  // a temporary file, and the final rename fails.
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 300, "s.ply"));
  fs::create_directory(at("mesh.ply"));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "mesh.ply"}), {"mesh.ply"}));
  EXPECT_TRUE(fs::is_directory(at("mesh.ply")));
  EXPECT_TRUE(fs::is_empty(at("mesh.ply")));
  EXPECT_EQ(entries(), (std::vector<std::string>{"mesh.ply", "s.ply"}));
}

TEST_F(CliAtomicOutput, SuccessReplacesTheOutputAndLeavesNoTemporaryFile) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 1000, "s.xyz"));
  const std::string previous = "a previous mesh, to be replaced\n";
  write_file(at("mesh.ply"), previous);
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "s.xyz", "-o", "mesh.ply", "--stats", "stats.json"})));
  ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "s.xyz", "-o", "oriented.ply", "--stats", "normals.json"})));
  EXPECT_NE(read_bytes(at("mesh.ply")), previous);
  EXPECT_GT(io::read_mesh(at("mesh.ply")).triangles.size(), 100U);
  EXPECT_EQ(entries(), (std::vector<std::string>{"mesh.ply", "normals.json", "oriented.ply", "s.xyz", "stats.json"}));
  EXPECT_TRUE(hidden_entries().empty());
}

TEST_F(CliAtomicOutput, InterruptStopsAtOnceAndKeepsThePreviousOutput) {
  // 400k points take seconds to reconstruct: Ctrl-C arrives mid-run.
  ASSERT_NO_FATAL_FAILURE(generate("torus", 400000, "t.ply"));
  const std::string previous = "a previous mesh, to be kept\n";
  write_file(at("mesh.ply"), previous);
  for (const double delay : {0.3, 1.0}) {
    const RunResult run = interrupted({"reconstruct", "t.ply", "-o", "mesh.ply", "--stats", "stats.json"}, delay);
    EXPECT_EQ(run.exit_code, 128 + SIGINT) << "ended by SIGINT, as the shell expects" << describe(run);
    EXPECT_NE(run.err.find("recon: interrupted"), std::string::npos) << describe(run);
    EXPECT_LT(std::stoi(run.out), 1000) << "milliseconds from SIGINT to the end";
    EXPECT_EQ(read_bytes(at("mesh.ply")), previous);
    EXPECT_EQ(entries(), (std::vector<std::string>{"mesh.ply", "t.ply"}));
  }
}

// ---------------------------------------------------------------- normals

TEST_F(CliNormals, SphereNormalsAreUnitAndOutward) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 5000, "s.xyz"));
  const RunResult run = recon({"normals", "s.xyz", "-o", "n.ply"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_TRUE(read_bytes(at("n.ply")).starts_with("ply\nformat binary_little_endian 1.0\n"));

  const PointCloud input = io::read_points(at("s.xyz"));
  const PointCloud cloud = io::read_points(at("n.ply"));
  ASSERT_EQ(input.size(), 5000U);
  ASSERT_EQ(cloud.size(), 5000U);
  ASSERT_TRUE(cloud.has_normals());
  ASSERT_EQ(cloud.normals.size(), cloud.size());
  std::size_t not_unit = 0, inward = 0, far_from_radial = 0, moved = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.positions[i];
    const Vec3& n = cloud.normals[i];
    if (std::abs(n.norm() - 1.0) > 1e-9) ++not_unit;
    if (!(n.dot(p) > 0.0)) ++inward;
    // The sphere is centred at the origin: the true normal is p / |p|.
    if (!(n.dot(p.normalized()) > 0.95)) ++far_from_radial;
    if (p != input.positions[i]) ++moved;
  }
  EXPECT_EQ(not_unit, 0U);
  EXPECT_EQ(inward, 0U);
  EXPECT_EQ(far_from_radial, 0U);
  EXPECT_EQ(moved, 0U) << "the positions should be written back unchanged, in order";
}

TEST_F(CliNormals, AsciiFlagWritesAsciiPly) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 2000, "s.xyz"));
  ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "s.xyz", "-o", "n.ply", "--ascii"})));
  const std::string content = read_bytes(at("n.ply"));
  EXPECT_TRUE(content.starts_with("ply\nformat ascii 1.0\n")) << content.substr(0, 100);
  const PointCloud cloud = io::read_points(at("n.ply"));
  EXPECT_EQ(cloud.size(), 2000U);
  EXPECT_EQ(cloud.normals.size(), 2000U);
}

// A sphere's samples, red above the equator and blue below, as a binary PLY
// with "uchar red green blue" (made from `recon generate`'s cloud).
void add_red_above_blue_below(const fs::path& from, const fs::path& to) {
  PointCloud cloud = io::read_points(from);
  for (const Vec3& p : cloud.positions) cloud.colors.push_back(p.z() > 0.0 ? Color{255, 0, 0} : Color{0, 0, 255});
  io::write_points(to, cloud);
}

TEST_F(CliNormals, KeepsTheInputsColoursUnlessNoColors) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 3000, "s.xyz"));
  add_red_above_blue_below(at("s.xyz"), at("c.ply"));
  const RunResult run = recon({"normals", "c.ply", "-o", "n.ply"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_EQ(lines_starting_with(run.out, "read      c.ply: 3000 points with colours").size(), 1U) << run.out;
  const PointCloud input = io::read_points(at("c.ply"));
  const PointCloud cloud = io::read_points(at("n.ply"));
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_TRUE(cloud.positions == input.positions);
  EXPECT_TRUE(cloud.colors == input.colors) << "the colours are written back in the input's order";
  // As text: x y z nx ny nz r g b.
  ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "c.ply", "-o", "n.xyz"})));
  const std::string text = read_bytes(at("n.xyz"));
  const std::string first = text.substr(0, text.find('\n'));
  EXPECT_EQ(std::count(first.begin(), first.end(), ' '), 8) << first;
  EXPECT_TRUE(first.ends_with(input.colors[0] == Color{255, 0, 0} ? " 255 0 0" : " 0 0 255")) << first;
  ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "c.ply", "-o", "plain.ply", "--no-colors"})));
  EXPECT_FALSE(io::read_points(at("plain.ply")).has_colors());
}

// ---------------------------------------------------------------- reconstruct

TEST_F(CliReconstruct, TorusIsClosedGenusOneAndStatsMatchTheFile) {
  ASSERT_NO_FATAL_FAILURE(generate("torus", 20000, "t.ply"));
  const RunResult run = recon({"reconstruct", "t.ply", "-o", "m.ply", "--stats", "st.json"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_NE(run.out.find("1 component,"), std::string::npos) << describe(run);
  EXPECT_TRUE(read_bytes(at("m.ply")).starts_with("ply\nformat binary_little_endian 1.0\n"));

  const Mesh mesh = io::read_mesh(at("m.ply"));
  expect_closed_torus(mesh);
  const MeshTopology t = analyze_topology(mesh);
  EXPECT_EQ(t.vertices, mesh.vertices.size()) << "the file holds vertices no triangle uses";

  const std::string json = read_bytes(at("st.json"));
  EXPECT_EQ(stat_count(json, "input", "points"), 20000);
  EXPECT_EQ(stat_count(json, "mesh", "vertices"), static_cast<long>(mesh.vertices.size())) << json;
  EXPECT_EQ(stat_count(json, "mesh", "faces"), static_cast<long>(mesh.triangles.size())) << json;
  EXPECT_EQ(stat_count(json, "mesh", "components"), 1) << json;
  EXPECT_EQ(stat_count(json, "mesh", "boundary_loops"), 0) << json;
  EXPECT_EQ(stat_count(json, "mesh", "euler_characteristic"), 0) << json;
  EXPECT_EQ(stat_count(json, "orientation", "components"), 1) << json;

  // Every phase's time: present, positive, and within the total.
  const std::optional<double> total = stat(json, "", "seconds_total");
  ASSERT_TRUE(total.has_value()) << json;
  const std::vector<std::pair<const char*, const char*>> timings = {
      {"input", "seconds"},                // reading
      {"tangent_planes", "seconds_tree"},  // phase I
      {"tangent_planes", "seconds_knn_pca"},
      {"tangent_planes", "seconds_spacing"},
      {"orientation", "seconds_emst"},  // phase II
      {"orientation", "seconds_graph"},
      {"orientation", "seconds_mst"},
      {"contouring", "seconds"},  // phases III and IV together
      {"output", "seconds"},      // writing
  };
  for (const auto& [section, key] : timings) {
    const std::optional<double> seconds = stat(json, section, key);
    ASSERT_TRUE(seconds.has_value()) << section << "." << key << " missing in\n" << json;
    EXPECT_GT(*seconds, 0.0) << section << "." << key;
    EXPECT_LE(*seconds, *total) << section << "." << key;
  }
  // Every step's peak memory (the process's, where /proc allows it): at
  // least what the program itself occupies, and none above the overall peak.
  if (const std::optional<double> peak = stat(json, "memory", "peak_mib_total")) {
    for (const char* step : {"read", "tangent planes", "orientation", "signed distance", "contouring", "write"}) {
      const std::optional<double> mib = stat(json, "peak_mib", step);
      ASSERT_TRUE(mib.has_value()) << step << " missing in\n" << json;
      EXPECT_GT(*mib, 1.0) << step;
      EXPECT_LE(*mib, *peak) << step;
    }
  }
  EXPECT_EQ(entries(), (std::vector<std::string>{"m.ply", "st.json", "t.ply"}));
}

// A mesh file as written, with the counts its --stats file gives.
struct WrittenMesh {
  std::string bytes;
  long faces = -1;
  long vertices = -1;
};

class CliMeshFormat : public CliTest {
 protected:
  /// Reconstructs a 5,000-point torus into `name` and returns the file's
  /// bytes with the face and vertex counts of its --stats.
  WrittenMesh reconstruct_torus(const std::string& name) {
    WrittenMesh written;
    generate("torus", 5000, "t.ply");
    const RunResult run = recon({"--quiet", "reconstruct", "t.ply", "-o", name, "--stats", "st.json"});
    EXPECT_TRUE(succeeded(run));
    EXPECT_TRUE(run.out.empty()) << describe(run);
    if (!fs::exists(at(name))) {
      ADD_FAILURE() << name << " was not written";
      return written;
    }
    written.bytes = read_bytes(at(name));
    const std::string json = read_bytes(at("st.json"));
    written.faces = stat_count(json, "mesh", "faces");
    written.vertices = stat_count(json, "mesh", "vertices");
    EXPECT_GT(written.faces, 1000) << json;
    EXPECT_EQ(stat_count(json, "mesh", "components"), 1) << json;
    EXPECT_EQ(stat_count(json, "mesh", "boundary_loops"), 0) << json;
    EXPECT_EQ(entries(), (std::vector<std::string>{name, "st.json", "t.ply"}));
    return written;
  }
};

TEST_F(CliMeshFormat, Obj) {
  const WrittenMesh written = reconstruct_torus("m.obj");
  EXPECT_EQ(static_cast<long>(lines_starting_with(written.bytes, "v ").size()), written.vertices);
  EXPECT_EQ(static_cast<long>(lines_starting_with(written.bytes, "f ").size()), written.faces);
  const Mesh mesh = io::read_mesh(at("m.obj"));
  EXPECT_EQ(static_cast<long>(mesh.triangles.size()), written.faces);
  expect_closed_torus(mesh);
}

TEST_F(CliMeshFormat, Off) {
  const WrittenMesh written = reconstruct_torus("m.off");
  EXPECT_TRUE(written.bytes.starts_with("OFF")) << written.bytes.substr(0, 40);
  const Mesh mesh = io::read_mesh(at("m.off"));
  EXPECT_EQ(static_cast<long>(mesh.vertices.size()), written.vertices);
  EXPECT_EQ(static_cast<long>(mesh.triangles.size()), written.faces);
  expect_closed_torus(mesh);
}

TEST_F(CliMeshFormat, BinaryStl) {
  const WrittenMesh written = reconstruct_torus("m.stl");
  ASSERT_GT(written.faces, 0);
  EXPECT_EQ(static_cast<long>(written.bytes.size()), 84 + 50 * written.faces);
  ASSERT_GE(written.bytes.size(), 84U);
  // A binary STL must not start with "solid" (readers take that for ASCII STL).
  EXPECT_FALSE(written.bytes.starts_with("solid"));
  std::uint32_t count = 0;  // little-endian, at byte 80
  for (std::size_t i = 0; i < 4; ++i)
    count |= static_cast<std::uint32_t>(static_cast<unsigned char>(written.bytes[80 + i])) << (8 * i);
  EXPECT_EQ(static_cast<long>(count), written.faces);
}

// --normals: PLY and OBJ carry them (ASCII PLY: tests/io/glb_test.cpp); without it the
// file is byte for byte the one of a run that never made them; a .glb
// always has them; a tiled run writes them too (as PLY).
TEST_F(CliMeshFormat, NormalsOnlyWhenAskedAndAlwaysInGlb) {
  const WrittenMesh plain = reconstruct_torus("m.ply");
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "t.ply", "-o", "n.ply", "--normals"})));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "t.ply", "-o", "n.obj", "--normals"})));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "t.ply", "-o", "m.glb"})));
  EXPECT_EQ(plain.bytes.find("property float nx"), std::string::npos);
  const Mesh n = io::read_mesh(at("n.ply"));
  EXPECT_EQ(static_cast<long>(n.normals.size()), plain.vertices);
  EXPECT_TRUE(n.vertices == io::read_mesh(at("m.ply")).vertices) << "the same mesh, with normals";
  const std::string obj = read_bytes(at("n.obj"));
  EXPECT_EQ(static_cast<long>(lines_starting_with(obj, "vn ").size()), plain.vertices);
  EXPECT_NE(obj.find("//"), std::string::npos);
  // Outward on the torus: the normal points away from the ring's core.
  std::size_t inward = 0;
  for (std::size_t v = 0; v < n.vertices.size(); ++v) {
    const Vec3& p = n.vertices[v];
    const Vec3 core = Vec3(p.x(), p.y(), 0.0).normalized();
    inward += n.normals[v].dot(p - core) > 0.0 ? 0u : 1u;
  }
  EXPECT_EQ(inward, 0u);
  const std::string glb = read_bytes(at("m.glb"));
  ASSERT_GE(glb.size(), 20u);
  EXPECT_EQ(glb.substr(0, 4), "glTF");
  EXPECT_NE(glb.find("\"NORMAL\":1"), std::string::npos);
  EXPECT_NE(glb.find("\"count\":" + std::to_string(3 * plain.faces) + ","), std::string::npos) << "the indices";
  // Tiled: the same normals (tests/tiles/tiles_test.cpp compares them); GLB is refused there.
  ASSERT_TRUE(
      succeeded(recon({"--quiet", "reconstruct", "t.ply", "-o", "tiled.ply", "--normals", "--tile-size", "0.5"})));
  EXPECT_EQ(io::read_mesh(at("tiled.ply")).normals.size(), n.normals.size());
  const RunResult tiled_glb = recon({"reconstruct", "t.ply", "-o", "tiled.glb", "--tile-size", "0.5"});
  EXPECT_EQ(tiled_glb.exit_code, 1) << describe(tiled_glb);
  EXPECT_NE(tiled_glb.err.find("binary PLY"), std::string::npos) << describe(tiled_glb);
  EXPECT_FALSE(fs::exists(at("tiled.glb")));
}

TEST_F(CliReconstruct, TwoShapesGiveTwoComponents) {
  ASSERT_NO_FATAL_FAILURE(generate("two", 30000, "two.ply"));
  const RunResult run = recon({"reconstruct", "two.ply", "-o", "m.ply"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_NE(run.out.find("2 components"), std::string::npos) << describe(run);
  const MeshTopology t = analyze_topology(io::read_mesh(at("m.ply")));
  EXPECT_EQ(t.components, 2U);
  EXPECT_TRUE(t.watertight());
  // A sphere (2) and a torus (0).
  EXPECT_EQ(t.euler_characteristic, 2);
  EXPECT_GT(t.signed_volume, 0.0);
}

// ---------------------------------------------------------------- what is printed

// Colours travel to the mesh, in PLY and OBJ; --no-colors drops them.
TEST_F(CliReconstruct, ColoursReachTheMeshUnlessNoColors) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 8000, "s.xyz"));
  add_red_above_blue_below(at("s.xyz"), at("c.ply"));
  const RunResult run = recon({"reconstruct", "c.ply", "-o", "m.ply", "--stats", "st.json"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_EQ(lines_starting_with(run.out, "colours   mesh vertices coloured from the samples").size(), 1U) << run.out;
  const std::string json = read_bytes(at("st.json"));
  EXPECT_NE(json.find("\"has_colors\": true"), std::string::npos);
  EXPECT_EQ(stat_count(json, "colors", "k"), 8);
  const Mesh mesh = io::read_mesh(at("m.ply"));
  ASSERT_EQ(mesh.colors.size(), mesh.vertices.size());
  const double margin = 2.0 * stat(json, "contouring", "cell").value_or(1.0);
  std::size_t checked = 0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const double z = mesh.vertices[v].z();
    if (std::abs(z) <= margin) continue;
    ++checked;
    ASSERT_EQ(mesh.colors[v], z > 0.0 ? (Color{255, 0, 0}) : (Color{0, 0, 255})) << "vertex " << v << " at z " << z;
  }
  EXPECT_GT(checked, mesh.vertices.size() / 2);

  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "c.ply", "-o", "m.obj"})));
  const std::string obj = read_bytes(at("m.obj"));
  EXPECT_TRUE(obj.find(" 1 0 0\n") != std::string::npos && obj.find(" 0 0 1\n") != std::string::npos)
      << "'v x y z r g b' lines, red and blue";
  EXPECT_TRUE(io::read_mesh(at("m.obj")).colors == mesh.colors);

  const RunResult plain = recon({"reconstruct", "c.ply", "-o", "plain.ply", "--no-colors"});
  ASSERT_TRUE(succeeded(plain));
  EXPECT_TRUE(lines_starting_with(plain.out, "colours ").empty()) << plain.out;
  EXPECT_EQ(lines_starting_with(plain.out, "read      c.ply: 8000 points (").size(), 1U) << plain.out;
  EXPECT_FALSE(io::read_mesh(at("plain.ply")).has_colors());
  EXPECT_EQ(read_bytes(at("plain.ply")).find("red"), std::string::npos);
}

TEST_F(CliOutput, QuietPrintsNothing) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 1500, "s.ply"));
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--quiet", "reconstruct", "s.ply", "-o", "m.ply", "--stats", "st.json"},
        std::vector<std::string>{"-q", "normals", "s.ply", "-o", "n.ply"},
        std::vector<std::string>{"-q", "generate", "torus", "-n", "100", "-o", "t.xyz"}}) {
    const RunResult run = recon(args);
    EXPECT_TRUE(succeeded(run));
    EXPECT_TRUE(run.out.empty()) << describe(run);
  }
  EXPECT_EQ(entries(), (std::vector<std::string>{"m.ply", "n.ply", "s.ply", "st.json", "t.xyz"}));
}

TEST_F(CliOutput, ReconstructPrintsOneLinePerPhase) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 1500, "s.ply"));
  const RunResult run = recon({"reconstruct", "s.ply", "-o", "m.ply"});
  ASSERT_TRUE(succeeded(run));
  // "phase I " does not match "phase II", nor "phase II " "phase III".
  for (const char* phase : {"phase I ", "phase II ", "phase III ", "phase IV "})
    EXPECT_EQ(lines_starting_with(run.out, phase).size(), 1U) << phase << describe(run);
  EXPECT_EQ(lines_starting_with(run.out, "read ").size(), 1U) << describe(run);
  EXPECT_EQ(lines_starting_with(run.out, "wrote ").size(), 1U) << describe(run);
  // Phases I and II only, for normals.
  const RunResult normals = recon({"normals", "s.ply", "-o", "n.ply"});
  ASSERT_TRUE(succeeded(normals));
  EXPECT_EQ(lines_starting_with(normals.out, "phase I ").size(), 1U) << describe(normals);
  EXPECT_EQ(lines_starting_with(normals.out, "phase II ").size(), 1U) << describe(normals);
  EXPECT_TRUE(lines_starting_with(normals.out, "phase III ").empty()) << describe(normals);
}

// ---------------------------------------------------------------- lattice

TEST_F(CliLattice, ResolutionAndCellChangeTheLattice) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 3000, "s.ply"));
  Box<3> box;
  for (const Vec3& p : io::read_points(at("s.ply")).positions) box.extend(p);
  const double longest = box.extent().maxCoeff();

  struct Outcome {
    double cell = 0.0;
    long faces = -1;
  };
  const auto run_with = [&](const std::string& option, const std::string& value) {
    const RunResult run =
        recon({"--quiet", "reconstruct", "s.ply", "-o", "m.ply", option, value, "--stats", "st.json"});
    EXPECT_TRUE(succeeded(run)) << option << " " << value;
    const std::string json = fs::exists(at("st.json")) ? read_bytes(at("st.json")) : std::string();
    EXPECT_EQ(stat_count(json, "mesh", "faces"), static_cast<long>(io::read_mesh(at("m.ply")).triangles.size()));
    return Outcome{stat(json, "contouring", "cell").value_or(-1.0), stat_count(json, "mesh", "faces")};
  };
  const Outcome fine = run_with("--resolution", "20");
  const Outcome coarse = run_with("--resolution", "10");
  EXPECT_NEAR(fine.cell, longest / 20.0, 1e-12 * longest);
  EXPECT_NEAR(coarse.cell, longest / 10.0, 1e-12 * longest);
  EXPECT_LT(coarse.faces, fine.faces);
  EXPECT_GT(coarse.faces, 0);

  const Outcome small_cell = run_with("--cell", "0.2");
  const Outcome large_cell = run_with("--cell", "0.4");
  EXPECT_EQ(small_cell.cell, 0.2);
  EXPECT_EQ(large_cell.cell, 0.4);
  EXPECT_LT(large_cell.faces, small_cell.faces);
  EXPECT_GT(large_cell.faces, 0);
}

TEST_F(CliLattice, ResolutionAndCellTogetherAreRefused) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 300, "s.ply"));
  const RunResult run = recon({"reconstruct", "s.ply", "-o", "m.ply", "--cell", "0.2", "--resolution", "20"});
  EXPECT_NE(run.exit_code, 0) << describe(run);
  EXPECT_NE(run.err.find("--cell"), std::string::npos) << describe(run);
  EXPECT_NE(run.err.find("--resolution"), std::string::npos) << describe(run);
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

// ---------------------------------------------------------------- info

TEST_F(CliInfo, ReportsDuplicatesAndPointCount) {
  std::mt19937_64 random(11);
  std::vector<Vec3> points = random_cube_points(100, random);
  for (const int i : {3, 17, 17, 42, 60, 88, 99}) {  // 7 exact copies of earlier points
    const Vec3 copy = points[static_cast<std::size_t>(i)];
    points.push_back(copy);
  }
  std::shuffle(points.begin(), points.end(), random);
  write_file(at("dups.xyz"), xyz_text(points));

  const RunResult run = recon({"info", "dups.xyz"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_NE(run.out.find("\npoints        107\n"), std::string::npos) << describe(run);
  EXPECT_NE(run.out.find("\nduplicates    7 "), std::string::npos) << describe(run);
  EXPECT_EQ(entries(), std::vector<std::string>{"dups.xyz"});
}

TEST_F(CliInfo, ReaderNotesAreSaidUnderTheReadLine) {
  // A 3 x 2 depth image with one pixel without a return.
  write_file(at("o.pcd"),
             "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 3\nHEIGHT 2\nPOINTS 6\nDATA ascii\n"
             "0 0 1\n1 0 1\n2 0 1\n0 1 1\nnan nan nan\n2 1 1\n");
  const RunResult run = recon({"info", "o.pcd"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_NE(run.out.find("o.pcd: 5 points"), std::string::npos) << describe(run);
  EXPECT_NE(run.out.find("\n          skipped 1 point with no position (NaN x y z in an organized cloud); the first "
                         "at line 12 (row 1, column 1)\n"),
            std::string::npos)
      << describe(run);
}

TEST_F(CliErrors, UseNormalsSaysTheReaderDroppedThem) {
  write_file(at("n.pcd"),
             "FIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\nPOINTS 2\n"
             "DATA ascii\n0 0 0 0 0 1\n1 0 0 nan nan nan\n");
  EXPECT_TRUE(refused(recon({"reconstruct", "n.pcd", "-o", "m.ply", "--use-normals"}),
                      {"--use-normals: the input's normals were dropped when it was read (1 point has no normal (NaN), "
                       "the first at line 7; recon estimates its own); run without the option"}));
  // LAZ is named with the tools that decompress it.
  write_file(at("scan.laz"), "LASF");
  EXPECT_TRUE(refused(recon({"info", "scan.laz"}), {"scan.laz: LAZ (compressed LAS) is not read", "laszip -i IN"}));
  EXPECT_EQ(entries(), (std::vector<std::string>{"n.pcd", "scan.laz"}));
}

// ---------------------------------------------------------------- text columns

TEST_F(CliTextColumns, ColoursAreSaidNotTakenForNormals) {
  write_file(at("rgb.xyz"), "0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n0 0 1 10 20 30\n");
  const RunResult run = recon({"info", "rgb.xyz"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_NE(run.out.find("read      rgb.xyz: 4 points with colours ("), std::string::npos) << describe(run);
  EXPECT_NE(run.out.find("\n          columns: x y z r g b (no header; the last three are integers 0-255: colours)\n"),
            std::string::npos)
      << describe(run);
  // A CloudCompare export with "\r\n" line ends, named by its header.
  write_file(at("cc.csv"), "//X,Y,Z,R,G,B\r\n0,0,0,255,0,0\r\n1,0,0,0,255,0\r\n");
  const RunResult cc = recon({"info", "cc.csv"});
  ASSERT_TRUE(succeeded(cc));
  EXPECT_NE(cc.out.find("columns: x y z r g b (from the header on line 1; colours: integers 0-255)"), std::string::npos)
      << describe(cc);
}

TEST_F(CliTextColumns, ColumnsOptionNamesWhatTheValuesLeaveInDoubt) {
  write_file(at("seven.txt"), "0 0 0 7 1 2 3\n1 0 0 7 4 5 6\n0 1 0 7 7 8 9\n0 0 1 7 1 2 3\n");
  EXPECT_TRUE(refused(recon({"info", "seven.txt"}),
                      {"seven.txt: the columns after x y z leave doubt", "--columns x,y,z,_,r,g,b"}));
  const RunResult run = recon({"info", "seven.txt", "--columns", "x,y,z,_,r,g,b"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_NE(run.out.find("4 points with colours"), std::string::npos) << describe(run);
  EXPECT_NE(run.out.find("columns: x y z _ r g b (from --columns; colours: integers 0-255)"), std::string::npos)
      << describe(run);
  EXPECT_TRUE(
      refused(recon({"info", "seven.txt", "--columns", "x,y,z,q,r,g,b"}), {"--columns names an unknown column 'q'"}));
  EXPECT_TRUE(refused(recon({"info", "seven.txt", "--columns", "x,y,z"}),
                      {"seven.txt:1: --columns names 3 columns, but this line has 7"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"seven.txt"});
}

// ---------------------------------------------------------------- determinism

// Large enough that every parallel part really splits its work (kd-tree
// build tasks above 65536 points, OpenMP chunks of 4096, several lattice
// waves), and three threads on any machine, so the split differs from two.
TEST_F(CliDeterminism, ThreadCountDoesNotChangeTheOutput) {
  ASSERT_NO_FATAL_FAILURE(generate("two", 150000, "t.ply"));
  for (const std::string threads : {"1", "2", "3"}) {
    ASSERT_TRUE(succeeded(recon({"--quiet", "--threads", threads, "reconstruct", "t.ply", "-o", "m" + threads + ".ply",
                                 "--stats", threads + ".json"})));
    ASSERT_TRUE(succeeded(recon({"--quiet", "--threads", threads, "normals", "t.ply", "-o", "n" + threads + ".ply"})));
    // The option took effect, so the comparison is between different runs.
    EXPECT_EQ(stat_count(read_bytes(at(threads + ".json")), "", "threads"), std::stol(threads));
  }
  const std::string mesh = read_bytes(at("m1.ply")), normals = read_bytes(at("n1.ply"));
  EXPECT_GT(mesh.size(), 100000U);
  for (const std::string threads : {"2", "3"}) {
    EXPECT_TRUE(mesh == read_bytes(at("m" + threads + ".ply"))) << "--threads " << threads << " wrote another mesh";
    EXPECT_TRUE(normals == read_bytes(at("n" + threads + ".ply"))) << "--threads " << threads << " wrote other normals";
  }
}

// ---------------------------------------------------------------- report
// (what the page shows is tested in a browser: web/tests/report.test.mjs)

TEST_F(CliReport, ReconstructWritesOnePageWithTheRunsStatsAndTheSameMesh) {
  ASSERT_NO_FATAL_FAILURE(generate("torus", 6000, "t.ply"));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "t.ply", "-o", "plain.ply"})));
  const RunResult run = recon({"reconstruct", "t.ply", "-o", "m.ply", "--report", "r.html", "--stats", "s.json"});
  ASSERT_TRUE(succeeded(run)) << describe(run);
  EXPECT_EQ(lines_starting_with(run.out, "wrote     r.html (report: 6000 of 6000 points drawn").size(), 1U) << run.out;
  // Keeping the graph and the corners for the report changes nothing.
  EXPECT_TRUE(read_bytes(at("m.ply")) == read_bytes(at("plain.ply")));
  const std::string page = read_bytes(at("r.html"));
  EXPECT_TRUE(page.starts_with("<!doctype html>"));
  EXPECT_TRUE(page.ends_with("</html>\n"));
  EXPECT_NE(page.find("id=\"recon-data\""), std::string::npos);
  // The stats in the page are the file's: the same face count and phase times.
  const std::string stats = read_bytes(at("s.json"));
  const long faces = stat_count(stats, "mesh", "faces");
  EXPECT_GT(faces, 1000);
  EXPECT_NE(page.find("\"faces\":" + std::to_string(faces)), std::string::npos);
  EXPECT_EQ(hidden_entries(), std::vector<std::string>{});
}

TEST_F(CliReport, NormalsWritesAReportWithoutLatticeLayers) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 3000, "s.xyz"));
  ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "s.xyz", "-o", "n.ply", "--report", "r.html"})));
  const std::string page = read_bytes(at("r.html"));
  EXPECT_NE(page.find("\"graph\":{"), std::string::npos);
  EXPECT_EQ(page.find("\"mesh\":{"), std::string::npos);
  EXPECT_EQ(page.find("\"corners\":{"), std::string::npos);
}

TEST_F(CliReport, AColouredRunsPageCarriesThePointsAndTheMeshsColours) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 3000, "s.xyz"));
  add_red_above_blue_below(at("s.xyz"), at("c.ply"));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "c.ply", "-o", "m.ply", "--report", "r.html"})));
  const std::string page = read_bytes(at("r.html"));
  // An array's number in the data block (the statistics have a "colors" object too).
  const auto names_an_array = [](const std::string& text, const std::string& key) {
    for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1))
      if (at + key.size() < text.size() && std::isdigit(static_cast<unsigned char>(text[at + key.size()]))) return true;
    return false;
  };
  EXPECT_TRUE(names_an_array(page, ",\"color\":")) << "layer 1's colours";
  EXPECT_TRUE(names_an_array(page, ",\"colors\":")) << "the mesh's colours";
  ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "c.ply", "-o", "n.ply", "--report", "n.html"})));
  EXPECT_TRUE(names_an_array(read_bytes(at("n.html")), ",\"color\":"));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "s.xyz", "-o", "p.ply", "--report", "p.html"})));
  const std::string plain = read_bytes(at("p.html"));
  EXPECT_FALSE(names_an_array(plain, ",\"color\":") || names_an_array(plain, ",\"colors\":"));
}

TEST_F(CliReport, BadReportPathIsRefusedBeforeAnyWork) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 3000, "s.xyz"));
  RunResult run = recon({"reconstruct", "s.xyz", "-o", "m.ply", "--report", "missing/r.html"});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("missing/r.html: cannot write: folder 'missing' does not exist"), std::string::npos)
      << run.err;
  EXPECT_EQ(run.out, "");  // refused before reading
  run = recon({"reconstruct", "s.xyz", "-o", "m.ply", "--report", "m.ply"});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("m.ply is named for two outputs"), std::string::npos) << run.err;
  run = recon({"normals", "s.xyz", "-o", "n.ply", "--report", "s.xyz"});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("refusing to overwrite the input file"), std::string::npos) << run.err;
  EXPECT_EQ(entries(), std::vector<std::string>{"s.xyz"});
}

// ---------------------------------------------------------------- curves (2D)

using CliCurves = CliTest;

/// "x y" lines of n points stratified around a circle (one random point in
/// each of n equal arcs, seeded).
std::string circle_xy_text(const Vec2& centre, double radius, int n, std::uint64_t seed) {
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

ObjCurves read_obj_curves(const fs::path& path) {
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

bool closed(const std::vector<std::size_t>& line) { return line.size() > 2 && line.front() == line.back(); }

TEST_F(CliCurves, TwoColumnsMakeOneClosedCurveInObjWithStats) {
  write_file(at("circle.txt"), circle_xy_text(Vec2(1.0, -2.0), 1.5, 200, 1));
  const RunResult run = recon({"reconstruct", "circle.txt", "-o", "circle.obj", "--stats", "st.json"});
  ASSERT_TRUE(succeeded(run));
  for (const char* phase :
       {"phase I   tangent lines", "phase II  orientation: 1 component", "phase III signed distance",
        "phase IV  marching squares", "curves    1 curve: 1 closed, 0 open"})
    EXPECT_NE(run.out.find(phase), std::string::npos) << phase << describe(run);
  const ObjCurves obj = read_obj_curves(at("circle.obj"));
  ASSERT_EQ(obj.lines.size(), 1U);
  EXPECT_TRUE(closed(obj.lines[0]));
  EXPECT_EQ(obj.lines[0].size(), obj.vertices.size() + 1);
  // 200 points on a radius of 1.5: the library's bound (reconstruct_curve_test.cpp)
  // is about 0.015 here; 1 % of the radius holds it.
  for (const Vec2& v : obj.vertices) EXPECT_NEAR((v - Vec2(1.0, -2.0)).norm(), 1.5, 0.015);
  const std::string stats = read_bytes(at("st.json"));
  EXPECT_EQ(stat_count(stats, "input", "dimension"), 2);
  EXPECT_EQ(stat_count(stats, "input", "points"), 200);
  EXPECT_EQ(stat_count(stats, "curves", "count"), 1);
  EXPECT_EQ(stat_count(stats, "curves", "closed"), 1);
  EXPECT_EQ(stat_count(stats, "curves", "vertices"), static_cast<long>(obj.vertices.size()));
  EXPECT_EQ(entries(), (std::vector<std::string>{"circle.obj", "circle.txt", "st.json"}));
}

TEST_F(CliCurves, SvgShowsPointsNormalsAndCurves) {
  write_file(at("two.xyz"), circle_xy_text(Vec2(0.0, 0.0), 1.0, 150, 2) + circle_xy_text(Vec2(4.0, 1.0), 0.7, 100, 3));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "two.xyz", "-o", "two.svg"})));
  const std::string svg = read_bytes(at("two.svg"));
  EXPECT_TRUE(svg.starts_with("<?xml")) << svg.substr(0, 100);
  EXPECT_NE(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
  EXPECT_TRUE(svg.ends_with("</svg>\n"));
  auto count = [&](std::string_view what) {
    std::size_t n = 0;
    for (std::size_t at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("<circle "), 250U);     // the points
  EXPECT_EQ(count("<path d=\"M"), 250U);  // a normal each
  EXPECT_EQ(count("<path class=\"closed\""), 2U);
  EXPECT_EQ(count("<path class=\"open\""), 0U);
}

TEST_F(CliCurves, PlainTextCurvesAndAFlatCloudReadAs2D) {
  // Three columns with a constant z are a surface to `-o mesh.ply` but a
  // curve when curves are asked for (.txt, .svg).
  std::string flat;
  std::istringstream xy(circle_xy_text(Vec2(0.5, 0.5), 2.0, 160, 4));
  for (std::string line; std::getline(xy, line);) flat += line + " 7.25\n";
  write_file(at("flat.xyz"), flat);
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "flat.xyz", "-o", "flat.txt"})));
  const std::string text = read_bytes(at("flat.txt"));
  EXPECT_NE(text.find("# curve 1: closed"), std::string::npos) << text.substr(0, 300);
  EXPECT_EQ(text.find("# curve 2"), std::string::npos);
}

TEST_F(CliCurves, BadInputsAreOneLineErrors) {
  write_file(at("bad.txt"), "0 0\n1 0\n1 2 3\n");
  const RunResult run = recon({"reconstruct", "bad.txt", "-o", "out.svg"});
  EXPECT_TRUE(refused(run, {"expected 2 numbers (x y) on a line, found 3"}));
  EXPECT_TRUE(run.err.starts_with("recon: error: bad.txt:3:")) << describe(run);

  std::vector<Vec3> solid;
  for (int i = 0; i < 40; ++i) solid.emplace_back(std::cos(i), std::sin(i), 0.1 * i);
  write_file(at("solid.xyz"), xyz_text(solid));
  EXPECT_TRUE(refused(recon({"reconstruct", "solid.xyz", "-o", "out.svg"}), {"solid.xyz", "not 2D"}));

  write_file(at("few.txt"), "0 0\n1 0\n0 1\n1 1\n2 2\n");
  EXPECT_TRUE(refused(recon({"reconstruct", "few.txt", "-o", "out.svg"}), {"only 5 points", "lower --k"}));
  write_file(at("ok.txt"), circle_xy_text(Vec2::Zero(), 1.0, 50, 5));
  EXPECT_TRUE(
      refused(recon({"reconstruct", "ok.txt", "-o", "out.ply"}), {"out.ply", "known curve formats: .svg, .obj, .txt"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "ok.txt", "-o", "out.svg", "--use-normals"}), {"no normals"}));
  // The 3D commands say what two columns are.
  EXPECT_TRUE(refused(recon({"normals", "ok.txt", "-o", "n.ply"}), {"ok.txt:1:", "2D points"}));
  EXPECT_EQ(entries(), (std::vector<std::string>{"bad.txt", "few.txt", "ok.txt", "solid.xyz"}));
}

TEST_F(CliCurves, HoppeCurve1IsOneOpenCurve) {
  const fs::path input = testing::shared_data("hoppe_curve1/curve1.pts");
  RECON_REQUIRE_DATA(input);
  const RunResult run = recon({"reconstruct", input.string(), "-o", "curve1.obj"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_NE(run.out.find("126 points in 2D"), std::string::npos) << describe(run);
  const ObjCurves obj = read_obj_curves(at("curve1.obj"));
  ASSERT_EQ(obj.lines.size(), 1U);
  EXPECT_FALSE(closed(obj.lines[0]));
}

TEST_F(CliCurves, ReportIsRefusedWithWhereToLook) {
  write_file(at("circle.txt"), circle_xy_text(Vec2::Zero(), 1.0, 100, 6));
  const RunResult run = recon({"reconstruct", "circle.txt", "-o", "c.svg", "--report", "r.html"});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("--report draws 3D reconstructions; for curves, the SVG output shows"), std::string::npos)
      << run.err;
  EXPECT_EQ(entries(), std::vector<std::string>{"circle.txt"});
}

// ---------------------------------------------------------------- generate

using CliGenerate = CliTest;

// The largest distance from the points of `cloud` to the shape's surface.
double farthest_from(const Shape& shape, const PointCloud& cloud) {
  double farthest = 0.0;
  for (const Vec3& p : cloud.positions) farthest = std::max(farthest, shape.distance(p));
  return farthest;
}

TEST_F(CliGenerate, NewShapesWriteCloudsOnTheirSurfaces) {
  for (const char* name : {"part", "handle", "conics"}) {
    const std::string file = std::string(name) + ".xyz";
    ASSERT_NO_FATAL_FAILURE(generate(name, 3000, file));
    const PointCloud cloud = io::read_points(at(file));
    EXPECT_EQ(cloud.size(), 3000U) << name;
    EXPECT_FALSE(cloud.has_normals()) << name;
    // Written in text as the shortest round-tripping decimals: still on the surface.
    EXPECT_LT(farthest_from(*make_shape(name), cloud), 1e-12) << name;
  }
}

TEST_F(CliGenerate, ConicsComeAtTheCoursesSizeUnlessToldOtherwise) {
  EXPECT_TRUE(succeeded(recon({"--quiet", "generate", "conics", "-o", "c.ply"})));
  EXPECT_EQ(io::read_points(at("c.ply")).size(), 16000U);
  EXPECT_TRUE(succeeded(recon({"--quiet", "generate", "handle", "-o", "h.ply"})));
  EXPECT_EQ(io::read_points(at("h.ply")).size(), 100000U);
}

// --truth: a noise-free sample of the true surface with its normals, drawn
// with a seed of its own (not the cloud), written atomically.
TEST_F(CliGenerate, TruthIsADenseSampleOfTheSurfaceWithNormals) {
  const RunResult run = recon({"generate", "part", "-n", "2000", "--noise", "0.01", "-o", "p.ply", "--truth", "gt.ply",
                               "--truth-points", "5000"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_NE(run.out.find("gt.ply: 5000 points of the true surface"), std::string::npos) << describe(run);
  EXPECT_EQ(entries(), (std::vector<std::string>{"gt.ply", "p.ply"}));
  const PointCloud truth = io::read_points(at("gt.ply"));
  ASSERT_EQ(truth.size(), 5000U);
  ASSERT_TRUE(truth.has_normals());
  const auto part = make_machined_part();
  EXPECT_LT(farthest_from(*part, truth), 1e-12);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    ASSERT_NEAR(truth.normals[i].norm(), 1.0, 1e-12);
    ASSERT_NEAR(part->distance(truth.positions[i] + 1e-3 * truth.normals[i]), 1e-3, 1e-9);
  }
  const PointCloud noise_free = part->sample(2000, 1);  // the cloud, before its noise
  EXPECT_NE(std::vector<Vec3>(truth.positions.begin(), truth.positions.begin() + 2000), noise_free.positions);
  EXPECT_TRUE(succeeded(recon({"--quiet", "generate", "conics", "-o", "c.xyz", "--truth", "c_gt.ply"})));
  EXPECT_EQ(io::read_points(at("c_gt.ply")).size(), 300000U);  // the default
}

TEST_F(CliGenerate, BadTruthOptionsAreRefusedBeforeWriting) {
  const RunResult zero =
      recon({"generate", "handle", "-n", "100", "-o", "h.ply", "--truth", "gt.ply", "--truth-points", "0"});
  EXPECT_EQ(zero.exit_code, 2) << describe(zero);  // a usage error, like every option out of range
  EXPECT_TRUE(zero.err.starts_with("recon: error: --truth-points: Value 0 not in range")) << describe(zero);
  EXPECT_EQ(count_lines(zero.err), 1U) << describe(zero);
  const RunResult alone = recon({"generate", "handle", "-n", "100", "-o", "h.ply", "--truth-points", "10"});
  EXPECT_EQ(alone.exit_code, 2) << describe(alone);
  EXPECT_NE(alone.err.find("--truth-points requires --truth"), std::string::npos) << describe(alone);
  EXPECT_TRUE(
      refused(recon({"generate", "handle", "-n", "100", "-o", "h.ply", "--truth", "gt.xyz"}), {"gt.xyz", ".ply"}));
  EXPECT_TRUE(refused(recon({"generate", "handle", "-n", "100", "-o", "h.ply", "--truth", "h.ply"}),
                      {"h.ply is named for two outputs"}));
  EXPECT_TRUE(
      refused(recon({"generate", "handle", "-n", "100", "-o", "h.ply", "--truth", "nowhere/gt.ply"}), {"nowhere"}));
  EXPECT_TRUE(entries().empty());
}

// ---------------------------------------------------------------- lab

using CliLab = CliTest;

// The alternatives lab on the course's conics, with their true normals:
// the table, the skipped runs, and the JSON, one entry per run.
TEST_F(CliLab, PrintsTheTableAndWritesEveryRunAsJson) {
  const RunResult made = recon({"--quiet", "generate", "conics", "-n", "2500", "--with-normals", "-o", "c.ply"});
  ASSERT_TRUE(succeeded(made));
  const RunResult run = recon({"lab", "c.ply", "--stats", "lab.json", "--max-list-heap", "1000"});
  ASSERT_TRUE(succeeded(run));
  for (const char* part : {"truth     the input's own normals", "prim/fibonacci-heap", "prim/pairing-heap", "kruskal",
                           "boruvka", "prim-array", "mutual-knn", "riemannian", "brute-force", "grid", "kd-tree",
                           "skipped prim/list-heap: 2500 points is more than 1000"})
    EXPECT_NE(run.out.find(part), std::string::npos) << part << describe(run);
  // The graph rows: pieces found. The Riemannian graph keeps the five
  // solids apart, the complete graph's tree joins them.
  const auto riemannian = lines_starting_with(run.out, "graph   riemannian ");
  const auto complete = lines_starting_with(run.out, "graph   complete ");
  ASSERT_EQ(riemannian.size(), 1u) << describe(run);
  ASSERT_EQ(complete.size(), 1u) << describe(run);
  EXPECT_NE(riemannian[0].find("      5 "), std::string::npos) << riemannian[0];
  EXPECT_NE(complete[0].find("      1 "), std::string::npos) << complete[0];

  const std::string json = read_bytes(at("lab.json"));
  std::size_t entries_found = 0;
  for (std::size_t at = json.find("\"name\": "); at != std::string::npos; at = json.find("\"name\": ", at + 1))
    ++entries_found;
  EXPECT_EQ(entries_found, 18u) << json;
  EXPECT_NE(json.find("\"runs\": ["), std::string::npos) << json;
  for (const char* part : {"\"kind\": \"queue\"", "\"kind\": \"mst\"", "\"kind\": \"graph\"", "\"kind\": \"search\"",
                           "\"graph\": \"riemannian\"", "\"tree_weight\": ", "\"seconds\": ", "\"decrease_keys\": ",
                           "\"distance_evaluations\": ", "\"agree_truth\": ",
                           "\"seconds\": null,\n      \"skipped\": \"2500 points is more than 1000 for the list heap"})
    EXPECT_NE(json.find(part), std::string::npos) << part << json;
  EXPECT_EQ(stat_count(json, "input", "points"), 2500);
}

TEST_F(CliLab, RefusesANegativeLimit) {
  ASSERT_NO_FATAL_FAILURE(generate("torus", 600, "t.ply"));
  const RunResult run = recon({"lab", "t.ply", "--max-complete", "-3"});
  EXPECT_EQ(run.exit_code, 2) << describe(run);
  EXPECT_NE(run.err.find("--max-complete"), std::string::npos) << describe(run);
}

TEST_F(CliLab, AnAlternativeThatDisagreesIsAnErrorNotARow) {
  ASSERT_NO_FATAL_FAILURE(generate("torus", 600, "t.ply"));
  for (const char* spoiled : {"kruskal", "grid", "prim/pairing-heap"})
    EXPECT_TRUE(refused(recon({"lab", "t.ply", "--stats", "lab.json", "--test-spoil", spoiled}),
                        {"lab: ", spoiled, "disagree"}));
  // Nothing half-written: the statistics are not written.
  EXPECT_EQ(entries(), std::vector<std::string>{"t.ply"});
}

// ---------------------------------------------------------------- real data

TEST_F(CliRealData, HoppeCactus) {
  const fs::path input = testing::shared_data("hoppe_cactus/cactus.pts");
  RECON_REQUIRE_DATA(input);
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", input.string(), "-o", "cactus.ply"})));
  EXPECT_GE(io::read_mesh(at("cactus.ply")).triangles.size(), 100U);
}

TEST_F(CliRealData, PclLamppost) {
  const fs::path input = testing::shared_data("pcl_lamppost/lamppost.pcd");
  RECON_REQUIRE_DATA(input);
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", input.string(), "-o", "lamppost.ply"})));
  EXPECT_GE(io::read_mesh(at("lamppost.ply")).triangles.size(), 100U);
}

// ---------------------------------------------------------------- tiles

// --tile-size: the same triangles as the run in memory (phase IV's mesh,
// which is hoppe92's whole mesh), the tiles gone afterwards.
TEST_F(CliTiles, TileSizeGivesTheSameMeshAsInMemory) {
  ASSERT_NO_FATAL_FAILURE(generate("two", 30000, "two.ply"));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "two.ply", "-o", "whole.ply", "--method", "hoppe92"})));
  const RunResult tiled = recon({"reconstruct", "two.ply", "-o", "tiled.ply", "--method", "hoppe92", "--tile-size",
                                 "0.9", "--stats", "tiled.json"});
  ASSERT_TRUE(succeeded(tiled)) << describe(tiled);
  EXPECT_NE(tiled.out.find("tiles     --tile-size: "), std::string::npos) << tiled.out;
  const std::string json = read_bytes(at("tiled.json"));
  EXPECT_GT(stat(json, "tiled", "tiles").value_or(0.0), 4.0);
  EXPECT_EQ(stat(json, "tiled", "objects"), 2.0);
  const Mesh whole = io::read_mesh(at("whole.ply")), mesh = io::read_mesh(at("tiled.ply"));
  EXPECT_TRUE(same_mesh(mesh, whole, 1e-9));
  EXPECT_EQ(entries(), (std::vector<std::string>{"tiled.json", "tiled.ply", "two.ply", "whole.ply"}));
}

// The default method in tiles: phase V too, its open boundary trimmed over
// the whole mesh, as in memory.
TEST_F(CliTiles, RefinedMeshInTilesIsTheInMemoryOne) {
  ASSERT_NO_FATAL_FAILURE(generate("terrain", 15000, "t.ply"));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "t.ply", "-o", "whole.ply", "--stats", "whole.json"})));
  const RunResult tiled =
      recon({"reconstruct", "t.ply", "-o", "tiled.ply", "--tile-size", "0.5", "--stats", "tiled.json"});
  ASSERT_TRUE(succeeded(tiled)) << describe(tiled);
  EXPECT_NE(tiled.out.find("refine    "), std::string::npos) << tiled.out;
  EXPECT_NE(tiled.out.find("(refined, phase V included)"), std::string::npos) << tiled.out;
  const std::string json = read_bytes(at("tiled.json"));
  EXPECT_GT(stat(json, "tiled", "tiles").value_or(0.0), 4.0);
  const std::optional<double> trimmed = stat(json, "tiled", "trimmed_triangles");
  EXPECT_GT(trimmed.value_or(0.0), 0.0);
  EXPECT_EQ(trimmed, stat(read_bytes(at("whole.json")), "refinement", "trimmed_triangles"));
  EXPECT_TRUE(same_mesh(io::read_mesh(at("tiled.ply")), io::read_mesh(at("whole.ply")), 1e-9));
}

// Colours come through tiles as in memory, and --no-colors drops them there too.
TEST_F(CliTiles, ColoursComeThroughTilesUnlessNoColors) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 20000, "s.xyz"));
  add_red_above_blue_below(at("s.xyz"), at("c.ply"));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "c.ply", "-o", "whole.ply"})));
  const RunResult tiled = recon({"reconstruct", "c.ply", "-o", "tiled.ply", "--tile-size", "0.7"});
  ASSERT_TRUE(succeeded(tiled)) << describe(tiled);
  EXPECT_NE(tiled.out.find("(refined, phase V included, with colours)"), std::string::npos) << tiled.out;
  const Mesh whole = io::read_mesh(at("whole.ply")), mesh = io::read_mesh(at("tiled.ply"));
  ASSERT_TRUE(same_mesh(mesh, whole, 1e-9));
  ASSERT_TRUE(mesh.has_colors());
  const KdTree<3> tree(whole.vertices);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    ASSERT_EQ(mesh.colors[v], whole.colors[tree.nearest(mesh.vertices[v]).index]) << "vertex " << v;
  ASSERT_TRUE(
      succeeded(recon({"--quiet", "reconstruct", "c.ply", "-o", "plain.ply", "--tile-size", "0.7", "--no-colors"})));
  EXPECT_FALSE(io::read_mesh(at("plain.ply")).has_colors());
}

// A cloud estimated to need several times --max-memory is reconstructed in
// tiles, and the process's peak stays within the limit.
TEST_F(CliTiles, PastMaxMemoryTilesAndStaysWithinIt) {
  ASSERT_NO_FATAL_FAILURE(generate("terrain", 250000, "t.ply"));
  const RunResult run = recon({"reconstruct", "t.ply", "-o", "m.ply", "--max-memory", "64M", "--stats", "m.json"});
  ASSERT_TRUE(succeeded(run)) << describe(run);
  EXPECT_NE(run.out.find("250000 points need about 0.235 GB, more than --max-memory 0.064 GB"), std::string::npos)
      << run.out;
  const std::string json = read_bytes(at("m.json"));
  EXPECT_GT(stat(json, "tiled", "tiles").value_or(0.0), 4.0);
  EXPECT_EQ(stat(json, "tiled", "inexact_samples"), 0.0);
  const MeshTopology topology = analyze_topology(io::read_mesh(at("m.ply")));
  EXPECT_EQ(topology.components, 1u);
  EXPECT_EQ(topology.boundary_loops, 1u);
  EXPECT_EQ(topology.euler_characteristic, 1);
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)  // (their shadow memory counts too)
  const std::optional<double> peak = stat(json, "memory", "peak_mib_total");
  ASSERT_TRUE(peak.has_value());
  EXPECT_LT(*peak * 1024 * 1024, 64e6) << "MiB at the peak";
#endif
}

TEST_F(CliTiles, WhatTilesDoNotDoIsRefusedBeforeAnyWork) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 5000, "s.ply"));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.obj", "--tile-size", "1"}), {"name the output .ply"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--tile-size", "1", "--use-normals"}),
                      {"drop --use-normals"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--tile-size", "1", "--ascii"}), {"drop --ascii"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

TEST_F(CliTiles, InterruptRemovesTheTiles) {
  ASSERT_NO_FATAL_FAILURE(generate("terrain", 600000, "t.ply"));
  const RunResult run = interrupted({"reconstruct", "t.ply", "-o", "m.ply", "--tile-size", "0.5"}, 0.8);
  EXPECT_EQ(run.exit_code, 128 + SIGINT) << describe(run);
  EXPECT_LT(std::stoi(run.out), 1000) << "milliseconds from SIGINT to the end";
  EXPECT_EQ(entries(), std::vector<std::string>{"t.ply"});
}

// ---------------------------------------------------------------- limits (issue 28)
// Numbers, bounds and the messages about them: every numeric option refuses
// NaN, infinities, negatives and the out-of-range in one readable line; a
// huge tile size is one tile; a run that finds no surface is an error that
// says why; a thread count past the machine is refused before any thread
// starts; a memory limit too small for a tiled run's statistics says so.

using CliLimits = CliTest;

/// An option refused while the command line is read: exit status 2, one
/// line naming the option and `part`, and no number of 20 digits or more
/// (CLI11's own checks printed the largest double, 310 digits, as a bound).
::testing::AssertionResult option_refused(const RunResult& run, std::string_view option, std::string_view part) {
  if (run.exit_code != 2) return ::testing::AssertionFailure() << "expected exit status 2" << describe(run);
  if (count_lines(run.err) != 1 || !run.err.starts_with("recon: error: " + std::string(option) + ": "))
    return ::testing::AssertionFailure() << "expected one line naming " << option << describe(run);
  if (run.err.find(part) == std::string::npos)
    return ::testing::AssertionFailure() << "the message lacks '" << part << "'" << describe(run);
  std::size_t digits = 0;
  for (const char c : run.err) {
    digits = std::isdigit(static_cast<unsigned char>(c)) ? digits + 1 : 0;
    if (digits >= 20) return ::testing::AssertionFailure() << "a number of 20 digits or more" << describe(run);
  }
  return ::testing::AssertionSuccess();
}

TEST_F(CliLimits, NumericOptionsRefuseNanInfinityNegativeAndOutOfRange) {
  write_file(at("s.xyz"), "0 0 0\n1 0 0\n0 1 0\n");  // never read: the options are refused first
  struct Case {
    std::vector<std::string> args;
    std::string option, expected;
  };
  const std::string length = "expected a finite length greater than 0, found '";
  const std::vector<Case> cases = {
      {{"--tile-size", "nan"}, "--tile-size", length + "nan'"},
      {{"--tile-size", "0"}, "--tile-size", length + "0'"},
      {{"--tile-size", "-1"}, "--tile-size", length + "-1'"},
      {{"--tile-size", "inf"}, "--tile-size", length + "inf'"},
      {{"--tile-size", "1e999"}, "--tile-size", length + "1e999'"},
      {{"--cell", "nan"}, "--cell", length + "nan'"},
      {{"--cell", "inf"}, "--cell", length + "inf'"},
      {{"--cell", "0"}, "--cell", length + "0'"},
      {{"--rho", "nan"}, "--rho", length + "nan'"},
      {{"--rho", "-inf"}, "--rho", length + "-inf'"},
      {{"--rho", "0"}, "--rho", length + "0'"},
      {{"--delta", "inf"}, "--delta", "expected a finite length of 0 or more, found 'inf'"},
      {{"--delta", "nan"}, "--delta", "expected a finite length of 0 or more, found 'nan'"},
      {{"--delta", "-1"}, "--delta", "expected a finite length of 0 or more, found '-1'"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"reconstruct", "s.xyz", "-o", "m.ply"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    EXPECT_TRUE(option_refused(recon(args), c.option, c.expected));
  }
  EXPECT_TRUE(option_refused(recon({"--threads", "-1", "info", "s.xyz"}), "--threads",
                             "expected a whole number from 0 to 2147483647, found '-1'"));
  EXPECT_TRUE(option_refused(recon({"--threads", "nan", "info", "s.xyz"}), "--threads", "found 'nan'"));
  EXPECT_TRUE(option_refused(recon({"generate", "sphere", "-o", "g.xyz", "--noise", "nan"}), "--noise",
                             "expected a number from 0 to 1, found 'nan'"));
  EXPECT_TRUE(option_refused(recon({"lab", "s.xyz", "--max-complete", "-1"}), "--max-complete",
                             "expected a whole number from 0 to 1000000000000, found '-1'"));
  EXPECT_EQ(entries(), std::vector<std::string>{"s.xyz"});
}

/// No run of 20 digits or more in `text`.
bool has_no_long_number(const std::string& text) {
  std::size_t digits = 0;
  for (const char c : text) {
    digits = std::isdigit(static_cast<unsigned char>(c)) ? digits + 1 : 0;
    if (digits >= 20) return false;
  }
  return true;
}

// Lengths past any cloud (coordinates stop at +-1e15), or so small that the
// lattice cannot hold the cloud, are refused with short figures; they
// overflowed in the phases (SIGFPE under --trap-fp) or printed a 300-digit
// count of cubes.
TEST_F(CliLimits, HugeAndTinyLengthsAreRefusedWithoutOverflow) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 2000, "s.ply"));
  struct Case {
    std::vector<std::string> args;
    std::string part;
  };
  const std::vector<Case> cases = {
      {{"--rho", "1e300"}, "rho of 1e+300 is longer than any cloud can be (at most 4e+15"},
      {{"--cell", "1e300"}, "a cell of 1e+300 is longer than any cloud can be"},
      {{"--delta", "1e300"}, "delta of 1e+300 is longer than any cloud can be"},
      {{"--cell", "1e-300"}, "the lattice would need 2e+300 cubes along axis x (at most 2097150)"},
      {{"--rho", "1e-300"}, "cubes along axis x (at most 2097150)"},
      {{"--rho", "1e-300", "--tile-size", "1"}, "cubes along axis x (at most 2097150)"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"reconstruct", "s.ply", "-o", "m.ply"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const RunResult run = recon(args);
    EXPECT_TRUE(refused(run, {c.part}));
    EXPECT_TRUE(has_no_long_number(run.err)) << describe(run);
  }
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

// A tile size past the cloud is one tile (the count of cubes overflowed an
// int and gave the smallest tiles: 4 on this terrain).
TEST_F(CliLimits, HugeTileSizeIsOneTile) {
  ASSERT_NO_FATAL_FAILURE(generate("terrain", 8000, "s.ply"));
  for (const std::string size : {"1e10", "1e30", "1e300"}) {
    const RunResult run =
        recon({"--quiet", "reconstruct", "s.ply", "-o", "m.ply", "--tile-size", size, "--stats", "m.json"});
    ASSERT_TRUE(succeeded(run)) << describe(run);
    EXPECT_EQ(stat_count(read_bytes(at("m.json")), "tiled", "tiles"), 1) << "--tile-size " << size;
  }
}

// A lattice cell as large as the cloud (given, or from a given rho) finds
// no surface: an error saying so, with the figures, and no file written.
TEST_F(CliLimits, NoSurfaceFoundIsAnErrorAndWritesNothing) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 2000, "s.ply"));  // a unit sphere: longest side 2
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--cell", "10"}),
                      {"no surface found", "cell 10,", "longest side is 2", "use a cell under about 0.5 (--cell)"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--rho", "1e6"}),
                      {"no surface found", "rho 1e+06", "a smaller --rho"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--method", "hoppe92", "--rho", "1e6"}),
                      {"no surface found", "cell 1e+06", "the cell is rho by default"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--cell", "10", "--tile-size", "1"}),
                      {"no surface found: no tile's contour holds a triangle (cell 10; tiles: 1)", "(--cell"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

// Tens of thousands of threads crashed inside the OpenMP runtime.
TEST_F(CliLimits, ThreadsPastTheMachineAreRefused) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 300, "s.ply"));
  EXPECT_TRUE(refused(recon({"--threads", "70000", "reconstruct", "s.ply", "-o", "m.ply"}),
                      {"a thread count of 70000", "at most", "a core"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

// 1 MB lets a tiled run measure the cloud on about 260 points, drawn as whole
// patches of the cloud: none of 300000 here. The message said "only 0
// points; k = 20 needs at least 21".
TEST_F(CliLimits, MemoryLimitTooSmallForTheStatisticsSaysSo) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 300000, "s.ply"));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--max-memory", "1M"}),
                      {"the memory limit is too small for the cloud-wide statistics", "1 MB allowed",
                       "of the 300000 points", "0 drawn", "needs at least 21", "raise --max-memory"}));
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

// ---------------------------------------------------------------- streams and special outputs (issue 28)

/// Runs a shell line in the work folder, where RECON stands for the program;
/// for pipes and FIFOs, which recon() (stdin from /dev/null) cannot set up.
class CliStreams : public CliTest {
 protected:
  [[nodiscard]] RunResult shell(const std::string& line, int seconds = 30) const {
    std::string expanded = line;
    for (std::size_t at = expanded.find("RECON"); at != std::string::npos; at = expanded.find("RECON", at + 1))
      expanded.replace(at, 5, shell_quoted(RECON_CLI_PATH));
    RunResult run;
    run.command = line;
    const fs::path out = work_folder().parent_path() / "shell_out.txt";
    const fs::path err = work_folder().parent_path() / "shell_err.txt";
    const std::string command = "cd " + shell_quoted(work_folder().string()) + " && timeout -k 5 " +
                                std::to_string(seconds) + " sh -c " + shell_quoted(expanded) + " >" +
                                shell_quoted(out.string()) + " 2>" + shell_quoted(err.string());
    const int status = std::system(command.c_str());
    if (status != -1 && WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
    if (fs::exists(out)) run.out = read_bytes(out);
    if (fs::exists(err)) run.err = read_bytes(err);
    return run;
  }
};

TEST_F(CliStreams, ReconstructReadsAPipeOnce) {
  // The 2D check read the pipe first, and the reader then found it empty.
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 1000, "s.xyz"));
  for (const std::string input : {"-", "/dev/stdin"}) {
    const RunResult run =
        shell("cat s.xyz | RECON --quiet reconstruct " + input + " --format xyz -o m.ply --stats st.json");
    ASSERT_EQ(run.exit_code, 0) << describe(run);
    EXPECT_GT(io::read_mesh(at("m.ply")).triangles.size(), 100U);
    EXPECT_EQ(stat_count(read_bytes(at("st.json")), "input", "points"), 1000) << input;
  }
  // 2D points from a pipe: the check and the reading see the same bytes.
  write_file(at("circle.txt"), circle_xy_text(Vec2(0.0, 0.0), 1.0, 200, 1));
  const RunResult curves = shell("cat circle.txt | RECON --quiet reconstruct - --format xyz -o c.obj");
  ASSERT_EQ(curves.exit_code, 0) << describe(curves);
  EXPECT_EQ(read_obj_curves(at("c.obj")).lines.size(), 1U);
  // Without --format, a stream has no extension to go by.
  const RunResult unnamed = shell("cat s.xyz | RECON reconstruct - -o n.ply");
  EXPECT_EQ(unnamed.exit_code, 1) << describe(unnamed);
  EXPECT_NE(unnamed.err.find("--format"), std::string::npos) << describe(unnamed);
}

TEST_F(CliStreams, ReconstructReadsAFifoOnce) {
  // From a FIFO the second open waited forever for a writer that was gone.
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 1000, "s.xyz"));
  ASSERT_EQ(::mkfifo(at("in.xyz").c_str(), 0600), 0);
  const RunResult run = shell(
      "cat s.xyz > in.xyz & RECON --quiet reconstruct in.xyz -o m.ply; status=$?; wait; "
      "exit $status",
      20);
  ASSERT_EQ(run.exit_code, 0) << describe(run);
  EXPECT_GT(io::read_mesh(at("m.ply")).triangles.size(), 100U);
  // A tiled run reads its input in passes: a stream is refused, not read as empty.
  const RunResult tiled = shell("cat s.xyz | RECON reconstruct - --format xyz -o t.ply --tile-size 0.5");
  EXPECT_EQ(tiled.exit_code, 1) << describe(tiled);
  EXPECT_NE(tiled.err.find("can be read only once"), std::string::npos) << describe(tiled);
}

TEST_F(CliStreams, OutputsThroughLinksAndFifosNeverReplaceThem) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 500, "s.xyz"));
  fs::create_directory(at("real"));
  write_file(at("real/st.json"), "{}\n");
  ASSERT_EQ(::chmod(at("real/st.json").c_str(), 0600), 0);
  fs::create_symlink("real/m.ply", at("m.ply"));      // dangling: its target is created
  fs::create_symlink("real/st.json", at("st.json"));  // an existing private file
  ASSERT_EQ(::mkfifo(at("report.fifo").c_str(), 0600), 0);
  const RunResult run = shell(
      "cat report.fifo > copy.html & RECON --quiet reconstruct s.xyz -o m.ply --stats st.json "
      "--report report.fifo; status=$?; wait; exit $status");
  EXPECT_EQ(run.exit_code, 0) << describe(run);
  const std::string report = read_bytes(at("copy.html"));
  EXPECT_TRUE(fs::is_symlink(at("m.ply")));
  EXPECT_TRUE(fs::is_symlink(at("st.json")));
  EXPECT_GT(io::read_mesh(at("real/m.ply")).triangles.size(), 50U);
  EXPECT_EQ(stat_count(read_bytes(at("real/st.json")), "input", "points"), 500);
  EXPECT_EQ(fs::status(at("real/st.json")).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_EQ(fs::status(at("report.fifo")).type(), fs::file_type::fifo);
  EXPECT_NE(report.find("<html"), std::string::npos) << report.substr(0, 200);
  EXPECT_EQ(entries(), (std::vector<std::string>{"copy.html", "m.ply", "real", "report.fifo", "s.xyz", "st.json"}));
}

TEST_F(CliStreams, ColumnsAreRefusedWhereTheyWouldBeIgnored) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 300, "s.ply"));
  EXPECT_TRUE(refused(recon({"info", "s.ply", "--columns", "z,y,x"}), {"s.ply: --columns applies to delimited text"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "s.ply", "-o", "m.ply", "--columns", "z,y,x"}),
                      {"--columns applies to delimited text"}));
  write_file(at("circle.txt"), circle_xy_text(Vec2(0.0, 0.0), 1.0, 100, 1));
  EXPECT_TRUE(
      refused(recon({"reconstruct", "circle.txt", "-o", "c.obj", "--columns", "x,y"}), {"--columns names 3D columns"}));
  EXPECT_EQ(entries(), (std::vector<std::string>{"circle.txt", "s.ply"}));
}

}  // namespace
}  // namespace recon

namespace recon {
namespace {

// --simplify and --max-error: bad values refused in one line naming the
// option, before anything is written; a tiled run refuses them (its mesh is
// never whole in memory); a good run reports before and after in --stats.
TEST_F(CliErrors, SimplifyRefusesBadValues) {
  generate("box", 3000, "box.ply");
  for (const char* bad : {"0", "-5", "1.5", "100%", "0%", "nan", "inf", "many"})
    EXPECT_TRUE(option_refused(recon({"reconstruct", "box.ply", "-o", "out.ply", "--simplify", bad}), "--simplify",
                               "expected a triangle count"))
        << bad;
  for (const char* bad : {"0", "-1", "nan"})
    EXPECT_TRUE(option_refused(recon({"reconstruct", "box.ply", "-o", "out.ply", "--max-error", bad}), "--max-error",
                               "greater than 0"))
        << bad;
  EXPECT_TRUE(refused(recon({"reconstruct", "box.ply", "-o", "out.ply", "--simplify", "99999999"}),
                      {"simplify to 99999999 triangles", "the mesh has only"}));
  EXPECT_TRUE(refused(recon({"reconstruct", "box.ply", "-o", "out.ply", "--simplify", "0.1", "--tile-size", "0.5"}),
                      {"tiled runs", "--simplify"}));
  EXPECT_FALSE(fs::exists(at("out.ply")));
  const RunResult run = recon({"reconstruct", "box.ply", "-o", "out.ply", "--simplify", "10%", "--max-error", "0.5",
                               "--stats", "stats.json", "-q"});
  ASSERT_TRUE(succeeded(run));
  const std::string stats = read_bytes(at("stats.json"));
  EXPECT_NE(stats.find("\"triangles_before\""), std::string::npos);
  EXPECT_NE(stats.find("\"triangles_after\""), std::string::npos);
  EXPECT_NE(stats.find("\"vertex_error_rho\""), std::string::npos);
}

// `recon simplify` is phase VI alone, on a mesh read from a file: a mesh
// reconstructed and then simplified is, byte for byte, the one
// `reconstruct --simplify` writes; and a tiled run's mesh (never whole in
// memory, so `reconstruct` refuses to simplify it) simplifies to the
// in-memory run's simplified mesh, though the stitch numbers its vertices
// otherwise (simplify() works on a numbering of its own).
class CliSimplify : public CliTest {};

TEST_F(CliSimplify, AMeshFromAFileSimplifiesAsInReconstruct) {
  ASSERT_NO_FATAL_FAILURE(generate("box", 6000, "box.ply"));
  ASSERT_TRUE(succeeded(recon({"-q", "reconstruct", "box.ply", "-o", "direct.ply", "--simplify", "300"})));
  ASSERT_TRUE(succeeded(recon({"-q", "reconstruct", "box.ply", "-o", "full.ply"})));
  const RunResult run = recon({"simplify", "full.ply", "-o", "after.ply", "--to", "300", "--stats", "s.json"});
  ASSERT_TRUE(succeeded(run)) << describe(run);
  EXPECT_NE(run.out.find("phase VI  simplification: "), std::string::npos) << run.out;
  EXPECT_EQ(read_bytes(at("after.ply")), read_bytes(at("direct.ply")));
  const std::string json = read_bytes(at("s.json"));
  EXPECT_LE(stat(json, "simplification", "triangles_after").value_or(1e9), 300.0);
  EXPECT_EQ(stat(json, "read", "triangles"), static_cast<double>(io::read_mesh(at("full.ply")).triangles.size()));
}

// --normals on `recon simplify`: a unit normal per vertex of the result
// (the input PLY has none: all from the final faces).
TEST_F(CliSimplify, NormalsAreWrittenWhenAsked) {
  ASSERT_NO_FATAL_FAILURE(generate("box", 6000, "box.ply"));
  ASSERT_TRUE(succeeded(recon({"-q", "reconstruct", "box.ply", "-o", "full.ply"})));
  ASSERT_TRUE(succeeded(recon({"-q", "simplify", "full.ply", "-o", "plain.ply", "--to", "300"})));
  EXPECT_FALSE(io::read_mesh(at("plain.ply")).has_normals());
  ASSERT_TRUE(succeeded(recon({"-q", "simplify", "full.ply", "-o", "n.ply", "--to", "300", "--normals"})));
  const Mesh mesh = io::read_mesh(at("n.ply"));
  ASSERT_EQ(mesh.normals.size(), mesh.vertices.size());
  for (const Vec3& n : mesh.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-6);
}

TEST_F(CliSimplify, ATiledMeshSimplifiesToTheInMemoryOne) {
  ASSERT_NO_FATAL_FAILURE(generate("terrain", 15000, "t.ply"));
  ASSERT_TRUE(succeeded(recon({"-q", "reconstruct", "t.ply", "-o", "whole.ply", "--simplify", "10%"})));
  ASSERT_TRUE(succeeded(recon({"-q", "reconstruct", "t.ply", "-o", "tiled.ply", "--tile-size", "0.5"})));
  ASSERT_TRUE(succeeded(recon({"-q", "simplify", "tiled.ply", "-o", "after.ply", "--to", "10%"})));
  EXPECT_TRUE(same_mesh(io::read_mesh(at("after.ply")), io::read_mesh(at("whole.ply")), 0.0));
}

TEST_F(CliSimplify, BadRequestsAreOneLineErrorsAndWriteNothing) {
  ASSERT_NO_FATAL_FAILURE(generate("box", 3000, "box.ply"));
  ASSERT_TRUE(succeeded(recon({"-q", "reconstruct", "box.ply", "-o", "m.ply"})));
  EXPECT_TRUE(refused(recon({"simplify", "m.ply", "-o", "out.ply"}), {"give --to", "--max-distance"}));
  EXPECT_TRUE(refused(recon({"simplify", "m.ply", "-o", "out.ply", "--to", "99999999"}),
                      {"m.ply", "cannot simplify to 99999999 triangles", "the mesh has only"}));
  EXPECT_TRUE(
      option_refused(recon({"simplify", "m.ply", "-o", "out.ply", "--to", "0"}), "--to", "expected a triangle count"));
  EXPECT_TRUE(option_refused(recon({"simplify", "m.ply", "-o", "out.ply", "--max-distance", "-1"}), "--max-distance",
                             "greater than 0"));
  EXPECT_TRUE(refused(recon({"simplify", "missing.ply", "-o", "out.ply", "--to", "10"}), {"missing.ply"}));
  EXPECT_TRUE(refused(recon({"simplify", "box.ply", "-o", "out.ply", "--to", "10"}), {"box.ply"}));  // points, no faces
  EXPECT_TRUE(refused(recon({"simplify", "m.ply", "-o", "m.ply", "--to", "10"}), {"m.ply"}));        // the input
  EXPECT_FALSE(fs::exists(at("out.ply")));
  EXPECT_TRUE(refused(recon({"reconstruct", "box.ply", "-o", "t.ply", "--simplify", "10", "--tile-size", "0.5"}),
                      {"recon simplify"}));
}

}  // namespace
}  // namespace recon
