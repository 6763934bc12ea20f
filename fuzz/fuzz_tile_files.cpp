// A libFuzzer target for the readers of a tiled run's files (tiles/files.h):
// the plan, a tile's points and colours, its orientation, the
// reconciliation's signs, a tile's mesh. A recon::Error is the right answer
// to a bad file; a crash, a sanitizer report, a leak or another exception
// is a finding.
//
// The first byte picks the kind of file (its value modulo 6). The second
// picks how the rest becomes the file: as it is (bit 0 clear: the
// checksum's check is what is fuzzed, and nearly every input stops there),
// or sealed (bit 0 set: the kind's magic, the rest, and a trailer whose
// checksum matches, so that the fuzzer reaches the checks past it: every
// count, index and coordinate). The readers read files, so the bytes go to
// a file in a folder of this process's own.

#include "recon/core/errors.h"
#include "tiles/binary_file.h"
#include "tiles/files.h"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace {

namespace fs = std::filesystem;
namespace tf = recon::tile_files;

const fs::path& folder() {
  static const fs::path dir = [] {
    std::string pattern = (fs::temp_directory_path() / "recon-fuzz-tiles-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) std::abort();
    return fs::path(pattern);
  }();
  return dir;
}

struct Kind {
  const char* file;
  const char* magic;
  void (*read)(const fs::path& dir, const fs::path& file);
};

const Kind kinds[] = {
    {"plan.bin", tf::plan_magic, [](const fs::path&, const fs::path& f) { static_cast<void>(tf::read_plan_file(f)); }},
    {"tile-000000.points", tf::points_magic,
     [](const fs::path&, const fs::path& f) { static_cast<void>(tf::read_point_records(f)); }},
    {"tile-000000.colors", tf::colors_magic,
     [](const fs::path&, const fs::path& f) { static_cast<void>(tf::read_colors(f)); }},
    {"tile-000000.orient", tf::orient_magic,
     [](const fs::path&, const fs::path& f) { static_cast<void>(tf::read_orientation(f)); }},
    {"flips.bin", tf::flips_magic, [](const fs::path& d, const fs::path&) { static_cast<void>(tf::read_flips(d)); }},
    {"tile-000000.mesh", tf::mesh_magic,
     [](const fs::path&, const fs::path& f) { static_cast<void>(tf::read_mesh(f)); }},
};

std::string sealed(const char* magic, std::string_view body) {
  std::string bytes(magic, 8);
  bytes.append(body);
  recon::detail::Checksum sum;
  sum.add(bytes.data(), bytes.size());
  const recon::detail::ChecksumTrailer trailer = sum.trailer();
  bytes.append(reinterpret_cast<const char*>(&trailer), sizeof trailer);
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const Kind& kind = kinds[data[0] % std::size(kinds)];
  const std::string_view body(reinterpret_cast<const char*>(data + 2), size - 2);
  const fs::path file = folder() / kind.file;
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (data[1] & 1) {
      out << sealed(kind.magic, body);
    } else {
      out << body;
    }
  }
  try {
    kind.read(folder(), file);
  } catch (const recon::Error&) {
  }
  return 0;
}
