// The `recon` program, end to end: curves in the plane (2D input).

#include "cli/cli_helpers.h"

namespace recon {
namespace {

using namespace cli_testing;

using CliCurves = CliTest;

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

}  // namespace
}  // namespace recon
