// The report's page (write_report): arrays that round-trip, colours, a page
// written whole or not at all, and the lab panel. The layers are tested in
// report_test.cpp.
#include "recon/report/report.h"

#include "hand_made_lab.h"
#include "mesh_compare.h"
#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/reconstruct.h"
#include "recon/structures/mesh.h"
#include "report_test_helpers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>

namespace recon {
namespace {

using namespace report_testing;

// ---- the page

std::vector<unsigned char> base64_decode(std::string_view text) {
  auto digit = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  std::vector<unsigned char> out;
  unsigned value = 0;
  int bits = 0;
  for (const char c : text) {
    const int d = digit(c);
    if (d < 0) break;  // '=' padding
    value = (value << 6) | static_cast<unsigned>(d);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((value >> bits) & 0xff));
    }
  }
  return out;
}

template <class T>
std::vector<T> decode(std::string_view html, int array) {
  const auto raw = base64_decode(element(html, "recon-array-" + std::to_string(array)));
  std::vector<T> values(raw.size() / sizeof(T));
  std::memcpy(values.data(), raw.data(), values.size() * sizeof(T));
  return values;
}

TEST(ReportPage, ArraysRoundTripThroughThePage) {
  const Reconstruction& r = open_and_closed();
  ReportOptions options;
  options.title = "half </script><script>alert(1)</script> & whole";
  options.stats_json = R"({"note":"a </script> in a string","n":3})";
  const ReportLayers layers = make_report_layers(report_input(r), options);
  const std::string html = report_html(layers, options);
  // The viewer is in the page and the data elements sit before it.
  const auto data_at = html.find("id=\"recon-data\"");
  ASSERT_NE(data_at, std::string::npos);
  EXPECT_LT(data_at, html.rfind("<script>"));
  EXPECT_NE(html.find("recon report"), std::string::npos);
  // Nothing in the data ends its element early: each data element holds
  // exactly one "</script>", its own.
  const std::string_view json = element(html, "recon-data");
  EXPECT_EQ(json.find('<'), std::string_view::npos);
  EXPECT_NE(json.find("half \\u003c/script>\\u003cscript>alert(1)\\u003c/script> & whole"), std::string_view::npos);
  EXPECT_NE(json.find("\"stats\":{\"note\":\"a \\u003c/script> in a string\",\"n\":3}"), std::string_view::npos);
  // The arrays are numbered in the order written: points.position is 0,
  // points.component 1, ..., kdtree.boxes 8.
  EXPECT_NE(json.find("\"position\":0,\"component\":1,\"origin\":2,\"pca_normal\":3"), std::string_view::npos);
  EXPECT_EQ(decode<float>(html, 0), layers.points);
  EXPECT_EQ(decode<std::uint32_t>(html, 1), layers.component);
  EXPECT_EQ(decode<std::int8_t>(html, 3), layers.pca_normals);
  EXPECT_EQ(decode<float>(html, 8), layers.kdtree_boxes);
  // ... graph 10-12, corners 13-14, mesh 15-17, refinement 18-20 and its distances 21.
  EXPECT_EQ(decode<float>(html, 14).size(), layers.corner_values.size());
  EXPECT_EQ(decode<std::uint32_t>(html, 16), layers.mesh.triangles);
  EXPECT_EQ(decode<float>(html, 17), layers.mesh.boundary_segments);
  EXPECT_EQ(decode<float>(html, 18), layers.refined.vertices);
  EXPECT_EQ(decode<std::uint32_t>(html, 19), layers.refined.triangles);
  EXPECT_EQ(decode<float>(html, 21), layers.refined_distance);
  EXPECT_TRUE(element(html, "recon-array-22").empty());
  EXPECT_NE(json.find("\"distance\":{\"value\":21,\"mean\":"), std::string_view::npos);
  EXPECT_NE(json.find("\"drawn_box\":{\"min\":["), std::string_view::npos);
}

