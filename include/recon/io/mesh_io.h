#pragma once
// Reading and writing triangle meshes: PLY (binary little-endian by default,
// or ascii), OBJ, OFF and binary STL, chosen from the extension.
// Writing is atomic (temporary file in the same folder, then rename).
// Reading (PLY, OBJ, OFF) exists for reference surfaces and round trips;
// polygons with more than three corners are split into a fan.
//
// Written files: PLY vertices as "property double" (lossless; the binary
// file is 24 bytes a vertex) and faces as "property list uchar int
// vertex_indices"; OBJ "v" and 1-based "f" lines and OFF, with the shortest
// decimals that read back exactly; binary STL with float32 corners and a
// unit facet normal computed from the corner order (zero when degenerate).
// write_mesh throws InvalidInputError, before creating anything, for
// colours present but not one per vertex, a vertex coordinate that is not
// finite or beyond +-max_coordinate (it would not read back), an index out of
// range, or (STL) a coordinate beyond float range.
//
// Colours (Mesh::colors, one per vertex) are written where the format has a
// place for them: PLY "property uchar red", green, blue after x, y, z (three
// bytes in binary); OBJ "v x y z r g b" with r g b in [0, 1] to 4 decimals
// (the extension MeshLab, Open3D and many scanners read; the same bytes
// read back); OFF as COFF, "x y z r g b a" with each 0 to 255 and alpha 255
// (as MeshLab and Open3D write it). Binary STL has no standard place for
// colours (the attribute word's colour is a vendor extension read in
// incompatible ways): the colours are dropped and the file is the same as
// without them.
//
// Normals (Mesh::normals, one unit normal per vertex) are written when the
// mesh has them, as floats (shading needs no more; the shortest decimals
// that read back as the same floats in text): PLY "property float nx", ny,
// nz after x, y, z (before the colours); OBJ a "vn" line after each "v" line
// and faces "f a//a b//b c//c"; GLB always has them (a mesh without gets
// the area-weighted ones, vertex_normals.h). OFF and STL have no place for
// them: dropped. Without normals the bytes are as before they existed.
// write_mesh refuses (InvalidInputError) normals not one per vertex or not
// finite, and for GLB not unit (glTF requires unit normals).
//
// GLB (glTF 2.0 binary: src/io/glb.cpp says what it holds) is written, not
// read.
//
// Reading: PLY takes the "vertex" element's x, y, z (and its colours, as
// read_points does) and the "face" element's "vertex_indices" or
// "vertex_index" list (any integer count type, any index type holding whole
// numbers); OBJ takes "v" lines (with "v x y z r g b" colours when every one
// has them) and "f" lines (corners v, v/vt, v/vt/vn, v//vn; negative numbers
// count back from the last vertex read); OFF takes its vertices and faces
// (COFF's colours are not read). A file without a triangle, a face with
// fewer than three corners or an index out of range is a ParseError naming
// the line or byte; reading STL is refused (InvalidInputError). Files are
// mapped, not copied, and errors are reported as for read_points (see
// point_io.h), including the line limit and the count of vertices with a
// coordinate that is not finite or beyond +-max_coordinate.

#include "recon/structures/mesh.h"

#include <filesystem>
#include <string_view>

namespace recon::io {

enum class MeshFormat { automatic, ply, obj, off, stl, glb };

/// The format of the path's extension: .ply, .obj, .off, .stl, .glb (case-insensitive).
/// Cost: O(1).
/// Throws: InvalidInputError for another extension or none.
/// Pre: none.
[[nodiscard]] MeshFormat mesh_format_from_path(const std::filesystem::path& path);

struct WriteMeshOptions {
  MeshFormat format = MeshFormat::automatic;
  bool ascii = false;  ///< PLY only
};

/// Writes `mesh` (#V vertices, #F triangles) atomically in the format chosen (see above).
/// Cost: O(V + F).
/// Throws: InvalidInputError, before creating anything, as listed above (and for an unknown extension);
/// IoError when the file cannot be written (atomic_file.h).
/// Pre: none.
void write_mesh(const std::filesystem::path& path, const Mesh& mesh, const WriteMeshOptions& options = {});
/// Reads a PLY, OBJ or OFF mesh (see "Reading" above).
/// Cost: O(file size).
/// Throws: ParseError and IoError as read_points (point_io.h) and as listed above; InvalidInputError for
/// STL, GLB or an unknown extension.
/// Pre: the file does not change while it is read.
[[nodiscard]] Mesh read_mesh(const std::filesystem::path& path);

}  // namespace recon::io
