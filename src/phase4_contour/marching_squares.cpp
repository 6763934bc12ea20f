#include "recon/phase4_contour/marching_squares.h"

#include "recon/core/errors.h"
#include "recon/core/timer.h"
#include "recon/structures/lattice.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <string>
#include <unordered_map>

namespace recon {
namespace {

using Index2 = Lattice<2>::Index;

constexpr double undefined = std::numeric_limits<double>::quiet_NaN();
constexpr std::uint32_t no_vertex = std::numeric_limits<std::uint32_t>::max();
constexpr double vertex_margin = 1e-3;  // fraction of a side kept between a vertex and a corner

std::uint64_t pack(const Index2& i) { return Lattice<2>::key(i); }

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

// The walk's state between its steps: the lattice, the corners met (in a
// plain hash map: the 2D walk is serial and small), the queue of squares,
// and the segments drawn so far (per vertex, the vertex its segment leads
// to).
class SquareWalk {
 public:
  SquareWalk(const ScalarField2& f, const Lattice<2>& lattice, const MarchingSquaresOptions& options,
             MarchingSquaresResult& result)
      : f_(f), lattice_(lattice), options_(options), result_(result) {}

  void seed(std::span<const Vec2> seeds);
  void walk();
  void chain();
  void summarise();

 private:
  Corner& corner_at(const Index2& i);
  void visit(const Index2& square);
  [[nodiscard]] bool is_seam(const std::array<double, 4>& v, const std::array<bool, 4>& inside) const;
  void emit_segments(const Index2& square, const std::array<double, 4>& v, const std::array<bool, 4>& inside);
  std::uint32_t vertex_on(const Index2& square, int s, const std::array<double, 4>& v);
  void go_on(const Index2& square, const std::array<double, 4>& v, const std::array<bool, 4>& inside);
  void follow(std::uint32_t start, std::vector<bool>& used);

