#include "recon/detail/binary_file.h"

#include <cstring>

namespace recon::detail {

BinaryWriter::BinaryWriter(const std::filesystem::path& target, const char (&magic)[9]) : file_(target) {
  write(magic, 8);
}

void BinaryWriter::write(const void* data, std::size_t bytes) {
  file_.stream().write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
}

void BinaryWriter::commit() { file_.commit(); }

BinaryReader::BinaryReader(const std::filesystem::path& path, const char (&magic)[9])
    : path_(path), in_(path, std::ios::binary) {
  if (!in_) throw IoError(path.string() + ": cannot open the file for reading");
  std::error_code error;
  size_ = std::filesystem::file_size(path, error);
  if (error) throw IoError(path.string() + ": cannot read its size (" + error.message() + ")");
  char found[8] = {};
  if (size_ < 8) throw ParseError(path.string() + ": not a recon tile file (" + std::to_string(size_) + " bytes)");
  read(found, 8);
  if (std::memcmp(found, magic, 8) != 0)
    throw ParseError(path.string() + ": not a recon tile file of the kind expected (" + std::string(magic, 8) + ")");
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

void BinaryReader::read(void* data, std::size_t bytes) {
  if (bytes > size_ - at_)
    throw ParseError(path_.string() + ": truncated at byte " + std::to_string(size_) + " (" +
                     std::to_string(bytes) + " bytes wanted at byte " + std::to_string(at_) + ")");
  in_.read(static_cast<char*>(data), static_cast<std::streamsize>(bytes));
  if (!in_) throw IoError(path_.string() + ": read failed at byte " + std::to_string(at_));
  at_ += bytes;
}

}  // namespace recon::detail
