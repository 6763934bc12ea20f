#include "readers.h"

#include "formats.h"

#include "recon/errors.h"

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
template <ReaderWithNotes read>
void run_with_notes(std::string_view content) {
  try {
    recon::io::ReadNotes notes;
    static_cast<void>(read("fuzz-input", content, recon::io::ReadPointsOptions{}, notes));
  } catch (const recon::Error&) {
  }
}

}  // namespace

Reader reader_named(std::string_view name) {
  using namespace recon::io::detail;
  static constexpr std::pair<std::string_view, Reader> readers[] = {
      {"ply_points", run<read_ply_points>}, {"ply_mesh", run<read_ply_mesh>},
      {"xyz_points", run_with_notes<read_xyz_points>}, {"pts_points", run<read_pts_points>},
      {"obj_points", run<read_obj_points>}, {"obj_mesh", run<read_obj_mesh>},
      {"off_points", run<read_off_points>}, {"off_mesh", run<read_off_mesh>},
      {"pcd_points", run_with_notes<read_pcd_points>}, {"xy_points", run<read_xy_points>},
      {"las_points", run_with_notes<read_las_points>},
  };
  for (const auto& [known, reader] : readers) {
    if (known == name) return reader;
  }
  return nullptr;
}

}  // namespace recon::fuzz
