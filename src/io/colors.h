#pragma once
// Colours in files, shared by the formats that carry them (ply_read.cpp, ply_write.cpp,
// obj.cpp, off.cpp, xyz.cpp): how a stored value becomes 0 to 255, and the
// text forms written.
//
// The rule, by the type a channel is stored as:
//   - 8-bit integers (PLY uchar, char): as they are;
//   - 16-bit integers (ushort, short): scaled from 0-65535, v / 257 rounded
//     (65535 / 255 = 257, so 65535 is 255 and 257 is 1);
//   - wider integers (int, uint, ...): as they are (writers that store 0-255
//     in an int);
//   - floating point (PLY float and double, OBJ's "v x y z r g b"): 0-1
//     scaled by 255 and rounded, the convention of MeshLab and Open3D; but
//     when some value of the file exceeds 1, the file's floating-point
//     colours are taken as 0-255 (some exporters write those), since a
//     colour in 0-1 never exceeds 1;
// then clamped to 0-255 (a negative value is 0), and NaN is 0. When any of
// a file's three channels is floating point, all three follow the
// floating-point rule.

#include "io_detail.h"

#include "recon/core/point_cloud.h"

#include <array>
#include <string>
#include <vector>

namespace recon::io::detail {

/// Collects the colours of a file's points as they are read, and turns
/// them into 0-255 by the rule above once all are read (the floating-point
/// rule looks at every value first).
class ColorReader {
 public:
  /// The types the red, green and blue channels are stored as.
  explicit ColorReader(const std::array<ScalarType, 3>& types);

  void reserve(std::size_t points);
  void add(double red, double green, double blue);
  /// The colours, one per add() since the last take(), in order; the reader
  /// is empty after (a file read in parts takes each part's colours).
  [[nodiscard]] std::vector<Color> take();

  /// True when the conversion waits on the whole file (a channel is
  /// floating point: see beyond_one()).
  [[nodiscard]] bool floating() const { return floating_; }
  /// True when some floating-point value read so far exceeds 1.
  [[nodiscard]] bool beyond_one() const { return beyond_one_; }
  /// For a file read in parts: beyond_one() of the whole file, found by a
  /// survey of it, so that take() converts every part as it would the whole.
  void assume_beyond_one(bool beyond_one) { beyond_one_ = beyond_one; }

 private:
  std::array<ScalarType, 3> types_;
  bool floating_ = false;                     ///< some channel is floating point
  bool beyond_one_ = false;                   ///< a floating-point value above 1 was read
  std::vector<Color> colors_;                 ///< integer channels: converted at once
  std::vector<std::array<float, 3>> floats_;  ///< floating point: as read, clamped to 0-255
};

/// Appends "r g b", each 0 to 255 (PLY ascii, xyz, OFF).
void append_color_bytes(std::string& out, const Color& color);
/// Appends "r g b", each in [0, 1] with at most 4 decimals, which read back
/// as the same 0-255 value (OBJ).
void append_color_unit(std::string& out, const Color& color);

}  // namespace recon::io::detail
