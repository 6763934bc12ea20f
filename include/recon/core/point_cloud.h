#pragma once
// Basic geometric types shared by every phase.

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace recon {

/// A point or vector in D dimensions (D = 2 for curves, 3 for surfaces).
template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
using Vec2 = Vec<2>;
using Vec3 = Vec<3>;

/// The largest coordinate magnitude recon accepts. Beyond it, squared
/// distances and lattice indices lose the precision the phases rely on;
/// readers refuse such values (with how many and where the first is) and
/// so does the kd-tree. Real scans, even geo-referenced ones in millimetres,
/// stay far below it.
inline constexpr double max_coordinate = 1e15;

/// A colour: red, green, blue, 0 to 255 each.
using Color = std::array<std::uint8_t, 3>;

/// An unorganized point cloud: positions, and normals and colours when the
/// source had them. `normals` and `colors` are each either empty or have
/// exactly one entry per position.
struct PointCloud {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<Color> colors;

  [[nodiscard]] std::size_t size() const { return positions.size(); }
  [[nodiscard]] bool has_normals() const { return !normals.empty(); }
  [[nodiscard]] bool has_colors() const { return !colors.empty(); }
};

/// A point cloud held elsewhere (numpy arrays, a memory map), seen in place:
/// the same arrays as PointCloud, not owned, never copied by the view.
struct PointCloudView {
  std::span<const Vec3> positions;
  std::span<const Vec3> normals;  ///< empty or one per position
  std::span<const Color> colors;  ///< empty or one per position

  PointCloudView() = default;
  PointCloudView(const PointCloud& cloud)  // NOLINT: a cloud is its own view
      : positions(cloud.positions), normals(cloud.normals), colors(cloud.colors) {}
  PointCloudView(std::span<const Vec3> p, std::span<const Vec3> n, std::span<const Color> c)
      : positions(p), normals(n), colors(c) {}
  [[nodiscard]] std::size_t size() const { return positions.size(); }
  [[nodiscard]] bool has_normals() const { return !normals.empty(); }
  [[nodiscard]] bool has_colors() const { return !colors.empty(); }
};

/// Axis-aligned bounding box.
template <int D>
struct Box {
  Vec<D> min = Vec<D>::Constant(std::numeric_limits<double>::infinity());
  Vec<D> max = Vec<D>::Constant(-std::numeric_limits<double>::infinity());

  void extend(const Vec<D>& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  [[nodiscard]] bool empty() const { return (min.array() > max.array()).any(); }
  [[nodiscard]] Vec<D> extent() const { return max - min; }
  [[nodiscard]] double diagonal() const { return empty() ? 0.0 : extent().norm(); }
};

/// The smallest box holding `points`; empty() for no points.
/// Cost: O(n).
/// Throws: nothing.
/// Pre: finite coordinates.
template <int D>
[[nodiscard]] Box<D> bounding_box(std::span<const Vec<D>> points) {
  Box<D> box;
  for (const auto& p : points) box.extend(p);
  return box;
}

}  // namespace recon
