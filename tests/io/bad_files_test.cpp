// Bad input files, format by format: each must be refused with one
// ParseError (or IoError) that names the file, the line or byte, and what
// was wrong, and nothing may cost more than the part of the file it looks at.
//
// The table of each format holds the cases no other test covers. Already
// covered elsewhere: an empty file, a folder and a missing file
// (PointIoErrors.*, point_io_test.cpp); PLY's header errors (wrong magic
// word, unknown property type, list property on the vertex element, ...),
// an ASCII body shorter than its header promises, text where numbers belong,
// truncated binary bodies and huge header counts (ply_test.cpp); the other
// formats' malformed lines (PointIo<Format>.Errors, point_io_test.cpp); the
// mesh readers' face errors (MeshIo.Errors).

#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"
#include "recon/core/resource_usage.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

constexpr std::size_t max_line = std::size_t{1} << 20;  // the readers' limit, 1 MiB

/// One bad file: its content, where the message must say the problem is
/// (":LINE: ", ": byte N: " or ": " for the file as a whole, right after
/// the file name) and a phrase that says what was wrong.
struct BadFile {
  std::string content;
  std::string where;
  std::string what;
};

/// Writes each case as `name` in a fresh folder and checks the message of
/// the ParseError that reading it as a point cloud throws.
void expect_refused(const char* name, const std::vector<BadFile>& cases) {
  TempFolder folder;
  const std::filesystem::path path = folder / name;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const BadFile& c = cases[i];
    write_file(path, c.content);
    const std::string message = point_read_error(path);
    EXPECT_TRUE(message.starts_with(path.string() + c.where))
        << "case " << i << ": '" << message << "' does not start with the file and '" << c.where << "'";
    EXPECT_CONTAINS(message, c.what) << " (case " << i << ")";
  }
}

/// Cases every text-based format shares, after a valid first line.
std::vector<BadFile> common_cases(const std::string& first_line) {
  return {
      // A line too long to be a line of numbers: refused at the limit, not at the end of the file.
      {first_line + std::string(max_line + 1, '7') + "\n1 2 3\n", ":2: ", "line 2 is longer than 1048576 bytes"},
      // The same without any line end: the file ends inside the long line.
      {first_line + std::string(3 * max_line, ' '), ":2: ", "line 2 is longer than 1048576 bytes"},
      // A binary file (an executable's first bytes) given as text.
      {first_line + std::string("\x7f"
                                "ELF\x02\x01\x01\0\0\0\0",
                                11),
       ":2: ", "a NUL byte at column 8"},
  };
}

const std::string ply_ascii_header =
    "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar red\nend_header\n";  // the body starts on line 9

TEST(BadFiles, Ply) {
  std::vector<BadFile> cases = common_cases("ply\n");
  const std::string binary_header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n";
  cases.insert(
      cases.end(),
      {
          // The header only: the body is missing.
          {ply_ascii_header, ":8: ", "the file ends inside vertex 0 (counting from 0), but the header promises 2"},
          {binary_header, ": byte " + std::to_string(binary_header.size()) + ": ",
           "the file ends inside vertex 0 (counting from 0), but the header promises 2"},
          // Numbers too large for the property's type.
          {ply_ascii_header + "1 2 3 255\n1 2 3 256\n",
           ":10: ", "'256' for red does not fit its type uint8 (0 to 255)"},
          {ply_ascii_header + "1 2 3 -1\n", ":9: ", "'-1' for red does not fit its type uint8"},
          {ply_ascii_header + "1 2 4e38 0\n", ":9: ", "'4e38' for z does not fit its type float32"},
          // A long line in the body, where values may wrap across lines.
          {ply_ascii_header + "1 2 3 4\n" + std::string(max_line + 1, ' ') + "5\n",
           ":10: ", "line 10 is longer than 1048576 bytes"},
          {ply_ascii_header + "1 2 3 4\n1 2 3" + std::string(max_line, '0') + "\n",
           ":10: ", "line 10 is longer than 1048576 bytes"},
          {ply_ascii_header + "1 2 3 4\n" + std::string("1 2\0 3 4\n", 9), ":10: ", "a NUL byte at column 4"},
      });
  expect_refused("bad.ply", cases);
}

