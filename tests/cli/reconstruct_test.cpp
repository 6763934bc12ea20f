// The `recon` program, end to end: `normals` and `reconstruct` (the mesh
// formats, what is printed, the lattice options, the same output whatever the
// thread count).

#include "cli/cli_helpers.h"
#include "conics_truth.h"

#include "recon/estimate_normals.h"

namespace recon {
namespace {

using namespace cli_testing;

// ---------------------------------------------------------------- normals

using CliNormals = CliTest;

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

// Issue 27: `recon normals` gives the refined normals, as reconstruct
// orients them; the 1992 walk (--method hoppe92) turns the tall narrow cone
// inside out, as it always did. The stats say which method ran.
TEST_F(CliNormals, TheDefaultGetsEveryConicRightAndHoppe92IsAsItWas) {
  ASSERT_TRUE(succeeded(recon({"--quiet", "generate", "conics", "--with-normals", "-o", "c.ply"})));
  const RunResult run = recon({"normals", "c.ply", "-o", "n.ply", "--stats", "n.json"});
  ASSERT_TRUE(succeeded(run));
  EXPECT_EQ(lines_starting_with(run.out, "          second-order fits: ").size(), 1U) << run.out;
  ASSERT_TRUE(
      succeeded(recon({"--quiet", "normals", "c.ply", "-o", "h.ply", "--method", "hoppe92", "--stats", "h.json"})));
  EXPECT_NE(read_bytes(at("n.json")).find("\"method\": \"refined\""), std::string::npos);
  EXPECT_NE(read_bytes(at("h.json")).find("\"method\": \"hoppe92\""), std::string::npos);

  const PointCloud truth = io::read_points(at("c.ply"));
  const std::vector<double> refined = testing::right_per_conic(truth, io::read_points(at("n.ply")).normals);
  for (std::size_t p = 0; p < refined.size(); ++p) EXPECT_GE(refined[p], 0.99) << "piece " << p;
  EXPECT_LT(testing::right_per_conic(truth, io::read_points(at("h.ply")).normals)[0], 0.05) << "the tall cone, hoppe92";
}

// Issue 27: `recon normals` faces the hollow ball's inner wall into the
// cavity and the ball inside it out again, and says so in its stats.
TEST_F(CliNormals, NestedWallsFaceTheTrueWay) {
  ASSERT_TRUE(succeeded(recon({"--quiet", "generate", "nested", "-n", "30000", "--with-normals", "-o", "b.ply"})));
  ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "b.ply", "-o", "n.ply", "--stats", "n.json"})));
  const std::vector<double> right =
      testing::right_per_ball(io::read_points(at("b.ply")), io::read_points(at("n.ply")).normals, 3);
  for (std::size_t w = 0; w < right.size(); ++w) EXPECT_GE(right[w], 0.99) << "wall " << w;
  EXPECT_NE(read_bytes(at("n.json")).find("\"pieces_nested\": 2"), std::string::npos);
  EXPECT_NE(read_bytes(at("n.json")).find("\"nested_turned\": 1"), std::string::npos);
}

// The normals written are estimate_normals()'s of the method asked for
// (estimate_normals_test.cpp: reconstruct()'s phase II normals, and for
// hoppe92 the paper's phases called plainly), bit for bit, in input order.
TEST_F(CliNormals, EachMethodWritesTheLibrarysNormals) {
  ASSERT_TRUE(succeeded(recon({"--quiet", "generate", "part", "-n", "20000", "-o", "p.ply"})));
  const PointCloud cloud = io::read_points(at("p.ply"));
  for (const Method method : {Method::refined, Method::hoppe92}) {
    ASSERT_TRUE(succeeded(recon({"--quiet", "normals", "p.ply", "-o", "n.ply", "--method", method_name(method)})));
    NormalEstimationOptions options;
    options.method = method;
    EXPECT_TRUE(io::read_points(at("n.ply")).normals == estimate_normals(cloud, options).normals_in_input_order())
        << method_name(method);
  }
}

TEST_F(CliNormals, AnUnknownMethodIsRefusedInOneLine) {
  ASSERT_NO_FATAL_FAILURE(generate("sphere", 500, "s.ply"));
  EXPECT_TRUE(option_refused(recon({"normals", "s.ply", "-o", "n.ply", "--method", "sideways"}), "--method",
                             "sideways not in {refined,hoppe92}"));
  EXPECT_EQ(entries(), std::vector<std::string>{"s.ply"});
}

// ---------------------------------------------------------------- reconstruct

using CliReconstruct = CliTest;

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

using CliOutput = CliTest;

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

using CliLattice = CliTest;

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

// ---------------------------------------------------------------- determinism

using CliDeterminism = CliTest;

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

}  // namespace
}  // namespace recon
