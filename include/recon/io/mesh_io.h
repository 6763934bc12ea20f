#pragma once
// Reading and writing triangle meshes: PLY (binary little-endian by default,
// or ascii), OBJ, OFF and binary STL, chosen from the extension.
// Writing is atomic (temporary file in the same folder, then rename).
// Reading (PLY, OBJ, OFF) exists for reference surfaces and round trips;
// polygons with more than three corners are split into a fan.

#include "recon/mesh.h"

#include <filesystem>
#include <string_view>

namespace recon::io {

enum class MeshFormat { automatic, ply, obj, off, stl };

[[nodiscard]] MeshFormat mesh_format_from_path(const std::filesystem::path& path);

struct WriteMeshOptions {
  MeshFormat format = MeshFormat::automatic;
  bool ascii = false;  ///< PLY only
};

void write_mesh(const std::filesystem::path& path, const Mesh& mesh, const WriteMeshOptions& options = {});
[[nodiscard]] Mesh read_mesh(const std::filesystem::path& path);

}  // namespace recon::io