TEST(BadFiles, Xyz) {
  std::vector<BadFile> cases = common_cases("1 2 3\n");
  cases.push_back({"1 2 3\n1 2 3e400\n", ":2: ", "'3e400' for z is too large for a double"});
  expect_refused("bad.xyz", cases);
}

TEST(BadFiles, Pts) {
  std::vector<BadFile> cases = common_cases("p 1 2 3\n");
  cases.push_back({"p 1 2 3\np -1e309 2 3\n", ":2: ", "'-1e309' for x is too large for a double"});
  expect_refused("bad.pts", cases);
}

TEST(BadFiles, Obj) {
  std::vector<BadFile> cases = common_cases("v 1 2 3\n");
  cases.insert(cases.end(),
               {
                   // OBJ skips statements it does not know; bytes that cannot begin a statement end the reading.
                   {"v 1 2 3\n\x89PNG\r\n", ":2: ", "expected an OBJ statement (v, vn, f, ...), found '?PNG'"},
                   {"v 1 2 3\nv 1e999 0 0\n", ":2: ", "'1e999' for x is too large for a double"},
               });
  expect_refused("bad.obj", cases);
}

TEST(BadFiles, Off) {
  std::vector<BadFile> cases = common_cases("OFF\n");
  cases.insert(cases.end(), {
                                // The header only, and a header that promises more vertices than there are.
                                {"OFF\n3 1 0\n", ":2: ", "the file ends after 0 vertices; the header promises 3"},
                                {"OFF\n# c\n1000000000000 0 0\n0 0 0\n",
                                 ":4: ", "the file ends after 1 vertices; the header promises 1000000000000"},
                                {"OFF\n1 0 0\n0 0 1e999\n", ":3: ", "'1e999' for z is too large for a double"},
                            });
  expect_refused("bad.off", cases);
}

TEST(BadFiles, Pcd) {
  std::vector<BadFile> cases = common_cases("FIELDS x y z\n");
  const std::string header = "FIELDS x y z i\nSIZE 4 4 4 1\nTYPE F F F U\nPOINTS 2\n";
  const std::string binary = header + "DATA binary\n";
  cases.insert(
      cases.end(),
      {
          // The header only.
          {header + "DATA ascii\n", ":5: ", "the file ends after 0 points; the header promises 2"},
          {binary, ": byte " + std::to_string(binary.size()) + ": ", "the header promises 2 points of 13 bytes"},
          // Numbers too large for the field's type.
          {header + "DATA ascii\n1 2 3 4\n1 2 3 256\n", ":7: ", "'256' in column 4 does not fit its type uint8"},
          {header + "DATA ascii\n1 2 5e38 4\n", ":6: ", "'5e38' in column 3 does not fit its type float32"},
          // More values a line than a line can hold: refused before anything is sized by the count.
          {"FIELDS x y z h\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1048576\nPOINTS 1\nDATA ascii\n1 2 3\n",
           ":4: ", "the fields add up to 1048579 values a point"},
          // A wrong magic word: PCD has none, but any unknown header line is refused.
          {"ply\nformat ascii 1.0\n", ":1: ", "unexpected line in the PCD header: 'ply'"},
      });
  expect_refused("bad.pcd", cases);
}

TEST(BadFiles, MeshReadersShareTheLimits) {
  TempFolder folder;
  for (const char* name : {"m.ply", "m.obj", "m.off"}) {
    write_file(folder / name, std::string(max_line + 1, 'x'));
    const std::string message = message_of<ParseError>([&] { static_cast<void>(read_mesh(folder / name)); });
    EXPECT_TRUE(message.starts_with((folder / name).string() + ":1: line 1 is longer than 1048576 bytes")) << message;
  }
}

