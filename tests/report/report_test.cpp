#include "recon/report/report.h"

#include "hand_made_lab.h"
#include "mesh_compare.h"
#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/reconstruct.h"
#include "recon/structures/mesh.h"

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

Reconstruction reconstruct_for_report(const PointCloud& cloud) {
  ReconstructionOptions options;
  options.keep_graph = true;
  options.keep_corners = true;
  return reconstruct(cloud, options);
}

// A half sphere (open: the mesh has a boundary) beside a whole one, far
// enough apart to be two components.
const Reconstruction& open_and_closed() {
  static const Reconstruction r = [] {
    PointCloud cloud;
    for (const Vec3& p : make_sphere()->sample(6000, 5).positions)
      if (p.z() > 0.0) cloud.positions.push_back(p);
    for (const Vec3& p : make_sphere()->sample(3000, 6).positions) cloud.positions.push_back(p + Vec3(4.0, 0.0, 0.0));
    return reconstruct_for_report(cloud);
  }();
  return r;
}

Vec3 at(const std::vector<float>& v, std::size_t i) {
  return {static_cast<double>(v[3 * i]), static_cast<double>(v[3 * i + 1]), static_cast<double>(v[3 * i + 2])};
}
Vec3 normal_at(const std::vector<std::int8_t>& v, std::size_t i) {
  return Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]) / 127.0;
}

std::string_view element(std::string_view html, const std::string& id);

TEST(Report, EveryPointWithItsPlaneNormalsAndComponentWhenWithinBudget) {
  const Reconstruction& r = open_and_closed();
  const ReportLayers layers = make_report_layers(report_input(r));
  const std::size_t n = r.points().size();
  ASSERT_EQ(layers.points_total, n);
  ASSERT_EQ(layers.point_stride, 1u);
  ASSERT_EQ(layers.points.size(), 3 * n);
  const double tolerance = 1e-6 * layers.diagonal;  // float storage
  std::set<std::uint32_t> components;
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_LT((at(layers.points, i) + layers.centre - r.points()[i] - r.offset).norm(), tolerance);
    EXPECT_LT((at(layers.origins, i) + layers.centre - r.planes.origins[i] - r.offset).norm(), tolerance);
    // int8 normals: within 1/127 per coordinate of the true ones.
    EXPECT_LT((normal_at(layers.pca_normals, i) - r.planes.normals[i]).lpNorm<Eigen::Infinity>(), 0.5 / 127 + 1e-9);
    EXPECT_LT((normal_at(layers.normals, i) - r.normals()[i]).lpNorm<Eigen::Infinity>(), 0.5 / 127 + 1e-9);
    EXPECT_EQ(layers.flipped[i] == 1, r.planes.normals[i].dot(r.normals()[i]) < 0.0);
    EXPECT_GE(layers.planarity[i], 0.0F);
    EXPECT_LE(layers.planarity[i], 1.0F / 3.0F + 1e-6F);
    EXPECT_EQ(layers.component[i], r.oriented->graph.components.label[i]);
    components.insert(layers.component[i]);
  }
  EXPECT_EQ(components.size(), 2u);
  EXPECT_EQ(layers.component_count, 2u);
  // The centre is the middle of the points' box, in input coordinates.
  const Box<3> box = bounding_box<3>(r.points());
  EXPECT_LT((layers.centre - (0.5 * (box.min + box.max) + r.offset)).norm(), 1e-12);
}

