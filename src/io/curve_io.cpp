// Choosing how 2D points are read and how curves are written (the formats
// themselves live in xyz.cpp, obj.cpp and svg.cpp).

#include "recon/io/curve_io.h"

#include "formats.h"
#include "io_detail.h"

#include "recon/core/errors.h"
#include "recon/io/atomic_file.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace recon::io {
namespace {

PointFormat resolve(const std::filesystem::path& path, PointFormat format) {
  return format == PointFormat::automatic ? point_format_from_path(path) : format;
}

// Plain text columns: xyz files, and .pts files without Hoppe's records.
bool is_plain_columns(PointFormat format, std::string_view file, std::string_view content) {
  return format == PointFormat::xyz || (format == PointFormat::pts && !detail::pts_has_records(file, content));
}

// The axis every point shares, in the order x, z, y; -1 when none.
int shared_axis(const std::vector<Vec3>& points) {
  for (const int axis : {0, 2, 1}) {
    const double first = points.front()[axis];
    if (std::all_of(points.begin(), points.end(), [&](const Vec3& p) { return p[axis] == first; })) return axis;
  }
  return -1;
}

}  // namespace

bool holds_2d_points(const PointSource& source, const ReadPointsOptions& options) {
  const PointFormat format = resolve(source.path(), options.format);
  if (format != PointFormat::xyz && format != PointFormat::pts) return false;
  const std::string file = source.path().string();
  const std::string_view content = source.bytes();
  if (content.empty()) detail::fail_in_file(file, "the file is empty");
  if (is_plain_columns(format, file, content)) return detail::xyz_column_count(file, content) == 2;
  const PointCloud cloud = detail::read_pts_points(file, content);
  return shared_axis(cloud.positions) == 0;
}

bool holds_2d_points(const std::filesystem::path& path, const ReadPointsOptions& options) {
  const PointFormat format = resolve(path, options.format);
  if (format != PointFormat::xyz && format != PointFormat::pts) return false;  // not opened: it cannot be 2D
  return holds_2d_points(PointSource(path, options.max_stream_bytes), options);
}

std::vector<Vec2> read_points_2d(const PointSource& source, const ReadPointsOptions& options) {
  const PointFormat format = resolve(source.path(), options.format);
  const std::string file = source.path().string();
  const std::string_view content = source.bytes();
  if (content.empty()) detail::fail_in_file(file, "the file is empty");
  if (is_plain_columns(format, file, content) && detail::xyz_column_count(file, content) == 2)
    return detail::read_xy_points(file, content);
  ReadPointsOptions read_options;
  read_options.format = format;
  const PointCloud cloud = read_points(source, read_options);
  const int axis = shared_axis(cloud.positions);
  if (axis < 0)
    detail::fail_in_file(file,
                         "the points are not 2D: no coordinate is the same for all of them (a curve needs two "
                         "columns, x y, or points in a plane x, y or z = constant, as in Hoppe's 2D .pts files)");
  const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
  std::vector<Vec2> points;
  points.reserve(cloud.size());
  for (const Vec3& p : cloud.positions) points.emplace_back(p[u], p[v]);
  return points;
}

std::vector<Vec2> read_points_2d(const std::filesystem::path& path, const ReadPointsOptions& options) {
  return read_points_2d(PointSource(path, options.max_stream_bytes), options);
}

CurveFormat curve_format_from_path(const std::filesystem::path& path) {
  const std::string extension = detail::lower_case(path.extension().string());
  if (extension == ".svg") return CurveFormat::svg;
  if (extension == ".obj") return CurveFormat::obj;
  if (extension == ".txt") return CurveFormat::txt;
  detail::fail_unknown_extension(path, extension, "known curve formats: .svg, .obj, .txt");
}

void write_curves(const std::filesystem::path& path, const PolylineSet& curves, const WriteCurvesOptions& options) {
  const CurveFormat format = options.format == CurveFormat::automatic ? curve_format_from_path(path) : options.format;
  const std::string file = path.string();
  auto check = [&](std::span<const Vec2> values, const char* what, bool bounded) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      const bool ok = bounded ? detail::coordinate_in_range(values[i].x()) && detail::coordinate_in_range(values[i].y())
                              : std::isfinite(values[i].x()) && std::isfinite(values[i].y());
      if (!ok)
        throw InvalidInputError(file + ": cannot write: " + what + " " + std::to_string(i) +
                                (bounded
                                     ? " has a coordinate that is not finite or beyond " + detail::coordinate_bound()
                                     : std::string(" is not finite")));
    }
  };
  check(curves.vertices, "vertex", true);
  check(options.points, "point", true);
  check(options.normals, "normal", false);
  if (!options.normals.empty() && options.normals.size() != options.points.size())
    throw InvalidInputError(file + ": cannot write: " + std::to_string(options.normals.size()) + " normals for " +
                            std::to_string(options.points.size()) + " points");
  for (std::size_t c = 0; c < curves.polylines.size(); ++c)
    for (const std::uint32_t v : curves.polylines[c].vertices)
      if (v >= curves.vertices.size())
        throw InvalidInputError(file + ": cannot write: curve " + std::to_string(c) + " uses vertex " +
                                std::to_string(v) + ", but there are " + std::to_string(curves.vertices.size()));
  AtomicFile output(path);
  switch (format) {
    case CurveFormat::svg:
      detail::write_svg_curves(output.stream(), curves, options.points, options.normals, options.normal_length);
      break;
    case CurveFormat::obj:
      detail::write_obj_curves(output.stream(), curves);
      break;
    case CurveFormat::txt:
      detail::write_text_curves(output.stream(), curves);
      break;
    case CurveFormat::automatic:
      throw InvalidInputError(file + ": no curve format chosen");
  }
  output.commit();
}

}  // namespace recon::io
