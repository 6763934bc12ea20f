#pragma once
// Reading and writing point clouds.
//
// Formats (chosen from the file extension unless named):
//   ply  - PLY 1.0, ascii / binary_little_endian / binary_big_endian. The
//          "vertex" element's x, y, z (and nx, ny, nz when all three are
//          present) of any scalar type; every other property and element
//          (faces, colours, ...) is skipped, so a mesh's vertices read as a
//          cloud.
//   xyz  - text, 3 or 6 numbers a line (x y z [nx ny nz]); blank lines and
//          '#' comments allowed. Extensions .xyz, .txt, .asc, .pwn.
//   pts  - text, either Hoppe's format ("p x y z" records; other one-letter
//          records and '#' comments are ignored) or plain xyz columns; the
//          first record decides.
//   obj  - "v x y z" lines (faces and the rest ignored).
//   off  - OFF / NOFF header, counts, vertices (faces ignored).
//   pcd  - PCD v0.7 with x, y, z fields (normal_x... used when present),
//          DATA ascii or binary.
//
// Errors: ParseError with "FILE:LINE: ..." (text) or "FILE: byte N: ..."
// (binary) for malformed content, including non-finite coordinates;
// IoError when the file cannot be opened; InvalidInputError for an unknown
// format name or extension.

#include "recon/point_cloud.h"

#include <filesystem>
#include <string_view>

namespace recon::io {

enum class PointFormat { automatic, ply, xyz, pts, obj, off, pcd };

/// "ply", "xyz", "pts", "obj", "off", "pcd"; throws InvalidInputError otherwise.
[[nodiscard]] PointFormat point_format_from_name(std::string_view name);
/// From the extension (case-insensitive); throws InvalidInputError when unknown.
[[nodiscard]] PointFormat point_format_from_path(const std::filesystem::path& path);

struct ReadPointsOptions {
  PointFormat format = PointFormat::automatic;  ///< automatic: from the extension
};

[[nodiscard]] PointCloud read_points(const std::filesystem::path& path, const ReadPointsOptions& options = {});

struct WritePointsOptions {
  PointFormat format = PointFormat::automatic;  ///< ply or xyz; automatic: from the extension
  bool ascii = false;                           ///< PLY only: ascii instead of binary little-endian
};

/// Writes positions and, when present, normals. Doubles are written with
/// full precision (PLY: property double; text: 17 significant digits).
/// The file is written to a temporary file in the same folder and renamed
/// into place when complete: a failure leaves no partial file.
void write_points(const std::filesystem::path& path, const PointCloud& cloud, const WritePointsOptions& options = {});

}  // namespace recon::io
