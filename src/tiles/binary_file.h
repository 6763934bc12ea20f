#pragma once
// The files of a tiled run (tiles.h), not part of the API: plain records of
// trivially copyable values in the machine's byte order, written whole or
// not at all (io::AtomicFile), read back with every length checked against
// the file, so that a truncated or foreign file is an error naming it, not
// a crash.
//
// Every file ends with a trailer: the number of bytes before it and their
// CRC-32 (zlib's). The reader checks it before handing out any value, so a
// flipped bit or a torn copy (a disk, a network share between Dask workers)
// is a ParseError naming the file, not a wrong mesh. A CRC finds every
// burst of up to 32 flipped bits and all but one in 2^32 other damage; it
// is no defence against a file forged on purpose, so the readers still
// check every index they use (tiles/files.h).

#include "recon/core/errors.h"
#include "recon/io/atomic_file.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace recon::detail {

/// The end of every tile file.
struct ChecksumTrailer {
  std::uint64_t bytes = 0;  ///< of the file before the trailer (its magic included)
  std::uint32_t crc = 0;    ///< CRC-32 of those bytes
  char tag[4] = {'C', 'R', 'C', '.'};
};
static_assert(sizeof(ChecksumTrailer) == 16);

/// A running CRC-32 over the bytes of a file as they are written.
class Checksum {
 public:
  void add(const void* data, std::size_t bytes);
  [[nodiscard]] ChecksumTrailer trailer() const;

 private:
  std::uint64_t bytes_ = 0;
  std::uint32_t crc_ = 0;
};

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
  /// Appends the checksum trailer and renames the file into place; IoError
  /// when it cannot be written whole.
  void commit();

 private:
  void write(const void* data, std::size_t bytes);
  io::AtomicFile file_;
  Checksum checksum_;
};

class BinaryReader {
 public:
  /// Checks the whole file first: ParseError unless it starts with `magic`
  /// and ends with a trailer whose length and CRC-32 match the bytes before
  /// it; IoError when it cannot be opened or read. Cost: one pass over the
  /// file (a tile's points: a few hundred MB at most, read again from the
  /// page cache by the gets).
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
  /// Every value left to the trailer (written by put_records).
  template <class T>
  std::vector<T> get_rest() {
    static_assert(std::is_trivially_copyable_v<T>);
    check_whole(sizeof(T));
    std::vector<T> values(static_cast<std::size_t>((size_ - at_) / sizeof(T)));
    read(values.data(), values.size() * sizeof(T));
    return values;
  }
  /// ParseError unless every byte before the trailer was read (a file
  /// longer than its records say is not the file expected).
  void finish() const;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  void check_checksum(std::uint64_t file_size);
  void read(void* data, std::size_t bytes);
  void check_whole(std::size_t size) const;
  void check_left(std::uint64_t count, std::size_t size) const;
  std::filesystem::path path_;
  std::ifstream in_;
  std::uint64_t size_ = 0, at_ = 0;  // size_: the bytes before the trailer
};

}  // namespace recon::detail
