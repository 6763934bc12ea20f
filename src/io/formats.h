#pragma once
// The readers and writers of each file format, one source file per format
// (ply.cpp, xyz.cpp, obj.cpp, off.cpp, pcd.cpp, stl.cpp). point_io.cpp and
// mesh_io.cpp choose among them.
//
// A reader gets the file name (for messages only) and the whole content of
// the file, which is not empty (usually a memory map of it: a reader must
// look no further than it needs, so garbage is refused early). A writer gets data already checked by
// check_cloud_for_writing / check_mesh_for_writing and an open stream.

#include "recon/mesh.h"
#include "recon/point_cloud.h"

#include <ostream>
#include <string_view>

namespace recon::io::detail {

[[nodiscard]] PointCloud read_ply_points(std::string_view file, std::string_view content);
[[nodiscard]] Mesh read_ply_mesh(std::string_view file, std::string_view content);
void write_ply_points(std::ostream& out, const PointCloud& cloud, bool ascii);
void write_ply_mesh(std::ostream& out, const Mesh& mesh, bool ascii);

[[nodiscard]] PointCloud read_xyz_points(std::string_view file, std::string_view content);
[[nodiscard]] PointCloud read_pts_points(std::string_view file, std::string_view content);
void write_xyz_points(std::ostream& out, const PointCloud& cloud);

[[nodiscard]] PointCloud read_obj_points(std::string_view file, std::string_view content);
[[nodiscard]] Mesh read_obj_mesh(std::string_view file, std::string_view content);
void write_obj_mesh(std::ostream& out, const Mesh& mesh);

[[nodiscard]] PointCloud read_off_points(std::string_view file, std::string_view content);
[[nodiscard]] Mesh read_off_mesh(std::string_view file, std::string_view content);
void write_off_mesh(std::ostream& out, const Mesh& mesh);

[[nodiscard]] PointCloud read_pcd_points(std::string_view file, std::string_view content);

void write_stl_mesh(std::ostream& out, const Mesh& mesh);

}  // namespace recon::io::detail
