#pragma once
// Reading and writing point clouds.
//
// Formats (chosen from the file extension unless named):
//   ply  - PLY 1.0, ascii / binary_little_endian / binary_big_endian. The
//          "vertex" element's x, y, z (and nx, ny, nz when all three are
//          present, and the colours red, green, blue, or diffuse_red,
//          diffuse_green, diffuse_blue, when all three are) of any scalar
//          type; every other property and element (faces, alpha, ...) is
//          skipped, so a mesh's vertices read as a cloud. A property name
//          declared twice in an element is refused (ParseError at the second
//          line). Elements may come in any order; a list property on the
//          vertex element is refused. ASCII values may wrap across lines, but
//          text after the last declared element is an error; bytes after the
//          last element of a binary body are ignored.
//   xyz  - delimited text, one point a line, the same number of fields on
//          every line. Extensions .xyz, .txt, .asc, .pwn, .csv.
//          Separators: blanks (spaces, tabs), commas or semicolons, with
//          blanks around them allowed. The first line of numbers decides for
//          the whole file; another separator later is an error. Between
//          semicolons a comma inside a number is its decimal mark ("1,5;2;3"):
//          the only decimal comma read. Lines end with \n, \r\n or \r; a
//          UTF-8 byte-order mark is skipped; blank lines and '#' comments
//          (also after the numbers) are allowed.
//          What the columns hold, in this order of precedence:
//          1. ReadPointsOptions::columns (--columns): x y z nx ny nz r g b
//             (or normal_x ..., red ...) and _ for a column to skip. It must
//             name x, y and z, a triple whole or not at all, and as many
//             columns as the file has. A header line is then skipped (the
//             note says so).
//          2. A header: the first line that is not a comment, when it
//             starts with "//" (CloudCompare) or holds no number. Its names,
//             in any case and separated by any of the separators, are the
//             same; any other name (intensity, scalar_*, ...) is a column
//             recon ignores. It must name x, y and z; normals and colours
//             are used only when all three are named (a note says what was
//             ignored). Named normals may have any length.
//          3. Neither: 3 columns are x y z; 4 are x y z and a value recon
//             ignores (an intensity); 6 are x y z and a triple; 7 x y z, a
//             value and a triple, in either order; 9 x y z and two triples
//             (normals and colours, in either order). A triple holds normals
//             when its length is 1 (within 1 %) on every line (a NaN or
//             infinite triple does not count against it: it is then a bad
//             normal), else colours when its values fit colours; the whole
//             file's values decide, and what does not decide is refused
//             (ParseError "FILE: the columns after x y z leave doubt: ...",
//             naming --columns), as is any other count.
//          Colours are integers 0 to 255, or fractions 0 to 1 (scaled to
//          0-255 and rounded), one or the other in the whole file (only 0s
//          and 1s: fractions, 1 is 255). A named colour value that fits
//          neither is an error at its line.
//          ReadNotes says what the columns hold whenever --columns, a header
//          or the values decided it, e.g. "columns: x y z r g b (no header;
//          the last three are integers 0-255: colours)".
//          The file is parsed once from its map: values whose meaning waits
//          on the whole file are held as doubles until the end (to read a
//          file larger than the memory, see read_points_in_chunks in
//          point_stream.h).
//   pts  - text, either Hoppe's format ("p x y z" records; other one-letter
//          records such as d, s, g, n and '#' comments are ignored) or plain
//          columns read as xyz (above); the first record decides (a letter
//          and numbers: Hoppe's format; a line of names: a header of plain
//          columns).
//   obj  - "v x y z" lines, and "v x y z r g b" (r g b in [0, 1]) for the
//          colours when every "v" line has them; other numbers after z (the
//          w weight) are ignored. "vn" lines become the normals only when there are exactly
//          as many as "v" lines (OBJ ties normals to face corners, so another
//          count cannot be matched to the points; dropped normals are not
//          checked). Other statements are ignored, but a statement keyword
//          must be letters, digits and '_' (so garbage is not skipped over).
//   off  - [ST][C][N]OFF header (NOFF: normals after each position), counts
//          on the header line or the next one, '#' comments, one vertex a
//          line (colours after it ignored); faces are not read. 4OFF, nOFF
//          and binary OFF are refused.
//   pcd  - PCD v0.7 with x, y, z fields of any type (F 4/8, I or U 1/2/4/8),
//          normal_x, normal_y, normal_z used when all are present, rgb (or
//          rgba) of 4 bytes as colours (PCL's packed 0x00RRGGBB), other
//          fields skipped and never checked (a name FIELDS lists twice,
//          but the padding "_", is refused); DATA ascii, binary
//          (little-endian records) or binary_compressed (LZF, the fields
//          stored column by column). NaN is "no value": a point with a NaN
//          coordinate in an organized cloud (HEIGHT > 1), or with all of
//          x, y, z NaN in any cloud, has no position and is skipped (a
//          ReadNotes line counts them and places the first, also by row and
//          column); a NaN in some but not all of x, y, z of an unorganized
//          cloud is an invalid point (see below). A NaN normal component
//          drops the normals of the whole cloud, said in a note ("normals
//          dropped: ...; recon estimates its own"); a colour that is not a
//          number (ascii) drops the colours the same way.
//   las  - LAS 1.0 to 1.4, uncompressed, point data record formats 0 to 10,
//          the 32-bit or (1.4) 64-bit point count, header size, offset to
//          the points and record length as the header gives them (longer
//          records: extra bytes, skipped). A coordinate is X * scale +
//          offset, computed in double (millimetres of geo-referenced
//          coordinates of 1e6-1e7 are kept). Colours of formats 2, 3, 5,
//          7, 8, 10 are 16-bit: taken as they are when every value of the
//          file is at most 255, else by their high byte; a note says which.
//   laz  - compressed LAS (.laz, or LAS content with laszip's compression
//          bit) is refused with a message naming tools that decompress it.
//
// Colours (PointCloud::colors) become 0 to 255 by the type they are stored
// as: 8-bit integers as they are, 16-bit integers scaled (v / 257, rounded),
// wider integers as they are, floating point in [0, 1] times 255, rounded
// (or as they are, when some value of the file exceeds 1: 0-255 written as
// floats); then clamped to 0-255, NaN as 0. When one of the three channels
// is floating point, all three follow that rule. Alpha is ignored.
// Delimited text (xyz), whose values have no declared type, has a stricter
// rule of its own (above): integers 0 to 255 or fractions 0 to 1 for the
// whole file, and any other value is an error, not clamped.
//
// The file is mapped into memory read-only (mmap), not copied; a pipe or
// another file that cannot be mapped is read whole, up to a limit
// (ReadPointsOptions::max_stream_bytes) applied as the bytes come: the
// memory held never exceeds the bytes read by more than a megabyte. Readers look no further
// than they need, so a bad file is refused after its first pages, however
// large, and a header count never sizes an allocation beyond what the file
// could hold. Numbers are parsed with std::from_chars; in PLY and PCD text
// each value must fit its declared type (a uchar 0 to 255, a float within
// +-3.4e38, ...).
//
// Errors: ParseError with "FILE:LINE: ..." (text) or "FILE: byte N: ..."
// (binary) for malformed content, stopping at the first such problem:
// text where a number belongs, a number too large for a double or for its
// declared type (values too small become 0), a header promising more than
// the file holds, a text line longer than 1 MiB ("line N is longer than
// 1048576 bytes"), a NUL byte in text (binary data read as text); in
// delimited text also mixed separators, an empty field, a line with another
// number of fields, a header without x, y and z, and a colour value out of
// range. Element and point numbers in messages count from 0.
// Coordinates that are NaN, infinite or beyond +-max_coordinate (1e15), and
// normal components that are NaN or infinite, are not a stop: the reader
// reads on and then throws one ParseError that counts them and places the
// first, "FILE: 3 points have a coordinate that is not finite or beyond
// +-1e+15; the first at line 17 (z = nan)" ("at byte N" in binary data,
// "at point N" in decompressed data; "; and 2 points have a normal that is
// not finite ..." when both occur). PCD's points without a position are not
// counted: they are skipped (see above). With ReadPointsOptions::skip_invalid
// the points with such a coordinate are left out instead, with their normals
// and colours (a left-out point's normal is not checked), and a note says so
// in the same words, "skipped as invalid: 3 points have ..."; a file where
// no point is left is "FILE: no points: every point is invalid (...)".
// "FILE: the file is empty" and "FILE: no points ..." when there is nothing
// to read. IoError "FILE: cannot open: reason" when the file is missing, a
// folder or unreadable, "FILE: cannot read: reason" when reading fails,
// "FILE: more than N bytes from a stream ..." beyond max_stream_bytes;
// InvalidInputError for an unknown format name or extension (the message
// lists the known ones and the --format option), for .laz ("FILE: LAZ
// (compressed LAS) is not read by recon ...: decompress it first, e.g.
// 'laszip -i FILE -o out.las', ..."; LAS content with the compression bit
// gives the same words as a ParseError at byte 104), and for
// ReadPointsOptions::columns naming an unknown column, one twice, part of a
// triple, or no x, y or z ("--columns names an unknown column 'q' ..."),
// and for columns given with a format they do not apply to ("FILE:
// --columns applies to delimited text (xyz, and pts without 'p' records),
// not to ply, ...": ply, pcd, las, obj, off, and .pts with Hoppe's
// records): an option is refused rather than ignored.

