// Choosing a mesh format and handing the file to its reader or writer
// (the formats themselves live in ply_read.cpp, ply_write.cpp, obj.cpp, off.cpp, stl.cpp).

#include "recon/io/mesh_io.h"

#include "formats.h"
#include "io_detail.h"

#include "recon/core/errors.h"
#include "recon/io/atomic_file.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace recon::io {
namespace {

MeshFormat resolve(const std::filesystem::path& path, MeshFormat format) {
  return format == MeshFormat::automatic ? mesh_format_from_path(path) : format;
}

/// STL stores float32: refuse what would become infinite instead of writing it.
void check_for_stl(const std::string& file, const Mesh& mesh) {
  if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    throw InvalidInputError(file + ": cannot write: STL holds at most 2^32 - 1 triangles");
  constexpr auto largest = static_cast<double>(std::numeric_limits<float>::max());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (mesh.vertices[i].cwiseAbs().maxCoeff() > largest)
      throw InvalidInputError(file + ": cannot write: vertex " + std::to_string(i) +
                              " is too large for the float coordinates of STL");
  }
}

}  // namespace

MeshFormat mesh_format_from_path(const std::filesystem::path& path) {
  const std::string extension = detail::lower_case(path.extension().string());
  if (extension == ".ply") return MeshFormat::ply;
  if (extension == ".obj") return MeshFormat::obj;
  if (extension == ".off") return MeshFormat::off;
  if (extension == ".stl") return MeshFormat::stl;
  if (extension == ".glb") return MeshFormat::glb;
  detail::fail_unknown_extension(path, extension, "known mesh formats: .ply, .obj, .off, .stl, .glb");
}

void write_mesh(const std::filesystem::path& path, const Mesh& mesh, const WriteMeshOptions& options) {
  const MeshFormat format = resolve(path, options.format);
  const std::string file = path.string();
  detail::check_mesh_for_writing(file, mesh);
  if (format == MeshFormat::stl) check_for_stl(file, mesh);
  if (format == MeshFormat::glb) detail::check_mesh_for_glb(file, mesh);
  AtomicFile output(path);
  switch (format) {
    case MeshFormat::ply:
      detail::write_ply_mesh(output.stream(), mesh, options.ascii);
      break;
    case MeshFormat::obj:
      detail::write_obj_mesh(output.stream(), mesh);
      break;
    case MeshFormat::off:
      detail::write_off_mesh(output.stream(), mesh);
      break;
    case MeshFormat::stl:
      detail::write_stl_mesh(output.stream(), mesh);
      break;
    case MeshFormat::glb:
      detail::write_glb_mesh(output.stream(), mesh);
      break;
    case MeshFormat::automatic:
      throw InvalidInputError(file + ": no mesh format chosen");
  }
  output.commit();
}

Mesh read_mesh(const std::filesystem::path& path) {
  const MeshFormat format = mesh_format_from_path(path);
  const std::string file = path.string();
  if (format == MeshFormat::stl)
    throw InvalidInputError(file + ": reading STL is not supported (it has no shared vertices); use PLY, OBJ or OFF");
  if (format == MeshFormat::glb) throw InvalidInputError(file + ": reading GLB is not supported; use PLY, OBJ or OFF");
  const detail::FileContent file_content = detail::read_file(path);
  const std::string_view content = file_content.view();
  if (content.empty()) detail::fail_in_file(file, "the file is empty");
  switch (format) {
    case MeshFormat::ply:
      return detail::read_ply_mesh(file, content);
    case MeshFormat::obj:
      return detail::read_obj_mesh(file, content);
    case MeshFormat::off:
      return detail::read_off_mesh(file, content);
    case MeshFormat::stl:
    case MeshFormat::glb:
    case MeshFormat::automatic:
      break;
  }
  throw InvalidInputError(file + ": no mesh format chosen");
}

}  // namespace recon::io
