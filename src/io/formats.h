#pragma once
// The readers and writers of each file format, one source file per format
// (ply_read.cpp, ply_write.cpp, xyz.cpp, obj.cpp, off.cpp, pcd.cpp, las.cpp, stl.cpp, svg.cpp). point_io.cpp,
// mesh_io.cpp and curve_io.cpp choose among them.
//
// A reader gets the file name (for messages only) and the whole content of
// the file, which is not empty (usually a memory map of it: a reader must
// look no further than it needs, so garbage is refused early). A writer gets data already checked by
// check_cloud_for_writing / check_mesh_for_writing and an open stream.

#include "point_parts.h"

#include "recon/core/point_cloud.h"
#include "recon/io/point_io.h"
#include "recon/structures/mesh.h"
#include "recon/structures/polyline.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace recon::io::detail {

/// The format read_points reads `path` as (ReadPointsOptions::format, or
/// from the extension).
[[nodiscard]] PointFormat point_format_of(const std::filesystem::path& path, const ReadPointsOptions& options);
/// InvalidInputError "FILE: --columns applies to delimited text ..." when
/// ReadPointsOptions::columns is given for a format other than xyz and pts:
/// an option that would be ignored is refused.
void check_columns_apply(std::string_view file, PointFormat format, const ReadPointsOptions& options);
/// The content of a point file as read_points opens it (read_file), after
/// refusing LAZ and columns that do not apply (InvalidInputError);
/// ParseError "FILE: the file is empty".
[[nodiscard]] FileContent open_points(const std::filesystem::path& path, PointFormat format,
                                      const ReadPointsOptions& options);

[[nodiscard]] PointCloud read_ply_points(std::string_view file, std::string_view content);
/// The points into `parts`: whole, or in parts (a survey first when the
/// colours are floating point; see point_parts.h).
void read_ply_points(std::string_view file, std::string_view content, PointParts& parts);
[[nodiscard]] Mesh read_ply_mesh(std::string_view file, std::string_view content);
void write_ply_points(std::ostream& out, const PointCloud& cloud, bool ascii);
void write_ply_mesh(std::ostream& out, const Mesh& mesh, bool ascii);
/// The parts of a PLY mesh as write_ply_mesh writes them, for writers that
/// do not hold the mesh (mesh_stream.cpp): the header, up to its
/// "end_header" line; a vertex record (`color` nullptr: none); a triangle's
/// face record in binary.
/// With `normals`, "property float nx, ny, nz" after x, y, z (before the colours).
[[nodiscard]] std::string ply_mesh_header(bool ascii, std::size_t vertices, std::size_t triangles, bool colors,
                                          bool normals = false);
/// `normal` nullptr: none.
void append_ply_vertex(std::string& out, const Vec3& position, const Color* color, bool ascii,
                       const Vec3* normal = nullptr);
void append_ply_triangle_binary(std::string& out, const std::array<std::uint32_t, 3>& triangle);

[[nodiscard]] PointCloud read_xyz_points(std::string_view file, std::string_view content);
[[nodiscard]] PointCloud read_xyz_points(std::string_view file, std::string_view content,
                                         const ReadPointsOptions& options, ReadNotes& notes);
/// The points into `parts`: whole, or in parts (a survey first when values
/// decide what columns hold; see point_parts.h).
void read_xyz_points(std::string_view file, std::string_view content, const ReadPointsOptions& options,
                     ReadNotes& notes, PointParts& parts);
[[nodiscard]] PointCloud read_pts_points(std::string_view file, std::string_view content);
/// As above; plain columns follow `options` (ReadPointsOptions::columns),
/// and Hoppe's records refuse columns (InvalidInputError).
[[nodiscard]] PointCloud read_pts_points(std::string_view file, std::string_view content,
                                         const ReadPointsOptions& options, ReadNotes& notes);
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
/// The points into `parts`, whole or in parts (the colours' range is found
/// by a first walk over the records in both cases).
void read_las_points(std::string_view file, std::string_view content, ReadNotes& notes, PointParts& parts);
/// "LAZ (compressed LAS) is not read ...; decompress it first, e.g. ...":
/// what is said of LAS content with laszip's compression bit (after "FILE:
/// byte 104: "). The commands say IN for the file: a message names it once.
[[nodiscard]] std::string laz_advice();
/// "FILE: " and laz_advice(): what is said of a .laz file.
[[nodiscard]] std::string laz_refusal(std::string_view file);

void write_svg_curves(std::ostream& out, const PolylineSet& curves, std::span<const Vec2> points,
                      std::span<const Vec2> normals, double normal_length);
void write_obj_curves(std::ostream& out, const PolylineSet& curves);
void write_text_curves(std::ostream& out, const PolylineSet& curves);

void write_stl_mesh(std::ostream& out, const Mesh& mesh);

/// GLB (glb.cpp). check_mesh_for_glb refuses, before anything is written,
/// what GLB cannot hold (InvalidInputError naming the file): a coordinate
/// beyond float range, a normal that is not unit, a file of 4 GiB or more.
void check_mesh_for_glb(std::string_view file, const Mesh& mesh);
void write_glb_mesh(std::ostream& out, const Mesh& mesh);

}  // namespace recon::io::detail
