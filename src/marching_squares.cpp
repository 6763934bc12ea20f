#include "recon/marching_squares.h"

#include "recon/errors.h"
#include "recon/marching_cubes.h"  // lattice_margin, shared with the 3D lattice
#include "recon/timer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <string>
#include <unordered_map>

namespace recon {
namespace {

using Index2 = std::array<std::int32_t, 2>;

constexpr std::int32_t max_squares_per_axis = std::int32_t{1} << 30;
constexpr double undefined = std::numeric_limits<double>::quiet_NaN();
constexpr std::uint32_t no_vertex = std::numeric_limits<std::uint32_t>::max();
constexpr double vertex_margin = 1e-3;  // fraction of a side kept between a vertex and a corner

std::uint64_t pack(const Index2& i) {
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(i[0])) |
         (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i[1])) << 32);
}

Index2 unpack(std::uint64_t key) {
  return {static_cast<std::int32_t>(key & 0xffffffffu), static_cast<std::int32_t>(key >> 32)};
}

// Corner c of a square, counter-clockwise from its lower left corner.
Index2 corner_of_square(const Index2& square, int c) {
  static constexpr int dx[4] = {0, 1, 1, 0}, dy[4] = {0, 0, 1, 1};
  return {square[0] + dx[c], square[1] + dy[c]};
}

// Side j runs from corner j to corner j + 1. Its lattice edge starts at the
// lower of the two corners and runs along `axis`.
struct Side {
  int lower_corner;
  int upper_corner;
  int axis;
};
constexpr Side sides[4] = {{0, 1, 0}, {1, 2, 1}, {3, 2, 0}, {0, 3, 1}};

// What the walk knows about one lattice corner: f there, the vertex on each
// lattice edge leaving it in the + direction, and whether the square whose
// lower left corner it is has been visited.
struct Corner {
  double value = undefined;
  std::array<std::uint32_t, 2> vertex{no_vertex, no_vertex};
  bool evaluated = false;
  bool visited_square = false;
};

}  // namespace

