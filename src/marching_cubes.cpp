#include "recon/marching_cubes.h"

#include "recon/errors.h"
#include "recon/marching_cubes_table.h"
#include "recon/timer.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace recon {
namespace {

// Lattice coordinates packed 21 bits per axis into one 64-bit key.
constexpr int key_bits = 21;
constexpr std::int32_t max_cubes_per_axis = (1 << key_bits) - 2;
constexpr std::uint64_t key_mask = (std::uint64_t{1} << key_bits) - 1;

using Index3 = std::array<std::int32_t, 3>;

std::uint64_t pack(const Index3& i) {
  return static_cast<std::uint64_t>(i[0]) | (static_cast<std::uint64_t>(i[1]) << key_bits) |
         (static_cast<std::uint64_t>(i[2]) << (2 * key_bits));
}

Index3 unpack(std::uint64_t key) {
  return {static_cast<std::int32_t>(key & key_mask), static_cast<std::int32_t>((key >> key_bits) & key_mask),
          static_cast<std::int32_t>((key >> (2 * key_bits)) & key_mask)};
}

Index3 corner_of_cube(const Index3& cube, int c) {
  return {cube[0] + (c & 1), cube[1] + ((c >> 1) & 1), cube[2] + ((c >> 2) & 1)};
}

constexpr double undefined = std::numeric_limits<double>::quiet_NaN();
constexpr double vertex_margin = 1e-3;  // fraction of an edge kept between a vertex and a corner

}  // namespace

double estimate_visited_cubes(std::size_t samples, double spacing, double cell) {
  // Area ~ samples * spacing^2; a surface of area A crosses about 3 A / cell^2
  // cubes (each cube is entered through faces it shares with neighbours).
  const double area = static_cast<double>(samples) * spacing * spacing;
  return 3.0 * area / (cell * cell) + static_cast<double>(samples);
}