// A run whose input had colours: layer 1 carries each drawn point's, and
// the final mesh's layer (8, or 7 in hoppe92) each drawn vertex's, within
// the budgets; the page holds them as arrays the JSON names. A run without
// colours has no such keys.
const Reconstruction& colored_sphere(Method method) {
  static const auto make = [](Method m) {
    PointCloud cloud = make_sphere()->sample(4000, 22);
    for (const Vec3& p : cloud.positions)
      cloud.colors.push_back(
          {static_cast<std::uint8_t>(p.z() > 0.0 ? 255 : 0), static_cast<std::uint8_t>(p.x() > 0.0 ? 200 : 20), 0});
    ReconstructionOptions options;
    options.method = m;
    return reconstruct(cloud, options);
  };
  static const Reconstruction refined = make(Method::refined), hoppe92 = make(Method::hoppe92);
  return method == Method::refined ? refined : hoppe92;
}

// Each drawn vertex's colour is its mesh vertex's (found by its position).
void expect_vertex_colors(const ReportMesh& drawn, const Mesh& mesh, const Vec3& centre) {
  ASSERT_EQ(drawn.colors.size(), drawn.vertices.size());
  std::map<std::array<float, 3>, Color> by_position;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3 p = mesh.vertices[v] - centre;
    by_position[{static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())}] = mesh.colors[v];
  }
  for (std::size_t v = 0; v < drawn.vertices.size() / 3; ++v) {
    const auto found = by_position.find({drawn.vertices[3 * v], drawn.vertices[3 * v + 1], drawn.vertices[3 * v + 2]});
    ASSERT_NE(found, by_position.end()) << v;
    EXPECT_EQ((Color{drawn.colors[3 * v], drawn.colors[3 * v + 1], drawn.colors[3 * v + 2]}), found->second) << v;
  }
}

// The number the page's JSON gives the array `key` after `after`.
int array_number(std::string_view json, std::string_view after, std::string_view key) {
  const std::size_t from = json.find(after);
  const std::string label = "\"" + std::string(key) + "\":";
  const std::size_t at = json.find(label, from == std::string_view::npos ? 0 : from);
  if (from == std::string_view::npos || at == std::string_view::npos) return -1;
  return std::atoi(std::string(json.substr(at + label.size(), 12)).c_str());
}

TEST(Report, ColoursOfThePointsAndOfTheFinalMesh) {
  ReportOptions options;
  options.max_points = 1000;    // every 4th point
  options.max_triangles = 500;  // a subsample of each mesh
  for (const Method method : {Method::refined, Method::hoppe92}) {
    const Reconstruction& r = colored_sphere(method);
    ASSERT_TRUE(r.mesh().has_colors());
    const ReportLayers layers = make_report_layers(report_input(r), options);
    ASSERT_EQ(layers.point_stride, 4u);
    ASSERT_EQ(layers.point_colors.size(), layers.points.size());
    for (std::size_t i = 0, j = 0; j < r.colors.size(); ++i, j += layers.point_stride)
      for (std::size_t c = 0; c < 3; ++c) ASSERT_EQ(layers.point_colors[3 * i + c], r.colors[j][c]) << j;
    const ReportMesh& final_mesh = method == Method::refined ? layers.refined : layers.mesh;
    EXPECT_GT(final_mesh.triangle_stride, 1u);
    expect_vertex_colors(final_mesh, r.mesh(), layers.centre);
    if (method == Method::refined) {
      EXPECT_TRUE(layers.mesh.colors.empty()) << "phase IV's mesh has none";
    }

    const std::string html = report_html(layers, options);
    const std::string_view json = element(html, "recon-data");
    const int points = array_number(json, "\"points\":{", "color");
    ASSERT_GE(points, 0);
    EXPECT_EQ(decode<std::uint8_t>(html, points), layers.point_colors);
    const int mesh = array_number(json, method == Method::refined ? "\"refinement\":{" : "\"mesh\":{", "colors");
    ASSERT_GE(mesh, 0);
    EXPECT_EQ(decode<std::uint8_t>(html, mesh), final_mesh.colors);
  }
  const std::string plain = report_html(make_report_layers(report_input(small_sphere(Method::refined))));
  EXPECT_EQ(element(plain, "recon-data").find("\"color"), std::string_view::npos);
}

