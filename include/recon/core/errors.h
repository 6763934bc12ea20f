#pragma once
// The exceptions recon throws. Every message is meant to be shown to a user
// as it is: it says what was wrong and, where possible, what to change.

#include <cstdint>
#include <stdexcept>
#include <string>

namespace recon {

/// Base of every recon exception.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A parameter or a data set the algorithm cannot work with (k too large,
/// fewer distinct points than needed, non-finite coordinates, ...).
class InvalidInputError : public Error {
 public:
  using Error::Error;
};

/// A file could not be opened, read, written or renamed. `error_code()` is
/// the errno value behind it when there was one (ENOENT: no such file), 0
/// otherwise.
class IoError : public Error {
 public:
  explicit IoError(const std::string& what, int error_code = 0) : Error(what), error_code_(error_code) {}
  [[nodiscard]] int error_code() const { return error_code_; }

 private:
  int error_code_ = 0;
};

/// A file is malformed. The message starts with "FILE:LINE:" for text or
/// "FILE: byte OFFSET:" for binary content, then says what was wrong.
class ParseError : public Error {
 public:
  using Error::Error;
};

/// A run would need more memory (or lattice cells) than allowed.
class ResourceLimitError : public Error {
 public:
  using Error::Error;
};

}  // namespace recon
