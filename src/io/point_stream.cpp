// Reading a point cloud in chunks (point_stream.h): the readers of PLY,
// delimited text and LAS write into a PointParts (point_parts.h) that hands
// each full part here; other formats are read whole and handed out in
// slices.

#include "recon/io/point_stream.h"

#include "formats.h"
#include "io_detail.h"
#include "point_parts.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <optional>
#include <span>
#include <string>

namespace recon::io {
namespace {

using Take = std::function<void(PointCloudView chunk, std::size_t first)>;

bool streams(PointFormat format) {
  return format == PointFormat::ply || format == PointFormat::xyz || format == PointFormat::las;
}

/// Any format: read whole by read_points, handed out in slices.
StreamedCloud hand_out_whole(const std::filesystem::path& path, const PointChunkOptions& options, const Take& take,
                             ReadNotes& notes) {
  const PointCloud cloud = read_points(path, options.read, &notes);
  const std::span<const Vec3> positions(cloud.positions), normals(cloud.normals);
  const std::span<const Color> colors(cloud.colors);
  for (std::size_t first = 0; first < cloud.size(); first += options.chunk_points) {
    const std::size_t n = std::min(options.chunk_points, cloud.size() - first);
    take(PointCloudView(positions.subspan(first, n), cloud.has_normals() ? normals.subspan(first, n) : normals,
                        cloud.has_colors() ? colors.subspan(first, n) : colors),
         first);
  }
  return {cloud.size(), cloud.has_normals(), cloud.has_colors(), false};
}

/// Hands each part from a reader on to `take`, without the invalid points
/// when they are skipped, and counts what was handed out.
class ChunkHandler {
 public:
  ChunkHandler(const Take& take, bool skip_invalid, bool mapped) : take_(take), skip_invalid_(skip_invalid) {
    result_.streamed = mapped;
  }

  void operator()(PointCloud& part) {
    if (skip_invalid_) dropped_ += detail::SkipInvalidPoints::drop_unreadable(part);
    if (part.size() == 0) return;
    result_.has_normals = part.has_normals();
    result_.has_colors = part.has_colors();
    {
      const detail::SkipInvalidPoints::Hide hide;  // the caller's code reads as if no scope were open
      take_(PointCloudView(part), result_.points);
    }
    result_.points += part.size();
  }

  [[nodiscard]] const StreamedCloud& result() const { return result_; }
  [[nodiscard]] std::size_t dropped() const { return dropped_; }

 private:
  const Take& take_;
  bool skip_invalid_;
  std::size_t dropped_ = 0;
  StreamedCloud result_;
};

void read_in_parts(PointFormat format, const std::string& file, std::string_view content,
                   const ReadPointsOptions& options, ReadNotes& notes, detail::PointParts& parts) {
  switch (format) {
    case PointFormat::ply:
      return detail::read_ply_points(file, content, parts);
    case PointFormat::xyz:
      return detail::read_xyz_points(file, content, options, notes, parts);
    case PointFormat::las:
      return detail::read_las_points(file, content, notes, parts);
    default:
      throw InvalidInputError(file + ": this format is not read in parts");
  }
}

}  // namespace

StreamedCloud read_points_in_chunks(const std::filesystem::path& path, const PointChunkOptions& options,
                                    const Take& take, ReadNotes* notes) {
  if (options.chunk_points == 0) throw InvalidInputError("read_points_in_chunks: chunk_points must be at least 1");
  ReadNotes ignored;
  ReadNotes& said = notes != nullptr ? *notes : ignored;
  const PointFormat format = detail::point_format_of(path, options.read);
  if (!streams(format)) return hand_out_whole(path, options, take, said);

  const std::string file = path.string();
  const detail::FileContent content = detail::open_points(path, format, options.read);
  // The readers' PointCheckers hand the invalid points to this scope instead of refusing them.
  std::optional<detail::SkipInvalidPoints> skipping;
  if (options.read.skip_invalid) skipping.emplace();
  ChunkHandler handler(take, options.read.skip_invalid, content.mapped());
  detail::PointParts parts(options.chunk_points, std::ref(handler), content);
  read_in_parts(format, file, content.view(), options.read, said, parts);
  if (skipping) skipping->conclude(file, handler.dropped(), handler.result().points, said);
  return handler.result();
}

}  // namespace recon::io