// The web page's view of phase I alone (web/webapp/): no oriented normals
// yet, so no layer 5 in the data (the viewer lists it as not yet there).
TEST(Report, PhaseIAloneHasNoOrientedNormals) {
  const Reconstruction& r = open_and_closed();
  ReportInput input = report_input(r);
  input.normals = {};
  input.oriented = nullptr;
  input.contour = nullptr;
  input.refinement = nullptr;
  const ReportLayers layers = make_report_layers(input);
  EXPECT_EQ(layers.points.size(), 3 * r.points().size());
  EXPECT_EQ(layers.pca_normals.size(), 3 * r.points().size());
  EXPECT_TRUE(layers.normals.empty());
  EXPECT_TRUE(layers.flipped.empty());
  const std::string html = report_html(layers);
  const std::string_view json = element(html, "recon-data");
  EXPECT_NE(json.find("\"pca_normal\":"), std::string_view::npos);
  EXPECT_EQ(json.find("\"normal\":"), std::string_view::npos);
  EXPECT_EQ(json.find("\"flipped\":"), std::string_view::npos);
  input.normals = r.normals().first(3);  // neither all nor none
  EXPECT_THROW((void)make_report_layers(input), InvalidInputError);
}

TEST(Report, KdTreeCellsAreTheNodeBoxesDownToTheDrawnDepth) {
  const Reconstruction& r = open_and_closed();
  ReportOptions options;
  options.max_kdtree_depth = 5;
  const ReportLayers layers = make_report_layers(report_input(r), options);
  const KdTree<3>& tree = r.planes.point_tree;
  EXPECT_EQ(layers.kdtree_depth, tree.depth());
  EXPECT_EQ(layers.kdtree_drawn_depth, 5);
  // A full binary tree down to depth 5 (the leaves are deeper): 63 nodes.
  ASSERT_EQ(layers.kdtree_level.size(), 63u);
  ASSERT_EQ(layers.kdtree_boxes.size(), 6 * 63u);
  std::map<int, std::size_t> per_level;
  for (const auto level : layers.kdtree_level) ++per_level[level];
  for (int d = 0; d <= 5; ++d) EXPECT_EQ(per_level[d], std::size_t{1} << d);
  // The cells of one depth hold every point, each point in one cell.
  const float slack = 1e-5F;
  for (int d : {1, 3, 5}) {
    for (std::size_t i = 0; i < r.points().size(); i += 37) {
      const Vec3 p = r.points()[i] + r.offset - layers.centre;
      int holding = 0;
      for (std::size_t b = 0; b < layers.kdtree_level.size(); ++b) {
        if (layers.kdtree_level[b] != d) continue;
        const Vec3 lo = at(layers.kdtree_boxes, 2 * b), hi = at(layers.kdtree_boxes, 2 * b + 1);
        holding += ((p.array() >= lo.array() - slack) && (p.array() <= hi.array() + slack)).all() ? 1 : 0;
      }
      EXPECT_GE(holding, 1) << "point " << i << " at depth " << d;
    }
  }
}

TEST(Report, GraphAndSpanningTreeWithTheEdgesWhereTheOrientationTurns) {
  const Reconstruction& r = open_and_closed();
  ReportOptions options;
  options.max_edges = 10'000'000;
  const ReportLayers layers = make_report_layers(report_input(r), options);
  ASSERT_TRUE(layers.has_graph);
  const auto& o = *r.oriented;
  EXPECT_EQ(layers.graph.edges_total, o.graph.graph.edge_count());
  EXPECT_EQ(layers.graph.vertex_stride, 1u);
  EXPECT_EQ(layers.graph.segments.size(), 6 * o.graph.graph.edge_count());  // every edge once
  // Every vertex but the two roots has a tree edge to its parent.
  const std::size_t n = r.points().size();
  EXPECT_EQ(layers.graph.tree_edges_total, n - 2);
  ASSERT_EQ(layers.graph.tree_flip.size(), n - 2);
  std::size_t e = 0, flips = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t parent = o.tree.parent[i];
    if (parent == SpanningForest::no_parent) continue;
    const Vec3 a = at(layers.graph.tree_segments, 2 * e) + layers.centre,
               b = at(layers.graph.tree_segments, 2 * e + 1) + layers.centre;
    EXPECT_LT((a - r.points()[i] - r.offset).norm(), 1e-5);
    EXPECT_LT((b - r.points()[parent] - r.offset).norm(), 1e-5);
    // Where the oriented normals agree across the edge (everywhere but a
    // few the vote turned), a flip is where the PCA normals disagree.
    if (r.normals()[i].dot(r.normals()[parent]) > 0.0) {
      EXPECT_EQ(layers.graph.tree_flip[e] == 1, r.planes.normals[i].dot(r.planes.normals[parent]) < 0.0)
          << "edge " << e;
    }
    flips += layers.graph.tree_flip[e];
    ++e;
  }
  EXPECT_EQ(flips, layers.graph.tree_flips_total);
  EXPECT_GT(flips, 0u);  // PCA's signs are arbitrary: a walk over a sphere must turn some
}