// --------------------------------------------------------------------------
// Coordinates that are not finite or beyond max_coordinate: every reader reads
// on, counts the points and names the first

constexpr const char* three_bad = "3 points have a coordinate that is not finite or beyond +-1e+15; the first at ";

TEST(BadCoordinates, TextFormats) {
  // Three bad points: NaN, infinity, and a value beyond 1e15, after good ones.
  const std::vector<std::pair<const char*, BadFile>> cases = {
      {"c.xyz",
       {"0 0 0\n# c\n1 nan 0\n1 1 1\n-inf 0 0\n0 0 2e15\n", ": ", std::string(three_bad) + "line 3 (y = nan)"}},
      {"c.pts",
       {"p 0 0 0\np 1 2 -1.5e15\np inf 0 0\nd 1 2 3\np 0 nan 0\n", ": ",
        std::string(three_bad) + "line 2 (z = -1.5e+15)"}},
      {"c.obj",
       {"v 0 0 0\nvt 1 1\nv 0 0 INF\nv 1e16 0 0\nv 0 NaN 0\n", ": ", std::string(three_bad) + "line 3 (z = inf)"}},
      {"c.off",
       {"OFF\n4 0 0\n0 0 0\n1 2 nan\n1e300 0 0\n0 -inf 0\n", ": ", std::string(three_bad) + "line 4 (z = nan)"}},
      {"c.ply",
       {"ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nend_header\n0 0 0 1\n1 1 nan 2\n\n2 2 2\n3\n-1e20 0 0 4\ninf 0 0 5\n",
        ": ", std::string(three_bad) + "line 10 (z = nan)"}},
      {"c.pcd",
       {"FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nPOINTS 5\nDATA ascii\n0 0 0\nnan nan nan\n1 nan 1\n"
        "inf 1 1\n1 1 -2e15\n",
        ": ", std::string(three_bad) + "line 8 (y = nan)"}},
  };
  for (const auto& [name, c] : cases) expect_refused(name, {c});
}

TEST(BadCoordinates, ExactlyTheBoundIsAccepted) {
  TempFolder folder;
  write_file(folder / "b.xyz", "1e15 -1e15 0\n1 2 3\n");
  EXPECT_EQ(read_points(folder / "b.xyz").positions[0], Vec3(1e15, -1e15, 0));
}

TEST(BadCoordinates, NormalsThatAreNotFinite) {
  // Named normals only need to be finite (their length does not matter); a
  // bad position and a bad normal are both reported. Without a header, the
  // last three of six columns are normals when they are unit vectors on
  // every line, a NaN one counting as a bad normal, not against the rule.
  const std::vector<std::pair<const char*, BadFile>> cases = {
      {"n.xyz",
       {"x y z nx ny nz\n0 0 0 0 0 1\n1 1 1 nan 0 1\n2 2 2 0 1e300 0\n", ": ",
        "1 point has a normal that is not finite (NaN or infinity); the first at line 3 (nx = nan)"}},
      {"u.xyz",
       {"0 0 0 0 0 1\n1 1 1 nan 0 1\n2 2 2 0 -1 0\n", ": ",
        "1 point has a normal that is not finite (NaN or infinity); the first at line 2 (nx = nan)"}},
      {"n.off",
       {"NOFF\n2 0 0\n0 0 0 0 0 1\n1 1 1 0 -inf 0\n", ": ",
        "1 point has a normal that is not finite (NaN or infinity); the first at line 4 (ny = -inf)"}},
      {"n.obj",
       {"v 0 0 0\nv 1 1 nan\nvn 0 0 1\nvn 0 0 nan\n", ": ",
        "1 point has a coordinate that is not finite or beyond +-1e+15; the first at line 2 (z = nan); and "
        "1 point has a normal that is not finite (NaN or infinity); the first at line 4 (nz = nan)"}},
  };
  for (const auto& [name, c] : cases) expect_refused(name, {c});
}

