// The `recon` program, end to end: tiled runs (--tile-size, --max-memory).

#include "cli/cli_helpers.h"

namespace recon {
namespace {

using namespace cli_testing;

using CliTiles = CliTest;

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

}  // namespace
}  // namespace recon
