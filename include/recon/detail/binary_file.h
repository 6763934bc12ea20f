#pragma once
// The files of a tiled run (tiles.h), not part of the API: plain records of
// trivially copyable values in the machine's byte order, written whole or
// not at all (io::AtomicFile), read back with every length checked against
// the file, so that a truncated or foreign file is an error naming it, not
// a crash.

#include "recon/errors.h"
#include "recon/io/atomic_file.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace recon::detail {

class BinaryWriter {
 public:
  /// Starts the file with `magic` (8 characters naming its kind).
  BinaryWriter(const std::filesystem::path& target, const char (&magic)[9]);

  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    write(&value, sizeof(T));
  }
  /// A length (uint64), then the values.
  template <class T>
  void put_vector(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(static_cast<std::uint64_t>(values.size()));
    write(values.data(), values.size() * sizeof(T));
  }
  /// The values alone (a file of records to its end; see get_rest).
  template <class T>
  void put_records(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    write(values.data(), values.size() * sizeof(T));
  }
  /// Renames the file into place; IoError when it cannot be written whole.
  void commit();

 private:
  void write(const void* data, std::size_t bytes);
  io::AtomicFile file_;
};

class BinaryReader {
 public:
  /// ParseError unless the file starts with `magic`; IoError when it cannot be opened.
  BinaryReader(const std::filesystem::path& path, const char (&magic)[9]);

  template <class T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    read(&value, sizeof(T));
    return value;
  }
  template <class T>
  std::vector<T> get_vector() {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto count = get<std::uint64_t>();
    check_left(count, sizeof(T));
    std::vector<T> values(static_cast<std::size_t>(count));
    read(values.data(), values.size() * sizeof(T));
    return values;
  }
  /// Every value left to the end of the file (written by put_records).
  template <class T>
  std::vector<T> get_rest() {
    static_assert(std::is_trivially_copyable_v<T>);
    check_whole(sizeof(T));
    std::vector<T> values(static_cast<std::size_t>((size_ - at_) / sizeof(T)));
    read(values.data(), values.size() * sizeof(T));
    return values;
  }

 private:
  void read(void* data, std::size_t bytes);
  void check_whole(std::size_t size) const;
  void check_left(std::uint64_t count, std::size_t size) const;
  std::filesystem::path path_;
  std::ifstream in_;
  std::uint64_t size_ = 0, at_ = 0;
};

}  // namespace recon::detail