  const ScalarField2& f_;
  const Lattice<2>& lattice_;
  const MarchingSquaresOptions& options_;
  MarchingSquaresResult& result_;
  std::unordered_map<std::uint64_t, Corner> corners_;
  std::deque<Index2> queue_;
  std::vector<std::uint32_t> next_;  // per vertex: the vertex its segment leads to
  std::vector<bool> has_previous_;
  std::chrono::steady_clock::duration field_time_{};
};

// The corner's record, f evaluated there the first time it is asked for.
Corner& SquareWalk::corner_at(const Index2& i) {
  Corner& corner = corners_[pack(i)];
  if (!corner.evaluated) {
    corner.evaluated = true;
    const auto started = std::chrono::steady_clock::now();
    const std::optional<double> v = f_(lattice_.position(i));
    field_time_ += std::chrono::steady_clock::now() - started;
    // A NaN from f is undefined too (never compared: see fp_traps.h).
    corner.value = v ? *v : undefined;
  }
  return corner;
}

// A square of the lattice not visited yet joins the queue.
void SquareWalk::visit(const Index2& square) {
  if (!lattice_.contains(square)) return;
  Corner& lower = corners_[pack(square)];
  if (lower.visited_square) return;
  lower.visited_square = true;
  if (++result_.visited_squares > options_.max_squares)
    throw ResourceLimitError("the lattice walk passed " + std::to_string(options_.max_squares) +
                             " squares, the most allowed: use a larger --cell");
  queue_.push_back(square);
  if (options_.keep_corners) result_.squares.push_back(square);
}

// Find: the squares that hold a seed start the walk.
void SquareWalk::seed(std::span<const Vec2> seeds) {
  for (const Vec2& p : seeds) visit(lattice_.cell_of(p));
  result_.seed_squares = result_.visited_squares;
}

// The walk, square by square in the order met: evaluate its corners,
// classify them, emit its segments and go on across the sides the curve
// crosses.
void SquareWalk::walk() {
  while (!queue_.empty()) {
    const Index2 square = queue_.front();
    queue_.pop_front();
    std::array<double, 4> v{};
    bool complete = true;
    for (int c = 0; c < 4; ++c) {
      v[static_cast<std::size_t>(c)] = corner_at(corner_of_square(square, c)).value;
      complete = complete && !std::isnan(v[static_cast<std::size_t>(c)]);
    }
    if (!complete) {
      ++result_.undefined_squares;
      continue;
    }
    std::array<bool, 4> inside{};
    for (std::size_t c = 0; c < 4; ++c) inside[c] = v[c] < 0.0;
    if (is_seam(v, inside)) {
      ++result_.seam_squares;
      continue;
    }
    emit_segments(square, v, inside);
    go_on(square, v, inside);
  }
}

// The seam test (max_slope > 0): a side where f changes sign too steeply.
bool SquareWalk::is_seam(const std::array<double, 4>& v, const std::array<bool, 4>& inside) const {
  if (!(options_.max_slope > 0.0)) return false;
  bool seam = false;
  for (const Side& side : sides) {
    const auto a = static_cast<std::size_t>(side.lower_corner), b = static_cast<std::size_t>(side.upper_corner);
    seam = seam || (inside[a] != inside[b] && std::abs(v[a] - v[b]) > options_.max_slope * options_.cell);
  }
  return seam;
}

// The square's segments, from the side where the curve enters (inside
// corner first, going counter-clockwise) to the side where it leaves; a
// saddle decided by the bilinear interpolant's value at its saddle point.
void SquareWalk::emit_segments(const Index2& square, const std::array<double, 4>& v,
                               const std::array<bool, 4>& inside) {
  int starts[2], ends[2], start_count = 0, end_count = 0;
  for (int s = 0; s < 4; ++s) {
    const bool a = inside[static_cast<std::size_t>(s)], b = inside[static_cast<std::size_t>((s + 1) % 4)];
    if (a && !b) starts[start_count++] = s;
    if (!a && b) ends[end_count++] = s;
  }
  auto segment = [&](int from, int to) {
    const std::uint32_t a = vertex_on(square, from, v), b = vertex_on(square, to, v);
    next_[a] = b;
    has_previous_[b] = true;
  };
  if (start_count == 1) {
    segment(starts[0], ends[0]);
  } else if (start_count == 2) {
    ++result_.saddle_squares;
    // Both saddle configurations have a denominator of one strict sign:
    // the two inside corners are < 0 and the two outside ones >= 0.
    const double saddle = (v[0] * v[2] - v[1] * v[3]) / (v[0] + v[2] - v[1] - v[3]);
    const int turn = saddle < 0.0 ? 1 : 3;  // joined: the next side; cut apart: the previous one
    for (const int s : starts) segment(s, (s + turn) % 4);
  }
}

// The vertex on side s, made the first time a square asks for it and kept
// in the record of the side's lower corner (shared with the neighbour).
std::uint32_t SquareWalk::vertex_on(const Index2& square, int s, const std::array<double, 4>& v) {
  const Side& side = sides[s];
  const Index2 lower = corner_of_square(square, side.lower_corner);
  std::uint32_t& id = corner_at(lower).vertex[static_cast<std::size_t>(side.axis)];
  if (id == no_vertex) {
    PolylineSet& curves = result_.curves;
    id = static_cast<std::uint32_t>(curves.vertices.size());
    const double v0 = v[static_cast<std::size_t>(side.lower_corner)];
    const double v1 = v[static_cast<std::size_t>(side.upper_corner)];
    const double t = std::clamp(v0 / (v0 - v1), vertex_margin, 1.0 - vertex_margin);
    Vec2 p = lattice_.position(lower);
    p[side.axis] += t * options_.cell;
    curves.vertices.push_back(p);
    next_.push_back(no_vertex);
    has_previous_.push_back(false);
  }
  return id;
}

// The neighbours across the sides where the signs differ or f = 0 at a corner.
void SquareWalk::go_on(const Index2& square, const std::array<double, 4>& v, const std::array<bool, 4>& inside) {
  for (int s = 0; s < 4; ++s) {
    const auto lower = static_cast<std::size_t>(sides[s].lower_corner);
    const auto upper = static_cast<std::size_t>(sides[s].upper_corner);
    if (inside[lower] == inside[upper] && v[lower] != 0.0 && v[upper] != 0.0) continue;
    static constexpr int step_x[4] = {0, 1, 0, -1}, step_y[4] = {-1, 0, 1, 0};
    visit({square[0] + step_x[s], square[1] + step_y[s]});
  }
}

// Chain the segments head to tail: first the chains with a free end
// (open), then the loops left.
void SquareWalk::chain() {
  const std::size_t n = result_.curves.vertices.size();
  std::vector<bool> used(n, false);
  for (std::uint32_t i = 0; i < n; ++i)
    if (!has_previous_[i]) follow(i, used);
  for (std::uint32_t i = 0; i < n; ++i)
    if (!used[i]) follow(i, used);
}

void SquareWalk::follow(std::uint32_t start, std::vector<bool>& used) {
  Polyline line;
  std::uint32_t at = start;
  while (at != no_vertex && !used[at]) {
    used[at] = true;
    line.vertices.push_back(at);
    at = next_[at];
  }
  line.closed = at == start;
  result_.curves.polylines.push_back(std::move(line));
}

// The counts, and the corners sorted (the hash map's order is not a
// documented one) when kept.
void SquareWalk::summarise() {
  result_.evaluated_corners = 0;
  for (const auto& [key, corner] : corners_) {
    if (!corner.evaluated) continue;
    ++result_.evaluated_corners;
    const bool defined = !std::isnan(corner.value);
    if (!defined) ++result_.undefined_corners;
    if (options_.keep_corners)
      result_.corners.push_back({Lattice<2>::index(key), defined ? corner.value : 0.0, defined});
  }
  if (options_.keep_corners)
    std::sort(result_.corners.begin(), result_.corners.end(),
              [](const SquareCorner& a, const SquareCorner& b) { return a.index < b.index; });
  result_.seconds_field = std::chrono::duration<double>(field_time_).count();
}

}  // namespace

MarchingSquaresResult marching_squares(const ScalarField2& f, std::span<const Vec2> seeds,
                                       const MarchingSquaresOptions& options) {
  check_lattice_cell(options.cell);
  if (!std::isfinite(options.max_slope) || !(options.max_slope >= 0.0))
    throw InvalidInputError("marching squares: the seam test's slope must be 0 (off) or positive");
  Timer timer;
  MarchingSquaresResult result;
  result.cell = options.cell;
  if (seeds.empty()) return result;
  const Lattice<2> lattice = make_lattice<2>(seeds, options.cell);
  result.origin = lattice.origin;
  result.size = lattice.size;
  SquareWalk walk(f, lattice, options, result);
  walk.seed(seeds);
  walk.walk();
  walk.chain();
  walk.summarise();
  result.seconds = timer.lap();
  return result;
}

}  // namespace recon