TEST(BadCoordinates, BinaryFormatsNameTheByte) {
  TempFolder folder;
  for (const bool big : {false, true}) {
    Bytes bytes(big);
    bytes.ply_header(
        "element vertex 4\nproperty double x\nproperty float y\nproperty double z\n"
        "property float nx\nproperty float ny\nproperty float nz\n");
    const std::size_t body = bytes.size();  // records of 32 bytes: x at 0, y at 8, z at 12, normal at 20
    bytes.put(1.0).put(2.0F).put(3.0).put(0.0F).put(0.0F).put(1.0F);
    bytes.put(1.0).put(std::numeric_limits<float>::signaling_NaN()).put(3.0).put(0.0F).put(0.0F).put(1.0F);
    bytes.put(1.0).put(2.0F).put(-3e15).put(0.0F).put(std::numeric_limits<float>::infinity()).put(1.0F);
    bytes.put(-std::numeric_limits<double>::infinity()).put(2.0F).put(3.0).put(0.0F).put(0.0F).put(1.0F);
    write_file(folder / "b.ply", bytes.str());
    const std::string message = point_read_error(folder / "b.ply");
    EXPECT_EQ(message, (folder / "b.ply").string() + ": " + three_bad + "byte " + std::to_string(body + 32 + 8) +
                           " (y = nan); and 1 point has a normal that is not finite (NaN or infinity); the first at "
                           "byte " +
                           std::to_string(body + 64 + 24) + " (ny = inf)");
  }

  // PCD: the all-NaN point is "no measurement" and skipped; the others are counted.
  Bytes pcd;
  pcd.text("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 4\nDATA binary\n");
  const std::size_t data = pcd.size();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  pcd.put(1.0F).put(2.0F).put(3.0F);
  pcd.put(nan).put(nan).put(nan);
  pcd.put(1.0F).put(std::numeric_limits<float>::infinity()).put(3.0F);
  pcd.put(1.0F).put(2.0F).put(nan);
  write_file(folder / "b.pcd", pcd.str());
  EXPECT_EQ(point_read_error(folder / "b.pcd"),
            (folder / "b.pcd").string() +
                ": 2 points have a coordinate that is not finite or beyond +-1e+15; the first "
                "at byte " +
                std::to_string(data + 24 + 4) + " (y = inf)");
}

// --------------------------------------------------------------------------
// The limits never touch a valid file

TEST(BadFiles, ALineOfExactlyTheLimitIsRead) {
  TempFolder folder;
  // A comment that makes line 2 exactly 1 MiB long, and a last line of exactly 1 MiB without a line end.
  const std::string comment = "# " + std::string(max_line - 2, 'c');
  const std::string last = "4 5 6" + std::string(max_line - 5, ' ');
  write_file(folder / "long.xyz", "1 2 3\n" + comment + "\n" + last);
  const PointCloud cloud = read_points(folder / "long.xyz");
  ASSERT_EQ(cloud.size(), 2U);
  EXPECT_EQ(cloud.positions[1], Vec3(4, 5, 6));

  // ASCII PLY: the line limit counts from each line end, not across the body.
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 100000\nproperty double x\nproperty double y\n"
      "property double z\nend_header\n";
  for (int i = 0; i < 100000; ++i) ply += "0.125 -2.5 1234.5\n";  // 1.8 MB of body
  write_file(folder / "big.ply", ply);
  EXPECT_EQ(read_points(folder / "big.ply").size(), 100000U);
}

// --------------------------------------------------------------------------
// Files that cannot be read

