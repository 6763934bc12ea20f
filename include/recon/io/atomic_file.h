#pragma once
// Write-then-rename, so that an output file is either complete or absent
// (a previous version stays intact until the new one is whole), for every
// file recon writes: meshes, clouds, curves, --stats, --report, tile files.
//
// What a target path names decides how it is written (output_target()):
//   - a regular file, or nothing yet: a temporary file beside it, renamed
//     onto it by commit(). A symbolic link is followed to its last target
//     (as a shell's '>' does): the link stays a link and the file it names
//     is replaced, atomically; a dangling link's target is created. An
//     existing file keeps its mode and, where the user may set them, its
//     owner and group. commit() calls fsync on the file before the rename
//     and on its folder after it, so that a crash leaves the old file or
//     the new one, never an empty one.
//   - a FIFO or a character device (/dev/null, a terminal), or a regular
//     file reached through a descriptor link (/dev/stdout, /dev/fd/N,
//     /proc/self/fd/N: the shell's redirection, which may append): written
//     in place as a stream. It is never replaced, but then nothing is
//     atomic: a failed run may leave part of its output in the stream.
//   - a folder, a block device or a socket: refused (IoError).

#include <filesystem>
#include <fstream>

namespace recon::io {

/// How a target path is written (see above).
struct OutputTarget {
  enum class Kind { file, stream };
  Kind kind = Kind::file;
  /// file: the path the finished file is renamed onto (the target, or the
  /// file its symbolic links lead to); stream: the target as given.
  std::filesystem::path path;
};

/// Decides how `target` is written, looking at the file system only (it
/// opens nothing, so it can be asked of any path).
/// Cost: a stat and one readlink per symbolic link.
/// Throws: IoError "TARGET: cannot write: it is a folder" (or "a block device", "a socket"), for more than
/// 40 links in a chain, or a link that cannot be read.
/// Pre: none.
[[nodiscard]] OutputTarget output_target(const std::filesystem::path& target);

class AtomicFile {
 public:
  /// output: the target is written as output_target() says. scratch: a
  /// temporary file beside the target (beside the file its links lead to),
  /// whatever the target is, never renamed onto it: a part of an output
  /// being assembled (mesh_stream.h); commit() is refused.
  enum class Use { output, scratch };

  /// Opens a temporary file next to the target (same folder, so the final
  /// rename cannot cross file systems), or the stream itself (a FIFO waits here for its reader).
  /// Cost: O(1) system calls (and output_target's).
  /// Throws: IoError when it cannot (no such folder, not writable, the old file's mode cannot be given),
  /// or when output_target() refuses the target.
  /// Pre: none.
  explicit AtomicFile(std::filesystem::path target, Use use = Use::output);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  /// Removes the temporary file unless commit() succeeded (a stream is
  /// closed: what was written to it stays written).
  ~AtomicFile();

  std::ofstream& stream() { return out_; }
  /// The temporary file being written (removed unless committed); for a
  /// stream, the stream's path.
  [[nodiscard]] const std::filesystem::path& temporary() const { return temporary_; }
  /// Flushes, closes, syncs and renames onto the target (a stream: flushes
  /// and closes).
  /// Cost: O(bytes not yet flushed), two fsyncs and a rename.
  /// Throws: IoError when a write, sync or the rename fails, and for a scratch file.
  /// Pre: called once.
  void commit();

 private:
  void open_temporary(const std::filesystem::path& folder);
  void keep_mode_and_owner() const;
  void discard_temporary() noexcept;
  void sync_and_rename();

  std::filesystem::path target_;  // as given, for messages
  std::filesystem::path final_;   // the file renamed onto (links followed)
  std::filesystem::path temporary_;
  std::ofstream out_;
  bool streaming_ = false;
  bool scratch_ = false;
  bool committed_ = false;
  int slot_ = -1;  // in the registry of pending temporaries, or -1
};

/// Removes the temporary files of every AtomicFile not yet committed or
/// destroyed. Async-signal-safe (it only reads lock-free flags and calls
/// unlink): a SIGINT handler calls it before the program ends, so an
/// interrupted run leaves no partial file behind (the previous output,
/// never touched before commit(), stays as it was).
/// Cost: O(files pending).
/// Throws: nothing.
/// Pre: none.
void remove_pending_temporaries() noexcept;

}  // namespace recon::io