#include "recon/core/point_cloud.h"

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace recon::io {

enum class PointFormat { automatic, ply, xyz, pts, obj, off, pcd, las, laz };

/// The format named "ply", "xyz", "pts", "obj", "off", "pcd", "las" or "laz" (case-insensitive).
/// Cost: O(1).
/// Throws: InvalidInputError for another name.
/// Pre: none.
[[nodiscard]] PointFormat point_format_from_name(std::string_view name);
/// The format of the path's extension (case-insensitive; .txt .asc .pwn .csv are xyz).
/// Cost: O(1).
/// Throws: InvalidInputError for an unknown extension or none.
/// Pre: none.
[[nodiscard]] PointFormat point_format_from_path(const std::filesystem::path& path);

struct ReadPointsOptions {
  PointFormat format = PointFormat::automatic;  ///< automatic: from the extension
  /// A stream (pipe, device) is held whole in memory: IoError "FILE: more
  /// than N bytes from a stream ..." beyond this; 0: half the physical memory.
  std::size_t max_stream_bytes = 0;
  /// Text columns: what each column holds, in order ("x", "y", "z", "nx",
  /// "ny", "nz", "r", "g", "b", "_" for a column to skip); it wins over a
  /// header line. Empty: from the header line, or from the values (see xyz
  /// above).
  std::vector<std::string> columns;
  /// Skip points with a coordinate that is not finite or beyond
  /// +-max_coordinate instead of refusing the file (ReadNotes says how many).
  bool skip_invalid = false;
};

/// "x,y,z,_,r,g,b" (as --columns takes them) -> {"x", "y", "z", "_", "r",
/// "g", "b"}: the text split at commas, nothing checked; "" -> {}.
/// Cost: O(length).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] inline std::vector<std::string> column_names(std::string_view text) {
  std::vector<std::string> names;
  if (text.empty()) return names;
  for (std::size_t start = 0;;) {
    const std::size_t comma = text.find(',', start);
    names.emplace_back(text.substr(start, comma - start));
    if (comma == std::string_view::npos) return names;
    start = comma + 1;
  }
}