MarchingCubesResult marching_cubes(const ScalarField& f, std::span<const Vec3> seeds,
                                   const MarchingCubesOptions& options, bool keep_corners) {
  if (!(options.cell > 0.0) || !std::isfinite(options.cell))
    throw InvalidInputError("the lattice cell size must be a positive length");
  Timer timer;
  MarchingCubesResult result;
  result.cell = options.cell;
  if (seeds.empty()) return result;

  Box<3> box;
  for (const Vec3& p : seeds) box.extend(p);
  const double margin = lattice_margin * options.cell;
  result.origin = box.min - Vec3::Constant(margin);
  for (int a = 0; a < 3; ++a) {
    const double cubes = std::ceil((box.max[a] - box.min[a] + 2.0 * margin) / options.cell);
    if (cubes > max_cubes_per_axis)
      throw ResourceLimitError("the lattice would need " + std::to_string(static_cast<long long>(cubes)) +
                               " cubes along axis " + "xyz"[a] + " (at most " + std::to_string(max_cubes_per_axis) +
                               "): use a larger --cell or a smaller --resolution");
    result.size[static_cast<std::size_t>(a)] = static_cast<std::int32_t>(cubes);
  }

  std::chrono::steady_clock::duration field_time{};
  std::unordered_map<std::uint64_t, double> corner_value;
  std::unordered_map<std::uint64_t, std::uint32_t> edge_vertex;  // key * 3 + axis -> vertex
  std::unordered_set<std::uint64_t> visited;
  std::vector<std::uint64_t> queue;
  auto position = [&](const Index3& i) {
    return Vec3(result.origin.x() + i[0] * options.cell, result.origin.y() + i[1] * options.cell,
                result.origin.z() + i[2] * options.cell);
  };
  auto inside_lattice = [&](const Index3& cube) {
    for (std::size_t a = 0; a < 3; ++a)
      if (cube[a] < 0 || cube[a] >= result.size[a]) return false;
    return true;
  };
  auto visit = [&](const Index3& cube) {
    if (!inside_lattice(cube) || !visited.insert(pack(cube)).second) return;
    if (visited.size() > options.max_cubes)
      throw ResourceLimitError("the lattice walk passed " + std::to_string(options.max_cubes) +
                               " cubes: use a larger --cell or a smaller --resolution");
    queue.push_back(pack(cube));
  };
  auto value_at = [&](const Index3& corner) {
    const auto [it, inserted] = corner_value.try_emplace(pack(corner), undefined);
    if (inserted) {
      const auto started = std::chrono::steady_clock::now();
      const std::optional<double> v = f(position(corner));
      field_time += std::chrono::steady_clock::now() - started;
      if (v) it->second = *v;
    }
    return it->second;
  };

  for (const Vec3& p : seeds) {
    Index3 cube;
    for (int a = 0; a < 3; ++a)
      cube[static_cast<std::size_t>(a)] = static_cast<std::int32_t>(std::floor((p[a] - result.origin[a]) / options.cell));
    visit(cube);
  }
  result.seed_cubes = visited.size();

  for (std::size_t head = 0; head < queue.size(); ++head) {
    const Index3 cube = unpack(queue[head]);
    std::array<double, 8> value;
    bool complete = true;
    unsigned config = 0;
    for (int c = 0; c < 8; ++c) {
      value[static_cast<std::size_t>(c)] = value_at(corner_of_cube(cube, c));
      if (std::isnan(value[static_cast<std::size_t>(c)])) complete = false;
      if (value[static_cast<std::size_t>(c)] < 0.0) config |= 1u << c;
    }
    if (!complete) {
      ++result.undefined_cubes;
      continue;
    }
    const mc::CubeCase& cube_case = mc::cube_case(config);
    // Vertices: one per crossed lattice edge, shared through edge_vertex;
    // then the centres of the loops that need one (private to this cube).
    std::array<std::uint32_t, 12 + 4> vertex{};
    for (int l = 0; l < cube_case.loop_count; ++l) {
      const auto& loop = cube_case.loops[static_cast<std::size_t>(l)];
      Vec3 centre = Vec3::Zero();
      for (int j = 0; j < loop.size; ++j) {
        const int e = loop.edges[static_cast<std::size_t>(j)];
        const auto ends = mc::edge_corners(e);
        const Index3 lower = corner_of_cube(cube, ends[0]);
        const auto [it, inserted] =
            edge_vertex.try_emplace(pack(lower) * 3 + static_cast<std::uint64_t>(mc::edge_axis(e)),
                                    static_cast<std::uint32_t>(result.mesh.vertices.size()));
        if (inserted) {
          const double v0 = value[static_cast<std::size_t>(ends[0])], v1 = value[static_cast<std::size_t>(ends[1])];
          const double t = std::clamp(v0 / (v0 - v1), vertex_margin, 1.0 - vertex_margin);
          Vec3 p = position(lower);
          p[mc::edge_axis(e)] += t * options.cell;
          result.mesh.vertices.push_back(p);
        }
        vertex[static_cast<std::size_t>(e)] = it->second;
        centre += result.mesh.vertices[it->second];
      }
      if (loop.centred) {
        vertex[static_cast<std::size_t>(mc::loop_centre + l)] = static_cast<std::uint32_t>(result.mesh.vertices.size());
        result.mesh.vertices.push_back(centre / loop.size);
      }
    }
    for (int t = 0; t < cube_case.triangle_count; ++t) {
      const auto& corners = cube_case.triangles[static_cast<std::size_t>(t)];
      result.mesh.triangles.push_back({vertex[corners[0]], vertex[corners[1]], vertex[corners[2]]});
    }

    // Continue through every face the surface crosses, or touches at a
    // corner where f = 0 (the surface may go on in the neighbour only).
    for (int a = 0; a < 3; ++a) {
      for (int s = 0; s < 2; ++s) {
        int inside = 0;
        bool touches = false;
        for (int c = 0; c < 8; ++c) {
          if (((c >> a) & 1) != s) continue;
          if ((config >> c) & 1u) ++inside;
          if (value[static_cast<std::size_t>(c)] == 0.0) touches = true;
        }
        if ((inside == 0 || inside == 4) && !touches) continue;
        Index3 next = cube;
        next[static_cast<std::size_t>(a)] += s == 0 ? -1 : 1;
        visit(next);
      }
    }
  }

  result.visited_cubes = visited.size();
  result.evaluated_corners = corner_value.size();
  for (const auto& [key, v] : corner_value) {
    if (std::isnan(v)) ++result.undefined_corners;
    if (keep_corners) result.corners.push_back({unpack(key), std::isnan(v) ? 0.0 : v, !std::isnan(v)});
  }
  result.seconds = timer.lap();
  result.seconds_field = std::chrono::duration<double>(field_time).count();
  return result;
}

}  // namespace recon
