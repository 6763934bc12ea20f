// ReadPointsOptions::skip_invalid, for every point reader: the points a
// reader would refuse (a coordinate that is NaN, infinite or beyond
// +-max_coordinate) are left out instead, and a note says how many and
// where the first was, in the words of the refusal. The oracle is the
// refusal itself: the same file read without the option.
// (LAS and PCD have cases of their own in las_test.cpp and pcd_test.cpp.)

#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

PointCloud read_skipping(const std::filesystem::path& path, ReadNotes& notes) {
  return testing::read_with_notes(path, notes, true);
}

std::string binary_ply() {
  Bytes bytes;
  bytes.text(
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property double z\nend_header\n");
  bytes.put(0.0).put(0.0).put(0.0);
  bytes.put(1.0).put(-std::numeric_limits<double>::infinity()).put(1.0);
  bytes.put(2.0).put(2.0).put(2.0);
  bytes.put(3e15).put(3.0).put(3.0);
  return bytes.str();
}

TEST(BadCoordinatesSkipped, EveryReaderLeavesOutWhatItWouldRefuse) {
  struct Case {
    std::string name;
    std::string content;
  };
  const std::vector<Case> cases = {
      {"a.xyz", "0 0 0\n1 nan 1\n2 2 2\n1e300 0 0\n"},
      {"a.pts", "p 0 0 0\np 1 nan 1\np 2 2 2\np 1e300 0 0\n"},
      {"a.obj", "v 0 0 0\nv 1 nan 1\nv 2 2 2\nv 1e300 0 0\nf 1 2 3\n"},
      {"a.off", "OFF\n4 1 0\n0 0 0\n1 nan 1\n2 2 2\n1e300 0 0\n3 0 1 2\n"},
      {"a.ply",
       "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
       "end_header\n0 0 0\n1 nan 1\n2 2 2\n-inf 0 0\n"},
      {"b.ply", binary_ply()},
      {"a.pcd", "FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nPOINTS 4\nDATA ascii\n0 0 0\n1 nan 1\n2 2 2\n1e300 0 0\n"},
  };
  TempFolder folder;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::filesystem::path path = folder / c.name;
    write_file(path, c.content);
    const std::string refusal = point_read_error(path);
    ASSERT_EQ(refusal.substr(0, path.string().size() + 2), path.string() + ": ");
    EXPECT_CONTAINS(refusal, "2 points have a coordinate that is not finite or beyond +-1e+15; the first at ");

    ReadNotes notes;
    const PointCloud cloud = read_skipping(path, notes);
    ASSERT_EQ(cloud.size(), 2U);
    EXPECT_EQ(cloud.positions[0], Vec3(0, 0, 0));
    EXPECT_EQ(cloud.positions[1], Vec3(2, 2, 2));
    EXPECT_EQ(notes.skipped_points, 2U);
    ASSERT_EQ(notes.lines.size(), 1U);
    EXPECT_EQ(notes.lines[0], "skipped as invalid: " + refusal.substr(path.string().size() + 2));
  }
}

TEST(BadCoordinatesSkipped, NormalsStayWithTheirPoints) {
  TempFolder folder;
  // The skipped point's normal is not checked; the others keep theirs.
  write_file(folder / "n.xyz", "0 0 0 0 0 1\n1 inf 1 nan 0 0\n2 2 2 0 1 0\n");
  ReadNotes notes;
  const PointCloud cloud = read_skipping(folder / "n.xyz", notes);
  ASSERT_EQ(cloud.size(), 2U);
  ASSERT_EQ(cloud.normals.size(), 2U);
  EXPECT_EQ(cloud.normals[0], Vec3(0, 0, 1));
  EXPECT_EQ(cloud.normals[1], Vec3(0, 1, 0));
  EXPECT_EQ(notes.skipped_points, 1U);

  // A bad normal of a kept point is still refused.
  write_file(folder / "m.xyz", "0 0 0 0 0 1\n1 inf 1 0 0 1\n2 2 2 0 nan 0\n");
  const std::string message =
      message_of<ParseError>([&] { static_cast<void>(read_skipping(folder / "m.xyz", notes)); });
  EXPECT_EQ(message, (folder / "m.xyz").string() +
                         ": 1 point has a normal that is not finite (NaN or infinity); the first at line 3 (ny = nan)");
}

TEST(BadCoordinatesSkipped, NothingLeftIsNoPoints) {
  TempFolder folder;
  write_file(folder / "all.xyz", "nan 0 0\n1 inf 1\n");
  const std::string message = message_of<ParseError>([&] {
    ReadNotes notes;
    static_cast<void>(read_skipping(folder / "all.xyz", notes));
  });
  EXPECT_EQ(message, (folder / "all.xyz").string() +
                         ": no points: every point is invalid (2 points have a coordinate that is not finite or beyond "
                         "+-1e+15; the first at line 1 (x = nan))");
}

TEST(BadCoordinatesSkipped, AGoodFileIsReadAsItIs) {
  TempFolder folder;
  write_file(folder / "g.xyz", "0 0 0\n1 1 1\n");
  ReadNotes notes;
  EXPECT_EQ(read_skipping(folder / "g.xyz", notes).size(), 2U);
  EXPECT_TRUE(notes.lines.empty());
  EXPECT_EQ(notes.skipped_points, 0U);
}

}  // namespace
}  // namespace recon::io
