#include "readers.h"

#include "formats.h"

#include "recon/core/errors.h"

#include <string>
#include <utility>

namespace recon::fuzz {
namespace {

template <auto read>
void run(std::string_view content) {
  try {
    static_cast<void>(read("fuzz-input", content));
  } catch (const recon::Error&) {
  }
}

/// A point reader that takes options and notes (as read_points calls it),
/// with the default options. The type picks that overload where a reader
/// also has a plain one.
using ReaderWithNotes = recon::PointCloud (*)(std::string_view, std::string_view, const recon::io::ReadPointsOptions&,
                                              recon::io::ReadNotes&);
/// A point reader of the whole file (picks that overload where a reader
/// also hands its points out in parts, for streaming).
using WholeReader = recon::PointCloud (*)(std::string_view, std::string_view);
template <WholeReader read>
void run_whole(std::string_view content) {
  run<read>(content);
}

template <ReaderWithNotes read>
void run_with_notes(std::string_view content) {
  try {
    recon::io::ReadNotes notes;
    static_cast<void>(read("fuzz-input", content, recon::io::ReadPointsOptions{}, notes));
  } catch (const recon::Error&) {
  }
}

// Delimited text as read_points reads it. A first line "#columns NAMES"
// (a comment to the reader) gives NAMES, split at commas, as --columns
// would, so that the fuzzer reaches the plans named by --columns too.
recon::PointCloud read_text_columns(std::string_view file, std::string_view content) {
  recon::io::ReadPointsOptions options;
  constexpr std::string_view mark = "#columns ";
  if (content.starts_with(mark)) {
    const std::string_view names = content.substr(mark.size());
    options.columns = recon::io::column_names(names.substr(0, names.find('\n')));
  }
  recon::io::ReadNotes notes;
  return recon::io::detail::read_xyz_points(file, content, options, notes);
}

}  // namespace

Reader reader_named(std::string_view name) {
  using namespace recon::io::detail;
  static constexpr std::pair<std::string_view, Reader> readers[] = {
      {"ply_points", run_whole<read_ply_points>},
      {"ply_mesh", run<read_ply_mesh>},
      {"xyz_points", run<read_text_columns>},
      {"pts_points", run_with_notes<read_pts_points>},
      {"obj_points", run<read_obj_points>},
      {"obj_mesh", run<read_obj_mesh>},
      {"off_points", run<read_off_points>},
      {"off_mesh", run<read_off_mesh>},
      {"pcd_points", run_with_notes<read_pcd_points>},
      {"xy_points", run<read_xy_points>},
      {"las_points", run_with_notes<read_las_points>},
  };
  for (const auto& [known, reader] : readers) {
    if (known == name) return reader;
  }
  return nullptr;
}

}  // namespace recon::fuzz
