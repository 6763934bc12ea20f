#include "recon/phase1_planes/local_quadrics.h"

#include "recon/core/errors.h"
#include "recon/core/progress.h"
#include "recon/core/timer.h"
#include "recon/phase1_planes/pca.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>
#include <utility>

namespace recon {

std::array<Vec3, 2> tangent_basis(const Vec3& n) {
  // Two unit vectors perpendicular to n and to each other, built from n's
  // coordinates without a division by a small number (the sign of n.z picks
  // the formula that stays away from 1 / 0).
  const double sign = n.z() >= 0.0 ? 1.0 : -1.0;
  const double a = -1.0 / (sign + n.z());
  const double b = n.x() * n.y() * a;
  return {Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x()), Vec3(b, sign + n.y() * n.y() * a, -n.y())};
}

namespace {

using Row = std::span<const std::uint32_t>;

// The height function w = a u^2 + b u v + c v^2 + d u + e v + g over the
// frame (origin, t1, t2, normal), in the data's units.
struct Quadric {
  Vec3 origin = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  std::array<double, 6> c{};  // a b c d e g
  double residual = 0.0;      // RMS of w - h(u, v) over the fitted samples
  bool flat = false;          // fell back to the plane

  [[nodiscard]] double height(double u, double v) const {
    return c[0] * u * u + c[1] * u * v + c[2] * v * v + c[3] * u + c[4] * v + c[5];
  }
  [[nodiscard]] std::array<double, 2> slope(double u, double v) const {
    return {2.0 * c[0] * u + c[1] * v + c[3], c[1] * u + 2.0 * c[2] * v + c[4]};
  }
};

struct Local {
  double u, v, w;
};

Local local(const Quadric& q, const std::array<Vec3, 2>& t, const Vec3& p) {
  const Vec3 d = p - q.origin;
  return {d.dot(t[0]), d.dot(t[1]), d.dot(q.normal)};
}

constexpr std::uint32_t own_frame = UINT32_MAX;

// Every sample's fit, kept compactly while the samples choose among them:
// the coefficients and residual in float (far more precise than the data
// they describe), the frame phase I's plane unless the fit was redone on
// one sheet (frames then holds it).
class Fits {
 public:
  explicit Fits(const TangentPlanes<3>& planes) : planes_(&planes), packed_(planes.origins.size()) {}

  [[nodiscard]] std::size_t size() const { return packed_.size(); }
  [[nodiscard]] double residual(std::size_t i) const { return static_cast<double>(packed_[i].residual); }
  [[nodiscard]] bool flat(std::size_t i) const { return packed_[i].flat != 0; }
  [[nodiscard]] Quadric operator[](std::size_t i) const {
    const Packed& p = packed_[i];
    Quadric q;
    q.origin = p.frame == own_frame ? planes_->origins[i] : frames[p.frame].origin;
    q.normal = p.frame == own_frame ? planes_->normals[i] : frames[p.frame].normal;
    for (std::size_t c = 0; c < 6; ++c) q.c[c] = static_cast<double>(p.c[c]);
    q.residual = static_cast<double>(p.residual);
    q.flat = p.flat != 0;
    return q;
  }
  /// (In phase I's frame of sample i, or in frames[frame].)
  void set(std::size_t i, const Quadric& q, std::uint32_t frame = own_frame) {
    Packed& p = packed_[i];
    for (std::size_t c = 0; c < 6; ++c) p.c[c] = static_cast<float>(q.c[c]);
    p.residual = static_cast<float>(q.residual);
    p.flat = q.flat ? 1 : 0;
    p.frame = frame;
  }

  struct Frame {
    Vec3 origin, normal;
  };
  std::vector<Frame> frames;

