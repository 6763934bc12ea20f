// 2D points in (two columns, Hoppe's x = 0 records, flat 3D files) and
// curves out (SVG, OBJ polylines, plain text), with their errors.

#include "recon/io/curve_io.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

PolylineSet square_and_hook() {
  PolylineSet set;
  set.vertices = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1), Vec2(3, 0), Vec2(3, 2.5)};
  set.polylines = {{{0, 1, 2, 3}, true}, {{4, 5}, false}};
  return set;
}

TEST(CurveIo, TwoColumnsAreRead) {
  TempFolder folder;
  const std::vector<Vec2> points =
      read_2d_text(folder, "a.txt", "# x y\n0.5 1.5\n\n-2, 3e-1  # comma and comment\n4 5\n");
  ASSERT_EQ(points.size(), 3U);
  EXPECT_EQ(points[0], Vec2(0.5, 1.5));
  EXPECT_EQ(points[1], Vec2(-2.0, 0.3));
  EXPECT_EQ(points[2], Vec2(4.0, 5.0));
}

TEST(CurveIo, HoppePtsWithConstantXIsReadAsYZ) {
  TempFolder folder;
  const std::vector<Vec2> points = read_2d_text(folder, "c.pts", "p 0 0.25 0.5\np 0 0.75 1\n# comment\np 0 1 -2\n");
  ASSERT_EQ(points.size(), 3U);
  EXPECT_EQ(points[0], Vec2(0.25, 0.5));
  EXPECT_EQ(points[2], Vec2(1.0, -2.0));
  // A 3D .pts (x varies) is not taken for 2D.
  write_file(folder / "d.pts", "p 0 0.25 0.5\np 1 0.75 1\np 0 1 -2\n");
  EXPECT_FALSE(holds_2d_points(folder / "d.pts"));
}

TEST(CurveIo, FlatThreeColumnsAreReadWhenAsked) {
  TempFolder folder;
  write_file(folder / "z.xyz", "1 2 5\n3 4 5\n5 6 5\n");
  EXPECT_FALSE(holds_2d_points(folder / "z.xyz"));  // a flat surface unless curves are asked for
  const std::vector<Vec2> points = read_points_2d(folder / "z.xyz");
  ASSERT_EQ(points.size(), 3U);
  EXPECT_EQ(points[1], Vec2(3.0, 4.0));
  write_file(folder / "y.xyz", "1 -1 5\n3 -1 6\n5 -1 7\n");
  EXPECT_EQ(read_points_2d(folder / "y.xyz")[2], Vec2(5.0, 7.0));
}

TEST(CurveIo, BadFilesNameTheFileAndLine) {
  TempFolder folder;
  write_file(folder / "mixed.txt", "0 0\n1 1\n2 2 2\n");
  EXPECT_CONTAINS(message_of<ParseError>([&] { (void)read_points_2d(folder / "mixed.txt"); }),
                  "mixed.txt:3: expected 2 numbers (x y) on a line, found 3");
  write_file(folder / "word.txt", "0 0\n1 one\n");
  EXPECT_CONTAINS(message_of<ParseError>([&] { (void)read_points_2d(folder / "word.txt"); }), "word.txt:2:");
  write_file(folder / "nan.txt", "0 0\n1 nan\n2 2\n");
  EXPECT_CONTAINS(message_of<ParseError>([&] { (void)read_points_2d(folder / "nan.txt"); }),
                  "1 point has a coordinate that is not finite");
  write_file(folder / "solid.xyz", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
  EXPECT_CONTAINS(message_of<ParseError>([&] { (void)read_points_2d(folder / "solid.xyz"); }), "not 2D");
  write_file(folder / "empty.txt", "");
  EXPECT_CONTAINS(message_of<ParseError>([&] { (void)read_points_2d(folder / "empty.txt"); }), "empty");
  EXPECT_THROW((void)read_points_2d(folder / "missing.txt"), IoError);
}

TEST(CurveIo, ObjHasOneLineStatementPerCurveClosedOnesEndingAtTheirStart) {
  TempFolder folder;
  write_curves(folder / "c.obj", square_and_hook());
  std::istringstream text(read_bytes(folder / "c.obj"));
  std::vector<std::string> v_lines, l_lines;
  for (std::string line; std::getline(text, line);) {
    if (line.starts_with("v ")) v_lines.push_back(line);
    if (line.starts_with("l ")) l_lines.push_back(line);
  }
  ASSERT_EQ(v_lines.size(), 6U);
  EXPECT_EQ(v_lines[5], "v 3 2.5 0");
  EXPECT_EQ(l_lines, (std::vector<std::string>{"l 1 2 3 4 1", "l 5 6"}));
}

TEST(CurveIo, TextRepeatsTheFirstVertexOfClosedCurves) {
  TempFolder folder;
  write_curves(folder / "c.txt", square_and_hook());
  const std::string text = read_bytes(folder / "c.txt");
  EXPECT_CONTAINS(
      text, "# curve 1: closed, 4 vertices\n0 0\n1 0\n1 1\n0 1\n0 0\n\n# curve 2: open, 2 vertices\n3 0\n3 2.5\n");
}

TEST(CurveIo, SvgDrawsPointsNormalsAndCurvesWithYUp) {
  TempFolder folder;
  const std::vector<Vec2> points{Vec2(0, 0), Vec2(1, 1)}, normals{Vec2(0, 1), Vec2(1, 0)};
  WriteCurvesOptions options;
  options.points = points;
  options.normals = normals;
  options.normal_length = 0.5;
  write_curves(folder / "c.svg", square_and_hook(), options);
  const std::string svg = read_bytes(folder / "c.svg");
  EXPECT_CONTAINS(svg, "<path class=\"closed\" d=\"M0,0 L1,0 L1,-1 L0,-1 Z\"/>");
  EXPECT_CONTAINS(svg, "<path class=\"open\" d=\"M3,0 L3,-2.5\"/>");
  EXPECT_CONTAINS(svg, "<path d=\"M0,0 L0,-0.5\"/>");  // the first normal, pointing up
  EXPECT_CONTAINS(svg, "<circle cx=\"1\" cy=\"-1\"");
}

TEST(CurveIo, BadCurvesAreRefusedBeforeAnyFileIsMade) {
  TempFolder folder;
  PolylineSet bad = square_and_hook();
  bad.vertices[2].x() = std::numeric_limits<double>::infinity();
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_curves(folder / "a.svg", bad); }), "vertex 2");
  bad = square_and_hook();
  bad.polylines[1].vertices.push_back(17);
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_curves(folder / "b.obj", bad); }), "uses vertex 17");
  const std::vector<Vec2> points(3, Vec2::Zero()), normals(2, Vec2::UnitX());
  WriteCurvesOptions options;
  options.points = points;
  options.normals = normals;
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_curves(folder / "c.svg", square_and_hook(), options); }),
                  "2 normals for 3 points");
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_curves(folder / "d.ply", square_and_hook()); }),
                  "known curve formats");
  EXPECT_TRUE(folder.entries().empty());
  EXPECT_THROW(write_curves(folder / "no" / "e.svg", square_and_hook()), IoError);
  EXPECT_TRUE(folder.entries().empty());
}

}  // namespace
}  // namespace recon::io
