#pragma once
// Reading points in the plane and writing the curves reconstructed from
// them.
//
// 2D points come from
//   - plain text columns (.xyz .txt .asc .pwn, and .pts without records)
//     with two numbers a line, "x y": the same rules as 3D xyz text
//     (blanks or single commas between numbers, '#' comments, blank lines),
//     and every line must have two numbers;
//   - any 3D point file (see point_io.h) whose points all share one
//     coordinate: x first (Hoppe's 2D .pts files, such as curve1.pts, are
//     "p 0 y z" records, read as (y, z)), then z (read as (x, y)), then y
//     (read as (x, z)).
// Errors are those of the readers (ParseError "FILE:LINE: what" and so on,
// see point_io.h), and ParseError "FILE: the points are not 2D: ..." when
// no coordinate is shared by every point.
//
// Curves are written, atomically (io/atomic_file.h), as
//   svg - a picture: the points, their normals (when given) and the curves;
//   obj - "v x y 0" lines and one "l" line per curve (1-based; a closed
//         curve's line ends with its first vertex again);
//   txt - "x y" lines, a blank line between curves, a comment line before
//         each saying closed or open; a closed curve repeats its first vertex.
// Numbers are written with the shortest decimals that read back exactly.

#include "recon/io/point_io.h"
#include "recon/structures/polyline.h"

#include <filesystem>
#include <span>
#include <vector>

namespace recon::io {

/// True when the file holds 2D points a user means as such: two text
/// columns, or Hoppe's .pts records with the same x on every point (the
/// curve format of his programs). A 3D file that happens to be flat is not
/// taken for 2D here: it reconstructs as a flat surface unless a curve
/// output is asked for. A file of another format than xyz or pts is not opened: false.
/// Cost: O(file size) at most (a .pts file with records is read whole).
/// Throws: what read_points throws for a file it cannot read (IoError, ParseError); InvalidInputError for
/// an unknown extension.
/// Pre: the file does not change while it is read.
[[nodiscard]] bool holds_2d_points(const std::filesystem::path& path, const ReadPointsOptions& options = {});
/// As above, on a source opened once (a stream is not read again).
/// Cost, throws and preconditions as above (but the IoErrors of opening were the source's).
[[nodiscard]] bool holds_2d_points(const PointSource& source, const ReadPointsOptions& options = {});

/// The 2D points of a file (see above).
/// Cost: O(file size).
/// Throws: the readers' errors (see above; IoError, ParseError, InvalidInputError as read_points), and
/// ParseError "FILE: the points are not 2D: ..." when no coordinate is shared by every point.
/// Pre: the file does not change while it is read.
[[nodiscard]] std::vector<Vec2> read_points_2d(const std::filesystem::path& path,
                                               const ReadPointsOptions& options = {});
/// As above, on a source opened once.
/// Cost, throws and preconditions as above (but the IoErrors of opening were the source's).
[[nodiscard]] std::vector<Vec2> read_points_2d(const PointSource& source, const ReadPointsOptions& options = {});

enum class CurveFormat { automatic, svg, obj, txt };

/// From the extension (.svg, .obj, .txt; case-insensitive).
/// Cost: O(1).
/// Throws: InvalidInputError naming the known ones for another extension or none.
/// Pre: none.
[[nodiscard]] CurveFormat curve_format_from_path(const std::filesystem::path& path);

struct WriteCurvesOptions {
  CurveFormat format = CurveFormat::automatic;  ///< automatic: from the extension
  std::span<const Vec2> points;                 ///< samples to draw (SVG only; may be empty)
  std::span<const Vec2> normals;                ///< their unit normals (SVG only; empty or one per point)
  double normal_length = 0.0;                   ///< drawn length of a normal; 0: 1/40 of the picture's diagonal
};

/// Writes `curves` (and for SVG the points and normals of `options`) atomically, in the format chosen.
/// Cost: O(V + m) for V vertices and m polyline entries (and the points drawn).
/// Throws: InvalidInputError, before creating anything, for a coordinate that is not finite or beyond
/// +-max_coordinate, a normal that is not finite, a polyline vertex out of range, normals that are not
/// one per point, or an unknown extension; IoError when the file cannot be written (atomic_file.h).
/// Pre: none.
void write_curves(const std::filesystem::path& path, const PolylineSet& curves, const WriteCurvesOptions& options = {});

}  // namespace recon::io