 private:
  struct Packed {
    std::array<float, 6> c{};
    float residual = 0.0f;
    std::uint32_t frame = own_frame;
    std::uint8_t flat = 1;
  };
  const TangentPlanes<3>* planes_;
  std::vector<Packed> packed_;
};

// Solves the 6 x 6 symmetric positive definite system (lower triangle
// packed by rows in m: m[i (i + 1) / 2 + j] for j <= i) in place by
// Cholesky's method, the solution replacing b. False when a pivot is
// negligible (the samples do not pin down a quadric: too few, or on a line).
bool solve_cholesky_6(std::array<double, 21>& m, std::array<double, 6>& b) {
  auto at = [&m](std::size_t i, std::size_t j) -> double& { return m[i * (i + 1) / 2 + j]; };
  double largest = 0.0;
  for (std::size_t i = 0; i < 6; ++i) largest = std::max(largest, at(i, i));
  for (std::size_t i = 0; i < 6; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      double sum = at(i, j);
      for (std::size_t k = 0; k < j; ++k) sum -= at(i, k) * at(j, k);
      if (i == j) {
        if (!(sum > 1e-9 * largest)) return false;
        at(i, i) = std::sqrt(sum);
      } else {
        at(i, j) = sum / at(j, j);
      }
    }
  }
  for (std::size_t i = 0; i < 6; ++i) {  // L y = b
    for (std::size_t k = 0; k < i; ++k) b[i] -= at(i, k) * b[k];
    b[i] /= at(i, i);
  }
  for (std::size_t i = 6; i-- > 0;) {  // L^T x = y
    for (std::size_t k = i + 1; k < 6; ++k) b[i] -= at(k, i) * b[k];
    b[i] /= at(i, i);
  }
  return true;
}

// Least squares over the samples `rows` of the plane fit `plane`: the
// frame is the plane's, coordinates are scaled by the farthest sample so
// that the 6 x 6 normal equations stay well conditioned.
// `heights`, when not empty, receives each sample's height over the plane.
Quadric fit_quadric(std::span<const Vec3> x, Row rows, const PlaneFit<3>& plane, std::span<double> heights = {}) {
  Quadric q;
  q.origin = plane.centroid;
  q.normal = plane.normal;
  const auto t = tangent_basis(q.normal);
  std::array<Local, 256> at;  // rows.size() <= 256 (phase I's largest k)
  const std::size_t count = std::min(rows.size(), at.size());
  double scale2 = 0.0;
  for (std::size_t r = 0; r < count; ++r) {
    at[r] = local(q, t, x[rows[r]]);
    scale2 = std::max(scale2, at[r].u * at[r].u + at[r].v * at[r].v + at[r].w * at[r].w);
    if (!heights.empty()) heights[r] = at[r].w;
  }
  q.flat = true;
  if (scale2 > 0.0 && count >= 6) {
    const double scale = std::sqrt(scale2), inverse = 1.0 / scale;
    std::array<double, 21> normal_matrix{};  // rows (u^2, uv, v^2, u, v, 1), lower triangle
    std::array<double, 6> right{};
    for (std::size_t r = 0; r < count; ++r) {
      const double u = at[r].u * inverse, v = at[r].v * inverse, w = at[r].w * inverse;
      const std::array<double, 6> a{u * u, u * v, v * v, u, v, 1.0};
      std::size_t e = 0;
      for (std::size_t i = 0; i < 6; ++i) {
        for (std::size_t j = 0; j <= i; ++j) normal_matrix[e++] += a[i] * a[j];
        right[i] += a[i] * w;
      }
    }
    if (solve_cholesky_6(normal_matrix, right)) {
      q.c = {right[0] * inverse, right[1] * inverse, right[2] * inverse, right[3], right[4], right[5] * scale};
      q.flat = false;
    }
  }
  double sum2 = 0.0;
  for (std::size_t r = 0; r < count; ++r) {
    const double e = at[r].w - q.height(at[r].u, at[r].v);
    sum2 += e * e;
  }
  q.residual = count == 0 ? 0.0 : std::sqrt(sum2 / static_cast<double>(count));
  return q;
}

// The (u, v) of p's foot on the quadric's graph.
std::array<double, 2> drop(const Quadric& q, const Local& l) {
  double u = l.u, v = l.v;
  for (int step = 0; step < 3; ++step) {
    const auto g = q.slope(u, v);
    const Vec3 m = Vec3(-g[0], -g[1], 1.0).normalized();
    const double off = (Vec3(l.u, l.v, l.w) - Vec3(u, v, q.height(u, v))).dot(m);
    const Vec3 moved = Vec3(l.u, l.v, l.w) - off * m;
    u = moved.x();
    v = moved.y();
  }
  return {u, v};
}

// Where p lands on the quadric, moved along the surface's normal, with the
// normal and the curvature there.
struct Foot {
  Vec3 point;
  Vec3 normal;
  Curvature curvature;
};

