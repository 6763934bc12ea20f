// Step 1's cloud-wide measures over the tiles (tiles/statistics.h).
#include "tiles/statistics.h"

#include "recon/core/errors.h"
#include "recon/reconstruct_parts.h"
#include "tiles/binary_file.h"
#include "tiles/files.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

namespace recon::tile_statistics {
namespace {

inline constexpr char values_magic[9] = "RCNSTAT1";

// One owned sample's values, for the medians (a step writes one file of
// them per tile; the next step's overwrite it).
struct Values {
  float a = 0.0f, b = 0.0f, c = 0.0f;
};

// ---------------------------------------------------------------------------
// The median by rank over the values on disk.

// Floats in the order of their values, as unsigned keys (negatives below
// positives; NaN above infinity).
std::uint32_t order_key(float value) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  return (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
}

float from_order_key(std::uint32_t key) {
  const std::uint32_t bits = (key & 0x80000000u) != 0 ? key & 0x7fffffffu : ~key;
  float value = 0.0f;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// Which value of a record counts (none: the record is left out).
using Pick = std::function<std::optional<float>(const Values&)>;

class Selection {
 public:
  Selection(const TilePlan& plan, const std::filesystem::path& dir) : plan_(plan), dir_(dir) {}

  // The value nth_element would put at `rank(count)` (count: the values
  // picked) among every tile's picked values; nullopt when none is picked.
  std::optional<float> select(const Pick& pick, const std::function<std::uint64_t(std::uint64_t)>& rank) const {
    std::vector<std::uint64_t> counts(1u << 16, 0);
    std::uint64_t total = 0;
    each_value(pick, [&](std::uint32_t key) {
      ++counts[key >> 16];
      ++total;
    });
    if (total == 0) return std::nullopt;
    std::uint64_t wanted = rank(total);
    const std::uint32_t high = bucket_of(counts, wanted);
    std::fill(counts.begin(), counts.end(), 0);
    each_value(pick, [&](std::uint32_t key) {
      if (key >> 16 == high) ++counts[key & 0xffffu];
    });
    return from_order_key(high << 16 | bucket_of(counts, wanted));
  }

  [[nodiscard]] std::optional<float> median(const Pick& pick) const {
    return select(pick, [](std::uint64_t n) { return n / 2; });
  }
  [[nodiscard]] std::optional<float> quantile(const Pick& pick, double q) const {
    return select(pick, [q](std::uint64_t n) { return static_cast<std::uint64_t>(q * static_cast<double>(n - 1)); });
  }

 private:
  // The bucket holding the value of rank `wanted`; `wanted` becomes its rank within the bucket.
  static std::uint32_t bucket_of(const std::vector<std::uint64_t>& counts, std::uint64_t& wanted) {
    for (std::uint32_t b = 0; b < counts.size(); ++b) {
      if (wanted < counts[b]) return b;
      wanted -= counts[b];
    }
    throw InvalidInputError("tile statistics: a rank beyond the values");  // (cannot happen: rank < total)
  }

  void each_value(const Pick& pick, const std::function<void(std::uint32_t)>& take) const {
    for (const TileInfo& info : plan_.tiles) {
      const auto path = tile_files::of_tile(dir_, info.id, "stats");
      if (!std::filesystem::exists(path)) continue;  // (a tile that measured nothing)
      for (const Values& v : detail::BinaryReader(path, values_magic).get_rest<Values>())
        if (const std::optional<float> value = pick(v)) take(order_key(*value));
    }
  }

  const TilePlan& plan_;
  std::filesystem::path dir_;
};

// ---------------------------------------------------------------------------
// The tiles, one at a time (each runs phase I on every thread).

// Phase I (planes only) over a tile's points with these options; null when
// they make no plane (a tile of fewer than k + 1 points, or of copies).
std::optional<Reconstruction> planes_of(const TilePlan& plan, const tile_files::TilePoints& points,
                                        const ReconstructionOptions& options) {
  if (points.positions.size() <= static_cast<std::size_t>(options.planes.k)) return std::nullopt;
  ReconstructionOptions o = options;
  o.method = Method::hoppe92;  // (the fits are taken apart, below)
  o.offset = plan.offset;
  try {
    return reconstruct_phase_1(PointCloudView(points.positions, {}, {}), o);
  } catch (const InvalidInputError&) {
    return std::nullopt;
  }
}

// A tile's samples it owns (spatial order), and how many of its points it
// owns without planes to measure them by (they make the measures inexact).
struct Owned {
  std::vector<std::uint32_t> samples;
  std::uint64_t unmeasured = 0;
};

Owned owned(const TilePlan& plan, const TileInfo& info, const tile_files::TilePoints& points,
            const std::optional<Reconstruction>& r) {
  Owned o;
  if (!r) {
    for (const Vec3& p : points.positions) o.unmeasured += tile_files::tile_at(plan, p - plan.offset) == info.index;
    return o;
  }
  const std::span<const Vec3> w = r->points();
  for (std::uint32_t j = 0; j < w.size(); ++j)
    if (tile_files::tile_at(plan, w[j]) == info.index) o.samples.push_back(j);
  return o;
}

struct TileVisit {
  const TileInfo& info;
  const Reconstruction& r;
  const std::vector<std::uint32_t>& samples;
};

// Runs phase I with `options` over each tile and `visit` over what it owns;
// writes the tile's values when `visit` fills them. Returns the owned
// points left unmeasured.
std::uint64_t over_tiles(const TilePlan& plan, const std::filesystem::path& dir, const ReconstructionOptions& options,
                         const std::function<void(const TileVisit&, std::vector<Values>&)>& visit) {
  std::uint64_t unmeasured = 0;
  for (const TileInfo& info : plan.tiles) {
    const tile_files::TilePoints points = tile_files::read_points(dir, plan, info);
    const std::optional<Reconstruction> r = planes_of(plan, points, options);
    const Owned own = owned(plan, info, points, r);
    unmeasured += own.unmeasured;
    const auto path = tile_files::of_tile(dir, info.id, "stats");
    std::filesystem::remove(path);
    if (!r) continue;
    std::vector<Values> values;
    visit(TileVisit{info, *r, own.samples}, values);
    detail::BinaryWriter out(path, values_magic);
    out.put_records<Values>(values);
    out.commit();
  }
  return unmeasured;
}

// ---------------------------------------------------------------------------
// Step A: the spacing at k.

struct Spacing {
  CloudSpacing spacing;
  double radius_median = 0.0;
  double radius_q = 0.0, rho_q = 0.0;  // (see Measures)
  std::uint64_t distinct = 0, samples = 0, inexact = 0;
  std::vector<double> probes;  // the noise probes' residuals at 2k
};

Spacing measure_spacing(const TilePlan& plan, const std::filesystem::path& dir, const ReconstructionOptions& asked,
                        int k, std::uint64_t cloud_points) {
  ReconstructionOptions o = asked;
  o.planes.k = k;
  o.planes.adapt_k = false;
  o.planes.cloud.reset();
  o.planes.keep_spacing_parts = true;
  Spacing s;
  SpacingSums sums;
  const std::uint64_t unmeasured = over_tiles(plan, dir, o, [&](const TileVisit& t, std::vector<Values>& values) {
    const TangentPlanes<3>& planes = t.r.planes;
    const std::span<const Vec3> w = t.r.points();
    const tile_files::CoreBox core = tile_files::core_at(plan, t.info.index);
    for (const std::uint32_t j : t.samples) {
      // (radius, gap_i before the copies' fill, lambda_0)
      values.push_back({planes.radius[j], planes.rho_given ? 0.0f : planes.raw_gap[j], planes.eigenvalues[j][0]});
      if (!planes.rho_given) sums.add(planes.relative_spacing[j]);
      s.distinct += planes.neighbors.row(j)[0] == j ? 1u : 0u;
      if (is_noise_probe<3>(w[j], cloud_points) && static_cast<std::uint64_t>(2 * k) <= cloud_points)
        s.probes.push_back(probe_residual<3>(planes, w, w[j], 2 * k));
      if (tile_files::outside_core(plan, core, w[j]) + 2.0 * static_cast<double>(planes.radius[j]) > plan.halo)
        ++s.inexact;
    }
    s.samples += t.samples.size();
  });
  s.inexact += unmeasured;
  const Selection select(plan, dir);
  const auto positive = [](float v) { return v > 0.0f ? std::optional<float>(v) : std::nullopt; };
  const std::optional<float> lambda = select.median([](const Values& v) { return v.c; });
  s.spacing.noise = lambda ? std::sqrt(static_cast<double>(*lambda)) : 0.0;
  s.radius_median = static_cast<double>(select.median([](const Values& v) { return v.a; }).value_or(0.0f));
  s.radius_q = 1.5 * static_cast<double>(select.quantile([](const Values& v) { return v.a; }, 0.999).value_or(0.0f));
  if (asked.planes.rho) {
    s.spacing.rho = s.spacing.gap = s.rho_q = *asked.planes.rho;
    return s;
  }
  s.spacing.irregularity = sums.irregularity();
  const double irregularity = s.spacing.irregularity;
  const auto rho_i = [irregularity](const Values& v) { return local_rho_of(v.b, v.a, irregularity); };
  s.spacing.rho =
      static_cast<double>(select.median([&](const Values& v) { return positive(rho_i(v)); }).value_or(0.0f));
  s.spacing.gap = static_cast<double>(select.median([&](const Values& v) { return positive(v.b); }).value_or(0.0f));
  s.rho_q = static_cast<double>(select.quantile(rho_i, 0.999).value_or(0.0f));
  return s;
}

// ---------------------------------------------------------------------------
// Steps B and C: the quadrics (refined).

LocalQuadricOptions fit_options(const ReconstructionOptions& asked, double cell) {
  LocalQuadricOptions fits = asked.quadrics;
  if (fits.min_sheet_separation <= 0.0) fits.min_sheet_separation = 1.5 * cell;  // (as reconstruct() does)
  fits.keep_parts = true;
  fits.cloud.reset();
  return fits;
}

ReconstructionOptions given_spacing(const ReconstructionOptions& asked, int k, const CloudSpacing& spacing) {
  ReconstructionOptions o = asked;
  o.planes.k = k;
  o.planes.adapt_k = false;
  if (!o.planes.rho) o.planes.cloud = spacing;
  return o;
}

// B: the median of the own fits' residuals (finite ones) and their lower
// quartile (at the ranks fit_local_quadrics takes), and the samples split.
struct OwnFits {
  double median = 0.0, quartile = 0.0;
  std::uint64_t split = 0;
};
OwnFits own_fits(const TilePlan& plan, const std::filesystem::path& dir, const ReconstructionOptions& o,
                 const LocalQuadricOptions& fits) {
  std::uint64_t split = 0;
  over_tiles(plan, dir, o, [&](const TileVisit& t, std::vector<Values>& values) {
    const LocalQuadrics q = fit_local_quadrics(t.r.planes, fits);
    for (const std::uint32_t j : t.samples) {
      values.push_back({q.fit_residual[j], 0.0f, 0.0f});
      split += q.was_split[j];
    }
  });
  const auto finite = [](const Values& v) { return std::isfinite(v.a) ? std::optional<float>(v.a) : std::nullopt; };
  const Selection residuals(plan, dir);
  return {static_cast<double>(residuals.median(finite).value_or(0.0f)),
          static_cast<double>(residuals.select(finite, [](std::uint64_t n) { return n / 4; }).value_or(0.0f)), split};
}

// C: the median of the residuals of the quadrics taken, given B's medians.
double taken_fits(const TilePlan& plan, const std::filesystem::path& dir, const ReconstructionOptions& o,
                  LocalQuadricOptions fits, const QuadricMedians& medians) {
  fits.cloud = medians;
  over_tiles(plan, dir, o, [&](const TileVisit& t, std::vector<Values>& values) {
    const LocalQuadrics q = fit_local_quadrics(t.r.planes, fits);
    for (const std::uint32_t j : t.samples) values.push_back({q.residual[j], 0.0f, 0.0f});
  });
  const std::optional<float> m = Selection(plan, dir).median([](const Values& v) { return v.a; });
  return m && std::isfinite(*m) ? static_cast<double>(*m) : 0.0;
}

}  // namespace

Measures measure_over_tiles(const TilePlan& plan, const std::filesystem::path& dir,
                            const ReconstructionOptions& asked) {
  const std::uint64_t n = plan.input_points;
  // A, and A again when the noise raises k.
  int k = asked.planes.k;
  Spacing a = measure_spacing(plan, dir, asked, k, n);
  const int raised =
      raised_k(asked.planes, a.spacing.noise, a.spacing.rho, a.distinct, n, [&] { return probes_median(a.probes); });
  if (raised > 0) a = measure_spacing(plan, dir, asked, k = raised, n);

  Measures m;
  if (asked.method == Method::refined) {
    const double cell = lattice_cell([&] { return plan.box.extent().maxCoeff(); }, a.spacing.rho, asked);
    const LocalQuadricOptions fits = fit_options(asked, cell);
    OwnFits own = own_fits(plan, dir, given_spacing(asked, k, a.spacing), fits);
    if (k > asked.planes.k && 4 * own.split > a.samples) {  // (B: the raise undone)
      a = measure_spacing(plan, dir, asked, k = asked.planes.k, n);
      own = own_fits(plan, dir, given_spacing(asked, k, a.spacing), fits);
    }
    QuadricMedians medians{own.median, a.radius_median, 0.0, own.quartile};
    medians.noise = taken_fits(plan, dir, given_spacing(asked, k, a.spacing), fits, medians);
    a.spacing.noise = medians.noise;
    m.quadric_medians = medians;
  }
  m.k = k;
  m.spacing = a.spacing;
  m.samples = a.samples;
  m.inexact = a.inexact;
  m.radius_q = a.radius_q;
  m.rho_q = a.rho_q;
  return m;
}

}  // namespace recon::tile_statistics
