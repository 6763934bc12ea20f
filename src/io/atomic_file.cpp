#include "recon/io/atomic_file.h"

#include "recon/core/errors.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
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

constexpr int max_links = 40;  // as Linux's own limit on a chain of symbolic links

/// `target` with its symbolic links followed to the last one's target (which
/// may not exist). `through_descriptor` is set when a link of the chain lies
/// under /proc (/dev/stdout -> /proc/self/fd/1 -> ...): such a link names an
/// open descriptor, not a place for a new file.
std::filesystem::path follow_links(const std::filesystem::path& target, bool& through_descriptor) {
  std::filesystem::path at = target;
  for (int hops = 0;; ++hops) {
    std::error_code ec;
    if (!std::filesystem::is_symlink(std::filesystem::symlink_status(at, ec))) return at;
    if (hops == max_links)
      throw IoError(
          target.string() + ": cannot write: more than " + std::to_string(max_links) + " symbolic links in a chain",
          ELOOP);
    const std::filesystem::path link = std::filesystem::read_symlink(at, ec);
    if (ec)
      throw IoError(target.string() + ": cannot write: cannot read the link " + at.string() + ": " + ec.message());
    if (std::filesystem::absolute(at, ec).string().starts_with("/proc/")) through_descriptor = true;
    at = link.is_absolute() ? link : at.parent_path() / link;
  }
}

[[noreturn]] void refuse(const std::filesystem::path& target, const char* what, int error) {
  throw IoError(
      target.string() + ": cannot write: it is " + what + "; recon writes regular files, FIFOs and character devices",
      error);
}

void sync_path(const std::filesystem::path& path, int flags, const std::filesystem::path& target) {
  const int fd = ::open(path.c_str(), flags | O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    throw IoError(target.string() + ": cannot sync " + path.string() + ": " + std::strerror(error), error);
  }
  const int result = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  // A folder on a file system that cannot sync one (EINVAL) is as safe as that file system makes it.
  if (result != 0 && !(error == EINVAL && (flags & O_DIRECTORY) != 0))
    throw IoError(target.string() + ": write failed (fsync: " + std::strerror(error) + ")", error);
}

}  // namespace

OutputTarget output_target(const std::filesystem::path& target) {
  struct stat status {};
  bool through_descriptor = false;
  if (::stat(target.c_str(), &status) != 0) {  // follows the links
    // Nothing there (or not reachable): a file to create, where the links lead.
    return {OutputTarget::Kind::file, follow_links(target, through_descriptor)};
  }
  if (S_ISDIR(status.st_mode)) refuse(target, "a folder", EISDIR);
  if (S_ISBLK(status.st_mode)) refuse(target, "a block device", ENOTSUP);
  if (S_ISSOCK(status.st_mode)) refuse(target, "a socket", ENOTSUP);
  if (!S_ISREG(status.st_mode)) return {OutputTarget::Kind::stream, target};  // a FIFO, a character device
  std::filesystem::path last = follow_links(target, through_descriptor);
  if (through_descriptor) return {OutputTarget::Kind::stream, target};
  return {OutputTarget::Kind::file, std::move(last)};
}

void remove_pending_temporaries() noexcept {
  for (PendingTemporary& p : pending)
    if (p.active.load()) ::unlink(p.path);
}

AtomicFile::AtomicFile(std::filesystem::path target, Use use)
    : target_(std::move(target)), scratch_(use == Use::scratch) {
  const OutputTarget where = scratch_ ? OutputTarget{OutputTarget::Kind::file, target_} : output_target(target_);
  if (where.kind == OutputTarget::Kind::stream) {
    streaming_ = true;
    temporary_ = target_;
    // Appending: a FIFO or a device has no end to truncate, and a file behind
    // a descriptor link (/dev/stdout on a shell's '>>') keeps what it held.
    // A FIFO waits here for its reader, as with '>'.
    out_.open(target_, std::ios::binary | std::ios::app);
    if (!out_) {
      const int error = errno;
      throw IoError(target_.string() + ": cannot write: " + std::strerror(error), error);
    }
    return;
  }
  bool ignored = false;
  final_ = scratch_ ? follow_links(target_, ignored) : where.path;
  std::filesystem::path folder = final_.parent_path();
  if (folder.empty()) folder = ".";
  if (std::error_code ec; !std::filesystem::is_directory(folder, ec))
    throw IoError(target_.string() + ": cannot write: folder '" + folder.string() + "' does not exist");
  open_temporary(folder);
  if (scratch_) return;
  try {
    keep_mode_and_owner();
  } catch (...) {
    discard_temporary();  // no destructor runs for a constructor that throws
    throw;
  }
}

void AtomicFile::open_temporary(const std::filesystem::path& folder) {
  // Built by appending: GCC 12 at -O3 warns falsely (-Wrestrict) on a chain of '+'.
  std::string name = ".";
  name += final_.filename().string();
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

/// The file being replaced keeps its permissions, owner and group: set on
/// the temporary before anything is written into it (so a private file's
/// new content is never readable by others). The owner can be given only
/// by a privileged user, the group only to one of the user's groups: what
/// cannot be kept is left as the temporary has it.
void AtomicFile::keep_mode_and_owner() const {
  struct stat old {};
  if (::stat(final_.c_str(), &old) != 0) return;  // a new file: the umask decides, as for any new file
  // The owner first: chown clears the set-user-ID and set-group-ID bits that chmod then restores.
  if (::chown(temporary_.c_str(), old.st_uid, old.st_gid) != 0)
    static_cast<void>(::chown(temporary_.c_str(), static_cast<uid_t>(-1), old.st_gid));
  if (::chmod(temporary_.c_str(), old.st_mode & 07777) != 0) {
    const int error = errno;
    throw IoError(target_.string() + ": cannot give the new file the old one's mode: " + std::strerror(error), error);
  }
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  if (streaming_) {
    out_.close();  // what was written to a stream stays written
    return;
  }
  discard_temporary();
}

void AtomicFile::discard_temporary() noexcept {
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
  unregister_temporary(std::exchange(slot_, -1));
}

void AtomicFile::commit() {
  if (scratch_) throw IoError(target_.string() + ": a scratch file is never committed");
  out_.flush();
  const bool written = static_cast<bool>(out_);
  out_.close();
  if (!written || out_.fail()) throw IoError(target_.string() + ": write failed (disk full?)");
  if (!streaming_) sync_and_rename();
  committed_ = true;
  unregister_temporary(slot_);
}

/// The content reaches the disk before the name does: a crash after the
/// rename can then not leave an empty or partial file under the target's
/// name (ext4 and XFS may write the rename first otherwise). The folder's
/// fsync makes the rename itself durable.
void AtomicFile::sync_and_rename() {
  sync_path(temporary_, 0, target_);
  std::error_code ec;
  std::filesystem::rename(temporary_, final_, ec);
  if (ec) throw IoError(target_.string() + ": cannot rename the finished output into place: " + ec.message());
  std::filesystem::path folder = final_.parent_path();
  if (folder.empty()) folder = ".";
  sync_path(folder, O_DIRECTORY, target_);
}

}  // namespace recon::io
