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
  /// Flushes, closes and renames onto the target. Throws IoError on failure.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace recon::io