TEST(Report, RefusesColoursThatAreNotOnePerPointOrVertex) {
  const Reconstruction& r = colored_sphere(Method::hoppe92);
  ReportInput input = report_input(r);
  input.colors = input.colors.subspan(1);
  EXPECT_THROW((void)make_report_layers(input), InvalidInputError);
  Mesh mesh = r.mesh();
  mesh.colors.pop_back();
  input = report_input(r);
  input.mesh = &mesh;
  EXPECT_THROW((void)make_report_layers(input), InvalidInputError);
}

TEST(ReportPage, WrittenWholeOrNotAtAll) {
  const Reconstruction& r = open_and_closed();
  const ReportLayers layers = make_report_layers(report_input(r));
  const auto folder = std::filesystem::temp_directory_path() / "recon_report_test";
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  EXPECT_THROW(write_report(folder / "missing" / "r.html", layers), IoError);
  write_report(folder / "r.html", layers);
  std::ifstream in(folder / "r.html", std::ios::binary);
  const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(written, report_html(layers));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), std::filesystem::directory_iterator{}), 1)
      << "no temporary file left";
  std::filesystem::remove_all(folder);
}

// ---- the lab panel

// A sphere beside a torus: the complete graph's tree joins them, the
// Riemannian graph keeps them apart.
const testing::HandMadeLab& sphere_and_torus_lab() {
  static const testing::HandMadeLab lab = testing::hand_made_lab(make_sphere_and_torus()->sample(3000, 11));
  return lab;
}

ReportInput lab_input(const testing::HandMadeLab& lab) {
  ReportInput input;
  input.points = lab.points;
  input.planes = &lab.planes;
  input.oriented = &lab.default_orientation;
  input.normals = lab.default_orientation.normals;
  return input;
}

ReportLayers layers_with_lab(const testing::HandMadeLab& lab, const ReportOptions& options = {}) {
  const ReportInput input = lab_input(lab);
  ReportLayers layers = make_report_layers(input, options);
  layers.lab = make_report_lab(lab.graphs, lab.runs_json, input.points, input.offset, layers, options);
  return layers;
}

// Within the budgets every edge is drawn once, every tree edge with its
// flip, and every point with its piece.
void expect_whole_graph(const ReportLabGraph& drawn, const OrientedNormals<3>& o, const ReportLayers& layers) {
  const std::size_t n = o.normals.size();
  EXPECT_EQ(drawn.drawn.edges_total, o.graph.graph.edge_count());
  EXPECT_EQ(drawn.drawn.vertex_stride, 1u);
  EXPECT_EQ(drawn.drawn.segments.size(), 6 * o.graph.graph.edge_count());
  EXPECT_EQ(drawn.drawn.tree_edges_total, n - o.component_count()) << "a tree per piece";
  ASSERT_EQ(drawn.drawn.tree_flip.size(), drawn.drawn.tree_edges_total);
  EXPECT_EQ(drawn.drawn.tree_segments.size(), 6 * drawn.drawn.tree_flip.size());
  std::size_t flips = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (o.tree.parent[i] != SpanningForest::no_parent) flips += o.flipped[i] != o.flipped[o.tree.parent[i]] ? 1U : 0U;
  EXPECT_EQ(drawn.drawn.tree_flips_total, flips);
  EXPECT_EQ(static_cast<std::size_t>(std::count(drawn.drawn.tree_flip.begin(), drawn.drawn.tree_flip.end(), 1)), flips);
  EXPECT_EQ(drawn.component_count, o.component_count());
  EXPECT_EQ(drawn.component, o.graph.components.label);
  EXPECT_EQ(drawn.flips, o.flip_count);
  // The segments join the points as layer 1 draws them.
  for (std::size_t e = 0; 6 * e < drawn.drawn.segments.size(); e += 97) {
    const Vec3 a = at(drawn.drawn.segments, 2 * e), b = at(drawn.drawn.segments, 2 * e + 1);
    const auto drawn_point = [&](const Vec3& p) {
      for (std::size_t i = 0; i < n; ++i)
        if ((at(layers.points, i) - p).norm() < 1e-9) return true;
      return false;
    };
    EXPECT_TRUE(drawn_point(a) && drawn_point(b)) << "segment " << e;
  }
}

