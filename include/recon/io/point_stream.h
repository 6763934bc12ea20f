#pragma once
// Reading a point cloud in chunks, never holding it whole: the input side of
// the out-of-core (tiled) mode, for clouds of 100 million points and more.
//
// read_points_in_chunks hands the points of a file to a function in
// consecutive chunks of at most PointChunkOptions::chunk_points points, in
// the order of the file. Put end to end, the chunks are the cloud that
// read_points (point_io.h) reads from the same file with the same options:
// the same positions, normals and colours, bit for bit, and the same notes.
//
// What stays in memory: PLY (ascii, binary little and big endian), delimited
// text (xyz, txt, asc, pwn, csv) and LAS are read straight from the
// memory-mapped file, and the pages behind the reader are given back as it
// goes (madvise MADV_DONTNEED), so the resident memory is one chunk and a
// few megabytes of the file (the kernel maps a file's pages in blocks of up
// to 2 MiB), however large the file is (StreamedCloud::streamed): with
// chunks of 65536 points, binary PLY files of 36 MB and of 360 MB each grew
// it by about 6 MiB. Every other format (pts, obj, off, pcd) is read
// whole by read_points and then handed out in chunks; so is a pipe or a
// device, which read_points holds whole anyway (streamed is false).
//
// Decisions the whole file makes. A few rules of the readers look at every
// value of a file before they say what a value means: what the columns of
// a text file without a header hold (normals or colours) and whether its
// colours are 0-255 or fractions, also with a header or --columns naming
// r g b; whether PLY colours of a floating-point type are 0-1 or 0-255;
// whether LAS's 16-bit colours are 0-255 or 0-65535. To give each chunk the
// meaning read_points gives the whole, such a file is read twice: a first
// pass reads it through and decides, keeping no points, and a second hands
// the chunks out. (LAS reads only the colour fields in its first pass; a
// text file with 3 or 4 columns, named columns without colours, or a PLY
// file without floating-point colours is read once.)
//
// Errors are those of read_points, with the same messages ("FILE:LINE: ..."
// in text, "FILE: byte N: ..." in binary data), but one may come after some
// chunks were handed out, since a reader finds a problem only where it
// stands; a file read twice throws in its first pass, before any chunk.
// Points with a coordinate that is not finite or beyond +-max_coordinate are
// refused after the last chunk, in one message counting them, as
// read_points refuses them; with ReadPointsOptions::skip_invalid they are
// left out of the chunks instead (a chunk may then hold fewer points, and a
// chunk left empty is not handed out), and "FILE: no points: every point is
// invalid (...)" comes at the end when none was left. Whatever `take` throws
// ends the reading and goes to the caller.

#include "recon/core/point_cloud.h"
#include "recon/io/point_io.h"

#include <cstddef>
#include <filesystem>
#include <functional>

namespace recon::io {

struct PointChunkOptions {
  std::size_t chunk_points = std::size_t{1} << 20;  ///< at most this many points per call of `take`
  ReadPointsOptions read{};                         ///< format, columns, skip_invalid, as read_points takes them
};

/// What was read.
struct StreamedCloud {
  std::size_t points = 0;    ///< handed out, in all chunks
  bool has_normals = false;  ///< the chunks had normals
  bool has_colors = false;   ///< the chunks had colours
  bool streamed = true;      ///< false when the file had to be read whole (see the top of the file)
};

/// Calls take(chunk, first) for consecutive chunks of the file's points, in
/// file order; `first` is the index of the chunk's first point in the whole
/// cloud. The chunk view is valid during the call only. `notes`, when given,
/// receives what read_points would say (ReadNotes).
/// Cost: O(file size), twice for a file whose meaning the whole decides (see above); memory one chunk.
/// Throws: what read_points throws (see above for when); InvalidInputError when chunk_points is 0;
/// what `take` throws.
/// Pre: the file does not change while it is read (see file_being_read() in point_io.h).
StreamedCloud read_points_in_chunks(const std::filesystem::path& path, const PointChunkOptions& options,
                                    const std::function<void(PointCloudView chunk, std::size_t first)>& take,
                                    ReadNotes* notes = nullptr);

}  // namespace recon::io
