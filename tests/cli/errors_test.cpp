// The `recon` program, end to end: bad input and bad options, each refused in
// one line with an exit status, and the limits of numbers, lengths, threads
// and memory (issue 28).

#include "cli/cli_helpers.h"

namespace recon {
namespace {

using namespace cli_testing;

// ---------------------------------------------------------------- errors

using CliErrors = CliTest;

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
  // 370 bytes a point at k = 20, and the refined method's fits (normals do
  // not work in tiles).
  EXPECT_TRUE(refused(recon({"normals", "s.ply", "-o", "n.ply", "--max-memory", "2MB"}), {"8.2 MB", "lower --k"}));
  EXPECT_TRUE(refused(recon({"normals", "s.ply", "-o", "n.ply", "--method", "hoppe92", "--max-memory", "2MB"}),
                      {"7.4 MB", "lower --k"}));
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

// ---------------------------------------------------------------- limits (issue 28)
// Numbers, bounds and the messages about them: every numeric option refuses
// NaN, infinities, negatives and the out-of-range in one readable line; a
// huge tile size is one tile; a run that finds no surface is an error that
// says why; a thread count past the machine is refused before any thread
// starts; a memory limit too small for a tiled run's statistics says so.

using CliLimits = CliTest;

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

}  // namespace
}  // namespace recon
