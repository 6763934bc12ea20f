#pragma once
// Walking text held in memory: line by line (LineScanner, Fields) for the
// line-oriented formats, token by token across lines (TokenScanner) for
// ASCII PLY. Nothing is copied; every piece is a view into the file content.

#include <cstddef>
#include <cstring>
#include <string_view>

namespace recon::io::detail {

/// Space, tab, carriage return, form feed, vertical tab (not newline).
[[nodiscard]] inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

[[nodiscard]] inline std::string_view trim(std::string_view text) {
  std::size_t begin = 0;
  while (begin < text.size() && is_blank(text[begin])) ++begin;
  std::size_t end = text.size();
  while (end > begin && is_blank(text[end - 1])) --end;
  return text.substr(begin, end - begin);
}

/// The line up to a comment mark ('#' for every text format here).
[[nodiscard]] inline std::string_view without_comment(std::string_view line, char mark = '#') {
  const std::size_t at = line.find(mark);
  return at == std::string_view::npos ? line : line.substr(0, at);
}

/// Lines of a text, numbered from 1. "\n" and "\r\n" both end a line; the
/// last line needs no newline.
class LineScanner {
 public:
  /// Starts at byte `start`, which is the beginning of line `first_line`.
  explicit LineScanner(std::string_view text, std::size_t start = 0, std::size_t first_line = 1)
      : text_(text), position_(start), line_number_(first_line - 1) {}

  /// The next line without its line end; false at the end of the text.
  bool next(std::string_view& line) {
    if (position_ >= text_.size()) return false;
    const char* begin = text_.data() + position_;
    const std::size_t left = text_.size() - position_;
    const void* newline = std::memchr(begin, '\n', left);
    const std::size_t length = newline ? static_cast<std::size_t>(static_cast<const char*>(newline) - begin) : left;
    position_ += newline ? length + 1 : length;
    ++line_number_;
    line = std::string_view(begin, length);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return true;
  }

  /// Number of the line last returned by next() (0 before the first).
  [[nodiscard]] std::size_t line_number() const { return line_number_; }
  /// Byte offset just after the line last returned (where the next begins).
  [[nodiscard]] std::size_t position() const { return position_; }
  [[nodiscard]] bool at_end() const { return position_ >= text_.size(); }

 private:
  std::string_view text_;
  std::size_t position_;
  std::size_t line_number_;
};

/// The whitespace-separated fields of one line.
class Fields {
 public:
  explicit Fields(std::string_view line) : line_(line) {}

  /// The next field; false when none is left.
  bool next(std::string_view& field) {
    while (position_ < line_.size() && is_blank(line_[position_])) ++position_;
    if (position_ >= line_.size()) return false;
    const std::size_t begin = position_;
    while (position_ < line_.size() && !is_blank(line_[position_])) ++position_;
    field = line_.substr(begin, position_ - begin);
    return true;
  }

  /// Counts the fields left (consumes them).
  std::size_t count_rest() {
    std::size_t n = 0;
    for (std::string_view ignored; next(ignored);) ++n;
    return n;
  }

 private:
  std::string_view line_;
  std::size_t position_ = 0;
};

/// Whitespace-separated tokens of a text across line ends, remembering on
/// which line each token stands.
class TokenScanner {
 public:
  /// Starts at byte `start`, which lies on line `line`.
  TokenScanner(std::string_view text, std::size_t start, std::size_t line)
      : text_(text), position_(start), line_number_(line), token_line_(line) {
    if (start > 0 && start <= text.size() && text[start - 1] == '\n' && line > 1) token_line_ = line - 1;
  }

  /// The next token; false at the end of the text.
  bool next(std::string_view& token) {
    const std::size_t size = text_.size();
    while (position_ < size) {
      const char c = text_[position_];
      if (c == '\n') {
        ++line_number_;
      } else if (!is_blank(c)) {
        break;
      }
      ++position_;
    }
    if (position_ >= size) {
      line_number_ = token_line_;  // report the end of the data, not the blank lines after it
      return false;
    }
    const std::size_t begin = position_;
    while (position_ < size && text_[position_] != '\n' && !is_blank(text_[position_])) ++position_;
    token = text_.substr(begin, position_ - begin);
    token_line_ = line_number_;
    return true;
  }

  /// The line of the token last returned; at the end of the text, the line
  /// of the last token (or of the text before `start` when there was none).
  [[nodiscard]] std::size_t line_number() const { return line_number_; }
  [[nodiscard]] std::size_t bytes_left() const { return text_.size() - position_; }

 private:
  std::string_view text_;
  std::size_t position_;
  std::size_t line_number_;
  std::size_t token_line_;
};

}  // namespace recon::io::detail