/// What a reader chose or skipped that the user should hear about, one line
/// each, e.g. "columns: x y z r g b (no header; the last three are integers
/// 0-255: colours)" or "skipped 1200 points with no position (NaN x y z in
/// an organized cloud); the first at byte 356 (row 0, column 3)".
struct ReadNotes {
  std::vector<std::string> lines;
  std::size_t skipped_points = 0;  ///< points left out (invalid or no measurement)
};

/// Reads a point cloud; `notes`, when given, receives what the reader chose
/// or skipped.
/// Cost: O(file size), mapped, not copied (a stream is read whole first).
/// Throws: ParseError, IoError and InvalidInputError as listed under "Errors" above.
/// Pre: the file does not change while it is read (see file_being_read()).
[[nodiscard]] PointCloud read_points(const std::filesystem::path& path, const ReadPointsOptions& options = {},
                                     ReadNotes* notes = nullptr);

namespace detail {
class FileContent;
}

/// A point file opened once, for a program that looks at its input before
/// reading it (reconstruct asks whether it holds 2D points): a regular file
/// is mapped, so looking costs nothing; a stream (a pipe, a FIFO,
/// /dev/stdin) can be read only once, so it is read whole into memory here,
/// up to `max_stream_bytes` (as ReadPointsOptions::max_stream_bytes).
class PointSource {
 public:
  /// Opens `path`: maps a regular file, reads a stream whole.
  /// Cost: O(1) for a mapped file; O(bytes) for a stream.
  /// Throws: IoError when the file cannot be opened or read, or a stream is longer than the limit.
  /// Pre: none.
  explicit PointSource(std::filesystem::path path, std::size_t max_stream_bytes = 0);
  PointSource(PointSource&&) noexcept;
  PointSource& operator=(PointSource&&) noexcept;
  ~PointSource();

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::string_view bytes() const;
  /// Memory held for a stream's bytes (0 for a mapped file): within the
  /// bytes read and a page, however the stream grew (no doubling buffer).
  [[nodiscard]] std::size_t held_bytes() const;

