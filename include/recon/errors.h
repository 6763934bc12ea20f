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

/// A file could not be opened, read, written or renamed.
class IoError : public Error {
 public:
  using Error::Error;
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