TEST(ReportLab, EachGraphWithItsSpanningTreeAndPieces) {
  const testing::HandMadeLab& lab = sphere_and_torus_lab();
  const ReportLayers layers = layers_with_lab(lab);
  ASSERT_TRUE(layers.lab);
  ASSERT_EQ(layers.lab->graphs.size(), 5u);
  const std::string names[] = {"complete", "emst", "knn", "mutual-knn", "riemannian"};
  for (std::size_t g = 0; g < 5; ++g) {
    SCOPED_TRACE(names[g]);
    EXPECT_EQ(layers.lab->graphs[g].name, names[g]);
    expect_whole_graph(layers.lab->graphs[g], lab.graphs[g].oriented, layers);
  }
  // What the panel is for: the complete graph's tree joins the two
  // objects, the Riemannian graph keeps them apart.
  EXPECT_EQ(layers.lab->graphs[0].component_count, 1u);
  EXPECT_EQ(layers.lab->graphs[0].drawn.edges_total, lab.points.size() - 1) << "a tree";
  EXPECT_EQ(layers.lab->graphs[4].component_count, 2u);
  EXPECT_EQ(layers.lab->runs_json, lab.runs_json);
}

TEST(ReportLab, GraphsDrawnWithinTheBudgetsOfLayers1And4) {
  const testing::HandMadeLab& lab = sphere_and_torus_lab();
  ReportOptions options;
  options.max_points = 500;
  options.max_edges = 2000;
  const ReportLayers layers = layers_with_lab(lab, options);
  const std::size_t drawn_points = layers.points.size() / 3;
  ASSERT_GT(layers.point_stride, 1u);
  for (std::size_t g = 0; g < 5; ++g) {
    const ReportLabGraph& drawn = layers.lab->graphs[g];
    const OrientedNormals<3>& o = lab.graphs[g].oriented;
    SCOPED_TRACE(drawn.name);
    EXPECT_EQ(drawn.drawn.edges_total, o.graph.graph.edge_count());
    EXPECT_LE(drawn.drawn.segments.size() / 6, 2000u);
    EXPECT_EQ(drawn.drawn.vertex_stride % layers.point_stride, 0u) << "the edges start at drawn points";
    ASSERT_EQ(drawn.component.size(), drawn_points) << "a piece per drawn point";
    std::size_t with_parent = 0;
    for (std::size_t j = 0; j < drawn_points; ++j) {
      const std::size_t i = j * layers.point_stride;
      EXPECT_EQ(drawn.component[j], o.graph.components.label[i]);
      with_parent += o.tree.parent[i] != SpanningForest::no_parent ? 1U : 0U;
    }
    EXPECT_EQ(drawn.drawn.tree_flip.size(), with_parent) << "one tree edge per drawn point that has a parent";
    EXPECT_EQ(drawn.drawn.tree_edges_total, o.normals.size() - o.component_count());
  }
}

// The number the JSON gives `key` after position `from`.
std::size_t number_after(std::string_view json, std::size_t from, std::string_view key) {
  const std::string quoted = "\"" + std::string(key) + "\":";
  const auto at = json.find(quoted, from);
  if (at == std::string_view::npos) return std::numeric_limits<std::size_t>::max();
  return static_cast<std::size_t>(std::stoull(std::string(json.substr(at + quoted.size(), 20))));
}

