// The textbook path (reference.h) as the oracle of the optimised one: on
// small clouds, reconstruct() with Method::hoppe92 and plain_options() must
// find the same planes, the same EMST, the same graph, the same oriented
// normals and the same mesh as reference::reconstruct.

#include "recon/alternatives/reference.h"

#include "mesh_compare.h"
#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/reconstruct.h"
#include "recon/structures/kdtree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <span>
#include <string>

namespace recon {
namespace {

struct Case {
  const char* shape;
  std::size_t points;
  int k;
};

// Both paths on one case, computed once for all the tests of the case.
struct Computed {
  PointCloud cloud;
  reference::Options options;
  reference::Result reference;
  Reconstruction optimised;
};

const Computed& computed(const Case& c) {
  static std::map<std::string, std::unique_ptr<Computed>> cache;
  std::unique_ptr<Computed>& entry = cache[c.shape];
  if (entry) return *entry;
  entry = std::make_unique<Computed>();
  const auto shape = make_shape(c.shape);
  entry->cloud = shape->sample(c.points, 7);
  const double spacing = std::sqrt(shape->area() / static_cast<double>(c.points));
  entry->options.k = c.k;
  entry->options.rho = 2.0 * spacing;
  entry->options.delta = 0.1 * entry->options.rho;
  entry->options.cell = entry->options.rho;
  entry->reference = reference::reconstruct(entry->cloud.positions, entry->options);
  entry->optimised = reconstruct(entry->cloud, reference::plain_options(entry->options));
  return *entry;
}

class ReferencePath : public ::testing::TestWithParam<Case> {
 protected:
  void SetUp() override {
    const Computed& c = computed(GetParam());
    options_ = c.options;
    reference_ = &c.reference;
    optimised_ = &c.optimised;
  }
  reference::Options options_;
  const reference::Result* reference_ = nullptr;
  const Reconstruction* optimised_ = nullptr;
};

TEST_P(ReferencePath, SamePlanesAndOrientation) {
  const Reconstruction& r = *optimised_;
  ASSERT_EQ(r.offset, Vec3::Zero());
  for (std::size_t j = 0; j < r.order.size(); ++j) {
    const std::uint32_t i = r.order[j];
    EXPECT_LT((r.planes.origins[j] - reference_->origins[i]).norm(), 1e-12) << "origin of point " << i;
    EXPECT_LT((r.normals()[j] - reference_->normals[i]).norm(), 1e-9) << "oriented normal of point " << i;
  }
}

// Edges as (smaller, larger) input indices; `order` maps the optimised
// path's spatial indices to input ones (empty: already input indices).
std::set<std::pair<std::uint32_t, std::uint32_t>> edge_set(std::span<const Edge> edges,
                                                           std::span<const std::uint32_t> order = {}) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> set;
  for (const Edge& e : edges) {
    const std::uint32_t u = order.empty() ? e.u : order[e.u], v = order.empty() ? e.v : order[e.v];
    set.insert({std::min(u, v), std::max(u, v)});
  }
  return set;
}

TEST_P(ReferencePath, SameEmstAndGraph) {
  const RiemannianGraph<3>& g = optimised_->oriented->graph;
  ASSERT_EQ(g.emst.size(), reference_->emst.size());
  EXPECT_EQ(edge_set(g.emst, optimised_->order), edge_set(reference_->emst));
  EXPECT_EQ(g.edge_count, reference_->graph.size());
  const std::vector<Edge> graph = edge_list(g.graph, [](std::uint32_t, std::uint64_t) { return 0.0; });
  EXPECT_EQ(edge_set(graph, optimised_->order), edge_set(reference_->graph));
}

TEST_P(ReferencePath, SameMesh) {
  EXPECT_TRUE(same_mesh(optimised_->mesh(), reference_->mesh, 1e-9 * options_.cell));
  EXPECT_GT(reference_->mesh.triangles.size(), 500u);
}

INSTANTIATE_TEST_SUITE_P(Shapes, ReferencePath,
                         ::testing::Values(Case{"sphere", 1200, 12}, Case{"torus", 2000, 15}, Case{"two", 2000, 12},
                                           Case{"terrain", 1500, 10}, Case{"box", 1500, 12}),
                         [](const ::testing::TestParamInfo<Case>& param) { return std::string(param.param.shape); });

// The comparison can fail: a reference run with another delta draws
// another mesh on an open surface (its boundary is where f is undefined).
TEST(ReferencePath, AnotherDeltaIsAnotherMesh) {
  const Computed& c = computed(Case{"terrain", 1500, 10});
  reference::Options wider = c.options;
  wider.delta = 0.6 * c.options.rho;
  EXPECT_FALSE(
      same_mesh(c.optimised.mesh(), reference::reconstruct(c.cloud.positions, wider).mesh, 1e-9 * c.options.cell));
}

TEST(ReferencePath, RefusesWhatItCannotDo) {
  const PointCloud cloud = make_sphere()->sample(50, 1);
  reference::Options options;
  options.rho = options.cell = 0.1;
  options.k = 60;
  EXPECT_THROW((void)reference::reconstruct(cloud.positions, options), InvalidInputError);
  options.k = 2;
  EXPECT_THROW((void)reference::reconstruct(cloud.positions, options), InvalidInputError);
  options.k = 10;
  options.cell = 0.0;
  EXPECT_THROW((void)reference::reconstruct(cloud.positions, options), InvalidInputError);
}

}  // namespace
}  // namespace recon