Foot foot_on(const Quadric& q, const Vec3& p, const Vec3& side) {
  const auto t = tangent_basis(q.normal);
  const auto [u, v] = drop(q, local(q, t, p));
  const auto g = q.slope(u, v);
  const double w = std::sqrt(1.0 + g[0] * g[0] + g[1] * g[1]);
  Foot foot;
  foot.point = q.origin + u * t[0] + v * t[1] + q.height(u, v) * q.normal;
  foot.normal = ((q.normal - g[0] * t[0] - g[1] * t[1]) / w).normalized();
  // Heights along the normal kept must be measured on its side.
  const double sign = foot.normal.dot(side) < 0.0 ? -1.0 : 1.0;
  foot.normal *= sign;
  // The height over the tangent plane at the foot is (a du^2 + b du dv +
  // c dv^2) / w, where (du, dv) are a tangent vector's components along
  // (t1, t2); rewritten for the basis of the foot's own normal.
  const auto s = tangent_basis(foot.normal);
  const double j11 = s[0].dot(t[0]), j12 = s[1].dot(t[0]), j21 = s[0].dot(t[1]), j22 = s[1].dot(t[1]);
  const double a = sign * q.c[0] / w, b = sign * q.c[1] / w, c = sign * q.c[2] / w;
  foot.curvature.p = static_cast<float>(a * j11 * j11 + b * j11 * j21 + c * j21 * j21);
  foot.curvature.q = static_cast<float>(2.0 * a * j11 * j12 + b * (j11 * j22 + j12 * j21) + 2.0 * c * j21 * j22);
  foot.curvature.r = static_cast<float>(a * j12 * j12 + b * j12 * j22 + c * j22 * j22);
  return foot;
}

// Whether heights could hold an empty band wider than `gap` times their
// range, by counting them in bins: such a band covers some run of bins
// whole, and a neighbourhood on one sheet (nearly all of them) has no run
// of empty bins that long. Saves sorting every neighbourhood.
bool may_have_band(std::span<const double> heights, double gap) {
  constexpr std::size_t bins = 16;
  const auto [low, high] = std::minmax_element(heights.begin(), heights.end());
  const double range = *high - *low;
  if (!(range > 0.0)) return false;
  std::array<std::uint8_t, bins> filled{};
  for (const double h : heights)
    filled[std::min(bins - 1, static_cast<std::size_t>((h - *low) / range * static_cast<double>(bins)))] = 1;
  // Whole bins inside any wider band, less one for rounding at bin edges.
  const int run_needed = static_cast<int>(std::floor(gap * static_cast<double>(bins))) - 2;
  int run = 0;
  for (const std::uint8_t f : filled) {
    run = f ? 0 : run + 1;
    if (run >= std::max(1, run_needed)) return true;
  }
  return false;
}

// Two sheets: heights over a neighbourhood's plane that fall in two groups
// of at least `min_points` with an empty band wider than `gap` times the
// whole range between them. Returns the height in the middle of the band,
// or NaN when there is no such band. Sorts `heights`.
double sheet_cut(std::span<double> heights, const LocalQuadricOptions& options) {
  constexpr double none_found = std::numeric_limits<double>::quiet_NaN();
  if (heights.empty() || !may_have_band(heights, options.sheet_gap)) return none_found;
  std::sort(heights.begin(), heights.end());
  const auto m = static_cast<std::size_t>(std::max(1, options.min_sheet_points));
  const double range = heights.back() - heights.front();
  double widest = 0.0, cut = none_found;
  for (std::size_t p = m; p + m <= heights.size(); ++p) {
    const double band = heights[p] - heights[p - 1];
    if (band > widest) {
      widest = band;
      cut = 0.5 * (heights[p] + heights[p - 1]);
    }
  }
  return range > 0.0 && widest > options.sheet_gap * range ? cut : none_found;
}

// Step 2 for one sample: when its neighbourhood spans two sheets, the
// quadric of the part on x_i's own sheet (the split must explain the
// misfit: its residual at most a quarter of the whole's). The heights are
// taken over phase I's plane, or, where that plane leans across both sheets
// (a neighbourhood reaching over one side only), over the plane of x_i's
// nearest third of its neighbours, which lie on its own sheet.
struct SheetFit {
  Quadric quadric;
  Vec3 origin, normal;                                    // the plane the heights were taken over
  double cut = std::numeric_limits<double>::quiet_NaN();  // the sheets' dividing height over it
  bool above = false;                                     // x_i's sheet lies above the cut
};

