#pragma once
// Writing a triangle mesh as it comes, never holding it whole: the output
// side of the out-of-core (tiled) mode.
//
// PlyMeshStream writes a binary PLY file, byte for byte the file that
// write_mesh (mesh_io.h) writes for the same mesh: the same header, x y z as
// "property double" (then "property float nx", ny, nz with normals, and
// "property uchar red", green, blue with colours),
// faces as "property list uchar int vertex_indices" ("uint" beyond 2^31 - 1
// vertices). Since the header holds the counts, which are known only at the
// end, the vertex records and the face records go to two temporary files
// beside the output, in blocks of a megabyte; finish() writes the header and
// copies both parts into a third temporary file, which is renamed onto
// `path` (AtomicFile, atomic_file.h). The disk holds the mesh about twice
// meanwhile, the memory two blocks.
//
// Destroyed without finish() (an exception, an interruption), it removes
// every temporary and leaves `path` as it was. A SIGINT handler that calls
// remove_pending_temporaries() removes them too.
//
// Errors: IoError "PATH: cannot write ..." when a temporary cannot be made
// (the folder does not exist or is not writable), "PATH: write failed
// (disk full?)" when writing fails; InvalidInputError "PATH: cannot write:
// ..." for a vertex coordinate that is not finite or beyond +-max_coordinate
// (it would not read back; at add_vertex), a colour missing or given against
// `with_colors`, more than 2^32 vertices, and, at finish(), a triangle that
// uses a vertex never added (the message names the first triangle that used
// the largest such index); a call after finish().

#include "recon/core/point_cloud.h"
#include "recon/io/atomic_file.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace recon::io {

class PlyMeshStream {
 public:
  /// Opens the temporary files beside `path`; `with_colors`: every vertex
  /// has a colour (add_vertex with a Color), else none has; `with_normals`:
  /// every vertex has a unit normal (add_vertex with a normal), else none has.
  /// Cost: O(1) system calls.
  /// Throws: IoError when a temporary cannot be made or the target is refused (atomic_file.h).
  /// Pre: none.
  PlyMeshStream(const std::filesystem::path& path, bool with_colors, bool with_normals = false);
  PlyMeshStream(const PlyMeshStream&) = delete;
  PlyMeshStream& operator=(const PlyMeshStream&) = delete;
  ~PlyMeshStream();

  /// Adds a vertex and returns its index (0, 1, 2, ... in the order added);
  /// the third form with a normal (the stream opened with_normals), `color` null: none.
  /// Cost: O(1) amortized (a block written every megabyte).
  /// Throws: InvalidInputError for a coordinate that is not finite or beyond +-max_coordinate, a colour or
  /// normal missing or given against how the stream was opened, a normal that is not unit (within 1e-3),
  /// more than 2^32 vertices, or a call after finish(); IoError when a block cannot be written.
  /// Pre: none.
  std::uint32_t add_vertex(const Vec3& position);
  std::uint32_t add_vertex(const Vec3& position, const Color& color);
  std::uint32_t add_vertex(const Vec3& position, const Color* color, const Vec3& normal);
  /// Adds a triangle of vertex indices; a vertex may be added after the
  /// triangles that use it (checked at finish()).
  /// Cost: O(1) amortized.
  /// Throws: InvalidInputError after finish(); IoError when a block cannot be written.
  /// Pre: none.
  void add_triangle(const std::array<std::uint32_t, 3>& triangle);
  /// Writes the file and renames it onto `path`.
  /// Cost: O(V + F), copying both parts into the output.
  /// Throws: InvalidInputError for a triangle that uses a vertex never added, or a second call; IoError
  /// when writing, reading back a part, syncing or renaming fails.
  /// Pre: none.
  void finish();

  [[nodiscard]] std::size_t vertex_count() const { return vertices_; }
  [[nodiscard]] std::size_t triangle_count() const { return triangles_; }

 private:
  /// Records not yet written to a part, and the part's temporary file.
  struct Part {
    explicit Part(const std::filesystem::path& path) : file(path, AtomicFile::Use::scratch) {}
    AtomicFile file;  // a scratch file beside the output (even a FIFO's), removed with the Part
    std::string buffer;
  };

  std::uint32_t add(const Vec3& position, const Color* color, const Vec3* normal);
  void flush_if_full(Part& part);
  void flush(Part& part);
  void check_open() const;
  void check_indices() const;
  void copy_part(Part& part);

  std::filesystem::path path_;
  bool with_colors_;
  bool with_normals_;
  AtomicFile output_;
  std::optional<Part> vertex_part_;
  std::optional<Part> face_part_;
  std::size_t vertices_ = 0;
  std::size_t triangles_ = 0;
  std::uint64_t vertices_needed_ = 0;  ///< the largest index a triangle used, plus one
  std::size_t first_needing_ = 0;      ///< the first triangle that used that index
  bool finished_ = false;
};

}  // namespace recon::io