// A thinned mesh keeps only its drawn triangles' vertices, renumbered:
// each drawn triangle has the corners of the triangle it stands for.
void expect_thinned(const ReportMesh& drawn, const Mesh& mesh, const Vec3& centre) {
  ASSERT_GT(drawn.triangle_stride, 1u);
  EXPECT_EQ(drawn.triangles.size() / 3, (mesh.triangles.size() + drawn.triangle_stride - 1) / drawn.triangle_stride);
  std::set<std::uint32_t> used;
  for (std::size_t t = 0; 3 * t < drawn.triangles.size(); ++t)
    for (std::size_t c = 0; c < 3; ++c) {
      const std::uint32_t v = drawn.triangles[3 * t + c];
      ASSERT_LT(v, drawn.vertices.size() / 3);
      used.insert(v);
      const Vec3 original = mesh.vertices[mesh.triangles[t * drawn.triangle_stride][c]];
      EXPECT_LT((at(drawn.vertices, v) + centre - original).norm(), 1e-5);
    }
  EXPECT_EQ(used.size(), drawn.vertices.size() / 3) << "no vertex stored that no drawn triangle uses";
  EXPECT_LT(drawn.vertices.size() / 3, mesh.vertices.size());
}

TEST(Report, BudgetsDrawARegularSubsampleAndSaySo) {
  const Reconstruction& r = open_and_closed();
  const std::size_t n = r.points().size();
  ReportOptions options;
  options.max_points = 1000;
  options.max_edges = 5000;
  options.max_corners = 700;
  options.max_triangles = 2000;
  const ReportLayers layers = make_report_layers(report_input(r), options);
  EXPECT_EQ(layers.point_stride, (n + 999) / 1000);
  EXPECT_LE(layers.points.size() / 3, 1000u);
  EXPECT_GT(layers.points.size() / 3, 900u);
  for (std::size_t j = 0; j < layers.points.size() / 3; ++j)
    EXPECT_LT((at(layers.points, j) + layers.centre - r.points()[j * layers.point_stride] - r.offset).norm(), 1e-5);
  EXPECT_LE(layers.graph.segments.size() / 6, 5000u);
  EXPECT_GT(layers.graph.segments.size() / 6, 2500u);  // the stride is the smallest that fits, give or take 1/8
  EXPECT_EQ(layers.graph.vertex_stride % layers.point_stride, 0U);  // the edges start at drawn points
  std::size_t drawn_with_parent = 0;
  for (std::size_t i = 0; i < n; i += layers.point_stride)
    drawn_with_parent += r.oriented->tree.parent[i] != SpanningForest::no_parent ? 1U : 0U;
  EXPECT_EQ(layers.graph.tree_flip.size(), drawn_with_parent) << "one tree edge per drawn point that has a parent";
  EXPECT_LE(layers.corner_values.size(), 700u);
  // Each mesh layer has the triangle budget to itself.
  EXPECT_LE(layers.mesh.triangles.size() / 3, 2000u);
  EXPECT_LE(layers.refined.triangles.size() / 3, 2000u);
  EXPECT_EQ(layers.mesh.triangles_total, r.contour.mesh.triangles.size());
  EXPECT_EQ(layers.refined.triangles_total, r.refinement->mesh.triangles.size());
  expect_thinned(layers.mesh, r.contour.mesh, layers.centre);
  expect_thinned(layers.refined, r.refinement->mesh, layers.centre);
  EXPECT_EQ(layers.refined_distance.size(), layers.refined.vertices.size() / 3) << "one distance per drawn vertex";
  EXPECT_EQ(layers.corners_total, r.contour.evaluated_corners);
}

