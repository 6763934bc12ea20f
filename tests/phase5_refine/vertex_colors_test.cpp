// vertex_colors: the inverse-distance blend of the k nearest samples'
// colours, against a brute-force oracle (every sample's distance, the k
// smallest by distance and index, the weights of the header's formula),
// a vertex on a sample, thread counts, and the errors.

#include "recon/phase5_refine/vertex_colors.h"

#include "recon/core/errors.h"
#include "recon/core/parallel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

namespace recon {
namespace {

struct Samples {
  std::vector<Vec3> points;
  std::vector<Color> colors;
};

Samples random_samples(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255);
  Samples s;
  for (std::size_t i = 0; i < n; ++i) {
    s.points.emplace_back(unit(random), unit(random), unit(random));
    s.colors.push_back({static_cast<std::uint8_t>(byte(random)), static_cast<std::uint8_t>(byte(random)),
                        static_cast<std::uint8_t>(byte(random))});
  }
  return s;
}

// The oracle: every sample measured, the k nearest by (distance, index),
// weights 1 / (d^2 + 1e-6 d_k^2) summed nearest first.
Color brute_force_blend(const Vec3& v, const std::vector<Vec3>& points, const std::vector<Color>& colors,
                        std::size_t k) {
  std::vector<Neighbor> all;
  for (std::uint32_t i = 0; i < points.size(); ++i) all.push_back({i, (points[i] - v).squaredNorm()});
  std::sort(all.begin(), all.end());
  all.resize(std::min(k, all.size()));
  const double floor2 = std::max(1e-6 * all.back().distance2, std::numeric_limits<double>::min());
  std::array<double, 3> sum{};
  double weights = 0.0;
  for (const Neighbor& n : all) {
    const double w = 1.0 / (n.distance2 + floor2);
    for (std::size_t c = 0; c < 3; ++c) sum[c] += w * colors[n.index][c];
    weights += w;
  }
  Color out{};
  for (std::size_t c = 0; c < 3; ++c) out[c] = static_cast<std::uint8_t>(std::lround(sum[c] / weights));
  return out;
}

TEST(VertexColors, BlendIsTheInverseDistanceWeightsOfTheKNearest) {
  const Samples s = random_samples(2000, 1);
  const KdTree<3> tree(s.points);  // not renumbered: its indices are the samples'
  const std::vector<Vec3> vertices = random_samples(300, 2).points;
  for (const int k : {1, 2, 8, 20}) {
    VertexColorOptions options;
    options.k = k;
    const std::vector<Color> colors = vertex_colors(vertices, tree, s.colors, options);
    ASSERT_EQ(colors.size(), vertices.size());
    for (std::size_t v = 0; v < vertices.size(); ++v)
      ASSERT_EQ(colors[v], brute_force_blend(vertices[v], s.points, s.colors, static_cast<std::size_t>(k)))
          << "vertex " << v << ", k = " << k;
  }
}

TEST(VertexColors, OneNeighbourIsTheNearestSamplesColour) {
  const Samples s = random_samples(500, 3);
  const KdTree<3> tree(s.points);
  const std::vector<Vec3> vertices = random_samples(100, 4).points;
  VertexColorOptions options;
  options.k = 1;
  const std::vector<Color> colors = vertex_colors(vertices, tree, s.colors, options);
  for (std::size_t v = 0; v < vertices.size(); ++v) EXPECT_EQ(colors[v], s.colors[tree.nearest(vertices[v]).index]);
}

// A vertex on a sample takes that sample's colour, whatever the others'.
TEST(VertexColors, AVertexOnASampleTakesItsColour) {
  Samples s;
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 10; ++y) {
      s.points.emplace_back(x, y, 0.0);
      s.colors.push_back({static_cast<std::uint8_t>(25 * x), static_cast<std::uint8_t>(25 * y), 255});
    }
  const KdTree<3> tree(s.points);
  const std::vector<Color> colors = vertex_colors(s.points, tree, s.colors);
  EXPECT_TRUE(colors == s.colors);
  // Halfway between two samples (and far from the rest): their mean.
  const std::vector<Vec3> between = {Vec3(-10.5, 0.0, 0.0)};
  Samples two;
  two.points = {Vec3(-11, 0, 0), Vec3(-10, 0, 0)};
  two.colors = {Color{0, 100, 255}, Color{200, 0, 255}};
  VertexColorOptions options;
  options.k = 2;
  EXPECT_EQ(vertex_colors(between, KdTree<3>(two.points), two.colors, options)[0], (Color{100, 50, 255}));
}

TEST(VertexColors, ThreadCountDoesNotChangeTheColours) {
  const Samples s = random_samples(20000, 5);
  const KdTree<3> tree(s.points);
  const std::vector<Vec3> vertices = random_samples(20000, 6).points;
  const int threads = thread_count();
  std::vector<std::vector<Color>> runs;
  for (const int t : {1, 2, 3}) {
    set_thread_count(t);
    runs.push_back(vertex_colors(vertices, tree, s.colors));
  }
  set_thread_count(threads);
  EXPECT_TRUE(runs[0] == runs[1]);
  EXPECT_TRUE(runs[0] == runs[2]);
}

TEST(VertexColors, Errors) {
  const Samples s = random_samples(10, 7);
  const KdTree<3> tree(s.points);
  const std::vector<Vec3> vertices = {Vec3::Zero()};
  const std::vector<Color> fewer(s.colors.begin(), s.colors.end() - 1);
  EXPECT_THROW(static_cast<void>(vertex_colors(vertices, tree, fewer)), InvalidInputError);
  for (const int k : {0, 65}) {
    VertexColorOptions options;
    options.k = k;
    EXPECT_THROW(static_cast<void>(vertex_colors(vertices, tree, s.colors, options)), InvalidInputError);
  }
  const KdTree<3> empty;
  EXPECT_THROW(static_cast<void>(vertex_colors(vertices, empty, {})), InvalidInputError);
  EXPECT_TRUE(vertex_colors({}, empty, {}).empty());
  // More neighbours asked for than there are samples: all of them.
  VertexColorOptions options;
  options.k = 64;
  EXPECT_EQ(vertex_colors(vertices, tree, s.colors, options)[0],
            brute_force_blend(vertices[0], s.points, s.colors, 10));
}

}  // namespace
}  // namespace recon
