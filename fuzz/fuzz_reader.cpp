// A libFuzzer target for one of recon's readers, chosen at compile time by
// READER ("ply_points", "obj_mesh", ...; see CMakeLists.txt).
//
// The reader gets the bytes as the whole content of a file, exactly as
// read_points / read_mesh hand it a memory map. A recon::Error is the right
// answer to a bad file; another exception escapes and libFuzzer reports it
// as a crash, like a sanitizer report, a leak or a timeout.

#include "readers.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const recon::fuzz::Reader read = recon::fuzz::reader_named(READER);
  if (read == nullptr) std::abort();  // a misspelt READER in CMakeLists.txt
  // The readers are never called with an empty file (read_points refuses it first).
  if (size == 0) return 0;
  read(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