TEST(BadFiles, UnreadableFile) {
  TempFolder folder;
  if (::geteuid() != 0) {
    write_file(folder / "locked.xyz", "1 2 3\n");
    std::filesystem::permissions(folder / "locked.xyz", std::filesystem::perms::none);
    const std::string message = message_of<IoError>([&] { static_cast<void>(read_points(folder / "locked.xyz")); });
    EXPECT_TRUE(message.starts_with((folder / "locked.xyz").string() + ": cannot open: Permission denied")) << message;
  } else {
    // As root, permissions do not stop reading; a file whose read() fails does: /proc/self/mem at
    // offset 0, an address no process maps. It opens, then the first read fails with EIO.
    std::cout << "[ NOTE     ] running as root: chmod 000 would not stop reading; /proc/self/mem stands in\n";
    const std::string message = message_of<IoError>(
        [&] { static_cast<void>(read_points("/proc/self/mem", testing::as_format(PointFormat::xyz))); });
    EXPECT_TRUE(message.starts_with("/proc/self/mem: cannot read: ")) << message;
  }
}

TEST(BadFiles, PipeIsReadWithoutAMap) {
  TempFolder folder;
  const std::filesystem::path fifo = folder / "points.xyz";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { write_file(fifo, "1 2 3\n4 5 6\n"); });
  const PointCloud cloud = read_points(fifo);
  writer.join();
  ASSERT_EQ(cloud.size(), 2U);
  EXPECT_EQ(cloud.positions[1], Vec3(4, 5, 6));
}

TEST(BadFiles, AStreamBeyondItsLimitIsRefused) {
  // /dev/zero never ends: a stream is held whole in memory, so it must stop
  // at the limit (by default half the machine's memory) with a message.
  const std::string message = message_of<IoError>(
      [&] { static_cast<void>(read_points("/dev/zero", testing::as_format(PointFormat::xyz, 3 << 20))); });
  EXPECT_TRUE(message.starts_with("/dev/zero: more than 3145728 bytes from a stream")) << message;
  EXPECT_CONTAINS(message, "save it to a file first");
  // Within the limit, a pipe reads as before.
  TempFolder folder;
  const std::filesystem::path fifo = folder / "points.xyz";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { write_file(fifo, "1 2 3\n4 5 6\n"); });
  const PointCloud cloud = read_points(fifo, testing::as_format(PointFormat::automatic, 12));
  writer.join();
  EXPECT_EQ(cloud.size(), 2U);
}

// file_being_read() names a mapped input only while a reader works on it
// (the program's SIGBUS handler relies on it; CliErrors.AnInputShortened
// WhileReadIsNamed sees the name in the middle of a read): before and after
// a read, and after a read that failed, it is empty.
TEST(BadFiles, NoFileIsBeingReadBeforeOrAfterAReader) {
  TempFolder folder;
  write_file(folder / "points.xyz", "1 2 3\n4 5 6\n");
  write_file(folder / "bad.xyz", "1 2 3\nx\n");
  EXPECT_STREQ(file_being_read(), "");
  static_cast<void>(read_points(folder / "points.xyz"));
  EXPECT_STREQ(file_being_read(), "");
  static_cast<void>(message_of<ParseError>([&] { static_cast<void>(read_points(folder / "bad.xyz")); }));
  EXPECT_STREQ(file_being_read(), "");
}

// --------------------------------------------------------------------------
// Several gigabytes of garbage

/// A sparse file of `size` bytes that starts with `start` (the rest reads as
/// zeros and takes no disk space).
void make_sparse_file(const std::filesystem::path& path, const std::string& start, std::uint64_t size) {
  write_file(path, start);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::ftruncate(fd, static_cast<off_t>(size)), 0);
  ::close(fd);
}