TEST(Report, CornersAreTheEvaluatedLatticeCornersWithUndefinedOnesMarked) {
  const Reconstruction& r = open_and_closed();
  const ReportLayers layers = make_report_layers(report_input(r));
  ASSERT_TRUE(layers.has_corners);
  const auto& corners = r.contour.corners;
  ASSERT_EQ(layers.corner_values.size(), corners.size());
  std::size_t undefined = 0;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Vec3 index(corners[i].index[0], corners[i].index[1], corners[i].index[2]);
    const Vec3 expected = r.contour.origin + r.contour.cell * index + r.offset;
    EXPECT_LT((at(layers.corners, i) + layers.centre - expected).norm(), 1e-5);
    if (corners[i].defined) {
      EXPECT_FLOAT_EQ(layers.corner_values[i], static_cast<float>(corners[i].value));
    } else {
      EXPECT_TRUE(std::isnan(layers.corner_values[i]));
      ++undefined;
    }
  }
  EXPECT_EQ(undefined, r.contour.undefined_corners);
  EXPECT_GT(undefined, 0u);  // under the open half sphere
}

// Every triangle and vertex of `mesh` drawn, and its boundary, which is
// the half sphere's rim: near z = 0 (below `rim`), on the first sphere.
void expect_whole_with_rim(const ReportMesh& drawn, const Mesh& mesh, const Vec3& centre, double rim) {
  ASSERT_EQ(drawn.triangles.size(), 3 * mesh.triangles.size());
  ASSERT_EQ(drawn.vertices.size(), 3 * mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); v += 11)
    EXPECT_LT((at(drawn.vertices, v) + centre - mesh.vertices[v]).norm(), 1e-5);
  const MeshTopology t = analyze_topology(mesh);
  EXPECT_GT(t.boundary_edges, 0u);
  EXPECT_EQ(drawn.boundary_edges_total, t.boundary_edges);
  EXPECT_EQ(drawn.boundary_segments.size(), 6 * t.boundary_edges);
  for (std::size_t e = 0; e < 2 * t.boundary_edges; ++e) {
    const Vec3 p = at(drawn.boundary_segments, e) + centre;
    EXPECT_LT(p.x(), 2.0);
    EXPECT_LT(std::abs(p.z()), rim);
  }
}

TEST(Report, ContouredAndRefinedMeshesWithTheirBoundaryEdges) {
  const Reconstruction& r = open_and_closed();
  const ReportLayers layers = make_report_layers(report_input(r));
  ASSERT_TRUE(layers.has_mesh);
  // The contoured surface runs on past the open edge (f reaches about
  // 1.5 rho + delta past the last samples); phase V cuts it back.
  expect_whole_with_rim(layers.mesh, r.contour.mesh, layers.centre, 0.4);
  ASSERT_TRUE(layers.has_refinement);
  expect_whole_with_rim(layers.refined, r.refinement->mesh, layers.centre, 0.25);
  EXPECT_EQ(layers.refined_distance.size(), r.refinement->mesh.vertices.size());
}

