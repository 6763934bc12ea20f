#pragma once
// Where the streaming-capable readers (ply_read.cpp, xyz.cpp, las.cpp) put the
// points they read: the whole cloud at once for read_points, or parts of a
// bounded size handed on as they fill for read_points_in_chunks
// (point_stream.h).
//
// A reader writes its points into part(), and after each point asks
// full(); when it is, the reader completes the part (the colours and
// normals whose form waited on a rule of the file) and hand()s it on. At the
// end it completes the last part and calls finish(). For read_points the
// part never fills, so the reader's own code at the end completes the whole
// cloud, which take_whole() then gives.
//
// A decision that the whole file makes (PLY's floating-point colours in 0-1
// or 0-255, LAS's 16-bit colours, what the columns of a text file hold)
// cannot wait for the end when the points are handed on before it: a reader
// in parts first surveys the file, reading it through with the points
// dropped (dropping()), and then reads it again knowing the answer.
//
// Memory stays bounded by the part and a little more: every hand() (and
// behind(), which a reader calls while it walks what it does not keep) lets
// go of the pages of the mapped file behind the reader (FileContent::let_go).

#include "io_detail.h"

#include "recon/core/point_cloud.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <utility>

namespace recon::io::detail {

/// Lets go of the pages of a mapped file behind a reader walking it from
/// the front, a step of a few hundred KiB at a time.
class PageRelease {
 public:
  PageRelease() = default;  ///< lets go of nothing (read_points keeps its map whole)
  explicit PageRelease(const FileContent& content) : content_(&content), next_(step) {}

  /// The reader has read everything before byte `position`.
  void behind(std::size_t position) {
    if (position < next_) return;
    content_->let_go(released_, position);
    released_ = position;
    next_ = position + step;
  }
  /// A fresh walk from the front of the same file.
  [[nodiscard]] PageRelease restarted() const { return content_ != nullptr ? PageRelease(*content_) : PageRelease(); }

 private:
  static constexpr std::size_t step = std::size_t{1} << 18;
  const FileContent* content_ = nullptr;
  std::size_t released_ = 0;
  std::size_t next_ = std::numeric_limits<std::size_t>::max();
};

/// The points of a reader, whole or in parts (see the top of the file).
class PointParts {
 public:
  using Take = std::function<void(PointCloud& part)>;

  /// The whole cloud in one part (read_points).
  PointParts() = default;
  /// Parts of at most `limit` points (limit >= 1) for `take`, which may
  /// change the part (it is emptied after); `content` is the mapped file.
  PointParts(std::size_t limit, Take take, const FileContent& content)
      : limit_(limit), take_(std::move(take)), pages_(content) {}

  [[nodiscard]] PointCloud& part() { return part_; }
  [[nodiscard]] bool whole() const { return !take_; }
  [[nodiscard]] bool full() const { return part_.size() >= limit_; }
  /// How many points to reserve room for when the file holds `wanted`.
  [[nodiscard]] std::size_t room(std::uint64_t wanted) const {
    return static_cast<std::size_t>(std::min<std::uint64_t>(wanted, limit_));
  }
  /// Points read so far, in all parts.
  [[nodiscard]] std::uint64_t count() const { return handed_ + part_.size(); }

  /// Hands the part, complete, on and empties it; the reader has read
  /// everything before byte `position`.
  void hand(std::size_t position) {
    handed_ += part_.size();
    take_(part_);
    part_.positions.clear();
    part_.normals.clear();
    part_.colors.clear();
    pages_.behind(position);
  }
  /// The reader has read everything before byte `position` (and keeps none of it).
  void behind(std::size_t position) { pages_.behind(position); }
  /// After the last point: hands on the last part (not when whole).
  void finish(std::size_t position) {
    if (!whole() && part_.size() != 0) hand(position);
  }
  [[nodiscard]] PointCloud take_whole() { return std::move(part_); }

  /// Parts of the same size whose points are dropped: a survey of the file.
  [[nodiscard]] PointParts dropping() const {
    PointParts survey;
    survey.limit_ = limit_;
    survey.take_ = [](PointCloud&) {};
    survey.pages_ = pages_.restarted();
    return survey;
  }
  /// A fresh walk of the pages from the front of the file.
  [[nodiscard]] PageRelease pages() const { return pages_.restarted(); }

 private:
  std::size_t limit_ = std::numeric_limits<std::size_t>::max();
  Take take_;
  PageRelease pages_;
  PointCloud part_;
  std::uint64_t handed_ = 0;
};

/// Runs `pass` over a PointParts that drops its points: a reader's survey
/// before it reads the file in parts. Bad positions found meanwhile are not
/// counted for ReadPointsOptions::skip_invalid (the real pass counts them):
/// under a SkipInvalidPoints scope the survey opens one of its own.
template <class Pass>
void survey(const PointParts& parts, Pass&& pass) {
  PointParts dropped = parts.dropping();
  std::optional<SkipInvalidPoints> own_scope;
  if (SkipInvalidPoints::current() != nullptr) own_scope.emplace();
  std::forward<Pass>(pass)(dropped);
}

}  // namespace recon::io::detail