 private:
  std::filesystem::path path_;
  std::unique_ptr<detail::FileContent> content_;
};

/// True when `path` is something other than a regular file or a folder (a
/// pipe, a FIFO, a device, /dev/stdin on a pipe): what can be read only
/// once. False when it does not exist (opening it says so).
/// Cost: one stat.
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] bool is_stream(const std::filesystem::path& path);

/// read_points on a source already opened; options.max_stream_bytes was the
/// source's to apply.
/// Cost: O(file size).
/// Throws: ParseError and InvalidInputError as read_points (the IoErrors of opening were the source's).
/// Pre: as read_points.
[[nodiscard]] PointCloud read_points(const PointSource& source, const ReadPointsOptions& options = {},
                                     ReadNotes* notes = nullptr);

/// The mapped input file a reader of this library is reading at this
/// moment, or "" when none. Reading a page that another program cut off the
/// end of a mapped file (by shortening the file meanwhile) raises SIGBUS
/// instead of returning an error; a program's SIGBUS handler can name the
/// file with this. Async-signal-safe.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] const char* file_being_read() noexcept;

struct WritePointsOptions {
  PointFormat format = PointFormat::automatic;  ///< ply or xyz; automatic: from the extension
  bool ascii = false;                           ///< PLY only: ascii instead of binary little-endian
};

/// Writes positions and, when present, normals and colours, as ply or xyz.
/// Doubles are written losslessly (PLY: property double; text: the shortest
/// decimal that reads back as the same double, at most 17 significant digits), so a written
/// cloud reads back bit for bit. Colours are written after the other
/// properties: PLY "property uchar red", green, blue (three bytes in binary);
/// xyz "x y z [nx ny nz] r g b" with r g b 0 to 255 (the delimited-text
/// reader tells such columns by their values).
/// The file is written to a temporary file in the same folder and renamed
/// into place when complete: a failure leaves no partial file.
/// Cost: O(n) for n points.
/// Throws: InvalidInputError, before creating anything, for a format other than ply or xyz, an unknown
/// extension, normals or colours present but not one per point, a value that is not finite or a
/// coordinate beyond +-max_coordinate (it would not read back); IoError when the file cannot be written
/// (atomic_file.h).
/// Pre: none.
void write_points(const std::filesystem::path& path, const PointCloud& cloud, const WritePointsOptions& options = {});

}  // namespace recon::io
