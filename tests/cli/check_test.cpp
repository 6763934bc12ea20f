// The `recon` program, end to end: `recon check` (mesh_embedding.h) on meshes
// written by hand, one a rule, and on a mesh recon reconstructed.

#include "cli/cli_helpers.h"

#include <gtest/gtest.h>

namespace recon::cli_testing {
namespace {

class CliCheck : public CliTest {};

// Two triangles: the second crossing the first, or beside it.
std::string two_triangles(double z) {
  return "ply\nformat ascii 1.0\nelement vertex 6\nproperty double x\nproperty double y\nproperty double z\n"
         "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n4 0 0\n0 4 0\n1 1 " +
         std::to_string(z) + "\n1 1 1\n2 1 1\n3 0 1 2\n3 3 4 5\n";
}

TEST_F(CliCheck, CountsAndExitStatus) {
  write_file(at("apart.ply"), two_triangles(0.5));
  const RunResult good = recon({"check", "apart.ply"});
  ASSERT_TRUE(succeeded(good));
  EXPECT_NE(good.out.find("0 intersecting triangle pairs"), std::string::npos) << good.out;
  EXPECT_NE(good.out.find(": embedded"), std::string::npos) << good.out;
  write_file(at("crossing.ply"), two_triangles(-1.0));
  const RunResult bad = recon({"check", "crossing.ply"});
  EXPECT_TRUE(refused(bad, {"crossing.ply", "not embedded", "1 intersecting triangle pairs"}));
  EXPECT_NE(bad.out.find("1 intersecting triangle pairs"), std::string::npos) << bad.out;
  EXPECT_TRUE(refused(recon({"check", "missing.ply"}), {"missing.ply"}));
}

// The part (creases, corners, holes): by default the refined mesh crosses
// itself where phase V sharpened its creases, and the check says so; with
// --embedded it does not; hoppe92's mesh (phase IV's) is embedded as it is.
TEST_F(CliCheck, AReconstructedPartIsEmbeddedWhenAsked) {
  ASSERT_TRUE(succeeded(recon({"-q", "generate", "part", "-n", "6000", "-o", "part.ply"})));
  ASSERT_TRUE(succeeded(recon({"-q", "reconstruct", "part.ply", "-o", "mesh.ply"})));
  EXPECT_TRUE(refused(recon({"-q", "check", "mesh.ply"}), {"mesh.ply", "not embedded", "intersecting"}));
  ASSERT_TRUE(succeeded(recon({"-q", "reconstruct", "part.ply", "--embedded", "-o", "embedded.ply"})));
  EXPECT_TRUE(succeeded(recon({"-q", "check", "embedded.ply"})));
  ASSERT_TRUE(succeeded(recon({"-q", "reconstruct", "part.ply", "--method", "hoppe92", "-o", "hoppe92.ply"})));
  EXPECT_TRUE(succeeded(recon({"-q", "check", "hoppe92.ply"})));
}

}  // namespace
}  // namespace recon::cli_testing