TEST(Report, BoundaryEdgesWithinTheirBudget) {
  const Reconstruction& r = open_and_closed();
  ReportOptions options;
  options.max_boundary_edges = 10;
  const ReportLayers layers = make_report_layers(report_input(r), options);
  for (const auto& [drawn, mesh] :
       {std::pair{&layers.mesh, &r.contour.mesh}, std::pair{&layers.refined, &r.refinement->mesh}}) {
    const auto boundary = boundary_edges(*mesh);
    ASSERT_GT(boundary.size(), 10u);
    EXPECT_EQ(drawn->boundary_edges_total, boundary.size());
    EXPECT_EQ(drawn->boundary_stride, (boundary.size() + 9) / 10);
    ASSERT_EQ(drawn->boundary_segments.size(),
              6 * ((boundary.size() + drawn->boundary_stride - 1) / drawn->boundary_stride));
    for (std::size_t e = 0; 6 * e < drawn->boundary_segments.size(); ++e) {
      const auto& [a, b] = boundary[e * drawn->boundary_stride];
      EXPECT_LT((at(drawn->boundary_segments, 2 * e) + layers.centre - mesh->vertices[a]).norm(), 1e-5);
      EXPECT_LT((at(drawn->boundary_segments, 2 * e + 1) + layers.centre - mesh->vertices[b]).norm(), 1e-5);
    }
  }
}

// ---- layer 8: the refinement and its distance to the 1992 surface

const Reconstruction& small_sphere(Method method) {
  static const auto make = [](Method m) {
    ReconstructionOptions options;
    options.method = m;
    return reconstruct(make_sphere()->sample(2500, 21), options);
  };
  static const Reconstruction refined = make(Method::refined), hoppe92 = make(Method::hoppe92);
  return method == Method::refined ? refined : hoppe92;
}

void expect_distances_to(const ReportLayers& layers, const Mesh& refined, const Mesh& contoured) {
  ASSERT_EQ(layers.refined_distance.size(), refined.vertices.size());
  double max = 0.0, sum = 0.0;
  for (std::size_t v = 0; v < refined.vertices.size(); ++v) {
    const double expected = brute_force_distance(refined.vertices[v], contoured);
    EXPECT_NEAR(layers.refined_distance[v], expected, 1e-6 + 1e-6 * expected) << "vertex " << v;
    max = std::max(max, expected);
    sum += expected;
  }
  EXPECT_NEAR(layers.distance_max, max, 1e-9 + 1e-6 * max);
  EXPECT_NEAR(layers.distance_mean, sum / static_cast<double>(refined.vertices.size()), 1e-9 + 1e-6 * max);
  EXPECT_LE(layers.distance_scale, layers.distance_max);
  EXPECT_GT(layers.distance_scale, 0.0);
}

TEST(Report, RefinementLayerDrawsTheRefinedMeshByItsDistanceToThe1992Surface) {
  const Reconstruction& r = small_sphere(Method::refined);
  ASSERT_TRUE(r.refinement);
  const ReportLayers layers = make_report_layers(report_input(r));
  ASSERT_TRUE(layers.has_mesh);
  ASSERT_TRUE(layers.has_refinement);
  EXPECT_EQ(layers.mesh.triangles_total, r.contour.mesh.triangles.size());
  EXPECT_EQ(layers.mesh.triangles.size(), 3 * r.contour.mesh.triangles.size());
  EXPECT_EQ(layers.refined.triangles_total, r.refinement->mesh.triangles.size());
  EXPECT_EQ(layers.refined.triangles.size(), 3 * r.refinement->mesh.triangles.size());
  EXPECT_EQ(layers.refined.vertices.size(), 3 * r.refinement->mesh.vertices.size());
  expect_distances_to(layers, r.refinement->mesh, r.contour.mesh);
  // Phase V moves the vertices by a fraction of a cell.
  EXPECT_LT(layers.distance_max, r.contour.cell);
}

