#pragma once
// Phase IV: contour tracing. The zero set of the signed distance f becomes
// a triangle mesh by marching cubes over a lattice, visiting only the cubes
// near the surface.
//
// Lattice: cubes of side `cell`, aligned on the data's bounding box. The
// walk starts from the cubes that contain a sample and moves to a
// neighbouring cube only across a face whose four corners do not all have
// the same sign: the surface goes through that face, so it continues in the
// neighbour. Corner values are computed once and kept in a hash table, so time
// and memory grow with the area of the surface, not the volume of the box.
//
// Per cube: if a corner is undefined (phase III), the cube yields nothing and
// the walk does not go on through it: the surface stays open there.
// Otherwise the case table (marching_cubes_table.h) gives the triangles;
// each vertex sits on a lattice edge where f changes sign, at the linear
// interpolation of the two corner values, and is shared by every triangle
// using that edge: the mesh is indexed. A corner where f = 0 counts as
// outside; a vertex is kept at least 1/1000 of the edge away from the
// corners so that no triangle has zero area.

#include "recon/mesh.h"
#include "recon/point_cloud.h"

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace recon {

/// Lattice corner (0, 0, 0) sits this many cubes below the seeds' bounding
/// box on each axis: room for the surface to close beyond the outermost
/// samples, and a fractional part that keeps lattice planes off round
/// coordinates (flat data at z = 0 would otherwise put corners exactly on
/// the surface).
inline constexpr double lattice_margin = 3.381966;

struct MarchingCubesOptions {
  double cell = 0.0;                     ///< cube side (a length); must be > 0
  std::size_t max_cubes = 200'000'000;   ///< refuse lattices that would visit more (memory guard)
};

/// One evaluated lattice corner, for inspection and the visual feedback.
struct LatticeCorner {
  std::array<std::int32_t, 3> index{};  ///< lattice coordinates
  double value = 0.0;                   ///< f, when defined
  bool defined = false;
};

struct MarchingCubesResult {
  Mesh mesh;
  double cell = 0.0;
  Vec3 origin = Vec3::Zero();             ///< position of lattice corner (0, 0, 0)
  std::array<std::int32_t, 3> size{};     ///< cubes along each axis
  std::size_t seed_cubes = 0;             ///< cubes containing a sample
  std::size_t visited_cubes = 0;          ///< cubes whose corners were looked at
  std::size_t undefined_cubes = 0;        ///< visited cubes with an undefined corner
  std::size_t evaluated_corners = 0;
  std::size_t undefined_corners = 0;
  std::vector<LatticeCorner> corners;     ///< every evaluated corner (if keep_corners)
  double seconds = 0.0;                   ///< the whole walk, evaluations of f included
  double seconds_field = 0.0;             ///< of which evaluating f (phase III's share)
};

/// The lattice of a walk: where corner (0, 0, 0) sits, the cube side, and
/// the cubes along each axis.
struct Lattice {
  Vec3 origin = Vec3::Zero();
  double cell = 0.0;
  std::array<std::int32_t, 3> size{};
  [[nodiscard]] Vec3 position(const std::array<std::int32_t, 3>& corner) const {
    return {origin.x() + corner[0] * cell, origin.y() + corner[1] * cell, origin.z() + corner[2] * cell};
  }
};

/// The lattice marching_cubes() lays over `seeds` (not empty) at cube side
/// `cell`. Throws as marching_cubes() does for the cell and the lattice size.
[[nodiscard]] Lattice make_lattice(std::span<const Vec3> seeds, double cell);

/// The walk's first wave, which depends on the seeds and the cell only: the
/// lattice, the cubes that hold a seed (in the order the walk takes them,
/// seed by seed) and the corners of those cubes, each once, in the order the
/// walk meets them (a cube's corners in marching-cubes order). It can be
/// built, and f evaluated at its corners, before f's signs are settled:
/// reconstruct() does both beside phase II, and the walk then starts from
/// it with the values instead of from the seeds.
class SeedWave {
 public:
  /// Throws as marching_cubes() does for the cell and the lattice size, and
  /// InvalidInputError when there are no seeds.
  SeedWave(std::span<const Vec3> seeds, double cell);
  SeedWave(SeedWave&&) noexcept;
  SeedWave& operator=(SeedWave&&) noexcept;
  ~SeedWave();

  /// (A wave moved from, as into marching_cubes(), is empty: no cubes, no
  /// corners, and lattice() must not be called.)
  [[nodiscard]] const Lattice& lattice() const;
  [[nodiscard]] std::size_t cube_count() const;
  [[nodiscard]] std::size_t corner_count() const;
  /// Corner i of the wave, in the order above. Corner indices past
  /// corner_count() throw InvalidInputError here and below.
  [[nodiscard]] std::array<std::int32_t, 3> corner(std::size_t i) const;
  /// Gives f's value at corner i (NaN: undefined). The walk takes it instead
  /// of calling f there: it must be what f gives, or the mesh is that of
  /// another function. Safe from several threads at once for distinct i.
  void set_value(std::size_t i, double value);
  /// The value given at corner i; NaN when none was (or f is undefined there).
  [[nodiscard]] double value(std::size_t i) const;

  struct Walk;  // the walk's state: the lattice, its corner table and the first wave's cubes

 private:
  std::unique_ptr<Walk> walk_;
  friend struct SeedWaveAccess;
};

/// The function contoured: its value at a point, or nullopt where undefined.
/// It is called from several threads at once (one wave of corners at a time).
using ScalarField = std::function<std::optional<double>(const Vec3&)>;

/// Estimated cubes a walk will visit for `samples` points on a surface
/// where each sample stands for a spacing x spacing square, at cube side
/// `cell` (used to refuse before allocating; an upper estimate).
[[nodiscard]] double estimate_visited_cubes(std::size_t samples, double spacing, double cell);

/// Contours f = 0 starting from the cubes that contain `seeds` (normally the
/// input points). Throws InvalidInputError for a cell that is not a positive
/// length, ResourceLimitError when the lattice needs more than 2^21 cubes
/// along an axis or the walk would exceed max_cubes.
[[nodiscard]] MarchingCubesResult marching_cubes(const ScalarField& f, std::span<const Vec3> seeds,
                                                 const MarchingCubesOptions& options, bool keep_corners = false);

/// The same walk from a first wave built beforehand (at options.cell): f is
/// not called at the corners whose value was given (SeedWave::set_value).
/// Throws InvalidInputError when the wave was built at another cell or was
/// moved away already.
[[nodiscard]] MarchingCubesResult marching_cubes(const ScalarField& f, SeedWave wave,
                                                 const MarchingCubesOptions& options, bool keep_corners = false);

}  // namespace recon
