// The report's layers (make_report_layers): what each layer draws, within
// its budget, and what it refuses. The page itself is tested in
// report_page_test.cpp.
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

Vec3 normal_at(const std::vector<std::int8_t>& v, std::size_t i) {
  return Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]) / 127.0;
}

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

// The nearest point of the 1992 surface can be the middle of a large
// triangle whose corners all lie farther than another triangle's corner:
// here a refined vertex just above a unit triangle's centre (its corners
// 0.577 away), with a small triangle's corner 0.3 above it. The search must
// reach L / sqrt 3 beyond the distance found around the nearest corner.
TEST(Report, RefinementDistanceReachesTheMiddleOfALargeTriangle) {
  const Reconstruction& r = small_sphere(Method::refined);
  const double h = std::sqrt(3.0) / 2.0;
  const Vec3 centre(0.5, h / 3.0, 0.0);
  Mesh contoured;
  contoured.vertices = {Vec3(0, 0, 0),
                        Vec3(1, 0, 0),
                        Vec3(0.5, h, 0),  // the unit triangle
                        centre + Vec3(0, 0, 0.31),
                        centre + Vec3(0.05, 0, 0.35),
                        centre + Vec3(0, 0.05, 0.35)};
  contoured.triangles = {{0, 1, 2}, {3, 4, 5}};
  Refinement moved;
  moved.mesh.vertices = {centre + Vec3(0, 0, 0.01), centre + Vec3(0.001, 0, 0.01), centre + Vec3(0, 0.001, 0.01)};
  moved.mesh.triangles = {{0, 1, 2}};
  ReportInput input = report_input(r);
  input.mesh = &contoured;
  input.refinement = &moved;
  const ReportLayers layers = make_report_layers(input);
  expect_distances_to(layers, moved.mesh, contoured);
  EXPECT_NEAR(layers.distance_max, 0.01, 1e-9);
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
}  // namespace
}  // namespace recon