double cut_over(std::span<const Vec3> x, Row row, const Vec3& o, const Vec3& n, const LocalQuadricOptions& options,
                std::vector<double>& heights) {
  heights.clear();
  for (const std::uint32_t j : row) heights.push_back((x[j] - o).dot(n));
  return sheet_cut(heights, options);
}

// Two parallel sheets closer than `separation` (the lattice could not
// follow them apart) stay one surface between them: the other side's
// samples, fitted with a plane parallel to this sheet's and nearer than
// that. (The other side of a crease is no parallel sheet and is split off.)
// `same` narrows to the separations that decide this pair alike.
bool too_close_to_split(std::span<const Vec3> x, Row row, const Vec3& o, const Vec3& n, double cut, bool above,
                        const PlaneFit<3>& sheet, double separation, SeparationRange& same) {
  if (!(separation > 0.0)) return false;
  std::vector<std::uint32_t> other;
  for (const std::uint32_t j : row)
    if (((x[j] - o).dot(n) > cut) != above) other.push_back(j);
  if (other.size() < 3) return false;
  const PlaneFit<3> far = fit_plane<3>(x, other);
  if (!(std::abs(far.normal.dot(sheet.normal)) > 0.9)) return false;
  const double gap = std::abs((far.centroid - sheet.centroid).dot(sheet.normal));
  if (gap < separation) {
    same.below = std::max(same.below, gap);
    return true;
  }
  same.up_to = std::min(same.up_to, gap);
  return false;
}

SheetFit fit_own_sheet(const TangentPlanes<3>& planes, std::size_t i, const Quadric& whole,
                       const LocalQuadricOptions& options, std::vector<double>& heights,
                       std::vector<std::uint32_t>& kept, SeparationRange& same) {
  const std::span<const Vec3> x = planes.point_tree.points();
  const Row row = planes.neighbors.row(i);
  SheetFit fit{whole, planes.origins[i], planes.normals[i]};
  double cut = cut_over(x, row, fit.origin, fit.normal, options, heights);
  if (std::isnan(cut)) {
    const PlaneFit<3> near = fit_plane<3>(x, row.first(std::max<std::size_t>(6, row.size() / 3)));
    if (!(near.eigenvalues[1] > 1e-6 * near.eigenvalues[2])) return fit;
    fit.origin = near.centroid;
    fit.normal = near.normal.dot(planes.normals[i]) < 0.0 ? Vec3(-near.normal) : near.normal;
    cut = cut_over(x, row, fit.origin, fit.normal, options, heights);
    if (std::isnan(cut)) return fit;
  }
  const Vec3 &o = fit.origin, &n = fit.normal;
  const bool above = (x[i] - o).dot(n) > cut;
  kept.clear();
  for (const std::uint32_t j : row)
    if (((x[j] - o).dot(n) > cut) == above) kept.push_back(j);
  // The own sheet must be a sheet: enough distinct samples spread in two
  // directions, lying along the plane (two sheets of a thin part are nearly
  // parallel), and fitted far better than the whole.
  std::sort(kept.begin(), kept.end(), [&x](std::uint32_t a, std::uint32_t b) {
    return std::lexicographical_compare(x[a].data(), x[a].data() + 3, x[b].data(), x[b].data() + 3);
  });
  const auto distinct =
      std::unique(kept.begin(), kept.end(), [&x](std::uint32_t a, std::uint32_t b) { return x[a] == x[b]; });
  kept.erase(distinct, kept.end());
  if (kept.size() < 6) return fit;
  PlaneFit<3> sheet = fit_plane<3>(x, kept);
  if (!(sheet.eigenvalues[1] > 1e-6 * sheet.eigenvalues[2]) || std::abs(sheet.normal.dot(n)) < 0.9) return fit;
  if (too_close_to_split(x, row, o, n, cut, above, sheet, options.min_sheet_separation, same)) return fit;
  if (sheet.normal.dot(planes.normals[i]) < 0.0) sheet.normal = -sheet.normal;
  const Quadric part = fit_quadric(x, kept, sheet);
  if (part.flat || !(part.residual < 0.25 * whole.residual)) return fit;
  fit.quadric = part;
  fit.cut = cut;
  fit.above = above;
  return fit;
}

// Step 3 for one poorly fitted sample: the best-fitting quadric among its
// neighbours' that x_i lies on (its own unless one fits clearly better).
// Near a corner no neighbourhood of a neighbour may lie on one face; when
// the best one still fits worse than `poor`, the neighbours' neighbours are
// asked.
struct Support {
  std::uint32_t index;
  double residual;
};

