#include "recon/io/atomic_file.h"

#include "recon/errors.h"

#include <atomic>
#include <cstring>
#include <string>
#include <system_error>

#include <unistd.h>

namespace recon::io {
namespace {
std::atomic<unsigned> counter{0};
}

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  std::filesystem::path folder = target_.parent_path();
  if (folder.empty()) folder = ".";
  if (std::error_code ec; !std::filesystem::is_directory(folder, ec))
    throw IoError(target_.string() + ": cannot write: folder '" + folder.string() + "' does not exist");
  // Built by appending: GCC 12 at -O3 warns falsely (-Wrestrict) on a chain of '+'.
  std::string name = ".";
  name += target_.filename().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  temporary_ = folder / name;
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) throw IoError(target_.string() + ": cannot write in '" + folder.string() + "': " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
}

void AtomicFile::commit() {
  out_.flush();
  const bool written = static_cast<bool>(out_);
  out_.close();
  if (!written || out_.fail()) throw IoError(target_.string() + ": write failed (disk full?)");
  std::error_code ec;
  std::filesystem::rename(temporary_, target_, ec);
  if (ec) throw IoError(target_.string() + ": cannot rename the finished output into place: " + ec.message());
  committed_ = true;
}

}  // namespace recon::io
