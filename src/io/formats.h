#pragma once
// The readers and writers of each file format, one source file per format
// (ply.cpp, xyz.cpp, obj.cpp, off.cpp, pcd.cpp, las.cpp, stl.cpp, svg.cpp). point_io.cpp,
// mesh_io.cpp and curve_io.cpp choose among them.
//
// A reader gets the file name (for messages only) and the whole content of
// the file, which is not empty (usually a memory map of it: a reader must
// look no further than it needs, so garbage is refused early). A writer gets data already checked by
// check_cloud_for_writing / check_mesh_for_writing and an open stream.

#include "recon/io/point_io.h"
#include "recon/mesh.h"
#include "recon/point_cloud.h"
#include "recon/polyline.h"

#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace recon::io::detail {

[[nodiscard]] PointCloud read_ply_points(std::string_view file, std::string_view content);
[[nodiscard]] Mesh read_ply_mesh(std::string_view file, std::string_view content);
void write_ply_points(std::ostream& out, const PointCloud& cloud, bool ascii);
void write_ply_mesh(std::ostream& out, const Mesh& mesh, bool ascii);

[[nodiscard]] PointCloud read_xyz_points(std::string_view file, std::string_view content);
[[nodiscard]] PointCloud read_xyz_points(std::string_view file, std::string_view content,
                                         const ReadPointsOptions& options, ReadNotes& notes);
[[nodiscard]] PointCloud read_pts_points(std::string_view file, std::string_view content);
/// Numbers on the first line of plain text columns that has any (0: none).
[[nodiscard]] std::size_t xyz_column_count(std::string_view file, std::string_view content);
/// Plain text columns of two numbers a line: 2D points.
[[nodiscard]] std::vector<Vec2> read_xy_points(std::string_view file, std::string_view content);
/// True when .pts content is Hoppe's record format (its first field is a letter).
[[nodiscard]] bool pts_has_records(std::string_view file, std::string_view content);
void write_xyz_points(std::ostream& out, const PointCloud& cloud);

[[nodiscard]] PointCloud read_obj_points(std::string_view file, std::string_view content);
[[nodiscard]] Mesh read_obj_mesh(std::string_view file, std::string_view content);
void write_obj_mesh(std::ostream& out, const Mesh& mesh);

[[nodiscard]] PointCloud read_off_points(std::string_view file, std::string_view content);
[[nodiscard]] Mesh read_off_mesh(std::string_view file, std::string_view content);
void write_off_mesh(std::ostream& out, const Mesh& mesh);

/// PCD v0.7 (pcd.cpp); `notes` hears of skipped NaN points and dropped normals or colours.
[[nodiscard]] PointCloud read_pcd_points(std::string_view file, std::string_view content,
                                         const ReadPointsOptions& options, ReadNotes& notes);

/// LAS 1.0-1.4 (las.cpp); `notes` hears how 16-bit colours became 8-bit.
[[nodiscard]] PointCloud read_las_points(std::string_view file, std::string_view content,
                                         const ReadPointsOptions& options, ReadNotes& notes);
/// "LAZ (compressed LAS) is not read ...: decompress FILE first, e.g. ...":
/// what is said of a .laz file and of LAS content with laszip's compression bit.
[[nodiscard]] std::string laz_refusal(std::string_view file);

void write_svg_curves(std::ostream& out, const PolylineSet& curves, std::span<const Vec2> points,
                      std::span<const Vec2> normals, double normal_length);
void write_obj_curves(std::ostream& out, const PolylineSet& curves);
void write_text_curves(std::ostream& out, const PolylineSet& curves);

void write_stl_mesh(std::ostream& out, const Mesh& mesh);

}  // namespace recon::io::detail
