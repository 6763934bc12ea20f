#include "recon/io/atomic_file.h"

#include "recon/errors.h"

#include <atomic>
#include <cstring>
#include <string>
#include <system_error>
#include <utility>

#include <unistd.h>

namespace recon::io {
namespace {
std::atomic<unsigned> counter{0};

// The temporaries in progress, for remove_pending_temporaries(): fixed
// storage, so that a signal handler can read it without allocating or
// locking. A slot's path is written before its flag is set and is not
// touched again until the flag is cleared.
constexpr int max_pending = 16;
constexpr std::size_t max_path = 4096;
struct PendingTemporary {
  std::atomic<bool> claimed{false};  // owned by an AtomicFile
  std::atomic<bool> active{false};   // path is complete and the file may exist
  char path[max_path] = {};
};
static_assert(std::atomic<bool>::is_always_lock_free);
PendingTemporary pending[max_pending];

int register_temporary(const std::filesystem::path& path) {
  const std::string& text = path.native();
  if (text.size() >= max_path) return -1;  // not cleaned on a signal; still removed by the destructor
  for (int i = 0; i < max_pending; ++i) {
    if (pending[i].claimed.exchange(true)) continue;
    std::memcpy(pending[i].path, text.c_str(), text.size() + 1);
    pending[i].active.store(true);
    return i;
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot < 0) return;
  pending[slot].active.store(false);
  pending[slot].claimed.store(false);
}
}  // namespace

void remove_pending_temporaries() noexcept {
  for (PendingTemporary& p : pending)
    if (p.active.load()) ::unlink(p.path);
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
  slot_ = register_temporary(temporary_);  // before the file exists: a signal then finds it
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    const int error = errno;
    unregister_temporary(std::exchange(slot_, -1));
    throw IoError(target_.string() + ": cannot write in '" + folder.string() + "': " + std::strerror(error), error);
  }
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
  unregister_temporary(slot_);
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
  unregister_temporary(slot_);
}

}  // namespace recon::io
