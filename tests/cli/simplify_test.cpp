// The `recon` program, end to end: phase VI, `reconstruct --simplify` and
// `recon simplify`.

#include "cli/cli_helpers.h"

namespace recon {
namespace {

using namespace cli_testing;

// A suite name per theme, so that --gtest_filter can pick one.
using CliErrors = CliTest;

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
