// A tiled run's folder (TileWorkspace, tiles.h): made exclusively, locked
// for the run, removed after it, also from a signal handler; and the
// folders of runs that died without removing theirs (SIGKILL, a power
// cut), removed by the next run in the same parent.
//
// The lock is flock(2) on a file inside the folder, held by an open file
// descriptor for the workspace's life: the kernel drops it when the process
// ends, however it ends, so a folder whose lock can be taken belongs to no
// live run. Process ids are not used: two containers sharing a --tmpdir
// may run recon under the same pid.
#include "recon/tiles/tiles.h"

#include "recon/core/errors.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <string_view>

namespace recon {

namespace {

constexpr std::string_view workspace_prefix = "recon-tiles-";
constexpr const char* lock_name = "recon-tiles.lock";

// The workspaces alive, for remove_tile_workspaces (a signal handler): fixed
// buffers and lock-free flags only. A slot is claimed, then its path
// written, then marked active; the handler reads active slots only.
constexpr int max_workspaces = 16;
struct Registered {
  std::atomic<bool> claimed{false};
  std::atomic<bool> active{false};
  char path[max_workspace_path + 1] = {};
};
static_assert(std::atomic<bool>::is_always_lock_free);
Registered workspaces[max_workspaces];

int register_workspace(const std::string& path) {
  for (int slot = 0; slot < max_workspaces; ++slot) {
    if (workspaces[slot].claimed.exchange(true)) continue;
    std::memcpy(workspaces[slot].path, path.c_str(), path.size() + 1);
    workspaces[slot].active.store(true);
    return slot;
  }
  return -1;  // (more than 16 at once: not cleaned on a signal; the next run removes it as stale)
}

void unregister_workspace(int slot) {
  if (slot < 0) return;
  workspaces[slot].active.store(false);
  workspaces[slot].claimed.store(false);
}

// Every entry of `dir` (a workspace holds plain files only, whatever their
// names: tiles, temporaries, the lock), then `dir` itself. Other threads
// may still be committing files into it (a tile step does not stop for a
// signal), so it goes round again while rmdir finds the folder not empty;
// once the folder is gone, they cannot add to it. Async-signal-safe.
void remove_workspace_files(const char* dir) noexcept {
  const int saved_errno = errno;
  for (int round = 0; round < 10000; ++round) {
    const int fd = ::open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0) break;
    alignas(dirent64) char buffer[8192];
    for (ssize_t bytes; (bytes = ::getdents64(fd, buffer, sizeof buffer)) > 0;)
      for (ssize_t at = 0; at < bytes;) {
        const auto* entry = reinterpret_cast<const dirent64*>(buffer + at);
        at += entry->d_reclen;
        const char* name = entry->d_name;
        if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0) ::unlinkat(fd, name, 0);
      }
    ::close(fd);
    if (::rmdir(dir) == 0 || errno != ENOTEMPTY) break;
  }
  errno = saved_errno;
}

// The lock file is made under another name, locked, and only then renamed
// to lock_name: a cleaner that finds lock_name in a live run's folder
// always finds it locked. Returns the descriptor that holds the lock. On a
// file system without flock (some network and FUSE ones) the folder goes
// unlocked: no cleaner can take its lock either, so none removes it.
bool without_locks(int error) { return error == ENOLCK || error == EOPNOTSUPP || error == ENOSYS; }

int lock_workspace(const std::filesystem::path& dir) {
  const std::filesystem::path fresh = dir / ".recon-tiles.lock-new", lock = dir / lock_name;
  const int fd = ::open(fresh.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) throw IoError(fresh.string() + ": cannot create the tiles' lock file: " + std::strerror(errno), errno);
  if ((::flock(fd, LOCK_EX | LOCK_NB) != 0 && !without_locks(errno)) || ::rename(fresh.c_str(), lock.c_str()) != 0) {
    const int error = errno;
    ::close(fd);
    throw IoError(lock.string() + ": cannot lock the tiles' folder: " + std::strerror(error), error);
  }
  return fd;
}

// Whether `dir` is a workspace no live run holds: a real folder (not a
// link) named like one, with a lock file whose lock can be taken. Then it
// is removed, the lock held meanwhile.
bool remove_if_stale(const std::filesystem::directory_entry& entry) {
  std::error_code error;
  if (!entry.path().filename().string().starts_with(workspace_prefix) || !entry.is_directory(error) ||
      entry.is_symlink(error))
    return false;
  const std::filesystem::path lock = entry.path() / lock_name;
  if (!std::filesystem::is_regular_file(std::filesystem::symlink_status(lock, error))) return false;
  const int fd = ::open(lock.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return false;
  const bool stale = ::flock(fd, LOCK_EX | LOCK_NB) == 0;
  if (stale) std::filesystem::remove_all(entry.path(), error);
  ::close(fd);
  return stale && !error;
}

}  // namespace

std::size_t remove_stale_tile_workspaces(const std::filesystem::path& parent) noexcept {
  std::size_t removed = 0;
  try {
    std::error_code error;
    std::filesystem::directory_iterator it(parent, std::filesystem::directory_options::skip_permission_denied, error);
    for (; !error && it != std::filesystem::directory_iterator(); it.increment(error))
      if (remove_if_stale(*it)) ++removed;
  } catch (const std::exception&) {  // (bad_alloc: a clean-up is no reason to fail the run)
  }
  return removed;
}

void remove_tile_workspaces() noexcept {
  for (Registered& w : workspaces)
    if (w.active.load()) remove_workspace_files(w.path);
}

TileWorkspace::TileWorkspace(const std::filesystem::path& parent) {
  std::string pattern = (parent / (std::string(workspace_prefix) + "XXXXXX")).string();
  if (pattern.size() > max_workspace_path)
    throw InvalidInputError(parent.string().substr(0, 60) +
                            "...: the folder for a tiled run's files must have a path of at most " +
                            std::to_string(max_workspace_path - workspace_prefix.size() - 7) +
                            " characters (this one has " + std::to_string(parent.string().size()) + ")");
  remove_stale_tile_workspaces(parent);
  if (::mkdtemp(pattern.data()) == nullptr)
    throw IoError(parent.string() + ": cannot create a folder for the tiles there: " + std::strerror(errno), errno);
  path_ = pattern;
  slot_ = register_workspace(pattern);
  try {
    lock_ = lock_workspace(path_);
  } catch (...) {
    unregister_workspace(slot_);
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
    throw;
  }
}

TileWorkspace::~TileWorkspace() {
  unregister_workspace(slot_);
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
  ::close(lock_);  // (after the removal: a cleaner meanwhile finds the lock taken)
}

}  // namespace recon
