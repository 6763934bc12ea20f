// Writing a binary PLY mesh as it comes (mesh_stream.h): the records go to
// two temporary parts through buffers of a megabyte, written by the same
// functions as write_mesh's (ply_write.cpp), and finish() joins header and parts.

#include "recon/io/mesh_stream.h"

#include "formats.h"
#include "io_detail.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <vector>

namespace recon::io {
namespace {

constexpr std::size_t block_size = std::size_t{1} << 20;

}  // namespace

PlyMeshStream::PlyMeshStream(const std::filesystem::path& path, bool with_colors, bool with_normals)
    : path_(path), with_colors_(with_colors), with_normals_(with_normals), output_(path) {
  // Three temporaries of the same target: their names differ by a counter.
  vertex_part_.emplace(path);
  face_part_.emplace(path);
  vertex_part_->buffer.reserve(block_size + 64);
  face_part_->buffer.reserve(block_size + 64);
}

PlyMeshStream::~PlyMeshStream() = default;  // an AtomicFile not committed removes its temporary

std::uint32_t PlyMeshStream::add_vertex(const Vec3& position) {
  if (with_colors_)
    throw InvalidInputError(path_.string() + ": cannot write: vertex " + std::to_string(vertices_) +
                            " has no colour, but the mesh has colours");
  return add(position, nullptr, nullptr);
}

std::uint32_t PlyMeshStream::add_vertex(const Vec3& position, const Color& color) {
  if (!with_colors_)
    throw InvalidInputError(path_.string() + ": cannot write: vertex " + std::to_string(vertices_) +
                            " has a colour, but the mesh was opened without colours");
  return add(position, &color, nullptr);
}

std::uint32_t PlyMeshStream::add_vertex(const Vec3& position, const Color* color, const Vec3& normal) {
  if (with_colors_ != (color != nullptr))
    throw InvalidInputError(path_.string() + ": cannot write: vertex " + std::to_string(vertices_) +
                            (color ? " has a colour, but the mesh was opened without colours"
                                   : " has no colour, but the mesh has colours"));
  const double norm = normal.norm();
  if (!std::isfinite(norm) || !(std::abs(norm - 1.0) < 1e-3))  // (isfinite first: no comparison with a NaN)
    throw InvalidInputError(path_.string() + ": cannot write: vertex " + std::to_string(vertices_) +
                            "'s normal is not a unit vector");
  return add(position, color, &normal);
}

std::uint32_t PlyMeshStream::add(const Vec3& position, const Color* color, const Vec3* normal) {
  check_open();
  if (with_normals_ != (normal != nullptr))
    throw InvalidInputError(path_.string() + ": cannot write: vertex " + std::to_string(vertices_) +
                            (normal ? " has a normal, but the mesh was opened without normals"
                                    : " has no normal, but the mesh has normals"));
  if (vertices_ > std::numeric_limits<std::uint32_t>::max())
    throw InvalidInputError(path_.string() + ": cannot write: more than 2^32 vertices");
  if (!detail::coordinate_in_range(position.x()) || !detail::coordinate_in_range(position.y()) ||
      !detail::coordinate_in_range(position.z()))
    throw InvalidInputError(path_.string() + ": cannot write: vertex " + std::to_string(vertices_) +
                            " has a coordinate that is not finite or beyond " + detail::coordinate_bound());
  detail::append_ply_vertex(vertex_part_->buffer, position, color, false, normal);
  flush_if_full(*vertex_part_);
  return static_cast<std::uint32_t>(vertices_++);
}

void PlyMeshStream::add_triangle(const std::array<std::uint32_t, 3>& triangle) {
  check_open();
  const std::uint64_t needed = std::uint64_t{std::max({triangle[0], triangle[1], triangle[2]})} + 1;
  if (needed > vertices_needed_) {
    vertices_needed_ = needed;
    first_needing_ = triangles_;
  }
  detail::append_ply_triangle_binary(face_part_->buffer, triangle);
  flush_if_full(*face_part_);
  ++triangles_;
}

void PlyMeshStream::flush_if_full(Part& part) {
  if (part.buffer.size() >= block_size) flush(part);
}

void PlyMeshStream::flush(Part& part) {
  std::ofstream& out = part.file.stream();
  out.write(part.buffer.data(), static_cast<std::streamsize>(part.buffer.size()));
  part.buffer.clear();
  if (!out) throw IoError(path_.string() + ": write failed (disk full?)");
}

void PlyMeshStream::check_open() const {
  if (finished_) throw InvalidInputError(path_.string() + ": the mesh is finished; nothing can be added");
}

void PlyMeshStream::check_indices() const {
  if (vertices_needed_ <= vertices_) return;
  throw InvalidInputError(path_.string() + ": cannot write: triangle " + std::to_string(first_needing_) +
                          " uses vertex " + std::to_string(vertices_needed_ - 1) + ", but the mesh has " +
                          std::to_string(vertices_) + " vertices");
}

/// Appends the part's temporary file to the output and removes it.
void PlyMeshStream::copy_part(Part& part) {
  flush(part);
  part.file.stream().close();
  if (part.file.stream().fail()) throw IoError(path_.string() + ": write failed (disk full?)");
  std::ifstream in(part.file.temporary(), std::ios::binary);
  std::vector<char> block(block_size);
  std::ofstream& out = output_.stream();
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    out.write(block.data(), in.gcount());
  }
  if (!in.eof()) {
    const int error = errno;
    throw IoError(path_.string() + ": cannot read back a temporary part: " + std::strerror(error), error);
  }
  if (!out) throw IoError(path_.string() + ": write failed (disk full?)");
}

void PlyMeshStream::finish() {
  check_open();
  check_indices();
  finished_ = true;
  const std::string header = detail::ply_mesh_header(false, vertices_, triangles_, with_colors_, with_normals_);
  output_.stream().write(header.data(), static_cast<std::streamsize>(header.size()));
  copy_part(*vertex_part_);
  vertex_part_.reset();
  copy_part(*face_part_);
  face_part_.reset();
  output_.commit();
}

}  // namespace recon::io
