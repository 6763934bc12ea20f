// Choosing a point cloud format and handing the file to its reader or writer
// (the formats themselves live in ply_read.cpp, xyz.cpp, obj.cpp, off.cpp, pcd.cpp,
// las.cpp), and leaving out invalid points when asked (skip_invalid).

#include "recon/io/point_io.h"

#include "formats.h"
#include "io_detail.h"

#include "recon/core/errors.h"
#include "recon/io/atomic_file.h"

#include <array>
#include <string>
#include <utility>

namespace recon::io {
namespace {

constexpr std::array<std::pair<std::string_view, PointFormat>, 8> format_names = {{
    {"ply", PointFormat::ply},
    {"xyz", PointFormat::xyz},
    {"pts", PointFormat::pts},
    {"obj", PointFormat::obj},
    {"off", PointFormat::off},
    {"pcd", PointFormat::pcd},
    {"las", PointFormat::las},
    {"laz", PointFormat::laz},  // known only to be refused with a way out
}};

constexpr std::array<std::pair<std::string_view, PointFormat>, 12> extensions = {{
    {".ply", PointFormat::ply},
    {".xyz", PointFormat::xyz},
    {".txt", PointFormat::xyz},
    {".asc", PointFormat::xyz},
    {".pwn", PointFormat::xyz},
    {".csv", PointFormat::xyz},
    {".pts", PointFormat::pts},
    {".obj", PointFormat::obj},
    {".off", PointFormat::off},
    {".pcd", PointFormat::pcd},
    {".las", PointFormat::las},
    {".laz", PointFormat::laz},
}};

std::string_view name_of(PointFormat format) {
  for (const auto& [name, known] : format_names) {
    if (known == format) return name;
  }
  return "automatic";
}

PointFormat resolve(const std::filesystem::path& path, PointFormat format) {
  return format == PointFormat::automatic ? point_format_from_path(path) : format;
}

}  // namespace

PointFormat point_format_from_name(std::string_view name) {
  const std::string lower = detail::lower_case(name);
  for (const auto& [known, format] : format_names) {
    if (lower == known) return format;
  }
  throw InvalidInputError("unknown point format '" + std::string(name) +
                          "'; known formats: ply, xyz, pts, obj, off, pcd, las");
}

PointFormat point_format_from_path(const std::filesystem::path& path) {
  const std::string extension = detail::lower_case(path.extension().string());
  for (const auto& [known, format] : extensions) {
    if (extension == known) return format;
  }
  detail::fail_unknown_extension(path, extension,
                                 "known point formats: .ply, .xyz (also .txt, .asc, .pwn, .csv), .pts, .obj, .off, "
                                 ".pcd, .las - or name the format with --format (ply, xyz, pts, obj, off, pcd, las)");
}

namespace {

PointCloud read_as(PointFormat format, const std::string& file, std::string_view content,
                   const ReadPointsOptions& options, ReadNotes& said) {
  switch (format) {
    case PointFormat::ply:
      return detail::read_ply_points(file, content);
    case PointFormat::xyz:
      return detail::read_xyz_points(file, content, options, said);
    case PointFormat::pts:
      return detail::read_pts_points(file, content, options, said);
    case PointFormat::obj:
      return detail::read_obj_points(file, content);
    case PointFormat::off:
      return detail::read_off_points(file, content);
    case PointFormat::pcd:
      return detail::read_pcd_points(file, content, options, said);
    case PointFormat::las:
      return detail::read_las_points(file, content, options, said);
    case PointFormat::laz:
    case PointFormat::automatic:
      break;
  }
  throw InvalidInputError(file + ": no point format chosen");
}

}  // namespace

namespace detail {

void check_columns_apply(std::string_view file, PointFormat format, const ReadPointsOptions& options) {
  if (options.columns.empty() || format == PointFormat::xyz || format == PointFormat::pts) return;
  throw InvalidInputError(std::string(file) + ": --columns applies to delimited text (xyz, and pts without 'p' " +
                          "records), not to " + std::string(name_of(format)) +
                          ", whose header names what each value is; drop --columns");
}

PointFormat point_format_of(const std::filesystem::path& path, const ReadPointsOptions& options) {
  return resolve(path, options.format);
}

FileContent open_points(const std::filesystem::path& path, PointFormat format, const ReadPointsOptions& options) {
  const std::string file = path.string();
  if (format == PointFormat::laz) throw InvalidInputError(laz_refusal(file));
  check_columns_apply(file, format, options);
  FileContent content = read_file(path, options.max_stream_bytes);
  if (content.view().empty()) fail_in_file(file, "the file is empty");
  return content;
}

}  // namespace detail

namespace {

/// The content, whole, as `format`, leaving out the invalid points when asked.
PointCloud read_content(PointFormat format, const std::string& file, std::string_view content,
                        const ReadPointsOptions& options, ReadNotes* notes) {
  ReadNotes ignored;
  ReadNotes& said = notes != nullptr ? *notes : ignored;
  if (!options.skip_invalid) return read_as(format, file, content, options, said);
  // The readers' PointCheckers hand the invalid points to this scope instead of refusing them.
  const detail::SkipInvalidPoints skipping;
  PointCloud cloud = read_as(format, file, content, options, said);
  skipping.remove_from(file, cloud, said);
  return cloud;
}

}  // namespace

PointCloud read_points(const std::filesystem::path& path, const ReadPointsOptions& options, ReadNotes* notes) {
  const PointFormat format = resolve(path, options.format);
  const detail::FileContent file_content = detail::open_points(path, format, options);
  return read_content(format, path.string(), file_content.view(), options, notes);
}

PointSource::PointSource(std::filesystem::path path, std::size_t max_stream_bytes)
    : path_(std::move(path)),
      content_(std::make_unique<detail::FileContent>(detail::read_file(path_, max_stream_bytes))) {}
PointSource::PointSource(PointSource&&) noexcept = default;
PointSource& PointSource::operator=(PointSource&&) noexcept = default;
PointSource::~PointSource() = default;

std::string_view PointSource::bytes() const { return content_->view(); }
std::size_t PointSource::held_bytes() const { return content_->held_bytes(); }

bool is_stream(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  return !ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
         !std::filesystem::is_directory(status);
}

PointCloud read_points(const PointSource& source, const ReadPointsOptions& options, ReadNotes* notes) {
  const PointFormat format = resolve(source.path(), options.format);
  const std::string file = source.path().string();
  if (format == PointFormat::laz) throw InvalidInputError(detail::laz_refusal(file));
  detail::check_columns_apply(file, format, options);
  if (source.bytes().empty()) detail::fail_in_file(file, "the file is empty");
  return read_content(format, file, source.bytes(), options, notes);
}

void write_points(const std::filesystem::path& path, const PointCloud& cloud, const WritePointsOptions& options) {
  const PointFormat format = resolve(path, options.format);
  const std::string file = path.string();
  if (format != PointFormat::ply && format != PointFormat::xyz)
    throw InvalidInputError(file + ": cannot write points as " + std::string(name_of(format)) +
                            "; recon writes point clouds as ply or xyz");
  detail::check_cloud_for_writing(file, cloud);
  AtomicFile output(path);
  if (format == PointFormat::ply) {
    detail::write_ply_points(output.stream(), cloud, options.ascii);
  } else {
    detail::write_xyz_points(output.stream(), cloud);
  }
  output.commit();
}

}  // namespace recon::io