TEST(ReportLabPage, LabPartWithTheRunsAndEachGraphsArrays) {
  const testing::HandMadeLab& lab = sphere_and_torus_lab();
  const ReportLayers layers = layers_with_lab(lab);
  const std::string html = report_html(layers);
  const std::string_view json = element(html, "recon-data");
  // The runs as written, then the graphs in order.
  const auto lab_at = json.find("\"lab\":{\"stats\":" + lab.runs_json + ",\"graphs\":[{\"name\":\"complete\"");
  ASSERT_NE(lab_at, std::string_view::npos);
  EXPECT_LT(json.find("\"points\":{"), lab_at);
  std::size_t from = json.find("\"graphs\":[", lab_at);  // past the runs, which name the graphs too
  for (const ReportLabGraph& g : layers.lab->graphs) {
    from = json.find("{\"name\":\"" + g.name + "\"", from);
    ASSERT_NE(from, std::string_view::npos) << g.name;
    SCOPED_TRACE(g.name);
    EXPECT_EQ(number_after(json, from, "components"), g.component_count);
    EXPECT_EQ(number_after(json, from, "flips"), g.flips);
    EXPECT_EQ(number_after(json, from, "edges_total"), g.drawn.edges_total);
    EXPECT_EQ(number_after(json, from, "drawn"), g.drawn.segments.size() / 6);
    EXPECT_EQ(number_after(json, from, "tree_drawn"), g.drawn.tree_flip.size());
    EXPECT_EQ(number_after(json, from, "tree_total"), g.drawn.tree_edges_total);
    EXPECT_EQ(number_after(json, from, "flips_total"), g.drawn.tree_flips_total);
    const auto segments = decode<float>(html, static_cast<int>(number_after(json, from, "segments")));
    EXPECT_EQ(segments, g.drawn.segments);
    EXPECT_EQ(segments.size() / 6, number_after(json, from, "drawn")) << "a segment per edge drawn";
    EXPECT_EQ(decode<std::uint32_t>(html, static_cast<int>(number_after(json, from, "component"))), g.component);
    EXPECT_EQ(decode<std::uint8_t>(html, static_cast<int>(number_after(json, from, "tree_flip"))), g.drawn.tree_flip);
  }
}

TEST(ReportLabPage, WithoutALabPartThePageHasNoLabKey) {
  const testing::HandMadeLab& lab = sphere_and_torus_lab();
  const ReportLayers layers = make_report_layers(lab_input(lab));
  EXPECT_FALSE(layers.lab);
  const std::string html = report_html(layers);
  EXPECT_EQ(element(html, "recon-data").find("\"lab\""), std::string_view::npos);
  // An empty lab part still has a panel, with no runs and no graphs.
  ReportLayers empty = layers;
  empty.lab = make_report_lab({}, "", lab.points, Vec3::Zero(), layers);
  EXPECT_NE(element(report_html(empty), "recon-data").find("\"lab\":{\"stats\":{},\"graphs\":[]}"),
            std::string_view::npos);
}

TEST(ReportLab, RefusesGraphsOfOtherPoints) {
  const testing::HandMadeLab& lab = sphere_and_torus_lab();
  const ReportInput input = lab_input(lab);
  const ReportLayers layers = make_report_layers(input);
  EXPECT_THROW((void)make_report_lab(lab.graphs, lab.runs_json, input.points.subspan(1), input.offset, layers),
               InvalidInputError);
  std::vector<LabGraph> released(lab.graphs.begin(), lab.graphs.begin() + 1);
  released[0].oriented.graph.graph = Graph{};
  EXPECT_THROW((void)make_report_lab(released, lab.runs_json, input.points, input.offset, layers), InvalidInputError);
}

}  // namespace
}  // namespace recon
