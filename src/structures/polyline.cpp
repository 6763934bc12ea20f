#include "recon/structures/polyline.h"

#include <algorithm>

namespace recon {

std::size_t PolylineSet::closed_count() const {
  return static_cast<std::size_t>(
      std::count_if(polylines.begin(), polylines.end(), [](const Polyline& line) { return line.closed; }));
}

double length(const PolylineSet& set, const Polyline& line) {
  const std::size_t n = line.vertices.size();
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i)
    total += (set.vertices[line.vertices[i + 1]] - set.vertices[line.vertices[i]]).norm();
  if (line.closed && n > 1) total += (set.vertices[line.vertices[0]] - set.vertices[line.vertices[n - 1]]).norm();
  return total;
}

double signed_area(const PolylineSet& set, const Polyline& line) {
  if (!line.closed) return 0.0;
  const std::size_t n = line.vertices.size();
  if (n == 0) return 0.0;
  // Relative to the first vertex: far from the origin, products of raw
  // coordinates would cancel away the digits the area lives in.
  const Vec2 o = set.vertices[line.vertices[0]];
  double twice = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = set.vertices[line.vertices[i]] - o;
    const Vec2 b = set.vertices[line.vertices[(i + 1) % n]] - o;
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * twice;
}

}  // namespace recon