// x_i lies on j's quadric when within three times its residual (and a
// millionth of its neighbourhood, for rounding on exact data).
void consider(const TangentPlanes<3>& planes, std::uint32_t i, std::uint32_t j, const Fits& fits, Support& best) {
  if (!(fits.residual(j) < best.residual)) return;
  const Quadric q = fits[j];
  const Local l = local(q, tangent_basis(q.normal), planes.point_tree.points()[i]);
  if (std::abs(l.w - q.height(l.u, l.v)) <= 3.0 * q.residual + 1e-6 * static_cast<double>(planes.radius[j]))
    best = {j, q.residual};
}

std::uint32_t support_of(const TangentPlanes<3>& planes, std::uint32_t i, const Fits& fits,
                         const LocalQuadricOptions& options, double poor) {
  Support best{i, options.crease_ratio * fits.residual(i)};
  for (const std::uint32_t j : planes.neighbors.row(i)) consider(planes, i, j, fits, best);
  if (best.index == i ? fits.residual(i) <= poor : best.residual <= poor) return best.index;
  for (const std::uint32_t j : planes.neighbors.row(i))
    for (const std::uint32_t m : planes.neighbors.row(j)) consider(planes, i, m, fits, best);
  return best.index;
}

double median_radius(std::span<const float> radius) {
  std::vector<float> sorted(radius.begin(), radius.end());
  if (sorted.empty()) return 0.0;
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  return static_cast<double>(*middle);
}

// The median of the fits' finite residuals and their lower quartile (the
// values nth_element puts at ranks n / 2 and n / 4), 0 where there are none.
std::pair<double, double> median_and_quartile(const Fits& fits) {
  std::vector<double> residual;
  residual.reserve(fits.size());
  for (std::size_t i = 0; i < fits.size(); ++i)
    if (std::isfinite(fits.residual(i))) residual.push_back(fits.residual(i));
  if (residual.empty()) return {0.0, 0.0};
  const auto middle = residual.begin() + static_cast<std::ptrdiff_t>(residual.size() / 2);
  std::nth_element(residual.begin(), middle, residual.end());
  const auto quarter = residual.begin() + static_cast<std::ptrdiff_t>(residual.size() / 4);
  std::nth_element(residual.begin(), quarter, middle);
  return {*middle, *quarter};
}

}  // namespace

SurfacePoint project_onto_quadric(const Vec3& origin, const Vec3& normal, const Curvature& curvature, const Vec3& p) {
  Quadric q;
  q.origin = origin;
  q.normal = normal;
  q.c = {static_cast<double>(curvature.p),
         static_cast<double>(curvature.q),
         static_cast<double>(curvature.r),
         0.0,
         0.0,
         0.0};
  const auto t = tangent_basis(normal);
  const auto [u, v] = drop(q, local(q, t, p));
  const auto g = q.slope(u, v);
  return {origin + u * t[0] + v * t[1] + q.height(u, v) * normal, (normal - g[0] * t[0] - g[1] * t[1]).normalized()};
}

namespace {

// Step 1: the quadric of every sample's own neighbourhood.
// Also marks the samples whose neighbourhood's heights fall in two groups
// (sheet_cut), whatever their residual: where most of the cloud is a thin
// part, the typical residual is the two sheets'.
Fits fit_all(const TangentPlanes<3>& planes, const LocalQuadricOptions& options, std::vector<std::uint8_t>& banded) {
  const std::span<const Vec3> x = planes.point_tree.points();
  Fits fits(planes);
  banded.assign(fits.size(), 0);
  const auto count = static_cast<std::int64_t>(fits.size());
  ProgressCounter* const progress = progress_counter();
#pragma omp parallel
  {
    std::array<double, 256> heights{};
#pragma omp for schedule(dynamic, 1024)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (progress != nullptr && (s & 4095) == 4095) progress->advance(4096);
      if (planes.radius[i] == 0.0f) {  // copies of one point: no surface to fit, nothing to lend
        Quadric none;
        none.flat = true;
        none.residual = std::numeric_limits<double>::infinity();
        fits.set(i, none);
        continue;
      }
      const Row row = planes.neighbors.row(i);
      const std::span<double> h(heights.data(), std::min(row.size(), heights.size()));
      const Quadric q = fit_quadric(x, row, PlaneFit<3>{planes.origins[i], planes.normals[i], Vec3::Zero()}, h);
      fits.set(i, q);
      // Suspected of spanning two sheets: heights in two groups over phase
      // I's plane, or a misfit too large for noise on a surface.
      banded[i] = q.residual > 0.0 && (!std::isnan(sheet_cut(h, options)) ||
                                       q.residual > options.sheet_residual * static_cast<double>(planes.radius[i]))
                      ? 1
                      : 0;
    }
  }
  return fits;
}

