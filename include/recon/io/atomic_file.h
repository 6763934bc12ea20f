#pragma once
// Write-then-rename, so that an output file is either complete or absent
// (a previous version stays intact until the new one is whole).

#include <filesystem>
#include <fstream>

namespace recon::io {

class AtomicFile {
 public:
  /// Opens a temporary file next to `target` (same folder, so the final
  /// rename cannot cross file systems). Throws IoError when it cannot.
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  /// Removes the temporary file unless commit() succeeded.
  ~AtomicFile();

  std::ofstream& stream() { return out_; }
  /// The temporary file being written (removed unless committed).
  [[nodiscard]] const std::filesystem::path& temporary() const { return temporary_; }
  /// Flushes, closes and renames onto the target. Throws IoError on failure.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  std::ofstream out_;
  bool committed_ = false;
  int slot_ = -1;  // in the registry of pending temporaries, or -1
};

/// Removes the temporary files of every AtomicFile not yet committed or
/// destroyed. Async-signal-safe (it only reads lock-free flags and calls
/// unlink): a SIGINT handler calls it before the program ends, so an
/// interrupted run leaves no partial file behind (the previous output,
/// never touched before commit(), stays as it was).
void remove_pending_temporaries() noexcept;

}  // namespace recon::io