TEST(BadFiles, GigabytesOfGarbageAreRefusedAfterTheFirstPages) {
  constexpr std::uint64_t size = std::uint64_t{4} << 30;  // 4 GiB
  TempFolder folder;
  // Seeded random bytes with no line end and no NUL, then zeros to 4 GiB: the first line never ends.
  std::mt19937 random(2026);
  std::uniform_int_distribution<int> byte(1, 255);
  std::string garbage;
  while (garbage.size() < 65536) {
    const char c = static_cast<char>(byte(random));
    if (c != '\n') garbage += c;
  }
  const std::string binary_ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n";

  struct Case {
    const char* name;
    std::string start;
    std::string where;
    std::string what;
  };
  const Case cases[] = {
      {"g.ply", garbage, ":1: ", "line 1 is longer than 1048576 bytes"},
      {"g.xyz", garbage, ":1: ", "line 1 is longer than 1048576 bytes"},
      {"g.pts", garbage, ":1: ", "line 1 is longer than 1048576 bytes"},
      {"g.obj", garbage, ":1: ", "line 1 is longer than 1048576 bytes"},
      {"g.off", garbage, ":1: ", "line 1 is longer than 1048576 bytes"},
      {"g.pcd", garbage, ":1: ", "line 1 is longer than 1048576 bytes"},
      // A valid binary header whose count the 4 GiB of zeros cannot hold (12 GB are promised).
      {"h.ply", binary_ply, ": byte ", "but the header promises 1000000000 'vertex' elements"},
  };
  const bool peak_resettable = reset_peak_resident();
  if (!peak_resettable) std::cout << "[ NOTE     ] the peak resident size cannot be reset here; only time is checked\n";
  for (const Case& c : cases) {
    const std::filesystem::path path = folder / c.name;
    make_sparse_file(path, c.start, size);
    ASSERT_EQ(std::filesystem::file_size(path), size);
    static_cast<void>(reset_peak_resident());
    const std::size_t before = resident_bytes().value_or(0);
    const auto start = std::chrono::steady_clock::now();
    const std::string message = point_read_error(path);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(message.starts_with(path.string() + c.where)) << message;
    EXPECT_CONTAINS(message, c.what);
    // Reading 4 GiB would take seconds and 4 GiB of resident pages; the first pages take milliseconds.
    EXPECT_LT(seconds, 1.0) << c.name;
    if (peak_resettable) {
      const std::size_t peak = peak_resident_bytes().value_or(0);
      EXPECT_LT(peak, before + (std::size_t{16} << 20))
          << c.name << ": the peak grew by " << (peak - before) << " bytes";
    }
    std::filesystem::remove(path);
  }
}

}  // namespace
}  // namespace recon::io

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

TEST(BadFiles, AStreamHoldsNoMoreThanItsBytesAndAPage) {
  // The limit on a stream is a limit on memory: the buffer must not grow
  // past it (a doubling buffer held up to twice the bytes read, 16 GiB for
  // /dev/zero against a cap of 12).
  TempFolder folder;
  const std::filesystem::path fifo = folder / "points.xyz";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::size_t size = (std::size_t{3} << 20) + 5;  // past a doubling from 1 or 2 MiB
  const std::string content(size, ' ');
  std::thread writer([&] { write_file(fifo, content); });
  const PointSource source(fifo, size);
  writer.join();
  EXPECT_EQ(source.bytes().size(), size);
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGE_SIZE));
  EXPECT_LE(source.held_bytes(), (size / page + 1) * page);
  EXPECT_GE(source.held_bytes(), size);
}

TEST(BadFiles, DevZeroIsRefusedAtTheLimitQuickly) {
  // 64 MiB of /dev/zero: refused as the bytes come, in well under a second.
  const auto start = std::chrono::steady_clock::now();
  const std::string message = testing::message_of<IoError>([&] {
    static_cast<void>(read_points("/dev/zero", testing::as_format(PointFormat::xyz, std::size_t{64} << 20)));
  });
  EXPECT_TRUE(message.starts_with("/dev/zero: more than 67108864 bytes from a stream")) << message;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
}

}  // namespace
}  // namespace recon::io
