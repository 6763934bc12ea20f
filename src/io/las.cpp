// LAS 1.0-1.4 point clouds (ASPRS LiDAR exchange format): not read yet.

#include "formats.h"
#include "io_detail.h"

namespace recon::io::detail {

PointCloud read_las_points(std::string_view file, std::string_view /*content*/, const ReadPointsOptions& /*options*/,
                           ReadNotes& /*notes*/) {
  fail_in_file(file, "LAS files are not read yet");
}

}  // namespace recon::io::detail