// Step 2 over the samples whose neighbourhood may span two sheets.
void split_sheets(const TangentPlanes<3>& planes, Fits& fits, const std::vector<std::uint8_t>& suspect,
                  const LocalQuadricOptions& options, LocalQuadrics& result) {
  const std::size_t n = fits.size();
  // The suspects, each with a frame slot and room for its split.
  std::vector<std::uint32_t> suspects;
  for (std::uint32_t i = 0; i < n; ++i)
    if (suspect[i]) suspects.push_back(i);
  fits.frames.resize(suspects.size());
  if (options.keep_parts) result.was_split.assign(n, 0);
  std::size_t split = 0;
  // Without a separation no pair is measured: a positive one could change the fits.
  double below = -std::numeric_limits<double>::infinity();
  double up_to = options.min_sheet_separation > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  const auto count = static_cast<std::int64_t>(suspects.size());
#pragma omp parallel reduction(+ : split) reduction(max : below) reduction(min : up_to)
  {
    std::vector<double> heights;
    std::vector<std::uint32_t> kept;
    SeparationRange same;
#pragma omp for schedule(dynamic, 64)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto slot = static_cast<std::size_t>(s);
      const std::uint32_t i = suspects[slot];
      const SheetFit sheet = fit_own_sheet(planes, i, fits[i], options, heights, kept, same);
      if (std::isnan(sheet.cut)) continue;
      fits.frames[slot] = {sheet.quadric.origin, sheet.quadric.normal};
      fits.set(i, sheet.quadric, static_cast<std::uint32_t>(slot));
      if (options.keep_parts) result.was_split[i] = 1;
      ++split;
    }
    below = std::max(below, same.below);
    up_to = std::min(up_to, same.up_to);
  }
  result.split = split;
  result.same_fits = {below, up_to};
}

// The samples with a neighbour whose (new) normal is more than the crease
// angle away from theirs.
std::vector<std::uint8_t> crease_band(const TangentPlanes<3>& planes, const std::vector<Vec3>& normals) {
  const double cosine = std::cos(crease_angle_degrees * std::numbers::pi / 180.0);
  std::vector<std::uint8_t> band(normals.size(), 0);
  const auto count = static_cast<std::int64_t>(normals.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    for (const std::uint32_t j : planes.neighbors.row(i))
      if (std::abs(normals[i].dot(normals[j])) < cosine) {
        band[i] = 1;
        break;
      }
  }
  return band;
}

// What step 3 did for one sample.
struct Taken {
  bool borrowed;  // a neighbour's quadric
  bool flat;      // a flat plane (no surface, an unresolved misfit, or a flat fit)
};

// Step 3 for sample i: the quadric it takes (its own, or a better one of a
// neighbour's where its fit is poor), and the sample moved onto it, into
// `result`. `look_beyond`: the residual beyond which a fit looks for a
// better one; `poor`: that of a fit which explains nothing (a better one is
// looked for further; beyond 2.5 times it, none is trusted); `far_radius`:
// the neighbourhood radius beyond which there is no surface.
Taken take_quadric(const TangentPlanes<3>& planes, const Fits& fits, const LocalQuadricOptions& options,
                   std::uint32_t i, double look_beyond, double poor, double far_radius, LocalQuadrics& result) {
  const std::span<const Vec3> x = planes.point_tree.points();
  const bool look = fits.residual(i) > look_beyond && std::isfinite(fits.residual(i));
  const std::uint32_t j = look ? support_of(planes, i, fits, options, poor) : i;
  const Quadric q = fits[j];
  result.residual[i] = static_cast<float>(q.residual);
  const auto radius = static_cast<double>(planes.radius[i]);
  if (radius > far_radius || !(q.residual <= options.surface_residual * radius)) {
    // No surface here (a blob of strays, copies of one point): phase I's
    // plane stays, which passes through no sample (it draws nothing).
    result.origins[i] = planes.origins[i];
    result.normals[i] = planes.normals[i];
    return {j != i, true};
  }
  const Foot foot = foot_on(q, x[i], planes.normals[i]);
  if (q.residual > 2.5 * poor) {
    // Unresolved, and far beyond what noise explains (a corner's samples
    // may find no neighbourhood on one face): the sample itself is nearer
    // the surface than its foot on a misfit, and the plane there is flat.
    result.origins[i] = x[i];
    result.normals[i] = foot.normal;
    return {j != i, true};
  }
  result.origins[i] = foot.point;
  result.normals[i] = foot.normal;
  result.curvature[i] = q.flat ? Curvature{} : foot.curvature;
  return {j != i, q.flat};
}

