// The `recon` program, end to end: outputs never half-written, streams and
// special files (pipes, FIFOs, links), and the report page.

#include "cli/cli_helpers.h"

namespace recon {
namespace {

using namespace cli_testing;

// ---------------------------------------------------------------- never half-written

using CliAtomicOutput = CliTest;

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

// ---------------------------------------------------------------- report

using CliReport = CliTest;
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

// The base64 arrays of a report page, in the order of their ids
// (recon-array-0, -1, ...).
std::vector<std::string> report_arrays(const std::string& page) {
  std::vector<std::string> arrays;
  for (;;) {
    const std::string tag = "<script id=\"recon-array-" + std::to_string(arrays.size()) + "\"";
    const std::size_t start = page.find('>', page.find(tag));
    if (page.find(tag) == std::string::npos || start == std::string::npos) return arrays;
    arrays.push_back(page.substr(start + 1, page.find("</script>", start) - start - 1));
  }
}

// Issue 27: `recon normals --report` draws the walk reconstruct's phase II
// made: layers 1-5 (points, planes, the graph and its tree, the oriented
// normals, drawn first) are the reconstruct report's, byte for byte; in
// hoppe92 they are not (its planes and walk are the 1992 ones).
TEST_F(CliReport, NormalsDrawsTheWalkOfReconstructsPhaseTwo) {
  ASSERT_TRUE(succeeded(recon({"--quiet", "generate", "conics", "-n", "4000", "-o", "c.ply"})));
  ASSERT_TRUE(succeeded(recon({"--quiet", "reconstruct", "c.ply", "-o", "m.ply", "--report", "m.html"})));
  ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "c.ply", "-o", "n.ply", "--report", "n.html"})));
  ASSERT_TRUE(
      succeeded(recon({"--quiet", "normals", "c.ply", "-o", "h.ply", "--method", "hoppe92", "--report", "h.html"})));
  const std::vector<std::string> mesh = report_arrays(read_bytes(at("m.html")));
  const std::vector<std::string> refined = report_arrays(read_bytes(at("n.html")));
  const std::vector<std::string> hoppe92 = report_arrays(read_bytes(at("h.html")));
  ASSERT_GE(refined.size(), 13U);  // points (8 arrays), kd-tree (2), graph (3)
  ASSERT_EQ(hoppe92.size(), refined.size());
  ASSERT_GT(mesh.size(), refined.size());  // and the lattice and meshes
  std::size_t differ = 0;
  for (std::size_t i = 0; i < refined.size(); ++i) {
    EXPECT_TRUE(refined[i] == mesh[i]) << "array " << i;
    if (hoppe92[i] != refined[i]) ++differ;
  }
  EXPECT_GT(differ, 0U);
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
