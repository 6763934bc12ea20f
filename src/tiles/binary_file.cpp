#include "tiles/binary_file.h"

#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>

namespace recon::detail {

namespace {
std::string hex(std::uint32_t value) {
  char text[16];
  std::snprintf(text, sizeof text, "%08x", static_cast<unsigned>(value));
  return text;
}
}  // namespace

void Checksum::add(const void* data, std::size_t bytes) {
  const auto* at = static_cast<const Bytef*>(data);
  bytes_ += bytes;
  while (bytes > 0) {  // (zlib takes an unsigned int at a time)
    const auto part = static_cast<uInt>(std::min<std::size_t>(bytes, std::numeric_limits<uInt>::max()));
    crc_ = static_cast<std::uint32_t>(crc32(crc_, at, part));
    at += part;
    bytes -= part;
  }
}

ChecksumTrailer Checksum::trailer() const {
  ChecksumTrailer t;
  t.bytes = bytes_;
  t.crc = crc_;
  return t;
}

BinaryWriter::BinaryWriter(const std::filesystem::path& target, const char (&magic)[9]) : file_(target) {
  write(magic, 8);
}

void BinaryWriter::write(const void* data, std::size_t bytes) {
  checksum_.add(data, bytes);
  file_.stream().write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
}

void BinaryWriter::commit() {
  const ChecksumTrailer trailer = checksum_.trailer();
  file_.stream().write(reinterpret_cast<const char*>(&trailer), sizeof trailer);
  file_.commit();
}

BinaryReader::BinaryReader(const std::filesystem::path& path, const char (&magic)[9])
    : path_(path), in_(path, std::ios::binary) {
  if (!in_) throw IoError(path.string() + ": cannot open the file for reading");
  std::error_code error;
  const std::uint64_t size = std::filesystem::file_size(path, error);
  if (error) throw IoError(path.string() + ": cannot read its size (" + error.message() + ")");
  size_ = size;
  char found[8] = {};
  if (size < 8) throw ParseError(path.string() + ": not a recon tile file (" + std::to_string(size) + " bytes)");
  read(found, 8);
  if (std::memcmp(found, magic, 8) != 0)
    throw ParseError(path.string() + ": not a recon tile file of the kind expected (" + std::string(magic, 8) + ")");
  check_checksum(size);
}

// The trailer, then a pass over the bytes before it; back to byte 8 after.
void BinaryReader::check_checksum(std::uint64_t file_size) {
  const auto damaged = [&](const std::string& what) { return ParseError(path_.string() + ": damaged: " + what); };
  if (file_size < 8 + sizeof(ChecksumTrailer))
    throw damaged("no checksum at its end (" + std::to_string(file_size) + " bytes; truncated?)");
  ChecksumTrailer stored;
  in_.seekg(static_cast<std::streamoff>(file_size - sizeof stored));
  in_.read(reinterpret_cast<char*>(&stored), sizeof stored);
  if (!in_) throw IoError(path_.string() + ": read failed at byte " + std::to_string(file_size - sizeof stored));
  const ChecksumTrailer expected_tag;
  if (std::memcmp(stored.tag, expected_tag.tag, sizeof stored.tag) != 0)
    throw damaged("no checksum at its end (truncated, or written by another program?)");
  const std::uint64_t body = file_size - sizeof stored;
  if (stored.bytes != body)
    throw damaged("its checksum covers " + std::to_string(stored.bytes) + " bytes, and " + std::to_string(body) +
                  " precede it (truncated or extended)");
  Checksum computed;
  std::vector<char> buffer(std::size_t{1} << 16);
  in_.seekg(0);
  for (std::uint64_t done = 0; done < body;) {
    const auto part = static_cast<std::size_t>(std::min<std::uint64_t>(buffer.size(), body - done));
    in_.read(buffer.data(), static_cast<std::streamsize>(part));
    if (!in_) throw IoError(path_.string() + ": read failed at byte " + std::to_string(done));
    computed.add(buffer.data(), part);
    done += part;
  }
  if (computed.trailer().crc != stored.crc)
    throw damaged("its CRC-32 is " + hex(computed.trailer().crc) + ", its trailer says " + hex(stored.crc) +
                  " (a changed byte)");
  size_ = body;
  in_.seekg(static_cast<std::streamoff>(at_));
}

void BinaryReader::check_left(std::uint64_t count, std::size_t size) const {
  if (count > (size_ - at_) / size)
    throw ParseError(path_.string() + ": truncated: a record at byte " + std::to_string(at_) + " claims " +
                     std::to_string(count) + " values of " + std::to_string(size) + " bytes, and " +
                     std::to_string(size_ - at_) + " bytes are left");
}

void BinaryReader::check_whole(std::size_t size) const {
  if ((size_ - at_) % size != 0)
    throw ParseError(path_.string() + ": truncated: " + std::to_string(size_ - at_) + " bytes after byte " +
                     std::to_string(at_) + " are not whole records of " + std::to_string(size) + " bytes");
}

void BinaryReader::finish() const {
  if (at_ != size_)
    throw ParseError(path_.string() + ": byte " + std::to_string(at_) + ": " + std::to_string(size_ - at_) +
                     " bytes more than its records hold");
}

void BinaryReader::read(void* data, std::size_t bytes) {
  if (bytes > size_ - at_)
    throw ParseError(path_.string() + ": truncated at byte " + std::to_string(size_) + " (" + std::to_string(bytes) +
                     " bytes wanted at byte " + std::to_string(at_) + ")");
  in_.read(static_cast<char*>(data), static_cast<std::streamsize>(bytes));
  if (!in_) throw IoError(path_.string() + ": read failed at byte " + std::to_string(at_));
  at_ += bytes;
}

}  // namespace recon::detail