MarchingSquaresResult marching_squares(const ScalarField2& f, std::span<const Vec2> seeds,
                                       const MarchingSquaresOptions& options, bool keep_corners) {
  if (!std::isfinite(options.cell) || !(options.cell > 0.0))  // isfinite first: see fp_traps.h
    throw InvalidInputError("the lattice cell size must be a positive length");
  if (!std::isfinite(options.max_slope) || !(options.max_slope >= 0.0))
    throw InvalidInputError("marching squares: the seam test's slope must be 0 (off) or positive");
  Timer timer;
  MarchingSquaresResult result;
  result.cell = options.cell;
  if (seeds.empty()) return result;

  Box<2> box;
  for (const Vec2& p : seeds) box.extend(p);
  const double margin = lattice_margin * options.cell;
  result.origin = box.min - Vec2::Constant(margin);
  for (int a = 0; a < 2; ++a) {
    const double squares = std::ceil((box.max[a] - box.min[a] + 2.0 * margin) / options.cell);
    if (!(squares <= max_squares_per_axis))
      throw ResourceLimitError("the lattice would need " + std::to_string(squares) + " squares along axis " + "xy"[a] +
                               " (at most " + std::to_string(max_squares_per_axis) + "): use a larger --cell");
    result.size[static_cast<std::size_t>(a)] = static_cast<std::int32_t>(squares);
  }
  auto position = [&](const Index2& i) {
    return Vec2(result.origin.x() + i[0] * options.cell, result.origin.y() + i[1] * options.cell);
  };

  std::unordered_map<std::uint64_t, Corner> corners;
  std::chrono::steady_clock::duration field_time{};
  auto corner_at = [&](const Index2& i) -> Corner& {
    Corner& corner = corners[pack(i)];
    if (!corner.evaluated) {
      corner.evaluated = true;
      const auto started = std::chrono::steady_clock::now();
      const std::optional<double> v = f(position(i));
      field_time += std::chrono::steady_clock::now() - started;
      // A NaN from f is undefined too (never compared: see fp_traps.h).
      corner.value = v ? *v : undefined;
    }
    return corner;
  };

  std::deque<Index2> queue;
  auto visit = [&](const Index2& square) {
    if (square[0] < 0 || square[1] < 0 || square[0] >= result.size[0] || square[1] >= result.size[1]) return;
    Corner& lower = corners[pack(square)];
    if (lower.visited_square) return;
    lower.visited_square = true;
    if (++result.visited_squares > options.max_squares)
      throw ResourceLimitError("the lattice walk passed " + std::to_string(options.max_squares) +
                               " squares, the most allowed: use a larger --cell");
    queue.push_back(square);
    if (keep_corners) result.squares.push_back(square);
  };
  for (const Vec2& p : seeds) {
    Index2 square;
    for (std::size_t a = 0; a < 2; ++a)
      square[a] = static_cast<std::int32_t>(std::floor((p[static_cast<int>(a)] - result.origin[static_cast<int>(a)]) /
                                                       options.cell));
    visit(square);
  }
  result.seed_squares = result.visited_squares;

  PolylineSet& curves = result.curves;
  std::vector<std::uint32_t> next;  // per vertex: the vertex its segment leads to
  std::vector<bool> has_previous;
  auto vertex_on = [&](const Index2& square, int s, const std::array<double, 4>& v) {
    const Side& side = sides[s];
    std::uint32_t& id = corner_at(corner_of_square(square, side.lower_corner)).vertex[static_cast<std::size_t>(side.axis)];
    if (id == no_vertex) {
      id = static_cast<std::uint32_t>(curves.vertices.size());
      const double v0 = v[static_cast<std::size_t>(side.lower_corner)];
      const double v1 = v[static_cast<std::size_t>(side.upper_corner)];
      const double t = std::clamp(v0 / (v0 - v1), vertex_margin, 1.0 - vertex_margin);
      Vec2 p = position(corner_of_square(square, side.lower_corner));
      p[side.axis] += t * options.cell;
      curves.vertices.push_back(p);
      next.push_back(no_vertex);
      has_previous.push_back(false);
    }
    return id;
  };

  while (!queue.empty()) {
    const Index2 square = queue.front();
    queue.pop_front();
    std::array<double, 4> v{};
    bool complete = true;
    for (int c = 0; c < 4; ++c) {
      v[static_cast<std::size_t>(c)] = corner_at(corner_of_square(square, c)).value;
      complete = complete && !std::isnan(v[static_cast<std::size_t>(c)]);
    }
    if (!complete) {
      ++result.undefined_squares;
      continue;
    }
    std::array<bool, 4> inside{};
    for (std::size_t c = 0; c < 4; ++c) inside[c] = v[c] < 0.0;
    if (options.max_slope > 0.0) {
      bool seam = false;
      for (const Side& side : sides) {
        const auto a = static_cast<std::size_t>(side.lower_corner), b = static_cast<std::size_t>(side.upper_corner);
        seam = seam || (inside[a] != inside[b] && std::abs(v[a] - v[b]) > options.max_slope * options.cell);
      }
      if (seam) {
        ++result.seam_squares;
        continue;
      }
    }

    // Sides where the curve enters the square (inside corner first, going
    // counter-clockwise) and where it leaves.
    int starts[2], ends[2], start_count = 0, end_count = 0;
    for (int s = 0; s < 4; ++s) {
      const bool a = inside[static_cast<std::size_t>(s)], b = inside[static_cast<std::size_t>((s + 1) % 4)];
      if (a && !b) starts[start_count++] = s;
      if (!a && b) ends[end_count++] = s;
    }
    auto segment = [&](int from, int to) {
      const std::uint32_t a = vertex_on(square, from, v), b = vertex_on(square, to, v);
      next[a] = b;
      has_previous[b] = true;
    };
    if (start_count == 1) {
      segment(starts[0], ends[0]);
    } else if (start_count == 2) {
      ++result.saddle_squares;
      // Both saddle configurations have a denominator of one strict sign:
      // the two inside corners are < 0 and the two outside ones >= 0.
      const double saddle = (v[0] * v[2] - v[1] * v[3]) / (v[0] + v[2] - v[1] - v[3]);
      const int turn = saddle < 0.0 ? 1 : 3;  // joined: the next side; cut apart: the previous one
      for (const int s : starts) segment(s, (s + turn) % 4);
    }

    for (int s = 0; s < 4; ++s) {
      const auto lower = static_cast<std::size_t>(sides[s].lower_corner);
      const auto upper = static_cast<std::size_t>(sides[s].upper_corner);
      if (inside[lower] == inside[upper] && v[lower] != 0.0 && v[upper] != 0.0) continue;
      static constexpr int step_x[4] = {0, 1, 0, -1}, step_y[4] = {-1, 0, 1, 0};
      visit({square[0] + step_x[s], square[1] + step_y[s]});
    }
  }

  // Chains: first those with a free end (open), then the loops left.
  std::vector<bool> used(curves.vertices.size(), false);
  auto follow = [&](std::uint32_t start) {
    Polyline line;
    std::uint32_t at = start;
    while (at != no_vertex && !used[at]) {
      used[at] = true;
      line.vertices.push_back(at);
      at = next[at];
    }
    line.closed = at == start;
    curves.polylines.push_back(std::move(line));
  };
  for (std::uint32_t i = 0; i < curves.vertices.size(); ++i)
    if (!has_previous[i]) follow(i);
  for (std::uint32_t i = 0; i < curves.vertices.size(); ++i)
    if (!used[i]) follow(i);

  result.evaluated_corners = 0;
  for (const auto& [key, corner] : corners) {
    if (!corner.evaluated) continue;
    ++result.evaluated_corners;
    const bool defined = !std::isnan(corner.value);
    if (!defined) ++result.undefined_corners;
    if (keep_corners) result.corners.push_back({unpack(key), defined ? corner.value : 0.0, defined});
  }
  if (keep_corners)  // the hash table's order is not a documented one
    std::sort(result.corners.begin(), result.corners.end(),
              [](const SquareCorner& a, const SquareCorner& b) { return a.index < b.index; });
  result.seconds = timer.lap();
  result.seconds_field = std::chrono::duration<double>(field_time).count();
  return result;
}

}  // namespace recon