// The median of the residuals of the quadrics taken (0 when not finite).
double median_taken_residual(const std::vector<float>& residual) {
  std::vector<double> taken(residual.begin(), residual.end());
  if (taken.empty()) return 0.0;
  const auto middle = taken.begin() + static_cast<std::ptrdiff_t>(taken.size() / 2);
  std::nth_element(taken.begin(), middle, taken.end());
  return std::isfinite(*middle) ? *middle : 0.0;
}

}  // namespace

LocalQuadrics fit_local_quadrics(const TangentPlanes<3>& planes, const LocalQuadricOptions& options) {
  if (!planes.point_tree.numbered_by_leaf_order() || planes.neighbors.size() != planes.origins.size())
    throw InvalidInputError(
        "fit_local_quadrics: the planes need their neighbour lists and a tree numbered by leaf order");
  Timer timer;
  const std::size_t n = planes.origins.size();
  LocalQuadrics result;
  std::vector<std::uint8_t> banded;
  Fits fits = fit_all(planes, options, banded);
  split_sheets(planes, fits, banded, options, result);
  banded = {};
  // A fit is poor (a crease, a corner) beyond four times the typical
  // residual; those look for a better one, and so do those beyond the
  // faces' own residual where creases hold most samples (see the header).
  if (options.keep_parts) {
    result.fit_residual.resize(n);
    for (std::size_t i = 0; i < n; ++i) result.fit_residual[i] = static_cast<float>(fits.residual(i));
  }
  if (options.cloud) {
    result.medians.fit_residual = options.cloud->fit_residual;
    result.medians.fit_residual_quartile = options.cloud->fit_residual_quartile;
  } else {
    std::tie(result.medians.fit_residual, result.medians.fit_residual_quartile) = median_and_quartile(fits);
  }
  const double poor = 4.0 * result.medians.fit_residual;
  // Neighbourhoods far wider than the typical one are strays' (scattered
  // outliers reach each other across empty space): no surface there.
  result.medians.radius = options.cloud ? options.cloud->radius : median_radius(planes.radius);
  const double far_radius = options.stray_radius * result.medians.radius;
  const double look_beyond = std::min(poor, std::max(options.crease_quartile * result.medians.fit_residual_quartile,
                                                     options.smooth_residual * result.medians.radius));

  // Step 3, and each sample onto the quadric it takes.
  result.origins.resize(n);
  result.normals.resize(n);
  result.curvature.resize(n);
  result.residual.resize(n);
  std::size_t borrowed = 0, flat = 0;
  const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : borrowed, flat)
  for (std::int64_t s = 0; s < count; ++s) {
    const Taken taken =
        take_quadric(planes, fits, options, static_cast<std::uint32_t>(s), look_beyond, poor, far_radius, result);
    borrowed += taken.borrowed ? 1u : 0u;
    flat += taken.flat ? 1u : 0u;
  }
  result.borrowed = borrowed;
  result.flat = flat;
  result.near_crease = crease_band(planes, result.normals);
  result.noise = options.cloud ? options.cloud->noise : median_taken_residual(result.residual);
  result.medians.noise = result.noise;
  result.seconds = timer.lap();
  return result;
}

void adopt_second_order(TangentPlanes<3>& planes, LocalQuadrics& quadrics) {
  quadrics.guide.resize(planes.normals.size());
  for (std::size_t i = 0; i < planes.normals.size(); ++i) quadrics.guide[i] = planes.normals[i].cast<float>();
  planes.origins = std::move(quadrics.origins);
  planes.normals = std::move(quadrics.normals);
  quadrics.origins = {};
  quadrics.normals = {};
  planes.noise = quadrics.noise;
}

}  // namespace recon