// Far from the mesh the search must look beyond the nearest vertex's
// triangles: the refined mesh here is the contoured one blown up by 1.5.
TEST(Report, RefinementDistancesFarFromThe1992Surface) {
  const Reconstruction& r = small_sphere(Method::refined);
  Refinement moved;
  moved.mesh = r.contour.mesh;
  for (Vec3& v : moved.mesh.vertices) v *= 1.5;
  ReportInput input = report_input(r);
  input.refinement = &moved;
  const ReportLayers layers = make_report_layers(input);
  expect_distances_to(layers, moved.mesh, r.contour.mesh);
  EXPECT_GT(layers.distance_mean, 0.4);  // the unit sphere's vertices moved out by 0.5
  // The first view frames what is drawn, the larger sphere included.
  for (std::size_t v = 0; v < layers.refined.vertices.size() / 3; ++v) {
    const Vec3 p = at(layers.refined.vertices, v);
    EXPECT_TRUE((p.array() >= layers.drawn_box.min.array() - 1e-9).all() &&
                (p.array() <= layers.drawn_box.max.array() + 1e-9).all());
  }
  EXPECT_GT(layers.drawn_box.extent().minCoeff(), 2.9);
}

TEST(Report, Hoppe92RunHasNoRefinementLayer) {
  const Reconstruction& r = small_sphere(Method::hoppe92);
  ASSERT_FALSE(r.refinement);
  const ReportLayers layers = make_report_layers(report_input(r));
  EXPECT_FALSE(layers.has_refinement);
  EXPECT_TRUE(layers.refined.triangles.empty());
  EXPECT_TRUE(layers.refined_distance.empty());
  ASSERT_TRUE(layers.has_mesh);
  EXPECT_EQ(layers.mesh.triangles.size(), 3 * r.mesh().triangles.size()) << "the whole budget for layer 7";
  const std::string html = report_html(layers);
  const std::string_view json = element(html, "recon-data");
  EXPECT_NE(json.find("\"mesh\":{"), std::string::npos);
  EXPECT_EQ(json.find("\"refinement\""), std::string::npos);
}

TEST(Report, NormalsOnlyRunHasNoLatticeLayers) {
  const Reconstruction& r = open_and_closed();
  ReportInput input = report_input(r);
  input.contour = nullptr;
  const ReportLayers layers = make_report_layers(input);
  EXPECT_FALSE(layers.has_corners);
  EXPECT_FALSE(layers.has_mesh);
  EXPECT_FALSE(layers.has_refinement);
  EXPECT_TRUE(layers.has_graph);
  const std::string html = report_html(layers);
  const std::string_view json = element(html, "recon-data");
  EXPECT_NE(json.find("\"graph\":{"), std::string::npos);
  EXPECT_EQ(json.find("\"mesh\""), std::string::npos);
  EXPECT_EQ(json.find("\"refinement\""), std::string::npos);
  EXPECT_EQ(json.find("\"corners\""), std::string::npos);
}

TEST(Report, GraphReleasedOrSkippedMeansNoGraphLayer) {
  ReconstructionOptions options;
  options.keep_graph = false;
  const Reconstruction r = reconstruct(make_sphere()->sample(3000, 9), options);
  const ReportLayers layers = make_report_layers(report_input(r));
  EXPECT_FALSE(layers.has_graph);
  EXPECT_FALSE(layers.has_corners);  // keep_corners was off
  EXPECT_TRUE(layers.has_mesh);
}

TEST(Report, RefusesMismatchedInput) {
  const Reconstruction& r = open_and_closed();
  ReportInput input = report_input(r);
  input.normals = input.normals.subspan(1);
  EXPECT_THROW((void)make_report_layers(input), InvalidInputError);
  input.planes = nullptr;
  EXPECT_THROW((void)make_report_layers(input), InvalidInputError);
}

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

// The text of the element with this id.
std::string_view element(std::string_view html, const std::string& id) {
  const std::string open = "id=\"" + id + "\"";
  const auto at = html.find(open);
  if (at == std::string_view::npos) return {};
  const auto start = html.find('>', at) + 1;
  return html.substr(start, html.find("</script>", start) - start);
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
