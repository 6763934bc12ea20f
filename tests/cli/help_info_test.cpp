// The `recon` program, end to end: help and version, `info`, the columns of
// text files, `generate`, `lab`, and the real clouds of the course.

#include "cli/cli_helpers.h"

namespace recon {
namespace {

using namespace cli_testing;

// ---------------------------------------------------------------- help

using CliHelp = CliTest;

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
      {"normals", {"input", "--format", "--output", "--k", "--rho", "--ascii", "--stats", "--method", "hoppe92"}},
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

// ---------------------------------------------------------------- info

using CliInfo = CliTest;
using CliErrors = CliTest;

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

using CliTextColumns = CliTest;

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

// --scan: a range scanner's cloud, about -n points, with the true normals
// of the points it hit and the whole surface as the truth.
TEST_F(CliGenerate, ScanWritesWhatTheViewsSeeWithTheWholeTruth) {
  const RunResult run = recon({"generate", "box", "--scan", "3", "-n", "3000", "--noise", "0.002", "--with-normals",
                               "-o", "b.ply", "--truth", "gt.ply", "--truth-points", "6000"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_NE(run.out.find("scanned from 3 views of 'box'"), std::string::npos) << describe(run);
  const PointCloud cloud = io::read_points(at("b.ply")), truth = io::read_points(at("gt.ply"));
  EXPECT_GT(cloud.size(), 2000U);
  EXPECT_LT(cloud.size(), 4000U);
  ASSERT_TRUE(cloud.has_normals());
  for (const Vec3& n : cloud.normals) ASSERT_GT(n.z(), -0.5);  // the views stand above: no bottom face
  std::size_t bottom = 0;
  for (const Vec3& n : truth.normals) bottom += n.z() < -0.5 ? 1U : 0U;
  EXPECT_GT(bottom, 500U);  // the truth has it
}

TEST_F(CliGenerate, BadScanAndThicknessOptionsAreRefusedBeforeWriting) {
  EXPECT_TRUE(option_refused(recon({"generate", "box", "--scan", "0", "-o", "b.ply"}), "--scan", "not in range"));
  EXPECT_TRUE(option_refused(recon({"generate", "box", "--scan", "65", "-o", "b.ply"}), "--scan", "not in range"));
  const RunResult lone = recon({"generate", "box", "--misregistration", "0.01", "-o", "b.ply"});
  EXPECT_EQ(lone.exit_code, 2) << describe(lone);
  EXPECT_NE(lone.err.find("--misregistration requires --scan"), std::string::npos) << describe(lone);
  EXPECT_TRUE(
      refused(recon({"generate", "torus", "--thickness", "0.1", "-o", "t.ply"}), {"shape 'torus' has no thickness"}));
  EXPECT_TRUE(refused(recon({"generate", "club", "--thickness", "0.2", "-o", "c.ply"}),
                      {"thickness 0.2 out of range for 'club': it must lie strictly between 0 and 0.1"}));
  EXPECT_TRUE(
      option_refused(recon({"generate", "plate", "--thickness", "nan", "-o", "p.ply"}), "--thickness", "found 'nan'"));
  EXPECT_TRUE(entries().empty());
}

TEST_F(CliGenerate, ThinSolidsTakeTheirThickness) {
  ASSERT_TRUE(succeeded(recon({"--quiet", "generate", "plate", "--thickness", "0.01", "-n", "2000", "-o", "p.xyz"})));
  double top = 0.0;
  for (const Vec3& p : io::read_points(at("p.xyz")).positions) top = std::max(top, p.z());
  EXPECT_NEAR(top, 0.005, 1e-12);
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

using CliRealData = CliTest;

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

}  // namespace
}  // namespace recon
