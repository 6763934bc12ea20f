#pragma once
// Polylines: the curves of the 2D reconstruction (what a Mesh is in 3D).

#include "recon/core/point_cloud.h"

#include <cstdint>
#include <vector>

namespace recon {

/// An ordered chain of vertices. A closed polyline also joins its last
/// vertex back to its first (which is not repeated at the end).
struct Polyline {
  std::vector<std::uint32_t> vertices;  ///< indices into PolylineSet::vertices, in curve order
  bool closed = false;
};

/// Polylines over shared vertices. A reconstructed curve runs with the
/// inside (where the signed distance is negative) on its left: a closed
/// curve around a solid runs counter-clockwise (positive signed area), one
/// around a hole clockwise.
struct PolylineSet {
  std::vector<Vec2> vertices;
  std::vector<Polyline> polylines;

  [[nodiscard]] std::size_t closed_count() const;
  [[nodiscard]] std::size_t open_count() const { return polylines.size() - closed_count(); }
};

/// Total length of the segments of `line` (with the closing one when closed).
/// Cost: O(m) for m vertices in `line`.
/// Throws: nothing.
/// Pre: line's indices are below set.vertices.size().
[[nodiscard]] double length(const PolylineSet& set, const Polyline& line);
/// Signed area enclosed by a closed polyline (shoelace formula): positive
/// when it runs counter-clockwise. 0 for an open one.
/// Cost: O(m) for m vertices in `line`.
/// Throws: nothing.
/// Pre: line's indices are below set.vertices.size().
[[nodiscard]] double signed_area(const PolylineSet& set, const Polyline& line);

}  // namespace recon
